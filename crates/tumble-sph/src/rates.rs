//! One evaluation of the fluid's equations: the walls' extrapolated state, then each fluid
//! particle's acceleration, density rate and XSPH correction, each gathered by the particle
//! itself over its neighbours in slot order (no scatter, no atomics: the same sums for any
//! number of threads).

use rayon::prelude::*;
use tumble_geom::DVec3;

use crate::eos::Tait;
use crate::floating::BodyState;
use crate::kernel::{Dimension, WendlandC2};
use crate::neighbours::FluidGrid;
use crate::particles::{FluidParticles, ParticleKind};
use crate::pass::{Batch, Neighbourhood, ParticleRates, PassConstants, WallSums, particle_rates, wall_reaction, wall_sums};
use crate::settings::{DensityDiffusion, FluidSettings, Viscosity, WallRole};

/// The constants of one evaluation, derived once from the settings.
#[derive(Clone, Copy, Debug)]
pub(crate) struct Method {
    pub dimension: Dimension,
    /// The pair passes use 256-bit lanes (AVX2); the results are the same either way.
    pub wide_lanes: bool,
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
    /// The artificial viscosity's α, 0 with the laminar term.
    pub fn artificial_alpha(&self) -> f64 {
        match self.viscosity {
            Viscosity::Artificial { alpha } => alpha,
            Viscosity::Laminar => 0.0,
        }
    }

    pub fn new(s: &FluidSettings) -> Self {
        let kernel = WendlandC2::new(s.h, s.dimension);
        let eos = Tait::new(s.rho0, s.sound_speed);
        Method {
            dimension: s.dimension,
            wide_lanes: wide_lanes_available(),
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
    /// P/ρ².
    pub pressure_term: Vec<f64>,
    /// m/ρ.
    pub volume: Vec<f64>,
    /// Monaghan's tensile term R = −0.2 P/ρ² where P < 0, else 0 (zero without the correction).
    pub tensile: Vec<f64>,
    /// 1 for a fluid particle, 0 for a wall particle.
    pub fluid: Vec<f64>,
    /// Fluid particles within 2h of a buffer's face, whose density diffusion is left out (empty
    /// without buffers).
    pub diffusion_off: Vec<bool>,
    /// Each particle's fluid fraction ε beside coupled solids (1 for walls; empty uncoupled): a
    /// particle's density is then the superficial ε ρ, its pressure that of ρ.
    pub fraction: Vec<f64>,
    /// ρ = density / ε for the pressure, the walls' extrapolation and the density diffusion
    /// (empty uncoupled).
    pub intrinsic: Vec<f64>,
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

/// How the walls move at one instant: each moving wall by its motion at `time`, each floating
/// body by its state; the buffers at their own velocities.
#[derive(Clone, Copy)]
pub(crate) struct WallsAt<'a> {
    pub settings: &'a FluidSettings,
    pub bodies: &'a [BodyState],
    pub time: f64,
}

impl WallsAt<'_> {
    /// The acceleration of the material of a wall in `role` at `x`.
    fn acceleration(&self, grid: &FluidGrid, role: WallRole, x: DVec3) -> DVec3 {
        match role {
            WallRole::Moving(k) => self.settings.moving_walls[k].acceleration_at(x, self.time),
            WallRole::Body(k) => {
                let body = &self.bodies[k];
                body.acceleration_at(grid.separation(x, body.centre))
            }
            WallRole::Fixed | WallRole::Inflow(_) | WallRole::Outflow(_) => DVec3::ZERO,
        }
    }
}

/// Pressure of the fluid particles from the equation of state, then each wall particle's
/// pressure, density and viscous velocity extrapolated from the fluid (Adami et al. 2012):
/// P_w = max(0, (Σ P_f W + (g − a_w)·Σ ρ_f r_wf W) / Σ W), ρ_w from the equation of state,
/// v̂_w = 2 v_w − Σ v_f W / Σ W. A wall particle with no fluid in reach has P = 0, ρ = ρ₀.
/// A wall moving by a prescribed motion or a floating body has its acceleration a_w from `walls`;
/// others none. The clamp keeps a wall from holding a thin film by suction (particles clung to
/// the wall a dam break had left, docs/sph.md). Buffers differ: an inflow's particles take the
/// extrapolated pressure but keep their own velocity for the viscous terms (they stand for fluid
/// arriving at the inflow velocity); an outflow's take the outlet's pressure and the velocity
/// of the fluid beside them ṽ, which they then move with.
pub(crate) fn prepare(method: &Method, grid: &FluidGrid, p: &mut FluidParticles, inputs: &mut PairInputs, walls: WallsAt) {
    let n = p.len();
    inputs.pressure.resize(n, 0.0);
    inputs.viscous_velocity.resize(n, DVec3::ZERO);
    let kind = &p.kind;
    if inputs.fraction.is_empty() {
        inputs.intrinsic.clear();
    } else {
        let fraction = &inputs.fraction;
        inputs.intrinsic.resize(n, 0.0);
        inputs.intrinsic.par_iter_mut().zip(p.density.par_iter()).enumerate().for_each(|(i, (r, &rho))| *r = rho / fraction[i]);
    }
    let intrinsic = if inputs.intrinsic.is_empty() { &p.density } else { &inputs.intrinsic };
    inputs.pressure.par_iter_mut().zip(intrinsic.par_iter()).zip(kind.par_iter()).for_each(|((pr, &rho), &k)| {
        if k == ParticleKind::Fluid {
            *pr = method.eos.pressure(rho);
        }
    });
    let states = wall_states(method, grid, p, intrinsic, &inputs.pressure, walls);
    let (settings, wall) = (walls.settings, &p.wall);
    inputs
        .pressure
        .par_iter_mut()
        .zip(inputs.viscous_velocity.par_iter_mut())
        .zip(p.density.par_iter_mut())
        .zip(p.velocity.par_iter_mut())
        .zip(states.par_iter())
        .enumerate()
        .for_each(|(i, ((((pr, vv), rho), velocity), &(pw, rho_w, v)))| {
            if kind[i] == ParticleKind::Wall {
                *pr = pw;
                *rho = rho_w;
                *vv = v;
                if let WallRole::Outflow(_) = settings.wall_role(wall[i]) {
                    *velocity = v;
                }
            } else {
                *vv = *velocity;
            }
        });
    // A wall particle's density is its own (its fraction is 1).
    if !inputs.intrinsic.is_empty() {
        let density = &p.density;
        inputs.intrinsic.par_iter_mut().enumerate().filter(|(i, _)| kind[*i] == ParticleKind::Wall).for_each(|(i, r)| *r = density[i]);
    }
    // What the pass reads of each neighbour, computed once per particle instead of once per pair.
    inputs.pressure_term.resize(n, 0.0);
    inputs.volume.resize(n, 0.0);
    inputs.tensile.resize(n, 0.0);
    inputs.fluid.resize(n, 0.0);
    // The density diffusion's kernel is cut at a buffer's face: the buffer's densities are not
    // the fluid's continuation, and the sum there acts as a source that held the inflow's
    // pressure short of driving the flow (a channel carried 5–7 % less than it took in;
    // docs/sph.md, "Inflow and outflow"). It is left out within 2h of the faces.
    if settings.inflows.is_empty() && settings.outflows.is_empty() {
        inputs.diffusion_off.clear();
    } else {
        let (reach, plane) = (2.0 * method.kernel.h(), method.dimension == Dimension::Two);
        inputs.diffusion_off.resize(n, false);
        inputs.diffusion_off.par_iter_mut().zip(p.position.par_iter()).for_each(|(off, &x)| {
            *off = settings.inflows.iter().any(|b| b.buffer.past_exit(x).abs() < reach && b.buffer.across(x, plane))
                || settings.outflows.iter().any(|b| b.buffer.past_entry(x).abs() < reach && b.buffer.across(x, plane));
        });
    }
    let tensile = method.tensile;
    let (pressure, density, mass) = (&inputs.pressure, &p.density, &p.mass);
    inputs
        .pressure_term
        .par_iter_mut()
        .zip(inputs.volume.par_iter_mut())
        .zip(inputs.tensile.par_iter_mut())
        .zip(inputs.fluid.par_iter_mut())
        .enumerate()
        .for_each(|(i, (((pt, vol), r), f))| {
            let (pr, rho) = (pressure[i], density[i]);
            *pt = pr / (rho * rho);
            *vol = mass[i] / rho;
            *r = if tensile && pr < 0.0 { -0.2 * pr / (rho * rho) } else { 0.0 };
            *f = if kind[i] == ParticleKind::Fluid { 1.0 } else { 0.0 };
        });
}

/// Each wall particle's extrapolated pressure, density and viscous velocity (zeros for fluid).
/// `density` is the fluid's own ρ (the superficial density over ε beside coupled solids).
fn wall_states(method: &Method, grid: &FluidGrid, p: &FluidParticles, density: &[f64], pressure: &[f64], walls: WallsAt) -> Vec<(f64, f64, DVec3)> {
    let constants = PassConstants::new(method, 0.0, false);
    let (plane, wide) = (method.dimension == Dimension::Two, method.wide_lanes);
    let (position, velocity) = (&p.position, &p.velocity);
    (0..p.len())
        .into_par_iter()
        .map_init(
            || Box::new(Batch::new()),
            |batch, w| {
                if p.kind[w] != ParticleKind::Wall {
                    return (0.0, 0.0, DVec3::ZERO);
                }
                let list = grid.neighbours(w);
                let separation = |x, y| grid.separation(x, y);
                let sums = match (plane, wide) {
                    // SAFETY: `wide_lanes` is set only where the processor has AVX2 (`Method::new`).
                    (true, true) => unsafe { wall_sums_avx2::<true>(&constants, p, density, pressure, grid, w, list, batch) },
                    (false, true) => unsafe { wall_sums_avx2::<false>(&constants, p, density, pressure, grid, w, list, batch) },
                    (true, false) => wall_sums::<true>(&constants, position, velocity, density, pressure, separation, w, list, batch),
                    (false, false) => wall_sums::<false>(&constants, position, velocity, density, pressure, separation, w, list, batch),
                };
                let role = walls.settings.wall_role(p.wall[w]);
                if let WallRole::Outflow(k) = role {
                    let pw = walls.settings.outflows[k].pressure;
                    let v = if sums.w > 0.0 { sums.velocity / sums.w } else { velocity[w] };
                    return (pw, method.eos.density(pw), v);
                }
                if let WallRole::Inflow(k) = role {
                    // The fluid's pressure continued linearly across the open face from the
                    // particle's mirror image in the fluid: with Adami's average instead, the
                    // inflow's pressure fell short of the gradient that drives the flow, and the
                    // density diffusion drained the fluid beside it (a channel carried 5 % less
                    // than it took in).
                    let buffer = &walls.settings.inflows[k].buffer;
                    let x = position[w];
                    let mirror = x - 2.0 * buffer.past_exit(x) * buffer.direction();
                    let pw = match crate::buffers::pressure_fit(grid, p, pressure, &method.kernel, mirror, plane) {
                        Some((at_mirror, gradient)) => at_mirror + gradient.dot(x - mirror),
                        None => 0.0,
                    };
                    return (pw, method.eos.density(pw), velocity[w]);
                }
                if sums.w > 0.0 {
                    // The wall's own acceleration enters as a body force of the opposite sign.
                    let a_w = walls.acceleration(grid, role, position[w]);
                    let pw = ((sums.pressure + (method.external - a_w).dot(sums.density_moment)) / sums.w).max(0.0);
                    (pw, method.eos.density(pw), 2.0 * velocity[w] - sums.velocity / sums.w)
                } else {
                    (0.0, method.rho0, velocity[w])
                }
            },
        )
        .collect()
}

/// [`wall_sums`] compiled for AVX2; the processor must have it.
#[cfg_attr(target_arch = "x86_64", target_feature(enable = "avx2"))]
#[allow(clippy::too_many_arguments)]
unsafe fn wall_sums_avx2<const PLANE: bool>(
    constants: &PassConstants,
    p: &FluidParticles,
    density: &[f64],
    pressure: &[f64],
    grid: &FluidGrid,
    w: usize,
    list: &[u32],
    batch: &mut Batch,
) -> WallSums {
    wall_sums::<PLANE>(constants, &p.position, &p.velocity, density, pressure, |x, y| grid.separation(x, y), w, list, batch)
}

/// Each fluid particle's rates, gathered over its neighbours:
/// - continuity with density diffusion: dρ_a/dt = Σ m_b v_ab·∇W + δ h c₀ Σ ψ_ab·∇W V_b;
/// - momentum: dv_a/dt = −Σ m_b (P_a/ρ_a² + P_b/ρ_b² + R_ab + Π_ab) ∇W + laminar term + g + f;
/// - XSPH: −ε Σ (m_b/ρ̄_ab) v_ab W;
/// - the wall repulsion within Δp/2 of a wall particle, k (r₀ − r) along r_ab.
pub(crate) fn evaluate(method: &Method, grid: &FluidGrid, p: &FluidParticles, inputs: &PairInputs, out: &mut Rates) {
    // One copy of the pass per combination of the method's switches, so none is tested per pair.
    let plane = method.dimension == Dimension::Two;
    let laminar = matches!(method.viscosity, Viscosity::Laminar);
    let diffuse = method.diffusion_scale != 0.0;
    let (tensile, xsph) = (method.tensile, method.xsph != 0.0);
    macro_rules! dispatch {
        ($($p:literal $l:literal $d:literal $t:literal $x:literal),*) => {
            match (plane, laminar, diffuse, tensile, xsph) {
                $(($p, $l, $d, $t, $x) => evaluate_with::<$p, $l, $d, $t, $x>(method, grid, p, inputs, out),)*
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

/// The pass of [`evaluate`] for one combination of switches: the plane (2D), laminar (else
/// artificial) viscosity, density diffusion, the tensile correction, XSPH.
fn evaluate_with<const PLANE: bool, const LAMINAR: bool, const DIFFUSE: bool, const TENSILE: bool, const XSPH: bool>(
    method: &Method,
    grid: &FluidGrid,
    p: &FluidParticles,
    inputs: &PairInputs,
    out: &mut Rates,
) {
    out.resize(p.len());
    let alpha = method.artificial_alpha();
    let fourtakas = matches!(method.diffusion, DensityDiffusion::Fourtakas { .. });
    let constants = PassConstants::new(method, alpha, fourtakas);
    let hood = neighbourhood(p, inputs);
    let kind = &p.kind;
    let wide = method.wide_lanes;
    out.acceleration.par_iter_mut().zip(out.density_rate.par_iter_mut()).zip(out.xsph.par_iter_mut()).enumerate().for_each_init(
        || Box::new(Batch::new()),
        |batch, (a, ((acc_out, drho_out), xsph_out))| {
            if kind[a] != ParticleKind::Fluid {
                *acc_out = DVec3::ZERO;
                *drho_out = 0.0;
                *xsph_out = DVec3::ZERO;
                return;
            }
            let list = grid.neighbours(a);
            let r = if wide {
                // SAFETY: `wide_lanes` is set only where the processor has AVX2 (`Method::new`).
                unsafe { particle_rates_avx2::<PLANE, LAMINAR, DIFFUSE, TENSILE, XSPH>(&constants, &hood, grid, a, list, batch) }
            } else {
                particle_rates::<PLANE, LAMINAR, DIFFUSE, TENSILE, XSPH>(&constants, &hood, |x, y| grid.separation(x, y), a, list, batch)
            };
            *acc_out = r.acceleration + method.external;
            // Beside coupled solids the fluid's own density diffuses, into ε ρ's rate.
            let diffusion = match (inputs.diffusion_off.get(a) == Some(&true), inputs.fraction.get(a)) {
                (true, _) => 0.0,
                (false, None) => method.diffusion_scale * r.diffusion,
                (false, Some(&e)) => e * method.diffusion_scale * r.diffusion,
            };
            *drho_out = r.continuity + diffusion;
            *xsph_out = method.xsph * r.xsph;
        },
    );
}

/// The fluid's force and torque (about each body's centre) on each floating body, over the body
/// particles `members` (indices in the sorted arrays, ascending): each particle's force gathered
/// in parallel ([`wall_reaction`]), then added body by body in the order of `members`, so the
/// sums do not depend on the number of threads. `first_body` is the first body's wall number.
pub(crate) fn body_loads(
    method: &Method,
    grid: &FluidGrid,
    p: &FluidParticles,
    inputs: &PairInputs,
    bodies: &[BodyState],
    first_body: u16,
    members: &[u32],
) -> Vec<(DVec3, DVec3)> {
    let mut loads = vec![(DVec3::ZERO, DVec3::ZERO); bodies.len()];
    if members.is_empty() {
        return loads;
    }
    let alpha = method.artificial_alpha();
    let constants = PassConstants::new(method, alpha, false);
    let hood = neighbourhood(p, inputs);
    let separation = |x, y| grid.separation(x, y);
    let forces: Vec<DVec3> = members
        .par_iter()
        .map(|&w| {
            let (w, list) = (w as usize, grid.neighbours(w as usize));
            match (matches!(method.viscosity, Viscosity::Laminar), method.tensile) {
                (false, false) => wall_reaction::<false, false>(&constants, &hood, separation, w, list),
                (false, true) => wall_reaction::<false, true>(&constants, &hood, separation, w, list),
                (true, false) => wall_reaction::<true, false>(&constants, &hood, separation, w, list),
                (true, true) => wall_reaction::<true, true>(&constants, &hood, separation, w, list),
            }
        })
        .collect();
    for (&w, f) in members.iter().zip(forces) {
        let k = (p.wall[w as usize] - first_body) as usize;
        let arm = grid.separation(p.position[w as usize], bodies[k].centre);
        loads[k].0 += f;
        loads[k].1 += arm.cross(f);
    }
    loads
}

/// What the passes read of every particle.
fn neighbourhood<'a>(p: &'a FluidParticles, inputs: &'a PairInputs) -> Neighbourhood<'a> {
    Neighbourhood {
        position: &p.position,
        velocity: &p.velocity,
        viscous_velocity: &inputs.viscous_velocity,
        density: &p.density,
        diffused: if inputs.intrinsic.is_empty() { &p.density } else { &inputs.intrinsic },
        mass: &p.mass,
        pressure_term: &inputs.pressure_term,
        volume: &inputs.volume,
        tensile: &inputs.tensile,
        fluid: &inputs.fluid,
    }
}

/// Whether the pass may use 256-bit lanes (the same results as without: see [`crate::pass`]).
fn wide_lanes_available() -> bool {
    #[cfg(target_arch = "x86_64")]
    {
        std::is_x86_feature_detected!("avx2")
    }
    #[cfg(not(target_arch = "x86_64"))]
    {
        false
    }
}

/// [`particle_rates`] compiled for AVX2; the processor must have it.
#[cfg_attr(target_arch = "x86_64", target_feature(enable = "avx2"))]
unsafe fn particle_rates_avx2<const PLANE: bool, const LAMINAR: bool, const DIFFUSE: bool, const TENSILE: bool, const XSPH: bool>(
    constants: &PassConstants,
    hood: &Neighbourhood,
    grid: &FluidGrid,
    a: usize,
    list: &[u32],
    batch: &mut Batch,
) -> ParticleRates {
    particle_rates::<PLANE, LAMINAR, DIFFUSE, TENSILE, XSPH>(constants, hood, |x, y| grid.separation(x, y), a, list, batch)
}
