//! The [sph] section's floating bodies: their shapes, masses and starting motion, their wall
//! particles, and the fluid cleared from them.

use super::sph::{file_name, in_plane, plane_box, region_cylinder};
use super::{finite3, positive};
use crate::SceneError;
use crate::schema::*;
use glam::DVec3;
use tumble_geom::PeriodicBox;
use tumble_sph::{BodyShape, Dimension, FloatingBody, FluidParticles, FluidSettings, ParticleKind, wall_layers};

/// The floating bodies: each one's mass and inertia in `settings`, its wall particles (numbered
/// after the moving walls), and the fluid within half a spacing of it cleared. Returns their names.
pub(super) fn add_floating(
    s: &SphSection,
    settings: &mut FluidSettings,
    domain: &PeriodicBox,
    particles: &mut FluidParticles,
) -> Result<Vec<String>, SceneError> {
    let dimension = settings.dimension;
    let two_d = dimension == Dimension::Two;
    let mut names: Vec<String> = Vec::new();
    for (k, b) in s.floating.iter().enumerate() {
        let f = |x: &str| format!("sph.floating[{k}].{x}");
        let taken: Vec<&str> = names.iter().map(String::as_str).collect();
        file_name(f("name"), &b.name, &taken, "the body's", "floating_<name>.csv")?;
        let density = positive(&f("density"), b.density)?;
        let velocity = finite3(&f("velocity"), b.velocity)?;
        let spin = finite3(&f("angular_velocity"), b.angular_velocity)?;
        if two_d && (velocity.y != 0.0 || spin.x != 0.0 || spin.z != 0.0) {
            return Err(SceneError::field(
                f("velocity"),
                "a 2D body moves in the x–z plane and turns about y: velocity without y, angular_velocity along y only",
            ));
        }
        let shape = match (&b.box_, &b.cylinder) {
            (Some(bx), None) => BodyShape::Box(plane_box(&f("box"), bx, dimension)?),
            (None, Some(c)) => {
                let mut c = region_cylinder(&f("cylinder"), c, dimension)?;
                c.point = in_plane(dimension, c.point);
                BodyShape::Cylinder(c)
            }
            _ => {
                return Err(SceneError::field(
                    format!("sph.floating[{k}]"),
                    "give exactly one shape: box = { min, max } or cylinder = { point, axis, radius, length }",
                ));
            }
        };
        // Whether the box from `low` to `high` reaches more than `slack` past a closed side of
        // the domain, or is longer than a periodic axis (a 2D fluid's y left out).
        let beyond = |low: DVec3, high: DVec3, slack: f64| {
            (0..3).any(|a| {
                (!two_d || a != 1)
                    && if domain.periodic[a] {
                        high[a] - low[a] > domain.max[a] - domain.min[a]
                    } else {
                        low[a] < domain.min[a] - slack || high[a] > domain.max[a] + slack
                    }
            })
        };
        let outside = || SceneError::field(format!("sph.floating[{k}]"), "must lie inside the domain");
        // Checked on the shape's bounds before its particles are laid (a body far larger than
        // the domain would otherwise be filled with particles first), then on the particles.
        let (low, high) = bounds(&shape);
        if beyond(low, high, settings.spacing) {
            return Err(outside());
        }
        let points = shape.particles(wall_layers(settings), settings.spacing, dimension);
        if points.is_empty() {
            return Err(SceneError::field(
                format!("sph.floating[{k}]"),
                format!("holds no particle at spacing {}: make it at least one spacing across", settings.spacing),
            ));
        }
        if points.iter().any(|&x| beyond(x, x, 0.0)) {
            return Err(outside());
        }
        let mut body = FloatingBody::uniform(&shape, density, dimension);
        body.start.velocity = velocity;
        body.start.angular_velocity = spin;
        settings.floating.push(body);
        // The fluid keeps half a spacing from the body's surface, as the body's particles do.
        let margin = 0.5 * settings.spacing * (1.0 - 1e-9);
        particles.retain(|kind, x| kind == ParticleKind::Wall || !shape.covers(x, margin, dimension));
        let first = particles.len();
        for x in points {
            particles.push(ParticleKind::Wall, x, DVec3::ZERO, settings.rho0, settings.particle_mass());
        }
        particles.assign_moving_wall(first, settings.body_wall_number(k));
        names.push(b.name.clone());
    }
    Ok(names)
}

/// The corners of a box around the body.
fn bounds(shape: &BodyShape) -> (DVec3, DVec3) {
    match shape {
        BodyShape::Box(b) => (b.min, b.max),
        BodyShape::Cylinder(c) => {
            let end = c.point + c.axis * c.length;
            (c.point.min(end) - DVec3::splat(c.radius), c.point.max(end) + DVec3::splat(c.radius))
        }
    }
}
