//! The smallest sphere enclosing a set of points (Welzl's algorithm) or of spheres.
//!
//! - [`enclosing_sphere_of_points`]: Welzl's algorithm in its move-to-front form
//!   (Gärtner), after a deterministic shuffle. It loops over the points and recurses
//!   only on the support set, so the recursion is at most five deep for any number
//!   of points. Exact up to rounding.
//! - [`enclosing_sphere_of_spheres`]: equal radii reduce exactly to the points'
//!   sphere grown by r. Unequal radii use the pivoting (basis-improvement) form of
//!   the LP-type algorithm, because Welzl's algorithm is known to fail for balls
//!   (Fischer & Gärtner, "The smallest enclosing ball of balls", 2003): keep a basis
//!   of at most four spheres, take the sphere farthest outside its ball, and replace
//!   the basis by that of the five (the best of all sub-bases, found exhaustively).
//!   The radius grows strictly at each pivot, so it terminates, and it stops only
//!   when every sphere is inside: exact up to rounding.
//!
//! Degenerate input (duplicate, collinear, coplanar centres) is handled by solving
//! the support equations in the affine hull of the support with full pivoting and
//! skipping dependent directions; a candidate that does not touch all of its
//! support is discarded.

use crate::DVec3;

/// A ball: centre and radius.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Ball {
    pub centre: DVec3,
    pub radius: f64,
}

impl Ball {
    /// True when the sphere (x, r) lies inside, with a relative tolerance of `1e-10` of the radius.
    #[inline]
    pub fn contains_sphere(&self, x: DVec3, r: f64) -> bool {
        (x - self.centre).length() + r <= self.radius + tolerance(self.radius)
    }

    /// Volume (4/3)πR³.
    pub fn volume(&self) -> f64 {
        4.0 / 3.0 * std::f64::consts::PI * self.radius.powi(3)
    }
}

#[inline]
fn tolerance(radius: f64) -> f64 {
    1e-10 * radius.abs() + 1e-300
}

/// The smallest sphere enclosing `points` (Welzl, move-to-front). An empty set gives radius −1.
pub fn enclosing_sphere_of_points(points: &[DVec3]) -> Ball {
    let mut order: Vec<usize> = (0..points.len()).collect();
    shuffle(&mut order);
    let mut support = [0usize; 4];
    let zeros = vec![0.0; points.len()];
    move_to_front(points, &zeros, &mut order, points.len(), &mut support, 0)
}

/// The smallest sphere enclosing the spheres (centres, radii). Radii must be ≥ 0.
pub fn enclosing_sphere_of_spheres(centres: &[DVec3], radii: &[f64]) -> Ball {
    assert_eq!(centres.len(), radii.len());
    if centres.is_empty() {
        return Ball { centre: DVec3::ZERO, radius: -1.0 };
    }
    let r0 = radii[0];
    if radii.iter().all(|&r| r == r0) {
        let b = enclosing_sphere_of_points(centres);
        return Ball { centre: b.centre, radius: b.radius + r0 };
    }
    pivoting(centres, radii)
}

/// A deterministic Fisher–Yates shuffle (xorshift seeded by the length): the expected-linear
/// running time of Welzl's algorithm needs a random order, reproducibility needs a fixed one.
fn shuffle(order: &mut [usize]) {
    let mut s = 0x9E37_79B9_7F4A_7C15u64 ^ (order.len() as u64).wrapping_mul(0xBF58_476D_1CE4_E5B9);
    for i in (1..order.len()).rev() {
        s ^= s << 13;
        s ^= s >> 7;
        s ^= s << 17;
        let j = (s % (i as u64 + 1)) as usize;
        order.swap(i, j);
    }
}

/// Welzl's mb(order[..end], support[..ns]) with move-to-front; recursion only adds to the support.
fn move_to_front(x: &[DVec3], r: &[f64], order: &mut Vec<usize>, end: usize, support: &mut [usize; 4], ns: usize) -> Ball {
    let mut ball = if ns == 0 { Ball { centre: DVec3::ZERO, radius: -1.0 } } else { support_ball(x, r, &support[..ns]) };
    if ns == 4 {
        return ball;
    }
    let mut i = 0;
    while i < end {
        let p = order[i];
        if ball.radius < 0.0 || !ball.contains_sphere(x[p], r[p]) {
            support[ns] = p;
            ball = move_to_front(x, r, order, i, support, ns + 1);
            // Move p to the front: the points before it shift by one, the next one stays at i + 1.
            order.copy_within(0..i, 1);
            order[0] = p;
        }
        i += 1;
    }
    ball
}

/// The smallest ball touching every sphere of `support` from inside, centre in the affine hull of
/// their centres; falls back to the best sub-support ball when the support is degenerate.
fn support_ball(x: &[DVec3], r: &[f64], support: &[usize]) -> Ball {
    let c: Vec<DVec3> = support.iter().map(|&i| x[i]).collect();
    let rr: Vec<f64> = support.iter().map(|&i| r[i]).collect();
    if let Some(b) = tangent_balls(&c, &rr).into_iter().find(|b| touches_all(b, &c, &rr)) {
        return b;
    }
    // Degenerate (rounding put a point slightly off the hull): the smallest ball of the set.
    best_ball(&c, &rr)
}

fn touches_all(b: &Ball, c: &[DVec3], r: &[f64]) -> bool {
    let scale = b.radius.abs().max(c.iter().map(|p| (*p - c[0]).length()).fold(0.0, f64::max));
    c.iter().zip(r).all(|(p, &ri)| ((*p - b.centre).length() - (b.radius - ri)).abs() <= 1e-8 * scale + 1e-300)
}

/// Candidate balls with every sphere of the set internally tangent and the centre in the affine
/// hull of the centres, smallest first (up to two: the roots of a quadratic in R).
pub fn tangent_balls(c: &[DVec3], r: &[f64]) -> Vec<Ball> {
    let k = c.len();
    if k == 0 {
        return Vec::new();
    }
    let r_max = r.iter().cloned().fold(f64::NEG_INFINITY, f64::max);
    if k == 1 {
        return vec![Ball { centre: c[0], radius: r[0] }];
    }
    // x = centre − c0 = Σ λ_j v_j; 2 v_i·x = |v_i|² − (r_i² − r0²) + 2R (r_i − r0), i = 1..k−1.
    let v: Vec<DVec3> = c[1..].iter().map(|p| *p - c[0]).collect();
    let m = k - 1;
    let mut g = [[0.0f64; 3]; 3];
    let mut ba = [0.0f64; 3];
    let mut bb = [0.0f64; 3];
    for i in 0..m {
        for j in 0..m {
            g[i][j] = 2.0 * v[i].dot(v[j]);
        }
        ba[i] = v[i].length_squared() - (r[i + 1] * r[i + 1] - r[0] * r[0]);
        bb[i] = 2.0 * (r[i + 1] - r[0]);
    }
    let (la, lb) = solve_pivoted(g, ba, bb, m);
    let (mut xa, mut xb) = (DVec3::ZERO, DVec3::ZERO);
    for j in 0..m {
        xa += la[j] * v[j];
        xb += lb[j] * v[j];
    }
    // |xa + R xb|² = (R − r0)²  ⇒  (|xb|² − 1) R² + 2 (xa·xb + r0) R + |xa|² − r0² = 0.
    let qa = xb.length_squared() - 1.0;
    let qb = 2.0 * (xa.dot(xb) + r[0]);
    let qc = xa.length_squared() - r[0] * r[0];
    let mut roots = Vec::with_capacity(2);
    if qa.abs() < 1e-14 {
        if qb != 0.0 {
            roots.push(-qc / qb);
        }
    } else {
        let disc = qb * qb - 4.0 * qa * qc;
        if disc >= 0.0 {
            // Numerically stable pair of roots.
            let s = disc.sqrt();
            let q = -0.5 * (qb + qb.signum() * s);
            if q != 0.0 {
                roots.push(q / qa);
                roots.push(qc / q);
            } else {
                roots.push(0.0);
            }
        }
    }
    let scale = v.iter().map(|d| d.length()).fold(r_max.abs(), f64::max);
    let mut out: Vec<Ball> = roots
        .into_iter()
        .filter(|&radius| radius.is_finite() && radius >= r_max - 1e-12 * scale)
        .map(|radius| Ball { centre: c[0] + xa + radius * xb, radius: radius.max(r_max) })
        .collect();
    out.sort_by(|a, b| a.radius.total_cmp(&b.radius));
    out
}

/// Solves G λ = b for two right-hand sides by Gaussian elimination with full pivoting; dependent
/// rows (pivot below 1e-12 of the largest) are skipped and their λ set to 0.
#[allow(clippy::needless_range_loop)] // row and column indices of a small dense matrix
fn solve_pivoted(mut g: [[f64; 3]; 3], mut a: [f64; 3], mut b: [f64; 3], m: usize) -> ([f64; 3], [f64; 3]) {
    let mut col = [0usize, 1, 2];
    let big = (0..m).flat_map(|i| (0..m).map(move |j| (i, j))).map(|(i, j)| g[i][j].abs()).fold(0.0, f64::max);
    let mut rank = 0;
    for step in 0..m {
        let mut best = (0.0, step, step);
        for i in step..m {
            for j in step..m {
                if g[i][j].abs() > best.0 {
                    best = (g[i][j].abs(), i, j);
                }
            }
        }
        if best.0 <= 1e-12 * big || best.0 == 0.0 {
            break;
        }
        let (_, pi, pj) = best;
        g.swap(step, pi);
        a.swap(step, pi);
        b.swap(step, pi);
        for row in g.iter_mut() {
            row.swap(step, pj);
        }
        col.swap(step, pj);
        for i in step + 1..m {
            let f = g[i][step] / g[step][step];
            for j in step..m {
                g[i][j] -= f * g[step][j];
            }
            a[i] -= f * a[step];
            b[i] -= f * b[step];
        }
        rank += 1;
    }
    let (mut ya, mut yb) = ([0.0; 3], [0.0; 3]);
    for i in (0..rank).rev() {
        let (mut sa, mut sb) = (a[i], b[i]);
        for j in i + 1..rank {
            sa -= g[i][j] * ya[j];
            sb -= g[i][j] * yb[j];
        }
        ya[i] = sa / g[i][i];
        yb[i] = sb / g[i][i];
    }
    let (mut la, mut lb) = ([0.0; 3], [0.0; 3]);
    for i in 0..m {
        la[col[i]] = ya[i];
        lb[col[i]] = yb[i];
    }
    (la, lb)
}

/// The smallest enclosing ball of at most five spheres, by trying every subset of at most four as
/// the support (the exhaustive basis computation of the LP-type algorithm, also the test oracle).
pub fn best_ball(c: &[DVec3], r: &[f64]) -> Ball {
    let k = c.len();
    let mut best = Ball { centre: DVec3::ZERO, radius: f64::INFINITY };
    for mask in 1u32..(1 << k) {
        if mask.count_ones() > 4 {
            continue;
        }
        let (sc, sr): (Vec<DVec3>, Vec<f64>) = (0..k).filter(|i| mask & (1 << i) != 0).map(|i| (c[i], r[i])).unzip();
        for b in tangent_balls(&sc, &sr) {
            if b.radius < best.radius && touches_all(&b, &sc, &sr) && c.iter().zip(r).all(|(p, &ri)| b.contains_sphere(*p, ri)) {
                best = b;
            }
        }
    }
    if !best.radius.is_finite() {
        // Only reachable through rounding in degenerate input: a ball around the first sphere
        // grown to cover the rest (never too small).
        let radius = c.iter().zip(r).map(|(p, &ri)| (*p - c[0]).length() + ri).fold(0.0, f64::max);
        best = Ball { centre: c[0], radius };
    }
    best
}

/// Pivoting: basis of ≤ 4 spheres; add the farthest violator and recompute the basis exhaustively.
fn pivoting(c: &[DVec3], r: &[f64]) -> Ball {
    let mut basis: Vec<usize> = vec![(0..c.len()).max_by(|&a, &b| r[a].total_cmp(&r[b])).unwrap()];
    let mut ball = Ball { centre: c[basis[0]], radius: r[basis[0]] };
    for _ in 0..10_000 {
        let (mut far, mut excess) = (usize::MAX, tolerance(ball.radius));
        for i in 0..c.len() {
            let e = (c[i] - ball.centre).length() + r[i] - ball.radius;
            if e > excess {
                (far, excess) = (i, e);
            }
        }
        if far == usize::MAX {
            break;
        }
        basis.push(far);
        let bc: Vec<DVec3> = basis.iter().map(|&i| c[i]).collect();
        let br: Vec<f64> = basis.iter().map(|&i| r[i]).collect();
        let next = best_ball(&bc, &br);
        if next.radius <= ball.radius {
            // Rounding: no progress is possible; grow to cover the violator and stop.
            ball.radius += excess;
            break;
        }
        ball = next;
        basis.retain(|&i| ((c[i] - ball.centre).length() + r[i] - ball.radius).abs() <= 1e-8 * ball.radius.max(1e-300));
        if basis.len() > 4 {
            basis.truncate(4);
        }
    }
    ball
}

#[cfg(test)]
mod tests {
    use super::*;
    use proptest::prelude::*;

    /// Brute force: every subset of at most four spheres as the support; the smallest ball touching
    /// all of its support that contains every sphere.
    fn brute_force(c: &[DVec3], r: &[f64]) -> f64 {
        let k = c.len();
        let mut best = f64::INFINITY;
        for mask in 1u32..(1 << k) {
            if mask.count_ones() > 4 {
                continue;
            }
            let (sc, sr): (Vec<DVec3>, Vec<f64>) = (0..k).filter(|i| mask & (1 << i) != 0).map(|i| (c[i], r[i])).unzip();
            for b in tangent_balls(&sc, &sr) {
                if touches_all(&b, &sc, &sr) && c.iter().zip(r).all(|(p, &ri)| (*p - b.centre).length() + ri <= b.radius * (1.0 + 1e-9) + 1e-12) {
                    best = best.min(b.radius);
                }
            }
        }
        best
    }

    fn assert_encloses(b: &Ball, c: &[DVec3], r: &[f64]) {
        for (p, &ri) in c.iter().zip(r) {
            assert!((*p - b.centre).length() + ri <= b.radius * (1.0 + 1e-9) + 1e-12, "{p:?} r {ri} outside {b:?}");
        }
    }

    #[test]
    fn two_touching_spheres() {
        let b = enclosing_sphere_of_spheres(&[DVec3::ZERO, DVec3::new(2.0, 0.0, 0.0)], &[1.0, 1.0]);
        assert!((b.radius - 2.0).abs() < 1e-15 && (b.centre - DVec3::X).length() < 1e-15);
    }

    #[test]
    fn regular_tetrahedron_and_its_centre() {
        let p = [DVec3::new(1.0, 1.0, 1.0), DVec3::new(1.0, -1.0, -1.0), DVec3::new(-1.0, 1.0, -1.0), DVec3::new(-1.0, -1.0, 1.0)];
        let mut pts = p.to_vec();
        pts.push(DVec3::ZERO);
        let b = enclosing_sphere_of_points(&pts);
        assert!((b.radius - 3f64.sqrt()).abs() < 1e-12 && b.centre.length() < 1e-12);
    }

    #[test]
    fn a_small_sphere_inside_a_big_one() {
        let b = enclosing_sphere_of_spheres(&[DVec3::ZERO, DVec3::new(0.5, 0.0, 0.0)], &[2.0, 0.1]);
        assert_eq!(b.radius, 2.0);
    }

    #[test]
    fn thousands_of_points_on_a_sphere() {
        // Points on the unit sphere (Fibonacci lattice) and inside it: radius 1, centre 0.
        let n = 5000;
        let pts: Vec<DVec3> = (0..n)
            .map(|i| {
                let z = 1.0 - 2.0 * (i as f64 + 0.5) / n as f64;
                let phi = i as f64 * 2.399_963_229_728_653;
                let s = (1.0 - z * z).sqrt();
                DVec3::new(s * phi.cos(), s * phi.sin(), z) * if i % 3 == 0 { 0.5 } else { 1.0 }
            })
            .collect();
        let b = enclosing_sphere_of_points(&pts);
        assert!((b.radius - 1.0).abs() < 1e-3 && b.centre.length() < 1e-3, "{b:?}");
        assert_encloses(&b, &pts, &vec![0.0; n]);
        let radii: Vec<f64> = (0..n).map(|i| 0.01 + 0.001 * (i % 7) as f64).collect();
        let bs = enclosing_sphere_of_spheres(&pts, &radii);
        assert_encloses(&bs, &pts, &radii);
        assert!(bs.radius < 1.0 + 0.017 + 1e-9);
    }

    fn coord() -> impl Strategy<Value = f64> {
        // Small integers make duplicate, collinear and coplanar points common; reals the generic case.
        prop_oneof![(-2i32..=2).prop_map(|k| k as f64), -3.0f64..3.0]
    }

    fn point() -> impl Strategy<Value = DVec3> {
        (coord(), coord(), coord()).prop_map(|(x, y, z)| DVec3::new(x, y, z))
    }

    proptest! {
        #![proptest_config(ProptestConfig::with_cases(400))]
        #[test]
        fn welzl_matches_brute_force_on_points(pts in prop::collection::vec(point(), 1..9)) {
            let b = enclosing_sphere_of_points(&pts);
            let zeros = vec![0.0; pts.len()];
            assert_encloses(&b, &pts, &zeros);
            let brute = brute_force(&pts, &zeros);
            prop_assert!((b.radius - brute).abs() <= 1e-9 * brute.max(1.0), "welzl {} brute {}", b.radius, brute);
        }

        #[test]
        fn equal_spheres_match_brute_force(pts in prop::collection::vec(point(), 1..9), r in 0.01f64..2.0) {
            let radii = vec![r; pts.len()];
            let b = enclosing_sphere_of_spheres(&pts, &radii);
            assert_encloses(&b, &pts, &radii);
            let brute = brute_force(&pts, &radii);
            prop_assert!((b.radius - brute).abs() <= 1e-9 * brute.max(1.0), "ours {} brute {}", b.radius, brute);
        }

        #[test]
        fn unequal_spheres_match_brute_force(balls in prop::collection::vec((point(), 0.0f64..1.5), 1..8)) {
            let (pts, radii): (Vec<DVec3>, Vec<f64>) = balls.into_iter().unzip();
            let b = enclosing_sphere_of_spheres(&pts, &radii);
            assert_encloses(&b, &pts, &radii);
            let brute = brute_force(&pts, &radii);
            prop_assert!((b.radius - brute).abs() <= 1e-9 * brute.max(1.0), "ours {} brute {}", b.radius, brute);
        }

        #[test]
        fn pivoting_agrees_with_welzl_on_points(pts in prop::collection::vec(point(), 1..40)) {
            let zeros = vec![0.0; pts.len()];
            let (w, p) = (enclosing_sphere_of_points(&pts), pivoting(&pts, &zeros));
            prop_assert!((w.radius - p.radius).abs() <= 1e-9 * w.radius.max(1.0), "welzl {} pivoting {}", w.radius, p.radius);
        }
    }
}
