//! Property tests of the CPU backend: action and reaction, conservation laws, no phantom forces.

mod common;

use common::{P, scene};
use glam::DVec3;
use proptest::prelude::*;
use tumble::Simulation;

fn vec3(r: f64) -> impl Strategy<Value = DVec3> {
    (-r..r, -r..r, -r..r).prop_map(|(x, y, z)| DVec3::new(x, y, z))
}

/// Overlap allowed on purpose: the scene check rejects explicit overlaps, so use a lattice-free builder.
fn pair_scene(a: P, b: P, cohesion: bool) -> Simulation {
    let mut compiled = scene(&[a.clone(), P { x: a.x + DVec3::X * 0.5, ..b.clone() }], cohesion, false, 1.0, "");
    // Put the second particle where the property needs it (explicit overlaps are refused by the scene check).
    compiled.particles.position[1] = b.x;
    Simulation::new(compiled, 1)
}

fn particle() -> impl Strategy<Value = P> {
    (vec3(0.02), vec3(1.0), vec3(50.0), 0.01f64..0.03, 1.0f64..1.5).prop_map(|(x, v, w, d, ratio)| P { x, v, w, d, de: d * ratio })
}

proptest! {
    #![proptest_config(ProptestConfig::with_cases(64))]

    #[test]
    fn pair_forces_are_equal_and_opposite(a in particle(), b in particle(), cohesion in any::<bool>()) {
        let sim = pair_scene(a, b, cohesion);
        let cpu = sim.cpu();
        let (i, j) = (cpu.index_of(0).unwrap(), cpu.index_of(1).unwrap());
        let s = cpu.contact_sums();
        prop_assert_eq!(s[i].force, -s[j].force);
        // Torques balance the moment of the pair force about any point: angular momentum is conserved.
        let st = cpu.state();
        let total = st.pos[i].cross(s[i].force) + st.pos[j].cross(s[j].force) + s[i].torque + s[j].torque;
        let scale = (st.pos[i].length() + 0.05) * s[i].force.length() + 1e-30;
        prop_assert!(total.length() <= 1e-12 * scale, "net moment {:?} (scale {})", total, scale);
    }

    #[test]
    fn separated_particles_feel_nothing(a in particle(), b in particle(), gap in 1e-6f64..0.05, cohesion in any::<bool>()) {
        let reach = if cohesion { 0.5 * (a.de + b.de) } else { 0.5 * (a.d + b.d) };
        let dir = (b.x - a.x).try_normalize().unwrap_or(DVec3::X);
        let b = P { x: a.x + dir * (reach + gap), ..b };
        let sim = pair_scene(a, b, cohesion);
        for s in sim.cpu().contact_sums() {
            prop_assert_eq!(s.force, DVec3::ZERO);
            prop_assert_eq!(s.torque, DVec3::ZERO);
        }
    }
}

fn cloud(n: usize, seed: u64, half: f64) -> Vec<P> {
    let mut rng = tumble_scene::Rng::new(seed);
    let spacing = 2.0 * half / 6.0;
    (0..n)
        .map(|k| {
            let site = DVec3::new((k % 6) as f64, ((k / 6) % 6) as f64, (k / 36) as f64) * spacing - DVec3::splat(half - 0.5 * spacing);
            P {
                x: site,
                v: DVec3::new(rng.range(-1.0, 1.0), rng.range(-1.0, 1.0), rng.range(-1.0, 1.0)),
                w: DVec3::new(rng.range(-20.0, 20.0), rng.range(-20.0, 20.0), rng.range(-20.0, 20.0)),
                d: rng.range(0.015, 0.03),
                de: 0.032,
            }
        })
        .collect()
}

proptest! {
    #![proptest_config(ProptestConfig::with_cases(12))]

    #[test]
    fn linear_momentum_is_conserved_in_a_closed_periodic_box(seed in 0u64..1_000_000, cohesion in any::<bool>()) {
        let particles = cloud(200, seed, 0.1);
        let mut sim = Simulation::new(scene(&particles, cohesion, true, 0.1, ""), 2);
        let momentum = |sim: &Simulation| {
            let s = sim.cpu().state();
            (0..s.len()).fold((DVec3::ZERO, 0.0), |(p, scale), i| (p + s.vel[i] * s.mass[i], scale + s.mass[i] * s.vel[i].length()))
        };
        let (p0, scale) = momentum(&sim);
        sim.advance(1000);
        let (p1, _) = momentum(&sim);
        prop_assert!(sim.observables().dissipated_energy > 0.0, "particles must have collided");
        prop_assert!((p1 - p0).length() < 1e-12 * scale, "{:?} -> {:?} (scale {:e})", p0, p1, scale);
    }

    #[test]
    fn angular_momentum_is_conserved_in_frictional_collisions(
        offset in vec3(0.015), va in vec3(1.0), vb in vec3(1.0), wa in vec3(40.0), wb in vec3(40.0), da in 0.02f64..0.035, db in 0.02f64..0.035,
        history in proptest::bool::ANY,
    ) {
        // Two spheres aimed at each other with an offset: oblique, frictional, spinning;
        // history-free, or with a tangential spring and rolling resistance.
        let a = P { x: DVec3::new(-0.03, 0.0, 0.0), v: DVec3::new(1.5, 0.0, 0.0) + va * 0.3, w: wa, d: da, de: da };
        let b = P { x: DVec3::new(0.03, 0.0, 0.0) + DVec3::new(0.0, offset.y, offset.z), v: DVec3::new(-1.5, 0.0, 0.0) + vb * 0.3, w: wb, d: db, de: db };
        let tangential = if history { common::HISTORY_ROLLING } else { common::VISCOUS };
        let mut sim = Simulation::new(common::scene_with_tangential(&[a, b], false, false, 1.0, "", tangential), 1);
        let l = |sim: &Simulation| {
            let s = sim.cpu().state();
            (0..s.len()).map(|i| s.pos[i].cross(s.vel[i]) * s.mass[i] + s.omega[i] / s.inv_inertia[i]).sum::<DVec3>()
        };
        let l0 = l(&sim);
        sim.advance(3000);
        prop_assume!(sim.observables().dissipated_energy > 0.0); // they met
        let l1 = l(&sim);
        prop_assert!((l1 - l0).length() < 1e-12 * l0.length().max(1e-6), "{:?} -> {:?}", l0, l1);
    }
}

#[test]
fn results_are_bit_identical_for_1_2_and_4_threads() {
    let particles = cloud(216, 3, 0.1);
    // History-free and with tangential springs (their slots are re-sorted with the particles).
    for history in [false, true] {
        let run = |threads: usize| {
            let tangential = if history { common::HISTORY_ROLLING } else { common::VISCOUS };
            let mut sim = Simulation::new(common::scene_with_tangential(&particles, true, true, 0.1, "resort_interval = 7", tangential), threads);
            assert_eq!(sim.plan().model.history, history);
            sim.advance(1500);
            let s = sim.cpu().state();
            let mut bytes = Vec::new();
            for i in 0..s.len() {
                for v in [s.pos[i], s.vel[i], s.omega[i]] {
                    bytes.extend(v.to_array().map(f64::to_bits));
                }
                bytes.push(s.dissipated[i].to_bits());
            }
            bytes.extend(s.history.spring.iter().flat_map(|v| v.xi.to_array().map(f64::to_bits)));
            (bytes, sim.observables().contacts, s.history.total())
        };
        let (one, contacts, springs) = run(1);
        assert!(contacts > 0);
        assert_eq!(springs > 0, history);
        assert_eq!(one, run(2).0, "history = {history}");
        assert_eq!(one, run(4).0, "history = {history}");
    }
}

#[test]
fn the_neighbour_list_never_misses_a_contact() {
    // Fast, polydisperse, periodic: particles cross the skin often and the list must keep up.
    let mut particles = cloud(216, 11, 0.1);
    for p in &mut particles {
        p.v *= 3.0;
    }
    let mut sim = Simulation::new(scene(&particles, false, true, 0.1, "resort_interval = 5"), 2);
    let domain = sim.plan().model.domain;
    let mut checked = 0;
    for _ in 0..400 {
        sim.advance(1);
        let s = sim.cpu().state();
        // Brute force by id: bodies touching (|d| < r_a + r_b).
        let mut by_id = vec![0usize; s.len()];
        for i in 0..s.len() {
            by_id[s.id[i] as usize] = i;
        }
        let x: Vec<DVec3> = by_id.iter().map(|&i| s.pos[i]).collect();
        let r: Vec<f64> = by_id.iter().map(|&i| s.radius[i]).collect();
        let expected = tumble_broad::brute_force_pairs(&x, &r, &domain);
        assert_eq!(sim.cpu().touching_pairs(), expected);
        checked += expected.len();
    }
    assert!(checked > 1000, "the test must see contacts ({checked})");
    assert!(sim.cpu().neighbour_builds() > 10, "and rebuilds ({})", sim.cpu().neighbour_builds());
}
