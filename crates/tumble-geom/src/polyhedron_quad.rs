use crate::polyhedron_polyhedron::{Buf, face_contact, max_dot, min_dot};
use crate::{ContactFeature, DVec3, PolyContact, Polyhedron, Pose, Quad, segment_closest_points};

impl Quad {
    /// Contact of a convex polyhedron (A at `pose`) with this quad (B), face, edge or corner.
    ///
    /// The quad is a flat convex polygon: the separating-axis test runs over its normal, the
    /// polyhedron's face normals and the cross products of the polyhedron's edges with the
    /// quad's four edges, and the axis of minimum penetration is the normal (from the quad to
    /// the polyhedron). A quad-face axis gives the polyhedron's incident face clipped by the
    /// quad (up to four points), a polyhedron face the quad clipped by that face, an edge axis
    /// the edges' closest points.
    ///
    /// One-sided quads push only towards their normal side: no contact once the polyhedron's
    /// centre is behind the plane, and no normal pointing behind it.
    ///
    /// ```
    /// use tumble_geom::{DVec3, Polyhedron, Pose, Quad};
    /// let q = Quad::new([DVec3::ZERO, DVec3::X, DVec3::new(1.0, 1.0, 0.0), DVec3::Y], false);
    /// let cube = Polyhedron::cube(0.2);
    /// // On the face, then hanging over the x = 1 edge: the contact is clipped to the quad.
    /// let c = q.polyhedron_contact(&cube, &Pose::from_position(DVec3::new(0.5, 0.5, 0.09))).unwrap();
    /// assert!((c.normal - DVec3::Z).length() < 1e-12 && (c.depth - 0.01).abs() < 1e-12);
    /// let c = q.polyhedron_contact(&cube, &Pose::from_position(DVec3::new(1.05, 0.5, 0.09))).unwrap();
    /// assert!((c.normal - DVec3::Z).length() < 1e-12);
    /// assert!(c.manifold().iter().all(|m| m.point.x <= 1.0 + 1e-12));
    /// ```
    pub fn polyhedron_contact(&self, poly: &Polyhedron, pose: &Pose) -> Option<PolyContact> {
        let h = self.normal.dot(pose.position - self.corners[0]);
        let rb = poly.bounding_radius();
        if h.abs() >= rb || (!self.two_sided && h <= 0.0) {
            return None;
        }
        // Body frame of the polyhedron.
        let qc: [DVec3; 4] = self.corners.map(|c| pose.to_body(c));
        let qn = pose.unrotate(self.normal);
        let verts = poly.vertices();
        let size = poly.size();
        let tie = 1e-9 * size;

        // (depth, normal, which): which = 0 quad face, 1 + f polyhedron face, edges encoded apart.
        #[derive(Clone, Copy)]
        enum Axis {
            QuadFace(f64),
            PolyFace(usize),
            Edges(usize, usize),
            InPlane,
        }
        let mut best: Option<(f64, DVec3, Axis)> = None;
        let consider = |depth: f64, m: DVec3, axis: Axis, best: &mut Option<(f64, DVec3, Axis)>| -> bool {
            if depth <= 0.0 {
                return false; // separating axis
            }
            let allowed = self.two_sided || m.dot(qn) >= -1e-12;
            if allowed && best.is_none_or(|b| depth < b.0 - tie) {
                *best = Some((depth, m, axis));
            }
            true
        };
        // Quad normal, both sides (a one-sided quad keeps only its front).
        let h0 = qn.dot(qc[0]);
        let front = h0 - min_dot(verts, qn);
        let back = max_dot(verts, qn) - h0;
        if !consider(front, qn, Axis::QuadFace(1.0), &mut best) || !consider(back, -qn, Axis::QuadFace(-1.0), &mut best) {
            return None;
        }
        // Polyhedron faces: m = −n_f.
        for (fi, f) in poly.faces().iter().enumerate() {
            let depth = f.offset - min_dot(&qc, f.normal);
            if !consider(depth, -f.normal, Axis::PolyFace(fi), &mut best) {
                return None;
            }
        }
        // Edge pairs, both orientations.
        for (ei, e) in poly.edges().iter().enumerate() {
            let u = verts[e.vertices[1] as usize] - verts[e.vertices[0] as usize];
            for k in 0..4 {
                let v = qc[(k + 1) % 4] - qc[k];
                let m = u.cross(v);
                if m.length_squared() <= 1e-20 * u.length_squared() * v.length_squared() {
                    continue;
                }
                let m = m.normalize();
                for m in [m, -m] {
                    let depth = max_dot(&qc, m) - min_dot(verts, m);
                    if !consider(depth, m, Axis::Edges(ei, k), &mut best) {
                        return None;
                    }
                }
            }
        }
        // A one-sided quad bars the back half of the sphere of directions, so the least overlap
        // over the front half can lie on its rim, the quad's plane: there the overlap is the 2D
        // support function of the shapes' shadows, least along an edge normal of a shadow.
        if !self.two_sided {
            let quad_edges = (0..4).map(|k| qc[(k + 1) % 4] - qc[k]);
            let poly_edges = poly.edges().iter().map(|e| verts[e.vertices[1] as usize] - verts[e.vertices[0] as usize]);
            for w in quad_edges.chain(poly_edges) {
                let m = qn.cross(w);
                if m.length_squared() <= 1e-20 * w.length_squared() {
                    continue;
                }
                let m = m.normalize();
                for m in [m, -m] {
                    let depth = max_dot(&qc, m) - min_dot(verts, m);
                    if !consider(depth, m, Axis::InPlane, &mut best) {
                        return None;
                    }
                }
            }
        }
        let (depth, m, axis) = best?;
        let contact = match axis {
            Axis::QuadFace(sign) => {
                let n = qn * sign;
                let ref_poly: Buf<DVec3> = if sign > 0.0 { qc.iter().copied().collect() } else { qc.iter().rev().copied().collect() };
                let inc = poly.faces().iter().min_by(|a, b| a.normal.dot(n).total_cmp(&b.normal.dot(n))).unwrap();
                let inc_poly: Buf<DVec3> = inc.vertices.iter().map(|&i| verts[i as usize]).collect();
                face_contact(&ref_poly, n, n.dot(qc[0]), &inc_poly, depth, n, ContactFeature::Surface, || verts[poly.support_index(-n)])
            }
            Axis::PolyFace(fi) => {
                let f = &poly.faces()[fi];
                let ref_poly: Buf<DVec3> = f.vertices.iter().map(|&i| verts[i as usize]).collect();
                let deepest = *qc.iter().min_by(|a, b| a.dot(f.normal).total_cmp(&b.dot(f.normal))).unwrap();
                face_contact(&ref_poly, f.normal, f.offset, &qc, depth, m, ContactFeature::Surface, || deepest)
            }
            Axis::Edges(ei, k) => {
                let e = &poly.edges()[ei];
                let (pa, pb) = segment_closest_points(verts[e.vertices[0] as usize], verts[e.vertices[1] as usize], qc[k], qc[(k + 1) % 4]);
                PolyContact::single(m, depth, 0.5 * (pa + pb), ContactFeature::Surface)
            }
            // Halfway between the polyhedron's deepest vertex and the quad's supporting line.
            Axis::InPlane => PolyContact::single(m, depth, verts[poly.support_index(-m)] + m * (0.5 * depth), ContactFeature::Surface),
        };
        Some(contact.transformed(pose))
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use glam::DQuat;

    fn unit_square(two_sided: bool) -> Quad {
        Quad::new([DVec3::ZERO, DVec3::X, DVec3::new(1.0, 1.0, 0.0), DVec3::Y], two_sided)
    }

    #[test]
    fn corner_of_the_quad_into_a_cube_face() {
        // A cube beyond the corner (1, 1) of the quad, below the plane level but pressed sideways
        // onto the quad's corner: the quad's corner sticks 0.01 into the cube's −x face.
        let q = unit_square(true);
        let cube = Polyhedron::cube(0.2);
        let pose = Pose::from_position(DVec3::new(1.09, 0.95, 0.0));
        let c = q.polyhedron_contact(&cube, &pose).unwrap();
        assert!((c.normal - DVec3::X).length() < 1e-12, "{c:?}");
        assert!((c.depth - 0.01).abs() < 1e-12);
    }

    #[test]
    fn one_sided_quad_ignores_a_body_behind_it() {
        let cube = Polyhedron::cube(0.2);
        let pose = Pose::from_position(DVec3::new(0.5, 0.5, -0.09));
        assert!(unit_square(false).polyhedron_contact(&cube, &pose).is_none());
        let c = unit_square(true).polyhedron_contact(&cube, &pose).unwrap();
        assert!((c.normal + DVec3::Z).length() < 1e-12 && (c.depth - 0.01).abs() < 1e-12);
    }

    #[test]
    fn edge_on_edge_beyond_the_quad() {
        // A cube rotated 45° about y with its lower edge crossing the quad's x = 1 edge from beyond.
        let q = unit_square(false);
        let cube = Polyhedron::cube(0.2);
        let s = 0.1 * 2f64.sqrt();
        let pose = Pose::new(DVec3::new(1.0 + s - 0.01, 0.5, 0.0), DQuat::from_rotation_y(std::f64::consts::FRAC_PI_4));
        let c = q.polyhedron_contact(&cube, &pose);
        // Centre on the plane: a one-sided quad gives nothing; two-sided pushes along +x.
        assert!(c.is_none());
        let c = unit_square(true).polyhedron_contact(&cube, &pose).unwrap();
        assert!(
            (c.normal - DVec3::new(1.0, 0.0, 1.0).normalize()).length() < 1e-9 || (c.normal - DVec3::new(1.0, 0.0, -1.0).normalize()).length() < 1e-9,
            "{c:?}"
        );
        assert!((c.depth - 0.01 / 2f64.sqrt()).abs() < 1e-12);
    }
}
