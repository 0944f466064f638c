//! Tangential spring with history (Cundall–Strack, Mindlin) and rolling resistance
//! (docs/physics.md, "The spring with history" and "Rolling resistance").

use glam::DVec3;

/// Stiffness and damping of the tangential spring of one material pair.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum SpringLaw {
    /// Cundall–Strack: constant k_t [N/m]; η_t = damping + 2 damping_ratio √(m* k_t) [N s/m].
    Linear { stiffness: f64, damping: f64, damping_ratio: f64 },
    /// Hertz–Mindlin: k_t = 8 G* √(R* δ), η_t = −2 √(5/6) β √(k_t m*).
    Mindlin { g_star: f64, beta: f64 },
}

impl SpringLaw {
    /// (k_t, η_t) at overlap `overlap` for a pair with effective radius and mass.
    #[inline]
    pub fn stiffness_damping(&self, overlap: f64, r_star: f64, m_star: f64) -> (f64, f64) {
        match *self {
            SpringLaw::Linear { stiffness, damping, damping_ratio } => {
                (stiffness, if damping_ratio > 0.0 { damping + 2.0 * damping_ratio * (m_star * stiffness).sqrt() } else { damping })
            }
            SpringLaw::Mindlin { g_star, beta } => {
                let k_t = 8.0 * g_star * (r_star * overlap).sqrt();
                (k_t, -2.0 * (5.0f64 / 6.0).sqrt() * beta * (k_t * m_star).sqrt())
            }
        }
    }
}

/// One step of a history contact: the force on i and the spring to keep.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct SpringForce {
    pub force: DVec3,
    /// The spring ξ after this step (the contact's stored history).
    pub spring: DVec3,
    /// Energy stored in the spring after the step.
    pub energy: f64,
    /// Power dissipated by tangential damping and sliding this step (≥ 0 up to round-off).
    pub dissipation: f64,
    /// True when the Coulomb limit capped the force.
    pub sliding: bool,
}

/// `stored` projected onto the plane normal to `n` and rescaled to its old length: a contact's
/// stored spring (or rolling torque) follows the turning normal without loading or unloading.
#[inline]
pub(crate) fn rotate_into_tangent_plane(stored: DVec3, n: DVec3) -> DVec3 {
    let old_len2 = stored.length_squared();
    let mut v = stored - n * n.dot(stored);
    if old_len2 > 0.0 {
        let len2 = v.length_squared();
        if len2 > 0.0 {
            v *= (old_len2 / len2).sqrt();
        }
    }
    v
}

/// Advances the spring `spring` of a contact with normal `n` by the tangential
/// relative velocity `vt` over `dt` and returns the force on i.
///
/// `normal` is the friction capacity's normal force, max(F_n, 0): a pulling
/// dashpot gives no friction. The old spring is first rotated into the current
/// tangent plane, keeping its length; then ξ ← ξ + v_t Δt, and with the
/// Coulomb limit L = μ·normal (docs/physics.md, "The sliding rule"):
///
/// - the spring alone reaches L: the contact slides, F_t = L along −ξ̂, ξ is
///   truncated to the capped elastic force, ξ = −F_t/k_t, and the dashpot is off;
/// - otherwise F_t = −k_t ξ − η_t v_t, scaled back to L if the dashpot takes
///   it past the limit; ξ is kept as it is (the elastic part is below L).
///
/// Friction never pushes along a slip that keeps its direction (F_t · v_t ≤ 0 in gross
/// sliding); a spring returns what it stored only while it unloads.
///
/// ```
/// use tumble_contact::{DVec3, SpringLaw, history_force};
/// let law = SpringLaw::Linear { stiffness: 1.0e4, damping: 0.0, damping_ratio: 0.0 };
/// // Stuck: 1 mm of slip loads the spring to 10 N, below μ|F_n| = 50 N.
/// let f = history_force(&law, 0.5, 100.0, 1e-4, 0.05, 0.1, DVec3::ZERO, DVec3::Z, DVec3::new(1.0, 0.0, 0.0), 1e-3);
/// assert!((f.force.x + 10.0).abs() < 1e-9 && !f.sliding);
/// ```
#[allow(clippy::too_many_arguments)]
#[inline]
pub fn history_force(
    law: &SpringLaw,
    friction: f64,
    normal: f64,
    overlap: f64,
    r_star: f64,
    m_star: f64,
    spring: DVec3,
    n: DVec3,
    vt: DVec3,
    dt: f64,
) -> SpringForce {
    let (k_t, eta_t) = law.stiffness_damping(overlap, r_star, m_star);
    let mut xi = rotate_into_tangent_plane(spring, n);
    let rotated_energy = 0.5 * k_t * xi.length_squared();
    xi += vt * dt;
    let limit = friction * normal.max(0.0);
    let elastic = -k_t * xi;
    let elastic_magnitude = elastic.length();
    let (force, sliding) = if elastic_magnitude > limit {
        // The spring alone is past the limit: it slides, truncated along itself to what L implies.
        let force = elastic * (limit / elastic_magnitude);
        xi = if k_t > 0.0 { -force / k_t } else { DVec3::ZERO };
        (force, true)
    } else {
        let trial = elastic - eta_t * vt;
        let magnitude = trial.length();
        // The dashpot alone took it past L; the capped force then opposes the slip (|trial| > |elastic| needs trial · v_t < 0).
        if magnitude > limit { (trial * (limit / magnitude), true) } else { (trial, false) }
    };
    let energy = 0.5 * k_t * xi.length_squared();
    // Work done on the contact minus what the spring kept.
    let dissipation = if dt > 0.0 { -force.dot(vt) - (energy - rotated_energy) / dt } else { 0.0 };
    SpringForce { force, spring: xi, energy, dissipation, sliding }
}

/// Rolling resistance (constant directional torque) on i: −μ_r R* |F_n| ω̂_rel,
/// capped so that alone it would not reverse ω_rel = ω_i − ω_j within the step.
///
/// `inv_inertia_sum` is 1/I_i + 1/I_j (1/I_i against a wall).
///
/// ```
/// use tumble_contact::{DVec3, rolling_torque};
/// let m = rolling_torque(0.1, 0.05, 10.0, DVec3::new(0.0, 2.0, 0.0), 1.0e3, 1.0e-4);
/// assert!((m.y + 0.05).abs() < 1e-12); // μ_r R* |F_n| = 0.05 N m, against ω
/// ```
#[inline]
pub fn rolling_torque(rolling_friction: f64, r_star: f64, normal: f64, omega_rel: DVec3, inv_inertia_sum: f64, dt: f64) -> DVec3 {
    let w = omega_rel.length();
    if w == 0.0 || rolling_friction == 0.0 {
        return DVec3::ZERO;
    }
    let full = rolling_friction * r_star * normal;
    // The torque that stops the relative rolling in exactly one step.
    let stop = if inv_inertia_sum > 0.0 && dt > 0.0 { w / (inv_inertia_sum * dt) } else { f64::INFINITY };
    omega_rel * (-full.min(stop) / w)
}

#[cfg(test)]
mod tests {
    use super::*;

    const LAW: SpringLaw = SpringLaw::Linear { stiffness: 1.0e4, damping: 2.0, damping_ratio: 0.0 };

    #[test]
    fn spring_grows_with_slip_and_damping_opposes_it() {
        let v = DVec3::new(0.1, 0.0, 0.0);
        let f = history_force(&LAW, 1.0, 1e3, 1e-4, 0.05, 0.1, DVec3::ZERO, DVec3::Z, v, 1e-3);
        assert!(!f.sliding);
        assert!((f.spring - v * 1e-3).length() < 1e-15);
        assert!((f.force.x - (-1.0e4 * 1e-4 - 2.0 * 0.1)).abs() < 1e-12);
        let g = history_force(&LAW, 1.0, 1e3, 1e-4, 0.05, 0.1, f.spring, DVec3::Z, v, 1e-3);
        assert!((g.spring.x - 2e-4).abs() < 1e-15);
    }

    #[test]
    fn coulomb_limit_truncates_the_spring_to_the_capped_elastic_force() {
        let v = DVec3::new(0.0, 3.0, 0.0);
        let f = history_force(&LAW, 0.5, 10.0, 1e-4, 0.05, 0.1, DVec3::new(0.0, 0.01, 0.0), DVec3::Z, v, 1e-3);
        assert!(f.sliding);
        assert!((f.force.length() - 5.0).abs() < 1e-12);
        assert!(f.force.y < 0.0);
        // The spring alone supplies the capped force; the dashpot is off while sliding.
        assert!((-1.0e4 * f.spring - f.force).length() < 1e-12);
        assert!(f.dissipation > 0.0);
    }

    #[test]
    fn damping_past_the_limit_at_onset_never_stores_a_spring_against_the_slip() {
        // The case that broke Hertz–Mindlin sliding: at contact onset η_t|v_t| alone exceeds μF_n.
        let law = SpringLaw::Linear { stiffness: 1.0e4, damping: 50.0, damping_ratio: 0.0 };
        let v = DVec3::new(0.2, 0.0, 0.0);
        let f = history_force(&law, 0.4, 10.0, 1e-4, 0.05, 0.1, DVec3::ZERO, DVec3::Z, v, 1e-4);
        assert!(f.sliding && (f.force.length() - 4.0).abs() < 1e-12 && f.force.x < 0.0);
        assert!(f.spring.dot(v) > 0.0, "the stored spring points along the slip: {:?}", f.spring);
        // A stiffer spring next step (Mindlin k_t grows with δ) still pulls against the slip.
        let stiff = SpringLaw::Linear { stiffness: 1.0e7, damping: 50.0, damping_ratio: 0.0 };
        let g = history_force(&stiff, 0.4, 10.0, 1e-4, 0.05, 0.1, f.spring, DVec3::Z, v, 1e-4);
        assert!(g.force.dot(v) < 0.0 && (g.force.length() - 4.0).abs() < 1e-12);
    }

    #[test]
    fn a_pulling_normal_force_gives_no_friction() {
        let v = DVec3::new(0.1, 0.0, 0.0);
        let f = history_force(&LAW, 0.5, -3.0, 1e-4, 0.05, 0.1, DVec3::new(1e-4, 0.0, 0.0), DVec3::Z, v, 1e-3);
        assert_eq!(f.force, DVec3::ZERO);
        assert_eq!(f.spring, DVec3::ZERO);
    }

    #[test]
    fn a_spring_left_above_a_falling_limit_is_truncated_along_itself() {
        // The slip reverses while the normal force drops under the spring: it gives back part of what
        // it stored along its own direction (flipping it against the slip made resting contacts chatter).
        let v = DVec3::new(-0.1, 0.0, 0.0);
        let old = DVec3::new(0.01, 0.0, 0.0);
        let f = history_force(&LAW, 0.5, 10.0, 1e-4, 0.05, 0.1, old, DVec3::Z, v, 1e-3);
        assert!(f.sliding && (f.force.x + 5.0).abs() < 1e-12);
        assert!((f.spring.x - 5e-4).abs() < 1e-15);
        assert!(f.dissipation >= 0.0, "truncation dissipates: {}", f.dissipation);
    }

    #[test]
    fn spring_rotates_into_the_new_tangent_plane_keeping_its_length() {
        let law = SpringLaw::Linear { stiffness: 1.0e4, damping: 0.0, damping_ratio: 0.0 };
        let n = DVec3::new(0.0, 0.6, 0.8);
        let old = DVec3::new(0.0, 1e-4, 0.0);
        let f = history_force(&law, 10.0, 1e3, 1e-4, 0.05, 0.1, old, n, DVec3::ZERO, 1e-3);
        assert!(f.spring.dot(n).abs() < 1e-18);
        assert!((f.spring.length() - 1e-4).abs() < 1e-16);
        assert!(f.dissipation.abs() < 1e-9, "a pure rotation stores and dissipates nothing: {}", f.dissipation);
    }

    #[test]
    fn mindlin_stiffness_follows_the_contact_radius() {
        let law = SpringLaw::Mindlin { g_star: 1e7, beta: -0.2 };
        let (k1, e1) = law.stiffness_damping(1e-4, 0.05, 0.1);
        let (k4, _) = law.stiffness_damping(4e-4, 0.05, 0.1);
        assert!((k1 - 8.0 * 1e7 * (0.05f64 * 1e-4).sqrt()).abs() < 1e-6 * k1);
        assert!((k4 / k1 - 2.0).abs() < 1e-12);
        assert!((e1 - 2.0 * (5.0f64 / 6.0).sqrt() * 0.2 * (k1 * 0.1).sqrt()).abs() < 1e-9 * e1);
    }

    #[test]
    fn rolling_torque_never_reverses_the_relative_spin() {
        let w = DVec3::new(1e-3, 0.0, 0.0);
        let m = rolling_torque(0.5, 0.05, 1e3, w, 10.0, 1e-3);
        assert!((m.x + 1e-3 / (10.0 * 1e-3)).abs() < 1e-15);
        assert_eq!(rolling_torque(0.5, 0.05, 1e3, DVec3::ZERO, 10.0, 1e-3), DVec3::ZERO);
    }
}
