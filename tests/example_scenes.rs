//! Every example scene compiles and runs (briefly) without tripping the instability monitor.

use std::path::Path;
use tumble::{RunOptions, load_scene, run_compiled, run_scene_file};

#[test]
fn every_example_scene_runs() {
    let root = Path::new(env!("CARGO_MANIFEST_DIR")).join("scenes");
    let mut scenes: Vec<_> =
        std::fs::read_dir(&root).unwrap().map(|e| e.unwrap().path()).filter(|p| p.extension().is_some_and(|e| e == "toml")).collect();
    scenes.push(root.join("bench/packed_bed.toml"));
    scenes.push(root.join("bench/packed_bed_history.toml"));
    scenes.push(root.join("lab_mill/lab_mill_20.toml"));
    scenes.push(root.join("lab_mill/lab_mill_30.toml"));
    // mill_at_speed starts from mill_settle's checkpoint: the_mill_settled_once_… runs it.
    scenes.push(root.join("protocols/hopper_gate.toml"));
    scenes.push(root.join("protocols/hopper_pour.toml"));
    scenes.push(root.join("protocols/mill_settle.toml"));
    scenes.sort();
    assert!(scenes.len() >= 5);
    for path in scenes {
        let full = load_scene(&path, None, None).unwrap_or_else(|e| panic!("{e}"));
        // 60 steps each: enough to exercise every pass without a long test.
        let compiled = load_scene(&path, Some(60.0 * full.plan.model.dt), None).unwrap();
        let out = std::env::temp_dir().join(format!("tumble-example-{}-{}", std::process::id(), full.plan.run.name));
        let summary = run_compiled(compiled, &RunOptions { out_dir: Some(out.clone()), threads: 2, ..Default::default() })
            .unwrap_or_else(|e| panic!("{}: {e}", path.display()));
        assert!(summary.steps >= 60 && summary.final_observables.finite, "{}", path.display());
        println!("{}: {} particles, {:.3e} particle-steps/s", path.display(), summary.particles, summary.particle_steps_per_second);
        let _ = std::fs::remove_dir_all(&out);
    }
}

/// The protocol of scenes/protocols/: the mill settles once (ending early when the balls rest)
/// and the settled charge starts the mill at 30, 50 and 70 % of its critical speed. Each run
/// starts from the same state, and the mill works harder on the charge the faster it turns.
#[test]
fn the_mill_settled_once_runs_at_three_speeds_from_one_checkpoint() {
    let root = Path::new(env!("CARGO_MANIFEST_DIR")).join("scenes/protocols");
    let dir = std::env::temp_dir().join(format!("tumble-protocol-{}", std::process::id()));
    let _ = std::fs::remove_dir_all(&dir);
    std::fs::create_dir_all(&dir).unwrap();
    let settle = dir.join("mill-settle");
    let settled =
        run_scene_file(&root.join("mill_settle.toml"), &RunOptions { out_dir: Some(settle.clone()), threads: 2, ..Default::default() }).unwrap();
    let why = settled.ended_early.expect("the charge comes to rest before the 3 s the scene allows");
    println!("settled: {why}");
    let text = std::fs::read_to_string(root.join("mill_at_speed.toml")).unwrap();
    let text = text.replace("from = \"out/mill-settle\"", &format!("from = {:?}", settle.to_str().unwrap()));
    let text = text.replace("duration = 2.0", "duration = 0.6");
    let read = |out: &Path, column: &str| -> Vec<f64> {
        let csv = std::fs::read_to_string(out.join("observables.csv")).unwrap();
        let header: Vec<&str> = csv.lines().next().unwrap().split(',').collect();
        let k = header.iter().position(|h| *h == column).unwrap();
        csv.lines().skip(1).map(|l| l.split(',').nth(k).unwrap().parse().unwrap()).collect()
    };
    let mut work = Vec::new();
    for rpm in ["13.76", "22.94", "32.12"] {
        let scene = dir.join(format!("mill_{rpm}.toml"));
        std::fs::write(&scene, text.replace("rpm = 32.12", &format!("rpm = {rpm}"))).unwrap();
        let out = dir.join(format!("mill-{rpm}"));
        run_scene_file(&scene, &RunOptions { out_dir: Some(out.clone()), threads: 2, ..Default::default() }).unwrap();
        for column in ["kinetic_energy", "potential_energy", "contacts"] {
            assert_eq!(read(&out, column)[0].to_bits(), read(&dir.join("mill-13.76"), column)[0].to_bits(), "{rpm} rpm starts elsewhere: {column}");
        }
        work.push(*read(&out, "wall_work").last().unwrap());
    }
    println!("wall work over 0.6 s at 30, 50, 70 % of critical: {work:?} J");
    assert!(work[0] > 0.0 && work[0] < work[1] && work[1] < work[2], "{work:?}");
    let _ = std::fs::remove_dir_all(&dir);
}
