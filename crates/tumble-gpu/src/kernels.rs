//! Compute pipelines (one per entry point, specialised by the plan's switches)
//! and the bind groups that tie them to one simulation's buffers.

use crate::buffers::Buffers;
use crate::context::Gpu;
use crate::shaders::{ShaderSource, Switches, sources};
use crate::upload::{MAX_GROUPS_X, SCAN_THREADS, ScanParams};
use std::collections::{HashMap, HashSet};
use std::sync::Mutex;
use std::time::{Duration, Instant};
use wgpu::util::DeviceExt;

/// What this process has compiled: distinct shader variants, pipeline builds and their time.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct ShaderCompileStats {
    /// Distinct (module, override constants) pairs compiled.
    pub variants: usize,
    /// Compute pipelines built (one per entry point, repeats included).
    pub pipelines: u64,
    /// Time spent creating shader modules and pipelines.
    pub time: Duration,
}

static COMPILED: Mutex<(Option<HashSet<String>>, u64, Duration)> = Mutex::new((None, 0, Duration::ZERO));

/// Books one module's pipelines under its variant key.
pub(crate) fn record_compile(variant: String, pipelines: u64, time: Duration) {
    let mut c = COMPILED.lock().unwrap_or_else(|e| e.into_inner());
    c.0.get_or_insert_with(HashSet::new).insert(variant);
    c.1 += pipelines;
    c.2 += time;
}

/// The shader variants this process has compiled so far and the time it took (tests report it).
pub fn shader_compile_stats() -> ShaderCompileStats {
    let c = COMPILED.lock().unwrap_or_else(|e| e.into_inner());
    ShaderCompileStats { variants: c.0.as_ref().map_or(0, HashSet::len), pipelines: c.1, time: c.2 }
}

/// How a binding is used (binding number = position in the list).
#[derive(Clone, Copy)]
enum Use {
    Uniform,
    Read,
    Write,
}

fn layout(gpu: &Gpu, label: &str, uses: &[Use]) -> wgpu::BindGroupLayout {
    let entries: Vec<wgpu::BindGroupLayoutEntry> = uses
        .iter()
        .enumerate()
        .map(|(k, u)| wgpu::BindGroupLayoutEntry {
            binding: k as u32,
            visibility: wgpu::ShaderStages::COMPUTE,
            ty: wgpu::BindingType::Buffer {
                ty: match u {
                    Use::Uniform => wgpu::BufferBindingType::Uniform,
                    Use::Read => wgpu::BufferBindingType::Storage { read_only: true },
                    Use::Write => wgpu::BufferBindingType::Storage { read_only: false },
                },
                has_dynamic_offset: false,
                min_binding_size: None,
            },
            count: None,
        })
        .collect();
    gpu.device.create_bind_group_layout(&wgpu::BindGroupLayoutDescriptor { label: Some(label), entries: &entries })
}

fn bind(gpu: &Gpu, label: &str, layout: &wgpu::BindGroupLayout, buffers: &[&wgpu::Buffer]) -> wgpu::BindGroup {
    let entries: Vec<wgpu::BindGroupEntry> =
        buffers.iter().enumerate().map(|(k, b)| wgpu::BindGroupEntry { binding: k as u32, resource: b.as_entire_binding() }).collect();
    gpu.device.create_bind_group(&wgpu::BindGroupDescriptor { label: Some(label), layout, entries: &entries })
}

/// The pipelines and bind groups of one simulation.
pub struct Kernels {
    pub pipelines: HashMap<&'static str, wgpu::ComputePipeline>,
    pub broad: wgpu::BindGroup,
    /// The contact pass reading history generation 0 and writing 1, and the swapped pair.
    pub forces: [wgpu::BindGroup; 2],
    pub integrate: wgpu::BindGroup,
    /// One per per-particle array, in `Buffers::particle_arrays` order.
    pub reorder: Vec<wgpu::BindGroup>,
    /// Per scan level: reduce (into the next level) and scan bind groups.
    pub scan: Vec<wgpu::BindGroup>,
    /// Keeps the scan uniforms alive.
    _scan_params: Vec<wgpu::Buffer>,
}

impl Kernels {
    pub fn new(gpu: &Gpu, buffers: &Buffers, switches: &Switches) -> Kernels {
        use Use::*;
        let layouts: HashMap<&str, wgpu::BindGroupLayout> = [
            ("broad", layout(gpu, "broad", &[Uniform, Read, Read, Write, Write, Read, Write, Write])),
            ("scan", layout(gpu, "scan", &[Uniform, Write, Write])),
            ("reorder", layout(gpu, "reorder", &[Uniform, Read, Read, Write])),
            (
                "forces",
                layout(
                    gpu,
                    "forces",
                    &[Uniform, Read, Read, Read, Read, Read, Read, Read, Read, Read, Read, Write, Write, Write, Read, Write, Write, Write, Read],
                ),
            ),
            ("integrate", layout(gpu, "integrate", &[Uniform, Write, Write, Write, Write, Write, Write, Read, Read, Write, Write, Read])),
        ]
        .into_iter()
        .collect();
        let mut pipelines = HashMap::new();
        for shader in sources() {
            create_pipelines(gpu, &shader, &layouts[shader.name], switches, &mut pipelines);
        }
        let b = buffers;
        let broad = bind(gpu, "broad", &layouts["broad"], &[&b.params, &b.pos, &b.props, &b.cell, &b.count, &b.cell_start, &b.cursor, &b.cell_list]);
        let forces = [0, 1].map(|g| {
            bind(
                gpu,
                "forces",
                &layouts["forces"],
                &[
                    &b.params,
                    &b.pos,
                    &b.vel,
                    &b.omega,
                    &b.acc,
                    &b.alpha,
                    &b.props,
                    &b.cell,
                    &b.cell_start,
                    &b.cell_list,
                    &b.tables,
                    &b.force,
                    &b.torque,
                    &b.stats,
                    &b.history[g],
                    &b.history[1 - g],
                    &b.wall_power,
                    &b.wall_work,
                    &b.orient,
                ],
            )
        });
        let integrate = bind(
            gpu,
            "integrate",
            &layouts["integrate"],
            &[&b.params, &b.pos, &b.vel, &b.omega, &b.acc, &b.alpha, &b.props, &b.force, &b.torque, &b.energy, &b.orient, &b.tables],
        );
        let reorder =
            b.particle_arrays().iter().map(|a| bind(gpu, "reorder", &layouts["reorder"], &[&b.params, &b.cell_list, a, &b.scratch])).collect();
        // Scan level l reads level l and writes/reads the sums of level l + 1 (none above the top).
        let levels = b.scan_sizes.len();
        let mut scan = Vec::new();
        let mut scan_params = Vec::new();
        for l in 0..levels {
            let data = if l == 0 { &b.cell_start } else { &b.scan_levels[l - 1] };
            let sums = if l + 1 < levels { &b.scan_levels[l] } else { &b.count };
            let p = ScanParams { n: b.scan_sizes[l], offsets: u32::from(l + 1 < levels), row: MAX_GROUPS_X * SCAN_THREADS, pad: 0 };
            let u = gpu.device.create_buffer_init(&wgpu::util::BufferInitDescriptor {
                label: Some("scan params"),
                contents: bytemuck::bytes_of(&p),
                usage: wgpu::BufferUsages::UNIFORM,
            });
            scan.push(bind(gpu, "scan", &layouts["scan"], &[&u, data, sums]));
            scan_params.push(u);
        }
        Kernels { pipelines, broad, forces, integrate, reorder, scan, _scan_params: scan_params }
    }

    pub fn pipeline(&self, entry: &str) -> &wgpu::ComputePipeline {
        &self.pipelines[entry]
    }
}

fn create_pipelines(
    gpu: &Gpu,
    shader: &ShaderSource,
    layout: &wgpu::BindGroupLayout,
    switches: &Switches,
    out: &mut HashMap<&'static str, wgpu::ComputePipeline>,
) {
    let start = Instant::now();
    let module = gpu.device.create_shader_module(wgpu::ShaderModuleDescriptor {
        label: Some(shader.name),
        source: wgpu::ShaderSource::Wgsl(shader.source.as_str().into()),
    });
    let pipeline_layout = gpu.device.create_pipeline_layout(&wgpu::PipelineLayoutDescriptor {
        label: Some(shader.name),
        bind_group_layouts: &[Some(layout)],
        immediate_size: 0,
    });
    let constants = switches.constants_for(shader);
    for &entry in shader.entry_points {
        let pipeline = gpu.device.create_compute_pipeline(&wgpu::ComputePipelineDescriptor {
            label: Some(entry),
            layout: Some(&pipeline_layout),
            module: &module,
            entry_point: Some(entry),
            compilation_options: wgpu::PipelineCompilationOptions { constants: &constants, zero_initialize_workgroup_memory: true },
            cache: None,
        });
        out.insert(entry, pipeline);
    }
    record_compile(format!("{} {constants:?}", shader.name), shader.entry_points.len() as u64, start.elapsed());
}
