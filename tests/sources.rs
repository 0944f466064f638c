//! Particle sources on the CPU: crowded insertion never overlaps a particle or a wall, mass
//! targets end within one particle, sieve and mixture fractions come out within sampling
//! error, polyhedra get uniformly random orientations, and the particles are the same for any
//! thread count. (Both backends: the suite's `sources` behaviour.)

use glam::DVec3;
use tumble::{Simulation, compile, parse_scene};

/// A closed box (walls) with a source; `source` is the `[[sources]]` table's body.
fn scene(gravity: f64, duration: f64, source: &str) -> tumble::CompiledScene {
    let text = format!(
        r#"
name = "sources"
[run]
duration = {duration}
integrator = "verlet"
seed = 7
[domain]
min = [-0.2, -0.2, -0.2]
max = [0.2, 0.2, 0.2]
[gravity]
acceleration = [0.0, 0.0, {gravity}]
[[materials]]
name = "glass"
density = 2500.0
[contact]
normal = {{ model = "linear", stiffness = 1.0e4 }}
restitution = 0.5
tangential = {{ model = "history", friction = 0.5 }}
[[walls]]
name = "box"
material = "glass"
box = {{ min = [-0.1, -0.1, -0.1], max = [0.1, 0.1, 0.1] }}
[[sources]]
name = "feed"
material = "glass"
{source}
"#
    );
    compile(&parse_scene(&text).unwrap()).unwrap()
}

/// Smallest gap of any particle to another and to any wall, in units of its radius (negative: overlap).
fn smallest_gap(sim: &Simulation) -> f64 {
    let s = sim.state();
    let walls = sim.walls();
    let mut worst = f64::INFINITY;
    for i in 0..s.len() {
        for j in i + 1..s.len() {
            let gap = (s.pos[i] - s.pos[j]).length() - s.radius[i] - s.radius[j];
            worst = worst.min(gap / s.radius[i].min(s.radius[j]));
        }
        for w in walls.iter() {
            if let Some(c) = w.shape.sphere_contact(s.pos[i], s.radius[i]) {
                worst = worst.min(-c.overlap / s.radius[i]);
            }
        }
    }
    worst
}

#[test]
fn a_crowded_source_never_inserts_an_overlap_with_a_particle_or_a_wall() {
    // A region reaching into the walls, asked for far more than it holds at once: most
    // candidates are refused, by particles and by walls, and the rest must clear both.
    let mut sim = Simulation::new(
        scene(
            0.0,
            0.02,
            r#"shape = { sphere = { diameter = { min = 0.008, max = 0.016 } } }
region = { box = { min = [-0.12, -0.12, -0.12], max = [0.12, 0.12, 0.0] } }
rate = { particles_per_second = 200000.0 }
interval = 0.002"#,
        ),
        2,
    );
    let every = sim.plan().model.sources[0].every;
    let mut worst = smallest_gap(&sim);
    let mut before = sim.particles();
    while sim.steps() < sim.plan().run.steps {
        sim.advance(every);
        // Between events the spheres move: only the state right after an event is checked.
        worst = worst.min(smallest_gap(&sim));
        assert!(sim.particles() >= before);
        before = sim.particles();
    }
    let books = sim.feeder_books().unwrap();
    println!("{} particles inserted, {} bodies deferred, smallest gap {worst:.3e} r", books.sources[0].inserted, books.sources[0].deferred);
    assert!(books.sources[0].deferred > 0, "the region must be crowded for this test to mean anything");
    assert!(books.sources[0].inserted > 1000);
    assert!(worst >= -1e-9, "an inserted particle overlaps by {:.3e} of its radius", -worst);
}

#[test]
fn a_mass_target_ends_within_one_particle_and_sieve_fractions_match_within_sampling_error() {
    let classes = [(0.004, 0.006, 0.2), (0.006, 0.008, 0.5), (0.008, 0.010, 0.3)];
    let sieve: Vec<String> = classes.iter().map(|(a, b, f)| format!("[{a}, {b}, {f}]")).collect();
    let target = 2.0;
    let sim = Simulation::new(
        scene(
            0.0,
            0.05,
            &format!(
                "shape = {{ sphere = {{ diameter = {{ sieve = [{}] }} }} }}\nregion = {{ box = {{ min = [-0.095, -0.095, -0.095], max = [0.095, 0.095, 0.095] }} }}\ntotal = {{ kg = {target} }}",
                sieve.join(", ")
            ),
        ),
        1,
    );
    let s = sim.state();
    let mass: f64 = s.mass.iter().sum();
    let m_max = 2500.0 * std::f64::consts::PI / 6.0 * 0.010f64.powi(3);
    println!("{} particles, {mass} kg against a target of {target} kg (largest particle {m_max:.3e} kg)", s.len());
    assert!(mass >= target && mass < target + m_max, "inserted {mass} kg for a target of {target} kg");
    for (a, b, f) in classes {
        let in_class: f64 = (0..s.len()).filter(|&i| 2.0 * s.radius[i] >= a && 2.0 * s.radius[i] < b).map(|i| s.mass[i]).sum();
        let share = in_class / mass;
        // A class's mass share over n particles: standard error below 0.02 here; 0.05 catches
        // number fractions taken for mass fractions (which put 0.36 in the smallest class).
        println!("class [{a}, {b}): mass fraction {share:.4} (requested {f})");
        assert!((share - f).abs() < 0.05, "class [{a}, {b}): {share} against {f}");
    }
}

#[test]
fn a_mixture_inserts_its_shares_and_polyhedra_turn_uniformly_at_random() {
    let sim = Simulation::new(
        scene(
            0.0,
            0.05,
            r#"mixture = [{ fraction = 0.25, shape = { cube = { edge = 0.008 } } }, { fraction = 0.75, shape = { sphere = { diameter = 0.008 } } }]
region = { box = { min = [-0.095, -0.095, -0.095], max = [0.095, 0.095, 0.095] } }
total = { particles = 1200 }"#,
        ),
        1,
    );
    let s = sim.state();
    assert_eq!(s.len(), 1200);
    let cubes: Vec<usize> = (0..s.len()).filter(|&i| s.shape[i] != tumble_scene::SPHERE).collect();
    let share = cubes.len() as f64 / s.len() as f64;
    // Binomial standard error: 0.0125.
    assert!((share - 0.25).abs() < 0.04, "cube share {share}");
    // A uniform rotation sends a body axis to a uniform direction: mean 0, each component's
    // mean square 1/3 (standard error of the mean 0.03 over 300 cubes).
    let axes: Vec<DVec3> = cubes.iter().map(|&i| s.orient[i] * DVec3::Z).collect();
    let mean = axes.iter().sum::<DVec3>() / axes.len() as f64;
    let square = axes.iter().map(|a| a * a).sum::<DVec3>() / axes.len() as f64;
    println!("{} cubes ({share:.3}); mean body z axis {mean:.3}, mean squares {square:.3}", cubes.len());
    assert!(mean.length() < 0.15, "orientations are not uniform: mean axis {mean}");
    assert!((square - DVec3::splat(1.0 / 3.0)).abs().max_element() < 0.06, "orientations are not uniform: {square}");
}

#[test]
fn inserted_particles_are_the_same_for_any_thread_count() {
    let source = r#"shape = { sphere = { diameter = { normal = { mean = 0.01, std = 0.001 } } } }
region = { cylinder = { base = [0.0, 0.0, 0.02], axis = [0.0, 0.0, 1.0], radius = 0.08, length = 0.07 } }
velocity = [0.0, 0.0, -0.5]
rate = { kg_per_second = 20.0 }"#;
    let run = |threads: usize| {
        let mut sim = Simulation::new(scene(-9.81, 0.1, source), threads);
        let steps = sim.plan().run.steps;
        sim.advance(steps);
        (sim.state().into_owned(), sim.inserted())
    };
    let (a, ia) = run(1);
    let (b, ib) = run(2);
    println!("{} particles at the end; inserted {ia:?}", a.len());
    assert!(a.len() > 500);
    assert_eq!(ia, ib);
    assert!(a == b, "one and two threads differ");
}

/// The GPU's growth chunk: an eighth of what the sources may insert, at least 1,024 slots and
/// never more than that total; `run.capacity_chunk` sets it; 0 without sources.
#[test]
fn the_capacity_chunk_is_an_eighth_of_the_capacity_at_least_1024_and_at_most_all_of_it() {
    let shape = r#"shape = { sphere = { diameter = 0.01 } }
region = { box = { min = [-0.05, -0.05, -0.05], max = [0.05, 0.05, 0.05] } }"#;
    let chunk_of = |rate: f64| {
        let s = scene(0.0, 0.1, &format!("{shape}\nrate = {{ particles_per_second = {rate} }}"));
        let (most, chunk) = (s.plan.inserted_at_most(), s.plan.tuning.capacity_chunk);
        println!("{rate} particles/s for 0.1 s: at most {most} particles, chunk {chunk}");
        (most, chunk)
    };
    let (most, chunk) = chunk_of(500.0);
    assert!(most < 1024 && chunk == most, "a small capacity is one chunk");
    let (most, chunk) = chunk_of(2.0e4);
    assert!((1024..8192).contains(&most) && chunk == 1024, "at least 1,024 slots");
    let (most, chunk) = chunk_of(1.0e6);
    assert!(most >= 100_000 && chunk == most.div_ceil(8), "an eighth of a large capacity");
    let text = std::fs::read_to_string("scenes/protocols/hopper_pour.toml").unwrap();
    let set = text.replace("[run]\n", "[run]\ncapacity_chunk = 100\n");
    assert_eq!(compile(&parse_scene(&set).unwrap()).unwrap().plan.tuning.capacity_chunk, 100);
    let plain = std::fs::read_to_string("scenes/box_settle.toml").unwrap();
    assert_eq!(compile(&parse_scene(&plain).unwrap()).unwrap().plan.tuning.capacity_chunk, 0);
}

/// A cube of edge 2a about the origin as an OBJ file of 12 triangles, normals outward.
fn cube_obj(a: f64) -> std::path::PathBuf {
    let mut text = String::new();
    for k in 0..8 {
        let s = |bit: usize| if k & bit == 0 { -a } else { a };
        text += &format!("v {} {} {}\n", s(1), s(2), s(4));
    }
    // Each face as two triangles, wound counter-clockwise seen from outside (1-based indices).
    for [p, q, r, t] in [[1, 3, 4, 2], [5, 6, 8, 7], [1, 2, 6, 5], [3, 7, 8, 4], [1, 5, 7, 3], [2, 4, 8, 6]] {
        text += &format!("f {p} {q} {r}\nf {p} {r} {t}\n");
    }
    let path = std::env::temp_dir().join(format!("tumble-source-cube-{}.obj", std::process::id()));
    std::fs::write(&path, text).unwrap();
    path
}

/// A source whose region is a closed mesh (a cube turned 30° about z, from an OBJ file)
/// inserts its whole total at once, every sphere wholly inside the turned cube and clear of
/// the others.
#[test]
fn a_source_fills_the_inside_of_a_closed_mesh() {
    let (a, r) = (0.05, 0.004);
    let file = cube_obj(a);
    let sim = Simulation::new(
        scene(
            0.0,
            1e-4,
            &format!(
                "shape = {{ sphere = {{ diameter = {} }} }}\nregion = {{ mesh = {{ file = \"{}\", rotate = {{ axis = [0.0, 0.0, 1.0], degrees = 30.0 }} }} }}\ntotal = {{ particles = 300 }}",
                2.0 * r,
                file.display()
            ),
        ),
        1,
    );
    std::fs::remove_file(&file).unwrap();
    let plan = sim.plan().describe(0);
    assert!(plan.contains("source       feed (closed mesh of 12 triangles, 1.0000e-3 m³):"), "{plan}");
    let s = sim.state();
    assert_eq!(s.len(), 300, "the whole total fits at once (10 % of the cube's volume)");
    let back = glam::DQuat::from_rotation_z(-30f64.to_radians());
    let deepest = (0..s.len()).map(|i| a - (back * s.pos[i]).abs().max_element()).fold(f64::INFINITY, f64::min);
    println!("300 spheres of radius {r} in a turned cube of half-edge {a}: the nearest comes {deepest:.4e} m from a face");
    assert!(deepest >= r - 1e-12, "a sphere reaches {:.3e} m out of the cube", r - deepest);
    assert!(smallest_gap(&sim) >= -1e-9);
    // Uniform: the particles' centre of mass is the cube's (standard error about 1.6 mm here).
    let mean = s.pos.iter().sum::<DVec3>() / s.len() as f64;
    assert!(mean.length() < 0.008, "centre of the particles {mean}");
}
