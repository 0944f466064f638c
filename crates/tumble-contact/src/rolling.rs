//! Elastic–plastic spring rolling resistance, EPSD2 (docs/physics.md, "Rolling resistance"):
//! a rolling spring stored with the contact's history, capped at μ_r R* F_n.

use crate::NormalLaw;
use glam::DVec3;

/// How a pair resists rolling.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub enum RollingModel {
    /// Constant directional torque −μ_r R* F_n ω̂_rel (no history; see [`crate::rolling_torque`]).
    #[default]
    Constant,
    /// Elastic–plastic spring without damping (Ai et al. 2011's model C spring, k_r of
    /// Wensrich & Katterfeld 2012; LIGGGHTS's `epsd2` drops the dashpot too but takes
    /// k_r = k_t R*²): the torque is history, it lives beside the tangential spring.
    Epsd2,
}

/// The rolling spring's stiffness k_r = 2.25 k_n μ_r² R*² [N m/rad], k_n the normal law's
/// secant stiffness F_el/δ at this overlap (the Hertz k_n grows as √δ).
///
/// ```
/// use tumble_contact::{NormalLaw, rolling_stiffness};
/// let k_r = rolling_stiffness(&NormalLaw::linear(1.0e5, 0.8), 1e-4, 0.1, 0.05);
/// assert!((k_r - 2.25 * 1.0e5 * 0.01 * 0.0025).abs() < 1e-12);
/// ```
#[inline]
pub fn rolling_stiffness(law: &NormalLaw, overlap: f64, rolling_friction: f64, r_star: f64) -> f64 {
    let k_n = match *law {
        NormalLaw::Linear { stiffness, .. } => stiffness,
        NormalLaw::Hertz { e_star, .. } => 4.0 / 3.0 * e_star * (r_star * overlap.max(0.0)).sqrt(),
    };
    2.25 * k_n * rolling_friction * rolling_friction * r_star * r_star
}

/// One step of a rolling spring: the torque on i and what the contact keeps.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct RollingSpring {
    /// Torque on i (j receives its negation); the stored history.
    pub torque: DVec3,
    /// ½ |M_r|² / k_r after the step.
    pub energy: f64,
    /// Work done on the spring less the change of what it stores, per Δt (≥ 0 up to round-off).
    pub dissipation: f64,
    /// True when μ_r R* F_n capped the torque.
    pub rolling: bool,
}

/// Advances the stored rolling torque `stored` (booked at `stored_energy`) of a contact with
/// normal `n` by the relative spin `omega_rel` = ω_i − ω_j over `dt`.
///
/// The old torque is first turned into the current tangent plane, keeping its length (as the
/// tangential spring ξ is); then M_r ← M_r − k_r ω_t Δt with ω_t the tangent part of ω_rel
/// (the twist about n is not resisted), and |M_r| is capped at μ_r R* `normal` (`normal` is
/// max(F_n, 0)). Below the cap the contact rocks elastically; at it, it rolls against a
/// constant torque, as the constant-torque model does.
///
/// ```
/// use tumble_contact::{DVec3, epsd2_torque};
/// // k_r = 2 N m/rad, 0.01 rad of rolling in one step: 0.02 N m back, below the 0.05 N m cap.
/// let r = epsd2_torque(2.0, 0.05, DVec3::ZERO, 0.0, DVec3::Z, DVec3::new(10.0, 0.0, 0.0), 1e-3);
/// assert!((r.torque.x + 0.02).abs() < 1e-15 && !r.rolling);
/// ```
#[inline]
pub fn epsd2_torque(k_r: f64, limit: f64, stored: DVec3, stored_energy: f64, n: DVec3, omega_rel: DVec3, dt: f64) -> RollingSpring {
    let mut torque = crate::history::rotate_into_tangent_plane(stored, n);
    let omega_t = omega_rel - n * n.dot(omega_rel);
    torque -= k_r * dt * omega_t;
    let magnitude = torque.length();
    let limit = limit.max(0.0);
    let rolling = magnitude > limit;
    if rolling {
        torque = if magnitude > 0.0 { torque * (limit / magnitude) } else { DVec3::ZERO };
    }
    let energy = if k_r > 0.0 { 0.5 * torque.length_squared() / k_r } else { 0.0 };
    // The couple's power on the pair is M_r · ω_rel; the contact takes its negation.
    let dissipation = if dt > 0.0 { -torque.dot(omega_rel) - (energy - stored_energy) / dt } else { 0.0 };
    RollingSpring { torque, energy, dissipation, rolling }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn spring_accumulates_the_rolling_angle_and_caps_at_the_limit() {
        let w = DVec3::new(0.0, 5.0, 0.0);
        let a = epsd2_torque(4.0, 1.0, DVec3::ZERO, 0.0, DVec3::Z, w, 1e-3);
        let b = epsd2_torque(4.0, 1.0, a.torque, a.energy, DVec3::Z, w, 1e-3);
        assert!((b.torque.y + 4.0 * 2.0 * 5e-3).abs() < 1e-15);
        // Stuck: the end-of-step torque's work exceeds the stored energy's growth by ½ k_r ω² Δt only.
        assert!((b.dissipation - 0.5 * 4.0 * 25.0 * 1e-3).abs() < 1e-12, "{}", b.dissipation);
        let c = epsd2_torque(4.0, 0.01, b.torque, b.energy, DVec3::Z, w, 1e-3);
        assert!(c.rolling && (c.torque.length() - 0.01).abs() < 1e-15 && c.torque.y < 0.0);
        assert!(c.dissipation > 0.0 && (c.dissipation - (0.01 * 5.0 - (c.energy - b.energy) / 1e-3)).abs() < 1e-9);
    }

    #[test]
    fn twist_about_the_normal_is_not_resisted_and_a_stored_torque_turns_with_the_plane() {
        let r = epsd2_torque(4.0, 1.0, DVec3::ZERO, 0.0, DVec3::Z, DVec3::new(0.0, 0.0, 7.0), 1e-3);
        assert_eq!(r.torque, DVec3::ZERO);
        let n = DVec3::new(0.6, 0.0, 0.8);
        let old = DVec3::new(0.01, 0.0, 0.0);
        let t = epsd2_torque(4.0, 1.0, old, 0.5 * 1e-4 / 4.0, n, DVec3::ZERO, 1e-3);
        assert!(t.torque.dot(n).abs() < 1e-18 && (t.torque.length() - 0.01).abs() < 1e-16);
        assert!(t.dissipation.abs() < 1e-12);
    }

    #[test]
    fn a_pulling_contact_keeps_no_rolling_torque() {
        let r = epsd2_torque(4.0, -3.0, DVec3::new(0.1, 0.0, 0.0), 0.0, DVec3::Z, DVec3::X, 1e-3);
        assert_eq!(r.torque, DVec3::ZERO);
    }

    #[test]
    fn hertz_rolling_stiffness_uses_the_secant_normal_stiffness() {
        let law = NormalLaw::hertz(1e7, 4e6, 0.5);
        let k = rolling_stiffness(&law, 4e-4, 0.2, 0.05);
        let k_n = 4.0 / 3.0 * 1e7 * (0.05f64 * 4e-4).sqrt();
        assert!((k / (2.25 * k_n * 0.04 * 0.0025) - 1.0).abs() < 1e-14);
    }
}
