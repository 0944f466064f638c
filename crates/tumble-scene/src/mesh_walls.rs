//! A `[[walls]] mesh` entry compiled: the file read, placed and checked, binned for the contact
//! search, and given its range of spring keys.

use crate::SceneError;
use crate::compile::{finite3, positive, unit};
use crate::mesh_file::{MeshPlacement, load_mesh};
use crate::schema::{MeshSection, Scene};
use glam::{DQuat, DVec3};
use tumble_geom::{MeshWall, SurfaceShape};

/// Spring keys of mesh triangles count up from 0 below this (tumble-state's `MESH_KEY` bit).
pub const MESH_TRIANGLES_AT_MOST: u32 = 1 << 30;

/// Wall `k`'s mesh, binned on cells of about `cell`; its triangles' spring keys start at
/// `first_key`. Returns the surface and the checks' warnings, each naming the wall.
pub(crate) fn mesh_wall(scene: &Scene, k: usize, m: &MeshSection, cell: f64, first_key: u32) -> Result<(SurfaceShape, Vec<String>), SceneError> {
    let (wall, warnings) = placed_mesh(scene, &format!("walls[{k}].mesh"), m, cell, first_key)?;
    Ok((SurfaceShape::Mesh(wall), warnings))
}

/// The mesh of section `field` read, placed and checked, binned on cells of about `cell`, its
/// triangles' spring keys from `first_key`; with the checks' warnings, each naming the section.
pub(crate) fn placed_mesh(scene: &Scene, field: &str, m: &MeshSection, cell: f64, first_key: u32) -> Result<(MeshWall, Vec<String>), SceneError> {
    let f = |x: &str| format!("{field}.{x}");
    let rotation = match &m.rotate {
        None => DQuat::IDENTITY,
        Some(r) => {
            if !r.degrees.is_finite() {
                return Err(SceneError::field(f("rotate.degrees"), format!("must be a finite angle, got {}", r.degrees)));
            }
            DQuat::from_axis_angle(unit(&f("rotate.axis"), r.axis)?, r.degrees.to_radians())
        }
    };
    let placement = MeshPlacement { scale: positive(&f("scale"), m.scale)?, rotation, translation: finite3(&f("translate"), m.translate)? };
    if !(m.curvature.is_finite() && (0.0..90.0).contains(&m.curvature)) {
        return Err(SceneError::field(f("curvature"), format!("must be an angle from 0 to 90 degrees, got {}", m.curvature)));
    }
    let path = match &scene.folder {
        Some(folder) => folder.join(&m.file),
        None => std::path::PathBuf::from(&m.file),
    };
    let (mesh, report) = load_mesh(&path, &placement, m.curvature.to_radians()).map_err(|e| SceneError::field(f("file"), e))?;
    if m.closed && report.open_edges > 0 {
        return Err(SceneError::field(
            f("closed"),
            format!("{}: {} open edges (a closed body or container has none); remove closed = true for a sheet", path.display(), report.open_edges),
        ));
    }
    let triangles = mesh.triangles.len() as u64;
    if first_key as u64 + triangles > MESH_TRIANGLES_AT_MOST as u64 {
        return Err(SceneError::field(f("file"), format!("the scene's meshes hold more than {MESH_TRIANGLES_AT_MOST} triangles")));
    }
    let warnings = report.warnings().into_iter().map(|w| format!("{field} ({}): {w}", path.display())).collect();
    Ok((MeshWall::new(mesh, cell, first_key), warnings))
}

/// The closed mesh of section `field` whose inside `what` fills (`the fluid`, `a source`),
/// read and placed as [`placed_mesh`] does; one with open edges is refused.
pub(crate) fn closed_mesh(scene: &Scene, field: &str, m: &MeshSection, cell: f64, what: &str) -> Result<MeshWall, SceneError> {
    let (wall, _) = placed_mesh(scene, field, m, cell, 0)?;
    let open = wall.body.mesh.across.iter().flatten().filter(|&&t| t == tumble_geom::OPEN).count();
    if open > 0 {
        return Err(SceneError::field(
            field,
            format!("{what} fills the inside of a closed mesh; this one has {open} open edges (close the surface in the CAD file)"),
        ));
    }
    Ok(wall)
}

/// The point of a mesh nearest to `x`, and its distance.
pub(crate) fn nearest_distance(m: &MeshWall, x: DVec3) -> f64 {
    (0..m.body.mesh.triangles.len()).map(|t| (tumble_geom::closest_point_on_triangle(x, m.corners(t)).0 - x).length()).fold(f64::INFINITY, f64::min)
}
