//! Compute pipelines (one per entry point, specialised by the plan's switches)
//! and the bind groups that tie them to one simulation's buffers.

use crate::buffers::Buffers;
use crate::context::{AdapterDescription, Gpu, GpuError};
use crate::shaders::{ShaderSource, Switches, sources_for};
use crate::upload::{MAX_GROUPS_X, Params, SCAN_THREADS, ScanParams, WORKGROUP};
use std::collections::{HashMap, HashSet};
use std::sync::Mutex;
use std::time::{Duration, Instant};
use tumble_shaders::{Access, Binding, Feature};
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

/// The bind group layout of a module: its bindings that `switches` needs, each at its number.
fn layout(gpu: &Gpu, shader: &ShaderSource, switches: &Switches) -> wgpu::BindGroupLayout {
    let entries: Vec<wgpu::BindGroupLayoutEntry> = bound(shader.module.bindings, switches).map(|(k, b)| layout_entry(k, b)).collect();
    gpu.device.create_bind_group_layout(&wgpu::BindGroupLayoutDescriptor { label: Some(shader.name), entries: &entries })
}

/// The layout entry of binding number `k`, a buffer as its access says.
pub(crate) fn layout_entry(k: u32, b: &Binding) -> wgpu::BindGroupLayoutEntry {
    wgpu::BindGroupLayoutEntry {
        binding: k,
        visibility: wgpu::ShaderStages::COMPUTE,
        ty: wgpu::BindingType::Buffer {
            ty: match b.access {
                Access::Uniform => wgpu::BufferBindingType::Uniform,
                Access::Read => wgpu::BufferBindingType::Storage { read_only: true },
                Access::ReadWrite => wgpu::BufferBindingType::Storage { read_only: false },
            },
            has_dynamic_offset: false,
            min_binding_size: None,
        },
        count: None,
    }
}

/// The bindings of a table that `switches` needs, with their numbers.
fn bound<'a>(bindings: &'a [Binding], switches: &'a Switches) -> impl Iterator<Item = (u32, &'a Binding)> + 'a {
    bindings.iter().enumerate().filter(|(_, b)| switches.feature(b.feature)).map(|(k, b)| (k as u32, b))
}

/// A bind group of a module: each binding it needs gets the buffer `buffer` names for it.
pub(crate) fn bind<'a>(
    gpu: &Gpu,
    (shader, layout): (&ShaderSource, &wgpu::BindGroupLayout),
    switches: &Switches,
    buffer: impl Fn(&str) -> Option<&'a wgpu::Buffer>,
) -> wgpu::BindGroup {
    let entries: Vec<wgpu::BindGroupEntry> = bound(shader.module.bindings, switches)
        .map(|(k, b)| {
            let resource = buffer(b.name).unwrap_or_else(|| panic!("{}: no buffer for the binding {}", shader.name, b.name)).as_entire_binding();
            wgpu::BindGroupEntry { binding: k, resource }
        })
        .collect();
    gpu.device.create_bind_group(&wgpu::BindGroupDescriptor { label: Some(shader.name), layout, entries: &entries })
}

/// Checks the adapter's limits against what the plan's pipelines need, before any is built.
pub fn check_limits(limits: &wgpu::Limits, adapter: &AdapterDescription, switches: &Switches) -> Result<(), GpuError> {
    let refuse = |what: String, limit: &'static str, needed: u64, allowed: u64| {
        if needed <= allowed { Ok(()) } else { Err(GpuError::Limit { what, limit, needed, allowed, adapter: adapter.to_string() }) }
    };
    let features: Vec<&str> = [
        (Feature::History, "contact history"),
        (Feature::Moving, "moving walls"),
        (Feature::Polyhedra, "polyhedra"),
        (Feature::Periodic, "periodic axes"),
    ]
    .into_iter()
    .filter(|(f, _)| switches.feature(*f))
    .map(|(_, name)| name)
    .collect();
    let with = if features.is_empty() { String::new() } else { format!(" with {}", features.join(", ")) };
    refuse("the kernels use one bind group and".into(), "max_bind_groups", 1, limits.max_bind_groups as u64)?;
    for shader in sources_for(switches) {
        let storage = shader.storage_buffers(switches) as u64;
        let pass = pass_name(shader.name);
        refuse(
            format!("{pass} binds {storage} storage buffers{with} and"),
            "max_storage_buffers_per_shader_stage",
            storage,
            limits.max_storage_buffers_per_shader_stage as u64,
        )?;
        let bindings = shader.module.bindings.len() as u64;
        refuse(
            format!("{pass} numbers its bindings up to {} and", bindings - 1),
            "max_bindings_per_bind_group",
            bindings,
            limits.max_bindings_per_bind_group as u64,
        )?;
    }
    let uniform = std::mem::size_of::<Params>().max(std::mem::size_of::<ScanParams>()) as u64;
    refuse(
        format!("the step parameters take {uniform} bytes and"),
        "max_uniform_buffer_binding_size",
        uniform,
        limits.max_uniform_buffer_binding_size,
    )?;
    let threads = WORKGROUP.max(SCAN_THREADS) as u64;
    refuse(
        format!("the scan runs {threads} threads per workgroup and"),
        "max_compute_workgroup_size_x",
        threads,
        limits.max_compute_workgroup_size_x as u64,
    )?;
    refuse(
        format!("the scan runs {threads} threads per workgroup and"),
        "max_compute_invocations_per_workgroup",
        threads,
        limits.max_compute_invocations_per_workgroup as u64,
    )?;
    refuse(
        format!("the scan shares {} bytes per workgroup and", 4 * SCAN_THREADS),
        "max_compute_workgroup_storage_size",
        4 * SCAN_THREADS as u64,
        limits.max_compute_workgroup_storage_size as u64,
    )?;
    // Without moving walls the drum histogram's stand-in is one workgroup atomic.
    let reduce = WORKGROUP as u64 * crate::reduce::PARTIAL_BYTES + if switches.moving { 0 } else { 4 };
    refuse(
        format!("the output-row reduction shares {reduce} bytes per workgroup and"),
        "max_compute_workgroup_storage_size",
        reduce,
        limits.max_compute_workgroup_storage_size as u64,
    )?;
    refuse(
        format!("dispatch rows of {MAX_GROUPS_X} workgroups need"),
        "max_compute_workgroups_per_dimension",
        MAX_GROUPS_X as u64,
        limits.max_compute_workgroups_per_dimension as u64,
    )
}

/// How an error names a module's pass.
fn pass_name(module: &str) -> String {
    match module {
        "forces" => "the contact pass (forces.wgsl)".into(),
        "integrate" => "the update (integrate.wgsl)".into(),
        "broad" => "the broad phase (broad.wgsl)".into(),
        other => format!("the {other} pass ({other}.wgsl)"),
    }
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
    /// The plan's pipelines and their bind groups, once the adapter's limits are checked.
    pub fn new(gpu: &Gpu, buffers: &Buffers, switches: &Switches) -> Result<Kernels, GpuError> {
        check_limits(&gpu.limits, &gpu.adapter, switches)?;
        let shaders = sources_for(switches);
        let layouts: Vec<wgpu::BindGroupLayout> = shaders.iter().map(|s| layout(gpu, s, switches)).collect();
        let mut pipelines = HashMap::new();
        for (shader, layout) in shaders.iter().zip(&layouts) {
            create_pipelines(gpu, shader, layout, switches, &mut pipelines);
        }
        Ok(Self::bound(gpu, pipelines, &shaders, &layouts, buffers, switches))
    }

    /// The same pipelines bound to other buffers (the arrays grown or resized): no compilation.
    pub fn rebound(&self, gpu: &Gpu, buffers: &Buffers, switches: &Switches) -> Kernels {
        let shaders = sources_for(switches);
        // A pipeline made with an explicit layout hands that layout back.
        let layouts: Vec<wgpu::BindGroupLayout> = shaders.iter().map(|s| self.pipeline(s.entry_points[0]).get_bind_group_layout(0)).collect();
        Self::bound(gpu, self.pipelines.clone(), &shaders, &layouts, buffers, switches)
    }

    fn bound(
        gpu: &Gpu,
        pipelines: HashMap<&'static str, wgpu::ComputePipeline>,
        shaders: &[ShaderSource],
        layouts: &[wgpu::BindGroupLayout],
        buffers: &Buffers,
        switches: &Switches,
    ) -> Kernels {
        let module = |name: &str| {
            let k = shaders.iter().position(|s| s.name == name).expect("a module of the backend");
            (&shaders[k], &layouts[k])
        };
        let b = buffers;
        let broad = bind(gpu, module("broad"), switches, |n| b.named(n));
        let forces = [0, 1].map(|g| {
            bind(gpu, module("forces"), switches, |n| match n {
                "hist_old" => Some(&b.history[g]),
                "hist_new" => Some(&b.history[1 - g]),
                "force_out" => Some(&b.force),
                "torque_out" => Some(&b.torque),
                "stats_out" => Some(&b.stats),
                _ => b.named(n),
            })
        });
        let integrate = bind(gpu, module("integrate"), switches, |n| match n {
            "force_in" => Some(&b.force),
            "torque_in" => Some(&b.torque),
            _ => b.named(n),
        });
        let reorder = b
            .particle_arrays()
            .into_iter()
            .map(|array| {
                bind(gpu, module("reorder"), switches, |n| match n {
                    "src" => Some(array),
                    "dst" => Some(&b.scratch),
                    _ => b.named(n),
                })
            })
            .collect();
        // Scan level l reads level l and writes/reads the sums of level l + 1 (none above the top).
        let levels = b.scan_sizes.len();
        let mut scan = Vec::new();
        let mut scan_params = Vec::new();
        for l in 0..levels {
            let data = if l == 0 { &b.cell_start } else { &b.scan_levels[l - 1] };
            let sums = if l + 1 < levels { &b.scan_levels[l] } else { &b.count };
            let p = ScanParams { n: b.scan_sizes[l], offsets: u32::from(l + 1 < levels), row: MAX_GROUPS_X * SCAN_THREADS, _pad: 0 };
            let u = gpu.device.create_buffer_init(&wgpu::util::BufferInitDescriptor {
                label: Some("scan params"),
                contents: bytemuck::bytes_of(&p),
                usage: wgpu::BufferUsages::UNIFORM,
            });
            scan.push(bind(gpu, module("scan"), switches, |n| match n {
                "scan" => Some(&u),
                "data" => Some(data),
                "sums" => Some(sums),
                _ => None,
            }));
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

#[cfg(test)]
mod tests {
    use super::*;

    fn gl() -> AdapterDescription {
        AdapterDescription {
            name: "llvmpipe (LLVM 19.1.7, 256 bits)".into(),
            backend: "Gl".into(),
            driver: "llvmpipe".into(),
            device_type: "Cpu".into(),
        }
    }

    /// A desktop Vulkan adapter's limits as far as the kernels care.
    fn roomy() -> wgpu::Limits {
        wgpu::Limits { max_storage_buffers_per_shader_stage: 64, ..wgpu::Limits::default() }
    }

    #[test]
    fn an_adapter_with_16_storage_buffers_is_refused_the_contact_pass_of_every_feature_with_what_it_would_take() {
        let gl_limits = wgpu::Limits { max_storage_buffers_per_shader_stage: 16, ..roomy() };
        let everything = Switches::everything();
        let e = check_limits(&gl_limits, &gl(), &everything).unwrap_err();
        let text = e.to_string();
        for part in [
            "contact pass",
            "18 storage buffers",
            "contact history, moving walls, polyhedra",
            "max_storage_buffers_per_shader_stage",
            "allows 16",
            "llvmpipe",
            "Gl",
            "Vulkan",
            "backend = \"cpu\"",
        ] {
            assert!(text.contains(part), "{part}: {text}");
        }
        assert!(matches!(e, GpuError::Limit { needed: 18, allowed: 16, .. }), "{e:?}");
        // Spheres against static walls bind 14 (with the wall loads); history with moving walls 17; either alone fits.
        let spheres = Switches { history: false, moving: false, polyhedra: false, ..everything };
        assert_eq!(check_limits(&gl_limits, &gl(), &spheres), Ok(()));
        assert!(check_limits(&gl_limits, &gl(), &Switches { polyhedra: false, ..everything }).is_err());
        assert_eq!(check_limits(&gl_limits, &gl(), &Switches { moving: false, polyhedra: false, ..everything }), Ok(()));
        assert_eq!(check_limits(&roomy(), &gl(), &everything), Ok(()));
    }

    #[test]
    fn workgroup_and_uniform_limits_are_checked_too() {
        let everything = Switches::everything();
        for (limits, name) in [
            (wgpu::Limits { max_compute_workgroup_size_x: 128, ..roomy() }, "max_compute_workgroup_size_x"),
            (wgpu::Limits { max_compute_invocations_per_workgroup: 128, ..roomy() }, "max_compute_invocations_per_workgroup"),
            (wgpu::Limits { max_compute_workgroup_storage_size: 512, ..roomy() }, "max_compute_workgroup_storage_size"),
            (wgpu::Limits { max_compute_workgroups_per_dimension: 1024, ..roomy() }, "max_compute_workgroups_per_dimension"),
            (wgpu::Limits { max_uniform_buffer_binding_size: 64, ..roomy() }, "max_uniform_buffer_binding_size"),
            (wgpu::Limits { max_bindings_per_bind_group: 12, ..roomy() }, "max_bindings_per_bind_group"),
        ] {
            let e = check_limits(&limits, &gl(), &everything).unwrap_err();
            assert!(matches!(&e, GpuError::Limit { limit, .. } if *limit == name), "{name}: {e}");
        }
    }
}
