//! Floating bodies: Archimedes' draft, and the momentum and angular momentum the fluid and a
//! body exchange.

mod common;

use common::{G, restored_and_stepped, run_to, stepped_on};
use tumble_geom::{DVec3, PeriodicBox};
use tumble_sph::*;

/// The 2D settings of these cases: water, artificial viscosity, Fourtakas δ-SPH.
fn water(dp: f64, sound_speed: f64, gravity: DVec3, domain: PeriodicBox) -> FluidSettings {
    FluidSettings {
        dimension: Dimension::Two,
        spacing: dp,
        h: 1.5 * dp,
        rho0: 1000.0,
        mu: 1e-3,
        sound_speed,
        viscosity: Viscosity::Artificial { alpha: 0.02 },
        density_diffusion: DensityDiffusion::Fourtakas { delta: 0.1 },
        tensile_correction: false,
        xsph: 0.0,
        gravity,
        body_force: DVec3::ZERO,
        domain,
        moving_walls: Vec::new(),
        floating: Vec::new(),
        inflows: Vec::new(),
        outflows: Vec::new(),
    }
}

/// Adds `shape` as floating body with `density`, starting with `velocity` and `spin` (about y),
/// and leaves out the fluid within half a spacing of it.
fn add_body(settings: &mut FluidSettings, particles: &mut FluidParticles, shape: &BodyShape, density: f64, velocity: DVec3, spin: f64) {
    let dp = settings.spacing;
    particles.retain(|kind, x| kind == ParticleKind::Wall || !shape.covers(x, 0.5 * dp * (1.0 - 1e-9), settings.dimension));
    let mut body = FloatingBody::uniform(shape, density, settings.dimension);
    body.start.velocity = velocity;
    body.start.angular_velocity = DVec3::new(0.0, spin, 0.0);
    settings.floating.push(body);
    let first = particles.len();
    for x in shape.particles(wall_layers(settings), dp, settings.dimension) {
        particles.push(ParticleKind::Wall, x, DVec3::ZERO, settings.rho0, settings.particle_mass());
    }
    particles.assign_moving_wall(first, settings.body_wall_number(settings.floating.len() - 1));
}

/// A box 0.16 × 0.08 m in a 2D tank of water 0.2 m deep settles with the share of its height
/// under water that its density is of the water's (Archimedes): at half the water's density,
/// dropped in with a quarter of its height under water, it sinks to half; at a quarter, let go
/// with half its height under water, it rises to a quarter. Its draft (from the mean level far
/// from it and its mean bottom over the last two periods of its heave) is within a tenth of a spacing. A missing
/// factor in the force, the mass or the gravity would put it a spacing or more away.
#[test]
fn a_floating_box_settles_at_its_archimedes_draft() {
    for (density, start) in [(500.0, 0.25), (250.0, 0.5)] {
        archimedes(density, start);
    }
}

fn archimedes(density: f64, start: f64) {
    let (dp, depth, length) = (0.01, 0.2, 0.5);
    let (width, height) = (0.16, 0.08);
    let layers = 3.0 * dp;
    let domain = PeriodicBox { min: DVec3::new(-layers, 0.0, -layers), max: DVec3::new(length + layers, 0.0, 2.0 * depth), periodic: [false; 3] };
    // A stronger artificial viscosity damps the heave and the tank's sloshing within the run;
    // the equilibrium does not depend on it.
    let settings = water(dp, 10.0, DVec3::new(0.0, 0.0, -G), domain);
    let mut settings = FluidSettings { viscosity: Viscosity::Artificial { alpha: 0.1 }, ..settings };
    let mut particles = FluidParticles::default();
    add_fluid_block(&mut particles, &settings, Aabb::new(DVec3::ZERO, DVec3::new(length, 0.0, depth)), DVec3::ZERO);
    add_wall_box(
        &mut particles,
        &settings,
        Aabb::new(DVec3::ZERO, DVec3::new(length, 0.0, 2.0 * depth)),
        [[true, true], [false, false], [true, false]],
        DVec3::ZERO,
    );
    let bottom = depth - start * height;
    let x0 = 0.5 * (length - width);
    let shape = BodyShape::Box(Aabb::new(DVec3::new(x0, 0.0, bottom), DVec3::new(x0 + width, 0.0, bottom + height)));
    add_body(&mut settings, &mut particles, &shape, density, DVec3::ZERO, 0.0);
    let mut phase = FluidPhase::new(settings, particles).unwrap();
    let dt = TimeStepLimits::planned(phase.settings()).dt();
    // The heave and the sloshing it sets off have a period of about 0.7 s: average over two.
    let (settle, average) = (2.0, 1.4);
    run_to(&mut phase, settle, dt);
    let (mut sum_bottom, mut sum_level, mut samples) = (0.0, 0.0, 0.0);
    let mut lowest: f64 = f64::INFINITY;
    while phase.time() < settle + average - 1e-12 {
        let next = phase.time() + 0.01;
        run_to(&mut phase, next, dt);
        let body = phase.bodies()[0];
        sum_bottom += body.centre.z - 0.5 * height;
        // The level 0.08 m from either end, clear of the body's edge by twice that.
        let level = 0.5
            * (phase.water_height(DVec3::new(0.08, 0.0, 0.0), 2.0 * depth) + phase.water_height(DVec3::new(length - 0.08, 0.0, 0.0), 2.0 * depth));
        sum_level += level;
        samples += 1.0;
        lowest = lowest.min(body.centre.z);
        assert!(body.orientation.to_scaled_axis().length() < 0.05, "the box turned over: {:?}", body.orientation);
    }
    let draft = (sum_level - sum_bottom) / samples;
    let expected = density / 1000.0 * height;
    println!(
        "draft {draft:.5} m, expected {expected:.5} m ({:+.3} spacings); level {:.5} m; lowest centre {lowest:.5} m",
        (draft - expected) / dp,
        sum_level / samples
    );
    assert!((draft - expected).abs() < 0.1 * dp, "the box floats with a draft of {draft:.5} m; Archimedes gives {expected:.5} m");
}

/// A body moving and turning through still fluid in a periodic 2D box without gravity: the
/// momentum of fluid and body together stays what it was to round-off, while the body hands a
/// good part of its own to the fluid. Fluid and body exchange equal and opposite forces.
#[test]
fn fluid_and_body_conserve_momentum_to_round_off() {
    let (dp, side) = (0.01, 0.2);
    let domain = PeriodicBox { min: DVec3::ZERO, max: DVec3::new(side, 0.0, side), periodic: [true, false, true] };
    let mut settings = water(dp, 5.0, DVec3::ZERO, domain);
    let mut particles = FluidParticles::default();
    add_fluid_block(&mut particles, &settings, Aabb::new(DVec3::ZERO, DVec3::new(side, 0.0, side)), DVec3::ZERO);
    let shape = BodyShape::Box(Aabb::new(DVec3::new(0.07, 0.0, 0.08), DVec3::new(0.13, 0.0, 0.12)));
    let velocity = DVec3::new(0.3, 0.0, 0.1);
    add_body(&mut settings, &mut particles, &shape, 700.0, velocity, 4.0);
    let mut phase = FluidPhase::new(settings, particles).unwrap();
    let mass = phase.settings().floating[0].mass;
    let momentum = |phase: &FluidPhase| phase.observables().momentum + mass * phase.bodies()[0].velocity;
    let before = momentum(&phase);
    let dt = TimeStepLimits::planned(phase.settings()).dt();
    run_to(&mut phase, 0.1, dt);
    let drift = (momentum(&phase) - before).length();
    let handed = phase.observables().momentum.length();
    let scale = mass * velocity.length();
    println!("{} steps: momentum moved by {drift:.3e} of {scale:.3e} kg m/s; the fluid took {handed:.3e}", phase.steps());
    assert!(drift < 1e-12 * scale, "fluid + body momentum drifted by {drift:.3e} kg m/s ({:.2e} of the body's)", drift / scale);
    assert!(handed > 0.1 * scale, "the body handed only {handed:.3e} kg m/s to the fluid");
}

/// A drop of water in free space with a box turning inside it, off its centre: the angular
/// momentum of the drop and the box (orbital and spin) changes by less than 10⁻⁴ of the box's
/// spin while the box hands a fifth or more of its spin to the water. The pressure and the
/// artificial viscosity act along the line between two particles, so only the time step's
/// error remains; a torque taken about the wrong point, or with the wrong sign, breaks it.
#[test]
fn a_turning_body_and_a_drop_conserve_angular_momentum() {
    let (dp, radius, spin) = (0.01, 0.1, 6.0);
    let reach = 2.0 * radius;
    let domain = PeriodicBox { min: DVec3::new(-reach, 0.0, -reach), max: DVec3::new(reach, 0.0, reach), periodic: [false; 3] };
    let mut settings = water(dp, 5.0, DVec3::ZERO, domain);
    let mut particles = FluidParticles::default();
    add_fluid_cylinder(&mut particles, &settings, &tumble_geom::Cylinder::new(DVec3::ZERO, DVec3::Y, radius, 1.0, true), None, DVec3::ZERO);
    let shape = BodyShape::Box(Aabb::new(DVec3::new(-0.01, 0.0, -0.04), DVec3::new(0.05, 0.0, 0.0)));
    add_body(&mut settings, &mut particles, &shape, 1000.0, DVec3::ZERO, spin);
    let mut phase = FluidPhase::new(settings, particles).unwrap();
    let body = phase.settings().floating[0];
    let angular_momentum = |phase: &FluidPhase| {
        let p = phase.particles();
        let fluid: DVec3 = (0..p.len()).filter(|&i| p.kind[i] == ParticleKind::Fluid).map(|i| p.mass[i] * p.position[i].cross(p.velocity[i])).sum();
        let b = phase.bodies()[0];
        fluid + body.mass * b.centre.cross(b.velocity) + DVec3::new(0.0, body.inertia[1].y * b.angular_velocity.y, 0.0)
    };
    let before = angular_momentum(&phase);
    let dt = TimeStepLimits::planned(phase.settings()).dt();
    run_to(&mut phase, 0.1, dt);
    let change = (angular_momentum(&phase) - before).length();
    let spin_left = phase.bodies()[0].angular_velocity.y / spin;
    println!(
        "{} steps: angular momentum changed by {:.3e} of {:.3e}; the box kept {spin_left:.3} of its spin",
        phase.steps(),
        change,
        before.length()
    );
    assert!(change < 1e-4 * before.length(), "angular momentum changed by {change:.3e} of {:.3e}", before.length());
    assert!(spin_left < 0.8, "the box kept {spin_left:.3} of its spin: the water barely took any");
}

/// The box of the momentum case: one thread and three give the same bits, and a phase restored
/// from a snapshot halfway continues exactly as the one it was taken from.
#[test]
fn a_floating_body_is_deterministic_and_restarts_bit_identically() {
    let (dp, side) = (0.01, 0.2);
    let domain = PeriodicBox { min: DVec3::ZERO, max: DVec3::new(side, 0.0, side), periodic: [true, false, true] };
    let mut settings = water(dp, 5.0, DVec3::new(0.0, 0.0, -G), domain);
    let mut particles = FluidParticles::default();
    add_fluid_block(&mut particles, &settings, Aabb::new(DVec3::ZERO, DVec3::new(side, 0.0, side)), DVec3::ZERO);
    let shape = BodyShape::Cylinder(tumble_geom::Cylinder::new(DVec3::new(0.1, 0.0, 0.1), DVec3::Y, 0.03, 1.0, false));
    add_body(&mut settings, &mut particles, &shape, 700.0, DVec3::new(0.3, 0.0, 0.1), 4.0);
    let dt = TimeStepLimits::planned(&settings).dt();
    let make = || FluidPhase::new(settings.clone(), particles.clone()).unwrap();
    let (one, three) = (stepped_on(1, 60, dt, make), stepped_on(3, 60, dt, make));
    assert!(one.particles() == three.particles() && one.bodies() == three.bodies(), "1 and 3 threads differ");
    let restored = restored_and_stepped(&stepped_on(2, 30, dt, make), 30, dt, make);
    assert!(restored.particles() == one.particles() && restored.bodies() == one.bodies(), "the restored phase went its own way");
    assert!(one.bodies()[0].velocity != DVec3::new(0.3, 0.0, 0.1), "the body never felt the fluid");
}
