//! Running a scene end to end: compile, step, monitor, write outputs and checkpoints; resume a
//! run from its newest checkpoint.

use crate::Simulation;
use crate::agglomerates::AgglomerateStats;
use crate::checkpoint::{self, Checkpoint, CheckpointHeader, SceneRecord};
use crate::flow::FlowCounter;
use crate::monitor::{Instability, Monitor};
use crate::output::{AgglomeratesCsv, ExtraColumns, ObservablesCsv, TracksCsv};
use crate::progress::Progress;
use crate::summary::{running_json, summary_json};
use crate::vtk::{SeriesIndex, SnapshotWriter};
use serde::{Deserialize, Serialize};
use std::fmt;
use std::path::{Path, PathBuf};
use std::sync::Arc;
use std::sync::atomic::{AtomicBool, Ordering};
use std::time::Instant;
use tumble_scene::schema::{BackendName, DtSpec};
use tumble_scene::{CompiledScene, Plan, Scene, SceneError, compile, parse_scene, read_scene};
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
    /// A run cannot be resumed (no checkpoint, a damaged or mismatched one); nothing was changed.
    Resume(String),
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
            RunError::Resume(e) => write!(f, "cannot resume: {e}"),
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

/// Runs a scene file with the given options; its text is recorded in the run's checkpoints.
pub fn run_scene_file(path: &Path, options: &RunOptions) -> Result<RunSummary, RunError> {
    let compiled = load_scene(path, options.duration, options.dt).map_err(RunError::Scene)?;
    let record = scene_record(path, options)?;
    run_recorded(compiled, Some(record), options)
}

/// The scene file `path` as a checkpoint records it, with the overrides of `options`.
pub fn scene_record(path: &Path, options: &RunOptions) -> Result<SceneRecord, RunError> {
    let text = std::fs::read_to_string(path).map_err(|e| RunError::Io(path.to_path_buf(), e))?;
    Ok(SceneRecord {
        path: std::fs::canonicalize(path).unwrap_or_else(|_| path.to_path_buf()),
        text,
        duration: options.duration,
        dt: options.dt,
        checkpoint_interval: options.checkpoint_interval,
    })
}

fn io<T>(path: &Path, r: std::io::Result<T>) -> Result<T, RunError> {
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
    let (sim, seed_warnings) = set_up(backend, compiled, options.threads)?;
    crate::outdir::prepare(&out_dir, options.overwrite).map_err(RunError::OutputFolder)?;
    io(&out_dir, crate::outdir::write_atomic(&out_dir.join("summary.json"), &running_json(&sim, &plan_text)))?;
    let initial_particles = sim.particles();
    let mut outputs = io(&out_dir, Outputs::open(&out_dir, sim.plan(), initial_particles, None))?;
    let mut extra = ExtraRows::new(sim.plan());
    let mut last_agglomerates = None;
    let (initial, monitor_range) = {
        let frame = sim.frame(true);
        let state = frame.state.as_deref().expect("asked for the state");
        let monitor_range = potential_range(sim.plan(), state);
        let fluid = sim.plan().model.fluid.is_some();
        io(&out_dir, outputs.obs.row(&frame.observables, fluid, sim.removed(), &extra.row(sim.plan(), sim.time(), &frame)))?;
        io(&out_dir, outputs.tracks.rows(0.0, &frame.tracks))?;
        if let Some(w) = outputs.agglo.as_mut() {
            let a = agglomerates_of(sim.plan(), state);
            io(&out_dir, w.row(0.0, &a))?;
            last_agglomerates = Some(a);
        }
        if let Some(w) = outputs.snapshots.as_mut() {
            io(&out_dir, w.write(0, &sim, sim.time(), state))?;
        }
        (frame.observables, monitor_range)
    };
    let monitor = Monitor::new(sim.plan(), &initial, monitor_range);
    // The starting state is checked before step 1.
    let stopped = monitor.check(0, &initial).err().map(Stop::Unstable);
    let books = Books { initial_particles, monitor, extra, last_agglomerates, files: Vec::new(), series: Vec::new() };
    let checkpoint_every = checkpoint_every(sim.plan(), options.checkpoint_interval.or(scene.as_ref().and_then(|s| s.checkpoint_interval)));
    let mut run = Run::new(sim, out_dir, options, books, outputs, scene, plan_text, None, checkpoint_every);
    run.warnings = seed_warnings;
    // A checkpoint at step 0 makes any run with checkpoints resumable, however early it is killed.
    run.go(stopped, true)
}

/// The scene on `backend`, its particles taken from `run.start.from` when the scene names a
/// checkpoint there; the warnings say what the seed did not carry over.
fn set_up(backend: BackendName, compiled: CompiledScene, threads: usize) -> Result<(Simulation, Vec<String>), RunError> {
    let on = |e: tumble_gpu::GpuError| RunError::Backend(format!("backend {}: {e}", backend.name()));
    let Some(from) = compiled.plan.run.start_from.clone() else {
        return Ok((Simulation::on(backend, compiled, threads).map_err(on)?, Vec::new()));
    };
    let seed_error = |e: String| RunError::Scene(SceneError::field("run.start.from", e));
    let state = crate::seed::read_state(Path::new(&from)).map_err(seed_error)?;
    let (compiled, state, warnings) = crate::seed::seeded(compiled, &state).map_err(seed_error)?;
    Ok((Simulation::from_state(backend, compiled, state, threads).map_err(on)?, warnings))
}

/// Steps between checkpoints: the command's interval, else the scene's.
fn checkpoint_every(plan: &Plan, interval: Option<f64>) -> Option<u64> {
    match interval {
        Some(s) => Some(((s / plan.model.dt).round() as u64).max(1)),
        None => plan.run.checkpoint_every,
    }
}

/// Continues the run in `dir` from its newest checkpoint, appending to its files.
///
/// The scene is the one the run started with (recorded in the checkpoint); `options.duration`
/// may extend it, `options.threads` is free (the CPU's results do not depend on it), and the
/// backend must be the one that wrote the checkpoint. A refusal changes nothing in `dir`.
pub fn resume_run(dir: &Path, options: &RunOptions) -> Result<RunSummary, RunError> {
    let refuse = RunError::Resume;
    if !dir.join(crate::outdir::MARKER).is_file() {
        return Err(refuse(format!("{}: not the output folder of a tumble run (no {} marker)", dir.display(), crate::outdir::MARKER)));
    }
    let (path, Checkpoint { header: cp, snapshot }) = checkpoint::newest(dir).map_err(refuse)?;
    let shown = path.display();
    let Some(mut record) = cp.scene.clone() else {
        return Err(refuse(format!(
            "{shown}: the checkpoint records no scene (the run was started through the library's run_compiled); run_scene_file records it"
        )));
    };
    if let Ok(now) = std::fs::read_to_string(&record.path)
        && now != record.text
    {
        return Err(refuse(format!(
            "{}: the scene file changed since the run in {} started, and a run continues only the scene it started with; restore the file, or start a new run with tumble run",
            record.path.display(),
            dir.display()
        )));
    }
    if options.dt.is_some_and(|dt| Some(dt) != record.dt) {
        return Err(refuse(format!("{shown}: a resumed run keeps the dt it started with; leave out --dt")));
    }
    let backend = match cp.backend.as_str() {
        "cpu" => BackendName::Cpu,
        "gpu" => BackendName::Gpu,
        other => return Err(refuse(format!("{shown}: written by an unknown backend `{other}`"))),
    };
    if options.backend.is_some_and(|b| b != backend) {
        return Err(refuse(format!("{shown}: written by the {} backend; a run continues on the backend that started it", backend.name())));
    }
    if options.duration.is_some() {
        record.duration = options.duration;
    }
    if options.checkpoint_interval.is_some() {
        record.checkpoint_interval = options.checkpoint_interval;
    }
    let compiled = compile_record(&record).map_err(RunError::Scene)?;
    let plan_text = compiled.plan.describe(compiled.particles.len());
    let books: Books = postcard::from_bytes(&cp.books).map_err(|e| refuse(format!("{shown}: the run's books cannot be decoded: {e}")))?;
    let folder_scene = std::fs::read_to_string(dir.join("summary.json"))
        .ok()
        .and_then(|t| serde_json::from_str::<serde_json::Value>(&t).ok())
        .and_then(|v| v["scene"].as_str().map(str::to_string));
    if let Some(name) = folder_scene
        && name != snapshot.scene
    {
        return Err(refuse(format!("{shown}: a checkpoint of scene `{}`, but the run in {} is scene `{name}`", snapshot.scene, dir.display())));
    }
    // The restore replaces every particle on the CPU; a device's arrays are sized to the seed's
    // particles, so a seeded GPU run is set up seeded again (its seed must still be there).
    let mut sim = match backend {
        BackendName::Cpu => Simulation::on(backend, compiled, options.threads).map_err(|e| RunError::Backend(format!("backend cpu: {e}")))?,
        BackendName::Gpu => set_up(backend, compiled, options.threads)?.0,
    };
    sim.restore(&snapshot).map_err(|e| refuse(format!("{shown}: {e}")))?;
    let total = sim.plan().run.steps;
    if sim.steps() >= total {
        return Err(refuse(format!(
            "{shown}: the run already reached its end (step {}, t = {:.6e} s); pass --duration longer than {} s to continue it",
            sim.steps(),
            sim.time(),
            sim.plan().run.duration
        )));
    }
    check_files(dir, &books).map_err(refuse)?;
    io(dir, checkpoint::remove_unfinished(dir))?;
    let outputs = io(dir, Outputs::open(dir, sim.plan(), books.initial_particles, Some(&books)))?;
    io(dir, crate::outdir::write_atomic(&dir.join("summary.json"), &running_json(&sim, &plan_text)))?;
    let checkpoint_every = checkpoint_every(sim.plan(), record.checkpoint_interval);
    let mut run = Run::new(sim, dir.to_path_buf(), options, books, outputs, Some(record), plan_text, Some(cp.step), checkpoint_every);
    if cp.tumble_version != env!("CARGO_PKG_VERSION") {
        run.warnings.push(format!(
            "resumed from a checkpoint of tumble {} with tumble {}: the continuation is not guaranteed to be bit-identical",
            cp.tumble_version,
            env!("CARGO_PKG_VERSION")
        ));
    }
    run.go(None, false)
}

/// The recorded scene compiled with the recorded overrides.
fn compile_record(record: &SceneRecord) -> Result<CompiledScene, SceneError> {
    let mut scene: Scene = parse_scene(&record.text).map_err(|e| e.in_file(&record.path))?;
    if let Some(d) = record.duration {
        scene.run.duration = d;
    }
    if let Some(dt) = record.dt {
        scene.run.dt = Some(DtSpec::Seconds(dt));
    }
    compile(&scene).map_err(|e| e.in_file(&record.path))
}

/// Refuses a folder whose output files are shorter than the checkpoint says they were.
fn check_files(dir: &Path, books: &Books) -> Result<(), String> {
    for (name, len) in &books.files {
        let path = dir.join(name);
        let now = std::fs::metadata(&path).map_err(|e| format!("{}: {e}; the output folder was changed after the checkpoint", path.display()))?.len();
        if now < *len {
            return Err(format!("{}: {now} bytes, but {len} at the checkpoint; the output folder was changed after the checkpoint", path.display()));
        }
    }
    Ok(())
}

/// What the run loop keeps besides the backend's state; a checkpoint carries it.
#[derive(Serialize, Deserialize)]
struct Books {
    initial_particles: usize,
    monitor: Monitor,
    extra: ExtraRows,
    last_agglomerates: Option<AgglomerateStats>,
    /// Each output file (relative to the folder) and its length in bytes when the books were taken.
    files: Vec<(String, u64)>,
    series: SeriesIndex,
}

/// The run's output files.
struct Outputs {
    obs: ObservablesCsv,
    tracks: TracksCsv,
    agglo: Option<AgglomeratesCsv>,
    snapshots: Option<SnapshotWriter>,
}

impl Outputs {
    /// New files, or (`resume`) the files of an earlier part cut back to its checkpoint.
    fn open(dir: &Path, plan: &Plan, initial_particles: usize, resume: Option<&Books>) -> std::io::Result<Self> {
        if let Some(books) = resume {
            for (name, len) in &books.files {
                std::fs::OpenOptions::new().write(true).open(dir.join(name))?.set_len(*len)?;
            }
        }
        let append = resume.is_some();
        let agglo = match plan.run.agglomerates {
            true => Some(AgglomeratesCsv::open(dir, initial_particles, append)?),
            false => None,
        };
        let snapshots = match (plan.run.snapshot_every, resume) {
            (None, _) => None,
            (Some(_), None) => Some(SnapshotWriter::create(dir, plan)?),
            (Some(_), Some(books)) => Some(SnapshotWriter::reopen(dir, plan, books.series.clone())?),
        };
        Ok(Outputs { obs: ObservablesCsv::open(dir, plan, append)?, tracks: TracksCsv::open(dir, plan, append)?, agglo, snapshots })
    }

    /// The length of each CSV file now (every row is flushed as it is written).
    fn lengths(&self, dir: &Path) -> std::io::Result<Vec<(String, u64)>> {
        let mut names = vec!["observables.csv", "tracks.csv"];
        if self.agglo.is_some() {
            names.push("agglomerates.csv");
        }
        names.into_iter().map(|n| Ok((n.to_string(), std::fs::metadata(dir.join(n))?.len()))).collect()
    }
}

/// One `tumble run` or `tumble resume`: the simulation, its outputs and its books.
struct Run<'o> {
    sim: Simulation,
    out_dir: PathBuf,
    options: &'o RunOptions,
    books: Books,
    outputs: Outputs,
    scene: Option<SceneRecord>,
    plan_text: String,
    resumed_from: Option<u64>,
    checkpoint_every: Option<u64>,
    checkpoints: CheckpointReport,
    warnings: Vec<String>,
    /// Flow planes and agglomerates need the particle arrays at every output row; nothing else does.
    rows_need_state: bool,
}

impl<'o> Run<'o> {
    #[allow(clippy::too_many_arguments)]
    fn new(
        sim: Simulation,
        out_dir: PathBuf,
        options: &'o RunOptions,
        books: Books,
        outputs: Outputs,
        scene: Option<SceneRecord>,
        plan_text: String,
        resumed_from: Option<u64>,
        checkpoint_every: Option<u64>,
    ) -> Self {
        let rows_need_state = !sim.plan().model.flow_planes.is_empty() || sim.plan().run.agglomerates;
        let checkpoints = CheckpointReport { every_steps: checkpoint_every.unwrap_or(0), ..Default::default() };
        Run {
            sim,
            out_dir,
            options,
            books,
            outputs,
            scene,
            plan_text,
            resumed_from,
            checkpoint_every,
            checkpoints,
            warnings: Vec::new(),
            rows_need_state,
        }
    }

    /// Steps to the end, writing rows, snapshots and checkpoints; `stopped` is a stop found before step 1.
    fn go(mut self, mut stopped: Option<Stop>, checkpoint_first: bool) -> Result<RunSummary, RunError> {
        if stopped.is_none() && checkpoint_first && self.checkpoint_every.is_some() {
            self.checkpoint()?;
        }
        let plan = self.sim.plan();
        let (total, every, snapshot_every) = (plan.run.steps, plan.run.output_every, plan.run.snapshot_every);
        let mut progress = self.options.progress.then(|| Progress::new(self.options.terminal, total, plan.run.duration));
        let start = Instant::now();
        let mut particle_steps = 0u128;
        let next = |step: u64, every: u64| (step / every + 1) * every;
        while stopped.is_none() && self.sim.steps() < total {
            // Advance to the next output, snapshot or checkpoint, in chunks short enough to answer Ctrl-C promptly.
            let mut target = next(self.sim.steps(), every).min(total);
            for k in [snapshot_every, self.checkpoint_every].into_iter().flatten() {
                target = target.min(next(self.sim.steps(), k));
            }
            let chunk = (target - self.sim.steps()).min(MAX_CHUNK);
            let n = self.sim.particles() as u128;
            self.sim.advance(chunk);
            particle_steps += n * chunk as u128;
            if let Some(fault) = self.sim.fault() {
                stopped = Some(Stop::Capacity(self.books.monitor.explain_fault(fault.to_string())));
                break;
            }
            let step = self.sim.steps();
            // Every part of a distributed run stops at the same step.
            let interrupted = self.sim.agree(self.options.interrupt.as_ref().is_some_and(|f| f.load(Ordering::Relaxed))) && step < total;
            let on_cadence = step.is_multiple_of(every);
            let snapshot = snapshot_every.is_some_and(|k| step.is_multiple_of(k));
            if on_cadence || snapshot {
                stopped = self.rows(step, on_cadence, snapshot)?;
                if let Some(Stop::Ended(_)) = stopped
                    && self.checkpoint_every.is_some()
                {
                    // The state a later run starts from (run.start.from).
                    self.checkpoint()?;
                }
                if stopped.is_some() {
                    break;
                }
            }
            // Before the last row when that row is off the output cadence: a run continued past
            // its end then writes the rows an uninterrupted run would have.
            if self.checkpoint_every.is_some_and(|k| step.is_multiple_of(k) || interrupted || step == total) {
                self.checkpoint()?;
            }
            if step == total && !on_cadence {
                stopped = self.rows(step, true, false)?;
                if stopped.is_some() {
                    break;
                }
            }
            if interrupted {
                stopped = Some(Stop::Interrupted);
                break;
            }
            if let Some(p) = progress.as_mut() {
                p.update(step, self.sim.time(), particle_steps);
            }
        }
        if let Some(p) = progress.as_mut() {
            p.finish(self.sim.steps(), self.sim.time(), particle_steps);
        }
        self.finish(stopped, start.elapsed().as_secs_f64(), particle_steps)
    }

    /// The output row (`output`) and snapshot (`snapshot`) of `step`, from one frame; a stop the row finds.
    fn rows(&mut self, step: u64, output: bool, snapshot: bool) -> Result<Option<Stop>, RunError> {
        let (sim, out_dir) = (&self.sim, self.out_dir.as_path());
        // One frame (one read-back on a device) serves the monitor, the rows and the snapshot.
        let frame = sim.frame((output && self.rows_need_state) || snapshot);
        let o = frame.observables;
        let mut ended = None;
        if output {
            if let Err(e) = self.books.monitor.check(step, &o) {
                return Ok(Some(Stop::Unstable(e)));
            }
            let extra = self.books.extra.row(sim.plan(), sim.time(), &frame);
            io(out_dir, self.outputs.obs.row(&o, sim.plan().model.fluid.is_some(), sim.removed(), &extra))?;
            if let Some(text) = too_many_lost(sim.plan(), sim.removed(), self.books.initial_particles, o.time) {
                return Ok(Some(Stop::Lost(text)));
            }
            ended =
                sim.plan().run.end_when.filter(|e| o.time >= e.after && o.kinetic_energy + o.rotational_energy < e.kinetic_energy_below).map(|e| {
                    Stop::Ended(format!(
                        "the particles' kinetic energy {:.3e} J fell below run.end_when.kinetic_energy_below = {:e} J at t = {:.6e} s",
                        o.kinetic_energy + o.rotational_energy,
                        e.kinetic_energy_below,
                        o.time
                    ))
                });
            io(out_dir, self.outputs.tracks.rows(o.time, &frame.tracks))?;
            if let (Some(w), Some(state)) = (self.outputs.agglo.as_mut(), frame.state.as_deref()) {
                let a = agglomerates_of(sim.plan(), state);
                io(out_dir, w.row(o.time, &a))?;
                self.books.last_agglomerates = Some(a);
            }
        }
        // Never write NaN: a non-finite state is stopped by the monitor at the next output.
        if let (true, true, Some(w), Some(k), Some(state)) =
            (snapshot, o.finite, self.outputs.snapshots.as_mut(), sim.plan().run.snapshot_every, frame.state.as_deref())
        {
            io(out_dir, w.write((step / k) as usize, sim, o.time, state))?;
        }
        Ok(ended)
    }

    /// Writes a checkpoint of the run as it stands.
    fn checkpoint(&mut self) -> Result<(), RunError> {
        let t0 = Instant::now();
        self.books.files = io(&self.out_dir, self.outputs.lengths(&self.out_dir))?;
        self.books.series = self.outputs.snapshots.as_ref().map(|w| w.index().clone()).unwrap_or_default();
        let header = CheckpointHeader {
            tumble_version: env!("CARGO_PKG_VERSION").to_string(),
            scene: self.scene.clone(),
            backend: self.sim.backend_name().to_string(),
            step: self.sim.steps(),
            time: self.sim.time(),
            books: postcard::to_stdvec(&self.books).expect("the books always encode"),
        };
        let sim = &self.sim;
        let (path, bytes) =
            io(&self.out_dir, checkpoint::write(&self.out_dir, &header, |w| sim.backend().write_snapshot(w), sim.plan().run.checkpoint_keep))?;
        let c = &mut self.checkpoints;
        c.written += 1;
        c.last = Some(path);
        c.last_bytes = bytes;
        c.seconds += t0.elapsed().as_secs_f64();
        Ok(())
    }

    /// Writes the final summary.json and says how the run ended.
    fn finish(self, stopped: Option<Stop>, wall_seconds: f64, particle_steps: u128) -> Result<RunSummary, RunError> {
        let sim = &self.sim;
        let mut warnings = self.warnings;
        warnings.extend(lost_warning(sim.removed(), self.books.initial_particles));
        let summary = RunSummary {
            out_dir: self.out_dir.clone(),
            steps: sim.steps(),
            particles: sim.particles(),
            wall_seconds,
            particle_steps_per_second: particle_steps as f64 / wall_seconds.max(1e-12),
            final_observables: sim.observables(),
            final_agglomerates: self.books.last_agglomerates,
            removed: sim.removed(),
            warnings,
            resumed_from_step: self.resumed_from,
            ended_early: match &stopped {
                Some(Stop::Ended(why)) => Some(why.clone()),
                _ => None,
            },
            checkpoints: self.checkpoint_every.map(|_| self.checkpoints),
        };
        let stop_text = match &stopped {
            Some(Stop::Ended(_)) => None,
            Some(Stop::Unstable(e)) => Some(e.to_string()),
            Some(Stop::Capacity(e)) => Some(e.clone()),
            Some(Stop::Lost(e)) => Some(e.clone()),
            Some(Stop::Interrupted) => {
                let resume = if self.checkpoint_every.is_some() {
                    format!("; `tumble resume {}` continues it", self.out_dir.display())
                } else {
                    String::new()
                };
                Some(format!("interrupted by a signal (Ctrl-C, SIGTERM or SIGHUP) at step {} (t = {:.6e} s){resume}", sim.steps(), sim.time()))
            }
            None => None,
        };
        let status = match &stopped {
            None | Some(Stop::Ended(_)) => "completed",
            Some(Stop::Interrupted) => "interrupted",
            Some(_) => "stopped",
        };
        let json = summary_json(sim, &summary, &self.plan_text, status, stop_text);
        // Replaced in one rename: a reader sees the "running" summary or the final one, never half of either.
        io(&self.out_dir, crate::outdir::write_atomic(&self.out_dir.join("summary.json"), &json))?;
        match stopped {
            Some(Stop::Unstable(e)) => Err(RunError::Unstable(e)),
            Some(Stop::Capacity(e)) => Err(RunError::Capacity(e)),
            Some(Stop::Lost(e)) => Err(RunError::Lost(e)),
            Some(Stop::Interrupted) => Err(RunError::Interrupted { step: summary.steps, out_dir: self.out_dir }),
            None | Some(Stop::Ended(_)) => Ok(summary),
        }
    }
}

/// Agglomerate statistics of state `s` (positions wrapped into the domain).
fn agglomerates_of(plan: &Plan, s: &State) -> crate::agglomerates::AgglomerateStats {
    crate::agglomerates::agglomerates(&s.pos, &s.radius, Some(&plan.model.domain))
}

/// Wall power (mean over the output interval), drum profiles and flow-plane counts.
#[derive(Serialize, Deserialize)]
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
    /// The scene's `run.end_when` was met: a completed run.
    Ended(String),
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

/// Σ m |g| × the domain's extent along g: the potential energy gravity can release.
fn potential_range(plan: &Plan, s: &State) -> f64 {
    let g = plan.model.gravity;
    if g == glam::DVec3::ZERO {
        return 0.0;
    }
    let height = (plan.model.domain.extent() * g.abs()).element_sum();
    (0..s.len()).filter(|&i| s.inv_mass[i] != 0.0).map(|i| s.mass[i] * height).sum()
}
