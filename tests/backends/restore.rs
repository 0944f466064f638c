//! GPU snapshots that do not fit are refused and change nothing (the suite's `restore`
//! behaviour continues runs bit-identically on every backend).

use crate::support::scene;
use tumble::{Snapshot, SnapshotError};
use tumble_gpu::GpuSimulation;

const SMALL_MILL: &str = include_str!("../../scenes/conformance/small_mill.toml");
const SMALL_CUBE_DRUM: &str = include_str!("../../scenes/conformance/cube_drum.toml");

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
