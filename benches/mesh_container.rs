//! The packed bed (scenes/bench/packed_bed.toml) in its analytic box and in the same box given
//! as a closed mesh of about 100, 10,000 and 1,000,000 triangles, on 1 thread: what a mesh
//! container costs against the analytic one. Criterion's "elem/s" is particle-steps/s.
//!
//! `TUMBLE_BENCH_LATTICE=20` shrinks the bed to 20 × 20 × 16 for a quick run.

use criterion::{Criterion, Throughput, criterion_group, criterion_main};
use glam::DVec3;
use std::time::Duration;
use tumble::Simulation;
use tumble_geom::box_triangles_subdivided;

/// The bed's scene text with the container written as `container`.
fn bed(container: &str) -> tumble::CompiledScene {
    let path = format!("{}/scenes/bench/packed_bed.toml", env!("CARGO_MANIFEST_DIR"));
    let mut text = std::fs::read_to_string(path).unwrap();
    let analytic = "box = { min = [0.0, 0.0, 0.0], max = [0.5, 0.5, 0.5] }";
    assert!(text.contains(analytic), "packed_bed.toml's container changed");
    text = text.replace(analytic, container);
    if let Ok(n) = std::env::var("TUMBLE_BENCH_LATTICE") {
        let n: f64 = n.parse().expect("TUMBLE_BENCH_LATTICE is a lattice size");
        text = text.replace("max = [0.5, 0.5, 0.4], spacing", &format!("max = [{}, {}, {}], spacing", 0.01 * n, 0.01 * n, 0.008 * n));
    }
    tumble::compile(&tumble::parse_scene(&text).unwrap()).unwrap_or_else(|e| panic!("{e}"))
}

/// The box as an OBJ file of 12 n² triangles facing inward; returns its path.
fn box_mesh(n: usize) -> (std::path::PathBuf, usize) {
    let (v, mut t) = box_triangles_subdivided(DVec3::ZERO, DVec3::splat(0.5), n);
    t.iter_mut().for_each(|t| t.swap(1, 2));
    let mut text = String::with_capacity(40 * (v.len() + t.len()));
    for v in &v {
        text += &format!("v {} {} {}\n", v.x, v.y, v.z);
    }
    for t in &t {
        text += &format!("f {} {} {}\n", t[0] + 1, t[1] + 1, t[2] + 1);
    }
    let path = std::env::temp_dir().join(format!("tumble-bench-box-{n}-{}.obj", std::process::id()));
    std::fs::write(&path, text).unwrap();
    (path, t.len())
}

fn mesh_container(c: &mut Criterion) {
    let steps = 10;
    let mut group = c.benchmark_group("mesh_container");
    group.sample_size(10).measurement_time(Duration::from_secs(20)).warm_up_time(Duration::from_secs(3));
    let mut containers = vec![("analytic_box".to_string(), "box = { min = [0.0, 0.0, 0.0], max = [0.5, 0.5, 0.5] }".to_string(), None)];
    for n in [3, 29, 289] {
        let (path, triangles) = box_mesh(n);
        containers.push((format!("mesh_{triangles}_triangles"), format!("mesh = {{ file = \"{}\", closed = true }}", path.display()), Some(path)));
    }
    for (name, container, file) in containers {
        let mut sim = Simulation::new(bed(&container), 1);
        sim.advance(200); // let gravity settle the lattice's first compression wave
        group.throughput(Throughput::Elements(sim.particles() as u64 * steps));
        group.bench_function(format!("{}_spheres_{name}", sim.particles()), |b| b.iter(|| sim.advance(steps)));
        if let Some(f) = file {
            let _ = std::fs::remove_file(f);
        }
    }
    group.finish();
}

criterion_group!(benches, mesh_container);
criterion_main!(benches);
