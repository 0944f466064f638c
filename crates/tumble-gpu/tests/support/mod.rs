//! What the GPU test files share: one device used by one test at a time, the skip line when
//! there is no adapter, scene compilation, and the CPU and GPU simulations seen as one drum.
#![allow(dead_code)] // each test file uses a different part

use std::sync::Mutex;
use tumble_cpu::CpuSimulation;
use tumble_gpu::GpuSimulation;
use tumble_scene::{CompiledScene, compile, parse_scene};

static SERIAL: Mutex<()> = Mutex::new(());

/// Runs `f` on the GPU, or prints one skip line when there is no adapter.
pub fn on_gpu(name: &str, f: impl FnOnce()) {
    let _guard = SERIAL.lock().unwrap_or_else(|e| e.into_inner());
    match tumble_gpu::gpu() {
        Ok(_) => f(),
        Err(e) => println!("skipped {name}: no GPU adapter ({e})"),
    }
}

/// A scene text compiled; a bad scene fails the test with its message.
pub fn scene(text: &str) -> CompiledScene {
    compile(&parse_scene(text).unwrap()).unwrap_or_else(|e| panic!("{e}"))
}

/// Either backend, seen through the few calls a drum or mill test needs.
pub trait Drum {
    fn advance(&mut self, steps: u64);
    fn time(&self) -> f64;
    fn work(&self) -> Vec<f64>;
    fn profile(&self) -> tumble_cpu::DrumProfile;
    fn observables(&self) -> tumble_cpu::Observables;
}

impl Drum for CpuSimulation {
    fn advance(&mut self, steps: u64) {
        CpuSimulation::advance(self, steps)
    }
    fn time(&self) -> f64 {
        CpuSimulation::time(self)
    }
    fn work(&self) -> Vec<f64> {
        self.wall_work().to_vec()
    }
    fn profile(&self) -> tumble_cpu::DrumProfile {
        self.drum_profiles()[0]
    }
    fn observables(&self) -> tumble_cpu::Observables {
        CpuSimulation::observables(self)
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
    fn profile(&self) -> tumble_cpu::DrumProfile {
        self.drum_profiles()[0]
    }
    fn observables(&self) -> tumble_cpu::Observables {
        GpuSimulation::observables(self)
    }
}
