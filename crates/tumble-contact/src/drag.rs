//! One-way fluid drag and the flow fields it sees.

use glam::DVec3;

/// A prescribed fluid velocity field.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum FlowField {
    Uniform(DVec3),
    /// Taylor–Green vortex with amplitude A and frequency a (docs/physics.md, "Drag and flow fields").
    TaylorGreen {
        amplitude: f64,
        frequency: f64,
    },
}

impl FlowField {
    /// Fluid velocity at `x` (the fields here are steady).
    #[inline]
    pub fn velocity(&self, x: DVec3) -> DVec3 {
        match *self {
            FlowField::Uniform(u) => u,
            FlowField::TaylorGreen { amplitude: a, frequency: k } => {
                let h = std::f64::consts::FRAC_PI_2;
                let (sx, cx) = (k * x.x + h).sin_cos();
                let (sy, cy) = (k * x.y + h).sin_cos();
                let (sz, cz) = (k * x.z + h).sin_cos();
                DVec3::new(a * cx * sy * sz, a * sx * cy * sz, -2.0 * a * sx * sy * cz)
            }
        }
    }
}

/// Particle relaxation time τ_p = ρ_p d² / (18 μ_f).
pub fn stokes_relaxation_time(density: f64, diameter: f64, viscosity: f64) -> f64 {
    density * diameter * diameter / (18.0 * viscosity)
}

/// Stokes drag (m/τ_p)(u_f − v).
#[inline]
pub fn stokes_drag(mass: f64, tau: f64, fluid_velocity: DVec3, v: DVec3) -> DVec3 {
    (fluid_velocity - v) * (mass / tau)
}

/// Quadratic drag −α |v| v.
#[inline]
pub fn quadratic_drag(alpha: f64, v: DVec3) -> DVec3 {
    -v * (alpha * v.length())
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn taylor_green_is_divergence_free() {
        let f = FlowField::TaylorGreen { amplitude: 5.0, frequency: 3.0 };
        let h = 1e-6;
        for p in [DVec3::new(0.1, 0.7, 1.3), DVec3::new(2.0, -0.4, 0.9)] {
            let div = (f.velocity(p + DVec3::X * h).x - f.velocity(p - DVec3::X * h).x + f.velocity(p + DVec3::Y * h).y
                - f.velocity(p - DVec3::Y * h).y
                + f.velocity(p + DVec3::Z * h).z
                - f.velocity(p - DVec3::Z * h).z)
                / (2.0 * h);
            assert!(div.abs() < 1e-6, "{div}");
        }
    }
}
