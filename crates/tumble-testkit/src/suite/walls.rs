//! Moving walls: a drum's drive power against the torque of its forces, flow planes and the
//! moving walls' snapshot series.

use crate::Observable::*;
use crate::Tolerance;
use crate::scenes::{compiled, replaced, steps, test_scene};
use glam::DVec3;
use tumble::{RunOptions, Simulation, compile, parse_scene, run_compiled};
use tumble_scene::schema::BackendName;

/// One ball in a turning drum with rolling resistance: the shell's power is ω times the torque
/// about the axis of the wall forces on the ball, (x − a) × F + I α, and the shell's own torque
/// (observables.csv's `tz_<shell>`) is that torque negated.
pub fn a_drum_drive_power_is_torque_times_omega(backend: BackendName) {
    let s = compiled(&replaced(&test_scene("drum_one_ball"), "duration = 3.0", "duration = 1.0"));
    let steps = steps(&s);
    let mut sim = Simulation::on(backend, s, 1).unwrap();
    let omega = 10.0 * std::f64::consts::TAU / 60.0;
    let g = DVec3::new(0.0, -9.81, 0.0);
    let (mut checked, mut worst) = (0, 0.0f64);
    for _ in 0..20 {
        sim.advance(steps / 20);
        let st = sim.state();
        let f = (st.acc[0] - g) * st.mass[0];
        let torque = (st.pos[0].cross(f) + st.alpha[0] / st.inv_inertia[0]).z;
        let power = sim.wall_power()[0];
        // The shell takes the reaction: its torque about the axis is the ball's, negated.
        let shell = sim.frame(false).wall_torque[0].z;
        let scale = torque.abs() + 5e-4 / omega;
        assert!((shell + torque).abs() <= Tolerance::on(WallLoad, backend) * scale, "shell torque {shell} vs −(ball's) {}", -torque);
        // A sign error or a missing ω is O(1) of the power.
        let tolerance = Tolerance::on(WallPower, backend);
        assert!((power - torque * omega).abs() <= tolerance * (power.abs() + 5e-4), "power {power} vs torque × ω {}", torque * omega);
        worst = worst.max((power - torque * omega).abs() / (power.abs() + 5e-4));
        checked += (power.abs() > 1e-4) as usize;
    }
    println!("{backend:?}: power against torque × ω within {worst:.1e}");
    assert!(checked > 15, "the ball should stay in contact and be driven");
    let p = sim.drum_profiles()[0];
    assert!(p.com_angle > 0.0 && p.torque_arm_power > 0.0, "{p:?}");
}

/// A flow plane counts the mass of the spheres falling through it; a paddle that touches
/// nothing does no work and is written as a series of snapshots.
pub fn flow_planes_count_the_mass_through_and_moving_walls_write_a_series(backend: BackendName) {
    let text = test_scene("flow_paddle");
    // A longer step than the plan's t_col/50 (still t_col/6) keeps the software GPU adapter quick.
    let text = match backend {
        BackendName::Gpu => replaced(&text, "duration = 0.4", "duration = 0.4\ndt = 2e-4"),
        BackendName::Cpu => text,
    };
    let out = std::env::temp_dir().join(format!("tumble-flow-{backend:?}-{}", std::process::id()));
    let _ = std::fs::remove_dir_all(&out);
    let compiled = compile(&parse_scene(&text).unwrap()).unwrap();
    run_compiled(compiled, &RunOptions { out_dir: Some(out.clone()), threads: 1, backend: Some(backend), ..Default::default() }).unwrap();
    let csv = std::fs::read_to_string(out.join("observables.csv")).unwrap();
    let header: Vec<&str> = csv.lines().next().unwrap().split(',').collect();
    let col = |name: &str| header.iter().position(|h| *h == name).unwrap_or_else(|| panic!("no column {name} in {header:?}"));
    let last: Vec<f64> = csv.lines().last().unwrap().split(',').map(|x| x.parse().unwrap()).collect();
    let mass = 5.0 * 7800.0 * std::f64::consts::PI / 6.0 * 0.02f64.powi(3);
    let through = last[col("mass_outlet")];
    println!("{backend:?}: mass through the outlet {through:e} of {mass:e} kg");
    // One sphere missing would be 20 %.
    assert!((through - mass).abs() < Tolerance::on(Mass, backend) * mass, "{through} vs {mass}");
    // A wall that never touches anything does no work.
    assert_eq!(last[col("power_paddle")], 0.0);
    assert!(out.join("walls.pvd").exists() && out.join("snapshots/walls_000004.vtp").exists());
    assert!(!out.join("walls.vtp").exists());
    let a = std::fs::read(out.join("snapshots/walls_000000.vtp")).unwrap();
    let b = std::fs::read(out.join("snapshots/walls_000004.vtp")).unwrap();
    assert_ne!(a, b, "the paddle turned");
    let _ = std::fs::remove_dir_all(&out);
}

/// `scenes/test/belt.toml`: a sphere dropped on a belt at V slips until its contact point moves
/// with the belt; the friction impulse J gives v = J/m and ω r = 5J/(2m), so its centre then
/// moves at 2/7 V, and the belt's work is the sphere's energy gain plus what was dissipated. The
/// belt is a plane translating in its own plane, then a conveyor: a quad whose surface velocity
/// (given with a part along its normal, which is dropped) moves while its geometry stays.
pub fn a_belt_drags_a_rolling_sphere_until_its_contact_point_moves_with_it(backend: BackendName) {
    let v = 0.5;
    let conveyor =
        "quad = { corners = [[-2.0, -1.0, 0.0], [2.0, -1.0, 0.0], [2.0, 1.0, 0.0], [-2.0, 1.0, 0.0]] }\nsurface_velocity = [0.5, 0.0, 0.3]";
    let belt = test_scene("belt");
    let moving_plane = "plane = { point = [0.0, 0.0, 0.0], normal = [0.0, 0.0, 1.0] }\nmotion = { translate = { velocity = [0.5, 0.0, 0.0] } }";
    let mut plane_work = None;
    for (what, text) in [("translating plane", belt.clone()), ("quad conveyor", replaced(&belt, moving_plane, conveyor))] {
        let s = compiled(&text);
        let steps = steps(&s);
        let mut sim = Simulation::on(backend, s, 1).unwrap();
        let start = sim.observables();
        sim.advance(steps);
        let st = sim.state();
        let contact = st.vel[0] + st.omega[0].cross(DVec3::new(0.0, 0.0, -0.05));
        let o = sim.observables();
        let gain = o.mechanical_energy() + o.dissipated_energy - start.mechanical_energy() - start.dissipated_energy;
        println!(
            "{backend:?}: belt ({what}): contact point {contact}, centre {} (2/7 V = {}), work {:.6e}, gain {gain:.6e}",
            st.vel[0],
            2.0 / 7.0 * v,
            o.wall_work
        );
        assert!((contact.x - v).abs() < Tolerance::on(BeltSpeed, backend), "{what}: contact point moves at {contact}, belt at {v}");
        assert!((st.vel[0].x - 2.0 / 7.0 * v).abs() < Tolerance::on(BeltSpeed, backend), "{what}: centre at {} vs 2/7 V", st.vel[0]);
        // Sliding and rolling friction dissipate; the belt's work is booked against both.
        assert!((o.wall_work - gain).abs() < 0.02 * o.wall_work, "{what}: work {} vs gain {gain}", o.wall_work);
        // The conveyor does the translating plane's work (a normal part left in its velocity
        // pushes the sphere up through the face: 21× the work, 8.5 mm/s upward on the GPU).
        let first = *plane_work.get_or_insert(o.wall_work);
        assert!((o.wall_work - first).abs() < 1e-5 * first, "{what}: work {} vs the translating plane's {first}", o.wall_work);
        assert!(st.vel[0].z.abs() < 1e-4, "{what}: the sphere leaves the belt at {}", st.vel[0]);
    }
}

/// `scenes/test/pile.toml` settling in its box. At every output the force and torque on the box
/// (about the origin) balance the particles' momentum: Σ F_wall = Σ m (g − a) and
/// Σ τ_wall = Σ x × m (g − a) − I α, since the pairs' forces and moments cancel; at rest the box
/// carries the bed's weight M g and its moment Σ m x × g (at rest after 2 s: on the CPU
/// the residual falls from 1e-4 at 1.2 s to 2e-10 at 2 s, on the GPU to 4e-6).
pub fn a_bed_at_rest_in_a_box_puts_its_weight_on_the_walls(backend: BackendName) {
    let s = compiled(&replaced(&replaced(&test_scene("pile"), "restitution = 0.5", "restitution = 0.1"), "duration = 1.0", "duration = 2.0"));
    let steps = steps(&s);
    let size = s.plan.model.domain.extent().length();
    let mut sim = Simulation::on(backend, s, 1).unwrap();
    let g = sim.plan().model.gravity;
    let tolerance = Tolerance::on(WallLoad, backend);
    let (mut worst_balance, mut weight, mut moment) = (0.0f64, DVec3::ZERO, DVec3::ZERO);
    let (mut force, mut torque) = (DVec3::ZERO, DVec3::ZERO);
    for _ in 0..10 {
        sim.advance(steps / 10);
        let frame = sim.frame(true);
        let st = frame.state.as_deref().unwrap();
        assert_eq!((frame.wall_force.len(), frame.wall_torque.len()), (1, 1), "one wall group, the box");
        (force, torque) = (frame.wall_force[0], frame.wall_torque[0]);
        let (mut momentum, mut angular) = (DVec3::ZERO, DVec3::ZERO);
        (weight, moment) = (DVec3::ZERO, DVec3::ZERO);
        for i in 0..st.len() {
            let f = tumble::vtk::particle_force(st, i, g);
            momentum -= f;
            angular -= st.pos[i].cross(f) + tumble::vtk::particle_torque(st, i);
            weight += st.mass[i] * g;
            moment += st.pos[i].cross(st.mass[i] * g);
        }
        let scale = weight.length();
        let balance = ((force - momentum).length() / scale).max((torque - angular).length() / (scale * size));
        assert!(balance <= tolerance, "wall force {force} vs Σ m (g − a) {momentum}, torque {torque} vs {angular}");
        worst_balance = worst_balance.max(balance);
    }
    let o = sim.observables();
    let (rest_force, rest_torque) = ((force - weight).length() / weight.length(), (torque - moment).length() / (weight.length() * size));
    println!(
        "{backend:?}: box load {force} (M g = {weight}), torque {torque} (Σ m x × g = {moment}); momentum balance within {worst_balance:.1e}, at rest within {rest_force:.1e} (force), {rest_torque:.1e} (torque); kinetic energy {:.1e} J",
        o.kinetic_energy
    );
    assert!(
        rest_force <= tolerance && rest_torque <= tolerance,
        "at rest the box carries M g = {weight} and Σ m x × g = {moment}: {force}, {torque}"
    );
}

/// `scenes/test/belt.toml`'s sphere resting on its floor, which starts oscillating vertically at
/// 0.2 s (x = A sin(ω S(t)), ramped to full speed over 0.1 s, S the motion time): the sphere
/// stays put until the start, then rides the floor. A spring-dashpot on a moving base follows it
/// with amplitude A / (1 − m ω² / k) (base excitation well below resonance, f / f_n = 0.2), and
/// the damping force sees the floor's true velocity: a floor posed without its velocity would
/// throw the sphere off by tens of per cent of A. (On the CPU: 0.08 % of A before the start,
/// 0.5 % after the ramp's transient.)
pub fn a_sphere_on_an_oscillating_floor_rides_it_from_its_start_time(backend: BackendName) {
    let text = replaced(&test_scene("belt"), "duration = 0.5", "duration = 0.6");
    let text = replaced(
        &text,
        "motion = { translate = { velocity = [0.5, 0.0, 0.0] } }",
        "motion = { oscillate = { direction = [0.0, 0.0, 1.0], amplitude = 0.002, frequency = 5.0 }, start = 0.2, ramp = 0.1 }",
    );
    let s = compiled(&text);
    let (dt, total) = (s.plan.model.dt, steps(&s));
    let timing = s.plan.model.walls[0].timing;
    let (m, k) = (7800.0 * std::f64::consts::PI / 6.0 * 0.1f64.powi(3), 1.0e5);
    let (a, omega, r) = (0.002, std::f64::consts::TAU * 5.0, 0.05);
    let rest = r - m * 9.81 / k;
    let mut sim = Simulation::on(backend, s, 1).unwrap();
    let (mut before, mut ramping, mut after) = (0.0f64, 0.0f64, 0.0f64);
    let chunk = 10;
    for _ in 0..total / chunk {
        sim.advance(chunk);
        let t = sim.time();
        let z = sim.state().pos[0].z;
        let expected = rest + a * (omega * timing.elapsed(t)).sin() / (1.0 - m * omega * omega / k);
        if t < 0.15 {
            continue;
        }
        if t <= 0.2 {
            before = before.max((z - rest).abs());
        } else {
            let err = (z - expected).abs();
            // The ramp's transient has decayed by 0.35 s (1/(ζ ω_n) = 0.03 s).
            if t < 0.35 { ramping = ramping.max(err) } else { after = after.max(err) }
        }
    }
    println!(
        "{backend:?}: oscillating floor: |z − rest| ≤ {before:.3e} m before the start, |z − steady response| ≤ {ramping:.3e} m while ramping, {after:.3e} m after (A = {a} m, dt = {dt:e} s)"
    );
    assert!(before < 0.01 * a, "the sphere moved before the floor started: {before:e} m");
    assert!(ramping < 0.05 * a, "the sphere does not follow the ramping floor: {ramping:e} m off");
    // The steady response's phase lag from damping (ζ = 0.22) is 0.003 rad: 0.4 % of A.
    assert!(after < 0.01 * a, "the sphere does not ride the floor: {after:e} m off");
}
