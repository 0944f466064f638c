//! GPU runs continued from a snapshot: bit-identical to the run that wrote it on the same
//! adapter; a snapshot that does not fit is refused and changes nothing.

use crate::support::scene;
use tumble::{Snapshot, SnapshotError};
use tumble_gpu::GpuSimulation;

const SMALL_MILL: &str = include_str!("../../scenes/conformance/small_mill.toml");
const SMALL_CUBE_DRUM: &str = include_str!("../../scenes/conformance/cube_drum.toml");

/// Runs `before` steps, snapshots through bytes, then compares `after` more steps of the
/// original with the same steps of a fresh simulation restored from the bytes.
fn continues_bit_identically(name: &str, text: &str, before: u64, after: u64) {
    let mut original = GpuSimulation::new(scene(text)).unwrap();
    original.advance(before);
    let bytes = original.snapshot().to_bytes();
    let at_snapshot = original.observables();
    original.advance(after);

    let mut restored = GpuSimulation::new(scene(text)).unwrap();
    restored.restore(&Snapshot::from_bytes(&bytes).unwrap()).unwrap();
    assert_eq!(restored.steps(), before);
    assert_eq!(restored.observables(), at_snapshot, "{name}: the restored state reads differently");
    restored.advance(after);
    let (a, b) = (original.snapshot(), restored.snapshot());
    assert!(a.state.len() > 10, "{name}: particles left: {}", a.state.len());
    assert!(a.walls.work.iter().any(|&w| w != 0.0), "{name}: the walls did work");
    assert!(!original.springs().is_empty(), "{name}: springs are held");
    assert!(a.device == b.device, "{name}: the continued run's device memory differs from the original's");
    assert_eq!(a.to_bytes(), b.to_bytes(), "{name}: the continued run differs from the original");
}

pub fn a_mill_with_lifters_and_springs_continues_bit_identically() {
    // Moving shell and lifters (wall work as Kahan pairs), springs in two generations, re-sorts;
    // the snapshot falls inside a submission batch.
    continues_bit_identically("small mill", SMALL_MILL, 203, 250);
}

pub fn a_drum_of_cubes_continues_bit_identically() {
    // Polyhedra: orientations and table shapes on top of the moving walls.
    continues_bit_identically("cube drum", SMALL_CUBE_DRUM, 150, 150);
}

pub fn a_snapshot_that_does_not_fit_is_refused_and_changes_nothing() {
    let mut mill = GpuSimulation::new(scene(SMALL_MILL)).unwrap();
    mill.advance(20);
    let before = mill.snapshot().to_bytes();

    let cpu = tumble::Simulation::new(scene(SMALL_MILL), 1).snapshot();
    let err = mill.restore(&cpu).unwrap_err();
    assert!(matches!(err, SnapshotError::Mismatch(_)) && err.to_string().contains("cpu"), "{err}");

    let cubes = GpuSimulation::new(scene(SMALL_CUBE_DRUM)).unwrap().snapshot();
    let err = mill.restore(&cubes).unwrap_err();
    assert!(matches!(err, SnapshotError::Mismatch(_)), "{err}");

    let mut cut = Snapshot::from_bytes(&before).unwrap();
    let image = cut.device.as_mut().unwrap();
    image.buffers[0].1.truncate(16);
    let err = mill.restore(&cut).unwrap_err();
    assert!(err.to_string().contains("`pos` buffer"), "{err}");
    cut.device = None;
    assert!(matches!(mill.restore(&cut), Err(SnapshotError::Corrupt(_))));

    assert_eq!(mill.snapshot().to_bytes(), before, "a refused restore changed the run");
}
