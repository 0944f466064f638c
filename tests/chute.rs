//! The periodic inclined chute (scenes/chute.toml) at CI size: a short start of the flow runs
//! under the instability monitor without a stop, and the mass through its flow plane on the
//! periodic slope axis matches the spheres' own unwrapped displacements, Σ m Δx / L_x.

use tumble::{FlowCounter, Monitor, RunOptions, Simulation, load_scene, run_compiled};

fn scene_path() -> std::path::PathBuf {
    std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join("scenes").join("chute.toml")
}

/// The run loop itself (outputs, flow-plane columns, the monitor at every row) over the first
/// 10 ms: no false alarm from the potential energy across wraps.
#[test]
fn the_chute_runs_under_the_monitor_at_the_plan_step() {
    let compiled = load_scene(&scene_path(), Some(0.01), None).unwrap();
    assert!(compiled.plan.run.monitor.enabled);
    let out = std::env::temp_dir().join(format!("tumble-chute-{}", std::process::id()));
    let _ = std::fs::remove_dir_all(&out);
    let summary = run_compiled(compiled, &RunOptions { out_dir: Some(out.clone()), threads: 2, ..Default::default() })
        .unwrap_or_else(|e| panic!("the chute stopped: {e}"));
    let csv = std::fs::read_to_string(out.join("observables.csv")).unwrap();
    let header: Vec<&str> = csv.lines().next().unwrap().split(',').collect();
    assert!(header.contains(&"mass_downslope"), "{header:?}");
    assert!(summary.final_observables.kinetic_energy > 0.0);
    let _ = std::fs::remove_dir_all(&out);
}

/// 100 ms of flow started from rest, the monitor checking every 1 ms. The flow plane's mass is
/// exactly Σ m × the change of ⌊(x_unwrapped − p) / L_x⌋ between the first and the last state
/// (the net crossings telescope over the rows, however often a sphere wrapped in between), and
/// within a few % of Σ m Δx / L_x = M ⟨Δx⟩ / L_x, the mean velocity's flux: each sphere's
/// crossings differ from its Δx / L_x by less than one, with no sign preferred once the spheres
/// have spread along x (measured 0.2 % after a third of a box length on average).
/// Potential energy from wrapped positions would have stopped the run at the first wrap, and
/// side-of-plane counting loses every sphere that goes round between two rows.
#[test]
fn the_chute_flux_through_its_periodic_plane_matches_the_spheres_displacements() {
    let compiled = load_scene(&scene_path(), Some(0.1), None).unwrap();
    let (steps, dt) = (compiled.plan.run.steps, compiled.plan.model.dt);
    let mut sim = Simulation::new(compiled, 2);
    let plan = sim.plan().clone();
    let l = plan.model.domain.extent();
    let plane = plan.model.flow_planes[0].plane.clone();
    assert_eq!(plane.normal, glam::DVec3::X);
    let s0 = sim.state().into_owned();
    let range: f64 = {
        let height = (l * plan.model.gravity.abs()).element_sum();
        (0..s0.len()).filter(|&i| s0.inv_mass[i] != 0.0).map(|i| s0.mass[i] * height).sum()
    };
    let monitor = Monitor::new(&plan, &sim.observables(), range);
    let mut flow = FlowCounter::new(&sim);
    let every = (1e-3 / dt).round() as u64;
    while sim.steps() < steps {
        sim.advance(every.min(steps - sim.steps()));
        monitor.check(sim.steps(), &sim.observables()).unwrap_or_else(|e| panic!("{e}"));
        flow.update(&sim);
    }
    let s = sim.state();
    assert_eq!(s.len(), s0.len(), "no sphere left the chute");
    let mut start = vec![glam::DVec3::ZERO; s0.len()];
    for i in 0..s0.len() {
        start[s0.id[i] as usize] = s0.unwrapped(i, l);
    }
    let level = |x: glam::DVec3| ((x.x - plane.point.x) / l.x).floor();
    let (mut carried, mut crossed, mut wrapped, mut total) = (0.0, 0.0, 0, 0.0);
    for i in (0..s.len()).filter(|&i| s.inv_mass[i] != 0.0) {
        let (x0, x1) = (start[s.id[i] as usize], s.unwrapped(i, l));
        carried += s.mass[i] * (x1.x - x0.x) / l.x;
        crossed += s.mass[i] * (level(x1) - level(x0));
        wrapped += (s.image[i][0] != 0) as usize;
        total += s.mass[i];
    }
    let measured = flow.mass[0];
    println!(
        "{measured:.5e} kg through the plane ({:.2} box masses), net crossings of the unwrapped paths {crossed:.5e} kg, Σ m Δx / L_x = {carried:.5e} kg; {wrapped} spheres wrapped",
        measured / total
    );
    assert!(measured > 0.2 * total, "the flow should carry a fifth of its mass through the plane in 100 ms, carried {measured:e} kg of {total:e} kg");
    assert!(wrapped as f64 > 0.2 * s.len() as f64, "a fifth of the spheres should wrap round the periodic axis, {wrapped} did");
    assert!((measured - crossed).abs() <= 1e-9 * measured, "flow plane {measured:e} kg against the unwrapped paths' net crossings {crossed:e} kg");
    assert!((measured - carried).abs() <= 0.05 * carried, "flow plane {measured:e} kg against Σ m Δx / L_x = {carried:e} kg");
}
