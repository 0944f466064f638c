//! The f32 overlap-volume contact (shaders/volume_contact.wgsl) against tumble-geom's f64
//! `VolumeContact` on random configurations: the six test solids against each other, planes,
//! quads, drum shells, pipes and a lifter bar's hull.
//!
//! Compared: the volume (of size³), the push (of size²), the turns (of size³), the contact point
//! (of size, when the area is not tiny), the penetration depth and Σ weight × depth × gradient over
//! the corners and edge points inside (of size; continuous where a point enters or leaves, unlike
//! their count).
//! Excluded as the f32 band: grazing contacts (the push jumps by a face's area when a face
//! touches a parallel face, so f32 and f64 may differ on whether it has), at most 3 %.

use crate::polyhedra_contact::{Rng, f32_vec, solids};
use glam::DVec3;
use tumble_geom::{Cylinder, Plane, Polyhedron, Pose, Prism, Quad, SurfaceShape, VolumeContact, polyhedron_polyhedron_volume};
use tumble_gpu::shapes::{ContactAnswer, ContactQuery, evaluate};

/// (volume, push, turn_a, turn_b, point, depth, Σ depth × gradient).
type Volume = (f64, DVec3, DVec3, DVec3, DVec3, f64, DVec3);

fn of_geom(c: &VolumeContact) -> Volume {
    let corners = c.points.iter().map(|v| v.normal * (v.depth * v.weight)).sum();
    (c.volume, c.push, c.turn_a, c.turn_b, c.point, c.depth, corners)
}

fn of_gpu(a: &ContactAnswer) -> Option<Volume> {
    let v = |w: [f32; 4]| DVec3::new(w[0] as f64, w[1] as f64, w[2] as f64);
    a.hit().then(|| (a.extra[3] as f64, v(a.normal), v(a.extra), v(a.turn_b), a.point(), a.depth(), v(a.corners)))
}

/// The worst relative error of each compared quantity, and the cases outside them.
#[derive(Default)]
struct Worst {
    errors: [f64; 7],
    band: usize,
    contacts: usize,
    failures: Vec<String>,
}

const LIMITS: [f64; 7] = [1e-5, 1e-4, 1e-4, 1e-4, 1e-3, 1e-4, 1e-4];
const NAMES: [&str; 7] = ["volume", "push", "turn_a", "turn_b", "point", "depth", "corners"];

fn compare(name: &str, shapes: &[Polyhedron], queries: &[ContactQuery], sizes: &[f64], cpu: impl Fn(usize) -> Option<VolumeContact>) -> Worst {
    let t = std::time::Instant::now();
    let gpu = evaluate(shapes, queries).unwrap();
    let elapsed = t.elapsed();
    let mut w = Worst::default();
    for (i, g) in gpu.iter().enumerate() {
        let size = sizes[i];
        let c = cpu(i).map(|c| of_geom(&c));
        let g = of_gpu(g);
        w.contacts += c.is_some() as usize;
        let (c, g) = match (c, g) {
            (None, None) => continue,
            (Some(c), Some(g)) => (c, g),
            (c, g) => {
                let volume = c.map_or(0.0, |c| c.0).max(g.map_or(0.0, |g| g.0));
                if volume < 1e-6 * size.powi(3) {
                    w.band += 1;
                } else {
                    w.failures.push(format!("case {i}: found on one side only (V {volume:e})"));
                }
                continue;
            }
        };
        let area = c.1.length();
        let errors = [
            (c.0 - g.0).abs() / size.powi(3),
            (c.1 - g.1).length() / size.powi(2),
            (c.2 - g.2).length() / size.powi(3),
            (c.3 - g.3).length() / size.powi(3),
            if area > 1e-3 * size * size { (c.4 - g.4).length() / size } else { 0.0 },
            (c.5 - g.5).abs() / size,
            (c.6 - g.6).length() / size,
        ];
        if errors.iter().zip(LIMITS).all(|(e, l)| *e <= l) {
            for k in 0..7 {
                w.errors[k] = w.errors[k].max(errors[k]);
            }
        } else if c.0.min(g.0) < 1e-6 * size.powi(3) {
            w.band += 1;
        } else {
            w.failures.push(format!("case {i}: errors {:?}: cpu {c:?} gpu {g:?}", errors.map(|e| format!("{e:.1e}"))));
        }
    }
    let worst: Vec<String> = NAMES.iter().zip(w.errors).map(|(n, e)| format!("{n} {e:.1e}")).collect();
    println!(
        "{name}: {} cases ({} in contact) in {:.1} ms; worst {}; {} in the f32 band, {} failures",
        queries.len(),
        w.contacts,
        elapsed.as_secs_f64() * 1e3,
        worst.join(", "),
        w.band,
        w.failures.len()
    );
    for f in w.failures.iter().take(5) {
        println!("  {f}");
    }
    assert!(w.failures.is_empty(), "{name}: {} cases disagree", w.failures.len());
    assert!(w.band * 100 <= 3 * queries.len(), "{name}: {} in the band", w.band);
    w
}

pub fn volume_contacts_match_tumble_geom() {
    let shapes = solids(1.0);
    // Pairs.
    let mut rng = Rng(99);
    let (mut queries, mut sizes, mut poses) = (Vec::new(), Vec::new(), Vec::new());
    for _ in 0..1500 {
        let (ia, ib) = (rng.index(shapes.len()), rng.index(shapes.len()));
        let (a, b) = (&shapes[ia], &shapes[ib]);
        let xb = f32_vec(DVec3::new(rng.range(-1.0, 1.0), rng.range(-1.0, 1.0), rng.range(-1.0, 1.0)));
        let xa = f32_vec(xb + rng.unit() * (a.bounding_radius() + b.bounding_radius()) * rng.range(0.4, 1.0));
        let (qa, qb) = (rng.quat(), rng.quat());
        queries.push(ContactQuery::polyhedra(ia as u32, xa, qa, ib as u32, xb, qb).volume());
        sizes.push(a.size().max(b.size()));
        poses.push((ia, Pose::new(xa, qa), ib, Pose::new(xb, qb)));
    }
    let w = compare("volume pairs", &shapes, &queries, &sizes, |i| {
        let (ia, pa, ib, pb) = &poses[i];
        polyhedron_polyhedron_volume(&shapes[*ia], pa, &shapes[*ib], pb)
    });
    assert!(w.contacts > 500, "{}", w.contacts);

    // Walls.
    let walls: Vec<(&str, SurfaceShape)> = vec![
        ("plane", SurfaceShape::Plane(Plane::new(DVec3::new(0.0, 0.0, -0.2), DVec3::new(0.2, -0.1, 1.0).normalize()))),
        (
            "one-sided quad",
            SurfaceShape::Quad(Quad::new(
                [DVec3::new(-1.0, -1.0, 0.0), DVec3::new(1.5, -1.0, 0.1), DVec3::new(1.5, 1.0, 0.1), DVec3::new(-1.0, 1.0, 0.0)],
                false,
            )),
        ),
        (
            "two-sided quad",
            SurfaceShape::Quad(Quad::new(
                [DVec3::new(-0.8, 0.0, -0.6), DVec3::new(0.9, 0.0, -0.6), DVec3::new(0.9, 0.0, 0.7), DVec3::new(-0.8, 0.0, 0.7)],
                true,
            )),
        ),
        ("drum shell", SurfaceShape::Cylinder(Cylinder::new(DVec3::new(0.0, 0.0, -1.5), DVec3::new(0.0, 0.1, 1.0).normalize(), 3.0, 3.0, true))),
        ("pipe", SurfaceShape::Cylinder(Cylinder::new(DVec3::new(0.0, -1.5, 0.0), DVec3::new(0.1, 1.0, 0.0).normalize(), 0.8, 3.0, false))),
    ];
    for (name, wall) in &walls {
        let mut rng = Rng(31);
        let (mut queries, mut sizes, mut poses) = (Vec::new(), Vec::new(), Vec::new());
        for _ in 0..800 {
            let ia = rng.index(shapes.len());
            let a = &shapes[ia];
            let anchor = match wall {
                SurfaceShape::Plane(p) => p.point + DVec3::new(rng.range(-1.0, 1.0), rng.range(-1.0, 1.0), 0.0),
                SurfaceShape::Quad(q) => {
                    let (s, t) = (rng.range(-0.2, 1.2), rng.range(-0.2, 1.2));
                    q.corners[0] + (q.corners[1] - q.corners[0]) * s + (q.corners[3] - q.corners[0]) * t
                }
                SurfaceShape::Cylinder(c) => {
                    let radial = (rng.unit() - c.axis * rng.unit().dot(c.axis)).normalize_or(c.axis.any_orthonormal_vector());
                    let radial = (radial - c.axis * radial.dot(c.axis)).normalize();
                    c.point + c.axis * rng.range(0.2, c.length - 0.2) + radial * c.radius
                }
                SurfaceShape::Prism(_) | SurfaceShape::Mesh(_) => unreachable!(),
            };
            let x = f32_vec(anchor + rng.unit() * a.bounding_radius() * rng.range(0.0, 1.0));
            let q = rng.quat();
            queries.push(ContactQuery::wall(ia as u32, x, q, wall).volume());
            sizes.push(a.size());
            poses.push((ia, Pose::new(x, q)));
        }
        let w = compare(name, &shapes, &queries, &sizes, |i| {
            let (ia, pose) = poses[i];
            wall.polyhedron_volume(&shapes[ia], &pose)
        });
        assert!(w.contacts > 200, "{name}: {}", w.contacts);
    }

    // A lifter bar's hull, as the device meets it: one more shape of the table.
    let end = |z: f64| [DVec3::new(-0.5, -2.0, z), DVec3::new(0.5, -2.0, z), DVec3::new(0.3, -1.6, z), DVec3::new(-0.3, -1.6, z)];
    let prism = Prism::new(end(-1.0), end(1.0), DVec3::ZERO, DVec3::Z);
    let (hull, hull_pose) = (prism.hull.as_deref().unwrap().clone(), prism.hull_pose);
    let mut shapes = solids(0.5);
    let lifter = shapes.len() as u32;
    shapes.push(hull.clone());
    let mut rng = Rng(5);
    let (mut queries, mut sizes, mut poses) = (Vec::new(), Vec::new(), Vec::new());
    for _ in 0..800 {
        let ia = rng.index(lifter as usize);
        let a = &shapes[ia];
        let x = f32_vec(
            DVec3::new(rng.range(-0.6, 0.6), rng.range(-1.9, -1.5), rng.range(-1.2, 1.2)) + rng.unit() * a.bounding_radius() * rng.range(0.0, 1.2),
        );
        let q = rng.quat();
        queries.push(ContactQuery::polyhedra(ia as u32, x, q, lifter, hull_pose.position, hull_pose.rotation).volume());
        sizes.push(a.size());
        poses.push((ia, Pose::new(x, q)));
    }
    let w = compare("lifter hull", &shapes, &queries, &sizes, |i| {
        let (ia, pose) = poses[i];
        polyhedron_polyhedron_volume(&shapes[ia], &pose, &hull, &hull_pose)
    });
    assert!(w.contacts > 200, "{}", w.contacts);
}
