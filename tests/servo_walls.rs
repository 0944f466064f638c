//! Servo walls: a wall translated along a direction until the particles push back on it with
//! a target force (proportional control of its speed, capped at `max_speed`).

use tumble::{Simulation, compile, parse_scene};
use tumble_testkit::scenes::{replaced, test_scene};

fn sim(text: &str) -> Simulation {
    Simulation::new(compile(&parse_scene(text).unwrap()).unwrap_or_else(|e| panic!("{e}")), 1)
}

/// The press scene run to its end: (the plate's offset, the load on it along its direction,
/// the floor's load, the sphere's centre height, the run).
fn pressed(text: &str) -> (f64, f64, f64, f64, Simulation) {
    let mut s = sim(text);
    s.advance(s.plan().run.steps);
    let frame = s.frame(false);
    let (offset, press, floor) = (frame.servo_offset[1], frame.wall_force[1].z, -frame.wall_force[0].z);
    let z = s.state().pos[0].z;
    (offset, press, floor, z, s)
}

#[test]
fn a_servo_plate_holds_a_sphere_on_a_floor_with_its_target_force() {
    let (offset, press, floor, z, s) = pressed(&test_scene("servo_press"));
    let (k, r, target) = (1.0e5, 0.05, 50.0);
    let weight = s.state().mass[0] * 9.81;
    // At rest: the plate carries the target, the floor the target plus the weight; each overlap
    // is its force over k, so the plate stands at 2r less both overlaps (it started at 0.12).
    let (top, bottom) = (target / k, (target + weight) / k);
    let expected = 0.12 - (2.0 * r - top - bottom);
    println!(
        "press {press} N (target {target}), floor {floor} N (target + mg = {}), offset {offset} m (expected {expected}), centre {z}",
        target + weight
    );
    assert!((press - target).abs() < 1e-9 * target, "the plate holds {press} N, not {target}");
    assert!((floor - target - weight).abs() < 1e-9 * target, "the floor holds {floor} N");
    assert!((offset - expected).abs() < 1e-9 * expected, "the plate travelled {offset} m, expected {expected}");
    assert!((z - (r - bottom)).abs() < 1e-12, "centre at {z}");
    // The plate's work went into the contacts' elastic energy and the damping (booked at each
    // pass's force times the speed of the step before it: 0.7 % high while the load rises).
    let o = s.observables();
    let gain = o.mechanical_energy() + o.dissipated_energy - (s.state().mass[0] * 9.81 * r);
    println!("plate work {} J, gain {gain} J", o.wall_work);
    assert!(o.wall_work > 0.0 && (o.wall_work - gain).abs() < 0.02 * o.wall_work, "work {} vs gain {gain}", o.wall_work);
}

#[test]
fn a_servo_mesh_presses_as_a_servo_plane() {
    let dir = std::env::temp_dir().join(format!("tumble-servo-{}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    let sheet = dir.join("plate.obj");
    // A two-sided sheet at z = 0.12 (its normal's side does not matter).
    std::fs::write(&sheet, "v -0.2 -0.2 0.12\nv 0.2 -0.2 0.12\nv 0.2 0.2 0.12\nv -0.2 0.2 0.12\nf 1 2 3\nf 1 3 4\n").unwrap();
    let text = test_scene("servo_press");
    let plane = pressed(&text);
    let mesh = pressed(&replaced(
        &text,
        "plane = { point = [0.0, 0.0, 0.12], normal = [0.0, 0.0, -1.0] }",
        &format!("mesh = {{ file = \"{}\" }}", sheet.display()),
    ));
    println!("plane: offset {} press {}; mesh: offset {} press {}", plane.0, plane.1, mesh.0, mesh.1);
    assert!((plane.0 - mesh.0).abs() < 1e-12 && (plane.1 - mesh.1).abs() < 1e-9, "mesh {:?} vs plane {:?}", (mesh.0, mesh.1), (plane.0, plane.1));
    std::fs::remove_dir_all(&dir).unwrap();
}

#[test]
fn a_servo_run_continued_from_a_snapshot_is_bit_identical() {
    let text = test_scene("servo_press");
    let mut straight = sim(&text);
    let steps = straight.plan().run.steps;
    straight.advance(steps);
    // Stopped while the plate is still closing in (the contact starts near 0.4 s).
    let mut first = sim(&text);
    first.advance(steps / 2 + 17);
    let snap = tumble_state::Snapshot::from_bytes(&first.snapshot().to_bytes()).unwrap();
    assert!(snap.walls.servos[1].speed > 0.0, "{:?}", snap.walls.servos);
    let mut resumed = sim(&text);
    resumed.restore(&snap).unwrap();
    resumed.advance(steps - snap.step);
    let bits = |s: &Simulation| {
        let st = s.state();
        let f = s.frame(false);
        (st.pos[0].to_array().map(f64::to_bits), st.vel[0].to_array().map(f64::to_bits), f.servo_offset[1].to_bits(), f.wall_work[1].to_bits())
    };
    assert_eq!(bits(&straight), bits(&resumed));
}

#[test]
fn a_servo_is_refused_with_a_motion_or_a_bad_force_and_on_the_gpu() {
    let text = test_scene("servo_press");
    for (with, field, says) in [
        (
            "servo = { direction = [0.0, 0.0, -1.0], force = 50.0, max_speed = 0.05 }\nmotion = { translate = { velocity = [0.0, 0.0, -0.1] } }",
            "walls[1].servo.direction",
            "without motion",
        ),
        ("servo = { direction = [0.0, 0.0, -1.0], force = -50.0, max_speed = 0.05 }", "walls[1].servo.force", "positive"),
        ("servo = { direction = [0.0, 0.0, 0.0], force = 50.0, max_speed = 0.05 }", "walls[1].servo.direction", "non-zero"),
        ("servo = { direction = [0.0, 0.0, -1.0], force = 50.0, max_speed = 0.0 }", "walls[1].servo.max_speed", "positive"),
    ] {
        let bad = replaced(&text, "servo = { direction = [0.0, 0.0, -1.0], force = 50.0, max_speed = 0.05 }", with);
        let err = compile(&parse_scene(&bad).unwrap()).unwrap_err().to_string();
        assert!(err.contains(field) && err.contains(says) && !err.contains('\n'), "{err}");
    }
    let plan = compile(&parse_scene(&text).unwrap()).unwrap();
    assert!(plan.plan.model.wall_groups[1].moving, "a servo's power is reported");
    assert_eq!(plan.plan.report.wall_step_limit.as_ref().map(|l| l.speed), Some(0.05), "its largest speed bounds Δt");
    // The GPU backend refuses it in one line, before it looks for an adapter.
    let Err(e) = tumble_gpu::GpuSimulation::new(plan) else { panic!("the GPU backend took a servo wall") };
    let why = e.to_string();
    assert!(why.contains("servo walls") && why.contains("\"press\"") && !why.contains('\n'), "{why}");
}

/// Archard wear: a sphere (no rotation) sent sliding at 2 m/s across a mesh sheet of 16
/// triangles with μ = 0.5 has slid v0 t − ½ μ g t² at t = 0.3 s (it stops at 0.41 s); the sheet
/// has lost K/H · m g · (the distance slid), on the triangles under the path only.
#[test]
fn a_sliding_sphere_wears_the_triangles_under_its_path_as_archard_says() {
    let dir = std::env::temp_dir().join(format!("tumble-wear-{}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    // 8 squares of 0.25 m along x (x from −0.5 to 1.5), two triangles each.
    let mut obj = String::new();
    for i in 0..=8 {
        let x = -0.5 + 0.25 * i as f64;
        obj += &format!("v {x} -0.5 0\nv {x} 0.5 0\n");
    }
    for i in 0..8 {
        let (a, b, c, d) = (2 * i + 1, 2 * i + 3, 2 * i + 4, 2 * i + 2);
        obj += &format!("f {a} {b} {c}\nf {a} {c} {d}\n");
    }
    let sheet = dir.join("sheet.obj");
    std::fs::write(&sheet, obj).unwrap();
    let (k, h) = (1e-4, 2e9);
    let text = replaced(
        &replaced(
            &replaced(&test_scene("belt"), "rotation = \"on\"", "rotation = \"off\""),
            "plane = { point = [0.0, 0.0, 0.0], normal = [0.0, 0.0, 1.0] }\nmotion = { translate = { velocity = [0.5, 0.0, 0.0] } }",
            &format!("mesh = {{ file = \"{}\" }}\nwear = {{ coefficient = {k}, hardness = {h} }}", sheet.display()),
        ),
        "positions = [[0.0, 0.0, 0.05]]",
        // Resting at its weight's overlap, m g / k.
        "positions = [[0.0, 0.0, 0.0495993]]\nvelocity = [2.0, 0.0, 0.0]",
    );
    let mut s = sim(&text);
    let steps = (0.3 / s.plan().model.dt).round() as u64;
    s.advance(steps);
    let (t, st) = (s.time(), s.state());
    let (m, slid) = (st.mass[0], st.pos[0].x);
    let wear = s.mesh_wear();
    let total: f64 = wear[0].iter().sum();
    let expected = k / h * m * 9.81 * slid;
    let analytic = 2.0 * t - 0.5 * 0.5 * 9.81 * t * t;
    println!("slid {slid} m (v0 t − ½ μ g t² = {analytic}), worn {total:e} m³ (K/H m g s = {expected:e}), per triangle {:?}", wear[0]);
    assert!((slid - analytic).abs() < 1e-3 * slid, "slid {slid}");
    // Booked with each pass's slip velocity, the step's end (a rectangle rule): −8e-4 at this Δt.
    assert!((total - expected).abs() < 2e-3 * expected, "worn {total} vs {expected}");
    // The path runs over squares 2 and 3 (x from 0 to 0.41): nothing elsewhere.
    for (t, &v) in wear[0].iter().enumerate() {
        let square = t / 2;
        assert!(v >= 0.0 && ((square == 2 || square == 3) || v == 0.0), "triangle {t} wore {v}");
    }
    assert!(wear[0][4] + wear[0][5] > 0.5 * total, "{:?}", wear[0]);
    // Wear continues across a restart bit for bit.
    let mut first = sim(&text);
    first.advance(101);
    let snap = tumble_state::Snapshot::from_bytes(&first.snapshot().to_bytes()).unwrap();
    let mut resumed = sim(&text);
    resumed.restore(&snap).unwrap();
    resumed.advance(steps - 101);
    let bits = |w: Vec<Vec<f64>>| w[0].iter().map(|v| v.to_bits()).collect::<Vec<_>>();
    assert_eq!(bits(resumed.mesh_wear()), bits(wear));
    std::fs::remove_dir_all(&dir).unwrap();
}
