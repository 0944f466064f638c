//! The backend seam on the GPU: an output row is one read-back, and tracked polyhedra carry
//! their real orientation, as on the CPU.

use tumble::Simulation;
use tumble_gpu::GpuSimulation;
use tumble_scene::{CompiledScene, compile, parse_scene};
use tumble_testkit::scenes::file;

/// The drum of cubes with lifters for `steps` steps, its top group tracked.
fn tracked_cube_drum(steps: u64) -> CompiledScene {
    let mut scene = parse_scene(&file("scenes/drum_cubes.toml")).unwrap();
    let dt = compile(&scene).unwrap().plan.model.dt;
    scene.run.duration = steps as f64 * dt;
    scene.run.dt = Some(tumble_scene::schema::DtSpec::Seconds(dt));
    let top = scene.particles.iter_mut().find(|g| g.name.as_deref() == Some("cubes-above")).expect("the drum's top group");
    top.track = true;
    compile(&scene).unwrap()
}

fn readbacks(sim: &Simulation) -> u64 {
    sim.downcast::<GpuSimulation>().expect("a GPU simulation").readbacks()
}

pub fn an_output_row_is_one_read_back() {
    let mut sim = Simulation::gpu(tracked_cube_drum(40)).unwrap();
    sim.advance(40);
    let before = readbacks(&sim);
    let frame = sim.frame(false);
    assert_eq!(readbacks(&sim) - before, 1, "an output row without the particle arrays");
    // What the run loop asks beside the frame: the particles removed, the outlets' tallies.
    let before = readbacks(&sim);
    let _ = (sim.removed(), sim.particles(), sim.outlet_tallies());
    assert_eq!(readbacks(&sim), before, "the removed count after an output row costs a read-back");
    assert!(!frame.tracks.is_empty() && frame.drums.len() == 1 && frame.drums[0].charge_mass > 0.0, "tracks and the drum's charge are in the frame");
    let before = readbacks(&sim);
    let with_state = sim.frame(true);
    assert_eq!(readbacks(&sim) - before, 1, "an output row with the particle arrays");
    assert_eq!(with_state.state.as_ref().map(|s| s.len()), Some(frame.observables.particles));
    // The one read-back gives what the separate calls give.
    assert_eq!(frame.observables, sim.observables());
    assert_eq!(frame.wall_work, sim.wall_work());
    assert_eq!(frame.wall_power, sim.wall_power());
    assert_eq!(frame.tracks, sim.tracks());
    assert_eq!(format!("{:?}", frame.drums), format!("{:?}", sim.drum_profiles()));
    assert_eq!(format!("{:?}", frame.drums), format!("{:?}", with_state.drums), "the snapshot row's drums are the device's");
    println!("read-backs per output row: 1 ({} in all so far)", readbacks(&sim));
}

pub fn tracked_polyhedra_carry_the_cpus_orientation() {
    let steps = 60;
    let mut cpu = Simulation::new(tracked_cube_drum(steps), 1);
    let mut gpu = Simulation::gpu(tracked_cube_drum(steps)).unwrap();
    for at in [0, steps] {
        let (c, g) = (cpu.tracks(), gpu.tracks());
        assert!(c.len() > 5 && c.len() == g.len());
        let mut worst: f64 = 0.0;
        for (c, g) in c.iter().zip(&g) {
            assert_eq!(c.id, g.id);
            assert!(c.orientation.dot(glam::DQuat::IDENTITY).abs() < 0.999_999, "random orientations are not the identity");
            // q and −q are one rotation.
            worst = worst.max(1.0 - c.orientation.dot(g.orientation).abs());
        }
        println!("step {at}: worst 1 − |q_cpu · q_gpu| = {worst:.2e}");
        assert!(worst < 1e-6, "step {at}: the GPU's tracked orientation is not the CPU's ({worst:e})");
        cpu.advance(steps);
        gpu.advance(steps);
    }
}
