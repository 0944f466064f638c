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

/// The sources suite's two streams on the GPU with the arrays grown 8 slots at a time end in
/// the state (positions, velocities, spins, by id, bit for bit) of a run that reserved one
/// chunk for everything. A snapshot of the grown run taken mid-way continues on a run planned
/// with the large chunk: the restore resizes that run's arrays to the snapshot's, and it ends
/// there too. Growth keeps the dead slots after the live ones, so no sum changes order.
pub fn arrays_grown_in_chunks_end_where_one_reservation_ends() {
    let grown_scene = scene(&tumble_testkit::suite::streams(0.3, 0.7, Some(8)));
    let reserved_scene = scene(&tumble_testkit::suite::streams(0.3, 0.7, None));
    let (total, every) = (grown_scene.plan.run.steps, grown_scene.plan.model.sources[0].every);
    assert_eq!(reserved_scene.plan.tuning.capacity_chunk, reserved_scene.plan.inserted_at_most(), "the default chunk holds every insertion here");
    let middle = 5 * every + every / 3;
    let mut grown = tumble::Simulation::on(BackendName::Gpu, grown_scene, 1).unwrap();
    let mut reserved = tumble::Simulation::on(BackendName::Gpu, reserved_scene.clone(), 1).unwrap();
    let (start_grown, start_reserved) = (gpu_of(&mut grown).slots(), gpu_of(&mut reserved).slots());
    // Each insertion event reads the state back once (the feeder's look at the particles gives
    // the insertion its slots too); each stretch between events ends with the history check.
    let events = {
        let mut steps: Vec<u64> = grown
            .plan()
            .model
            .sources
            .iter()
            .flat_map(|s| (s.first_step..=s.last_step).step_by(s.every as usize))
            .filter(|&s| s > 0 && s <= middle)
            .collect();
        steps.sort_unstable();
        steps.dedup();
        steps.len() as u64
    };
    let before = gpu_of(&mut grown).readbacks();
    grown.advance(middle);
    let readbacks = gpu_of(&mut grown).readbacks() - before;
    println!("{events} insertion events up to step {middle}: {readbacks} read-backs");
    assert!(readbacks <= 2 * events + 1, "{readbacks} read-backs for {events} insertion events");
    let snapshot = grown.snapshot();
    let books = tumble::Phase::snapshot(grown.dem());
    grown.advance(total - middle);
    reserved.advance(total);
    let mut continued = tumble::Simulation::on(BackendName::Gpu, reserved_scene, 1).unwrap();
    continued.restore(&snapshot).unwrap();
    assert_eq!(gpu_of(&mut continued).slots(), snapshot.device.as_ref().unwrap().counter("slots").unwrap() as u32, "the restore resized the arrays");
    tumble::Phase::restore(continued.dem_mut(), &books).unwrap();
    continued.advance(total - middle);
    let inserted = grown.inserted();
    let reserved_bytes = gpu_of(&mut reserved).memory_bytes();
    let g = gpu_of(&mut grown);
    let (times, slots, bytes) = (g.times_grown(), g.slots(), g.memory_bytes());
    println!(
        "grown 8 at a time: {times} times, {start_grown} → {slots} slots ({:.1} KiB); one reservation: {start_reserved} slots ({:.1} KiB); inserted {inserted:?}",
        bytes as f64 / 1024.0,
        reserved_bytes as f64 / 1024.0,
    );
    assert!(times >= 5, "the test must grow the arrays several times: {times}");
    assert!(start_grown < start_reserved);
    let end = grown.snapshot();
    for (name, other) in [("one reservation", reserved.snapshot()), ("continued on the other plan", continued.snapshot())] {
        let (a, b) = (&end.state, &other.state);
        assert_eq!(a.id, b.id, "{name}: other particles alive");
        let bits = |v: &[glam::DVec3]| v.iter().flat_map(|x| x.to_array().map(f64::to_bits)).collect::<Vec<_>>();
        assert!(bits(&a.pos) == bits(&b.pos) && bits(&a.vel) == bits(&b.vel) && bits(&a.omega) == bits(&b.omega), "{name}: the states differ");
        assert_eq!(end.outlets, other.outlets, "{name}");
        assert_eq!(end.walls.work, other.walls.work, "{name}");
    }
}

fn gpu_of(sim: &mut tumble::Simulation) -> &GpuSimulation {
    sim.gpu_simulation().expect("a GPU run")
}
