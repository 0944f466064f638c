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

/// A periodic 2D channel of height L with `per_height` particles across it; the upper plate moves
/// at `lid` and the fluid is driven by `drive`.
fn channel(per_height: usize, drive: f64, lid: f64) -> FluidPhase {
    let dp = L / per_height as f64;
    let width = 8.0 * dp;
    let layers = 3.0 * dp;
    let settings = FluidSettings {
        dimension: Dimension::Two,
        spacing: dp,
        h: 1.5 * dp,
        rho0: RHO,
        mu: RHO * NU,
        // Ten times the flow's largest speed.
        sound_speed: 10.0 * V_MAX,
        viscosity: Viscosity::Laminar,
        density_diffusion: DensityDiffusion::None,
        tensile_correction: false,
        xsph: 0.0,
        gravity: DVec3::ZERO,
        body_force: DVec3::new(drive, 0.0, 0.0),
        domain: PeriodicBox { min: DVec3::new(0.0, 0.0, -layers), max: DVec3::new(width, 0.0, L + layers), periodic: [true, false, false] },
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
