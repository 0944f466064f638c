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
}
