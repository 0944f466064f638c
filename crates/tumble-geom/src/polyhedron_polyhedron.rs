use glam::DMat3;
use smallvec::SmallVec;

use crate::{DVec3, Polyhedron, Pose};

/// Inline capacity of the per-call vertex buffers (larger shapes spill to the heap).
pub(crate) const INLINE: usize = 32;
pub(crate) type Buf<T> = SmallVec<[T; INLINE]>;

/// One point of a contact manifold (world frame).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct ManifoldPoint {
    /// Halfway through the overlap at this point.
    pub point: DVec3,
    /// Overlap at this point along the contact normal (> 0).
    pub depth: f64,
}

/// The features that gave the contact normal.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum ContactFeature {
    /// A face of A (normal = −that face's normal).
    FaceA(u32),
    /// A face of B (normal = that face's normal).
    FaceB(u32),
    /// Edge of A × edge of B.
    EdgeEdge(u32, u32),
    /// An edge of B (sphere against polyhedron B).
    EdgeB(u32),
    /// A vertex of B (sphere against polyhedron B).
    VertexB(u32),
    /// A world surface (plane, quad face, edge or corner, cylinder).
    Surface,
    /// parry3d's GJK/EPA (large shapes, see [`SAT_MAX_EDGE_PAIRS`]).
    Gjk,
}

/// A contact between body A and body B (B may be a world surface).
///
/// - `normal`: unit, from B to A: moving A along `+normal` by `depth` separates the bodies.
/// - `depth`: the penetration depth ≥ 0, the minimum translation distance of A out of B.
/// - `point`: the depth-weighted mean of the manifold points, each halfway through the overlap.
/// - the manifold: up to four points with their own depths (face contacts give the clipped
///   incident face, edge–edge contacts and spheres give one point).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct PolyContact {
    pub normal: DVec3,
    pub depth: f64,
    pub point: DVec3,
    pub feature: ContactFeature,
    points: [ManifoldPoint; 4],
    len: u8,
}

impl PolyContact {
    /// A contact with a single point.
    pub fn single(normal: DVec3, depth: f64, point: DVec3, feature: ContactFeature) -> PolyContact {
        let mp = ManifoldPoint { point, depth };
        PolyContact { normal, depth, point, feature, points: [mp; 4], len: 1 }
    }

    /// A contact from manifold points (1 to 4, depths > 0); `point` is their depth-weighted mean.
    pub(crate) fn from_manifold(normal: DVec3, depth: f64, pts: &[ManifoldPoint], feature: ContactFeature) -> PolyContact {
        debug_assert!(!pts.is_empty() && pts.len() <= 4);
        let mut points = [pts[0]; 4];
        points[..pts.len()].copy_from_slice(pts);
        let w: f64 = pts.iter().map(|p| p.depth).sum();
        let point = if w > 0.0 { pts.iter().map(|p| p.point * p.depth).sum::<DVec3>() / w } else { pts[0].point };
        PolyContact { normal, depth, point, feature, points, len: pts.len() as u8 }
    }

    /// The manifold points (1 to 4).
    pub fn manifold(&self) -> &[ManifoldPoint] {
        &self.points[..self.len as usize]
    }

    /// The same contact seen from the other side (normal from A to B, feature sides swapped).
    pub fn flipped(mut self) -> PolyContact {
        self.normal = -self.normal;
        self.feature = match self.feature {
            ContactFeature::FaceA(f) => ContactFeature::FaceB(f),
            ContactFeature::FaceB(f) => ContactFeature::FaceA(f),
            ContactFeature::EdgeEdge(a, b) => ContactFeature::EdgeEdge(b, a),
            other => other,
        };
        self
    }

    pub(crate) fn transformed(mut self, pose: &Pose) -> PolyContact {
        self.normal = pose.rotate(self.normal);
        self.point = pose.to_world(self.point);
        for p in &mut self.points[..self.len as usize] {
            p.point = pose.to_world(p.point);
        }
        self
    }
}

/// Remembers the last separating axis of a pair, tried first on the next call (the spec's cache).
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub struct SeparationCache {
    pub feature: Option<ContactFeature>,
}

/// Above this many edge pairs (edges of A × edges of B) [`polyhedron_polyhedron`] hands the
/// pair to parry3d's GJK/EPA: the separating-axis edge loop grows as E_A·E_B and was measured
/// slower than parry from about 1,300 pairs (a 16-vertex triangulated hull with itself); the
/// named solids (a dodecahedron pair has 900) stay on the fast path.
pub const SAT_MAX_EDGE_PAIRS: usize = 1300;

/// Contact of convex polyhedron A (at `pose_a`) with convex polyhedron B (at `pose_b`), or `None`
/// when they do not overlap (touching counts as separated).
///
/// Runs [`polyhedron_polyhedron_sat`] unless the pair has more than [`SAT_MAX_EDGE_PAIRS`] edge
/// pairs, then [`polyhedron_polyhedron_gjk`] (parry3d; one manifold point).
///
/// ```
/// use tumble_geom::{DVec3, Polyhedron, Pose, polyhedron_polyhedron};
/// let cube = Polyhedron::cube(1.0);
/// // A rests 0.1 deep on top of B.
/// let (a, b) = (Pose::from_position(DVec3::new(0.2, 0.1, 0.9)), Pose::from_position(DVec3::ZERO));
/// let c = polyhedron_polyhedron(&cube, &a, &cube, &b).unwrap();
/// assert!((c.normal - DVec3::Z).length() < 1e-12);
/// assert!((c.depth - 0.1).abs() < 1e-12);
/// assert_eq!(c.manifold().len(), 4);
/// assert!((c.point.z - 0.45).abs() < 1e-12);
/// assert!(polyhedron_polyhedron(&cube, &Pose::from_position(DVec3::new(0.0, 0.0, 1.01)), &cube, &b).is_none());
/// ```
pub fn polyhedron_polyhedron(a: &Polyhedron, pose_a: &Pose, b: &Polyhedron, pose_b: &Pose) -> Option<PolyContact> {
    polyhedron_polyhedron_cached(a, pose_a, b, pose_b, &mut SeparationCache::default())
}

/// [`polyhedron_polyhedron`] that tries the pair's last separating axis first and stores the new one.
pub fn polyhedron_polyhedron_cached(
    a: &Polyhedron,
    pose_a: &Pose,
    b: &Polyhedron,
    pose_b: &Pose,
    cache: &mut SeparationCache,
) -> Option<PolyContact> {
    if a.edges().len() * b.edges().len() > SAT_MAX_EDGE_PAIRS {
        polyhedron_polyhedron_gjk(a, pose_a, b, pose_b)
    } else {
        polyhedron_polyhedron_sat(a, pose_a, b, pose_b, cache)
    }
}

/// The pair through parry3d's `contact` (GJK/EPA), in this crate's conventions: normal from B to
/// A, depth > 0, one point halfway between parry's two surface points.
pub fn polyhedron_polyhedron_gjk(a: &Polyhedron, pose_a: &Pose, b: &Polyhedron, pose_b: &Pose) -> Option<PolyContact> {
    if (pose_a.position - pose_b.position).length_squared() >= (a.bounding_radius() + b.bounding_radius()).powi(2) {
        return None;
    }
    let c = parry3d_f64::query::contact(&pose_a.to_parry(), a.parry_shape(), &pose_b.to_parry(), b.parry_shape(), 0.0).ok()??;
    (c.dist < 0.0).then(|| PolyContact::single(-c.normal1, -c.dist, 0.5 * (c.point1 + c.point2), ContactFeature::Gjk))
}

/// The separating-axis fast path, whatever the size of the shapes.
///
/// The test runs over the face normals of both bodies and the edge pairs that form faces of
/// the Minkowski difference (Gauss-map test): the axis of minimum penetration is the contact
/// normal, so `depth` is the exact penetration depth (parry3d's EPA agrees to its tolerance).
/// A face axis gives a vertex–face contact of up to four points (the incident face clipped by
/// the reference face), an edge axis the edge–edge closest points with normal `u × v` oriented
/// from B to A. `cache` holds the last separating (or contact) axis, tried first.
pub fn polyhedron_polyhedron_sat(a: &Polyhedron, pose_a: &Pose, b: &Polyhedron, pose_b: &Pose, cache: &mut SeparationCache) -> Option<PolyContact> {
    // Everything in B's body frame.
    let rel = pose_b.relative(pose_a);
    let t = rel.position;
    if t.length_squared() >= (a.bounding_radius() + b.bounding_radius()).powi(2) {
        return None;
    }
    let r = DMat3::from_quat(rel.rotation);
    let va: Buf<DVec3> = a.vertices().iter().map(|v| r * *v + t).collect();
    let na: Buf<DVec3> = a.faces().iter().map(|f| r * f.normal).collect();
    let oa: Buf<f64> = a.faces().iter().zip(&na).map(|(f, n)| f.offset + n.dot(t)).collect();
    let vb = b.vertices();
    let ctx = Ctx { a, b, va: &va, na: &na, oa: &oa };

    if let Some(f) = cache.feature
        && ctx.separation(f).is_some_and(|s| s >= 0.0)
    {
        return None;
    }

    // Faces of B: A's deepest vertex below each.
    let mut best_b = (f64::NEG_INFINITY, 0usize);
    for (fi, f) in b.faces().iter().enumerate() {
        let s = min_dot(&va, f.normal) - f.offset;
        if s >= 0.0 {
            cache.feature = Some(ContactFeature::FaceB(fi as u32));
            return None;
        }
        if s > best_b.0 {
            best_b = (s, fi);
        }
    }
    // Faces of A: B's deepest vertex below each.
    let mut best_a = (f64::NEG_INFINITY, 0usize);
    for (fi, n) in na.iter().enumerate() {
        let s = min_dot(vb, *n) - oa[fi];
        if s >= 0.0 {
            cache.feature = Some(ContactFeature::FaceA(fi as u32));
            return None;
        }
        if s > best_a.0 {
            best_a = (s, fi);
        }
    }
    // Edge pairs that form a face of the Minkowski difference (Gauss-map arcs cross). With arcs
    // a→b (A's edge) and c→d (B's, negated normals): c, d on opposite sides of the plane of a, b;
    // a, b on opposite sides of the plane of c, d; and the same hemisphere.
    // Only edge pairs shallower than the best face matter.
    let mut best_e = (best_a.0.max(best_b.0), usize::MAX, usize::MAX);
    let eb: Buf<(u32, u32, DVec3)> = b
        .edges()
        .iter()
        .map(|e| {
            let (n0, n1) = (b.faces()[e.faces[0] as usize].normal, b.faces()[e.faces[1] as usize].normal);
            (e.faces[0], e.faces[1], n1.cross(n0)) // d × c with c = −n0, d = −n1
        })
        .collect();
    let mut side_b: Buf<f64> = smallvec::smallvec![0.0; b.faces().len()];
    for (ia, ea) in a.edges().iter().enumerate() {
        let (an, bn) = (na[ea.faces[0] as usize], na[ea.faces[1] as usize]);
        let bxa = bn.cross(an);
        // n_f · (b × a) for every face of B once per edge of A; c·(b×a) = −that.
        for (sb, f) in side_b.iter_mut().zip(b.faces()) {
            *sb = f.normal.dot(bxa);
        }
        let (p0, p1) = (va[ea.vertices[0] as usize], va[ea.vertices[1] as usize]);
        let u = p1 - p0;
        for (ib, &(f0, f1, dxc)) in eb.iter().enumerate() {
            let (cba, dba) = (-side_b[f0 as usize], -side_b[f1 as usize]);
            if cba * dba >= 0.0 {
                continue;
            }
            let (adc, bdc) = (an.dot(dxc), bn.dot(dxc));
            if !(adc * bdc < 0.0 && cba * bdc > 0.0) {
                continue;
            }
            let eb_ = &b.edges()[ib];
            let q0 = vb[eb_.vertices[0] as usize];
            let v = vb[eb_.vertices[1] as usize] - q0;
            // Separation num/len along n = u × v (unnormalised) oriented away from B's centre;
            // the square root only for a new best (num < 0 < len: s > thr ⇔ num² < thr² len²).
            let n = u.cross(v);
            let len2 = n.length_squared();
            if len2 <= 1e-24 * u.length_squared() * v.length_squared() {
                continue; // parallel edges: a face axis covers them
            }
            let num = if n.dot(q0) < 0.0 { -n.dot(p0 - q0) } else { n.dot(p0 - q0) };
            if num >= 0.0 {
                cache.feature = Some(ContactFeature::EdgeEdge(ia as u32, ib as u32));
                return None;
            }
            if num * num < best_e.0 * best_e.0 * len2 {
                best_e = (num / len2.sqrt(), ia, ib);
            }
        }
    }

    // Minimum penetration; face contacts win near-ties (they give the steadier manifold).
    let tie = 1e-9 * (a.size() + b.size());
    let contact = if best_e.1 != usize::MAX && best_e.0 > best_a.0.max(best_b.0) + tie {
        let (ea, eb_) = (&a.edges()[best_e.1], &b.edges()[best_e.2]);
        let (p0, p1) = (va[ea.vertices[0] as usize], va[ea.vertices[1] as usize]);
        let (q0, q1) = (vb[eb_.vertices[0] as usize], vb[eb_.vertices[1] as usize]);
        let mut n = (p1 - p0).cross(q1 - q0).normalize();
        if n.dot(q0) < 0.0 {
            n = -n;
        }
        let depth = -best_e.0;
        let (pa, pb) = segment_closest_points(p0, p1, q0, q1);
        PolyContact::single(n, depth, 0.5 * (pa + pb), ContactFeature::EdgeEdge(best_e.1 as u32, best_e.2 as u32))
    } else if best_b.0 >= best_a.0 - tie {
        let f = &b.faces()[best_b.1];
        let ref_poly: Buf<DVec3> = f.vertices.iter().map(|&i| vb[i as usize]).collect();
        let inc = a.faces().iter().enumerate().min_by(|x, y| na[x.0].dot(f.normal).total_cmp(&na[y.0].dot(f.normal))).unwrap().1;
        let inc_poly: Buf<DVec3> = inc.vertices.iter().map(|&i| va[i as usize]).collect();
        face_contact(&ref_poly, f.normal, f.offset, &inc_poly, -best_b.0, f.normal, ContactFeature::FaceB(best_b.1 as u32), || {
            va[a.support_index(r.transpose() * -f.normal)]
        })
    } else {
        let n = na[best_a.1];
        let fa = &a.faces()[best_a.1];
        let ref_poly: Buf<DVec3> = fa.vertices.iter().map(|&i| va[i as usize]).collect();
        let inc = b.faces().iter().min_by(|x, y| x.normal.dot(n).total_cmp(&y.normal.dot(n))).unwrap();
        let inc_poly: Buf<DVec3> = inc.vertices.iter().map(|&i| vb[i as usize]).collect();
        face_contact(&ref_poly, n, oa[best_a.1], &inc_poly, -best_a.0, -n, ContactFeature::FaceA(best_a.1 as u32), || vb[b.support_index(-n)])
    };
    cache.feature = Some(contact.feature);
    Some(contact.transformed(pose_b))
}

/// The pair in B's frame, for re-testing a cached axis.
struct Ctx<'a> {
    a: &'a Polyhedron,
    b: &'a Polyhedron,
    va: &'a [DVec3],
    na: &'a [DVec3],
    oa: &'a [f64],
}

impl Ctx<'_> {
    fn separation(&self, f: ContactFeature) -> Option<f64> {
        match f {
            ContactFeature::FaceB(i) => {
                let face = self.b.faces().get(i as usize)?;
                Some(min_dot(self.va, face.normal) - face.offset)
            }
            ContactFeature::FaceA(i) => Some(min_dot(self.b.vertices(), *self.na.get(i as usize)?) - self.oa[i as usize]),
            ContactFeature::EdgeEdge(ia, ib) => {
                let (ea, eb) = (self.a.edges().get(ia as usize)?, self.b.edges().get(ib as usize)?);
                let p0 = self.va[ea.vertices[0] as usize];
                let q0 = self.b.vertices()[eb.vertices[0] as usize];
                let u = self.va[ea.vertices[1] as usize] - p0;
                let v = self.b.vertices()[eb.vertices[1] as usize] - q0;
                // A cached edge axis may no longer be a Minkowski face: check it as a plain axis.
                let mut n = u.cross(v);
                if n.length_squared() <= 1e-24 * u.length_squared() * v.length_squared() {
                    return None;
                }
                n = n.normalize();
                let s1 = min_dot(self.va, n) - max_dot(self.b.vertices(), n);
                let s2 = min_dot(self.va, -n) - max_dot(self.b.vertices(), -n);
                Some(s1.max(s2))
            }
            _ => None,
        }
    }
}

#[inline]
pub(crate) fn min_dot(pts: &[DVec3], n: DVec3) -> f64 {
    pts.iter().map(|p| p.dot(n)).fold(f64::INFINITY, f64::min)
}

#[inline]
pub(crate) fn max_dot(pts: &[DVec3], n: DVec3) -> f64 {
    pts.iter().map(|p| p.dot(n)).fold(f64::NEG_INFINITY, f64::max)
}

/// Closest points between segments P(s) = p0 + s u and Q(t) = q0 + t v, s, t ∈ [0, 1]
/// (s = (b e − c d)/D, t = (a e − b d)/D, clamped; parallel segments use their overlap's midpoint).
pub fn segment_closest_points(p0: DVec3, p1: DVec3, q0: DVec3, q1: DVec3) -> (DVec3, DVec3) {
    let (u, v, w) = (p1 - p0, q1 - q0, p0 - q0);
    let (a, b, c, d, e) = (u.dot(u), u.dot(v), v.dot(v), u.dot(w), v.dot(w));
    let den = a * c - b * b;
    let (s, t);
    if den <= 1e-12 * a * c {
        // Parallel: the middle of the overlap of the projections onto P.
        let t0 = (-d / a).clamp(0.0, 1.0);
        let t1 = ((b - d) / a).clamp(0.0, 1.0);
        s = 0.5 * (t0 + t1);
        t = ((b * s + e) / c).clamp(0.0, 1.0);
    } else {
        let s0 = ((b * e - c * d) / den).clamp(0.0, 1.0);
        let t0 = ((b * s0 + e) / c).clamp(0.0, 1.0);
        s = ((b * t0 - d) / a).clamp(0.0, 1.0);
        t = t0;
    }
    (p0 + u * s, q0 + v * t)
}

/// Face contact: clip the incident polygon by the side planes of the reference face (polygon
/// counter-clockwise about `ref_n`, plane `ref_n · p = ref_off`), keep the points below it, at
/// most four. `normal` is the contact normal (B to A) in the same frame.
#[allow(clippy::too_many_arguments)]
pub(crate) fn face_contact(
    ref_poly: &[DVec3],
    ref_n: DVec3,
    ref_off: f64,
    inc_poly: &[DVec3],
    depth: f64,
    normal: DVec3,
    feature: ContactFeature,
    deepest: impl FnOnce() -> DVec3,
) -> PolyContact {
    let mut poly: Buf<DVec3> = inc_poly.iter().copied().collect();
    let mut next: Buf<DVec3> = SmallVec::new();
    let m = ref_poly.len();
    for k in 0..m {
        let (r0, r1) = (ref_poly[k], ref_poly[(k + 1) % m]);
        let side = (r1 - r0).cross(ref_n);
        let off = side.dot(r0);
        clip(&poly, side, off, &mut next);
        std::mem::swap(&mut poly, &mut next);
        if poly.is_empty() {
            break;
        }
    }
    let mut pts: Buf<ManifoldPoint> = poly
        .iter()
        .filter_map(|p| {
            let d = ref_off - ref_n.dot(*p);
            (d > 0.0).then(|| ManifoldPoint { point: *p + ref_n * (0.5 * d), depth: d })
        })
        .collect();
    if pts.is_empty() {
        // Rounding left nothing inside: the deepest vertex alone.
        let p = deepest();
        let d = (ref_off - ref_n.dot(p)).max(0.0);
        pts.push(ManifoldPoint { point: p + ref_n * (0.5 * d), depth: depth.max(d) });
    }
    let chosen = reduce_to_four(&pts, ref_n);
    PolyContact::from_manifold(normal, depth, &chosen, feature)
}

/// Sutherland–Hodgman against the half-space `side · p ≤ off`.
fn clip(poly: &[DVec3], side: DVec3, off: f64, out: &mut Buf<DVec3>) {
    out.clear();
    let n = poly.len();
    for k in 0..n {
        let (p, q) = (poly[k], poly[(k + 1) % n]);
        let (dp, dq) = (side.dot(p) - off, side.dot(q) - off);
        if dp <= 0.0 {
            out.push(p);
        }
        if (dp < 0.0 && dq > 0.0) || (dp > 0.0 && dq < 0.0) {
            out.push(p + (q - p) * (dp / (dp - dq)));
        }
    }
}

/// At most four points spanning the manifold: the deepest, the farthest from it, the one
/// making the largest triangle with those, and the largest on the other side.
pub(crate) fn reduce_to_four(pts: &[ManifoldPoint], n: DVec3) -> Buf<ManifoldPoint> {
    if pts.len() <= 4 {
        return pts.iter().copied().collect();
    }
    let i0 = (0..pts.len()).max_by(|&i, &j| pts[i].depth.total_cmp(&pts[j].depth)).unwrap();
    let p0 = pts[i0].point;
    let i1 = (0..pts.len()).max_by(|&i, &j| (pts[i].point - p0).length_squared().total_cmp(&(pts[j].point - p0).length_squared())).unwrap();
    let p1 = pts[i1].point;
    let area = |i: usize| (p1 - p0).cross(pts[i].point - p0).dot(n);
    let i2 = (0..pts.len()).max_by(|&i, &j| area(i).abs().total_cmp(&area(j).abs())).unwrap();
    let sign = area(i2).signum();
    let i3 = (0..pts.len()).min_by(|&i, &j| (sign * area(i)).total_cmp(&(sign * area(j)))).unwrap();
    let mut out: Buf<ManifoldPoint> = SmallVec::new();
    for i in [i0, i1, i2, i3] {
        if !out.iter().any(|p: &ManifoldPoint| p.point == pts[i].point) {
            out.push(pts[i]);
        }
    }
    out
}

#[cfg(test)]
mod tests {
    use super::*;
    use glam::DQuat;

    #[test]
    fn vertex_into_face_normal_is_the_face_normal() {
        // A cube balanced on a corner above B's top face, the corner 0.05 deep.
        let cube = Polyhedron::cube(1.0);
        let tilt = DQuat::from_rotation_arc(DVec3::ONE.normalize(), -DVec3::Z);
        let h = 0.5 + 0.5 * 3f64.sqrt() - 0.05;
        let c = polyhedron_polyhedron(&cube, &Pose::new(DVec3::new(0.1, -0.1, h), tilt), &cube, &Pose::IDENTITY).unwrap();
        assert!((c.normal - DVec3::Z).length() < 1e-12, "{c:?}");
        assert!((c.depth - 0.05).abs() < 1e-12);
        assert_eq!(c.manifold().len(), 1);
        assert!((c.point - DVec3::new(0.1, -0.1, 0.475)).length() < 1e-12, "{:?}", c.point);
        assert!(matches!(c.feature, ContactFeature::FaceB(_)));
        // Swapping the roles flips the normal and takes A's face.
        let d = polyhedron_polyhedron(&cube, &Pose::IDENTITY, &cube, &Pose::new(DVec3::new(0.1, -0.1, h), tilt)).unwrap();
        assert!((d.normal + DVec3::Z).length() < 1e-12);
        assert!((d.depth - 0.05).abs() < 1e-12);
        assert!(matches!(d.feature, ContactFeature::FaceA(_)));
    }

    #[test]
    fn crossed_edges_give_the_cross_product_normal() {
        // Two cubes rotated 45° about perpendicular horizontal axes: their edges cross.
        let cube = Polyhedron::cube(1.0);
        let s = 0.5 * 2f64.sqrt();
        let qa = DQuat::from_rotation_x(std::f64::consts::FRAC_PI_4);
        let qb = DQuat::from_rotation_y(std::f64::consts::FRAC_PI_4);
        let gap = -0.02;
        let c = polyhedron_polyhedron(&cube, &Pose::new(DVec3::new(0.0, 0.0, 2.0 * s + gap), qa), &cube, &Pose::new(DVec3::ZERO, qb)).unwrap();
        assert!((c.normal - DVec3::Z).length() < 1e-12, "{c:?}");
        assert!((c.depth - 0.02).abs() < 1e-12);
        assert!(matches!(c.feature, ContactFeature::EdgeEdge(_, _)));
        assert!((c.point - DVec3::new(0.0, 0.0, s - 0.01)).length() < 1e-12, "{:?}", c.point);
    }

    #[test]
    fn cache_returns_the_separating_axis() {
        let cube = Polyhedron::cube(1.0);
        let mut cache = SeparationCache::default();
        let a = Pose::from_position(DVec3::new(1.2, 0.0, 0.3));
        assert!(polyhedron_polyhedron_cached(&cube, &a, &cube, &Pose::IDENTITY, &mut cache).is_none());
        assert!(cache.feature.is_some());
        assert!(polyhedron_polyhedron_cached(&cube, &a, &cube, &Pose::IDENTITY, &mut cache).is_none());
        let a = Pose::from_position(DVec3::new(0.9, 0.0, 0.3));
        let c = polyhedron_polyhedron_cached(&cube, &a, &cube, &Pose::IDENTITY, &mut cache).unwrap();
        assert!((c.normal - DVec3::X).length() < 1e-12 && (c.depth - 0.1).abs() < 1e-12);
    }

    #[test]
    fn segment_closest_points_formula() {
        let (p, q) =
            segment_closest_points(DVec3::new(-1.0, 0.0, 0.0), DVec3::new(1.0, 0.0, 0.0), DVec3::new(0.3, -1.0, 0.5), DVec3::new(0.3, 1.0, 0.5));
        assert!((p - DVec3::new(0.3, 0.0, 0.0)).length() < 1e-15 && (q - DVec3::new(0.3, 0.0, 0.5)).length() < 1e-15);
        // Parallel, overlapping on [0.5, 1].
        let (p, q) = segment_closest_points(DVec3::ZERO, DVec3::X, DVec3::new(0.5, 1.0, 0.0), DVec3::new(2.0, 1.0, 0.0));
        assert!((p - DVec3::new(0.75, 0.0, 0.0)).length() < 1e-15 && (q - DVec3::new(0.75, 1.0, 0.0)).length() < 1e-15);
    }
}
