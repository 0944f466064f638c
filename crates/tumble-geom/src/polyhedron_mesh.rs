//! Overlap-volume contacts of a convex polyhedron with a triangle mesh.
//!
//! Triangles joined by flat edges form a patch, and a patch meets a polyhedron as one polygon
//! wall (a quad) does: the overlap with the solid behind it, the polyhedron's corners and edges
//! below it, and the patch's outline corners and edges inside the polyhedron, all in one
//! contact, so the normal law sees the whole overlap however the patch is triangulated. The
//! solid behind a patch is the union of its triangles' prisms (each triangle and the planes
//! through its edges), which tile it: the overlap's volume, gradient and moments are sums over
//! the triangles. An edge inside a patch is no edge of the surface: its prism side splits the
//! sums, but a corner's depth is never measured to it and it pokes into nothing. Patches meet
//! at ridges and valleys as a box's quads do, one contact each.

use crate::mesh::{EdgeKind, TriangleMesh};
use crate::overlap_volume::{Moments, PLANE_TOLERANCE, Region, overlap_moments_in, smooth_depth, with_scratch};
use crate::polyhedron_polyhedron::Buf;
use crate::volume_contact::{CORNER_SMOOTHING, PenetratingPoint, VolumeContact, corners_inside, edge_density, edges_inside, segment_loads};
use crate::{DVec3, Polyhedron, Pose, closest_point_on_triangle};
use smallvec::SmallVec;
use std::collections::HashMap;

/// A polyhedron's contact with one flat patch of a mesh.
#[derive(Clone, Debug)]
pub struct PatchContact {
    /// The patch, named by its lowest triangle index (stable while the contact slides over it).
    pub patch: u32,
    pub contact: VolumeContact,
    /// The triangles under the overlap, each with its share of the overlap's volume (the shares
    /// sum to one): how the contact's load and wear are spread over the triangles.
    pub triangles: SmallVec<[(u32, f64); 4]>,
}

/// A mesh's flat patches and the outline corners each triangle carries.
#[derive(Clone, Debug, Default)]
pub struct MeshPatches {
    /// Per triangle: its patch, named by the patch's lowest triangle index.
    pub patch: Vec<u32>,
    /// Per triangle and corner: a corner of the patch's outline (the outline turns there) that
    /// this triangle carries (the patch's lowest triangle with an outline edge at it).
    pub corner: Vec<[bool; 3]>,
}

impl MeshPatches {
    /// The patches of `mesh`: triangles joined across its flat edges.
    pub fn new(mesh: &TriangleMesh) -> MeshPatches {
        let n = mesh.triangles.len();
        let mut parent: Vec<u32> = (0..n as u32).collect();
        let find = |parent: &mut Vec<u32>, mut x: u32| {
            while parent[x as usize] != x {
                parent[x as usize] = parent[parent[x as usize] as usize];
                x = parent[x as usize];
            }
            x
        };
        for t in 0..n {
            for k in 0..3 {
                if mesh.edges[t][k] == EdgeKind::Flat {
                    let (a, b) = (find(&mut parent, t as u32), find(&mut parent, mesh.across[t][k]));
                    // The smaller root wins, so every root is its patch's lowest triangle.
                    parent[a.max(b) as usize] = a.min(b);
                }
            }
        }
        let patch: Vec<u32> = (0..n as u32).map(|t| find(&mut parent, t)).collect();
        // Per (patch, vertex): the lowest triangle with an outline edge there, and those edges' directions.
        let mut at: HashMap<(u32, u32), (u32, Vec<DVec3>)> = HashMap::new();
        for (t, &group) in patch.iter().enumerate() {
            for k in 0..3 {
                if mesh.edges[t][k] == EdgeKind::Flat {
                    continue;
                }
                let (p, q) = (mesh.triangles[t][k], mesh.triangles[t][(k + 1) % 3]);
                let d = mesh.vertices[q as usize] - mesh.vertices[p as usize];
                for (v, dir) in [(p, d), (q, -d)] {
                    let e = at.entry((group, v)).or_insert((t as u32, Vec::new()));
                    e.0 = e.0.min(t as u32);
                    e.1.push(dir);
                }
            }
        }
        let mut corner = vec![[false; 3]; n];
        // Each entry writes its own triangle's slot, so the map's order does not matter.
        for ((_, v), (t, dirs)) in at {
            let turns = dirs.iter().any(|a| dirs.iter().any(|b| a.cross(*b).length() > 1e-6 * a.length() * b.length()));
            if turns {
                let k = mesh.triangles[t as usize].iter().position(|&w| w == v).expect("the triangle has the vertex");
                corner[t as usize][k] = true;
            }
        }
        MeshPatches { patch, corner }
    }

    /// The overlap-volume contacts of `poly` at `pose` with the patches of the `candidates`
    /// (triangle indices within twice its bounding radius, ascending), all in the mesh's frame,
    /// appended to `out` in patch order. A one-sided mesh pushes only towards
    /// its normals' side (no triangle acts once the centre is behind it); a two-sided patch
    /// pushes towards the side the centre is on.
    pub fn polyhedron_volumes(&self, mesh: &TriangleMesh, poly: &Polyhedron, pose: &Pose, candidates: &[u32], out: &mut Vec<PatchContact>) {
        let (x, rb) = (pose.position, poly.bounding_radius());
        // (patch, triangle, height of the centre above the triangle's plane, whether within rb)
        let mut near: Buf<(u32, u32, f64, bool)> = Buf::new();
        for &t in candidates {
            let c = mesh.corners(t as usize);
            let h = mesh.normals[t as usize].dot(x - c[0]);
            let gap = (closest_point_on_triangle(x, c).0 - x).length();
            if gap >= 2.0 * rb {
                continue;
            }
            let acts = h.abs() < rb && (mesh.two_sided || h > 0.0) && gap < rb;
            near.push((self.patch[t as usize], t, h, acts));
        }
        near.sort_unstable_by_key(|&(p, t, _, _)| (p, t));
        let mut start = 0;
        while start < near.len() {
            let patch = near[start].0;
            let end = start + near[start..].iter().take_while(|e| e.0 == patch).count();
            if let Some((contact, triangles)) = self.patch_volume(mesh, poly, pose, &near[start..end]) {
                out.push(PatchContact { patch, contact, triangles });
            }
            start = end;
        }
    }

    /// One patch's contact from its triangles near the polyhedron (patch, triangle, height,
    /// whether it acts): those within the bounding radius make the overlap, those within twice
    /// it give the outline sides a corner's depth is measured to.
    #[allow(clippy::type_complexity)]
    fn patch_volume(
        &self,
        mesh: &TriangleMesh,
        poly: &Polyhedron,
        pose: &Pose,
        near: &[(u32, u32, f64, bool)],
    ) -> Option<(VolumeContact, SmallVec<[(u32, f64); 4]>)> {
        let (x, rb) = (pose.position, poly.bounding_radius());
        let &(_, first, h, _) = near.iter().find(|e| e.3)?;
        let side = if h > 0.0 { 1.0 } else { -1.0 };
        let origin = x - mesh.normals[first as usize] * h;
        let eps = PLANE_TOLERANCE * rb;
        let tau = CORNER_SMOOTHING * rb;
        let density = edge_density(poly);
        // The surface's planes a depth is measured to: the triangle's own (first), then the outline's sides.
        let mut surface: Buf<(DVec3, f64)> = Buf::new();
        surface.push((DVec3::ZERO, 0.0));
        for &(_, t, _, _) in near {
            let t = t as usize;
            let c = mesh.corners(t).map(|p| p - origin);
            for k in 0..3 {
                if mesh.edges[t][k] != EdgeKind::Flat {
                    // A straight stretch of outline cut into several edges is one side.
                    let (m, o) = outline_side(c, k, mesh.normals[t] * side);
                    if !surface[1..].iter().any(|&(n, p)| (n - m).length() < 1e-9 && (p - o).abs() < 1e-9 * rb) {
                        surface.push((m, o));
                    }
                }
            }
        }
        with_scratch(|sc| {
            sc.a.set_polyhedron(poly, pose, origin);
            let mut sum = Moments::default();
            let mut depth = 0.0f64;
            let mut found = false;
            let mut points = Vec::new();
            let mut triangles: SmallVec<[(u32, f64); 4]> = SmallVec::new();
            for &(_, t, _, acts) in near {
                if !acts {
                    continue;
                }
                self.set_prism(mesh, t as usize, side, origin, 2.0 * rb, &mut sc.b);
                if let Some((m, d)) = overlap_moments_in(&sc.a, &sc.b, eps, None, &mut sc.clip) {
                    sum.accumulate(&m);
                    depth = depth.max(d);
                    found = true;
                    triangles.push((t, m.volume));
                }
                surface[0] = sc.b.planes[0];
                corners_below(&mut points, &sc.a, &sc.b, &surface, t, mesh, origin, tau);
                edges_below(&mut points, &sc.a, &sc.b, &surface, t, mesh, origin, density);
                // The patch's own outline corners and edges inside the polyhedron.
                corners_inside(&mut points, &sc.b, &sc.a, origin, tau, -1.0, None);
                edges_inside(&mut points, &sc.b, &sc.a, origin, -1.0, density, None);
            }
            if !found {
                return None;
            }
            // Volume shares; a grazing contact of no volume spreads evenly.
            let (total, count) = (sum.volume, triangles.len() as f64);
            for s in &mut triangles {
                s.1 = if total > 0.0 { s.1 / total } else { 1.0 / count };
            }
            VolumeContact::from_moments(&sum, origin, x, None, sum.area, depth, points).map(|c| (c, triangles))
        })
    }

    /// Makes `b` the prism behind triangle `t` (on the side `side` of its normal), relative to
    /// `origin` and `behind` deep: planes the surface, then the sides in edge order; vertices and
    /// edges the outline corners and edges the triangle carries.
    fn set_prism(&self, mesh: &TriangleMesh, t: usize, side: f64, origin: DVec3, behind: f64, b: &mut Region) {
        let c = mesh.corners(t).map(|p| p - origin);
        let n = mesh.normals[t];
        let m = n * side;
        let centroid = (c[0] + c[1] + c[2]) / 3.0;
        b.clear();
        b.planes.push((m, m.dot(c[0])));
        b.add_face(m, if side > 0.0 { [c[0], c[1], c[2]] } else { [c[2], c[1], c[0]] });
        for k in 0..3 {
            let (p, q) = (c[k], c[(k + 1) % 3]);
            let (along, plane) = if mesh.edges[t][k] == EdgeKind::Flat {
                // Built the same way from both triangles (the vertex of lower index first, the
                // normals' mean), so the two sides are one plane, each prism's the other's negation.
                let u = mesh.across[t][k] as usize;
                let mean = (n + mesh.normals[u]).normalize();
                let (vp, vq) = (mesh.triangles[t][k], mesh.triangles[t][(k + 1) % 3]);
                let (lo, hi) = if vp < vq { (p, q) } else { (q, p) };
                let s = (hi - lo).cross(mean).normalize();
                let s = if s.dot(centroid - lo) > 0.0 { -s } else { s };
                b.planes.push((s, s.dot(lo)));
                (mean * side, s)
            } else {
                let plane = outline_side(c, k, m);
                b.planes.push(plane);
                b.edges.push([p, q]);
                (m, plane.0)
            };
            let mut face = [p, q, q - along * behind, p - along * behind];
            if (face[1] - face[0]).cross(face[2] - face[0]).dot(plane) < 0.0 {
                face.reverse();
            }
            b.add_face(plane, face);
            if self.corner[t][k] {
                b.vertices.push(p);
            }
        }
    }
}

/// The side plane through edge `k` of the triangle with corners `c` perpendicular to the
/// triangle (surface normal `m`), facing out of it.
fn outline_side(c: [DVec3; 3], k: usize, m: DVec3) -> (DVec3, f64) {
    let (p, q) = (c[k], c[(k + 1) % 3]);
    let s = (q - p).cross(m).normalize();
    let s = if s.dot((c[0] + c[1] + c[2]) / 3.0 - p) > 0.0 { -s } else { s };
    (s, s.dot(p))
}

/// Whether `p` lies inside the sides of triangle `t`'s prism `b` (planes 1 to 3, in edge
/// order); a point on a side inside the patch belongs to the triangle of lower index, so each
/// point behind the patch is in exactly one prism.
fn inside_sides(b: &Region, p: DVec3, t: u32, mesh: &TriangleMesh) -> bool {
    (0..3).all(|k| {
        let (s, o) = b.planes[1 + k];
        let d = o - s.dot(p);
        d > 0.0 || (d == 0.0 && mesh.edges[t as usize][k] == EdgeKind::Flat && t < mesh.across[t as usize][k])
    })
}

/// How deep `p` lies below the surface (`surface[0]`) and the smoothed distance to it and the
/// outline's sides it lies inside (as [`Region::penetration`]; a side `p` is outside of faces
/// away from it where the outline turns inwards, so it is no face `p` could leave by).
fn surface_depth(surface: &[(DVec3, f64)], p: DVec3, tau: f64) -> Option<(f64, DVec3)> {
    let (m0, o0) = surface[0];
    if o0 - m0.dot(p) <= 0.0 {
        return None;
    }
    smooth_depth(surface.iter().filter(|&&(m, o)| o - m.dot(p) > 0.0), p, tau)
}

/// The polyhedron's (`a`) corners in the prism `b`, their depths smoothed over `tau` against
/// the `surface`.
#[allow(clippy::too_many_arguments)]
fn corners_below(
    out: &mut Vec<PenetratingPoint>,
    a: &Region,
    b: &Region,
    surface: &[(DVec3, f64)],
    t: u32,
    mesh: &TriangleMesh,
    origin: DVec3,
    tau: f64,
) {
    for &v in &a.vertices {
        if !inside_sides(b, v, t, mesh) {
            continue;
        }
        if let Some((depth, normal)) = surface_depth(surface, v, tau) {
            out.push(PenetratingPoint { point: v + origin, depth, normal, weight: 1.0 });
        }
    }
}

/// The parts of the polyhedron's (`a`) edges in the prism `b` below the surface: three Gauss
/// points per piece on which one plane of the `surface` the piece lies inside is the nearest
/// (as `edges_inside` weighs them).
#[allow(clippy::too_many_arguments)]
fn edges_below(
    out: &mut Vec<PenetratingPoint>,
    a: &Region,
    b: &Region,
    surface: &[(DVec3, f64)],
    t: u32,
    mesh: &TriangleMesh,
    origin: DVec3,
    density: f64,
) {
    for &[p0, p1] in &a.edges {
        let e = p1 - p0;
        let (mut lo, mut hi) = (0.0f64, 1.0f64);
        for k in 0..3 {
            let (s, o) = b.planes[1 + k];
            let (h0, rate) = (o - s.dot(p0), s.dot(e));
            if rate > 0.0 {
                hi = hi.min(h0 / rate);
            } else if rate < 0.0 {
                lo = lo.max(h0 / rate);
            } else if h0 < 0.0 || (h0 == 0.0 && !(mesh.edges[t as usize][k] == EdgeKind::Flat && t < mesh.across[t as usize][k])) {
                // An edge lying in a side inside the patch belongs to the triangle of lower index.
                hi = lo;
            }
        }
        if hi <= lo {
            continue;
        }
        let (q0, q1) = (p0 + e * lo, p0 + e * hi);
        let length = (q1 - q0).length();
        // The planes this part lies inside (at both ends, so all along it), the surface first; the
        // ends lie on the prism's own sides, so within round-off of them counts as inside.
        let slack = -1e-9 * length;
        let planes: Buf<(DVec3, f64)> =
            surface.iter().enumerate().filter(|&(f, &(m, o))| f == 0 || (o - m.dot(q0) > slack && o - m.dot(q1) > slack)).map(|(_, &p)| p).collect();
        segment_loads(out, &planes, q0, q1, origin, 1.0, density);
    }
}
