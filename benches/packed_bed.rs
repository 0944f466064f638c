//! The packed-bed benchmark (scenes/bench/packed_bed.toml): 100,000 spheres at rest
//! under gravity in a box, linear contact, viscous-Coulomb friction, at 1 and 2 threads;
//! and the same bed with tangential springs (scenes/bench/packed_bed_history.toml).
//! Criterion's throughput is in elements = particle-steps, so "elem/s" is the Cundall number.
//!
//! `TUMBLE_BENCH_LATTICE=20` shrinks the bed to 20 × 20 × 16 for a quick run.

use criterion::{Criterion, Throughput, criterion_group, criterion_main};
use std::time::Duration;
use tumble::Simulation;

fn bed(file: &str) -> tumble::CompiledScene {
    let path = format!("{}/scenes/bench/{file}", env!("CARGO_MANIFEST_DIR"));
    let mut scene = tumble::read_scene(path.as_ref()).unwrap();
    if let Ok(n) = std::env::var("TUMBLE_BENCH_LATTICE") {
        let n: f64 = n.parse().expect("TUMBLE_BENCH_LATTICE is a lattice size");
        let lattice = scene.particles[0].lattice.as_mut().unwrap();
        lattice.max = [0.01 * n, 0.01 * n, 0.008 * n].into();
    }
    tumble::compile(&scene).unwrap()
}

fn packed_bed(c: &mut Criterion) {
    for (name, file) in [("packed_bed", "packed_bed.toml"), ("packed_bed_history", "packed_bed_history.toml")] {
        bench_bed(c, name, file);
    }
}

fn bench_bed(c: &mut Criterion, name: &str, file: &str) {
    let steps = 10;
    let mut group = c.benchmark_group(name);
    group.sample_size(10).measurement_time(Duration::from_secs(20)).warm_up_time(Duration::from_secs(3));
    for threads in [1, 2] {
        let mut sim = Simulation::new(bed(file), threads);
        sim.advance(200); // let gravity settle the lattice's first compression wave
        group.throughput(Throughput::Elements(sim.particles() as u64 * steps));
        group.bench_function(format!("{}_spheres_{threads}_threads", sim.particles()), |b| b.iter(|| sim.advance(steps)));
    }
    group.finish();
}

criterion_group!(benches, packed_bed);
criterion_main!(benches);
