//! A column of water at rest in a tank keeps the hydrostatic pressure ρ g z, its walls tight
//! and its surface flat, with and without density diffusion.

mod common;

use common::*;
use tumble_geom::DVec3;
use tumble_sph::*;

/// `pressure_tolerance` is a fraction of the bottom pressure ρ g H.
fn check_column(diffusion: DensityDiffusion, viscosity: Viscosity, pressure_tolerance: f64) {
    let (width, height, n) = (0.2, 0.4, 40);
    let mut phase = column_in_tank(width, width, height, n, diffusion, viscosity);
    let dt = TimeStepLimits::planned(phase.settings()).dt();
    let dp = phase.settings().spacing;
    let h = phase.settings().h;
    let rho0 = phase.settings().rho0;
    let bottom = rho0 * G * height;
    let t_settle = 1.0;
    run_to(&mut phase, t_settle, dt);
    let o = phase.observables();
    // Pressure along the centre line, every Δp from 2h below the surface down to the floor.
    let mut worst: f64 = 0.0;
    let mut depth = 2.0 * h;
    while depth <= height - 0.5 * dp {
        let z = height - depth;
        let p = phase.pressure_at(DVec3::new(0.5 * width, 0.0, z)).expect("inside the fluid");
        worst = worst.max((p - rho0 * G * depth).abs() / bottom);
        depth += dp;
    }
    // Surface: the highest particle of each lattice column.
    let p = phase.particles();
    let columns = (width / dp).round() as usize;
    let mut tops = vec![f64::NEG_INFINITY; columns];
    let mut escaped = 0;
    for i in 0..p.len() {
        if p.kind[i] != ParticleKind::Fluid {
            continue;
        }
        let x = p.position[i];
        if x.x < 0.0 || x.x > width || x.z < 0.0 {
            escaped += 1;
            continue;
        }
        let c = ((x.x / dp) as usize).min(columns - 1);
        tops[c] = tops[c].max(x.z);
    }
    let spread = |tops: &[f64]| tops.iter().cloned().fold(f64::NEG_INFINITY, f64::max) - tops.iter().cloned().fold(f64::INFINITY, f64::min);
    // The columns within 2h of a side wall sit lower (the wall's extrapolated pressure pulls the
    // corner's particles down by about a tenth of a spacing): judged apart.
    let beside_wall = (2.0 * h / dp).ceil() as usize;
    let flat = spread(&tops[beside_wall..columns - beside_wall]);
    let flat_with_corners = spread(&tops);
    println!(
        "{diffusion:?} {viscosity:?}: worst pressure error {:.3} % of ρgH, density deviation {:.3} %, surface spread {:.3} Δp ({:.3} Δp with the columns by the walls), KE {:.3e} J/m, escaped {escaped}",
        100.0 * worst,
        100.0 * o.largest_density_deviation,
        flat / dp,
        flat_with_corners / dp,
        o.kinetic_energy
    );
    assert_eq!(escaped, 0, "fluid particles crossed a wall");
    assert!(worst < pressure_tolerance, "pressure off hydrostatic by {:.3} % of the bottom pressure", 100.0 * worst);
    assert!(o.largest_density_deviation < 0.01);
    assert!(flat < 0.1 * dp, "surface not flat: {:.3} Δp", flat / dp);
    assert!(flat_with_corners < 0.2 * dp, "surface by the walls not flat: {:.3} Δp", flat_with_corners / dp);
}

#[test]
fn column_at_rest_without_diffusion() {
    check_column(DensityDiffusion::None, Viscosity::Artificial { alpha: 0.02 }, 0.02);
}

#[test]
fn column_at_rest_with_fourtakas_diffusion() {
    check_column(DensityDiffusion::Fourtakas { delta: 0.1 }, Viscosity::Artificial { alpha: 0.02 }, 0.02);
}

#[test]
/// The whole density difference diffuses, pulling the column's hydrostatic gradient towards
/// uniform: the pressure near the floor drifts low (2.3 % of ρgH after 1 s, and growing), which is
/// why the hydrostatic-corrected form is the default.
fn column_at_rest_with_molteni_colagrossi_diffusion() {
    check_column(DensityDiffusion::MolteniColagrossi { delta: 0.1 }, Viscosity::Artificial { alpha: 0.02 }, 0.03);
}

#[test]
fn column_at_rest_with_laminar_viscosity() {
    check_column(DensityDiffusion::Fourtakas { delta: 0.1 }, Viscosity::Laminar, 0.02);
}

/// The same column in 3D (a square tank, 16 particles over the height at CI size): pressure on
/// the vertical axis, density, walls.
#[test]
fn column_at_rest_in_3d() {
    let (width, height, n) = (0.1, 0.16, 16);
    let mut phase = column_3d(width, height, n, DensityDiffusion::Fourtakas { delta: 0.1 }, Viscosity::Artificial { alpha: 0.02 });
    let dt = TimeStepLimits::planned(phase.settings()).dt();
    let (dp, h, rho0) = (phase.settings().spacing, phase.settings().h, phase.settings().rho0);
    run_to(&mut phase, 0.5, dt);
    let o = phase.observables();
    let bottom = rho0 * G * height;
    let mut worst: f64 = 0.0;
    let mut depth = 2.0 * h;
    while depth <= height - 0.5 * dp {
        let p = phase.pressure_at(DVec3::new(0.5 * width, 0.5 * width, height - depth)).expect("inside the fluid");
        worst = worst.max((p - rho0 * G * depth).abs() / bottom);
        depth += dp;
    }
    let p = phase.particles();
    let escaped = (0..p.len())
        .filter(|&i| p.kind[i] == ParticleKind::Fluid)
        .filter(|&i| {
            let x = p.position[i];
            x.x < 0.0 || x.x > width || x.y < 0.0 || x.y > width || x.z < 0.0
        })
        .count();
    println!(
        "3D column: worst pressure error {:.3} % of ρgH, density deviation {:.3} %, escaped {escaped}",
        100.0 * worst,
        100.0 * o.largest_density_deviation
    );
    assert_eq!(escaped, 0);
    assert!(worst < 0.02, "pressure off hydrostatic by {:.3} % of ρgH", 100.0 * worst);
    assert!(o.largest_density_deviation < 0.01);
}
