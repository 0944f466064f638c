//! The [sph] section: the fluid's settings, its particles (regions of fluid, and the scene's
//! walls as dummy particles), its probes, its time-step limits and what the plan warns.

use super::{finite3, non_negative, positive};
use crate::SceneError;
use crate::plan::{SphPlan, Wall};
use crate::schema::*;
use glam::DVec3;
use tumble_geom::{Cylinder, Motion, PeriodicBox};
use tumble_sph::{
    Aabb, DensityDiffusion, Dimension, FluidParticles, FluidPhase, FluidSettings, MovingWall, ParticleKind, Rectangle, TimeStepLimits, Viscosity,
    add_fluid_block, add_fluid_cylinder, add_wall_box, add_wall_cylinder, add_wall_rectangle, add_wall_slab, on_fluid_side, wall_layers,
};

/// h / Δp unless the scene says otherwise: the lattice's kernel gradient sums to within 0.3 %
/// of the continuum's there (docs/sph.md, "Smoothing length").
pub const SMOOTHING_RATIO: f64 = 1.5;
/// c₀ / v_max unless the scene says otherwise: density within about 1 %.
pub const SOUND_SPEED_FACTOR: f64 = 10.0;

/// The fluid's plan and starting particles, or none without an [sph] table.
/// `compiled` are the scene's walls as the particles see them (lifters as their bars).
pub(super) fn sph(scene: &Scene, domain: &PeriodicBox, gravity: DVec3, compiled: &[Wall]) -> Result<Option<(SphPlan, FluidParticles)>, SceneError> {
    let Some(s) = &scene.sph else { return Ok(None) };
    let dimension = match s.dimension {
        2 => Dimension::Two,
        3 => Dimension::Three,
        d => return Err(SceneError::field("sph.dimension", format!("must be 2 (a plane flow in x–z) or 3, got {d}"))),
    };
    let spacing = positive("sph.spacing", s.spacing)?;
    let ratio = s.smoothing_ratio.unwrap_or(SMOOTHING_RATIO);
    if !(1.0..=3.0).contains(&ratio) {
        return Err(SceneError::field("sph.smoothing_ratio", format!("h / spacing must be from 1 to 3 (default {SMOOTHING_RATIO}), got {ratio}")));
    }
    let rho0 = positive("sph.density", s.density)?;
    let mu = non_negative("sph.viscosity", s.viscosity)?;
    let body_force = finite3("sph.body_force", s.body_force)?;
    let (sound_speed, expected_speed) = match (s.sound_speed, s.expected_speed) {
        (Some(c), None) => {
            if s.sound_speed_factor.is_some() {
                return Err(SceneError::field(
                    "sph.sound_speed_factor",
                    "goes with expected_speed; with sound_speed given it has nothing to multiply",
                ));
            }
            let c = positive("sph.sound_speed", c)?;
            (c, c / SOUND_SPEED_FACTOR)
        }
        (None, Some(v)) => {
            let v = positive("sph.expected_speed", v)?;
            let factor = s.sound_speed_factor.unwrap_or(SOUND_SPEED_FACTOR);
            if !(factor.is_finite() && factor >= 1.0) {
                return Err(SceneError::field(
                    "sph.sound_speed_factor",
                    format!("c0 / expected_speed must be at least 1 (10 keeps density within about 1 %), got {factor}"),
                ));
            }
            (factor * v, v)
        }
        _ => {
            return Err(SceneError::field(
                "sph",
                "give exactly one of sound_speed (c0, m/s) or expected_speed (the largest flow speed, m/s; c0 = sound_speed_factor × it); for a column of height H falling, expected_speed = sqrt(2 g H)",
            ));
        }
    };
    let viscosity = match s.viscosity_model {
        SphViscositySection::Laminar {} => {
            if mu == 0.0 {
                return Err(SceneError::field("sph.viscosity", "the laminar model needs a positive dynamic viscosity (water: 1.0e-3 Pa s)"));
            }
            Viscosity::Laminar
        }
        SphViscositySection::Artificial { alpha } => Viscosity::Artificial { alpha: positive("sph.viscosity_model.alpha", alpha)? },
    };
    let unit = |field: &str, delta: f64| {
        if delta > 0.0 && delta <= 1.0 { Ok(delta) } else { Err(SceneError::field(field, format!("must be in (0, 1] (0.1 is usual), got {delta}"))) }
    };
    let density_diffusion = match s.density_diffusion {
        DensityDiffusionSection::None {} => DensityDiffusion::None,
        DensityDiffusionSection::MolteniColagrossi { delta } => {
            DensityDiffusion::MolteniColagrossi { delta: unit("sph.density_diffusion.delta", delta)? }
        }
        DensityDiffusionSection::Fourtakas { delta } => DensityDiffusion::Fourtakas { delta: unit("sph.density_diffusion.delta", delta)? },
    };
    if !(0.0..=1.0).contains(&s.xsph) {
        return Err(SceneError::field("sph.xsph", format!("ε must be from 0 (off) to 1 (0.5 is usual), got {}", s.xsph)));
    }
    if dimension == Dimension::Two && (gravity.y != 0.0 || body_force.y != 0.0) {
        return Err(SceneError::field("sph.dimension", "a 2D fluid moves in the x–z plane: gravity and sph.body_force must have no y component"));
    }
    let mut settings = FluidSettings {
        dimension,
        spacing,
        h: ratio * spacing,
        rho0,
        mu,
        sound_speed,
        viscosity,
        density_diffusion,
        tensile_correction: s.tensile_correction,
        xsph: s.xsph,
        gravity,
        body_force,
        domain: *domain,
        moving_walls: Vec::new(),
        floating: Vec::new(),
        inflows: Vec::new(),
        outflows: Vec::new(),
    };
    // The grid reaches over the wall particles outside the domain's closed sides; a 2D fluid lies at y = 0.
    let reach = (wall_layers(&settings) as f64 + 1.0) * spacing;
    for k in 0..3 {
        if !domain.periodic[k] {
            settings.domain.min[k] -= reach;
            settings.domain.max[k] += reach;
        }
    }
    if dimension == Dimension::Two {
        (settings.domain.min.y, settings.domain.max.y, settings.domain.periodic[1]) = (0.0, 0.0, false);
    }
    // The phase's own checks (a periodic axis must hold two of its cells, …), before any particle is made.
    FluidPhase::new(settings.clone(), FluidParticles::default()).map_err(|e| SceneError::field("sph", e))?;
    check_counts(scene, s, &settings, domain)?;
    let mut particles = FluidParticles::default();
    fill_regions(scene, s, &settings, domain, &mut particles)?;
    let walls = add_walls(scene, compiled, &settings, domain, &mut particles)?;
    settings.moving_walls = walls.moving.iter().map(|&(_, wall, _)| wall).collect();
    // Fluid on the wrong side of a cylinder, a rectangle or a mesh, or within half a spacing of it, is left out.
    particles.retain(|kind, x| kind == ParticleKind::Wall || walls.leave_fluid_at(x, &settings));
    let floating = super::sph_floating::add_floating(s, &mut settings, domain, &mut particles)?;
    super::sph_buffers::add_buffers(s, &mut settings, domain, &mut particles)?;
    let fluid_particles = particles.fluid_count();
    if fluid_particles == 0 {
        return Err(SceneError::field(
            "sph.regions",
            "no fluid is left on the fluid's side of the walls; put the regions inside the drums (outside the pipes), in front of the quads",
        ));
    }
    let probes = super::sph_probes::probes(s, dimension, domain)?;
    let limits = TimeStepLimits::new(&settings, expected_speed, settings.external_acceleration().length());
    let mut warnings = Vec::new();
    if sound_speed < SOUND_SPEED_FACTOR * expected_speed * (1.0 - 1e-12) {
        warnings.push(format!(
            "sph: c0 = {sound_speed:.4} m/s is {:.1} times the expected speed; below 10 the density varies by more than about 1 % and the front runs ahead (docs/sph.md, \"Stability\")",
            sound_speed / expected_speed
        ));
    }
    if s.tensile_correction && density_diffusion == DensityDiffusion::None {
        warnings.push(
            "sph: the tensile correction without density diffusion made the dam break's density noisier, not smoother (2.5–26 % error in docs/sph.md, \"Stability\"); add density_diffusion".into(),
        );
    }
    for &(k, _, speed) in &walls.moving {
        if speed > expected_speed * (1.0 + 1e-12) {
            warnings.push(format!(
                "sph: walls[{k}] moves its fluid's side at {speed:.4} m/s, above the expected speed {expected_speed:.4} m/s the sound speed and time step were chosen for; raise sph.expected_speed"
            ));
        }
    }
    if density_diffusion == DensityDiffusion::None && viscosity == Viscosity::Laminar {
        warnings
            .push("sph: laminar viscosity without density diffusion lets pressure noise grow in violent flows (docs/sph.md, \"Stability\")".into());
    }
    for (k, inflow) in settings.inflows.iter().enumerate() {
        let peak = inflow.peak_speed(dimension == Dimension::Two);
        if peak > expected_speed * (1.0 + 1e-12) {
            warnings.push(format!(
                "sph: inflows[{k}] brings fluid in at up to {peak:.4} m/s, above the expected speed {expected_speed:.4} m/s the sound speed and time step were chosen for; raise sph.expected_speed"
            ));
        }
    }
    for (name, body) in floating.iter().zip(&settings.floating) {
        let speed = body.start.velocity.length();
        if speed > expected_speed * (1.0 + 1e-12) {
            warnings.push(format!(
                "sph: floating body \"{name}\" starts at {speed:.4} m/s, above the expected speed {expected_speed:.4} m/s the sound speed and time step were chosen for; raise sph.expected_speed"
            ));
        }
    }
    let coupling = super::sph_coupling::coupling(scene, &settings, domain, &mut warnings)?;
    let plan = SphPlan {
        settings,
        limits,
        expected_speed,
        fluid_particles,
        wall_particles: particles.len() - fluid_particles,
        probes,
        floating,
        warnings,
        coupling,
    };
    Ok(Some((plan, particles)))
}

/// A box of the fluid's scene (a region, a body, a buffer) at `field`: finite corners in the
/// fluid's space, max above min on every active axis.
pub(super) fn plane_box(field: &str, b: &SphBoxSection, dimension: Dimension) -> Result<Aabb, SceneError> {
    let min = in_plane(dimension, finite3(&format!("{field}.min"), b.min)?);
    let max = in_plane(dimension, finite3(&format!("{field}.max"), b.max)?);
    if (0..3).any(|a| !(dimension == Dimension::Two && a == 1) && max[a] <= min[a]) {
        return Err(SceneError::field(field, "max must exceed min on every axis (in 2D, x and z)"));
    }
    Ok(Aabb::new(min, max))
}

/// A name that becomes an output file `<file>` (`<name>` in it): not empty, letters, digits,
/// `_` or `-`, and not one of `taken`.
pub(super) fn file_name(field: String, name: &str, taken: &[&str], what: &str, file: &str) -> Result<(), SceneError> {
    let bad = name.is_empty() || name.chars().any(|c| !(c.is_ascii_alphanumeric() || c == '_' || c == '-'));
    if bad || taken.contains(&name) {
        return Err(SceneError::field(field, format!("names {what} file {file}: unique, letters, digits, '_' or '-'; got \"{name}\"")));
    }
    Ok(())
}

/// `x` in the fluid's space: a 2D fluid lies in the x–z plane at y = 0.
pub(super) fn in_plane(dimension: Dimension, mut x: DVec3) -> DVec3 {
    if dimension == Dimension::Two {
        x.y = 0.0;
    }
    x
}

fn fill_regions(
    scene: &Scene,
    s: &SphSection,
    settings: &FluidSettings,
    domain: &PeriodicBox,
    particles: &mut FluidParticles,
) -> Result<(), SceneError> {
    if s.regions.is_empty() {
        return Err(SceneError::field("sph.regions", "the fluid fills nothing; add [[sph.regions]] with box = { min = [...], max = [...] }"));
    }
    for (k, r) in s.regions.iter().enumerate() {
        let f = |x: &str| format!("sph.regions[{k}].{x}");
        let velocity = finite3(&f("velocity"), r.velocity)?;
        if settings.dimension == Dimension::Two && velocity.y != 0.0 {
            return Err(SceneError::field(f("velocity"), "a 2D fluid moves in the x–z plane: the velocity must have no y component"));
        }
        let flat = |k: usize| settings.dimension == Dimension::Two && k == 1;
        let inside = |x: DVec3| (0..3).all(|a| flat(a) || (x[a] >= domain.min[a] && x[a] <= domain.max[a]));
        let clip = match &r.box_ {
            Some(b) => {
                let b = plane_box(&f("box"), b, settings.dimension)?;
                if !(inside(b.min) && inside(b.max)) {
                    return Err(SceneError::field(f("box"), "must lie inside the domain"));
                }
                Some(b)
            }
            None => None,
        };
        let added = match (&r.cylinder, clip) {
            _ if r.mesh.is_some() => {
                if r.cylinder.is_some() {
                    return Err(SceneError::field(f("mesh"), "give a region one shape: a mesh or a cylinder (with a box: the part inside it)"));
                }
                let m = r.mesh.as_ref().expect("checked");
                super::sph_meshes::fill_mesh_region(scene, k, m, clip, settings, domain, velocity, particles)?
            }
            (Some(c), clip) => {
                let cylinder = region_cylinder(&f("cylinder"), c, settings.dimension)?;
                let first = particles.len();
                let added = add_fluid_cylinder(particles, settings, &cylinder, clip, velocity);
                if !particles.position[first..].iter().all(|&x| inside(x)) {
                    return Err(SceneError::field(f("cylinder"), "must lie inside the domain"));
                }
                added
            }
            (None, Some(b)) => add_fluid_block(particles, settings, b, velocity),
            (None, None) => {
                return Err(SceneError::field(
                    format!("sph.regions[{k}]"),
                    "give the region's shape: box = { min = [...], max = [...] }, cylinder = { point, axis, radius, length } or mesh = { file = \"...\" } (with a box: the part inside it)",
                ));
            }
        };
        if added == 0 {
            return Err(SceneError::field(
                format!("sph.regions[{k}]"),
                format!("holds no fluid at spacing {}: make it at least one spacing wide", settings.spacing),
            ));
        }
    }
    Ok(())
}

/// A region's cylinder, checked: positive radius and length, a unit axis (in 2D along y).
pub(super) fn region_cylinder(field: &str, c: &SphCylinderSection, dimension: Dimension) -> Result<Cylinder, SceneError> {
    positive(&format!("{field}.radius"), c.radius)?;
    positive(&format!("{field}.length"), c.length)?;
    let axis = finite3(&format!("{field}.axis"), c.axis)?;
    if axis.length() == 0.0 {
        return Err(SceneError::field(format!("{field}.axis"), "must be a non-zero direction"));
    }
    let axis = axis.normalize();
    if dimension == Dimension::Two && axis.cross(DVec3::Y).length() > 1e-9 {
        return Err(SceneError::field(format!("{field}.axis"), "a 2D fluid moves in the x–z plane: the cylinder's axis must be y"));
    }
    Ok(Cylinder::new(finite3(&format!("{field}.point"), c.point)?, axis, c.radius, c.length, true))
}

/// What the walls clear fluid from (the wrong side of a cylinder, the space behind a rectangle
/// and within Δp/2 in front of it), and the moving walls, each with its `[[walls]]` index and the
/// largest speed of its wall particles at full rate.
#[derive(Default)]
struct FluidWalls {
    cylinders: Vec<Cylinder>,
    rectangles: Vec<Rectangle>,
    meshes: Vec<super::sph_meshes::FluidMesh>,
    moving: Vec<(usize, MovingWall, f64)>,
}

impl FluidWalls {
    fn leave_fluid_at(&self, x: DVec3, settings: &FluidSettings) -> bool {
        let (spacing, dimension) = (settings.spacing, settings.dimension);
        let thickness = wall_layers(settings) as f64 * spacing;
        self.cylinders.iter().all(|c| on_fluid_side(c, x, spacing, dimension))
            && !self.rectangles.iter().any(|r| r.covers(x, 0.5 * spacing))
            && self.meshes.iter().all(|m| m.leaves_fluid_at(x, spacing, thickness))
    }
}

/// The scene's walls as dummy particles on the fluid's side: a box's closed sides (the fluid
/// inside), an axis-aligned plane's layers behind it across the domain, a cylinder's rings, a
/// quad's and a mesh's layers behind their surfaces. Returns what the fluid must leave.
fn add_walls(
    scene: &Scene,
    compiled: &[Wall],
    settings: &FluidSettings,
    domain: &PeriodicBox,
    particles: &mut FluidParticles,
) -> Result<FluidWalls, SceneError> {
    let two_d = settings.dimension == Dimension::Two;
    let mut walls = FluidWalls::default();
    let thickness = wall_layers(settings) as f64 * settings.spacing;
    for (k, w) in scene.walls.iter().enumerate() {
        let f = |x: &str| format!("walls[{k}].{x}");
        let not_yet = || {
            SceneError::field(
                format!("walls[{k}]"),
                "the SPH fluid's walls are boxes, axis-aligned planes, rectangular quads, cylinders, lifters and meshes, static or moving, so far; servos and conveyors are not yet made into wall particles",
            )
        };
        if w.servo.is_some() || w.surface_velocity.is_some() {
            return Err(not_yet());
        }
        let first = particles.len();
        if let Some(b) = &w.box_ {
            if b.floor_hole.is_some() {
                return Err(SceneError::field(f("box.floor_hole"), "the SPH fluid's walls have no holes yet; leave it out"));
            }
            let min = in_plane(settings.dimension, finite3(&f("box.min"), b.min)?);
            let max = in_plane(settings.dimension, finite3(&f("box.max"), b.max)?);
            let (inner, closed) = box_sides(k, settings, domain, min, max)?;
            add_wall_box(particles, settings, inner, closed, DVec3::ZERO);
        } else if let Some(p) = &w.plane {
            let normal = finite3(&f("plane.normal"), p.normal)?;
            let point = finite3(&f("plane.point"), p.point)?;
            let axis = (0..3).find(|&a| normal[a] != 0.0 && (0..3).all(|b| b == a || normal[b] == 0.0));
            let Some(a) = axis.filter(|&a| !(two_d && a == 1)) else {
                return Err(SceneError::field(f("plane.normal"), "the SPH fluid takes planes along x, y or z (in 2D, x or z) so far"));
            };
            // The fluid is on the side the normal points to; the layers lie behind the plane.
            let (mut lower, mut upper) = (domain.min, domain.max);
            if normal[a] > 0.0 {
                (lower[a], upper[a]) = (point[a] - thickness, point[a]);
            } else {
                (lower[a], upper[a]) = (point[a], point[a] + thickness);
            }
            // Layers the fluid's grid cannot reach are left out.
            let (lower, upper) =
                (in_plane(settings.dimension, lower).max(settings.domain.min), in_plane(settings.dimension, upper).min(settings.domain.max));
            if (0..3).all(|a| (two_d && a == 1) || lower[a] < upper[a]) {
                add_wall_slab(particles, settings, lower, upper, DVec3::ZERO);
            }
        } else if let Some(q) = &w.quad {
            let mut corners = [DVec3::ZERO; 4];
            for (i, c) in q.corners.iter().enumerate() {
                corners[i] = finite3(&f(&format!("quad.corners[{i}]")), *c)?;
            }
            let Some(rectangle) = Rectangle::new(corners) else {
                return Err(SceneError::field(f("quad.corners"), "the SPH fluid's quads are rectangles: corners in order, with right angles"));
            };
            if two_d && !rectangle.edges.iter().any(|e| e.cross(DVec3::Y).length() <= 1e-9 * e.length()) {
                return Err(SceneError::field(f("quad.corners"), "a 2D fluid moves in the x–z plane: a quad across it needs one edge along y"));
            }
            // The layers lie behind the rectangle; the fluid is on the side its normal points to.
            add_wall_rectangle(particles, settings, &rectangle, DVec3::ZERO);
            walls.rectangles.push(rectangle);
        } else if let Some(c) = &w.cylinder {
            let c = crate::walls::cylinder(k, c)?;
            if two_d && c.axis.cross(DVec3::Y).length() > 1e-9 {
                return Err(SceneError::field(
                    f("cylinder.axis"),
                    "a 2D fluid moves in the x–z plane: a cylinder around it must have its axis along y",
                ));
            }
            add_wall_cylinder(particles, settings, &c, DVec3::ZERO);
            walls.cylinders.push(c);
        } else if w.mesh.is_some() {
            walls.meshes.push(super::sph_meshes::add_mesh_wall(k, compiled, settings, particles)?);
        } else if w.lifters.is_some() {
            let bars: Vec<&Wall> = compiled.iter().filter(|c| c.group as usize == k).collect();
            walls.meshes.extend(super::sph_meshes::add_lifters(k, &bars, settings, particles)?);
            // The bars turn with their drum: its motion, as the particles' lifters take it.
            if let Some(Wall { motion: Some(motion), timing, .. }) = bars.first().copied() {
                if two_d && motion_leaves_plane(motion) {
                    return Err(SceneError::field(f("on"), "a 2D fluid moves in the x–z plane: its drum must turn about y"));
                }
                add_moving(&mut walls, particles, first, k, MovingWall { motion: *motion, timing: *timing });
            }
            continue;
        } else {
            return Err(not_yet());
        }
        if let Some(m) = &w.motion {
            let (Some(motion), timing) = crate::walls::motion(k, m)? else { unreachable!("a motion section gives a motion") };
            if two_d && motion_leaves_plane(&motion) {
                return Err(SceneError::field(f("motion"), "a 2D fluid moves in the x–z plane: rotate about y, translate and oscillate within x–z"));
            }
            add_moving(&mut walls, particles, first, k, MovingWall { motion, timing });
        }
    }
    Ok(walls)
}

/// The wall particles from `first` on move as `wall`, the motion of `[[walls]]` entry `k`.
fn add_moving(walls: &mut FluidWalls, particles: &mut FluidParticles, first: usize, k: usize, wall: MovingWall) {
    let speed = particles.position[first..].iter().map(|&x| wall.motion.velocity_at(x).length()).fold(0.0, f64::max);
    walls.moving.push((k, wall, speed));
    particles.assign_moving_wall(first, walls.moving.len() as u16);
}

/// Whether a motion would carry a 2D fluid's walls out of the x–z plane.
fn motion_leaves_plane(motion: &Motion) -> bool {
    match *motion {
        Motion::Rotate { axis, .. } => axis.cross(DVec3::Y).length() > 1e-9,
        Motion::Translate { velocity } => velocity.y != 0.0,
        Motion::Oscillate { direction, .. } => direction.y != 0.0,
    }
}

/// A box wall's fluid side and its closed sides: all but those on a periodic axis (where the
/// box is cut to the domain) and, in 2D, y. A side beyond the domain is refused: the fluid's
/// grid ends there.
fn box_sides(
    k: usize,
    settings: &FluidSettings,
    domain: &PeriodicBox,
    min: DVec3,
    max: DVec3,
) -> Result<(Aabb, tumble_sph::ClosedSides), SceneError> {
    let two_d = settings.dimension == Dimension::Two;
    let (mut inner, mut closed) = (Aabb::new(min, max), [[false; 2]; 3]);
    let slack = 1e-9 * (domain.max - domain.min).max_element();
    for a in 0..3 {
        if two_d && a == 1 {
            continue;
        }
        if domain.periodic[a] {
            (inner.min[a], inner.max[a]) = (domain.min[a], domain.max[a]);
            continue;
        }
        if min[a] < domain.min[a] - slack || max[a] > domain.max[a] + slack || max[a] <= min[a] {
            return Err(SceneError::field(
                format!("walls[{k}].box"),
                "a box around the SPH fluid must lie inside the domain (its walls are particles behind its sides; the fluid's grid ends at the domain)",
            ));
        }
        closed[a] = [true, true];
    }
    Ok((inner, closed))
}

/// Lattice sites in the box `min`–`max` at the fluid's spacing (its active axes).
fn sites(settings: &FluidSettings, min: DVec3, max: DVec3) -> f64 {
    (0..3)
        .filter(|&a| !(settings.dimension == Dimension::Two && a == 1))
        .map(|a| ((max[a] - min[a]) / settings.spacing + 1.0).max(0.0))
        .product::<f64>()
        .min(f64::MAX)
}

/// Refuses a fluid whose regions and walls would hold more particles than ids allow or memory
/// holds, before any is made: an upper bound from the regions' and walls' lattices in the domain.
fn check_counts(scene: &Scene, s: &SphSection, settings: &FluidSettings, domain: &PeriodicBox) -> Result<(), SceneError> {
    let (lo, hi) = (settings.domain.min, settings.domain.max);
    let clip = |min: V3, max: V3| (DVec3::from(min).max(lo), DVec3::from(max).min(hi));
    let mut total = 0.0;
    let per_volume = |v: f64| v / settings.spacing.powi(settings.dimension.count());
    // A region or a floating body: a cylinder's volume, or a box's lattice sites in the grid.
    let mut solid = |cylinder: Option<&SphCylinderSection>, bx: Option<&SphBoxSection>| {
        if let Some(c) = cylinder {
            let area = std::f64::consts::PI * c.radius * c.radius;
            total += per_volume(if settings.dimension == Dimension::Two { area } else { area * c.length.abs() }).min(f64::MAX);
        } else if let Some(b) = bx {
            let (min, max) = clip(b.min, b.max);
            total += sites(settings, min, max);
        }
    };
    for r in &s.regions {
        solid(r.cylinder.as_ref(), r.box_.as_ref());
    }
    for b in &s.floating {
        solid(b.cylinder.as_ref(), b.box_.as_ref());
    }
    for b in &s.inflows {
        solid(None, Some(&b.box_));
    }
    let thickness = wall_layers(settings) as f64 * settings.spacing;
    for (k, w) in scene.walls.iter().enumerate() {
        if let Some(b) = &w.box_ {
            let flat = |field: &str, x: V3| Ok::<_, SceneError>(in_plane(settings.dimension, finite3(&format!("walls[{k}].box.{field}"), x)?));
            let (inner, _) = box_sides(k, settings, domain, flat("min", b.min)?, flat("max", b.max)?)?;
            total += sites(settings, inner.min - thickness, inner.max + thickness) - sites(settings, inner.min, inner.max);
        } else if let Some(c) = &w.cylinder {
            // Rings of the shell, each around its circumference, along the length (3D).
            let around = std::f64::consts::TAU * (c.radius.abs() + thickness) / settings.spacing;
            let along = if settings.dimension == Dimension::Two { 1.0 } else { c.length.abs() / settings.spacing + 1.0 };
            total += (around * along * wall_layers(settings) as f64).min(f64::MAX);
        } else if let Some(q) = &w.quad {
            // Layers behind the rectangle: its area over Δp² (2D: its longer edge over Δp) each.
            let c: Vec<DVec3> = q.corners.iter().map(|&c| DVec3::from(c)).collect();
            let (a, b) = ((c[1] - c[0]).length(), (c[3] - c[0]).length());
            let each = if settings.dimension == Dimension::Two { a.max(b) / settings.spacing } else { a * b / settings.spacing.powi(2) };
            total += (each * wall_layers(settings) as f64).min(f64::MAX);
        } else if w.plane.is_some() {
            // A slab across the domain, a wall's thickness deep.
            let full = sites(settings, lo, hi);
            let deepest = (0..3).map(|a| hi[a] - lo[a]).fold(f64::INFINITY, f64::min).max(settings.spacing);
            total += full * (thickness / deepest).min(1.0);
        }
    }
    check_total("sph.spacing", total)
}

/// Refuses, naming `field`, a fluid that would hold about `total` particles: more than ids allow
/// or memory holds.
pub(super) fn check_total(field: &str, total: f64) -> Result<(), SceneError> {
    const MOST: f64 = u32::MAX as f64;
    const BYTES_PER_PARTICLE: f64 = 512.0;
    if total > MOST {
        return Err(SceneError::field(
            field,
            format!("the fluid and its walls would hold about {total:.3e} particles; a scene holds at most {MOST:.0} (32-bit ids)"),
        ));
    }
    if let Some(available) = crate::particles::available_memory()
        && total * BYTES_PER_PARTICLE > available.bytes
    {
        return Err(SceneError::field(
            field,
            format!(
                "the fluid and its walls would hold about {total:.3e} particles, which need about {:.1} GiB; there is {available}",
                total * BYTES_PER_PARTICLE / (1u64 << 30) as f64,
            ),
        ));
    }
    Ok(())
}
