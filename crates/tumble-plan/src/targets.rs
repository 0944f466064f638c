//! Scene helpers for particle-laden flows: properties from target dimensionless numbers
//! (docs/physics.md): the Stokes number Stk = ρ d² u_0 / (18 μ l_0) in a Taylor–Green vortex,
//! and the stickiness number Sy = L_e √k_c / (e √(L_e² k_c + u² m*)).
//!
//! Representative values are taken over the movable particles: the mean of ρd² (so Stk is the
//! mean of the particles' Stokes numbers, exact for one size and density), the mean effect
//! length L_e = d_e − d_b and the mean mass m̄, with m* = m̄/2 (two equal particles). The
//! Taylor–Green scales are u_0 = ⟨|u|⟩ (the mean speed over the periodic cell, by quadrature:
//! u_0 = 0.7799 A, see [`taylor_green_mean_speed`]) and the vortex size l_0 = π/a.

use std::f64::consts::PI;
#[cfg(test)]
use tumble_contact::stickiness_number;

/// The Taylor–Green scales and the Stokes number of a scene's particles.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct TaylorGreenNumbers {
    /// u_0 = ⟨|u|⟩ over the periodic cell, m/s.
    pub mean_flow_speed: f64,
    /// l_0 = π/a, m.
    pub vortex_size: f64,
    /// Stk = mean(ρ d²) u_0 / (18 μ l_0) (Stokes drag only).
    pub stokes_number: Option<f64>,
    /// μ_f, Pa s (given, or derived from a target Stokes number).
    pub viscosity: Option<f64>,
}

/// The stickiness number of the scene's representative pair (the first movable particle's material with itself).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Stickiness {
    pub number: f64,
    /// k_c, N/m.
    pub stiffness: f64,
    /// u of Sy, m/s.
    pub collision_speed: f64,
    /// L_e = d_e − d_b (mean over movable particles), m.
    pub effect_length: f64,
    /// m* = m̄/2, kg.
    pub reduced_mass: f64,
    pub restitution: f64,
}

/// The target numbers a scene's plan reports.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct Targets {
    pub taylor_green: Option<TaylorGreenNumbers>,
    pub stickiness: Option<Stickiness>,
}

/// ⟨|u|⟩ / A of the Taylor–Green field, by the midpoint rule on 128³ points of [0, π/2]³ (|u|/A
/// depends only on sin² and cos² of X, Y, Z, so this octant's mean is the whole cell's). Agrees
/// with 64³ to 2e-5; ⟨|u|²⟩ = 3A²/4 exactly, a check of the same rule.
pub fn taylor_green_mean_speed_factor() -> f64 {
    static FACTOR: std::sync::OnceLock<f64> = std::sync::OnceLock::new();
    *FACTOR.get_or_init(|| taylor_green_quadrature(128).0)
}

/// u_0 = ⟨|u|⟩ of a Taylor–Green vortex of amplitude A (independent of the frequency).
pub fn taylor_green_mean_speed(amplitude: f64) -> f64 {
    amplitude.abs() * taylor_green_mean_speed_factor()
}

/// (⟨|u|⟩/A, ⟨|u|²⟩/A²) by the midpoint rule with n points per axis on [0, π/2]³.
pub fn taylor_green_quadrature(n: usize) -> (f64, f64) {
    let h = 0.5 * PI / n as f64;
    let sc: Vec<(f64, f64)> = (0..n).map(|i| ((i as f64 + 0.5) * h).sin_cos()).map(|(s, c)| (s * s, c * c)).collect();
    let (mut sum, mut sum_sq) = (0.0, 0.0);
    for &(sx, cx) in &sc {
        for &(sy, cy) in &sc {
            for &(sz, cz) in &sc {
                let q = cx * sy * sz + sx * cy * sz + 4.0 * sx * sy * cz;
                sum += q.sqrt();
                sum_sq += q;
            }
        }
    }
    let m = (n * n * n) as f64;
    (sum / m, sum_sq / m)
}

/// μ_f that gives Stokes number `stk`: μ = mean(ρd²) u_0 / (18 Stk l_0).
pub fn viscosity_for_stokes_number(stk: f64, mean_rho_d2: f64, u0: f64, l0: f64) -> f64 {
    mean_rho_d2 * u0 / (18.0 * stk * l0)
}

/// k_c that gives stickiness number `sy`: k_c = Sy² e² u² m* / (L_e² (1 − Sy² e²)); needs Sy e < 1.
pub fn cohesion_for_stickiness_number(sy: f64, restitution: f64, effect_length: f64, speed: f64, m_star: f64) -> f64 {
    let q = sy * sy * restitution * restitution;
    q * speed * speed * m_star / (effect_length * effect_length * (1.0 - q))
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn taylor_green_mean_speed_converges_and_the_mean_square_is_exact() {
        let (coarse, sq) = taylor_green_quadrature(64);
        let fine = taylor_green_mean_speed_factor();
        assert!((coarse - fine).abs() < 2e-5, "{coarse} {fine}");
        assert!((sq - 0.75).abs() < 1e-12, "{sq}");
        assert!((fine - 0.77994).abs() < 1e-5, "{fine}");
    }

    #[test]
    fn stickiness_round_trip() {
        let (e, l, u, m) = (0.5, 0.025, 2.0, 0.065);
        for sy in [0.1, 0.6, 1.0, 1.5, 1.99] {
            let k = cohesion_for_stickiness_number(sy, e, l, u, m);
            assert!((stickiness_number(l, k, e, u, m) - sy).abs() < 1e-12 * sy);
        }
    }
}
