//! Normal force laws: linear spring-dashpot and Hertz with Tsuji-type damping.

/// A normal contact law with its parameters for one material pair.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum NormalLaw {
    /// F = k_n δ − η_n v_n, with η_n from the restitution and the pair's m*.
    Linear { stiffness: f64, restitution: f64, damping_ratio: f64 },
    /// F = (4/3) E* √(R* δ) δ + 2 √(5/6) β √(S_n m*) v_n.
    Hertz { e_star: f64, g_star: f64, restitution: f64, beta: f64 },
}

impl NormalLaw {
    pub fn linear(stiffness: f64, restitution: f64) -> Self {
        NormalLaw::Linear { stiffness, restitution, damping_ratio: crate::damping_ratio(restitution) }
    }

    pub fn hertz(e_star: f64, g_star: f64, restitution: f64) -> Self {
        NormalLaw::Hertz { e_star, g_star, restitution, beta: crate::hertz_beta(restitution) }
    }

    pub fn restitution(&self) -> f64 {
        match *self {
            NormalLaw::Linear { restitution, .. } | NormalLaw::Hertz { restitution, .. } => restitution,
        }
    }
}

/// The normal force of one contact, split for energy bookkeeping.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct NormalForce {
    /// Spring part along n (positive repels).
    pub elastic: f64,
    /// Dashpot part along n.
    pub damping: f64,
    /// Energy stored in the spring.
    pub energy: f64,
    /// Tangent stiffness dF/dδ, used for local contact-time estimates.
    pub stiffness: f64,
}

impl NormalForce {
    pub fn total(&self) -> f64 {
        self.elastic + self.damping
    }
}

/// Normal force for overlap `overlap` > 0 and normal relative velocity `vn` = v·n
/// (negative while approaching).
#[inline]
pub fn normal_force(law: &NormalLaw, overlap: f64, vn: f64, m_star: f64, r_star: f64) -> NormalForce {
    match *law {
        NormalLaw::Linear { stiffness, damping_ratio, .. } => {
            let eta = 2.0 * damping_ratio * (m_star * stiffness).sqrt();
            NormalForce { elastic: stiffness * overlap, damping: -eta * vn, energy: 0.5 * stiffness * overlap * overlap, stiffness }
        }
        NormalLaw::Hertz { e_star, beta, .. } => {
            let root = (r_star * overlap).sqrt();
            let k = 4.0 / 3.0 * e_star * root;
            let s_n = 2.0 * e_star * root;
            NormalForce {
                elastic: k * overlap,
                damping: 2.0 * (5.0f64 / 6.0).sqrt() * beta * (s_n * m_star).sqrt() * vn,
                energy: 0.4 * k * overlap * overlap,
                stiffness: s_n,
            }
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn damping_opposes_approach_and_separation() {
        for law in [NormalLaw::linear(1e5, 0.5), NormalLaw::hertz(1e7, 4e6, 0.5)] {
            assert!(normal_force(&law, 1e-4, -1.0, 0.01, 0.05).damping > 0.0);
            assert!(normal_force(&law, 1e-4, 1.0, 0.01, 0.05).damping < 0.0);
        }
    }

    #[test]
    fn hertz_energy_integrates_the_elastic_force() {
        let law = NormalLaw::hertz(1e7, 4e6, 1.0);
        let (d, h) = (2e-4, 1e-9);
        let e = |x: f64| normal_force(&law, x, 0.0, 0.01, 0.05).energy;
        let f = normal_force(&law, d, 0.0, 0.01, 0.05).elastic;
        assert!(((e(d + h) - e(d - h)) / (2.0 * h) - f).abs() < 1e-6 * f);
    }
}
