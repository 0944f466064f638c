//! The Snapshot: everything a backend needs to continue a run bit-identically,
//! serialisable with serde and versioned.

use crate::{ContactSum, Fault, State};
use glam::DVec3;
use serde::{Deserialize, Serialize};

/// The layout version written into every snapshot; a reader refuses any other.
/// 4: contact springs carry the EPSD2 rolling torque and its energy; 5: outlet tallies;
/// 6: servo walls' state and mesh wear; 7: forces held on the particles (a coupled fluid's).
pub const SNAPSHOT_VERSION: u32 = 7;

/// The first bytes of an encoded snapshot.
const MAGIC: &[u8; 8] = b"TUMBLESN";

/// A run frozen between two steps.
///
/// Per-particle arrays are in the backend's memory order (not id order), so a
/// restore reproduces every summation order and the continuation is bit-identical.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct Snapshot {
    pub version: u32,
    /// The scene's name and time step: a restore refuses a snapshot of another scene.
    pub scene: String,
    pub dt: f64,
    /// The backend that wrote it (`cpu`, `gpu`) and its precision (`f64`, `f32`).
    pub backend: String,
    pub precision: String,
    pub step: u64,
    pub time: f64,
    /// Particles that left the domain through a non-periodic side so far.
    pub removed: u64,
    /// Per outlet of the plan: what it deleted so far.
    pub outlets: Vec<OutletTally>,
    /// Every per-particle array, contact springs with their stored energies included.
    pub state: State,
    /// Each particle's share of the last contact pass (empty when a removal made it stale).
    pub last_pass: Vec<ContactSum>,
    pub walls: WallState,
    /// The neighbour list's build state (backends that keep one).
    pub neighbours: Option<NeighbourState>,
    /// The step of the last re-sort by cell, if any.
    pub last_resort: Option<u64>,
    pub fault: Option<Fault>,
    /// Random-number state of models that draw at run time (none does yet: empty).
    pub rng: Vec<u64>,
    /// Forces held on the particles by id (a coupled fluid's; empty without them).
    pub external: Vec<DVec3>,
    /// A device backend's own memory, for a bit-identical continuation there (None on the CPU).
    pub device: Option<DeviceImage>,
}

/// What one outlet deleted: particles and their mass.
#[derive(Clone, Copy, Debug, Default, PartialEq, Serialize, Deserialize)]
pub struct OutletTally {
    pub count: u64,
    pub mass: f64,
}

/// A [`Snapshot`] borrowed from a backend's own arrays: it encodes to the same bytes without
/// copying them first (a state of a million particles is a gigabyte to copy).
#[derive(Serialize)]
pub struct SnapshotRef<'a> {
    pub version: u32,
    pub scene: &'a str,
    pub dt: f64,
    pub backend: &'a str,
    pub precision: &'a str,
    pub step: u64,
    pub time: f64,
    pub removed: u64,
    pub outlets: &'a [OutletTally],
    pub state: &'a State,
    pub last_pass: &'a [ContactSum],
    pub walls: WallState,
    pub neighbours: Option<NeighbourStateRef<'a>>,
    pub last_resort: Option<u64>,
    pub fault: Option<Fault>,
    pub rng: &'a [u64],
    pub external: &'a [DVec3],
    pub device: Option<&'a DeviceImage>,
}

/// [`NeighbourState`] borrowed.
#[derive(Serialize)]
pub struct NeighbourStateRef<'a> {
    pub reference: &'a [DVec3],
    pub valid: bool,
    pub builds: u64,
}

impl SnapshotRef<'_> {
    /// Streams the bytes [`Snapshot::to_bytes`] would give for the owned snapshot into `w`.
    pub fn write_to<W: std::io::Write>(&self, mut w: W) -> std::io::Result<W> {
        w.write_all(MAGIC)?;
        w.write_all(&self.version.to_le_bytes())?;
        postcard::to_io(self, w).map_err(std::io::Error::other)
    }
}

/// A device backend's memory between two steps: its buffers byte for byte (slot order,
/// springs, Kahan pairs, cell tables) and its host-side counters. `state` beside it holds
/// the same particles widened to f64 in id order, for readers that are not that backend.
#[derive(Clone, Debug, Default, PartialEq, Serialize, Deserialize)]
pub struct DeviceImage {
    /// The adapter that wrote it: another adapter continues the run, not bit-identically.
    pub adapter: String,
    /// (buffer name, its bytes), in the backend's fixed order.
    pub buffers: Vec<(String, Vec<u8>)>,
    /// (counter name, value): the backend's step bookkeeping that is not in a buffer.
    pub counters: Vec<(String, u64)>,
}

impl DeviceImage {
    /// The bytes of the buffer called `name`.
    pub fn buffer(&self, name: &str) -> Option<&[u8]> {
        self.buffers.iter().find(|(n, _)| n == name).map(|(_, b)| b.as_slice())
    }

    /// The counter called `name`.
    pub fn counter(&self, name: &str) -> Option<u64> {
        self.counters.iter().find(|(n, _)| n == name).map(|&(_, v)| v)
    }
}

/// The world's moving geometry and its energy books.
#[derive(Clone, Debug, Default, PartialEq, Serialize, Deserialize)]
pub struct WallState {
    /// The time of the walls' current pose (each wall's pose follows from its motion).
    pub time: f64,
    /// `time` when the neighbour list's wall candidates were built.
    pub built_at: f64,
    /// Per wall group: power at the last force pass and work done since t = 0.
    pub power: Vec<f64>,
    pub work: Vec<f64>,
    /// Kahan compensation of `work`, where a backend keeps one (empty otherwise).
    pub work_compensation: Vec<f64>,
    /// Per wall group: its servo's state (default for groups without one; empty on backends
    /// without servos).
    pub servos: Vec<ServoState>,
    /// Per wall: the volume worn off each of its triangles since t = 0 (empty without wear).
    pub wear: Vec<Vec<f64>>,
}

/// Where a servo wall is: its offset along the servo's direction from its t = 0 pose (the
/// current pose, and the pose of the last neighbour-list build) and its speed over the next step.
#[derive(Clone, Copy, Debug, Default, PartialEq, Serialize, Deserialize)]
pub struct ServoState {
    pub offset: f64,
    pub built_offset: f64,
    pub speed: f64,
}

/// What a Verlet list needs to be rebuilt exactly as it was.
#[derive(Clone, Debug, Default, PartialEq, Serialize, Deserialize)]
pub struct NeighbourState {
    /// Positions at the last build, in memory order.
    pub reference: Vec<DVec3>,
    /// False when the list was invalidated (it is rebuilt at the next step anyway).
    pub valid: bool,
    /// Rebuilds so far.
    pub builds: u64,
}

/// A snapshot that cannot be read or does not fit the run it is given to.
#[derive(Clone, Debug, PartialEq)]
pub enum SnapshotError {
    /// Not a tumble snapshot, or cut short.
    Corrupt(String),
    /// Written by another layout version.
    Version { found: u32, expected: u32 },
    /// Written for another scene, time step or backend.
    Mismatch(String),
    /// The backend cannot restore (yet).
    Unsupported(String),
}

impl std::fmt::Display for SnapshotError {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        match self {
            SnapshotError::Corrupt(why) => write!(f, "not a readable tumble snapshot: {why}"),
            SnapshotError::Version { found, expected } => {
                write!(f, "snapshot layout version {found}, but this tumble reads version {expected}")
            }
            SnapshotError::Mismatch(why) => write!(f, "snapshot does not fit this run: {why}"),
            SnapshotError::Unsupported(why) => write!(f, "{why}"),
        }
    }
}

impl std::error::Error for SnapshotError {}

impl Snapshot {
    /// Encodes as magic, version (little-endian u32), then the postcard body (f64 bit-exact).
    pub fn to_bytes(&self) -> Vec<u8> {
        self.write_to(Vec::new()).expect("a snapshot always encodes into memory")
    }

    /// Streams what [`Snapshot::to_bytes`] returns into `w` (a file: no copy of the whole in memory).
    pub fn write_to<W: std::io::Write>(&self, mut w: W) -> std::io::Result<W> {
        w.write_all(MAGIC)?;
        w.write_all(&self.version.to_le_bytes())?;
        postcard::to_io(self, w).map_err(std::io::Error::other)
    }

    /// Decodes what [`Snapshot::to_bytes`] wrote, refusing other versions.
    pub fn from_bytes(bytes: &[u8]) -> Result<Snapshot, SnapshotError> {
        if bytes.len() < 12 || &bytes[..8] != MAGIC {
            return Err(SnapshotError::Corrupt("missing the TUMBLESN header".into()));
        }
        let found = u32::from_le_bytes(bytes[8..12].try_into().unwrap());
        if found != SNAPSHOT_VERSION {
            return Err(SnapshotError::Version { found, expected: SNAPSHOT_VERSION });
        }
        let (snapshot, rest): (Snapshot, &[u8]) = postcard::take_from_bytes(&bytes[12..]).map_err(|e| SnapshotError::Corrupt(e.to_string()))?;
        if !rest.is_empty() {
            return Err(SnapshotError::Corrupt(format!("{} bytes after the end", rest.len())));
        }
        Ok(snapshot)
    }

    /// Refuses a snapshot of another scene or time step than `plan`'s.
    pub fn check_fits(&self, plan: &tumble_plan::Plan) -> Result<(), SnapshotError> {
        if self.version != SNAPSHOT_VERSION {
            return Err(SnapshotError::Version { found: self.version, expected: SNAPSHOT_VERSION });
        }
        if self.scene != plan.run.name {
            return Err(SnapshotError::Mismatch(format!("written for scene `{}`, this run is `{}`", self.scene, plan.run.name)));
        }
        if self.dt.to_bits() != plan.model.dt.to_bits() {
            return Err(SnapshotError::Mismatch(format!("written with dt = {:e} s, this run has dt = {:e} s", self.dt, plan.model.dt)));
        }
        if self.outlets.len() != plan.model.outlets.len() {
            return Err(SnapshotError::Mismatch(format!("written with {} outlets, this run has {}", self.outlets.len(), plan.model.outlets.len())));
        }
        Ok(())
    }
}
