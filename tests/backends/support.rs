//! What the GPU test modules share: scene compilation and the CPU and GPU simulations seen
//! as one drum.

use tumble::{DrumProfile, Observables, Simulation};
use tumble_gpu::GpuSimulation;
pub use tumble_testkit::scenes::compiled as scene;

/// Either backend, seen through the few calls a drum or mill test needs.
pub trait Drum {
    fn advance(&mut self, steps: u64);
    fn time(&self) -> f64;
    fn work(&self) -> Vec<f64>;
    fn profile(&self) -> DrumProfile;
    fn observables(&self) -> Observables;
}

impl Drum for Simulation {
    fn advance(&mut self, steps: u64) {
        Simulation::advance(self, steps)
    }
    fn time(&self) -> f64 {
        Simulation::time(self)
    }
    fn work(&self) -> Vec<f64> {
        self.wall_work()
    }
    fn profile(&self) -> DrumProfile {
        self.drum_profiles()[0]
    }
    fn observables(&self) -> Observables {
        Simulation::observables(self)
    }
}

impl Drum for GpuSimulation {
    fn advance(&mut self, steps: u64) {
        GpuSimulation::advance(self, steps)
    }
    fn time(&self) -> f64 {
        GpuSimulation::time(self)
    }
    fn work(&self) -> Vec<f64> {
        self.wall_work()
    }
    fn profile(&self) -> DrumProfile {
        self.drum_profiles()[0]
    }
    fn observables(&self) -> Observables {
        GpuSimulation::observables(self)
    }
}
