//! Every example scene compiles and runs (briefly) without tripping the instability monitor.

use std::path::Path;
use tumble::{RunOptions, load_scene, run_compiled};

#[test]
fn every_example_scene_runs() {
    let root = Path::new(env!("CARGO_MANIFEST_DIR")).join("scenes");
    let mut scenes: Vec<_> =
        std::fs::read_dir(&root).unwrap().map(|e| e.unwrap().path()).filter(|p| p.extension().is_some_and(|e| e == "toml")).collect();
    scenes.push(root.join("bench/packed_bed.toml"));
    scenes.push(root.join("bench/packed_bed_history.toml"));
    scenes.push(root.join("lab_mill/lab_mill_20.toml"));
    scenes.push(root.join("lab_mill/lab_mill_30.toml"));
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
