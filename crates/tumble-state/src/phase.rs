//! A phase: a family of particles with its own arrays, grid, step, section of each output row,
//! snapshot series and checkpoint section. The DEM's particles are one phase, an SPH fluid
//! another; the run loop holds every phase only through [`Phase`] and knows none of their
//! models.

use crate::PolyData;
use glam::DVec3;
use std::any::Any;
use std::fmt;

/// One of a phase's output tables: a file of rows, written at every output row.
#[derive(Clone, Debug, PartialEq)]
pub struct PhaseTable {
    /// The file in the run's folder (`observables.csv`, `fluid.csv`, `probe_gauge1.csv`).
    pub file: String,
    /// Column names after `t`.
    pub columns: Vec<String>,
    /// This output row's lines in the file (most tables write one; tracks.csv one per tracked
    /// particle). A value that is not finite is undefined there and written as an empty cell.
    pub rows: Vec<Vec<f64>>,
}

impl PhaseTable {
    /// A table of one line.
    pub fn line(file: impl Into<String>, columns: &[&str], values: Vec<f64>) -> Self {
        PhaseTable { file: file.into(), columns: columns.iter().map(|c| c.to_string()).collect(), rows: vec![values] }
    }

    /// The value in `column` of the first line, if both exist.
    pub fn value(&self, column: &str) -> Option<f64> {
        let k = self.columns.iter().position(|c| c == column)?;
        self.rows.first().and_then(|r| r.get(k)).copied()
    }
}

/// A phase's particles as plain arrays: positions and named per-point fields.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct PhasePoints {
    pub positions: Vec<DVec3>,
    pub scalars: Vec<(&'static str, Vec<f64>)>,
    pub vectors: Vec<(&'static str, Vec<DVec3>)>,
    pub integers: Vec<(&'static str, Vec<i32>)>,
}

impl PhasePoints {
    /// The points as a snapshot piece: one vertex per point, the fields as point data (the
    /// first scalar and vector ParaView's defaults).
    pub fn poly_data(&self) -> PolyData {
        use crate::Array;
        let mut point_data: Vec<Array> = self.scalars.iter().map(|(name, v)| Array::f64(name, 1, v.clone())).collect();
        point_data.extend(self.vectors.iter().map(|(name, v)| Array::f64(name, 3, v.iter().flat_map(|x| x.to_array()).collect())));
        point_data.extend(self.integers.iter().map(|(name, v)| Array::i32(name, v.clone())));
        PolyData {
            points: self.positions.iter().flat_map(|x| x.to_array()).collect(),
            verts: crate::Cells::of((0..self.positions.len()).map(|k| [k])),
            point_data,
            point_attributes: (self.scalars.first().map(|(n, _)| n.to_string()), self.vectors.first().map(|(n, _)| n.to_string())),
            ..Default::default()
        }
    }
}

/// Why an unstable run was stopped: where, the cause, and what to change.
#[derive(Clone, Debug, PartialEq)]
pub struct Instability {
    pub step: u64,
    pub time: f64,
    pub cause: String,
    /// What to change: a Δt, or why Δt will not help and what will.
    pub remedy: String,
    pub dt: f64,
    /// The Δt to rerun at: the plan's default when the step is the cause, else the step that ran.
    pub suggested_dt: f64,
}

impl fmt::Display for Instability {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        write!(f, "simulation unstable at step {} (t = {:.6e} s): {}; {}", self.step, self.time, self.cause, self.remedy)
    }
}

/// Why a phase stops the run.
#[derive(Clone, Debug, PartialEq)]
pub enum PhaseStop {
    /// Its monitor found the run unstable.
    Unstable(Instability),
    /// A fixed capacity ran out (contact history slots, a source's room on a device).
    Capacity(String),
    /// More particles left than the scene allows.
    Lost(String),
    /// The scene's end condition was met: the run is complete.
    Ended(String),
    /// The phase cannot go on (a fluid's fault): the cause and a Δt that works.
    Failed(String),
}

impl fmt::Display for PhaseStop {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self {
            PhaseStop::Unstable(e) => e.fmt(f),
            PhaseStop::Capacity(s) | PhaseStop::Lost(s) | PhaseStop::Ended(s) | PhaseStop::Failed(s) => f.write_str(s),
        }
    }
}

/// What the run loop asks for at an output step.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct OutputRequest {
    /// The step (the snapshot series number the loop gives it is its own).
    pub step: u64,
    /// The output row: the monitor's checks and the tables.
    pub row: bool,
    /// The snapshot series.
    pub series: bool,
    /// The run's first row (step 0 of a new run): the starting state is written whatever it
    /// is, then checked.
    pub start: bool,
}

/// A phase's part of one output step.
#[derive(Clone, Debug, Default)]
pub struct PhaseOutput {
    /// Its tables' lines, written in this order.
    pub tables: Vec<PhaseTable>,
    /// Its snapshot series: (series name, this step's piece).
    pub series: Vec<(String, PolyData)>,
    /// A stop found while making the row, after which these tables are still written (an
    /// ended run's last row; the row that shows particles were lost, with no further table).
    pub stop: Option<PhaseStop>,
}

/// What the run loop asks of a phase. Every phase steps on the run's clock: `advance` takes the
/// same steps of the same Δt as every other phase.
pub trait Phase {
    /// The phase's name: its summary section and the snapshot series of its points.
    fn name(&self) -> &'static str;
    /// Advances `steps` steps of `dt`, or stops short and says why.
    fn advance(&mut self, steps: u64, dt: f64) -> Result<(), PhaseStop>;
    /// The phase's moving particles (its particle-steps count these).
    fn particles(&self) -> usize;
    /// Bytes its arrays and grid take.
    fn memory_bytes(&self) -> u64;
    /// Its part of an output step, from one read of its state: its monitor's checks and its
    /// tables' lines (`row`), its snapshot series (`series`). A check that fails before
    /// anything is written is the error.
    fn output(&mut self, request: OutputRequest) -> Result<PhaseOutput, PhaseStop>;
    /// Snapshot pieces written once, when the series start (static walls).
    fn fixed_series(&self) -> Vec<(String, PolyData)> {
        Vec::new()
    }
    /// The values summary.json reports for it at the end (its main table's columns).
    fn summary(&self) -> Vec<(String, f64)>;
    /// Its checkpoint section: everything needed to continue it bit-identically that the
    /// checkpoint's body does not hold.
    fn snapshot(&self) -> Vec<u8>;
    /// Continues from a section [`Phase::snapshot`] wrote for the same scene.
    fn restore(&mut self, bytes: &[u8]) -> Result<(), String>;
    fn as_any(&self) -> &dyn Any;
    fn as_any_mut(&mut self) -> &mut dyn Any;
}
