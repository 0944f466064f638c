//! Running a scene end to end: the options, the summary and errors, setting a run up (seeded
//! from another run's checkpoint when the scene says so); the step loop is run_loop.rs and
//! continuing from a checkpoint resume.rs.

use crate::Simulation;
use crate::checkpoint::SceneRecord;
use crate::monitor::Instability;
use crate::run_loop::{Books, Outputs, Run};
use crate::summary::running_json;
use std::fmt;
use std::path::{Path, PathBuf};
use std::sync::Arc;
use std::sync::atomic::AtomicBool;
use tumble_scene::schema::{BackendName, DtSpec};
use tumble_scene::{CompiledScene, Plan, SceneError, compile, parse_scene, read_scene_text};
use tumble_state::{OutputRequest, PhaseStop, State};

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
    /// Simulated seconds between checkpoints; overrides `run.checkpoint_interval`.
    pub checkpoint_interval: Option<f64>,
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
            checkpoint_interval: None,
        }
    }
}

/// What a finished run reports (also written as summary.json).
#[derive(Clone, Debug)]
pub struct RunSummary {
    pub out_dir: PathBuf,
    pub steps: u64,
    pub particles: usize,
    /// Each phase beside the particles: its name and moving particles (the fluid's).
    pub phase_particles: Vec<(&'static str, usize)>,
    pub wall_seconds: f64,
    pub particle_steps_per_second: f64,
    pub final_observables: crate::Observables,
    /// Agglomerate statistics at the end, when the plan writes agglomerates.csv.
    pub final_agglomerates: Option<crate::agglomerates::AgglomerateStats>,
    /// Particles that left the domain through its non-periodic sides.
    pub removed: usize,
    /// What the user should know about a run that finished (also in summary.json).
    pub warnings: Vec<String>,
    /// The step of the checkpoint this run was resumed from.
    pub resumed_from_step: Option<u64>,
    /// Why the run ended before its duration (`run.end_when`), if it did.
    pub ended_early: Option<String>,
    /// The checkpoints this run wrote, when checkpoints are on.
    pub checkpoints: Option<CheckpointReport>,
    /// In a coupled run, the wall time of the fluid, the coupling and the particles.
    pub step_seconds: Option<crate::coupler::StepSeconds>,
}

/// The checkpoints one `tumble run` or `tumble resume` wrote.
#[derive(Clone, Debug, Default)]
pub struct CheckpointReport {
    pub every_steps: u64,
    pub written: usize,
    pub last: Option<PathBuf>,
    /// Size of the last checkpoint on disk.
    pub last_bytes: u64,
    /// Wall time spent writing checkpoints (snapshot, encoding, write, fsync).
    pub seconds: f64,
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
    /// The run ended, but a source never inserted a particle (its region had no room) and the
    /// scene does not allow it; the outputs were written.
    Idle(String),
    /// A run cannot be resumed (no checkpoint, a damaged or mismatched one); nothing was changed.
    Resume(String),
    /// A phase beside the particles (the SPH fluid) stopped: its cause and a Δt that works;
    /// outputs so far were written.
    Phase(String),
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
            RunError::Idle(e) => write!(f, "{e}"),
            RunError::Resume(e) => write!(f, "cannot resume: {e}"),
            RunError::Phase(e) => write!(f, "{e}"),
        }
    }
}

impl std::error::Error for RunError {}

/// Reads, overrides (duration, dt) and compiles a scene file.
pub fn load_scene(path: &Path, duration: Option<f64>, dt: Option<f64>) -> Result<CompiledScene, SceneError> {
    compile_text(&read_scene_text(path)?, path, duration, dt)
}

/// Scene text from the file `path`, parsed, overridden (duration, dt) and compiled; errors name `path`.
pub(crate) fn compile_text(text: &str, path: &Path, duration: Option<f64>, dt: Option<f64>) -> Result<CompiledScene, SceneError> {
    let mut scene = parse_scene(text).map_err(|e| e.in_file(path))?;
    scene.folder = path.parent().map(Path::to_path_buf);
    if let Some(d) = duration {
        scene.run.duration = d;
    }
    if let Some(dt) = dt {
        scene.run.dt = Some(DtSpec::Seconds(dt));
    }
    compile(&scene).map_err(|e| e.in_file(path))
}

/// Runs a scene file with the given options; its text is recorded in the run's checkpoints.
pub fn run_scene_file(path: &Path, options: &RunOptions) -> Result<RunSummary, RunError> {
    let (compiled, record) = load_recorded(path, options).map_err(RunError::Scene)?;
    run_recorded(compiled, Some(record), options)
}

/// A scene file compiled with the overrides of `options` ([`load_scene`]), and the record of
/// it that the run's checkpoints keep, from one reading of the file.
pub fn load_recorded(path: &Path, options: &RunOptions) -> Result<(CompiledScene, SceneRecord), SceneError> {
    let text = read_scene_text(path)?;
    let compiled = compile_text(&text, path, options.duration, options.dt)?;
    let record = SceneRecord {
        path: std::fs::canonicalize(path).unwrap_or_else(|_| path.to_path_buf()),
        inputs: crate::checkpoint::scene_inputs(&text, path),
        text,
        duration: options.duration,
        dt: options.dt,
        checkpoint_interval: options.checkpoint_interval,
    };
    Ok((compiled, record))
}

pub(crate) fn io<T>(path: &Path, r: std::io::Result<T>) -> Result<T, RunError> {
    r.map_err(|e| RunError::Io(path.to_path_buf(), e))
}

/// Runs a compiled scene, writing outputs into the chosen folder. Its checkpoints (when on)
/// record no scene text: `tumble resume` needs a run started from a file ([`run_scene_file`]).
pub fn run_compiled(compiled: CompiledScene, options: &RunOptions) -> Result<RunSummary, RunError> {
    run_recorded(compiled, None, options)
}

/// Runs a compiled scene whose source `scene` (from [`scene_record`]) its checkpoints record.
pub fn run_recorded(compiled: CompiledScene, scene: Option<SceneRecord>, options: &RunOptions) -> Result<RunSummary, RunError> {
    let out_dir = options.out_dir.clone().unwrap_or_else(|| Path::new("out").join(&compiled.plan.run.name));
    let plan_text = compiled.plan.describe(compiled.particles.len());
    let backend = options.backend.unwrap_or(compiled.plan.run.backend);
    // The backend is set up before any file is written: a missing adapter changes nothing.
    let (sim, seed_warnings) = set_up(backend, compiled, options.threads, true)?;
    crate::outdir::prepare(&out_dir, options.overwrite).map_err(RunError::OutputFolder)?;
    io(&out_dir, crate::outdir::write_atomic(&out_dir.join("summary.json"), &running_json(&sim, &plan_text)))?;
    let outputs = io(&out_dir, Outputs::open(&out_dir, &sim, None))?;
    let checkpoint_every = checkpoint_every(sim.plan(), options.checkpoint_interval.or(scene.as_ref().and_then(|s| s.checkpoint_interval)));
    let series = sim.plan().run.snapshot_every.is_some();
    let mut run = Run::new(sim, out_dir, options, Books::default(), outputs, scene, plan_text, None, checkpoint_every);
    run.warnings = seed_warnings;
    // The starting state is written, then checked before step 1.
    let stopped = run.rows(OutputRequest { step: 0, row: true, series, start: true })?;
    // A checkpoint at step 0 makes any run with checkpoints resumable, however early it is killed.
    run.go(stopped, true)
}

/// The scene on `backend`, its particles taken from `run.start.from` when the scene names a
/// checkpoint there and `seed` is set; the warnings say what the seed did not carry over.
pub(crate) fn set_up(backend: BackendName, compiled: CompiledScene, threads: usize, seed: bool) -> Result<(Simulation, Vec<String>), RunError> {
    let on = |e: tumble_gpu::GpuError| RunError::Backend(format!("backend {}: {e}", backend.name()));
    let Some(from) = compiled.plan.run.start_from.clone().filter(|_| seed) else {
        return Ok((Simulation::on(backend, compiled, threads).map_err(on)?, Vec::new()));
    };
    let seed_error = |e: String| RunError::Scene(SceneError::field("run.start.from", e));
    let state = crate::seed::read_state(Path::new(&from)).map_err(seed_error)?;
    let (compiled, state, warnings) = crate::seed::seeded(compiled, &state).map_err(seed_error)?;
    Ok((Simulation::from_state(backend, compiled, state, threads).map_err(on)?, warnings))
}

/// Steps between checkpoints: the command's interval, else the scene's.
pub(crate) fn checkpoint_every(plan: &Plan, interval: Option<f64>) -> Option<u64> {
    match interval {
        Some(s) => Some(((s / plan.model.dt).round() as u64).max(1)),
        None => plan.run.checkpoint_every,
    }
}

/// Agglomerate statistics of state `s` (positions wrapped into the domain).
pub(crate) fn agglomerates_of(plan: &Plan, s: &State) -> crate::agglomerates::AgglomerateStats {
    crate::agglomerates::agglomerates(&s.pos, &s.radius, Some(&plan.model.domain))
}

pub(crate) enum Stop {
    /// The scene's `run.end_when` was met: a completed run.
    Ended(String),
    Unstable(Instability),
    Capacity(String),
    Lost(String),
    /// A phase stopped (its cause and a Δt that works).
    Phase(String),
    /// The run reached its end, but a source never found room to insert a particle.
    Idle(String),
    Interrupted,
}

impl From<PhaseStop> for Stop {
    fn from(why: PhaseStop) -> Self {
        match why {
            PhaseStop::Unstable(e) => Stop::Unstable(e),
            PhaseStop::Capacity(e) => Stop::Capacity(e),
            PhaseStop::Lost(e) => Stop::Lost(e),
            PhaseStop::Ended(e) => Stop::Ended(e),
            PhaseStop::Failed(e) => Stop::Phase(e),
        }
    }
}

/// The stop message when more particles have left the domain than the scene allows.
pub(crate) fn too_many_lost(plan: &Plan, removed: usize, initial: usize, t: f64) -> Option<String> {
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
pub(crate) fn lost_warning(removed: usize, initial: usize) -> Option<String> {
    (removed > 0).then(|| {
        format!(
            "{removed} of {initial} particles ({:.2} %) left the domain through its non-periodic sides and were removed",
            100.0 * removed as f64 / initial.max(1) as f64
        )
    })
}

/// Σ m |g| × the domain's extent along g: the potential energy gravity can release.
pub(crate) fn potential_range(plan: &Plan, s: &State) -> f64 {
    let g = plan.model.gravity;
    if g == glam::DVec3::ZERO {
        return 0.0;
    }
    let height = (plan.model.domain.extent() * g.abs()).element_sum();
    (0..s.len()).filter(|&i| s.inv_mass[i] != 0.0).map(|i| s.mass[i] * height).sum()
}
