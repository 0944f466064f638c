//! Polyhedra throughput: a settling bed of cubes against the same bed of spheres of equal
//! volume (scenes/bench/packed_bed.toml's box and contact laws, lattice spacing 1.25 d, so the
//! bodies start apart and settle into contact). Throughput in particle-steps per second.
//!
//! `TUMBLE_BENCH_LATTICE=16` sets the lattice (n × n × 0.8 n sites; default 20: 6,400 bodies).

use criterion::{Criterion, Throughput, criterion_group, criterion_main};
use std::time::Duration;
use tumble::Simulation;
use tumble_scene::schema::{CubeSection, NamedOrientation, OrientationSpec, ShapeSection};

/// The bed with cubes (`cubes = true`) or spheres of the same volume.
fn bed(cubes: bool) -> tumble::CompiledScene {
    let path = format!("{}/scenes/bench/packed_bed.toml", env!("CARGO_MANIFEST_DIR"));
    let mut scene = tumble::read_scene(path.as_ref()).unwrap();
    let n: f64 = std::env::var("TUMBLE_BENCH_LATTICE").map_or(20.0, |s| s.parse().expect("TUMBLE_BENCH_LATTICE is a lattice size"));
    let spacing = 0.0125;
    let group = &mut scene.particles[0];
    let lattice = group.lattice.as_mut().unwrap();
    lattice.spacing = spacing;
    lattice.max = [spacing * n, spacing * n, spacing * 0.8 * n].into();
    if cubes {
        // Turned cubes at 1.25 cm overlap their neighbours by up to 0.9 mm at the start (their
        // bounding spheres are 1.4 cm across): the bed's historical figures were measured from
        // this start, so the starting-overlap check is waived rather than the lattice changed.
        scene.run.start.allow_overlap = true;
        // Same volume as the 1 cm sphere: a = d (π/6)^(1/3).
        group.shape = ShapeSection::Cube(CubeSection { edge: 0.01 * (std::f64::consts::PI / 6.0).cbrt() });
        group.orientation = Some(OrientationSpec::Named(NamedOrientation::Random));
    }
    let top = spacing * n;
    scene.domain.max = [top, top, top].into();
    scene.walls[0].box_.as_mut().unwrap().max = [top, top, top].into();
    tumble::compile(&scene).unwrap()
}

fn settling_bed(c: &mut Criterion) {
    let steps = 10;
    let mut group = c.benchmark_group("settling_bed");
    group.sample_size(10).measurement_time(Duration::from_secs(15)).warm_up_time(Duration::from_secs(2));
    for (shape, cubes) in [("spheres", false), ("cubes", true)] {
        for threads in [1, 2] {
            let mut sim = Simulation::new(bed(cubes), threads);
            sim.advance(2000); // 0.07 s: the bed has started to settle into contact
            group.throughput(Throughput::Elements(sim.particles() as u64 * steps));
            group.bench_function(format!("{}_{shape}_{threads}_threads", sim.particles()), |b| b.iter(|| sim.advance(steps)));
            eprintln!("{shape}: {} contacts after 2000 steps", sim.observables().contacts);
        }
    }
    group.finish();
}

criterion_group!(benches, settling_bed);
criterion_main!(benches);
