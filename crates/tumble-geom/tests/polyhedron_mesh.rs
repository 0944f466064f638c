//! Polyhedra against triangle meshes: a box as 12 triangles and as 108 meets a polyhedron as
//! the same box of six quads does, face by face, whatever the triangulation, from outside
//! (ridges and corners) and from inside (a container's valleys); a sheet as the quad it tiles.

use tumble_geom::{
    DEFAULT_CURVATURE, DQuat, DVec3, MeshWall, Polyhedron, Pose, Quad, SurfaceShape, TriangleMesh, VolumeContact, box_triangles_subdivided,
};

/// The six faces of the unit box as quads whose normals point out (`outward`) or in.
fn box_quads(outward: bool) -> Vec<SurfaceShape> {
    let centre = DVec3::splat(0.5);
    let mut quads = Vec::new();
    for axis in 0..3 {
        for side in [0.0, 1.0] {
            let (u, v) = ((axis + 1) % 3, (axis + 2) % 3);
            let corner = |a: f64, b: f64| {
                let mut p = DVec3::ZERO;
                p[axis] = side;
                p[u] = a;
                p[v] = b;
                p
            };
            let mut c = [corner(0.0, 0.0), corner(1.0, 0.0), corner(1.0, 1.0), corner(0.0, 1.0)];
            let q = Quad::new(c, false);
            if (q.normal.dot(c[0] - centre) > 0.0) != outward {
                c.reverse();
            }
            quads.push(SurfaceShape::Quad(Quad::new(c, false)));
        }
    }
    quads
}

fn box_mesh(n: usize, outward: bool) -> MeshWall {
    let (v, mut t) = box_triangles_subdivided(DVec3::ZERO, DVec3::ONE, n);
    if !outward {
        t.iter_mut().for_each(|tri| tri.swap(1, 2));
    }
    MeshWall::new(TriangleMesh::new(&v, &t, DEFAULT_CURVATURE).unwrap().0, 0.3, 0)
}

/// What the linear law makes of a contact's corner and edge loads: Σ w δ n, Σ w δ (p − x) × n
/// and Σ w δ² (the edges' split into pieces does not change them).
fn point_loads(c: &VolumeContact, x: DVec3) -> (DVec3, DVec3, f64) {
    c.points.iter().fold((DVec3::ZERO, DVec3::ZERO, 0.0), |(f, t, e), p| {
        (f + p.normal * (p.weight * p.depth), t + (p.point - x).cross(p.normal) * (p.weight * p.depth), e + p.weight * p.depth * p.depth)
    })
}

fn compare(a: &VolumeContact, b: &VolumeContact, x: DVec3, scale: f64, what: &str) {
    let close = |p: f64, q: f64, s: f64| (p - q).abs() <= 1e-9 * s;
    let near = |p: DVec3, q: DVec3, s: f64| (p - q).length() <= 1e-9 * s;
    let (s2, s3) = (scale * scale, scale * scale * scale);
    assert!(close(a.volume, b.volume, s3), "{what}: volume {} against {}", a.volume, b.volume);
    assert!(near(a.push, b.push, s2), "{what}: push {} against {}", a.push, b.push);
    assert!(near(a.turn_a, b.turn_a, s3), "{what}: turn {} against {}", a.turn_a, b.turn_a);
    assert!(
        close(a.area, b.area, s2) && close(a.depth, b.depth, scale),
        "{what}: area {} against {}, depth {} against {}",
        a.area,
        b.area,
        a.depth,
        b.depth
    );
    assert!(near(a.point, b.point, scale), "{what}: point {} against {}", a.point, b.point);
    let (fa, ta, ea) = point_loads(a, x);
    let (fb, tb, eb) = point_loads(b, x);
    // A corner's depth is a smooth minimum over the planes near it; a quad's far sides add terms
    // of exp(−distance / τ) that a patch's nearby outline leaves out (1e-9 at 20 τ).
    let near = |p: DVec3, q: DVec3, s: f64| (p - q).length() <= 1e-7 * s;
    let close = |p: f64, q: f64, s: f64| (p - q).abs() <= 1e-7 * s;
    assert!(near(fa, fb, scale) && near(ta, tb, s2) && close(ea, eb, s2), "{what}: corner and edge loads {fa} {ta} {ea} against {fb} {tb} {eb}");
}

fn random(seed: &mut u64) -> f64 {
    *seed ^= *seed << 13;
    *seed ^= *seed >> 7;
    *seed ^= *seed << 17;
    (*seed >> 11) as f64 / (1u64 << 53) as f64
}

/// Random poses of `poly` near the box's surface (outside or inside): each contact of the quads
/// has one of each mesh, with the same normal and the same sums. Returns the contacts compared
/// and how many poses touched two or three faces.
fn check_box(poly: &Polyhedron, outward: bool) -> (usize, usize) {
    let quads = box_quads(outward);
    let meshes = [box_mesh(1, outward), box_mesh(3, outward)];
    let rb = poly.bounding_radius();
    let mut seed = 0x2545_f491_4f6c_dd1du64;
    let (mut compared, mut several) = (0, 0);
    let mut found = Vec::new();
    for trial in 0..400 {
        // The centre within the bounding radius of the surface, on the side the walls push towards.
        let mut x = DVec3::new(random(&mut seed), random(&mut seed), random(&mut seed)) * (1.0 + rb) - DVec3::splat(0.5 * rb);
        let axis = (random(&mut seed) * 3.0) as usize % 3;
        let depth = (random(&mut seed) - 0.3) * rb;
        x[axis] = if random(&mut seed) < 0.5 { -depth } else { 1.0 + depth };
        if !outward {
            x = x.clamp(DVec3::splat(0.02), DVec3::splat(0.98));
            for k in 0..3 {
                if random(&mut seed) < 0.3 {
                    x[k] = if x[k] < 0.5 { 0.9 * rb * random(&mut seed) } else { 1.0 - 0.9 * rb * random(&mut seed) };
                }
            }
        }
        let turn = DQuat::from_axis_angle(
            DVec3::new(random(&mut seed) - 0.5, random(&mut seed) - 0.5, random(&mut seed) - 0.5).normalize(),
            6.0 * random(&mut seed),
        );
        let pose = Pose::new(x, turn);
        let expected: Vec<VolumeContact> = quads.iter().filter_map(|q| q.polyhedron_volume(poly, &pose)).collect();
        several += (expected.len() > 1) as usize;
        for mesh in &meshes {
            mesh.polyhedron_volumes(poly, &pose, &mut found);
            assert_eq!(found.len(), expected.len(), "trial {trial} at {x}: {} patch contacts against {} quads", found.len(), expected.len());
            for e in &expected {
                // The nearest in normal and depth: a polyhedron wedged into an edge can meet both faces alike.
                let miss = |f: &VolumeContact| (f.normal - e.normal).length() + (f.depth - e.depth).abs() / rb;
                let f = &found.iter().min_by(|a, b| miss(&a.contact).total_cmp(&miss(&b.contact))).expect("as many contacts as quads").contact;
                compare(f, e, x, poly.size(), &format!("trial {trial} at {x}"));
                compared += 1;
            }
        }
    }
    (compared, several)
}

#[test]
fn a_triangulated_box_meets_a_polyhedron_as_its_six_quads_do() {
    for (name, poly) in
        [("cube", Polyhedron::cube(0.2)), ("tetrahedron", Polyhedron::tetrahedron(0.25)), ("dodecahedron", Polyhedron::dodecahedron(0.1))]
    {
        for outward in [true, false] {
            let (compared, several) = check_box(&poly, outward);
            println!("{name}, {}: {compared} contacts compared, {several} poses on two or three faces", if outward { "outside" } else { "inside" });
            assert!(compared > 300, "{name}: only {compared} contacts");
            assert!(several > 10, "{name}: only {several} poses touch more than one face");
        }
    }
}

#[test]
fn a_cube_lying_across_a_sheets_diagonal_feels_one_contact_as_on_the_quad() {
    // Two triangles and the quad they tile, both two-sided; the cube's corners sit on the diagonal.
    let c = [DVec3::ZERO, DVec3::X, DVec3::new(1.0, 1.0, 0.0), DVec3::Y];
    let sheet = MeshWall::new(TriangleMesh::new(&c, &[[0, 1, 2], [0, 2, 3]], DEFAULT_CURVATURE).unwrap().0, 0.3, 0);
    let quad = SurfaceShape::Quad(Quad::new(c, true));
    let cube = Polyhedron::cube(0.2);
    let mut found = Vec::new();
    for (x, turn) in [
        (DVec3::new(0.5, 0.5, 0.09), DQuat::IDENTITY),
        (DVec3::new(0.4, 0.4, -0.095), DQuat::IDENTITY),
        (DVec3::new(0.3, 0.32, 0.1), DQuat::from_rotation_x(0.3)),
        (DVec3::new(0.5, 0.5, 0.12), DQuat::from_axis_angle(DVec3::new(1.0, 1.0, 0.0).normalize(), 0.9)),
    ] {
        let pose = Pose::new(x, turn);
        let e = quad.polyhedron_volume(&cube, &pose).expect("the cube touches the quad");
        sheet.polyhedron_volumes(&cube, &pose, &mut found);
        assert_eq!(found.len(), 1, "at {x}");
        compare(&found[0].contact, &e, x, 0.2, &format!("at {x}"));
        let shares = &found[0].triangles;
        assert!((shares.iter().map(|s| s.1).sum::<f64>() - 1.0).abs() < 1e-12, "{shares:?}");
    }
    // Centred on the diagonal face-on, the cube overlaps both triangles alike; shifted off it, by
    // the areas of its footprint on each side (a 0.2 square at (0.55, 0.45): 0.035 of 0.04 under [0, 1, 2]).
    for (x, under_first) in [(DVec3::new(0.5, 0.5, 0.09), 0.5), (DVec3::new(0.55, 0.45, 0.09), 0.5 + 0.5 * (1.0 - 0.5 * 0.5))] {
        sheet.polyhedron_volumes(&cube, &Pose::new(x, DQuat::IDENTITY), &mut found);
        let share = found[0].triangles.iter().find(|s| s.0 == 0).map_or(0.0, |s| s.1);
        assert!((share - under_first).abs() < 1e-9, "at {x}: {:?}, expected {under_first} under triangle 0", found[0].triangles);
    }
}

#[test]
fn a_moved_mesh_meets_a_polyhedron_as_the_mesh_with_moved_vertices_does() {
    let (v, t) = box_triangles_subdivided(DVec3::ZERO, DVec3::ONE, 2);
    let mesh = TriangleMesh::new(&v, &t, DEFAULT_CURVATURE).unwrap().0;
    let (rotation, shift) = (DQuat::from_axis_angle(DVec3::new(1.0, 2.0, 2.0).normalize(), 0.7), DVec3::new(0.3, -0.2, 0.1));
    let moved = MeshWall::new(mesh.clone(), 0.3, 0).moved(DVec3::ZERO, rotation, shift);
    let direct = MeshWall::new(mesh.transformed(|p| rotation * p + shift, false), 0.3, 0);
    let cube = Polyhedron::cube(0.2);
    let (mut a, mut b) = (Vec::new(), Vec::new());
    let mut seed = 99u64;
    let mut touched = 0;
    for _ in 0..200 {
        let local = DVec3::new(random(&mut seed) * 1.3 - 0.15, random(&mut seed) * 1.3 - 0.15, -0.1 + 0.1 * random(&mut seed));
        let pose = Pose::new(rotation * local + shift, DQuat::from_rotation_z(3.0 * random(&mut seed)) * rotation);
        moved.polyhedron_volumes(&cube, &pose, &mut a);
        direct.polyhedron_volumes(&cube, &pose, &mut b);
        assert_eq!(a.len(), b.len());
        for (pa, pb) in a.iter().zip(&b) {
            assert_eq!(pa.patch, pb.patch);
            assert_eq!(pa.triangles.len(), pb.triangles.len());
            for (ta, tb) in pa.triangles.iter().zip(&pb.triangles) {
                assert!(ta.0 == tb.0 && (ta.1 - tb.1).abs() < 1e-9, "shares {:?} against {:?}", pa.triangles, pb.triangles);
            }
            compare(&pa.contact, &pb.contact, pose.position, 0.2, "moved");
        }
        touched += !a.is_empty() as usize;
    }
    assert!(touched > 50, "{touched}");
}
