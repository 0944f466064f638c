//! The step loop of a run: output rows, snapshots and checkpoints at their cadence, the
//! monitor, the run's end and its summary.json.

use crate::Simulation;
use crate::checkpoint::{self, CheckpointHeader, SceneRecord};
use crate::output::TableFiles;
use crate::progress::Progress;
use crate::run::{CheckpointReport, RunError, RunOptions, RunSummary, Stop, io, lost_warning};
use crate::summary::summary_json;
use crate::vtk::{SeriesIndex, SnapshotWriter};
use serde::{Deserialize, Serialize};
use std::path::{Path, PathBuf};
use std::sync::atomic::Ordering;
use std::time::Instant;
use tumble_state::OutputRequest;

/// What the run loop keeps besides the particles' arrays (the checkpoint's body); a checkpoint
/// carries it.
#[derive(Default, Serialize, Deserialize)]
pub(crate) struct Books {
    /// Each output file (relative to the folder) and its length in bytes when the books were taken.
    pub(crate) files: Vec<(String, u64)>,
    pub(crate) series: SeriesIndex,
    /// Each phase's checkpoint section, in the simulation's order of phases (the particles first).
    pub(crate) phases: Vec<Vec<u8>>,
}

/// The run's output files.
pub(crate) struct Outputs {
    pub(crate) tables: TableFiles,
    pub(crate) snapshots: Option<SnapshotWriter>,
}

impl Outputs {
    /// New files, or (`resume`) the files of an earlier part cut back to its checkpoint.
    pub(crate) fn open(dir: &Path, sim: &Simulation, resume: Option<&Books>) -> std::io::Result<Self> {
        if let Some(books) = resume {
            for (name, len) in &books.files {
                std::fs::OpenOptions::new().write(true).open(dir.join(name))?.set_len(*len)?;
            }
        }
        let plan = sim.plan();
        let format = plan.run.snapshot_format;
        let snapshots = match (plan.run.snapshot_every, resume) {
            (None, _) => None,
            (Some(_), None) => Some(SnapshotWriter::create(dir, format, &sim.all_phases().flat_map(|p| p.fixed_series()).collect::<Vec<_>>())?),
            (Some(_), Some(books)) => Some(SnapshotWriter::reopen(dir, format, books.series.clone())?),
        };
        Ok(Outputs { tables: TableFiles::open(dir, resume.map_or(&[], |b| &b.files)), snapshots })
    }
}

/// One `tumble run` or `tumble resume`: the simulation, its outputs and its books.
pub(crate) struct Run<'o> {
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
    pub(crate) warnings: Vec<String>,
}

impl<'o> Run<'o> {
    #[allow(clippy::too_many_arguments)]
    pub(crate) fn new(
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
        let checkpoints = CheckpointReport { every_steps: checkpoint_every.unwrap_or(0), ..Default::default() };
        Run { sim, out_dir, options, books, outputs, scene, plan_text, resumed_from, checkpoint_every, checkpoints, warnings: Vec::new() }
    }

    /// Steps to the end, writing rows, snapshots and checkpoints; `stopped` is a stop found before step 1.
    pub(crate) fn go(mut self, mut stopped: Option<Stop>, checkpoint_first: bool) -> Result<RunSummary, RunError> {
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
            let n = self.sim.all_particles() as u128;
            let before = self.sim.steps();
            self.sim.advance(chunk);
            particle_steps += n * (self.sim.steps() - before) as u128;
            if let Some(why) = self.sim.stop() {
                stopped = Some(Stop::from(why.clone()));
                break;
            }
            let step = self.sim.steps();
            // Every part of a distributed run stops at the same step.
            let interrupted = self.sim.agree(self.options.interrupt.as_ref().is_some_and(|f| f.load(Ordering::Relaxed))) && step < total;
            let on_cadence = step.is_multiple_of(every);
            let snapshot = snapshot_every.is_some_and(|k| step.is_multiple_of(k));
            if on_cadence || snapshot {
                stopped = self.rows(OutputRequest { step, row: on_cadence, series: snapshot, start: false })?;
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
            // The state at the end is always in the snapshot series, on its cadence or not
            // (written after the checkpoint, as the row, so a continued run writes the series an
            // uninterrupted one would have).
            let final_snapshot = step == total && snapshot_every.is_some() && !snapshot;
            if step == total && (!on_cadence || final_snapshot) {
                stopped = self.rows(OutputRequest { step, row: !on_cadence, series: final_snapshot, start: false })?;
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

    /// Every phase's part of an output step: its row's tables and its snapshot series; a stop
    /// a phase finds. A phase whose checks fail before anything is written stops the run with
    /// nothing of the step written.
    pub(crate) fn rows(&mut self, request: OutputRequest) -> Result<Option<Stop>, RunError> {
        let mut outputs = Vec::new();
        for phase in self.sim.all_phases_mut() {
            match phase.output(request) {
                Ok(out) => outputs.push(out),
                Err(why) => return Ok(Some(Stop::from(why))),
            }
        }
        let (out_dir, t) = (self.out_dir.as_path(), self.sim.time());
        for out in &outputs {
            io(out_dir, self.outputs.tables.write(t, &out.tables))?;
        }
        if let (Some(w), Some(k)) = (self.outputs.snapshots.as_mut(), self.sim.plan().run.snapshot_every) {
            // The last snapshot of a run whose end is off the cadence takes the next number.
            let index = request.step.div_ceil(k) as usize;
            for (series, data) in outputs.iter().flat_map(|o| &o.series) {
                io(out_dir, w.add(series, index, t, data))?;
            }
        }
        Ok(outputs.into_iter().find_map(|o| o.stop).map(Stop::from))
    }

    /// Writes a checkpoint of the run as it stands.
    fn checkpoint(&mut self) -> Result<(), RunError> {
        let t0 = Instant::now();
        self.books.files = io(&self.out_dir, self.outputs.tables.lengths())?;
        self.books.series = self.outputs.snapshots.as_ref().map(|w| w.index().clone()).unwrap_or_default();
        self.books.phases = self.sim.all_phases().map(|p| p.snapshot()).collect();
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
    fn finish(self, mut stopped: Option<Stop>, wall_seconds: f64, particle_steps: u128) -> Result<RunSummary, RunError> {
        let sim = &self.sim;
        if matches!(stopped, None | Some(Stop::Ended(_)))
            && !sim.plan().run.allow_idle_sources
            && let Some(idle) = crate::feeder::idle_source(sim)
        {
            stopped = Some(Stop::Idle(format!(
                "{idle}; the run's results hold none of its particles (set run.allow_idle_sources = true if that is intended)"
            )));
        }
        let mut warnings = self.warnings;
        warnings.extend(lost_warning(sim.removed(), sim.dem().initial_particles() + inserted(sim)));
        warnings.extend(crate::feeder::shortfall_warnings(sim));
        let summary = RunSummary {
            out_dir: self.out_dir.clone(),
            steps: sim.steps(),
            particles: sim.particles(),
            phase_particles: sim.phases().iter().map(|p| (p.name(), p.particles())).collect(),
            wall_seconds,
            particle_steps_per_second: particle_steps as f64 / wall_seconds.max(1e-12),
            final_observables: sim.observables(),
            final_agglomerates: sim.dem().last_agglomerates().cloned(),
            removed: sim.removed(),
            warnings,
            resumed_from_step: self.resumed_from,
            ended_early: match &stopped {
                Some(Stop::Ended(why)) => Some(why.clone()),
                _ => None,
            },
            checkpoints: self.checkpoint_every.map(|_| self.checkpoints),
            step_seconds: sim.coupler().map(|c| c.seconds()),
        };
        let stop_text = match &stopped {
            Some(Stop::Ended(_)) => None,
            Some(Stop::Unstable(e)) => Some(e.to_string()),
            Some(Stop::Capacity(e)) => Some(e.clone()),
            Some(Stop::Lost(e)) => Some(e.clone()),
            Some(Stop::Phase(e)) => Some(e.clone()),
            Some(Stop::Idle(e)) => Some(e.clone()),
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
            Some(Stop::Phase(e)) => Err(RunError::Phase(e)),
            Some(Stop::Idle(e)) => Err(RunError::Idle(e)),
            Some(Stop::Interrupted) => Err(RunError::Interrupted { step: summary.steps, out_dir: self.out_dir }),
            None | Some(Stop::Ended(_)) => Ok(summary),
        }
    }
}

/// Particles the sources have inserted so far.
pub(crate) fn inserted(sim: &Simulation) -> usize {
    sim.inserted().iter().map(|s| s.0 as usize).sum()
}

/// Most steps advanced between two checks of the interrupt flag and the progress display.
const MAX_CHUNK: u64 = 200;
