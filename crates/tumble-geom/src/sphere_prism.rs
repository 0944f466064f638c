use crate::surface::contact_from_closest;
use crate::{DVec3, Polyhedron, Pose, Quad, SurfaceContact};
use std::sync::Arc;

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
    /// The prism as a polyhedron (hulled once, shared by every pose) and where its body frame
    /// sits now; `None` for a degenerate prism, which polyhedra then never touch.
    pub hull: Option<Arc<Polyhedron>>,
    pub hull_pose: Pose,
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
        let hull = Polyhedron::from_points(&verts);
        // The hull's body frame sits at its centre of mass: place it back where the corners are.
        let hull_pose = hull.as_ref().map_or(Pose::IDENTITY, |h| h.input_to_body().relative(&Pose::IDENTITY));
        Prism { faces, centre, bound, axis_point, axis, inner, hull: hull.map(Arc::new), hull_pose }
    }

    /// The vertices, for drawing.
    pub fn corners(&self) -> impl Iterator<Item = [DVec3; 4]> + '_ {
        self.faces.iter().map(|f| f.corners)
    }

    /// Contact of a convex polyhedron at `pose` with this prism (normal from the prism to the
    /// polyhedron): the prism's hull goes to the polyhedron–polyhedron routine.
    pub fn polyhedron_contact(&self, poly: &Polyhedron, pose: &Pose) -> Option<crate::PolyContact> {
        if (pose.position - self.centre).length() > self.bound + poly.bounding_radius() {
            return None;
        }
        crate::polyhedron_polyhedron(poly, pose, self.hull.as_deref()?, &self.hull_pose)
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
    use crate::DQuat;

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

    /// A turned lifter keeps its hull built once and posed: the contact equals that of a prism
    /// built from the turned corners (what the hull was rebuilt from on every call before).
    #[test]
    fn a_moved_prism_touches_polyhedra_as_one_built_where_it_moved() {
        let p = cube();
        let (pivot, rotation, shift) = (DVec3::new(0.0, 0.0, 3.0), DQuat::from_axis_angle(DVec3::new(0.3, 0.4, 0.8).normalize(), 0.7), DVec3::X);
        let crate::SurfaceShape::Prism(moved) = crate::SurfaceShape::Prism(Box::new(p.clone())).moved(pivot, rotation, shift) else { unreachable!() };
        let pt = |v: DVec3| pivot + rotation * (v - pivot) + shift;
        let rebuilt = Prism::new(p.faces[4].corners.map(pt), p.faces[5].corners.map(pt), pt(p.axis_point), rotation * p.axis);
        let small = crate::Polyhedron::cube(0.2);
        let pose = crate::Pose::new(pt(DVec3::new(0.5, 1.07, 0.55)), rotation * DQuat::from_rotation_z(0.2));
        let (a, b) = (moved.polyhedron_contact(&small, &pose).unwrap(), rebuilt.polyhedron_contact(&small, &pose).unwrap());
        assert!(
            (a.normal - b.normal).length() < 1e-12 && (a.depth - b.depth).abs() < 1e-12 && (a.point - b.point).length() < 1e-12,
            "{a:?} vs {b:?}"
        );
    }
}
