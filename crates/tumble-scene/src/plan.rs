//! The plan a scene compiles into: tumble-plan's plain data (ARCHITECTURE.md, "The plan").

pub use tumble_plan::plan::*;
