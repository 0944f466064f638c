//! Restart: a run continued from a snapshot (through its bytes) is bit-identical to the run
//! that wrote it, on the same backend (the GPU's snapshot carries the device image).

use crate::run_files::{assert_same_files, run_files};
use crate::scenes::{compiled, file};
use tumble::{Simulation, Snapshot};
use tumble_gpu::GpuSimulation;
use tumble_scene::schema::BackendName;

/// Tangential springs held now (the GPU keeps them on the device).
fn springs(sim: &Simulation) -> usize {
    match sim.downcast::<GpuSimulation>() {
        Some(gpu) => gpu.springs().len(),
        None => sim.state().history.total(),
    }
}

/// Runs `before` steps of `path`, snapshots through bytes, then compares `after` more steps of
/// the original with the same steps of a fresh simulation restored from the bytes.
fn continues_bit_identically(backend: BackendName, path: &str, before: u64, after: u64) {
    let sc = compiled(&file(path));
    let mut original = Simulation::on(backend, sc.clone(), 2).unwrap();
    original.advance(before);
    let bytes = original.snapshot().to_bytes();
    let at_snapshot = (original.observables(), original.neighbour_builds());
    original.advance(after);

    let mut restored = Simulation::on(backend, sc, 2).unwrap();
    restored.restore(&Snapshot::from_bytes(&bytes).unwrap()).unwrap();
    assert_eq!(restored.steps(), before);
    assert_eq!(restored.observables(), at_snapshot.0, "{path}: the restored state reads differently");
    restored.advance(after);
    let (a, b) = (original.snapshot(), restored.snapshot());
    assert!(a.state.len() > 10, "{path}: particles left: {}", a.state.len());
    assert!(a.walls.work.iter().any(|&w| w != 0.0), "{path}: the walls did work");
    assert!(springs(&original) > 0, "{path}: springs are held");
    if let (Some(then), Some(now)) = (at_snapshot.1, original.neighbour_builds()) {
        assert!(now > then, "{path}: the neighbour list is rebuilt after the snapshot too");
    }
    assert_eq!(a.to_bytes(), b.to_bytes(), "{path}: the continued run differs from the original");
    assert_eq!(original.observables(), restored.observables());
}

/// A mill with lifters and springs (moving shell and lifters, wall work as Kahan pairs,
/// springs in two generations, re-sorts; on the GPU the snapshot falls inside a submission
/// batch), and a drum of cubes (orientations and table shapes on top of the moving walls).
pub fn a_run_continued_from_a_snapshot_is_bit_identical(backend: BackendName) {
    continues_bit_identically(backend, "scenes/conformance/small_mill.toml", 203, 250);
    continues_bit_identically(backend, "scenes/conformance/cube_drum.toml", 200, 200);
}

/// The backend's state in the newest checkpoint of the run in `dir`.
fn final_state(dir: &std::path::Path) -> Vec<u8> {
    let (_, cp) = tumble::checkpoint::newest(dir).unwrap();
    without_device(&cp.snapshot)
}

/// A snapshot's particles and walls, without the device image (which keeps scratch buffers).
fn without_device(s: &Snapshot) -> Vec<u8> {
    let mut s = s.clone();
    s.device = None;
    s.to_bytes()
}

/// A run stopped and resumed from its checkpoints writes byte for byte the files of a run that
/// went straight through, and ends in the same state: stopped at T/2 by its duration (then resumed
/// to T) or by a signal after its first chunk; on the CPU resumed on 1 and on 2 threads.
pub fn a_resumed_run_writes_the_files_of_an_uninterrupted_one(backend: BackendName) {
    use std::sync::{Arc, atomic::AtomicBool};
    use tumble::{RunError, RunOptions, resume_run, run_scene_file};
    let root = std::env::temp_dir().join(format!("tumble-resume-{backend:?}-{}", std::process::id()));
    let _ = std::fs::remove_dir_all(&root);
    std::fs::create_dir_all(&root).unwrap();
    let text = file("scenes/conformance/small_mill.toml");
    let text = crate::scenes::replaced(&text, "duration = 0.6", "duration = 0.06\nsnapshot_interval = 0.01");
    let text = crate::scenes::replaced(&text, "output_interval = 0.02", "output_interval = 0.005");
    let scene = root.join("mill.toml");
    std::fs::write(&scene, text).unwrap();
    let options = |out: &str, threads: usize| RunOptions { out_dir: Some(root.join(out)), threads, backend: Some(backend), ..Default::default() };

    let straight = run_scene_file(&scene, &options("straight", 2)).unwrap();
    // Stopped at T/2 by its duration, resumed to T.
    let half = RunOptions { duration: Some(0.03), checkpoint_interval: Some(0.01), ..options("halves", 2) };
    run_scene_file(&scene, &half).unwrap();
    let resumed = resume_run(&root.join("halves"), &RunOptions { duration: Some(0.06), ..options("halves", 1) }).unwrap();
    // Stopped by a signal after the first chunk, resumed to the end.
    let flag = Arc::new(AtomicBool::new(true));
    let signalled = RunOptions { checkpoint_interval: Some(0.007), interrupt: Some(flag), ..options("signalled", 1) };
    let stop = run_scene_file(&scene, &signalled).unwrap_err();
    let RunError::Interrupted { step, .. } = stop else { panic!("{stop}") };
    assert!(step > 0 && step < straight.steps / 2, "stopped at step {step} of {}", straight.steps);
    let after_signal = resume_run(&root.join("signalled"), &options("signalled", 2)).unwrap();

    assert_eq!((resumed.steps, after_signal.steps), (straight.steps, straight.steps));
    assert_eq!(after_signal.resumed_from_step, Some(step));
    assert!(resumed.resumed_from_step.is_some_and(|s| 2 * s >= straight.steps - 2 && 2 * s <= straight.steps + 2), "{:?}", resumed.resumed_from_step);
    let reference = run_files(&root.join("straight"));
    assert!(reference.iter().any(|(n, _)| n.starts_with("snapshots/particles_")), "{:?}", reference.iter().map(|f| &f.0).collect::<Vec<_>>());
    for out in ["halves", "signalled"] {
        assert_same_files(&root.join("straight"), &root.join(out));
    }
    assert_eq!(final_state(&root.join("halves")), final_state(&root.join("signalled")), "the two resumed runs end in different states");
    let summary: serde_json::Value = serde_json::from_str(&std::fs::read_to_string(root.join("halves/summary.json")).unwrap()).unwrap();
    assert_eq!(summary["status"], "completed");
    assert_eq!(summary["resumed_from_step"], serde_json::json!(resumed.resumed_from_step.unwrap()));
    let _ = std::fs::remove_dir_all(&root);
}
