//! The adapter and device: found once per process and shared by every simulation.

use std::fmt;
use std::sync::{Arc, OnceLock};

/// Why the GPU backend cannot run a scene.
#[derive(Clone, Debug, PartialEq)]
pub enum GpuError {
    /// No adapter (no GPU, and no software Vulkan driver such as lavapipe).
    NoAdapter(String),
    /// The adapter refused a device.
    Device(String),
    /// The scene does not fit the adapter's buffers.
    TooLarge {
        /// Device memory the scene needs, bytes.
        needed: u64,
        /// The largest array, bytes.
        largest_array: u64,
        /// The largest buffer the adapter can bind, bytes.
        available: u64,
        adapter: String,
    },
    /// The adapter lacks a limit the kernels need.
    Unsupported(String),
    /// The plan's pipelines need more of an adapter limit than the adapter allows.
    Limit {
        /// What needs it, as a sentence start ("the contact pass (forces.wgsl) binds 18 storage buffers and").
        what: String,
        /// The `wgpu::Limits` field.
        limit: &'static str,
        needed: u64,
        allowed: u64,
        adapter: String,
    },
    /// The scene uses a model the GPU backend does not run yet.
    Feature(String),
}

impl fmt::Display for GpuError {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        let mib = |b: u64| b as f64 / (1u64 << 20) as f64;
        match self {
            GpuError::NoAdapter(e) => write!(f, "no GPU adapter found ({e}); install a Vulkan driver (mesa-vulkan-drivers gives a software one)"),
            GpuError::Device(e) => write!(f, "the GPU adapter refused a device: {e}"),
            GpuError::TooLarge { needed, largest_array, available, adapter } => write!(
                f,
                "the scene needs {:.1} MiB of GPU memory with a largest array of {:.1} MiB, but {adapter} binds at most {:.1} MiB per buffer",
                mib(*needed),
                mib(*largest_array),
                mib(*available)
            ),
            GpuError::Unsupported(e) => write!(f, "the GPU adapter cannot run tumble's kernels: {e}"),
            GpuError::Limit { what, limit, needed, allowed, adapter } => write!(
                f,
                "{what} needs {limit} ≥ {needed}; adapter {adapter} allows {allowed}: use a Vulkan, Metal or DX12 adapter (WGPU_BACKEND), or backend = \"cpu\""
            ),
            GpuError::Feature(e) => write!(f, "the GPU backend cannot run this scene: {e}"),
        }
    }
}

impl std::error::Error for GpuError {}

/// Name, backend and driver of the adapter, as summary.json reports them.
#[derive(Clone, Debug, PartialEq)]
pub struct AdapterDescription {
    pub name: String,
    pub backend: String,
    pub driver: String,
    pub device_type: String,
}

impl fmt::Display for AdapterDescription {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        write!(f, "{} ({}, {}, {})", self.name, self.backend, self.driver, self.device_type)
    }
}

/// A device with the adapter's own limits (not the conservative defaults).
pub struct Gpu {
    pub device: wgpu::Device,
    pub queue: wgpu::Queue,
    pub adapter: AdapterDescription,
    pub limits: wgpu::Limits,
    /// TIMESTAMP_QUERY is enabled: per-kernel times can be measured.
    pub timestamps: bool,
}

static GPU: OnceLock<Result<Arc<Gpu>, GpuError>> = OnceLock::new();

/// The process-wide device, created on first use.
pub fn gpu() -> Result<Arc<Gpu>, GpuError> {
    GPU.get_or_init(|| pollster::block_on(create()).map(Arc::new)).clone()
}

/// True when an adapter exists (for tests that skip without one).
pub fn available() -> bool {
    gpu().is_ok()
}

async fn create() -> Result<Gpu, GpuError> {
    let instance = wgpu::Instance::new(wgpu::InstanceDescriptor::new_without_display_handle_from_env());
    let options = wgpu::RequestAdapterOptions { power_preference: wgpu::PowerPreference::HighPerformance, ..Default::default() };
    let adapter = instance.request_adapter(&options).await.map_err(|e| GpuError::NoAdapter(e.to_string()))?;
    let info = adapter.get_info();
    // Each plan's pipelines are checked against these before they are built (kernels.rs).
    let limits = adapter.limits();
    let timestamps = adapter.features().contains(wgpu::Features::TIMESTAMP_QUERY);
    let required_features = if timestamps { wgpu::Features::TIMESTAMP_QUERY } else { wgpu::Features::empty() };
    let descriptor = wgpu::DeviceDescriptor { label: Some("tumble"), required_features, required_limits: limits.clone(), ..Default::default() };
    let (device, queue) = adapter.request_device(&descriptor).await.map_err(|e| GpuError::Device(e.to_string()))?;
    Ok(Gpu {
        device,
        queue,
        adapter: AdapterDescription {
            name: info.name.clone(),
            backend: format!("{:?}", info.backend),
            driver: if info.driver_info.is_empty() { info.driver.clone() } else { format!("{} {}", info.driver, info.driver_info) },
            device_type: format!("{:?}", info.device_type),
        },
        limits,
        timestamps,
    })
}
