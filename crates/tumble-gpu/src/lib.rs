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
//! The SPH fluid has its own arrays, sort and kernels ([`GpuFluid`], fluid.rs).
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
mod fluid;
mod grow;
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

pub use buffers::{
    BYTES_PER_CELL, BYTES_PER_PARTICLE, bytes_per_particle, device_bytes, history_bytes_per_particle, memory_bytes, wall_bytes_per_particle,
};
pub use context::{AdapterDescription, GpuError, available, gpu};
pub use fluid::{FLUID_BYTES_PER_PARTICLE, FluidParams, FluidReadBack, GpuFluid, fluid_device_bytes, fluid_gpu_refusal, fluid_params};
pub use kernels::{ShaderCompileStats, shader_compile_stats};
pub use upload::Grid;

use buffers::Buffers;
use context::Gpu;
use kernels::Kernels;
use std::cell::Cell;
use std::sync::Arc;
use tumble_plan::{CompiledScene, Plan};

/// Command buffers are submitted every this many steps.
pub(crate) const STEPS_PER_SUBMIT: u64 = 16;

/// A running GPU simulation.
pub struct GpuSimulation {
    plan: Plan,
    gpu: Arc<Gpu>,
    buffers: Buffers,
    kernels: Kernels,
    grid: upload::Grid,
    /// Particle slots on the device (removed particles keep theirs, flagged; the slots for
    /// particles sources insert later wait flagged too, holding the ids they will be given).
    slots: u32,
    /// Ids given so far (initial and inserted particles): ids at and above it are empty slots.
    created: u32,
    /// The slot of each id waiting for insertion (`created..slots`), as read at a step.
    waiting: std::cell::RefCell<Option<(u64, Vec<u32>)>>,
    /// Particles removed and the outlets' tallies, counted at the step held (outlets only).
    departed: std::cell::RefCell<Option<(u64, usize, Vec<tumble_state::OutletTally>)>>,
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
    /// Sizes of the wall buffers.
    wall_buffers: buffers::WallBuffers,
    /// Times the arrays grew for the sources.
    grown: u32,
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
        if let Some(why) = walls::unsupported_walls(&scene.plan, &hulls) {
            return Err(GpuError::Feature(format!("{why}; use backend = \"cpu\"")));
        }
        let gpu = context::gpu()?;
        let plan = scene.plan;
        let mut arrays = upload::ParticleArrays::from_state(&state, &plan);
        // Ids are slots of the history and image tables: every id, inserted ones included, stays
        // below the slot count. One chunk is reserved for the sources; insert grows by chunks.
        let created = state.next_id();
        let capacity = created as u64 + plan.tuning.capacity_chunk;
        if capacity > u32::MAX as u64 / 2 {
            return Err(GpuError::Feature(format!(
                "the scene starts with {created} particle ids and a chunk of {} slots; the GPU backend holds at most 2^31 slots",
                plan.tuning.capacity_chunk
            )));
        }
        arrays.pad_to(capacity as usize, &plan);
        let slots = arrays.pos.len() as u32;
        let grid = upload::Grid::planned(&plan, created as u64);
        let (tables, params) = upload::tables_and_params(&plan, &hulls, &grid, slots)?;
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
        let mut group = state.group.clone();
        let mut track = state.track.clone();
        group.resize(slots as usize, 0);
        track.resize(slots as usize, false);
        let reduction = reduce::Reduction::new(&gpu, &buffers, &kernels, &plan, slots, &track);
        let mut sim = GpuSimulation {
            group,
            track,
            created,
            departed: Default::default(),
            waiting: Default::default(),
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
            alive: Cell::new(Some(state.len())),
            moving,
            wall_entries,
            wall_buffers: walls,
            grown: 0,
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
        device_bytes(&self.plan, self.slots as u64, &self.grid)
    }

    /// Particle slots on the device (at most the plan's capacity, grown in chunks).
    pub fn slots(&self) -> u32 {
        self.slots
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
            if self.plan.model.history && (batches.is_multiple_of(16) || left == 0) {
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
        if self.plan.model.outlets.is_empty() {
            // Every id given is alive or removed (no read-back after an output row).
            return self.created as usize - self.particles();
        }
        self.departures().0
    }

    /// Per outlet: particles it deleted and their mass (f32 masses summed in f64 in id order).
    pub fn outlet_tallies(&self) -> Vec<tumble_state::OutletTally> {
        if self.plan.model.outlets.is_empty() {
            return Vec::new();
        }
        self.departures().1
    }

    /// Particles removed through the domain's sides, and the outlets' tallies, from the flags of
    /// the dead slots: one read-back of props and masses per step at most.
    fn departures(&self) -> (usize, Vec<tumble_state::OutletTally>) {
        if let Some((step, removed, tallies)) = self.departed.borrow().as_ref()
            && *step == self.step
        {
            return (*removed, tallies.clone());
        }
        let counted = self.count_departures();
        *self.departed.borrow_mut() = Some((self.step, counted.0, counted.1.clone()));
        counted
    }

    fn count_departures(&self) -> (usize, Vec<tumble_state::OutletTally>) {
        let n = self.slots as usize;
        let v = self.read_bytes(&[(&self.buffers.props, 16 * n as u64), (&self.buffers.alpha, 16 * n as u64)]);
        let props: Vec<[u32; 4]> = bytemuck::pod_collect_to_vec(&v[0]);
        let alpha: Vec<[f32; 4]> = bytemuck::pod_collect_to_vec(&v[1]);
        let mut dead: Vec<(u32, u32, f32)> = (0..n)
            .filter(|&i| props[i][3] & upload::FLAG_DEAD != 0 && props[i][2] < self.created)
            .map(|i| (props[i][2], (props[i][3] >> tumble_shaders::OUTLET_SHIFT) & 0xff, alpha[i][3]))
            .collect();
        dead.sort_unstable_by_key(|d| d.0);
        let mut tallies = vec![tumble_state::OutletTally::default(); self.plan.model.outlets.len()];
        let mut removed = 0;
        for (_, outlet, mass) in dead {
            match tallies.get_mut((outlet as usize).wrapping_sub(1)) {
                Some(t) => {
                    t.count += 1;
                    t.mass += mass as f64;
                }
                None => removed += 1,
            }
        }
        (removed, tallies)
    }

    /// Puts `new` (ids `created..`, in id order, no springs) into the empty slots waiting with
    /// their ids, growing the arrays by the plan's chunk when they are full; refused, changing
    /// nothing, when the device cannot hold them.
    pub fn insert(&mut self, new: &tumble_state::State) -> Result<(), String> {
        if new.is_empty() {
            return Ok(());
        }
        let last = new.id[new.len() - 1];
        if new.id.iter().enumerate().any(|(k, &id)| id != self.created + k as u32) {
            return Err(format!("inserted particles must take the ids {}.. in order; got {:?}", self.created, &new.id[..new.len().min(4)]));
        }
        let seen = self.waiting.take().filter(|(step, _)| *step == self.step);
        self.grow_to_hold(last)?;
        let waiting = match seen {
            Some((_, slots)) => slots,
            _ => self.waiting_slots(&self.read(&self.buffers.props, self.slots as usize)),
        };
        // Slots added since the read hold their own index as id.
        let slot_of = |id: u32| waiting.get((id - self.created) as usize).copied().unwrap_or(id);
        let slot_of: Vec<u32> = new.id.iter().map(|&id| slot_of(id)).collect();
        if let Some(k) = slot_of.iter().position(|&slot| slot >= self.slots) {
            return Err(format!("no empty slot on the GPU holds id {}", new.id[k]));
        }
        let mut a = upload::ParticleArrays::from_state(new, &self.plan);
        // Touching nothing, an inserted particle's acceleration is gravity's.
        let g = self.plan.model.gravity;
        for (k, acc) in a.acc.iter_mut().enumerate() {
            if new.inv_mass[k] != 0.0 {
                acc[0] = g.x as f32;
                acc[1] = g.y as f32;
                acc[2] = g.z as f32;
            }
        }
        let b = &self.buffers;
        let q = &self.gpu.queue;
        let put = |buffer: &wgpu::Buffer, slot: u32, bytes: &[u8]| q.write_buffer(buffer, slot as u64 * bytes.len() as u64, bytes);
        for (k, &slot) in slot_of.iter().enumerate() {
            put(&b.pos, slot, bytemuck::bytes_of(&a.pos[k]));
            put(&b.vel, slot, bytemuck::bytes_of(&a.vel[k]));
            put(&b.omega, slot, bytemuck::bytes_of(&a.omega[k]));
            put(&b.acc, slot, bytemuck::bytes_of(&a.acc[k]));
            put(&b.alpha, slot, bytemuck::bytes_of(&a.alpha[k]));
            put(&b.energy, slot, bytemuck::bytes_of(&a.energy[k]));
            put(&b.props, slot, bytemuck::bytes_of(&a.props[k]));
            if self.plan.model.polyhedra {
                put(&b.orient, slot, bytemuck::bytes_of(&a.orient[k]));
            }
        }
        self.gpu.queue.submit([]);
        let first = self.created as usize;
        self.group[first..first + new.len()].copy_from_slice(&new.group);
        self.created = last + 1;
        self.alive.set(None);
        Ok(())
    }

    /// The slot of each id waiting for insertion (`created..`), from `props` as read back.
    pub(crate) fn waiting_slots(&self, props: &[[u32; 4]]) -> Vec<u32> {
        let mut slots = vec![u32::MAX; props.len().saturating_sub(self.created as usize)];
        for (i, p) in props.iter().enumerate() {
            if p[3] & upload::FLAG_DEAD != 0 && p[2] >= self.created {
                slots[(p[2] - self.created) as usize] = i as u32;
            }
        }
        slots
    }

    /// Times the particle arrays grew because the sources needed more slots.
    pub fn times_grown(&self) -> u32 {
        self.grown
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
