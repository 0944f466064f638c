//! Polyhedral particles in the GPU step against the CPU engine: a box tumbling about its
//! intermediate axis (energy, angular momentum), an elastic octahedron–cube collision
//! (rebound speed), a settling bed of cubes and a sphere–polyhedron mixture (height,
//! kinetic-energy decay), and run-to-run bit-identical states.

use crate::support::scene;
use glam::DVec3;
use tumble::Simulation;
use tumble_gpu::GpuSimulation;
use tumble_scene::CompiledScene;
use tumble_testkit::scenes::spinning;

pub fn a_box_spun_about_its_intermediate_axis_tumbles_as_on_the_cpu() {
    let sc = scene(&spinning("{ box = { size = [0.1, 0.2, 0.3] } }", [1e-3, 5.0, 1e-3], 2e-3, 10.0));
    let mut cpu = Simulation::new(sc.clone(), 1);
    let mut gpu = GpuSimulation::new(sc).unwrap();
    let e = |s: &tumble_cpu::State| (s.rotational_energy(0), s.spin_momentum(0), s.orient[0]);
    let (e0, l0, _) = e(&gpu.state());
    let (mut de, mut dl, mut flip, mut early) = (0.0f64, 0.0f64, 1.0f64, 0.0f64);
    for k in 0..100 {
        gpu.advance(50);
        cpu.advance(50);
        let (eg, lg, qg) = e(&gpu.state());
        de = de.max((eg / e0 - 1.0).abs());
        dl = dl.max((lg - l0).length() / l0.length());
        flip = flip.min((qg * DVec3::Y).dot(DVec3::Y));
        if k < 10 {
            // Before the tumbling amplifies f32 rounding: the same orientation as the CPU.
            early = early.max(qg.angle_between(cpu.state().orient[0]));
        }
    }
    println!(
        "GPU tumbling box: energy error {de:.3e}, momentum error {dl:.3e}, min cos {flip:.4}, orientation off the CPU by {early:.2e} rad over 1 s"
    );
    assert!(flip < -0.9, "no tumbling: min cos {flip}");
    // f32 rounding of the five turns and the body/world round trip of ω each step: measured
    // 2e-6 over the first 1,000 steps, 1.4e-4 (L) and 2.8e-4 (E) over 5,000 steps and two flips
    // (the CPU in f64: L to 1e-13, E within its bounded O(Δt²) error).
    assert!(dl < 5e-4, "angular momentum drifts by {dl:e}");
    assert!(de < 1e-3, "energy error {de:e}");
    assert!(early < 1e-3, "orientation off the CPU by {early:e} rad");
}

/// An octahedron (vertex first) hits a cube face head-on at `speed`: (rebound / impact, |ω| after).
fn octahedron_on_cube(speed: f64, gpu: bool) -> (f64, f64) {
    let text = format!(
        r#"
name = "octahedron-cube"
[run]
duration = 1.0
integrator = "verlet"
[domain]
min = [-0.1, -0.1, -0.1]
max = [0.1, 0.1, 0.1]
[[materials]]
name = "steel"
density = 7800.0
[contact]
normal = {{ model = "linear", stiffness = 1.0e6 }}
restitution = 1.0
[[particles]]
material = "steel"
shape = {{ platonic = {{ kind = "octahedron", radius = 0.02 }} }}
positions = [[-0.0205, 0.0, 0.0]]
velocity = [{speed}, 0.0, 0.0]
[[particles]]
material = "steel"
shape = {{ cube = {{ edge = 0.03 }} }}
positions = [[0.015, 0.0, 0.0]]
"#
    );
    let sc = scene(&text);
    let steps = ((0.0005 / speed + 0.01) / sc.plan.model.dt).ceil() as u64;
    let st = if gpu {
        let mut s = GpuSimulation::new(sc).unwrap();
        s.advance(steps);
        s.state()
    } else {
        let mut s = Simulation::new(sc, 1);
        s.advance(steps);
        let mut st = s.state().into_owned();
        let order: Vec<u32> = (0..2).map(|id| s.cpu().index_of(id).unwrap() as u32).collect();
        st.permute(&order);
        st
    };
    ((st.vel[1].x - st.vel[0].x) / speed, st.omega[0].length().max(st.omega[1].length()))
}

pub fn octahedron_cube_elastic_rebound_matches_the_cpu() {
    for speed in [0.25, 1.0] {
        let (g, spin) = octahedron_on_cube(speed, true);
        let (c, _) = octahedron_on_cube(speed, false);
        println!("octahedron on cube at {speed} m/s: rebound / impact gpu {g:.6} cpu {c:.6}, gpu spin after {spin:.2e} rad/s");
        assert!((g - 1.0).abs() < 5e-3, "GPU rebound ratio {g}");
        assert!((g - c).abs() < 1e-3, "GPU {g} vs CPU {c}");
        assert!(spin < 1e-3, "a central impact must not spin: {spin}");
    }
}

/// A bed of frictional cubes (and, with `spheres`, a layer of spheres above them) settling
/// into a box under gravity: 112 cubes (and 32 spheres), 6,300 steps to 0.36 s (t_col at a cube corner / 10). On lavapipe
/// this is minutes, so the beds are small; the spheres settle slowest (they roll), so the
/// mixture is compared while the layers land on each other (to 0.18 s).
pub(crate) fn bed(spheres: bool, duration: f64) -> CompiledScene {
    let mut text = format!(
        r#"
name = "cube-bed"
[run]
duration = {duration}
integrator = "verlet"
dt = {{ collision_fraction = 10 }}
seed = 3
[domain]
min = [0.0, 0.0, 0.0]
max = [0.05, 0.05, 0.12]
[gravity]
acceleration = [0.0, 0.0, -9.81]
[[materials]]
name = "glass"
density = 2500.0
[contact]
normal = {{ model = "linear", stiffness = 1.0e3 }}
restitution = 0.3
tangential = {{ model = "history", friction = 0.4 }}
[[particles]]
material = "glass"
shape = {{ cube = {{ edge = 0.005 }} }}
orientation = "random"
lattice = {{ min = [0.005, 0.005, 0.005], max = [0.045, 0.045, 0.065], spacing = 0.0085, jitter = 0.05 }}
[[walls]]
name = "box"
material = "glass"
box = {{ min = [0.0, 0.0, 0.0], max = [0.05, 0.05, 0.12] }}
"#
    );
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
    settle_against_the_cpu("sphere and cube bed", true, 0.18);
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
