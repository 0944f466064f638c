//! Polyhedron contact: tumble's separating-axis fast path against parry3d's `contact`
//! (GJK/EPA for convex polyhedra; parry's own cuboid–cuboid routine as a second reference).
//!
//! Each iteration runs one contact query on each of 256 fixed random configurations, half of
//! them overlapping and half within the bounding spheres but apart, so the throughput in
//! elements/s is contact queries per second. `cargo bench -p tumble-geom --bench polyhedron_contact`.

use criterion::{Criterion, Throughput, criterion_group, criterion_main};
use glam::DQuat;
use parry3d_f64::query;
use parry3d_f64::shape::{ConvexPolyhedron, Cuboid};
use std::hint::black_box;
use std::time::Duration;
use tumble_geom::{DVec3, Polyhedron, Pose, SeparationCache, polyhedron_polyhedron, polyhedron_polyhedron_cached};
// The named solids here are all below SAT_MAX_EDGE_PAIRS: polyhedron_polyhedron is the fast path.

const N: usize = 256;

/// Poses of A around B at the origin: every other one overlapping, the rest apart.
fn configurations(a: &Polyhedron, b: &Polyhedron) -> Vec<(Pose, Pose)> {
    let mut s = 0x2545f4914f6cdd1du64;
    let mut rnd = move || {
        s ^= s << 13;
        s ^= s >> 7;
        s ^= s << 17;
        (s >> 11) as f64 / (1u64 << 53) as f64
    };
    let mut out = Vec::with_capacity(N);
    while out.len() < N {
        let qa = DQuat::from_xyzw(rnd() - 0.5, rnd() - 0.5, rnd() - 0.5, rnd() - 0.5).normalize();
        let qb = DQuat::from_xyzw(rnd() - 0.5, rnd() - 0.5, rnd() - 0.5, rnd() - 0.5).normalize();
        let dir = DVec3::new(rnd() - 0.5, rnd() - 0.5, rnd() - 0.5).normalize();
        let d = rnd() * (a.bounding_radius() + b.bounding_radius());
        let (pa, pb) = (Pose::new(dir * d, qa), Pose::new(DVec3::ZERO, qb));
        let hit = polyhedron_polyhedron(a, &pa, b, &pb).is_some();
        if hit == (out.len() % 2 == 0) {
            out.push((pa, pb));
        }
    }
    out
}

fn bench_pair(c: &mut Criterion, name: &str, a: &Polyhedron, b: &Polyhedron, cuboids: Option<(Cuboid, Cuboid)>) {
    let conf = configurations(a, b);
    let parry_poses: Vec<_> = conf.iter().map(|(pa, pb)| (pa.to_parry(), pb.to_parry())).collect();
    let (ha, hb): (ConvexPolyhedron, ConvexPolyhedron) = (a.to_parry(), b.to_parry());
    let mut group = c.benchmark_group(format!("polyhedron_contact/{name}"));
    group.sample_size(20).measurement_time(Duration::from_secs(3)).warm_up_time(Duration::from_secs(1));
    group.throughput(Throughput::Elements(N as u64));
    group.bench_function("tumble_sat", |bch| {
        bch.iter(|| conf.iter().filter(|(pa, pb)| black_box(polyhedron_polyhedron(a, pa, b, pb)).is_some()).count())
    });
    let mut caches = vec![SeparationCache::default(); N];
    group.bench_function("tumble_sat_cached", |bch| {
        bch.iter(|| {
            let mut hits = 0;
            for ((pa, pb), cache) in conf.iter().zip(caches.iter_mut()) {
                hits += black_box(polyhedron_polyhedron_cached(a, pa, b, pb, cache)).is_some() as usize;
            }
            hits
        })
    });
    group.bench_function("parry_convex_polyhedron", |bch| {
        bch.iter(|| {
            parry_poses.iter().filter(|(pa, pb)| black_box(query::contact(pa, &ha, pb, &hb, 0.0).unwrap()).is_some_and(|c| c.dist < 0.0)).count()
        })
    });
    if let Some((ca, cb)) = cuboids {
        group.bench_function("parry_cuboid", |bch| {
            bch.iter(|| {
                parry_poses.iter().filter(|(pa, pb)| black_box(query::contact(pa, &ca, pb, &cb, 0.0).unwrap()).is_some_and(|c| c.dist < 0.0)).count()
            })
        });
    }
    group.finish();
}

fn polyhedron_contact(c: &mut Criterion) {
    let cube = Polyhedron::cube(1.0);
    let half = parry3d_f64::math::Vector::splat(0.5);
    bench_pair(c, "cube_cube", &cube, &cube, Some((Cuboid::new(half), Cuboid::new(half))));
    let dodeca = Polyhedron::dodecahedron(0.5);
    bench_pair(c, "dodecahedron_dodecahedron", &dodeca, &dodeca, None);
    let ico = Polyhedron::icosahedron(0.6);
    bench_pair(c, "icosahedron_cube", &ico, &cube, None);
}

criterion_group!(benches, polyhedron_contact);
criterion_main!(benches);
