//! What a fluid phase is told: the method's switches and the fluid's properties, as plain data.

use tumble_geom::{DVec3, Motion, PeriodicBox, Timing};

use crate::buffers::{Inflow, Outflow};
use crate::floating::FloatingBody;
use crate::kernel::Dimension;

/// How momentum diffuses.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum Viscosity {
    /// The laminar term of Morris, Fox & Zhu (1997) with the fluid's dynamic viscosity.
    Laminar,
    /// Monaghan's (1992) artificial viscosity with coefficient α (0.01–0.1), for violent flows;
    /// the fluid's dynamic viscosity then only enters the time step.
    Artificial { alpha: f64 },
}

/// The density-diffusion (δ-SPH) term added to the continuity equation.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum DensityDiffusion {
    None,
    /// Molteni & Colagrossi (2009): the whole density difference diffuses; it pulls a column at
    /// rest away from its hydrostatic gradient near the free surface.
    MolteniColagrossi {
        delta: f64,
    },
    /// Fourtakas et al. (2019): only the difference beyond the hydrostatic one diffuses.
    Fourtakas {
        delta: f64,
    },
}

impl DensityDiffusion {
    pub fn delta(self) -> f64 {
        match self {
            DensityDiffusion::None => 0.0,
            DensityDiffusion::MolteniColagrossi { delta } | DensityDiffusion::Fourtakas { delta } => delta,
        }
    }
}

/// Everything the fluid's step reads, compiled from a scene (or written by a test).
#[derive(Clone, Debug)]
pub struct FluidSettings {
    pub dimension: Dimension,
    /// Initial particle spacing Δp, m.
    pub spacing: f64,
    /// Smoothing length h, m (≈ 1.3 Δp); the kernel reaches 2h.
    pub h: f64,
    /// Reference density ρ₀, kg/m³.
    pub rho0: f64,
    /// Dynamic viscosity μ, Pa·s.
    pub mu: f64,
    /// Reference sound speed c₀, m/s (10× the largest expected flow speed keeps density within ~1 %).
    pub sound_speed: f64,
    pub viscosity: Viscosity,
    pub density_diffusion: DensityDiffusion,
    /// Monaghan's (2000) tensile-instability correction, acting only where the pressure is negative.
    pub tensile_correction: bool,
    /// XSPH coefficient ε (0 turns it off): particles move with v − ε Σ (m_b/ρ̄_ab) v_ab W_ab.
    pub xsph: f64,
    pub gravity: DVec3,
    /// An acceleration on the fluid alone (drives a periodic channel flow).
    pub body_force: DVec3,
    /// The region the cell grid covers; its periodic axes are the fluid's. Particles leaving a
    /// non-periodic side are still found (binned into the edge cells), only more slowly.
    pub domain: PeriodicBox,
    /// The walls that move by a prescribed motion (a turning drum); wall particle i follows
    /// `moving_walls[wall[i] − 1]` (see [`FluidParticles::wall`](crate::FluidParticles)).
    pub moving_walls: Vec<MovingWall>,
    /// The rigid bodies the fluid moves; their wall particles are numbered after the moving
    /// walls: particle i belongs to `floating[wall[i] − 1 − moving_walls.len()]`.
    pub floating: Vec<FloatingBody>,
    /// Inflow buffers, their particles numbered after the floating bodies'.
    pub inflows: Vec<Inflow>,
    /// Outflow buffers, their particles numbered after the inflows'.
    pub outflows: Vec<Outflow>,
}

/// What a wall particle follows, by its number ([`FluidParticles::wall`](crate::FluidParticles)).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum WallRole {
    /// A wall at rest or moving at its particles' constant velocity.
    Fixed,
    Moving(usize),
    Body(usize),
    Inflow(usize),
    Outflow(usize),
}

/// A wall whose particles move by a prescribed rigid motion, when its timing says.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct MovingWall {
    pub motion: Motion,
    pub timing: Timing,
}

impl MovingWall {
    /// The velocity at time `t` of the wall material at `x`.
    pub fn velocity_at(&self, x: DVec3, t: f64) -> DVec3 {
        self.motion.instant(self.timing.elapsed(t), self.timing.rate(t)).velocity_at(x)
    }

    /// Where the wall material at `x` at time `t0` is at time `t1`.
    pub fn advance(&self, x: DVec3, t0: f64, t1: f64) -> DVec3 {
        self.motion.advance(x, self.timing.elapsed(t0), self.timing.elapsed(t1))
    }

    /// The acceleration at time `t` of the wall material at `x`.
    pub fn acceleration_at(&self, x: DVec3, t: f64) -> DVec3 {
        self.motion.acceleration_at(x, self.timing.elapsed(t), self.timing.rate(t), self.timing.rate_change(t))
    }
}

impl FluidSettings {
    /// The acceleration every fluid particle feels besides the other particles.
    pub fn external_acceleration(&self) -> DVec3 {
        self.gravity + self.body_force
    }

    /// The number [`FluidParticles::wall`](crate::FluidParticles) gives the particles of
    /// floating body `k`.
    pub fn body_wall_number(&self, k: usize) -> u16 {
        (self.moving_walls.len() + 1 + k) as u16
    }

    /// The number of inflow buffer `k`'s particles.
    pub fn inflow_wall_number(&self, k: usize) -> u16 {
        (self.moving_walls.len() + self.floating.len() + 1 + k) as u16
    }

    /// The number of outflow buffer `k`'s particles.
    pub fn outflow_wall_number(&self, k: usize) -> u16 {
        (self.moving_walls.len() + self.floating.len() + self.inflows.len() + 1 + k) as u16
    }

    /// How many wall numbers name something (beyond 0, a fixed wall).
    pub fn wall_numbers(&self) -> usize {
        self.moving_walls.len() + self.floating.len() + self.inflows.len() + self.outflows.len()
    }

    /// What wall number `w` follows.
    pub fn wall_role(&self, w: u16) -> WallRole {
        let mut k = w as usize;
        if k == 0 {
            return WallRole::Fixed;
        }
        k -= 1;
        for (count, role) in [
            (self.moving_walls.len(), WallRole::Moving as fn(usize) -> WallRole),
            (self.floating.len(), WallRole::Body),
            (self.inflows.len(), WallRole::Inflow),
        ] {
            if k < count {
                return role(k);
            }
            k -= count;
        }
        WallRole::Outflow(k)
    }

    /// The mass of one particle on the lattice of spacing Δp: ρ₀ Δp² in 2D (per metre of span), ρ₀ Δp³ in 3D.
    pub fn particle_mass(&self) -> f64 {
        self.rho0 * self.spacing.powi(self.dimension.count())
    }
}
