//! The backend-independent handle on a running simulation.

use tumble_cpu::{CpuSimulation, Observables, TrackRow};
use tumble_scene::{CompiledScene, Plan};

/// A simulation on one backend (the CPU reference for now).
pub struct Simulation {
    cpu: CpuSimulation,
}

impl Simulation {
    /// Sets up a compiled scene on the CPU backend with `threads` threads.
    pub fn new(scene: CompiledScene, threads: usize) -> Self {
        Simulation { cpu: CpuSimulation::new(scene, threads) }
    }

    pub fn plan(&self) -> &Plan {
        self.cpu.plan()
    }

    pub fn backend_name(&self) -> &'static str {
        "cpu"
    }

    pub fn device_name(&self) -> String {
        format!("CPU, {} threads", self.cpu.threads())
    }

    pub fn precision(&self) -> &'static str {
        "f64"
    }

    pub fn advance(&mut self, steps: u64) {
        self.cpu.advance(steps)
    }

    /// Why the backend stopped short of the requested steps (a fixed capacity ran out), if it did.
    pub fn fault(&self) -> Option<String> {
        self.cpu.history_overflow().map(|o| o.to_string())
    }

    pub fn steps(&self) -> u64 {
        self.cpu.steps()
    }

    pub fn time(&self) -> f64 {
        self.cpu.time()
    }

    pub fn particles(&self) -> usize {
        self.cpu.state().len()
    }

    pub fn removed(&self) -> usize {
        self.cpu.removed()
    }

    pub fn observables(&self) -> Observables {
        self.cpu.observables()
    }

    pub fn tracks(&self) -> Vec<TrackRow> {
        self.cpu.tracks()
    }

    /// The CPU state, for tests and tools that need every particle.
    pub fn cpu(&self) -> &CpuSimulation {
        &self.cpu
    }
}
