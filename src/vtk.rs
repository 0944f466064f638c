//! ParaView snapshots: `snapshots/particles_NNNNNN.vtp` (VTK XML PolyData, ASCII) and
//! `particles.pvd`, the time series that opens them all; `walls.vtp` when every wall is static,
//! else `snapshots/walls_NNNNNN.vtp` at each snapshot and `walls.pvd`.

use crate::{Simulation, State};
use std::fmt::Write as _;
use std::io;
use std::path::{Path, PathBuf};

/// Writes particle snapshots and keeps the .pvd collection current.
pub struct SnapshotWriter {
    out_dir: PathBuf,
    entries: Vec<(f64, String)>,
    moving_walls: bool,
    wall_entries: Vec<(f64, String)>,
    body_entries: Vec<(f64, String)>,
}

fn pvd(entries: &[(f64, String)]) -> String {
    let mut pvd = String::from("<?xml version=\"1.0\"?>\n<VTKFile type=\"Collection\" version=\"0.1\">\n  <Collection>\n");
    for (t, file) in entries {
        let _ = writeln!(pvd, "    <DataSet timestep=\"{t}\" part=\"0\" file=\"{file}\"/>");
    }
    pvd += "  </Collection>\n</VTKFile>\n";
    pvd
}

impl SnapshotWriter {
    /// Creates snapshots/ and, when the scene has walls and none moves, `walls.vtp`.
    pub fn create(out_dir: &Path, plan: &tumble_scene::Plan) -> io::Result<Self> {
        std::fs::create_dir_all(out_dir.join("snapshots"))?;
        let moving_walls = plan.model.walls.iter().any(|w| w.motion.is_some());
        if !plan.model.walls.is_empty() && !moving_walls {
            std::fs::write(out_dir.join("walls.vtp"), walls_vtp(plan, &plan.model.walls))?;
        }
        Ok(SnapshotWriter { out_dir: out_dir.to_path_buf(), entries: Vec::new(), moving_walls, wall_entries: Vec::new(), body_entries: Vec::new() })
    }

    /// Writes snapshot `index` of `state` (the run's particles at `time`) and rewrites the .pvd files.
    pub fn write(&mut self, index: usize, sim: &Simulation, time: f64, state: &State) -> io::Result<()> {
        let name = format!("snapshots/particles_{index:06}.vtp");
        std::fs::write(self.out_dir.join(&name), particles_vtp(state))?;
        self.entries.push((time, name));
        std::fs::write(self.out_dir.join("particles.pvd"), pvd(&self.entries))?;
        if sim.plan().model.polyhedra {
            let name = format!("snapshots/bodies_{index:06}.vtp");
            std::fs::write(self.out_dir.join(&name), bodies_vtp(sim.plan(), state))?;
            self.body_entries.push((time, name));
            std::fs::write(self.out_dir.join("bodies.pvd"), pvd(&self.body_entries))?;
        }
        if self.moving_walls {
            let name = format!("snapshots/walls_{index:06}.vtp");
            std::fs::write(self.out_dir.join(&name), walls_vtp(sim.plan(), &sim.walls()))?;
            self.wall_entries.push((time, name));
            std::fs::write(self.out_dir.join("walls.pvd"), pvd(&self.wall_entries))?;
        }
        Ok(())
    }
}

/// The polyhedral particles' surfaces as VTK XML PolyData polygons (sorted by id), with the
/// particle's id, group and speed as cell data: what ParaView shows as the bodies themselves.
pub fn bodies_vtp(plan: &tumble_scene::Plan, s: &State) -> String {
    let shapes = &plan.model.shapes;
    let mut order: Vec<usize> = (0..s.len()).filter(|&i| s.shape[i] != tumble_scene::SPHERE).collect();
    order.sort_by_key(|&i| s.id[i]);
    let (mut points, mut polys, mut cell_of) = (Vec::new(), Vec::new(), Vec::new());
    for &i in &order {
        let body = &shapes[s.shape[i] as usize].body;
        let base = points.len();
        points.extend(body.vertices().iter().map(|v| s.pos[i] + s.orient[i] * *v));
        for f in body.faces() {
            polys.push(f.vertices.iter().map(|&k| base + k as usize).collect());
            cell_of.push(i);
        }
    }
    polygons_vtp(&points, &polys, "id", |out| {
        array(out, "Int64", "id", 1, cell_of.iter().map(|&i| s.id[i].to_string()));
        array(out, "Int32", "group", 1, cell_of.iter().map(|&i| s.group[i].to_string()));
        array(out, "Float64", "speed", 1, cell_of.iter().map(|&i| s.vel[i].length().to_string()));
    })
}

/// VTK XML PolyData of polygons (each a list of indices into `points`), with the cell data
/// arrays `cells` writes (one value per polygon; `scalars` names the default one).
fn polygons_vtp(points: &[glam::DVec3], polys: &[Vec<usize>], scalars: &str, cells: impl FnOnce(&mut String)) -> String {
    let mut out = String::with_capacity(64 * points.len() + 1024);
    let _ = writeln!(out, "<?xml version=\"1.0\"?>");
    let _ = writeln!(out, "<VTKFile type=\"PolyData\" version=\"1.0\" byte_order=\"LittleEndian\" header_type=\"UInt64\">");
    let _ = writeln!(out, "  <PolyData>");
    let _ = writeln!(
        out,
        "    <Piece NumberOfPoints=\"{}\" NumberOfVerts=\"0\" NumberOfLines=\"0\" NumberOfStrips=\"0\" NumberOfPolys=\"{}\">",
        points.len(),
        polys.len()
    );
    let _ = writeln!(out, "      <CellData Scalars=\"{scalars}\">");
    cells(&mut out);
    let _ = writeln!(out, "      </CellData>");
    let _ = writeln!(out, "      <Points>");
    array(&mut out, "Float64", "position", 3, points.iter().flat_map(|p| p.to_array()).map(|v| v.to_string()));
    let _ = writeln!(out, "      </Points>");
    let _ = writeln!(out, "      <Polys>");
    array(&mut out, "Int64", "connectivity", 1, polys.iter().flatten().map(|i| i.to_string()));
    array(
        &mut out,
        "Int64",
        "offsets",
        1,
        polys.iter().scan(0, |n, p| {
            *n += p.len();
            Some(n.to_string())
        }),
    );
    let _ = writeln!(out, "      </Polys>");
    let _ = writeln!(out, "    </Piece>\n  </PolyData>\n</VTKFile>");
    out
}

/// The particles as VTK XML PolyData (one vertex per particle, sorted by id).
pub fn particles_vtp(s: &State) -> String {
    let mut order: Vec<usize> = (0..s.len()).collect();
    order.sort_by_key(|&i| s.id[i]);
    let n = order.len();
    let mut out = String::with_capacity(120 * n + 1024);
    let _ = writeln!(out, "<?xml version=\"1.0\"?>");
    let _ = writeln!(out, "<VTKFile type=\"PolyData\" version=\"1.0\" byte_order=\"LittleEndian\" header_type=\"UInt64\">");
    let _ = writeln!(out, "  <PolyData>");
    let _ = writeln!(out, "    <Piece NumberOfPoints=\"{n}\" NumberOfVerts=\"{n}\" NumberOfLines=\"0\" NumberOfStrips=\"0\" NumberOfPolys=\"0\">");
    let _ = writeln!(out, "      <PointData Scalars=\"radius\" Vectors=\"velocity\">");
    array(&mut out, "Float64", "radius", 1, order.iter().map(|&i| s.radius[i].to_string()));
    array(&mut out, "Float64", "velocity", 3, order.iter().flat_map(|&i| s.vel[i].to_array()).map(|v| v.to_string()));
    let omega = |i: usize| if s.omega.is_empty() { [0.0; 3] } else { s.omega[i].to_array() };
    array(&mut out, "Float64", "angular_velocity", 3, order.iter().flat_map(|&i| omega(i)).map(|v| v.to_string()));
    array(&mut out, "Int32", "material", 1, order.iter().map(|&i| s.material[i].to_string()));
    array(&mut out, "Int32", "group", 1, order.iter().map(|&i| s.group[i].to_string()));
    array(&mut out, "Int64", "id", 1, order.iter().map(|&i| s.id[i].to_string()));
    if !s.orient.is_empty() {
        array(
            &mut out,
            "Int32",
            "shape",
            1,
            order.iter().map(|&i| if s.shape[i] == tumble_scene::SPHERE { -1 } else { s.shape[i] as i32 }.to_string()),
        );
        array(
            &mut out,
            "Float64",
            "orientation",
            4,
            order.iter().flat_map(|&i| [s.orient[i].w, s.orient[i].x, s.orient[i].y, s.orient[i].z]).map(|v| v.to_string()),
        );
    }
    let _ = writeln!(out, "      </PointData>");
    let _ = writeln!(out, "      <Points>");
    array(&mut out, "Float64", "position", 3, order.iter().flat_map(|&i| s.pos[i].to_array()).map(|v| v.to_string()));
    let _ = writeln!(out, "      </Points>");
    let _ = writeln!(out, "      <Verts>");
    array(&mut out, "Int64", "connectivity", 1, (0..n).map(|k| k.to_string()));
    array(&mut out, "Int64", "offsets", 1, (1..=n).map(|k| k.to_string()));
    let _ = writeln!(out, "      </Verts>");
    let _ = writeln!(out, "    </Piece>\n  </PolyData>\n</VTKFile>");
    out
}

fn array(out: &mut String, ty: &str, name: &str, components: usize, values: impl Iterator<Item = String>) {
    let _ = write!(out, "        <DataArray type=\"{ty}\" Name=\"{name}\" NumberOfComponents=\"{components}\" format=\"ascii\">");
    for (k, v) in values.enumerate() {
        out.push_str(if k % (6 * components) == 0 { "\n          " } else { " " });
        out.push_str(&v);
    }
    out.push_str("\n        </DataArray>\n");
}

/// Walls (`plan.model.walls`, or the same walls in another pose) as VTK XML PolyData polygons: quads
/// as they are, planes as a square covering the domain, cylinders as 48 facets, lifters as their six faces.
pub fn walls_vtp(plan: &tumble_scene::Plan, walls: &[tumble_scene::Wall]) -> String {
    use tumble_geom::{DVec3, SurfaceShape};
    let mut points: Vec<DVec3> = Vec::new();
    let mut polys: Vec<Vec<usize>> = Vec::new();
    let mut wall_of_poly: Vec<usize> = Vec::new();
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
        }
    }
    polygons_vtp(&points, &polys, "wall", |out| {
        array(out, "Int32", "wall", 1, wall_of_poly.iter().map(|w| w.to_string()));
        array(out, "Int32", "material", 1, wall_of_poly.iter().map(|&w| walls[w].material.to_string()));
        array(out, "Int32", "group", 1, wall_of_poly.iter().map(|&w| walls[w].group.to_string()));
    })
}
