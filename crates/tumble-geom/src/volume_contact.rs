//! Overlap-volume contacts of a convex polyhedron with another one or with a wall: the volume V
//! of the overlap and its derivatives with respect to A's pose, the corners of each body inside
//! the other and the parts of their edges inside the other, everything an energy-conserving
//! normal force needs (docs/polyhedra.md, "The overlap-volume contact"). The force is a sum of
//! potentials, each the normal law at a depth: the law at V / A_ref (V spread over a reference
//! area) along V's gradient, the law at each corner inside the other body (its smoothed depth),
//! and the law along the edges inside, per unit length [`edge_density`] (so the edges of a face
//! lying flat weigh as much as its corners). A corner meets the law once, as the separating-axis
//! depth model has it; a face lying on a larger face meets it [`face_on_weight`] times (the
//! volume, its corners, its edges); crossed edges, which no corner enters, meet it along the
//! edges as a cone would (force ∝ δ²). The volume alone would leave corners (∝ δ⁵) and crossed
//! edges soft, the corners alone would let edges pass through edges.
//!
//! Walls are in `volume_walls.rs`.

use crate::overlap_volume::{Moments, PLANE_TOLERANCE, Region, Slab, outside_slab, overlap_moments_in, segment_pieces, with_scratch};
use crate::{DQuat, DVec3, Polyhedron, Pose, polyhedron_polyhedron};

/// The corner count of a polyhedron's largest face over its perimeter: the multiple of the normal
/// law an edge carries per unit length inside the other body.
pub fn edge_density(p: &Polyhedron) -> f64 {
    let f = p.largest_face();
    p.faces()[f].vertices.len() as f64 / p.face_perimeter(f)
}

/// How many times a face of the largest area lying on a larger face meets the normal law: once for
/// the volume, once per corner, once more for its edges together. The damping of every part is
/// that of the law at m* / this weight, so a face-on impact rebounds at the restitution asked for.
pub fn face_on_weight(p: &Polyhedron) -> f64 {
    1.0 + 2.0 * p.faces()[p.largest_face()].vertices.len() as f64
}

/// The width τ of the band in which a corner's push turns from one face to the next, as a
/// fraction of the smaller body's bounding radius.
pub const CORNER_SMOOTHING: f64 = 0.01;

/// Three-point Gauss–Legendre nodes and weights on [−1, 1]: exact for the linear law's energy,
/// force and moment along an edge piece (polynomials of degree 2 in the position).
const GAUSS: [(f64, f64); 3] = [(-0.774_596_669_241_483_4, 5.0 / 9.0), (0.0, 8.0 / 9.0), (0.774_596_669_241_483_4, 5.0 / 9.0)];

/// One point load of a volume contact: a corner inside the other body (or a wall's solid), or a
/// quadrature point of an edge's part inside it.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct PenetratingPoint {
    /// Where the load acts (world).
    pub point: DVec3,
    /// How deep the point is inside: for a corner the smoothed distance to the surface (see
    /// [`CORNER_SMOOTHING`]), for an edge point the distance to the nearest face.
    pub depth: f64,
    /// The depth's gradient, from B (or the wall) to A: the force on A along it pushes the point
    /// out. A unit vector except for a corner within ~τ of an edge of the body it is in.
    pub normal: DVec3,
    /// The multiple of the normal law this point carries: 1 for a corner, quadrature weight ×
    /// length × [`edge_density`] for an edge point.
    pub weight: f64,
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
    /// The corners and edge points of either body inside the other.
    pub points: Vec<PenetratingPoint>,
}

impl VolumeContact {
    /// dV/dt for A moving at (v, ω) relative to B at (v_b, ω_b), both centres' velocities:
    /// −(push · (v − v_b) + turn_a · ω + turn_b · ω_b). For a wall pass v_b = the wall's velocity
    /// at A's centre and put its spin into ω as ω − Ω (turn_b is zero).
    pub fn volume_rate(&self, v_rel: DVec3, omega_a: DVec3, omega_b: DVec3) -> f64 {
        -(self.push.dot(v_rel) + self.turn_a.dot(omega_a) + self.turn_b.dot(omega_b))
    }

    /// The same contact with both bodies moved rigidly: rotated by `rotation`, then shifted by `shift`.
    pub fn move_rigidly(&mut self, rotation: DQuat, shift: DVec3) {
        for v in [&mut self.push, &mut self.turn_a, &mut self.turn_b, &mut self.normal] {
            *v = rotation * *v;
        }
        self.point = rotation * self.point + shift;
        for p in &mut self.points {
            p.point = rotation * p.point + shift;
            p.normal = rotation * p.normal;
        }
    }

    /// A contact of corner and edge loads alone (no volume yet), normal `normal` at `point`;
    /// `None` without loads.
    pub(crate) fn points_only(normal: DVec3, point: DVec3, points: Vec<PenetratingPoint>) -> Option<VolumeContact> {
        let depth = points.iter().map(|p| p.depth).fold(0.0, f64::max);
        (depth > 0.0).then_some(VolumeContact {
            volume: 0.0,
            push: DVec3::ZERO,
            turn_a: DVec3::ZERO,
            turn_b: DVec3::ZERO,
            normal,
            point,
            area: 0.0,
            depth,
            points,
        })
    }

    pub(crate) fn from_moments(
        m: &Moments,
        origin: DVec3,
        xa: DVec3,
        xb: Option<DVec3>,
        push: DVec3,
        depth: f64,
        points: Vec<PenetratingPoint>,
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
            points,
        })
    }
}

/// The corners of `a` inside `b` (pushing A out along +gradient when `sign` = 1; B's corners
/// inside A take sign −1), depths smoothed over `tau`, into `out` (points relative to `origin`).
pub(crate) fn corners_inside(out: &mut Vec<PenetratingPoint>, a: &Region, b: &Region, origin: DVec3, tau: f64, sign: f64, slab: Slab) {
    for &v in &a.vertices {
        if outside_slab(slab, &[v], 0.0) {
            continue;
        }
        if let Some((depth, normal)) = b.penetration(v, tau) {
            out.push(PenetratingPoint { point: v + origin, depth, normal: sign * normal, weight: 1.0 });
        }
    }
}

/// The parts of `a`'s edges inside `b`: three Gauss points per piece on which one face of `b` is
/// the nearest, each carrying its quadrature weight × length × `density`.
pub(crate) fn edges_inside(out: &mut Vec<PenetratingPoint>, a: &Region, b: &Region, origin: DVec3, sign: f64, density: f64, slab: Slab) {
    for &[p0, p1] in &a.edges {
        if outside_slab(slab, &[p0, p1], 0.0) {
            continue;
        }
        segment_loads(out, &b.planes, p0, p1, origin, sign, density);
    }
}

/// The segment p0–p1's part inside `planes`: three Gauss points per piece on which one plane is
/// the nearest, each at its depth below that plane, pushing along `sign` × its normal, with its
/// quadrature weight × length × `density`.
pub(crate) fn segment_loads(out: &mut Vec<PenetratingPoint>, planes: &[(DVec3, f64)], p0: DVec3, p1: DVec3, origin: DVec3, sign: f64, density: f64) {
    let length = (p1 - p0).length();
    for (s0, s1, f) in segment_pieces(planes, p0, p1) {
        let (m, offset) = planes[f];
        let (mid, half) = (0.5 * (s0 + s1), 0.5 * (s1 - s0));
        for (x, w) in GAUSS {
            let p = p0 + (p1 - p0) * (mid + half * x);
            let depth = offset - m.dot(p);
            if depth > 0.0 {
                out.push(PenetratingPoint { point: p + origin, depth, normal: sign * m, weight: w * half * length * density });
            }
        }
    }
}

/// Every corner and edge point of A inside B and of B inside A, the edges weighed by their body's
/// [`edge_density`] (a wall's edges by the polyhedron's).
pub(crate) fn penetrating_points(
    a: &Region,
    b: &Region,
    origin: DVec3,
    tau: f64,
    a_density: f64,
    b_density: f64,
    slab: Slab,
) -> Vec<PenetratingPoint> {
    let mut out = Vec::new();
    corners_inside(&mut out, a, b, origin, tau, 1.0, slab);
    corners_inside(&mut out, b, a, origin, tau, -1.0, slab);
    edges_inside(&mut out, a, b, origin, 1.0, a_density, slab);
    edges_inside(&mut out, b, a, origin, -1.0, b_density, slab);
    out
}

/// The slab between the deepest points of two regions along the separating-axis normal `n` (B to
/// A): the overlap lies in it.
fn pair_slab(a: &Region, b: &Region, n: DVec3) -> Slab {
    let lo = a.vertices.iter().map(|v| n.dot(*v)).fold(f64::INFINITY, f64::min);
    let hi = b.vertices.iter().map(|v| n.dot(*v)).fold(f64::NEG_INFINITY, f64::max);
    Some((n, lo, hi))
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
    pair_volume(a, pose_a, b, pose_b, k.point, k.normal, k.depth, edge_density(b))
}

/// The volume contact of a pair whose separating-axis contact is (point, normal, depth); B's edges
/// carry `b_density` per unit length.
#[allow(clippy::too_many_arguments)]
pub(crate) fn pair_volume(
    a: &Polyhedron,
    pose_a: &Pose,
    b: &Polyhedron,
    pose_b: &Pose,
    origin: DVec3,
    normal: DVec3,
    depth: f64,
    b_density: f64,
) -> Option<VolumeContact> {
    let eps = PLANE_TOLERANCE * a.bounding_radius().max(b.bounding_radius());
    let tau = CORNER_SMOOTHING * a.bounding_radius().min(b.bounding_radius());
    with_scratch(|s| {
        s.a.set_polyhedron(a, pose_a, origin);
        s.b.set_polyhedron(b, pose_b, origin);
        let slab = pair_slab(&s.a, &s.b, normal);
        let (m, _) = overlap_moments_in(&s.a, &s.b, eps, slab, &mut s.clip)?;
        let points = penetrating_points(&s.a, &s.b, origin, tau, edge_density(a), b_density, slab);
        VolumeContact::from_moments(&m, origin, pose_a.position, Some(pose_b.position), m.area, depth, points)
    })
}

/// A polyhedron against a wall's hull (a lifter bar): the pair's contact with the hull's edges
/// weighed by the polyhedron's edge density.
pub fn wall_hull_volume(poly: &Polyhedron, pose: &Pose, hull: &Polyhedron, hull_pose: &Pose) -> Option<VolumeContact> {
    let k = polyhedron_polyhedron(poly, pose, hull, hull_pose)?;
    pair_volume(poly, pose, hull, hull_pose, k.point, k.normal, k.depth, edge_density(poly))
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::{Cylinder, Plane, Quad, SurfaceShape};
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

    /// The linear law's potential of a contact (k = 1, reference area `a_ref`): ½ (V / A)² plus
    /// Σ weight × ½ depth² over its points, and the force and torque about `x` that the contact
    /// applies for it.
    fn potential(c: &VolumeContact, a_ref: f64, x: DVec3) -> (f64, DVec3, DVec3) {
        let w = c.volume / (a_ref * a_ref);
        let mut u = 0.5 * (c.volume / a_ref).powi(2);
        let (mut f, mut t) = (c.push * w, c.turn_a * w);
        for p in &c.points {
            u += p.weight * 0.5 * p.depth * p.depth;
            f += p.normal * (p.weight * p.depth);
            t += (p.point - x).cross(p.normal * (p.weight * p.depth));
        }
        (u, f, t)
    }

    /// The whole normal force (volume, corners, edges) is the gradient of one potential: central
    /// differences of it under translations and rotations of A agree with the force and torque,
    /// for pairs of the test solids and against a plane and a quad (face, edge and corner regions).
    #[test]
    fn the_normal_force_is_the_gradient_of_its_potential() {
        let shapes = [Polyhedron::cube(1.0), Polyhedron::dodecahedron(0.6), Polyhedron::octahedron(1.2), Polyhedron::tetrahedron(1.3)];
        let quad = Quad::new([DVec3::new(-1.0, -1.0, 0.0), DVec3::new(1.0, -1.0, 0.1), DVec3::new(1.0, 1.0, 0.1), DVec3::new(-1.0, 1.0, 0.0)], false);
        let floor = Plane::new(DVec3::ZERO, DVec3::new(0.1, 0.2, 1.0));
        let drum = Cylinder::new(DVec3::ZERO, DVec3::Z, 1.0, 1.0, true);
        let mut seed = 0x1234_5678_9abc_def1u64;
        let mut next = || {
            seed ^= seed << 13;
            seed ^= seed >> 7;
            seed ^= seed << 17;
            (seed >> 11) as f64 / (1u64 << 53) as f64
        };
        let (mut checked, mut with_edges) = (0, 0);
        for trial in 0..320 {
            let a = &shapes[(trial / 4) % 4];
            let q = DQuat::from_axis_angle(DVec3::new(next() - 0.5, next() - 0.5, next() - 0.5).normalize(), 6.0 * next());
            let dir = DVec3::new(next() - 0.5, next() - 0.5, next() - 0.5).normalize();
            let (contact, x): (Box<dyn Fn(&Pose) -> Option<VolumeContact>>, DVec3) = match trial % 4 {
                3 => (Box::new(|p: &Pose| drum.polyhedron_volume(a, p)), {
                    let phi = 6.0 * next();
                    let r = 1.0 - a.bounding_radius() * (0.3 + 0.6 * next());
                    DVec3::new(r * phi.cos(), r * phi.sin(), 0.5)
                }),
                0 => {
                    let b = &shapes[(trial / 3) % 4];
                    let pb = Pose::new(DVec3::ZERO, DQuat::from_axis_angle(DVec3::new(1.0, -2.0, 0.5).normalize(), 0.3 * trial as f64));
                    let reach = a.bounding_radius() + b.bounding_radius();
                    (Box::new(move |p: &Pose| polyhedron_polyhedron_volume(a, p, b, &pb)), dir * reach * (0.6 + 0.3 * next()))
                }
                1 => (Box::new(|p: &Pose| floor.polyhedron_volume(a, p)), floor.normal * a.bounding_radius() * (0.5 + 0.45 * next()) + dir * 0.2),
                _ => (
                    Box::new(|p: &Pose| quad.polyhedron_volume(a, p)),
                    DVec3::new(2.4 * next() - 1.2, 2.4 * next() - 1.2, a.bounding_radius() * (0.5 + 0.45 * next())),
                ),
            };
            let a_ref = a.largest_face_area();
            let u = |x: DVec3, turn: DVec3| contact(&Pose::new(x, DQuat::from_scaled_axis(turn) * q)).map_or(0.0, |c| potential(&c, a_ref, x).0);
            let Some(c) = contact(&Pose::new(x, q)) else { continue };
            let (_, force, torque) = potential(&c, a_ref, x);
            if force.length() < 1e-4 {
                continue;
            }
            let h = 1e-6;
            let (mut grad, mut rot) = (DVec3::ZERO, DVec3::ZERO);
            for k in 0..3 {
                let e = DVec3::AXES[k] * h;
                grad[k] = (u(x + e, DVec3::ZERO) - u(x - e, DVec3::ZERO)) / (2.0 * h);
                rot[k] = (u(x, e) - u(x, -e)) / (2.0 * h);
            }
            let scale = force.length();
            assert!((grad + force).length() < 1e-5 * scale, "trial {trial}: −∂U/∂x {:?} against the force {force:?}", -grad);
            assert!((rot + torque).length() < 1e-5 * scale * a.size(), "trial {trial}: −∂U/∂θ {:?} against the torque {torque:?}", -rot);
            checked += 1;
            with_edges += c.points.iter().any(|p| p.weight != 1.0) as usize;
        }
        assert!(checked > 120 && with_edges > 100, "{checked} checked, {with_edges} with edge points");
    }

    #[test]
    fn segment_pieces_follow_the_nearest_face() {
        // A unit cube about the origin; a segment through it along x at y = 0.3, z = 0: the nearest
        // face is −x, then +y, then +x.
        let cube = Polyhedron::cube(1.0);
        let r = crate::overlap_volume::Region::of_polyhedron(&cube, &Pose::IDENTITY, DVec3::ZERO);
        let pieces = segment_pieces(&r.planes, DVec3::new(-1.0, 0.3, 0.0), DVec3::new(1.0, 0.3, 0.0));
        let normals: Vec<DVec3> = pieces.iter().map(|p| r.planes[p.2].0).collect();
        assert_eq!(normals, vec![-DVec3::X, DVec3::Y, DVec3::X]);
        let ends: Vec<(f64, f64)> = pieces.iter().map(|p| (p.0, p.1)).collect();
        let expected = [(0.25, 0.35), (0.35, 0.65), (0.65, 0.75)];
        assert!(ends.iter().zip(expected).all(|(a, b)| (a.0 - b.0).abs() < 1e-12 && (a.1 - b.1).abs() < 1e-12), "{ends:?}");
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
