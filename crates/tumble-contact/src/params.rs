//! Parameter derivations: damping from restitution, contact durations, time-step scales.

/// Damping ratio γ = −ln e / √(π² + ln² e) of a linear spring-dashpot with restitution e.
pub fn damping_ratio(restitution: f64) -> f64 {
    let l = restitution.ln();
    -l / (std::f64::consts::PI.powi(2) + l * l).sqrt()
}

/// Linear normal damping η_n = −2 ln(e) √(m* k_n) / √(π² + ln² e).
pub fn linear_damping(restitution: f64, m_star: f64, k_n: f64) -> f64 {
    2.0 * damping_ratio(restitution) * (m_star * k_n).sqrt()
}

/// Linear contact duration t_col = √(m*/k_n) √(π² + ln² e).
pub fn collision_time(k_n: f64, m_star: f64, restitution: f64) -> f64 {
    let l = restitution.ln();
    (m_star / k_n).sqrt() * (std::f64::consts::PI.powi(2) + l * l).sqrt()
}

/// Hertz effective moduli (E*, G*) of two materials given (E, ν) each.
pub fn hertz_effective_moduli(e_i: f64, nu_i: f64, e_j: f64, nu_j: f64) -> (f64, f64) {
    let e_star = 1.0 / ((1.0 - nu_i * nu_i) / e_i + (1.0 - nu_j * nu_j) / e_j);
    let g_star = 1.0 / (2.0 * (2.0 - nu_i) * (1.0 + nu_i) / e_i + 2.0 * (2.0 - nu_j) * (1.0 + nu_j) / e_j);
    (e_star, g_star)
}

/// Tsuji-type damping factor β = ln e / √(ln² e + π²) (negative for e < 1).
pub fn hertz_beta(restitution: f64) -> f64 {
    -damping_ratio(restitution)
}

/// Elastic Hertz contact duration t_H = 2.868 (m*² / (R* E*² v))^(1/5).
pub fn hertz_contact_time(m_star: f64, r_star: f64, e_star: f64, impact_speed: f64) -> f64 {
    2.868 * (m_star * m_star / (r_star * e_star * e_star * impact_speed)).powf(0.2)
}

/// Maximum overlap of an elastic Hertz impact, δ_max = (15 m* v² / (16 E* √R*))^(2/5).
pub fn hertz_max_overlap(m_star: f64, r_star: f64, e_star: f64, impact_speed: f64) -> f64 {
    (15.0 * m_star * impact_speed * impact_speed / (16.0 * e_star * r_star.sqrt())).powf(0.4)
}

/// Maximum force of an elastic Hertz impact, (4/3) E* √R* δ_max^(3/2).
pub fn hertz_max_force(m_star: f64, r_star: f64, e_star: f64, impact_speed: f64) -> f64 {
    4.0 / 3.0 * e_star * r_star.sqrt() * hertz_max_overlap(m_star, r_star, e_star, impact_speed).powf(1.5)
}

/// Rayleigh time Δt_R = π R √(ρ/G) / (0.1631 ν + 0.8766), G = E / (2(1+ν)).
pub fn rayleigh_time(radius: f64, density: f64, youngs_modulus: f64, poisson_ratio: f64) -> f64 {
    let g = youngs_modulus / (2.0 * (1.0 + poisson_ratio));
    std::f64::consts::PI * radius * (density / g).sqrt() / (0.1631 * poisson_ratio + 0.8766)
}

/// Restitution of a normal impact whose force is clipped at zero (`no_attraction`), in the
/// dimensionless form both laws reduce to: x'' = −max(0, x^p + c x^q x'), x(0) = 0, x'(0) = 1,
/// with (p, q) = (1, 0) for the linear law (c = 2γ) and (3/2, 1/4) for Hertz (c = √5 |β|).
/// Both are homogeneous, so e depends on c alone, not on mass, stiffness or speed.
fn clipped_restitution(p: f64, q: f64, c: f64) -> f64 {
    let accel = |x: f64, v: f64| if x > 0.0 { -(x.powf(p) + c * x.powf(q) * v).max(0.0) } else { 0.0 };
    let h = 2.0e-4;
    let (mut x, mut v) = (0.0f64, 1.0f64);
    // Contact ends when the overlap closes; the force is zero from the clip on, so v is final then.
    for step in 0..1_000_000 {
        let (k1x, k1v) = (v, accel(x, v));
        let (k2x, k2v) = (v + 0.5 * h * k1v, accel(x + 0.5 * h * k1x, v + 0.5 * h * k1v));
        let (k3x, k3v) = (v + 0.5 * h * k2v, accel(x + 0.5 * h * k2x, v + 0.5 * h * k2v));
        let (k4x, k4v) = (v + h * k3v, accel(x + h * k3x, v + h * k3v));
        x += h / 6.0 * (k1x + 2.0 * k2x + 2.0 * k3x + k4x);
        v += h / 6.0 * (k1v + 2.0 * k2v + 2.0 * k3v + k4v);
        if step > 0 && (x <= 0.0 || (v < 0.0 && accel(x, v) == 0.0)) {
            break;
        }
    }
    -v
}

/// The damping constant c for which `clipped_restitution(p, q, c)` = e (bisection; e falls with c).
fn clipped_damping(p: f64, q: f64, restitution: f64) -> f64 {
    if restitution >= 1.0 {
        return 0.0;
    }
    let (mut lo, mut hi) = (0.0f64, 1.0f64);
    // c = 1024 gives e ≈ 1e-6; scenes ask for at least MIN_CLIPPED_RESTITUTION.
    while hi < 1024.0 && clipped_restitution(p, q, hi) > restitution {
        hi *= 2.0;
    }
    for _ in 0..50 {
        let mid = 0.5 * (lo + hi);
        if clipped_restitution(p, q, mid) > restitution { lo = mid } else { hi = mid }
    }
    0.5 * (lo + hi)
}

/// The smallest restitution a scene may ask of a clipped contact: e ≈ 1e-4 needs c ≈ 100 already,
/// since a clipped dashpot lets go as soon as it would pull.
pub const MIN_CLIPPED_RESTITUTION: f64 = 1e-4;

/// Damping ratio γ of a linear spring-dashpot whose force is clipped at zero (`no_attraction`)
/// so that it still rebounds with restitution e. The clip removes the dashpot's pull at the end of
/// the contact, so γ is larger than [`damping_ratio`]'s.
///
/// ```
/// use tumble_contact::{clipped_damping_ratio, damping_ratio};
/// assert!(clipped_damping_ratio(0.5) > damping_ratio(0.5));
/// ```
pub fn clipped_damping_ratio(restitution: f64) -> f64 {
    0.5 * clipped_damping(1.0, 0.0, restitution)
}

/// Tsuji-type damping factor β (negative) of a Hertz contact whose force is clipped at zero
/// (`no_attraction`), chosen so that the impact rebounds with restitution e exactly.
///
/// ```
/// use tumble_contact::clipped_hertz_beta;
/// assert!(clipped_hertz_beta(0.5) < 0.0 && clipped_hertz_beta(1.0) == 0.0);
/// ```
pub fn clipped_hertz_beta(restitution: f64) -> f64 {
    -clipped_damping(1.5, 0.25, restitution) / 5f64.sqrt()
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn undamped_limit_has_no_damping_and_half_period_duration() {
        assert_eq!(damping_ratio(1.0), 0.0);
        let t = collision_time(1.0e5, 0.01, 1.0);
        assert!((t - std::f64::consts::PI * (0.01f64 / 1.0e5).sqrt()).abs() < 1e-15);
    }

    #[test]
    fn damped_duration_matches_the_damped_frequency() {
        // t_col = π / √(k/m − (η/2m)²), the form docs/physics.md gives first.
        let (k, m, e) = (1.0e5, 0.005, 0.8);
        let eta = linear_damping(e, m, k);
        let direct = std::f64::consts::PI / (k / m - (eta / (2.0 * m)).powi(2)).sqrt();
        assert!((collision_time(k, m, e) - direct).abs() < 1e-12 * direct);
    }

    #[test]
    fn effective_moduli_of_equal_materials() {
        let (e, g) = hertz_effective_moduli(1.0e7, 0.3, 1.0e7, 0.3);
        assert!((e - 1.0e7 / (2.0 * 0.91)).abs() < 1e-6);
        assert!((g - 1.0e7 / (4.0 * 1.7 * 1.3)).abs() < 1e-6);
    }

    #[test]
    fn the_dimensionless_impact_reproduces_the_unclipped_linear_closed_form() {
        // Unclipped, the linear law's restitution is exp(−γπ/√(1−γ²)); the clip only adds to it.
        for e in [0.3, 0.5, 0.8] {
            let gamma = damping_ratio(e);
            let c = 2.0 * gamma;
            assert!(clipped_restitution(1.0, 0.0, c) > e + 1e-3, "the clip must raise e above {e}");
            assert!((clipped_restitution(1.0, 0.0, 2.0 * clipped_damping_ratio(e)) - e).abs() < 1e-9);
        }
    }

    /// An impact of the real law, in dimensional form with a different integrator (velocity Verlet).
    fn dimensional_restitution(law: &crate::NormalLaw, m: f64, r: f64, v0: f64, dt: f64) -> f64 {
        let (mut x, mut v) = (0.0f64, -v0); // x: the gap (negative = overlap), v its rate
        let force = |x: f64, v: f64| if x < 0.0 { crate::normal_force(law, -x, v, m, r).total().max(0.0) } else { 0.0 };
        let mut a = force(x, v) / m;
        loop {
            x += v * dt + 0.5 * a * dt * dt;
            let vp = v + a * dt;
            let an = force(x, vp) / m;
            v += 0.5 * (a + an) * dt;
            a = an;
            if x > 0.0 && v > 0.0 {
                return v / v0;
            }
        }
    }

    #[test]
    fn clipped_damping_gives_the_requested_restitution_for_any_mass_stiffness_and_speed() {
        for e in [0.2, 0.5, 0.825] {
            let linear = crate::NormalLaw::Linear { stiffness: 1.0e5, restitution: e, damping_ratio: clipped_damping_ratio(e) };
            let (m, k) = (0.01f64, 1.0e5f64);
            let t = std::f64::consts::PI * (m / k).sqrt();
            for v0 in [0.1, 3.0] {
                let got = dimensional_restitution(&linear, m, 0.05, v0, t / 20_000.0);
                assert!((got - e).abs() < 2e-4, "linear e = {e} at {v0} m/s: {got}");
            }
            let (e_star, g_star) = hertz_effective_moduli(7.0e10, 0.33, 7.0e10, 0.33);
            let hertz = crate::NormalLaw::Hertz { e_star, g_star, restitution: e, beta: clipped_hertz_beta(e) };
            let (m, r) = (11.3, 0.1);
            for v0 in [0.2, 2.0] {
                let t = hertz_contact_time(m, r, e_star, v0);
                let got = dimensional_restitution(&hertz, m, r, v0, t / 20_000.0);
                assert!((got - e).abs() < 2e-4, "Hertz e = {e} at {v0} m/s: {got}");
            }
        }
    }
}
