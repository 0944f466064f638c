//! Polyhedral particles in the GPU step against the CPU engine: a settling sphere–polyhedron
//! mixture (height, kinetic-energy decay) and run-to-run bit-identical states. The tumbling box
//! and the octahedron–cube rebound are in the suite (tumble-testkit), against closed forms.

use crate::support::scene;
use tumble::Simulation;
use tumble_gpu::GpuSimulation;
use tumble_scene::CompiledScene;
use tumble_testkit::scenes::{replaced, test_scene};

/// `scenes/test/cube_bed.toml` for `duration`: a bed of frictional cubes (and, with `spheres`, a
/// layer of spheres above them) settling into a box under gravity: 112 cubes (and 32 spheres), 6,300 steps to 0.36 s (t_col at a cube corner / 10). On lavapipe
/// this is minutes, so the beds are small; the spheres settle slowest (they roll), so the
/// mixture is compared while the layers land on each other (to 0.15 s).
pub(crate) fn bed(spheres: bool, duration: f64) -> CompiledScene {
    let mut text = replaced(&test_scene("cube_bed"), "duration = 0.36", &format!("duration = {duration}"));
    if spheres {
        text.push_str(
            r#"
[[particles]]
material = "glass"
shape = { sphere = { diameter = 0.005 } }
lattice = { min = [0.005, 0.005, 0.075], max = [0.045, 0.045, 0.1], spacing = 0.0085, jitter = 0.05 }
"#,
        );
    }
    scene(&text)
}

/// (mean height, kinetic + rotational energy) of a state.
fn height_and_energy(s: &tumble_cpu::State) -> (f64, f64) {
    let n = s.len() as f64;
    let h = s.pos.iter().map(|p| p.z).sum::<f64>() / n;
    let e = (0..s.len()).map(|i| 0.5 * s.mass[i] * s.vel[i].length_squared() + s.rotational_energy(i)).sum::<f64>();
    (h, e)
}

/// Runs the bed on both backends for `duration`; the end is checked as a bed still falling
/// together (heights within 3 %, as many contacts).
fn settle_against_the_cpu(name: &str, spheres: bool, duration: f64) {
    let sc = bed(spheres, duration);
    let steps = sc.plan.run.steps;
    println!("{name}: {} particles, {} steps of {:.2e} s", sc.particles.len(), steps, sc.plan.model.dt);
    let mut cpu = Simulation::new(sc.clone(), 2);
    let mut gpu = GpuSimulation::new(sc).unwrap();
    let chunks = 6;
    let mut worst_height = 0.0f64;
    for k in 1..=chunks {
        let t = std::time::Instant::now();
        gpu.advance(steps / chunks);
        let gpu_time = t.elapsed().as_secs_f64();
        cpu.advance(steps / chunks);
        let (hc, ec) = height_and_energy(&cpu.state());
        let (hg, eg) = height_and_energy(&gpu.state());
        let (oc, og) = (cpu.observables(), gpu.observables());
        println!(
            "  t = {:.3} s: mean height cpu {hc:.5} gpu {hg:.5} m, kinetic cpu {ec:.3e} gpu {eg:.3e} J, contacts cpu {} gpu {}, dissipated cpu {:.4e} gpu {:.4e} J ({gpu_time:.1} s on the device)",
            cpu.time(),
            oc.contacts,
            og.contacts,
            oc.dissipated_energy,
            og.dissipated_energy
        );
        assert!(og.finite);
        let total = |o: &tumble::Observables| o.kinetic_energy + o.rotational_energy + o.potential_energy + o.elastic_energy + o.dissipated_energy;
        println!(
            "    energy total cpu {:.6e} gpu {:.6e} (elastic cpu {:.3e} gpu {:.3e})",
            total(&oc),
            total(&og),
            oc.elastic_energy,
            og.elastic_energy
        );
        worst_height = worst_height.max((hg - hc).abs() / hc);
        if k == 1 {
            // Falling, before many collisions: still the same trajectories.
            assert!((hg - hc).abs() < 5e-3 * hc && (eg - ec).abs() < 5e-2 * ec, "first chunk: height cpu {hc} gpu {hg}, kinetic cpu {ec} gpu {eg}");
        }
        if k == chunks {
            assert!((hg - hc).abs() < 0.03 * hc, "final mean height cpu {hc} gpu {hg}");
            assert!((og.contacts as f64 - oc.contacts as f64).abs() < 0.2 * oc.contacts as f64, "contacts cpu {} gpu {}", oc.contacts, og.contacts);
        }
    }
    println!("{name}: worst mean-height difference {:.2e} of the height", worst_height);
}

pub fn a_mixture_of_spheres_and_cubes_settles_as_on_the_cpu() {
    settle_against_the_cpu("sphere and cube bed", true, 0.15);
}

pub fn polyhedra_runs_give_bit_identical_states() {
    let sc = bed(true, 0.36);
    let run = || {
        let mut g = GpuSimulation::new(sc.clone()).unwrap();
        g.advance(600);
        g.device_arrays()
    };
    let (a, b) = (run(), run());
    assert!(!a.orient.is_empty());
    assert_eq!(a, b, "two runs differ");
    let moving = a.vel.iter().filter(|v| v[0] != 0.0 || v[1] != 0.0 || v[2] != 0.0).count();
    let turned = a.orient.iter().filter(|q| q[3] < 0.999).count();
    println!("two runs of 600 steps bit-identical ({moving} moving, {turned} turned)");
}

// The settled bed of cubes alone (height, kinetic-energy decay, contacts against the CPU) is the
// conformance suite's "polyhedra: cube bed" family, which CI runs after the tests.
