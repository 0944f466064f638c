//! Drag on a solid in a fluid of volume fraction ε, from empirical correlations of the
//! locally averaged equations (docs/sph.md, "Coupling the particles"):
//!
//! - Gidaspow (1994): Ergun (1952) for dense beds, ε < 0.8, and Wen & Yu (1966) for dilute ones,
//!   with the Schiller–Naumann drag coefficient of a single sphere;
//! - Di Felice (1994): a single sphere's drag (Dallavalle's coefficient) times ε^(2 − χ), the
//!   exponent χ depending on the particle Reynolds number.
//!
//! Each law gives k with F_d = k V (u − v): V the solid's volume, u the fluid's and v the solid's
//! velocity. In the Gidaspow form k = β / (1 − ε); it is written here without the division, so a
//! lone sphere (ε → 1) has a finite k.

/// Where Gidaspow's correlation switches from Ergun's to Wen & Yu's.
pub const ERGUN_BELOW: f64 = 0.8;

/// A drag correlation.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum DragLaw {
    /// Ergun below ε = 0.8, Wen & Yu above (Gidaspow 1994).
    Gidaspow,
    /// Di Felice (1994).
    DiFelice,
}

/// The fluid as the drag sees it.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct DragFluid {
    /// Density ρ_f, kg/m³.
    pub density: f64,
    /// Dynamic viscosity μ, Pa s.
    pub viscosity: f64,
}

impl DragFluid {
    /// The particle Reynolds number ρ_f d ε |u − v| / μ.
    pub fn reynolds(&self, diameter: f64, fraction: f64, slip: f64) -> f64 {
        self.density * diameter * fraction * slip / self.viscosity
    }
}

impl DragLaw {
    /// k = F_d / (V (u − v)), 1/s × kg/m³, for a sphere of `diameter` slipping at `slip` = |u − v|
    /// through fluid of volume fraction `fraction`.
    pub fn coefficient(self, fluid: &DragFluid, diameter: f64, fraction: f64, slip: f64) -> f64 {
        let (rho, mu, d, e) = (fluid.density, fluid.viscosity, diameter, fraction);
        let re = fluid.reynolds(d, e, slip);
        match self {
            DragLaw::Gidaspow if e < ERGUN_BELOW => 150.0 * mu * (1.0 - e) / (e * d * d) + 1.75 * rho * slip / d,
            DragLaw::Gidaspow => {
                // C_D |u − v|, finite as the slip vanishes: 24 μ (1 + 0.15 Re^0.687) / (ρ d ε) below Re = 1000.
                let cd_slip = if re <= 1000.0 { 24.0 * mu * (1.0 + 0.15 * re.powf(0.687)) / (rho * d * e) } else { 0.44 * slip };
                0.75 * cd_slip * rho * e.powf(-1.65) / d
            }
            DragLaw::DiFelice => {
                // C_D |u − v| = (0.63 √|u − v| + 4.8 √(μ / (ρ d ε)))², Dallavalle's coefficient.
                let root = 0.63 * slip.sqrt() + 4.8 * (mu / (rho * d * e)).sqrt();
                let chi = 3.7 - 0.65 * (-0.5 * (1.5 - re.log10()).powi(2)).exp();
                0.75 * root * root * rho * e.powf(2.0 - chi) / d
            }
        }
    }

    pub fn name(self) -> &'static str {
        match self {
            DragLaw::Gidaspow => "gidaspow",
            DragLaw::DiFelice => "di_felice",
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use std::f64::consts::PI;

    const WATER: DragFluid = DragFluid { density: 1000.0, viscosity: 1.0e-3 };

    /// A lone sphere creeping through the fluid feels Stokes's 3 π μ d (u − v) under Wen & Yu
    /// (Schiller–Naumann's coefficient is 24/Re there), and 23.04/24 of it under Di Felice
    /// (Dallavalle's (4.8)²/Re).
    #[test]
    fn a_lone_creeping_sphere_feels_stokes_drag() {
        let (d, slip) = (1.0e-4, 1.0e-6);
        let volume = PI * d * d * d / 6.0;
        let stokes = 3.0 * PI * WATER.viscosity * d * slip;
        let gidaspow = DragLaw::Gidaspow.coefficient(&WATER, d, 1.0, slip) * volume * slip;
        let di_felice = DragLaw::DiFelice.coefficient(&WATER, d, 1.0, slip) * volume * slip;
        assert!((gidaspow / stokes - 1.0).abs() < 1e-3, "Gidaspow {gidaspow:e} vs Stokes {stokes:e}");
        assert!((di_felice / stokes - 23.04 / 24.0).abs() < 1e-2, "Di Felice {di_felice:e} vs Stokes {stokes:e}");
        // No slip, no drag, and no 0/0.
        assert_eq!(DragLaw::DiFelice.coefficient(&WATER, d, 1.0, 0.0) * 0.0, 0.0);
        assert!(DragLaw::Gidaspow.coefficient(&WATER, d, 1.0, 0.0).is_finite());
    }

    /// At Re = 100 (ε = 1) the coefficients against their formulas evaluated by hand: Wen & Yu's
    /// C_D = 24 (1 + 0.15 · 100^0.687) / 100 = 1.0913, Dallavalle's (0.63 + 0.48)² = 1.2321, and
    /// Di Felice's χ = 3.7 − 0.65 e^(−0.125) = 3.1264 (irrelevant at ε = 1).
    #[test]
    fn the_drag_coefficients_at_re_100_are_the_correlations() {
        let d = 1.0e-3;
        let slip = 100.0 * WATER.viscosity / (WATER.density * d);
        let force = |law: DragLaw| law.coefficient(&WATER, d, 1.0, slip) * PI * d * d * d / 6.0 * slip;
        // F = C_D ½ ρ |u − v|² π d² / 4.
        let with = |cd: f64| cd * 0.5 * WATER.density * slip * slip * PI * d * d / 4.0;
        let wen_yu = 24.0 * (1.0 + 0.15 * 100f64.powf(0.687)) / 100.0;
        assert!((force(DragLaw::Gidaspow) / with(wen_yu) - 1.0).abs() < 1e-12);
        assert!((force(DragLaw::DiFelice) / with(1.2321) - 1.0).abs() < 1e-12);
    }

    /// In a bed the laws part: Ergun at ε = 0.5 is its two terms; Wen & Yu at ε = 0.9 scales the
    /// lone sphere's drag by ε^(−1.65) (its Re taken at ε); Di Felice's by ε^(2 − χ).
    #[test]
    fn hindrance_follows_each_correlation() {
        let (d, slip) = (2.0e-3, 0.01);
        let k = |law: DragLaw, e: f64| law.coefficient(&WATER, d, e, slip);
        let ergun = 150.0 * WATER.viscosity * 0.5 / (0.5 * d * d) + 1.75 * WATER.density * slip / d;
        assert!((k(DragLaw::Gidaspow, 0.5) / ergun - 1.0).abs() < 1e-12);
        let re = WATER.reynolds(d, 0.9, slip);
        let lone_at_re = 0.75 * 24.0 * (1.0 + 0.15 * re.powf(0.687)) / re * WATER.density * slip / d;
        assert!((k(DragLaw::Gidaspow, 0.9) / (lone_at_re * 0.9f64.powf(-1.65)) - 1.0).abs() < 1e-12);
        let chi = 3.7 - 0.65 * (-0.5 * (1.5 - re.log10()).powi(2)).exp();
        let cd = (0.63 + 4.8 / re.sqrt()).powi(2);
        let di_felice = 0.75 * cd * slip * WATER.density * 0.9f64.powf(2.0 - chi) / d;
        assert!((k(DragLaw::DiFelice, 0.9) / di_felice - 1.0).abs() < 1e-12);
        // Denser beds drag harder under both laws.
        for law in [DragLaw::Gidaspow, DragLaw::DiFelice] {
            assert!(k(law, 0.45) > k(law, 0.6) && k(law, 0.6) > k(law, 0.95), "{law:?}");
        }
    }
}
