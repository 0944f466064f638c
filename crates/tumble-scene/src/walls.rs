//! The [[walls]] entries compiled into surfaces: boxes as six quads, drums with their lifter
//! prisms, motions and the groups whose power `observables.csv` reports.

use crate::SceneError;
use crate::compile::{finite3, positive, unit};
use crate::plan::{Drum, Motion, Servo, Timing, Wall, WallGroup};
use crate::schema::*;
use glam::DVec3;
use tumble_geom::{Cylinder, PeriodicBox, Plane, Prism, Quad, SurfaceShape};

/// Largest distance of a quad's fourth corner from the plane of the other three, as a fraction
/// of its diagonal: a quad beyond it is two triangles, not one face.
const QUAD_PLANARITY: f64 = 1e-9;

/// Surfaces, their groups (one per [[walls]] entry), the drums among them and the meshes' warnings.
pub(crate) type CompiledWalls = (Vec<Wall>, Vec<WallGroup>, Vec<Drum>, Vec<String>);

/// The [[walls]] entries as surfaces (boxes as six quads, lifters as prisms, meshes binned on
/// cells of about `mesh_cell`), their groups and the drums.
pub(crate) fn compile_walls(
    scene: &Scene,
    lookup: &dyn Fn(String, &str) -> Result<u16, SceneError>,
    domain: &PeriodicBox,
    mesh_cell: f64,
) -> Result<CompiledWalls, SceneError> {
    let names: Vec<String> = scene.walls.iter().enumerate().map(|(k, w)| w.name.clone().unwrap_or_else(|| format!("wall{k}"))).collect();
    // Motions first: lifters take their cylinder's.
    let mut motions: Vec<Option<Motion>> = Vec::new();
    let mut timings: Vec<Timing> = Vec::new();
    for (k, w) in scene.walls.iter().enumerate() {
        let (motion, timing) = match &w.motion {
            None => (None, Timing::ALWAYS),
            Some(m) => motion(k, m)?,
        };
        motions.push(motion);
        timings.push(timing);
        if (w.motion.is_some() || w.surface_velocity.is_some() || w.servo.is_some()) && names[..k].contains(&names[k]) {
            return Err(SceneError::field(
                format!("walls[{k}].name"),
                format!("a moving wall needs a unique name (its power column); \"{}\" is used twice", names[k]),
            ));
        }
    }
    let mut walls: Vec<Wall> = Vec::new();
    let mut groups = Vec::new();
    let mut drums = Vec::new();
    let mut warnings = Vec::new();
    let mut mesh_keys = 0u32;
    for (k, w) in scene.walls.iter().enumerate() {
        let f = |x: &str| format!("walls[{k}].{x}");
        let material = match &w.material {
            Some(m) => lookup(f("material"), m)?,
            None => return Err(SceneError::field(f("material"), "missing: particles meet a wall through its material; name one of [[materials]]")),
        };
        let name = names[k].clone();
        let given = [w.plane.is_some(), w.quad.is_some(), w.box_.is_some(), w.cylinder.is_some(), w.lifters.is_some(), w.mesh.is_some()];
        if given.iter().filter(|&&b| b).count() != 1 {
            return Err(SceneError::field(format!("walls[{k}]"), "give exactly one shape: plane, quad, box, cylinder, lifters or mesh"));
        }
        let mut motion = motions[k];
        let mut timing = timings[k];
        let surface_velocity = conveyor(k, w)?;
        let servo = servo(k, w)?;
        let wear = wear(k, w)?;
        let group = k as u16;
        let mut shapes: Vec<(String, SurfaceShape)> = Vec::new();
        if let Some(m) = &w.mesh {
            let (shape, said) = crate::mesh_walls::mesh_wall(scene, k, m, mesh_cell, mesh_keys)?;
            if let SurfaceShape::Mesh(mesh) = &shape {
                mesh_keys += mesh.body.mesh.triangles.len() as u32;
            }
            warnings.extend(said);
            shapes.push((name.clone(), shape));
        } else if let Some(p) = &w.plane {
            shapes.push((name.clone(), SurfaceShape::Plane(Plane::new(finite3(&f("plane.point"), p.point)?, unit(&f("plane.normal"), p.normal)?))));
        } else if let Some(q) = &w.quad {
            let mut c = [DVec3::ZERO; 4];
            for (i, corner) in q.corners.iter().enumerate() {
                c[i] = finite3(&f(&format!("quad.corners[{i}]")), *corner)?;
            }
            if (c[1] - c[0]).cross(c[2] - c[0]).length() == 0.0 {
                return Err(SceneError::field(f("quad.corners"), "the first three corners are collinear"));
            }
            let quad = Quad::new(c, q.two_sided);
            if quad.planarity_error() > QUAD_PLANARITY {
                let diagonal = (c[2] - c[0]).length();
                return Err(SceneError::field(
                    f("quad.corners"),
                    format!(
                        "the four corners must lie in one plane: the fourth lies {:.3e} m from the plane through the first three, {:.3e} of the diagonal {:.4e} m; the tolerance is {QUAD_PLANARITY:e} of the diagonal ({:.3e} m)",
                        quad.planarity_error() * diagonal,
                        quad.planarity_error(),
                        diagonal,
                        QUAD_PLANARITY * diagonal
                    ),
                ));
            }
            shapes.push((name.clone(), SurfaceShape::Quad(quad)));
        } else if let Some(b) = &w.box_ {
            let (lo, hi) = (finite3(&f("box.min"), b.min)?, finite3(&f("box.max"), b.max)?);
            if (0..3).any(|a| hi[a] <= lo[a]) {
                return Err(SceneError::field(f("box"), "max must exceed min on every axis"));
            }
            for (side, quad) in ["-x", "+x", "-y", "+y", "-z", "+z"].iter().zip(Quad::box_faces(lo, hi)) {
                if *side == "-z"
                    && let Some(hole) = b.floor_hole
                {
                    let w = positive(&f("box.floor_hole"), hole)?;
                    let (c, half) = (0.5 * (lo + hi), 0.5 * w);
                    if c.x + half >= hi.x || c.y + half >= hi.y {
                        return Err(SceneError::field(
                            f("box.floor_hole"),
                            format!("a {w} m hole does not fit in the {} x {} m floor", hi.x - lo.x, hi.y - lo.y),
                        ));
                    }
                    // Four quads around the hole, normal +z like the floor they replace.
                    let (x0, x1, y0, y1) = (c.x - half, c.x + half, c.y - half, c.y + half);
                    let q = |ax: f64, bx: f64, ay: f64, by: f64| {
                        SurfaceShape::Quad(Quad::new(
                            [DVec3::new(ax, ay, lo.z), DVec3::new(bx, ay, lo.z), DVec3::new(bx, by, lo.z), DVec3::new(ax, by, lo.z)],
                            false,
                        ))
                    };
                    shapes.push((format!("{name}-z0"), q(lo.x, x0, lo.y, hi.y)));
                    shapes.push((format!("{name}-z1"), q(x1, hi.x, lo.y, hi.y)));
                    shapes.push((format!("{name}-z2"), q(x0, x1, lo.y, y0)));
                    shapes.push((format!("{name}-z3"), q(x0, x1, y1, hi.y)));
                    continue;
                }
                shapes.push((format!("{name}{side}"), SurfaceShape::Quad(quad)));
            }
        } else if let Some(c) = &w.cylinder {
            let cyl = cylinder(k, c)?;
            if let Some(Motion::Rotate { point, axis, omega }) = motion
                && c.inside
                && coaxial(&cyl, point, axis)
            {
                drums.push(Drum { name: name.clone(), point: cyl.point, axis, radius: cyl.radius, length: cyl.length, omega, timing: timings[k] });
            }
            shapes.push((name.clone(), SurfaceShape::Cylinder(cyl)));
        } else if let Some(l) = &w.lifters {
            let fl = |x: &str| format!("walls[{k}].lifters.{x}");
            if w.motion.is_some() {
                return Err(SceneError::field(f("motion"), "lifters move with the cylinder they are fixed to; give the motion on that cylinder"));
            }
            let host: Vec<usize> = (0..scene.walls.len()).filter(|&j| names[j] == l.on).collect();
            let j = match host[..] {
                [j] => j,
                [] => {
                    return Err(SceneError::field(
                        fl("on"),
                        format!("no wall is named \"{}\"; lifters need the name of an inside cylinder wall", l.on),
                    ));
                }
                _ => return Err(SceneError::field(fl("on"), format!("several walls are named \"{}\"; give the cylinder a unique name", l.on))),
            };
            let Some(c) = scene.walls[j].cylinder.as_ref().filter(|c| c.inside) else {
                return Err(SceneError::field(fl("on"), format!("wall \"{}\" is not an inside cylinder (lifters line a drum shell)", l.on)));
            };
            let cyl = cylinder(j, c)?;
            if l.count == 0 {
                return Err(SceneError::field(fl("count"), "must be at least 1 row"));
            }
            let h = positive(&fl("height"), l.height)?;
            let width = positive(&fl("width"), l.width)?;
            if h >= 0.5 * cyl.radius {
                return Err(SceneError::field(fl("height"), format!("must be less than half the drum radius {}, got {h}", cyl.radius)));
            }
            if !(l.face_angle >= 0.0 && l.face_angle < 75.0) {
                return Err(SceneError::field(
                    fl("face_angle"),
                    format!("must lie in [0, 75) degrees from the radial direction, got {}", l.face_angle),
                ));
            }
            if !l.phase.is_finite() {
                return Err(SceneError::field(fl("phase"), "must be a finite angle in degrees"));
            }
            let base = width + 2.0 * h * l.face_angle.to_radians().tan();
            if base * l.count as f64 >= std::f64::consts::TAU * (cyl.radius - h) {
                return Err(SceneError::field(
                    fl("count"),
                    format!(
                        "{} rows with a base {base:.4} m wide do not fit around the drum (circumference {:.4} m)",
                        l.count,
                        std::f64::consts::TAU * (cyl.radius - h)
                    ),
                ));
            }
            motion = motions[j];
            timing = timings[j];
            for (r, prism) in lifter_prisms(&cyl, l.count, h, width, base, l.phase.to_radians()).into_iter().enumerate() {
                shapes.push((format!("{name}{r}"), SurfaceShape::Prism(Box::new(prism))));
            }
        }
        groups.push(WallGroup { name, moving: motion.is_some() || surface_velocity != DVec3::ZERO || servo.is_some(), servo });
        for (wall_name, shape) in shapes {
            let (travel_speed, surface_speed) = match motion {
                None => (0.0, 0.0),
                Some(Motion::Oscillate { .. }) => (motion.unwrap().peak_speed(), motion.unwrap().peak_speed()),
                Some(Motion::Translate { velocity }) => match &shape {
                    // An infinite plane sliding in its own plane stays where it is.
                    SurfaceShape::Plane(p) => (velocity.dot(p.normal).abs(), velocity.length()),
                    _ => (velocity.length(), velocity.length()),
                },
                Some(Motion::Rotate { point, axis, omega }) => {
                    let speed = omega.abs() * max_radius(&shape, point, axis, domain);
                    // A drum shell about its own axis, or an end plate about its normal, stays in place.
                    let invariant = match &shape {
                        SurfaceShape::Cylinder(c) => coaxial(c, point, axis),
                        SurfaceShape::Plane(p) => p.normal.cross(axis).length() < 1e-9,
                        _ => false,
                    };
                    (if invariant { 0.0 } else { speed }, speed)
                }
            };
            let surface_speed = surface_speed.max(surface_velocity.length());
            // A servo translates the wall at up to its largest speed.
            let (travel_speed, surface_speed) = match (&servo, &shape) {
                (Some(s), SurfaceShape::Plane(p)) => (s.max_speed * s.direction.dot(p.normal).abs(), s.max_speed),
                (Some(s), _) => (s.max_speed, s.max_speed),
                (None, _) => (travel_speed, surface_speed),
            };
            walls.push(Wall { name: wall_name, material, shape, motion, surface_velocity, timing, group, travel_speed, surface_speed, wear });
        }
    }
    if walls.len() > u16::MAX as usize {
        return Err(SceneError::field("walls", format!("{} surfaces; at most {} are supported", walls.len(), u16::MAX)));
    }
    Ok((walls, groups, drums, warnings))
}

/// A conveyor's surface velocity (zero when none is given), checked.
fn conveyor(k: usize, w: &WallSection) -> Result<DVec3, SceneError> {
    let Some(v) = w.surface_velocity else { return Ok(DVec3::ZERO) };
    let field = format!("walls[{k}].surface_velocity");
    let v = finite3(&field, v)?;
    if w.motion.is_some() || w.lifters.is_some() {
        return Err(SceneError::field(field, "a conveyor's surface moves while the wall stays: give it on a wall without motion (not on lifters)"));
    }
    Ok(v)
}

/// A servo wall's controller, checked.
fn servo(k: usize, w: &WallSection) -> Result<Option<Servo>, SceneError> {
    let Some(s) = &w.servo else { return Ok(None) };
    let f = |x: &str| format!("walls[{k}].servo.{x}");
    if w.motion.is_some() || w.surface_velocity.is_some() || w.lifters.is_some() {
        return Err(SceneError::field(
            f("direction"),
            "a servo moves its wall itself: give it on a wall without motion or surface_velocity (not on lifters)",
        ));
    }
    let direction = unit(&f("direction"), s.direction)?;
    let force = positive(&f("force"), s.force)?;
    let max_speed = positive(&f("max_speed"), s.max_speed)?;
    let gain = match s.gain {
        Some(g) => positive(&f("gain"), g)?,
        None => max_speed / force,
    };
    Ok(Some(Servo { direction, force, max_speed, gain }))
}

/// A mesh wall's Archard wear coefficient over hardness (0 without wear), checked.
fn wear(k: usize, w: &WallSection) -> Result<f64, SceneError> {
    let Some(wear) = &w.wear else { return Ok(0.0) };
    let f = |x: &str| format!("walls[{k}].wear.{x}");
    if w.mesh.is_none() {
        return Err(SceneError::field(format!("walls[{k}].wear"), "wear is accumulated per triangle: give it on a mesh wall"));
    }
    Ok(positive(&f("coefficient"), wear.coefficient)? / positive(&f("hardness"), wear.hardness)?)
}

/// A wall's motion and its timing, checked.
pub(crate) fn motion(k: usize, m: &MotionSection) -> Result<(Option<Motion>, Timing), SceneError> {
    let f = |x: &str| format!("walls[{k}].motion.{x}");
    let given = [m.rotate.is_some(), m.translate.is_some(), m.oscillate.is_some()].iter().filter(|&&b| b).count();
    if given != 1 {
        return Err(SceneError::field(f("rotate"), format!("give exactly one of rotate, translate and oscillate (got {given})")));
    }
    let motion = if let Some(r) = &m.rotate {
        if !(r.rpm.is_finite() && r.rpm != 0.0) {
            return Err(SceneError::field(f("rotate.rpm"), format!("must be a non-zero number of revolutions per minute, got {}", r.rpm)));
        }
        Motion::Rotate {
            point: finite3(&f("rotate.point"), r.point)?,
            axis: unit(&f("rotate.axis"), r.axis)?,
            omega: r.rpm * std::f64::consts::TAU / 60.0,
        }
    } else if let Some(t) = &m.translate {
        let v = finite3(&f("translate.velocity"), t.velocity)?;
        if v == DVec3::ZERO {
            return Err(SceneError::field(f("translate.velocity"), "must be non-zero (leave motion out for a static wall)"));
        }
        Motion::Translate { velocity: v }
    } else {
        let o = m.oscillate.as_ref().unwrap();
        positive(&f("oscillate.amplitude"), o.amplitude)?;
        positive(&f("oscillate.frequency"), o.frequency)?;
        Motion::Oscillate {
            direction: unit(&f("oscillate.direction"), o.direction)?,
            amplitude: o.amplitude,
            omega: std::f64::consts::TAU * o.frequency,
        }
    };
    if !(m.start.is_finite() && m.start >= 0.0) {
        return Err(SceneError::field(f("start"), format!("must be a time in seconds, 0 or later, got {}", m.start)));
    }
    if !(m.ramp.is_finite() && m.ramp >= 0.0) {
        return Err(SceneError::field(f("ramp"), format!("must be a duration in seconds, 0 or more, got {}", m.ramp)));
    }
    let stop = m.stop.unwrap_or(f64::INFINITY);
    if stop.is_nan() || stop <= m.start {
        return Err(SceneError::field(f("stop"), format!("must come after motion.start = {} s, got {stop}", m.start)));
    }
    Ok((Some(motion), Timing { start: m.start, ramp: m.ramp, stop }))
}

pub(crate) fn cylinder(k: usize, c: &CylinderSection) -> Result<Cylinder, SceneError> {
    let f = |x: &str| format!("walls[{k}].cylinder.{x}");
    positive(&f("radius"), c.radius)?;
    positive(&f("length"), c.length)?;
    Ok(Cylinder::new(finite3(&f("point"), c.point)?, unit(&f("axis"), c.axis)?, c.radius, c.length, c.inside))
}

/// True when the rotation axis (point, unit axis) is the cylinder's own axis.
fn coaxial(c: &Cylinder, point: DVec3, axis: DVec3) -> bool {
    let d = c.point - point;
    axis.cross(c.axis).length() < 1e-9 && (d - axis * d.dot(axis)).length() < 1e-9 * c.radius
}

/// Largest distance of the surface from the axis (planes: over the domain's corners).
fn max_radius(shape: &SurfaceShape, point: DVec3, axis: DVec3, domain: &PeriodicBox) -> f64 {
    let r = |x: DVec3| {
        let d = x - point;
        (d - axis * d.dot(axis)).length()
    };
    match shape {
        SurfaceShape::Plane(_) => (0..8)
            .map(|k| {
                r(DVec3::new(
                    if k & 1 == 0 { domain.min.x } else { domain.max.x },
                    if k & 2 == 0 { domain.min.y } else { domain.max.y },
                    if k & 4 == 0 { domain.min.z } else { domain.max.z },
                ))
            })
            .fold(0.0, f64::max),
        SurfaceShape::Quad(q) => q.corners.iter().map(|&c| r(c)).fold(0.0, f64::max),
        SurfaceShape::Cylinder(c) => r(c.point).max(r(c.point + c.axis * c.length)) + c.radius,
        SurfaceShape::Prism(p) => p.faces.iter().flat_map(|q| q.corners).map(r).fold(0.0, f64::max),
        SurfaceShape::Mesh(m) => m.body.mesh.vertices.iter().map(|&v| r(m.to_world(v))).fold(0.0, f64::max),
    }
}

/// Lifter bars: prisms along the drum axis, top face `width` wide at R − h, base `base`
/// wide on the shell (tangent plane at R; its corners sit just beyond the shell).
fn lifter_prisms(c: &Cylinder, count: u32, h: f64, width: f64, base: f64, phase: f64) -> Vec<Prism> {
    let (u, v) = c.axis.any_orthonormal_pair();
    (0..count)
        .map(|k| {
            let phi = phase + std::f64::consts::TAU * k as f64 / count as f64;
            let er = u * phi.cos() + v * phi.sin();
            let et = c.axis.cross(er);
            let section = [(-0.5 * base, c.radius), (0.5 * base, c.radius), (0.5 * width, c.radius - h), (-0.5 * width, c.radius - h)];
            let at = |s: f64| section.map(|(x, y)| c.point + c.axis * s + et * x + er * y);
            Prism::new(at(0.0), at(c.length), c.point, c.axis)
        })
        .collect()
}
