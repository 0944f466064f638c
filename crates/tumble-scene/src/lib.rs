//! Scene files for tumble: parse (TOML), validate with clear errors, generate
//! particles and compile the plan — the smallest model the scene needs.
//!
//! ```
//! let text = r#"
//! name = "drop"
//! [run]
//! duration = 0.01
//! [domain]
//! min = [-1.0, -1.0, -1.0]
//! max = [1.0, 1.0, 1.0]
//! [[materials]]
//! name = "glass"
//! density = 2500.0
//! [contact]
//! normal = { model = "linear", stiffness = 1.0e5 }
//! restitution = 0.8
//! [[particles]]
//! material = "glass"
//! shape = { sphere = { diameter = 0.1 } }
//! positions = [[0.0, 0.0, 0.0]]
//! "#;
//! let scene = tumble_scene::parse_scene(text).unwrap();
//! let compiled = tumble_scene::compile(&scene).unwrap();
//! assert!(!compiled.plan.model.rotation);
//! ```

mod compile;
mod error;
mod load;
pub mod mesh_file;
mod mesh_walls;
mod particles;
mod plan;
mod rng;
pub mod schema;
mod shapes;
mod sizes;
mod sources;
mod start;
pub mod targets;
mod timescales;
mod walls;

pub use compile::compile;
pub use error::SceneError;
pub use load::{parse_scene, read_scene, read_scene_text};
pub use mesh_walls::MESH_TRIANGLES_AT_MOST;
pub use particles::InitialParticles;
pub use plan::{
    CompiledScene, Drag, Drum, Feature, Fluid, Material, Motion, PairParams, PhysicsModel, Plan, PlanReport, PolyhedronContact, RunSettings, Servo,
    SphPlan, SphProbe, SphProbeKind, Timescales, Tuning, Wall,
};
pub use rng::Rng;
pub use schema::Scene;
pub use shapes::{ParticleShape, SPHERE, equivalent_radius};
pub use sources::{Body, InsertRegion, MAX_OUTLETS, Outlet, OutletRegion, Rate, Source, SourceKind, Total};
pub use timescales::{ACCURATE_STEPS_PER_COLLISION, ImpactSpeed, STEPS_PER_COLLISION};
