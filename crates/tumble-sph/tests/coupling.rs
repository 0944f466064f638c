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

/// Two-way: five spheres thrown through a fully periodic box of water (no gravity), the
/// fluid taking each sphere's reaction, both stepped 100 times with the coupling's forces held
/// over each fluid step. The momentum of water and spheres together stays what it was to
/// round-off while the spheres hand most of theirs to the water.
#[test]
fn spheres_and_water_in_a_periodic_box_conserve_their_momentum() {
    let dp = 0.01;
    let side = 10.0 * dp;
    let settings = periodic_water(dp, side, Viscosity::Laminar, false, 0.0);
    let domain = settings.domain;
    let mut particles = FluidParticles::default();
    add_fluid_block(&mut particles, &settings, Aabb::new(DVec3::ZERO, DVec3::splat(side)), DVec3::ZERO);
    let mut phase = FluidPhase::new(settings.clone(), particles).unwrap();
    let water = DragFluid { density: 1000.0, viscosity: 1e-3 };
    let coupling = Coupling::new(settings.h, Dimension::Three, domain, DragLaw::Gidaspow, water).unwrap();
    let (radius, density) = (vec![0.004; 5], 2500.0);
    let mass: Vec<f64> = radius.iter().map(|r| density * 4.0 / 3.0 * std::f64::consts::PI * r * r * r).collect();
    let mut x: Vec<DVec3> = (0..5).map(|k| DVec3::new(0.013 + 0.017 * k as f64, 0.05 + 0.009 * k as f64, 0.031 * k as f64 + 0.01)).collect();
    let mut v: Vec<DVec3> = (0..5).map(|k| DVec3::new(0.3 - 0.1 * k as f64, 0.05 * k as f64, -0.2)).collect();
    let momentum = |phase: &FluidPhase, v: &[DVec3]| phase.observables().momentum + v.iter().zip(&mass).map(|(v, m)| *m * *v).sum::<DVec3>();
    let solids_momentum = |v: &[DVec3]| v.iter().zip(&mass).map(|(v, m)| *m * *v).sum::<DVec3>();
    let (start, thrown) = (momentum(&phase, &v), solids_momentum(&v));
    let scale: f64 = v.iter().zip(&mass).map(|(v, m)| m * v.length()).sum();
    let dt = TimeStepLimits::planned(phase.settings()).dt();
    for _ in 0..100 {
        let out = coupling.evaluate(phase.particles(), &phase.fluid_acceleration(), Solids { position: &x, velocity: &v, radius: &radius });
        phase.set_coupled_forces(&out.reaction);
        phase.step(dt).unwrap();
        for k in 0..5 {
            v[k] += dt * out.force[k] / mass[k];
            x[k] = domain.wrap(x[k] + dt * v[k]);
        }
    }
    let drift = (momentum(&phase, &v) - start).length() / scale;
    let handed = 1.0 - solids_momentum(&v).length() / thrown.length();
    println!("after 100 steps the spheres kept {:.1} % of their momentum; fluid + spheres drifted by {drift:.2e} of Σ m|v|", 100.0 * (1.0 - handed));
    assert!(handed > 0.1, "the spheres must hand on a good share of their momentum for this to test anything: {handed}");
    assert!(drift < 1e-12, "momentum drifted by {drift:.2e}");
}
