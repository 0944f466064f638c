//! Triangle meshes from CAD files: binary and ASCII STL (read by `stl_io`) and OBJ (read by
//! `tobj`, polygons triangulated), scaled, rotated and moved into place, then welded and checked
//! by [`TriangleMesh::new`].

use glam::{DQuat, DVec3};
use std::path::Path;
use tumble_geom::{MeshReport, TriangleMesh};

/// Where a mesh file's coordinates go: x ↦ rotation (scale x) + translation.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct MeshPlacement {
    /// File units to metres (0.001 for a file in millimetres); positive.
    pub scale: f64,
    pub rotation: DQuat,
    pub translation: DVec3,
}

impl Default for MeshPlacement {
    fn default() -> Self {
        MeshPlacement { scale: 1.0, rotation: DQuat::IDENTITY, translation: DVec3::ZERO }
    }
}

impl MeshPlacement {
    #[inline]
    pub fn apply(&self, x: DVec3) -> DVec3 {
        self.rotation * (x * self.scale) + self.translation
    }
}

/// The vertices and triangles of an STL or OBJ file (by its extension), as the file has them.
pub fn read_triangles(path: &Path) -> Result<(Vec<DVec3>, Vec<[u32; 3]>), String> {
    let shown = path.display();
    let extension = path.extension().and_then(|e| e.to_str()).map(str::to_ascii_lowercase);
    match extension.as_deref() {
        Some("stl") => {
            let mut file = std::fs::File::open(path).map_err(|e| format!("{shown}: cannot be read: {e}"))?;
            let mesh = stl_io::read_stl(&mut file).map_err(|e| format!("{shown}: not a readable STL file (binary or ASCII): {e}"))?;
            let vertices = mesh.vertices.iter().map(|v| DVec3::new(v.0[0] as f64, v.0[1] as f64, v.0[2] as f64)).collect();
            let triangles = mesh.faces.iter().map(|f| f.vertices.map(|k| k as u32)).collect();
            Ok((vertices, triangles))
        }
        Some("obj") => {
            let options = tobj::LoadOptions { triangulate: true, single_index: true, ignore_points: true, ignore_lines: true };
            let (models, _) = tobj::load_obj(path, &options).map_err(|e| format!("{shown}: not a readable OBJ file: {e}"))?;
            let mut vertices = Vec::new();
            let mut triangles = Vec::new();
            for model in models {
                let base = vertices.len() as u32;
                vertices.extend(model.mesh.positions.chunks_exact(3).map(|p| DVec3::new(p[0], p[1], p[2])));
                triangles.extend(model.mesh.indices.chunks_exact(3).map(|t| [base + t[0], base + t[1], base + t[2]]));
            }
            Ok((vertices, triangles))
        }
        _ => Err(format!("{shown}: a mesh file must be STL (.stl, binary or ASCII) or OBJ (.obj)")),
    }
}

/// A mesh file placed and checked: the mesh, what the checks found, and the lines to warn with.
pub fn load_mesh(path: &Path, placement: &MeshPlacement, curvature: f64) -> Result<(TriangleMesh, MeshReport), String> {
    if !(placement.scale > 0.0 && placement.scale.is_finite()) {
        return Err(format!("{}: scale must be a positive number, got {}", path.display(), placement.scale));
    }
    let (vertices, triangles) = read_triangles(path)?;
    let placed: Vec<DVec3> = vertices.iter().map(|&v| placement.apply(v)).collect();
    if let Some(v) = placed.iter().find(|v| !v.is_finite()) {
        return Err(format!("{}: a vertex is not a finite number ({v})", path.display()));
    }
    TriangleMesh::new(&placed, &triangles, curvature).map_err(|e| format!("{}: {e}", path.display()))
}

#[cfg(test)]
mod tests {
    use super::*;
    use tumble_geom::{DEFAULT_CURVATURE, box_triangles};

    fn dir(name: &str) -> std::path::PathBuf {
        let d = std::env::temp_dir().join(format!("tumble-mesh-file-{name}-{}", std::process::id()));
        std::fs::create_dir_all(&d).unwrap();
        d
    }

    /// The unit box of 12 triangles as STL triangles (each with its own corners, as files have them).
    fn box_stl() -> Vec<stl_io::Triangle> {
        let (v, t) = box_triangles(DVec3::ZERO, DVec3::ONE);
        t.iter()
            .map(|tri| {
                let c = tri.map(|k| v[k as usize]);
                let n = (c[1] - c[0]).cross(c[2] - c[0]).normalize();
                let f = |x: DVec3| stl_io::Vertex::new([x.x as f32, x.y as f32, x.z as f32]);
                stl_io::Triangle { normal: f(n), vertices: c.map(f) }
            })
            .collect()
    }

    #[test]
    fn a_box_reads_the_same_from_binary_stl_ascii_stl_and_obj_in_millimetres() {
        let d = dir("formats");
        let binary = d.join("box.stl");
        stl_io::write_stl(&mut std::fs::File::create(&binary).unwrap(), box_stl().iter()).unwrap();
        let mut ascii = String::from("solid box\n");
        for t in box_stl() {
            ascii += &format!("facet normal {} {} {}\n outer loop\n", t.normal.0[0], t.normal.0[1], t.normal.0[2]);
            for v in t.vertices {
                ascii += &format!("  vertex {} {} {}\n", v.0[0] * 1000.0, v.0[1] * 1000.0, v.0[2] * 1000.0);
            }
            ascii += " endloop\nendfacet\n";
        }
        ascii += "endsolid box\n";
        std::fs::write(d.join("box_mm.STL"), ascii).unwrap();
        // OBJ: the six faces as quads (triangulated on reading), 1-based indices, millimetres.
        let obj = "v 0 0 0\nv 1000 0 0\nv 1000 1000 0\nv 0 1000 0\nv 0 0 1000\nv 1000 0 1000\nv 1000 1000 1000\nv 0 1000 1000\n\
                   f 1 4 3 2\nf 5 6 7 8\nf 1 2 6 5\nf 2 3 7 6\nf 3 4 8 7\nf 4 1 5 8\n";
        std::fs::write(d.join("box.obj"), obj).unwrap();
        let shift = MeshPlacement { translation: DVec3::new(0.0, 0.0, 2.0), ..Default::default() };
        let mm = MeshPlacement { scale: 0.001, ..shift };
        for (file, placement) in [("box.stl", shift), ("box_mm.STL", mm), ("box.obj", mm)] {
            let (mesh, report) = load_mesh(&d.join(file), &placement, DEFAULT_CURVATURE).unwrap();
            assert_eq!((mesh.vertices.len(), mesh.triangles.len()), (8, 12), "{file}");
            assert!(mesh.is_closed() && !mesh.two_sided, "{file}");
            assert_eq!((report.open_edges, report.inconsistent_edges, report.degenerate), (0, 0, 0), "{file}");
            // Outward normals, and the box where the placement puts it.
            let centre = DVec3::new(0.5, 0.5, 2.5);
            for t in 0..12 {
                let c = mesh.corners(t);
                assert!(c.iter().all(|x| (x.z - 2.0) >= -1e-9 && (x.z - 3.0) <= 1e-9), "{file}: {c:?}");
                assert!(mesh.normals[t].dot(c.iter().sum::<DVec3>() / 3.0 - centre) > 0.0, "{file}: triangle {t} faces inward");
            }
        }
        std::fs::remove_dir_all(d).unwrap();
    }

    #[test]
    fn bad_files_are_refused_in_one_line_that_names_them() {
        let d = dir("bad");
        let cases = [
            ("missing.stl", None, "cannot be read"),
            ("box.step", Some("solid"), "must be STL (.stl, binary or ASCII) or OBJ (.obj)"),
            ("garbage.stl", Some("solid x\nfacet normal 0 0 1\n outer loop\n vertex 0 0\n"), "not a readable STL file"),
            ("flat.obj", Some("v 0 0 0\nv 1 0 0\nv 2 0 0\nf 1 2 3\n"), "no triangles with an area"),
            ("twice.obj", Some("v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 3\nf 2 3 1\n"), "triangles 0 and 1 have the same three corners"),
        ];
        for (name, text, expected) in cases {
            let path = d.join(name);
            if let Some(t) = text {
                std::fs::write(&path, t).unwrap();
            }
            let e = load_mesh(&path, &MeshPlacement::default(), DEFAULT_CURVATURE).unwrap_err();
            assert!(e.contains(expected) && e.contains(name) && !e.contains('\n'), "{name}: {e}");
        }
        let e = load_mesh(&d.join("x.stl"), &MeshPlacement { scale: 0.0, ..Default::default() }, DEFAULT_CURVATURE).unwrap_err();
        assert!(e.contains("scale must be a positive number"), "{e}");
        std::fs::remove_dir_all(d).unwrap();
    }
}
