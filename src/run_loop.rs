//! The step loop of a run: output rows, snapshots and checkpoints at their cadence, the
//! monitor, the run's end and its summary.json.

use crate::Simulation;
use crate::agglomerates::AgglomerateStats;
use crate::checkpoint::{self, CheckpointHeader, SceneRecord};
use crate::feeder::FeederBooks;
use crate::flow::FlowCounter;
use crate::monitor::Monitor;
use crate::output::{AgglomeratesCsv, ExtraColumns, ObservablesCsv, PhaseCsv, TracksCsv};
use crate::progress::Progress;
use crate::run::{CheckpointReport, RunError, RunOptions, RunSummary, Stop, agglomerates_of, io, lost_warning, too_many_lost};
use crate::summary::summary_json;
use crate::vtk::{SeriesIndex, SnapshotWriter};
use serde::{Deserialize, Serialize};
use std::path::{Path, PathBuf};
use std::sync::atomic::Ordering;
use std::time::Instant;
use tumble_scene::Plan;
use tumble_state::Frame;

/// What the run loop keeps besides the backend's state; a checkpoint carries it.
#[derive(Serialize, Deserialize)]
pub(crate) struct Books {
    pub(crate) initial_particles: usize,
    pub(crate) monitor: Monitor,
    pub(crate) extra: ExtraRows,
    pub(crate) last_agglomerates: Option<AgglomerateStats>,
    /// Each output file (relative to the folder) and its length in bytes when the books were taken.
    pub(crate) files: Vec<(String, u64)>,
    pub(crate) series: SeriesIndex,
    /// The sources' books (None without sources).
    pub(crate) feeder: Option<FeederBooks>,
    /// Each phase's snapshot section, in the simulation's order of phases.
    pub(crate) phases: Vec<Vec<u8>>,
}

/// The run's output files.
pub(crate) struct Outputs {
    pub(crate) obs: ObservablesCsv,
    pub(crate) tracks: TracksCsv,
    pub(crate) agglo: Option<AgglomeratesCsv>,
    pub(crate) snapshots: Option<SnapshotWriter>,
    pub(crate) phases: PhaseCsv,
}

impl Outputs {
    /// New files, or (`resume`) the files of an earlier part cut back to its checkpoint.
    pub(crate) fn open(dir: &Path, plan: &Plan, initial_particles: usize, resume: Option<&Books>) -> std::io::Result<Self> {
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
        Ok(Outputs {
            obs: ObservablesCsv::open(dir, plan, append)?,
            tracks: TracksCsv::open(dir, plan, append)?,
            agglo,
            snapshots,
            phases: PhaseCsv::open(dir, append),
        })
    }

    /// The length of each CSV file now (every row is flushed as it is written).
    pub(crate) fn lengths(&self, dir: &Path) -> std::io::Result<Vec<(String, u64)>> {
        let mut names = vec!["observables.csv", "tracks.csv"];
        if self.agglo.is_some() {
            names.push("agglomerates.csv");
        }
        names.extend(self.phases.names());
        names.into_iter().map(|n| Ok((n.to_string(), std::fs::metadata(dir.join(n))?.len()))).collect()
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
    /// Flow planes and agglomerates need the particle arrays at every output row; nothing else does.
    rows_need_state: bool,
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
            if let Some(e) = self.sim.phase_fault() {
                stopped = Some(Stop::Phase(e.to_string()));
                break;
            }
            if let Some(fault) = self.sim.fault() {
                stopped = Some(Stop::Capacity(self.books.monitor.explain_fault(fault.to_string())));
                break;
            }
            if let Some(e) = self.sim.feed_error() {
                stopped = Some(Stop::Capacity(e.to_string()));
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
            // The state at the end is always in the snapshot series, on its cadence or not
            // (written after the checkpoint, as the row, so a continued run writes the series an
            // uninterrupted one would have).
            let final_snapshot = step == total && snapshot_every.is_some() && !snapshot;
            if step == total && (!on_cadence || final_snapshot) {
                stopped = self.rows(step, !on_cadence, final_snapshot)?;
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
        if output {
            for phase in self.sim.phases_mut() {
                if let Err(e) = phase.check() {
                    return Ok(Some(Stop::Phase(format!("{}: {e}", phase.name()))));
                }
            }
        }
        let (sim, out_dir) = (&self.sim, self.out_dir.as_path());
        // One frame (one read-back on a device) serves the monitor, the rows and the snapshot.
        let frame = sim.frame((output && self.rows_need_state) || snapshot);
        let o = frame.observables;
        let mut ended = None;
        if output {
            if let Err(e) = self.books.monitor.check_with_inserted(step, &o, sim.inserted_energy()) {
                return Ok(Some(Stop::Unstable(e)));
            }
            let extra = self.books.extra.row(sim, &frame);
            io(out_dir, self.outputs.obs.row(&o, sim.plan().model.fluid.is_some(), sim.removed(), &extra))?;
            if let Some(text) = extra.flood {
                return Ok(Some(Stop::Lost(text)));
            }
            if let Some(text) = too_many_lost(sim.plan(), sim.removed(), self.books.initial_particles + inserted(sim), o.time) {
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
            for phase in sim.phases() {
                io(out_dir, self.outputs.phases.row(o.time, &phase.tables()))?;
            }
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
            // The last snapshot of a run whose end is off the cadence takes the next number.
            io(out_dir, w.write(step.div_ceil(k) as usize, sim, o.time, state))?;
        }
        Ok(ended)
    }

    /// Writes a checkpoint of the run as it stands.
    fn checkpoint(&mut self) -> Result<(), RunError> {
        let t0 = Instant::now();
        self.books.files = io(&self.out_dir, self.outputs.lengths(&self.out_dir))?;
        self.books.series = self.outputs.snapshots.as_ref().map(|w| w.index().clone()).unwrap_or_default();
        self.books.feeder = self.sim.feeder_books().cloned();
        self.books.phases = self.sim.phases().iter().map(|p| p.snapshot()).collect();
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
        warnings.extend(lost_warning(sim.removed(), self.books.initial_particles + inserted(sim)));
        warnings.extend(crate::feeder::shortfall_warnings(sim));
        let summary = RunSummary {
            out_dir: self.out_dir.clone(),
            steps: sim.steps(),
            particles: sim.particles(),
            phase_particles: sim.phases().iter().map(|p| (p.name(), p.particles())).collect(),
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

/// Wall power (mean over the output interval), drum profiles, flow-plane counts, sources and outlets.
#[derive(Serialize, Deserialize)]
pub(crate) struct ExtraRows {
    moving: Vec<usize>,
    last: Option<(f64, Vec<f64>)>,
    flow: Option<FlowCounter>,
    /// The outlets' books at the last row.
    last_outlets: Option<OutletBooks>,
}

/// What the outlets had deleted by the last row.
#[derive(Serialize, Deserialize)]
struct OutletBooks {
    time: f64,
    /// Per outlet: particles deleted and their mass since t = 0.
    deleted: Vec<(u64, f64)>,
}

impl ExtraRows {
    pub(crate) fn new(plan: &Plan) -> Self {
        let moving = (0..plan.model.wall_groups.len()).filter(|&g| plan.model.wall_groups[g].moving).collect();
        ExtraRows { moving, last: None, flow: None, last_outlets: None }
    }

    /// Why the run must stop because an outlet deleted more than `run.max_outlet_fraction` of
    /// the particles since the last row (of those there would be now had no outlet deleted
    /// any): an outlet whose normal points into the particles, or whose box holds them.
    fn outlet_flood(&self, sim: &Simulation, particles: usize, t: f64) -> Option<String> {
        let tallies = sim.outlet_tallies();
        let before = |k: usize| self.last_outlets.as_ref().map_or((0, 0.0), |last| last.deleted[k]);
        let since: Vec<u64> = tallies.iter().enumerate().map(|(k, o)| o.count - before(k).0).collect();
        let present = particles as u64 + since.iter().sum::<u64>();
        let limit = sim.plan().run.max_outlet_fraction;
        let (k, &deleted) = since.iter().enumerate().max_by_key(|(_, d)| **d)?;
        if deleted as f64 <= limit * present as f64 {
            return None;
        }
        let from = self.last_outlets.as_ref().map_or(0.0, |last| last.time);
        Some(format!(
            "outlet \"{}\" deleted {deleted} of {present} particles ({:.1} %) between t = {from:.6e} and {t:.6e} s, more than run.max_outlet_fraction = {limit} allows: check that its plane's normal points away from the particles, or its box lies where they leave (set run.max_outlet_fraction = 1 if emptying the domain at once is intended)",
            sim.plan().model.outlets[k].name,
            100.0 * deleted as f64 / present as f64
        ))
    }

    /// The extra columns of `sim`'s row now (the first row starts the flow count).
    pub(crate) fn row(&mut self, sim: &Simulation, frame: &Frame) -> ExtraColumns {
        let (plan, t) = (sim.plan(), sim.time());
        let inserted = sim.inserted();
        let tallies = sim.outlet_tallies();
        let outlets = tallies
            .iter()
            .enumerate()
            .map(|(k, o)| {
                let rate = match &self.last_outlets {
                    Some(last) if t > last.time => (o.mass - last.deleted[k].1) / (t - last.time),
                    _ => 0.0,
                };
                (o.count, o.mass, rate)
            })
            .collect();
        let flood = self.outlet_flood(sim, frame.observables.particles, t);
        if !tallies.is_empty() {
            self.last_outlets = Some(OutletBooks { time: t, deleted: tallies.iter().map(|o| (o.count, o.mass)).collect() });
        }
        // Nothing else to add.
        if plan.model.wall_groups.is_empty() && plan.model.drums.is_empty() && plan.model.flow_planes.is_empty() {
            return ExtraColumns { inserted, outlets, flood, ..Default::default() };
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
        let servo = plan.model.wall_groups.iter().enumerate().filter(|(_, g)| g.servo.is_some()).map(|(k, _)| frame.servo_offset[k]).collect();
        let wear = sim.mesh_wear().iter().zip(&plan.model.walls).filter(|(_, w)| w.wear > 0.0).map(|(t, _)| t.iter().sum()).collect();
        ExtraColumns { power, servo, wear, wall_loads, drums: frame.drums.clone(), flow, inserted, outlets, flood }
    }
}

/// Most steps advanced between two checks of the interrupt flag and the progress display.
const MAX_CHUNK: u64 = 200;
