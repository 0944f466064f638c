//! The verification table of `tumble verify`: every convergence expectation and the
//! single-step checks, with pass or fail.

use super::{convergence_rows, energy_balance, hertz_impact, slide_to_roll, sliding, verdicts};
use std::fmt::Write as _;
use tumble_integrate::Integrator;

/// Runs every case; returns the table and whether everything passed.
pub fn report() -> (String, bool) {
    let mut out = String::new();
    let mut all = true;
    let _ = writeln!(
        out,
        "{:<22} {:<20} {:<25} {:>9} {:>9} {:>11} {:>9}  result",
        "case", "measure", "integrator", "order", "expected", "error@T/256", "limit"
    );
    for v in verdicts(&convergence_rows()) {
        let x = v.expectation;
        all &= v.pass;
        let _ = writeln!(
            out,
            "{:<22} {:<20} {:<25} {:>9.2} {:>9.1} {:>11.3e} {:>9.0e}  {}",
            x.case,
            x.measure,
            x.integrator.name(),
            v.measured_order,
            x.order,
            v.finest_error,
            x.limit,
            if v.pass { "pass" } else { "FAIL" }
        );
    }
    let _ = writeln!(out, "\n{:<58} {:>14} {:>14} {:>9}  result", "single-step check", "value", "reference", "limit");
    let mut single = |name: &str, value: f64, reference: f64, limit: f64| {
        let error = if reference == 0.0 { value.abs() } else { (value / reference - 1.0).abs() };
        let pass = error <= limit && value.is_finite();
        all &= pass;
        let _ = writeln!(out, "{name:<58} {value:>14.6e} {reference:>14.6e} {limit:>9.0e}  {}", if pass { "pass" } else { "FAIL" });
    };
    let s = sliding(Integrator::Verlet, 50.0, false);
    single("3 sliding: speed after the stop [m/s]", s.speed_after_stop, 0.0, 1e-10);
    let h = hertz_impact(Integrator::Verlet, None);
    single("7 hertz impact: max overlap (relative)", h.max_overlap.0, h.max_overlap.1, 1e-2);
    single("7 hertz impact: max force (relative)", h.max_force.0, h.max_force.1, 1e-2);
    single("7 hertz impact: contact time (relative)", h.contact_time.0, h.contact_time.1, 1e-2);
    let r = slide_to_roll(Integrator::Verlet, 50.0);
    single("8 slide to roll: final v / v0 (relative)", r.final_speed_ratio, 5.0 / 7.0, 1e-4);
    single("8 slide to roll: roll time (relative)", r.roll_time.0, r.roll_time.1, 2e-3);
    single("9 energy balance |ΔE|/E0 at t_col/50", energy_balance(2).0, 0.0, 1e-2);
    (out, all)
}
