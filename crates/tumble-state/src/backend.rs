//! The seam between the run loop and a backend: what the loop may ask of any
//! backend, so a new one (distributed, later) plugs in without touching it.

use crate::{DrumProfile, Fault, Observables, Snapshot, SnapshotError, State, TrackRow};
use glam::DVec3;
use std::any::Any;
use std::borrow::Cow;
use tumble_plan::{Plan, Wall};

/// What a backend is and runs on, as summary.json reports it.
#[derive(Clone, Debug, PartialEq)]
pub struct BackendInfo {
    /// `cpu`, `gpu`, …
    pub name: &'static str,
    /// `f64` or `f32`.
    pub precision: &'static str,
    /// The device in words (`CPU, 4 threads`, or the adapter).
    pub device: String,
    /// The GPU adapter, on GPU backends.
    pub adapter: Option<AdapterInfo>,
}

/// Name, backend and driver of a GPU adapter.
#[derive(Clone, Debug, PartialEq)]
pub struct AdapterInfo {
    pub name: String,
    pub backend: String,
    pub driver: String,
    pub device_type: String,
}

/// Everything one output row needs, gathered in one go (one read-back on a device).
#[derive(Clone, Debug)]
pub struct Frame<'a> {
    pub observables: Observables,
    pub tracks: Vec<TrackRow>,
    /// Per wall group: power at the last force pass and work since t = 0.
    pub wall_power: Vec<f64>,
    pub wall_work: Vec<f64>,
    /// Per wall group at the last force pass: the particles' contact force on its surfaces, and
    /// its torque about the group's reference point (`PhysicsModel::wall_group_reference`).
    pub wall_force: Vec<DVec3>,
    pub wall_torque: Vec<DVec3>,
    /// Per wall group: a servo wall's offset along its direction from its t = 0 pose (zero
    /// without a servo; empty on backends without servos).
    pub servo_offset: Vec<f64>,
    pub drums: Vec<DrumProfile>,
    /// The particle arrays, when asked for (flow planes, agglomerates).
    pub state: Option<Cow<'a, State>>,
}

/// A backend steps a compiled scene and answers the run loop's questions.
///
/// `advance` steps in whole time steps, so a coupled solver can sub-cycle it
/// (k particle steps per fluid step). Questions a distributed backend must
/// answer collectively (every rank the same answer) go through [`Backend::agree`].
pub trait Backend: Any {
    fn plan(&self) -> &Plan;
    fn info(&self) -> BackendInfo;
    /// Advances `steps` steps, or fewer when a fixed capacity runs out (see [`Backend::fault`]).
    fn advance(&mut self, steps: u64);
    /// Steps taken so far.
    fn steps(&self) -> u64;
    /// Simulated time.
    fn time(&self) -> f64 {
        self.steps() as f64 * self.plan().model.dt
    }
    /// Particles still in the domain.
    fn particles(&self) -> usize;
    /// Particles that left the domain through a non-periodic side.
    fn removed(&self) -> usize;
    /// Per outlet of the plan: particles it deleted and their mass, since t = 0.
    fn outlet_tallies(&self) -> Vec<crate::OutletTally>;
    /// Adds `particles` (arrays of this plan's model, ids after every id so far, no springs,
    /// overlapping nothing) before the next step. Refused, changing nothing, when a backend's
    /// fixed capacity cannot hold them.
    fn insert(&mut self, particles: State) -> Result<(), String>;
    /// Why the backend stopped short of the requested steps, if it did.
    fn fault(&self) -> Option<Fault>;
    /// One output row: observables, tracked particles, wall power and work, drum
    /// profiles and, with `with_state`, the particle arrays.
    fn frame(&self, with_state: bool) -> Frame<'_>;
    fn observables(&self) -> Observables {
        self.frame(false).observables
    }
    fn tracks(&self) -> Vec<TrackRow> {
        self.frame(false).tracks
    }
    /// Every particle still in the domain in f64 (a device's widened from f32).
    fn state(&self) -> Cow<'_, State>;
    /// Power delivered to the particles by each wall group at the last force pass.
    fn wall_power(&self) -> Vec<f64>;
    /// Work done on the particles by each wall group since t = 0.
    fn wall_work(&self) -> Vec<f64>;
    /// The charge profile of each drum of the plan.
    fn drum_profiles(&self) -> Vec<DrumProfile> {
        self.frame(false).drums
    }
    /// The walls in their current pose.
    /// Per wall: the volume worn off each of its triangles since t = 0 (empty for walls without
    /// wear, and on backends without wear).
    fn mesh_wear(&self) -> Vec<Vec<f64>> {
        Vec::new()
    }
    fn walls(&self) -> Cow<'_, [Wall]>;
    /// Contact force on the particle with id `id` in the last force pass.
    fn contact_force(&self, id: u32) -> Option<DVec3>;
    /// Neighbour-list rebuilds, for backends that keep a list.
    fn neighbour_builds(&self) -> Option<u64> {
        None
    }
    /// Memory the particle and grid arrays take, bytes (device memory on a device).
    fn memory_bytes(&self) -> u64;
    /// Bytes per particle of this backend's state.
    fn bytes_per_particle(&self) -> u64;
    /// Holds `forces` (N, by particle id; an id beyond the slice gets none) on the particles
    /// from the next step on, until set again: a coupled fluid's forces over the particles'
    /// sub-steps. The accelerations of the last force pass take the change at once, so every
    /// step's kicks see the same forces. Refused by a backend that cannot hold them.
    fn set_external_forces(&mut self, forces: &[DVec3]) -> Result<(), String> {
        let _ = forces;
        Err(format!("the {} backend holds no forces on its particles yet", self.info().name))
    }

    /// The forces held on the particles by [`Backend::set_external_forces`], by id (empty
    /// without them).
    fn external_forces(&self) -> &[DVec3] {
        &[]
    }

    /// Everything needed to continue this run bit-identically.
    fn snapshot(&self) -> Snapshot;
    /// Streams [`Backend::snapshot`]'s bytes ([`Snapshot::to_bytes`]) into `w`; a backend whose
    /// arrays are on the host writes them without copying.
    fn write_snapshot(&self, w: &mut dyn std::io::Write) -> std::io::Result<()> {
        self.snapshot().write_to(w).map(|_| ())
    }
    /// Continues from `snapshot`, which this backend wrote for the same scene.
    fn restore(&mut self, snapshot: &Snapshot) -> Result<(), SnapshotError>;
    /// A collective decision: true when `local` is true on any part of the run (one process: `local`).
    fn agree(&self, local: bool) -> bool {
        local
    }
    fn as_any(&self) -> &dyn Any;
    fn as_any_mut(&mut self) -> &mut dyn Any;
}
