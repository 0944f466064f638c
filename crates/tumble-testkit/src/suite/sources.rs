//! Particle sources and outlets: insertion on schedule and clear of everything, deletion at
//! the step a projectile's closed form says.

use crate::scenes::{compiled, replaced, test_scene};
use tumble::Simulation;
use tumble_scene::schema::BackendName;

/// Height the falling stream starts at, its speed, and the nominal top of the box outlet under it.
const Z0: f64 = 0.8;
const V0: f64 = 1.0;
const G: f64 = 9.81;

/// The step at which a centre released at `z0` with downward speed `v0` is first below `z`
/// (velocity Verlet is exact for constant acceleration: z_n = z0 − v0 n Δt − g (n Δt)² / 2).
fn steps_to_fall(z0: f64, v0: f64, z: f64, dt: f64) -> u64 {
    (1..).find(|&n| z0 - v0 * n as f64 * dt - 0.5 * G * (n as f64 * dt).powi(2) < z).unwrap()
}

/// The belt scene with the two streams and their outlets (`box_top`: the box outlet's top;
/// `plane_x`: where the outlet plane crosses x; `capacity_chunk`: `run.capacity_chunk`).
pub fn streams(box_top: f64, plane_x: f64, capacity_chunk: Option<u64>) -> String {
    let belt = match capacity_chunk {
        Some(c) => replaced(&test_scene("belt"), "[run]\n", &format!("[run]\ncapacity_chunk = {c}\n")),
        None => test_scene("belt"),
    };
    format!(
        "{}\n{}",
        belt,
        format!(
            r#"
[[sources]]
name = "down"
material = "steel"
shape = {{ sphere = {{ diameter = 0.05 }} }}
region = {{ plane = {{ point = [-1.2, 0.0, {Z0}], normal = [0.0, 0.0, -1.0], width = 0.6, height = 0.6 }} }}
velocity = [0.0, 0.0, -{V0}]
rate = {{ particles_per_second = 200.0 }}
total = {{ particles = 60 }}

[[sources]]
name = "sideways"
material = "steel"
shape = {{ sphere = {{ diameter = 0.05 }} }}
region = {{ plane = {{ point = [0.2, 0.0, 0.6], normal = [1.0, 0.0, 0.0], width = 0.4, height = 0.2 }} }}
velocity = [5.0, 0.0, 0.0]
rate = {{ particles_per_second = 100.0 }}
start = 0.05
stop = 0.3

[[outlets]]
name = "box"
box = {{ min = [-1.6, -0.4, 0.1], max = [-0.8, 0.4, {box_top}] }}

[[outlets]]
name = "wall"
plane = {{ point = [{plane_x}, 0.0, 0.0], normal = [1.0, 0.0, 0.0] }}
"#
        )
    )
}

/// Two sources on the belt scene: a stream falling from a rectangle into a box outlet, and a
/// sideways stream thrown at 5 m/s through an outlet plane. Every row's inserted count is the
/// rate's schedule exactly; each new particle clears every other by more than contact; and
/// each outlet deletes every particle at the step the projectile's closed form gives (the
/// outlets' bounds sit half a step from a crossing, so f32 rounding cannot move one), booking
/// count × mass.
pub fn sources_insert_on_schedule_and_outlets_delete_at_the_projectile_step(backend: BackendName) {
    // The scene's Δt depends on the sources' particles (same size here): compile once to learn it.
    let dt = compiled(&streams(0.3, 0.7, None)).plan.model.dt;
    // Outlet bounds half a step from a crossing.
    let n_fall = steps_to_fall(Z0, V0, 0.3, dt);
    let at = |n: u64| Z0 - V0 * n as f64 * dt - 0.5 * G * (n as f64 * dt).powi(2);
    let box_top = 0.5 * (at(n_fall - 1) + at(n_fall));
    let n_side = ((0.5 / (5.0 * dt)).floor() as u64) + 1;
    let plane_x = 0.2 + 5.0 * dt * (n_side as f64 - 0.5);
    let scene = compiled(&streams(box_top, plane_x, None));
    assert_eq!(scene.plan.model.dt, dt);
    let plan = scene.plan.clone();
    let (down, side) = (&plan.model.sources[0], &plan.model.sources[1]);
    let mass = 7800.0 * std::f64::consts::PI / 6.0 * 0.05f64.powi(3);
    let mut sim = Simulation::on(backend, scene, 1).unwrap();
    // Events of both sources, in step order, to stop at.
    fn events(s: &tumble_scene::Source) -> impl Iterator<Item = u64> + '_ {
        (0..).map(move |k| s.first_step + k * s.every).take_while(move |&st| st <= s.last_step)
    }
    let mut stops: Vec<u64> = events(down).chain(events(side)).filter(|&s| s > 0).collect();
    stops.sort_unstable();
    stops.dedup();
    // (insertion step, count) per source, for the outlets' expectations.
    let mut inserted_at: Vec<Vec<(u64, u64)>> = vec![vec![], vec![]];
    let mut last = sim.inserted().iter().map(|c| c.0).collect::<Vec<_>>();
    for (k, n) in last.iter().enumerate() {
        if *n > 0 {
            inserted_at[k].push((0, *n));
        }
    }
    let mut worst_gap = f64::INFINITY;
    let mut seen = 1 + last.iter().sum::<u64>() as usize;
    for &stop in &stops {
        sim.advance(stop - sim.steps());
        let now = sim.inserted();
        for k in 0..2 {
            let s = &plan.model.sources[k];
            // The schedule: rate × the time the events so far cover, capped by the total.
            let events_done = (stop.saturating_sub(s.first_step) / s.every + 1).min((s.last_step - s.first_step) / s.every + 1);
            let rate = [200.0, 100.0][k];
            let mut expected = (rate * (events_done * s.every) as f64 * dt + 1e-9).floor() as u64;
            if k == 0 {
                expected = expected.min(60);
            }
            if stop >= s.first_step {
                assert_eq!(now[k].0, expected, "{backend:?}: source {} inserted {} by step {stop}, its schedule {expected}", s.name, now[k].0);
            }
            if now[k].0 > last[k] {
                inserted_at[k].push((stop, now[k].0 - last[k]));
            }
        }
        last = now.iter().map(|c| c.0).collect();
        // The new particles (ids from `seen` on) clear every other particle.
        let state = sim.state();
        for i in (0..state.len()).filter(|&i| state.id[i] as usize >= seen) {
            for j in (0..state.len()).filter(|&j| j != i) {
                let gap = (state.pos[i] - state.pos[j]).length() - state.radius[i] - state.radius[j];
                worst_gap = worst_gap.min(gap / state.radius[i]);
            }
        }
        seen = 1 + last.iter().sum::<u64>() as usize;
    }
    let total = plan.run.steps;
    sim.advance(total - sim.steps());
    let tallies = sim.outlet_tallies();
    let deleted = |k: usize, n: u64| inserted_at[k].iter().filter(|(s, _)| s + n <= total).map(|(_, c)| c).sum::<u64>();
    let (expect_box, expect_wall) = (deleted(0, n_fall), deleted(1, n_side));
    println!(
        "{backend:?}: sources inserted {last:?} on schedule, smallest gap of a new particle {worst_gap:.3e} r; outlets deleted {} (box, expected {expect_box}) and {} (plane, expected {expect_wall}), {:.6e} and {:.6e} kg",
        tallies[0].count, tallies[1].count, tallies[0].mass, tallies[1].mass
    );
    assert!(worst_gap > 0.0, "{backend:?}: an inserted particle overlaps another by {:.3e} of its radius", -worst_gap);
    assert_eq!((tallies[0].count, tallies[1].count), (expect_box, expect_wall), "{backend:?}: outlets deleted off the projectile's step");
    assert!(expect_box > 10 && expect_wall > 10, "the test must delete particles at both outlets");
    for t in &tallies {
        // f32 masses on the GPU.
        assert!((t.mass / (t.count as f64 * mass) - 1.0).abs() < 1e-6, "{backend:?}: deleted mass {} for {} particles of {mass} kg", t.mass, t.count);
    }
    assert_eq!(sim.particles() as u64 + sim.removed() as u64 + expect_box + expect_wall, 1 + last.iter().sum::<u64>());
}

/// The two streams stopped between insertion events, snapshotted with the particles' books (the
/// sources' among them), and
/// continued in a new simulation: its final state (on the GPU the device image too) is the
/// uninterrupted run's, inserted and deleted particles included. The GPU's arrays grow 8 slots
/// at a time, so both runs grow several times and the restore first resizes the new run's.
pub fn a_run_with_sources_continued_from_a_snapshot_is_bit_identical(backend: BackendName) {
    let scene = compiled(&streams(0.3, 0.7, Some(8)));
    let (total, every) = (scene.plan.run.steps, scene.plan.model.sources[0].every);
    let middle = 3 * every + every / 2;
    let mut straight = Simulation::on(backend, scene.clone(), 2).unwrap();
    straight.advance(middle);
    let snapshot = straight.snapshot();
    let books = tumble::Phase::snapshot(straight.dem());
    straight.advance(total - middle);
    let mut continued = Simulation::on(backend, scene, 1).unwrap();
    continued.restore(&snapshot).unwrap();
    tumble::Phase::restore(continued.dem_mut(), &books).unwrap();
    continued.advance(total - middle);
    let (a, b) = (straight.snapshot(), continued.snapshot());
    println!(
        "{backend:?}: continued from step {middle} to {total}: {} particles, inserted {:?}, outlets {:?}",
        a.state.len(),
        continued.inserted(),
        continued.outlet_tallies().iter().map(|t| t.count).collect::<Vec<_>>()
    );
    assert!(continued.outlet_tallies().iter().all(|t| t.count > 0), "the test must delete particles after the snapshot");
    assert_eq!(straight.inserted(), continued.inserted());
    assert!(a.to_bytes() == b.to_bytes(), "{backend:?}: the continued run's final snapshot differs from the uninterrupted run's");
}
