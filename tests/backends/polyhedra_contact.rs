//! The f32 polyhedra narrow phase (shaders/polyhedra.wgsl) against tumble-geom's f64
//! routines on random configurations: cubes, boxes, tetrahedra, octahedra,
//! dodecahedra and icosahedra against each other, spheres, planes, quads, drum
//! shells, pipes and lifter prisms.
//!
//! Agreement: contact found / not found identical, normal within 0.5°, depth within
//! 1e-4 and point within 1e-3 of the size, except in a thin band where the f64
//! answer itself is ill-conditioned: configurations whose answer moves by more than
//! the tolerance when the pose is perturbed by 3e-6 of the size (a near-tie between
//! two axes, nearly parallel edges), and grazing contacts shallower than 2e-5 of
//! the size. The band must stay below 3 % of the cases.
//!
//! The GPU receives f32 poses; tumble-geom gets the same f32-rounded poses in f64.

use glam::{DQuat, DVec3};
use tumble_geom::{Cylinder, Plane, PolyContact, Polyhedron, Pose, Prism, Quad, SurfaceShape, polyhedron_polyhedron, sphere_polyhedron};
use tumble_gpu::shapes::{ContactAnswer, ContactQuery, evaluate};

/// A small deterministic generator (PCG-style LCG).
pub(crate) struct Rng(pub(crate) u64);

impl Rng {
    pub(crate) fn uniform(&mut self) -> f64 {
        self.0 = self.0.wrapping_mul(6364136223846793005).wrapping_add(1442695040888963407);
        (self.0 >> 11) as f64 / (1u64 << 53) as f64
    }
    pub(crate) fn range(&mut self, lo: f64, hi: f64) -> f64 {
        lo + (hi - lo) * self.uniform()
    }
    pub(crate) fn unit(&mut self) -> DVec3 {
        loop {
            let v = DVec3::new(self.range(-1.0, 1.0), self.range(-1.0, 1.0), self.range(-1.0, 1.0));
            let l = v.length();
            if l > 0.1 && l <= 1.0 {
                return v / l;
            }
        }
    }
    pub(crate) fn quat(&mut self) -> DQuat {
        f32_quat(DQuat::from_axis_angle(self.unit(), self.range(0.0, std::f64::consts::PI)))
    }
    pub(crate) fn index(&mut self, n: usize) -> usize {
        ((self.uniform() * n as f64) as usize).min(n - 1)
    }
}

pub(crate) fn f32_vec(v: DVec3) -> DVec3 {
    v.as_vec3().as_dvec3()
}

fn f32_quat(q: DQuat) -> DQuat {
    DQuat::from_xyzw(q.x as f32 as f64, q.y as f32 as f64, q.z as f32 as f64, q.w as f32 as f64).normalize()
}

/// The six test solids at a given scale (bounding radii about `scale`).
pub(crate) fn solids(scale: f64) -> Vec<Polyhedron> {
    vec![
        Polyhedron::cube(1.1 * scale),
        Polyhedron::cuboid(DVec3::new(0.3, 0.55, 0.85) * scale),
        Polyhedron::tetrahedron(1.6 * scale),
        Polyhedron::octahedron(1.3 * scale),
        Polyhedron::dodecahedron(0.7 * scale),
        Polyhedron::icosahedron(1.05 * scale),
    ]
}

/// A contact as the comparison sees it: (normal, depth, point, spread).
type Answer = Option<(DVec3, f64, DVec3, f64)>;

/// The depth-weighted mean distance of the manifold points from the contact point (0 for one point).
fn spread(c: &PolyContact) -> f64 {
    let m = c.manifold();
    if m.len() < 2 {
        return 0.0;
    }
    m.iter().map(|p| p.depth * (p.point - c.point).length()).sum::<f64>() / m.iter().map(|p| p.depth).sum::<f64>()
}

fn of_geom(c: Option<PolyContact>) -> Answer {
    c.map(|c| (c.normal, c.depth, c.point, spread(&c)))
}

fn of_gpu(a: &ContactAnswer) -> Answer {
    a.hit().then(|| (a.normal(), a.depth(), a.point(), a.spread()))
}

/// The box around a four-point manifold, when there is one (the reduction may have chosen
/// those four among more, with exact ties: see `compare`).
fn four_point_box(c: &Option<PolyContact>) -> Option<(DVec3, DVec3)> {
    let c = c.as_ref()?;
    (c.manifold().len() == 4).then(|| {
        let lo = c.manifold().iter().fold(DVec3::INFINITY, |m, p| m.min(p.point));
        let hi = c.manifold().iter().fold(DVec3::NEG_INFINITY, |m, p| m.max(p.point));
        (lo, hi)
    })
}

/// Angle (degrees), depth error and point error (the larger of the point's and the spread's)
/// of two contacts, relative to `size`; Err when one is missing.
fn differences(a: &Answer, b: &Answer, size: f64) -> Result<Option<(f64, f64, f64)>, ()> {
    match (a, b) {
        (None, None) => Ok(None),
        (Some((na, da, pa, sa)), Some((nb, db, pb, sb))) => {
            let angle = na.dot(*nb).clamp(-1.0, 1.0).acos().to_degrees();
            Ok(Some((angle, (da - db).abs() / size, (*pa - *pb).length().max((sa - sb).abs()) / size)))
        }
        _ => Err(()),
    }
}

const MAX_ANGLE: f64 = 0.5;
const MAX_DEPTH: f64 = 1e-4;
const MAX_POINT: f64 = 1e-3;

fn within(d: Result<Option<(f64, f64, f64)>, ()>) -> bool {
    match d {
        Ok(None) => true,
        Ok(Some((a, dd, dp))) => a <= MAX_ANGLE && dd <= MAX_DEPTH && dp <= MAX_POINT,
        Err(()) => false,
    }
}

/// Agreement figures of one family of cases.
#[derive(Default, Debug)]
struct Report {
    cases: usize,
    contacts: usize,
    band: usize,
    /// Four-point manifolds reduced from more points with a different choice among exact ties.
    ties: usize,
    worst_angle: f64,
    worst_depth: f64,
    worst_point: f64,
    failures: Vec<String>,
}

/// One case: the GPU query, and tumble-geom's answer for A moved by a small rigid
/// perturbation (None: unperturbed) — both already in f32-rounded poses.
struct Case {
    query: ContactQuery,
    size: f64,
    describe: String,
}

fn perturbation(rng: &mut Rng, size: f64) -> (DVec3, DQuat) {
    let eps = 3e-6;
    (rng.unit() * eps * size, DQuat::from_axis_angle(rng.unit(), eps))
}

/// Runs the queries on the device and compares each with `cpu(case index, perturbation)`.
///
/// Manifolds of more than four points are reduced to four (the deepest, the farthest from
/// it, the largest triangle, the largest on the other side). With parallel edges (every
/// solid here but the tetrahedron) the triangle areas tie exactly, whatever the pose: an
/// edge parallel to the chord gives equal areas at both ends. tumble-geom then keeps the last
/// of the tied points as its f64 rounding falls, the device as its f32 rounding falls, and
/// the depth-weighted means differ although both are means over the same contact region. A
/// four-point manifold whose normal and depth agree and whose device point lies inside the
/// box around the f64 manifold (padded by the point tolerance) counts as such a tie.
fn compare(name: &str, cases: &[Case], shapes: &[Polyhedron], cpu: impl Fn(usize, Option<(DVec3, DQuat)>) -> Option<PolyContact>) -> Report {
    let queries: Vec<ContactQuery> = cases.iter().map(|c| c.query).collect();
    let t = std::time::Instant::now();
    let gpu = evaluate(shapes, &queries).unwrap();
    let elapsed = t.elapsed();
    let mut rng = Rng(0x5eed);
    let mut r = Report { cases: cases.len(), ..Default::default() };
    for (i, case) in cases.iter().enumerate() {
        let full = cpu(i, None);
        let reference = of_geom(full);
        let g = of_gpu(&gpu[i]);
        r.contacts += reference.is_some() as usize;
        let d = differences(&reference, &g, case.size);
        if within(d) {
            if let Ok(Some((a, dd, dp))) = d {
                r.worst_angle = r.worst_angle.max(a);
                r.worst_depth = r.worst_depth.max(dd);
                r.worst_point = r.worst_point.max(dp);
            }
            continue;
        }
        if let (Some((lo, hi)), Ok(Some((a, dd, _))), Some(p)) = (four_point_box(&full), d, g.map(|g| g.2)) {
            let pad = DVec3::splat(MAX_POINT * case.size);
            if a <= MAX_ANGLE && dd <= MAX_DEPTH && p.cmpge(lo - pad).all() && p.cmple(hi + pad).all() {
                r.ties += 1;
                continue;
            }
        }
        // Grazing contacts: found or not within the f32 band.
        let depth = reference.map_or(0.0, |c| c.1).max(g.map_or(0.0, |c| c.1));
        let grazing = d.is_err() && depth < 2e-5 * case.size;
        // Ill-conditioned: the f64 answer itself moves beyond the tolerance under a tiny perturbation.
        let unstable = (0..6).any(|_| !within(differences(&reference, &of_geom(cpu(i, Some(perturbation(&mut rng, case.size)))), case.size)));
        if grazing || unstable {
            r.band += 1;
        } else {
            r.failures.push(format!("{}: cpu {reference:?} gpu {g:?}", case.describe));
        }
    }
    println!(
        "{name}: {} cases ({} in contact) in {:.1} ms on the device; worst normal {:.2e}°, depth {:.2e}, point {:.2e} (of the size); {} reduction ties, {} in the f32 band, {} failures",
        r.cases,
        r.contacts,
        elapsed.as_secs_f64() * 1e3,
        r.worst_angle,
        r.worst_depth,
        r.worst_point,
        r.ties,
        r.band,
        r.failures.len()
    );
    for f in r.failures.iter().take(10) {
        println!("  {f}");
    }
    r
}

fn assert_agrees(r: &Report, min_contacts: usize) {
    assert!(r.failures.is_empty(), "{} cases disagree beyond the tolerance", r.failures.len());
    assert!(r.band * 100 <= 3 * r.cases, "{} of {} cases in the f32 band", r.band, r.cases);
    assert!(r.ties * 100 <= 10 * r.cases, "{} of {} cases with reduction ties", r.ties, r.cases);
    assert!(r.contacts >= min_contacts, "only {} contacts", r.contacts);
}

fn moved(pose: &Pose, p: Option<(DVec3, DQuat)>) -> Pose {
    match p {
        None => *pose,
        Some((dx, dq)) => Pose::new(pose.position + dx, dq * pose.rotation),
    }
}

pub fn polyhedron_pairs_match_tumble_geom() {
    for scale in [1.0, 0.002] {
        let shapes = solids(scale);
        let mut rng = Rng(42);
        let mut poses = Vec::new();
        let mut cases = Vec::new();
        for k in 0..2400 {
            let (ia, ib) = (rng.index(shapes.len()), rng.index(shapes.len()));
            let (a, b) = (&shapes[ia], &shapes[ib]);
            let reach = a.bounding_radius() + b.bounding_radius();
            let xb = f32_vec(DVec3::new(rng.range(-1.0, 1.0), rng.range(-1.0, 1.0), rng.range(-1.0, 1.0)) * scale);
            let xa = f32_vec(xb + rng.unit() * reach * rng.range(0.25, 1.0));
            let (qa, qb) = (rng.quat(), rng.quat());
            // Every tenth pair: both aligned (faces parallel, the manifold has several points).
            let (qa, qb) = if k % 10 == 0 { (qb, qb) } else { (qa, qb) };
            poses.push((ia, Pose::new(xa, qa), ib, Pose::new(xb, qb)));
            cases.push(Case {
                query: ContactQuery::polyhedra(ia as u32, xa, qa, ib as u32, xb, qb),
                size: a.size().max(b.size()),
                describe: format!("shapes {ia}/{ib} at {xa:?} {qa:?} / {xb:?} {qb:?}"),
            });
        }
        let r = compare(&format!("polyhedron pairs at scale {scale}"), &cases, &shapes, |i, p| {
            let (ia, pa, ib, pb) = &poses[i];
            polyhedron_polyhedron(&shapes[*ia], &moved(pa, p), &shapes[*ib], pb)
        });
        assert_agrees(&r, 800);
    }
}

pub fn spheres_against_polyhedra_match_tumble_geom() {
    let shapes = solids(1.0);
    let mut rng = Rng(7);
    let mut setups = Vec::new();
    let mut cases = Vec::new();
    for _ in 0..2000 {
        let ib = rng.index(shapes.len());
        let b = &shapes[ib];
        let radius = f32_vec(DVec3::splat(rng.range(0.05, 0.8) * b.bounding_radius())).x;
        let xb = f32_vec(DVec3::new(rng.range(-1.0, 1.0), rng.range(-1.0, 1.0), 0.3));
        let centre = f32_vec(xb + rng.unit() * (b.bounding_radius() + radius) * rng.range(0.0, 1.0));
        let qb = rng.quat();
        setups.push((centre, radius, ib, Pose::new(xb, qb)));
        cases.push(Case {
            query: ContactQuery::sphere(centre, radius, ib as u32, xb, qb),
            size: b.size(),
            describe: format!("sphere {radius} at {centre:?}, shape {ib} at {xb:?} {qb:?}"),
        });
    }
    let r = compare("spheres against polyhedra", &cases, &shapes, |i, p| {
        let (centre, radius, ib, pose) = setups[i];
        let centre = p.map_or(centre, |(dx, _)| centre + dx);
        sphere_polyhedron(centre, radius, &shapes[ib], &pose)
    });
    assert_agrees(&r, 800);
}

pub fn polyhedra_against_walls_match_tumble_geom() {
    let shapes = solids(1.0);
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
        ("drum shell", SurfaceShape::Cylinder(Cylinder::new(DVec3::new(0.0, 0.0, -1.5), DVec3::new(0.0, 0.1, 1.0).normalize(), 2.0, 3.0, true))),
        ("pipe", SurfaceShape::Cylinder(Cylinder::new(DVec3::new(0.0, -1.5, 0.0), DVec3::new(0.1, 1.0, 0.0).normalize(), 0.6, 3.0, false))),
    ];
    for (name, wall) in &walls {
        let mut rng = Rng(11);
        let mut setups = Vec::new();
        let mut cases = Vec::new();
        for _ in 0..1500 {
            let ia = rng.index(shapes.len());
            let a = &shapes[ia];
            // Near the surface: a random point of it, then off along a random direction.
            let anchor = match wall {
                SurfaceShape::Plane(p) => p.point + DVec3::new(rng.range(-1.0, 1.0), rng.range(-1.0, 1.0), 0.0),
                SurfaceShape::Quad(q) => {
                    let (s, t) = (rng.range(-0.2, 1.2), rng.range(-0.2, 1.2));
                    q.corners[0] + (q.corners[1] - q.corners[0]) * s + (q.corners[3] - q.corners[0]) * t
                }
                SurfaceShape::Cylinder(c) => {
                    let radial = (rng.unit() - c.axis * rng.unit().dot(c.axis)).normalize_or(c.axis.any_orthonormal_vector());
                    let radial = (radial - c.axis * radial.dot(c.axis)).normalize();
                    c.point + c.axis * rng.range(0.0, c.length) + radial * c.radius
                }
                SurfaceShape::Prism(_) | SurfaceShape::Mesh(_) => unreachable!(),
            };
            let x = f32_vec(anchor + rng.unit() * a.bounding_radius() * rng.range(0.0, 1.1));
            let q = rng.quat();
            setups.push((ia, Pose::new(x, q)));
            cases.push(Case { query: ContactQuery::wall(ia as u32, x, q, wall), size: a.size(), describe: format!("shape {ia} at {x:?} {q:?}") });
        }
        let r = compare(name, &cases, &shapes, |i, p| {
            let (ia, pose) = setups[i];
            wall.polyhedron_contact(&shapes[ia], &moved(&pose, p))
        });
        assert_agrees(&r, 300);
    }
}

pub fn polyhedra_against_lifter_prisms_as_table_shapes() {
    // A trapezoidal lifter bar along z on the inside of a drum of radius 2 about the z axis.
    let (axis_point, axis) = (DVec3::ZERO, DVec3::Z);
    let (r0, r1, w0, w1) = (2.0, 1.6, 0.5, 0.3);
    let end = |z: f64| [DVec3::new(-w0, -r0, z), DVec3::new(w0, -r0, z), DVec3::new(w1, -r1, z), DVec3::new(-w1, -r1, z)];
    let prism = Prism::new(end(-1.0), end(1.0), axis_point, axis);
    let corners: Vec<DVec3> = end(-1.0).into_iter().chain(end(1.0)).collect();
    let hull = Polyhedron::from_points(&corners).unwrap();
    let hull_pose = hull.input_to_body().relative(&Pose::IDENTITY);
    let mut shapes = solids(0.5);
    let lifter = shapes.len() as u32;
    shapes.push(hull.clone());
    let mut rng = Rng(5);
    let mut setups = Vec::new();
    let mut cases = Vec::new();
    for _ in 0..1500 {
        let ia = rng.index(lifter as usize);
        let a = &shapes[ia];
        let anchor = DVec3::new(rng.range(-0.6, 0.6), rng.range(-1.9, -1.5), rng.range(-1.2, 1.2));
        let x = f32_vec(anchor + rng.unit() * a.bounding_radius() * rng.range(0.0, 1.2));
        let q = rng.quat();
        setups.push((ia, Pose::new(x, q)));
        cases.push(Case {
            query: ContactQuery::polyhedra(ia as u32, x, q, lifter, hull_pose.position, hull_pose.rotation),
            size: a.size(),
            describe: format!("shape {ia} at {x:?} {q:?}"),
        });
    }
    let r = compare("lifter prism", &cases, &shapes, |i, p| {
        let (ia, pose) = setups[i];
        prism.polyhedron_contact(&shapes[ia], &moved(&pose, p))
    });
    assert_agrees(&r, 300);
}

pub fn resting_and_crossed_configurations_are_exact_to_f32() {
    // tumble-geom's doc and unit cases: a cube resting 0.1 deep on another (four manifold
    // points), a corner into a face, crossed edges, a cube on a floor.
    let shapes = vec![Polyhedron::cube(1.0)];
    let s = 0.5 * 2f64.sqrt();
    let tilt = DQuat::from_rotation_arc(DVec3::ONE.normalize(), -DVec3::Z);
    let h = 0.5 + 0.5 * 3f64.sqrt() - 0.05;
    let queries = [
        ContactQuery::polyhedra(0, DVec3::new(0.2, 0.1, 0.9), DQuat::IDENTITY, 0, DVec3::ZERO, DQuat::IDENTITY),
        ContactQuery::polyhedra(0, DVec3::new(0.1, -0.1, h), tilt, 0, DVec3::ZERO, DQuat::IDENTITY),
        ContactQuery::polyhedra(
            0,
            DVec3::new(0.0, 0.0, 2.0 * s - 0.02),
            DQuat::from_rotation_x(std::f64::consts::FRAC_PI_4),
            0,
            DVec3::ZERO,
            DQuat::from_rotation_y(std::f64::consts::FRAC_PI_4),
        ),
        ContactQuery::wall(0, DVec3::new(0.0, 0.0, 0.48), DQuat::IDENTITY, &SurfaceShape::Plane(Plane::new(DVec3::ZERO, DVec3::Z))),
        ContactQuery::sphere(DVec3::new(0.55, 0.55, 0.0), 0.1, 0, DVec3::ZERO, DQuat::IDENTITY),
    ];
    let expected = [
        (DVec3::Z, 0.1, DVec3::new(0.2 - 0.5 + 0.5 * 0.8, 0.1 - 0.5 + 0.5 * 0.9, 0.45)),
        (DVec3::Z, 0.05, DVec3::new(0.1, -0.1, 0.475)),
        (DVec3::Z, 0.02, DVec3::new(0.0, 0.0, s - 0.01)),
        (DVec3::Z, 0.02, DVec3::new(0.0, 0.0, -0.01)),
        (DVec3::new(1.0, 1.0, 0.0).normalize(), 0.1 - 0.05 * 2f64.sqrt(), DVec3::ZERO),
    ];
    let gpu = evaluate(&shapes, &queries).unwrap();
    for (k, (g, (n, d, p))) in gpu.iter().zip(expected).enumerate() {
        assert!(g.hit(), "case {k}");
        assert!((g.normal() - n).length() < 1e-6, "case {k}: normal {:?}", g.normal());
        assert!((g.depth() - d).abs() < 1e-6, "case {k}: depth {}", g.depth());
        if k < 4 {
            assert!((g.point() - p).length() < 1e-6, "case {k}: point {:?} vs {p:?}", g.point());
        }
    }
    // Just apart: nothing.
    let apart = [ContactQuery::polyhedra(0, DVec3::new(0.0, 0.0, 1.001), DQuat::IDENTITY, 0, DVec3::ZERO, DQuat::IDENTITY)];
    assert!(!evaluate(&shapes, &apart).unwrap()[0].hit());
}
