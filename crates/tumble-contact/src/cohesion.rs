//! Linear cohesion with an effect surface (docs/physics.md, "Cohesion").

/// Cohesive force along n (negative: attraction) for effect overlap δ_e.
#[inline]
pub fn cohesion_force(k_c: f64, effect_overlap: f64) -> f64 {
    if effect_overlap > 0.0 { -k_c * effect_overlap } else { 0.0 }
}

/// Potential energy of the cohesive bond, −½ k_c δ_e² (zero out of range).
#[inline]
pub fn cohesion_energy(k_c: f64, effect_overlap: f64) -> f64 {
    if effect_overlap > 0.0 { -0.5 * k_c * effect_overlap * effect_overlap } else { 0.0 }
}

/// Stickiness number Sy = L_e √k_c / (e √(L_e² k_c + u² m*)), L_e = d_e − d_b; Sy > 1 sticks.
pub fn stickiness_number(effect_length: f64, k_c: f64, restitution: f64, speed: f64, m_star: f64) -> f64 {
    let l = effect_length;
    l * k_c.sqrt() / (restitution * (l * l * k_c + speed * speed * m_star).sqrt())
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn attracts_only_in_range() {
        assert_eq!(cohesion_force(100.0, 0.01), -1.0);
        assert_eq!(cohesion_force(100.0, -0.01), 0.0);
        assert_eq!(cohesion_energy(100.0, 0.01), -0.005);
    }
}
