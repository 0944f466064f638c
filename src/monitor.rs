//! The instability monitor: stops a run that blows up, naming the cause and, when the step is the
//! cause, a Δt that works (docs/cli.md, "The instability monitor").

use crate::Observables;
use tumble_scene::{Plan, PolyhedronContact};

pub use tumble_state::Instability;

/// Overlap at t = 0 above which a later blow-up is put down to the starting state: at the plan's
/// default Δt contacts between moving particles stay within a few per cent of the radius.
pub const SUSPECT_INITIAL_OVERLAP: f64 = 0.1;

/// Watches observables at t = 0 and between output intervals.
#[derive(serde::Serialize, serde::Deserialize)]
pub struct Monitor {
    enabled: bool,
    max_overlap_ratio: f64,
    energy_growth: f64,
    has_source: bool,
    /// Depth-model polyhedron contacts are not conservative (docs/polyhedra.md): their error grows
    /// with the energy the contacts exchange, so the dissipated energy joins the scale.
    depth_polyhedra: bool,
    initial_energy: f64,
    initial_overlap: f64,
    initial_elastic: f64,
    /// Smallest energy scale: a small share of the scene's total energy range.
    energy_floor: f64,
    /// Largest kinetic + rotational + |elastic| energy seen so far.
    peak_energy: std::cell::Cell<f64>,
    dt: f64,
    default_dt: f64,
    collision_time: Option<f64>,
}

impl Monitor {
    /// A monitor for a plan, given the observables at t = 0 and the scene's potential-energy range.
    pub fn new(plan: &Plan, initial: &Observables, potential_range: f64) -> Self {
        Monitor {
            enabled: plan.run.monitor.enabled,
            max_overlap_ratio: plan.run.monitor.max_overlap_ratio,
            energy_growth: plan.run.monitor.energy_growth,
            has_source: plan.fluid_works_on_particles(),
            depth_polyhedra: plan.model.polyhedra && plan.model.polyhedron_contact == PolyhedronContact::Depth,
            initial_energy: initial.mechanical_energy() + initial.dissipated_energy - initial.wall_work,
            initial_overlap: if initial.max_overlap_ratio.is_finite() { initial.max_overlap_ratio } else { 0.0 },
            initial_elastic: initial.elastic_energy,
            energy_floor: (1e-3 * (initial.mechanical_energy().abs() + potential_range)).max(f64::MIN_POSITIVE),
            peak_energy: std::cell::Cell::new(moving_energy(initial)),
            dt: plan.model.dt,
            default_dt: plan.report.timescales.default_dt,
            collision_time: plan.report.timescales.collision_time,
        }
    }

    /// Checks one row of observables (step 0 is the starting state); non-finite values are always fatal.
    pub fn check(&self, step: u64, o: &Observables) -> Result<(), Instability> {
        self.check_with_inserted(step, o, 0.0)
    }

    /// [`Monitor::check`] for a run whose sources have brought in `inserted` J of kinetic and
    /// potential energy since t = 0 (booked like the walls' work).
    pub fn check_with_inserted(&self, step: u64, o: &Observables, inserted: f64) -> Result<(), Instability> {
        let stop =
            |cause: String, remedy: String, suggested_dt: f64| Err(Instability { step, time: o.time, cause, remedy, dt: self.dt, suggested_dt });
        if step == 0 {
            if !o.finite {
                return stop(
                    "the starting state is not finite (a position, velocity or energy is NaN or infinite at t = 0)".into(),
                    "dt will not fix it: check the scene's positions, velocities, sizes and densities".into(),
                    self.dt,
                );
            }
            if self.enabled && o.max_overlap_ratio > self.max_overlap_ratio {
                return stop(
                    format!(
                        "particles start overlapping by up to δ/r = {:.3} at t = 0 (bound {}), {:.3e} J stored in their contacts",
                        o.max_overlap_ratio, self.max_overlap_ratio, o.elastic_energy
                    ),
                    "dt will not fix it: start them apart (lattice spacing at least the largest diameter, fewer random particles, walls clear of the bed) or raise run.monitor.max_overlap_ratio if the overlap is meant".into(),
                    self.dt,
                );
            }
            return Ok(());
        }
        if !o.finite {
            return self.diagnose(step, o, "a position, velocity or energy became non-finite (NaN or infinity)".into(), true);
        }
        if !self.enabled {
            return Ok(());
        }
        if o.max_overlap_ratio > self.max_overlap_ratio {
            return self.diagnose(step, o, format!("overlap δ/r = {:.3} exceeds the bound {}", o.max_overlap_ratio, self.max_overlap_ratio), false);
        }
        if !self.has_source {
            // Energy in motion sets the scale: a resting bed must not gain a share of it.
            self.peak_energy.set(self.peak_energy.get().max(moving_energy(o)));
            let exchanged = if self.depth_polyhedra { o.dissipated_energy.max(0.0) } else { 0.0 };
            let scale = self.peak_energy.get().max(self.energy_floor) + exchanged;
            // Moving walls are a source whose work is booked: only unbooked gains count.
            let gain = o.mechanical_energy() + o.dissipated_energy - o.wall_work - inserted - self.initial_energy;
            if gain > self.energy_growth * scale {
                let of = if self.depth_polyhedra {
                    "the largest kinetic and elastic energy plus the dissipated energy"
                } else {
                    "the largest kinetic and elastic energy"
                };
                return self.diagnose(
                    step,
                    o,
                    format!("energy grew by {gain:.3e} J without a source ({:.0} % of {of}, {scale:.3e} J)", 100.0 * gain / scale),
                    false,
                );
            }
        }
        Ok(())
    }

    /// Names the cause of a failure seen after t = 0: the starting state, the model, or the step.
    fn diagnose(&self, step: u64, o: &Observables, what: String, blown_up: bool) -> Result<(), Instability> {
        let stop =
            |cause: String, remedy: String, suggested_dt: f64| Err(Instability { step, time: o.time, cause, remedy, dt: self.dt, suggested_dt });
        if self.initial_overlap > SUSPECT_INITIAL_OVERLAP {
            return stop(
                format!(
                    "{what}, after a start with overlaps up to δ/r = {:.3} ({:.3e} J stored in contacts at t = 0)",
                    self.initial_overlap, self.initial_elastic
                ),
                "dt will not fix it: start the particles apart (lattice spacing at least the largest diameter, walls clear of the bed)".into(),
                self.dt,
            );
        }
        let steps = |dt: f64| self.collision_time.map_or(String::new(), |t| format!(", {:.1} steps per collision", t / dt));
        if self.dt > self.default_dt * (1.0 + 1e-9) {
            return stop(
                format!("{what} at dt = {:.4e} s{}", self.dt, steps(self.dt)),
                format!("dt = {:.4e} s is too large, use dt <= {:.4e} s (the plan's default{})", self.dt, self.default_dt, steps(self.default_dt)),
                self.default_dt,
            );
        }
        let remedy = if blown_up {
            format!(
                "dt = {:.4e} s is at or below the plan's default{}, so the step is not the cause: check the contact parameters and moving walls",
                self.dt,
                steps(self.dt)
            )
        } else if what.starts_with("overlap") {
            format!(
                "dt will not fix it at dt = {:.4e} s{}: the contacts are too soft for these impacts; stiffen them (k_n or E) or slow the impacts",
                self.dt,
                steps(self.dt)
            )
        } else if self.depth_polyhedra {
            "dt will not fix it: the depth model's polyhedron contacts do not conserve energy (docs/polyhedra.md); use contact.polyhedron_model = \"volume\" or raise run.monitor.energy_growth if the gain stays bounded".into()
        } else {
            format!(
                "dt = {:.4e} s is at or below the plan's default{}, so the step is not the cause: raise run.monitor.energy_growth if the gain is expected",
                self.dt,
                steps(self.dt)
            )
        };
        stop(what, remedy, self.dt)
    }

    /// A capacity fault, with the starting state named when it is the likely cause.
    pub fn explain_fault(&self, fault: String) -> String {
        if self.initial_overlap > SUSPECT_INITIAL_OVERLAP {
            format!("{fault} (the particles start overlapping by up to δ/r = {:.3}: start them apart rather than adding slots)", self.initial_overlap)
        } else {
            fault
        }
    }
}

/// Kinetic, rotational and (absolute) elastic energy: the energy in motion.
fn moving_energy(o: &Observables) -> f64 {
    o.kinetic_energy + o.rotational_energy + o.elastic_energy.abs()
}
