use super::*;
use crate::cases::ColumnInTank;
use crate::settings::MovingWall;

/// Every pair within 2h at the end of every step is in the lists the next step reads, for a
/// collapsing column whose lists are kept over several steps; and they are kept (the run
/// rebuilt them fewer times than it stepped).
#[test]
fn the_neighbour_lists_never_miss_a_pair() {
    let mut phase = ColumnInTank::plane(0.3, 0.1, 0.2, 16).build();
    let dt = TimeStepLimits::planned(phase.settings()).dt();
    let reach2 = 4.0 * phase.settings().h * phase.settings().h;
    let mut builds = 0;
    for _ in 0..400 {
        phase.step(dt).unwrap();
        if phase.lists_due {
            builds += 1;
            continue;
        }
        let p = &phase.particles;
        for a in 0..p.len() {
            for b in 0..p.len() {
                if a == b || p.kind[a] == ParticleKind::Wall && p.kind[b] == ParticleKind::Wall {
                    continue;
                }
                if phase.grid.separation(p.position[a], p.position[b]).length_squared() < reach2 {
                    let listed = if p.kind[a] == ParticleKind::Fluid || p.kind[b] == ParticleKind::Fluid {
                        phase.grid.neighbours(a).contains(&(b as u32))
                    } else {
                        true
                    };
                    assert!(listed, "step {}: pair {a}-{b} within 2h is not listed", phase.steps);
                }
            }
        }
    }
    assert!(builds > 0 && builds < 200, "{builds} rebuilds in 400 steps");
}

/// The pair passes give the same bits in 256-bit lanes (AVX2) as in 128-bit ones, in 2D and
/// 3D, with every switch of the method on: no fused multiply–add or reordering creeps in.
#[test]
fn wide_and_narrow_lanes_give_the_same_bits() {
    let variants = [
        (Viscosity::Artificial { alpha: 0.02 }, crate::DensityDiffusion::Fourtakas { delta: 0.1 }, true, 0.5),
        (Viscosity::Laminar, crate::DensityDiffusion::MolteniColagrossi { delta: 0.1 }, false, 0.0),
    ];
    for three_d in [false, true] {
        for (viscosity, diffusion, tensile, xsph) in variants {
            let mut case = ColumnInTank::plane(0.3, 0.1, 0.2, 12);
            if three_d {
                case.dimension = crate::Dimension::Three;
                case.depth = 0.05;
            }
            (case.viscosity, case.diffusion, case.tensile_correction) = (viscosity, diffusion, tensile);
            let column = case.build();
            let settings = FluidSettings { xsph, ..column.settings().clone() };
            let mut wide = FluidPhase::new(settings.clone(), column.particles().clone()).unwrap();
            let mut narrow = FluidPhase::new(settings, column.particles().clone()).unwrap();
            narrow.method.wide_lanes = false;
            let dt = TimeStepLimits::planned(wide.settings()).dt();
            for _ in 0..60 {
                wide.step(dt).unwrap();
                narrow.step(dt).unwrap();
            }
            assert!(wide.particles == narrow.particles, "3D: {three_d}, {viscosity:?}");
            assert!(wide.particles.velocity.iter().any(|v| v.length() > 0.01), "the column has not moved");
        }
    }
}

/// A drum turning with the water inside in solid-body rotation: the walls' extrapolated
/// pressure matches p = ρ ω² r²/2 at the wall particles within a few pascals, because the
/// wall's centripetal acceleration enters Adami's condition; left out, the wall particles one
/// to two spacings beyond the water would read ρ ω² R d ≈ 50–110 Pa low.
#[test]
fn a_turning_walls_acceleration_enters_its_pressure() {
    use tumble_geom::{Cylinder, Motion, Timing};
    let (radius, dp, omega, rho0) = (0.1, 0.005, 10.0, 1000.0);
    let reach = radius + 4.0 * dp;
    let settings = FluidSettings {
        dimension: crate::Dimension::Two,
        spacing: dp,
        h: 1.5 * dp,
        rho0,
        mu: 1e-3,
        sound_speed: 20.0,
        viscosity: Viscosity::Artificial { alpha: 0.02 },
        density_diffusion: crate::DensityDiffusion::None,
        tensile_correction: false,
        xsph: 0.0,
        gravity: DVec3::ZERO,
        body_force: DVec3::ZERO,
        domain: tumble_geom::PeriodicBox { min: DVec3::new(-reach, 0.0, -reach), max: DVec3::new(reach, 0.0, reach), periodic: [false; 3] },
        moving_walls: vec![MovingWall { motion: Motion::Rotate { point: DVec3::ZERO, axis: DVec3::Y, omega }, timing: Timing::ALWAYS }],
        floating: Vec::new(),
        inflows: Vec::new(),
        outflows: Vec::new(),
    };
    let eos = Tait::new(rho0, settings.sound_speed);
    let exact = |r: f64| 0.5 * rho0 * omega * omega * r * r;
    let mut particles = FluidParticles::default();
    let rings = (radius / dp).round() as usize;
    for x in crate::cylinder_shell(&Cylinder::new(DVec3::ZERO, DVec3::Y, radius, 1.0, false), rings, dp, crate::Dimension::Two) {
        let v = omega * DVec3::Y.cross(x);
        particles.push(ParticleKind::Fluid, x, v, eos.density(exact(x.length())), rho0 * dp * dp);
    }
    let first_wall = particles.len();
    crate::add_wall_cylinder(&mut particles, &settings, &Cylinder::new(DVec3::ZERO, DVec3::Y, radius, 1.0, true), DVec3::ZERO);
    particles.assign_moving_wall(first_wall, 1);
    let mut phase = FluidPhase::new(settings, particles).unwrap();
    let settings = phase.settings.clone();
    let walls = WallsAt { settings: &settings, bodies: &[], time: 0.0 };
    crate::rates::prepare(&phase.method, &phase.grid, &mut phase.particles, &mut phase.inputs, walls);
    let p = &phase.particles;
    let mut worst: f64 = 0.0;
    let mut checked = 0;
    for i in 0..p.len() {
        let r = p.position[i].length();
        if p.kind[i] == ParticleKind::Wall && r < radius + 2.0 * dp {
            worst = worst.max((phase.inputs.pressure[i] - exact(r)).abs());
            checked += 1;
        }
    }
    println!("{checked} wall particles: largest error {worst:.2} Pa of the wall pressure");
    assert!(checked > 100, "{checked} wall particles checked");
    assert!(worst < 15.0, "the wall pressure is {worst:.1} Pa off rho omega² r²/2 (rho omega² R dp = {:.0} Pa)", rho0 * omega * omega * radius * dp);
}
