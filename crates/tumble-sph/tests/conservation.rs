//! What the scheme conserves: momentum of a closed periodic box to round-off, mass always, the
//! total energy of a viscous flow in a closed tank never growing; and the same bytes for any
//! number of threads.

mod common;

use common::*;
use tumble_geom::DVec3;
use tumble_sph::*;

/// A fully periodic 3D box of fluid stirred by a deterministic pseudo-random velocity field.
fn stirred_box(tensile: bool, viscosity: Viscosity) -> FluidPhase {
    let dp = 0.01;
    let side = 10.0 * dp;
    let settings = periodic_water(dp, side, viscosity, tensile, 0.3);
    let mut particles = FluidParticles::default();
    add_fluid_block(&mut particles, &settings, Aabb::new(DVec3::ZERO, DVec3::splat(side)), DVec3::ZERO);
    let mut state = 0x9e37_79b9_7f4a_7c15u64;
    let mut next = || {
        state ^= state << 13;
        state ^= state >> 7;
        state ^= state << 17;
        (state >> 11) as f64 / (1u64 << 53) as f64 - 0.5
    };
    for v in particles.velocity.iter_mut() {
        *v = DVec3::new(next(), next(), next());
    }
    FluidPhase::new(settings, particles).expect("valid box")
}

#[test]
fn periodic_box_conserves_momentum_to_round_off() {
    for (tensile, viscosity) in [(true, Viscosity::Laminar), (false, Viscosity::Artificial { alpha: 0.05 })] {
        let mut phase = stirred_box(tensile, viscosity);
        let start = phase.observables();
        let scale: f64 = {
            let p = phase.particles();
            (0..p.len()).map(|i| p.mass[i] * p.velocity[i].length()).sum()
        };
        let dt = TimeStepLimits::planned(phase.settings()).dt();
        for _ in 0..200 {
            phase.step(dt).unwrap();
        }
        let end = phase.observables();
        let drift = (end.momentum - start.momentum).length() / scale;
        println!(
            "{viscosity:?}, tensile {tensile}: momentum drift {drift:.2e} of Σ m|v|; kinetic energy {:.4} → {:.4} J",
            start.kinetic_energy, end.kinetic_energy
        );
        assert!(drift < 1e-13, "momentum drifted by {drift:.2e}");
        assert_eq!(end.mass, start.mass);
        // The stirring decays, it is not created.
        assert!(end.kinetic_energy < start.kinetic_energy);
    }
}

#[test]
fn results_are_the_same_bytes_for_one_and_two_threads() {
    let run = |threads: usize| {
        let pool = rayon::ThreadPoolBuilder::new().num_threads(threads).build().unwrap();
        pool.install(|| {
            let mut phase = column_in_tank(0.3, 0.1, 0.2, 20, DensityDiffusion::Fourtakas { delta: 0.1 }, Viscosity::Artificial { alpha: 0.02 });
            let dt = TimeStepLimits::planned(phase.settings()).dt();
            for _ in 0..300 {
                phase.step(dt).unwrap();
            }
            let p = phase.particles();
            let mut rows: Vec<(u32, [u64; 7])> = (0..p.len())
                .map(|i| {
                    let (x, v) = (p.position[i], p.velocity[i]);
                    (p.id[i], [x.x, x.y, x.z, v.x, v.y, v.z, p.density[i]].map(f64::to_bits))
                })
                .collect();
            rows.sort_unstable();
            rows
        })
    };
    assert!(run(1) == run(2), "one and two threads disagree");
}

/// Total energy E = kinetic + potential + Σ m e(ρ) of a column collapsing in a closed tank with
/// laminar viscosity: viscosity only removes energy, so E may not rise beyond the time-stepping
/// error; the bound measured is printed.
#[test]
fn energy_of_a_viscous_collapse_never_grows() {
    let mut phase = column_in_tank(0.3, 0.1, 0.2, 20, DensityDiffusion::Fourtakas { delta: 0.1 }, Viscosity::Laminar);
    let dt = TimeStepLimits::planned(phase.settings()).dt();
    let energy = |o: FluidObservables| o.kinetic_energy + o.potential_energy + o.elastic_energy;
    let e0 = energy(phase.observables());
    let scale = phase.observables().potential_energy;
    let mut highest = f64::NEG_INFINITY;
    let mut last = e0;
    while phase.time() < 0.6 {
        phase.step(dt).unwrap();
        last = energy(phase.observables());
        highest = highest.max(last - e0);
    }
    println!("energy: start {e0:.6} J/m, end {last:.6} J/m, largest rise {:.2e} of the potential energy", highest / scale);
    assert!(highest / scale < 1e-4, "energy rose by {:.2e} of the potential energy", highest / scale);
    assert!(last < e0, "the collapse dissipated nothing");
}

/// A run stopped at any step, written to bytes and restored into a fresh phase, continues to the
/// same bytes as one never stopped.
#[test]
fn a_restored_fluid_continues_bit_identically() {
    let build = || column_in_tank(0.3, 0.1, 0.2, 20, DensityDiffusion::Fourtakas { delta: 0.1 }, Viscosity::Artificial { alpha: 0.02 });
    let mut straight = build();
    let dt = TimeStepLimits::planned(straight.settings()).dt();
    for _ in 0..300 {
        straight.step(dt).unwrap();
    }
    let mut first = build();
    for _ in 0..137 {
        first.step(dt).unwrap();
    }
    let bytes = postcard::to_stdvec(&first.snapshot()).unwrap();
    let snapshot: FluidSnapshot = postcard::from_bytes(&bytes).unwrap();
    let mut resumed = build();
    resumed.restore(&snapshot).unwrap();
    for _ in 137..300 {
        resumed.step(dt).unwrap();
    }
    assert_eq!(resumed.steps(), 300);
    let encode = |phase: &FluidPhase| postcard::to_stdvec(&phase.snapshot()).unwrap();
    assert!(encode(&resumed) == encode(&straight), "the resumed fluid differs from the uninterrupted one");
    // A damaged snapshot is refused and changes nothing.
    let mut damaged = snapshot.clone();
    damaged.particles.density.pop();
    let before = resumed.snapshot();
    assert!(resumed.restore(&damaged).is_err());
    assert!(resumed.snapshot() == before);
}
