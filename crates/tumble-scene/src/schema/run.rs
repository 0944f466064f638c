//! The `[run]` and `[output]` tables: how long, how finely and with what checks a scene runs,
//! and what it writes.

use super::*;
pub use tumble_plan::{BackendName, EndWhenSection, MonitorSection, SnapshotFormat};

/// Extra outputs.
#[derive(Clone, Debug, Default, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct OutputSection {
    /// Planes whose mass flow is reported in observables.csv (`flow_<name>`, `mass_<name>`).
    #[serde(default)]
    pub flow_planes: Vec<FlowPlaneSection>,
    /// How snapshot .vtp files are encoded (docs/cli.md, "Snapshots").
    #[serde(default)]
    pub snapshot_format: SnapshotFormat,
    /// Write the contact network (`snapshots/contacts_NNNNNN.vtp`) at every snapshot.
    #[serde(default)]
    pub contacts: bool,
}

#[derive(Clone, Debug, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct FlowPlaneSection {
    pub name: String,
    pub point: V3,
    /// Flow counts positive from the side behind the normal to the side it points to.
    pub normal: V3,
}

#[derive(Clone, Debug, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct RunSection {
    pub duration: f64,
    pub dt: Option<DtSpec>,
    #[serde(default)]
    pub integrator: IntegratorName,
    #[serde(default)]
    pub backend: BackendName,
    pub output_interval: Option<f64>,
    pub snapshot_interval: Option<f64>,
    #[serde(default)]
    pub rotation: RotationMode,
    #[serde(default = "default_seed")]
    pub seed: u64,
    /// Run even when Δt exceeds the stability limit (the instability monitor still watches).
    #[serde(default)]
    pub allow_unstable_dt: bool,
    /// Steps between re-sorts of the particle arrays by cell.
    pub resort_interval: Option<u32>,
    /// Particle slots a backend with device arrays (the GPU) adds each time the sources need more.
    pub capacity_chunk: Option<u64>,
    /// Neighbour-list skin as a fraction of the largest interaction diameter.
    pub skin: Option<f64>,
    #[serde(default)]
    pub monitor: MonitorSection,
    /// Checks of the starting state before step 1.
    #[serde(default)]
    pub start: StartSection,
    /// Largest share of the particles that may leave the domain through its non-periodic
    /// sides before the run stops with an error (0.01; 1 allows any loss, as a hopper discharging).
    #[serde(default = "default_lost_fraction")]
    pub max_lost_fraction: f64,
    /// Largest share of the particles one outlet may delete within one output interval before
    /// the run stops with an error (0.5; 1 allows any, as an outlet meant to empty the domain at once).
    #[serde(default = "default_outlet_fraction")]
    pub max_outlet_fraction: f64,
    /// A source that found no room at any of its insertions (a region behind a wall, outside
    /// the domain) fails the run, exit status 3, unless this is true.
    #[serde(default)]
    pub allow_idle_sources: bool,
    /// Write agglomerates.csv at every output interval (default: when cohesion is on).
    pub agglomerates: Option<bool>,
    /// Simulated seconds between checkpoints (`checkpoints/` in the output folder, for
    /// `tumble resume`); none by default.
    pub checkpoint_interval: Option<f64>,
    /// Checkpoints kept (the newest ones); 3.
    pub checkpoint_keep: Option<u32>,
    /// End the run early once the particles have come to rest (a settling stage).
    pub end_when: Option<EndWhenSection>,
}

fn default_seed() -> u64 {
    1
}

fn default_lost_fraction() -> f64 {
    0.01
}

fn default_outlet_fraction() -> f64 {
    0.5
}

/// Starting-state checks: particles may start in contact only this deep.
#[derive(Clone, Debug, Deserialize, PartialEq)]
#[serde(deny_unknown_fields)]
pub struct StartSection {
    /// Deepest overlap accepted between two particles or a particle and a wall, as a
    /// fraction of the smaller diameter.
    #[serde(default = "default_start_overlap")]
    pub max_overlap: f64,
    /// Skip the overlap checks (a deliberately compressed packing).
    #[serde(default)]
    pub allow_overlap: bool,
    /// Take the particles' state (positions, velocities, spins, orientations, springs) from a
    /// checkpoint of another run: a checkpoint file or a run's output folder (its newest).
    #[serde(default)]
    pub from: Option<String>,
}

fn default_start_overlap() -> f64 {
    0.01
}

impl Default for StartSection {
    fn default() -> Self {
        StartSection { max_overlap: default_start_overlap(), allow_overlap: false, from: None }
    }
}

#[derive(Clone, Copy, Debug, Deserialize, PartialEq)]
#[serde(untagged)]
pub enum DtSpec {
    Seconds(f64),
    Fraction(CollisionFraction),
}

#[derive(Clone, Copy, Debug, Deserialize, PartialEq)]
#[serde(deny_unknown_fields)]
pub struct CollisionFraction {
    pub collision_fraction: f64,
}

#[derive(Clone, Copy, Debug, Default, Deserialize, PartialEq, Eq)]
#[serde(rename_all = "kebab-case")]
pub enum IntegratorName {
    Euler,
    SymplecticEuler,
    #[default]
    Verlet,
    ImplicitDrag,
    ImplicitDragSymplectic,
}

#[derive(Clone, Copy, Debug, Default, Deserialize, PartialEq, Eq)]
#[serde(rename_all = "kebab-case")]
pub enum RotationMode {
    #[default]
    Auto,
    Off,
    On,
}
