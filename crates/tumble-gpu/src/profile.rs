//! Per-kernel times from timestamp queries (when the adapter has TIMESTAMP_QUERY).

use crate::GpuSimulation;

/// Timestamps one profiling run can hold (two per pass).
pub const MAX_QUERIES: u32 = 4096;

/// Device time spent in one kernel over the profiled steps.
#[derive(Clone, Debug, PartialEq)]
pub struct KernelTime {
    pub kernel: &'static str,
    pub seconds: f64,
    pub passes: usize,
}

impl GpuSimulation {
    /// True when the adapter can time kernels.
    pub fn can_profile(&self) -> bool {
        self.gpu.timestamps
    }

    /// Advances `steps` steps with a timestamp around every pass and returns the
    /// device time per kernel, largest first (`None` without TIMESTAMP_QUERY).
    /// Passes beyond `MAX_QUERIES / 2` run untimed.
    pub fn profile(&mut self, steps: u64) -> Option<Vec<KernelTime>> {
        if !self.gpu.timestamps {
            return None;
        }
        let device = &self.gpu.device;
        let set =
            device.create_query_set(&wgpu::QuerySetDescriptor { label: Some("kernel times"), ty: wgpu::QueryType::Timestamp, count: MAX_QUERIES });
        let resolve = device.create_buffer(&wgpu::BufferDescriptor {
            label: Some("timestamps"),
            size: 8 * MAX_QUERIES as u64,
            usage: wgpu::BufferUsages::QUERY_RESOLVE | wgpu::BufferUsages::COPY_SRC,
            mapped_at_creation: false,
        });
        let mut names = Vec::new();
        // In batches, so the wall poses of moving walls fit their stage.
        let mut left = steps;
        while left > 0 {
            let batch = left.min(crate::STEPS_PER_SUBMIT);
            let encoder = self.gpu.device.create_command_encoder(&wgpu::CommandEncoderDescriptor { label: Some("profiled steps") });
            let mut r = crate::step::Recorder { encoder, timing: Some((&set, &mut names)) };
            for _ in 0..batch {
                self.record_step(&mut r);
            }
            let crate::step::Recorder { encoder, .. } = r;
            self.submit(encoder);
            left -= batch;
        }
        let mut encoder = self.gpu.device.create_command_encoder(&wgpu::CommandEncoderDescriptor { label: Some("timestamps") });
        let used = 2 * names.len() as u32;
        if used > 0 {
            encoder.resolve_query_set(&set, 0..used, &resolve, 0);
        }
        self.gpu.queue.submit([encoder.finish()]);
        self.alive.set(None);
        let ticks: Vec<u64> = self.read(&resolve, used as usize);
        let period = self.gpu.queue.get_timestamp_period() as f64 * 1e-9;
        let mut out: Vec<KernelTime> = Vec::new();
        for (k, name) in names.iter().enumerate() {
            let seconds = ticks[2 * k + 1].saturating_sub(ticks[2 * k]) as f64 * period;
            match out.iter_mut().find(|t| t.kernel == *name) {
                Some(t) => {
                    t.seconds += seconds;
                    t.passes += 1;
                }
                None => out.push(KernelTime { kernel: name, seconds, passes: 1 }),
            }
        }
        out.sort_by(|a, b| b.seconds.total_cmp(&a.seconds));
        Some(out)
    }
}
