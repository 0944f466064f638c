//! Overlap-volume contacts of a convex polyhedron with another one or with a wall: the volume V
//! of the overlap and its derivatives with respect to A's pose, everything an energy-conserving
//! normal force w'(V) needs (docs/polyhedra.md, "The overlap-volume contact").
//!
//! A wall is the solid behind its surface: a plane's half-space, a quad's semi-infinite prism
//! (the quad and its four side planes, so a box of quads is closed), and for a cylinder the
//! half-space behind its tangent plane at the azimuth of A's centre. That plane turns with A's
//! centre, so V depends on the centre's azimuth too, and the force carries the term that
//! derivative gives: w'(V) (S − T_u (u × r)/|r|²) with T_u the overlap's moment about the axis.
//! It makes the shell's normal force exert no torque about its own axis, as a cylinder's must.

use crate::overlap_volume::{Moments, PLANE_TOLERANCE, Region, overlap_moments};
use crate::polyhedron_polyhedron::Buf;
use crate::{Cylinder, DVec3, Plane, Polyhedron, Pose, Quad, SurfaceShape, polyhedron_polyhedron};

/// A corner of one body inside the other (or inside a wall's solid): how deep, and the outward
/// normal of the nearest surface it has to leave through. A potential of that depth per corner
/// stiffens corner and edge contacts, which the volume alone leaves soft.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct VertexPenetration {
    /// The corner (world).
    pub point: DVec3,
    /// Distance to the nearest surface of the body it is inside (> 0), smoothed where two
    /// surfaces are nearly as near (see [`CORNER_SMOOTHING`]).
    pub depth: f64,
    /// The depth's gradient, from B (or the wall) to A: the force on A along it pushes the corner
    /// out. A unit vector except within ~τ of an edge, where it turns from one face's normal to
    /// the next.
    pub normal: DVec3,
    /// The corner belongs to A (else to B or the wall).
    pub of_a: bool,
}

/// An overlap-volume contact of body A with body B or a wall (world frame).
#[derive(Clone, Debug, PartialEq)]
pub struct VolumeContact {
    /// Volume of the overlap.
    pub volume: f64,
    /// −∂V/∂x_A: the force on A per unit w'(V); B (or the wall) takes the opposite.
    pub push: DVec3,
    /// −∂V/∂θ_A about A's centre: the torque on A per unit w'(V).
    pub turn_a: DVec3,
    /// −∂V/∂θ_B about B's centre: the torque on B per unit w'(V) (zero for walls).
    pub turn_b: DVec3,
    /// The unit push, from B (or the wall) to A: the normal of the tangential laws.
    pub normal: DVec3,
    /// Where the tangential force acts: the point on the push's line of action nearest the
    /// overlap's centroid.
    pub point: DVec3,
    /// |S|: the area of B's faces inside A, projected on the normal (the contact patch).
    pub area: f64,
    /// Penetration depth: the SAT depth for pairs, the deepest point below the surface for walls.
    pub depth: f64,
    /// Corners of either body inside the other.
    pub vertices: Buf<VertexPenetration>,
}

impl VolumeContact {
    /// dV/dt for A moving at (v, ω) relative to B at (v_b, ω_b), both centres' velocities:
    /// −(push · (v − v_b) + turn_a · ω + turn_b · ω_b). For a wall pass v_b = the wall's velocity
    /// at A's centre and put its spin into ω as ω − Ω (turn_b is zero).
    pub fn volume_rate(&self, v_rel: DVec3, omega_a: DVec3, omega_b: DVec3) -> f64 {
        -(self.push.dot(v_rel) + self.turn_a.dot(omega_a) + self.turn_b.dot(omega_b))
    }

    fn from_moments(
        m: &Moments,
        origin: DVec3,
        xa: DVec3,
        xb: Option<DVec3>,
        push: DVec3,
        depth: f64,
        vertices: Buf<VertexPenetration>,
    ) -> Option<VolumeContact> {
        let o = m.world(origin);
        let area = o.area.length();
        if area == 0.0 || push.length_squared() == 0.0 {
            return None;
        }
        Some(VolumeContact {
            volume: o.volume,
            push,
            turn_a: o.torque_about(xa),
            turn_b: xb.map_or(DVec3::ZERO, |x| -o.torque_about(x)),
            normal: push.normalize(),
            point: o.action_point(),
            area,
            depth,
            vertices,
        })
    }
}

/// The share of the normal law an overlap-volume contact gives its overlap volume; the rest goes
/// to the corners inside the other body, spread over the corners of the largest face (so a face
/// lying on a larger face meets the whole law, and a corner meets (1 − share)/corners of it).
pub const VOLUME_SHARE: f64 = 0.5;

/// The width τ of the band in which a corner's push turns from one face to the next, as a
/// fraction of the smaller body's bounding radius.
pub const CORNER_SMOOTHING: f64 = 0.01;

/// The corners of A inside B and of B inside A (both relative to `origin`), depths smoothed over `tau`.
fn corner_penetrations(a: &Region, b: &Region, origin: DVec3, tau: f64) -> Buf<VertexPenetration> {
    let mut out = Buf::new();
    for &v in &a.vertices {
        if let Some((depth, normal)) = b.penetration(v, tau) {
            out.push(VertexPenetration { point: v + origin, depth, normal, of_a: true });
        }
    }
    for &v in &b.vertices {
        if let Some((depth, normal)) = a.penetration(v, tau) {
            out.push(VertexPenetration { point: v + origin, depth, normal: -normal, of_a: false });
        }
    }
    out
}

/// The overlap-volume contact of polyhedron A with polyhedron B, gated by the separating-axis
/// test (whose depth it reports and whose contact point is the origin of the sums).
///
/// ```
/// use tumble_geom::{DVec3, Polyhedron, Pose, polyhedron_polyhedron_volume};
/// let cube = Polyhedron::cube(1.0);
/// let c = polyhedron_polyhedron_volume(&cube, &Pose::from_position(DVec3::new(0.0, 0.0, 0.9)), &cube, &Pose::IDENTITY).unwrap();
/// assert!((c.volume - 0.1).abs() < 1e-12 && (c.push - DVec3::Z).length() < 1e-12 && (c.depth - 0.1).abs() < 1e-12);
/// ```
pub fn polyhedron_polyhedron_volume(a: &Polyhedron, pose_a: &Pose, b: &Polyhedron, pose_b: &Pose) -> Option<VolumeContact> {
    let k = polyhedron_polyhedron(a, pose_a, b, pose_b)?;
    let eps = PLANE_TOLERANCE * a.bounding_radius().max(b.bounding_radius());
    let (ra, rb) = (Region::of_polyhedron(a, pose_a, k.point), Region::of_polyhedron(b, pose_b, k.point));
    let (m, _) = overlap_moments(&ra, &rb, eps)?;
    let tau = CORNER_SMOOTHING * a.bounding_radius().min(b.bounding_radius());
    let corners = corner_penetrations(&ra, &rb, k.point, tau);
    VolumeContact::from_moments(&m, k.point, pose_a.position, Some(pose_b.position), m.area, k.depth, corners)
}

/// A square of half-size `half` about `centre` in the plane with unit normal `n`, counter-clockwise about n.
fn square(centre: DVec3, n: DVec3, half: f64) -> Buf<DVec3> {
    let u = n.any_orthonormal_vector() * half;
    let v = n.cross(u);
    [centre - u - v, centre + u - v, centre + u + v, centre - u + v].into_iter().collect()
}

/// The overlap of A (as a region about `surface`) with the solid behind a plane through `surface`
/// with outward unit normal `m` (pointing out of the solid).
fn behind_plane(a: &Region, rb: f64, m: DVec3) -> Option<(Moments, f64, Region)> {
    let solid = Region { planes: [(m, 0.0)].into_iter().collect(), faces: vec![(m, square(DVec3::ZERO, m, 2.0 * rb))], vertices: Buf::new() };
    let (mo, depth) = overlap_moments(a, &solid, PLANE_TOLERANCE * rb)?;
    Some((mo, depth, solid))
}

impl Plane {
    /// The overlap-volume contact of a polyhedron with the half-space behind this plane.
    pub fn polyhedron_volume(&self, poly: &Polyhedron, pose: &Pose) -> Option<VolumeContact> {
        let h = self.signed_distance(pose.position);
        if h >= poly.bounding_radius() {
            return None;
        }
        let foot = pose.position - self.normal * h;
        let a = Region::of_polyhedron(poly, pose, foot);
        let (m, depth, solid) = behind_plane(&a, poly.bounding_radius(), self.normal)?;
        VolumeContact::from_moments(
            &m,
            foot,
            pose.position,
            None,
            m.area,
            depth,
            corner_penetrations(&a, &solid, foot, CORNER_SMOOTHING * poly.bounding_radius()),
        )
    }
}

impl Quad {
    /// The overlap-volume contact of a polyhedron with the semi-infinite prism behind this quad
    /// (on the side away from the polyhedron's centre for a two-sided quad; none once the centre
    /// is behind a one-sided quad).
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
        let mut planes: Buf<(DVec3, f64)> = [(m, m.dot(c[0]))].into_iter().collect();
        let mut faces = vec![(m, ccw(c.into_iter().collect(), m))];
        for k in 0..4 {
            let (p, q) = (c[k], c[(k + 1) % 4]);
            let mut s = (q - p).cross(m).normalize();
            if s.dot(middle - p) > 0.0 {
                s = -s;
            }
            planes.push((s, s.dot(p)));
            faces.push((s, ccw([p, q, q - m * depth_behind, p - m * depth_behind].into_iter().collect(), s)));
        }
        let (a, solid) = (Region::of_polyhedron(poly, pose, origin), Region { planes, faces, vertices: c.into_iter().collect() });
        let (mo, depth) = overlap_moments(&a, &solid, PLANE_TOLERANCE * rb)?;
        VolumeContact::from_moments(&mo, origin, pose.position, None, mo.area, depth, corner_penetrations(&a, &solid, origin, CORNER_SMOOTHING * rb))
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
        let a = Region::of_polyhedron(poly, pose, surface);
        let (mo, depth, _) = behind_plane(&a, rb, m)?;
        // ∂V/∂φ of the tangent plane's azimuth: the overlap's moment about the axis.
        let t_u = (mo.moment - (self.point - surface).cross(mo.area)).dot(self.axis);
        let push = mo.area - self.axis.cross(radial) * (t_u / (rho * rho));
        // Corners against the true cylinder: radially beyond the shell (drum) or within it (pipe).
        let mut corners = Buf::new();
        for &v in &a.vertices {
            let r = v + surface - self.point;
            let across = r - self.axis * r.dot(self.axis);
            let len = across.length();
            let (depth, normal) = if self.inside { (len - self.radius, -across / len) } else { (self.radius - len, across / len) };
            if depth > 0.0 && len > 0.0 {
                corners.push(VertexPenetration { point: v + surface, depth, normal, of_a: true });
            }
        }
        VolumeContact::from_moments(&mo, surface, pose.position, None, push, depth, corners)
    }
}

impl SurfaceShape {
    /// The overlap-volume contact of a convex polyhedron (at `pose`) with this wall; a lifter
    /// bar is its hull, met as a polyhedron.
    pub fn polyhedron_volume(&self, poly: &Polyhedron, pose: &Pose) -> Option<VolumeContact> {
        match self {
            SurfaceShape::Plane(p) => p.polyhedron_volume(poly, pose),
            SurfaceShape::Quad(q) => q.polyhedron_volume(poly, pose),
            SurfaceShape::Cylinder(c) => c.polyhedron_volume(poly, pose),
            SurfaceShape::Prism(p) => {
                if (pose.position - p.centre).length() > p.bound + poly.bounding_radius() {
                    return None;
                }
                let c = polyhedron_polyhedron_volume(poly, pose, p.hull.as_deref()?, &p.hull_pose)?;
                Some(VolumeContact { turn_b: DVec3::ZERO, ..c })
            }
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use glam::DQuat;

    /// Central differences of V(x, q) against push and turn_a at `trials` random poses near the wall.
    fn check_derivatives(wall: &SurfaceShape, poly: &Polyhedron, place: impl Fn(f64, f64, f64) -> DVec3) -> usize {
        let mut seed = 0x9e37_79b9_7f4a_7c15u64;
        let mut next = || {
            seed ^= seed << 13;
            seed ^= seed >> 7;
            seed ^= seed << 17;
            (seed >> 11) as f64 / (1u64 << 53) as f64
        };
        let mut checked = 0;
        for trial in 0..100 {
            let x = place(next(), next(), next());
            let q = DQuat::from_axis_angle(DVec3::new(next() - 0.5, next() - 0.5, next() - 0.5).normalize(), 6.0 * next());
            let vol =
                |x: DVec3, turn: DVec3| wall.polyhedron_volume(poly, &Pose::new(x, DQuat::from_scaled_axis(turn) * q)).map_or(0.0, |c| c.volume);
            let Some(c) = wall.polyhedron_volume(poly, &Pose::new(x, q)) else { continue };
            if c.volume < 1e-4 * poly.volume() {
                continue;
            }
            let h = 1e-7;
            let (mut grad, mut rot) = (DVec3::ZERO, DVec3::ZERO);
            for k in 0..3 {
                let e = DVec3::AXES[k] * h;
                grad[k] = (vol(x + e, DVec3::ZERO) - vol(x - e, DVec3::ZERO)) / (2.0 * h);
                rot[k] = (vol(x, e) - vol(x, -e)) / (2.0 * h);
            }
            let scale = c.area.max(1e-3 * poly.size() * poly.size());
            assert!((grad + c.push).length() < 1e-5 * scale, "trial {trial}: ∂V/∂x {grad:?} against −push {:?}", -c.push);
            assert!((rot + c.turn_a).length() < 1e-5 * scale * poly.size(), "trial {trial}: ∂V/∂θ {rot:?} against −turn {:?}", -c.turn_a);
            assert!(c.depth > 0.0 && c.depth < poly.size());
            checked += 1;
        }
        checked
    }

    #[test]
    fn a_plane_walls_push_and_turn_are_the_volumes_derivatives() {
        let wall = SurfaceShape::Plane(Plane::new(DVec3::new(0.1, 0.2, 0.3), DVec3::new(0.2, 0.3, 1.0)));
        let poly = Polyhedron::dodecahedron(0.5);
        let n =
            check_derivatives(&wall, &poly, |a, b, c| DVec3::new(0.1 + a, 0.2 + b, 0.3) + DVec3::new(0.2, 0.3, 1.0).normalize() * (0.05 + 0.5 * c));
        assert!(n > 40, "{n}");
    }

    #[test]
    fn a_quads_push_and_turn_are_the_volumes_derivatives_at_its_face_edges_and_corners() {
        let corners = [DVec3::ZERO, DVec3::new(1.0, 0.0, 0.1), DVec3::new(1.0, 0.8, 0.1), DVec3::new(0.0, 0.8, 0.0)];
        let poly = Polyhedron::cube(0.4);
        for two_sided in [false, true] {
            let wall = SurfaceShape::Quad(Quad::new(corners, two_sided));
            let n = check_derivatives(&wall, &poly, |a, b, c| DVec3::new(-0.2 + 1.4 * a, -0.2 + 1.2 * b, 0.05 + 0.3 * (c - 0.3)));
            assert!(n > 30, "{n}");
        }
    }

    #[test]
    fn a_drum_and_a_pipes_push_and_turn_are_the_volumes_derivatives() {
        let poly = Polyhedron::cube(0.3);
        for inside in [true, false] {
            let wall = SurfaceShape::Cylinder(Cylinder::new(DVec3::new(0.0, 0.0, -1.0), DVec3::new(0.1, 0.0, 1.0), 1.0, 2.0, inside));
            let n = check_derivatives(&wall, &poly, |a, b, c| {
                let r = if inside { 0.78 + 0.2 * a } else { 1.05 + 0.15 * a };
                let phi = 6.0 * b;
                DVec3::new(r * phi.cos(), r * phi.sin(), 0.5 * (c - 0.5))
            });
            assert!(n > 40, "inside {inside}: {n}");
        }
    }

    #[test]
    fn a_drum_shells_normal_force_has_no_torque_about_its_axis() {
        let drum = Cylinder::new(DVec3::ZERO, DVec3::Z, 1.0, 2.0, true);
        let pose = Pose::new(DVec3::new(0.8, 0.1, 1.0), DQuat::from_axis_angle(DVec3::new(1.0, 2.0, 3.0).normalize(), 0.7));
        let c = drum.polyhedron_volume(&Polyhedron::cube(0.3), &pose).unwrap();
        let about_axis = (pose.position.cross(c.push) + c.turn_a).dot(DVec3::Z);
        assert!(about_axis.abs() < 1e-14, "{about_axis:e}");
        assert!(c.push.dot(pose.position) < 0.0, "pushes towards the axis");
    }

    #[test]
    fn a_cube_face_down_on_a_floor_has_its_area_and_depth() {
        let floor = Plane::new(DVec3::ZERO, DVec3::Z);
        let c = floor.polyhedron_volume(&Polyhedron::cube(0.2), &Pose::from_position(DVec3::new(0.3, 0.4, 0.099))).unwrap();
        assert!((c.volume - 0.04 * 0.001).abs() < 1e-15 && (c.area - 0.04).abs() < 1e-14 && (c.depth - 0.001).abs() < 1e-14);
        assert!((c.point - DVec3::new(0.3, 0.4, -0.0005)).length() < 1e-12, "{:?}", c.point);
        assert!(c.turn_a.length() < 1e-15);
    }

    #[test]
    fn pair_forces_and_torques_balance() {
        let (a, b) = (Polyhedron::dodecahedron(0.5), Polyhedron::octahedron(1.0));
        let (pa, pb) = (
            Pose::new(DVec3::new(0.6, 0.5, 0.4), DQuat::from_axis_angle(DVec3::new(1.0, 0.0, 1.0).normalize(), 0.4)),
            Pose::new(DVec3::new(0.1, -0.1, 0.0), DQuat::from_axis_angle(DVec3::Y, 1.1)),
        );
        let c = polyhedron_polyhedron_volume(&a, &pa, &b, &pb).unwrap();
        let total = pa.position.cross(c.push) + c.turn_a - pb.position.cross(c.push) + c.turn_b;
        assert!(total.length() < 1e-13, "{total:?}");
        // The rate of V under a common rigid motion is zero.
        let (v, w) = (DVec3::new(0.3, -0.2, 0.5), DVec3::new(1.0, 2.0, -0.5));
        let rate = c.volume_rate(v + w.cross(pa.position) - (v + w.cross(pb.position)), w, w);
        assert!(rate.abs() < 1e-13, "{rate:e}");
    }
}
