//! Per-kernel device times of a scene on the GPU backend (timestamp queries).
//!
//! `cargo run --release -p tumble-gpu --example gpu_profile -- SCENE [STEPS]`

fn main() {
    let args: Vec<String> = std::env::args().skip(1).collect();
    let Some(path) = args.first() else {
        eprintln!("usage: gpu_profile SCENE [STEPS]");
        std::process::exit(2);
    };
    let steps: u64 = args.get(1).and_then(|s| s.parse().ok()).unwrap_or(50);
    let scene = tumble_scene::read_scene(path.as_ref()).unwrap_or_else(|e| panic!("{e}"));
    let compiled = tumble_scene::compile(&scene).unwrap_or_else(|e| panic!("{e}"));
    let n = compiled.particles.len();
    let mut sim = tumble_gpu::GpuSimulation::new(compiled).unwrap_or_else(|e| panic!("{e}"));
    println!("{n} particles on {}, grid {:?}", sim.adapter(), sim.grid().dims);
    sim.advance(5);
    let start = std::time::Instant::now();
    sim.advance(steps);
    let wall = start.elapsed().as_secs_f64();
    println!("{steps} steps in {wall:.3} s: {:.3e} particle-steps/s", (n as f64 * steps as f64) / wall);
    match sim.profile(steps) {
        Some(times) => {
            let total: f64 = times.iter().map(|t| t.seconds).sum();
            for t in times {
                println!(
                    "{:<12} {:>10.3} ms per step {:>6.1} %  ({} passes)",
                    t.kernel,
                    1e3 * t.seconds / steps as f64,
                    100.0 * t.seconds / total,
                    t.passes
                );
            }
        }
        None => println!("the adapter has no TIMESTAMP_QUERY: no per-kernel split"),
    }
}
