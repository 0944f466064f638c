//! The validation cases as settings and particles, shared by the tests, the speed example and
//! `cargo xtask sph`: a column of water in a tank (at rest, or released as a dam break).

use tumble_geom::{DVec3, PeriodicBox};

use crate::kernel::Dimension;
use crate::particles::{Aabb, FluidParticles};
use crate::phase::FluidPhase;
use crate::settings::{DensityDiffusion, FluidSettings, Viscosity};
use crate::setup::{add_fluid_block, add_wall_box};

/// Standard gravity, m/s².
pub const G: f64 = 9.81;

/// A column of water `column_width` × `height` against the left wall of a tank `tank_length`
/// long, open at the top (2D in the x–z plane, or 3D with the tank `depth` deep and the column
/// filling it).
#[derive(Clone, Copy, Debug)]
pub struct ColumnInTank {
    pub dimension: Dimension,
    pub tank_length: f64,
    pub depth: f64,
    pub column_width: f64,
    pub height: f64,
    /// Particles over the column's height.
    pub per_height: usize,
    /// c₀ / √(2 g H): 10 keeps the density within about 1 %.
    pub sound_speed_factor: f64,
    pub diffusion: DensityDiffusion,
    pub viscosity: Viscosity,
    pub tensile_correction: bool,
}

impl ColumnInTank {
    /// A 2D column at rest filling a tank `width` wide (Fourtakas δ-SPH, α = 0.02, c₀ = 10 √(2gH)).
    pub fn plane(tank_length: f64, column_width: f64, height: f64, per_height: usize) -> Self {
        ColumnInTank {
            dimension: Dimension::Two,
            tank_length,
            depth: 0.0,
            column_width,
            height,
            per_height,
            sound_speed_factor: 10.0,
            diffusion: DensityDiffusion::Fourtakas { delta: 0.1 },
            viscosity: Viscosity::Artificial { alpha: 0.02 },
            tensile_correction: false,
        }
    }

    pub fn spacing(&self) -> f64 {
        self.height / self.per_height as f64
    }

    /// The phase, fluid at rest in hydrostatic balance; the tank's walls reach 1.5 H.
    pub fn build(&self) -> FluidPhase {
        let dp = self.spacing();
        let layers = 3.0 * dp;
        let three_d = self.dimension == Dimension::Three;
        let settings = FluidSettings {
            dimension: self.dimension,
            spacing: dp,
            h: 1.5 * dp,
            rho0: 1000.0,
            mu: 1e-3,
            sound_speed: self.sound_speed_factor * (2.0 * G * self.height).sqrt(),
            viscosity: self.viscosity,
            density_diffusion: self.diffusion,
            tensile_correction: self.tensile_correction,
            xsph: 0.0,
            gravity: DVec3::new(0.0, 0.0, -G),
            body_force: DVec3::ZERO,
            domain: PeriodicBox {
                min: DVec3::new(-layers, if three_d { -layers } else { 0.0 }, -layers),
                max: DVec3::new(self.tank_length + layers, if three_d { self.depth + layers } else { 0.0 }, 1.5 * self.height),
                periodic: [false; 3],
            },
            moving_walls: Vec::new(),
            floating: Vec::new(),
            inflows: Vec::new(),
            outflows: Vec::new(),
        };
        let mut particles = FluidParticles::default();
        let depth = if three_d { self.depth } else { 0.0 };
        add_fluid_block(&mut particles, &settings, Aabb::new(DVec3::ZERO, DVec3::new(self.column_width, depth, self.height)), DVec3::ZERO);
        let tank = Aabb::new(DVec3::ZERO, DVec3::new(self.tank_length, depth, 1.5 * self.height));
        add_wall_box(&mut particles, &settings, tank, [[true, true], [three_d, three_d], [true, false]], DVec3::ZERO);
        FluidPhase::new(settings, particles).expect("a column in a tank is a valid fluid")
    }
}

/// Martin & Moyce (1952), Phil. Trans. R. Soc. A 244, 312–324, Fig. 3, n² = 2, a = 2.25 in:
/// the surge front Z = x/a against T = t √(2g/a), as digitised in PySPH's examples.
pub const MARTIN_MOYCE_FRONT: [(f64, f64); 7] =
    [(0.832, 1.217), (1.219, 1.474), (1.997, 2.292), (2.547, 2.995), (3.345, 4.134), (4.034, 4.944), (4.418, 5.881)];

/// A recorded quantity at time `t`, interpolated linearly between the two rows around it
/// (`time` and `value` read a row); none outside the record.
pub fn interpolate<R>(rows: &[R], t: f64, time: impl Fn(&R) -> f64, value: impl Fn(&R) -> f64) -> Option<f64> {
    let k = rows.partition_point(|r| time(r) < t);
    if k == 0 || k >= rows.len() {
        return None;
    }
    let (r0, r1) = (&rows[k - 1], &rows[k]);
    Some(value(r0) + (value(r1) - value(r0)) * (t - time(r0)) / (time(r1) - time(r0)))
}
