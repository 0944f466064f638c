//! The plan of a tumble simulation as plain data: what a scene compiles into and what the
//! state crate and the backends read. The physics the kernels run (`PhysicsModel`), the run's
//! schedule (`RunSettings`), the backends' tuning, the report, the walls, sources and outlets,
//! the particle shapes and the starting particles; the SPH fluid's plan beside them.
//!
//! Nothing here reads a scene file: tumble-scene parses and checks the file and builds these.
//! The few options a scene file names as they are (which backend, the snapshot encoding, the
//! monitor's thresholds, when a run ends early, a diameter distribution) carry serde's derive
//! so the format reads them without a copy of its own.

mod describe;
mod particles;
pub mod plan;
mod rng;
mod run_options;
mod shapes;
mod sizes;
mod sources;
pub mod targets;
mod timescales;

pub use particles::InitialParticles;
pub use plan::{
    CompiledScene, CouplingPlan, Drag, Drum, Feature, FlowPlane, Fluid, Material, Motion, PairParams, PhysicsModel, Plan, PlanReport,
    PolyhedronContact, RunSettings, Servo, SphPlan, SphProbe, SphProbeKind, Timing, Tuning, WALL_ADVANCE_FRACTION, Wall, WallGroup, WallStepLimit,
};
pub use rng::Rng;
pub use run_options::{BackendName, EndWhenSection, MonitorSection, SnapshotFormat};
pub use shapes::{ParticleShape, SPHERE, equivalent_radius};
pub use sizes::{DiameterRange, DiameterSpec, LogNormalSize, LogNormalWrapper, NormalSize, NormalWrapper, SieveWrapper, TRUNCATION};
pub use sources::{Body, DEFAULT_INTERVAL, InsertRegion, MAX_OUTLETS, Outlet, OutletRegion, Rate, Source, SourceKind, Total, inserted_at_most};
pub use timescales::{ACCURATE_STEPS_PER_COLLISION, ImpactSpeed, STEPS_PER_COLLISION, TANGENTIAL_STEP_SHARE, Timescales};
