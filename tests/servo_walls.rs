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
