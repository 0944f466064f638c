//! The overlap of two convex polyhedra as a polytope, I = A ∩ B, with what an energy-conserving
//! contact needs from it (Feng, Han & Owen 2012): its volume V and, over the part of its boundary
//! that lies on B's faces, the area vector S = ∫ n_B dA and the first moment M = ∫ r × n_B dA.
//! Those are the derivatives of V: translating A by dx changes V by −S·dx, and turning A by dθ
//! about a point x changes it by −(M − x × S)·dθ, so a potential w(V) gives A the force
//! w'(V) S and the torque about x, w'(V) (M − x × S), with B taking the opposite wrench.
//!
//! I is built by clipping A's faces by every face plane of B (Sutherland–Hodgman per polygon,
//! a cap polygon on the plane closing the cut). A face of A that lies in a plane of B with the
//! same outward normal belongs to both boundaries: it counts half to each, which is the mean of
//! the two one-sided derivatives (an aligned stack of equal cubes then feels no sideways push).

use crate::{DVec3, Polyhedron, Pose};

/// Which body's surface a boundary polygon of the overlap lies on.
#[derive(Clone, Copy, Debug, PartialEq)]
enum Owner {
    A,
    B,
    /// Coplanar faces of both with the same outward normal.
    Both,
}

struct Polygon {
    points: Vec<DVec3>,
    owner: Owner,
}

/// The overlap polytope's volume and the derivatives of that volume (world frame).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct OverlapVolume {
    pub volume: f64,
    /// ∫ n_B dA over B's faces inside A: the force on A is w'(V) · area.
    pub area: DVec3,
    /// ∫ r × n_B dA over the same faces, about the world origin.
    pub moment: DVec3,
    /// Volume centroid of the overlap.
    pub centroid: DVec3,
}

impl OverlapVolume {
    /// ∂V/∂θ_A about the point `x` is −(moment − x × area); this is the torque per unit w'(V) on A about x.
    pub fn torque_about(&self, x: DVec3) -> DVec3 {
        self.moment - x.cross(self.area)
    }
}

/// Relative tolerance of "on the plane", in units of the bodies' size.
const PLANE_TOLERANCE: f64 = 1e-12;

/// The overlap of A (at `pose_a`) and B (at `pose_b`), or None when they do not intersect
/// (or only touch: zero volume).
///
/// ```
/// use tumble_geom::{DVec3, Polyhedron, Pose, overlap_volume};
/// let cube = Polyhedron::cube(1.0);
/// // Unit cubes overlapping by 0.1 along z: V = 0.1, B's top face (area 1, normal +z) pushes A up.
/// let o = overlap_volume(&cube, &Pose::from_position(DVec3::new(0.0, 0.0, 0.9)), &cube, &Pose::from_position(DVec3::ZERO)).unwrap();
/// assert!((o.volume - 0.1).abs() < 1e-12 && (o.area - DVec3::Z).length() < 1e-12);
/// ```
pub fn overlap_volume(a: &Polyhedron, pose_a: &Pose, b: &Polyhedron, pose_b: &Pose) -> Option<OverlapVolume> {
    let scale = a.bounding_radius().max(b.bounding_radius());
    let eps = PLANE_TOLERANCE * scale;
    let mut polygons: Vec<Polygon> = a
        .faces()
        .iter()
        .map(|f| Polygon { points: f.vertices.iter().map(|&v| pose_a.to_world(a.vertices()[v as usize])).collect(), owner: Owner::A })
        .collect();
    for face in b.faces() {
        let n = pose_b.rotate(face.normal);
        let d = n.dot(pose_b.to_world(face.centroid));
        let mut cut: Vec<DVec3> = Vec::new();
        let mut shared = false;
        for polygon in polygons.iter_mut() {
            let h: Vec<f64> = polygon.points.iter().map(|p| n.dot(*p) - d).collect();
            if h.iter().all(|x| x.abs() <= eps) {
                // In the plane: shared when it faces the same way, else a zero-thickness sliver.
                if polygon_normal(&polygon.points).dot(n) > 0.0 {
                    polygon.owner = if polygon.owner == Owner::A { Owner::Both } else { polygon.owner };
                    shared = true;
                } else {
                    polygon.points.clear();
                }
                continue;
            }
            polygon.points = clip(&polygon.points, &h, eps, &mut cut);
        }
        polygons.retain(|p| p.points.len() >= 3);
        if !shared && cut.len() >= 3 {
            let cap = convex_polygon_in_plane(cut, n, eps);
            if cap.len() >= 3 {
                polygons.push(Polygon { points: cap, owner: Owner::B });
            }
        }
        if polygons.is_empty() {
            return None;
        }
    }
    let mut volume = 0.0;
    let mut first = DVec3::ZERO;
    let (mut area, mut moment) = (DVec3::ZERO, DVec3::ZERO);
    for polygon in &polygons {
        let p = &polygon.points;
        let weight = match polygon.owner {
            Owner::A => 0.0,
            Owner::B => 1.0,
            Owner::Both => 0.5,
        };
        for k in 1..p.len() - 1 {
            let (p0, p1, p2) = (p[0], p[k], p[k + 1]);
            let cross = (p1 - p0).cross(p2 - p0);
            // Divergence theorem over the fan triangle: signed tetrahedron from the origin.
            let six_v = p0.dot(p1.cross(p2));
            volume += six_v / 6.0;
            first += six_v / 24.0 * (p0 + p1 + p2);
            let tri_area = 0.5 * cross;
            area += weight * tri_area;
            moment += weight * ((p0 + p1 + p2) / 3.0).cross(tri_area);
        }
    }
    (volume > 0.0).then(|| OverlapVolume { volume, area, moment, centroid: first / volume })
}

/// Newell's normal of a planar polygon (unnormalised; its length is twice the area).
fn polygon_normal(points: &[DVec3]) -> DVec3 {
    let mut n = DVec3::ZERO;
    for k in 0..points.len() {
        let (p, q) = (points[k], points[(k + 1) % points.len()]);
        n += DVec3::new((p.y - q.y) * (p.z + q.z), (p.z - q.z) * (p.x + q.x), (p.x - q.x) * (p.y + q.y));
    }
    n
}

/// The part of a convex polygon with signed heights `h` where h ≤ 0; points on the plane go to `cut`.
fn clip(points: &[DVec3], h: &[f64], eps: f64, cut: &mut Vec<DVec3>) -> Vec<DVec3> {
    let mut out = Vec::with_capacity(points.len() + 1);
    for k in 0..points.len() {
        let j = (k + 1) % points.len();
        let (p, hp, q, hq) = (points[k], h[k], points[j], h[j]);
        if hp <= eps {
            out.push(p);
            if hp >= -eps {
                cut.push(p);
            }
        }
        if (hp < -eps && hq > eps) || (hp > eps && hq < -eps) {
            let x = p + (q - p) * (hp / (hp - hq));
            out.push(x);
            cut.push(x);
        }
    }
    out
}

/// The distinct points of `points` (all in the plane with normal `n`) ordered counter-clockwise about n.
fn convex_polygon_in_plane(mut points: Vec<DVec3>, n: DVec3, eps: f64) -> Vec<DVec3> {
    let mut distinct: Vec<DVec3> = Vec::with_capacity(points.len());
    for p in points.drain(..) {
        if distinct.iter().all(|q| (*q - p).length() > 10.0 * eps) {
            distinct.push(p);
        }
    }
    let centre = distinct.iter().copied().sum::<DVec3>() / distinct.len() as f64;
    let u = n.any_orthonormal_vector();
    let v = n.cross(u);
    distinct.sort_by(|p, q| {
        let (dp, dq) = (*p - centre, *q - centre);
        dp.dot(v).atan2(dp.dot(u)).total_cmp(&dq.dot(v).atan2(dq.dot(u)))
    });
    distinct
}

#[cfg(test)]
mod tests {
    use super::*;
    use glam::DQuat;

    fn pose(x: DVec3, axis: DVec3, angle: f64) -> Pose {
        Pose::new(x, DQuat::from_axis_angle(axis.normalize(), angle))
    }

    #[test]
    fn aligned_boxes_overlap_in_a_box() {
        let cube = Polyhedron::cube(1.0);
        let o = overlap_volume(&cube, &Pose::from_position(DVec3::new(0.3, 0.2, 0.9)), &cube, &Pose::from_position(DVec3::ZERO)).unwrap();
        assert!((o.volume - 0.7 * 0.8 * 0.1).abs() < 1e-12, "{o:?}");
        assert!((o.centroid - DVec3::new(0.15, 0.1, 0.45)).length() < 1e-12);
        // B's faces inside A: its top (0.56 along +z), and its +x and +y sides (0.08 and 0.07).
        assert!((o.area - DVec3::new(0.08, 0.07, 0.56)).length() < 1e-12, "{:?}", o.area);
    }

    #[test]
    fn an_aligned_stack_feels_no_sideways_push() {
        let cube = Polyhedron::cube(1.0);
        let o = overlap_volume(&cube, &Pose::from_position(DVec3::new(0.0, 0.0, 0.95)), &cube, &Pose::from_position(DVec3::ZERO)).unwrap();
        assert!((o.volume - 0.05).abs() < 1e-12);
        assert!((o.area - DVec3::Z).length() < 1e-12, "{:?}", o.area);
        assert!(o.torque_about(DVec3::new(0.0, 0.0, 0.95)).length() < 1e-12);
    }

    #[test]
    fn separated_bodies_do_not_overlap() {
        let cube = Polyhedron::cube(1.0);
        assert!(overlap_volume(&cube, &Pose::from_position(DVec3::new(0.0, 0.0, 1.01)), &cube, &Pose::from_position(DVec3::ZERO)).is_none());
    }

    /// The area vector and moment are the volume's derivatives: central differences of V under
    /// translations and rotations of A agree with −S and −(M − x_A × S).
    #[test]
    fn area_and_moment_are_the_derivatives_of_the_volume() {
        let shapes = [Polyhedron::cube(1.0), Polyhedron::dodecahedron(0.6), Polyhedron::octahedron(1.2), Polyhedron::tetrahedron(1.3)];
        let mut seed = 0x2545_f491_4f6c_dd1du64;
        let mut next = || {
            seed ^= seed << 13;
            seed ^= seed >> 7;
            seed ^= seed << 17;
            (seed >> 11) as f64 / (1u64 << 53) as f64
        };
        let mut checked = 0;
        for trial in 0..200 {
            let (a, b) = (&shapes[trial % 4], &shapes[(trial / 4) % 4]);
            let axis = DVec3::new(next() - 0.5, next() - 0.5, next() - 0.5);
            let pb = pose(DVec3::ZERO, DVec3::new(next() - 0.5, next() - 0.5, next() - 0.5), 6.0 * next());
            let dir = DVec3::new(next() - 0.5, next() - 0.5, next() - 0.5).normalize();
            let reach = a.bounding_radius() + b.bounding_radius();
            let (xa, angle) = (dir * reach * (0.55 + 0.3 * next()), 6.0 * next());
            let at = |x: DVec3, turn: DVec3| -> f64 {
                let q = DQuat::from_scaled_axis(turn) * DQuat::from_axis_angle(axis.normalize(), angle);
                overlap_volume(a, &Pose::new(x, q), b, &pb).map_or(0.0, |o| o.volume)
            };
            let Some(o) = overlap_volume(a, &pose(xa, axis, angle), b, &pb) else { continue };
            if o.volume < 1e-3 * a.volume().min(b.volume()) {
                continue;
            }
            let h = 1e-6;
            let mut grad = DVec3::ZERO;
            let mut rot = DVec3::ZERO;
            for k in 0..3 {
                let e = DVec3::AXES[k] * h;
                grad[k] = (at(xa + e, DVec3::ZERO) - at(xa - e, DVec3::ZERO)) / (2.0 * h);
                rot[k] = (at(xa, e) - at(xa, -e)) / (2.0 * h);
            }
            let size = o.area.length().max(1e-3);
            assert!((grad + o.area).length() < 1e-5 * size, "trial {trial}: ∂V/∂x = {grad:?}, −S = {:?}", -o.area);
            assert!((rot + o.torque_about(xa)).length() < 1e-5 * size * reach, "trial {trial}: ∂V/∂θ = {rot:?} vs {:?}", -o.torque_about(xa));
            checked += 1;
        }
        assert!(checked > 50, "only {checked} overlapping trials");
    }

    #[test]
    fn volume_agrees_with_a_sampled_estimate() {
        let (a, b) = (Polyhedron::dodecahedron(0.6), Polyhedron::cube(1.0));
        let (pa, pb) = (pose(DVec3::new(0.4, 0.3, 0.5), DVec3::new(1.0, 2.0, 0.5), 0.7), pose(DVec3::ZERO, DVec3::new(0.3, -1.0, 0.2), 0.4));
        let o = overlap_volume(&a, &pa, &b, &pb).unwrap();
        // Midpoint grid over B's bounding cube: points inside both.
        let (n, half) = (120, 0.9);
        let cell = 2.0 * half / n as f64;
        let mut inside = 0usize;
        for i in 0..n {
            for j in 0..n {
                for k in 0..n {
                    let p = DVec3::new(-half + (i as f64 + 0.5) * cell, -half + (j as f64 + 0.5) * cell, -half + (k as f64 + 0.5) * cell);
                    if a.contains(pa.to_body(p)) && b.contains(pb.to_body(p)) {
                        inside += 1;
                    }
                }
            }
        }
        let sampled = inside as f64 * cell.powi(3);
        assert!((sampled / o.volume - 1.0).abs() < 1e-2, "clipped {} vs sampled {sampled}", o.volume);
    }
}
