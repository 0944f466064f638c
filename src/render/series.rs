//! A run's snapshot series on disk (what `src/vtk/mod.rs` writes) and the picture of one snapshot.

use super::colour::{unit, viridis};
use super::gpu::{Line, Picture, Sphere, Triangle};
use super::vtp::{self, PolyData};
use glam::DVec3;
use std::collections::HashMap;
use std::path::{Path, PathBuf};
use std::sync::Arc;

/// Walls: a translucent blue-grey, their edges darker.
const WALL_COLOUR: [f32; 3] = [0.62, 0.68, 0.78];
const WALL_ALPHA: f32 = 0.3;
const EDGE_COLOUR: [f32; 3] = [0.3, 0.33, 0.4];

/// The files of a run's snapshots.
pub struct Series {
    dir: PathBuf,
    particles: Vec<(f64, String)>,
    bodies: Option<Vec<(f64, String)>>,
    moving_walls: Option<Vec<(f64, String)>>,
    static_walls: Option<Arc<PolyData>>,
}

/// One snapshot read back: particles (points), polyhedral bodies and walls (polygons).
pub struct Snapshot {
    /// The NNNNNN of `particles_NNNNNN.vtp`.
    pub index: usize,
    pub time: f64,
    pub file: PathBuf,
    pub particles: PolyData,
    pub bodies: Option<PolyData>,
    pub walls: Option<Arc<PolyData>>,
}

impl Series {
    pub fn open(dir: &Path) -> Result<Series, String> {
        let pvd = dir.join("particles.pvd");
        if !pvd.exists() {
            return Err(format!("{}: no particles.pvd here; run the scene with run.snapshot_interval set to write snapshots", dir.display()));
        }
        let particles = vtp::read_pvd(&pvd)?;
        if particles.is_empty() {
            return Err(format!("{}: lists no snapshots", pvd.display()));
        }
        let optional = |name: &str| -> Result<Option<Vec<(f64, String)>>, String> {
            let path = dir.join(name);
            if !path.exists() {
                return Ok(None);
            }
            let entries = vtp::read_pvd(&path)?;
            if entries.len() != particles.len() {
                return Err(format!("{}: {} snapshots, but particles.pvd lists {}", path.display(), entries.len(), particles.len()));
            }
            Ok(Some(entries))
        };
        let (bodies, moving_walls) = (optional("bodies.pvd")?, optional("walls.pvd")?);
        let walls_vtp = dir.join("walls.vtp");
        let static_walls = if moving_walls.is_none() && walls_vtp.exists() { Some(Arc::new(vtp::read(&walls_vtp)?)) } else { None };
        Ok(Series { dir: dir.to_path_buf(), particles, bodies, moving_walls, static_walls })
    }

    /// Whether the walls have a snapshot of their own at each time (`walls.pvd`).
    pub fn walls_move(&self) -> bool {
        self.moving_walls.is_some()
    }

    pub fn len(&self) -> usize {
        self.particles.len()
    }

    pub fn is_empty(&self) -> bool {
        self.particles.is_empty()
    }

    /// Snapshot `k` of the series (in .pvd order).
    pub fn load(&self, k: usize) -> Result<Snapshot, String> {
        let (time, name) = &self.particles[k];
        let file = self.dir.join(name);
        let particles = vtp::read(&file)?;
        let index = name.rsplit('_').next().and_then(|s| s.trim_end_matches(".vtp").parse().ok()).unwrap_or(k);
        let bodies = self.bodies.as_ref().map(|b| vtp::read(&self.dir.join(&b[k].1))).transpose()?;
        let walls = match &self.moving_walls {
            Some(w) => Some(Arc::new(vtp::read(&self.dir.join(&w[k].1))?)),
            None => self.static_walls.clone(),
        };
        if particles.point_array("radius").is_none() && !particles.points.is_empty() {
            return Err(format!("{}: no point array \"radius\"", file.display()));
        }
        Ok(Snapshot { index, time: *time, file, particles, bodies, walls })
    }
}

impl Snapshot {
    /// Fails, naming the arrays there are, when the particles carry no field `name`.
    pub fn check_field(&self, name: &str) -> Result<(), String> {
        if self.particles.points.is_empty() || self.field(name).is_some() {
            return Ok(());
        }
        let names: Vec<&str> = self.particles.point_data.iter().map(|a| a.name.as_str()).collect();
        Err(format!("{}: --color {name}: no such point array (valid: speed, {})", self.file.display(), names.join(", ")))
    }

    /// Each particle's value of field `name`: a scalar array, a vector's magnitude, or `speed` = |velocity|.
    pub fn field(&self, name: &str) -> Option<Vec<f64>> {
        let array = self.particles.point_array(name).or_else(|| if name == "speed" { self.particles.point_array("velocity") } else { None })?;
        Some((0..array.len()).map(|i| array.scalar(i)).collect())
    }

    /// The smallest and largest value of the field (infinite bounds when there are no particles).
    pub fn field_range(&self, name: &str) -> (f64, f64) {
        self.field(name)
            .unwrap_or_default()
            .iter()
            .filter(|v| v.is_finite())
            .fold((f64::INFINITY, f64::NEG_INFINITY), |(lo, hi), &v| (lo.min(v), hi.max(v)))
    }

    fn radii(&self) -> Vec<f64> {
        self.particles.point_array("radius").map(|a| a.values.clone()).unwrap_or_else(|| vec![0.0; self.particles.points.len()])
    }

    /// The box around the particles (centre ± radius) and the bodies' corners.
    pub fn particle_bounds(&self) -> (DVec3, DVec3) {
        let (mut lo, mut hi) = (DVec3::INFINITY, DVec3::NEG_INFINITY);
        for (p, r) in self.particles.points.iter().zip(self.radii()) {
            let p = DVec3::from_array(*p);
            (lo, hi) = (lo.min(p - r), hi.max(p + r));
        }
        for p in self.bodies.iter().flat_map(|b| &b.points) {
            (lo, hi) = (lo.min(DVec3::from_array(*p)), hi.max(DVec3::from_array(*p)));
        }
        (lo, hi)
    }

    /// Every wall polygon's corners.
    fn wall_polygons(&self) -> Vec<Vec<DVec3>> {
        let Some(walls) = &self.walls else { return Vec::new() };
        walls.polys.iter().map(|p| p.iter().map(|&i| DVec3::from_array(walls.points[i])).collect()).collect()
    }

    /// The box of each wall polygon.
    pub fn wall_boxes(&self) -> Vec<(DVec3, DVec3)> {
        self.wall_polygons().iter().map(|p| bounding_box(p)).collect()
    }

    /// The wall polygons drawn: all but those far larger than `scale` ([`bounded`]).
    fn walls(&self, scale: f64) -> Vec<Vec<DVec3>> {
        self.wall_polygons().into_iter().filter(|p| bounded(bounding_box(p), scale)).collect()
    }

    /// The picture: spheres and bodies coloured by `field` over `range`, the bounded walls
    /// translucent with their edges; `scale` is the size of the particles' region.
    pub fn picture(&self, field: &str, range: (f64, f64), scale: f64) -> Picture {
        let values = self.field(field).unwrap_or_else(|| vec![f64::NAN; self.particles.points.len()]);
        let colour = |i: usize| viridis(unit(values[i], range));
        let radii = self.radii();
        let shape = self.particles.point_array("shape");
        let as_body = |i: usize| self.bodies.is_some() && shape.is_some_and(|s| s.values[i] >= 0.0);
        let mut picture = Picture::default();
        for (i, p) in self.particles.points.iter().enumerate() {
            if !as_body(i) {
                picture.spheres.push(Sphere { centre: DVec3::from_array(*p), radius: radii[i], colour: colour(i) });
            }
        }
        if let Some(bodies) = &self.bodies {
            let by_id: HashMap<i64, usize> =
                self.particles.point_array("id").map(|a| a.values.iter().enumerate().map(|(i, &id)| (id as i64, i)).collect()).unwrap_or_default();
            let body_ids = bodies.cell_array("id");
            for (c, poly) in bodies.polys.iter().enumerate() {
                let particle = body_ids.and_then(|ids| by_id.get(&(ids.values[c] as i64)).copied());
                let colour = particle.map_or(viridis(f64::NAN), colour);
                fan(poly.iter().map(|&i| DVec3::from_array(bodies.points[i])).collect(), colour, 1.0, &mut picture);
            }
        }
        for poly in self.walls(scale) {
            for k in 0..poly.len() {
                picture.lines.push(Line { ends: [poly[k], poly[(k + 1) % poly.len()]], colour: EDGE_COLOUR });
            }
            fan(poly, WALL_COLOUR, WALL_ALPHA, &mut picture);
        }
        picture
    }
}

/// The triangles of a convex polygon, fanned from its first corner.
fn fan(poly: Vec<DVec3>, colour: [f32; 3], alpha: f32, picture: &mut Picture) {
    for k in 1..poly.len().saturating_sub(1) {
        picture.triangles.push(Triangle { corners: [poly[0], poly[k], poly[k + 1]], colour, alpha });
    }
}

fn bounding_box(points: &[DVec3]) -> (DVec3, DVec3) {
    points.iter().fold((DVec3::INFINITY, DVec3::NEG_INFINITY), |(lo, hi), &q| (lo.min(q), hi.max(q)))
}

/// Whether a wall polygon with box `(lo, hi)` is drawn and framed: not far larger than the
/// particles' region of size `scale` (vtk.rs writes each unbounded plane as a square twice the
/// domain's diagonal, which would fill any frame).
pub fn bounded((lo, hi): (DVec3, DVec3), scale: f64) -> bool {
    (hi - lo).length() <= 2.5 * scale
}
