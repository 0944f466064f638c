//! Restart: a run continued from a snapshot (through its bytes) is bit-identical to the run
//! that wrote it, on the same backend (the GPU's snapshot carries the device image).

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
