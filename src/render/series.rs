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
    /// The particles' snapshots; none for a scene of fluid alone.
    particles: Option<Vec<(f64, String)>>,
    /// The SPH fluid's snapshots (`fluid.pvd`), when the scene has one.
    fluid: Option<Vec<(f64, String)>>,
    bodies: Option<Vec<(f64, String)>>,
    moving_walls: Option<Vec<(f64, String)>>,
    static_walls: Option<Arc<PolyData>>,
}

/// One snapshot read back: particles and fluid (points), polyhedral bodies and walls (polygons).
pub struct Snapshot {
    /// The NNNNNN of `particles_NNNNNN.vtp` (or `fluid_NNNNNN.vtp`).
    pub index: usize,
    pub time: f64,
    pub file: PathBuf,
    /// The particles (empty for a scene of fluid alone).
    pub particles: PolyData,
    /// The SPH fluid's particles: fluid (`kind` 0) and wall particles (`kind` 1).
    pub fluid: Option<PolyData>,
    pub bodies: Option<PolyData>,
    pub walls: Option<Arc<PolyData>>,
}

impl Series {
    pub fn open(dir: &Path) -> Result<Series, String> {
        let read = |name: &str| -> Result<Option<Vec<(f64, String)>>, String> {
            let path = dir.join(name);
            if !path.exists() {
                return Ok(None);
            }
            let entries = vtp::read_pvd(&path)?;
            if entries.is_empty() {
                return Err(format!("{}: lists no snapshots", path.display()));
            }
            Ok(Some(entries))
        };
        let (particles, fluid) = (read("particles.pvd")?, read("fluid.pvd")?);
        // The series every other one must match: the particles', or the fluid's without particles.
        let (lead, count) = match (&particles, &fluid) {
            (Some(p), _) => ("particles.pvd", p.len()),
            (None, Some(f)) => ("fluid.pvd", f.len()),
            (None, None) => {
                return Err(format!(
                    "{}: no particles.pvd or fluid.pvd here; run the scene with run.snapshot_interval set to write snapshots",
                    dir.display()
                ));
            }
        };
        let matching = |name: &str| -> Result<Option<Vec<(f64, String)>>, String> {
            let entries = read(name)?;
            match &entries {
                Some(e) if e.len() != count => Err(format!("{}: {} snapshots, but {lead} lists {count}", dir.join(name).display(), e.len())),
                _ => Ok(entries),
            }
        };
        let fluid = if particles.is_some() { matching("fluid.pvd")? } else { fluid };
        let (bodies, moving_walls) = (matching("bodies.pvd")?, matching("walls.pvd")?);
        let walls_vtp = dir.join("walls.vtp");
        let static_walls = if moving_walls.is_none() && walls_vtp.exists() { Some(Arc::new(vtp::read(&walls_vtp)?)) } else { None };
        Ok(Series { dir: dir.to_path_buf(), particles, fluid, bodies, moving_walls, static_walls })
    }

    /// The leading series' entries: the particles', or the fluid's.
    fn entries(&self) -> &[(f64, String)] {
        self.particles.as_deref().or(self.fluid.as_deref()).unwrap_or(&[])
    }

    /// Whether the walls have a snapshot of their own at each time (`walls.pvd`).
    pub fn walls_move(&self) -> bool {
        self.moving_walls.is_some()
    }

    pub fn len(&self) -> usize {
        self.entries().len()
    }

    pub fn is_empty(&self) -> bool {
        self.entries().is_empty()
    }

    /// Snapshot `k` of the series (in .pvd order).
    pub fn load(&self, k: usize) -> Result<Snapshot, String> {
        let (time, name) = &self.entries()[k];
        let file = self.dir.join(name);
        let particles = if self.particles.is_some() { vtp::read(&file)? } else { PolyData::default() };
        let fluid = self.fluid.as_ref().map(|f| vtp::read(&self.dir.join(&f[k].1))).transpose()?;
        if let Some(f) = &fluid
            && !f.points.is_empty()
            && f.point_array("radius").is_none()
        {
            return Err(format!("{}: no point array \"radius\"", self.dir.join(&self.fluid.as_ref().expect("read above")[k].1).display()));
        }
        let index = name.rsplit('_').next().and_then(|s| s.trim_end_matches(".vtp").parse().ok()).unwrap_or(k);
        let bodies = self.bodies.as_ref().map(|b| vtp::read(&self.dir.join(&b[k].1))).transpose()?;
        let walls = match &self.moving_walls {
            Some(w) => Some(Arc::new(vtp::read(&self.dir.join(&w[k].1))?)),
            None => self.static_walls.clone(),
        };
        if particles.point_array("radius").is_none() && !particles.points.is_empty() {
            return Err(format!("{}: no point array \"radius\"", file.display()));
        }
        Ok(Snapshot { index, time: *time, file, particles, fluid, bodies, walls })
    }
}

impl Snapshot {
    /// Fails, naming the arrays there are, when the particles carry no field `name`.
    pub fn check_field(&self, name: &str) -> Result<(), String> {
        let sets = std::iter::once(&self.particles).chain(self.fluid.as_ref()).filter(|d| !d.points.is_empty());
        let mut names: Vec<&str> = Vec::new();
        for data in sets {
            if field_of(data, name).is_some() {
                return Ok(());
            }
            for a in &data.point_data {
                if !names.contains(&a.name.as_str()) {
                    names.push(&a.name);
                }
            }
        }
        if names.is_empty() {
            return Ok(());
        }
        Err(format!("{}: --color {name}: no such point array (valid: speed, {})", self.file.display(), names.join(", ")))
    }

    /// Each particle's value of field `name`: a scalar array, a vector's magnitude, or `speed` = |velocity|.
    pub fn field(&self, name: &str) -> Option<Vec<f64>> {
        field_of(&self.particles, name)
    }

    /// The smallest and largest value of the field over the particles and the fluid's fluid
    /// particles (infinite bounds when there are none).
    pub fn field_range(&self, name: &str) -> (f64, f64) {
        let fluid: Vec<f64> = self.fluid.as_ref().and_then(|f| fluid_values(f, name)).unwrap_or_default().into_iter().flatten().collect();
        self.field(name)
            .unwrap_or_default()
            .iter()
            .chain(&fluid)
            .filter(|v| v.is_finite())
            .fold((f64::INFINITY, f64::NEG_INFINITY), |(lo, hi), &v| (lo.min(v), hi.max(v)))
    }

    fn radii(&self) -> Vec<f64> {
        point_radii(&self.particles)
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
        if let Some(f) = &self.fluid {
            for (p, r) in f.points.iter().zip(point_radii(f)) {
                let p = DVec3::from_array(*p);
                (lo, hi) = (lo.min(p - r), hi.max(p + r));
            }
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
        if let Some(f) = &self.fluid {
            // The fluid in the colour map; its wall particles in the walls' colour.
            let values = fluid_values(f, field).unwrap_or_default();
            for (i, (p, r)) in f.points.iter().zip(point_radii(f)).enumerate() {
                let colour = values.get(i).copied().flatten().map_or(WALL_COLOUR, |v| viridis(unit(v, range)));
                picture.spheres.push(Sphere { centre: DVec3::from_array(*p), radius: r, colour });
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

/// The values of field `name` over `data`'s points: a scalar array, a vector's magnitude, or
/// `speed` = |velocity|.
fn field_of(data: &PolyData, name: &str) -> Option<Vec<f64>> {
    let array = data.point_array(name).or_else(|| if name == "speed" { data.point_array("velocity") } else { None })?;
    Some((0..array.len()).map(|i| array.scalar(i)).collect())
}

/// Each fluid snapshot point's value of `name`: none for its wall particles (`kind` 1), which
/// are drawn as walls.
fn fluid_values(data: &PolyData, name: &str) -> Option<Vec<Option<f64>>> {
    let values = field_of(data, name)?;
    let kind = data.point_array("kind");
    Some(values.into_iter().enumerate().map(|(i, v)| (kind.is_none_or(|k| k.values[i] == 0.0)).then_some(v)).collect())
}

fn point_radii(data: &PolyData) -> Vec<f64> {
    data.point_array("radius").map(|a| a.values.clone()).unwrap_or_else(|| vec![0.0; data.points.len()])
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
