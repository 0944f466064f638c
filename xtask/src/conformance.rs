//! The conformance suite: one list of measurements, run on every backend this build has.
//!
//! Each measurement runs a scene once on a backend and yields one or more
//! observables, each checked against a reference (closed form where one exists)
//! with a tolerance stated per observable and precision. The CPU backend (f64) is
//! the reference implementation; the GPU backend joins this table when it lands.

use tumble::verify;
use tumble_integrate::Integrator;

/// A backend the suite can run on.
#[derive(Clone, Copy, Debug)]
pub enum Backend {
    CpuF64,
}

impl Backend {
    fn name(self) -> &'static str {
        match self {
            Backend::CpuF64 => "cpu-f64",
        }
    }
}

/// One observable: name, measured value, reference, and the allowed relative error
/// (absolute when the reference is 0).
struct Row {
    name: &'static str,
    value: f64,
    reference: f64,
    tolerance: f64,
}

fn row(name: &'static str, value: f64, reference: f64, tolerance: f64) -> Row {
    Row { name, value, reference, tolerance }
}

/// Last tracked sample of a verification scene run with Verlet at `dt` (the plan's when `None`).
fn last(text: &str, dt: Option<f64>) -> tumble::TrackRow {
    verify::trajectory(verify::scene_with(text, Integrator::Verlet, dt)).samples.last().unwrap().1[0]
}

/// Every measurement of the suite on one backend.
fn measurements(_backend: Backend) -> Vec<Row> {
    let tau = 10.0 * 0.01 / (18.0 * 0.00193);
    let mut rows = vec![
        row("stokes drag x(5τ) [m]", last(verify::STOKES_DRAG, Some(tau / 64.0)).position.x, 5.0 * tau + tau * ((-5.0f64).exp() - 1.0), 1e-4),
        // First order: the damping force jumps to zero between two steps at separation.
        row("damped collision rebound speed [m/s]", last(verify::NORMAL_COLLISION, None).velocity.x, 1.6, 1e-2),
        row("elastic collision rebound speed [m/s]", last(verify::ELASTIC_COLLISION, None).velocity.x, 2.0, 1e-4),
        row("sliding stop distance [m]", last(verify::SLIDING, None).position.x, 1.0 / (2.0 * 0.6 * 9.81), 1e-3),
        row(
            "quadratic drag v(2 s) [m/s]",
            last(verify::QUADRATIC_DRAG, Some(1e-3)).velocity.z,
            -(9.81f64 / 0.5).sqrt() * (2.0 * (9.81f64 * 0.5).sqrt()).tanh(),
            1e-4,
        ),
    ];
    let sol = verify::CohesiveSolution::new();
    let t = verify::trajectory(verify::scene_with(verify::COHESIVE_COLLISION, Integrator::Verlet, None));
    let stuck = t.samples.iter().filter(|(time, _)| *time > sol.t_contact).all(|(_, r)| r[0].position.x < 0.15);
    rows.push(row("cohesive collision sticks (1 = stuck)", if stuck { 1.0 } else { 0.0 }, 1.0, 0.0));
    let h = verify::hertz_impact(Integrator::Verlet, None);
    rows.push(row("hertz impact max overlap [m]", h.max_overlap.0, h.max_overlap.1, 1e-2));
    rows.push(row("hertz impact max force [N]", h.max_force.0, h.max_force.1, 1e-2));
    rows.push(row("hertz impact contact time [s]", h.contact_time.0, h.contact_time.1, 1e-2));
    rows.push(row("slide to roll final speed / v0", verify::slide_to_roll(Integrator::Verlet, 50.0).final_speed_ratio, 5.0 / 7.0, 1e-4));
    rows.push(row("energy balance |ΔE| / E0 (2,016 spheres)", verify::energy_balance(2).0, 0.0, 1e-2));
    rows
}

pub fn run(_args: &[String]) -> i32 {
    let backends = [Backend::CpuF64];
    println!("{:<42} {:<8} {:>14} {:>14} {:>10} {:>10}  pass", "observable", "backend", "value", "reference", "error", "tolerance");
    let mut failures = 0;
    let mut markdown = String::from("| observable | backend | value | reference | error | tolerance | pass |\n|---|---|---|---|---|---|---|\n");
    for &b in &backends {
        for r in measurements(b) {
            let error = if r.reference == 0.0 { r.value.abs() } else { ((r.value - r.reference) / r.reference).abs() };
            let pass = error <= r.tolerance && r.value.is_finite();
            failures += usize::from(!pass);
            let verdict = if pass { "pass" } else { "FAIL" };
            println!("{:<42} {:<8} {:>14.6e} {:>14.6e} {:>10.2e} {:>10.0e}  {verdict}", r.name, b.name(), r.value, r.reference, error, r.tolerance);
            markdown +=
                &format!("| {} | {} | {:.6e} | {:.6e} | {:.2e} | {:.0e} | {verdict} |\n", r.name, b.name(), r.value, r.reference, error, r.tolerance);
        }
    }
    let _ = std::fs::create_dir_all("target");
    let _ = std::fs::write("target/conformance.md", markdown);
    if failures > 0 {
        eprintln!("{failures} conformance check(s) failed");
        1
    } else {
        println!("all conformance checks passed on: {}", backends.map(|b| b.name()).join(", "));
        0
    }
}
