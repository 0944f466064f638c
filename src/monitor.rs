//! The instability monitor: stops a run that blows up, naming the cause and a Δt that works.

use crate::Observables;
use std::fmt;
use tumble_scene::Plan;

/// Why a run was stopped.
#[derive(Clone, Debug, PartialEq)]
pub struct Instability {
    pub step: u64,
    pub time: f64,
    pub cause: String,
    pub dt: f64,
    /// The Δt the plan would choose for this scene.
    pub suggested_dt: f64,
}

impl fmt::Display for Instability {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        write!(
            f,
            "simulation unstable at step {} (t = {:.6e} s): {}; dt = {:.4e} s is too large, use dt <= {:.4e} s",
            self.step, self.time, self.cause, self.dt, self.suggested_dt
        )
    }
}

/// Watches observables between output intervals.
pub struct Monitor {
    enabled: bool,
    max_overlap_ratio: f64,
    energy_growth: f64,
    has_source: bool,
    initial_energy: f64,
    /// Smallest energy scale: a small share of the scene's total energy range.
    energy_floor: f64,
    /// Largest kinetic + rotational + |elastic| energy seen so far.
    peak_energy: std::cell::Cell<f64>,
    dt: f64,
    suggested_dt: f64,
}

impl Monitor {
    /// A monitor for a plan, given the observables at t = 0 and the scene's potential-energy range.
    pub fn new(plan: &Plan, initial: &Observables, potential_range: f64) -> Self {
        // The plan's own choice, and never more than half the step that failed.
        let suggested_dt = plan
            .report
            .timescales
            .stability_limit
            .map_or(plan.report.timescales.default_dt, |l| l.min(plan.report.timescales.default_dt))
            .min(0.5 * plan.model.dt);
        Monitor {
            enabled: plan.run.monitor.enabled,
            max_overlap_ratio: plan.run.monitor.max_overlap_ratio,
            energy_growth: plan.run.monitor.energy_growth,
            has_source: plan.model.fluid.is_some(),
            initial_energy: initial.mechanical_energy() + initial.dissipated_energy - initial.wall_work,
            energy_floor: (1e-3 * (initial.mechanical_energy().abs() + potential_range)).max(f64::MIN_POSITIVE),
            peak_energy: std::cell::Cell::new(moving_energy(initial)),
            dt: plan.model.dt,
            suggested_dt,
        }
    }

    /// Checks one row of observables; non-finite values are always fatal.
    pub fn check(&self, step: u64, o: &Observables) -> Result<(), Instability> {
        let fail = |cause: String| Err(Instability { step, time: o.time, cause, dt: self.dt, suggested_dt: self.suggested_dt });
        if !o.finite {
            return fail("a position, velocity or energy became non-finite (NaN or infinity)".into());
        }
        if !self.enabled {
            return Ok(());
        }
        if o.max_overlap_ratio > self.max_overlap_ratio {
            return fail(format!("overlap δ/r = {:.3} exceeds the bound {}", o.max_overlap_ratio, self.max_overlap_ratio));
        }
        if !self.has_source {
            // Energy in motion sets the scale: a resting bed must not gain a share of it.
            self.peak_energy.set(self.peak_energy.get().max(moving_energy(o)));
            let scale = self.peak_energy.get().max(self.energy_floor);
            // Moving walls are a source whose work is booked: only unbooked gains count.
            let gain = o.mechanical_energy() + o.dissipated_energy - o.wall_work - self.initial_energy;
            if gain > self.energy_growth * scale {
                return fail(format!(
                    "energy grew by {:.3e} J without a source ({:.0} % of the largest kinetic and elastic energy, {:.3e} J)",
                    gain,
                    100.0 * gain / scale,
                    scale
                ));
            }
        }
        Ok(())
    }
}

/// Kinetic, rotational and (absolute) elastic energy: the energy in motion.
fn moving_energy(o: &Observables) -> f64 {
    o.kinetic_energy + o.rotational_energy + o.elastic_energy.abs()
}
