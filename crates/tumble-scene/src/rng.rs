//! The seeded generator scenes draw from (tumble-plan's `Rng`, which the sources also draw from at run time).

pub use tumble_plan::Rng;
