//! The conformance suite: one list of observables, run on every backend this build has.
//!
//! Each observable is a closure from a backend to a measured value, checked against a
//! reference (closed form where one exists) with a tolerance stated per observable and
//! precision. The CPU backend (f64) is the reference implementation; the GPU backend
//! joins this table when it lands.

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

struct Observable {
    name: &'static str,
    reference: f64,
    /// Allowed |value − reference| / |reference| (absolute when the reference is 0).
    tolerance: f64,
    measure: fn(Backend) -> f64,
}

fn observables() -> Vec<Observable> {
    vec![
        Observable {
            name: "stokes drag x(5τ) [m]",
            reference: {
                let tau = 10.0 * 0.01 / (18.0 * 0.00193);
                5.0 * tau + tau * ((-5.0f64).exp() - 1.0)
            },
            tolerance: 1e-4,
            measure: |_| {
                let t = verify::trajectory(verify::scene_with(verify::STOKES_DRAG, Integrator::Verlet, Some(10.0 * 0.01 / (18.0 * 0.00193) / 64.0)));
                t.samples.last().unwrap().1[0].position.x
            },
        },
        Observable {
            name: "damped collision rebound speed [m/s]",
            reference: 1.6,
            // First order: the damping force jumps to zero between two steps at separation.
            tolerance: 1e-2,
            measure: |_| verify::trajectory(verify::scene_with(verify::NORMAL_COLLISION, Integrator::Verlet, None)).samples.last().unwrap().1[0].velocity.x,
        },
        Observable {
            name: "elastic collision rebound speed [m/s]",
            reference: 2.0,
            tolerance: 1e-4,
            measure: |_| verify::trajectory(verify::scene_with(verify::ELASTIC_COLLISION, Integrator::Verlet, None)).samples.last().unwrap().1[0].velocity.x,
        },
        Observable {
            name: "sliding stop distance [m]",
            reference: 1.0 / (2.0 * 0.6 * 9.81),
            tolerance: 1e-3,
            measure: |_| verify::trajectory(verify::scene_with(verify::SLIDING, Integrator::Verlet, None)).samples.last().unwrap().1[0].position.x,
        },
        Observable {
            name: "cohesive collision sticks (1 = stuck)",
            reference: 1.0,
            tolerance: 0.0,
            measure: |_| {
                let t = verify::trajectory(verify::scene_with(verify::COHESIVE_COLLISION, Integrator::Verlet, None));
                let sol = verify::CohesiveSolution::new();
                let stuck = t.samples.iter().filter(|(time, _)| *time > sol.t_contact).all(|(_, r)| r[0].position.x < 0.15);
                if stuck { 1.0 } else { 0.0 }
            },
        },
        Observable {
            name: "quadratic drag v(2 s) [m/s]",
            reference: -(9.81f64 / 0.5).sqrt() * (2.0 * (9.81f64 * 0.5).sqrt()).tanh(),
            tolerance: 1e-4,
            measure: |_| verify::trajectory(verify::scene_with(verify::QUADRATIC_DRAG, Integrator::Verlet, Some(1e-3))).samples.last().unwrap().1[0].velocity.z,
        },
        Observable {
            name: "hertz impact max overlap [m]",
            reference: verify::hertz_impact(Integrator::Verlet, None).max_overlap.1,
            tolerance: 1e-2,
            measure: |_| verify::hertz_impact(Integrator::Verlet, None).max_overlap.0,
        },
        Observable {
            name: "hertz impact max force [N]",
            reference: verify::hertz_impact(Integrator::Verlet, None).max_force.1,
            tolerance: 1e-2,
            measure: |_| verify::hertz_impact(Integrator::Verlet, None).max_force.0,
        },
        Observable {
            name: "hertz impact contact time [s]",
            reference: verify::hertz_impact(Integrator::Verlet, None).contact_time.1,
            tolerance: 1e-2,
            measure: |_| verify::hertz_impact(Integrator::Verlet, None).contact_time.0,
        },
        Observable {
            name: "slide to roll final speed / v0",
            reference: 5.0 / 7.0,
            tolerance: 1e-4,
            measure: |_| verify::slide_to_roll(Integrator::Verlet, 50.0).final_speed_ratio,
        },
        Observable {
            name: "energy balance |ΔE| / E0 (2,016 spheres)",
            reference: 0.0,
            tolerance: 1e-2,
            measure: |_| verify::energy_balance(2).0,
        },
    ]
}

pub fn run(_args: &[String]) -> i32 {
    let backends = [Backend::CpuF64];
    println!("{:<42} {:<8} {:>14} {:>14} {:>10} {:>10}  pass", "observable", "backend", "value", "reference", "error", "tolerance");
    let mut failures = 0;
    let mut markdown = String::from("| observable | backend | value | reference | error | tolerance | pass |\n|---|---|---|---|---|---|---|\n");
    for o in observables() {
        for &b in &backends {
            let value = (o.measure)(b);
            let error = if o.reference == 0.0 { value.abs() } else { ((value - o.reference) / o.reference).abs() };
            let pass = error <= o.tolerance && value.is_finite();
            failures += usize::from(!pass);
            println!(
                "{:<42} {:<8} {:>14.6e} {:>14.6e} {:>10.2e} {:>10.0e}  {}",
                o.name,
                b.name(),
                value,
                o.reference,
                error,
                o.tolerance,
                if pass { "pass" } else { "FAIL" }
            );
            markdown += &format!("| {} | {} | {:.6e} | {:.6e} | {:.2e} | {:.0e} | {} |\n", o.name, b.name(), value, o.reference, error, o.tolerance, if pass { "pass" } else { "FAIL" });
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
