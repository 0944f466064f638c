//! The SPH fluid on the GPU: tumble-sph's method in f32 WGSL (sph_common.wgsl, sph_sort.wgsl,
//! sph_step.wgsl), one variant for every setting (the method's switches are uniform bits).
//!
//! Each step sorts the particles by cell (count, scan, scatter, order by slot, permute), then
//! runs the symplectic scheme's two evaluations (the walls' extrapolated state, then the
//! fluid's rates) and halves. Every sum is gathered in slot order with no float atomics, so a
//! run gives the same bits every time on one device, and a run continued from a snapshot of
//! the device's arrays continues bit-identically.
//!
//! Walls (fixed or moving by a motion), floating bodies, periodic axes, both viscosities, both
//! density diffusions, the tensile correction and XSPH run here; inflow or outflow buffers are
//! refused with the reason (they run on the CPU so far). A moving wall's particles move by a
//! table the host writes per half step in f64 (the rigid move over the half step, the velocity
//! at its end and the acceleration at its start, each an affine map of the position). A floating
//! body's particles move by the same table: the device sums the fluid's force on the body and its
//! moment at each evaluation, the host reads them back and integrates the body in f64 as
//! tumble-sph does, then writes its move.

mod motion;
mod read;

pub use read::FluidReadBack;

use std::collections::HashMap;
use std::sync::Arc;
use std::time::Instant;

use bytemuck::{Pod, Zeroable};
use glam::DVec3;
use tumble_shaders::{
    FLUID_MODULES, MODULES, Module, SCAN_BLOCK, SPH_DIFFUSE, SPH_FLUID, SPH_LAMINAR, SPH_MOTION_WORDS, SPH_TENSILE, SPH_WALL, SPH_XSPH,
};
use tumble_sph::{BodyState, BufferBooks, FluidParticles, FluidSettings, FluidSnapshot, ParticleKind, PassConstants, SKIN, Tait, Viscosity};
use wgpu::util::DeviceExt;

use crate::buffers::zeroed;
use crate::context::{Gpu, GpuError, gpu};
use crate::kernels::layout_entry;
use crate::upload::{MAX_GROUPS_X, ScanParams, WORKGROUP, dispatch};

/// The fluid's step parameters, field for field sph_common.wgsl's `FluidParams`.
#[repr(C)]
#[derive(Clone, Copy, Debug, Default, PartialEq, Pod, Zeroable)]
pub struct FluidParams {
    pub counts: [u32; 4],
    pub dims: [u32; 4],
    pub extent: [f32; 4],
    pub inv_cell: [f32; 4],
    pub kernel: [f32; 4],
    pub terms: [f32; 4],
    pub more_terms: [f32; 4],
    pub hydrostatic: [f32; 4],
    pub body_acceleration: [f32; 4],
    pub eos: [f32; 4],
    pub step: [f32; 4],
    pub bodies: [u32; 4],
}

/// Bytes the device holds per fluid or wall particle: eleven arrays of 16 bytes (position,
/// velocity, tags and their sorted copies; state, viscous velocity, rates, XSPH, the step's start)
/// and the sort's two words (cell, cell list).
pub const FLUID_BYTES_PER_PARTICLE: u64 = 16 * 11 + 8;

fn v4(v: DVec3, w: f64) -> [f32; 4] {
    [v.x as f32, v.y as f32, v.z as f32, w as f32]
}

/// Why a fluid cannot run on the GPU yet, or None.
pub fn fluid_gpu_refusal(settings: &FluidSettings) -> Option<String> {
    (!(settings.inflows.is_empty() && settings.outflows.is_empty()))
        .then(|| "the SPH fluid's inflow and outflow buffers run on the CPU backend so far; use --backend cpu".to_string())
}

/// The cell grid of the fluid's domain: cells at least 2h·SKIN wide (one along a flat axis).
fn grid_dims(settings: &FluidSettings) -> Result<([u32; 3], [f64; 3]), GpuError> {
    let cell = 2.0 * settings.h * SKIN;
    let extent = settings.domain.extent();
    let mut dims = [1u32; 3];
    let mut inv = [0.0; 3];
    for k in 0..3 {
        let n = (extent[k] / cell).floor();
        if settings.domain.periodic[k] && n < 2.0 {
            return Err(GpuError::Feature(format!(
                "the fluid's periodic {} axis is {:.4e} m long; it needs at least two cells of 2.4 h ({:.4e} m)",
                ["x", "y", "z"][k],
                extent[k],
                2.0 * cell
            )));
        }
        dims[k] = n.clamp(1.0, 1e6) as u32;
        inv[k] = if extent[k] > 0.0 { dims[k] as f64 / extent[k] } else { 0.0 };
    }
    Ok((dims, inv))
}

/// Bytes a fluid of `particles` (fluid and wall) takes on the device, and its cell grid.
pub fn fluid_device_bytes(settings: &FluidSettings, particles: usize) -> Result<(u64, [u32; 3]), GpuError> {
    let (dims, _) = grid_dims(settings)?;
    let cells: u64 = dims.iter().map(|&d| d as u64).product();
    Ok((FLUID_BYTES_PER_PARTICLE * particles as u64 + 12 * (cells + 2), dims))
}

/// The step parameters of `settings` over `n` particles on a grid of `dims` cells.
pub fn fluid_params(settings: &FluidSettings, n: u32, dims: [u32; 3], inv_cell: [f64; 3], dt: f64) -> FluidParams {
    let k = PassConstants::of(settings);
    let eos = Tait::new(settings.rho0, settings.sound_speed);
    let switches = [
        (settings.viscosity == Viscosity::Laminar, SPH_LAMINAR),
        (k.diffusion_scale != 0.0, SPH_DIFFUSE),
        (settings.tensile_correction, SPH_TENSILE),
        (settings.xsph != 0.0, SPH_XSPH),
    ]
    .iter()
    .filter(|(on, _)| *on)
    .fold(0, |bits, (_, bit)| bits | bit);
    let periodic = (0..3).filter(|&a| settings.domain.periodic[a]).fold(0, |bits, a| bits | (1 << a));
    let cells = dims.iter().product();
    FluidParams {
        counts: [n, cells, switches, MAX_GROUPS_X * WORKGROUP],
        dims: [dims[0], dims[1], dims[2], periodic],
        extent: v4(settings.domain.extent(), k.tiny),
        inv_cell: [inv_cell[0] as f32, inv_cell[1] as f32, inv_cell[2] as f32, 0.0],
        kernel: [k.support2 as f32, k.inv_h as f32, k.gradient_scale as f32, k.alpha as f32],
        terms: [k.inv_w_dp as f32, k.eta2 as f32, k.laminar_eta2 as f32, k.two_mu as f32],
        more_terms: [k.av_scale as f32, k.reach as f32, k.stiffness as f32, k.diffusion_scale as f32],
        hydrostatic: v4(k.hydrostatic, settings.xsph),
        body_acceleration: v4(settings.external_acceleration(), 0.0),
        eos: [eos.rho0 as f32, eos.b as f32, (1.0 / eos.rho0) as f32, 0.0],
        step: [dt as f32, (0.5 * dt) as f32, 0.0, 0.0],
        bodies: [settings.body_wall_number(0) as u32, settings.floating.len() as u32, body_centre_row(settings), 0],
    }
}

/// The motion table's row of the first floating body's centre: after the moving walls' and the
/// bodies' maps.
fn body_centre_row(settings: &FluidSettings) -> u32 {
    SPH_MOTION_WORDS * (settings.moving_walls.len() + settings.floating.len()) as u32
}

/// The device's arrays of one fluid (16-byte elements unless said otherwise).
struct FluidBuffers {
    params: wgpu::Buffer,
    pos: wgpu::Buffer,
    vel: wgpu::Buffer,
    tags: wgpu::Buffer,
    pos_sorted: wgpu::Buffer,
    vel_sorted: wgpu::Buffer,
    tags_sorted: wgpu::Buffer,
    state: wgpu::Buffer,
    viscous: wgpu::Buffer,
    rate: wgpu::Buffer,
    xsph: wgpu::Buffer,
    start: wgpu::Buffer,
    /// The motion table of the current half step, and those of a batch's half steps.
    motions: wgpu::Buffer,
    motion_stage: wgpu::Buffer,
    /// Per floating body: the fluid's force and its moment about the centre.
    body_sums: wgpu::Buffer,
    /// u32 per particle.
    cell: wgpu::Buffer,
    cell_list: wgpu::Buffer,
    /// u32 per cell and the spare bucket, and one more (the scan's total).
    count: wgpu::Buffer,
    cursor: wgpu::Buffer,
    cell_start: wgpu::Buffer,
    scan_levels: Vec<wgpu::Buffer>,
    scan_sizes: Vec<u32>,
}

impl FluidBuffers {
    fn named(&self, name: &str) -> Option<&wgpu::Buffer> {
        Some(match name {
            "fluid" => &self.params,
            "pos" => &self.pos,
            "vel" => &self.vel,
            "tags" => &self.tags,
            "pos_sorted" => &self.pos_sorted,
            "vel_sorted" => &self.vel_sorted,
            "tags_sorted" => &self.tags_sorted,
            "state" => &self.state,
            "viscous" => &self.viscous,
            "rate" => &self.rate,
            "xsph" => &self.xsph,
            "start" => &self.start,
            "motions" => &self.motions,
            "body_sums" => &self.body_sums,
            "cell" => &self.cell,
            "cell_list" => &self.cell_list,
            "count" => &self.count,
            "cursor" => &self.cursor,
            "cell_start" => &self.cell_start,
            _ => return None,
        })
    }
}

/// A module's pipelines (one per entry point) and its bind group layout.
fn build(gpu: &Gpu, module: &Module, pipelines: &mut HashMap<&'static str, wgpu::ComputePipeline>) -> wgpu::BindGroupLayout {
    let started = Instant::now();
    let entries: Vec<wgpu::BindGroupLayoutEntry> = module.bindings.iter().enumerate().map(|(k, b)| layout_entry(k as u32, b)).collect();
    let layout = gpu.device.create_bind_group_layout(&wgpu::BindGroupLayoutDescriptor { label: Some(module.name), entries: &entries });
    let source = module.source(|_| true);
    let shader =
        gpu.device.create_shader_module(wgpu::ShaderModuleDescriptor { label: Some(module.name), source: wgpu::ShaderSource::Wgsl(source.into()) });
    let pipeline_layout = gpu.device.create_pipeline_layout(&wgpu::PipelineLayoutDescriptor {
        label: Some(module.name),
        bind_group_layouts: &[Some(&layout)],
        immediate_size: 0,
    });
    for &entry in module.entry_points {
        let pipeline = gpu.device.create_compute_pipeline(&wgpu::ComputePipelineDescriptor {
            label: Some(entry),
            layout: Some(&pipeline_layout),
            module: &shader,
            entry_point: Some(entry),
            compilation_options: wgpu::PipelineCompilationOptions { constants: &[], zero_initialize_workgroup_memory: true },
            cache: None,
        });
        pipelines.insert(entry, pipeline);
    }
    crate::kernels::record_compile(module.name.to_string(), module.entry_points.len() as u64, started.elapsed());
    layout
}

fn bind<'a>(gpu: &Gpu, module: &Module, layout: &wgpu::BindGroupLayout, buffer: impl Fn(&str) -> Option<&'a wgpu::Buffer>) -> wgpu::BindGroup {
    let entries: Vec<wgpu::BindGroupEntry> = module
        .bindings
        .iter()
        .enumerate()
        .map(|(k, b)| {
            let resource = buffer(b.name).unwrap_or_else(|| panic!("{}: no buffer for the binding {}", module.name, b.name)).as_entire_binding();
            wgpu::BindGroupEntry { binding: k as u32, resource }
        })
        .collect();
    gpu.device.create_bind_group(&wgpu::BindGroupDescriptor { label: Some(module.name), layout, entries: &entries })
}

/// An SPH fluid stepped on the GPU in f32.
pub struct GpuFluid {
    gpu: Arc<Gpu>,
    settings: FluidSettings,
    /// The domain's centre: device positions are relative to it.
    centre: DVec3,
    params: FluidParams,
    n: u32,
    buffers: FluidBuffers,
    pipelines: HashMap<&'static str, wgpu::ComputePipeline>,
    sort_group: wgpu::BindGroup,
    step_group: wgpu::BindGroup,
    scan_groups: Vec<wgpu::BindGroup>,
    _scan_params: Vec<wgpu::Buffer>,
    /// The ids the particles had before the device held them (in their upload order), kept for
    /// nothing but the snapshot's next id.
    next_id: u32,
    /// The floating bodies, integrated on the host in f64 from the device's sums.
    bodies: Vec<BodyState>,
    time: f64,
    steps: u64,
}

impl GpuFluid {
    /// The fluid of `settings` over `particles` on the process's GPU; refuses what the GPU does not
    /// run yet and a fluid larger than the adapter's buffers.
    pub fn new(settings: &FluidSettings, particles: &FluidParticles) -> Result<GpuFluid, GpuError> {
        if let Some(why) = fluid_gpu_refusal(settings) {
            return Err(GpuError::Feature(why));
        }
        let gpu = gpu()?;
        let (dims, inv_cell) = grid_dims(settings)?;
        let n = particles.len() as u32;
        let cells: u32 = dims.iter().product();
        let largest = (16 * n as u64).max(4 * (cells as u64 + 2));
        let available = gpu.limits.max_storage_buffer_binding_size.min(gpu.limits.max_buffer_size);
        if largest > available {
            return Err(GpuError::TooLarge {
                needed: FLUID_BYTES_PER_PARTICLE * n as u64 + 12 * cells as u64,
                largest_array: largest,
                available,
                adapter: gpu.adapter.name.clone(),
            });
        }
        let params = fluid_params(settings, n, dims, inv_cell, 0.0);
        let centre = 0.5 * (settings.domain.min + settings.domain.max);
        let zero = |bytes: u64| zeroed(&gpu, "fluid array", bytes);
        let per = 16 * n as u64;
        let bodies = settings.floating.len() as u64;
        let motion_bytes = 16 * (body_centre_row(settings) as u64 + bodies);
        let buckets = cells as u64 + 2;
        let mut scan_sizes = vec![buckets as u32];
        while *scan_sizes.last().unwrap() > SCAN_BLOCK {
            scan_sizes.push(scan_sizes.last().unwrap().div_ceil(SCAN_BLOCK));
        }
        let buffers = FluidBuffers {
            params: gpu.device.create_buffer_init(&wgpu::util::BufferInitDescriptor {
                label: Some("fluid params"),
                contents: bytemuck::bytes_of(&params),
                usage: wgpu::BufferUsages::UNIFORM | wgpu::BufferUsages::COPY_DST,
            }),
            pos: zero(per),
            vel: zero(per),
            tags: zero(per),
            pos_sorted: zero(per),
            vel_sorted: zero(per),
            tags_sorted: zero(per),
            state: zero(per),
            viscous: zero(per),
            rate: zero(per),
            xsph: zero(per),
            start: zero(per),
            motions: zero(motion_bytes),
            motion_stage: zero(2 * crate::STEPS_PER_SUBMIT * motion_bytes),
            body_sums: zero(32 * bodies),
            cell: zero(4 * n as u64),
            cell_list: zero(4 * n as u64),
            count: zero(4 * buckets),
            cursor: zero(4 * buckets),
            cell_start: zero(4 * buckets),
            scan_levels: scan_sizes[1..].iter().map(|&s| zero(4 * s as u64)).collect(),
            scan_sizes,
        };
        let mut pipelines = HashMap::new();
        let [sort, step] = [&FLUID_MODULES[0], &FLUID_MODULES[1]];
        let scan = MODULES.iter().find(|m| m.name == "scan").expect("the scan module");
        let sort_layout = build(&gpu, sort, &mut pipelines);
        let step_layout = build(&gpu, step, &mut pipelines);
        let scan_layout = build(&gpu, scan, &mut pipelines);
        let sort_group = bind(&gpu, sort, &sort_layout, |name| buffers.named(name));
        let step_group = bind(&gpu, step, &step_layout, |name| buffers.named(name));
        // Scan level l reads level l and writes the sums of level l + 1 (none above the top).
        let levels = buffers.scan_sizes.len();
        let (mut scan_groups, mut scan_params) = (Vec::new(), Vec::new());
        for l in 0..levels {
            let data = if l == 0 { &buffers.cell_start } else { &buffers.scan_levels[l - 1] };
            let sums = if l + 1 < levels { &buffers.scan_levels[l] } else { &buffers.count };
            let p = ScanParams {
                n: buffers.scan_sizes[l],
                offsets: u32::from(l + 1 < levels),
                row: MAX_GROUPS_X * tumble_shaders::SCAN_THREADS,
                _pad: 0,
            };
            let u = gpu.device.create_buffer_init(&wgpu::util::BufferInitDescriptor {
                label: Some("fluid scan params"),
                contents: bytemuck::bytes_of(&p),
                usage: wgpu::BufferUsages::UNIFORM,
            });
            scan_groups.push(bind(&gpu, scan, &scan_layout, |name| match name {
                "scan" => Some(&u),
                "data" => Some(data),
                "sums" => Some(sums),
                _ => None,
            }));
            scan_params.push(u);
        }
        let mut fluid = GpuFluid {
            gpu,
            settings: settings.clone(),
            centre,
            params,
            n,
            buffers,
            pipelines,
            sort_group,
            step_group,
            scan_groups,
            _scan_params: scan_params,
            next_id: 0,
            bodies: settings.floating.iter().map(|b| b.start).collect(),
            time: 0.0,
            steps: 0,
        };
        fluid.upload(particles);
        Ok(fluid)
    }

    pub fn settings(&self) -> &FluidSettings {
        &self.settings
    }

    pub fn time(&self) -> f64 {
        self.time
    }

    pub fn steps(&self) -> u64 {
        self.steps
    }

    /// The adapter it runs on.
    pub fn adapter(&self) -> String {
        self.gpu.adapter.to_string()
    }

    /// Bytes its arrays take on the device.
    pub fn device_bytes(&self) -> u64 {
        FLUID_BYTES_PER_PARTICLE * self.n as u64 + 12 * (self.params.counts[1] as u64 + 2)
    }

    /// Writes `particles` (their order kept) into the device's arrays.
    fn upload(&mut self, p: &FluidParticles) {
        let c = self.centre;
        let pos: Vec<[f32; 4]> = (0..p.len()).map(|i| v4(p.position[i] - c, p.mass[i])).collect();
        let vel: Vec<[f32; 4]> = (0..p.len()).map(|i| v4(p.velocity[i], p.density[i])).collect();
        let tags: Vec<[u32; 4]> = (0..p.len())
            .map(|i| {
                let kind = if p.kind[i] == ParticleKind::Fluid { SPH_FLUID } else { SPH_WALL };
                [kind, p.id[i], p.wall[i] as u32, 0]
            })
            .collect();
        let q = &self.gpu.queue;
        let b = &self.buffers;
        if !p.is_empty() {
            q.write_buffer(&b.pos, 0, bytemuck::cast_slice(&pos));
            q.write_buffer(&b.vel, 0, bytemuck::cast_slice(&vel));
            q.write_buffer(&b.tags, 0, bytemuck::cast_slice(&tags));
        }
        self.next_id = p.id.iter().max().map_or(0, |&m| m + 1);
    }

    fn pass(&self, encoder: &mut wgpu::CommandEncoder, entry: &'static str, group: &wgpu::BindGroup, groups: (u32, u32)) {
        let mut pass = encoder.begin_compute_pass(&wgpu::ComputePassDescriptor { label: Some(entry), timestamp_writes: None });
        pass.set_pipeline(&self.pipelines[entry]);
        pass.set_bind_group(0, group, &[]);
        pass.dispatch_workgroups(groups.0, groups.1, 1);
    }

    /// The counting sort by cell and the permutation of the arrays into cell order.
    fn record_sort(&self, encoder: &mut wgpu::CommandEncoder) {
        let b = &self.buffers;
        let particles = dispatch(self.n, WORKGROUP);
        encoder.clear_buffer(&b.count, 0, None);
        encoder.clear_buffer(&b.cursor, 0, None);
        self.pass(encoder, "fluid_bin", &self.sort_group, particles);
        encoder.copy_buffer_to_buffer(&b.count, 0, &b.cell_start, 0, 4 * b.scan_sizes[0] as u64);
        let levels = b.scan_sizes.len();
        for l in 0..levels - 1 {
            self.pass(encoder, "reduce", &self.scan_groups[l], dispatch(b.scan_sizes[l], SCAN_BLOCK));
        }
        for l in (0..levels).rev() {
            self.pass(encoder, "scan_block", &self.scan_groups[l], dispatch(b.scan_sizes[l], SCAN_BLOCK));
        }
        self.pass(encoder, "fluid_scatter", &self.sort_group, particles);
        self.pass(encoder, "fluid_order_cells", &self.sort_group, dispatch(self.params.counts[1], WORKGROUP));
        self.pass(encoder, "fluid_permute", &self.sort_group, particles);
        let bytes = 16 * self.n as u64;
        encoder.copy_buffer_to_buffer(&b.pos_sorted, 0, &b.pos, 0, bytes);
        encoder.copy_buffer_to_buffer(&b.vel_sorted, 0, &b.vel, 0, bytes);
        encoder.copy_buffer_to_buffer(&b.tags_sorted, 0, &b.tags, 0, bytes);
    }

    /// One step; the motion tables of its halves are the stage's `2 step` and `2 step + 1`.
    fn record_step(&self, encoder: &mut wgpu::CommandEncoder, step: u64) {
        let particles = dispatch(self.n, WORKGROUP);
        self.record_sort(encoder);
        let table = 16 * SPH_MOTION_WORDS as u64 * self.settings.moving_walls.len() as u64;
        for (k, half) in ["fluid_first_half", "fluid_second_half"].into_iter().enumerate() {
            if table > 0 {
                encoder.copy_buffer_to_buffer(&self.buffers.motion_stage, (2 * step + k as u64) * table, &self.buffers.motions, 0, table);
            }
            self.record_evaluation(encoder);
            self.pass(encoder, half, &self.step_group, particles);
        }
    }

    /// Advances `steps` steps of `dt`, submitted in batches.
    pub fn advance(&mut self, steps: u64, dt: f64) {
        if self.n == 0 || steps == 0 {
            self.time += steps as f64 * dt;
            self.steps += steps;
            return;
        }
        let step = [dt as f32, (0.5 * dt) as f32, 0.0, 0.0];
        if self.params.step != step {
            self.params.step = step;
            self.gpu.queue.write_buffer(&self.buffers.params, 0, bytemuck::bytes_of(&self.params));
        }
        if !self.bodies.is_empty() {
            for _ in 0..steps {
                self.step_with_bodies(dt);
            }
            self.steps += steps;
            return;
        }
        let mut left = steps;
        while left > 0 {
            let batch = left.min(crate::STEPS_PER_SUBMIT);
            let mut encoder = self.gpu.device.create_command_encoder(&wgpu::CommandEncoderDescriptor { label: Some("fluid steps") });
            let mut tables = Vec::new();
            for step in 0..batch {
                // The host time sums Δt in f64 as the CPU's does, and the halves start where its do.
                let half = 0.5 * dt;
                tables.extend(self.motion_table(self.time, half, None));
                tables.extend(self.motion_table(self.time + half, half, None));
                self.record_step(&mut encoder, step);
                self.time += dt;
            }
            if !tables.is_empty() {
                self.gpu.queue.write_buffer(&self.buffers.motion_stage, 0, bytemuck::cast_slice(&tables));
            }
            self.gpu.queue.submit([encoder.finish()]);
            left -= batch;
        }
        self.steps += steps;
    }

    /// The fluid's state for a checkpoint: the device's arrays in their order.
    pub fn snapshot(&self) -> FluidSnapshot {
        self.snapshot_of(self.particles())
    }

    /// The snapshot of the fluid whose particles, read back, are `particles`.
    pub fn snapshot_of(&self, particles: FluidParticles) -> FluidSnapshot {
        FluidSnapshot {
            time: self.time,
            steps: self.steps,
            particles,
            list_positions: None,
            bodies: self.bodies.clone(),
            buffers: BufferBooks::default(),
            next_id: self.next_id,
        }
    }

    /// Continues from `snapshot` (of a fluid with the same settings and particle count),
    /// changing nothing when it does not fit.
    pub fn restore(&mut self, snapshot: &FluidSnapshot) -> Result<(), String> {
        let p = &snapshot.particles;
        if p.len() != self.n as usize {
            return Err(format!("the fluid snapshot holds {} particles; the GPU fluid has {}", p.len(), self.n));
        }
        if [p.id.len(), p.kind.len(), p.velocity.len(), p.density.len(), p.mass.len(), p.wall.len()].iter().any(|&len| len != p.len()) {
            return Err("the fluid snapshot's arrays differ in length".into());
        }
        if snapshot.bodies.len() != self.bodies.len() {
            return Err(format!("the fluid snapshot holds {} floating bodies; the GPU fluid has {}", snapshot.bodies.len(), self.bodies.len()));
        }
        self.upload(p);
        self.bodies.clone_from(&snapshot.bodies);
        self.next_id = self.next_id.max(snapshot.next_id);
        self.time = snapshot.time;
        self.steps = snapshot.steps;
        Ok(())
    }
}
