use crate::surface::contact_from_closest;
use crate::{DVec3, Quad, SurfaceContact};

/// A convex prism with a quadrilateral cross-section (a mill lifter bar): six
/// one-sided quads with outward normals, touched as one convex body (face, edge
/// and corner regions), so a sphere at an edge gets one contact, not one per face.
#[derive(Clone, Debug, PartialEq)]
pub struct Prism {
    /// Outward faces.
    pub faces: [Quad; 6],
    /// Centre and radius of a sphere enclosing the prism (first broad-phase test).
    pub centre: DVec3,
    pub bound: f64,
    /// An axis no point of the prism comes closer to than `inner` (the drum axis for a
    /// lifter: particles nearer the axis than inner − r cannot touch it).
    pub axis_point: DVec3,
    pub axis: DVec3,
    pub inner: f64,
}

impl Prism {
    /// A prism from two quadrilateral ends `a` and `b` (corresponding corners), with the
    /// drum axis (point, unit direction) for the annulus test.
    pub fn new(a: [DVec3; 4], b: [DVec3; 4], axis_point: DVec3, axis: DVec3) -> Self {
        let verts: Vec<DVec3> = a.iter().chain(&b).copied().collect();
        let centre = verts.iter().copied().sum::<DVec3>() / 8.0;
        let bound = verts.iter().map(|v| (*v - centre).length()).fold(0.0, f64::max);
        // Nearest approach to the axis: the projection of the prism on the cross-section is the
        // hull of its projected edges, so the least distance from the axis to a projected edge
        // (the axis must not pass through the prism, as it never does for a lifter).
        let flat = |v: DVec3| {
            let d = v - axis_point;
            d - axis * d.dot(axis)
        };
        let edges = (0..4).flat_map(|k| [(a[k], a[(k + 1) % 4]), (b[k], b[(k + 1) % 4]), (a[k], b[k])]);
        let inner = edges.map(|(p, q)| crate::sphere_quad::closest_on_segment(flat(p), flat(q), DVec3::ZERO).length()).fold(f64::INFINITY, f64::min);
        let outward = |c: [DVec3; 4]| {
            let q = Quad::new(c, false);
            if q.normal.dot(centre - c[0]) > 0.0 { Quad::new([c[3], c[2], c[1], c[0]], false) } else { q }
        };
        let side = |k: usize| outward([a[k], a[(k + 1) % 4], b[(k + 1) % 4], b[k]]);
        let faces = [side(0), side(1), side(2), side(3), outward(a), outward(b)];
        Prism { faces, centre, bound, axis_point, axis, inner }
    }

    /// The vertices, for drawing.
    pub fn corners(&self) -> impl Iterator<Item = [DVec3; 4]> + '_ {
        self.faces.iter().map(|f| f.corners)
    }

    /// Contact of a convex polyhedron at `pose` with this prism (normal from the prism to the
    /// polyhedron): the prism is hulled and handed to the polyhedron–polyhedron routine.
    pub fn polyhedron_contact(&self, poly: &crate::Polyhedron, pose: &crate::Pose) -> Option<crate::PolyContact> {
        if (pose.position - self.centre).length() > self.bound + poly.bounding_radius() {
            return None;
        }
        let corners: Vec<DVec3> = self.faces[4].corners.iter().chain(&self.faces[5].corners).copied().collect();
        let hull = crate::Polyhedron::from_points(&corners)?;
        // The hull's body frame sits at its centre of mass: place it back where the corners are.
        let hull_pose = hull.input_to_body().relative(&crate::Pose::IDENTITY);
        crate::polyhedron_polyhedron(poly, pose, &hull, &hull_pose)
    }

    pub fn sphere_proximity(&self, centre: DVec3, radius: f64, reach: f64) -> Option<SurfaceContact> {
        let range = radius + reach;
        if (centre - self.centre).length_squared() > (self.bound + range) * (self.bound + range) {
            return None;
        }
        let rel = centre - self.axis_point;
        let rho2 = (rel - self.axis * rel.dot(self.axis)).length_squared();
        let near = self.inner - range;
        if near > 0.0 && rho2 < near * near {
            return None;
        }
        let h = self.faces.each_ref().map(|f| f.normal.dot(centre - f.corners[0]));
        if h.iter().any(|&x| x >= range) {
            return None; // a face separates them
        }
        if h.iter().all(|&x| x <= 0.0) {
            // Centre inside: leave by the nearest face (the least penetration).
            let k = (0..6).max_by(|&a, &b| h[a].total_cmp(&h[b])).unwrap();
            let n = self.faces[k].normal;
            let overlap = radius - h[k];
            return Some(SurfaceContact { normal: n, overlap, point: centre - n * (h[k] + 0.5 * overlap) });
        }
        // Outside: the closest point lies on a face the centre is in front of.
        let mut best: Option<(f64, DVec3, DVec3)> = None;
        for (f, &hf) in self.faces.iter().zip(&h) {
            if hf <= 0.0 {
                continue;
            }
            let p = f.closest_point(centre);
            let d2 = (centre - p).length_squared();
            if best.is_none_or(|(b, _, _)| d2 < b) {
                best = Some((d2, p, f.normal));
            }
        }
        let (_, closest, normal) = best?;
        contact_from_closest(centre, radius, reach, closest, normal)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// A unit cube [0,1]³ as a prism along z, axis far below.
    fn cube() -> Prism {
        let a = [DVec3::new(0.0, 0.0, 0.0), DVec3::new(1.0, 0.0, 0.0), DVec3::new(1.0, 1.0, 0.0), DVec3::new(0.0, 1.0, 0.0)];
        let b = a.map(|v| v + DVec3::Z);
        Prism::new(a, b, DVec3::new(0.5, -10.0, 0.0), DVec3::Z)
    }

    #[test]
    fn faces_point_outwards_and_contacts_are_single() {
        let p = cube();
        for f in &p.faces {
            assert!(f.normal.dot(p.centre - f.corners[0]) < 0.0);
        }
        // Face.
        let c = p.sphere_proximity(DVec3::new(0.5, 1.05, 0.5), 0.1, 0.0).unwrap();
        assert!((c.normal - DVec3::Y).length() < 1e-12 && (c.overlap - 0.05).abs() < 1e-12);
        // Edge (x = 1, y = 1): one contact along the diagonal.
        let c = p.sphere_proximity(DVec3::new(1.05, 1.05, 0.5), 0.1, 0.0).unwrap();
        assert!((c.normal - DVec3::new(1.0, 1.0, 0.0).normalize()).length() < 1e-12);
        assert!((c.overlap - (0.1 - 0.05 * 2f64.sqrt())).abs() < 1e-12);
        // Corner.
        let c = p.sphere_proximity(DVec3::new(-0.04, -0.04, -0.04), 0.1, 0.0).unwrap();
        assert!((c.normal + DVec3::ONE.normalize()).length() < 1e-12);
        // Inside, nearest the y = 1 face.
        let c = p.sphere_proximity(DVec3::new(0.5, 0.9, 0.5), 0.1, 0.0).unwrap();
        assert!((c.normal - DVec3::Y).length() < 1e-12 && (c.overlap - 0.2).abs() < 1e-12);
        // Nearest approach to the axis: the middle of the y = 0 face, not a corner.
        assert!((p.inner - 10.0).abs() < 1e-12, "{}", p.inner);
        // Far away, and inside the annulus.
        assert!(p.sphere_proximity(DVec3::new(0.5, 1.2, 0.5), 0.1, 0.0).is_none());
        assert!(p.sphere_proximity(DVec3::new(0.5, -0.5, 0.5), 0.1, 0.0).is_none());
    }

    #[test]
    fn a_cube_pressed_into_the_top_face_is_pushed_out_along_it() {
        let p = cube();
        let small = crate::Polyhedron::cube(0.2);
        // Centred over the y = 1 face, 0.03 into it.
        let pose = crate::Pose::from_position(DVec3::new(0.5, 1.07, 0.5));
        let c = p.polyhedron_contact(&small, &pose).unwrap();
        assert!((c.normal - DVec3::Y).length() < 1e-9, "{:?}", c.normal);
        assert!((c.depth - 0.03).abs() < 1e-9, "{}", c.depth);
        assert!(p.polyhedron_contact(&small, &crate::Pose::from_position(DVec3::new(0.5, 1.2, 0.5))).is_none());
    }
}
