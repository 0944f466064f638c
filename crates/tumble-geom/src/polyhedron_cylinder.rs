use crate::polyhedron::planar_hull;
use crate::polyhedron_polyhedron::{Buf, reduce_to_four};
use crate::{ContactFeature, Cylinder, DVec3, ManifoldPoint, PolyContact, Polyhedron, Pose};

impl Cylinder {
    /// Contact of a convex polyhedron (A at `pose`) with this cylinder wall (B).
    ///
    /// As for spheres, the contact counts only while the polyhedron's centre projects onto the
    /// axis within the length (end caps are separate walls).
    ///
    /// - Inside (drum shell): the vertices beyond the radius penetrate; the normal points from
    ///   the shell towards the axis through the deepest vertex, the manifold is up to four of the
    ///   vertices outside, each with its own radial overlap.
    /// - Outside (pipe): the polyhedron's shadow on the plane across the axis (the 2D hull of
    ///   its vertices) against the circle: normal radial from the axis through the shadow's
    ///   point nearest the axis (against the nearest edge's outward normal when the axis
    ///   pierces the shadow: that edge has to clear the circle), depth = radius − distance, one point lifted back onto the polyhedron. Exact for
    ///   radial overlaps; an overlap that would be shorter along the axis is not looked for.
    ///
    /// ```
    /// use tumble_geom::{Cylinder, DVec3, Polyhedron, Pose};
    /// let drum = Cylinder::new(DVec3::ZERO, DVec3::Z, 1.0, 2.0, true);
    /// let c = drum.polyhedron_contact(&Polyhedron::cube(0.2), &Pose::from_position(DVec3::new(0.91, 0.0, 1.0))).unwrap();
    /// assert!((c.normal + DVec3::X).length() < 1e-12);
    /// assert!((c.depth - (0.1f64.hypot(1.01) - 1.0)).abs() < 1e-12);
    /// let pipe = Cylinder { inside: false, ..drum };
    /// let c = pipe.polyhedron_contact(&Polyhedron::cube(0.2), &Pose::from_position(DVec3::new(0.0, 1.09, 1.0))).unwrap();
    /// assert!((c.normal - DVec3::Y).length() < 1e-12 && (c.depth - 0.01).abs() < 1e-12);
    /// ```
    pub fn polyhedron_contact(&self, poly: &Polyhedron, pose: &Pose) -> Option<PolyContact> {
        let rel = pose.position - self.point;
        let s = rel.dot(self.axis);
        if s < 0.0 || s > self.length {
            return None;
        }
        let rho = (rel - self.axis * s).length();
        let rb = poly.bounding_radius();
        if (self.inside && rho + rb <= self.radius) || (!self.inside && rho - rb >= self.radius) {
            return None;
        }
        let world: Buf<DVec3> = poly.vertices().iter().map(|v| pose.to_world(*v)).collect();
        let radial: Buf<DVec3> = world.iter().map(|w| (*w - self.point) - self.axis * (*w - self.point).dot(self.axis)).collect();
        if self.inside { self.drum_contact(&world, &radial) } else { self.pipe_contact(&world, &radial, poly.size()) }
    }

    fn drum_contact(&self, world: &[DVec3], radial: &[DVec3]) -> Option<PolyContact> {
        let mut pts: Buf<ManifoldPoint> = Buf::new();
        let (mut depth, mut sum) = (0.0f64, DVec3::ZERO);
        for (w, r) in world.iter().zip(radial) {
            let len = r.length();
            let d = len - self.radius;
            if d > 0.0 {
                let inward = -*r / len;
                pts.push(ManifoldPoint { point: *w + inward * (0.5 * d), depth: d });
                depth = depth.max(d);
                sum += inward * d;
            }
        }
        if pts.is_empty() {
            return None;
        }
        let normal = sum.normalize();
        let chosen = reduce_to_four(&pts, normal);
        Some(PolyContact::from_manifold(normal, depth, &chosen, ContactFeature::Surface))
    }

    fn pipe_contact(&self, world: &[DVec3], radial: &[DVec3], size: f64) -> Option<PolyContact> {
        let idx: Buf<u32> = (0..radial.len() as u32).collect();
        let hull = planar_hull(radial, &idx, self.axis, size)?;
        let m = hull.len();
        // Signed distances of the axis from the shadow's edge lines (CCW about the axis).
        let mut nearest_line = (f64::NEG_INFINITY, 0usize, DVec3::ZERO);
        let mut closest = (f64::INFINITY, 0usize, 0.0f64);
        for k in 0..m {
            let (a, b) = (radial[hull[k] as usize], radial[hull[(k + 1) % m] as usize]);
            let e = b - a;
            let out = e.cross(self.axis).normalize();
            let d = -out.dot(a);
            if d > nearest_line.0 {
                nearest_line = (d, k, out);
            }
            let t = (-a.dot(e) / e.length_squared()).clamp(0.0, 1.0);
            let dist2 = (a + e * t).length_squared();
            if dist2 < closest.0 {
                closest = (dist2, k, t);
            }
        }
        let lift = |k: usize, t: f64| {
            let (i, j) = (hull[k] as usize, hull[(k + 1) % m] as usize);
            (world[i] + (world[j] - world[i]) * t, radial[i] + (radial[j] - radial[i]) * t)
        };
        let (normal, depth, surface) = if nearest_line.0 <= 0.0 {
            // The axis pierces the shadow: the nearest edge has to pass over the axis and clear
            // the circle, so the polyhedron moves against that edge's outward normal.
            let (k, out) = (nearest_line.1, nearest_line.2);
            let (a, b) = (radial[hull[k] as usize], radial[hull[(k + 1) % m] as usize]);
            let e = b - a;
            let t = (-a.dot(e) / e.length_squared()).clamp(0.0, 1.0);
            (-out, self.radius - nearest_line.0, lift(k, t).0)
        } else {
            let dist = closest.0.sqrt();
            let (p, r) = lift(closest.1, closest.2);
            (r / dist, self.radius - dist, p)
        };
        (depth > 0.0).then(|| PolyContact::single(normal, depth, surface + normal * (0.5 * depth), ContactFeature::Surface))
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use glam::DQuat;

    #[test]
    fn pipe_against_an_edge_and_through_the_shadow() {
        let pipe = Cylinder::new(DVec3::ZERO, DVec3::Z, 0.5, 4.0, false);
        // A cube turned 45° about the axis: its edge (along z) points at the axis.
        let cube = Polyhedron::cube(0.2);
        let s = 0.1 * 2f64.sqrt();
        let pose = Pose::new(DVec3::new(0.5 + s - 0.02, 0.0, 2.0), DQuat::from_rotation_z(std::f64::consts::FRAC_PI_4));
        let c = pipe.polyhedron_contact(&cube, &pose).unwrap();
        assert!((c.normal - DVec3::X).length() < 1e-12, "{c:?}");
        assert!((c.depth - 0.02).abs() < 1e-12);
        assert!((c.point - DVec3::new(0.49, 0.0, c.point.z)).length() < 1e-12);
        // A big slab the axis passes through, 0.2 from its lower side: pushed up until that side clears.
        let slab = Polyhedron::cuboid(DVec3::new(1.0, 0.3, 0.1));
        let c = pipe.polyhedron_contact(&slab, &Pose::from_position(DVec3::new(0.0, 0.1, 2.0))).unwrap();
        assert!((c.normal - DVec3::Y).length() < 1e-12, "{c:?}");
        assert!((c.depth - (0.5 + 0.2)).abs() < 1e-12);
        // Far away, or beyond the ends: nothing.
        assert!(pipe.polyhedron_contact(&cube, &Pose::from_position(DVec3::new(0.0, 0.8, 2.0))).is_none());
        assert!(pipe.polyhedron_contact(&cube, &Pose::from_position(DVec3::new(0.0, 0.55, 4.1))).is_none());
    }

    #[test]
    fn drum_manifold_has_the_outer_face_corners() {
        let drum = Cylinder::new(DVec3::ZERO, DVec3::Z, 1.0, 2.0, true);
        // A thin plate against the shell: its four outer corners stick out.
        let plate = Polyhedron::cuboid(DVec3::new(0.05, 0.02, 0.02));
        let c = drum.polyhedron_contact(&plate, &Pose::from_position(DVec3::new(0.96, 0.0, 1.0))).unwrap();
        assert_eq!(c.manifold().len(), 4);
        assert!((c.normal + DVec3::X).length() < 1e-9, "{c:?}");
        assert!(drum.polyhedron_contact(&plate, &Pose::from_position(DVec3::new(0.5, 0.0, 1.0))).is_none());
    }
}
