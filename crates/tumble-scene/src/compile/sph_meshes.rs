//! Meshes in the fluid's scene: a `[[walls]] mesh` as dummy wall particles behind its surface,
//! lifter bars as the closed meshes of their prisms, and a `[[sph.regions]] mesh`, the inside of
//! a closed mesh filled with fluid.
//!
//! Both use the fluid's global lattice, points at (i + ½) Δp from the origin on every axis (in
//! 2D the x–z plane at y = 0), so a mesh face on a multiple of Δp gets its layers at ½ Δp, 1½ Δp, …
//! behind it, as an analytic wall there does, and fluid filled from a box whose sides lie on
//! multiples of Δp meets it at the same distance.

use super::sph::check_total;
use crate::SceneError;
use crate::mesh_walls::closed_mesh;
use crate::plan::Wall;
use crate::schema::{MeshSection, Scene};
use glam::DVec3;
use std::collections::HashSet;
use std::ops::RangeInclusive;
use tumble_geom::{MeshWall, SurfaceShape, TriangleMesh};
use tumble_sph::{Aabb, Dimension, FluidParticles, FluidSettings, add_fluid_points, push_walls, wall_layers};

/// A mesh the fluid keeps off: a closed one (a body or a container) has a fluid side and a solid
/// side everywhere; a sheet only near its surface.
pub(super) struct FluidMesh {
    wall: MeshWall,
    closed: bool,
}

impl FluidMesh {
    /// Whether fluid may start at `x`: on the side the normals point to, at least half a spacing
    /// from the surface (`thickness` is the wall layers' depth, how far behind a sheet reaches).
    pub(super) fn leaves_fluid_at(&self, x: DVec3, spacing: f64, thickness: f64) -> bool {
        let d = if self.closed { Some(self.wall.signed_distance_anywhere(x)) } else { self.wall.signed_distance(x, thickness) };
        // Fluid exactly half a spacing off the surface (a box region filled up to the wall) stays,
        // whatever the round-off of its distance.
        d.is_none_or(|d| d >= (0.5 - 1e-9) * spacing)
    }
}

/// Indices i of the lattice points (i + ½) Δp from `lo` to `hi`.
fn indices(lo: f64, hi: f64, dp: f64) -> RangeInclusive<i64> {
    ((lo / dp - 0.5).ceil() as i64)..=((hi / dp - 0.5).floor() as i64)
}

/// The lattice points in the box `lo`–`hi`, as index triples (z, y, x), and how many there are.
fn box_indices(lo: DVec3, hi: DVec3, dp: f64, dimension: Dimension) -> ([RangeInclusive<i64>; 3], f64) {
    let mut ranges = [0, 1, 2].map(|a| indices(lo[a], hi[a], dp));
    if dimension == Dimension::Two {
        // The plane y = 0 is a lattice line of its own.
        let mut plane = 0..=0;
        if !(lo.y <= 0.0 && hi.y >= 0.0) {
            plane.next();
        }
        ranges[1] = plane;
    }
    let count = ranges.iter().map(|r| if r.is_empty() { 0.0 } else { (r.end() - r.start() + 1) as f64 }).product();
    (ranges, count)
}

fn lattice_point([i, j, k]: [i64; 3], dp: f64, dimension: Dimension) -> DVec3 {
    let y = if dimension == Dimension::Two { 0.0 } else { (j as f64 + 0.5) * dp };
    DVec3::new((i as f64 + 0.5) * dp, y, (k as f64 + 0.5) * dp)
}

/// Wall `k`'s mesh (as the particles' walls compiled it, among `walls`) as dummy particles:
/// every lattice point behind its surface (against the normals) no deeper than the wall layers'
/// thickness, inside the fluid's grid. The fluid is on the side the normals point to: outward
/// for a body standing in it, inward for a container.
pub(super) fn add_mesh_wall(k: usize, walls: &[Wall], settings: &FluidSettings, particles: &mut FluidParticles) -> Result<FluidMesh, SceneError> {
    let compiled = walls
        .iter()
        .find_map(|c| match &c.shape {
            SurfaceShape::Mesh(m) if c.group as usize == k => Some(m),
            _ => None,
        })
        .expect("the particles' walls compile every mesh wall");
    // Binned again on the fluid's scale, in the same pose.
    let binned = MeshWall::new(compiled.body.mesh.clone(), 2.0 * settings.h, 0);
    let wall = MeshWall { body: binned.body, rotation: compiled.rotation, translation: compiled.translation };
    add_layers(&format!("walls[{k}].mesh"), wall, settings, particles)
}

/// Wall `k`'s lifter bars (its compiled prisms) as closed meshes of dummy particles.
pub(super) fn add_lifters(k: usize, bars: &[&Wall], settings: &FluidSettings, particles: &mut FluidParticles) -> Result<Vec<FluidMesh>, SceneError> {
    let mut meshes = Vec::new();
    for (r, bar) in bars.iter().enumerate() {
        let SurfaceShape::Prism(prism) = &bar.shape else { continue };
        let field = format!("walls[{k}].lifters (bar {r})");
        // Each outward quad face as two triangles; corners welded by the mesh.
        let vertices: Vec<DVec3> = prism.faces.iter().flat_map(|q| q.corners).collect();
        let triangles: Vec<[u32; 3]> = (0..6u32).flat_map(|f| [[4 * f, 4 * f + 1, 4 * f + 2], [4 * f, 4 * f + 2, 4 * f + 3]]).collect();
        let mesh = TriangleMesh::new(&vertices, &triangles, tumble_geom::DEFAULT_CURVATURE)
            .map_err(|e| SceneError::field(field.clone(), format!("its bar is not a solid: {e}")))?
            .0;
        meshes.push(add_layers(&field, MeshWall::new(mesh, 2.0 * settings.h, 0), settings, particles)?);
    }
    Ok(meshes)
}

/// `wall`'s dummy particles: every lattice point behind its surface (against the normals) no
/// deeper than the wall layers' thickness, inside the fluid's grid; `field` names it in errors.
fn add_layers(field: &str, wall: MeshWall, settings: &FluidSettings, particles: &mut FluidParticles) -> Result<FluidMesh, SceneError> {
    let (dp, dimension) = (settings.spacing, settings.dimension);
    let thickness = wall_layers(settings) as f64 * dp;
    let grid = settings.domain;
    // Each triangle's box widened by the layers' depth, cut to the grid: the points to test.
    let boxes: Vec<([RangeInclusive<i64>; 3], f64)> = (0..wall.body.mesh.triangles.len())
        .map(|t| {
            let c = wall.corners(t);
            let lo = (c[0].min(c[1]).min(c[2]) - DVec3::splat(thickness)).max(grid.min);
            let hi = (c[0].max(c[1]).max(c[2]) + DVec3::splat(thickness)).min(grid.max);
            box_indices(lo, hi, dp, dimension)
        })
        .collect();
    check_total(field, boxes.iter().map(|b| b.1).sum())?;
    let mut sites: HashSet<[i64; 3]> = HashSet::new();
    for (ranges, _) in &boxes {
        for kz in ranges[2].clone() {
            for jy in ranges[1].clone() {
                for ix in ranges[0].clone() {
                    sites.insert([kz, jy, ix]);
                }
            }
        }
    }
    let mut sites: Vec<[i64; 3]> = sites.into_iter().collect();
    sites.sort_unstable();
    let points: Vec<DVec3> = sites
        .into_iter()
        .map(|[kz, jy, ix]| lattice_point([ix, jy, kz], dp, dimension))
        .filter(|&x| wall.signed_distance(x, thickness).is_some_and(|d| d < 0.0 && d >= -thickness))
        .collect();
    if points.is_empty() {
        let why = if dimension == Dimension::Two { "; a 2D fluid lies in the plane y = 0, which the mesh must cross" } else { "" };
        return Err(SceneError::field(
            field,
            format!("gives the fluid no wall particles: no lattice point lies behind its surface inside the fluid's grid{why}"),
        ));
    }
    push_walls(particles, settings, points, DVec3::ZERO);
    let closed = !wall.body.mesh.two_sided;
    Ok(FluidMesh { wall, closed })
}

/// Fills the inside of the closed mesh of `sph.regions[k]` (with `clip`, only the part inside
/// that box) with fluid at rest in hydrostatic balance, moving at `velocity`; returns how many
/// particles it added. The inside is where the mesh encloses, whichever way its normals point.
#[allow(clippy::too_many_arguments)]
pub(super) fn fill_mesh_region(
    scene: &Scene,
    k: usize,
    m: &MeshSection,
    clip: Option<Aabb>,
    settings: &FluidSettings,
    domain: &tumble_geom::PeriodicBox,
    velocity: DVec3,
    particles: &mut FluidParticles,
) -> Result<usize, SceneError> {
    let field = format!("sph.regions[{k}].mesh");
    let wall = closed_mesh(scene, &field, m, 2.0 * settings.h, "the fluid")?;
    let (dp, dimension) = (settings.spacing, settings.dimension);
    let (mut lo, mut hi) = wall.bounds();
    (lo, hi) = (lo.max(domain.min), hi.min(domain.max));
    if let Some(b) = clip {
        (lo, hi) = (lo.max(b.min), hi.min(b.max));
    }
    let (ranges, count) = box_indices(lo, hi, dp, dimension);
    check_total(&field, count)?;
    // Normals outward enclose a positive volume: the inside is behind them.
    let inward = if wall.enclosed_volume() > 0.0 { 1.0 } else { -1.0 };
    let volume = dp.powi(dimension.count());
    let mut points = Vec::new();
    for kz in ranges[2].clone() {
        for jy in ranges[1].clone() {
            for ix in ranges[0].clone() {
                let x = lattice_point([ix, jy, kz], dp, dimension);
                if inward * wall.signed_distance_anywhere(x) < 0.0 && clip.is_none_or(|b| in_box(&b, x, dimension)) {
                    points.push((x, volume));
                }
            }
        }
    }
    Ok(add_fluid_points(particles, settings, &points, velocity))
}

/// Whether `x` lies in `b` (half-open); a 2D fluid's box has no extent in y.
fn in_box(b: &Aabb, x: DVec3, dimension: Dimension) -> bool {
    (0..3).all(|a| (dimension == Dimension::Two && a == 1) || (x[a] >= b.min[a] && x[a] < b.max[a]))
}
