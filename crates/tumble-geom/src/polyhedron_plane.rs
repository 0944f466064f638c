use crate::polyhedron_polyhedron::{Buf, reduce_to_four};
use crate::{ContactFeature, ManifoldPoint, Plane, PolyContact, Polyhedron, Pose};

impl Plane {
    /// Contact of a convex polyhedron (A at `pose`) with this plane (B): the vertices below it.
    ///
    /// Normal = the plane normal, depth = the deepest vertex's distance below the plane, manifold
    /// = up to four of the vertices below (the deepest and the three spanning the largest area),
    /// each halfway through its own overlap; `point` is their depth-weighted mean. Exact: a
    /// convex body leaves a half-space fastest along its normal.
    ///
    /// ```
    /// use tumble_geom::{DVec3, Plane, Polyhedron, Pose};
    /// let floor = Plane::new(DVec3::ZERO, DVec3::Z);
    /// let c = floor.polyhedron_contact(&Polyhedron::cube(1.0), &Pose::from_position(DVec3::new(0.0, 0.0, 0.48))).unwrap();
    /// assert_eq!(c.normal, DVec3::Z);
    /// assert!((c.depth - 0.02).abs() < 1e-12);
    /// assert_eq!(c.manifold().len(), 4);
    /// assert!((c.point - DVec3::new(0.0, 0.0, -0.01)).length() < 1e-12);
    /// ```
    pub fn polyhedron_contact(&self, poly: &Polyhedron, pose: &Pose) -> Option<PolyContact> {
        if self.signed_distance(pose.position) >= poly.bounding_radius() {
            return None;
        }
        // In the body frame: the plane's normal and height there.
        let n = pose.unrotate(self.normal);
        let h = self.signed_distance(pose.position);
        let mut pts: Buf<ManifoldPoint> = Buf::new();
        let mut depth = 0.0f64;
        for v in poly.vertices() {
            let d = -(h + n.dot(*v));
            if d > 0.0 {
                depth = depth.max(d);
                pts.push(ManifoldPoint { point: pose.to_world(*v) + self.normal * (0.5 * d), depth: d });
            }
        }
        if pts.is_empty() {
            return None;
        }
        let chosen = reduce_to_four(&pts, self.normal);
        Some(PolyContact::from_manifold(self.normal, depth, &chosen, ContactFeature::Surface))
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::DVec3;
    use glam::DQuat;

    #[test]
    fn tilted_cube_touches_with_one_corner() {
        let floor = Plane::new(DVec3::new(0.0, 0.0, 1.0), DVec3::Z);
        let q = DQuat::from_rotation_arc(DVec3::ONE.normalize(), -DVec3::Z);
        let pose = Pose::new(DVec3::new(0.3, 0.2, 1.0 + 0.5 * 3f64.sqrt() - 0.01), q);
        let c = floor.polyhedron_contact(&Polyhedron::cube(1.0), &pose).unwrap();
        assert!((c.depth - 0.01).abs() < 1e-12);
        assert_eq!(c.manifold().len(), 1);
        assert!((c.point - DVec3::new(0.3, 0.2, 0.995)).length() < 1e-12);
        let lifted = Pose { position: pose.position + DVec3::Z * 0.02, ..pose };
        assert!(floor.polyhedron_contact(&Polyhedron::cube(1.0), &lifted).is_none());
    }
}
