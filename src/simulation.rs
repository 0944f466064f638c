//! The backend-independent handle on a running simulation.

use glam::DVec3;
use std::borrow::Cow;
use tumble_cpu::{CpuSimulation, Observables, State, TrackRow};
use tumble_gpu::{AdapterDescription, GpuError, GpuSimulation};
use tumble_scene::schema::BackendName;
use tumble_scene::{CompiledScene, Plan};

/// A simulation on one backend: the CPU reference (f64) or the GPU (f32).
pub struct Simulation {
    backend: Backend,
}

enum Backend {
    Cpu(CpuSimulation),
    Gpu(Box<GpuSimulation>),
}

impl Simulation {
    /// Sets up a compiled scene on the CPU backend with `threads` threads.
    pub fn new(scene: CompiledScene, threads: usize) -> Self {
        Simulation { backend: Backend::Cpu(CpuSimulation::new(scene, threads)) }
    }

    /// Sets up a compiled scene on the GPU backend (the process's adapter).
    pub fn gpu(scene: CompiledScene) -> Result<Self, GpuError> {
        Ok(Simulation { backend: Backend::Gpu(Box::new(GpuSimulation::new(scene)?)) })
    }

    /// Sets up a compiled scene on the named backend (`threads` is for the CPU).
    pub fn on(backend: BackendName, scene: CompiledScene, threads: usize) -> Result<Self, GpuError> {
        match backend {
            BackendName::Cpu => Ok(Self::new(scene, threads)),
            BackendName::Gpu => Self::gpu(scene),
        }
    }

    pub fn plan(&self) -> &Plan {
        match &self.backend {
            Backend::Cpu(s) => s.plan(),
            Backend::Gpu(s) => s.plan(),
        }
    }

    pub fn backend_name(&self) -> &'static str {
        match &self.backend {
            Backend::Cpu(_) => "cpu",
            Backend::Gpu(_) => "gpu",
        }
    }

    pub fn device_name(&self) -> String {
        match &self.backend {
            Backend::Cpu(s) => format!("CPU, {} threads", s.threads()),
            Backend::Gpu(s) => s.adapter().to_string(),
        }
    }

    /// The GPU adapter, on the GPU backend.
    pub fn adapter(&self) -> Option<&AdapterDescription> {
        match &self.backend {
            Backend::Cpu(_) => None,
            Backend::Gpu(s) => Some(s.adapter()),
        }
    }

    pub fn precision(&self) -> &'static str {
        match &self.backend {
            Backend::Cpu(_) => "f64",
            Backend::Gpu(_) => "f32",
        }
    }

    pub fn advance(&mut self, steps: u64) {
        match &mut self.backend {
            Backend::Cpu(s) => s.advance(steps),
            Backend::Gpu(s) => s.advance(steps),
        }
    }

    /// Why the backend stopped short of the requested steps (a fixed capacity ran out), if it did.
    pub fn fault(&self) -> Option<String> {
        match &self.backend {
            Backend::Cpu(s) => s.history_overflow().map(|o| o.to_string()),
            Backend::Gpu(s) => s.history_overflow().map(|o| o.to_string()),
        }
    }

    pub fn steps(&self) -> u64 {
        match &self.backend {
            Backend::Cpu(s) => s.steps(),
            Backend::Gpu(s) => s.steps(),
        }
    }

    pub fn time(&self) -> f64 {
        match &self.backend {
            Backend::Cpu(s) => s.time(),
            Backend::Gpu(s) => s.time(),
        }
    }

    pub fn particles(&self) -> usize {
        match &self.backend {
            Backend::Cpu(s) => s.state().len(),
            Backend::Gpu(s) => s.particles(),
        }
    }

    pub fn removed(&self) -> usize {
        match &self.backend {
            Backend::Cpu(s) => s.removed(),
            Backend::Gpu(s) => s.removed(),
        }
    }

    pub fn observables(&self) -> Observables {
        match &self.backend {
            Backend::Cpu(s) => s.observables(),
            Backend::Gpu(s) => s.observables(),
        }
    }

    pub fn tracks(&self) -> Vec<TrackRow> {
        match &self.backend {
            Backend::Cpu(s) => s.tracks(),
            Backend::Gpu(s) => s.tracks(),
        }
    }

    /// Every particle still in the domain (the GPU's are read back and widened to f64, in id order).
    pub fn state(&self) -> Cow<'_, State> {
        match &self.backend {
            Backend::Cpu(s) => Cow::Borrowed(s.state()),
            Backend::Gpu(s) => Cow::Owned(s.state()),
        }
    }

    /// Power delivered to the particles by each wall group at the last force pass (zero for static walls).
    pub fn wall_power(&self) -> Vec<f64> {
        match &self.backend {
            Backend::Cpu(s) => s.wall_power().to_vec(),
            Backend::Gpu(s) => s.wall_power(),
        }
    }

    /// Work done on the particles by each wall group since t = 0.
    pub fn wall_work(&self) -> Vec<f64> {
        match &self.backend {
            Backend::Cpu(s) => s.wall_work().to_vec(),
            Backend::Gpu(s) => s.wall_work(),
        }
    }

    /// The charge profile of each drum of the plan.
    pub fn drum_profiles(&self) -> Vec<tumble_cpu::DrumProfile> {
        match &self.backend {
            Backend::Cpu(s) => s.drum_profiles(),
            Backend::Gpu(s) => s.drum_profiles(),
        }
    }

    /// The walls in their current pose.
    pub fn walls(&self) -> Cow<'_, [tumble_scene::Wall]> {
        match &self.backend {
            Backend::Cpu(s) => Cow::Borrowed(s.walls()),
            Backend::Gpu(s) => Cow::Owned(s.walls()),
        }
    }

    /// Contact force on the particle with id `id` in the last force pass.
    pub fn contact_force(&self, id: u32) -> Option<DVec3> {
        match &self.backend {
            Backend::Cpu(s) => s.index_of(id).map(|i| s.contact_sums()[i].force),
            Backend::Gpu(s) => s.contact_force(id),
        }
    }

    /// Neighbour-list rebuilds (the CPU's Verlet list; the GPU bins every step).
    pub fn neighbour_builds(&self) -> Option<u64> {
        match &self.backend {
            Backend::Cpu(s) => Some(s.neighbour_builds()),
            Backend::Gpu(_) => None,
        }
    }

    /// Memory this simulation's particle and grid arrays take, bytes (GPU: device memory).
    pub fn memory_bytes(&self) -> u64 {
        match &self.backend {
            Backend::Cpu(s) => s.plan().memory_bytes(s.state().len()) as u64,
            Backend::Gpu(s) => s.memory_bytes(),
        }
    }

    /// Bytes per particle of this backend's state.
    pub fn bytes_per_particle(&self) -> u64 {
        match &self.backend {
            Backend::Cpu(s) => s.plan().bytes_per_particle as u64,
            Backend::Gpu(s) => tumble_gpu::bytes_per_particle(s.plan()),
        }
    }

    /// The CPU simulation, for tests and tools that need its internals.
    ///
    /// # Panics
    /// On the GPU backend; use the backend-independent methods there.
    pub fn cpu(&self) -> &CpuSimulation {
        match &self.backend {
            Backend::Cpu(s) => s,
            Backend::Gpu(_) => panic!("Simulation::cpu() on a GPU simulation"),
        }
    }

    /// The GPU simulation, on the GPU backend.
    pub fn gpu_simulation(&mut self) -> Option<&mut GpuSimulation> {
        match &mut self.backend {
            Backend::Cpu(_) => None,
            Backend::Gpu(s) => Some(s),
        }
    }
}
