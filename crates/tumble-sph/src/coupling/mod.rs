//! Unresolved coupling of the fluid and solid particles about the fluid's size (Robinson,
//! Ramaioli & Luding 2014; He et al. 2018; docs/sph.md, "Coupling the particles"), as three
//! gather passes over two cell grids of cells at least the kernel's support 2h:
//!
//! 1. each fluid particle a: its fluid fraction ε_a = 1 − Σ_i V_i W(r_ai), over the solids i
//!    within 2h;
//! 2. each solid i: the Shepard-normalised interpolation, with weights (m_b/ρ_b) W_bi over the
//!    fluid particles b within 2h, of the fluid's velocity u, fraction ε and force density
//!    ρ θ (θ the fluid–fluid part of the fluid's acceleration, pressure and viscous terms); the
//!    fluid's force on the solid F_i = V_i (ρ θ)_i + k V_i (u_i − v_i), k from the drag law at
//!    ε_i (buoyancy comes from the pressure gradient: no separate term);
//! 3. each fluid particle a: the reaction S_a = −Σ_i w_ai F_i, w_ai = (m_a/ρ_a) W_ai / Σ_b (m_b/ρ_b)
//!    W_bi. A solid's weights sum to one, so Σ_a S_a = −Σ_i F_i: momentum is conserved.
//!
//! Every sum runs in the grids' slot order over fixed cells, so the results are the same bits
//! for any number of threads. Wall particles take no part: the walls meet the solids as the
//! particles' own walls.

mod drag;

pub use drag::{DragFluid, DragLaw, ERGUN_BELOW};

use crate::kernel::{Dimension, WendlandC2};
use crate::particles::{FluidParticles, ParticleKind};
use glam::DVec3;
use rayon::prelude::*;
use tumble_broad::CellGrid;
use tumble_geom::PeriodicBox;

/// The solids as the coupling reads them.
#[derive(Clone, Copy, Debug)]
pub struct Solids<'a> {
    pub position: &'a [DVec3],
    pub velocity: &'a [DVec3],
    pub radius: &'a [f64],
}

/// What one evaluation of the coupling gives.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct CouplingForces {
    /// Per fluid particle (in the particles' order): its fluid fraction ε (1 for walls).
    pub fraction: Vec<f64>,
    /// Per solid: the fluid's velocity and fraction interpolated at its centre (its own
    /// velocity and 1 where no fluid is within reach).
    pub fluid_velocity: Vec<DVec3>,
    pub solid_fraction: Vec<f64>,
    /// Per solid: the drag, and the whole force of the fluid on it (drag, pressure and viscous).
    pub drag: Vec<DVec3>,
    pub force: Vec<DVec3>,
    /// Per fluid particle: the solids' reaction on it, N (zero for walls).
    pub reaction: Vec<DVec3>,
}

/// The coupling's constants: the kernel, the domain and the drag.
#[derive(Clone, Debug)]
pub struct Coupling {
    kernel: WendlandC2,
    /// (2h)².
    support2: f64,
    domain: PeriodicBox,
    law: DragLaw,
    fluid: DragFluid,
}

/// The least fluid fraction a fluid particle is given: the kernel's estimate dips below any
/// real packing (a random close packing leaves 0.36) where h is not well above the solids'
/// size, and the fluid's density is divided by it.
pub const LEAST_FRACTION: f64 = 0.2;

/// A sphere's volume.
fn volume(radius: f64) -> f64 {
    4.0 / 3.0 * std::f64::consts::PI * radius.powi(3)
}

/// A grid over `domain` with cells of at least `cell`, a flat axis padded to one cell.
fn grid(domain: &PeriodicBox, cell: f64, positions: &[DVec3]) -> CellGrid {
    let mut g = CellGrid::new(&crate::neighbours::padded(*domain, cell), cell);
    g.build(positions);
    g
}

impl Coupling {
    /// The coupling of a 3D fluid of smoothing length `h` in `domain`; a periodic axis must
    /// hold two cells of 2h.
    pub fn new(h: f64, dimension: Dimension, domain: PeriodicBox, law: DragLaw, fluid: DragFluid) -> Result<Self, String> {
        if dimension != Dimension::Three {
            return Err("the particles couple to a 3D fluid only (a plane fluid has no volume fraction of spheres)".into());
        }
        let extent = domain.extent();
        if (0..3).any(|k| domain.periodic[k] && extent[k] < 4.0 * h) {
            return Err(format!("a periodic axis of the coupled fluid must be at least 4h = {:.4e} m long", 4.0 * h));
        }
        let kernel = WendlandC2::new(h, dimension);
        Ok(Coupling { support2: kernel.support().powi(2), kernel, domain, law, fluid })
    }

    /// The coupling between `fluid` (with `acceleration`, each fluid particle's fluid–fluid
    /// acceleration θ) and `solids`.
    pub fn evaluate(&self, fluid: &FluidParticles, acceleration: &[DVec3], solids: Solids) -> CouplingForces {
        let fraction = self.fraction(fluid, solids);
        self.forces(fluid, fraction, acceleration, solids)
    }

    /// Calls f(j) for each particle j of `g` near `x`, in slot order.
    #[inline]
    fn near(g: &CellGrid, x: DVec3, mut f: impl FnMut(usize)) {
        let c = g.cell_coords(x);
        let d = g.dims();
        g.for_each_neighbour_run(c[0] + d[0] * (c[1] + d[1] * c[2]), |s0, s1| {
            for &j in &g.order()[s0..s1] {
                f(j as usize);
            }
        });
    }

    /// W(|a − b|) through the periodic axes. The grids' cells hand over many more candidates
    /// than lie within 2h (a 3³ block of cells of 2h is 6.4 times the support's volume), so
    /// those beyond are turned away on |a − b|² before the square root.
    #[inline]
    fn w(&self, a: DVec3, b: DVec3) -> f64 {
        let r2 = self.domain.minimum_image(a - b).length_squared();
        if r2 >= self.support2 {
            return 0.0;
        }
        self.kernel.value(r2.sqrt())
    }

    /// Pass 1: the fluid fraction at each fluid particle (1 for walls; at least
    /// [`LEAST_FRACTION`]), in the particles' order.
    pub fn fraction(&self, fluid: &FluidParticles, solids: Solids) -> Vec<f64> {
        let solid_grid = grid(&self.domain, self.kernel.support(), solids.position);
        (0..fluid.len())
            .into_par_iter()
            .map(|a| {
                if fluid.kind[a] != ParticleKind::Fluid {
                    return 1.0;
                }
                let mut solid = 0.0;
                Self::near(&solid_grid, fluid.position[a], |i| solid += volume(solids.radius[i]) * self.w(fluid.position[a], solids.position[i]));
                (1.0 - solid).max(LEAST_FRACTION)
            })
            .collect()
    }

    /// Passes 2 and 3: each solid's interpolations and force, and the reaction on each fluid
    /// particle, given the fluid `fraction` of pass 1 and θ (`acceleration`).
    pub fn forces(&self, fluid: &FluidParticles, fraction: Vec<f64>, acceleration: &[DVec3], solids: Solids) -> CouplingForces {
        let support = self.kernel.support();
        let n_fluid = fluid.len();
        let n_solid = solids.position.len();
        let fluid_grid = grid(&self.domain, support, &fluid.position);
        let solid_grid = grid(&self.domain, support, solids.position);
        let w = |a: DVec3, b: DVec3| self.w(a, b);
        let volume = |i: usize| volume(solids.radius[i]);
        // 2. Each solid's interpolations and force, and its Shepard denominator.
        let per_solid: Vec<(DVec3, f64, DVec3, DVec3, f64)> = (0..n_solid)
            .into_par_iter()
            .map(|i| {
                let x = solids.position[i];
                let (mut shepard, mut u, mut eps, mut force_density) = (0.0, DVec3::ZERO, 0.0, DVec3::ZERO);
                Self::near(&fluid_grid, x, |b| {
                    if fluid.kind[b] != ParticleKind::Fluid {
                        return;
                    }
                    let wb = w(x, fluid.position[b]);
                    let share = fluid.mass[b] / fluid.density[b] * wb;
                    shepard += share;
                    u += share * fluid.velocity[b];
                    eps += share * fraction[b];
                    force_density += fluid.mass[b] * wb * acceleration[b];
                });
                if shepard <= 0.0 {
                    return (solids.velocity[i], 1.0, DVec3::ZERO, DVec3::ZERO, 0.0);
                }
                let (u, eps) = (u / shepard, (eps / shepard).clamp(f64::MIN_POSITIVE, 1.0));
                let slip = u - solids.velocity[i];
                let d = 2.0 * solids.radius[i];
                let drag = self.law.coefficient(&self.fluid, d, eps, slip.length()) * volume(i) * slip;
                let force = drag + volume(i) * force_density / shepard;
                (u, eps, drag, force, shepard)
            })
            .collect();
        // 3. The reaction on each fluid particle, gathered from the solids near it.
        let reaction: Vec<DVec3> = (0..n_fluid)
            .into_par_iter()
            .map(|a| {
                if fluid.kind[a] != ParticleKind::Fluid {
                    return DVec3::ZERO;
                }
                let own = fluid.mass[a] / fluid.density[a];
                let mut s = DVec3::ZERO;
                Self::near(&solid_grid, fluid.position[a], |i| {
                    let (_, _, _, force, shepard) = per_solid[i];
                    if shepard > 0.0 {
                        s -= own * w(fluid.position[a], solids.position[i]) / shepard * force;
                    }
                });
                s
            })
            .collect();
        CouplingForces {
            fraction,
            fluid_velocity: per_solid.iter().map(|s| s.0).collect(),
            solid_fraction: per_solid.iter().map(|s| s.1).collect(),
            drag: per_solid.iter().map(|s| s.2).collect(),
            force: per_solid.iter().map(|s| s.3).collect(),
            reaction,
        }
    }
}

#[cfg(test)]
mod tests;
