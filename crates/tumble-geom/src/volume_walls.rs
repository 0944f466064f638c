//! Overlap-volume contacts of a polyhedron with walls (`volume_contact.rs` has the pairs). A wall
//! is the solid behind its surface: a plane's half-space, a quad's semi-infinite prism (the quad
//! and its four side planes, so a box of quads is closed; the quad's corners and rim are the
//! solid's), a lifter bar's hull, and for a cylinder the half-space behind its tangent plane at
//! the azimuth of A's centre. That plane turns with A's centre, so V depends on the centre's
//! azimuth too, and the force carries the term that derivative gives: w'(V) (S − T_u (u × r)/|r|²)
//! with T_u the overlap's moment about the axis. It makes the shell's normal force exert no torque
//! about its own axis, as a cylinder's must. Corners and edges meet the true cylinder, edges as
//! material points.

use crate::overlap_volume::{PLANE_TOLERANCE, Region, overlap_moments_in, with_scratch};
use crate::polyhedron_polyhedron::Buf;
use crate::volume_contact::{CORNER_SMOOTHING, PenetratingPoint, VolumeContact, edge_density, penetrating_points, wall_hull_volume};
use crate::{Cylinder, DVec3, Plane, Polyhedron, Pose, Quad, SurfaceShape};

/// A square of half-size `half` about `centre` in the plane with unit normal `n`, counter-clockwise about n.
fn square(centre: DVec3, n: DVec3, half: f64) -> Buf<DVec3> {
    let u = n.any_orthonormal_vector() * half;
    let v = n.cross(u);
    [centre - u - v, centre + u - v, centre + u + v, centre - u + v].into_iter().collect()
}

/// Makes `r` the solid behind a plane through the origin with outward unit normal `m` (pointing
/// out of the solid), big enough for a body of bounding radius `rb` about the origin.
fn set_half_space(r: &mut Region, m: DVec3, rb: f64) {
    r.clear();
    r.planes.push((m, 0.0));
    r.add_face(m, square(DVec3::ZERO, m, 2.0 * rb));
}

impl Plane {
    /// The overlap-volume contact of a polyhedron with the half-space behind this plane.
    pub fn polyhedron_volume(&self, poly: &Polyhedron, pose: &Pose) -> Option<VolumeContact> {
        let (h, rb) = (self.signed_distance(pose.position), poly.bounding_radius());
        if h >= rb {
            return None;
        }
        let foot = pose.position - self.normal * h;
        with_scratch(|s| {
            s.a.set_polyhedron(poly, pose, foot);
            set_half_space(&mut s.b, self.normal, rb);
            let (m, depth) = overlap_moments_in(&s.a, &s.b, PLANE_TOLERANCE * rb, None, &mut s.clip)?;
            let density = edge_density(poly);
            let points = penetrating_points(&s.a, &s.b, foot, CORNER_SMOOTHING * rb, density, density, None);
            VolumeContact::from_moments(&m, foot, pose.position, None, m.area, depth, points)
        })
    }
}

impl Quad {
    /// The overlap-volume contact of a polyhedron with the semi-infinite prism behind this quad
    /// (on the side away from the polyhedron's centre for a two-sided quad; none once the centre
    /// is behind a one-sided quad). The quad's corners and rim are the solid's corners and edges.
    pub fn polyhedron_volume(&self, poly: &Polyhedron, pose: &Pose) -> Option<VolumeContact> {
        let rb = poly.bounding_radius();
        let h = self.normal.dot(pose.position - self.corners[0]);
        if h.abs() >= rb || (!self.two_sided && h <= 0.0) {
            return None;
        }
        let m = if h > 0.0 { self.normal } else { -self.normal };
        let origin = pose.position - m * h.abs();
        let c: [DVec3; 4] = self.corners.map(|p| p - origin);
        let middle = c.iter().copied().sum::<DVec3>() / 4.0;
        let ccw = |mut p: Buf<DVec3>, n: DVec3| {
            if (p[1] - p[0]).cross(p[2] - p[0]).dot(n) < 0.0 {
                p.reverse();
            }
            p
        };
        let depth_behind = 2.0 * rb;
        with_scratch(|sc| {
            let solid = &mut sc.b;
            solid.clear();
            solid.planes.push((m, m.dot(c[0])));
            solid.vertices.extend_from_slice(&c);
            solid.edges.extend((0..4).map(|k| [c[k], c[(k + 1) % 4]]));
            solid.add_face(m, ccw(c.into_iter().collect(), m));
            for k in 0..4 {
                let (p, q) = (c[k], c[(k + 1) % 4]);
                let mut s = (q - p).cross(m).normalize();
                if s.dot(middle - p) > 0.0 {
                    s = -s;
                }
                solid.planes.push((s, s.dot(p)));
                solid.add_face(s, ccw([p, q, q - m * depth_behind, p - m * depth_behind].into_iter().collect(), s));
            }
            sc.a.set_polyhedron(poly, pose, origin);
            let (mo, depth) = overlap_moments_in(&sc.a, &sc.b, PLANE_TOLERANCE * rb, None, &mut sc.clip)?;
            let density = edge_density(poly);
            let points = penetrating_points(&sc.a, &sc.b, origin, CORNER_SMOOTHING * rb, density, density, None);
            VolumeContact::from_moments(&mo, origin, pose.position, None, mo.area, depth, points)
        })
    }
}

impl Cylinder {
    /// The overlap-volume contact of a polyhedron with the solid beyond the shell (inside: a
    /// drum) or within it (outside: a pipe), taken behind the tangent plane at the azimuth of the
    /// polyhedron's centre (module docs); only while the centre projects within the length.
    pub fn polyhedron_volume(&self, poly: &Polyhedron, pose: &Pose) -> Option<VolumeContact> {
        let rel = pose.position - self.point;
        let s = rel.dot(self.axis);
        if s < 0.0 || s > self.length {
            return None;
        }
        let radial = rel - self.axis * s;
        let rho = radial.length();
        let rb = poly.bounding_radius();
        if rho < 1e-12 * self.radius || (self.inside && rho + rb <= self.radius) || (!self.inside && rho - rb >= self.radius) {
            return None;
        }
        let out = radial / rho;
        let m = if self.inside { -out } else { out };
        let surface = self.point + self.axis * s + out * self.radius;
        with_scratch(|sc| {
            sc.a.set_polyhedron(poly, pose, surface);
            set_half_space(&mut sc.b, m, rb);
            let points = self.penetrating_points(&sc.a, surface, edge_density(poly));
            let Some((mo, depth)) = overlap_moments_in(&sc.a, &sc.b, PLANE_TOLERANCE * rb, None, &mut sc.clip) else {
                // Corners can cross the shell away from the centre's azimuth before anything
                // crosses the tangent plane: their loads begin at zero depth on their own.
                return VolumeContact::points_only(m, surface, points);
            };
            // ∂V/∂φ of the tangent plane's azimuth: the overlap's moment about the axis.
            let t_u = (mo.moment - (self.point - surface).cross(mo.area)).dot(self.axis);
            let push = mo.area - self.axis.cross(radial) * (t_u / (rho * rho));
            VolumeContact::from_moments(&mo, surface, pose.position, None, push, depth, points)
        })
    }

    /// The depth of `p` beyond the shell (drum) or within it (pipe), with its gradient (towards
    /// the inside of the drum, away from the pipe's axis).
    fn penetration(&self, p: DVec3) -> Option<(f64, DVec3)> {
        let r = p - self.point;
        let across = r - self.axis * r.dot(self.axis);
        let len = across.length();
        let (depth, normal) = if self.inside { (len - self.radius, -across / len) } else { (self.radius - len, across / len) };
        (depth > 0.0 && len > 0.0).then_some((depth, normal))
    }

    /// Corners and edge points of A (a region about `origin`) against the true cylinder. An edge is
    /// [`CYLINDER_EDGE_POINTS`] material points at the middles of equal parts (each carrying its
    /// part's length × density): the depth is not linear along an edge here, so no quadrature over
    /// the penetrating part would be exact, and points fixed on the body keep the potential exact.
    fn penetrating_points(&self, a: &Region, origin: DVec3, density: f64) -> Vec<PenetratingPoint> {
        let mut out = Vec::new();
        for &v in &a.vertices {
            if let Some((depth, normal)) = self.penetration(v + origin) {
                out.push(PenetratingPoint { point: v + origin, depth, normal, weight: 1.0 });
            }
        }
        let n = CYLINDER_EDGE_POINTS as f64;
        for &[p0, p1] in &a.edges {
            let weight = (p1 - p0).length() / n * density;
            for k in 0..CYLINDER_EDGE_POINTS {
                let p = origin + p0 + (p1 - p0) * ((k as f64 + 0.5) / n);
                if let Some((depth, normal)) = self.penetration(p) {
                    out.push(PenetratingPoint { point: p, depth, normal, weight });
                }
            }
        }
        out
    }
}

/// Material points per edge against a cylinder (the midpoint rule of the edge integral).
pub const CYLINDER_EDGE_POINTS: usize = 8;

impl SurfaceShape {
    /// The overlap-volume contact of a convex polyhedron (at `pose`) with this wall; a lifter
    /// bar is its hull, met as a polyhedron (its edges weighed by the polyhedron's edge density,
    /// as every wall's are).
    pub fn polyhedron_volume(&self, poly: &Polyhedron, pose: &Pose) -> Option<VolumeContact> {
        match self {
            SurfaceShape::Plane(p) => p.polyhedron_volume(poly, pose),
            SurfaceShape::Quad(q) => q.polyhedron_volume(poly, pose),
            SurfaceShape::Cylinder(c) => c.polyhedron_volume(poly, pose),
            SurfaceShape::Prism(p) => {
                if (pose.position - p.centre).length() > p.bound + poly.bounding_radius() {
                    return None;
                }
                let c = wall_hull_volume(poly, pose, p.hull.as_deref()?, &p.hull_pose)?;
                Some(VolumeContact { turn_b: DVec3::ZERO, ..c })
            }
            // A mesh gives one contact per flat patch: `MeshWall::polyhedron_volumes`.
            SurfaceShape::Mesh(_) => None,
        }
    }
}
