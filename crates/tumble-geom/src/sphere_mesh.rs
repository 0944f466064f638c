//! Sphere against a triangle mesh: the closest point of each nearby triangle (face, edge or
//! corner region) and the ownership rule that turns them into the contacts the sphere feels.
//!
//! The rule, so that a surface acts once however it is triangulated and a real ridge or
//! corner still acts:
//! 1. A triangle's closest point on a valley edge (concave as seen from the sphere's side) is
//!    no contact: the faces beside it hold the sphere. (Corners are left to rules 2 and 3: where
//!    ridges and valleys meet, a saddle corner can be the surface's closest point.)
//! 2. An edge contact is dropped when the triangle across that edge touches the sphere with its
//!    face; a corner contact when another triangle through that corner touches with its face or
//!    an edge.
//! 3. The triangles within reach join in groups when they share a flat edge, or when their
//!    closest points coincide (within 1e-9 of the radius: a ridge or corner reported by each
//!    triangle that meets there). Each group is at most one contact: its closest point, as the
//!    lowest triangle reporting that point which rules 1 and 2 leave; none when they rule out
//!    every report of it.
//!
//! A sphere on a flat surface, over a face, a shared edge or a shared corner, thus feels one
//! contact with the face normal; in a valley it feels each face; on a ridge or a corner it feels
//! one contact along the line from the edge or corner to its centre.

use crate::DVec3;
use crate::mesh::{EdgeKind, OPEN, TriangleMesh};
use smallvec::SmallVec;

/// Where on a triangle its closest point to a sphere lies.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Region {
    Face,
    /// Edge k, from corner k to corner k + 1.
    Edge(u8),
    /// Corner k.
    Vertex(u8),
}

/// One contact of a sphere with a mesh.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct MeshContact {
    /// The triangle that owns it, and where on it.
    pub triangle: u32,
    pub region: Region,
    /// Closest point of the surface.
    pub point: DVec3,
    /// Unit normal from the surface to the sphere's centre.
    pub normal: DVec3,
    /// Radius less the distance from the surface (negative when only within reach).
    pub overlap: f64,
}

/// Closest point of triangle (a, b, c) to `p` and its region (Ericson, Real-Time Collision
/// Detection, 2005, §5.1.5: the Voronoi regions by the signs of barycentric dot products).
pub fn closest_point_on_triangle(p: DVec3, [a, b, c]: [DVec3; 3]) -> (DVec3, Region) {
    let (ab, ac, ap) = (b - a, c - a, p - a);
    let (d1, d2) = (ab.dot(ap), ac.dot(ap));
    if d1 <= 0.0 && d2 <= 0.0 {
        return (a, Region::Vertex(0));
    }
    let bp = p - b;
    let (d3, d4) = (ab.dot(bp), ac.dot(bp));
    if d3 >= 0.0 && d4 <= d3 {
        return (b, Region::Vertex(1));
    }
    let vc = d1 * d4 - d3 * d2;
    if vc <= 0.0 && d1 >= 0.0 && d3 <= 0.0 {
        return (a + ab * (d1 / (d1 - d3)), Region::Edge(0));
    }
    let cp = p - c;
    let (d5, d6) = (ab.dot(cp), ac.dot(cp));
    if d6 >= 0.0 && d5 <= d6 {
        return (c, Region::Vertex(2));
    }
    let vb = d5 * d2 - d1 * d6;
    if vb <= 0.0 && d2 >= 0.0 && d6 <= 0.0 {
        return (a + ac * (d2 / (d2 - d6)), Region::Edge(2));
    }
    let va = d3 * d6 - d5 * d4;
    if va <= 0.0 && (d4 - d3) >= 0.0 && (d5 - d6) >= 0.0 {
        return (b + (c - b) * ((d4 - d3) / ((d4 - d3) + (d5 - d6))), Region::Edge(1));
    }
    let denom = 1.0 / (va + vb + vc);
    (a + ab * (vb * denom) + ac * (vc * denom), Region::Face)
}

/// In the groups of [`TriangleMesh::sphere_contacts_grouped`]: a triangle within reach whose
/// group gave no contact.
pub const NO_CONTACT: u8 = u8::MAX;

/// A triangle's contact before the ownership rule, with its distance from the centre.
#[derive(Clone, Copy, Debug)]
struct Raw {
    contact: MeshContact,
    distance: f64,
}

impl TriangleMesh {
    /// The closest point of triangle `t` to a sphere (centre, radius) as a contact, when it is
    /// within `reach` of its surface; faces push from whichever side the centre is on.
    pub fn triangle_contact(&self, t: usize, centre: DVec3, radius: f64, reach: f64) -> Option<MeshContact> {
        let (point, region) = closest_point_on_triangle(centre, self.corners(t));
        let offset = centre - point;
        let distance = offset.length();
        if distance >= radius + reach {
            return None;
        }
        let n = self.normals[t];
        let h = n.dot(offset);
        // One-sided: a face pushes a centre up to a radius behind it out along its normal; its
        // edges and corners touch only from the front.
        if !self.two_sided && (h <= -radius || (h <= 0.0 && region != Region::Face)) {
            return None;
        }
        let (normal, overlap) = match region {
            // The face normal itself, so a face contact is exactly a plane's.
            Region::Face if self.two_sided && h < 0.0 => (-n, radius + h),
            Region::Face => (n, radius - h),
            _ if distance > 0.0 => (offset / distance, radius - distance),
            _ => (n, radius),
        };
        Some(MeshContact { triangle: t as u32, region, point, normal, overlap })
    }

    /// The contacts of a sphere with the triangles `candidates` (ascending indices; every
    /// triangle the sphere may touch must be among them), by the ownership rule above.
    pub fn sphere_contacts(&self, centre: DVec3, radius: f64, reach: f64, candidates: impl IntoIterator<Item = u32>) -> SmallVec<[MeshContact; 4]> {
        self.sphere_contacts_grouped(centre, radius, reach, candidates, &mut SmallVec::new())
    }

    /// [`TriangleMesh::sphere_contacts`], also listing in `groups` each triangle within reach
    /// with the index of its group's contact, or [`NO_CONTACT`] when its group gave none (a
    /// spring follows its contact across the group's triangles, and off a ridge).
    pub fn sphere_contacts_grouped(
        &self,
        centre: DVec3,
        radius: f64,
        reach: f64,
        candidates: impl IntoIterator<Item = u32>,
        groups: &mut SmallVec<[(u32, u8); 8]>,
    ) -> SmallVec<[MeshContact; 4]> {
        groups.clear();
        // Every triangle within reach, and whether rule 1 rules it out.
        let mut raw: SmallVec<[(Raw, bool); 8]> = SmallVec::new();
        for t in candidates {
            let Some(c) = self.triangle_contact(t as usize, centre, radius, reach) else { continue };
            let valley = self.in_a_valley(&c, centre);
            raw.push((Raw { contact: c, distance: (centre - c.point).length() }, valley));
        }
        // Rule 2: an edge beside a touching face, a corner beside a touching face or edge.
        let touches = |t: u32, face_only: bool| {
            raw.iter().any(|(r, valley)| {
                !valley
                    && r.contact.triangle == t
                    && (r.contact.region == Region::Face || (!face_only && matches!(r.contact.region, Region::Edge(_))))
            })
        };
        let ruled_out: SmallVec<[bool; 8]> = raw
            .iter()
            .map(|&(r, valley)| {
                let t = r.contact.triangle as usize;
                valley
                    || match r.contact.region {
                        Region::Face => false,
                        Region::Edge(k) => {
                            let other = self.across[t][k as usize];
                            other != OPEN && touches(other, true)
                        }
                        Region::Vertex(k) => {
                            let v = self.triangles[t][k as usize];
                            raw.iter().any(|(o, _)| {
                                o.contact.triangle as usize != t
                                    && self.triangles[o.contact.triangle as usize].contains(&v)
                                    && touches(o.contact.triangle, false)
                            })
                        }
                    }
            })
            .collect();
        // Rule 3 over every triangle within reach, ruled out or not, so that a smooth surface
        // stays one group: joined by flat edges or coinciding points (union-find).
        let mut root: SmallVec<[usize; 8]> = (0..raw.len()).collect();
        fn find(root: &mut [usize], mut i: usize) -> usize {
            while root[i] != i {
                root[i] = root[root[i]];
                i = root[i];
            }
            i
        }
        let tolerance = 1e-9 * radius;
        for i in 0..raw.len() {
            for j in i + 1..raw.len() {
                let (a, b) = (raw[i].0.contact, raw[j].0.contact);
                let ta = a.triangle as usize;
                let flat = (0..3).any(|k| self.across[ta][k] == b.triangle && self.edges[ta][k] == EdgeKind::Flat);
                if flat || (a.point - b.point).length() <= tolerance {
                    let (ri, rj) = (find(&mut root, i), find(&mut root, j));
                    root[ri.max(rj)] = ri.min(rj);
                }
            }
        }
        let mut out: SmallVec<[MeshContact; 4]> = SmallVec::new();
        for i in 0..raw.len() {
            if find(&mut root, i) != i {
                continue;
            }
            // The group's closest point, as the lowest triangle reporting it that rules 1 and 2
            // leave (a ridge seen from behind one of its sides is still a ridge from the other);
            // when they rule out every report of it, a neighbouring face holds the sphere.
            let members: SmallVec<[usize; 8]> = (i..raw.len()).filter(|&j| find(&mut root, j) == i).collect();
            let closest = members.iter().map(|&j| raw[j].0.distance).fold(f64::INFINITY, f64::min);
            let at_closest = |j: &&usize| raw[**j].0.distance <= closest + tolerance;
            let best = members.iter().filter(at_closest).find(|&&j| !ruled_out[j]);
            let index = if best.is_some() { out.len() as u8 } else { NO_CONTACT };
            groups.extend(members.iter().map(|&j| (raw[j].0.contact.triangle, index)));
            if let Some(&best) = best {
                out.push(raw[best].0.contact);
            }
        }
        out
    }

    /// True when a contact sits on a valley edge, as seen from the sphere's side of its
    /// triangle (rule 1).
    fn in_a_valley(&self, c: &MeshContact, centre: DVec3) -> bool {
        let t = c.triangle as usize;
        let front = !self.two_sided || self.normals[t].dot(centre - c.point) >= 0.0;
        match c.region {
            Region::Face => false,
            Region::Edge(k) => match self.edges[t][k as usize] {
                EdgeKind::Concave => front,
                EdgeKind::Convex => !front,
                EdgeKind::Flat | EdgeKind::Open => false,
            },
            // A corner where ridges and valleys meet (a saddle) can be the closest point of the
            // surface; rule 2 and the groups settle corners.
            Region::Vertex(_) => false,
        }
    }

    /// [`TriangleMesh::sphere_contacts`] over every triangle (tests and small meshes).
    pub fn sphere_contacts_all(&self, centre: DVec3, radius: f64, reach: f64) -> SmallVec<[MeshContact; 4]> {
        self.sphere_contacts(centre, radius, reach, 0..self.triangles.len() as u32)
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::mesh::{DEFAULT_CURVATURE, box_triangles_subdivided};
    use crate::{Plane, Quad, SurfaceShape};

    fn mesh(v: &[DVec3], t: &[[u32; 3]]) -> TriangleMesh {
        TriangleMesh::new(v, t, DEFAULT_CURVATURE).unwrap().0
    }

    /// A deterministic stream of numbers in [0, 1).
    fn uniform(seed: u64) -> impl FnMut() -> f64 {
        let mut s = seed;
        move || {
            s = s.wrapping_mul(6364136223846793005).wrapping_add(1442695040888963407);
            (s >> 11) as f64 / (1u64 << 53) as f64
        }
    }

    #[test]
    fn closest_points_match_a_dense_search_of_the_triangle() {
        let mut u = uniform(7);
        for _ in 0..300 {
            let tri = [0, 1, 2].map(|_| DVec3::new(u(), u(), u()) * 2.0 - 1.0);
            let p = DVec3::new(u(), u(), u()) * 4.0 - 2.0;
            let (q, region) = closest_point_on_triangle(p, tri);
            let n = 120;
            let mut best = f64::INFINITY;
            for i in 0..=n {
                for j in 0..=n - i {
                    let (s, t) = (i as f64 / n as f64, j as f64 / n as f64);
                    let x = tri[0] + (tri[1] - tri[0]) * s + (tri[2] - tri[0]) * t;
                    best = best.min((x - p).length());
                }
            }
            let d = (q - p).length();
            assert!(d <= best + 1e-12 && d > best - 0.05, "closest {d}, dense search {best}");
            // The region names where q lies.
            match region {
                Region::Vertex(k) => assert_eq!(q, tri[k as usize]),
                Region::Edge(k) => {
                    let (a, b) = (tri[k as usize], tri[(k as usize + 1) % 3]);
                    assert!((q - a).cross(b - a).length() < 1e-12 * (b - a).length_squared().max(1.0));
                }
                Region::Face => {
                    let n = (tri[1] - tri[0]).cross(tri[2] - tri[0]).normalize();
                    assert!((p - q).cross(n).length() < 1e-9, "a face point is the foot of the perpendicular");
                }
            }
        }
    }

    /// A sphere anywhere above a flat plate triangulated 1 × 1 or 6 × 6 (two triangles per
    /// square), including straight over shared edges and corners, feels one contact: the
    /// plane's normal and overlap.
    #[test]
    fn a_flat_surface_is_one_contact_however_it_is_triangulated() {
        let r = 0.05;
        for n in [1, 6] {
            // The top face (+z) of a box subdivided n × n, alone: a plate with open edges.
            let (v, t) = box_triangles_subdivided(DVec3::ZERO, DVec3::ONE, n);
            let top: Vec<[u32; 3]> = t[t.len() - 2 * n * n..].to_vec();
            let plate = mesh(&v, &top);
            let plane = SurfaceShape::Plane(Plane::new(DVec3::new(0.0, 0.0, 1.0), DVec3::Z));
            let mut u = uniform(n as u64);
            let grid = |k: usize| k as f64 / n as f64;
            let mut centres: Vec<DVec3> = (0..200).map(|_| DVec3::new(0.1 + 0.8 * u(), 0.1 + 0.8 * u(), 1.0 + r * (0.2 + 0.79 * u()))).collect();
            // Over shared edges and corners exactly.
            for i in 1..n {
                centres.push(DVec3::new(grid(i), 0.37, 1.0 + 0.6 * r));
                centres.push(DVec3::new(grid(i), grid(i), 1.0 + 0.6 * r));
                centres.push(DVec3::new(grid(i), grid(n - i), 1.0 + 0.6 * r));
            }
            centres.push(DVec3::new(0.5, 0.5, 1.0 + 0.6 * r));
            for x in centres {
                let contacts = plate.sphere_contacts_all(x, r, 0.0);
                let expected = plane.sphere_contact(x, r).unwrap();
                assert_eq!(contacts.len(), 1, "{n}×{n} plate, centre {x}: {contacts:?}");
                let c = contacts[0];
                assert!((c.normal - DVec3::Z).length() < 1e-15, "normal {}", c.normal);
                assert!((c.overlap - expected.overlap).abs() < 1e-12 * r, "overlap {} against the plane's {}", c.overlap, expected.overlap);
            }
        }
    }

    /// A solid box, 12 triangles or each face cut 4 × 4: one contact per face touched from
    /// outside, one along the line to an edge or a corner the sphere is nearest to, as a box
    /// of quads with face, edge and corner contacts gives.
    #[test]
    fn a_triangulated_box_acts_on_a_sphere_outside_as_its_faces_edges_and_corners() {
        let r = 0.1;
        let quads: Vec<SurfaceShape> = Quad::box_faces(DVec3::ZERO, DVec3::ONE)
            .into_iter()
            .map(|q| {
                // Box faces of a container point inward: turn them outward for a solid box.
                let c = q.corners;
                SurfaceShape::Quad(Quad::new([c[0], c[3], c[2], c[1]], false))
            })
            .collect();
        for n in [1, 4] {
            let (v, t) = box_triangles_subdivided(DVec3::ZERO, DVec3::ONE, n);
            let solid = mesh(&v, &t);
            let mut seen = [0; 3];
            let mut u = uniform(40 + n as u64);
            for k in 0..600 {
                // Centres in a shell just outside the box: near faces, then edges, then corners
                // (coordinates beyond the box on one, two or three axes).
                let outside = 1 + k / 200;
                let mut x = DVec3::new(u(), u(), u());
                for axis in 0..outside {
                    let a = (axis + k) % 3;
                    x[a] = if u() < 0.5 { -r * u() } else { 1.0 + r * u() };
                }
                if x.cmpge(DVec3::ZERO).all() && x.cmple(DVec3::ONE).all() {
                    continue;
                }
                let mut expected: Vec<_> = quads.iter().filter_map(|q| q.sphere_contact(x, r)).collect();
                // A quad box reports an edge or corner once per quad meeting there: keep one.
                expected.dedup_by(|a, b| (a.point - b.point).length() < 1e-12);
                expected.sort_by(|a, b| a.point.to_array().partial_cmp(&b.point.to_array()).unwrap());
                expected.dedup_by(|a, b| (a.point - b.point).length() < 1e-12);
                let got = solid.sphere_contacts_all(x, r, 0.0);
                assert_eq!(got.len(), expected.len(), "{n}: centre {x}: {got:?} against {expected:?}");
                for e in &expected {
                    let g = got
                        .iter()
                        .find(|g| (g.normal - e.normal).length() < 1e-9)
                        .unwrap_or_else(|| panic!("{n}: centre {x}: no contact along {}", e.normal));
                    assert!((g.overlap - e.overlap).abs() < 1e-12, "{n}: centre {x}: overlap {} against {}", g.overlap, e.overlap);
                    seen[match g.region {
                        Region::Face => 0,
                        Region::Edge(_) => 1,
                        Region::Vertex(_) => 2,
                    }] += 1;
                }
            }
            assert!(seen.iter().all(|&k| k >= 10), "{n}: face, edge and corner contacts tested: {seen:?}");
        }
    }

    /// Inside a box (a container), a sphere in a corner feels the three walls and along an
    /// edge the two, each as a plane: the valleys add nothing.
    #[test]
    fn a_sphere_in_a_triangulated_container_feels_each_wall_as_a_plane() {
        let r = 0.1;
        for n in [1, 5] {
            let (v, t) = box_triangles_subdivided(DVec3::ZERO, DVec3::ONE, n);
            // Inward normals: the corner order reversed.
            let inward: Vec<[u32; 3]> = t.iter().map(|&[a, b, c]| [a, c, b]).collect();
            let container = mesh(&v, &inward);
            let walls = Quad::box_faces(DVec3::ZERO, DVec3::ONE).map(SurfaceShape::Quad);
            let mut u = uniform(90 + n as u64);
            for _ in 0..400 {
                let x = DVec3::new(u(), u(), u()) * (1.0 - 2.0 * r * 0.4) + DVec3::splat(r * 0.4);
                let expected: Vec<_> = walls.iter().filter_map(|w| w.sphere_contact(x, r)).collect();
                let got = container.sphere_contacts_all(x, r, 0.0);
                assert_eq!(got.len(), expected.len(), "{n}: centre {x}: {got:?}");
                for e in &expected {
                    let g = got.iter().find(|g| (g.normal - e.normal).length() < 1e-15).expect("each wall's normal");
                    assert!((g.overlap - e.overlap).abs() < 1e-12);
                }
            }
        }
    }

    /// A sheet folded along the y axis: z = slope |x| for x in [−1, 1], y in [−1, 1] (a valley
    /// for slope > 0, a ridge for slope < 0), each side cut into `columns` strips of two
    /// triangles, normals up.
    fn folded_sheet(slope: f64, columns: usize) -> TriangleMesh {
        let mut v = Vec::new();
        for i in 0..=2 * columns {
            let x = -1.0 + i as f64 / columns as f64;
            v.push(DVec3::new(x, -1.0, slope * x.abs()));
            v.push(DVec3::new(x, 1.0, slope * x.abs()));
        }
        let mut t = Vec::new();
        for i in 0..2 * columns as u32 {
            let (a, b, c, d) = (2 * i, 2 * i + 2, 2 * i + 3, 2 * i + 1);
            t.push([a, b, c]);
            t.push([a, c, d]);
        }
        let m = mesh(&v, &t);
        assert!(m.two_sided && m.normals.iter().all(|n| n.z > 0.0));
        m
    }

    /// On a shallow ridge (10°) the sphere's centre can lie in front of both sides; resting on
    /// one face near the ridge it still feels that face alone (rule 2), and over the ridge the
    /// ridge alone.
    #[test]
    fn a_sphere_beside_a_shallow_ridge_feels_the_face_it_rests_on() {
        let slope = -(10f64.to_radians()).tan();
        let ridge = folded_sheet(slope, 1);
        let r = 0.2;
        let n = DVec3::new(-slope, 0.0, 1.0).normalize();
        // Foot on the x > 0 side, 0.02 from the ridge line.
        let foot = DVec3::new(0.02, 0.0, slope * 0.02);
        let centre = foot + n * 0.9 * r;
        let c = ridge.sphere_contacts_all(centre, r, 0.0);
        assert_eq!(c.len(), 1, "{c:?}");
        assert!(c[0].region == Region::Face && (c[0].normal - n).length() < 1e-12);
        let over = DVec3::new(0.0, 0.3, 0.9 * r);
        let c = ridge.sphere_contacts_all(over, r, 0.0);
        assert_eq!(c.len(), 1, "{c:?}");
        assert!(matches!(c[0].region, Region::Edge(_)) && (c[0].normal - DVec3::Z).length() < 1e-12);
    }

    /// In a shallow valley (170° inside) cut finely, a sphere on one side near the valley
    /// line touches that line of the other side too; it is no contact (rule 1), even where the
    /// triangle under the centre is not the one along the valley.
    #[test]
    fn a_sphere_beside_a_shallow_valley_feels_the_face_it_rests_on() {
        let slope = (5f64.to_radians()).tan();
        let valley = folded_sheet(slope, 40);
        let r = 0.2;
        let n = DVec3::new(-slope, 0.0, 1.0).normalize();
        // Feet where the centre is within r of the valley line yet beside the other side's faces.
        for x in [0.045, 0.06, 0.075] {
            let foot = DVec3::new(x, 0.1, slope * x);
            let centre = foot + n * 0.95 * r;
            let c = valley.sphere_contacts_all(centre, r, 0.0);
            assert_eq!(c.len(), 1, "foot at x = {x}: {c:?}");
            // (At x = 0.075 the foot is on a flat edge between two strips: the same plane.)
            assert!((c[0].normal - n).length() < 1e-12, "{c:?}");
            assert!((c[0].overlap - 0.05 * r).abs() < 1e-12);
        }
    }

    #[test]
    fn a_valley_holds_a_sphere_on_both_faces_and_a_ridge_pushes_along_the_line_to_it() {
        // A V of two strips meeting along the y axis at 90°, opening upward.
        let v = [
            DVec3::new(-1.0, -1.0, 1.0),
            DVec3::new(0.0, -1.0, 0.0),
            DVec3::new(0.0, 1.0, 0.0),
            DVec3::new(-1.0, 1.0, 1.0),
            DVec3::new(1.0, -1.0, 1.0),
            DVec3::new(1.0, 1.0, 1.0),
        ];
        let valley = mesh(&v, &[[0, 1, 2], [0, 2, 3], [1, 4, 5], [1, 5, 2]]);
        assert!(valley.normals.iter().all(|n| n.z > 0.0));
        let r = 0.2;
        // Resting in the bottom: two face contacts at 45°.
        let bottom = DVec3::new(0.0, 0.1, r * 2f64.sqrt() * 0.99);
        let c = valley.sphere_contacts_all(bottom, r, 0.0);
        assert_eq!(c.len(), 2, "{c:?}");
        assert!(c.iter().all(|c| c.region == Region::Face && (c.normal.z - 0.5f64.sqrt()).abs() < 1e-12));
        // On one side near the bottom line: that face only, the valley edge adds nothing.
        let side = DVec3::new(-0.3, 0.0, 0.3) + DVec3::new(1.0, 0.0, 1.0).normalize() * 0.9 * r;
        let c = valley.sphere_contacts_all(side, r, 0.0);
        assert_eq!(c.len(), 1, "{c:?}");
        // Upside down the V is a ridge: one contact along the line to it.
        let ridge = valley.transformed(|x| DVec3::new(x.x, x.y, -x.z), true);
        let above = DVec3::new(0.05, 0.3, 0.9 * r);
        let c = ridge.sphere_contacts_all(above, r, 0.0);
        assert_eq!(c.len(), 1, "{c:?}");
        let expected = (above - DVec3::new(0.0, 0.3, 0.0)).normalize();
        assert!((c[0].normal - expected).length() < 1e-12 && matches!(c[0].region, Region::Edge(_)), "{c:?}");
    }
}
