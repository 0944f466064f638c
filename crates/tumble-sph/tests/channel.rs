//! Start-up of plane Poiseuille and Couette flow (Morris, Fox & Zhu 1997) against their series
//! solutions, at three resolutions: the error and its order.

mod common;

use std::f64::consts::PI;

use tumble_geom::{DVec3, PeriodicBox};
use tumble_sph::*;

const L: f64 = 1e-3;
const NU: f64 = 1e-6;
const RHO: f64 = 1000.0;
/// Morris et al.'s driving acceleration, giving a centre-line speed of F L²/(8ν) = 2.5e-5 m/s.
const F: f64 = 2e-4;
const V_MAX: f64 = F * L * L / (8.0 * NU);

/// Poiseuille flow between plates at z = 0 and z = L started from rest (Morris et al. 1997, eq. 21).
fn poiseuille(z: f64, t: f64) -> f64 {
    let steady = F / (2.0 * NU) * z * (L - z);
    let transient: f64 = (0..200)
        .map(|n| {
            let m = (2 * n + 1) as f64;
            4.0 * F * L * L / (NU * PI.powi(3) * m.powi(3)) * (m * PI * z / L).sin() * (-(m * m) * PI * PI * NU * t / (L * L)).exp()
        })
        .sum();
    steady - transient
}

/// Couette flow: the upper plate set moving at `v0` at t = 0 (Morris et al. 1997, eq. 22).
fn couette(z: f64, t: f64, v0: f64) -> f64 {
    let transient: f64 = (1..400)
        .map(|n| {
            let n = n as f64;
            2.0 * v0 / (n * PI) * (-1f64).powi(n as i32) * (n * PI * z / L).sin() * (-NU * n * n * PI * PI * t / (L * L)).exp()
        })
        .sum();
    v0 * z / L + transient
}

/// Water creeping at V_MAX in 2D at spacing `dp`: laminar viscosity, no density diffusion, no
/// gravity, c₀ ten times the flow's largest speed; an empty domain and no moving walls.
fn slow_water(dp: f64) -> FluidSettings {
    FluidSettings {
        dimension: Dimension::Two,
        spacing: dp,
        h: 1.5 * dp,
        rho0: RHO,
        mu: RHO * NU,
        sound_speed: 10.0 * V_MAX,
        viscosity: Viscosity::Laminar,
        density_diffusion: DensityDiffusion::None,
        tensile_correction: false,
        xsph: 0.0,
        gravity: DVec3::ZERO,
        body_force: DVec3::ZERO,
        domain: PeriodicBox { min: DVec3::ZERO, max: DVec3::ZERO, periodic: [false; 3] },
        moving_walls: Vec::new(),
        floating: Vec::new(),
        inflows: Vec::new(),
        outflows: Vec::new(),
    }
}

/// A periodic 2D channel of height L with `per_height` particles across it; the upper plate moves
/// at `lid` and the fluid is driven by `drive`.
fn channel(per_height: usize, drive: f64, lid: f64) -> FluidPhase {
    let dp = L / per_height as f64;
    let width = 8.0 * dp;
    let layers = 3.0 * dp;
    let settings = FluidSettings {
        body_force: DVec3::new(drive, 0.0, 0.0),
        domain: PeriodicBox { min: DVec3::new(0.0, 0.0, -layers), max: DVec3::new(width, 0.0, L + layers), periodic: [true, false, false] },
        ..slow_water(dp)
    };
    let mut particles = FluidParticles::default();
    add_fluid_block(&mut particles, &settings, Aabb::new(DVec3::ZERO, DVec3::new(width, 0.0, L)), DVec3::ZERO);
    add_wall_slab(&mut particles, &settings, DVec3::new(0.0, 0.0, -layers), DVec3::new(width, 0.0, 0.0), DVec3::ZERO);
    add_wall_slab(&mut particles, &settings, DVec3::new(0.0, 0.0, L), DVec3::new(width, 0.0, L + layers), DVec3::new(lid, 0.0, 0.0));
    FluidPhase::new(settings, particles).expect("valid channel")
}

/// The rms error of the fluid's x-velocity against `exact(z, t)` at each of `times`, relative to `scale`.
fn errors(mut phase: FluidPhase, times: &[f64], scale: f64, exact: impl Fn(f64, f64) -> f64) -> Vec<f64> {
    let dt = TimeStepLimits::planned(phase.settings()).dt();
    times
        .iter()
        .map(|&t| {
            common::run_to(&mut phase, t, dt);
            let p = phase.particles();
            let (mut sum, mut count) = (0.0, 0);
            for i in 0..p.len() {
                if p.kind[i] == ParticleKind::Fluid {
                    sum += (p.velocity[i].x - exact(p.position[i].z, t)).powi(2);
                    count += 1;
                }
            }
            (sum / count as f64).sqrt() / scale
        })
        .collect()
}

/// Prints the table and checks it: every refinement lowers every error, the finest stays below
/// `finest_bound`, and the order over the three resolutions exceeds one at every time.
fn check(name: &str, resolutions: &[usize; 3], times: &[f64], table: &[Vec<f64>], finest_bound: f64) {
    for (k, &t) in times.iter().enumerate() {
        let row: Vec<String> = table.iter().map(|e| format!("{:.3e}", e[k])).collect();
        let order = (table[0][k] / table[2][k]).ln() / (resolutions[2] as f64 / resolutions[0] as f64).ln();
        println!("{name} t {t:.4} s: rms error / v_max at {resolutions:?} particles across: {} (order {order:.2})", row.join(", "));
        assert!(table[0][k] > table[1][k] && table[1][k] > table[2][k], "{name} t {t}: errors do not fall with the spacing");
        assert!(table[2][k] < finest_bound, "{name} t {t}: error {:.3e} of v_max at the finest spacing", table[2][k]);
        assert!(order > 1.0, "{name} t {t}: order {order:.2}");
    }
}

#[test]
fn poiseuille_start_up_converges_to_the_series_solution() {
    let times = [0.0225, 0.045, 0.1125, 0.225];
    let resolutions = [10, 20, 40];
    let table: Vec<Vec<f64>> = resolutions.iter().map(|&n| errors(channel(n, F, 0.0), &times, V_MAX, poiseuille)).collect();
    check("Poiseuille", &resolutions, &times, &table, 0.003);
}

#[test]
fn couette_start_up_converges_to_the_series_solution() {
    let times = [0.0225, 0.045, 0.1125, 0.225];
    let resolutions = [10, 20, 40];
    let table: Vec<Vec<f64>> = resolutions.iter().map(|&n| errors(channel(n, 0.0, V_MAX), &times, V_MAX, |z, t| couette(z, t, V_MAX))).collect();
    check("Couette", &resolutions, &times, &table, 0.002);
}

/// Circular Couette flow: 2D water between a fixed inner cylinder of radius `R1` and an outer one
/// of radius `R2` turning at `OMEGA` (a moving wall), both with their wall particles in rings,
/// the fluid filled in rings between them; `per_gap` particles across the gap.
mod annulus {
    use super::*;
    use tumble_geom::{Cylinder, Motion, Timing};

    pub const R1: f64 = 1e-3;
    pub const R2: f64 = 2e-3;
    /// The outer wall's speed is V_MAX.
    pub const OMEGA: f64 = V_MAX / R2;

    /// The steady azimuthal speed u(r) = A r + B / r with u(R1) = 0 and u(R2) = Ω R2.
    pub fn steady(r: f64) -> f64 {
        let a = OMEGA * R2 * R2 / (R2 * R2 - R1 * R1);
        a * r - a * R1 * R1 / r
    }

    pub fn phase(per_gap: usize) -> FluidPhase {
        let dp = (R2 - R1) / per_gap as f64;
        let reach = R2 + 4.0 * dp;
        let settings = FluidSettings {
            domain: PeriodicBox { min: DVec3::new(-reach, 0.0, -reach), max: DVec3::new(reach, 0.0, reach), periodic: [false; 3] },
            moving_walls: vec![MovingWall { motion: Motion::Rotate { point: DVec3::ZERO, axis: DVec3::Y, omega: OMEGA }, timing: Timing::ALWAYS }],
            floating: Vec::new(),
            inflows: Vec::new(),
            outflows: Vec::new(),
            ..slow_water(dp)
        };
        let mut particles = FluidParticles::default();
        // The fluid in rings Δp apart, each particle carrying its share of the ring's area.
        for x in cylinder_shell(&Cylinder::new(DVec3::ZERO, DVec3::Y, R1, 1.0, true), per_gap, dp, Dimension::Two) {
            let r = x.length();
            let n = (std::f64::consts::TAU * r / dp).round();
            particles.push(ParticleKind::Fluid, x, DVec3::ZERO, RHO, RHO * dp * std::f64::consts::TAU * r / n);
        }
        let layers = wall_layers(&settings);
        let inner = Cylinder::new(DVec3::ZERO, DVec3::Y, R1, 1.0, false);
        for x in cylinder_shell(&inner, layers, dp, Dimension::Two) {
            particles.push(ParticleKind::Wall, x, DVec3::ZERO, RHO, RHO * dp * dp);
        }
        let outer_from = particles.len();
        add_wall_cylinder(&mut particles, &settings, &Cylinder::new(DVec3::ZERO, DVec3::Y, R2, 1.0, true), DVec3::ZERO);
        particles.assign_moving_wall(outer_from, 1);
        FluidPhase::new(settings, particles).expect("valid annulus")
    }

    /// The fluid's azimuthal velocity against the steady profile: rms over the fluid, relative to
    /// the wall's speed.
    pub fn error(phase: &FluidPhase) -> f64 {
        let p = phase.particles();
        let (mut sum, mut count) = (0.0, 0);
        for i in 0..p.len() {
            if p.kind[i] == ParticleKind::Fluid {
                let x = p.position[i];
                let r = x.length();
                // Rotation about +y carries (x, 0, z) towards (z, 0, −x).
                let u = p.velocity[i].dot(DVec3::new(x.z, 0.0, -x.x) / r);
                sum += (u - steady(r)).powi(2);
                count += 1;
            }
        }
        (sum / count as f64).sqrt() / V_MAX
    }
}

/// A moving wall: the outer cylinder of an annulus turns, and the water between it and the fixed
/// inner cylinder settles into circular Couette flow u = A r + B/r; the error falls with the
/// spacing, and the turning wall's particles stay on their circles at the angle Ω t.
#[test]
fn circular_couette_flow_from_a_turning_wall() {
    let t_end = 1.0; // seven gap diffusion times G²/ν: the start-up has died away
    let mut errors = Vec::new();
    for per_gap in [8, 16] {
        let mut phase = annulus::phase(per_gap);
        let start: Vec<(u32, DVec3)> = (0..phase.particles().len())
            .filter(|&i| phase.particles().wall[i] == 1)
            .map(|i| (phase.particles().id[i], phase.particles().position[i]))
            .collect();
        let dt = TimeStepLimits::planned(phase.settings()).dt();
        common::run_to(&mut phase, t_end, dt);
        let p = phase.particles();
        let angle = annulus::OMEGA * t_end;
        for (id, x0) in start {
            let i = p.id.iter().position(|&j| j == id).unwrap();
            let expected = DVec3::new(x0.x * angle.cos() + x0.z * angle.sin(), 0.0, -x0.x * angle.sin() + x0.z * angle.cos());
            assert!((p.position[i] - expected).length() < 1e-10 * annulus::R2, "wall particle {id} at {} instead of {expected}", p.position[i]);
        }
        let e = annulus::error(&phase);
        println!("circular Couette, {per_gap} particles across the gap: rms error {e:.3e} of the wall speed");
        errors.push(e);
    }
    assert!(errors[1] < errors[0], "the error does not fall with the spacing: {errors:?}");
    assert!(errors[1] < 0.02, "rms error {:.3e} of the wall speed at 16 across", errors[1]);
}
