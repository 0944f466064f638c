//! The Tait equation of state P = B ((ρ/ρ₀)^γ − 1), γ = 7, B = ρ₀ c₀²/γ.

/// The exponent of the Tait equation for water (Batchelor 1967; Monaghan 1994).
pub const GAMMA: f64 = 7.0;

#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Tait {
    /// Reference density ρ₀, kg/m³.
    pub rho0: f64,
    /// Reference sound speed c₀, m/s.
    pub c0: f64,
    /// B = ρ₀ c₀² / γ, Pa.
    pub b: f64,
}

impl Tait {
    pub fn new(rho0: f64, c0: f64) -> Self {
        Tait { rho0, c0, b: rho0 * c0 * c0 / GAMMA }
    }

    #[inline]
    pub fn pressure(&self, rho: f64) -> f64 {
        let x = rho / self.rho0;
        let x2 = x * x;
        let x3 = x2 * x;
        self.b * (x3 * x3 * x - 1.0)
    }

    /// The density whose pressure is `p` (the inverse of [`Tait::pressure`]); ρ₀·0 for p ≤ −B.
    #[inline]
    pub fn density(&self, p: f64) -> f64 {
        let base = p / self.b + 1.0;
        if base <= 0.0 { 0.0 } else { self.rho0 * base.powf(1.0 / GAMMA) }
    }

    /// The sound speed at density ρ: c² = dP/dρ = c₀² (ρ/ρ₀)^(γ−1).
    #[inline]
    pub fn sound_speed(&self, rho: f64) -> f64 {
        let x = rho / self.rho0;
        let x3 = x * x * x;
        self.c0 * x3
    }

    /// Elastic energy per unit mass stored by compression, e(ρ) = ∫_{ρ₀}^{ρ} P/ρ'² dρ'
    /// = (B/ρ₀) ((ρ/ρ₀)⁶/6 + ρ₀/ρ − 7/6), so that de = (P/ρ²) dρ and Σ m e closes the energy balance.
    #[inline]
    pub fn elastic_energy(&self, rho: f64) -> f64 {
        let x = rho / self.rho0;
        let x3 = x * x * x;
        self.b / self.rho0 * (x3 * x3 / 6.0 + 1.0 / x - 7.0 / 6.0)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn pressure_density_and_energy_agree() {
        let eos = Tait::new(1000.0, 20.0);
        assert_eq!(eos.pressure(1000.0), 0.0);
        for rho in [980.0, 999.0, 1003.0, 1020.0] {
            let p = eos.pressure(rho);
            assert!((eos.density(p) - rho).abs() < 1e-9 * rho);
            // de/dρ = P/ρ² by central difference.
            let e = 1e-4;
            let de = (eos.elastic_energy(rho + e) - eos.elastic_energy(rho - e)) / (2.0 * e);
            assert!((de - p / (rho * rho)).abs() < 1e-6 * (p / (rho * rho)).abs().max(1e-6), "ρ {rho}");
        }
        assert_eq!(eos.elastic_energy(1000.0), 0.0);
        assert!((eos.sound_speed(1000.0) - 20.0).abs() < 1e-12);
    }
}
