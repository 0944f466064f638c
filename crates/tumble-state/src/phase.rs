//! A phase beside the particles: a family of its own particles (an SPH fluid) with its own
//! arrays, grid, step, section of each output row, snapshot section and points in the
//! snapshots. The run loop holds phases only through [`Phase`].

use glam::DVec3;

/// One of a phase's output tables: a file of rows written at every output row.
#[derive(Clone, Debug, PartialEq)]
pub struct PhaseTable {
    /// The file in the run's folder (`fluid.csv`, `probe_gauge1.csv`).
    pub file: String,
    /// Column names after `time`.
    pub columns: Vec<String>,
    pub values: Vec<f64>,
}

/// A phase's particles for a snapshot: positions and named per-point fields.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct PhasePoints {
    pub positions: Vec<DVec3>,
    pub scalars: Vec<(&'static str, Vec<f64>)>,
    pub vectors: Vec<(&'static str, Vec<DVec3>)>,
    pub integers: Vec<(&'static str, Vec<i32>)>,
}

/// What the run loop asks of a phase. Phases step on the run's clock: `advance` takes the same
/// steps of the same Δt as the particles.
pub trait Phase: Send {
    /// The phase's name: its snapshot series and summary section (`fluid`).
    fn name(&self) -> &'static str;
    /// Advances `steps` steps of `dt`; on a fault, stops there and says why, with a Δt that works.
    fn advance(&mut self, steps: u64, dt: f64) -> Result<(), String>;
    /// The phase's moving particles (its particle-steps count these).
    fn particles(&self) -> usize;
    /// Bytes its arrays and grid take.
    fn memory_bytes(&self) -> u64;
    /// Its section of the output row now: each table's values.
    fn tables(&self) -> Vec<PhaseTable>;
    /// The phase's own instability monitor, at each output row: why it must stop, if it must
    /// (the cause, and what would make it stable).
    fn check(&mut self) -> Result<(), String>;
    /// Its particles for a snapshot.
    fn points(&self) -> PhasePoints;
    /// Everything needed to continue it bit-identically.
    fn snapshot(&self) -> Vec<u8>;
    /// Continues from bytes [`Phase::snapshot`] wrote for the same scene.
    fn restore(&mut self, bytes: &[u8]) -> Result<(), String>;
}
