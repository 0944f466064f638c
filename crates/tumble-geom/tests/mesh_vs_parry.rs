//! The sphere–mesh contacts against parry3d's closest point on a triangle mesh: whatever the
//! ownership rule drops, the deepest contact a sphere feels is the surface's closest point.

use parry3d_f64::query::PointQuery;
use parry3d_f64::shape::TriMesh;
use tumble_geom::{DEFAULT_CURVATURE, DVec3, TriangleMesh, box_triangles_subdivided};

/// A deterministic stream of numbers in [0, 1).
fn uniform(seed: u64) -> impl FnMut() -> f64 {
    let mut s = seed;
    move || {
        s = s.wrapping_mul(6364136223846793005).wrapping_add(1442695040888963407);
        (s >> 11) as f64 / (1u64 << 53) as f64
    }
}

/// A bumpy sheet over [0, 1]²: an n × n height field with random heights (ridges, valleys and
/// saddles everywhere), normals up.
fn bumpy_sheet(n: usize, amplitude: f64, seed: u64) -> (Vec<DVec3>, Vec<[u32; 3]>) {
    let mut u = uniform(seed);
    let mut v = Vec::new();
    for j in 0..=n {
        for i in 0..=n {
            v.push(DVec3::new(i as f64 / n as f64, j as f64 / n as f64, amplitude * (u() - 0.5)));
        }
    }
    let at = |i: usize, j: usize| (j * (n + 1) + i) as u32;
    let mut t = Vec::new();
    for j in 0..n {
        for i in 0..n {
            t.push([at(i, j), at(i + 1, j), at(i + 1, j + 1)]);
            t.push([at(i, j), at(i + 1, j + 1), at(i, j + 1)]);
        }
    }
    (v, t)
}

fn check(name: &str, v: &[DVec3], t: &[[u32; 3]], centres: impl Iterator<Item = DVec3>, r: f64) {
    let ours = TriangleMesh::new(v, t, DEFAULT_CURVATURE).unwrap().0;
    let oracle = TriMesh::new(v.to_vec(), t.to_vec()).unwrap();
    let (mut touching, mut several) = (0, 0);
    for x in centres {
        let projection = oracle.project_local_point(x, false);
        let distance = (x - projection.point).length();
        let contacts = ours.sphere_contacts_all(x, r, 0.0);
        if distance >= r * (1.0 - 1e-9) {
            assert!(contacts.iter().all(|c| c.overlap < 1e-9 * r), "{name}: centre {x} is {distance} from the surface: {contacts:?}");
            continue;
        }
        touching += 1;
        several += (contacts.len() > 1) as usize;
        let deepest = contacts.iter().map(|c| c.overlap).fold(f64::NEG_INFINITY, f64::max);
        assert!(
            (deepest - (r - distance)).abs() < 1e-9 * r,
            "{name}: centre {x}: deepest overlap {deepest}, parry's closest point gives {}: {contacts:?}",
            r - distance
        );
        for c in &contacts {
            // Every contact is a real point of the surface within the sphere.
            let p = oracle.project_local_point(c.point, false).point;
            assert!((p - c.point).length() < 1e-9, "{name}: contact point {} off the surface", c.point);
            assert!(c.overlap <= r - distance + 1e-9 * r);
        }
    }
    println!("{name}: {touching} touching spheres, {several} with more than one contact");
    assert!(touching > 100, "{name}: the test must touch the surface");
}

#[test]
fn the_deepest_contact_is_parrys_closest_point_on_a_bumpy_sheet() {
    for (n, amplitude) in [(6, 0.05), (12, 0.2)] {
        let (v, t) = bumpy_sheet(n, amplitude, n as u64);
        let mut u = uniform(100 + n as u64);
        let r = 0.08;
        // Above the sheet (its normals' side), away from its open rim.
        let centres = (0..600).map(move |_| DVec3::new(0.15 + 0.7 * u(), 0.15 + 0.7 * u(), (u() - 0.3) * 0.25));
        check(&format!("sheet {n}×{n}, amplitude {amplitude}"), &v, &t, centres, r);
    }
}

#[test]
fn the_deepest_contact_is_parrys_closest_point_outside_a_triangulated_box() {
    let (v, t) = box_triangles_subdivided(DVec3::ZERO, DVec3::ONE, 3);
    let mut u = uniform(5);
    let r = 0.1;
    let centres = (0..2000)
        .map(move |_| DVec3::new(u(), u(), u()) * 1.3 - DVec3::splat(0.15))
        .filter(|x| !(x.cmpge(DVec3::ZERO).all() && x.cmple(DVec3::ONE).all()));
    check("box 3×3", &v, &t, centres, r);
}
