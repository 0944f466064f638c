//! ParaView snapshots: each phase's series as `snapshots/<series>_NNNNNN.vtp` (VTK XML
//! PolyData, in the scene's `output.snapshot_format`: appended binary by default, see
//! encoding.rs) and `<series>.pvd`, the time series that opens them all. The particles give
//! `particles`, `bodies` (polyhedra), `walls` (when one moves; else `walls.vtp` once) and, with
//! `output.contacts`, `contacts` (contacts.rs); the fluid gives `fluid`.

pub mod contacts;
pub mod encoding;

use crate::State;
pub use encoding::{Array, Cells, PolyData, Values, encode};
use std::fmt::Write as _;
use std::io;
use std::path::{Path, PathBuf};
use tumble_scene::schema::SnapshotFormat;

/// Writes particle snapshots and keeps the .pvd collections current.
pub struct SnapshotWriter {
    out_dir: PathBuf,
    format: SnapshotFormat,
    /// (series name, its entries): particles, bodies, walls, contacts.
    series: Vec<(String, Vec<(f64, String)>)>,
}

/// Each series' entries (time, file relative to the output folder), as a checkpoint keeps them.
pub type SeriesIndex = Vec<(String, Vec<(f64, String)>)>;

fn pvd(entries: &[(f64, String)]) -> String {
    let mut pvd = String::from("<?xml version=\"1.0\"?>\n<VTKFile type=\"Collection\" version=\"0.1\">\n  <Collection>\n");
    for (t, file) in entries {
        let _ = writeln!(pvd, "    <DataSet timestep=\"{t}\" part=\"0\" file=\"{file}\"/>");
    }
    pvd += "  </Collection>\n</VTKFile>\n";
    pvd
}

/// The walls go in a series, one file per snapshot, when one moves (a servo too) or a mesh carries loads.
pub(crate) fn wall_series(plan: &tumble_scene::Plan) -> bool {
    let servo = |w: &tumble_scene::Wall| plan.model.wall_groups[w.group as usize].servo.is_some();
    plan.model.walls.iter().any(|w| w.motion.is_some() || servo(w) || matches!(w.shape, tumble_geom::SurfaceShape::Mesh(_)))
}

/// Adds each polygon's Archard wear to `data` (the walls' polygons as [`walls_vtp`] lays them
/// out, its `wall` cell array naming each one's wall) as cell data: `wear_volume` (m³ since
/// t = 0) and `wear_depth` (m: the volume over the triangle's area), zero on polygons of walls
/// without wear; nothing when no wall wears.
pub(crate) fn add_wear(data: &mut PolyData, walls: &[tumble_scene::Wall], wear: &[Vec<f64>]) {
    if wear.iter().all(Vec::is_empty) {
        return;
    }
    let Some(Values::I32(wall_of_poly)) = data.cell_data.iter().find(|a| a.name == "wall").map(|a| a.values.clone()) else { return };
    let (mut volume, mut depth) = (Vec::new(), Vec::new());
    let mut k = 0;
    for (p, &w) in wall_of_poly.iter().enumerate() {
        // k: the polygon's index within its wall (a mesh's triangle).
        k = if p > 0 && wall_of_poly[p - 1] == w { k + 1 } else { 0 };
        let (w, mut v, mut d) = (w as usize, 0.0, 0.0);
        if let (Some(&worn), tumble_geom::SurfaceShape::Mesh(m)) = (wear.get(w).and_then(|t| t.get(k)), &walls[w].shape) {
            let c = m.corners(k);
            let area = 0.5 * (c[1] - c[0]).cross(c[2] - c[0]).length();
            (v, d) = (worn, if area > 0.0 { worn / area } else { 0.0 });
        }
        volume.push(v);
        depth.push(d);
    }
    data.cell_data.push(Array::f64("wear_volume", 1, volume));
    data.cell_data.push(Array::f64("wear_depth", 1, depth));
}

impl SnapshotWriter {
    /// Creates snapshots/ and the pieces written once (`fixed`: file in the output folder and
    /// piece; the static walls' `walls.vtp`).
    pub fn create(out_dir: &Path, format: SnapshotFormat, fixed: &[(String, PolyData)]) -> io::Result<Self> {
        std::fs::create_dir_all(out_dir.join("snapshots"))?;
        for (file, data) in fixed {
            std::fs::write(out_dir.join(file), encode(data, format))?;
        }
        Ok(SnapshotWriter { out_dir: out_dir.to_path_buf(), format, series: Vec::new() })
    }

    /// Continues the series of a resumed run: the .pvd files list `series` again, and snapshot
    /// files written after the checkpoint (the resumed run writes them anew) are removed.
    pub fn reopen(out_dir: &Path, format: SnapshotFormat, series: SeriesIndex) -> io::Result<Self> {
        std::fs::create_dir_all(out_dir.join("snapshots"))?;
        let kept: std::collections::HashSet<&str> = series.iter().flat_map(|(_, e)| e.iter().map(|(_, f)| f.as_str())).collect();
        for e in std::fs::read_dir(out_dir.join("snapshots"))? {
            let name = format!("snapshots/{}", e?.file_name().to_string_lossy());
            if !kept.contains(name.as_str()) {
                std::fs::remove_file(out_dir.join(&name))?;
            }
        }
        for (name, entries) in &series {
            std::fs::write(out_dir.join(format!("{name}.pvd")), pvd(entries))?;
        }
        Ok(SnapshotWriter { out_dir: out_dir.to_path_buf(), format, series })
    }

    /// Every series' entries so far.
    pub fn index(&self) -> &SeriesIndex {
        &self.series
    }

    /// Writes `data` as `snapshots/<series>_<index>.vtp` and rewrites `<series>.pvd`.
    pub fn add(&mut self, series: &str, index: usize, time: f64, data: &PolyData) -> io::Result<()> {
        let name = format!("snapshots/{series}_{index:06}.vtp");
        std::fs::write(self.out_dir.join(&name), encode(data, self.format))?;
        let k = match self.series.iter().position(|(s, _)| *s == series) {
            Some(k) => k,
            None => {
                self.series.push((series.to_string(), Vec::new()));
                self.series.len() - 1
            }
        };
        self.series[k].1.push((time, name));
        std::fs::write(self.out_dir.join(format!("{series}.pvd")), pvd(&self.series[k].1))
    }
}

/// The polyhedral particles' surfaces as VTK XML PolyData polygons (sorted by id), with the
/// particle's id, group and speed as cell data: what ParaView shows as the bodies themselves.
pub fn bodies_vtp(plan: &tumble_scene::Plan, s: &State) -> PolyData {
    let shapes = &plan.model.shapes;
    let mut order: Vec<usize> = (0..s.len()).filter(|&i| s.shape[i] != tumble_scene::SPHERE).collect();
    order.sort_by_key(|&i| s.id[i]);
    let (mut points, mut polys, mut cell_of) = (Vec::new(), Vec::new(), Vec::new());
    for &i in &order {
        let body = &shapes[s.shape[i] as usize].body;
        let base = points.len();
        points.extend(body.vertices().iter().map(|v| s.pos[i] + s.orient[i] * *v));
        for f in body.faces() {
            polys.push(f.vertices.iter().map(|&k| base + k as usize).collect::<Vec<_>>());
            cell_of.push(i);
        }
    }
    PolyData {
        points: points.iter().flat_map(|p| p.to_array()).collect(),
        polys: Cells::of(polys),
        cell_data: vec![
            Array::i64("id", cell_of.iter().map(|&i| s.id[i] as i64).collect()),
            Array::i32("group", cell_of.iter().map(|&i| s.group[i] as i32).collect()),
            Array::f64("speed", 1, cell_of.iter().map(|&i| s.vel[i].length()).collect()),
        ],
        cell_attributes: (Some("id".into()), None),
        ..Default::default()
    }
}

/// Force on movable particle `i` at the last force pass: m (a − g), the contact forces plus
/// explicit drag; zero for fixed particles (their acceleration is not kept).
pub fn particle_force(s: &State, i: usize, gravity: glam::DVec3) -> glam::DVec3 {
    if s.inv_mass[i] == 0.0 { glam::DVec3::ZERO } else { s.mass[i] * (s.acc[i] - gravity) }
}

/// Torque about the centre of movable particle `i` at the last force pass, from its angular
/// acceleration: I α (world-frame R I Rᵀ α for polyhedra); zero without rotation and for fixed bodies.
pub fn particle_torque(s: &State, i: usize) -> glam::DVec3 {
    if s.alpha.is_empty() || s.inv_inertia[i] == 0.0 {
        return glam::DVec3::ZERO;
    }
    if s.orient.is_empty() {
        return s.alpha[i] / s.inv_inertia[i];
    }
    let q = s.orient[i];
    q * ((q.inverse() * s.alpha[i]) / s.inv_inertia_body[i])
}

/// The particles as VTK XML PolyData (one vertex per particle, sorted by id).
pub fn particles_vtp(s: &State, gravity: glam::DVec3) -> PolyData {
    let mut order: Vec<usize> = (0..s.len()).collect();
    order.sort_by_key(|&i| s.id[i]);
    let n = order.len();
    let vectors = |f: &dyn Fn(usize) -> [f64; 3]| order.iter().flat_map(|&i| f(i)).collect::<Vec<f64>>();
    let omega = |i: usize| if s.omega.is_empty() { [0.0; 3] } else { s.omega[i].to_array() };
    let mut point_data = vec![
        Array::f64("radius", 1, order.iter().map(|&i| s.radius[i]).collect()),
        Array::f64("velocity", 3, vectors(&|i| s.vel[i].to_array())),
        Array::f64("angular_velocity", 3, vectors(&omega)),
        Array::f64("force", 3, vectors(&|i| particle_force(s, i, gravity).to_array())),
        Array::f64("torque", 3, vectors(&|i| particle_torque(s, i).to_array())),
        Array::i32("material", order.iter().map(|&i| s.material[i] as i32).collect()),
        Array::i32("group", order.iter().map(|&i| s.group[i] as i32).collect()),
        Array::i64("id", order.iter().map(|&i| s.id[i] as i64).collect()),
    ];
    if !s.orient.is_empty() {
        point_data
            .push(Array::i32("shape", order.iter().map(|&i| if s.shape[i] == tumble_scene::SPHERE { -1 } else { s.shape[i] as i32 }).collect()));
        point_data.push(Array::f64(
            "orientation",
            4,
            order.iter().flat_map(|&i| [s.orient[i].w, s.orient[i].x, s.orient[i].y, s.orient[i].z]).collect(),
        ));
    }
    PolyData {
        points: vectors(&|i| s.pos[i].to_array()),
        verts: Cells::of((0..n).map(|k| [k])),
        point_data,
        point_attributes: (Some("radius".into()), Some("velocity".into())),
        ..Default::default()
    }
}

/// Walls (`plan.model.walls`, or the same walls in another pose) as VTK XML PolyData polygons: quads
/// as they are, planes as a square covering the domain, cylinders as 48 facets, lifters as their
/// six faces, meshes as their triangles. `mesh_loads` (per wall, per triangle: the particles'
/// force on it, as `tumble_cpu::network::mesh_loads` gives) adds each triangle's load as cell data.
pub fn walls_vtp(plan: &tumble_scene::Plan, walls: &[tumble_scene::Wall], mesh_loads: Option<&[Vec<tumble_geom::DVec3>]>) -> PolyData {
    use tumble_geom::{DVec3, SurfaceShape};
    let mut points: Vec<DVec3> = Vec::new();
    let mut polys: Vec<Vec<usize>> = Vec::new();
    let mut wall_of_poly: Vec<usize> = Vec::new();
    // Per polygon: the force on it and its normal and area (zero off meshes).
    let mut load_of_poly: Vec<(DVec3, DVec3, f64)> = Vec::new();
    let centre = 0.5 * (plan.model.domain.min + plan.model.domain.max);
    let size = plan.model.domain.extent().length();
    for (w, wall) in walls.iter().enumerate() {
        let mut quad = |corners: [DVec3; 4]| {
            polys.push((points.len()..points.len() + 4).collect());
            points.extend(corners);
            wall_of_poly.push(w);
        };
        match &wall.shape {
            SurfaceShape::Quad(q) => quad(q.corners),
            SurfaceShape::Plane(p) => {
                let foot = centre - p.normal * p.signed_distance(centre);
                let u = p.normal.any_orthonormal_vector() * size;
                let v = p.normal.cross(u);
                quad([foot - u - v, foot + u - v, foot + u + v, foot - u + v]);
            }
            SurfaceShape::Cylinder(c) => {
                let (u, v) = c.axis.any_orthonormal_pair();
                let ring = |k: usize, s: f64| {
                    let phi = std::f64::consts::TAU * k as f64 / 48.0;
                    c.point + c.axis * s + (u * phi.cos() + v * phi.sin()) * c.radius
                };
                for k in 0..48 {
                    quad([ring(k, 0.0), ring(k + 1, 0.0), ring(k + 1, c.length), ring(k, c.length)]);
                }
            }
            SurfaceShape::Prism(p) => p.corners().for_each(&mut quad),
            SurfaceShape::Mesh(m) => {
                for t in 0..m.body.mesh.triangles.len() {
                    load_of_poly.resize(polys.len(), (DVec3::ZERO, DVec3::ZERO, 0.0));
                    let c = m.corners(t);
                    let area = 0.5 * (c[1] - c[0]).cross(c[2] - c[0]);
                    let force = mesh_loads.and_then(|l| l.get(w)).and_then(|l| l.get(t)).copied().unwrap_or(DVec3::ZERO);
                    load_of_poly.push((force, area.normalize_or_zero(), area.length()));
                    polys.push((points.len()..points.len() + 3).collect());
                    points.extend(c);
                    wall_of_poly.push(w);
                }
            }
        }
    }
    let mut cell_data = vec![
        Array::i32("wall", wall_of_poly.iter().map(|&w| w as i32).collect()),
        Array::i32("material", wall_of_poly.iter().map(|&w| walls[w].material as i32).collect()),
        Array::i32("group", wall_of_poly.iter().map(|&w| walls[w].group as i32).collect()),
    ];
    if mesh_loads.is_some() && !load_of_poly.is_empty() {
        load_of_poly.resize(polys.len(), (DVec3::ZERO, DVec3::ZERO, 0.0));
        // Pressing into the wall is positive: the load against the normal the particles see.
        let normal = |&(f, n, _): &(DVec3, DVec3, f64)| -f.dot(n);
        let shear = |&(f, n, _): &(DVec3, DVec3, f64)| (f - n * f.dot(n)).length();
        let per_area = |v: f64, a: f64| if a > 0.0 { v / a } else { 0.0 };
        cell_data.push(Array::f64("force", 3, load_of_poly.iter().flat_map(|l| l.0.to_array()).collect()));
        cell_data.push(Array::f64("normal_force", 1, load_of_poly.iter().map(normal).collect()));
        cell_data.push(Array::f64("shear_force", 1, load_of_poly.iter().map(shear).collect()));
        cell_data.push(Array::f64("pressure", 1, load_of_poly.iter().map(|l| per_area(normal(l), l.2)).collect()));
        cell_data.push(Array::f64("shear_stress", 1, load_of_poly.iter().map(|l| per_area(shear(l), l.2)).collect()));
    }
    PolyData {
        points: points.iter().flat_map(|p| p.to_array()).collect(),
        polys: Cells::of(polys),
        cell_data,
        cell_attributes: (Some("wall".into()), None),
        ..Default::default()
    }
}
