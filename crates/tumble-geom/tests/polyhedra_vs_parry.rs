//! The polyhedron contact routines against parry3d's GJK/EPA `contact` (the oracle).
//!
//! For random hulls and the named solids at random poses and overlaps:
//! - parry finds a penetration deeper than 1e-6 of the size ⇒ we report a contact;
//!   parry finds none (or a gap wider than that) ⇒ we report none;
//! - depth within 5 % (or 1e-6 of the size) of parry's, or, where parry's EPA stops short (deep
//!   overlaps of bodies two decades apart in size; 20,000 random cases found one), no more than 5 % above the
//!   overlap along parry's own normal: there is then no shorter way out than ours;
//! - normal within 5° of parry's, unless the two normals are a tie: the overlap along parry's
//!   normal, measured with the support functions, equals our depth (then either is a minimum);
//! - our depth is the overlap of the two bodies along our own normal (support functions).

use glam::DQuat;
use parry3d_f64::query;
use parry3d_f64::shape::{Ball, ConvexPolyhedron};
use proptest::prelude::*;
use tumble_geom::{DVec3, PolyContact, Polyhedron, Pose, SeparationCache, polyhedron_polyhedron, polyhedron_polyhedron_sat, sphere_polyhedron};

fn named(k: usize, size: f64) -> Polyhedron {
    match k % 8 {
        0 => Polyhedron::cube(size),
        1 => Polyhedron::cuboid(DVec3::new(0.5, 0.2, 0.3) * size),
        2 => Polyhedron::tetrahedron(size),
        3 => Polyhedron::octahedron(size),
        4 => Polyhedron::dodecahedron(0.5 * size),
        5 => Polyhedron::icosahedron(0.6 * size),
        6 => Polyhedron::prism(3 + k % 5, 0.5 * size, 0.8 * size),
        _ => Polyhedron::prism(6, 0.5 * size, 0.2 * size),
    }
}

fn shape() -> impl Strategy<Value = Polyhedron> {
    prop_oneof![
        (0usize..40, 0.3f64..2.0).prop_map(|(k, s)| named(k, s)),
        (proptest::collection::vec((-1.0f64..1.0, -1.0f64..1.0, -1.0f64..1.0), 6..24), 0.2f64..1.0, 0.2f64..1.0)
            .prop_filter_map("degenerate cloud", |(pts, sy, sz)| {
                Polyhedron::from_points(&pts.iter().map(|&(x, y, z)| DVec3::new(x, y * sy, z * sz)).collect::<Vec<_>>())
            }),
    ]
}

fn rotation() -> impl Strategy<Value = DQuat> {
    (-1.0f64..1.0, -1.0f64..1.0, -1.0f64..1.0, -1.0f64..1.0).prop_filter_map("zero quaternion", |(x, y, z, w)| {
        let q = DQuat::from_xyzw(x, y, z, w);
        (q.length() > 0.1).then(|| q.normalize())
    })
}

fn unit() -> impl Strategy<Value = DVec3> {
    (-1.0f64..1.0, -1.0f64..1.0, -1.0f64..1.0).prop_filter_map("zero", |(x, y, z)| {
        let v = DVec3::new(x, y, z);
        (v.length() > 0.1).then(|| v.normalize())
    })
}

/// The overlap of A and B along n (from B to A): max_B n·b − min_A n·a.
fn overlap_along(a: &Polyhedron, pa: &Pose, b: &Polyhedron, pb: &Pose, n: DVec3) -> f64 {
    let max_b = b.vertices().iter().map(|v| n.dot(pb.to_world(*v))).fold(f64::NEG_INFINITY, f64::max);
    let min_a = a.vertices().iter().map(|v| n.dot(pa.to_world(*v))).fold(f64::INFINITY, f64::min);
    max_b - min_a
}

#[derive(Debug, Default, Clone, Copy)]
struct Stats {
    cases: usize,
    contacts: usize,
    separated: usize,
    ties: usize,
    /// Parry's depth shorter than the overlap along its own normal (its EPA stopped short).
    parry_short: usize,
    worst_angle_deg: f64,
    worst_depth_rel: f64,
}

/// Compares one configuration; returns Err with a message on a mismatch.
fn compare(
    a: &Polyhedron,
    pa: &Pose,
    pha: &ConvexPolyhedron,
    b: &Polyhedron,
    pb: &Pose,
    phb: &ConvexPolyhedron,
    st: &mut Stats,
) -> Result<(), String> {
    let size = a.size().max(b.size());
    let eps = 1e-6 * size;
    let oracle = query::contact(&pa.to_parry(), pha, &pb.to_parry(), phb, 0.0).map_err(|e| format!("parry: {e:?}"))?;
    // The fast path itself, whatever the shapes' size (the dispatcher may hand large ones to parry).
    let ours = polyhedron_polyhedron_sat(a, pa, b, pb, &mut SeparationCache::default());
    st.cases += 1;
    match (oracle, ours) {
        (Some(o), Some(c)) if o.dist < -eps => {
            st.contacts += 1;
            check_contact(&c, -o.normal1, -o.dist, size, st, |n| overlap_along(a, pa, b, pb, n))?;
            let own = overlap_along(a, pa, b, pb, c.normal);
            if (own - c.depth).abs() > 1e-9 * size {
                return Err(format!("depth {} is not the overlap {own} along our normal", c.depth));
            }
            for m in c.manifold() {
                if !(m.depth > 0.0 && m.depth <= c.depth + 1e-9 * size) {
                    return Err(format!("manifold depth {} outside (0, {}]", m.depth, c.depth));
                }
            }
            Ok(())
        }
        (Some(o), None) if o.dist < -eps => Err(format!("parry finds depth {} but we find no contact", -o.dist)),
        (Some(o), Some(c)) if o.dist > eps => Err(format!("parry finds a gap {} but we find depth {}", o.dist, c.depth)),
        (None, Some(c)) => Err(format!("parry finds no contact but we find depth {}", c.depth)),
        (None, None) => {
            st.separated += 1;
            Ok(())
        }
        (Some(o), None) if o.dist >= 0.0 => {
            st.separated += 1;
            Ok(())
        }
        _ => Ok(()), // within eps of touching: either answer is right
    }
}

fn check_contact(c: &PolyContact, n_ref: DVec3, d_ref: f64, size: f64, st: &mut Stats, overlap: impl Fn(DVec3) -> f64) -> Result<(), String> {
    let derr = (c.depth - d_ref).abs();
    if derr > (0.05 * d_ref).max(1e-6 * size) {
        // Parry's EPA can stop short on deep overlaps of very different sizes: it is wrong, not
        // we, when the bodies' overlap along its own normal is no shorter than our depth.
        let along_ref = overlap(n_ref);
        if !(along_ref >= c.depth - (0.05 * c.depth).max(1e-6 * size)) {
            return Err(format!("depth {} vs parry {d_ref} (overlap along parry's normal {along_ref})", c.depth));
        }
        st.parry_short += 1;
        return Ok(());
    }
    st.worst_depth_rel = st.worst_depth_rel.max(derr / d_ref.max(1e-6 * size));
    let angle = c.normal.dot(n_ref).clamp(-1.0, 1.0).acos().to_degrees();
    if angle > 5.0 {
        // A tie: parry's normal is as short a way out as ours.
        let along_ref = overlap(n_ref);
        if (along_ref - c.depth).abs() > (0.05 * c.depth).max(1e-6 * size) {
            return Err(format!("normal {:?} vs parry {n_ref:?} ({angle:.2}°), overlap along parry's {along_ref} vs depth {}", c.normal, c.depth));
        }
        st.ties += 1;
    } else {
        st.worst_angle_deg = st.worst_angle_deg.max(angle);
    }
    Ok(())
}

proptest! {
    #![proptest_config(ProptestConfig { cases: 256, ..ProptestConfig::default() })]

    #[test]
    fn polyhedron_pairs_agree_with_parry(a in shape(), b in shape(), qa in rotation(), qb in rotation(), dir in unit(), frac in 0.0f64..1.1) {
        let pb = Pose::new(DVec3::new(0.3, -0.2, 0.1), qb);
        let pa = Pose::new(pb.position + dir * frac * (a.bounding_radius() + b.bounding_radius()), qa);
        let mut st = Stats::default();
        compare(&a, &pa, &a.to_parry(), &b, &pb, &b.to_parry(), &mut st).map_err(TestCaseError::fail)?;
    }

    /// Sizes two decades apart, and deep overlaps (centre of the small one inside the big one).
    #[test]
    fn polyhedra_of_very_different_sizes_agree_with_parry(a in shape(), b in shape(), qa in rotation(), qb in rotation(), dir in unit(),
                                                          frac in 0.0f64..1.05, scale in -2.0f64..2.0) {
        let a = a.scaled(10f64.powf(scale));
        let pb = Pose::new(DVec3::new(1.0, 2.0, -3.0), qb);
        let pa = Pose::new(pb.position + dir * frac * (a.bounding_radius() + b.bounding_radius()), qa);
        let mut st = Stats::default();
        compare(&a, &pa, &a.to_parry(), &b, &pb, &b.to_parry(), &mut st).map_err(TestCaseError::fail)?;
    }

    #[test]
    fn spheres_on_polyhedra_agree_with_parry(b in shape(), qb in rotation(), dir in unit(), frac in 0.0f64..1.2, r in 0.05f64..0.8) {
        let pb = Pose::new(DVec3::new(-0.4, 0.2, 1.0), qb);
        let centre = pb.position + dir * frac * (b.bounding_radius() + r);
        let size = b.size();
        let eps = 1e-6 * size;
        let oracle = query::contact(&Pose::from_position(centre).to_parry(), &Ball::new(r), &pb.to_parry(), &b.to_parry(), 0.0).unwrap();
        let ours = sphere_polyhedron(centre, r, &b, &pb);
        match (oracle, ours) {
            (Some(o), Some(c)) if o.dist < -eps => {
                let mut st = Stats::default();
                check_contact(&c, -o.normal1, -o.dist, size, &mut st, |_| f64::NAN).map_err(TestCaseError::fail)?;
            }
            (Some(o), None) if o.dist < -eps => prop_assert!(false, "parry finds depth {} but we find none", -o.dist),
            (Some(o), Some(c)) if o.dist > eps => prop_assert!(false, "parry gap {} but we find depth {}", o.dist, c.depth),
            (None, Some(c)) => prop_assert!(false, "parry none, we find depth {}", c.depth),
            _ => {}
        }
    }
}

/// A seeded sweep that reports the worst normal angle and depth error (run with --nocapture).
#[test]
fn sweep_reports_worst_errors() {
    let mut s = 0x9e3779b97f4a7c15u64;
    let mut rnd = move || {
        s ^= s << 13;
        s ^= s >> 7;
        s ^= s << 17;
        (s >> 11) as f64 / (1u64 << 53) as f64
    };
    let mut shapes: Vec<Polyhedron> = (0..16).map(|k| named(k, 0.5 + rnd())).collect();
    while shapes.len() < 32 {
        let n = 6 + (rnd() * 16.0) as usize;
        let pts: Vec<DVec3> = (0..n).map(|_| DVec3::new(rnd() - 0.5, 0.6 * (rnd() - 0.5), 0.9 * (rnd() - 0.5))).collect();
        if let Some(p) = Polyhedron::from_points(&pts) {
            shapes.push(p);
        }
    }
    let parry: Vec<ConvexPolyhedron> = shapes.iter().map(|p| p.to_parry()).collect();
    let mut quat = || DQuat::from_xyzw(rnd() - 0.5, rnd() - 0.5, rnd() - 0.5, rnd() - 0.5).normalize();
    let mut st = Stats::default();
    let mut failures = Vec::new();
    let mut r2 = 0.31f64;
    for i in 0..1500 {
        let (ia, ib) = (i % shapes.len(), (i * 7 + 3) % shapes.len());
        let (qa, qb) = (quat(), quat());
        r2 = (r2 * 3.9 * (1.0 - r2)).clamp(0.01, 0.99); // a cheap second stream for the distances
        let dir = (qa * DVec3::X + qb * DVec3::Y * 0.3).normalize();
        let (a, b) = (&shapes[ia], &shapes[ib]);
        let pb = Pose::new(DVec3::ZERO, qb);
        let pa = Pose::new(dir * r2 * (a.bounding_radius() + b.bounding_radius()), qa);
        if let Err(e) = compare(a, &pa, &parry[ia], b, &pb, &parry[ib], &mut st) {
            failures.push(format!("case {i} ({ia} vs {ib}): {e}"));
        }
    }
    eprintln!("polyhedron sweep: {st:?}");
    // Spheres around the same shapes.
    let mut ss = Stats::default();
    for i in 0..1500 {
        let b = &shapes[i % shapes.len()];
        let pb = Pose::new(DVec3::ZERO, quat());
        let r = 0.05 + 0.5 * r2;
        r2 = (r2 * 3.9 * (1.0 - r2)).clamp(0.01, 0.99);
        let centre = (pb.rotation * DVec3::new(0.3, 1.0, -0.2)).normalize() * (b.bounding_radius() + r) * r2 * 1.1;
        let oracle = query::contact(&Pose::from_position(centre).to_parry(), &Ball::new(r), &pb.to_parry(), &parry[i % shapes.len()], 0.0).unwrap();
        let size = b.size();
        ss.cases += 1;
        match (oracle, sphere_polyhedron(centre, r, b, &pb)) {
            (Some(o), Some(c)) if o.dist < -1e-6 * size => {
                ss.contacts += 1;
                if let Err(e) = check_contact(&c, -o.normal1, -o.dist, size, &mut ss, |_| f64::NAN) {
                    failures.push(format!("sphere case {i}: {e}"));
                }
            }
            (Some(o), None) if o.dist < -1e-6 * size => failures.push(format!("sphere case {i}: parry depth {}, ours none", -o.dist)),
            (None, Some(c)) => failures.push(format!("sphere case {i}: parry none, ours {}", c.depth)),
            _ => ss.separated += 1,
        }
    }
    eprintln!("sphere sweep: {ss:?}");
    assert!(failures.is_empty(), "{} failures:\n{}", failures.len(), failures.join("\n"));
}

mod walls {
    use super::*;
    use parry3d_f64::shape::{Cylinder as ParryCylinder, HalfSpace, Triangle};
    use tumble_geom::{Cylinder, Plane, Quad, SurfaceShape};

    fn angle_deg(a: DVec3, b: DVec3) -> f64 {
        a.dot(b).clamp(-1.0, 1.0).acos().to_degrees()
    }

    /// Overlap of the polyhedron (A) and a point set (B) along n from B to A.
    fn overlap_pts(a: &Polyhedron, pa: &Pose, b: &[DVec3], n: DVec3) -> f64 {
        let max_b = b.iter().map(|v| n.dot(*v)).fold(f64::NEG_INFINITY, f64::max);
        let min_a = a.vertices().iter().map(|v| n.dot(pa.to_world(*v))).fold(f64::INFINITY, f64::min);
        max_b - min_a
    }

    proptest! {
        #![proptest_config(ProptestConfig { cases: 256, ..ProptestConfig::default() })]

        #[test]
        fn plane_agrees_with_parry_halfspace(p in shape(), q in rotation(), n in unit(), h in -0.6f64..1.1) {
            let plane = Plane::new(DVec3::new(0.1, 0.2, -0.3), n);
            let pose = Pose::new(plane.point + n * h * p.bounding_radius(), q);
            let size = p.size();
            let hs_pose = Pose::new(plane.point, DQuat::from_rotation_arc(DVec3::Y, n));
            // Half-space first: parry3d 0.31.1's support-map-then-half-space order passes the
            // relative pose uninverted (its intersection test inverts it), so it answers wrongly.
            let oracle = query::contact(&hs_pose.to_parry(), &HalfSpace::new(DVec3::Y), &pose.to_parry(), &p.to_parry(), 0.0).unwrap();
            let ours = SurfaceShape::Plane(plane).polyhedron_contact(&p, &pose);
            match (oracle, ours) {
                (Some(o), Some(c)) if o.dist < -1e-9 * size => {
                    prop_assert!(angle_deg(c.normal, o.normal1) < 1e-5, "normal {:?} vs {:?}", c.normal, o.normal1);
                    prop_assert!((c.depth + o.dist).abs() < 1e-9 * size, "depth {} vs {}", c.depth, -o.dist);
                    prop_assert!(c.manifold().len() <= 4 && c.manifold().iter().all(|m| m.depth > 0.0 && m.depth <= c.depth));
                }
                (Some(o), None) => prop_assert!(o.dist > -1e-9 * size, "parry depth {}", -o.dist),
                (None, Some(c)) => prop_assert!(false, "parry none, ours {}", c.depth),
                _ => {}
            }
        }

        /// Quads: parry's two triangles decide overlap; our depth is the overlap along our normal
        /// and no sampled direction (nor the quad normal, nor parry's triangle normals) is shorter.
        #[test]
        fn quad_contacts_are_minimum_translations(p in shape(), q in rotation(), dir in unit(), frac in 0.0f64..1.1, two_sided in any::<bool>(),
                                                 samples in proptest::collection::vec(unit(), 64)) {
            let c = |x: f64, y: f64| DVec3::new(x, y, 0.05 * x + 0.02 * y);
            let quad = Quad::new([c(-0.8, -0.5), c(0.9, -0.6), c(1.0, 0.7), c(-0.7, 0.6)], two_sided);
            assert!(quad.planarity_error() < 1e-12);
            let centre = DVec3::new(0.3, 0.0, 0.06) + dir * frac * p.bounding_radius() * 1.5;
            let pose = Pose::new(centre, q);
            let size = p.size();
            let ours = quad.polyhedron_contact(&p, &pose);
            let tris = [Triangle::new(quad.corners[0], quad.corners[1], quad.corners[2]), Triangle::new(quad.corners[0], quad.corners[2], quad.corners[3])];
            let ph = p.to_parry();
            let pen = tris.iter().filter_map(|t| query::contact(&pose.to_parry(), &ph, &Pose::IDENTITY.to_parry(), t, 0.0).unwrap()).map(|c| -c.dist).fold(f64::NEG_INFINITY, f64::max);
            let h = quad.normal.dot(centre - quad.corners[0]);
            match ours {
                Some(c) => {
                    prop_assert!(c.depth > 0.0);
                    prop_assert!(pen > -1e-9 * size, "parry finds the triangles apart by {}", -pen);
                    let own = overlap_pts(&p, &pose, &quad.corners, c.normal);
                    prop_assert!((own - c.depth).abs() < 1e-9 * size, "depth {} vs overlap along the normal {own}", c.depth);
                    let mut dirs = samples.clone();
                    dirs.push(quad.normal);
                    dirs.push(-quad.normal);
                    // The rim of a one-sided quad's allowed directions, where its least overlap can lie.
                    let (t1, t2) = (quad.normal.any_orthonormal_vector(), quad.normal.cross(quad.normal.any_orthonormal_vector()));
                    dirs.extend((0..720).map(|i| { let a = i as f64 * std::f64::consts::PI / 360.0; t1 * a.cos() + t2 * a.sin() }));
                    for d in dirs {
                        if !two_sided && d.dot(quad.normal) < 0.0 { continue; }
                        let o = overlap_pts(&p, &pose, &quad.corners, d);
                        prop_assert!(o >= c.depth - 1e-9 * size, "direction {d:?} overlaps only {o} < depth {}", c.depth);
                    }
                    if !two_sided { prop_assert!(c.normal.dot(quad.normal) >= -1e-9 && h > 0.0); }
                }
                None => {
                    // Apart per parry, or a one-sided quad with the centre behind it.
                    prop_assert!(pen < 1e-9 * size || (!two_sided && h <= 0.0), "parry finds depth {pen}, we none (h = {h})");
                }
            }
        }

        #[test]
        fn pipe_agrees_with_parry_cylinder(p in shape(), q in rotation(), axis in unit(), ang in 0.0f64..6.3, gap in -0.3f64..0.2) {
            let r = 0.6;
            let size = p.size();
            let len = 40.0 * size.max(r);
            let start = DVec3::new(0.2, -0.1, 0.3);
            let pipe = Cylinder::new(start, axis, r, len, false);
            let (t1, t2) = (axis.any_orthonormal_vector(), axis.cross(axis.any_orthonormal_vector()));
            let radial = t1 * ang.cos() + t2 * ang.sin();
            let centre = start + axis * (0.5 * len) + radial * (r + p.bounding_radius() * (0.6 + gap));
            let pose = Pose::new(centre, q);
            let cyl_pose = Pose::new(start + axis * (0.5 * len), DQuat::from_rotation_arc(DVec3::Y, axis));
            let oracle = query::contact(&pose.to_parry(), &p.to_parry(), &cyl_pose.to_parry(), &ParryCylinder::new(0.5 * len, r), 0.0).unwrap();
            let ours = SurfaceShape::Cylinder(pipe).polyhedron_contact(&p, &pose);
            let eps = 1e-4 * size; // EPA on a curved support map converges to a tolerance only
            match (oracle, ours) {
                (Some(o), Some(c)) if o.dist < -eps => {
                    prop_assert!(angle_deg(c.normal, -o.normal1) < 5.0, "normal {:?} vs {:?}", c.normal, -o.normal1);
                    prop_assert!((c.depth + o.dist).abs() < (0.05 * -o.dist).max(1e-6 * size), "depth {} vs {}", c.depth, -o.dist);
                }
                (Some(o), None) => prop_assert!(o.dist > -eps, "parry depth {}", -o.dist),
                (None, Some(c)) => prop_assert!(c.depth < eps, "parry none, ours {}", c.depth),
                (Some(o), Some(c)) if o.dist > eps => prop_assert!(false, "parry gap {}, ours {}", o.dist, c.depth),
                _ => {}
            }
        }

        #[test]
        fn drum_depth_is_the_deepest_vertex_overlap(p in shape(), q in rotation(), ang in 0.0f64..6.3, gap in -0.3f64..0.3) {
            let r = 3.0;
            let drum = Cylinder::new(DVec3::ZERO, DVec3::Z, r, 10.0, true);
            let radial = DVec3::new(ang.cos(), ang.sin(), 0.0);
            let pose = Pose::new(DVec3::Z * 5.0 + radial * (r - p.bounding_radius() * (0.6 + gap)), q);
            let deepest = p.vertices().iter().map(|v| pose.to_world(*v).truncate().length() - r).fold(f64::NEG_INFINITY, f64::max);
            match drum.polyhedron_contact(&p, &pose) {
                Some(c) => {
                    prop_assert!((c.depth - deepest).abs() < 1e-12 * r);
                    prop_assert!(c.normal.dot(-radial) > 0.5 && c.normal.z.abs() < 1e-12);
                }
                None => prop_assert!(deepest <= 0.0),
            }
        }
    }
}

/// Large hulls go to parry3d through the dispatcher; the fast path agrees with it there too.
#[test]
fn large_hulls_use_gjk_and_agree_with_the_fast_path() {
    let mut s = 5u64;
    let mut r = move || {
        s ^= s << 13;
        s ^= s >> 7;
        s ^= s << 17;
        (s >> 11) as f64 / (1u64 << 53) as f64 - 0.5
    };
    let ball = Polyhedron::from_points(&(0..40).map(|_| DVec3::new(r(), r(), r()).normalize()).collect::<Vec<_>>()).unwrap();
    assert!(ball.edges().len().pow(2) > tumble_geom::SAT_MAX_EDGE_PAIRS);
    let mut found = 0;
    for k in 0..200 {
        let q = DQuat::from_xyzw(r(), r(), r(), r()).normalize();
        let pa = Pose::new(DVec3::new(r(), r(), r()).normalize() * (1.2 + 0.8 * r()), q);
        let via = polyhedron_polyhedron(&ball, &pa, &ball, &Pose::IDENTITY);
        let sat = polyhedron_polyhedron_sat(&ball, &pa, &ball, &Pose::IDENTITY, &mut SeparationCache::default());
        match (via, sat) {
            (Some(g), Some(c)) => {
                found += 1;
                assert_eq!(g.feature, tumble_geom::ContactFeature::Gjk);
                assert!((g.depth - c.depth).abs() <= (0.05 * c.depth).max(1e-6f64), "case {k}: {} vs {}", g.depth, c.depth);
            }
            (None, None) => {}
            (g, c) => assert!(g.map_or(0.0, |g| g.depth).max(c.map_or(0.0, |c| c.depth)) < 1e-6, "case {k}: {g:?} vs {c:?}"),
        }
    }
    assert!(found > 20, "{found}");
}
