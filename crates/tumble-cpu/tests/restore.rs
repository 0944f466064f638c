//! CPU restarts beyond the suite's `restore` behaviour: a different thread count, and refusals.

use std::path::PathBuf;
use tumble_cpu::CpuSimulation;
use tumble_state::{Snapshot, SnapshotError};

fn scene_file(name: &str) -> tumble_scene::CompiledScene {
    let root = PathBuf::from(env!("CARGO_MANIFEST_DIR")).parent().and_then(|p| p.parent()).unwrap().to_path_buf();
    let path = root.join("scenes").join(name);
    tumble_scene::compile(&tumble_scene::read_scene(&path).unwrap()).unwrap()
}

#[test]
fn a_periodic_cascade_continues_bit_identically_on_another_thread_count() {
    // A periodic axis, two materials, cohesion, a fixed particle; restored on 1 thread, written on 2.
    let mut original = CpuSimulation::new(scene_file("pipe_cascade.toml"), 2);
    original.advance(500);
    let snapshot = original.snapshot();
    original.advance(500);
    let mut restored = CpuSimulation::new(scene_file("pipe_cascade.toml"), 1);
    restored.restore(&snapshot).unwrap();
    restored.advance(500);
    assert_eq!(original.snapshot().to_bytes(), restored.snapshot().to_bytes());
}

#[test]
fn a_snapshot_of_another_scene_or_version_is_refused_and_changes_nothing() {
    let mut heap = CpuSimulation::new(scene_file("heap_history.toml"), 1);
    heap.advance(10);
    let mut box_settle = CpuSimulation::new(scene_file("box_settle.toml"), 1);
    let before = box_settle.snapshot().to_bytes();
    let err = box_settle.restore(&heap.snapshot()).unwrap_err();
    assert!(matches!(err, SnapshotError::Mismatch(_)), "{err}");
    assert!(err.to_string().contains("heap"), "{err}");
    assert_eq!(box_settle.snapshot().to_bytes(), before);

    let mut bytes = heap.snapshot().to_bytes();
    bytes[8] = bytes[8].wrapping_add(1);
    assert!(matches!(Snapshot::from_bytes(&bytes), Err(SnapshotError::Version { found, expected }) if found == expected + 1));
    let bytes = heap.snapshot().to_bytes();
    assert!(matches!(Snapshot::from_bytes(&bytes[..bytes.len() - 3]), Err(SnapshotError::Corrupt(_))));
}
