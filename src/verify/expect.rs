//! What each convergence measurement must show: the order (±0.3) and the error at T/256.
//! One table for the tests, `tumble verify` and `cargo xtask verify`.

use super::{ErrorRow, fitted_order};
use tumble_integrate::Integrator::{self, *};

/// The expected order and the error bound at the finest step of one (case, measure, integrator).
#[derive(Clone, Copy, Debug)]
pub struct Expectation {
    pub case: &'static str,
    pub measure: &'static str,
    pub integrator: Integrator,
    pub order: f64,
    pub limit: f64,
}

/// Measured against expected.
#[derive(Clone, Copy, Debug)]
pub struct Verdict {
    pub expectation: Expectation,
    pub measured_order: f64,
    pub finest_error: f64,
    pub pass: bool,
}

/// Largest accepted |measured − expected order|.
pub const ORDER_TOLERANCE: f64 = 0.3;

fn each(case: &'static str, measure: &'static str, list: &[(Integrator, f64, f64)]) -> Vec<Expectation> {
    list.iter().map(|&(integrator, order, limit)| Expectation { case, measure, integrator, order, limit }).collect()
}

/// The expectations, with the reason wherever an order differs from the integrator's nominal one.
pub fn expectations() -> Vec<Expectation> {
    let mut e = each(
        "1 stokes drag",
        "x(t) / (u τ)",
        &[(Euler, 1.0, 1e-3), (SymplecticEuler, 1.0, 5e-3), (Verlet, 2.0, 1e-5), (ImplicitDrag, 1.0, 3e-3), (ImplicitDragSymplectic, 1.0, 1e-3)],
    );
    // In contact the force is smooth: the contact starts exactly at t = 0.
    let smooth =
        [(Euler, 1.0, 2e-2), (SymplecticEuler, 1.0, 3e-3), (Verlet, 2.0, 5e-5), (ImplicitDrag, 1.0, 1e-2), (ImplicitDragSymplectic, 1.0, 3e-3)];
    e.extend(each("2 damped collision", "x(t) in contact", &smooth));
    e.extend(each("2 damped collision", "v(t) in contact", &smooth.map(|(i, o, l)| (i, o, 3.0 * l))));
    // Leaving contact, the damping force jumps from η v to 0 between two steps: first order for every scheme.
    e.extend(each(
        "2 damped collision",
        "rebound speed",
        &[(Euler, 1.0, 3e-2), (SymplecticEuler, 1.0, 1e-3), (Verlet, 1.0, 2e-3), (ImplicitDrag, 1.0, 2e-2), (ImplicitDragSymplectic, 1.0, 1e-3)],
    ));
    // With e = 1 the force vanishes at t = 0, so symplectic Euler's positions are Verlet's.
    e.extend(each(
        "2 elastic collision",
        "x(t) in contact",
        &[(SymplecticEuler, 2.0, 1e-4), (Verlet, 2.0, 1e-4), (ImplicitDragSymplectic, 2.0, 1e-4), (Euler, 1.0, 2e-2), (ImplicitDrag, 1.0, 1e-2)],
    ));
    e.extend(each(
        "2 elastic collision",
        "v(t) in contact",
        &[(SymplecticEuler, 1.0, 1e-2), (Verlet, 2.0, 1e-4), (Euler, 1.0, 3e-2), (ImplicitDrag, 1.0, 2e-2)],
    ));
    e.extend(each(
        "4 cohesive collision",
        "x(t) approach",
        &[(Euler, 1.0, 1e-3), (SymplecticEuler, 2.0, 1e-6), (Verlet, 2.0, 1e-6), (ImplicitDrag, 1.0, 1e-3), (ImplicitDragSymplectic, 2.0, 1e-6)],
    ));
    // Contact begins between steps, where the damping force jumps: first order.
    e.extend(each(
        "4 cohesive collision",
        "x(t) first contact",
        &[(Euler, 1.0, 2e-3), (SymplecticEuler, 1.0, 1e-4), (Verlet, 1.0, 5e-5), (ImplicitDrag, 1.0, 1e-3), (ImplicitDragSymplectic, 1.0, 1e-4)],
    ));
    // The linearised implicit update v' = (v + gΔt)/(1 + α|v|Δt/m) matches the Taylor series to second order.
    e.extend(each(
        "5 quadratic drag",
        "v(t) / v_terminal",
        &[(Euler, 1.0, 1e-3), (SymplecticEuler, 1.0, 1e-3), (Verlet, 2.0, 1e-5), (ImplicitDrag, 2.0, 1e-5), (ImplicitDragSymplectic, 2.0, 1e-5)],
    ));
    e
}

/// Checks every expectation that `rows` has data for (order over the four finest steps).
pub fn verdicts(rows: &[ErrorRow]) -> Vec<Verdict> {
    expectations()
        .into_iter()
        .filter_map(|x| {
            let group: Vec<&ErrorRow> = rows.iter().filter(|r| r.case == x.case && r.measure == x.measure && r.integrator == x.integrator).collect();
            if group.len() < 4 {
                return None;
            }
            let measured_order = fitted_order(&group[group.len() - 4..]);
            let finest_error = group.last().unwrap().error;
            let pass = (measured_order - x.order).abs() <= ORDER_TOLERANCE && finest_error < x.limit;
            Some(Verdict { expectation: x, measured_order, finest_error, pass })
        })
        .collect()
}
