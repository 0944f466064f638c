//! Fluid particle-steps per second of a dam break (2D or 3D) on the CPU:
//! `cargo run --release -p tumble-sph --example dam_break_speed -- [2|3] [particles over the height] [steps] [threads]`.
//! Each step evaluates the rates twice (symplectic scheme); walls are not counted as particles.

use std::time::Instant;

use tumble_geom::{DVec3, PeriodicBox};
use tumble_sph::*;

fn main() {
    let args: Vec<String> = std::env::args().skip(1).collect();
    let arg = |k: usize, default: usize| args.get(k).map(|v| v.parse().expect("a whole number")).unwrap_or(default);
    let dimension = if arg(0, 2) == 3 { Dimension::Three } else { Dimension::Two };
    let per_height = arg(1, 100);
    let steps = arg(2, 200);
    let threads = arg(3, 1);
    let pool = rayon::ThreadPoolBuilder::new().num_threads(threads).build().unwrap();
    // The column of Martin & Moyce: a wide, 2a high, in a tank 4a long (and a deep in 3D).
    let a = 0.1;
    let dp = 2.0 * a / per_height as f64;
    let g = 9.81;
    let layers = 3.0 * dp;
    let depth = if dimension == Dimension::Three { a } else { 0.0 };
    let settings = FluidSettings {
        dimension,
        spacing: dp,
        h: 1.5 * dp,
        rho0: 1000.0,
        mu: 1e-3,
        sound_speed: 10.0 * (2.0 * g * 2.0 * a).sqrt(),
        viscosity: Viscosity::Artificial { alpha: 0.02 },
        density_diffusion: DensityDiffusion::Fourtakas { delta: 0.1 },
        tensile_correction: false,
        xsph: 0.0,
        gravity: DVec3::new(0.0, 0.0, -g),
        body_force: DVec3::ZERO,
        domain: PeriodicBox {
            min: DVec3::new(-layers, if depth > 0.0 { -layers } else { 0.0 }, -layers),
            max: DVec3::new(4.0 * a + layers, if depth > 0.0 { depth + layers } else { 0.0 }, 4.0 * a),
            periodic: [false; 3],
        },
    };
    let mut particles = FluidParticles::default();
    let fluid = add_fluid_block(&mut particles, &settings, Aabb::new(DVec3::ZERO, DVec3::new(a, depth, 2.0 * a)), DVec3::ZERO);
    let y_closed = depth > 0.0;
    let walls = add_wall_box(
        &mut particles,
        &settings,
        Aabb::new(DVec3::ZERO, DVec3::new(4.0 * a, depth, 4.0 * a)),
        [[true, true], [y_closed, y_closed], [true, false]],
        DVec3::ZERO,
    );
    let mut phase = FluidPhase::new(settings, particles).expect("valid dam break");
    let dt = TimeStepLimits::planned(phase.settings()).dt();
    pool.install(|| {
        phase.step(dt).unwrap();
        let start = Instant::now();
        for _ in 0..steps {
            phase.step(dt).unwrap();
        }
        let seconds = start.elapsed().as_secs_f64();
        println!(
            "{}D dam break: {fluid} fluid + {walls} wall particles, {steps} steps of {dt:.3e} s on {threads} thread(s): {:.3e} fluid particle-steps/s",
            dimension.count(),
            fluid as f64 * steps as f64 / seconds
        );
    });
}
