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

/// 20 ms of flow started from rest, the monitor checking every 1 ms, and the flow plane's mass
/// against Σ m Δx / L_x of the unwrapped positions: each sphere's crossings differ from its
/// Δx / L_x by less than one, and for Δx ≪ L_x that is a Bernoulli draw, so the sum agrees to a
/// few √(crossings) particle masses. Potential energy from wrapped positions would have stopped
/// the run at the first wrap, and side-of-plane counting loses every sphere that goes round.
#[test]
fn the_chute_flux_through_its_periodic_plane_matches_the_spheres_displacements() {
    let compiled = load_scene(&scene_path(), Some(0.02), None).unwrap();
    let (steps, dt) = (compiled.plan.run.steps, compiled.plan.model.dt);
    let mut sim = Simulation::new(compiled, 2);
    let plan = sim.plan().clone();
    let l = plan.model.domain.extent();
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
    let (mut carried, mut wrapped, mut m_mean, mut movable) = (0.0, 0, 0.0, 0);
    for i in (0..s.len()).filter(|&i| s.inv_mass[i] != 0.0) {
        carried += s.mass[i] * (s.unwrapped(i, l).x - start[s.id[i] as usize].x) / l.x;
        wrapped += (s.image[i][0] != 0) as usize;
        m_mean += s.mass[i];
        movable += 1;
    }
    m_mean /= movable as f64;
    let measured = flow.mass[0];
    let crossings = carried / m_mean;
    let tolerance = (4.0 * crossings.abs().sqrt() + 2.0) * m_mean;
    println!("{measured:.4e} kg through the plane, Σ m Δx / L = {carried:.4e} kg ({crossings:.0} crossings), {wrapped} spheres wrapped");
    assert!(crossings > 30.0, "the flow should carry tens of spheres through the plane in 20 ms, carried {crossings:.1}");
    assert!(wrapped > 20, "spheres should wrap round the periodic axis, {wrapped} did");
    assert!((measured - carried).abs() <= tolerance, "flow plane {measured:e} kg against Σ m Δx / L_x = {carried:e} kg (± {tolerance:e})");
}
