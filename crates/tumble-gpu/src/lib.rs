//! The GPU backend of tumble: the CPU backend's physics in f32 WGSL compute
//! shaders on whatever adapter wgpu reaches (Vulkan, Metal, DX12, GL; lavapipe
//! in CI).
//!
//! Each step: broad phase on the device (cell index, counting sort with a
//! reduce-then-scan prefix sum, cell ranges ordered by slot; the particle arrays
//! re-sorted by cell every `resort_interval` steps), the contact pass gather
//! style (each particle sums its own contacts over the 27 neighbouring cells and
//! the walls, pairs computed in canonical order and negated), then body forces
//! and the plan's integrator. There are no float atomics and the order of every
//! sum is fixed, so a run gives bit-identical results every time on one device.
//!
//! The plan's features are WGSL override constants: a scene without rotation,
//! cohesion, walls, moving walls, lifters, drag or periodic axes builds pipelines
//! without that code. Moving walls get their pose at each contact pass's force
//! time from the host, and their power per wall group is summed on the host in
//! id order ([`GpuSimulation::wall_power`], [`GpuSimulation::wall_work`]).
//!
//! ```no_run
//! let scene = tumble_scene::read_scene("scenes/box_settle.toml".as_ref()).unwrap();
//! let mut sim = tumble_gpu::GpuSimulation::new(tumble_scene::compile(&scene).unwrap()).unwrap();
//! sim.advance(100);
//! println!("{} on {}", sim.observables().kinetic_energy, sim.adapter());
//! ```

mod backend;
mod buffers;
mod context;
mod drums;
mod history;
mod kernels;
mod prisms;
pub mod profile;
mod readback;
mod reduce;
mod restore;
pub mod shaders;
pub mod shapes;
mod step;
mod upload;
mod walls;

pub use buffers::{BYTES_PER_CELL, BYTES_PER_PARTICLE, bytes_per_particle, history_bytes_per_particle, memory_bytes, wall_bytes_per_particle};
pub use context::{AdapterDescription, GpuError, available, gpu};
pub use kernels::{ShaderCompileStats, shader_compile_stats};
pub use upload::Grid;

use buffers::Buffers;
use context::Gpu;
use kernels::Kernels;
use std::cell::Cell;
use std::sync::Arc;
use tumble_scene::{CompiledScene, Plan};

/// Command buffers are submitted every this many steps.
pub(crate) const STEPS_PER_SUBMIT: u64 = 16;

/// A running GPU simulation.
pub struct GpuSimulation {
    plan: Plan,
    gpu: Arc<Gpu>,
    buffers: Buffers,
    kernels: Kernels,
    grid: upload::Grid,
    /// Particle slots on the device (removed particles keep theirs, flagged).
    slots: u32,
    /// Group and track flag by particle id (the device does not need them).
    group: Vec<u16>,
    track: Vec<bool>,
    step: u64,
    last_resort: Option<u64>,
    /// Committed contact passes: history generation `generation % 2` is the one read next.
    generation: u64,
    /// The first contact-history overflow found (the run stops there).
    overflow: Cell<Option<tumble_state::HistoryOverflow>>,
    /// Read-backs from the device so far (each one submission and one mapping).
    readbacks: Cell<u64>,
    /// Bytes those read-backs copied.
    readback_bytes: Cell<u64>,
    /// The output row's reductions and track gather (reduce.rs).
    reduction: reduce::Reduction,
    /// Particles still in the domain, when known since the last step.
    alive: Cell<Option<usize>>,
    /// Some wall moves: its pose is uploaded before every contact pass.
    moving: bool,
    /// Entries (vec4) of the wall section of the table (moving walls only).
    wall_entries: usize,
    /// The wall tables of the steps recorded since the last submission (moving walls only).
    pending_walls: Vec<[f32; 4]>,
    /// The time of the walls' pose in the last recorded contact pass.
    wall_time: f64,
    /// Lifter bars as table shapes (polyhedral particles only).
    hulls: prisms::PrismHulls,
}

impl GpuSimulation {
    /// Uploads a compiled scene to the process's GPU and evaluates the initial forces.
    pub fn new(scene: CompiledScene) -> Result<Self, GpuError> {
        let state = tumble_state::State::from_scene(&scene);
        Self::from_state(scene, state)
    }

    /// Sets up `scene` starting from `state` ([`tumble_state::State::from_scene`]'s arrays)
    /// instead of the scene's particles, its springs included (in f32).
    pub fn from_state(scene: CompiledScene, state: tumble_state::State) -> Result<Self, GpuError> {
        let hulls = prisms::PrismHulls::new(&scene.plan)?;
        if scene.plan.model.pairs.iter().any(|p| p.rolling > 0.0 && p.rolling_model == tumble_contact::RollingModel::Epsd2) {
            return Err(GpuError::Feature(
                "contact.rolling_model = \"epsd2\" (the rolling spring kept with the contact history) is not on the GPU backend yet; use backend = \"cpu\" or rolling_model = \"constant\"".into(),
            ));
        }
        if let Some(why) = upload::unsupported_walls(&scene.plan, &hulls) {
            return Err(GpuError::Feature(format!("{why}; use backend = \"cpu\"")));
        }
        let gpu = context::gpu()?;
        let plan = scene.plan;
        let arrays = upload::ParticleArrays::from_state(&state, &plan);
        let slots = arrays.pos.len() as u32;
        let grid = upload::Grid::new(&plan, arrays.pos.len());
        let (tables, shape_base) = upload::tables_with_shapes(&plan, &hulls)?;
        let params = upload::params(&plan, &grid, slots, shape_base);
        let moving = upload::moving_walls(&plan);
        // The wall section the stage rewrites each step: the 6-vec4 entries and their extras,
        // never the shape table after them.
        let wall_entries = if moving { upload::wall_table(&plan, 0.0, &hulls).len() } else { 0 };
        let walls = buffers::WallBuffers {
            groups: plan.model.wall_groups.len() as u64,
            work_groups: if moving { plan.model.wall_groups.len() as u64 } else { 0 },
            stage_bytes: 16 * (wall_entries as u64) * STEPS_PER_SUBMIT,
        };
        let buffers = Buffers::new(&gpu, &arrays, &tables, &params, &grid, upload::history_slots(&plan), walls)?;
        let kernels = Kernels::new(&gpu, &buffers, &shaders::Switches::from_plan(&plan))?;
        let reduction = reduce::Reduction::new(&gpu, &buffers, &kernels, &plan, slots, &state.track);
        let mut sim = GpuSimulation {
            group: state.group.clone(),
            track: state.track.clone(),
            plan,
            gpu,
            buffers,
            kernels,
            grid,
            slots,
            step: 0,
            last_resort: None,
            generation: 0,
            overflow: Cell::new(None),
            readbacks: Cell::new(0),
            readback_bytes: Cell::new(0),
            reduction,
            alive: Cell::new(Some(slots as usize)),
            moving,
            wall_entries,
            pending_walls: Vec::new(),
            wall_time: 0.0,
            hulls,
        };
        if sim.plan.model.history && state.history.total() > 0 {
            sim.upload_springs(&state.history);
        }
        let mut r = sim.recorder();
        sim.record_initial(&mut r);
        sim.submit(r.encoder);
        Ok(sim)
    }

    fn recorder(&self) -> step::Recorder<'static> {
        step::Recorder {
            encoder: self.gpu.device.create_command_encoder(&wgpu::CommandEncoderDescriptor { label: Some("tumble step") }),
            timing: None,
        }
    }

    pub fn plan(&self) -> &Plan {
        &self.plan
    }

    /// The adapter this simulation runs on.
    pub fn adapter(&self) -> &AdapterDescription {
        &self.gpu.adapter
    }

    /// The cell grid of the broad phase.
    pub fn grid(&self) -> &upload::Grid {
        &self.grid
    }

    /// Device memory this simulation holds, bytes.
    pub fn memory_bytes(&self) -> u64 {
        memory_bytes(self.slots as u64, &self.grid, upload::history_slots(&self.plan))
            + self.slots as u64 * buffers::wall_bytes_per_particle(&self.plan)
            + if self.plan.model.polyhedra { 16 * self.slots as u64 } else { 0 }
    }

    /// Submits recorded steps, with the wall poses they copy from the stage (moving walls).
    pub(crate) fn submit(&mut self, encoder: wgpu::CommandEncoder) -> wgpu::SubmissionIndex {
        if !self.pending_walls.is_empty() {
            // Queue writes run before the command buffers submitted after them and after those before.
            self.gpu.queue.write_buffer(&self.buffers.wall_stage, 0, bytemuck::cast_slice(&self.pending_walls));
            self.pending_walls.clear();
        }
        self.gpu.queue.submit([encoder.finish()])
    }

    /// Steps taken so far.
    pub fn steps(&self) -> u64 {
        self.step
    }

    /// Simulated time.
    pub fn time(&self) -> f64 {
        self.step as f64 * self.plan.model.dt
    }

    /// Advances `steps` steps (recorded in batches; returns once the device is done).
    /// With contact history the slot counts are checked every 256 steps and at the end, and
    /// the run stops at the first overflow (see [`GpuSimulation::history_overflow`]).
    pub fn advance(&mut self, steps: u64) {
        let mut left = steps;
        let mut previous = None;
        let mut batches = 0u64;
        while left > 0 {
            if self.plan.model.history && self.history_overflow().is_some() {
                break;
            }
            let batch = left.min(STEPS_PER_SUBMIT);
            let mut r = self.recorder();
            for _ in 0..batch {
                self.record_step(&mut r);
            }
            let index = self.submit(r.encoder);
            // Keep at most two batches in flight.
            if let Some(p) = previous.replace(index) {
                let _ = self.gpu.device.poll(wgpu::PollType::Wait { submission_index: Some(p), timeout: None });
            }
            left -= batch;
            batches += 1;
            // Every 16 batches (256 steps) and at the end: a small readback that waits for the device.
            if self.plan.model.history && (batches % 16 == 0 || left == 0) {
                self.check_history();
            }
        }
        self.wait();
        if steps > 0 && self.plan.model.domain.periodic.iter().any(|&p| !p) {
            self.alive.set(None);
        }
    }

    /// Blocks until the device has finished everything submitted.
    pub fn wait(&self) {
        let _ = self.gpu.device.poll(wgpu::PollType::Wait { submission_index: None, timeout: None });
    }

    /// Particles still in the domain.
    pub fn particles(&self) -> usize {
        if let Some(n) = self.alive.get() {
            return n;
        }
        let props: Vec<[u32; 4]> = self.read(&self.buffers.props, self.slots as usize);
        let n = props.iter().filter(|p| p[3] & upload::FLAG_DEAD == 0).count();
        self.alive.set(Some(n));
        n
    }

    /// Particles that left the domain through a non-periodic side.
    pub fn removed(&self) -> usize {
        self.slots as usize - self.particles()
    }

    /// Read-backs from the device so far: each is one submission, one mapping and one wait.
    pub fn readbacks(&self) -> u64 {
        self.readbacks.get()
    }

    /// Bytes copied back from the device by those read-backs so far.
    pub fn readback_bytes(&self) -> u64 {
        self.readback_bytes.get()
    }
}
