//! Running a scene end to end: compile, step, monitor, write outputs.

use crate::monitor::{Instability, Monitor};
use crate::output::{ObservablesCsv, TracksCsv};
use crate::Simulation;
use std::fmt;
use std::path::{Path, PathBuf};
use std::time::Instant;
use tumble_scene::schema::DtSpec;
use tumble_scene::{CompiledScene, SceneError, compile, read_scene};

/// Options of `tumble run`.
#[derive(Clone, Debug)]
pub struct RunOptions {
    /// Output folder; `None` means `out/<scene name>/`.
    pub out_dir: Option<PathBuf>,
    pub threads: usize,
    pub duration: Option<f64>,
    pub dt: Option<f64>,
    /// Print periodic progress lines to standard error.
    pub progress: bool,
}

impl Default for RunOptions {
    fn default() -> Self {
        RunOptions {
            out_dir: None,
            threads: std::thread::available_parallelism().map_or(1, |n| n.get()),
            duration: None,
            dt: None,
            progress: false,
        }
    }
}

/// What a finished run reports (also written as summary.json).
#[derive(Clone, Debug)]
pub struct RunSummary {
    pub out_dir: PathBuf,
    pub steps: u64,
    pub particles: usize,
    pub wall_seconds: f64,
    pub particle_steps_per_second: f64,
    pub final_observables: crate::Observables,
}

#[derive(Debug)]
pub enum RunError {
    Scene(SceneError),
    Io(PathBuf, std::io::Error),
    /// The run went unstable; partial outputs were written.
    Unstable(Instability),
}

impl fmt::Display for RunError {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self {
            RunError::Scene(e) => write!(f, "{e}"),
            RunError::Io(p, e) => write!(f, "{}: {e}", p.display()),
            RunError::Unstable(e) => write!(f, "{e}"),
        }
    }
}

impl std::error::Error for RunError {}

/// Reads, overrides (duration, dt) and compiles a scene file.
pub fn load_scene(path: &Path, duration: Option<f64>, dt: Option<f64>) -> Result<CompiledScene, SceneError> {
    let mut scene = read_scene(path)?;
    if let Some(d) = duration {
        scene.run.duration = d;
    }
    if let Some(dt) = dt {
        scene.run.dt = Some(DtSpec::Seconds(dt));
    }
    compile(&scene).map_err(|e| e.in_file(path))
}

/// Runs a scene file with the given options.
pub fn run_scene_file(path: &Path, options: &RunOptions) -> Result<RunSummary, RunError> {
    let compiled = load_scene(path, options.duration, options.dt).map_err(RunError::Scene)?;
    run_compiled(compiled, options)
}

fn io<T>(path: &Path, r: std::io::Result<T>) -> Result<T, RunError> {
    r.map_err(|e| RunError::Io(path.to_path_buf(), e))
}

/// Runs a compiled scene, writing outputs into the chosen folder.
pub fn run_compiled(compiled: CompiledScene, options: &RunOptions) -> Result<RunSummary, RunError> {
    let out_dir = options.out_dir.clone().unwrap_or_else(|| Path::new("out").join(&compiled.plan.name));
    io(&out_dir, std::fs::create_dir_all(&out_dir))?;
    let plan_text = compiled.plan.describe(compiled.particles.len());
    let mut sim = Simulation::new(compiled, options.threads);
    let fluid = sim.plan().fluid.is_some();
    let mut obs_csv = io(&out_dir, ObservablesCsv::create(&out_dir, fluid))?;
    let mut tracks_csv = io(&out_dir, TracksCsv::create(&out_dir))?;
    let initial = sim.observables();
    let monitor = Monitor::new(sim.plan(), &initial, potential_range(&sim));
    io(&out_dir, obs_csv.row(&initial, fluid))?;
    io(&out_dir, tracks_csv.rows(0.0, &sim.tracks()))?;

    let (total, every) = (sim.plan().steps, sim.plan().output_every);
    let start = Instant::now();
    let mut last_report = Instant::now();
    let mut particle_steps = 0u128;
    let mut stopped = None;
    while sim.steps() < total {
        let chunk = every.min(total - sim.steps());
        let n = sim.particles() as u128;
        sim.advance(chunk);
        particle_steps += n * chunk as u128;
        let o = sim.observables();
        if let Err(e) = monitor.check(sim.steps(), &o) {
            stopped = Some(e);
            break;
        }
        io(&out_dir, obs_csv.row(&o, fluid))?;
        io(&out_dir, tracks_csv.rows(o.time, &sim.tracks()))?;
        if options.progress && last_report.elapsed().as_secs_f64() > 2.0 {
            last_report = Instant::now();
            let wall = start.elapsed().as_secs_f64();
            eprintln!(
                "t = {:.4e} s ({:.0} %), {:.0} steps/s, {:.3e} particle-steps/s",
                o.time,
                100.0 * sim.steps() as f64 / total as f64,
                sim.steps() as f64 / wall,
                particle_steps as f64 / wall
            );
        }
    }
    let wall_seconds = start.elapsed().as_secs_f64();
    let final_observables = sim.observables();
    let summary = RunSummary {
        out_dir: out_dir.clone(),
        steps: sim.steps(),
        particles: sim.particles(),
        wall_seconds,
        particle_steps_per_second: particle_steps as f64 / wall_seconds.max(1e-12),
        final_observables,
    };
    let json = summary_json(&sim, &summary, &plan_text, stopped.as_ref());
    io(&out_dir, std::fs::write(out_dir.join("summary.json"), json))?;
    match stopped {
        Some(e) => Err(RunError::Unstable(e)),
        None => Ok(summary),
    }
}

/// Σ m |g| × the domain's extent along g: the potential energy gravity can release.
fn potential_range(sim: &Simulation) -> f64 {
    let plan = sim.plan();
    let g = plan.gravity;
    if g == glam::DVec3::ZERO {
        return 0.0;
    }
    let height = (plan.domain.extent() * g.abs()).element_sum();
    let s = sim.cpu().state();
    (0..s.len()).filter(|&i| s.inv_mass[i] != 0.0).map(|i| s.mass[i] * height).sum()
}

fn finite_or_null(x: f64) -> serde_json::Value {
    if x.is_finite() { serde_json::json!(x) } else { serde_json::Value::Null }
}

fn summary_json(sim: &Simulation, s: &RunSummary, plan_text: &str, stopped: Option<&Instability>) -> String {
    let plan = sim.plan();
    let o = &s.final_observables;
    let features: serde_json::Map<String, serde_json::Value> = plan
        .features
        .iter()
        .map(|f| (f.name.to_string(), serde_json::json!({ "active": f.active, "reason": f.reason })))
        .collect();
    let value = serde_json::json!({
        "scene": plan.name,
        "backend": sim.backend_name(),
        "device": sim.device_name(),
        "precision": sim.precision(),
        "particles": s.particles,
        "steps": s.steps,
        "dt": plan.dt,
        "simulated_time": sim.time(),
        "wall_seconds": s.wall_seconds,
        "particle_steps_per_second": finite_or_null(s.particle_steps_per_second),
        "removed_particles": sim.removed(),
        "neighbour_list_builds": sim.cpu().neighbour_builds(),
        "plan": {
            "integrator": plan.integrator.name(),
            "collision_time": plan.timescales.collision_time,
            "stability_limit": plan.timescales.stability_limit,
            "steps_per_collision": plan.steps_per_collision(),
            "cell_size": plan.cell_size,
            "memory_bytes": plan.memory_bytes(s.particles),
            "features": features,
            "text": plan_text,
        },
        "final": {
            "kinetic_energy": finite_or_null(o.kinetic_energy),
            "rotational_energy": finite_or_null(o.rotational_energy),
            "potential_energy": finite_or_null(o.potential_energy),
            "elastic_energy": finite_or_null(o.elastic_energy),
            "dissipated_energy": finite_or_null(o.dissipated_energy),
            "contacts": o.contacts,
        },
        "stopped": stopped.map(|e| e.to_string()),
    });
    serde_json::to_string_pretty(&value).unwrap() + "\n"
}
