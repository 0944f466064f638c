//! Properties from target dimensionless numbers (the numbers and formulas are tumble-plan's
//! `targets`): the representative values over a scene's movable particles they are taken at.

use crate::particles::InitialParticles;
use crate::plan::Material;
pub use tumble_plan::targets::*;

/// The representative values over the movable particles that the target numbers are taken at.
pub(crate) struct MovableMeans {
    /// No particle is movable (the means are then zero).
    pub none: bool,
    /// The first movable particle, whose material with itself is the stickiness pair.
    pub first: Option<usize>,
    /// mean(ρ d²), kg/m.
    pub rho_d2: f64,
    /// L_e = d_e − d_b, m.
    pub effect_length: f64,
    /// m* = m̄/2, kg.
    pub reduced_mass: f64,
}

impl MovableMeans {
    pub(crate) fn new(p: &InitialParticles, materials: &[Material]) -> MovableMeans {
        let movable: Vec<usize> = (0..p.len()).filter(|&i| !p.fixed[i]).collect();
        let count = movable.len().max(1) as f64;
        let density = |i: usize| materials[p.material[i] as usize].density;
        let rho_d2 = movable.iter().map(|&i| density(i) * 4.0 * p.radius[i] * p.radius[i]).sum::<f64>() / count;
        let mean_mass = movable.iter().map(|&i| density(i) * p.volume[i]).sum::<f64>() / count;
        let effect_length = movable.iter().map(|&i| 2.0 * (p.effect_radius[i] - p.radius[i])).sum::<f64>() / count;
        MovableMeans { none: movable.is_empty(), first: movable.first().copied(), rho_d2, effect_length, reduced_mass: 0.5 * mean_mass }
    }
}
