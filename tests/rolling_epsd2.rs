//! EPSD2 rolling resistance (docs/physics.md, "Rolling resistance"): a sphere on a floor
//! rocks on its rolling spring below μ_r R* F_n and rolls against the constant-torque
//! deceleration above it; an incline holds below tan θ = μ_r; the rolling torque is history
//! and survives a restart bit for bit.

use glam::DVec3;
use tumble::verify::*;
use tumble::{Simulation, compile};
use tumble_contact::{SpringLaw, TangentialLaw};
use tumble_scene::schema::{RollingModelName, Scene};
use tumble_state::{SNAPSHOT_VERSION, Snapshot};

const MU_R: f64 = 0.1;
const R: f64 = 0.5 * DIAMETER;
const K_N: f64 = 1.0e5;

/// A sphere rolling without slip along +x at `speed` on the flat floor, or at rest on an incline.
fn scene(model: RollingModelName, angle_deg: f64, speed: f64, restitution: f64, duration: f64) -> Scene {
    let mut floor = FloorScene::incline(FrictionModel::History, 0.5, angle_deg, duration);
    floor.rolling_friction = MU_R;
    floor.restitution = restitution;
    floor.velocity = DVec3::new(speed, 0.0, 0.0);
    let mut scene = floor.parsed();
    scene.contact.as_mut().unwrap().rolling_model = Some(model);
    // Rolling: the contact point at −R ẑ is at rest, v + ω × (−R ẑ) = 0.
    scene.particles[0].angular_velocity = Some([0.0, speed / R, 0.0].into());
    scene
}

/// ω_y sampled every step over `steps`, with the times.
fn spin_history(sim: &mut Simulation, steps: u64) -> Vec<(f64, f64)> {
    (0..steps)
        .map(|_| {
            sim.advance(1);
            (sim.time(), sim.tracks()[0].angular_velocity.y)
        })
        .collect()
}

#[test]
fn saturated_epsd2_spring_stops_a_rolling_sphere_at_the_constant_torque_deceleration() {
    let decel = |model| {
        let compiled = compile(&scene(model, 0.0, 0.5, 0.8, 0.3)).unwrap();
        let steps = compiled.plan.run.steps;
        let mut sim = Simulation::new(compiled, 1);
        let e0 = sim.observables().mechanical_energy();
        sim.advance(steps / 5);
        let (t0, v0) = (sim.time(), sim.tracks()[0].velocity.x);
        sim.advance(steps - steps / 5);
        let (t1, v1) = (sim.time(), sim.tracks()[0].velocity.x);
        let o = sim.observables();
        let balance = (o.mechanical_energy() + o.dissipated_energy - e0).abs() / e0;
        ((v0 - v1) / (t1 - t0), balance)
    };
    let theory = 5.0 / 7.0 * MU_R * G;
    let (epsd2, balance) = decel(RollingModelName::Epsd2);
    let (constant, constant_balance) = decel(RollingModelName::Constant);
    println!(
        "deceleration: EPSD2 {epsd2:.6e}, constant {constant:.6e}, 5/7 μ_r g = {theory:.6e}; energy balance EPSD2 {balance:.2e}, constant {constant_balance:.2e} of E0"
    );
    assert!((epsd2 / theory - 1.0).abs() < 1e-3, "EPSD2 deceleration {epsd2} vs 5/7 μ_r g = {theory}");
    assert!((epsd2 / constant - 1.0).abs() < 1e-3, "EPSD2 {epsd2} vs constant torque {constant}");
    // The integrator's own error (the constant-torque model's is of the same size) bounds it.
    assert!(balance < 2e-5, "energy books off by {balance:.3e} of E0");
}

#[test]
fn below_the_limit_the_sphere_rocks_at_the_rolling_spring_frequency() {
    // ω_0 √(I_c k_r) = 0.4 of μ_r R m g: the spring never saturates. e = 1: no damping.
    let w0 = 0.01;
    let compiled = compile(&scene(RollingModelName::Epsd2, 0.0, w0 * R, 1.0, 0.1)).unwrap();
    let TangentialLaw::History { spring: SpringLaw::Linear { stiffness: k_t, .. }, .. } = compiled.plan.model.pairs[0].tangential else {
        panic!("linear history law expected")
    };
    let m = sphere_mass();
    let i = 0.4 * m * R * R;
    let k_r = 2.25 * K_N * MU_R * MU_R * R * R;
    // Centre x and rotation φ coupled by the tangential spring at the contact point:
    // det(K − ω² M) = 0 with M = diag(m, I), K = [[k_t, k_t R], [k_t R, k_t R² + k_r]]; the slow root.
    let (a, b, c) = (m * i, -(k_t * i + m * (k_t * R * R + k_r)), k_t * k_r);
    let omega2 = (-b - (b * b - 4.0 * a * c).sqrt()) / (2.0 * a);
    let theory = 2.0 * std::f64::consts::PI / omega2.sqrt();
    let rigid = 2.0 * std::f64::consts::PI * (1.4 * m * R * R / k_r).sqrt();
    let steps = compiled.plan.run.steps;
    let mut sim = Simulation::new(compiled, 1);
    let samples = spin_history(&mut sim, steps);
    // Downward zero crossings of ω_y, linearly interpolated.
    let crossings: Vec<f64> =
        samples.windows(2).filter(|w| w[0].1 > 0.0 && w[1].1 <= 0.0).map(|w| w[0].0 + (w[1].0 - w[0].0) * w[0].1 / (w[0].1 - w[1].1)).collect();
    assert!(crossings.len() >= 5, "only {} oscillations", crossings.len());
    let measured = (crossings[crossings.len() - 1] - crossings[0]) / (crossings.len() - 1) as f64;
    let amplitude = samples.iter().map(|s| s.1.abs()).fold(0.0, f64::max);
    println!(
        "rocking period {measured:.6e} s, theory {theory:.6e} s (rigid contact 2π√(I_c/k_r) = {rigid:.6e} s), peak |ω| {amplitude:.4e} of ω0 = {w0}"
    );
    assert!((measured / theory - 1.0).abs() < 2e-3, "period {measured} vs {theory}");
    assert!(amplitude <= 1.01 * w0, "elastic rocking cannot gain energy: {amplitude}");
}

#[test]
fn epsd2_holds_a_sphere_below_tan_theta_equal_mu_r_and_rolls_above() {
    let threshold = MU_R.atan().to_degrees(); // 5.71°
    let run = |angle: f64| {
        let compiled = compile(&scene(RollingModelName::Epsd2, angle, 0.0, 0.8, 1.0)).unwrap();
        let steps = compiled.plan.run.steps;
        let mut sim = Simulation::new(compiled, 1);
        sim.advance(steps / 5);
        let a = sim.tracks()[0];
        sim.advance(steps - steps / 5);
        let b = sim.tracks()[0];
        ((b.velocity.x - a.velocity.x) / (0.8 * 1.0), b.position.x - a.position.x)
    };
    for angle in [2.0, threshold - 0.7] {
        let (acc, distance) = run(angle);
        println!("{angle:.2}°: held, moved {distance:.3e} m");
        // The spring holds the sphere a small elastic rotation M/k_r down the slope.
        assert!(distance.abs() < 1e-5, "{angle}° with μ_r = {MU_R}: moved {distance} m (a = {acc})");
    }
    for angle in [threshold + 0.8, 10.0] {
        let t = f64::to_radians(angle);
        let (acc, _) = run(angle);
        let theory = 5.0 / 7.0 * G * (t.sin() - MU_R * t.cos());
        println!("{angle:.2}°: a = {acc:.6e} vs {theory:.6e}");
        assert!((acc / theory - 1.0).abs() < 5e-3, "{angle}°: a = {acc} vs 5/7 g (sinθ − μ_r cosθ) = {theory}");
    }
}

#[test]
fn a_restart_continues_the_rocking_bit_for_bit_with_the_rolling_torque_in_the_snapshot() {
    let compiled = compile(&scene(RollingModelName::Epsd2, 0.0, 0.01 * R, 1.0, 0.02)).unwrap();
    let mut sim = Simulation::new(compiled.clone(), 1);
    sim.advance(300);
    let snapshot = Snapshot::from_bytes(&sim.snapshot().to_bytes()).unwrap();
    let h = &snapshot.state.history;
    assert!(h.of(0).any(|(_, s)| s.roll != DVec3::ZERO && s.roll_energy > 0.0), "no rolling torque in the snapshot");
    sim.advance(400);
    let mut restarted = Simulation::new(compiled, 1);
    restarted.restore(&snapshot).unwrap();
    restarted.advance(400);
    let bits = |s: &Simulation| {
        let t = s.tracks()[0];
        [t.position, t.velocity, t.angular_velocity].map(|v| v.to_array().map(f64::to_bits))
    };
    assert_eq!(bits(&sim), bits(&restarted));
    assert_eq!(sim.state().history, restarted.state().history);
    // A snapshot of the layout before the rolling torque is refused with a clear line.
    let mut old = snapshot.to_bytes();
    old[8..12].copy_from_slice(&(SNAPSHOT_VERSION - 1).to_le_bytes());
    let err = Snapshot::from_bytes(&old).unwrap_err().to_string();
    assert!(err.contains(&format!("version {}", SNAPSHOT_VERSION - 1)), "{err}");
}

#[test]
fn epsd2_without_history_is_refused_naming_the_field() {
    let mut floor = FloorScene::incline(FrictionModel::ViscousCoulomb, 0.5, 0.0, 0.1);
    floor.rolling_friction = MU_R;
    let mut s = floor.parsed();
    s.contact.as_mut().unwrap().rolling_model = Some(RollingModelName::Epsd2);
    let err = compile(&s).unwrap_err().to_string();
    println!("{err}");
    assert!(err.contains("contact.rolling_model") && err.contains("history"), "{err}");
}

#[test]
fn the_gpu_backend_refuses_epsd2_naming_the_field() {
    let compiled = compile(&scene(RollingModelName::Epsd2, 0.0, 0.0, 0.8, 0.1)).unwrap();
    let Err(err) = Simulation::gpu(compiled) else { panic!("the GPU backend ran EPSD2") };
    let err = err.to_string();
    assert!(err.contains("contact.rolling_model") && err.contains("cpu"), "{err}");
}
