//! Scenes the fluid tests share.
#![allow(dead_code)]

use tumble_sph::cases::ColumnInTank;
#[allow(unused_imports)]
pub use tumble_sph::cases::G;
use tumble_sph::*;

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
    ColumnInTank { diffusion, viscosity, ..ColumnInTank::plane(width, column_width, height, per_height) }.build()
}

/// A square 3D tank `width` × `width`, open at the top, full of water to `height`.
pub fn column_3d(width: f64, height: f64, per_height: usize, diffusion: DensityDiffusion, viscosity: Viscosity) -> FluidPhase {
    ColumnInTank { dimension: Dimension::Three, depth: width, diffusion, viscosity, ..ColumnInTank::plane(width, width, height, per_height) }.build()
}

/// Steps `phase` to time `t_end` at its planned time step (the last step shortened to land on it).
pub fn run_to(phase: &mut FluidPhase, t_end: f64, dt: f64) {
    while phase.time() < t_end - 1e-12 {
        let step = dt.min(t_end - phase.time());
        phase.step(step).unwrap_or_else(|e| panic!("{e}"));
    }
}

/// The phase `make` builds, stepped `steps` times at `dt` on `threads` threads.
pub fn stepped_on(threads: usize, steps: usize, dt: f64, make: impl Fn() -> FluidPhase + Sync) -> FluidPhase {
    let pool = rayon::ThreadPoolBuilder::new().num_threads(threads).build().unwrap();
    pool.install(|| {
        let mut phase = make();
        for _ in 0..steps {
            phase.step(dt).unwrap_or_else(|e| panic!("{e}"));
        }
        phase
    })
}

/// A phase `make` builds, restored from `snapshot`'s phase and stepped `steps` more times.
pub fn restored_and_stepped(snapshot: &FluidPhase, steps: usize, dt: f64, make: impl Fn() -> FluidPhase) -> FluidPhase {
    let mut phase = make();
    phase.restore(&snapshot.snapshot()).unwrap();
    for _ in 0..steps {
        phase.step(dt).unwrap_or_else(|e| panic!("{e}"));
    }
    phase
}

/// Water (ρ₀ = 1000 kg/m³, μ = 1e-3 Pa s, c = 10 m/s, h = 1.5 Δp, Fourtakas's δ-SPH with δ = 0.1)
/// in a fully periodic cube of side `side` from the origin, without gravity.
pub fn periodic_water(spacing: f64, side: f64, viscosity: Viscosity, tensile_correction: bool, xsph: f64) -> FluidSettings {
    FluidSettings {
        dimension: Dimension::Three,
        spacing,
        h: 1.5 * spacing,
        rho0: 1000.0,
        mu: 1e-3,
        sound_speed: 10.0,
        viscosity,
        density_diffusion: DensityDiffusion::Fourtakas { delta: 0.1 },
        tensile_correction,
        xsph,
        gravity: tumble_geom::DVec3::ZERO,
        body_force: tumble_geom::DVec3::ZERO,
        domain: tumble_geom::PeriodicBox { min: tumble_geom::DVec3::ZERO, max: tumble_geom::DVec3::splat(side), periodic: [true; 3] },
        moving_walls: Vec::new(),
        floating: Vec::new(),
        inflows: Vec::new(),
        outflows: Vec::new(),
    }
}
