//! Fluid particle-steps per second of a dam break (2D or 3D) on the CPU:
//! `cargo run --release -p tumble-sph --example dam_break_speed -- [2|3] [particles over the height] [steps] [threads]`.
//! Each step evaluates the rates twice (symplectic scheme); walls are not counted as particles.

use std::time::Instant;

use tumble_sph::cases::ColumnInTank;
use tumble_sph::*;

fn main() {
    let args: Vec<String> = std::env::args().skip(1).collect();
    let arg = |k: usize, default: usize| args.get(k).map(|v| v.parse().expect("a whole number")).unwrap_or(default);
    let three_d = arg(0, 2) == 3;
    let per_height = arg(1, 100);
    let steps = arg(2, 200);
    let threads = arg(3, 1);
    let pool = rayon::ThreadPoolBuilder::new().num_threads(threads).build().unwrap();
    // The column of Martin & Moyce: a wide, 2a high, in a tank 4a long (and a deep in 3D).
    let a = 0.1;
    let mut case = ColumnInTank::plane(4.0 * a, a, 2.0 * a, per_height);
    if three_d {
        case.dimension = Dimension::Three;
        case.depth = a;
    }
    let mut phase = case.build();
    let fluid = phase.particles().fluid_count();
    let walls = phase.particles().len() - fluid;
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
            case.dimension.count(),
            fluid as f64 * steps as f64 / seconds
        );
    });
}
