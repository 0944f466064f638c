//! One evaluation of the fluid's equations: the walls' extrapolated state, then each fluid
//! particle's acceleration, density rate and XSPH correction, each gathered by the particle
//! itself over its neighbours in slot order (no scatter, no atomics: the same sums for any
//! number of threads).

use rayon::prelude::*;
use tumble_geom::DVec3;

use crate::eos::Tait;
use crate::kernel::WendlandC2;
use crate::neighbours::FluidGrid;
use crate::particles::{FluidParticles, ParticleKind};
use crate::settings::{DensityDiffusion, FluidSettings, Viscosity};

/// The constants of one evaluation, derived once from the settings.
#[derive(Clone, Copy, Debug)]
pub(crate) struct Method {
    pub kernel: WendlandC2,
    pub eos: Tait,
    /// (2h)².
    pub support2: f64,
    /// η² = 0.01 h², keeping 1/r² finite in the artificial viscosity and the density diffusion
    /// (Monaghan's value, which their coefficients α and δ are calibrated with).
    pub eta2: f64,
    /// η² = 10⁻⁴ h² in the laminar term: Morris's 0.01 h² weakens the viscous operator by 2 %
    /// for the nearest neighbours at h = 1.5 Δp, whatever the resolution, which stalled the
    /// convergence of channel flows at about 0.8 % of the peak speed (tests/channel.rs).
    pub laminar_eta2: f64,
    pub viscosity: Viscosity,
    /// 2μ for the laminar term (μ_a + μ_b).
    pub two_mu: f64,
    pub diffusion: DensityDiffusion,
    /// δ h c₀ of the density diffusion.
    pub diffusion_scale: f64,
    /// W(Δp), the reference of the tensile correction.
    pub w_dp: f64,
    pub tensile: bool,
    pub xsph: f64,
    pub external: DVec3,
    /// 1/c₀², turning a hydrostatic pressure difference into a density difference.
    pub density_per_pressure: f64,
    pub rho0: f64,
    /// The wall repulsion's reach r₀ = Δp/2 and stiffness k = (c₀/Δp)² (an acceleration per metre).
    pub repulsion_reach: f64,
    pub repulsion_stiffness: f64,
}

impl Method {
    pub fn new(s: &FluidSettings) -> Self {
        let kernel = WendlandC2::new(s.h, s.dimension);
        let eos = Tait::new(s.rho0, s.sound_speed);
        Method {
            kernel,
            eos,
            support2: 4.0 * s.h * s.h,
            eta2: 0.01 * s.h * s.h,
            laminar_eta2: 1e-4 * s.h * s.h,
            viscosity: s.viscosity,
            two_mu: 2.0 * s.mu,
            diffusion: s.density_diffusion,
            diffusion_scale: s.density_diffusion.delta() * s.h * s.sound_speed,
            w_dp: kernel.value(s.spacing),
            tensile: s.tensile_correction,
            xsph: s.xsph,
            external: s.external_acceleration(),
            density_per_pressure: 1.0 / (s.sound_speed * s.sound_speed),
            rho0: s.rho0,
            repulsion_reach: 0.5 * s.spacing,
            // Stiff enough to stop a particle arriving at a quarter of the sound speed within Δp/4,
            // soft enough that its period 2π Δp/c₀ spans about twenty steps: Monaghan's (1994)
            // Lennard-Jones form (r₀/r)¹² − (r₀/r)⁴ at a useful strength made the collapse of a
            // column unstable where the wave hit the far wall (tests/conservation.rs).
            repulsion_stiffness: (s.sound_speed / s.spacing).powi(2),
        }
    }
}

/// What an evaluation reads besides the particles: pressure of every particle, and for wall
/// particles the velocity the viscous term sees (Adami's 2 v_w − ṽ).
#[derive(Clone, Debug, Default)]
pub(crate) struct PairInputs {
    pub pressure: Vec<f64>,
    pub viscous_velocity: Vec<DVec3>,
}

/// What an evaluation produces per particle (zero for walls).
#[derive(Clone, Debug, Default)]
pub struct Rates {
    pub acceleration: Vec<DVec3>,
    pub density_rate: Vec<f64>,
    /// The XSPH correction to the advection velocity.
    pub xsph: Vec<DVec3>,
}

impl Rates {
    pub(crate) fn resize(&mut self, n: usize) {
        self.acceleration.resize(n, DVec3::ZERO);
        self.density_rate.resize(n, 0.0);
        self.xsph.resize(n, DVec3::ZERO);
    }
}

/// Pressure of the fluid particles from the equation of state, then each wall particle's
/// pressure, density and viscous velocity extrapolated from the fluid (Adami et al. 2012):
/// P_w = max(0, (Σ P_f W + (g − a_w)·Σ ρ_f r_wf W) / Σ W), ρ_w from the equation of state,
/// v̂_w = 2 v_w − Σ v_f W / Σ W. A wall particle with no fluid in reach has P = 0, ρ = ρ₀.
/// Walls move at constant velocity, so a_w = 0. The clamp keeps a wall from holding a thin
/// film by suction (particles clung to the wall a dam break had left, docs/sph.md).
pub(crate) fn prepare(method: &Method, grid: &FluidGrid, p: &mut FluidParticles, inputs: &mut PairInputs) {
    let n = p.len();
    inputs.pressure.resize(n, 0.0);
    inputs.viscous_velocity.resize(n, DVec3::ZERO);
    let (kind, position, velocity) = (&p.kind, &p.position, &p.velocity);
    inputs.pressure.par_iter_mut().zip(p.density.par_iter()).zip(kind.par_iter()).for_each(|((pr, &rho), &k)| {
        if k == ParticleKind::Fluid {
            *pr = method.eos.pressure(rho);
        }
    });
    let fluid_pressure = &inputs.pressure;
    let walls: Vec<(f64, f64, DVec3)> = (0..n)
        .into_par_iter()
        .map(|w| {
            if kind[w] != ParticleKind::Wall {
                return (0.0, 0.0, DVec3::ZERO);
            }
            let xw = position[w];
            let mut sum_w = 0.0;
            let mut sum_p = 0.0;
            let mut sum_rho_r = DVec3::ZERO;
            let mut sum_v = DVec3::ZERO;
            for &f in grid.neighbours(w) {
                let f = f as usize;
                let d = grid.separation(xw, position[f]);
                let r2 = d.length_squared();
                if r2 >= method.support2 {
                    continue;
                }
                let wk = method.kernel.value(r2.sqrt());
                sum_w += wk;
                sum_p += fluid_pressure[f] * wk;
                sum_rho_r += p.density[f] * wk * d;
                sum_v += wk * velocity[f];
            }
            if sum_w > 0.0 {
                let pw = ((sum_p + method.external.dot(sum_rho_r)) / sum_w).max(0.0);
                (pw, method.eos.density(pw), 2.0 * velocity[w] - sum_v / sum_w)
            } else {
                (0.0, method.rho0, velocity[w])
            }
        })
        .collect();
    inputs
        .pressure
        .par_iter_mut()
        .zip(inputs.viscous_velocity.par_iter_mut())
        .zip(p.density.par_iter_mut())
        .zip(walls.par_iter())
        .enumerate()
        .for_each(|(i, (((pr, vv), rho), &(pw, rho_w, v)))| {
            if kind[i] == ParticleKind::Wall {
                *pr = pw;
                *rho = rho_w;
                *vv = v;
            } else {
                *vv = velocity[i];
            }
        });
}

/// Each fluid particle's rates, gathered over its neighbours:
/// - continuity with density diffusion: dρ_a/dt = Σ m_b v_ab·∇W + δ h c₀ Σ ψ_ab·∇W V_b;
/// - momentum: dv_a/dt = −Σ m_b (P_a/ρ_a² + P_b/ρ_b² + R_ab + Π_ab) ∇W + laminar term + g + f;
/// - XSPH: −ε Σ (m_b/ρ̄_ab) v_ab W;
/// - the wall repulsion within Δp/2 of a wall particle, k (r₀ − r) along r_ab.
pub(crate) fn evaluate(method: &Method, grid: &FluidGrid, p: &FluidParticles, inputs: &PairInputs, out: &mut Rates) {
    // One copy of the pass per combination of the method's switches, so none is tested per pair.
    let laminar = matches!(method.viscosity, Viscosity::Laminar);
    let diffuse = method.diffusion_scale != 0.0;
    let fourtakas = matches!(method.diffusion, DensityDiffusion::Fourtakas { .. });
    let (tensile, xsph) = (method.tensile, method.xsph != 0.0);
    macro_rules! dispatch {
        ($($l:literal $d:literal $f:literal $t:literal $x:literal),*) => {
            match (laminar, diffuse, fourtakas, tensile, xsph) {
                $(($l, $d, $f, $t, $x) => evaluate_with::<$l, $d, $f, $t, $x>(method, grid, p, inputs, out),)*
            }
        };
    }
    dispatch!(
        false false false false false, false false false false true, false false false true false, false false false true true,
        false false true false false, false false true false true, false false true true false, false false true true true,
        false true false false false, false true false false true, false true false true false, false true false true true,
        false true true false false, false true true false true, false true true true false, false true true true true,
        true false false false false, true false false false true, true false false true false, true false false true true,
        true false true false false, true false true false true, true false true true false, true false true true true,
        true true false false false, true true false false true, true true false true false, true true false true true,
        true true true false false, true true true false true, true true true true false, true true true true true
    )
}

/// The pass of [`evaluate`] for one combination of switches: laminar (else artificial)
/// viscosity, density diffusion, its hydrostatic correction, the tensile correction, XSPH.
fn evaluate_with<const LAMINAR: bool, const DIFFUSE: bool, const FOURTAKAS: bool, const TENSILE: bool, const XSPH: bool>(
    method: &Method,
    grid: &FluidGrid,
    p: &FluidParticles,
    inputs: &PairInputs,
    out: &mut Rates,
) {
    let n = p.len();
    out.resize(n);
    let (kind, position, velocity, density, mass) = (&p.kind, &p.position, &p.velocity, &p.density, &p.mass);
    let pressure = &inputs.pressure;
    let vhat = &inputs.viscous_velocity;
    let tensile_factor = |pr: f64, rho: f64| if TENSILE && pr < 0.0 { -0.2 * pr / (rho * rho) } else { 0.0 };
    let alpha = match method.viscosity {
        Viscosity::Artificial { alpha } => alpha,
        Viscosity::Laminar => 0.0,
    };
    // The method's constants as locals, so they stay in registers across the pair loop.
    let (support2, eta2, laminar_eta2, two_mu) = (method.support2, method.eta2, method.laminar_eta2, method.two_mu);
    let (kernel, w_dp, av_scale) = (method.kernel, method.w_dp, alpha * method.eos.c0 * method.kernel.h());
    let (hydrostatic_scale, external) = (method.density_per_pressure * method.rho0, method.external);
    let (reach, stiffness) = (method.repulsion_reach, method.repulsion_stiffness);
    out.acceleration.par_iter_mut().zip(out.density_rate.par_iter_mut()).zip(out.xsph.par_iter_mut()).enumerate().for_each(
        |(a, ((acc_out, drho_out), xsph_out))| {
            if kind[a] != ParticleKind::Fluid {
                *acc_out = DVec3::ZERO;
                *drho_out = 0.0;
                *xsph_out = DVec3::ZERO;
                return;
            }
            let xa = position[a];
            let va = velocity[a];
            let rho_a = density[a];
            let pa = pressure[a];
            let pa_term = pa / (rho_a * rho_a);
            let ra = tensile_factor(pa, rho_a);
            let mut acc = DVec3::ZERO;
            let mut drho = 0.0;
            let mut diffusion = 0.0;
            let mut xsph = DVec3::ZERO;
            for &b in grid.neighbours(a) {
                let b = b as usize;
                let d = grid.separation(xa, position[b]);
                let r2 = d.length_squared();
                if r2 >= support2 {
                    continue;
                }
                let r = r2.sqrt();
                let gw = kernel.gradient_over_r(r);
                let grad = d * gw;
                let mb = mass[b];
                let rho_b = density[b];
                let pb = pressure[b];
                let fluid_b = kind[b] == ParticleKind::Fluid;
                // Continuity and pressure see the wall's own velocity; the viscous terms Adami's.
                let v_ab = va - velocity[b];
                drho += mb * v_ab.dot(grad);
                let mut p_term = pa_term + pb / (rho_b * rho_b);
                if TENSILE {
                    let rb = tensile_factor(pb, rho_b);
                    if ra + rb > 0.0 {
                        let f = kernel.value(r) / w_dp;
                        let f2 = f * f;
                        p_term += (ra + rb) * f2 * f2;
                    }
                }
                let v_visc = va - vhat[b];
                if LAMINAR {
                    acc += (mb * two_mu * r2 * gw / (rho_a * rho_b * (r2 + laminar_eta2))) * v_visc;
                } else {
                    let vr = v_visc.dot(d);
                    if vr < 0.0 {
                        let mean_rho = 0.5 * (rho_a + rho_b);
                        p_term -= av_scale * vr / (mean_rho * (r2 + eta2));
                    }
                }
                acc -= (mb * p_term) * grad;
                if fluid_b {
                    if DIFFUSE {
                        let mut drho_ab = rho_a - rho_b;
                        if FOURTAKAS {
                            // ρ_H(a) − ρ_H(b) = ρ₀ g·r_ab / c₀² to first order in ρ₀ g r / B.
                            drho_ab -= hydrostatic_scale * external.dot(d);
                        }
                        diffusion += 2.0 * drho_ab * r2 * gw / (r2 + eta2) * (mb / rho_b);
                    }
                    if XSPH {
                        xsph -= (mb / (0.5 * (rho_a + rho_b)) * kernel.value(r)) * v_ab;
                    }
                } else if r < reach && r > 0.0 {
                    // A linear penalty: zero at r₀ and continuous, so it only acts in a violent impact.
                    acc += (stiffness * (reach - r) / r) * d;
                }
            }
            *acc_out = acc + method.external;
            *drho_out = drho + method.diffusion_scale * diffusion;
            *xsph_out = method.xsph * xsph;
        },
    );
}
