//! The GPU backend against the CPU reference on small scenes, and run-to-run
//! determinism on the GPU.

use crate::support::scene;
use tumble::Simulation;
use tumble_gpu::GpuSimulation;
use tumble_scene::{CompiledScene, compile, parse_scene};
use tumble_testkit::scenes::{file, replaced, shortened, test_scene};

fn verify_scene(name: &str) -> String {
    file(&format!("scenes/verify/{name}"))
}

fn example_scene(name: &str) -> String {
    file(&format!("scenes/{name}"))
}

/// Final tracked rows of both backends after the whole run.
fn both(scene: CompiledScene) -> (Vec<tumble::TrackRow>, Vec<tumble::TrackRow>) {
    let steps = scene.plan.run.steps;
    let mut cpu = Simulation::new(scene.clone(), 1);
    let mut gpu = GpuSimulation::new(scene).unwrap();
    cpu.advance(steps);
    gpu.advance(steps);
    (cpu.tracks(), gpu.tracks())
}

/// Runs `steps` steps on both backends and compares the observables.
fn compare_observables(scene: CompiledScene, steps: u64, tolerance: f64) -> (tumble::Observables, tumble::Observables) {
    let mut cpu = Simulation::new(scene.clone(), 2);
    let mut gpu = GpuSimulation::new(scene).unwrap();
    cpu.advance(steps);
    gpu.advance(steps);
    let (c, g) = (cpu.observables(), gpu.observables());
    println!("{} after {steps} steps\n  cpu {c:?}\n  gpu {g:?}", cpu.plan().run.name);
    assert!(g.finite);
    assert_eq!(c.particles, g.particles, "particles left");
    // A missed neighbour would show here first.
    assert!((c.contacts as i64 - g.contacts as i64).abs() <= c.contacts as i64 / 50 + 1, "contacts: cpu {} gpu {}", c.contacts, g.contacts);
    let scale = c.kinetic_energy.abs() + c.potential_energy.abs() + c.elastic_energy.abs() + c.rotational_energy.abs() + 1e-300;
    for (name, a, b) in [
        ("kinetic", c.kinetic_energy, g.kinetic_energy),
        ("potential", c.potential_energy, g.potential_energy),
        ("rotational", c.rotational_energy, g.rotational_energy),
        ("elastic", c.elastic_energy, g.elastic_energy),
        ("dissipated", c.dissipated_energy, g.dissipated_energy),
        ("fluid work", c.fluid_work, g.fluid_work),
    ] {
        assert!((a - b).abs() <= tolerance * scale, "{name}: cpu {a} gpu {b} (scale {scale})");
    }
    (c, g)
}

fn short(text: &str, steps: f64) -> CompiledScene {
    shortened(text, steps as u64)
}

pub fn verification_scenes_end_where_the_cpu_ends() {
    for f in [
        "01_stokes_drag.toml",
        "02_normal_collision.toml",
        "02_elastic_collision.toml",
        "03_sliding.toml",
        "04_cohesive_collision.toml",
        "05_quadratic_drag.toml",
        "07_hertz_impact.toml",
        "08_slide_to_roll.toml",
    ] {
        let (c, g) = both(scene(&verify_scene(f)));
        assert_eq!(c.len(), g.len());
        for (a, b) in c.iter().zip(&g) {
            let (dx, dv, dw) =
                ((a.position - b.position).length(), (a.velocity - b.velocity).length(), (a.angular_velocity - b.angular_velocity).length());
            println!("{f} id {}: |dx| {dx:.2e} |dv| {dv:.2e} |dw| {dw:.2e}", a.id);
            assert_eq!(a.id, b.id);
            assert!(dx < 1e-4 && dv < 2e-4 * a.velocity.length().max(1.0) && dw < 1e-3 * a.angular_velocity.length().max(1.0), "{f}: {a:?} vs {b:?}");
        }
    }
}

pub fn every_integrator_matches_the_cpu_on_stokes_drag() {
    use tumble_scene::schema::IntegratorName::*;
    for integrator in [Euler, SymplecticEuler, Verlet, ImplicitDrag, ImplicitDragSymplectic] {
        let mut s = parse_scene(&verify_scene("01_stokes_drag.toml")).unwrap();
        s.run.integrator = integrator;
        let (c, g) = both(compile(&s).unwrap());
        println!("{integrator:?}: cpu x {} gpu x {}", c[0].position.x, g[0].position.x);
        assert!((c[0].position - g[0].position).length() < 2e-5 * c[0].position.length(), "{integrator:?}");
        assert!((c[0].velocity - g[0].velocity).length() < 2e-5, "{integrator:?}");
    }
}

pub fn falling_bed_with_walls_agrees() {
    compare_observables(short(&verify_scene("09_energy_balance.toml"), 400.0), 400, 2e-3);
}

pub fn periodic_taylor_green_suspension_agrees() {
    compare_observables(short(&example_scene("taylor_green.toml"), 200.0), 200, 1e-3);
}

pub fn cohesive_drum_inside_a_cylinder_agrees() {
    compare_observables(short(&example_scene("drum_cohesive.toml"), 200.0), 200, 5e-3);
}

pub fn pipe_cascade_with_a_fixed_particle_and_a_periodic_axis_agrees() {
    compare_observables(short(&example_scene("pipe_cascade.toml"), 300.0), 300, 5e-3);
}

pub fn hertz_contacts_on_two_sided_quads_agree() {
    compare_observables(short(&example_scene("hertz_quads.toml"), 300.0), 300, 5e-3);
}

pub fn forward_euler_with_dynamic_only_friction_agrees() {
    compare_observables(short(&example_scene("friction_failure_modes.toml"), 300.0), 300, 5e-3);
}

pub fn particles_leaving_the_domain_are_removed_as_on_the_cpu() {
    // The quadratic-drag sphere falls out of the bottom of its domain.
    let mut s = parse_scene(&verify_scene("05_quadratic_drag.toml")).unwrap();
    s.domain.min[2] = -2.0;
    let c = compile(&s).unwrap();
    let steps = c.plan.run.steps;
    let mut cpu = Simulation::new(c.clone(), 1);
    let mut gpu = GpuSimulation::new(c).unwrap();
    cpu.advance(steps);
    gpu.advance(steps);
    assert_eq!(cpu.removed(), 1);
    assert_eq!(gpu.removed(), 1);
    assert_eq!(gpu.particles(), 0);
    assert!(gpu.tracks().is_empty());
}

pub fn the_broad_phase_tables_are_a_sorted_counting_sort_with_a_three_level_scan() {
    // 140,000 small spheres spread through a large box: over 1,048,576 cells, so the scan
    // needs three levels of 1,024-value blocks.
    let scene = scene(&test_scene("sparse_lattice"));
    let n = scene.particles.len();
    assert!(n > 130_000, "{n}");
    let mut gpu = GpuSimulation::new(scene).unwrap();
    gpu.advance(1);
    let (cell, start, list) = gpu.cell_tables();
    let cells = gpu.grid().cells() as usize;
    assert!(cells + 2 > 1 << 20 && gpu.scan_levels() == 3, "{cells} cells, {} levels", gpu.scan_levels());
    assert_eq!(start.len(), cells + 2);
    assert_eq!(start[0], 0);
    assert_eq!(*start.last().unwrap() as usize, n);
    let mut counts = vec![0u32; cells + 1];
    for &c in &cell {
        counts[c as usize] += 1;
    }
    let mut seen = vec![false; n];
    for c in 0..=cells {
        assert_eq!(start[c + 1] - start[c], counts[c], "cell {c}");
        let slots = &list[start[c] as usize..start[c + 1] as usize];
        assert!(slots.windows(2).all(|w| w[0] < w[1]), "cell {c} is ordered by slot");
        for &k in slots {
            assert_eq!(cell[k as usize] as usize, c);
            assert!(!std::mem::replace(&mut seen[k as usize], true));
        }
    }
    assert!(seen.iter().all(|&s| s));
}

/// The conformance settling bed with tangential springs (Cundall–Strack) and rolling resistance.
fn bed_with_history() -> String {
    example_scene("conformance/settling_bed_history.toml")
}

/// Two Hertz spheres colliding obliquely with Hertz–Mindlin springs and rolling resistance.
fn oblique_mindlin_pair() -> String {
    verify_scene("07_hertz_impact.toml")
        .replace("restitution = 1.0", "restitution = 0.8\ntangential = { model = \"history\", friction = 0.3 }\nrolling_friction = 0.05")
        .replace("velocity = [0.5, 0.0, 0.0]", "velocity = [0.5, 0.3, 0.0]")
        .replace("velocity = [-0.5, 0.0, 0.0]", "velocity = [-0.5, -0.2, 0.1]")
}

pub fn falling_bed_with_history_and_rolling_resistance_agrees() {
    let scene = short(&bed_with_history(), 1000.0);
    assert!(scene.plan.model.history && scene.plan.model.rolling);
    let (_, g) = compare_observables(scene, 1000, 2e-3);
    assert!(g.contacts > 0);
}

pub fn oblique_mindlin_collision_agrees() {
    let (c, g) = both(scene(&oblique_mindlin_pair()));
    for (a, b) in c.iter().zip(&g) {
        println!("cpu v {:?} ω {:?}\ngpu v {:?} ω {:?}", a.velocity, a.angular_velocity, b.velocity, b.angular_velocity);
        assert!((a.velocity - b.velocity).length() < 1e-4, "velocity: cpu {:?} gpu {:?}", a.velocity, b.velocity);
        assert!((a.angular_velocity - b.angular_velocity).length() < 1e-2, "spin: cpu {:?} gpu {:?}", a.angular_velocity, b.angular_velocity);
    }
    // The tangential spring acted: the spheres spin after the collision.
    assert!(c[0].angular_velocity.length() > 1.0, "{:?}", c[0].angular_velocity);
}

pub fn history_runs_give_bit_identical_states_and_springs() {
    let scene = short(&bed_with_history(), 1000.0);
    let run = || {
        let mut gpu = GpuSimulation::new(scene.clone()).unwrap();
        gpu.advance(1000);
        assert!(gpu.history_overflow().is_none());
        (gpu.device_arrays(), gpu.springs(), gpu.spring_energies())
    };
    let ((a, sa, ea), (b, sb, eb)) = (run(), run());
    let bits = |v: &Vec<[f32; 4]>| v.iter().flat_map(|x| x.map(f32::to_bits)).collect::<Vec<u32>>();
    assert_eq!(bits(&a.pos), bits(&b.pos));
    assert_eq!(bits(&a.vel), bits(&b.vel));
    assert_eq!(bits(&a.omega), bits(&b.omega));
    assert_eq!(bits(&a.force), bits(&b.force));
    assert_eq!(bits(&a.torque), bits(&b.torque));
    assert_eq!(sa, sb);
    assert_eq!(ea, eb, "stored energies");
    assert!(sa.len() > 20, "springs held: {}", sa.len());
    assert!(ea.values().any(|&e| f32::from_bits(e) > 0.0) && ea.keys().eq(sa.keys()), "every spring stores its energy");
    // Both sides of a pair hold the same spring with opposite sign (exactly).
    for (&(owner, key), xi) in &sa {
        if key & tumble_cpu::WALL_KEY == 0 {
            let other = sb.get(&(key, owner)).unwrap_or_else(|| panic!("{owner} holds a spring for {key} but not the reverse"));
            assert_eq!(xi.map(|x| -f32::from_bits(x)), other.map(f32::from_bits));
            assert_eq!(ea[&(owner, key)], ea[&(key, owner)], "both sides store the same energy");
        }
    }
}

pub fn history_pair_forces_are_exactly_equal_and_opposite_and_the_spring_ends_with_the_contact() {
    let scene = scene(&oblique_mindlin_pair());
    let steps = scene.plan.run.steps;
    let mut gpu = GpuSimulation::new(scene).unwrap();
    let (mut touching, mut held) = (0, 0);
    for _ in 0..steps.min(400) {
        gpu.advance(1);
        let (a, b) = (gpu.contact_force(0).unwrap(), gpu.contact_force(1).unwrap());
        assert_eq!(a, -b);
        touching += usize::from(a != glam::DVec3::ZERO);
        held = held.max(gpu.springs().len());
    }
    gpu.advance(steps.saturating_sub(400));
    assert!(touching > 10);
    assert_eq!(held, 2, "each side of the one contact holds the spring");
    assert!(gpu.springs().is_empty(), "the spring must go with the contact");
}

/// `scenes/test/springs_released.toml`: two spheres colliding obliquely and a third bouncing off a
/// floor at a slant, without gravity: every contact ends with its tangential spring loaded, so the
/// energy the springs hold at separation must be booked as dissipated. `normal` is "linear"
/// (Cundall–Strack spring) or "hertz" (Mindlin: k_t follows the overlap, so the stored energy is
/// not ½ k_t(δ) |ξ|² of any later δ).
fn springs_released(normal: &str) -> String {
    let text = test_scene("springs_released");
    if normal == "linear" {
        return text;
    }
    let text = replaced(&text, "name = \"springs-released-linear\"", &format!("name = \"springs-released-{normal}\""));
    let text = replaced(&text, "model = \"linear\", stiffness = 1.0e3", &format!("model = \"{normal}\""));
    // Hertz: a step well below the plan's 0.2 Δt_R, so that Verlet's own energy residual stays small.
    replaced(&text, "duration = 0.03", "duration = 0.03\ndt = 1.0e-4")
}

pub fn springs_that_end_with_their_contact_are_booked_as_dissipated_as_on_the_cpu() {
    let mut failures = Vec::new();
    for normal in ["linear", "hertz"] {
        let s = scene(&springs_released(normal));
        let steps = s.plan.run.steps;
        let mut cpu = Simulation::new(s.clone(), 1);
        let mut gpu = GpuSimulation::new(s).unwrap();
        let (c0, g0) = (cpu.observables(), gpu.observables());
        // Mid-collision: both contacts hold a spring on each side that touches.
        cpu.advance(steps / 8);
        gpu.advance(steps / 8);
        let energies = gpu.spring_energies();
        assert_eq!(energies.len(), 3, "pair (both sides) and wall springs: {energies:?}");
        assert_eq!(energies[&(0, 1)], energies[&(1, 0)], "both sides store the same energy");
        cpu.advance(steps - steps / 8);
        gpu.advance(steps - steps / 8);
        let (c, g) = (cpu.observables(), gpu.observables());
        assert!(c.contacts == 0 && g.contacts == 0 && gpu.springs().is_empty(), "every contact ended");
        // No external work: what the particles lost is what was dissipated.
        let residual = |o: &tumble::Observables, o0: &tumble::Observables| o.mechanical_energy() + o.dissipated_energy - o0.mechanical_energy();
        let (rc, rg) = (residual(&c, &c0), residual(&g, &g0));
        let scale = c0.kinetic_energy;
        println!(
            "{normal}: {steps} steps, E0 {scale:.6e} J; dissipated cpu {:.6e} gpu {:.6e}; balance residual cpu {rc:.3e} ({:.3} %) gpu {rg:.3e} ({:.3} %)",
            c.dissipated_energy,
            g.dissipated_energy,
            100.0 * rc / scale,
            100.0 * rg / scale
        );
        assert!(c.dissipated_energy > 0.1 * scale, "the collisions dissipate: {}", c.dissipated_energy);
        // Both cases are printed before any judgement (the numbers without the fix are the point).
        if (g.dissipated_energy - c.dissipated_energy).abs() > 2e-4 * scale {
            failures.push(format!("{normal}: dissipated cpu {} gpu {}", c.dissipated_energy, g.dissipated_energy));
        }
        // Verlet's own residual (~0.1 % here) is the CPU's; the GPU's is the same to f32 rounding.
        if rc.abs() > 3e-3 * scale || rg.abs() > 3e-3 * scale || (rg - rc).abs() > 5e-5 * scale {
            failures.push(format!("{normal}: balance residual cpu {rc} gpu {rg}"));
        }
    }
    assert!(failures.is_empty(), "{failures:#?}");
}

pub fn history_slot_overflow_is_reported() {
    let text = bed_with_history().replace("rolling_friction = 0.05", "rolling_friction = 0.05\nhistory_slots = 1");
    let mut gpu = GpuSimulation::new(short(&text, 1000.0)).unwrap();
    gpu.advance(1000);
    let o = gpu.history_overflow().expect("a bed overflows one slot per particle");
    assert!(o.contacts > 1 && o.slots == 1 && o.step <= 1000, "{o:?}");
    assert!(o.to_string().contains("contact.history_slots = 1"), "{o}");
    assert_eq!(gpu.steps(), o.step, "the run stops at the batch where it overflowed");
}

/// A sphere of 20 mm touched by 2 mm spheres on most of its surface: the contact kernel takes
/// a particle's neighbours in range in rounds of 32, and this one has about 90, in three rounds.
fn large_sphere_among_small_ones() -> (String, usize) {
    // Directions of a Fibonacci lattice, those well below the equator left out so that the
    // contacts push the large sphere one way.
    let n = 150;
    let golden = std::f64::consts::PI * (3.0 - 5f64.sqrt());
    let centres: Vec<String> = (0..n)
        .filter_map(|k| {
            let z = 1.0 - 2.0 * (k as f64 + 0.5) / n as f64;
            let s = (1.0 - z * z).sqrt();
            let phi = golden * k as f64;
            // Each small sphere 0.1 mm into the large one.
            let r = 0.0109;
            (z > -0.2).then(|| format!("[{:.9}, {:.9}, {:.9}]", r * s * phi.cos(), r * s * phi.sin(), r * z))
        })
        .collect();
    let small = centres.len();
    let text = format!(
        r#"name = "large-among-small"
[run]
duration = 2.0e-4
integrator = "verlet"
output_interval = 1.0e-4
start = {{ allow_overlap = true }}

[domain]
min = [-0.05, -0.05, -0.05]
max = [0.05, 0.05, 0.05]

[[materials]]
name = "rubber"
density = 2500.0
youngs_modulus = 1.0e7
poisson_ratio = 0.3

[contact]
normal = {{ model = "hertz" }}
restitution = 0.5

[[particles]]
name = "large"
material = "rubber"
shape = {{ sphere = {{ diameter = 0.02 }} }}
positions = [[0.0, 0.0, 0.0]]
track = true

[[particles]]
name = "small"
material = "rubber"
shape = {{ sphere = {{ diameter = 0.002 }} }}
positions = [{}]
"#,
        centres.join(", ")
    );
    (text, small)
}

pub fn a_sphere_with_more_neighbours_than_one_round_holds_feels_every_one() {
    let (text, small) = large_sphere_among_small_ones();
    assert!(small > 3 * 28, "{small} small spheres");
    let scene = scene(&text);
    let steps = 20;
    let mut cpu = Simulation::new(scene.clone(), 1);
    let mut gpu = GpuSimulation::new(scene).unwrap();
    cpu.advance(steps);
    gpu.advance(steps);
    let (c, g) = (cpu.observables(), gpu.observables());
    assert_eq!(c.contacts, small as u64, "every small sphere touches the large one");
    assert_eq!(g.contacts, c.contacts);
    let (c, g) = (cpu.tracks(), gpu.tracks());
    let (vc, vg) = (c[0].velocity, g[0].velocity);
    println!("large sphere after {steps} steps: cpu v {vc:?}, gpu v {vg:?}");
    // One contact left out or counted twice moves it by about 1/60 of its speed.
    assert!(vc.length() > 1e-4, "{vc:?}");
    assert!((vc - vg).length() < 1e-3 * vc.length(), "cpu {vc:?} gpu {vg:?}");
}
