//! Device buffers and the memory they take.

use crate::context::{Gpu, GpuError};
use crate::upload::{Grid, ParticleArrays, SCAN_BLOCK};
use wgpu::util::DeviceExt;

/// Device bytes per particle: ten 16-byte arrays (position, velocity, angular
/// velocity, acceleration, angular acceleration, properties, energy books,
/// force, torque, and the re-sort scratch), 8 bytes of contact statistics, and
/// 4 bytes each of cell index and cell list.
pub const BYTES_PER_PARTICLE: u64 = 10 * 16 + 8 + 4 + 4;

/// Device bytes per particle of contact history with `slots` slots: two generations of
/// `slots` 16-byte slots (spring, key), one 16-byte count entry and the slots' stored
/// energies (f32, four to a 16-byte entry; history.wgsl).
pub fn history_bytes_per_particle(slots: usize) -> u64 {
    2 * 16 * history_entries_per_particle(slots)
}

/// 16-byte history entries per particle in one generation: slots, count, energies.
pub(crate) fn history_entries_per_particle(slots: usize) -> u64 {
    if slots == 0 {
        0
    } else {
        let (slots, counts) = (slots as u64, tumble_shaders::HISTORY_COUNT_ENTRIES as u64);
        slots + counts + slots.div_ceil(tumble_shaders::HISTORY_ENERGIES_PER_ENTRY as u64)
    }
}

/// Device bytes per particle of a plan (history slots, orientations and periodic images included).
pub fn bytes_per_particle(plan: &tumble_plan::Plan) -> u64 {
    BYTES_PER_PARTICLE
        + history_bytes_per_particle(crate::upload::history_slots(plan))
        + wall_bytes_per_particle(plan)
        + if plan.model.polyhedra { 16 } else { 0 }
        + if plan.model.domain.periodic.iter().any(|&p| p) { 16 } else { 0 }
}

/// Device bytes per grid cell: counts, cursors and starts (u32 each).
pub const BYTES_PER_CELL: u64 = 3 * 4;

/// Device memory of a scene with `particles` particles on `grid` and `history_slots` history slots each, bytes.
pub fn memory_bytes(particles: u64, grid: &Grid, history_slots: usize) -> u64 {
    let cells = grid.cells() as u64 + 2;
    particles * (BYTES_PER_PARTICLE + history_bytes_per_particle(history_slots)) + cells * BYTES_PER_CELL + cells.div_ceil(SCAN_BLOCK as u64) * 4 * 2
}

/// Device memory of `plan` with `slots` particle slots on `grid`, bytes (every per-particle
/// array the plan needs and the grid's).
pub fn device_bytes(plan: &tumble_plan::Plan, slots: u64, grid: &Grid) -> u64 {
    memory_bytes(0, grid, 0) + slots * bytes_per_particle(plan)
}

/// Sizes of the wall buffers (zero without walls).
#[derive(Clone, Copy, Debug, Default)]
pub struct WallBuffers {
    /// Wall groups with a load booked per particle (every group).
    pub groups: u64,
    /// Wall groups with work booked per particle (every group with moving walls, else none).
    pub work_groups: u64,
    /// Bytes of the per-step wall tables of one batch.
    pub stage_bytes: u64,
}

/// Device bytes per particle for the wall loads (32 bytes per group) and, with moving walls,
/// the work (8 bytes per group).
pub fn wall_bytes_per_particle(plan: &tumble_plan::Plan) -> u64 {
    let groups = plan.model.wall_groups.len() as u64;
    32 * groups + if crate::upload::moving_walls(plan) { 8 * groups } else { 0 }
}

/// Every buffer of one simulation.
pub struct Buffers {
    pub params: wgpu::Buffer,
    pub pos: wgpu::Buffer,
    pub vel: wgpu::Buffer,
    pub omega: wgpu::Buffer,
    pub acc: wgpu::Buffer,
    pub alpha: wgpu::Buffer,
    pub props: wgpu::Buffer,
    pub energy: wgpu::Buffer,
    pub force: wgpu::Buffer,
    pub torque: wgpu::Buffer,
    pub stats: wgpu::Buffer,
    pub scratch: wgpu::Buffer,
    pub cell: wgpu::Buffer,
    pub cell_list: wgpu::Buffer,
    pub count: wgpu::Buffer,
    pub cursor: wgpu::Buffer,
    pub cell_start: wgpu::Buffer,
    pub tables: wgpu::Buffer,
    /// Orientations (polyhedra scenes; one dummy element otherwise).
    pub orient: wgpu::Buffer,
    /// Whether `orient` holds one orientation per particle (and is re-sorted with them).
    pub oriented: bool,
    /// Periodic images by original id (integrate.wgsl; one dummy element without a periodic axis).
    pub image: wgpu::Buffer,
    /// Whether `image` holds one entry per particle.
    pub imaged: bool,
    /// The two generations of contact-history slots (history.wgsl; 16 bytes each without history).
    pub history: [wgpu::Buffer; 2],
    /// Per particle id and wall group: the load of the last pass (force and power, torque about
    /// the device's origin: two vec4) and, with moving walls, the work since t = 0 (Kahan
    /// pairs); 16 bytes each without them.
    pub wall_load: wgpu::Buffer,
    pub wall_work: wgpu::Buffer,
    /// Moving walls: the wall tables of each step of a batch, copied into `tables` before its contact pass.
    pub wall_stage: wgpu::Buffer,
    /// Block sums of the scan, one buffer per level above the cell starts.
    pub scan_levels: Vec<wgpu::Buffer>,
    /// Values at each scan level (level 0: the cell starts).
    pub scan_sizes: Vec<u32>,
}

const STORAGE: wgpu::BufferUsages = wgpu::BufferUsages::STORAGE.union(wgpu::BufferUsages::COPY_SRC).union(wgpu::BufferUsages::COPY_DST);

fn init(gpu: &Gpu, label: &str, bytes: &[u8]) -> wgpu::Buffer {
    // Bindings must not be empty.
    let mut data = bytes.to_vec();
    if data.len() < 16 {
        data.resize(16, 0);
    }
    gpu.device.create_buffer_init(&wgpu::util::BufferInitDescriptor { label: Some(label), contents: &data, usage: STORAGE })
}

pub(crate) fn zeroed(gpu: &Gpu, label: &str, bytes: u64) -> wgpu::Buffer {
    gpu.device.create_buffer(&wgpu::BufferDescriptor {
        label: Some(label),
        size: bytes.max(16).next_multiple_of(4),
        usage: STORAGE,
        mapped_at_creation: false,
    })
}

impl Buffers {
    /// Checks that the scene fits, then uploads it.
    pub fn new(
        gpu: &Gpu,
        arrays: &ParticleArrays,
        tables: &[[f32; 4]],
        params: &crate::upload::Params,
        grid: &Grid,
        history_slots: usize,
        walls: WallBuffers,
    ) -> Result<Buffers, GpuError> {
        let n = arrays.pos.len() as u64;
        let cells = grid.cells() as u64 + 2;
        let history_bytes = 16 * n * history_entries_per_particle(history_slots);
        let largest = (16 * n).max(4 * cells).max(16 * tables.len() as u64).max(history_bytes).max(32 * n * walls.groups);
        let available = gpu.limits.max_storage_buffer_binding_size.min(gpu.limits.max_buffer_size);
        if largest > available || cells > u32::MAX as u64 / 2 || n > u32::MAX as u64 / 2 {
            return Err(GpuError::TooLarge {
                needed: memory_bytes(n, grid, history_slots),
                largest_array: largest,
                available,
                adapter: gpu.adapter.name.clone(),
            });
        }
        let b = |x: &[[f32; 4]]| bytemuck::cast_slice::<[f32; 4], u8>(x).to_vec();
        let mut scan_sizes = vec![cells as u32];
        while *scan_sizes.last().unwrap() > SCAN_BLOCK {
            scan_sizes.push(scan_sizes.last().unwrap().div_ceil(SCAN_BLOCK));
        }
        let cell_start = zeroed(gpu, "cell_start", 4 * cells);
        let scan_levels = scan_sizes[1..].iter().map(|&s| zeroed(gpu, "scan level", 4 * s as u64)).collect();
        Ok(Buffers {
            params: gpu.device.create_buffer_init(&wgpu::util::BufferInitDescriptor {
                label: Some("params"),
                contents: bytemuck::bytes_of(params),
                usage: wgpu::BufferUsages::UNIFORM,
            }),
            pos: init(gpu, "pos", &b(&arrays.pos)),
            vel: init(gpu, "vel", &b(&arrays.vel)),
            omega: init(gpu, "omega", &b(&arrays.omega)),
            acc: init(gpu, "acc", &b(&arrays.acc)),
            alpha: init(gpu, "alpha", &b(&arrays.alpha)),
            props: init(gpu, "props", bytemuck::cast_slice(&arrays.props)),
            energy: init(gpu, "energy", &b(&arrays.energy)),
            force: zeroed(gpu, "force", 16 * n),
            torque: zeroed(gpu, "torque", 16 * n),
            stats: zeroed(gpu, "stats", 8 * n),
            scratch: zeroed(gpu, "scratch", 16 * n),
            cell: zeroed(gpu, "cell", 4 * n),
            cell_list: zeroed(gpu, "cell_list", 4 * n),
            count: zeroed(gpu, "count", 4 * cells),
            cursor: zeroed(gpu, "cursor", 4 * cells),
            cell_start,
            tables: init(gpu, "tables", &b(tables)),
            orient: init(gpu, "orient", &b(&arrays.orient)),
            oriented: !arrays.orient.is_empty(),
            image: init(gpu, "image", bytemuck::cast_slice(&arrays.image)),
            imaged: !arrays.image.is_empty(),
            // Zeroed: no particle holds a spring at t = 0.
            history: [zeroed(gpu, "history a", history_bytes), zeroed(gpu, "history b", history_bytes)],
            wall_load: zeroed(gpu, "wall load", 32 * n * walls.groups),
            wall_work: zeroed(gpu, "wall work", 8 * n * walls.work_groups),
            wall_stage: zeroed(gpu, "wall stage", walls.stage_bytes),
            scan_levels,
            scan_sizes,
        })
    }

    /// The buffer a kernel binding of this name reads (tumble-shaders' bindings.rs), where the
    /// name alone decides it.
    pub fn named(&self, binding: &str) -> Option<&wgpu::Buffer> {
        Some(match binding {
            "params" => &self.params,
            "pos" => &self.pos,
            "vel" => &self.vel,
            "omega" => &self.omega,
            "acc" => &self.acc,
            "alpha" => &self.alpha,
            "props" => &self.props,
            "energy" => &self.energy,
            "cell" => &self.cell,
            "count" => &self.count,
            "cell_start" => &self.cell_start,
            "cursor" => &self.cursor,
            "cell_list" => &self.cell_list,
            "tables" => &self.tables,
            "orient" => &self.orient,
            "image" => &self.image,
            "wall_load" => &self.wall_load,
            "wall_work" => &self.wall_work,
            _ => return None,
        })
    }

    /// The per-particle arrays the re-sort moves, in a fixed order.
    pub fn particle_arrays(&self) -> Vec<&wgpu::Buffer> {
        let mut arrays = vec![&self.pos, &self.vel, &self.omega, &self.acc, &self.alpha, &self.props, &self.energy];
        if self.oriented {
            arrays.push(&self.orient);
        }
        arrays
    }
}
