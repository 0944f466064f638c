//! The analytic verification cases (docs/verification.md) at CI size: a projectile, the
//! linear spring-dashpot collision, the Hertz impact and a sphere resting on a plane.

use crate::Observable::*;
use crate::Tolerance;
use crate::scenes::replaced;
use glam::DVec3;
use tumble::verify::*;
use tumble_integrate::Integrator;
use tumble_scene::schema::BackendName;

/// Case 8's sphere thrown up from 0.5 m above its floor at [1, 0, 2] m/s, with steps of 1 ms:
/// velocity Verlet integrates a constant force exactly, so the track is the parabola to
/// rounding (symplectic Euler would be g t Δt / 2 low).
pub fn a_projectile_follows_its_parabola_exactly(backend: BackendName) {
    let text = replaced(SLIDE_TO_ROLL, "positions = [[0.0, 0.0, 0.04999948636]]", "positions = [[0.0, 0.0, 0.5]]");
    let text = replaced(&text, "velocity = [1.0, 0.0, 0.0]", "velocity = [1.0, 0.0, 2.0]");
    let t = trajectory_on(backend, scene_with(&text, Integrator::Verlet, Some(1e-3)));
    let (x0, v0, g) = (DVec3::new(0.0, 0.0, 0.5), DVec3::new(1.0, 0.0, 2.0), DVec3::new(0.0, 0.0, -G));
    let (mut dx, mut dv) = (0.0f64, 0.0f64);
    for (time, rows) in &t.samples {
        dx = dx.max((rows[0].position - (x0 + v0 * time + 0.5 * g * time * time)).length());
        dv = dv.max((rows[0].velocity - (v0 + g * time)).length());
    }
    println!("{backend:?}: {} steps, worst |x − x(t)| {dx:.2e} m, |v − v(t)| {dv:.2e} m/s", t.samples.len() - 1);
    assert!(t.samples.len() > 100, "the projectile should fly the whole run");
    assert!(dx < Tolerance::on(FreeFallPosition, backend), "position off the parabola by {dx:e} m");
    assert!(dv < Tolerance::on(FreeFallVelocity, backend), "velocity off v0 + g t by {dv:e} m/s");
}

/// Worst |x − x(t)| / (|u0| / b) of case 2's damped collision while in contact, at t_col/`divisor`.
fn oscillator_error(backend: BackendName, divisor: f64) -> f64 {
    let (d, u0, e) = (0.1, -2.0, 0.8);
    let t_col = normal_collision_time(e);
    // The underdamped oscillator: e = exp(a π / b), t_col = π / b.
    let (a, b) = (e.ln() / t_col, std::f64::consts::PI / t_col);
    let dt = t_col / divisor;
    let t = trajectory_on(backend, scene_with(NORMAL_COLLISION, Integrator::Verlet, Some(dt)));
    let exact = |time: f64| d + (a * time).exp() * (u0 / b) * (b * time).sin();
    t.samples
        .iter()
        .filter(|(time, _)| *time < t_col - 1.5 * dt)
        .map(|(time, r)| (r[0].position.x - exact(*time)).abs() / (u0.abs() / b))
        .fold(0.0, f64::max)
}

/// Case 2 inside the contact: x(t) is the damped oscillator's, converging at Verlet's second order.
pub fn a_damped_linear_contact_follows_the_oscillator_at_second_order(backend: BackendName) {
    let (coarse, fine) = (oscillator_error(backend, 16.0), oscillator_error(backend, 32.0));
    let order = (coarse / fine).log2();
    println!("{backend:?}: x(t) error {coarse:.3e} at t_col/16, {fine:.3e} at t_col/32: order {order:.2}");
    assert!(fine < Tolerance::on(OscillatorTrajectory, backend), "x(t) off the oscillator by {fine:e} of |u0|/b");
    assert!((order - 2.0).abs() < Tolerance::on(ConvergenceOrder, backend), "order {order} (Verlet is second order)");
}

/// Case 2 after the contact: a linear spring-dashpot returns e |u0| (and the undamped one |u0|).
pub fn linear_collisions_rebound_at_e_times_the_impact_speed(backend: BackendName) {
    let rebound = |text: &str| trajectory_on(backend, scene_with(text, Integrator::Verlet, None)).samples.last().unwrap().1[0].velocity.x;
    let (damped, elastic) = (rebound(NORMAL_COLLISION), rebound(ELASTIC_COLLISION));
    println!("{backend:?}: rebound e = 0.8: {damped} m/s (1.6), e = 1: {elastic} m/s (2)");
    assert!((damped / 1.6 - 1.0).abs() < Tolerance::on(DampedRebound, backend), "e = 0.8 rebounds at {damped} m/s, not 1.6");
    assert!((elastic / 2.0 - 1.0).abs() < Tolerance::on(ElasticRebound, backend), "e = 1 rebounds at {elastic} m/s, not 2");
}

/// Case 7: δ_max, F_max, t_H and the rebound of two Hertz spheres against Hertz theory at the
/// plan's default step: within 0.2 of the Rayleigh time and 50 steps per Hertz contact.
pub fn a_hertz_impact_meets_hertz_theory(backend: BackendName) {
    let r = hertz_impact_on(backend, Integrator::Verlet, None);
    println!("{backend:?}: {r:?}");
    let rayleigh = tumble_contact::rayleigh_time(0.01, 2500.0, 1.0e7, 0.3);
    assert!(r.dt <= 0.2 * rayleigh * (1.0 + 1e-9), "default Δt {} is above 0.2 Δt_R = {}", r.dt, 0.2 * rayleigh);
    let steps = r.contact_time.1 / r.dt;
    assert!(steps >= 50.0 * (1.0 - 1e-6), "default Δt {} gives {steps} steps per Hertz contact, not 50", r.dt);
    for (name, (sim, theory)) in [("δ_max", r.max_overlap), ("F_max", r.max_force), ("t_H", r.contact_time), ("rebound", r.rebound_speed)] {
        assert!((sim / theory - 1.0).abs() < Tolerance::on(HertzImpact, backend), "{name}: {sim} vs Hertz {theory}");
    }
}

/// A sphere set down touching its floor at rest: its overlap peaks at (1 + e) m g / k one
/// contact time later (the damped oscillator from rest), then rests at m g / k without moving.
pub fn a_sphere_set_on_a_plane_rests_at_m_g_over_k(backend: BackendName) {
    let e = 0.5;
    let t_col = 50.0 * floor_dt(e);
    // Twenty contact times: the oscillation has decayed by e^20 = 1e-6.
    let floor = FloorScene {
        restitution: e,
        position: DVec3::new(0.0, 0.0, 0.5 * DIAMETER),
        ..FloorScene::incline(FrictionModel::History, 0.5, 0.0, 20.0 * t_col)
    };
    let t = trajectory_on(backend, floor.compile());
    let rest = sphere_mass() * G / 1.0e5;
    let overlaps: Vec<f64> = t.samples.iter().map(|(_, r)| 0.5 * DIAMETER - r[0].position.z).collect();
    let peak = parabola_peak(&overlaps);
    let last = &t.samples.last().unwrap().1[0];
    let (end, speed) = (0.5 * DIAMETER - last.position.z, last.velocity.length());
    println!(
        "{backend:?}: peak overlap {peak:.6e} ((1 + e) m g / k = {:.6e}), rest {end:.6e} (m g / k = {rest:.6e}), speed {speed:.1e}",
        (1.0 + e) * rest
    );
    assert!((peak / ((1.0 + e) * rest) - 1.0).abs() < Tolerance::on(PeakOverlap, backend), "peak overlap {peak} vs (1 + e) m g / k");
    assert!((end / rest - 1.0).abs() < Tolerance::on(RestOverlap, backend), "rests at overlap {end} vs m g / k = {rest}");
    assert!(speed < Tolerance::on(RestSpeed, backend), "still moving at {speed} m/s");
    // Nothing pushes it sideways.
    assert!(last.position.x.abs() + last.position.y.abs() < 1e-12, "drifted to {}", last.position);
}

/// The largest value of evenly spaced samples, refined by the parabola through it and its neighbours.
pub(crate) fn parabola_peak(y: &[f64]) -> f64 {
    let k = (1..y.len() - 1).max_by(|&a, &b| y[a].total_cmp(&y[b])).expect("three samples or more");
    let (y0, y1, y2) = (y[k - 1], y[k], y[k + 1]);
    let curvature = y0 - 2.0 * y1 + y2;
    if curvature == 0.0 { y1 } else { y1 - 0.125 * (y2 - y0).powi(2) / curvature }
}
