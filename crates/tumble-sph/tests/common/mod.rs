//! Scenes the fluid tests share, written as settings and particles.
#![allow(dead_code)]

use tumble_geom::{DVec3, PeriodicBox};
use tumble_sph::*;

pub const G: f64 = 9.81;

/// A 2D tank of width `width` open at the top, holding a column `column_width` × `height` against
/// its left wall, resolved with `per_height` particles over the height.
pub fn column_in_tank(
    width: f64,
    column_width: f64,
    height: f64,
    per_height: usize,
    diffusion: DensityDiffusion,
    viscosity: Viscosity,
) -> FluidPhase {
    let dp = height / per_height as f64;
    let v_max = (2.0 * G * height).sqrt();
    let layers = 3.0 * dp;
    let settings = FluidSettings {
        dimension: Dimension::Two,
        spacing: dp,
        h: 1.5 * dp,
        rho0: 1000.0,
        mu: 1e-3,
        sound_speed: 10.0 * v_max,
        viscosity,
        density_diffusion: diffusion,
        tensile_correction: false,
        xsph: 0.0,
        gravity: DVec3::new(0.0, 0.0, -G),
        body_force: DVec3::ZERO,
        domain: PeriodicBox { min: DVec3::new(-layers, 0.0, -layers), max: DVec3::new(width + layers, 0.0, 2.0 * height), periodic: [false; 3] },
    };
    let mut particles = FluidParticles::default();
    add_fluid_block(&mut particles, &settings, Aabb::new(DVec3::ZERO, DVec3::new(column_width, 0.0, height)), DVec3::ZERO);
    let tank = Aabb::new(DVec3::ZERO, DVec3::new(width, 0.0, 2.0 * height));
    add_wall_box(&mut particles, &settings, tank, [[true, true], [false, false], [true, false]], DVec3::ZERO);
    FluidPhase::new(settings, particles).expect("valid fluid")
}

/// A square 3D tank `width` × `width`, open at the top, full of water to `height`.
pub fn column_3d(width: f64, height: f64, per_height: usize, diffusion: DensityDiffusion, viscosity: Viscosity) -> FluidPhase {
    let dp = height / per_height as f64;
    let v_max = (2.0 * G * height).sqrt();
    let layers = 3.0 * dp;
    let settings = FluidSettings {
        dimension: Dimension::Three,
        spacing: dp,
        h: 1.5 * dp,
        rho0: 1000.0,
        mu: 1e-3,
        sound_speed: 10.0 * v_max,
        viscosity,
        density_diffusion: diffusion,
        tensile_correction: false,
        xsph: 0.0,
        gravity: DVec3::new(0.0, 0.0, -G),
        body_force: DVec3::ZERO,
        domain: PeriodicBox { min: DVec3::splat(-layers), max: DVec3::new(width + layers, width + layers, 1.5 * height), periodic: [false; 3] },
    };
    let mut particles = FluidParticles::default();
    add_fluid_block(&mut particles, &settings, Aabb::new(DVec3::ZERO, DVec3::new(width, width, height)), DVec3::ZERO);
    let tank = Aabb::new(DVec3::ZERO, DVec3::new(width, width, 1.5 * height));
    add_wall_box(&mut particles, &settings, tank, [[true, true], [true, true], [true, false]], DVec3::ZERO);
    FluidPhase::new(settings, particles).expect("valid fluid")
}

/// Steps `phase` to time `t_end` at its planned time step (the last step shortened to land on it).
pub fn run_to(phase: &mut FluidPhase, t_end: f64, dt: f64) {
    while phase.time() < t_end - 1e-12 {
        let step = dt.min(t_end - phase.time());
        phase.step(step).unwrap_or_else(|e| panic!("{e}"));
    }
}
