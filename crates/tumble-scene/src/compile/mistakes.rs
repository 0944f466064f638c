//! Scenes that would run to the end and mean nothing: refused where no scene can mean it
//! (an outlet that deletes every particle in the first step), otherwise warned with the likely
//! cause (`tumble plan`, and `tumble run` before its first step).

use crate::SceneError;
use crate::particles::InitialParticles;
use crate::plan::PhysicsModel;
use crate::rng::Rng;
use crate::schema::Scene;
use crate::sources::{Outlet, OutletRegion, Source};
use glam::DVec3;

/// Places drawn in a source's region to find one clear of the walls (as the feeder draws them).
const PLACES_TRIED: usize = 200;

/// Warnings about schedules the run never reaches, sources without room, flow planes nothing
/// crosses, and units that look mistaken.
pub(super) fn warnings(scene: &Scene, model: &PhysicsModel) -> Vec<String> {
    let mut warnings = Vec::new();
    schedules_after_the_end(scene, model, &mut warnings);
    sources_without_room(model, &mut warnings);
    flow_planes_nothing_crosses(model, &mut warnings);
    implausible_units(scene, model, &mut warnings);
    warnings
}

/// An outlet that holds every particle at t = 0, or the whole region of a source, deletes
/// them as soon as the run starts: its normal points the wrong way, or its box is misplaced.
pub(super) fn check_outlets(outlets: &[Outlet], particles: &InitialParticles, sources: &[Source]) -> Result<(), SceneError> {
    for (k, o) in outlets.iter().enumerate() {
        let (field, side) = match o.region {
            OutletRegion::Beyond { normal, .. } => (
                format!("outlets[{k}].plane.normal"),
                format!("on the side its normal {normal} points to, which the outlet deletes; point the normal away from them ({})", -normal),
            ),
            OutletRegion::Box { .. } => {
                (format!("outlets[{k}].box"), "inside its box, which the outlet deletes; place the box where particles leave".into())
            }
        };
        let n = particles.len();
        if n > 0 && particles.position.iter().all(|&x| o.region.contains(x)) {
            return Err(SceneError::field(
                field,
                format!("outlet \"{}\" would delete all {n} particles in the first step: they start {side}", o.name),
            ));
        }
        // The region lies in a half-space or a box when all the corners of its bounds do.
        for s in sources {
            let (lo, hi) = s.region.bounds();
            let corners = (0..8).map(|c| DVec3::new([lo.x, hi.x][c & 1], [lo.y, hi.y][(c >> 1) & 1], [lo.z, hi.z][c >> 2]));
            if corners.into_iter().all(|x| o.region.contains(x)) {
                return Err(SceneError::field(
                    field,
                    format!("outlet \"{}\" would delete every particle source \"{}\" inserts: its region lies {side}", o.name, s.name),
                ));
            }
        }
    }
    Ok(())
}

/// A motion or a source that starts at or after the end of the run never acts: the drum
/// never turns, nothing is inserted.
fn schedules_after_the_end(scene: &Scene, model: &PhysicsModel, warnings: &mut Vec<String>) {
    let end = scene.run.duration;
    for (k, w) in scene.walls.iter().enumerate() {
        if let Some(m) = &w.motion
            && m.start >= end
        {
            warnings.push(format!(
                "walls[{k}].motion.start = {} s is not before the end of the run (run.duration = {end} s): wall \"{}\" never moves",
                m.start, model.wall_groups[k].name
            ));
        }
    }
    for (k, s) in scene.sources.iter().enumerate() {
        if s.start >= end {
            warnings.push(format!(
                "sources[{k}].start = {} s is not before the end of the run (run.duration = {end} s): source \"{}\" inserts nothing",
                s.start, model.sources[k].name
            ));
        }
    }
}

/// A source none of whose places is clear of the walls and inside the domain (a region
/// behind an end plate, outside a drum's shell) inserts nothing.
fn sources_without_room(model: &PhysicsModel, warnings: &mut Vec<String>) {
    for s in &model.sources {
        let walls: Vec<_> = model.walls.iter().map(|w| w.shape_at(s.first_step as f64 * model.dt)).collect();
        let mut rng = Rng::new(s.seed);
        let (mut outside, mut blocked) = (0, vec![0usize; walls.len()]);
        let room = (0..PLACES_TRIED).any(|_| {
            let r = s.draw_body(&mut rng, &model.shapes).radius;
            // A mesh too thin for the body has no place inside: that counts as outside.
            let Some(x) = s.region.sample(&mut rng, r).filter(|&x| model.domain.contains(x)) else {
                outside += 1;
                return false;
            };
            match walls.iter().position(|w| w.sphere_contact(x, r).is_some()) {
                Some(w) => {
                    blocked[w] += 1;
                    false
                }
                None => true,
            }
        });
        if room {
            continue;
        }
        let mut why: Vec<String> =
            blocked.iter().enumerate().filter(|(_, n)| **n > 0).map(|(w, n)| format!("{n} overlap wall \"{}\"", model.walls[w].name)).collect();
        if outside > 0 {
            why.push(format!("{outside} lie outside the domain"));
        }
        warnings.push(format!(
            "source \"{}\" has no room: none of {PLACES_TRIED} places drawn in its region is clear of the walls and inside the domain ({}), so it will insert nothing; move its region inside the walls",
            s.name,
            why.join(", ")
        ));
    }
}

/// A flow plane no particle reaches reads 0 kg/s for the whole run: one that misses the
/// domain, or lies wholly beyond a (parallel) outlet plane, or behind a static plane wall.
fn flow_planes_nothing_crosses(model: &PhysicsModel, warnings: &mut Vec<String>) {
    let (lo, hi) = (model.domain.min, model.domain.max);
    let corners: Vec<DVec3> = (0..8).map(|c| DVec3::new([lo.x, hi.x][c & 1], [lo.y, hi.y][(c >> 1) & 1], [lo.z, hi.z][c >> 2])).collect();
    let parallel = |a: DVec3, b: DVec3| a.cross(b).length() < 1e-9;
    for (k, fp) in model.flow_planes.iter().enumerate() {
        let (p, n) = (fp.plane.point, fp.plane.normal);
        let label = format!("output.flow_planes[{k}] (\"{}\")", fp.name);
        let side: Vec<f64> = corners.iter().map(|&c| n.dot(c - p)).collect();
        if side.iter().all(|&d| d > 0.0) || side.iter().all(|&d| d < 0.0) {
            warnings.push(format!("{label} misses the domain: no particle crosses it, so it reads 0 kg/s; place it inside the domain"));
            continue;
        }
        for o in &model.outlets {
            if let OutletRegion::Beyond { point, normal } = o.region
                && parallel(n, normal)
                && (p - point).dot(normal) > 0.0
            {
                warnings.push(format!(
                    "{label} lies {:.4e} m beyond outlet \"{}\", on the side the outlet deletes: particles are deleted before they reach it, so it reads 0 kg/s; place it before the outlet",
                    (p - point).dot(normal),
                    o.name
                ));
            }
        }
        for w in model.walls.iter().filter(|w| w.motion.is_none()) {
            if let tumble_geom::SurfaceShape::Plane(wall) = &w.shape
                && parallel(n, wall.normal)
                && (p - wall.point).dot(wall.normal) < 0.0
            {
                warnings.push(format!(
                    "{label} lies {:.4e} m behind wall \"{}\", where no particle goes, so it reads 0 kg/s; place it on the particles' side of the wall",
                    -(p - wall.point).dot(wall.normal),
                    w.name
                ));
            }
        }
    }
}

/// Lightest particle density taken for kg/m³, kg/m³: below it a density reads as g/cm³
/// (glass 2.5, steel 7.8). The verification scenes' 10 kg/m³ is meant.
const LIGHTEST_DENSITY: f64 = 10.0;
/// Heaviest particle density taken as meant, kg/m³ (osmium, the densest element, is 22 590).
const HEAVIEST_DENSITY: f64 = 1.0e5;
/// Strongest gravity taken as meant, m/s² (about 10 g): beyond it, mm/s² or a centrifuge.
const STRONGEST_GRAVITY: f64 = 100.0;

/// Densities, gravity and output intervals in the wrong units or out of proportion to the run.
fn implausible_units(scene: &Scene, model: &PhysicsModel, warnings: &mut Vec<String>) {
    // Only the materials particles are made of: a wall's density is never read.
    let particle_materials: Vec<&str> =
        scene.particles.iter().map(|p| p.material.as_str()).chain(scene.sources.iter().map(|s| s.material.as_str())).collect();
    for (k, m) in model.materials.iter().enumerate().filter(|(_, m)| particle_materials.contains(&m.name.as_str())) {
        if m.density < LIGHTEST_DENSITY {
            warnings.push(format!(
                "materials[{k}].density = {} kg/m³ is lighter than any solid particle: densities are in kg/m³, and this looks like g/cm³ ({} g/cm³ is {} kg/m³)",
                m.density,
                m.density,
                m.density * 1000.0
            ));
        } else if m.density > HEAVIEST_DENSITY {
            warnings.push(format!(
                "materials[{k}].density = {} kg/m³ is heavier than any solid (osmium is 22590 kg/m³): densities are in kg/m³",
                m.density
            ));
        }
    }
    let g = model.gravity.length();
    if g > STRONGEST_GRAVITY {
        warnings.push(format!(
            "gravity.acceleration has magnitude {g} m/s² ({:.0} times Earth's): accelerations are in m/s², and this looks like mm/s² ({:?} mm/s² is {:?} m/s²)",
            g / 9.80665,
            model.gravity.to_array(),
            (model.gravity / 1000.0).to_array()
        ));
    }
    let end = scene.run.duration;
    if let Some(t) = scene.run.output_interval
        && t > end
    {
        warnings.push(format!(
            "run.output_interval = {t} s is longer than the run (run.duration = {end} s): observables.csv gets only its rows at the start and the end"
        ));
    }
}
