//! Tangential springs with history and rolling resistance against closed forms, over runs
//! short enough for a software GPU adapter.

use crate::Observable::*;
use crate::Tolerance;
use tumble::verify::*;
use tumble_integrate::Integrator;
use tumble_scene::schema::BackendName;

const HISTORY: &str = "{ model = \"history\", friction = 0.5 }";

/// Case 8 with a tangential spring: sliding at μ g, then rolling at 5/7 of the initial speed.
pub fn slide_to_roll_at_five_sevenths(backend: BackendName) {
    let r = slide_to_roll_with(backend, Integrator::Verlet, 50.0, Some(HISTORY));
    println!("{r:?}");
    assert!((r.final_speed_ratio - 5.0 / 7.0).abs() < Tolerance::on(SpeedRatio, backend), "final v/v0 = {} (theory 5/7)", r.final_speed_ratio);
    assert!(r.sliding_error < Tolerance::on(SlidingDeceleration, backend), "sliding deceleration off μg by {}", r.sliding_error);
    let (measured, theory) = r.roll_time;
    assert!((measured - theory).abs() < Tolerance::on(RollTime, backend) * theory, "rolling starts at {measured} s, theory {theory} s");
}

/// Oblique impacts that slide throughout: v_t' and Rω' as Coulomb theory gives them.
pub fn oblique_impacts_follow_coulomb_theory_while_sliding(backend: BackendName) {
    let (mu, e) = (0.1, 0.8);
    let angle = 50.0;
    let i = oblique_impact_on(backend, FrictionModel::History, false, mu, e, angle);
    let (vt, spin) = coulomb_impact(angle, mu, e);
    println!("{angle}°: {i:?} theory v_t {vt} spin {spin}");
    assert!((i.tangential / vt - 1.0).abs() < Tolerance::on(TangentialRatio, backend), "{angle}°: v_t'/v_t = {} vs {vt}", i.tangential);
    assert!((i.spin / spin - 1.0).abs() < Tolerance::on(SpinRatio, backend), "{angle}°: Rω'/v_t = {} vs {spin}", i.spin);
    assert!((i.normal - e).abs() < Tolerance::on(Restitution, backend), "{angle}°: v_n'/v_n = {}", i.normal);
    // Hertz–Mindlin with the measured restitution.
    let i = oblique_impact_on(backend, FrictionModel::History, true, mu, e, 60.0);
    let (vt, spin) = coulomb_impact(60.0, mu, i.normal);
    assert!(
        (i.tangential / vt - 1.0).abs() < Tolerance::on(TangentialRatio, backend) && (i.spin / spin - 1.0).abs() < Tolerance::on(SpinRatio, backend),
        "Hertz–Mindlin 60°: {i:?} vs {vt} {spin}"
    );
}

/// Damped Hertz–Mindlin impacts that slide throughout (e = 0.5, μ = 0.4, the regime where a spring
/// reset through the dashpot pushed along the slip): Coulomb theory with the measured restitution,
/// with the dashpot free to pull and clipped (`no_attraction`, damping recomputed to keep e).
pub fn damped_hertz_mindlin_impacts_slide_at_the_coulomb_limit(backend: BackendName) {
    let (mu, e) = (0.4, 0.5);
    // Sliding throughout needs tan θ ≥ 7/2 μ (1 + e) = 2.1: θ ≥ 64.5°.
    for (angle, clipped) in [(70.0, true), (80.0, false)] {
        let i = oblique_impact_with(backend, FrictionModel::History, true, mu, e, angle, clipped);
        let (vt, spin) = coulomb_impact(angle, mu, i.normal);
        println!("{angle}° clipped {clipped}: {i:?} theory v_t {vt} spin {spin}");
        if clipped {
            assert!((i.normal - e).abs() < Tolerance::on(Restitution, backend), "{angle}°: the clipped dashpot gives e = {}", i.normal);
        }
        assert!((i.tangential / vt - 1.0).abs() < Tolerance::on(TangentialRatio, backend), "{angle}°: v_t'/v_t = {} vs {vt}", i.tangential);
        assert!((i.spin / spin - 1.0).abs() < Tolerance::on(SpinRatio, backend), "{angle}°: Rω'/v_t = {} vs {spin}", i.spin);
    }
}

/// A sphere on a 15° incline below the friction angle stays put (a history-free law creeps).
pub fn a_spring_holds_a_sphere_on_an_incline(backend: BackendName) {
    let angle = 15.0;
    let held = creep_speed_on(backend, FrictionModel::History, 0.5, angle, 0.02);
    println!("{angle}°: creep {held} m/s");
    // Over 0.02 s the normal settling transient is still there (−1.5e-6 m/s in f64); viscous-Coulomb
    // creeps at m g sinθ / c_t = 1.8e-4 m/s.
    assert!(held.abs() < Tolerance::on(CreepSpeed, backend), "history creeps at {held} m/s on {angle}°");
}

/// Below the slip threshold a sphere rolls down at 5/7 g sin θ without slipping.
pub fn rolls_at_five_sevenths_g_sin_theta(backend: BackendName) {
    let m = incline_motion_on(backend, FrictionModel::History, 0.5, 0.0, 20.0, 0.05);
    let a = 5.0 / 7.0 * G * f64::to_radians(20.0).sin();
    println!("{m:?} vs {a}");
    assert!((m.acceleration / a - 1.0).abs() < Tolerance::on(RollingAcceleration, backend), "a = {} vs 5/7 g sinθ = {a}", m.acceleration);
    assert!(m.slip < Tolerance::on(SlipSpeed, backend), "slips at {} m/s", m.slip);
}

/// Rolling resistance μ_r holds a sphere below tan θ = μ_r and lets it roll at
/// 5/7 g (sin θ − μ_r cos θ) above.
pub fn rolling_resistance_holds_below_tan_theta_equal_mu_r_and_rolls_above(backend: BackendName) {
    let mu_r: f64 = 0.1; // threshold 5.71°
    let m = incline_motion_on(backend, FrictionModel::History, 0.5, mu_r, 3.0, 0.05);
    println!("3°: {m:?}");
    // Free rolling would be 5/7 g sin 3° = 0.37 m/s²; over 0.05 s the fit still sees the settling transient.
    assert!(m.acceleration.abs() < 1e-3 && m.distance.abs() < 1e-5, "3° with μ_r = {mu_r}: {m:?}");
    let t = f64::to_radians(10.0);
    let m = incline_motion_on(backend, FrictionModel::History, 0.5, mu_r, 10.0, 0.05);
    let a = 5.0 / 7.0 * G * (t.sin() - mu_r * t.cos());
    println!("10°: {m:?} vs {a}");
    assert!(
        (m.acceleration / a - 1.0).abs() < Tolerance::on(ResistedRollingAcceleration, backend),
        "10°: a = {} vs 5/7 g (sinθ − μ_r cosθ) = {a}",
        m.acceleration
    );
}
