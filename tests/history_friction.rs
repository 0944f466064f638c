//! Tangential springs with history and rolling resistance against closed forms,
//! and where the history-free models fail (docs/physics.md, "Tangential force"). Case 8 with a
//! spring, and short runs of these on either backend, are in the suite (tumble-testkit).

mod common;

use glam::DVec3;
use tumble::verify::*;
use tumble::{RunError, RunOptions, Simulation, compile, parse_scene, run_compiled};
use tumble_testkit::scenes::test_scene;

#[test]
fn oblique_impacts_follow_coulomb_theory_while_sliding() {
    let (mu, e) = (0.1, 0.8);
    // Sliding throughout needs tan θ ≥ 7/2 μ (1 + e): θ ≥ 32.2° here.
    for model in [FrictionModel::History, FrictionModel::ViscousCoulomb] {
        for angle in [40.0, 50.0, 60.0, 70.0, 85.0] {
            let i = oblique_impact(model, false, mu, e, angle);
            let (vt, spin) = coulomb_impact(angle, mu, e);
            // The contact's finite duration and lever arm r − δ/2 leave ~1 % on the spin near the threshold.
            assert!((i.tangential / vt - 1.0).abs() < 5e-3, "{} at {angle}°: v_t'/v_t = {} vs {vt}", model.name(), i.tangential);
            assert!((i.spin / spin - 1.0).abs() < 1.5e-2, "{} at {angle}°: Rω'/v_t = {} vs {spin}", model.name(), i.spin);
            assert!((i.normal - e).abs() < 2e-3, "{} at {angle}°: v_n'/v_n = {}", model.name(), i.normal);
        }
    }
}

#[test]
fn hertz_mindlin_impacts_follow_coulomb_theory_with_the_measured_restitution() {
    // Tsuji damping gives only roughly e for Hertz: the theory uses the measured v_n'/v_n.
    for angle in [50.0, 70.0] {
        let i = oblique_impact(FrictionModel::History, true, 0.1, 0.8, angle);
        let (vt, spin) = coulomb_impact(angle, 0.1, i.normal);
        assert!((i.normal - 0.8).abs() < 0.05, "Hertz restitution {}", i.normal);
        assert!((i.tangential / vt - 1.0).abs() < 5e-3, "Hertz–Mindlin at {angle}°: v_t'/v_t = {} vs {vt}", i.tangential);
        assert!((i.spin / spin - 1.0).abs() < 1.5e-2, "Hertz–Mindlin at {angle}°: Rω'/v_t = {} vs {spin}", i.spin);
    }
    let scene = FloorScene { hertz: true, ..FloorScene::incline(FrictionModel::History, 0.5, 10.0, 0.1) }.compile();
    assert!(scene.plan.report.features.iter().any(|f| f.name == "tangential" && f.reason.contains("Hertz–Mindlin")));
}

#[test]
fn sticking_impacts_viscous_ends_rolling_history_springs_back() {
    // A history-free law ends a sticking impact rolling (5/7); the tangential spring
    // stores energy and returns it: the sphere leaves with v_t' < ω'R (spin overshoot).
    let v = oblique_impact(FrictionModel::ViscousCoulomb, false, 0.1, 0.8, 10.0);
    assert!((v.tangential - 5.0 / 7.0).abs() < 2e-3 && (v.spin - 5.0 / 7.0).abs() < 2e-3, "{v:?}");
    let h = oblique_impact(FrictionModel::History, false, 0.1, 0.8, 10.0);
    assert!(h.tangential < 0.6 && h.spin > 1.0, "history at 10°: {h:?}");
}

#[test]
fn history_holds_a_sphere_on_an_incline_that_history_free_models_creep_down() {
    let mu = 0.5; // atan μ = 26.6°
    let c_t = viscous_coefficient(0.8);
    for angle in [5.0, 15.0, 25.0] {
        let s = f64::to_radians(angle).sin();
        let held = creep_speed(FrictionModel::History, mu, angle, 1.0);
        assert!(held.abs() < 1e-9, "history creeps at {held} m/s on {angle}°");
        // Viscous-Coulomb creeps where c_t v = m g sin θ.
        let viscous = creep_speed(FrictionModel::ViscousCoulomb, mu, angle, 1.0);
        let theory = sphere_mass() * G * s / c_t;
        assert!((viscous / theory - 1.0).abs() < 0.01, "viscous-Coulomb creep {viscous} vs m g sinθ / c_t = {theory} on {angle}°");
        // Stick-limited cancels only the slip of the last step: it creeps at g sin θ Δt.
        let dt = floor_dt(0.8);
        let stick = creep_speed(FrictionModel::StickLimited, mu, angle, 1.0);
        assert!((stick / (G * s * dt) - 1.0).abs() < 0.02, "stick-limited creep {stick} vs g sinθ Δt = {} on {angle}°", G * s * dt);
        assert!(creep_speed(FrictionModel::DynamicOnly, mu, angle, 1.0) > 1e-6, "dynamic-only should drift on {angle}°");
    }
}

#[test]
fn rolls_at_five_sevenths_g_sin_theta_below_the_slip_threshold_and_slides_above() {
    let mu: f64 = 0.5;
    let threshold = (3.5 * mu).atan().to_degrees(); // 60.3°
    for angle in [20.0, 40.0, threshold - 2.0] {
        let t = f64::to_radians(angle);
        let m = incline_motion(FrictionModel::History, mu, 0.0, angle, 0.3);
        let a = 5.0 / 7.0 * G * t.sin();
        assert!((m.acceleration / a - 1.0).abs() < 1e-3, "{angle}°: a = {} vs 5/7 g sinθ = {a}", m.acceleration);
        assert!(m.slip < 1e-4, "{angle}°: slips at {} m/s", m.slip);
    }
    for angle in [threshold + 2.0, 70.0] {
        let t = f64::to_radians(angle);
        let m = incline_motion(FrictionModel::History, mu, 0.0, angle, 0.3);
        let a = G * (t.sin() - mu * t.cos());
        let spin = 2.5 * mu * G * t.cos();
        assert!((m.acceleration / a - 1.0).abs() < 1e-3, "{angle}°: a = {} vs g(sinθ − μcosθ) = {a}", m.acceleration);
        assert!((m.spin_acceleration / spin - 1.0).abs() < 1e-3, "{angle}°: R dω/dt = {} vs 5/2 μ g cosθ = {spin}", m.spin_acceleration);
        assert!(m.slip > 0.01, "{angle}°: should slide");
    }
}

#[test]
fn rolling_resistance_holds_below_tan_theta_equal_mu_r_and_rolls_above() {
    let mu_r: f64 = 0.1;
    let threshold = mu_r.atan().to_degrees(); // 5.71°
    for angle in [2.0, threshold - 0.7] {
        let m = incline_motion(FrictionModel::History, 0.5, mu_r, angle, 1.0);
        assert!(m.acceleration.abs() < 1e-6 && m.distance.abs() < 1e-4, "{angle}° with μ_r = {mu_r}: {m:?}");
    }
    for angle in [threshold + 0.8, 10.0] {
        let t = f64::to_radians(angle);
        let m = incline_motion(FrictionModel::History, 0.5, mu_r, angle, 1.0);
        let a = 5.0 / 7.0 * G * (t.sin() - mu_r * t.cos());
        assert!((m.acceleration / a - 1.0).abs() < 5e-3, "{angle}°: a = {} vs 5/7 g (sinθ − μ_r cosθ) = {a}", m.acceleration);
    }
    // Rolling resistance works with the history-free models too.
    let m = incline_motion(FrictionModel::ViscousCoulomb, 0.5, mu_r, 3.0, 1.0);
    assert!(m.acceleration.abs() < 1e-6, "viscous-Coulomb with μ_r on 3°: {m:?}");
}

/// Two spheres pressed together and sheared, no gravity: a pair's spring forces are
/// exactly equal and opposite, and a contact's spring is dropped when it opens.
#[test]
fn history_pair_forces_are_exactly_opposite_and_the_spring_ends_with_the_contact() {
    let d = 0.01;
    let p = |x: f64, vy: f64| common::P { x: DVec3::new(x, 0.0, 0.0), v: DVec3::new(-x * 20.0, vy, 0.0), w: DVec3::ZERO, d, de: d };
    let scene = common::scene_with_tangential(&[p(-0.0051, 0.3), p(0.0051, -0.2)], false, false, 0.1, "", "{ model = \"history\", friction = 0.3 }");
    assert!(scene.plan.model.history);
    let mut sim = tumble_cpu::CpuSimulation::new(scene, 1);
    let mut held = 0;
    for _ in 0..400 {
        sim.advance(1);
        let s = sim.contact_sums();
        assert_eq!(s[0].force, -s[1].force);
        held = held.max(sim.state().history.total());
    }
    assert_eq!(held, 2, "each side of the one contact holds the spring");
    assert!(sim.touching_pairs().is_empty(), "the pair should have separated");
    assert_eq!(sim.state().history.total(), 0, "the spring must go with the contact");
}

#[test]
fn history_slot_overflow_stops_the_run_with_a_clear_error() {
    // A sphere resting in the corner of a box touches three walls; one slot cannot hold them.
    let text = test_scene("history_overflow");
    let dir = std::env::temp_dir().join(format!("tumble-overflow-{}", std::process::id()));
    let options = RunOptions { out_dir: Some(dir.clone()), ..RunOptions::default() };
    match run_compiled(compile(&parse_scene(&text).unwrap()).unwrap(), &options) {
        Err(RunError::Capacity(msg)) => {
            assert!(msg.contains("history_slots = 1") && msg.contains("at least 3"), "{msg}");
        }
        other => panic!("expected a capacity error, got {other:?}"),
    }
    let summary = std::fs::read_to_string(dir.join("summary.json")).unwrap();
    assert!(summary.contains("contact history overflow"), "{summary}");
    let _ = std::fs::remove_dir_all(dir);
}

#[test]
fn plan_warns_when_a_quasi_static_scene_uses_history_free_friction() {
    let scene = FloorScene::incline(FrictionModel::ViscousCoulomb, 0.5, 10.0, 0.1).compile();
    assert!(scene.plan.report.warnings.iter().any(|w| w.contains("quasi-static")), "{:?}", scene.plan.report.warnings);
    let scene = FloorScene::incline(FrictionModel::History, 0.5, 10.0, 0.1).compile();
    assert!(!scene.plan.report.warnings.iter().any(|w| w.contains("quasi-static")), "{:?}", scene.plan.report.warnings);
    assert!(scene.plan.model.history && scene.plan.report.features.iter().any(|f| f.name == "history" && f.active));
    let _ = Simulation::new(scene, 1);
}

/// Case 9's falling, settling bed with tangential springs: the energy balance closes,
/// springs that end with their contact included (their stored energy is booked as dissipated).
#[test]
fn energy_balance_closes_with_tangential_springs() {
    for (label, tangential) in [
        ("Cundall–Strack", "tangential = { model = \"history\", friction = 0.4 }"),
        ("Cundall–Strack with rolling resistance", "tangential = { model = \"history\", friction = 0.4 }\nrolling_friction = 0.05"),
        (
            "Cundall–Strack with an EPSD2 rolling spring",
            "tangential = { model = \"history\", friction = 0.4 }\nrolling_friction = 0.05\nrolling_model = \"epsd2\"",
        ),
    ] {
        let text = ENERGY_BALANCE.replace("tangential = { model = \"viscous-coulomb\", friction = 0.4, viscous = 1.0 }", tangential);
        assert_ne!(text, ENERGY_BALANCE);
        let mut scene = parse_scene(&text).unwrap();
        scene.run.duration = 0.25;
        let compiled = compile(&scene).unwrap();
        assert!(compiled.plan.model.history);
        let steps = compiled.plan.run.steps;
        let mut sim = Simulation::new(compiled, 2);
        let e0 = sim.observables().mechanical_energy();
        sim.advance(steps);
        let o = sim.observables();
        let error = (o.mechanical_energy() + o.dissipated_energy - e0).abs() / e0;
        assert!(o.dissipated_energy > 0.3 * e0, "{label}: the bed should have settled");
        println!("{label}: energy balance {error:.3e} of E0, dissipated {:.3} E0", o.dissipated_energy / e0);
        assert!(error < 2e-3, "{label}: energy balance off by {error:.3e} of E0");
    }
}
