//! Chung & Ooi (2011) particle-impact benchmarks 1–8 on the CPU against Hertz theory and
//! rigid-body Coulomb theory (docs/chung-ooi.md). Hertz–Mindlin ("history") and viscous-Coulomb.

use glam::DVec3;
use tumble::verify::FrictionModel::{self, History, ViscousCoulomb};
use tumble::verify::chung_ooi::*;

const MODELS: [FrictionModel; 2] = [History, ViscousCoulomb];

fn check_hertz(s: &ImpactSetup, what: &str) {
    let r = s.run();
    let (t_h, d, f) = s.hertz();
    assert!((r.contact_time / t_h - 1.0).abs() < 1e-2, "{what}: t_c {} vs t_H {t_h}", r.contact_time);
    assert!((r.max_overlap / d - 1.0).abs() < 1e-2, "{what}: δ_max {} vs {d}", r.max_overlap);
    assert!((r.max_force / f - 1.0).abs() < 1e-2, "{what}: F_max {} vs {f}", r.max_force);
    assert!((r.restitution - 1.0).abs() < 2e-3, "{what}: e = {}", r.restitution);
}

#[test]
fn test1_identical_spheres_follow_hertz() {
    for m in [GLASS, LIMESTONE] {
        let body = |s: f64| Body::new(m, 0.01, DVec3::new(0.0, 0.0, 10.0 * s), DVec3::ZERO);
        check_hertz(&ImpactSetup::new(History, 0.35, 1.0, body(-1.0), Some(body(1.0))), m.name);
    }
}

#[test]
fn test2_sphere_on_wall_follows_hertz_and_keeps_e() {
    for m in [ALUMINIUM_ALLOY, MAGNESIUM_ALLOY] {
        let a = Body::new(m, 0.1, DVec3::new(0.0, 0.0, -0.2), DVec3::ZERO);
        check_hertz(&ImpactSetup::new(History, 0.0, 1.0, a, None), m.name);
    }
    // Tsuji damping (and its no_attraction recalibration) keeps e within 0.2 % here.
    for e in [0.2, 0.5, 0.8, 0.95] {
        for no_attraction in [false, true] {
            let a = Body::new(ALUMINIUM_OXIDE, OXIDE_RADIUS, DVec3::new(0.0, 0.0, -3.9), DVec3::ZERO);
            let r = ImpactSetup { no_attraction, ..ImpactSetup::new(History, 0.0, e, a, None) }.run();
            assert!((r.restitution - e).abs() < 5e-3, "e = {e}, no_attraction = {no_attraction}: measured {}", r.restitution);
        }
    }
}

#[test]
fn test3_unequal_spheres_follow_hertz() {
    let a = Body::new(GLASS, 0.01, DVec3::new(0.0, 0.0, -5.0), DVec3::ZERO);
    let b = Body::new(GLASS, 0.02, DVec3::new(0.0, 0.0, 5.0), DVec3::ZERO);
    check_hertz(&ImpactSetup::new(History, 0.35, 1.0, a, Some(b)), "glass 1 cm on 2 cm");
}

/// Gross sliding (χ < 1): with no_attraction J_t = μ J_n and β = χ − 1 (rigid-body theory,
/// the measured e in χ); without, the limit μ max(F_n, 0) gives J_t = μ ∫max(F_n,0)dt, and β follows from that impulse.
fn assert_gross_sliding(s: ImpactSetup, what: &str) {
    let (_, k_t) = s.compliances();
    for no_attraction in [true, false] {
        let s = ImpactSetup { no_attraction, ..s };
        let r = s.run();
        let chi = s.chi(r.restitution);
        let tag = format!("{what} {} e = {} no_attraction = {no_attraction}", s.model.name(), s.restitution);
        assert!(chi < 0.95, "{tag}: χ = {chi} is not gross sliding");
        let capacity = s.friction * r.compressive_impulse;
        let ratio = r.tangential_impulse.abs() / capacity;
        assert!((ratio - 1.0).abs() < 1e-2, "{tag}: J_t / μ∫max(F_n,0)dt = {ratio}");
        let beta_from_capacity = capacity * k_t / r.slip_before.abs() - 1.0;
        assert!((r.beta() - beta_from_capacity).abs() < 1e-2, "{tag}: β = {} vs {beta_from_capacity}", r.beta());
        if no_attraction {
            assert!((r.friction_ratio(s.friction) - 1.0).abs() < 1e-2, "{tag}: J_t / μJ_n = {}", r.friction_ratio(s.friction));
            assert!((r.beta() - (chi - 1.0)).abs() < 1e-2, "{tag}: β = {} vs χ − 1 = {}", r.beta(), chi - 1.0);
        }
    }
}

/// Sticking (χ > 1): friction stays within the Coulomb bound; a history-free law ends the impact
/// rolling (β = 0 as a rigid sphere), a Mindlin spring returns its energy (β ≠ 0, |β| ≤ 1).
fn assert_sticking(s: ImpactSetup, what: &str) {
    let r = s.run();
    let tag = format!("{what} {} e = {}", s.model.name(), s.restitution);
    assert!(s.chi(r.restitution) > 1.05, "{tag}: χ = {} is not sticking", s.chi(r.restitution));
    assert!(r.tangential_impulse.abs() <= s.friction * r.compressive_impulse * (1.0 + 1e-3), "{tag}: {r:?}");
    match s.model {
        ViscousCoulomb => assert!(r.beta().abs() < 1e-2, "{tag}: β = {}", r.beta()),
        _ => assert!(r.beta().abs() <= 1.0, "{tag}: β = {}", r.beta()),
    }
}

/// History at e = 0.5 (the damped case of the sliding rule), viscous-Coulomb at the paper's e = 0.98.
const CASES: [(FrictionModel, f64); 2] = [(History, 0.5), (ViscousCoulomb, 0.98)];

#[test]
fn test4_oblique_impacts_at_constant_speed() {
    for m in MODELS {
        for e in [0.98, 0.5] {
            for angle in [40.0, 60.0, 80.0] {
                assert_gross_sliding(oblique_at_angle(m, e, angle), &format!("test 4 at {angle}°"));
            }
            for angle in [5.0, 20.0] {
                assert_sticking(oblique_at_angle(m, e, angle), &format!("test 4 at {angle}°"));
            }
        }
    }
}

#[test]
fn test5_oblique_impacts_at_constant_normal_speed() {
    for (m, e) in CASES {
        for v_t in [5.0, 10.0] {
            assert_gross_sliding(oblique_with_tangential(m, e, v_t), &format!("test 5 at v_t = {v_t}"));
        }
        assert_sticking(oblique_with_tangential(m, e, 0.5), "test 5 at v_t = 0.5");
    }
}

#[test]
fn test6_spinning_sphere_onto_wall() {
    for (m, e) in CASES {
        for spin in [2000.0, -4000.0] {
            assert_gross_sliding(spinning_onto_wall(m, e, spin), &format!("test 6 at ω = {spin}"));
        }
        assert_sticking(spinning_onto_wall(m, e, 100.0), "test 6 at ω = 100");
    }
}

#[test]
fn test7_spheres_with_equal_and_opposite_spins() {
    for (m, e) in CASES {
        for spin in [10.0, 20.0] {
            assert_gross_sliding(spinning_pair(m, e, spin), &format!("test 7 at ω = {spin}"));
        }
        assert_sticking(spinning_pair(m, e, 1.0), "test 7 at ω = 1");
    }
}

#[test]
fn test8_unequal_spheres_with_rotation() {
    for (m, e) in CASES {
        for spin in [10.0, -10.0] {
            assert_gross_sliding(unequal_spinning_pair(m, e, 0.1, spin), &format!("test 8 at ω = {spin}"));
        }
        assert_sticking(unequal_spinning_pair(m, e, 0.1, 3.0), "test 8 at ω = 3");
    }
}
