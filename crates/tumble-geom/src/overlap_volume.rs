//! The overlap of two convex bodies as a polytope, I = A ∩ B, with what an energy-conserving
//! contact needs from it (Feng, Han & Owen 2012): its volume V and, over the part of its boundary
//! that lies on B's faces, the area vector S = ∫ n_B dA and the first moment M = ∫ r × n_B dA.
//! Those are the derivatives of V: translating A by dx changes V by −S·dx, and turning A by dθ
//! about a point x changes it by −(M − x × S)·dθ, so a potential w(V) gives A the force
//! w'(V) S and the torque about x, w'(V) (M − x × S), with B taking the opposite wrench.
//!
//! The boundary of I is A's faces clipped by B's planes and B's faces clipped by A's planes
//! (Sutherland–Hodgman per polygon); V follows from the divergence theorem over both sets, S and
//! M from B's set alone. A face of one body lying in a plane of the other with the same outward
//! normal belongs to both boundaries: each copy counts half, which is the mean of the two
//! one-sided derivatives (an aligned stack of equal cubes then feels no sideways push). A wall
//! is a body of the same kind: its bounding planes and its faces as polygons large enough to
//! cover any cross-section of A (`overlap_walls.rs`).
//!
//! Everything is computed relative to an `origin` near the overlap, so that the divergence sums
//! are of the size of V itself and not of the bodies' (this is what keeps the f32 port exact
//! enough for overlaps of 1e-4 of the size).

use crate::polyhedron_polyhedron::Buf;
use crate::{DVec3, Polyhedron, Pose};

/// The overlap polytope's volume and the derivatives of that volume.
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

    /// The point on the line of action of the area vector nearest the overlap's centroid: where a
    /// contact force along `area` acts (exactly, when the moment has no part along the area).
    pub fn action_point(&self) -> DVec3 {
        let s2 = self.area.length_squared();
        if s2 == 0.0 {
            return self.centroid;
        }
        self.centroid + self.area.cross(self.torque_about(self.centroid)) / s2
    }
}

/// Relative tolerance of "on the plane", in units of the bodies' size.
pub(crate) const PLANE_TOLERANCE: f64 = 1e-12;

/// A convex body as the clipper sees it, relative to the origin of the computation: its bounding
/// planes m · p ≤ offset (m the outward unit normal) and the faces of its boundary that can lie
/// inside the other body (convex polygons, counter-clockwise seen from outside).
#[derive(Default)]
pub(crate) struct Region {
    pub planes: Vec<(DVec3, f64)>,
    /// Each face's outward normal and where its corners lie in `loops` (start, count).
    pub faces: Vec<(DVec3, u32, u32)>,
    pub loops: Vec<DVec3>,
    /// Corners that can poke into the other body.
    pub vertices: Vec<DVec3>,
    /// Edges that can cross into the other body.
    pub edges: Vec<[DVec3; 2]>,
}

/// Per-thread buffers the contact routines refill on every call (nothing allocated per contact).
#[derive(Default)]
pub(crate) struct Scratch {
    pub a: Region,
    pub b: Region,
    pub clip: ClipBuffers,
}

thread_local! {
    static SCRATCH: std::cell::RefCell<Scratch> = std::cell::RefCell::new(Scratch::default());
}

/// Runs `f` with this thread's scratch buffers.
pub(crate) fn with_scratch<T>(f: impl FnOnce(&mut Scratch) -> T) -> T {
    SCRATCH.with(|s| f(&mut s.borrow_mut()))
}

impl Region {
    /// A polyhedron at `pose`, relative to `origin`.
    #[cfg(test)]
    pub fn of_polyhedron(p: &Polyhedron, pose: &Pose, origin: DVec3) -> Region {
        let mut region = Region::default();
        region.set_polyhedron(p, pose, origin);
        region
    }

    /// Empties the region, keeping its buffers.
    pub fn clear(&mut self) {
        self.planes.clear();
        self.faces.clear();
        self.loops.clear();
        self.vertices.clear();
        self.edges.clear();
    }

    /// Makes this region the polyhedron `p` at `pose`, relative to `origin`.
    pub fn set_polyhedron(&mut self, p: &Polyhedron, pose: &Pose, origin: DVec3) {
        self.clear();
        self.vertices.extend(p.vertices().iter().map(|v| pose.to_world(*v) - origin));
        for f in p.faces() {
            let n = pose.rotate(f.normal);
            self.planes.push((n, n.dot(self.vertices[f.vertices[0] as usize])));
            let start = self.loops.len() as u32;
            for &v in &f.vertices {
                self.loops.push(self.vertices[v as usize]);
            }
            self.faces.push((n, start, f.vertices.len() as u32));
        }
        for e in p.edges() {
            self.edges.push([self.vertices[e.vertices[0] as usize], self.vertices[e.vertices[1] as usize]]);
        }
    }

    /// Adds a face: its outward normal and corners (counter-clockwise seen from outside).
    pub fn add_face(&mut self, normal: DVec3, corners: impl IntoIterator<Item = DVec3>) {
        let start = self.loops.len() as u32;
        self.loops.extend(corners);
        self.faces.push((normal, start, self.loops.len() as u32 - start));
    }

    /// Face k: its outward normal and corners.
    pub fn face(&self, k: usize) -> (DVec3, &[DVec3]) {
        let (n, start, count) = self.faces[k];
        (n, &self.loops[start as usize..(start + count) as usize])
    }

    /// How deep `p` lies inside this region and the gradient of that depth, or `None` outside.
    ///
    /// The depth is the smooth minimum of the distances d_f to the bounding planes,
    /// d = −τ ln Σ exp(−d_f / τ), so a corner near an edge of the region turns its push from one
    /// face's normal to the other's over a band of width ~τ rather than at once (a kink in a
    /// potential costs the integrator its order); d ≤ min d_f, equal to it far from edges. The
    /// gradient −∂d/∂p = Σ w_f m_f (weights exp(−d_f/τ) normalised) points out through the
    /// nearest faces and is a unit vector only away from edges.
    pub fn penetration(&self, p: DVec3, tau: f64) -> Option<(f64, DVec3)> {
        if self.planes.iter().any(|&(m, offset)| offset - m.dot(p) <= 0.0) {
            return None;
        }
        smooth_depth(self.planes.iter(), p, tau)
    }
}

/// The smooth minimum d = −τ ln Σ exp(−d_f / τ) of the distances d_f of `p` inside `planes`
/// (each positive) and its gradient −∂d/∂p, as [`Region::penetration`] describes; `None` unless
/// d > 0.
pub(crate) fn smooth_depth<'a>(planes: impl Iterator<Item = &'a (DVec3, f64)> + Clone, p: DVec3, tau: f64) -> Option<(f64, DVec3)> {
    let nearest = planes.clone().fold(f64::INFINITY, |n, &(m, offset)| n.min(offset - m.dot(p)));
    let (mut sum, mut out) = (0.0, DVec3::ZERO);
    for &(m, offset) in planes {
        let w = (-(offset - m.dot(p) - nearest) / tau).exp();
        sum += w;
        out += w * m;
    }
    let depth = nearest - tau * sum.ln();
    (depth > 0.0).then(|| (depth, out / sum))
}

/// The part of the segment p0 + s (p1 − p0), s ∈ [0, 1], inside a region, as the pieces on which
/// one plane is the nearest: (s from, s to, plane index). On each piece the distance to the
/// region's surface is linear in s.
pub(crate) fn segment_pieces(planes: &[(DVec3, f64)], p0: DVec3, p1: DVec3) -> Buf<(f64, f64, usize)> {
    let e = p1 - p0;
    // h_f(s) = a_f − s b_f: the distance inside plane f.
    let (mut lo, mut hi) = (0.0f64, 1.0f64);
    let ab: Buf<(f64, f64)> = planes.iter().map(|&(m, o)| (o - m.dot(p0), m.dot(e))).collect();
    for &(a, b) in &ab {
        if b > 0.0 {
            hi = hi.min(a / b);
        } else if b < 0.0 {
            lo = lo.max(a / b);
        } else if a <= 0.0 {
            return Buf::new();
        }
    }
    let mut out = Buf::new();
    if hi <= lo {
        return out;
    }
    let nearest = |s: f64| {
        (0..ab.len()).min_by(|&f, &g| (ab[f].0 - s * ab[f].1).total_cmp(&(ab[g].0 - s * ab[g].1)).then(ab[g].1.total_cmp(&ab[f].1))).unwrap()
    };
    let mut s = lo;
    let mut f = nearest(lo);
    for _ in 0..=ab.len() {
        // The next plane to become nearer: one that falls faster along s.
        let (mut next, mut g_next) = (hi, f);
        for (g, &(a, b)) in ab.iter().enumerate() {
            if b > ab[f].1 {
                let x = (a - ab[f].0) / (b - ab[f].1);
                if x > s && x < next {
                    next = x;
                    g_next = g;
                }
            }
        }
        out.push((s, next, f));
        if next >= hi || g_next == f {
            break;
        }
        s = next;
        f = g_next;
    }
    out
}

/// Sums over the overlap's boundary, relative to the computation's origin.
#[derive(Clone, Copy, Debug, Default)]
pub(crate) struct Moments {
    pub volume: f64,
    /// ∫ x dV.
    pub first: DVec3,
    /// ∫ n_B dA and ∫ r × n_B dA over B's faces inside A.
    pub area: DVec3,
    pub moment: DVec3,
}

impl Moments {
    /// Adds the sums of another part of the same overlap (computed about the same origin).
    pub(crate) fn accumulate(&mut self, other: &Moments) {
        self.volume += other.volume;
        self.first += other.first;
        self.area += other.area;
        self.moment += other.moment;
    }

    /// Adds one boundary polygon: its share of the volume (divergence theorem, fan tetrahedra
    /// from the origin) with weight `wv` and of the area and moment with weight `wa`.
    fn add(&mut self, p: &[DVec3], wv: f64, wa: f64) {
        for k in 1..p.len() - 1 {
            let (p0, p1, p2) = (p[0], p[k], p[k + 1]);
            let six_v = p0.dot(p1.cross(p2));
            self.volume += wv * six_v / 6.0;
            self.first += wv * six_v / 24.0 * (p0 + p1 + p2);
            if wa != 0.0 {
                let tri_area = 0.5 * (p1 - p0).cross(p2 - p0);
                self.area += wa * tri_area;
                self.moment += wa * ((p0 + p1 + p2) / 3.0).cross(tri_area);
            }
        }
    }
}

/// Two polygon buffers the clipper passes back and forth (one pair per overlap, so no polygon is
/// allocated or moved per plane).
#[derive(Default)]
pub(crate) struct ClipBuffers {
    pub poly: Buf<DVec3>,
    next: Buf<DVec3>,
    h: Buf<f64>,
}

/// Clips the convex polygon `points` (outward normal `normal`) to every plane of `planes` into
/// `buf.poly`; returns whether it lies in one of those planes facing the same way (shared), or
/// `None` when nothing of positive area is left (or it lies in a plane facing the other way: a
/// touch).
pub(crate) fn clip_polygon(points: &[DVec3], normal: DVec3, planes: &[(DVec3, f64)], eps: f64, buf: &mut ClipBuffers) -> Option<bool> {
    buf.poly.clear();
    buf.poly.extend_from_slice(points);
    let mut shared = false;
    for &(m, offset) in planes {
        buf.h.clear();
        let (mut inside, mut outside, mut flat) = (true, true, true);
        for p in &buf.poly {
            let x = m.dot(*p) - offset;
            inside &= x <= eps;
            outside &= x >= -eps;
            flat &= x.abs() <= eps;
            buf.h.push(x);
        }
        if flat {
            if normal.dot(m) > 0.0 {
                shared = true;
                continue;
            }
            return None;
        }
        if inside {
            continue;
        }
        if outside {
            return None;
        }
        buf.next.clear();
        let n = buf.poly.len();
        for k in 0..n {
            let j = if k + 1 == n { 0 } else { k + 1 };
            let (p, hp, q, hq) = (buf.poly[k], buf.h[k], buf.poly[j], buf.h[j]);
            if hp <= eps {
                buf.next.push(p);
            }
            if (hp < -eps && hq > eps) || (hp > eps && hq < -eps) {
                buf.next.push(p + (q - p) * (hp / (hp - hq)));
            }
        }
        if buf.next.len() < 3 {
            return None;
        }
        std::mem::swap(&mut buf.poly, &mut buf.next);
    }
    Some(shared)
}

/// A slab the overlap lies in: (unit n, lo, hi) with lo ≤ n · x ≤ hi for every point x of A ∩ B.
pub(crate) type Slab = Option<(DVec3, f64, f64)>;

/// Whether points (all of them) lie outside the slab, by more than `eps`.
pub(crate) fn outside_slab(slab: Slab, points: &[DVec3], eps: f64) -> bool {
    slab.is_some_and(|(n, lo, hi)| points.iter().all(|p| n.dot(*p) > hi + eps) || points.iter().all(|p| n.dot(*p) < lo - eps))
}

/// The overlap's sums: A's faces clipped by B's planes (volume only) and B's faces clipped by
/// A's planes (volume, area and moment), skipping the faces outside `slab` (they cannot touch
/// the overlap); also the largest depth of the overlap below B's first plane (for walls, whose
/// first plane is the surface itself). `None` without a positive volume.
pub(crate) fn overlap_moments_in(a: &Region, b: &Region, eps: f64, slab: Slab, buf: &mut ClipBuffers) -> Option<(Moments, f64)> {
    let mut m = Moments::default();
    let (m0, o0) = b.planes[0];
    let mut depth = 0.0f64;
    for k in 0..a.faces.len() {
        let (n, face) = a.face(k);
        if outside_slab(slab, face, eps) {
            continue;
        }
        if let Some(shared) = clip_polygon(face, n, &b.planes, eps, buf) {
            m.add(&buf.poly, if shared { 0.5 } else { 1.0 }, 0.0);
            depth = buf.poly.iter().map(|p| o0 - m0.dot(*p)).fold(depth, f64::max);
        }
    }
    for k in 0..b.faces.len() {
        let (n, face) = b.face(k);
        if outside_slab(slab, face, eps) {
            continue;
        }
        if let Some(shared) = clip_polygon(face, n, &a.planes, eps, buf) {
            let w = if shared { 0.5 } else { 1.0 };
            m.add(&buf.poly, w, w);
        }
    }
    (m.volume > 0.0).then_some((m, depth))
}

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
    overlap_volume_about(a, pose_a, b, pose_b, 0.5 * (pose_a.position + pose_b.position))
}

/// [`overlap_volume`] computed relative to `origin` (a point near the overlap keeps the sums
/// small; the answer is in world coordinates either way).
pub fn overlap_volume_about(a: &Polyhedron, pose_a: &Pose, b: &Polyhedron, pose_b: &Pose, origin: DVec3) -> Option<OverlapVolume> {
    let reach = a.bounding_radius() + b.bounding_radius();
    if (pose_a.position - pose_b.position).length_squared() >= reach * reach {
        return None;
    }
    let eps = PLANE_TOLERANCE * a.bounding_radius().max(b.bounding_radius());
    with_scratch(|s| {
        s.a.set_polyhedron(a, pose_a, origin);
        s.b.set_polyhedron(b, pose_b, origin);
        let (m, _) = overlap_moments_in(&s.a, &s.b, eps, None, &mut s.clip)?;
        Some(m.world(origin))
    })
}

impl Moments {
    /// In world coordinates, the computation's origin at `origin`.
    pub(crate) fn world(&self, origin: DVec3) -> OverlapVolume {
        OverlapVolume {
            volume: self.volume,
            area: self.area,
            moment: self.moment + origin.cross(self.area),
            centroid: origin + self.first / self.volume,
        }
    }
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
        // The force acts through the middle of the shared face's strip.
        assert!((o.action_point() - DVec3::new(0.0, 0.0, 0.475)).length() < 1e-12, "{:?}", o.action_point());
    }

    #[test]
    fn separated_and_touching_bodies_do_not_overlap() {
        let cube = Polyhedron::cube(1.0);
        assert!(overlap_volume(&cube, &Pose::from_position(DVec3::new(0.0, 0.0, 1.01)), &cube, &Pose::from_position(DVec3::ZERO)).is_none());
        assert!(overlap_volume(&cube, &Pose::from_position(DVec3::new(0.2, 0.0, 1.0)), &cube, &Pose::from_position(DVec3::ZERO)).is_none());
    }

    /// The first moments over the whole boundary close: ∮ n dA = 0 means S equals minus A's
    /// clipped faces' area, a check of the polygon orientation on both sides.
    #[test]
    fn the_boundary_of_the_overlap_is_closed() {
        let (a, b) = (Polyhedron::dodecahedron(0.6), Polyhedron::cube(1.0));
        let (pa, pb) = (pose(DVec3::new(0.4, 0.3, 0.5), DVec3::new(1.0, 2.0, 0.5), 0.7), pose(DVec3::ZERO, DVec3::new(0.3, -1.0, 0.2), 0.4));
        let (ra, rb) = (Region::of_polyhedron(&a, &pa, DVec3::ZERO), Region::of_polyhedron(&b, &pb, DVec3::ZERO));
        let mut a_side = DVec3::ZERO;
        let mut buf = ClipBuffers::default();
        for k in 0..ra.faces.len() {
            let (n, face) = ra.face(k);
            if clip_polygon(face, n, &rb.planes, 1e-12, &mut buf).is_some() {
                let mut m = Moments::default();
                m.add(&buf.poly, 0.0, 1.0);
                a_side += m.area;
            }
        }
        let o = overlap_volume(&a, &pa, &b, &pb).unwrap();
        assert!((o.area + a_side).length() < 1e-12, "S {:?}, A's faces {a_side:?}", o.area);
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
    fn the_answer_does_not_depend_on_the_origin() {
        let (a, b) = (Polyhedron::octahedron(1.2), Polyhedron::dodecahedron(0.6));
        let (pa, pb) = (pose(DVec3::new(0.5, 0.4, 0.6), DVec3::new(1.0, 0.2, 0.5), 0.3), pose(DVec3::ZERO, DVec3::new(0.3, 1.0, 0.2), 1.4));
        let o1 = overlap_volume_about(&a, &pa, &b, &pb, DVec3::ZERO).unwrap();
        let o2 = overlap_volume_about(&a, &pa, &b, &pb, DVec3::new(3.0, -2.0, 7.0)).unwrap();
        assert!((o1.volume - o2.volume).abs() < 1e-12 && (o1.area - o2.area).length() < 1e-12);
        assert!((o1.moment - o2.moment).length() < 1e-11 && (o1.centroid - o2.centroid).length() < 1e-11);
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
