//! Polyhedral particles in the engine (issue 6, verification case 6 and the polyhedra checks):
//! spin and tumbling, an elastic octahedron–cube collision, a cube settling on its face.

use glam::{DQuat, DVec3};
use tumble::{Simulation, compile, parse_scene};

fn sim(text: &str) -> Simulation {
    Simulation::new(compile(&parse_scene(text).unwrap()).unwrap_or_else(|e| panic!("{e}")), 1)
}

/// A free body (no gravity, no walls) of the given shape, spinning at `omega`.
fn spinning(shape: &str, omega: [f64; 3], dt: f64, duration: f64) -> String {
    format!(
        r#"
name = "spin"
[run]
duration = {duration}
dt = {dt}
integrator = "verlet"
[domain]
min = [-1.0, -1.0, -1.0]
max = [1.0, 1.0, 1.0]
[[materials]]
name = "steel"
density = 7800.0
[contact]
normal = {{ model = "linear", stiffness = 1.0e5 }}
restitution = 1.0
[[particles]]
material = "steel"
shape = {shape}
positions = [[0.0, 0.0, 0.0]]
angular_velocity = [{}, {}, {}]
"#,
        omega[0], omega[1], omega[2]
    )
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
fn case_6_spin_about_the_intermediate_axis_tumbles_conserving_energy_and_momentum() {
    let (de_coarse, dl, flip) = tumbling(2e-3);
    let (de_fine, _, _) = tumbling(1e-3);
    eprintln!("tumbling box: energy error {de_coarse:.3e} (dt 2e-3), {de_fine:.3e} (dt 1e-3); momentum error {dl:.3e}; min cos {flip:.4}");
    // The gyroscopic term is present: the body flips over (the y axis points backwards).
    assert!(flip < -0.9, "no tumbling: min cos {flip}");
    assert!(dl < 1e-10, "angular momentum drifts by {dl:e}");
    assert!(de_fine < 1e-5, "energy error {de_fine:e}");
    let order = (de_coarse / de_fine).log2();
    assert!((order - 2.0).abs() < 0.3, "energy error should fall as Δt²: order {order}");
}

/// An octahedron (vertex first) hits a cube face head-on at `speed`: rebound speed / impact speed.
fn octahedron_on_cube(speed: f64) -> f64 {
    let text = format!(
        r#"
name = "octahedron-cube"
[run]
duration = 1.0
integrator = "verlet"
[domain]
min = [-1.0, -1.0, -1.0]
max = [1.0, 1.0, 1.0]
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
    let mut s = sim(&text);
    // Until well after the contact ends (0.0005 m gap, then t_col = π √(m*/k)).
    let gap_time = 0.0005 / speed;
    let steps = ((gap_time + 0.01) / s.plan().dt).ceil() as u64;
    s.advance(steps);
    let st = s.cpu().state();
    let (a, b) = (s.cpu().index_of(0).unwrap(), s.cpu().index_of(1).unwrap());
    assert!(st.omega[a].length() < 1e-9 && st.omega[b].length() < 1e-9, "a central impact must not spin: {} {}", st.omega[a], st.omega[b]);
    (st.vel[b].x - st.vel[a].x) / speed
}

#[test]
fn octahedron_cube_elastic_rebound_within_half_a_percent() {
    let mut worst = 0.0f64;
    for speed in [0.0625, 0.125, 0.25, 0.5, 1.0, 2.0, 4.0] {
        let ratio = octahedron_on_cube(speed);
        eprintln!("octahedron on cube at {speed} m/s: rebound / impact = {ratio:.6}");
        worst = worst.max((ratio - 1.0).abs());
    }
    assert!(worst < 5e-3, "worst rebound error {worst:e}");
}

#[test]
fn a_cube_dropped_on_its_face_settles_without_drift_or_spin() {
    let text = r#"
name = "cube-drop"
[run]
duration = 1.0
integrator = "verlet"
[domain]
min = [-0.5, -0.5, -0.1]
max = [0.5, 0.5, 0.5]
[gravity]
acceleration = [0.0, 0.0, -9.81]
[[materials]]
name = "steel"
density = 7800.0
[contact]
normal = { model = "linear", stiffness = 1.0e5 }
restitution = 0.5
tangential = { model = "history", friction = 0.5 }
[[particles]]
material = "steel"
shape = { cube = { edge = 0.02 } }
positions = [[0.01, -0.02, 0.05]]
[[walls]]
name = "floor"
material = "steel"
plane = { point = [0.0, 0.0, 0.0], normal = [0.0, 0.0, 1.0] }
"#;
    let mut s = sim(text);
    s.advance(s.plan().steps);
    let st = s.cpu().state();
    let m = st.mass[0];
    let rest_height = 0.01 - m * 9.81 / 1.0e5;
    eprintln!("cube at rest: x = {}, ω = {}, q = {}", st.pos[0], st.omega[0], st.orient[0]);
    assert!((st.pos[0].x - 0.01).abs() < 1e-9 && (st.pos[0].y + 0.02).abs() < 1e-9, "drifted to {}", st.pos[0]);
    assert!((st.pos[0].z - rest_height).abs() < 1e-3 * 0.02, "rests at {} instead of {rest_height}", st.pos[0].z);
    assert!(st.omega[0].length() < 1e-9, "spins at {}", st.omega[0]);
    assert!(st.vel[0].length() < 1e-6, "moves at {}", st.vel[0]);
    let tilt = (st.orient[0] * DVec3::Z).dot(DVec3::Z);
    assert!(tilt > 1.0 - 1e-12 && st.orient[0].angle_between(DQuat::IDENTITY) < 1e-9, "turned: {}", st.orient[0]);
}

#[test]
fn a_tilted_cube_lands_on_its_face_and_then_stays_put() {
    // Tilted 8° about a skew axis: it lands on an edge, rocks onto its face and must then rest,
    // neither creeping (the spring holds it) nor spinning.
    let axis = DVec3::new(1.0, 2.0, 0.0).normalize();
    let q = DQuat::from_axis_angle(axis, 8f64.to_radians());
    let text = format!(
        r#"
name = "cube-tilted"
[run]
duration = 1.5
integrator = "verlet"
[domain]
min = [-0.5, -0.5, -0.1]
max = [0.5, 0.5, 0.5]
[gravity]
acceleration = [0.0, 0.0, -9.81]
[[materials]]
name = "steel"
density = 7800.0
[contact]
normal = {{ model = "linear", stiffness = 1.0e5 }}
restitution = 0.3
tangential = {{ model = "history", friction = 0.5 }}
[[particles]]
material = "steel"
shape = {{ cube = {{ edge = 0.02 }} }}
positions = [[0.0, 0.0, 0.03]]
orientation = [{}, {}, {}, {}]
[[walls]]
name = "floor"
material = "steel"
plane = {{ point = [0.0, 0.0, 0.0], normal = [0.0, 0.0, 1.0] }}
"#,
        q.w, q.x, q.y, q.z
    );
    let mut s = sim(&text);
    s.advance((1.0 / s.plan().dt) as u64);
    let (x1, q1) = (s.cpu().state().pos[0], s.cpu().state().orient[0]);
    s.advance(s.plan().steps - s.steps());
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
    assert!((st.pos[0] - x1).length() < 1e-9, "creeps by {:e} m in 0.5 s", (st.pos[0] - x1).length());
    assert!(st.orient[0].angle_between(q1) < 1e-6, "turns by {:e} rad in 0.5 s", st.orient[0].angle_between(q1));
    assert!(st.omega[0].length() < 1e-7 && st.vel[0].length() < 1e-7, "still moving: v {}, ω {}", st.vel[0], st.omega[0]);
}
