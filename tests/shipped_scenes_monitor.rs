//! The plan's default Δt and the instability monitor on every shipped scene: the default meets
//! the plan's own accuracy target, every example and study scene runs under the monitor at it,
//! and the monitor's advice, when followed, makes a failing run pass.

use std::path::{Path, PathBuf};
use tumble::{Monitor, Observables, RunError, RunOptions, compile, parse_scene, read_scene, run_compiled};
use tumble_scene::schema::{DtSpec, IntegratorName, Scene};
use tumble_scene::{ACCURATE_STEPS_PER_COLLISION, STEPS_PER_COLLISION};

/// Example scenes (scenes/*.toml) and the study scenes the xtasks run (bench, conformance).
fn shipped_scenes() -> Vec<PathBuf> {
    let root = Path::new(env!("CARGO_MANIFEST_DIR")).join("scenes");
    let mut scenes = Vec::new();
    for dir in [root.clone(), root.join("bench"), root.join("conformance")] {
        scenes.extend(std::fs::read_dir(&dir).unwrap().map(|e| e.unwrap().path()).filter(|p| p.extension().is_some_and(|e| e == "toml")));
    }
    scenes.sort();
    assert!(scenes.len() >= 20, "found only {} scenes", scenes.len());
    scenes
}

/// The scene at the plan's default Δt.
fn at_default_dt(path: &Path) -> Scene {
    let mut scene = read_scene(path).unwrap_or_else(|e| panic!("{e}"));
    scene.run.dt = None;
    scene
}

fn tmp(name: &str) -> PathBuf {
    let d = std::env::temp_dir().join(format!("tumble-monitor-{name}-{}", std::process::id()));
    let _ = std::fs::remove_dir_all(&d);
    d
}

#[test]
fn the_default_dt_of_every_shipped_scene_meets_the_plans_accuracy_target() {
    for path in shipped_scenes() {
        let plan = compile(&at_default_dt(&path)).unwrap_or_else(|e| panic!("{}: {e}", path.display())).plan;
        let ts = &plan.report.timescales;
        let steps = plan.steps_per_collision();
        println!(
            "{}: default dt {:.4e} s, {} steps per collision, impact speed {:.3} m/s",
            path.display(),
            plan.model.dt,
            steps.map_or("no contact time, so no".into(), |s| format!("{s:.1}")),
            ts.impact.speed
        );
        if let Some(s) = steps {
            assert!(s >= STEPS_PER_COLLISION * (1.0 - 1e-9), "{}: {s} steps per collision at the default", path.display());
        }
        for w in &plan.report.warnings {
            assert!(!w.contains("steps per collision") && !w.contains("relaxation time"), "{}: the default triggers \"{w}\"", path.display());
        }
    }
}

#[test]
fn a_hertz_default_resolves_the_contact_at_the_printed_impact_speed() {
    // hertz_quads: spheres dropped onto quads; the drop sets the impact speed the default is taken at.
    let path = Path::new(env!("CARGO_MANIFEST_DIR")).join("scenes/hertz_quads.toml");
    let plan = compile(&at_default_dt(&path)).unwrap().plan;
    let ts = &plan.report.timescales;
    let g = plan.model.gravity.length();
    let particle = (ts.impact.initial.powi(2) + 2.0 * g * ts.impact.drop_height).sqrt();
    let expected = (2.0 * particle).max(particle + ts.impact.wall);
    assert!((ts.impact.speed - expected.max(0.1)).abs() <= 1e-12 * expected, "{:?}", ts.impact);
    assert!(ts.impact.drop_height > 0.0 && ts.impact.drop_height <= plan.model.domain.extent().max_element());
    let t_h = ts.collision_time.unwrap();
    assert!(plan.model.dt <= 0.2 * ts.rayleigh_time.unwrap() * (1.0 + 1e-12));
    assert!((t_h / plan.model.dt) >= STEPS_PER_COLLISION * (1.0 - 1e-9), "{} steps", t_h / plan.model.dt);
    let text = plan.describe(1);
    assert!(text.contains(&format!("impact       {:.4} m/s", ts.impact.speed)), "{text}");
}

#[test]
fn every_shipped_scene_runs_briefly_under_the_monitor_at_the_default_dt() {
    const STEPS: f64 = 300.0;
    for path in shipped_scenes() {
        let mut scene = at_default_dt(&path);
        let dt = compile(&scene).unwrap().plan.model.dt;
        scene.run.duration = scene.run.duration.min(STEPS * dt);
        scene.run.output_interval = Some(scene.run.duration / 6.0);
        scene.run.snapshot_interval = None;
        scene.run.monitor.enabled = true;
        let compiled = compile(&scene).unwrap();
        assert_eq!(compiled.plan.model.dt, dt);
        let out = tmp(&compiled.plan.run.name);
        let summary = run_compiled(compiled, &RunOptions { out_dir: Some(out.clone()), threads: 2, ..Default::default() })
            .unwrap_or_else(|e| panic!("{}: {e}", path.display()));
        assert!(summary.final_observables.finite, "{}", path.display());
        let _ = std::fs::remove_dir_all(&out);
    }
}

/// The Δt in "use dt <= X s" of a monitor message.
fn advised_dt(message: &str) -> f64 {
    let rest = message.split("use dt <= ").nth(1).unwrap_or_else(|| panic!("no advice in: {message}"));
    rest.split(' ').next().unwrap().parse().unwrap()
}

#[test]
fn following_the_monitors_advice_makes_an_unstable_run_pass() {
    // A sphere sliding on a floor, integrated at 1.5 × 2/ω: the contact oscillation grows every step.
    let path = Path::new(env!("CARGO_MANIFEST_DIR")).join("scenes/verify/03_sliding.toml");
    let mut scene = read_scene(&path).unwrap();
    let default_dt = compile(&at_default_dt(&path)).unwrap().plan.model.dt;
    // 2/ω of the sphere (d = 0.1 m, ρ = 10 kg/m³) on the floor with k_n = 1e5 N/m.
    let limit = 2.0 / (1.0e5 / (10.0 * std::f64::consts::PI / 6.0 * 1e-3)).sqrt();
    assert!(compile(&scene).unwrap().plan.report.timescales.stability_limit.unwrap() <= limit);
    scene.run.dt = Some(DtSpec::Seconds(1.5 * limit));
    scene.run.integrator = IntegratorName::SymplecticEuler;
    scene.run.allow_unstable_dt = true;
    // Rows every step of the failing run: the growth is seen before the contact ends.
    scene.run.output_interval = Some(1.5 * limit);
    let out = tmp("advice");
    let err = run_compiled(compile(&scene).unwrap(), &RunOptions { out_dir: Some(out.clone()), threads: 1, ..Default::default() }).unwrap_err();
    let RunError::Unstable(e) = &err else { panic!("expected an instability, got {err}") };
    let message = err.to_string();
    assert!(!message.contains('\n'), "one line: {message}");
    assert!(message.contains("is too large"), "names the step as the cause: {message}");
    let advice = advised_dt(&message);
    // The advice is the plan's default (within the message's four digits), not half the failed step.
    assert!((advice - default_dt).abs() <= 1e-4 * default_dt && (e.suggested_dt - default_dt).abs() <= 1e-12 * default_dt, "{message}");
    assert!(advice < 0.5 * limit);
    scene.run.dt = Some(DtSpec::Seconds(advice));
    scene.run.allow_unstable_dt = false;
    let summary =
        run_compiled(compile(&scene).unwrap(), &RunOptions { out_dir: Some(out.clone()), threads: 1, overwrite: true, ..Default::default() })
            .unwrap_or_else(|e| panic!("following \"{message}\" still fails: {e}"));
    assert!(summary.final_observables.finite);
    let _ = std::fs::remove_dir_all(&out);
}

/// A monitor for `scene`, whose t = 0 row is `initial`.
fn monitor_of(scene: &Scene, initial: &Observables) -> (Monitor, f64) {
    let plan = compile(scene).unwrap().plan;
    (Monitor::new(&plan, initial, 1.0), plan.model.dt)
}

fn row(time: f64, kinetic: f64, overlap: f64) -> Observables {
    Observables { time, kinetic_energy: kinetic, max_overlap_ratio: overlap, particles: 1, finite: true, ..Default::default() }
}

#[test]
fn a_deep_starting_overlap_is_named_at_t0_and_not_blamed_on_the_step() {
    let path = Path::new(env!("CARGO_MANIFEST_DIR")).join("scenes/verify/03_sliding.toml");
    let scene = read_scene(&path).unwrap();
    let start = Observables { elastic_energy: 2.0, ..row(0.0, 0.0, 0.8) };
    let (monitor, _) = monitor_of(&scene, &start);
    let e = monitor.check(0, &start).unwrap_err().to_string();
    assert!(e.contains("at step 0") && e.contains("t = 0") && e.contains("δ/r = 0.800") && e.contains("dt will not fix it"), "{e}");
    assert!(!e.contains("use dt <="), "{e}");
    // A start at δ/r = 0.3 passes t = 0; a later blow-up is put down to it, not to Δt.
    let start = row(0.0, 0.0, 0.3);
    let (monitor, _) = monitor_of(&scene, &start);
    assert!(monitor.check(0, &start).is_ok());
    let e = monitor.check(100, &row(0.01, 0.0, 0.7)).unwrap_err().to_string();
    assert!(e.contains("after a start with overlaps up to δ/r = 0.300") && e.contains("dt will not fix it"), "{e}");
    // A non-finite start is refused at t = 0 whether or not the monitor is on.
    let mut off = scene.clone();
    off.run.monitor.enabled = false;
    let bad = Observables { finite: false, ..row(0.0, f64::INFINITY, 0.0) };
    let (monitor, _) = monitor_of(&off, &bad);
    assert!(monitor.check(0, &bad).unwrap_err().to_string().contains("starting state is not finite"));
}

#[test]
fn energy_growth_at_the_default_dt_is_not_blamed_on_the_step() {
    let path = Path::new(env!("CARGO_MANIFEST_DIR")).join("scenes/verify/03_sliding.toml");
    let scene = at_default_dt(&path);
    let start = row(0.0, 1.0, 0.0);
    let (monitor, dt) = monitor_of(&scene, &start);
    let e = monitor.check(100, &row(0.01, 1.5, 0.01)).unwrap_err();
    assert!(e.cause.contains("energy grew by 5.000e-1 J"), "{e}");
    assert!(e.to_string().contains("the step is not the cause") && !e.to_string().contains("use dt <="), "{e}");
    assert_eq!(e.suggested_dt, dt);
    // The same gain at twice the default is the step's doing, and the advice is the default.
    let mut coarse = scene.clone();
    coarse.run.dt = Some(DtSpec::Seconds(2.0 * dt));
    let (monitor, _) = monitor_of(&coarse, &start);
    let e = monitor.check(100, &row(0.01, 1.5, 0.01)).unwrap_err();
    assert_eq!(e.suggested_dt, dt);
    assert!((advised_dt(&e.to_string()) - dt).abs() <= 1e-4 * dt, "{e}");
    assert!(ACCURATE_STEPS_PER_COLLISION < STEPS_PER_COLLISION);
}

#[test]
fn the_plan_prints_its_impact_speed_estimate() {
    let path = Path::new(env!("CARGO_MANIFEST_DIR")).join("scenes/ball_mill.toml");
    let scene = parse_scene(&std::fs::read_to_string(&path).unwrap()).unwrap();
    let plan = compile(&scene).unwrap().plan;
    let i = plan.report.timescales.impact;
    // A drum: the whole domain's height along g (walls lift particles) and the fastest wall point.
    assert!((i.drop_height - plan.model.domain.extent().y).abs() < 1e-12, "{i:?}");
    let particle = (2.0 * 9.81 * i.drop_height).sqrt();
    assert!(i.wall > 0.0 && (i.speed - (2.0 * particle).max(particle + i.wall)).abs() < 1e-9, "{i:?}");
    assert!(plan.describe(1).contains("impact       "));
}

#[test]
fn cohesion_stiffer_than_the_normal_spring_is_refused_by_the_plan() {
    let path = Path::new(env!("CARGO_MANIFEST_DIR")).join("scenes/conformance/cohesive_cluster.toml");
    let text = std::fs::read_to_string(&path).unwrap().replace("cohesion = { stiffness = 50.0 }", "cohesion = { stiffness = 1.0e7 }");
    let e = compile(&parse_scene(&text).unwrap()).unwrap_err().to_string();
    assert!(e.contains("k_c = 1.0000e7 N/m is not below the normal stiffness k_n = 1.0000e3 N/m") && e.contains("whatever the dt"), "{e}");
    // The shipped cluster (k_c = 50 N/m) compiles.
    assert!(compile(&read_scene(&path).unwrap()).is_ok());
}
