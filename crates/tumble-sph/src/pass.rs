//! The pass over one fluid particle's neighbours, four neighbours abreast.
//!
//! The neighbour lists reach 2h plus a skin, so about a third of their entries (2D; nearly half
//! in 3D) lie beyond the kernel. The pass first copies the entries within 2h, and what the sums
//! read of them, into a batch of contiguous arrays (a branch-free compaction), then evaluates the
//! batch in lanes of four with no branch: the artificial viscosity's switch is a `min`, the
//! kernel's cut-off a `max`, and the fluid-only and wall-only terms are weighted by 1 or 0. Each
//! lane keeps its own sums, added in a fixed order at the end, so the result depends on the list
//! alone, never on the number of threads or on the instruction set the pass was compiled for (no
//! fused multiply–add is used: AVX2 and SSE2 round alike).

use tumble_geom::DVec3;

use crate::rates::Method;
use crate::settings::{DensityDiffusion, FluidSettings};

/// Neighbours evaluated abreast.
const LANES: usize = 4;
/// Neighbours copied per batch (a multiple of [`LANES`]).
const BATCH: usize = 64;

/// What the pass reads of every particle, besides position and velocity: the extrapolated
/// pressure term P/ρ², the volume m/ρ, the tensile term R, the viscous velocity (Adami's 2 v_w − ṽ
/// for a wall particle), and 1 for a fluid particle, 0 for a wall particle.
pub(crate) struct Neighbourhood<'a> {
    pub position: &'a [DVec3],
    pub velocity: &'a [DVec3],
    pub viscous_velocity: &'a [DVec3],
    pub density: &'a [f64],
    /// The density the diffusion evens out: the fluid's own ρ (the density itself uncoupled).
    pub diffused: &'a [f64],
    pub mass: &'a [f64],
    pub pressure_term: &'a [f64],
    pub volume: &'a [f64],
    pub tensile: &'a [f64],
    pub fluid: &'a [f64],
}

/// One particle's rates: acceleration (without the external one), density rate (continuity and
/// diffusion apart) and the XSPH sum.
#[derive(Clone, Copy, Debug, Default)]
pub(crate) struct ParticleRates {
    pub acceleration: DVec3,
    pub continuity: f64,
    pub diffusion: f64,
    pub xsph: DVec3,
}

/// The method's constants the pair terms read, as plain numbers: the CPU's pass and the GPU's
/// kernels (tumble-gpu) take them from here.
#[derive(Clone, Copy, Debug)]
pub struct PassConstants {
    /// (2h)².
    pub support2: f64,
    pub inv_h: f64,
    /// −5 α / h², so that (dW/dr)/r = this · (1 − q/2)³.
    pub gradient_scale: f64,
    /// The kernel's normalisation α.
    pub alpha: f64,
    /// 1/W(Δp), the tensile correction's reference.
    pub inv_w_dp: f64,
    /// η² of the artificial viscosity and the density diffusion.
    pub eta2: f64,
    /// η² of the laminar term.
    pub laminar_eta2: f64,
    /// 2μ of the laminar term.
    pub two_mu: f64,
    /// α c₀ h of the artificial viscosity (zero with the laminar term).
    pub av_scale: f64,
    /// ρ₀/c₀² times the external acceleration: Fourtakas's hydrostatic density difference per metre.
    pub hydrostatic: DVec3,
    /// The wall repulsion's reach r₀ and stiffness.
    pub reach: f64,
    pub stiffness: f64,
    /// The smallest distance the repulsion divides by (coincident particles feel none).
    pub tiny: f64,
    /// δ h c₀ of the density diffusion (zero without it).
    pub diffusion_scale: f64,
}

impl PassConstants {
    pub(crate) fn new(method: &Method, alpha_av: f64, fourtakas: bool) -> Self {
        let h = method.kernel.h();
        let inv_h = 1.0 / h;
        let alpha = method.kernel.value(0.0);
        PassConstants {
            support2: method.support2,
            inv_h,
            gradient_scale: -5.0 * alpha * inv_h * inv_h,
            alpha,
            inv_w_dp: 1.0 / method.w_dp,
            eta2: method.eta2,
            laminar_eta2: method.laminar_eta2,
            two_mu: method.two_mu,
            av_scale: alpha_av * method.eos.c0 * h,
            hydrostatic: if fourtakas { method.density_per_pressure * method.rho0 * method.external } else { DVec3::ZERO },
            reach: method.repulsion_reach,
            stiffness: method.repulsion_stiffness,
            tiny: 1e-9 * h,
            diffusion_scale: method.diffusion_scale,
        }
    }

    /// The constants of the fluid `settings` describe, as an evaluation of its rates uses them.
    pub fn of(settings: &FluidSettings) -> Self {
        let method = Method::new(settings);
        PassConstants::new(&method, method.artificial_alpha(), matches!(method.diffusion, DensityDiffusion::Fourtakas { .. }))
    }
}

/// The batch of neighbours within 2h, one array per quantity: scratch space a thread reuses
/// from particle to particle (only entries written for the current particle are read).
pub(crate) struct Batch {
    len: usize,
    index: [u32; BATCH],
    d: [[f64; BATCH]; 3],
    r2: [f64; BATCH],
    v: [[f64; BATCH]; 3],
    vv: [[f64; BATCH]; 3],
    rho: [f64; BATCH],
    rho_diffused: [f64; BATCH],
    m: [f64; BATCH],
    p_term: [f64; BATCH],
    volume: [f64; BATCH],
    tensile: [f64; BATCH],
    fluid: [f64; BATCH],
}

impl Batch {
    pub fn new() -> Self {
        let z = [0.0; BATCH];
        Batch {
            len: 0,
            index: [0; BATCH],
            d: [z; 3],
            r2: z,
            v: [z; 3],
            vv: [z; 3],
            rho: z,
            rho_diffused: z,
            m: z,
            p_term: z,
            volume: z,
            tensile: z,
            fluid: z,
        }
    }
}

/// The rates of fluid particle `a` over the entries of `list`, in the [`crate::rates`] equations.
/// `PLANE` leaves out the y components (2D: the plane x–z).
#[inline(always)]
#[allow(clippy::too_many_arguments)]
pub(crate) fn particle_rates<const PLANE: bool, const LAMINAR: bool, const DIFFUSE: bool, const TENSILE: bool, const XSPH: bool>(
    k: &PassConstants,
    n: &Neighbourhood,
    separation: impl Fn(DVec3, DVec3) -> DVec3,
    a: usize,
    list: &[u32],
    batch: &mut Batch,
) -> ParticleRates {
    let xa = n.position[a];
    let va = n.velocity[a];
    let rho_a = n.density[a];
    let rho_da = n.diffused[a];
    let pa_term = n.pressure_term[a];
    let ra = n.tensile[a];
    let mut sums = Lanes::default();
    for chunk in list.chunks(BATCH) {
        // The entries within 2h, their separations first; what else the sums read after.
        let mut len = 0;
        for &b in chunk {
            let d = separation(xa, n.position[b as usize]);
            let r2 = d.length_squared();
            batch.index[len] = b;
            batch.d[0][len] = d.x;
            if !PLANE {
                batch.d[1][len] = d.y;
            }
            batch.d[2][len] = d.z;
            batch.r2[len] = r2;
            len += (r2 < k.support2) as usize;
        }
        batch.len = len;
        for i in 0..batch.len {
            let b = batch.index[i] as usize;
            let (v, vv) = (n.velocity[b], n.viscous_velocity[b]);
            batch.v[0][i] = v.x;
            batch.v[2][i] = v.z;
            batch.vv[0][i] = vv.x;
            batch.vv[2][i] = vv.z;
            if !PLANE {
                batch.v[1][i] = v.y;
                batch.vv[1][i] = vv.y;
            }
            batch.rho[i] = n.density[b];
            batch.m[i] = n.mass[b];
            batch.p_term[i] = n.pressure_term[b];
            if DIFFUSE {
                batch.volume[i] = n.volume[b];
                batch.rho_diffused[i] = n.diffused[b];
            }
            if TENSILE {
                batch.tensile[i] = n.tensile[b];
            }
            batch.fluid[i] = n.fluid[b];
        }
        // Pad to whole lanes with entries beyond the kernel, whose terms are all zero.
        while !batch.len.is_multiple_of(LANES) {
            let i = batch.len;
            for c in 0..3 {
                batch.d[c][i] = 0.0;
                batch.v[c][i] = va[c];
                batch.vv[c][i] = va[c];
            }
            batch.r2[i] = 4.0 * k.support2;
            batch.rho[i] = rho_a;
            batch.rho_diffused[i] = rho_da;
            batch.m[i] = 0.0;
            batch.p_term[i] = 0.0;
            batch.volume[i] = 0.0;
            batch.tensile[i] = 0.0;
            batch.fluid[i] = 1.0;
            batch.len += 1;
        }
        let mut start = 0;
        while start < batch.len {
            sums.add::<PLANE, LAMINAR, DIFFUSE, TENSILE, XSPH>(k, batch, start, [va.x, va.y, va.z], [rho_a, rho_da], pa_term, ra);
            start += LANES;
        }
    }
    sums.total()
}

/// Four partial sums of each rate.
#[derive(Default)]
struct Lanes {
    acc: [[f64; LANES]; 3],
    continuity: [f64; LANES],
    diffusion: [f64; LANES],
    xsph: [[f64; LANES]; 3],
}

impl Lanes {
    /// Adds the terms of batch entries `start..start + LANES`.
    #[inline(always)]
    #[allow(clippy::too_many_arguments)]
    fn add<const PLANE: bool, const LAMINAR: bool, const DIFFUSE: bool, const TENSILE: bool, const XSPH: bool>(
        &mut self,
        k: &PassConstants,
        b: &Batch,
        start: usize,
        va: [f64; 3],
        [rho_a, rho_da]: [f64; 2],
        pa_term: f64,
        ra: f64,
    ) {
        let axes: &[usize] = if PLANE { &[0, 2] } else { &[0, 1, 2] };
        let e = start;
        let d: [&[f64; LANES]; 3] = [lanes(&b.d[0], e), lanes(&b.d[1], e), lanes(&b.d[2], e)];
        let v: [&[f64; LANES]; 3] = [lanes(&b.v[0], e), lanes(&b.v[1], e), lanes(&b.v[2], e)];
        let vv: [&[f64; LANES]; 3] = [lanes(&b.vv[0], e), lanes(&b.vv[1], e), lanes(&b.vv[2], e)];
        let (r2, rho, m) = (lanes(&b.r2, e), lanes(&b.rho, e), lanes(&b.m, e));
        let (p_term_b, volume, tensile, fluid) = (lanes(&b.p_term, e), lanes(&b.volume, e), lanes(&b.tensile, e), lanes(&b.fluid, e));
        for l in 0..LANES {
            let r = r2[l].sqrt();
            let q = r * k.inv_h;
            let s = (1.0 - 0.5 * q).max(0.0);
            let s2 = s * s;
            let gw = k.gradient_scale * s2 * s;
            let w = k.alpha * s2 * s2 * (2.0 * q + 1.0);
            // Continuity sees the neighbour's own velocity, the viscous terms Adami's.
            let mut v_dot_grad = 0.0;
            let mut vr = 0.0;
            for &c in axes {
                v_dot_grad += (va[c] - v[c][l]) * d[c][l];
                vr += (va[c] - vv[c][l]) * d[c][l];
            }
            self.continuity[l] += m[l] * v_dot_grad * gw;
            let mut p_term = pa_term + p_term_b[l];
            if TENSILE {
                let f = w * k.inv_w_dp;
                let f2 = f * f;
                p_term += (ra + tensile[l]) * f2 * f2;
            }
            let mean_rho = 0.5 * (rho_a + rho[l]);
            let laminar = if LAMINAR {
                m[l] * k.two_mu * r2[l] * gw / (rho_a * rho[l] * (r2[l] + k.laminar_eta2))
            } else {
                p_term -= k.av_scale * vr.min(0.0) / (mean_rho * (r2[l] + k.eta2));
                0.0
            };
            let pressure = m[l] * p_term * gw;
            // A linear penalty against wall particles only: zero at r₀ and beyond.
            let repulsion = (1.0 - fluid[l]) * k.stiffness * (k.reach - r).max(0.0) / r.max(k.tiny);
            for &c in axes {
                let mut a = repulsion * d[c][l] - pressure * d[c][l];
                if LAMINAR {
                    a += laminar * (va[c] - vv[c][l]);
                }
                self.acc[c][l] += a;
            }
            if DIFFUSE {
                let mut drho_ab = rho_da - lanes(&b.rho_diffused, e)[l];
                let mut hydrostatic = 0.0;
                for &c in axes {
                    hydrostatic += k.hydrostatic[c] * d[c][l];
                }
                drho_ab -= hydrostatic;
                self.diffusion[l] += fluid[l] * (2.0 * drho_ab * r2[l] * gw / (r2[l] + k.eta2) * volume[l]);
            }
            if XSPH {
                let c = fluid[l] * (m[l] / mean_rho * w);
                for &ax in axes {
                    self.xsph[ax][l] -= c * (va[ax] - v[ax][l]);
                }
            }
        }
    }

    /// The lanes' sums added in a fixed order.
    fn total(&self) -> ParticleRates {
        let sum = |x: &[f64; LANES]| (x[0] + x[1]) + (x[2] + x[3]);
        ParticleRates {
            acceleration: DVec3::new(sum(&self.acc[0]), sum(&self.acc[1]), sum(&self.acc[2])),
            continuity: sum(&self.continuity),
            diffusion: sum(&self.diffusion),
            xsph: DVec3::new(sum(&self.xsph[0]), sum(&self.xsph[1]), sum(&self.xsph[2])),
        }
    }
}

#[inline(always)]
fn lanes(x: &[f64; BATCH], start: usize) -> &[f64; LANES] {
    x[start..start + LANES].try_into().unwrap()
}

/// A wall particle's kernel sums over the fluid in its list (Adami et al. 2012): Σ W, Σ P W,
/// Σ ρ W r_wf and Σ W v_f.
#[derive(Clone, Copy, Debug, Default)]
pub(crate) struct WallSums {
    pub w: f64,
    pub pressure: f64,
    pub density_moment: DVec3,
    pub velocity: DVec3,
}

/// The sums of wall particle `w` over the fluid particles of `list`, four abreast as in
/// [`particle_rates`]; the fluid's pressure is read from the batch's pressure column.
#[inline(always)]
#[allow(clippy::too_many_arguments)]
pub(crate) fn wall_sums<const PLANE: bool>(
    k: &PassConstants,
    position: &[DVec3],
    velocity: &[DVec3],
    density: &[f64],
    pressure: &[f64],
    separation: impl Fn(DVec3, DVec3) -> DVec3,
    w: usize,
    list: &[u32],
    batch: &mut Batch,
) -> WallSums {
    let axes: &[usize] = if PLANE { &[0, 2] } else { &[0, 1, 2] };
    let xw = position[w];
    let mut sum_w = [0.0; LANES];
    let mut sum_p = [0.0; LANES];
    let mut sum_rho_r = [[0.0; LANES]; 3];
    let mut sum_v = [[0.0; LANES]; 3];
    for chunk in list.chunks(BATCH) {
        let mut len = 0;
        for &f in chunk {
            let d = separation(xw, position[f as usize]);
            let r2 = d.length_squared();
            batch.index[len] = f;
            batch.d[0][len] = d.x;
            batch.d[1][len] = d.y;
            batch.d[2][len] = d.z;
            batch.r2[len] = r2;
            len += (r2 < k.support2) as usize;
        }
        for i in 0..len {
            let f = batch.index[i] as usize;
            let v = velocity[f];
            batch.v[0][i] = v.x;
            batch.v[1][i] = v.y;
            batch.v[2][i] = v.z;
            batch.rho[i] = density[f];
            batch.p_term[i] = pressure[f];
        }
        while !len.is_multiple_of(LANES) {
            for c in 0..3 {
                batch.d[c][len] = 0.0;
                batch.v[c][len] = 0.0;
            }
            batch.r2[len] = 4.0 * k.support2;
            batch.rho[len] = 0.0;
            batch.p_term[len] = 0.0;
            len += 1;
        }
        let mut e = 0;
        while e < len {
            let (r2, rho, p) = (lanes(&batch.r2, e), lanes(&batch.rho, e), lanes(&batch.p_term, e));
            let d: [&[f64; LANES]; 3] = [lanes(&batch.d[0], e), lanes(&batch.d[1], e), lanes(&batch.d[2], e)];
            let v: [&[f64; LANES]; 3] = [lanes(&batch.v[0], e), lanes(&batch.v[1], e), lanes(&batch.v[2], e)];
            for l in 0..LANES {
                let q = r2[l].sqrt() * k.inv_h;
                let s = (1.0 - 0.5 * q).max(0.0);
                let s2 = s * s;
                let wk = k.alpha * s2 * s2 * (2.0 * q + 1.0);
                sum_w[l] += wk;
                sum_p[l] += p[l] * wk;
                for &c in axes {
                    sum_rho_r[c][l] += rho[l] * wk * d[c][l];
                    sum_v[c][l] += wk * v[c][l];
                }
            }
            e += LANES;
        }
    }
    let sum = |x: &[f64; LANES]| (x[0] + x[1]) + (x[2] + x[3]);
    WallSums {
        w: sum(&sum_w),
        pressure: sum(&sum_p),
        density_moment: DVec3::new(sum(&sum_rho_r[0]), sum(&sum_rho_r[1]), sum(&sum_rho_r[2])),
        velocity: DVec3::new(sum(&sum_v[0]), sum(&sum_v[1]), sum(&sum_v[2])),
    }
}

/// The force the fluid particles of `list` exert on wall particle `w` (a floating body's): minus
/// the sum of what each of them feels from `w` in [`particle_rates`] (pressure with the tensile
/// term, the viscosity, the repulsion), each term computed as the fluid particle computes it, so
/// that fluid and body exchange equal and opposite forces and momentum is conserved to round-off.
#[allow(clippy::too_many_arguments)]
pub(crate) fn wall_reaction<const LAMINAR: bool, const TENSILE: bool>(
    k: &PassConstants,
    n: &Neighbourhood,
    separation: impl Fn(DVec3, DVec3) -> DVec3,
    w: usize,
    list: &[u32],
) -> DVec3 {
    let (xw, vvw, rho_w, mw) = (n.position[w], n.viscous_velocity[w], n.density[w], n.mass[w]);
    let mut force = DVec3::ZERO;
    for &f in list {
        let f = f as usize;
        let d = separation(n.position[f], xw);
        let r2 = d.length_squared();
        if r2 >= k.support2 {
            continue;
        }
        let r = r2.sqrt();
        let q = r * k.inv_h;
        let s = (1.0 - 0.5 * q).max(0.0);
        let s2 = s * s;
        let gw = k.gradient_scale * s2 * s;
        let kernel = k.alpha * s2 * s2 * (2.0 * q + 1.0);
        let (vf, rho_f) = (n.velocity[f], n.density[f]);
        let mut p_term = n.pressure_term[f] + n.pressure_term[w];
        if TENSILE {
            let x = kernel * k.inv_w_dp;
            let x2 = x * x;
            p_term += (n.tensile[f] + n.tensile[w]) * x2 * x2;
        }
        let laminar = if LAMINAR {
            mw * k.two_mu * r2 * gw / (rho_f * rho_w * (r2 + k.laminar_eta2))
        } else {
            let vr = (vf - vvw).dot(d);
            p_term -= k.av_scale * vr.min(0.0) / (0.5 * (rho_f + rho_w) * (r2 + k.eta2));
            0.0
        };
        let repulsion = k.stiffness * (k.reach - r).max(0.0) / r.max(k.tiny);
        let mut acceleration = (repulsion - mw * p_term * gw) * d;
        if LAMINAR {
            acceleration += laminar * (vf - vvw);
        }
        force -= n.mass[f] * acceleration;
    }
    force
}
