//! The run's schedule: the step Δt (chosen or checked against the stability and
//! moving-geometry limits), the step count and the output and snapshot cadence.

use super::positive;
use crate::SceneError;
use crate::particles::InitialParticles;
use crate::plan::{SphPlan, WALL_ADVANCE_FRACTION, Wall, WallGroup, WallStepLimit};
use crate::schema::*;
use crate::timescales::Timescales;

/// Moving geometry: a wall must not advance more than 0.025 r_min per step.
pub(super) fn wall_step_limit(walls: &[Wall], wall_groups: &[WallGroup], particles: &InitialParticles) -> Option<WallStepLimit> {
    walls.iter().filter(|w| w.surface_speed > 0.0).max_by(|a, b| a.surface_speed.total_cmp(&b.surface_speed)).and_then(|w| {
        let r_min = (0..particles.len()).filter(|&i| !particles.fixed[i]).map(|i| particles.radius[i]).fold(f64::INFINITY, f64::min);
        r_min.is_finite().then(|| WallStepLimit {
            dt: WALL_ADVANCE_FRACTION * r_min / w.surface_speed,
            wall: wall_groups[w.group as usize].name.clone(),
            speed: w.surface_speed,
            r_min,
        })
    })
}

/// Δt: the scene's, or the plan's default; refused above a limit unless the scene allows it.
pub(super) fn step(
    scene: &Scene,
    timescales: &Timescales,
    wall_step_limit: Option<&WallStepLimit>,
    sph: Option<&SphPlan>,
) -> Result<f64, SceneError> {
    let run = &scene.run;
    // Particles and fluid share one clock: the shorter of their steps.
    let default_dt = match (scene.has_particles(), sph) {
        (true, Some(s)) => timescales.default_dt.min(s.limits.dt()),
        (false, Some(s)) => s.limits.dt(),
        (_, None) => timescales.default_dt,
    };
    let dt = match run.dt {
        None => default_dt.min(run.duration),
        Some(DtSpec::Seconds(dt)) => positive("run.dt", dt)?,
        Some(DtSpec::Fraction(f)) => {
            positive("run.dt.collision_fraction", f.collision_fraction)?;
            let t = timescales
                .collision_time
                .ok_or_else(|| SceneError::field("run.dt.collision_fraction", "this scene has no contact time to divide; give dt in seconds"))?;
            let dt = t / f.collision_fraction;
            // A fraction near zero (1e-320) overflows: allow_unstable_dt cannot make Δt = ∞ run.
            if !dt.is_finite() {
                return Err(SceneError::field(
                    "run.dt.collision_fraction",
                    format!("the collision time {t:.4e} s over {} gives Δt = {dt} s; Δt must be a finite number of seconds", f.collision_fraction),
                ));
            }
            dt
        }
    };
    if let Some(limit) = timescales.stability_limit
        && dt > limit
        && !run.allow_unstable_dt
    {
        return Err(SceneError::field(
            "run.dt",
            format!(
                "dt = {dt:.4e} s is above the stability limit {limit:.4e} s of this scene; use dt <= {limit:.4e} (the plan's default is {:.4e}) or set run.allow_unstable_dt = true",
                timescales.default_dt
            ),
        ));
    }
    if let Some(s) = sph
        && dt > s.limits.dt()
        && !run.allow_unstable_dt
    {
        return Err(SceneError::field(
            "run.dt",
            format!(
                "dt = {dt:.4e} s is above the SPH fluid's limit {:.4e} s, set by {}; use dt <= {:.4e} s or set run.allow_unstable_dt = true",
                s.limits.dt(),
                s.limits.binding(),
                s.limits.dt()
            ),
        ));
    }
    if let Some(w) = wall_step_limit
        && dt > w.dt
        && !run.allow_unstable_dt
    {
        return Err(SceneError::field(
            "run.dt",
            format!(
                "dt = {dt:.4e} s lets wall \"{}\" (moving at {:.4} m/s) advance more than {WALL_ADVANCE_FRACTION} r_min = {:.3e} m per step; use dt <= {:.4e} or set run.allow_unstable_dt = true",
                w.wall,
                w.speed,
                WALL_ADVANCE_FRACTION * w.r_min,
                w.dt
            ),
        ));
    }
    Ok(dt)
}

/// Steps to the end, steps per output row and per snapshot.
pub(super) struct Schedule {
    pub steps: u64,
    pub output_every: u64,
    pub snapshot_every: Option<u64>,
    pub checkpoint_every: Option<u64>,
    pub checkpoint_keep: usize,
}

/// The most steps a run may take: far beyond any real run (days at 1e7 particle-steps/s for
/// one particle), so a Δt of 1e-320 s is refused instead of hanging.
pub const MAX_STEPS: f64 = 1e10;

/// Checkpoints kept when the scene does not say: the newest and two before it, in case the
/// newest was written by a run whose files were damaged afterwards.
pub const DEFAULT_CHECKPOINT_KEEP: usize = 3;

/// The run's step counts; with a coupled fluid each is a whole number of the fluid's steps of
/// `substeps` × Δt, so that every row, snapshot and checkpoint finds both phases at one time.
pub(super) fn schedule(scene: &Scene, dt: f64, substeps: u64) -> Result<Schedule, SceneError> {
    let run = &scene.run;
    let exact = run.duration / dt;
    if exact.is_nan() || exact > MAX_STEPS {
        return Err(SceneError::field(
            "run.dt",
            format!(
                "dt = {dt:.4e} s over run.duration = {:.4e} s gives {exact:.3e} steps, more than the {MAX_STEPS:.0e} a run may take; use a larger dt or a shorter duration",
                run.duration
            ),
        ));
    }
    let whole = |steps: u64| steps.div_ceil(substeps) * substeps;
    let steps = whole((exact - 1e-9).ceil().max(1.0) as u64);
    // An interval longer than any run saturates: such a row or checkpoint never falls due.
    let every = |interval: f64| ((interval / dt / substeps as f64).round() as u64).max(1).saturating_mul(substeps);
    let output_interval = run.output_interval.unwrap_or(run.duration / 100.0);
    positive("run.output_interval", output_interval)?;
    let output_every = every(output_interval);
    let snapshot_every = match run.snapshot_interval {
        Some(s) => Some(every(positive("run.snapshot_interval", s)?)),
        None => None,
    };
    let checkpoint_every = match run.checkpoint_interval {
        Some(s) => Some(every(positive("run.checkpoint_interval", s)?)),
        None => None,
    };
    let checkpoint_keep = match run.checkpoint_keep {
        Some(0) => {
            return Err(SceneError::field("run.checkpoint_keep", "checkpoint_keep = 0 would keep no checkpoint to resume from; use 1 or more"));
        }
        Some(k) => k as usize,
        None => DEFAULT_CHECKPOINT_KEEP,
    };
    Ok(Schedule { steps, output_every, snapshot_every, checkpoint_every, checkpoint_keep })
}

/// The early end of a settling run, checked.
pub(super) fn end_when(scene: &Scene) -> Result<Option<crate::schema::EndWhenSection>, SceneError> {
    let Some(e) = scene.run.end_when else { return Ok(None) };
    positive("run.end_when.kinetic_energy_below", e.kinetic_energy_below)?;
    if !(e.after.is_finite() && e.after >= 0.0) {
        return Err(SceneError::field("run.end_when.after", format!("must be a time in seconds, 0 or later, got {}", e.after)));
    }
    Ok(Some(e))
}

/// The instability monitor's thresholds.
pub(super) fn monitor(scene: &Scene) -> Result<MonitorSection, SceneError> {
    let monitor = scene.run.monitor;
    positive("run.monitor.max_overlap_ratio", monitor.max_overlap_ratio)?;
    positive("run.monitor.energy_growth", monitor.energy_growth)?;
    Ok(monitor)
}
