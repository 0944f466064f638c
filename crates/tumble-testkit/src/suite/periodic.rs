//! Periodic boundaries: the potential energy follows a particle across every wrap (unwrapped
//! positions, from the periodic image counts), and a flow plane on a periodic axis counts every
//! pass of a stream, however many times it wrapped between two output rows.

use crate::Observable::*;
use crate::Tolerance;
use crate::scenes::{compiled, replaced, test_scene};
use glam::DVec3;
use tumble::{FlowCounter, Simulation};
use tumble_scene::schema::BackendName;

/// `scenes/test/periodic_incline.toml`: one sphere slides without friction down a plane
/// inclined at 20°, wrapping round x about a dozen times. Set at its resting overlap, its
/// kinetic + potential energy stays at its start (Verlet is exact for the constant force; f32
/// rounds each velocity increment), the
/// potential is −m g·x at the unwrapped position x + n L, and n counts the wraps of
/// x(t) = x0 + v0 t + ½ g_x t².
pub fn a_sphere_sliding_round_a_periodic_incline_keeps_its_energy(backend: BackendName) {
    let text = test_scene("periodic_incline");
    let (k, d, rho) = (1.0e5, 0.02, 7800.0);
    let m = rho * std::f64::consts::PI / 6.0 * d * d * d;
    let g = DVec3::new(3.3552, 0.0, -9.2184);
    let z0 = 0.5 * d - m * -g.z / k;
    let text = replaced(&text, "positions = [[0.025, 0.025, 0.01]]", &format!("positions = [[0.025, 0.025, {z0:?}]]"));
    let scene = compiled(&text);
    let (steps, dt, l) = (scene.plan.run.steps, scene.plan.model.dt, scene.plan.model.domain.extent());
    let mut sim = Simulation::on(backend, scene, 1).unwrap();
    let start = sim.observables();
    let (x0, v0) = (0.025, 1.0);
    let chunks = 20;
    let (mut worst, mut worst_potential) = (0.0f64, 0.0f64);
    for c in 1..=chunks {
        sim.advance(steps / chunks);
        let t = (c * (steps / chunks)) as f64 * dt;
        let o = sim.observables();
        let s = sim.state();
        let x = s.unwrapped(0, l);
        let travelled = x0 + v0 * t + 0.5 * g.x * t * t;
        // The wraps so far: the box's image the particle is in.
        assert_eq!(s.image[0], [(travelled / l.x).floor() as i32, 0, 0], "t = {t}: {x} for {travelled}");
        // f64 is exact to rounding; f32's biased velocity increments (above) walk x off by N² 2⁻²⁴ v Δt / 2.
        let off = match crate::Precision::of(backend) {
            crate::Precision::F64 => 1e-9,
            crate::Precision::F32 => 1e-3,
        };
        assert!((x.x - travelled).abs() < off, "t = {t}: unwrapped x {} against x0 + v0 t + ½ g t² = {travelled}", x.x);
        // The potential the backend reports is that of the unwrapped position (a missed wrap: m g_x L = 5.5e-3 J).
        let unwrapped = -m * g.dot(x);
        let scale = o.kinetic_energy + m * g.length() * (travelled - x0 + d);
        assert!(
            (o.potential_energy - unwrapped).abs() <= Tolerance::on(PeriodicPotential, backend) * scale,
            "t = {t}: potential {} against −m g·x_unwrapped {unwrapped}",
            o.potential_energy
        );
        worst_potential = worst_potential.max((o.potential_energy - unwrapped).abs() / scale);
        let drift = (o.kinetic_energy + o.potential_energy) - (start.kinetic_energy + start.potential_energy);
        worst = worst.max(drift.abs() / scale);
        assert!(drift.abs() <= Tolerance::on(PeriodicEnergy, backend) * scale, "t = {t}: kinetic + potential moved by {drift} J of {scale} J");
    }
    let wraps = sim.state().image[0][0];
    println!(
        "{backend:?}: {wraps} wraps, kinetic + potential held to {worst:.1e}, potential against −m g·x_unwrapped {worst_potential:.1e} of the scale"
    );
    assert!(wraps >= 10, "the sphere should wrap round x at least ten times, wrapped {wraps}");
}

/// `scenes/test/periodic_stream.toml`: a lattice of spheres streaming at v along a periodic
/// axis, 2.5 box lengths per output interval. The flow plane across it measures N m v / L_x,
/// ρ_mass v A, in every interval, to one particle's mass.
pub fn a_flow_plane_on_a_periodic_axis_measures_the_mass_flux_of_a_stream(backend: BackendName) {
    let scene = compiled(&test_scene("periodic_stream"));
    let (steps, dt, l) = (scene.plan.run.steps, scene.plan.model.dt, scene.plan.model.domain.extent());
    let mut sim = Simulation::on(backend, scene, 1).unwrap();
    let s = sim.state();
    let (n, m) = (s.len(), s.mass[0]);
    let v = 2.0;
    let expected = n as f64 * m * v / l.x;
    let mut flow = FlowCounter::new(&sim);
    let rows = 4;
    let mut total = 0.0;
    for _ in 0..rows {
        sim.advance(steps / rows);
        let (rate, mass) = flow.update(&sim)[0];
        let interval = (steps / rows) as f64 * dt;
        println!("{backend:?}: {rate:.6} kg/s through the plane, ρ v A = {expected:.6} kg/s");
        // One particle's crossing more or less is m / interval.
        assert!((rate - expected).abs() <= 1.01 * m / interval, "rate {rate} kg/s against ρ v A = {expected} kg/s");
        total = mass;
    }
    let through = expected * steps as f64 * dt;
    assert!((total - through).abs() <= Tolerance::on(Mass, backend) * through + 1.01 * m, "mass {total} kg against {through} kg");
    assert_eq!(n, 128);
}

/// `scenes/test/periodic_stream.toml` continued from a snapshot (through its bytes) after its
/// spheres have wrapped: the image counts travel with the snapshot (on the GPU in the device
/// image), so the continuation, its wraps and its potential are bit-identical to the original.
pub fn a_periodic_run_continued_from_a_snapshot_keeps_its_image_counts(backend: BackendName) {
    let scene = compiled(&test_scene("periodic_stream"));
    let steps = scene.plan.run.steps;
    let mut original = Simulation::on(backend, scene.clone(), 2).unwrap();
    original.advance(steps / 4);
    let bytes = original.snapshot().to_bytes();
    let images_then = original.state().image.clone();
    assert!(images_then.iter().all(|n| n[0] >= 1), "every sphere wrapped before the snapshot: {images_then:?}");
    original.advance(steps / 4);

    let mut restored = Simulation::on(backend, scene, 2).unwrap();
    restored.restore(&tumble::Snapshot::from_bytes(&bytes).unwrap()).unwrap();
    assert_eq!(restored.state().image, images_then, "the restored run has the snapshot's image counts");
    restored.advance(steps / 4);
    let (a, b) = (original.state(), restored.state());
    assert!(a.image.iter().zip(&images_then).all(|(now, then)| now[0] > then[0]), "the spheres wrapped again after the snapshot");
    assert_eq!(a.image, b.image);
    assert_eq!(original.snapshot().to_bytes(), restored.snapshot().to_bytes(), "the continued run differs from the original");
    assert_eq!(original.observables(), restored.observables());
}
