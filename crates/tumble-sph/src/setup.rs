//! Filling a phase: fluid blocks at rest in hydrostatic balance, and the dummy-particle walls of a tank.

use tumble_geom::{Cylinder, DVec3};

use crate::eos::Tait;
use crate::particles::{
    Aabb, ClosedSides, FluidParticles, ParticleKind, Rectangle, cylinder_fill, cylinder_shell, lattice_points, rectangle_layers, wall_shell,
};
use crate::settings::FluidSettings;

/// Layers of wall particles so that a fluid particle touching the wall has a full kernel: ⌈2h/Δp⌉.
pub fn wall_layers(settings: &FluidSettings) -> usize {
    (2.0 * settings.h / settings.spacing - 1e-9).ceil() as usize
}

/// Adds a block of fluid on the lattice anchored at `region.min`, moving at `velocity`. With
/// gravity, the density starts hydrostatic below the block's own free surface (half a spacing
/// above its highest particle), so a column at rest starts at rest.
pub fn add_fluid_block(particles: &mut FluidParticles, settings: &FluidSettings, region: Aabb, velocity: DVec3) -> usize {
    let volume = settings.spacing.powi(settings.dimension.count());
    let points: Vec<(DVec3, f64)> =
        lattice_points(region, region.min, settings.spacing, settings.dimension).into_iter().map(|x| (x, volume)).collect();
    add_fluid_points(particles, settings, &points, velocity)
}

/// Adds the fluid filling a cylinder in rings ([`cylinder_fill`](crate::cylinder_fill)), only
/// the points inside `clip` when one is given (a drum filled to a level), moving at `velocity`,
/// hydrostatic as [`add_fluid_block`]'s.
pub fn add_fluid_cylinder(
    particles: &mut FluidParticles,
    settings: &FluidSettings,
    cylinder: &Cylinder,
    clip: Option<Aabb>,
    velocity: DVec3,
) -> usize {
    let two_d = settings.dimension == crate::Dimension::Two;
    let inside = |x: DVec3| clip.is_none_or(|b| (0..3).all(|k| (two_d && k == 1) || (x[k] >= b.min[k] && x[k] < b.max[k])));
    let points: Vec<(DVec3, f64)> = cylinder_fill(cylinder, settings.spacing, settings.dimension).into_iter().filter(|&(x, _)| inside(x)).collect();
    add_fluid_points(particles, settings, &points, velocity)
}

/// Adds fluid particles at `points`, each of mass ρ₀ times its volume, in hydrostatic balance
/// below the highest point's free surface (half a spacing above it).
pub fn add_fluid_points(particles: &mut FluidParticles, settings: &FluidSettings, points: &[(DVec3, f64)], velocity: DVec3) -> usize {
    let g = settings.gravity.length();
    let up = if g > 0.0 { -settings.gravity / g } else { DVec3::ZERO };
    let top = points.iter().map(|(x, _)| up.dot(*x)).fold(f64::NEG_INFINITY, f64::max) + 0.5 * settings.spacing;
    let eos = Tait::new(settings.rho0, settings.sound_speed);
    for &(x, volume) in points {
        let depth = top - up.dot(x);
        let rho = if g > 0.0 { eos.density(settings.rho0 * g * depth) } else { settings.rho0 };
        particles.push(ParticleKind::Fluid, x, velocity, rho, settings.rho0 * volume);
    }
    points.len()
}

/// Adds the dummy particles of a box's closed sides (a tank: `inner` is the fluid's side of the
/// walls), moving at `velocity`.
pub fn add_wall_box(particles: &mut FluidParticles, settings: &FluidSettings, inner: Aabb, closed: ClosedSides, velocity: DVec3) -> usize {
    push_walls(particles, settings, wall_shell(inner, closed, wall_layers(settings), settings.spacing, settings.dimension), velocity)
}

/// Adds the dummy particles of a cylinder (a drum with the fluid inside, or a pipe with it
/// outside), moving at `velocity`; see [`cylinder_shell`](crate::cylinder_shell).
pub fn add_wall_cylinder(particles: &mut FluidParticles, settings: &FluidSettings, cylinder: &Cylinder, velocity: DVec3) -> usize {
    push_walls(particles, settings, cylinder_shell(cylinder, wall_layers(settings), settings.spacing, settings.dimension), velocity)
}

/// Adds the dummy particles of a rectangular plate (a gate, a baffle) in layers behind it,
/// against its normal, moving at `velocity`; see [`rectangle_layers`](crate::rectangle_layers).
pub fn add_wall_rectangle(particles: &mut FluidParticles, settings: &FluidSettings, rectangle: &Rectangle, velocity: DVec3) -> usize {
    push_walls(particles, settings, rectangle_layers(rectangle, wall_layers(settings), settings.spacing, settings.dimension), velocity)
}

/// Adds wall particles on the lattice filling the box `lower`–`upper` (anchored at `lower`),
/// moving at `velocity`: a channel's plate.
pub fn add_wall_slab(particles: &mut FluidParticles, settings: &FluidSettings, lower: DVec3, upper: DVec3, velocity: DVec3) -> usize {
    push_walls(particles, settings, lattice_points(Aabb::new(lower, upper), lower, settings.spacing, settings.dimension), velocity)
}

/// Adds wall particles at `points`, at rest density and lattice mass, moving at `velocity`.
pub fn push_walls(particles: &mut FluidParticles, settings: &FluidSettings, points: Vec<DVec3>, velocity: DVec3) -> usize {
    let mass = settings.particle_mass();
    for &x in &points {
        particles.push(ParticleKind::Wall, x, velocity, settings.rho0, mass);
    }
    points.len()
}

/// Fills inflow buffer `k` of `settings` with its particles, on the lattice anchored at its
/// box's low corner, moving at the inflow velocity, at rest density.
pub fn add_inflow(particles: &mut FluidParticles, settings: &FluidSettings, k: usize) -> usize {
    let inflow = &settings.inflows[k];
    let first = particles.len();
    let region = inflow.buffer.region;
    let added = push_walls(particles, settings, lattice_points(region, region.min, settings.spacing, settings.dimension), inflow.velocity());
    particles.assign_moving_wall(first, settings.inflow_wall_number(k));
    added
}
