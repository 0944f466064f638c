//! The analytic verification cases of docs/verification.md, shared by the tests,
//! `cargo xtask verify` and (later) `tumble verify`.
//!
//! Each case loads its scene from `scenes/verify/`, runs it at a sequence of
//! time steps and integrators, and compares with the closed form.

mod cases;
pub mod chung_ooi;
mod expect;
mod friction;
mod report;

pub use cases::*;
pub use expect::{Expectation, ORDER_TOLERANCE, Verdict, expectations, verdicts};
pub use friction::*;
pub use report::report;

use crate::{Simulation, TrackRow};
use tumble_integrate::Integrator;
use tumble_scene::schema::{BackendName, DtSpec, IntegratorName};
use tumble_scene::{CompiledScene, Scene, compile, parse_scene};

/// One measured error of one case, integrator and time step.
#[derive(Clone, Debug, PartialEq)]
pub struct ErrorRow {
    pub case: &'static str,
    /// What was measured (e.g. `x(t) in contact`, `rebound speed`).
    pub measure: &'static str,
    pub integrator: Integrator,
    /// Steps per reference time (t_col, τ, …): the x axis of the charts.
    pub steps_per_scale: f64,
    pub dt: f64,
    pub error: f64,
    /// Particle-steps taken.
    pub particle_steps: u64,
    pub wall_seconds: f64,
}

impl ErrorRow {
    /// The CSV columns of [`ErrorRow::csv`].
    pub const CSV_HEADER: &'static str = "case,measure,integrator,steps_per_scale,dt,error,particle_steps,wall_seconds";

    /// This row as CSV fields (no line end), in the order of [`ErrorRow::CSV_HEADER`].
    pub fn csv(&self) -> String {
        format!(
            "{},{},{},{},{},{},{},{}",
            self.case,
            self.measure,
            self.integrator.name(),
            self.steps_per_scale,
            self.dt,
            self.error,
            self.particle_steps,
            self.wall_seconds
        )
    }
}

/// The step counts per reference time every convergence study uses: t/8 … t/256.
pub const DIVISORS: [f64; 6] = [8.0, 16.0, 32.0, 64.0, 128.0, 256.0];

/// Least-squares slope of log(error) against log(dt): the measured order.
pub fn fitted_order(rows: &[&ErrorRow]) -> f64 {
    let pts: Vec<(f64, f64)> = rows.iter().filter(|r| r.error > 0.0).map(|r| (r.dt.ln(), r.error.ln())).collect();
    let n = pts.len() as f64;
    let (mx, my) = (pts.iter().map(|p| p.0).sum::<f64>() / n, pts.iter().map(|p| p.1).sum::<f64>() / n);
    let sxy: f64 = pts.iter().map(|p| (p.0 - mx) * (p.1 - my)).sum();
    let sxx: f64 = pts.iter().map(|p| (p.0 - mx).powi(2)).sum();
    sxy / sxx
}

pub(crate) fn integrator_name(i: Integrator) -> IntegratorName {
    match i {
        Integrator::Euler => IntegratorName::Euler,
        Integrator::SymplecticEuler => IntegratorName::SymplecticEuler,
        Integrator::Verlet => IntegratorName::Verlet,
        Integrator::ImplicitDrag => IntegratorName::ImplicitDrag,
        Integrator::ImplicitDragSymplectic => IntegratorName::ImplicitDragSymplectic,
    }
}

/// A verification scene with the integrator and Δt replaced.
pub fn scene_with(text: &str, integrator: Integrator, dt: Option<f64>) -> CompiledScene {
    let mut scene: Scene = parse_scene(text).expect("verification scene parses");
    scene.run.integrator = integrator_name(integrator);
    if let Some(dt) = dt {
        scene.run.dt = Some(DtSpec::Seconds(dt));
        scene.run.output_interval = Some(dt);
    }
    scene.run.monitor.enabled = false;
    scene.run.allow_unstable_dt = true;
    compile(&scene).expect("verification scene compiles")
}

/// Tracked particles after every step, with the simulated time.
pub struct Trajectory {
    pub samples: Vec<(f64, Vec<TrackRow>)>,
    pub particle_steps: u64,
    pub wall_seconds: f64,
    pub last: Simulation,
}

/// Runs a compiled scene to its duration on the CPU, sampling the tracked particles every step.
pub fn trajectory(scene: CompiledScene) -> Trajectory {
    trajectory_on(BackendName::Cpu, scene)
}

/// Sets up a scene on a backend (the CPU with one thread).
///
/// # Panics
/// When the GPU backend has no adapter; callers check [`tumble_gpu::available`] first.
pub fn simulation_on(backend: BackendName, scene: CompiledScene) -> Simulation {
    Simulation::on(backend, scene, 1).unwrap_or_else(|e| panic!("backend {backend:?}: {e}"))
}

/// Like [`trajectory`] on the given backend.
pub fn trajectory_on(backend: BackendName, scene: CompiledScene) -> Trajectory {
    let steps = scene.plan.run.steps;
    let mut sim = simulation_on(backend, scene);
    let mut samples = Vec::with_capacity(steps as usize + 1);
    samples.push((0.0, sim.tracks()));
    let start = std::time::Instant::now();
    let mut particle_steps = 0;
    for _ in 0..steps {
        particle_steps += sim.particles() as u64;
        sim.advance(1);
        samples.push((sim.time(), sim.tracks()));
    }
    Trajectory { samples, particle_steps, wall_seconds: start.elapsed().as_secs_f64(), last: sim }
}

/// Every convergence study: cases 1, 2 (damped and elastic), 4 and 5, all integrators.
pub fn convergence_rows() -> Vec<ErrorRow> {
    let all = Integrator::ALL;
    let mut rows = stokes_drag(&all);
    rows.extend(normal_collision(0.8, &all));
    rows.extend(normal_collision(1.0, &all));
    rows.extend(cohesive_collision(&all).0);
    rows.extend(quadratic_drag(&all));
    rows
}
