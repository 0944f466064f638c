//! The polyhedron shape table on the device, and a batch evaluator of the
//! polyhedron narrow phase (tumble-shaders' `polyhedra.wgsl` and its pair files) for tests and diagnostics.
//!
//! The table is one array of 16-byte words (`vec4<f32>`); every index and count
//! is stored as an f32 holding a whole number (exact below 2²⁴), so no bit
//! pattern is ever reinterpreted. For `S` shapes:
//!
//! ```text
//! word 4s     (vertex start, vertex count, face start, face count)      header of shape s
//! word 4s + 1 (edge start, edge count, bounding radius, unused)
//! word 4s + 2 (volume / principal unit inertia (x, y, z), equivalent radius)
//!             inverse principal inertia = inverse mass × xyz; radius of the sphere of equal volume
//! word 4s + 3 (largest face area, its corners, its perimeter, 0)   the overlap-volume contact's references
//! vertices    (x, y, z, 0)                    body frame, one word each
//! faces       (nx, ny, nz, offset)            plane n · p = offset, then
//!             (list start, list length, 0, 0) where its vertex loop starts (a word index, see below)
//! edges       (v0, v1, f0, f1)                local vertex and face indices; f0 runs v0 → v1 counter-clockwise
//! loops       (i, j, k, l)                    face vertex loops, four local vertex indices per word
//! ```
//!
//! Starts are absolute word indices (faces: the first of the face's two words); a
//! face's loop entry `k` is component `k % 4` of word `list start + k / 4`, where
//! `list start` counts components from the start of the loop area (so loops of
//! different faces share words). Body frames are the principal frames of
//! `tumble_geom::Polyhedron`.

use bytemuck::{Pod, Zeroable};
use glam::{DQuat, DVec3};
use tumble_geom::Polyhedron;

/// Most vertices in one face loop on the device (the clipped polygon holds twice this).
pub const MAX_FACE_VERTICES: usize = tumble_shaders::MAX_FACE_VERTICES as usize;
/// Most vertices of one shape on the device (a manifold against a wall holds every vertex).
pub const MAX_VERTICES: usize = tumble_shaders::MAX_VERTICES as usize;

/// Header words per shape.
pub const HEADER_WORDS: usize = tumble_shaders::SHAPE_HEADER_WORDS as usize;
/// Face-loop vertex indices per word.
const LOOP_INDICES: usize = tumble_shaders::LOOP_INDICES_PER_WORD as usize;

/// The radius of the sphere of the polyhedron's volume (R* of the contact laws).
pub fn equivalent_radius(p: &Polyhedron) -> f64 {
    (3.0 * p.volume() / (4.0 * std::f64::consts::PI)).cbrt()
}

/// Why a shape cannot go on the device.
#[derive(Clone, Debug, PartialEq)]
pub struct ShapeError(pub String);

impl std::fmt::Display for ShapeError {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.write_str(&self.0)
    }
}

impl std::error::Error for ShapeError {}

/// The device shape table of a list of polyhedra (see the module documentation).
pub fn shape_table(shapes: &[Polyhedron]) -> Result<Vec<[f32; 4]>, ShapeError> {
    let mut words = vec![[0.0f32; 4]; HEADER_WORDS * shapes.len()];
    let mut loops: Vec<u32> = Vec::new();
    let mut loop_fixups: Vec<(usize, usize)> = Vec::new(); // (face info word, component start in `loops`)
    for (s, p) in shapes.iter().enumerate() {
        if p.vertices().len() > MAX_VERTICES {
            return Err(ShapeError(format!("shape {s} has {} vertices; the GPU backend takes at most {MAX_VERTICES}", p.vertices().len())));
        }
        // tumble-geom hands pairs with more edge pairs to parry3d's GJK/EPA, which the device does not run.
        if let Some(o) = shapes.iter().position(|o| o.edges().len() * p.edges().len() > tumble_geom::SAT_MAX_EDGE_PAIRS) {
            return Err(ShapeError(format!(
                "shapes {s} and {o} have {} edge pairs; the GPU backend runs the separating-axis test up to {} (larger pairs take GJK on the CPU)",
                p.edges().len() * shapes[o].edges().len(),
                tumble_geom::SAT_MAX_EDGE_PAIRS
            )));
        }
        if let Some(f) = p.faces().iter().position(|f| f.vertices.len() > MAX_FACE_VERTICES) {
            return Err(ShapeError(format!(
                "shape {s} has a face with {} vertices; the GPU backend clips faces of at most {MAX_FACE_VERTICES}",
                p.faces()[f].vertices.len()
            )));
        }
        let vert_start = words.len();
        words.extend(p.vertices().iter().map(|v| [v.x as f32, v.y as f32, v.z as f32, 0.0]));
        let face_start = words.len();
        for f in p.faces() {
            words.push([f.normal.x as f32, f.normal.y as f32, f.normal.z as f32, f.offset as f32]);
            loop_fixups.push((words.len(), loops.len()));
            words.push([0.0, f.vertices.len() as f32, 0.0, 0.0]);
            loops.extend_from_slice(&f.vertices);
        }
        let edge_start = words.len();
        words.extend(p.edges().iter().map(|e| [e.vertices[0] as f32, e.vertices[1] as f32, e.faces[0] as f32, e.faces[1] as f32]));
        words[HEADER_WORDS * s] = [vert_start as f32, p.vertices().len() as f32, face_start as f32, p.faces().len() as f32];
        words[HEADER_WORDS * s + 1] = [edge_start as f32, p.edges().len() as f32, p.bounding_radius() as f32, 0.0];
        let k = p.volume() / p.unit_inertia();
        words[HEADER_WORDS * s + 2] = [k.x as f32, k.y as f32, k.z as f32, equivalent_radius(p) as f32];
        let largest = p.largest_face();
        words[HEADER_WORDS * s + 3] = [p.largest_face_area() as f32, p.faces()[largest].vertices.len() as f32, p.face_perimeter(largest) as f32, 0.0];
    }
    let loop_start = words.len();
    for (word, component) in loop_fixups {
        words[word][0] = (LOOP_INDICES * loop_start + component) as f32;
    }
    for chunk in loops.chunks(LOOP_INDICES) {
        let mut w = [0.0f32; 4];
        for (k, &i) in chunk.iter().enumerate() {
            w[k] = i as f32;
        }
        words.push(w);
    }
    if words.len() * 4 >= 1 << 24 {
        return Err(ShapeError(format!("the shape table has {} words; indices must stay below 2^24 / 4", words.len())));
    }
    if words.is_empty() {
        words.push([0.0; 4]);
    }
    Ok(words)
}

/// Refuses shapes whose faces, clipped by another shape's planes (or a wall's square by theirs),
/// could outgrow the device's polygon buffer in the overlap-volume model: a convex polygon gains at
/// most one vertex per clipping plane.
pub fn check_volume_limits(shapes: &[Polyhedron]) -> Result<(), ShapeError> {
    let points = tumble_shaders::MANIFOLD_POINTS as usize;
    let widest = shapes.iter().map(|p| p.faces().iter().map(|f| f.vertices.len()).max().unwrap_or(0)).max().unwrap_or(0).max(4);
    match shapes.iter().position(|p| widest + p.faces().len() > points) {
        Some(s) => Err(ShapeError(format!(
            "shape {s} has {} faces: clipped against it, a face of {widest} vertices could reach {} points, over the GPU's {points} (use contact.polyhedron_model = \"depth\" or the CPU)",
            shapes[s].faces().len(),
            widest + shapes[s].faces().len()
        ))),
        None => Ok(()),
    }
}

/// Kinds of [`ContactQuery`].
pub mod query {
    /// Polyhedron `shape_a` against polyhedron `shape_b`.
    pub const POLYHEDRON: u32 = tumble_shaders::QUERY_POLYHEDRA;
    /// A sphere (radius `sphere_radius`, at `pos_a`) against polyhedron `shape_b`.
    pub const SPHERE: u32 = tumble_shaders::QUERY_SPHERE;
    /// Polyhedron `shape_a` against the wall in `wall` (6 words, the layout of geometry.wgsl).
    pub const WALL: u32 = tumble_shaders::QUERY_WALL;
    /// The overlap-volume contact of polyhedron `shape_a` with polyhedron `shape_b`.
    pub const VOLUME_PAIR: u32 = tumble_shaders::QUERY_VOLUME_PAIR;
    /// The overlap-volume contact of polyhedron `shape_a` with the wall in `wall`.
    pub const VOLUME_WALL: u32 = tumble_shaders::QUERY_VOLUME_WALL;
}

/// One narrow-phase query for [`evaluate`]: positions are relative to any common origin
/// (keep it near the bodies: f32), quaternions (x, y, z, w) body to world.
#[repr(C)]
#[derive(Clone, Copy, Debug, Pod, Zeroable)]
pub struct ContactQuery {
    /// (kind, shape a, shape b, sphere radius); indices as whole f32 numbers.
    pub head: [f32; 4],
    pub pos_a: [f32; 4],
    pub quat_a: [f32; 4],
    pub pos_b: [f32; 4],
    pub quat_b: [f32; 4],
    /// A wall entry (geometry.wgsl's layout, [`crate::upload::wall_entry`]): (kind WALL_PLANE, WALL_QUAD or
    /// WALL_CYLINDER; unused; two-sided / inside; unused), then the corners, points and directions.
    pub wall: [[f32; 4]; tumble_shaders::WALL_ENTRY_WORDS as usize],
}

impl ContactQuery {
    #[allow(clippy::too_many_arguments)]
    fn posed(kind: u32, a: u32, b: u32, radius: f64, pos_a: DVec3, quat_a: DQuat, pos_b: DVec3, quat_b: DQuat) -> Self {
        let v = |p: DVec3| [p.x as f32, p.y as f32, p.z as f32, 0.0];
        let q = |q: DQuat| [q.x as f32, q.y as f32, q.z as f32, q.w as f32];
        ContactQuery {
            head: [kind as f32, a as f32, b as f32, radius as f32],
            pos_a: v(pos_a),
            quat_a: q(quat_a),
            pos_b: v(pos_b),
            quat_b: q(quat_b),
            wall: [[0.0; 4]; tumble_shaders::WALL_ENTRY_WORDS as usize],
        }
    }

    /// Polyhedron `a` at (`pos_a`, `quat_a`) against polyhedron `b`.
    pub fn polyhedra(a: u32, pos_a: DVec3, quat_a: DQuat, b: u32, pos_b: DVec3, quat_b: DQuat) -> Self {
        Self::posed(query::POLYHEDRON, a, b, 0.0, pos_a, quat_a, pos_b, quat_b)
    }

    /// A sphere at `centre` against polyhedron `b`.
    pub fn sphere(centre: DVec3, radius: f64, b: u32, pos_b: DVec3, quat_b: DQuat) -> Self {
        Self::posed(query::SPHERE, 0, b, radius, centre, DQuat::IDENTITY, pos_b, quat_b)
    }

    /// Polyhedron `a` against a plane, quad or cylinder wall (prisms go as polyhedra: hull them).
    pub fn wall(a: u32, pos_a: DVec3, quat_a: DQuat, wall: &tumble_geom::SurfaceShape) -> Self {
        let mut c = Self::posed(query::WALL, a, 0, 0.0, pos_a, quat_a, DVec3::ZERO, DQuat::IDENTITY);
        c.wall = crate::upload::wall_entry(wall, 0, DVec3::ZERO);
        c
    }

    /// This query as its overlap-volume counterpart (pairs and walls; the answer's fields then
    /// hold a volume contact, see [`ContactAnswer`]).
    pub fn volume(mut self) -> Self {
        self.head[0] = match self.head[0] as u32 {
            query::POLYHEDRON => query::VOLUME_PAIR,
            query::WALL => query::VOLUME_WALL,
            k => panic!("query kind {k} has no volume counterpart"),
        } as f32;
        self
    }
}

/// The answer to one [`ContactQuery`]: the tumble-geom `PolyContact` in f32, or for the volume
/// kinds its `VolumeContact` (normal: the push; extra: turn_a and the volume; turn_b: turn_b and
/// the area; corners: Σ weight × depth × gradient over the corners and edge points, their count).
#[repr(C)]
#[derive(Clone, Copy, Debug, Default, PartialEq, Pod, Zeroable)]
pub struct ContactAnswer {
    /// Unit normal from B (or the wall) to A (volume: the push); w: 1 in contact, 0 not.
    pub normal: [f32; 4],
    /// The contact point relative to the query's origin; w: the depth.
    pub point: [f32; 4],
    /// (spread: the depth-weighted mean distance of the manifold points from the point, 0, 0, 0);
    /// volume: (turn_a, volume).
    pub extra: [f32; 4],
    /// Volume: (turn_b, area).
    pub turn_b: [f32; 4],
    /// Volume: (Σ weight × depth × gradient over the corners and edge points inside, their count).
    pub corners: [f32; 4],
}

const _: () = assert!(std::mem::size_of::<ContactAnswer>() == 16 * tumble_shaders::ANSWER_WORDS as usize);

impl ContactAnswer {
    pub fn hit(&self) -> bool {
        self.normal[3] != 0.0
    }
    pub fn normal(&self) -> DVec3 {
        DVec3::new(self.normal[0] as f64, self.normal[1] as f64, self.normal[2] as f64)
    }
    pub fn depth(&self) -> f64 {
        self.point[3] as f64
    }
    pub fn point(&self) -> DVec3 {
        DVec3::new(self.point[0] as f64, self.point[1] as f64, self.point[2] as f64)
    }
    /// The manifold's patch radius (twisting friction); 0 for a one-point contact.
    pub fn spread(&self) -> f64 {
        self.extra[0] as f64
    }
}

/// Evaluates a batch of narrow-phase queries on the device with the kernels of
/// tumble-shaders' narrow-phase files (one invocation per query).
pub fn evaluate(shapes: &[Polyhedron], queries: &[ContactQuery]) -> Result<Vec<ContactAnswer>, crate::GpuError> {
    use wgpu::util::DeviceExt;
    let gpu = crate::context::gpu()?;
    let table = shape_table(shapes).map_err(|e| crate::GpuError::Feature(e.0))?;
    if queries.is_empty() {
        return Ok(Vec::new());
    }
    let device = &gpu.device;
    let source = crate::shaders::polyhedra_test_source();
    let start = std::time::Instant::now();
    let module =
        device.create_shader_module(wgpu::ShaderModuleDescriptor { label: Some("polyhedra test"), source: wgpu::ShaderSource::Wgsl(source.into()) });
    let pipeline = device.create_compute_pipeline(&wgpu::ComputePipelineDescriptor {
        label: Some("polyhedra test"),
        layout: None,
        module: &module,
        entry_point: Some("evaluate"),
        compilation_options: Default::default(),
        cache: None,
    });
    crate::kernels::record_compile("polyhedra test".into(), 1, start.elapsed());
    let usage = wgpu::BufferUsages::STORAGE | wgpu::BufferUsages::COPY_SRC | wgpu::BufferUsages::COPY_DST;
    let shapes_buf =
        device.create_buffer_init(&wgpu::util::BufferInitDescriptor { label: Some("shapes"), contents: bytemuck::cast_slice(&table), usage });
    let queries_buf =
        device.create_buffer_init(&wgpu::util::BufferInitDescriptor { label: Some("queries"), contents: bytemuck::cast_slice(queries), usage });
    let bytes = (queries.len() * std::mem::size_of::<ContactAnswer>()) as u64;
    let answers = device.create_buffer(&wgpu::BufferDescriptor { label: Some("answers"), size: bytes, usage, mapped_at_creation: false });
    let staging = device.create_buffer(&wgpu::BufferDescriptor {
        label: Some("answers readback"),
        size: bytes,
        usage: wgpu::BufferUsages::MAP_READ | wgpu::BufferUsages::COPY_DST,
        mapped_at_creation: false,
    });
    let count = device.create_buffer_init(&wgpu::util::BufferInitDescriptor {
        label: Some("query count"),
        contents: bytemuck::bytes_of(&[queries.len() as u32, 0, 0, 0]),
        usage: wgpu::BufferUsages::UNIFORM,
    });
    let bind = device.create_bind_group(&wgpu::BindGroupDescriptor {
        label: Some("polyhedra test"),
        layout: &pipeline.get_bind_group_layout(0),
        entries: &[
            wgpu::BindGroupEntry { binding: 0, resource: count.as_entire_binding() },
            wgpu::BindGroupEntry { binding: 1, resource: shapes_buf.as_entire_binding() },
            wgpu::BindGroupEntry { binding: 2, resource: queries_buf.as_entire_binding() },
            wgpu::BindGroupEntry { binding: 3, resource: answers.as_entire_binding() },
        ],
    });
    let mut encoder = device.create_command_encoder(&wgpu::CommandEncoderDescriptor { label: Some("polyhedra test") });
    {
        let mut pass = encoder.begin_compute_pass(&wgpu::ComputePassDescriptor { label: Some("polyhedra test"), timestamp_writes: None });
        pass.set_pipeline(&pipeline);
        pass.set_bind_group(0, &bind, &[]);
        pass.dispatch_workgroups((queries.len() as u32).div_ceil(tumble_shaders::WORKGROUP), 1, 1);
    }
    encoder.copy_buffer_to_buffer(&answers, 0, &staging, 0, bytes);
    gpu.queue.submit([encoder.finish()]);
    staging.slice(..).map_async(wgpu::MapMode::Read, |r| r.expect("mapping the answers"));
    device.poll(wgpu::PollType::Wait { submission_index: None, timeout: None }).map_err(|e| crate::GpuError::Device(e.to_string()))?;
    let view = staging.slice(..).get_mapped_range().expect("mapped answers");
    let out = bytemuck::pod_collect_to_vec::<u8, ContactAnswer>(&view);
    drop(view);
    staging.unmap();
    Ok(out)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn shapes_beyond_the_device_limits_are_refused() {
        // A 12-gon prism has 36 edges (1,296 pairs with itself), a 13-gon prism 39 (1,521).
        assert!(shape_table(&[Polyhedron::prism(12, 1.0, 1.0)]).is_ok());
        assert!(shape_table(&[Polyhedron::prism(13, 1.0, 1.0)]).unwrap_err().0.contains("edge pairs"));
        // 20-gon prism: 40 vertices.
        let many: Vec<glam::DVec3> = (0..40).map(|k| glam::DVec3::new((k as f64).cos(), (k as f64).sin(), (k % 3) as f64)).collect();
        assert!(shape_table(&[Polyhedron::from_points(&many).unwrap()]).unwrap_err().0.contains("vertices"));
        assert!(shape_table(&[Polyhedron::dodecahedron(1.0), Polyhedron::icosahedron(1.0)]).is_ok());
        // The volume model's polygon buffer: an icosahedron (20 faces) against 5-gons fits, a
        // 12-gon prism's ends (12 vertices) against its 14 faces do too, 30 faces do not.
        assert!(check_volume_limits(&[Polyhedron::dodecahedron(1.0), Polyhedron::icosahedron(1.0)]).is_ok());
        assert!(check_volume_limits(&[Polyhedron::prism(12, 1.0, 1.0)]).is_ok());
        // 20 points spread over a sphere hull into 36 triangles.
        let ball: Vec<glam::DVec3> = (0..20)
            .map(|k| {
                let z = 1.0 - (2 * k + 1) as f64 / 20.0;
                let phi = k as f64 * 2.399963;
                glam::DVec3::new((1.0 - z * z).sqrt() * phi.cos(), (1.0 - z * z).sqrt() * phi.sin(), z)
            })
            .collect();
        let big = Polyhedron::from_points(&ball).unwrap();
        assert_eq!(big.faces().len(), 36);
        assert!(check_volume_limits(&[big]).unwrap_err().0.contains("36 faces"));
    }

    #[test]
    fn the_volume_contacts_constants_are_tumble_geoms() {
        assert_eq!(tumble_shaders::CORNER_SMOOTHING as f64, tumble_geom::CORNER_SMOOTHING as f32 as f64);
        assert_eq!(tumble_shaders::CYLINDER_EDGE_POINTS as usize, tumble_geom::CYLINDER_EDGE_POINTS);
    }

    #[test]
    fn table_layout_of_a_cube_and_a_tetrahedron() {
        let shapes = [Polyhedron::cube(1.0), Polyhedron::tetrahedron(1.0)];
        let t = shape_table(&shapes).unwrap();
        for (s, p) in shapes.iter().enumerate() {
            let [vs, nv, fs, nf] = t[HEADER_WORDS * s].map(|x| x as usize);
            let [es, ne] = [t[HEADER_WORDS * s + 1][0] as usize, t[HEADER_WORDS * s + 1][1] as usize];
            assert_eq!((nv, nf, ne), (p.vertices().len(), p.faces().len(), p.edges().len()));
            assert!((t[HEADER_WORDS * s + 1][2] as f64 - p.bounding_radius()).abs() < 1e-6);
            // Inverse inertia of a body of density 2: (1 / m) · V / I_unit = 1 / (2 I_unit).
            let m = p.mass(2.0);
            for (k, inertia) in p.principal_inertia(2.0).to_array().into_iter().enumerate() {
                let inv = t[HEADER_WORDS * s + 2][k] as f64 / m;
                assert!((inv * inertia - 1.0).abs() < 1e-6);
            }
            assert!((4.0 / 3.0 * std::f64::consts::PI * (t[HEADER_WORDS * s + 2][3] as f64).powi(3) / p.volume() - 1.0).abs() < 1e-6);
            // The volume contact's references: the largest face and its corners.
            assert_eq!(
                t[HEADER_WORDS * s + 3][..3],
                [p.largest_face_area() as f32, if s == 0 { 4.0 } else { 3.0 }, p.face_perimeter(p.largest_face()) as f32]
            );
            for (k, v) in p.vertices().iter().enumerate() {
                assert_eq!(t[vs + k][..3], [v.x as f32, v.y as f32, v.z as f32]);
            }
            for (k, f) in p.faces().iter().enumerate() {
                assert_eq!(t[fs + 2 * k][3], f.offset as f32);
                let (start, len) = (t[fs + 2 * k + 1][0] as usize, t[fs + 2 * k + 1][1] as usize);
                let lp: Vec<u32> = (0..len).map(|j| t[(start + j) / 4][(start + j) % 4] as u32).collect();
                assert_eq!(lp, f.vertices);
            }
            for (k, e) in p.edges().iter().enumerate() {
                assert_eq!(t[es + k], [e.vertices[0], e.vertices[1], e.faces[0], e.faces[1]].map(|x| x as f32));
            }
        }
    }
}
