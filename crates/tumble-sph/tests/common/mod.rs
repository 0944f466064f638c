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
