//! Running a scene end to end: compile, step, monitor, write outputs.

use crate::Simulation;
use crate::flow::FlowCounter;
use crate::monitor::{Instability, Monitor};
use crate::output::{AgglomeratesCsv, ExtraColumns, ObservablesCsv, TracksCsv};
use crate::progress::Progress;
use crate::vtk::SnapshotWriter;
use std::fmt;
use std::path::{Path, PathBuf};
use std::sync::Arc;
use std::sync::atomic::{AtomicBool, Ordering};
use std::time::Instant;
use tumble_scene::schema::{BackendName, DtSpec};
use tumble_scene::{CompiledScene, Plan, SceneError, compile, read_scene};
use tumble_state::{Frame, State};

/// Options of `tumble run`.
#[derive(Clone, Debug)]
pub struct RunOptions {
    /// Output folder; `None` means `out/<scene name>/`.
    pub out_dir: Option<PathBuf>,
    pub threads: usize,
    /// Overrides `run.duration` when the scene is read from a file ([`run_scene_file`]); a
    /// scene given to [`run_compiled`] already has its plan, and this is not looked at.
    pub duration: Option<f64>,
    /// Overrides `run.dt` (seconds) when the scene is read from a file, as `duration`.
    pub dt: Option<f64>,
    /// Report progress on standard error.
    pub progress: bool,
    /// Draw a redrawn bar (a terminal) rather than plain periodic lines.
    pub terminal: bool,
    /// Set from another thread (Ctrl-C) to stop after the current chunk, with every output flushed.
    pub interrupt: Option<Arc<AtomicBool>>,
    /// Backend; `None` means the scene's `run.backend`.
    pub backend: Option<BackendName>,
    /// Replace the outputs of an earlier tumble run in a non-empty output folder (one holding
    /// tumble's marker file); any other non-empty folder is refused.
    pub overwrite: bool,
}

impl Default for RunOptions {
    fn default() -> Self {
        RunOptions {
            out_dir: None,
            threads: std::thread::available_parallelism().map_or(1, |n| n.get()),
            duration: None,
            dt: None,
            progress: false,
            terminal: false,
            interrupt: None,
            backend: None,
            overwrite: false,
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
    /// Agglomerate statistics at the end, when the plan writes agglomerates.csv.
    pub final_agglomerates: Option<crate::agglomerates::AgglomerateStats>,
    /// Particles that left the domain through its non-periodic sides.
    pub removed: usize,
    /// What the user should know about a run that finished (also in summary.json).
    pub warnings: Vec<String>,
}

#[derive(Debug)]
pub enum RunError {
    Scene(SceneError),
    Io(PathBuf, std::io::Error),
    /// The run went unstable; partial outputs were written.
    Unstable(Instability),
    /// A fixed capacity ran out (contact history slots); outputs so far were written.
    Capacity(String),
    /// Stopped by the user; everything computed so far was written.
    Interrupted {
        step: u64,
        out_dir: PathBuf,
    },
    /// The backend could not be set up (no GPU adapter, scene too large for it).
    Backend(String),
    /// The output folder holds files tumble may not replace; nothing was written.
    OutputFolder(String),
    /// More particles left the domain than `run.max_lost_fraction` allows; outputs so far were written.
    Lost(String),
}

impl fmt::Display for RunError {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self {
            RunError::Scene(e) => write!(f, "{e}"),
            RunError::Io(p, e) => write!(f, "{}: {e}", p.display()),
            RunError::Unstable(e) => write!(f, "{e}"),
            RunError::Capacity(e) => write!(f, "{e}"),
            RunError::Interrupted { step, out_dir } => write!(f, "interrupted at step {step}; outputs so far are in {}", out_dir.display()),
            RunError::Backend(e) => write!(f, "{e}"),
            RunError::OutputFolder(e) => write!(f, "{e}"),
            RunError::Lost(e) => write!(f, "{e}"),
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
    let out_dir = options.out_dir.clone().unwrap_or_else(|| Path::new("out").join(&compiled.plan.run.name));
    let plan_text = compiled.plan.describe(compiled.particles.len());
    let backend = options.backend.unwrap_or(compiled.plan.run.backend);
    // The backend is set up before any file is written: a missing adapter changes nothing.
    let mut sim = Simulation::on(backend, compiled, options.threads).map_err(|e| RunError::Backend(format!("backend {}: {e}", backend.name())))?;
    crate::outdir::prepare(&out_dir, options.overwrite).map_err(RunError::OutputFolder)?;
    io(&out_dir, crate::outdir::write_atomic(&out_dir.join("summary.json"), &running_json(&sim, &plan_text)))?;
    let initial_particles = sim.particles();
    let fluid = sim.plan().model.fluid.is_some();
    let mut obs_csv = io(&out_dir, ObservablesCsv::create(&out_dir, sim.plan()))?;
    let mut tracks_csv = io(&out_dir, TracksCsv::create(&out_dir, sim.plan()))?;
    let mut agglo_csv = match sim.plan().run.agglomerates {
        true => Some(io(&out_dir, AgglomeratesCsv::create(&out_dir, sim.particles()))?),
        false => None,
    };
    let mut last_agglomerates = None;
    let mut snapshots = match sim.plan().run.snapshot_every {
        Some(_) => Some(io(&out_dir, SnapshotWriter::create(&out_dir, sim.plan()))?),
        None => None,
    };
    // Flow planes and agglomerates need the particle arrays at every output row; nothing else does.
    let rows_need_state = !sim.plan().model.flow_planes.is_empty() || sim.plan().run.agglomerates;
    let mut extra = ExtraRows::new(sim.plan());
    let initial = {
        let frame = sim.frame(true);
        let state = frame.state.as_deref().expect("asked for the state");
        let monitor_range = potential_range(sim.plan(), state);
        io(&out_dir, obs_csv.row(&frame.observables, fluid, sim.removed(), &extra.row(sim.plan(), sim.time(), &frame)))?;
        io(&out_dir, tracks_csv.rows(0.0, &frame.tracks))?;
        if let Some(w) = agglo_csv.as_mut() {
            let a = agglomerates_of(sim.plan(), state);
            io(&out_dir, w.row(0.0, &a))?;
            last_agglomerates = Some(a);
        }
        if let Some(w) = snapshots.as_mut() {
            io(&out_dir, w.write(0, &sim, sim.time(), state))?;
        }
        (frame.observables, monitor_range)
    };
    let monitor = Monitor::new(sim.plan(), &initial.0, initial.1);

    let (total, every, snapshot_every) = (sim.plan().run.steps, sim.plan().run.output_every, sim.plan().run.snapshot_every);
    let mut progress = options.progress.then(|| Progress::new(options.terminal, total, sim.plan().run.duration));
    let start = Instant::now();
    let mut particle_steps = 0u128;
    // The starting state is checked before step 1.
    let mut stopped = monitor.check(0, &initial.0).err().map(Stop::Unstable);
    let next = |step: u64, every: u64| (step / every + 1) * every;
    while stopped.is_none() && sim.steps() < total {
        // Advance to the next output or snapshot, in chunks short enough to answer Ctrl-C promptly.
        let mut target = next(sim.steps(), every).min(total);
        if let Some(k) = snapshot_every {
            target = target.min(next(sim.steps(), k));
        }
        let chunk = (target - sim.steps()).min(MAX_CHUNK);
        let n = sim.particles() as u128;
        sim.advance(chunk);
        particle_steps += n * chunk as u128;
        if let Some(fault) = sim.fault() {
            stopped = Some(Stop::Capacity(monitor.explain_fault(fault.to_string())));
            break;
        }
        // Every part of a distributed run stops at the same step.
        if sim.agree(options.interrupt.as_ref().is_some_and(|f| f.load(Ordering::Relaxed))) {
            stopped = Some(Stop::Interrupted);
            break;
        }
        let step = sim.steps();
        let output = step.is_multiple_of(every) || step == total;
        let snapshot = snapshot_every.is_some_and(|k| step.is_multiple_of(k));
        if output || snapshot {
            // One frame (one read-back on a device) serves the monitor, the rows and the snapshot.
            let frame = sim.frame((output && rows_need_state) || snapshot);
            let o = frame.observables;
            if output {
                if let Err(e) = monitor.check(step, &o) {
                    stopped = Some(Stop::Unstable(e));
                    break;
                }
                io(&out_dir, obs_csv.row(&o, fluid, sim.removed(), &extra.row(sim.plan(), sim.time(), &frame)))?;
                if let Some(text) = too_many_lost(sim.plan(), sim.removed(), initial_particles, o.time) {
                    stopped = Some(Stop::Lost(text));
                    break;
                }
                io(&out_dir, tracks_csv.rows(o.time, &frame.tracks))?;
                if let (Some(w), Some(state)) = (agglo_csv.as_mut(), frame.state.as_deref()) {
                    let a = agglomerates_of(sim.plan(), state);
                    io(&out_dir, w.row(o.time, &a))?;
                    last_agglomerates = Some(a);
                }
            }
            // Never write NaN: a non-finite state is stopped by the monitor at the next output.
            if let (true, true, Some(w), Some(k), Some(state)) = (snapshot, o.finite, snapshots.as_mut(), snapshot_every, frame.state.as_deref()) {
                io(&out_dir, w.write((step / k) as usize, &sim, o.time, state))?;
            }
        }
        if let Some(p) = progress.as_mut() {
            p.update(step, sim.time(), particle_steps);
        }
    }
    if let Some(p) = progress.as_mut() {
        p.finish(sim.steps(), sim.time(), particle_steps);
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
        final_agglomerates: last_agglomerates,
        removed: sim.removed(),
        warnings: lost_warning(sim.removed(), initial_particles).into_iter().collect(),
    };
    let stop_text = match &stopped {
        Some(Stop::Unstable(e)) => Some(e.to_string()),
        Some(Stop::Capacity(e)) => Some(e.clone()),
        Some(Stop::Lost(e)) => Some(e.clone()),
        Some(Stop::Interrupted) => {
            Some(format!("interrupted by a signal (Ctrl-C, SIGTERM or SIGHUP) at step {} (t = {:.6e} s)", sim.steps(), sim.time()))
        }
        None => None,
    };
    let status = match &stopped {
        None => "completed",
        Some(Stop::Interrupted) => "interrupted",
        Some(_) => "stopped",
    };
    let json = summary_json(&sim, &summary, &plan_text, status, stop_text);
    // Replaced in one rename: a reader sees the "running" summary or the final one, never half of either.
    io(&out_dir, crate::outdir::write_atomic(&out_dir.join("summary.json"), &json))?;
    match stopped {
        Some(Stop::Unstable(e)) => Err(RunError::Unstable(e)),
        Some(Stop::Capacity(e)) => Err(RunError::Capacity(e)),
        Some(Stop::Lost(e)) => Err(RunError::Lost(e)),
        Some(Stop::Interrupted) => Err(RunError::Interrupted { step: summary.steps, out_dir }),
        None => Ok(summary),
    }
}

/// Agglomerate statistics of state `s` (positions wrapped into the domain).
fn agglomerates_of(plan: &Plan, s: &State) -> crate::agglomerates::AgglomerateStats {
    crate::agglomerates::agglomerates(&s.pos, &s.radius, Some(&plan.model.domain))
}

/// Wall power (mean over the output interval), drum profiles and flow-plane counts.
struct ExtraRows {
    moving: Vec<usize>,
    last: Option<(f64, Vec<f64>)>,
    flow: Option<FlowCounter>,
}

impl ExtraRows {
    fn new(plan: &Plan) -> Self {
        let moving = (0..plan.model.wall_groups.len()).filter(|&g| plan.model.wall_groups[g].moving).collect();
        ExtraRows { moving, last: None, flow: None }
    }

    /// The extra columns of the row at time `t` (the first row starts the flow count).
    fn row(&mut self, plan: &Plan, t: f64, frame: &Frame) -> ExtraColumns {
        // Nothing to add.
        if plan.model.wall_groups.is_empty() && plan.model.drums.is_empty() && plan.model.flow_planes.is_empty() {
            return ExtraColumns::default();
        }
        let work = &frame.wall_work;
        let power = match &self.last {
            // Mean power since the last row: Δ(work) / Δt.
            Some((t0, w0)) if t > *t0 => self.moving.iter().map(|&g| (work[g] - w0[g]) / (t - t0)).collect(),
            // The first row: the power of the initial force pass.
            _ => self.moving.iter().map(|&g| frame.wall_power[g]).collect(),
        };
        self.last = Some((t, work.clone()));
        let flow = match (frame.state.as_deref(), plan.model.flow_planes.is_empty()) {
            (Some(s), false) => match self.flow.as_mut() {
                Some(f) => f.update_state(plan, s, t),
                None => {
                    let f = self.flow.insert(FlowCounter::from_state(plan, s, t));
                    f.mass.iter().map(|&m| (0.0, m)).collect()
                }
            },
            _ => Vec::new(),
        };
        let wall_loads = frame.wall_force.iter().copied().zip(frame.wall_torque.iter().copied()).collect();
        ExtraColumns { power, wall_loads, drums: frame.drums.clone(), flow }
    }
}

/// Most steps advanced between two checks of the interrupt flag and the progress display.
const MAX_CHUNK: u64 = 200;

enum Stop {
    Unstable(Instability),
    Capacity(String),
    Lost(String),
    Interrupted,
}

/// The stop message when more particles have left the domain than the scene allows.
fn too_many_lost(plan: &Plan, removed: usize, initial: usize, t: f64) -> Option<String> {
    let allowed = plan.run.max_lost_fraction * initial as f64;
    (removed as f64 > allowed).then(|| {
        format!(
            "{removed} of {initial} particles ({:.1} %) left the domain through its non-periodic sides by t = {t:.6e} s, more than run.max_lost_fraction = {} allows; check that walls enclose the particles, that lengths are in metres and Δt (or raise run.max_lost_fraction for an open outlet)",
            100.0 * removed as f64 / initial.max(1) as f64,
            plan.run.max_lost_fraction
        )
    })
}

/// The warning of a finished run that lost particles.
fn lost_warning(removed: usize, initial: usize) -> Option<String> {
    (removed > 0).then(|| {
        format!(
            "{removed} of {initial} particles ({:.2} %) left the domain through its non-periodic sides and were removed",
            100.0 * removed as f64 / initial.max(1) as f64
        )
    })
}

/// summary.json while the run goes on: what runs, and that it has not finished.
fn running_json(sim: &Simulation, plan_text: &str) -> String {
    let plan = sim.plan();
    let value = serde_json::json!({
        "scene": plan.run.name,
        "status": "running",
        "backend": sim.backend_name(),
        "particles": sim.particles(),
        "steps": plan.run.steps,
        "dt": plan.model.dt,
        "plan": { "text": plan_text },
    });
    serde_json::to_string_pretty(&value).unwrap() + "\n"
}

/// Σ m |g| × the domain's extent along g: the potential energy gravity can release.
fn potential_range(plan: &Plan, s: &State) -> f64 {
    let g = plan.model.gravity;
    if g == glam::DVec3::ZERO {
        return 0.0;
    }
    let height = (plan.model.domain.extent() * g.abs()).element_sum();
    (0..s.len()).filter(|&i| s.inv_mass[i] != 0.0).map(|i| s.mass[i] * height).sum()
}

fn finite_or_null(x: f64) -> serde_json::Value {
    if x.is_finite() { serde_json::json!(x) } else { serde_json::Value::Null }
}

fn summary_json(sim: &Simulation, s: &RunSummary, plan_text: &str, status: &str, stopped: Option<String>) -> String {
    let plan = sim.plan();
    let o = &s.final_observables;
    let features: serde_json::Map<String, serde_json::Value> =
        plan.report.features.iter().map(|f| (f.name.to_string(), serde_json::json!({ "active": f.active, "reason": f.reason }))).collect();
    let value = serde_json::json!({
        "scene": plan.run.name,
        "status": status,
        "backend": sim.backend_name(),
        "device": sim.device_name(),
        "precision": sim.precision(),
        "particles": s.particles,
        "steps": s.steps,
        "dt": plan.model.dt,
        "simulated_time": sim.time(),
        "wall_seconds": s.wall_seconds,
        "particle_steps_per_second": finite_or_null(s.particle_steps_per_second),
        "removed_particles": sim.removed(),
        "max_lost_fraction": plan.run.max_lost_fraction,
        "warnings": s.warnings,
        "neighbour_list_builds": sim.neighbour_builds(),
        "adapter": sim.adapter().map(|a| serde_json::json!({ "name": a.name, "backend": a.backend, "driver": a.driver, "device_type": a.device_type })),
        "memory_bytes": sim.memory_bytes(),
        "bytes_per_particle": sim.bytes_per_particle(),
        "plan": {
            "integrator": plan.model.integrator.name(),
            "collision_time": plan.report.timescales.collision_time,
            "stability_limit": plan.report.timescales.stability_limit,
            "steps_per_collision": plan.steps_per_collision(),
            "cell_size": plan.tuning.cell_size,
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
        "stopped": stopped,
    });
    let mut value = value;
    if let Some(a) = &s.final_agglomerates {
        value["agglomerates"] = serde_json::json!({
            "count": a.count,
            "mean_size": a.mean_size,
            "weighted_mean_size": a.weighted_mean_size,
            "max_size": a.max_size,
            "mean_void_fraction": a.mean_void_fraction,
            "mean_void_fraction_multi": a.mean_void_fraction_multi,
            "wrapping": a.wrapping,
        });
    }
    if let Some(tg) = &plan.report.targets.taylor_green {
        value["plan"]["mean_flow_speed"] = serde_json::json!(tg.mean_flow_speed);
        value["plan"]["vortex_size"] = serde_json::json!(tg.vortex_size);
        value["plan"]["stokes_number"] = serde_json::json!(tg.stokes_number);
    }
    if let Some(sy) = &plan.report.targets.stickiness {
        value["plan"]["stickiness_number"] = serde_json::json!(sy.number);
        value["plan"]["cohesion_stiffness"] = serde_json::json!(sy.stiffness);
    }
    serde_json::to_string_pretty(&value).unwrap() + "\n"
}
