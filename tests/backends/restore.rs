//! GPU snapshots that do not fit are refused and change nothing (the suite's `restore`
//! behaviour continues runs bit-identically on every backend).

use crate::support::scene;
use tumble::{Snapshot, SnapshotError};
use tumble_gpu::GpuSimulation;
use tumble_scene::schema::BackendName;

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

/// The small mill's charge settled on the CPU seeds a GPU run (`run.start.from`): the device
/// holds the CPU's springs in f32 and starts with the CPU's energies; the GPU's snapshot seeds
/// the CPU back with the device's springs. (The mill's walls stay still: their motion starts
/// after the test, so the shader variant is the moving mill's.)
pub fn a_charge_settled_on_one_backend_seeds_the_other_with_its_springs() {
    let text = SMALL_MILL.replace("rpm = 60.0 } }", "rpm = 60.0 }, start = 100.0 }");
    let mut settle = tumble::Simulation::new(scene(&text), 2);
    settle.advance(2000);
    let settled = settle.snapshot().state;
    assert!(settled.history.total() > 100, "the settled charge holds springs: {}", settled.history.total());
    let (cpu_scene, cpu_state, _) = tumble::seed::seeded(scene(&text), &settled).unwrap();
    let cpu = tumble::Simulation::from_state(BackendName::Cpu, cpu_scene, cpu_state, 1).unwrap();
    let (gpu_scene, gpu_state, warnings) = tumble::seed::seeded(scene(&text), &settled).unwrap();
    assert!(warnings.is_empty(), "{warnings:?}");
    let mut gpu = tumble::Simulation::from_state(BackendName::Gpu, gpu_scene, gpu_state, 1).unwrap();
    // Every spring, in f32.
    let springs = gpu.gpu_simulation().unwrap().springs();
    assert_eq!(springs.len(), settled.history.total(), "the device holds every spring");
    for i in 0..settled.len() {
        for (key, s) in settled.history.of(i) {
            let held = springs[&(settled.id[i], key)];
            assert_eq!(held, [(s.xi.x as f32).to_bits(), (s.xi.y as f32).to_bits(), (s.xi.z as f32).to_bits()], "spring {} → {key}", settled.id[i]);
        }
    }
    let (a, b) = (cpu.observables(), gpu.observables());
    println!(
        "seeded: elastic energy CPU {:.6e} J, GPU {:.6e} J; kinetic {:.6e} / {:.6e} J",
        a.elastic_energy, b.elastic_energy, a.kinetic_energy, b.kinetic_energy
    );
    assert!((a.elastic_energy - b.elastic_energy).abs() < 1e-3 * a.elastic_energy, "elastic: CPU {a:?}, GPU {b:?}");
    assert!((a.potential_energy - b.potential_energy).abs() < 1e-5 * a.potential_energy.abs());
    // Back: the GPU's snapshot carries its springs to a CPU run.
    gpu.advance(50);
    let from_gpu = gpu.snapshot().state;
    let held = gpu.gpu_simulation().unwrap().springs().len();
    assert_eq!(from_gpu.history.total(), held);
    let (scene_back, state_back, _) = tumble::seed::seeded(scene(&text), &from_gpu).unwrap();
    assert_eq!(state_back.history.total(), held, "a CPU run seeded from the GPU holds the device's springs");
    let back = tumble::Simulation::from_state(BackendName::Cpu, scene_back, state_back, 1).unwrap();
    assert!(back.observables().elastic_energy > 0.0);
}
