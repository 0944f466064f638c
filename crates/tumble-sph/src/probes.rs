//! What experiments measure in a flow, interpolated from the fluid particles with the kernel:
//! pressure and velocity at a point (Shepard-normalised), the water height along a vertical
//! line (a wave gauge), and the surge front.

use tumble_geom::DVec3;

use crate::particles::ParticleKind;
use crate::phase::FluidPhase;

/// Kernel sums of the fluid around a point: Σ W V_b and the weighted pressure and velocity.
#[derive(Clone, Copy, Debug, Default)]
struct Interpolation {
    fraction: f64,
    pressure: f64,
    velocity: DVec3,
}

fn interpolate(phase: &FluidPhase, x: DVec3) -> Interpolation {
    let p = phase.particles();
    let kernel = phase.kernel();
    let eos = phase.equation_of_state();
    let grid = phase.grid();
    let reach2 = kernel.support() * kernel.support();
    let mut s = Interpolation::default();
    grid.for_each_candidate_near(x, |b| {
        if p.kind[b] != ParticleKind::Fluid {
            return;
        }
        let d = grid.separation(x, p.position[b]);
        let r2 = d.length_squared();
        if r2 >= reach2 {
            return;
        }
        let wv = kernel.value(r2.sqrt()) * p.mass[b] / p.density[b];
        s.fraction += wv;
        s.pressure += wv * eos.pressure(phase.intrinsic_density(b));
        s.velocity += wv * p.velocity[b];
    });
    s
}

impl FluidPhase {
    /// The kernel-interpolated fluid fraction Σ_b W(x − x_b) V_b at `x` (≈ 1 inside the fluid).
    pub fn fluid_fraction(&self, x: DVec3) -> f64 {
        interpolate(self, x).fraction
    }

    /// Pressure at `x`, Σ P_b W V_b / Σ W V_b, where the fluid fraction there exceeds one half.
    pub fn pressure_at(&self, x: DVec3) -> Option<f64> {
        let s = interpolate(self, x);
        (s.fraction > 0.5).then(|| s.pressure / s.fraction)
    }

    /// Velocity at `x`, Shepard-normalised like [`FluidPhase::pressure_at`].
    pub fn velocity_at(&self, x: DVec3) -> Option<DVec3> {
        let s = interpolate(self, x);
        (s.fraction > 0.5).then(|| s.velocity / s.fraction)
    }

    /// A wave gauge on the vertical line through `base` (x and y) from `base.z` up to `top`: the
    /// highest sample, spaced at most Δp/4, where the fluid fraction is at least one half, then
    /// where the fraction crosses one half between it and the sample above, found by bisection
    /// to 10⁻⁶ Δp (the samples alone would read up to Δp/4 low, Δp/8 on average); `base.z` when
    /// no sample has fluid.
    pub fn water_height(&self, base: DVec3, top: f64) -> f64 {
        let step = 0.25 * self.settings().spacing;
        let samples = ((top - base.z) / step).ceil().max(1.0) as usize;
        let dz = (top - base.z) / samples as f64;
        let wet = |z: f64| self.fluid_fraction(DVec3::new(base.x, base.y, z)) >= 0.5;
        let Some(k) = (0..=samples).rev().find(|&k| wet(base.z + k as f64 * dz)) else { return base.z };
        let (mut low, mut high) = (base.z + k as f64 * dz, base.z + (k + 1) as f64 * dz);
        if k == samples {
            return low;
        }
        while high - low > 1e-6 * self.settings().spacing {
            let mid = 0.5 * (low + high);
            if wet(mid) { low = mid } else { high = mid }
        }
        low
    }

    /// The surge front: the largest coordinate of the fluid along the unit vector `direction`.
    pub fn front(&self, direction: DVec3) -> f64 {
        let p = self.particles();
        (0..p.len()).filter(|&i| p.kind[i] == ParticleKind::Fluid).map(|i| direction.dot(p.position[i])).fold(f64::NEG_INFINITY, f64::max)
    }
}
