//! Triangle meshes as walls: welded vertices, edge adjacency, the kind of every edge (open,
//! flat, a convex ridge or a concave valley) and the checks a CAD file needs before a run.
//!
//! The contact with a sphere, and the rule that makes a smooth surface one contact however it
//! is triangulated, are in `sphere_mesh.rs`.

use crate::DVec3;
use std::collections::HashMap;

/// No triangle across an edge (an open edge).
pub const OPEN: u32 = u32::MAX;

/// Two triangles whose normals differ by less than this are one smooth surface across their
/// edge, radians (0.25°; LIGGGHTS's default curvature tolerance is 0.256°).
pub const DEFAULT_CURVATURE: f64 = 0.25 * std::f64::consts::PI / 180.0;

/// How a mesh edge bends, seen from the side its first triangle's normal points to.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum EdgeKind {
    /// One triangle only.
    Open,
    /// Normals within the curvature angle: the two triangles are one smooth surface here.
    Flat,
    /// A ridge: the neighbour bends away from the normal side.
    Convex,
    /// A valley: the neighbour bends towards the normal side.
    Concave,
}

/// What loading a mesh found and repaired (nothing here stops a run).
#[derive(Clone, Debug, Default, PartialEq)]
pub struct MeshReport {
    /// Vertices merged into another within the welding tolerance.
    pub welded: usize,
    /// Triangles with an area below 1e-12 of the bounding box's diagonal squared, dropped.
    pub degenerate: usize,
    /// Edges with one triangle.
    pub open_edges: usize,
    /// Edges shared by more than two triangles (each such triangle pairs with the first other).
    pub non_manifold_edges: usize,
    /// Edges whose two triangles run along it in the same direction (their normals disagree).
    pub inconsistent_edges: usize,
    /// Triangles with an angle below one degree.
    pub slivers: usize,
}

impl MeshReport {
    /// One line per finding, for the plan's warnings.
    pub fn warnings(&self) -> Vec<String> {
        let mut w = Vec::new();
        let mut say = |n: usize, what: &str| {
            if n > 0 {
                w.push(format!("{n} {what}"));
            }
        };
        say(self.degenerate, "degenerate triangles (area below 1e-12 of the bounding box's diagonal squared) dropped");
        say(self.non_manifold_edges, "edges shared by more than two triangles");
        say(self.inconsistent_edges, "edges across which the triangles' orientation flips (normals disagree)");
        say(self.slivers, "triangles with an angle below 1° (contacts near them are sensitive to rounding)");
        w
    }
}

/// Why a mesh cannot be used.
#[derive(Clone, Debug, PartialEq)]
pub enum MeshError {
    /// No triangles (or none left after dropping degenerate ones).
    Empty,
    /// A triangle refers to a vertex that does not exist.
    BadIndex { triangle: usize, vertex: u32 },
    /// Two triangles with the same three vertices.
    Duplicate { first: usize, second: usize },
}

impl std::fmt::Display for MeshError {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        match self {
            MeshError::Empty => write!(f, "the mesh has no triangles with an area"),
            MeshError::BadIndex { triangle, vertex } => write!(f, "triangle {triangle} refers to vertex {vertex}, which does not exist"),
            MeshError::Duplicate { first, second } => {
                write!(f, "triangles {first} and {second} have the same three corners; remove the duplicate from the file")
            }
        }
    }
}

/// A triangle mesh ready for contacts: triangles in input order (less the degenerate ones),
/// each with its unit normal (right-handed with its corner order), the triangle across each of
/// its edges and that edge's kind, and the connected smooth surface it belongs to.
#[derive(Clone, Debug)]
pub struct TriangleMesh {
    pub vertices: Vec<DVec3>,
    pub triangles: Vec<[u32; 3]>,
    pub normals: Vec<DVec3>,
    /// Per triangle, for edge k (corner k to corner k + 1): the triangle across it, or [`OPEN`].
    pub across: Vec<[u32; 3]>,
    /// Per triangle and edge: how the surface bends there.
    pub edges: Vec<[EdgeKind; 3]>,
    /// Whether spheres behind the triangles are pushed back too (a sheet), or only those on
    /// the normals' side (a solid body or a container): by default, meshes with open edges.
    pub two_sided: bool,
}

impl TriangleMesh {
    /// Welds `vertices` closer than 1e-9 of the bounding box's diagonal, drops degenerate
    /// triangles and builds the adjacency; `curvature` is the largest angle between the
    /// normals of a flat edge ([`DEFAULT_CURVATURE`]).
    pub fn new(vertices: &[DVec3], triangles: &[[u32; 3]], curvature: f64) -> Result<(TriangleMesh, MeshReport), MeshError> {
        let mut report = MeshReport::default();
        for (t, tri) in triangles.iter().enumerate() {
            if let Some(&v) = tri.iter().find(|&&v| v as usize >= vertices.len()) {
                return Err(MeshError::BadIndex { triangle: t, vertex: v });
            }
        }
        let (lo, hi) = vertices.iter().fold((DVec3::INFINITY, DVec3::NEG_INFINITY), |(lo, hi), &v| (lo.min(v), hi.max(v)));
        let diagonal = if vertices.is_empty() { 0.0 } else { (hi - lo).length() };
        let (welded, map) = weld(vertices, 1e-9 * diagonal);
        report.welded = vertices.len() - welded.len();
        let mut kept = Vec::with_capacity(triangles.len());
        let mut normals = Vec::with_capacity(triangles.len());
        for tri in triangles {
            let t = tri.map(|v| map[v as usize]);
            let [a, b, c] = t.map(|v| welded[v as usize]);
            let cross = (b - a).cross(c - a);
            if t[0] == t[1] || t[1] == t[2] || t[0] == t[2] || 0.5 * cross.length() <= 1e-12 * diagonal * diagonal {
                report.degenerate += 1;
                continue;
            }
            if min_angle(a, b, c) < 1f64.to_radians() {
                report.slivers += 1;
            }
            kept.push(t);
            normals.push(cross.normalize());
        }
        if kept.is_empty() {
            return Err(MeshError::Empty);
        }
        let mut seen: HashMap<[u32; 3], usize> = HashMap::new();
        for (t, tri) in kept.iter().enumerate() {
            let mut key = *tri;
            key.sort_unstable();
            if let Some(&first) = seen.get(&key) {
                return Err(MeshError::Duplicate { first, second: t });
            }
            seen.insert(key, t);
        }
        // Every edge (unordered vertex pair) with the triangles and edge slots along it, in triangle order.
        let mut by_edge: HashMap<(u32, u32), Vec<(u32, usize)>> = HashMap::new();
        for (t, tri) in kept.iter().enumerate() {
            for k in 0..3 {
                let (p, q) = (tri[k], tri[(k + 1) % 3]);
                by_edge.entry((p.min(q), p.max(q))).or_default().push((t as u32, k));
            }
        }
        let mut across = vec![[OPEN; 3]; kept.len()];
        let mut edges = vec![[EdgeKind::Open; 3]; kept.len()];
        // Each edge writes only its own triangles' slots, so the map's order does not matter.
        for ((p, q), sides) in by_edge {
            if sides.len() == 1 {
                report.open_edges += 1;
                continue;
            }
            if sides.len() > 2 {
                report.non_manifold_edges += 1;
            }
            let (t1, k1) = sides[0];
            for &(t2, k2) in &sides[1..] {
                // Consistent neighbours run along the shared edge in opposite directions.
                let forward = |t: u32, k: usize| kept[t as usize][k] == p;
                if forward(t1, k1) == forward(t2, k2) {
                    report.inconsistent_edges += 1;
                }
                let kind_from = |from: u32, to: u32| {
                    let n = normals[from as usize];
                    let cos = n.dot(normals[to as usize]).clamp(-1.0, 1.0);
                    if cos.acos() < curvature {
                        return EdgeKind::Flat;
                    }
                    let far = kept[to as usize].iter().copied().find(|&v| v != p && v != q).expect("a triangle has a third corner");
                    if n.dot(welded[far as usize] - welded[p as usize]) < 0.0 { EdgeKind::Convex } else { EdgeKind::Concave }
                };
                for (from, kf, to) in [(t1, k1, t2), (t2, k2, t1)] {
                    if across[from as usize][kf] == OPEN {
                        across[from as usize][kf] = to;
                        edges[from as usize][kf] = kind_from(from, to);
                    }
                }
            }
        }
        let two_sided = report.open_edges > 0;
        Ok((TriangleMesh { vertices: welded, triangles: kept, normals, across, edges, two_sided }, report))
    }

    /// The corners of triangle `t`.
    #[inline]
    pub fn corners(&self, t: usize) -> [DVec3; 3] {
        self.triangles[t].map(|v| self.vertices[v as usize])
    }

    /// True when every edge has two triangles (a closed surface).
    pub fn is_closed(&self) -> bool {
        self.across.iter().all(|a| a.iter().all(|&t| t != OPEN))
    }

    /// The mesh with every vertex mapped by `f` (scale, rotation, translation); a mirroring map
    /// also flips the corner order, so the normals keep pointing to the same side.
    pub fn transformed(&self, f: impl Fn(DVec3) -> DVec3, mirrors: bool) -> TriangleMesh {
        let mut m = self.clone();
        m.vertices = self.vertices.iter().map(|&v| f(v)).collect();
        if mirrors {
            for (tri, (across, edges)) in m.triangles.iter_mut().zip(m.across.iter_mut().zip(m.edges.iter_mut())) {
                // Reversing (a, b, c) to (a, c, b): edge 0 (a-b) becomes edge 2, edge 2 (c-a) edge 0.
                tri.swap(1, 2);
                across.swap(0, 2);
                edges.swap(0, 2);
            }
        }
        for (t, n) in m.normals.iter_mut().enumerate() {
            let [a, b, c] = m.triangles[t].map(|v| m.vertices[v as usize]);
            *n = (b - a).cross(c - a).normalize();
        }
        m
    }
}

/// The smallest interior angle of a triangle, radians.
fn min_angle(a: DVec3, b: DVec3, c: DVec3) -> f64 {
    let angle = |p: DVec3, q: DVec3, r: DVec3| (q - p).angle_between(r - p);
    angle(a, b, c).min(angle(b, c, a)).min(angle(c, a, b))
}

/// Vertices merged when closer than `tolerance` (on a hash grid of that spacing, so the
/// result depends only on the input order); returns the kept vertices and each input's index.
fn weld(vertices: &[DVec3], tolerance: f64) -> (Vec<DVec3>, Vec<u32>) {
    if tolerance <= 0.0 {
        return (vertices.to_vec(), (0..vertices.len() as u32).collect());
    }
    let cell = |v: DVec3| (v / tolerance).floor().as_i64vec3().to_array();
    let mut grid: HashMap<[i64; 3], Vec<u32>> = HashMap::new();
    let mut kept: Vec<DVec3> = Vec::new();
    let mut map = Vec::with_capacity(vertices.len());
    for &v in vertices {
        let c = cell(v);
        let mut found = None;
        'search: for dx in -1..=1 {
            for dy in -1..=1 {
                for dz in -1..=1 {
                    if let Some(list) = grid.get(&[c[0] + dx, c[1] + dy, c[2] + dz])
                        && let Some(&k) = list.iter().find(|&&k| (kept[k as usize] - v).length() <= tolerance)
                    {
                        found = Some(k);
                        break 'search;
                    }
                }
            }
        }
        let k = found.unwrap_or_else(|| {
            kept.push(v);
            let k = kept.len() as u32 - 1;
            grid.entry(c).or_default().push(k);
            k
        });
        map.push(k);
    }
    (kept, map)
}

/// The 12 triangles of an axis-aligned box, normals outward (a solid body), two per face.
pub fn box_triangles(min: DVec3, max: DVec3) -> (Vec<DVec3>, Vec<[u32; 3]>) {
    box_triangles_subdivided(min, max, 1)
}

/// An axis-aligned box with each face cut into `n` × `n` squares of two triangles, normals outward.
pub fn box_triangles_subdivided(min: DVec3, max: DVec3, n: usize) -> (Vec<DVec3>, Vec<[u32; 3]>) {
    let mut vertices = Vec::new();
    let mut triangles = Vec::new();
    let size = max - min;
    // Each face: an origin corner and two edge vectors whose cross product points outward.
    let faces = [
        (min, DVec3::new(0.0, 0.0, size.z), DVec3::new(0.0, size.y, 0.0)),
        (DVec3::new(max.x, min.y, min.z), DVec3::new(0.0, size.y, 0.0), DVec3::new(0.0, 0.0, size.z)),
        (min, DVec3::new(size.x, 0.0, 0.0), DVec3::new(0.0, 0.0, size.z)),
        (DVec3::new(min.x, max.y, min.z), DVec3::new(0.0, 0.0, size.z), DVec3::new(size.x, 0.0, 0.0)),
        (min, DVec3::new(0.0, size.y, 0.0), DVec3::new(size.x, 0.0, 0.0)),
        (DVec3::new(min.x, min.y, max.z), DVec3::new(size.x, 0.0, 0.0), DVec3::new(0.0, size.y, 0.0)),
    ];
    for (origin, u, v) in faces {
        let base = vertices.len() as u32;
        for j in 0..=n {
            for i in 0..=n {
                vertices.push(origin + u * (i as f64 / n as f64) + v * (j as f64 / n as f64));
            }
        }
        let at = |i: usize, j: usize| base + (j * (n + 1) + i) as u32;
        for j in 0..n {
            for i in 0..n {
                triangles.push([at(i, j), at(i + 1, j), at(i + 1, j + 1)]);
                triangles.push([at(i, j), at(i + 1, j + 1), at(i, j + 1)]);
            }
        }
    }
    (vertices, triangles)
}

#[cfg(test)]
mod tests {
    use super::*;

    fn cube(n: usize) -> TriangleMesh {
        let (v, t) = box_triangles_subdivided(DVec3::ZERO, DVec3::ONE, n);
        TriangleMesh::new(&v, &t, DEFAULT_CURVATURE).unwrap().0
    }

    #[test]
    fn a_box_is_closed_with_outward_normals_ridges_on_its_edges_and_flat_diagonals() {
        for n in [1, 3] {
            let m = cube(n);
            assert_eq!(m.triangles.len(), 12 * n * n);
            assert!(m.is_closed());
            for t in 0..m.triangles.len() {
                let centroid = m.corners(t).iter().sum::<DVec3>() / 3.0;
                assert!(m.normals[t].dot(centroid - DVec3::splat(0.5)) > 0.0, "normal {t} points inward");
                for k in 0..3 {
                    let [p, q] = [m.triangles[t][k], m.triangles[t][(k + 1) % 3]].map(|v| m.vertices[v as usize]);
                    // On one of the cube's edges: two coordinates the same at both ends, each 0 or 1.
                    let on_cube_edge = (0..3).filter(|&c| p[c] == q[c] && (p[c] == 0.0 || p[c] == 1.0)).count() >= 2;
                    let expected = if on_cube_edge { EdgeKind::Convex } else { EdgeKind::Flat };
                    assert_eq!(m.edges[t][k], expected, "triangle {t} edge {k}: {p} – {q}");
                }
            }
        }
    }

    #[test]
    fn a_box_with_its_corner_order_reversed_is_a_container_of_valleys_and_a_mirror_image_stays_solid() {
        let (v, t) = box_triangles(DVec3::ZERO, DVec3::ONE);
        let inward: Vec<[u32; 3]> = t.iter().map(|&[a, b, c]| [a, c, b]).collect();
        let (container, _) = TriangleMesh::new(&v, &inward, DEFAULT_CURVATURE).unwrap();
        assert!(container.edges.iter().flatten().all(|&k| k == EdgeKind::Concave || k == EdgeKind::Flat));
        assert!(!container.two_sided, "a closed mesh is one-sided");
        // Mirrored with the corner order flipped: still a solid with outward normals.
        let m = cube(1).transformed(|v| DVec3::new(v.x, v.y, -v.z), true);
        for t in 0..12 {
            let centroid = m.corners(t).iter().sum::<DVec3>() / 3.0;
            assert!(m.normals[t].dot(centroid - DVec3::new(0.5, 0.5, -0.5)) > 0.0);
        }
    }

    #[test]
    fn a_soup_of_separate_triangles_is_welded_and_bad_triangles_reported() {
        // Two triangles of a square as an STL soup (corners repeated), with 1e-12 noise.
        let soup = [
            DVec3::new(0.0, 0.0, 0.0),
            DVec3::new(1.0, 0.0, 0.0),
            DVec3::new(1.0, 1.0, 0.0),
            DVec3::new(1e-12, 0.0, 0.0),
            DVec3::new(1.0, 1.0, 1e-12),
            DVec3::new(0.0, 1.0, 0.0),
            // A degenerate sliver: three collinear corners.
            DVec3::new(0.0, 0.0, 0.0),
            DVec3::new(0.5, 0.0, 0.0),
            DVec3::new(1.0, 0.0, 0.0),
        ];
        let (m, report) = TriangleMesh::new(&soup, &[[0, 1, 2], [3, 4, 5], [6, 7, 8]], DEFAULT_CURVATURE).unwrap();
        assert_eq!(m.vertices.len(), 5, "the shared corners are welded; the sliver's middle corner stays");
        assert_eq!(m.triangles.len(), 2);
        assert_eq!((report.welded, report.degenerate, report.open_edges, report.inconsistent_edges), (4, 1, 4, 0));
        assert_eq!(m.across[0][2], 1, "the diagonal joins the two triangles");
        assert_eq!(m.edges[0][2], EdgeKind::Flat);
        assert_eq!(report.warnings().len(), 1);
    }

    #[test]
    fn flipped_neighbours_duplicates_and_bad_indices_are_found() {
        let v = [DVec3::ZERO, DVec3::X, DVec3::new(1.0, 1.0, 0.0), DVec3::Y];
        let (_, report) = TriangleMesh::new(&v, &[[0, 1, 2], [0, 3, 2]], DEFAULT_CURVATURE).unwrap();
        assert_eq!(report.inconsistent_edges, 1);
        assert_eq!(TriangleMesh::new(&v, &[[0, 1, 2], [1, 2, 0]], DEFAULT_CURVATURE).unwrap_err(), MeshError::Duplicate { first: 0, second: 1 });
        assert_eq!(TriangleMesh::new(&v, &[[0, 1, 7]], DEFAULT_CURVATURE).unwrap_err(), MeshError::BadIndex { triangle: 0, vertex: 7 });
        assert_eq!(TriangleMesh::new(&v, &[[0, 1, 1]], DEFAULT_CURVATURE).unwrap_err(), MeshError::Empty);
        // A fin: three triangles on one edge.
        let fin = [DVec3::ZERO, DVec3::X, DVec3::Y, DVec3::NEG_Y, DVec3::Z];
        let (_, report) = TriangleMesh::new(&fin, &[[0, 1, 2], [1, 0, 3], [0, 1, 4]], DEFAULT_CURVATURE).unwrap();
        assert_eq!(report.non_manifold_edges, 1);
    }
}
