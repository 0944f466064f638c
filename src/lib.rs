//! tumble: a discrete element method engine for granular flow.
//!
//! This facade ties the layers together: a scene file compiles into a plan
//! ([`tumble_scene`]), a backend runs it ([`tumble_cpu`] in f64 or
//! [`tumble_gpu`] in f32, each a [`Backend`] behind [`Simulation`]), and [`run`] writes
//! the outputs (`summary.json`, `observables.csv`, `tracks.csv`) while the
//! instability monitor watches every output interval.
//!
//! ```no_run
//! let options = tumble::RunOptions { out_dir: Some("out/demo".into()), ..Default::default() };
//! let summary = tumble::run_scene_file("scenes/box_settle.toml".as_ref(), &options).unwrap();
//! println!("{} particle-steps/s", summary.particle_steps_per_second);
//! ```

pub mod agglomerates;
pub mod checkpoint;
pub mod cli;
pub mod coupler;
pub mod dem;
pub mod feeder;
mod flow;
mod monitor;
mod outdir;
mod output;
mod progress;
pub mod render;
mod resume;
mod run;
mod run_loop;
pub mod seed;
mod simulation;
pub mod sph_phase;
mod summary;
pub mod verify;
pub mod vtk;

pub use flow::FlowCounter;
pub use monitor::{Instability, Monitor};
pub use resume::resume_run;
pub use run::{CheckpointReport, RunError, RunOptions, RunSummary, load_recorded, load_scene, run_compiled, run_recorded, run_scene_file};
pub use simulation::Simulation;
pub use tumble_scene::{CompiledScene, Plan, Scene, SceneError, compile, parse_scene, read_scene};
pub use tumble_state::{
    Backend, DrumProfile, Fault, Frame, Observables, OutputRequest, Phase, PhaseOutput, PhasePoints, PhaseStop, PhaseTable, Snapshot, SnapshotError,
    State, TrackRow,
};
