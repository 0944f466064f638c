//! Polyhedral particles in the engine (issue 6, verification case 6 and the polyhedra checks):
//! spin and tumbling, a tilted cube righting itself onto a face, beds and their energy. The
//! suite (tumble-testkit) has the tumbling box, a cube resting face-down and the elastic
//! octahedron–cube impact on both backends.

use glam::{DQuat, DVec3};
use tumble::{Simulation, compile, parse_scene};
use tumble_testkit::scenes::{cube_drop, replaced, spinning, test_scene};

fn sim(text: &str) -> Simulation {
    Simulation::new(compile(&parse_scene(text).unwrap()).unwrap_or_else(|e| panic!("{e}")), 1)
}

#[test]
fn case_6_a_spinning_cube_turns_once_per_period_on_a_circle() {
    let tau = std::f64::consts::TAU;
    let mut s = sim(&spinning("{ cube = { edge = 0.1 } }", [tau, 0.0, 0.0], 1e-5, 1.0));
    let corner = DVec3::new(0.05, 0.05, 0.05);
    let (mut worst_radius, mut worst_axial) = (0.0f64, 0.0f64);
    for _ in 0..100 {
        s.advance(1000);
        let st = s.cpu().state();
        let p = st.orient[0] * corner;
        // The corner stays on its circle about the x axis.
        worst_radius = worst_radius.max(((p.y * p.y + p.z * p.z).sqrt() - 0.05 * 2f64.sqrt()).abs());
        worst_axial = worst_axial.max((p.x - 0.05).abs());
        assert!((st.orient[0].length() - 1.0).abs() < 1e-12);
    }
    let st = s.cpu().state();
    // One turn: back where it started (the rotation angle is 2π to 1e-9).
    let angle = 2.0 * st.orient[0].w.abs().min(1.0).acos();
    assert!(angle < 1e-9, "left {angle:e} rad from a full turn");
    assert!(worst_radius < 1e-12 && worst_axial < 1e-12, "vertex path off its circle by {worst_radius:e}, {worst_axial:e}");
    assert!((st.omega[0] - DVec3::new(tau, 0.0, 0.0)).length() < 1e-12);
}

/// Tumbling of a 1 × 2 × 3 box spun about its intermediate axis: worst relative energy error,
/// worst relative angular-momentum error and the lowest cos of the y axis against its start.
fn tumbling(dt: f64) -> (f64, f64, f64) {
    let mut s = sim(&spinning("{ box = { size = [0.1, 0.2, 0.3] } }", [1e-3, 5.0, 1e-3], dt, 10.0));
    let state = |s: &Simulation| {
        let st = s.cpu().state();
        (st.rotational_energy(0), st.spin_momentum(0), st.orient[0])
    };
    let (e0, l0, _) = state(&s);
    let (mut de, mut dl, mut flip) = (0.0f64, 0.0f64, 1.0f64);
    let steps = (10.0 / dt).round() as u64;
    for _ in 0..200 {
        s.advance(steps / 200);
        let (e, l, q) = state(&s);
        de = de.max((e / e0 - 1.0).abs());
        dl = dl.max((l - l0).length() / l0.length());
        flip = flip.min((q * DVec3::Y).dot(DVec3::Y));
    }
    (de, dl, flip)
}

#[test]
fn case_6_the_tumbling_boxs_energy_error_falls_as_dt_squared() {
    // The tumbling itself and its conservation at Δt = 2 ms are in the suite, on both backends.
    let (de_coarse, _, flip) = tumbling(2e-3);
    let (de_fine, _, _) = tumbling(1e-3);
    eprintln!("tumbling box: energy error {de_coarse:.3e} (dt 2e-3), {de_fine:.3e} (dt 1e-3); min cos {flip:.4}");
    assert!(de_fine < 1e-5, "energy error {de_fine:e}");
    let order = (de_coarse / de_fine).log2();
    assert!((order - 2.0).abs() < 0.3, "energy error should fall as Δt²: order {order}");
}

/// `scenes/test/elastic_pair.toml`: two steel bodies with a linear spring of `stiffness`, e = 1,
/// no friction; its two cubes replaced by (shape, position, orientation, velocity) each.
fn elastic_pair(stiffness: f64, a: (&str, [f64; 3], DQuat, f64), b: (&str, [f64; 3], DQuat, f64)) -> String {
    let body = |(shape, x, q, v): (&str, [f64; 3], DQuat, f64)| {
        format!(
            "[[particles]]\nmaterial = \"steel\"\nshape = {shape}\npositions = [[{}, {}, {}]]\norientation = [{}, {}, {}, {}]\nvelocity = [{v}, 0.0, 0.0]\n",
            x[0], x[1], x[2], q.w, q.x, q.y, q.z
        )
    };
    let text = replaced(&test_scene("elastic_pair"), "stiffness = 1.0e5", &format!("stiffness = {stiffness:e}"));
    let bodies = text.find("[[particles]]").unwrap();
    format!("{}{}{}", &text[..bodies], body(a), body(b))
}

#[test]
fn a_tilted_cube_lands_on_its_face_and_then_stays_put() {
    // Tilted 8° about a skew axis: it lands on an edge, rocks onto its face and must then rest,
    // neither creeping (the spring holds it) nor spinning.
    let axis = DVec3::new(1.0, 2.0, 0.0).normalize();
    let q = DQuat::from_axis_angle(axis, 8f64.to_radians());
    let text = cube_drop([0.0, 0.0, 0.03], [q.w, q.x, q.y, q.z], 0.3, 1.5);
    let mut s = sim(&text);
    s.advance((1.25 / s.plan().model.dt) as u64);
    let (x1, q1) = (s.cpu().state().pos[0], s.cpu().state().orient[0]);
    s.advance(s.plan().run.steps - s.steps());
    let st = s.cpu().state();
    // Face down: one body axis points along z.
    let up = [DVec3::X, DVec3::Y, DVec3::Z].iter().map(|&a| (st.orient[0] * a).dot(DVec3::Z).abs()).fold(0.0, f64::max);
    eprintln!(
        "tilted cube: up {up}, drift {:e} m, turn {:e} rad, ω {:e}",
        (st.pos[0] - x1).length(),
        st.orient[0].angle_between(q1),
        st.omega[0].length()
    );
    assert!(up > 1.0 - 1e-9, "not flat on a face: {up}");
    assert!((st.pos[0] - x1).length() < 1e-9, "creeps by {:e} m in 0.25 s", (st.pos[0] - x1).length());
    assert!(st.orient[0].angle_between(q1) < 1e-8, "turns by {:e} rad in 0.25 s", st.orient[0].angle_between(q1));
    assert!(st.omega[0].length() < 1e-7 && st.vel[0].length() < 1e-7, "still moving: v {}, ω {}", st.vel[0], st.omega[0]);
}

/// `scenes/test/mixed_bed.toml`: a box of cubes, dodecahedra and spheres (randomly turned)
/// poured onto a floor, with springs, for `duration`.
fn mixed_bed(duration: f64) -> String {
    replaced(&test_scene("mixed_bed"), "duration = 0.2", &format!("duration = {duration}"))
}

/// Initial mechanical energy and |ΔE| / E0 after `duration` (dissipation counted).
fn energy_balance(text: &str) -> (usize, f64, tumble::Observables) {
    let mut s = sim(text);
    let e0 = s.observables().mechanical_energy();
    s.advance(s.plan().run.steps);
    let o = s.observables();
    (s.particles(), (o.mechanical_energy() + o.dissipated_energy - e0).abs() / e0.abs(), o)
}

/// The mixed bed with only its cubes (the first group).
fn cube_bed(duration: f64) -> String {
    let text = mixed_bed(duration);
    let start = text.find("[[particles]]\nmaterial = \"glass\"\nshape = { platonic").unwrap();
    let end = text.find("[[walls]]").unwrap();
    format!("{}{}", &text[..start], &text[end..])
}

#[test]
fn a_frictional_bed_of_cubes_balances_its_energy() {
    let (n, balance, o) = energy_balance(&cube_bed(0.2));
    eprintln!("cube bed: {n} cubes, |ΔE|/E0 = {balance:.3e}, dissipated {:.3e} J, contacts {}", o.dissipated_energy, o.contacts);
    assert!(o.contacts > 40 && o.dissipated_energy > 0.0, "the cubes should have landed");
    assert!(balance < 2e-3, "energy balance off by {balance:e} of E0");
}

/// A frictional bed of cubes, dodecahedra and spheres over 0.4 s (slow in a debug build: about a
/// minute in release). Measured: 4.6e-4 in the volume model; the depth model's contacts, which
/// are not a potential, left 17 %.
#[test]
#[ignore = "slow: a minute in a release build (cargo test --release --test polyhedra -- --ignored)"]
fn a_mixed_bed_of_polyhedra_and_spheres_balances_its_energy() {
    let (n, balance, o) = energy_balance(&mixed_bed(0.4));
    eprintln!("mixed bed: {n} particles, |ΔE|/E0 = {balance:.3e}, contacts {}", o.contacts);
    assert!(balance < 2e-3, "energy balance off by {balance:e} of E0");
}

#[test]
fn polyhedra_results_are_bit_identical_for_1_2_and_4_threads() {
    let run = |threads: usize| {
        let mut s = Simulation::new(compile(&parse_scene(&mixed_bed(0.05)).unwrap()).unwrap(), threads);
        s.advance(s.plan().run.steps);
        let st = s.cpu().state();
        let mut rows: Vec<(u32, [u64; 13])> = (0..st.len())
            .map(|i| {
                let q = st.orient[i];
                let bits = [
                    st.pos[i].x,
                    st.pos[i].y,
                    st.pos[i].z,
                    st.vel[i].x,
                    st.vel[i].y,
                    st.vel[i].z,
                    st.omega[i].x,
                    st.omega[i].y,
                    st.omega[i].z,
                    q.w,
                    q.x,
                    q.y,
                    q.z,
                ];
                (st.id[i], bits.map(f64::to_bits))
            })
            .collect();
        rows.sort_unstable_by_key(|r| r.0);
        rows
    };
    let one = run(1);
    assert_eq!(one, run(2));
    assert_eq!(one, run(4));
}

#[test]
fn a_run_with_polyhedra_writes_orientations_and_body_surfaces() {
    // Two cubes and a sphere falling for a few snapshots: tracks.csv carries the quaternion and
    // bodies_NNNNNN.vtp holds six quads per cube, at the turned corners.
    let q = DQuat::from_rotation_z(0.3);
    let text = cube_drop([0.0, 0.0, 0.05], [q.w, q.x, q.y, q.z], 0.5, 0.02);
    let text = replaced(&text, "[run]", "[run]\noutput_interval = 0.005\nsnapshot_interval = 0.01");
    let text = replaced(&text, "positions = [[0.0, 0.0, 0.05]]", "positions = [[0.0, 0.0, 0.05], [0.1, 0.0, 0.05]]\ntrack = true")
        + "[[particles]]\nmaterial = \"steel\"\nshape = { sphere = { diameter = 0.02 } }\npositions = [[-0.1, 0.0, 0.05]]\n";
    let out = std::env::temp_dir().join(format!("tumble-bodies-{}", std::process::id()));
    let _ = std::fs::remove_dir_all(&out);
    let compiled = compile(&parse_scene(&text).unwrap()).unwrap();
    tumble::run_compiled(compiled, &tumble::RunOptions { out_dir: Some(out.clone()), threads: 1, ..Default::default() }).unwrap();
    let tracks = std::fs::read_to_string(out.join("tracks.csv")).unwrap();
    let header = tracks.lines().next().unwrap();
    assert!(header.ends_with(",qw,qx,qy,qz"), "{header}");
    let first: Vec<f64> = tracks.lines().nth(1).unwrap().split(',').map(|v| v.parse().unwrap()).collect();
    assert!((first[11] - q.w).abs() < 1e-6 && (first[14] - q.z).abs() < 1e-6, "quaternion columns {first:?}");
    assert!(out.join("bodies.pvd").exists());
    // The XML part of the (binary) files.
    let vtp = String::from_utf8_lossy(&std::fs::read(out.join("snapshots/bodies_000000.vtp")).unwrap()).into_owned();
    assert!(vtp.contains("NumberOfPoints=\"16\"") && vtp.contains("NumberOfPolys=\"12\""), "two cubes: 16 corners, 12 faces");
    let particles = String::from_utf8_lossy(&std::fs::read(out.join("snapshots/particles_000000.vtp")).unwrap()).into_owned();
    assert!(particles.contains("Name=\"orientation\" NumberOfComponents=\"4\"") && particles.contains("Name=\"shape\""));
    let _ = std::fs::remove_dir_all(&out);
}

/// The plan's contact time sees a polyhedron's effective mass at its worst vertex: two cubes
/// meeting corner-first act as m/5.5 each (1/m + m|v|²/I / m with |v|² = 3a²/4, I = m a²/6),
/// so t_col shrinks by √5.5 against two spheres of the same mass and law. The overlap-volume
/// model meets a face lying on a face with the law 1 + 2 × 4 = 9 times (the volume, four corners,
/// four edges), stiffer still: there t_col shrinks by 3.
#[test]
fn the_time_step_sees_the_mass_a_cube_has_at_its_corner_and_the_stiffness_of_its_face() {
    let collision_time = |shape: &str, model: &str| {
        let text = spinning(shape, [0.0; 3], 1e-5, 0.01)
            .replace("dt = 0.00001", "dt = { collision_fraction = 50 }")
            .replace("positions = [[0.0, 0.0, 0.0]]", "positions = [[-0.5, 0.0, 0.0], [0.5, 0.0, 0.0]]")
            .replace("angular_velocity = [0, 0, 0]", "")
            .replacen("[contact]\n", &format!("[contact]\npolyhedron_model = \"{model}\"\n"), 1);
        let plan = compile(&parse_scene(&text).unwrap()).unwrap_or_else(|e| panic!("{e}")).plan;
        (plan.report.timescales.collision_time.unwrap(), plan.model.dt)
    };
    // The sphere of the cube's volume: the same mass.
    let d = 0.1 * (6.0 / std::f64::consts::PI).cbrt();
    let (sphere, sphere_dt) = collision_time(&format!("{{ sphere = {{ diameter = {d} }} }}"), "depth");
    for (model, ratio) in [("depth", 5.5f64), ("volume", 9.0)] {
        let (cube, cube_dt) = collision_time("{ cube = { edge = 0.1 } }", model);
        let expected = ratio.sqrt();
        assert!(
            (sphere / cube / expected - 1.0).abs() < 1e-9,
            "{model}: t_col sphere {sphere:e} / cube {cube:e} = {}, expected {expected}",
            sphere / cube
        );
        // Δt = t_col / 50, then shortened to fit a whole number of steps into the duration.
        assert!(cube_dt <= cube / 50.0 && cube_dt > 0.99 * cube / 50.0, "Δt {cube_dt:e} for t_col {cube:e}");
        assert!(sphere_dt / cube_dt > 0.99 * expected, "Δt sphere {sphere_dt:e} cube {cube_dt:e}");
    }
}

/// (E + dissipated) / E0 at the end of the scene.
fn energy_ratio(text: &str) -> f64 {
    let mut s = sim(text);
    let e0 = s.observables().mechanical_energy();
    s.advance(s.plan().run.steps);
    let o = s.observables();
    (o.mechanical_energy() + o.dissipated_energy) / e0
}

/// A uniformly random rotation (Shoemake) from a 64-bit LCG.
fn random_rotation(seed: &mut u64) -> DQuat {
    let mut next = || {
        *seed = seed.wrapping_mul(6364136223846793005).wrapping_add(1442695040888963407);
        (*seed >> 11) as f64 / (1u64 << 53) as f64
    };
    let (u1, u2, u3) = (next(), next(), next());
    let t = std::f64::consts::TAU;
    DQuat::from_xyzw((1.0 - u1).sqrt() * (t * u2).sin(), (1.0 - u1).sqrt() * (t * u2).cos(), u1.sqrt() * (t * u3).sin(), u1.sqrt() * (t * u3).cos())
}

/// Elastic, frictionless collisions of randomly turned cubes and dodecahedra (1 m/s, offsets up to
/// 12 mm, so faces, edges and corners meet): the volume model's force is a gradient, so
/// (E + dissipated) / E0 stays at 1 to Verlet's error. Measured: worst 1.0e-4 at the plan's step
/// (2.5e-5 with the volume and corners alone; the depth model: 0.9996–1.0096).
#[test]
fn random_elastic_collisions_of_polyhedra_keep_their_energy() {
    let mut seed = 7u64;
    let mut ratios = Vec::new();
    for shape in ["{ cube = { edge = 0.03 } }", "{ platonic = { kind = \"dodecahedron\", radius = 0.02 } }"] {
        for k in 0..8 {
            let (qa, qb) = (random_rotation(&mut seed), random_rotation(&mut seed));
            let offset = 0.004 * (k % 4) as f64;
            let text = elastic_pair(1.0e5, (shape, [-0.04, offset, 0.0], qa, 0.5), (shape, [0.04, 0.0, 0.0], qb, -0.5))
                .replace("duration = 1.0", "duration = 0.09");
            ratios.push(energy_ratio(&text));
        }
    }
    let worst = ratios.iter().map(|r| (r - 1.0).abs()).fold(0.0, f64::max);
    eprintln!("elastic collisions (E + dissipated) / E0: {ratios:.6?}, worst {worst:.3e}");
    assert!(worst < 1e-3, "an elastic collision changed the energy by {worst:e}");
}

/// The same in a bed: 72 frictionless, elastic cubes poured into a box for 0.2 s. Measured: 1.0000
/// in the volume model, 1.047 in the depth model (so it is checked too: the gap is real).
#[test]
fn a_frictionless_elastic_bed_of_cubes_keeps_its_energy() {
    let text = cube_bed(0.2).replace("restitution = 0.5", "restitution = 1.0").replace("tangential = { model = \"history\", friction = 0.4 }\n", "");
    assert!(!text.contains("tangential") && text.contains("restitution = 1.0"));
    let r = energy_ratio(&text);
    let depth = energy_ratio(&text.replacen("[contact]\n", "[contact]\npolyhedron_model = \"depth\"\n", 1));
    eprintln!("frictionless elastic cube bed: (E + dissipated) / E0 = {r:.6} (volume), {depth:.4} (depth)");
    assert!((r - 1.0).abs() < 5e-3, "the elastic bed's energy changed by {:e}", r - 1.0);
    assert!((depth - 1.0).abs() > 1e-2, "the depth model should show its known gap, got {depth}");
}
