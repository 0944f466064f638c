use crate::{ContactFeature, DVec3, PolyContact, Polyhedron, Pose};

/// The point of the polyhedron (body frame) closest to the body point `p`, with its feature.
///
/// Inside the polyhedron the answer is the foot on the nearest face (the face of largest
/// signed distance); outside it is the foot on a face if that foot lies inside the face,
/// otherwise the closest point on an edge (vertices are edge ends).
pub fn closest_point_on_polyhedron(poly: &Polyhedron, p: DVec3) -> (DVec3, ContactFeature) {
    let faces = poly.faces();
    let verts = poly.vertices();
    let mut best = (f64::NEG_INFINITY, 0usize);
    for (fi, f) in faces.iter().enumerate() {
        let d = f.normal.dot(p) - f.offset;
        if d > best.0 {
            best = (d, fi);
        }
    }
    if best.0 <= 0.0 {
        let f = &faces[best.1];
        return (p - f.normal * best.0, ContactFeature::FaceB(best.1 as u32));
    }
    // Outside: a face whose plane p is in front of and whose foot lies inside the face.
    for (fi, f) in faces.iter().enumerate() {
        let d = f.normal.dot(p) - f.offset;
        if d <= 0.0 {
            continue;
        }
        let foot = p - f.normal * d;
        let n = f.vertices.len();
        let inside = (0..n).all(|k| {
            let (a, b) = (verts[f.vertices[k] as usize], verts[f.vertices[(k + 1) % n] as usize]);
            (b - a).cross(foot - a).dot(f.normal) >= 0.0
        });
        if inside {
            return (foot, ContactFeature::FaceB(fi as u32));
        }
    }
    // Edge or vertex region: the closest point over the edges of the faces p is in front of.
    let mut closest = (f64::INFINITY, DVec3::ZERO, ContactFeature::VertexB(0));
    for (ei, e) in poly.edges().iter().enumerate() {
        let in_front = e.faces.iter().any(|&f| faces[f as usize].normal.dot(p) > faces[f as usize].offset);
        if !in_front {
            continue;
        }
        let (a, b) = (verts[e.vertices[0] as usize], verts[e.vertices[1] as usize]);
        let ab = b - a;
        let t = ((p - a).dot(ab) / ab.length_squared()).clamp(0.0, 1.0);
        let q = a + ab * t;
        let d2 = (p - q).length_squared();
        if d2 < closest.0 {
            let feature = if t <= 0.0 {
                ContactFeature::VertexB(e.vertices[0])
            } else if t >= 1.0 {
                ContactFeature::VertexB(e.vertices[1])
            } else {
                ContactFeature::EdgeB(ei as u32)
            };
            closest = (d2, q, feature);
        }
    }
    (closest.1, closest.2)
}

/// Contact of a sphere (A: `centre`, `radius`, world frame) with a convex polyhedron (B at `pose`).
///
/// Normal from the polyhedron to the sphere centre (from the nearest face when the centre is
/// inside), depth = radius − distance (radius + distance inside), the point halfway through the
/// overlap. `None` when the sphere does not overlap.
///
/// ```
/// use tumble_geom::{DVec3, Polyhedron, Pose, sphere_polyhedron};
/// let cube = Polyhedron::cube(1.0);
/// // Over the +x face, then beyond the (+x, +y) edge.
/// let c = sphere_polyhedron(DVec3::new(0.55, 0.1, 0.0), 0.1, &cube, &Pose::IDENTITY).unwrap();
/// assert!((c.normal - DVec3::X).length() < 1e-12 && (c.depth - 0.05).abs() < 1e-12);
/// let c = sphere_polyhedron(DVec3::new(0.55, 0.55, 0.0), 0.1, &cube, &Pose::IDENTITY).unwrap();
/// assert!((c.normal - DVec3::new(1.0, 1.0, 0.0).normalize()).length() < 1e-12);
/// assert!((c.depth - (0.1 - 0.05 * 2f64.sqrt())).abs() < 1e-12);
/// ```
pub fn sphere_polyhedron(centre: DVec3, radius: f64, poly: &Polyhedron, pose: &Pose) -> Option<PolyContact> {
    let c = pose.to_body(centre);
    let rb = poly.bounding_radius() + radius;
    if c.length_squared() >= rb * rb {
        return None;
    }
    let (q, feature) = closest_point_on_polyhedron(poly, c);
    let d = c - q;
    let dist = d.length();
    let (normal, depth) = match feature {
        ContactFeature::FaceB(f) if poly.face_distance(f as usize, c) <= 0.0 => (poly.faces()[f as usize].normal, radius + dist),
        ContactFeature::FaceB(f) => (poly.faces()[f as usize].normal, radius - dist),
        _ => (d / dist, radius - dist),
    };
    (depth > 0.0).then(|| PolyContact::single(normal, depth, q - normal * (0.5 * depth), feature).transformed(pose))
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn inside_vertex_and_far_cases() {
        let cube = Polyhedron::cube(1.0);
        // Centre inside, nearest the +z face.
        let c = sphere_polyhedron(DVec3::new(0.0, 0.1, 0.4), 0.2, &cube, &Pose::IDENTITY).unwrap();
        assert!((c.normal - DVec3::Z).length() < 1e-12);
        assert!((c.depth - 0.3).abs() < 1e-12);
        // Vertex region.
        let p = DVec3::splat(0.55);
        let c = sphere_polyhedron(p, 0.1, &cube, &Pose::IDENTITY).unwrap();
        assert!((c.normal - DVec3::ONE.normalize()).length() < 1e-12);
        assert!(matches!(c.feature, ContactFeature::VertexB(_)));
        assert!(sphere_polyhedron(DVec3::splat(0.6), 0.1, &cube, &Pose::IDENTITY).is_none());
        // Posed: a translated cube.
        let pose = Pose::from_position(DVec3::new(5.0, 0.0, 0.0));
        let c = sphere_polyhedron(DVec3::new(5.0, 0.0, -0.55), 0.1, &cube, &pose).unwrap();
        assert!((c.normal + DVec3::Z).length() < 1e-12);
        assert!((c.point - DVec3::new(5.0, 0.0, -0.475)).length() < 1e-12);
    }
}
