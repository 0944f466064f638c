// tidy: long file: one type (the hull with its faces, edges, mass properties and named solids) and its tests.
use glam::{DMat3, DQuat};
use parry3d_f64::mass_properties::MassProperties;
use parry3d_f64::math::SymmetricEigen3;
use parry3d_f64::shape::ConvexPolyhedron;

use crate::{DVec3, Pose};

/// One face of a [`Polyhedron`]: a planar convex polygon.
#[derive(Clone, Debug, PartialEq)]
pub struct Face {
    /// Unit outward normal (body frame).
    pub normal: DVec3,
    /// Area centroid of the face (body frame).
    pub centroid: DVec3,
    /// `normal · centroid`: the plane is `normal · p = offset`.
    pub offset: f64,
    /// Vertex indices, counter-clockwise seen from outside (right-handed about `normal`).
    pub vertices: Vec<u32>,
}

/// One edge of a [`Polyhedron`], listed once.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Edge {
    /// Vertex indices; `faces[0]` runs from `vertices[0]` to `vertices[1]` counter-clockwise.
    pub vertices: [u32; 2],
    /// The two faces that meet at this edge.
    pub faces: [u32; 2],
}

/// A convex polyhedron in its body frame: the origin at the centre of mass and the axes
/// along the principal axes of inertia.
///
/// The hull of the given points is computed with parry3d, coplanar hull triangles are
/// merged into polygonal faces (points inside a face or on an edge are dropped), and the
/// mass properties come from parry3d's polyhedron integrals, diagonalised here.
///
/// ```
/// use tumble_geom::{DVec3, Polyhedron};
/// let cube = Polyhedron::cube(2.0);
/// assert_eq!((cube.vertices().len(), cube.faces().len(), cube.edges().len()), (8, 6, 12));
/// assert!((cube.volume() - 8.0).abs() < 1e-12);
/// // I = m a²/6 for a cube of edge a, here with density 3.
/// let i = cube.principal_inertia(3.0);
/// assert!((i.x - 24.0 * 4.0 / 6.0).abs() < 1e-10);
/// assert!((cube.bounding_radius() - 3f64.sqrt()).abs() < 1e-12);
/// ```
#[derive(Clone, Debug, PartialEq)]
pub struct Polyhedron {
    vertices: Vec<DVec3>,
    faces: Vec<Face>,
    edges: Vec<Edge>,
    bounding_radius: f64,
    volume: f64,
    unit_inertia: DVec3,
    input_to_body: Pose,
    /// parry3d's copy of the shape (body frame), for the GJK/EPA path of large shapes.
    parry: ConvexPolyhedron,
    /// The face of largest area (the first of equals).
    largest_face: usize,
}

/// Relative tolerance (of the size) for coplanarity and collinearity when building faces.
const PLANAR_TOL: f64 = 1e-9;

impl Polyhedron {
    /// The convex hull of `points` (any frame; at least four points not in one plane).
    ///
    /// Returns `None` for degenerate input (fewer than four points, all coplanar, non-finite).
    pub fn from_points(points: &[DVec3]) -> Option<Polyhedron> {
        if points.len() < 4 || points.iter().any(|p| !p.is_finite()) {
            return None;
        }
        let (hull_pts, tris) = parry3d_f64::transformation::try_convex_hull(points).ok()?;
        if tris.len() < 4 {
            return None;
        }
        let mp = MassProperties::from_convex_polyhedron(1.0, &hull_pts, &tris);
        let volume = mp.mass();
        let size = hull_pts.iter().map(|p| (*p - hull_pts[0]).length()).fold(0.0, f64::max);
        if volume.is_nan() || volume <= 1e-12 * size * size * size {
            return None;
        }
        let com = mp.local_com;
        let (axes, unit_inertia) = principal_frame(mp.reconstruct_inertia_matrix());
        // Body coordinates: p_body = axesᵀ (p − com).
        let rotation = DQuat::from_mat3(&axes).normalize();
        let to_body = |p: DVec3| axes.transpose() * (p - com);
        let body: Vec<DVec3> = hull_pts.iter().map(|p| to_body(*p)).collect();

        let (vertices, faces) = merge_faces(&body, &tris, size)?;
        let edges = edges_of(&faces)?;
        let bounding_radius = vertices.iter().map(|v| v.length()).fold(0.0, f64::max);
        // input = com + axes · body, so the body frame sits at `com` with orientation `rotation` in the input frame;
        // input_to_body maps input coordinates to body coordinates.
        let input_to_body = Pose { position: -rotation.inverse().mul_vec3(com), rotation: rotation.inverse() };
        let parry = ConvexPolyhedron::from_convex_hull(&vertices)?;
        let mut p = Polyhedron { vertices, faces, edges, bounding_radius, volume, unit_inertia, input_to_body, parry, largest_face: 0 };
        p.largest_face = (0..p.faces.len()).fold(0, |best, f| if p.face_area(f) > p.face_area(best) { f } else { best });
        Some(p)
    }

    /// A cube of edge length `edge`.
    pub fn cube(edge: f64) -> Polyhedron {
        Polyhedron::cuboid(DVec3::splat(0.5 * edge))
    }

    /// A rectangular box with the given half extents (body axes along the box axes).
    pub fn cuboid(half: DVec3) -> Polyhedron {
        Polyhedron::try_cuboid(half).expect("a box with positive half extents")
    }

    /// A box, or `None` where its sides are too unequal for a hull (flatter than about 1:1000).
    pub fn try_cuboid(half: DVec3) -> Option<Polyhedron> {
        let mut pts = Vec::with_capacity(8);
        for &x in &[-half.x, half.x] {
            for &y in &[-half.y, half.y] {
                for &z in &[-half.z, half.z] {
                    pts.push(DVec3::new(x, y, z));
                }
            }
        }
        Polyhedron::from_points(&pts)
    }

    /// A regular tetrahedron of edge length `edge`.
    pub fn tetrahedron(edge: f64) -> Polyhedron {
        let s = edge / (2.0 * 2f64.sqrt());
        let pts = [DVec3::new(1.0, 1.0, 1.0), DVec3::new(1.0, -1.0, -1.0), DVec3::new(-1.0, 1.0, -1.0), DVec3::new(-1.0, -1.0, 1.0)];
        Polyhedron::from_points(&pts.map(|p| p * s)).expect("a regular tetrahedron")
    }

    /// A regular octahedron of edge length `edge`.
    pub fn octahedron(edge: f64) -> Polyhedron {
        let s = edge / 2f64.sqrt();
        let pts = [DVec3::X, -DVec3::X, DVec3::Y, -DVec3::Y, DVec3::Z, -DVec3::Z];
        Polyhedron::from_points(&pts.map(|p| p * s)).expect("a regular octahedron")
    }

    /// A regular icosahedron of edge length `edge`.
    pub fn icosahedron(edge: f64) -> Polyhedron {
        let phi = golden();
        let mut pts = Vec::with_capacity(12);
        for &a in &[-1.0, 1.0] {
            for &b in &[-phi, phi] {
                pts.push(DVec3::new(0.0, a, b));
                pts.push(DVec3::new(a, b, 0.0));
                pts.push(DVec3::new(b, 0.0, a));
            }
        }
        let s = 0.5 * edge;
        Polyhedron::from_points(&pts.iter().map(|p| *p * s).collect::<Vec<_>>()).expect("a regular icosahedron")
    }

    /// A regular dodecahedron of edge length `edge`.
    pub fn dodecahedron(edge: f64) -> Polyhedron {
        let phi = golden();
        let mut pts = Vec::with_capacity(20);
        for &x in &[-1.0, 1.0] {
            for &y in &[-1.0, 1.0] {
                for &z in &[-1.0, 1.0] {
                    pts.push(DVec3::new(x, y, z));
                }
            }
        }
        for &a in &[-1.0 / phi, 1.0 / phi] {
            for &b in &[-phi, phi] {
                pts.push(DVec3::new(0.0, a, b));
                pts.push(DVec3::new(a, b, 0.0));
                pts.push(DVec3::new(b, 0.0, a));
            }
        }
        let s = 0.5 * edge * phi;
        Polyhedron::from_points(&pts.iter().map(|p| *p * s).collect::<Vec<_>>()).expect("a regular dodecahedron")
    }

    /// A right prism on a regular `n`-gon (`n ≥ 3`) of circumradius `radius`, axis along z, total `height`.
    pub fn prism(n: usize, radius: f64, height: f64) -> Polyhedron {
        Polyhedron::try_prism(n, radius, height).expect("a prism with positive radius and height")
    }

    /// A prism, or `None` where it is too flat or too thin for a hull.
    pub fn try_prism(n: usize, radius: f64, height: f64) -> Option<Polyhedron> {
        assert!(n >= 3, "a prism needs at least a triangle");
        let mut pts = Vec::with_capacity(2 * n);
        for k in 0..n {
            let th = std::f64::consts::TAU * k as f64 / n as f64;
            for &z in &[-0.5 * height, 0.5 * height] {
                pts.push(DVec3::new(radius * th.cos(), radius * th.sin(), z));
            }
        }
        Polyhedron::from_points(&pts)
    }

    /// The same shape scaled by `factor > 0` about its centre of mass (one particle type per size).
    ///
    /// ```
    /// use tumble_geom::Polyhedron;
    /// let big = Polyhedron::tetrahedron(1.0).scaled(3.0);
    /// assert!((big.volume() - 27.0 * Polyhedron::tetrahedron(1.0).volume()).abs() < 1e-12);
    /// ```
    pub fn scaled(&self, factor: f64) -> Polyhedron {
        assert!(factor > 0.0 && factor.is_finite(), "scale factor must be positive");
        let mut p = self.clone();
        p.vertices.iter_mut().for_each(|v| *v *= factor);
        for f in &mut p.faces {
            f.centroid *= factor;
            f.offset *= factor;
        }
        p.bounding_radius *= factor;
        p.volume *= factor.powi(3);
        p.unit_inertia *= factor.powi(5);
        p.input_to_body.position *= factor;
        p.parry = ConvexPolyhedron::from_convex_hull(&p.vertices).expect("a scaled hull stays valid");
        p
    }

    /// Vertices in the body frame.
    pub fn vertices(&self) -> &[DVec3] {
        &self.vertices
    }

    pub fn faces(&self) -> &[Face] {
        &self.faces
    }

    pub fn edges(&self) -> &[Edge] {
        &self.edges
    }

    /// Area of face `f`.
    pub fn face_area(&self, f: usize) -> f64 {
        let v = &self.faces[f].vertices;
        let p = |k: usize| self.vertices[v[k] as usize];
        (1..v.len() - 1).map(|k| (p(k) - p(0)).cross(p(k + 1) - p(0))).sum::<DVec3>().length() / 2.0
    }

    /// The largest face area: the contact area of a face lying on a flat wall.
    pub fn largest_face_area(&self) -> f64 {
        self.face_area(self.largest_face())
    }

    /// The face of largest area (the first of equals).
    pub fn largest_face(&self) -> usize {
        self.largest_face
    }

    /// The length of face `f`'s boundary.
    pub fn face_perimeter(&self, f: usize) -> f64 {
        let v = &self.faces[f].vertices;
        (0..v.len()).map(|k| (self.vertices[v[(k + 1) % v.len()] as usize] - self.vertices[v[k] as usize]).length()).sum()
    }

    /// Largest vertex distance from the centre of mass.
    pub fn bounding_radius(&self) -> f64 {
        self.bounding_radius
    }

    pub fn volume(&self) -> f64 {
        self.volume
    }

    pub fn mass(&self, density: f64) -> f64 {
        self.volume * density
    }

    /// Principal moments of inertia per unit density (about the body axes).
    pub fn unit_inertia(&self) -> DVec3 {
        self.unit_inertia
    }

    /// Principal moments of inertia for the given density.
    pub fn principal_inertia(&self, density: f64) -> DVec3 {
        self.unit_inertia * density
    }

    /// Maps the coordinates the points were given in to the body frame
    /// (`body = input_to_body.to_world(input)`).
    pub fn input_to_body(&self) -> Pose {
        self.input_to_body
    }

    /// Signed distance of the body point `p` from face `f`'s plane (negative inside).
    #[inline]
    pub fn face_distance(&self, f: usize, p: DVec3) -> f64 {
        self.faces[f].normal.dot(p) - self.faces[f].offset
    }

    /// Largest face distance of body point `p`: negative inside, the distance itself in face regions.
    pub fn max_face_distance(&self, p: DVec3) -> f64 {
        self.faces.iter().map(|f| f.normal.dot(p) - f.offset).fold(f64::NEG_INFINITY, f64::max)
    }

    /// Whether the body point `p` is inside (or on) the polyhedron.
    pub fn contains(&self, p: DVec3) -> bool {
        self.max_face_distance(p) <= 0.0
    }

    /// The vertex farthest along the body direction `dir` (its index).
    pub fn support_index(&self, dir: DVec3) -> usize {
        let mut best = 0;
        let mut best_d = f64::NEG_INFINITY;
        for (i, v) in self.vertices.iter().enumerate() {
            let d = v.dot(dir);
            if d > best_d {
                best_d = d;
                best = i;
            }
        }
        best
    }

    /// A characteristic size: twice the bounding radius.
    pub fn size(&self) -> f64 {
        2.0 * self.bounding_radius
    }

    /// The same shape as parry3d's convex polyhedron, in the body frame.
    pub fn parry_shape(&self) -> &ConvexPolyhedron {
        &self.parry
    }

    /// A copy of [`Self::parry_shape`].
    pub fn to_parry(&self) -> ConvexPolyhedron {
        self.parry.clone()
    }
}

fn golden() -> f64 {
    0.5 * (1.0 + 5f64.sqrt())
}

/// Principal axes (columns, right-handed) and moments of a symmetric inertia tensor.
///
/// A tensor that is already diagonal keeps the input axes (so a cube, a prism or a regular
/// solid keeps the orientation it was given in, although any frame is principal there);
/// otherwise the axes are the eigenvectors, moments ascending.
fn principal_frame(inertia: DMat3) -> (DMat3, DVec3) {
    let cols = inertia.to_cols_array_2d();
    let trace = inertia.x_axis.x + inertia.y_axis.y + inertia.z_axis.z;
    let off = cols[0][1].abs().max(cols[0][2].abs()).max(cols[1][2].abs());
    if off <= 1e-12 * trace {
        return (DMat3::IDENTITY, DVec3::new(inertia.x_axis.x, inertia.y_axis.y, inertia.z_axis.z));
    }
    let eig = SymmetricEigen3::new(inertia);
    let mut order = [0usize, 1, 2];
    let vals = eig.eigenvalues.to_array();
    order.sort_by(|a, b| vals[*a].total_cmp(&vals[*b]));
    let col = |i: usize| eig.eigenvectors.col(i).normalize();
    let (e0, e1) = (col(order[0]), col(order[1]));
    let e1 = (e1 - e0 * e0.dot(e1)).normalize();
    let e2 = e0.cross(e1);
    (DMat3::from_cols(e0, e1, e2), DVec3::new(vals[order[0]], vals[order[1]], vals[order[2]]))
}

/// Groups hull triangles by outward normal into polygon faces and drops points that are no
/// vertex of the polytope. Returns the compacted vertices and the faces.
fn merge_faces(points: &[DVec3], tris: &[[u32; 3]], size: f64) -> Option<(Vec<DVec3>, Vec<Face>)> {
    struct Group {
        normal_sum: DVec3,
        members: Vec<u32>,
    }
    let mut groups: Vec<Group> = Vec::new();
    for t in tris {
        let (a, b, c) = (points[t[0] as usize], points[t[1] as usize], points[t[2] as usize]);
        let area2 = (b - a).cross(c - a);
        let len = area2.length();
        if len <= 1e-14 * size * size {
            continue; // a sliver carries no face of its own
        }
        let n = area2 / len;
        // A convex polytope has one face per outward normal: group by normal alone.
        // By the sine of the angle: 1 − cos would merge faces up to √(2·tol) apart, leaving vertices off their plane.
        match groups.iter_mut().find(|g| {
            let m = g.normal_sum.normalize();
            m.dot(n) > 0.0 && m.cross(n).length() < PLANAR_TOL
        }) {
            Some(g) => {
                g.normal_sum += area2;
                g.members.extend_from_slice(t);
            }
            None => groups.push(Group { normal_sum: area2, members: t.to_vec() }),
        }
    }
    if groups.len() < 4 {
        return None;
    }
    // Each face's polygon: the 2D hull of its points in its plane (drops inner and collinear points).
    let mut loops: Vec<(DVec3, Vec<u32>)> = Vec::with_capacity(groups.len());
    for g in &mut groups {
        g.members.sort_unstable();
        g.members.dedup();
        let n = g.normal_sum.normalize();
        let loop_ = planar_hull(points, &g.members, n, size)?;
        loops.push((n, loop_));
    }
    // Compact the vertex list to the loop vertices.
    let mut remap = vec![u32::MAX; points.len()];
    let mut vertices = Vec::new();
    for (_, l) in &loops {
        for &i in l {
            if remap[i as usize] == u32::MAX {
                remap[i as usize] = vertices.len() as u32;
                vertices.push(points[i as usize]);
            }
        }
    }
    let faces = loops
        .into_iter()
        .map(|(n, l)| {
            let idx: Vec<u32> = l.iter().map(|&i| remap[i as usize]).collect();
            let (centroid, _) = polygon_centroid(&idx.iter().map(|&i| vertices[i as usize]).collect::<Vec<_>>(), n);
            // The plane through the face's vertices, averaged (they agree to rounding).
            let offset = idx.iter().map(|&i| n.dot(vertices[i as usize])).sum::<f64>() / idx.len() as f64;
            Face { normal: n, centroid, offset, vertices: idx }
        })
        .collect();
    Some((vertices, faces))
}

/// Counter-clockwise (about `n`) strictly convex hull of the given points of one plane.
pub(crate) fn planar_hull(points: &[DVec3], idx: &[u32], n: DVec3, size: f64) -> Option<Vec<u32>> {
    let t1 = n.any_orthonormal_vector();
    let t2 = n.cross(t1);
    let mut p: Vec<(f64, f64, u32)> = idx.iter().map(|&i| (points[i as usize].dot(t1), points[i as usize].dot(t2), i)).collect();
    p.sort_by(|a, b| a.0.total_cmp(&b.0).then(a.1.total_cmp(&b.1)));
    let eps = PLANAR_TOL * size * size;
    let cross = |o: (f64, f64, u32), a: (f64, f64, u32), b: (f64, f64, u32)| (a.0 - o.0) * (b.1 - o.1) - (a.1 - o.1) * (b.0 - o.0);
    // Andrew's monotone chain: lower hull, then upper hull (which may not pop into the lower one).
    let mut hull: Vec<(f64, f64, u32)> = Vec::with_capacity(2 * p.len());
    for &q in &p {
        while hull.len() >= 2 && cross(hull[hull.len() - 2], hull[hull.len() - 1], q) <= eps {
            hull.pop();
        }
        hull.push(q);
    }
    let lower = hull.len() + 1;
    for &q in p.iter().rev().skip(1) {
        while hull.len() >= lower && cross(hull[hull.len() - 2], hull[hull.len() - 1], q) <= eps {
            hull.pop();
        }
        hull.push(q);
    }
    hull.pop();
    let out: Vec<u32> = hull.iter().map(|h| h.2).collect();
    (out.len() >= 3).then_some(out)
}

/// Area centroid and area of a planar polygon.
fn polygon_centroid(pts: &[DVec3], n: DVec3) -> (DVec3, f64) {
    let o = pts[0];
    let mut area = 0.0;
    let mut c = DVec3::ZERO;
    for k in 1..pts.len() - 1 {
        let a = 0.5 * (pts[k] - o).cross(pts[k + 1] - o).dot(n);
        area += a;
        c += (o + pts[k] + pts[k + 1]) * (a / 3.0);
    }
    if area.abs() > 0.0 { (c / area, area) } else { (pts.iter().sum::<DVec3>() / pts.len() as f64, 0.0) }
}

/// Unique edges from the face loops; every edge must border exactly two faces.
fn edges_of(faces: &[Face]) -> Option<Vec<Edge>> {
    let mut edges: Vec<Edge> = Vec::new();
    let mut pending: std::collections::HashMap<(u32, u32), usize> = std::collections::HashMap::new();
    for (fi, f) in faces.iter().enumerate() {
        for k in 0..f.vertices.len() {
            let (a, b) = (f.vertices[k], f.vertices[(k + 1) % f.vertices.len()]);
            let key = (a.min(b), a.max(b));
            match pending.get(&key) {
                Some(&e) => {
                    if edges[e].faces[1] != u32::MAX {
                        return None;
                    }
                    edges[e].faces[1] = fi as u32;
                }
                None => {
                    pending.insert(key, edges.len());
                    edges.push(Edge { vertices: [a, b], faces: [fi as u32, u32::MAX] });
                }
            }
        }
    }
    edges.iter().all(|e| e.faces[1] != u32::MAX).then_some(edges)
}

#[cfg(test)]
mod tests {
    use super::*;

    fn check_closed(p: &Polyhedron) {
        let tol = 1e-12 * p.size();
        for (fi, f) in p.faces().iter().enumerate() {
            assert!((f.normal.length() - 1.0).abs() < 1e-12);
            // Outward: the centre of mass is inside, every vertex is on or behind the plane.
            assert!(f.offset > 0.0, "face {fi} does not face away from the centre");
            for v in p.vertices() {
                assert!(f.normal.dot(*v) - f.offset <= tol, "vertex outside face {fi}");
            }
            // Counter-clockwise about the normal.
            let vs: Vec<DVec3> = f.vertices.iter().map(|&i| p.vertices()[i as usize]).collect();
            let (_, area) = polygon_centroid(&vs, f.normal);
            assert!(area > 0.0);
        }
        // Euler: V − E + F = 2.
        assert_eq!(p.vertices().len() as i64 - p.edges().len() as i64 + p.faces().len() as i64, 2);
        // Centre of mass at the origin: the first moments of the vertices need not vanish, but the
        // centroid of the faces weighted by area and distance (the divergence theorem) does.
        let mut first = DVec3::ZERO;
        for f in p.faces() {
            let vs: Vec<DVec3> = f.vertices.iter().map(|&i| p.vertices()[i as usize]).collect();
            let o = vs[0];
            for k in 1..vs.len() - 1 {
                let (a, b, c) = (o, vs[k], vs[k + 1]);
                let vol = a.dot(b.cross(c)) / 6.0;
                first += (a + b + c) * (vol / 4.0);
            }
        }
        assert!(first.length() < 1e-10 * p.volume() * p.size(), "centre of mass off the origin: {first:?}");
    }

    #[test]
    fn cube_and_box_closed_forms() {
        let a = 0.7;
        let c = Polyhedron::cube(a);
        check_closed(&c);
        assert!((c.volume() - a * a * a).abs() < 1e-14);
        for k in 0..3 {
            assert!((c.unit_inertia()[k] - a.powi(5) / 6.0).abs() < 1e-14, "{:?}", c.unit_inertia());
        }
        let h = DVec3::new(0.1, 0.2, 0.3);
        let b = Polyhedron::cuboid(h);
        check_closed(&b);
        let m = 8.0 * h.x * h.y * h.z;
        assert!((b.volume() - m).abs() < 1e-15);
        let expected = DVec3::new(h.y * h.y + h.z * h.z, h.x * h.x + h.z * h.z, h.x * h.x + h.y * h.y) * (m / 3.0);
        assert!((b.unit_inertia() - expected).abs().max_element() < 1e-15, "{:?} vs {expected:?}", b.unit_inertia());
        assert_eq!(b.faces().len(), 6);
        assert!((b.principal_inertia(2500.0) - expected * 2500.0).length() < 1e-12);
        assert!((b.mass(2500.0) - m * 2500.0).abs() < 1e-12);
    }

    #[test]
    fn platonic_solids_volumes_and_inertia() {
        let a = 1.3;
        let phi = golden();
        let s5 = 5f64.sqrt();
        // (shape, V/a³, I/(m a²), V, E, F)
        let cases = [
            (Polyhedron::tetrahedron(a), 1.0 / (6.0 * 2f64.sqrt()), 1.0 / 20.0, 4, 6, 4),
            (Polyhedron::octahedron(a), 2f64.sqrt() / 3.0, 1.0 / 10.0, 6, 12, 8),
            (Polyhedron::icosahedron(a), 5.0 * (3.0 + s5) / 12.0, phi * phi / 10.0, 12, 30, 20),
            (Polyhedron::dodecahedron(a), (15.0 + 7.0 * s5) / 4.0, (39.0 * phi + 28.0) / 150.0, 20, 30, 12),
        ];
        for (p, v, i, nv, ne, nf) in cases {
            check_closed(&p);
            assert_eq!((p.vertices().len(), p.edges().len(), p.faces().len()), (nv, ne, nf));
            let vol = v * a * a * a;
            assert!((p.volume() - vol).abs() < 1e-12 * vol, "volume {} vs {vol}", p.volume());
            for k in 0..3 {
                let ik = i * vol * a * a;
                assert!((p.unit_inertia()[k] - ik).abs() < 1e-10 * ik, "inertia {:?} vs {ik}", p.unit_inertia());
            }
        }
    }

    #[test]
    fn prisms_have_n_plus_two_faces_and_closed_form_volume() {
        for n in [3usize, 4, 6, 7, 12] {
            let (r, h) = (0.4, 0.9);
            let p = Polyhedron::prism(n, r, h);
            check_closed(&p);
            assert_eq!(p.faces().len(), n + 2);
            assert_eq!(p.vertices().len(), 2 * n);
            let area = 0.5 * n as f64 * r * r * (std::f64::consts::TAU / n as f64).sin();
            assert!((p.volume() - area * h).abs() < 1e-12, "n = {n}");
            // Axial moment: the regular n-gon's polar moment, m (r²/6)(2 + cos(2π/n)).
            let iz = p.volume() * r * r * (2.0 + (std::f64::consts::TAU / n as f64).cos()) / 6.0;
            assert!((p.unit_inertia().z - iz).abs() < 1e-12, "n = {n}: {} vs {iz}", p.unit_inertia().z);
        }
    }

    #[test]
    fn random_hull_is_centred_on_principal_axes() {
        // A skewed cloud: the body frame must diagonalise the inertia tensor.
        let mut pts = Vec::new();
        let mut s = 12345u64;
        let mut rnd = || {
            s = s.wrapping_mul(6364136223846793005).wrapping_add(1442695040888963407);
            (s >> 11) as f64 / (1u64 << 53) as f64 - 0.5
        };
        for _ in 0..40 {
            let (x, y, z) = (rnd(), rnd(), rnd());
            pts.push(DVec3::new(x + 0.8 * y, y * 0.5, z + 0.3 * x) + DVec3::new(3.0, -2.0, 1.0));
        }
        let p = Polyhedron::from_points(&pts).unwrap();
        check_closed(&p);
        let mp = MassProperties::from_convex_polyhedron(
            1.0,
            p.vertices(),
            &p.faces()
                .iter()
                .flat_map(|f| (1..f.vertices.len() - 1).map(move |k| [f.vertices[0], f.vertices[k], f.vertices[k + 1]]))
                .collect::<Vec<_>>(),
        );
        assert!(mp.local_com.length() < 1e-12);
        let i = mp.reconstruct_inertia_matrix();
        let c = i.to_cols_array_2d();
        let scale = p.unit_inertia().max_element();
        assert!(c[0][1].abs().max(c[0][2].abs()).max(c[1][2].abs()) < 1e-10 * scale, "{i:?}");
        assert!((DVec3::new(c[0][0], c[1][1], c[2][2]) - p.unit_inertia()).abs().max_element() < 1e-10 * scale);
        assert!(p.unit_inertia().x <= p.unit_inertia().y && p.unit_inertia().y <= p.unit_inertia().z);
        // The input points map into the body hull.
        let to_body = p.input_to_body();
        for q in &pts {
            assert!(p.max_face_distance(to_body.to_world(*q)) < 1e-12);
        }
        // Principal axes orthonormal and right-handed.
        let m = DMat3::from_quat(to_body.rotation);
        assert!((m.determinant() - 1.0).abs() < 1e-12);
        assert!((m * m.transpose() - DMat3::IDENTITY).to_cols_array().iter().all(|x| x.abs() < 1e-12));
    }

    #[test]
    fn inner_and_coplanar_points_are_dropped() {
        let mut pts: Vec<DVec3> = Polyhedron::cube(2.0).vertices().to_vec();
        pts.push(DVec3::new(0.2, 0.1, 0.0)); // inside
        pts.push(DVec3::new(1.0, 0.3, -0.2)); // inside a face
        pts.push(DVec3::new(1.0, 1.0, 0.5)); // on an edge
        let p = Polyhedron::from_points(&pts).unwrap();
        check_closed(&p);
        assert_eq!((p.vertices().len(), p.edges().len(), p.faces().len()), (8, 12, 6));
    }

    #[test]
    fn degenerate_input_is_refused() {
        assert!(Polyhedron::from_points(&[DVec3::ZERO, DVec3::X, DVec3::Y]).is_none());
        assert!(Polyhedron::from_points(&[DVec3::ZERO, DVec3::X, DVec3::Y, DVec3::new(1.0, 1.0, 0.0)]).is_none());
    }
}
