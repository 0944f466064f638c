//! The GPU step on the packed bed (scenes/bench/packed_bed.toml: spheres at rest under
//! gravity in a box, linear contact, viscous-Coulomb friction, rotation) at several sizes.
//! Criterion's throughput is in elements = particle-steps. After the timed runs, the
//! per-kernel split (timestamp queries) is printed when the adapter supports it.
//!
//! `TUMBLE_GPU_BENCH_SIZES=10000,100000,1000000` picks the sizes (default 10k and 100k:
//! a software adapter takes seconds per step at 1M). Without an adapter it prints one line.
//! `TUMBLE_GPU_BENCH_BODIES=cubes` (or `settling-spheres`) runs the settling bed of
//! benches/polyhedra_bed.rs instead: lattice spacing 1.25 d, randomly turned cubes of the
//! sphere's volume (or the spheres themselves), starting apart and settling into contact.

use criterion::{Criterion, Throughput, criterion_group, criterion_main};
use std::time::Duration;
use tumble_gpu::GpuSimulation;

/// The packed bed with about `n` spheres (a square lattice of 10 mm spheres, 80 % as tall as wide).
fn bed(n: usize) -> tumble_scene::CompiledScene {
    let path = concat!(env!("CARGO_MANIFEST_DIR"), "/../../scenes/bench/packed_bed.toml");
    let mut scene = tumble_scene::read_scene(path.as_ref()).unwrap();
    let bodies = std::env::var("TUMBLE_GPU_BENCH_BODIES").unwrap_or_default();
    let spacing = if bodies.is_empty() { 0.01 } else { 0.0125 };
    if bodies == "cubes" {
        use tumble_scene::schema::{CubeSection, NamedOrientation, OrientationSpec, ShapeSection};
        scene.particles[0].shape = ShapeSection::Cube(CubeSection { edge: 0.01 * (std::f64::consts::PI / 6.0).cbrt() });
        scene.particles[0].orientation = Some(OrientationSpec::Named(NamedOrientation::Random));
    }
    let side = ((n as f64) / 0.8).cbrt().round();
    let (w, h) = (spacing * side, spacing * (0.8 * side).round());
    let lattice = scene.particles[0].lattice.as_mut().unwrap();
    lattice.spacing = spacing;
    lattice.max = [w, w, h].into();
    scene.domain.max = [w, w, 1.25 * h].into();
    scene.walls[0].box_.as_mut().unwrap().max = [w, w, 1.25 * h].into();
    tumble_scene::compile(&scene).unwrap()
}

fn gpu_bed(c: &mut Criterion) {
    if let Err(e) = tumble_gpu::gpu() {
        println!("skipped gpu_bed: no GPU adapter ({e})");
        return;
    }
    let sizes: Vec<usize> = std::env::var("TUMBLE_GPU_BENCH_SIZES")
        .map(|s| s.split(',').map(|x| x.trim().parse().expect("a particle count")).collect())
        .unwrap_or_else(|_| vec![10_000, 100_000]);
    let steps = 5;
    let mut group = c.benchmark_group("gpu_bed");
    group.sample_size(10).measurement_time(Duration::from_secs(10)).warm_up_time(Duration::from_secs(1));
    let mut splits = Vec::new();
    for n in sizes {
        let mut sim = GpuSimulation::new(bed(n)).unwrap_or_else(|e| panic!("{e}"));
        sim.advance(20);
        let particles = sim.particles();
        group.throughput(Throughput::Elements(particles as u64 * steps));
        let label = std::env::var("TUMBLE_GPU_BENCH_BODIES").unwrap_or_else(|_| "spheres".into());
        group.bench_function(format!("{particles}_{label}"), |b| b.iter(|| sim.advance(steps)));
        if let Some(times) = sim.profile(steps) {
            splits.push((particles, sim.adapter().to_string(), times));
        }
    }
    group.finish();
    for (n, adapter, times) in splits {
        let total: f64 = times.iter().map(|t| t.seconds).sum();
        println!("per-kernel device time, {n} spheres on {adapter}, per step:");
        for t in times {
            println!("  {:<12} {:>10.3} ms {:>6.1} %", t.kernel, 1e3 * t.seconds / steps as f64, 100.0 * t.seconds / total);
        }
    }
}

criterion_group!(benches, gpu_bed);
criterion_main!(benches);
