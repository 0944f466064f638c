//! A sphere settling through water at rest under the coupling's forces: the SPH column's own
//! pressure field buoys it, the drag law brakes it, and it reaches the terminal velocity the
//! law gives (the fluid held still: the reaction on it is left out here).

mod common;

use common::*;
use tumble_geom::DVec3;
use tumble_sph::coupling::{Coupling, DragFluid, DragLaw, Solids};
use tumble_sph::*;

/// A 3 mm sphere of density 2500 in a 3D column of water 0.1 m deep (8 and 11 particles over
/// its height: h/d = 6.3 and 4.5), with a viscosity of 1 Pa s for the drag (Re ~ 0.02, the
/// Stokes regime), released at mid-depth and integrated alone for 0.1 s (80 relaxation times)
/// in the fluid's hydrostatic field: its speed through the water about it reaches the balance of
/// weight, buoyancy and drag, (ρ_s − ρ_f) g = k v, within 1 % under both drag laws, and the
/// buoyancy it felt is within 1 % of ρ_f V g (without it the speed would be 3 times too high).
#[test]
fn a_sphere_settles_at_the_terminal_velocity_of_its_drag_law() {
    for per_height in [8, 11] {
        settles(per_height);
    }
}

fn settles(per_height: usize) {
    let mut phase = column_3d(0.1, 0.1, per_height, DensityDiffusion::Fourtakas { delta: 0.1 }, Viscosity::Artificial { alpha: 0.02 });
    let dt = TimeStepLimits::planned(phase.settings()).dt();
    // A few steps give the rates of a column already in hydrostatic balance.
    for _ in 0..5 {
        phase.step(dt).unwrap();
    }
    let (s, theta) = (phase.settings().clone(), phase.fluid_acceleration());
    let (rho_f, g) = (s.rho0, s.gravity);
    let (d, rho_s, mu) = (0.003, 2500.0, 1.0);
    let volume = std::f64::consts::PI * d * d * d / 6.0;
    let water = DragFluid { density: rho_f, viscosity: mu };
    let domain = tumble_geom::PeriodicBox { min: DVec3::splat(-0.05), max: DVec3::new(0.15, 0.15, 0.2), periodic: [false; 3] };
    for law in [DragLaw::Gidaspow, DragLaw::DiFelice] {
        let coupling = Coupling::new(s.h, Dimension::Three, domain, law, water).unwrap();
        let (mut x, mut v) = (DVec3::new(0.05, 0.05, 0.05), DVec3::ZERO);
        let (step, mass) = (2.0e-4, rho_s * volume);
        let mut last = tumble_sph::coupling::CouplingForces::default();
        for _ in 0..500 {
            last = coupling.evaluate(phase.particles(), &theta, Solids { position: &[x], velocity: &[v], radius: &[0.5 * d] });
            v += step * (g + last.force[0] / mass);
            x += step * v;
        }
        let buoyancy = last.force[0] - last.drag[0];
        let eps = last.solid_fraction[0];
        // The law's terminal speed: (ρ_s − ρ_f) g = k(ε, v) v, solved by fixed-point iteration.
        let mut terminal: f64 = 0.0;
        for _ in 0..50 {
            terminal = (rho_s - rho_f) * g.length() / law.coefficient(&water, d, eps, terminal.max(1e-12));
        }
        // Settling is relative to the water about it (the column's start-up leaves it stirring
        // at a fraction of a millimetre per second).
        let slip = v - last.fluid_velocity[0];
        println!(
            "{law:?}: settles at {:.5e} m/s through water moving at {:.3} m/s, against the law's {terminal:.5e} (Stokes {:.5e}); buoyancy {:.4e} N against ρ V g = {:.4e} N; ε = {eps:.5}, h/d = {:.2}",
            -slip.z,
            last.fluid_velocity[0],
            (rho_s - rho_f) * g.length() * d * d / (18.0 * mu),
            buoyancy.z,
            rho_f * volume * g.length(),
            s.h / d
        );
        assert!((buoyancy.z / (rho_f * volume * g.length()) - 1.0).abs() < 0.01, "{law:?}: buoyancy {}", buoyancy.z);
        assert!((-slip.z / terminal - 1.0).abs() < 0.01, "{law:?}: {} against {terminal}", -slip.z);
        assert!(slip.x.abs() + slip.y.abs() < 0.01 * terminal, "{law:?}: slips sideways at {slip}");
    }
}
