//! Open boundaries: inflow and outflow buffers. An inflow buffer is a box of particles moving
//! at the inflow velocity; one that passes the box's open face becomes fluid, and a new one
//! takes its place at the back of the box, a whole buffer depth behind it. A fluid particle
//! that enters an outflow buffer becomes one of its particles, at the outlet's pressure and
//! the velocity of the fluid beside it, and is removed once it leaves the box. Both kinds act
//! on the fluid as wall particles do. Particles change sides only when the arrays are re-sorted,
//! in one pass in array order, so the exchange does not depend on the number of threads.

use tumble_geom::{DVec3, Timing};

use crate::particles::{Aabb, FluidParticles, ParticleKind};
use crate::settings::{FluidSettings, WallRole};

/// An axis-aligned box and the direction of the flow through it, along one axis.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct BufferBox {
    pub region: Aabb,
    /// 0, 1 or 2.
    pub axis: usize,
    /// +1 when the flow runs towards the box's high side along `axis`, −1 towards its low side.
    pub sign: f64,
}

impl BufferBox {
    /// The unit vector of the flow.
    pub fn direction(&self) -> DVec3 {
        let mut d = DVec3::ZERO;
        d[self.axis] = self.sign;
        d
    }

    /// The box's extent along the flow.
    pub fn depth(&self) -> f64 {
        self.region.max[self.axis] - self.region.min[self.axis]
    }

    /// How far `x` lies beyond the face the flow leaves the box by (negative inside).
    pub fn past_exit(&self, x: DVec3) -> f64 {
        let a = self.axis;
        if self.sign > 0.0 { x[a] - self.region.max[a] } else { self.region.min[a] - x[a] }
    }

    /// How far `x` lies beyond the face the flow enters the box by (negative before it).
    pub fn past_entry(&self, x: DVec3) -> f64 {
        self.past_exit(x) + self.depth()
    }

    /// Whether `x` lies within the box across the flow (the other axes; in 2D x and z only).
    pub fn across(&self, x: DVec3, plane: bool) -> bool {
        (0..3).all(|k| k == self.axis || (plane && k == 1) || (x[k] >= self.region.min[k] && x[k] < self.region.max[k]))
    }
}

/// An inflow buffer: particles moving along the box's flow enter the fluid through the box's
/// open face, at `speed` on average over the face once `timing` has ramped it up, spread over the
/// face as `profile` says.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Inflow {
    pub buffer: BufferBox,
    /// The mean inflow speed at full rate, m/s (> 0).
    pub speed: f64,
    pub profile: InflowProfile,
    /// How the speed starts: from 0 at t = 0 up to full over `timing.ramp` (all at once with
    /// [`Timing::ALWAYS`]).
    pub timing: Timing,
}

/// How the inflow speed varies across the open face.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub enum InflowProfile {
    /// The same everywhere (plug flow).
    #[default]
    Uniform,
    /// Poiseuille's parabola across each axis of the face, zero at the box's sides: u = 6 U s (1 − s)
    /// across one axis (a 2D channel; peak 1.5 U), the product of two such across both (a
    /// rectangular duct in 3D; peak 2.25 U), so the mean over the face is U.
    Parabolic,
}

impl Inflow {
    /// A plug inflow at `speed` from the start.
    pub fn uniform(buffer: BufferBox, speed: f64) -> Self {
        Inflow { buffer, speed, profile: InflowProfile::Uniform, timing: Timing::ALWAYS }
    }

    /// The mean velocity over the face at full rate.
    pub fn velocity(&self) -> DVec3 {
        self.speed * self.buffer.direction()
    }

    /// The share of the mean speed at `x` on the face (1 for plug flow).
    pub fn shape(&self, x: DVec3, plane: bool) -> f64 {
        match self.profile {
            InflowProfile::Uniform => 1.0,
            InflowProfile::Parabolic => (0..3)
                .filter(|&k| k != self.buffer.axis && !(plane && k == 1))
                .map(|k| {
                    let (lo, hi) = (self.buffer.region.min[k], self.buffer.region.max[k]);
                    let s = ((x[k] - lo) / (hi - lo)).clamp(0.0, 1.0);
                    6.0 * s * (1.0 - s)
                })
                .product(),
        }
    }

    /// The largest speed over the face at full rate.
    pub fn peak_speed(&self, plane: bool) -> f64 {
        let across = if plane { 1 } else { 2 };
        match self.profile {
            InflowProfile::Uniform => self.speed,
            InflowProfile::Parabolic => self.speed * 1.5f64.powi(across),
        }
    }

    /// The velocity of the inflow's particle at `x` at time `t`.
    pub fn velocity_at(&self, x: DVec3, t: f64, plane: bool) -> DVec3 {
        self.timing.rate(t) * self.shape(x, plane) * self.velocity()
    }

    /// How far the inflow's particle at `x` moves from `t0` to `t1`: exactly, through the ramp.
    pub fn travel(&self, x: DVec3, t0: f64, t1: f64, plane: bool) -> DVec3 {
        (self.timing.elapsed(t1) - self.timing.elapsed(t0)) * self.shape(x, plane) * self.velocity()
    }
}

/// An outflow buffer: fluid entering the box leaves the fluid, held at `pressure`.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Outflow {
    pub buffer: BufferBox,
    /// The outlet's pressure, Pa.
    pub pressure: f64,
}

/// What has passed through the buffers since the start: the fluid's mass changes by exactly
/// `inflow_mass − outflow_mass` (the same particles' masses, added up).
#[derive(Clone, Copy, Debug, Default, PartialEq, serde::Serialize, serde::Deserialize)]
pub struct BufferBooks {
    pub inflow_particles: u64,
    pub inflow_mass: f64,
    pub outflow_particles: u64,
    pub outflow_mass: f64,
}

/// Moves particles across the buffers' faces: inflow particles past their open face become
/// fluid (and new ones start a buffer depth behind), fluid inside an outflow box joins it, and
/// outflow particles past its far face are removed. New particles take ids from `next_id`.
/// Returns whether anything changed.
pub(crate) fn exchange(settings: &FluidSettings, p: &mut FluidParticles, next_id: &mut u32, books: &mut BufferBooks) -> bool {
    if settings.inflows.is_empty() && settings.outflows.is_empty() {
        return false;
    }
    let plane = settings.dimension == crate::Dimension::Two;
    let n = p.len();
    let mut removed = vec![false; n];
    let mut changed = false;
    #[allow(clippy::needless_range_loop)] // pushes to `p` as it goes: the range is the particles before.
    for i in 0..n {
        let x = p.position[i];
        match (p.kind[i], settings.wall_role(p.wall[i])) {
            (ParticleKind::Wall, WallRole::Inflow(k)) => {
                let inflow = &settings.inflows[k];
                if inflow.buffer.past_exit(x) >= 0.0 {
                    let behind = x - inflow.buffer.depth() * inflow.buffer.direction();
                    // The same place across the face at the same time: the same velocity.
                    p.push_with_id(*next_id, ParticleKind::Wall, behind, p.velocity[i], p.density[i], p.mass[i]);
                    *p.wall.last_mut().expect("just pushed") = p.wall[i];
                    *next_id += 1;
                    p.kind[i] = ParticleKind::Fluid;
                    p.wall[i] = 0;
                    books.inflow_particles += 1;
                    books.inflow_mass += p.mass[i];
                    changed = true;
                }
            }
            (ParticleKind::Fluid, _) => {
                let joins =
                    settings.outflows.iter().position(|o| o.buffer.past_entry(x) >= 0.0 && o.buffer.past_exit(x) < 0.0 && o.buffer.across(x, plane));
                if let Some(k) = joins {
                    p.kind[i] = ParticleKind::Wall;
                    p.wall[i] = settings.outflow_wall_number(k);
                    books.outflow_particles += 1;
                    books.outflow_mass += p.mass[i];
                    changed = true;
                }
            }
            (ParticleKind::Wall, WallRole::Outflow(k)) => {
                let buffer = &settings.outflows[k].buffer;
                if buffer.past_exit(x) >= 0.0 || !buffer.across(x, plane) {
                    removed[i] = true;
                    changed = true;
                }
            }
            _ => {}
        }
    }
    if removed.iter().any(|&r| r) {
        p.remove_where(|i| i < n && removed[i]);
    }
    changed
}

/// The fluid's pressure at `x` and its gradient, fitted to the fluid within 2h by kernel-weighted
/// least squares, P ≈ a + ∇P·(x_f − x) (the first-order corrected interpolation of Liu & Liu
/// 2006, as Tafuni et al. 2018 use it for open boundaries); the Shepard average where the fluid
/// around `x` is too sparse to fit a plane through (fluid fraction below one half), none where
/// there is no fluid.
pub(crate) fn pressure_fit(
    grid: &crate::neighbours::FluidGrid,
    p: &FluidParticles,
    pressure: &[f64],
    kernel: &crate::kernel::WendlandC2,
    x: DVec3,
    plane: bool,
) -> Option<(f64, DVec3)> {
    let h = kernel.h();
    let reach2 = kernel.support() * kernel.support();
    // Moments of [1, d/h] ⊗ [1, d/h] and the right-hand side, d = x_f − x (scaled by h to keep
    // the system well conditioned); in 2D the y row is the identity's.
    let mut m = glam::DMat4::ZERO;
    let mut rhs = glam::DVec4::ZERO;
    grid.for_each_candidate_near(x, |f| {
        if p.kind[f] != ParticleKind::Fluid {
            return;
        }
        let d = grid.separation(p.position[f], x);
        let r2 = d.length_squared();
        if r2 >= reach2 {
            return;
        }
        let w = kernel.value(r2.sqrt()) * p.mass[f] / p.density[f];
        let u = glam::DVec4::new(1.0, d.x / h, if plane { 0.0 } else { d.y / h }, d.z / h);
        for c in 0..4 {
            *m.col_mut(c) += w * u[c] * u;
        }
        rhs += w * pressure[f] * u;
    });
    let fraction = m.x_axis.x;
    if fraction <= 0.0 {
        return None;
    }
    if plane {
        m.y_axis = glam::DVec4::Y;
    }
    if fraction < 0.5 || m.determinant().abs() < 1e-9 * fraction.powi(4) {
        return Some((rhs.x / fraction, DVec3::ZERO));
    }
    let fit = m.inverse() * rhs;
    Some((fit.x, DVec3::new(fit.y, fit.z, fit.w) / h))
}
