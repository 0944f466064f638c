//! Recording the step into command buffers (ARCHITECTURE.md, "The step (GPU)"):
//! broad phase (bin, scan, scatter, order cells; every few steps a re-sort of
//! the particle arrays by cell), the contact pass, then the update.

use crate::GpuSimulation;
use crate::upload::{SCAN_BLOCK, WORKGROUP, dispatch};
use tumble_integrate::Integrator;

/// Records passes into one encoder, optionally bracketing each with timestamps.
pub(crate) struct Recorder<'a> {
    pub encoder: wgpu::CommandEncoder,
    /// Query set and (kernel name per pass) when profiling.
    pub timing: Option<(&'a wgpu::QuerySet, &'a mut Vec<&'static str>)>,
}

impl Recorder<'_> {
    fn pass(&mut self, sim: &GpuSimulation, entry: &'static str, group: &wgpu::BindGroup, groups: (u32, u32)) {
        let timestamp_writes = self.timing.as_mut().and_then(|(set, names)| {
            let k = names.len() as u32;
            (2 * k + 1 < crate::profile::MAX_QUERIES).then(|| {
                names.push(entry);
                wgpu::ComputePassTimestampWrites {
                    query_set: set,
                    beginning_of_pass_write_index: Some(2 * k),
                    end_of_pass_write_index: Some(2 * k + 1),
                }
            })
        });
        let mut pass = self.encoder.begin_compute_pass(&wgpu::ComputePassDescriptor { label: Some(entry), timestamp_writes });
        pass.set_pipeline(sim.kernels.pipeline(entry));
        pass.set_bind_group(0, group, &[]);
        pass.dispatch_workgroups(groups.0, groups.1, 1);
    }
}

impl GpuSimulation {
    fn particle_groups(&self) -> (u32, u32) {
        dispatch(self.slots, WORKGROUP)
    }

    /// Cell index, counts, prefix sum, scatter and the in-cell order by slot.
    fn record_binning(&self, r: &mut Recorder) {
        let b = &self.buffers;
        r.encoder.clear_buffer(&b.count, 0, None);
        r.encoder.clear_buffer(&b.cursor, 0, None);
        r.pass(self, "bin", &self.kernels.broad, self.particle_groups());
        r.encoder.copy_buffer_to_buffer(&b.count, 0, &b.cell_start, 0, 4 * b.scan_sizes[0] as u64);
        // Reduce up the levels, scan the top, then scan each level with its block offsets.
        let levels = b.scan_sizes.len();
        for l in 0..levels - 1 {
            r.pass(self, "reduce", &self.kernels.scan[l], dispatch(b.scan_sizes[l], SCAN_BLOCK));
        }
        for l in (0..levels).rev() {
            r.pass(self, "scan_block", &self.kernels.scan[l], dispatch(b.scan_sizes[l], SCAN_BLOCK));
        }
        r.pass(self, "scatter", &self.kernels.broad, self.particle_groups());
        r.pass(self, "order_cells", &self.kernels.broad, dispatch(self.grid.cells() + 1, WORKGROUP));
    }

    /// The broad phase; at a re-sort the particle arrays are permuted into cell order and binned again.
    pub(crate) fn record_broad_phase(&mut self, r: &mut Recorder) {
        self.record_binning(r);
        let due = self.last_resort.is_none_or(|last| self.step >= last + self.plan.tuning.resort_interval.max(1) as u64);
        if due {
            let b = &self.buffers;
            let bytes = 16 * self.slots as u64;
            for (array, group) in b.particle_arrays().into_iter().zip(&self.kernels.reorder) {
                r.pass(self, "permute", group, self.particle_groups());
                r.encoder.copy_buffer_to_buffer(&b.scratch, 0, array, 0, bytes);
            }
            self.record_binning(r);
            self.last_resort = Some(self.step);
        }
    }

    /// The contact pass; with history it reads generation `self.generation % 2` and writes the other.
    pub(crate) fn record_forces(&self, r: &mut Recorder) {
        r.pass(self, "forces", &self.kernels.forces[(self.generation % 2) as usize], self.particle_groups());
    }

    /// The forces at t = 0, so Verlet's first half kick has an acceleration.
    pub(crate) fn record_initial(&mut self, r: &mut Recorder) {
        self.record_broad_phase(r);
        self.record_forces(r);
        if self.moving {
            // The t = 0 pass only seeds forces (its power is reported, its work is not booked).
            r.encoder.clear_buffer(&self.buffers.wall_work, 0, None);
        }
        r.pass(self, "initial", &self.kernels.integrate, self.particle_groups());
    }

    /// Moving walls: the walls at time `t` go into the table before the next contact pass
    /// (staged on the host, written to the device at the batch's submission).
    fn record_walls(&mut self, r: &mut Recorder, t: f64) {
        if !self.moving {
            return;
        }
        let bytes = 16 * self.wall_entries as u64;
        let offset = 16 * self.pending_walls.len() as u64;
        assert!(offset + bytes <= self.buffers.wall_stage.size(), "more steps recorded than one batch holds");
        self.pending_walls.extend(crate::upload::wall_table(&self.plan, t, &self.hulls));
        r.encoder.copy_buffer_to_buffer(&self.buffers.wall_stage, offset, &self.buffers.tables, 16 * 3 * self.plan.model.pairs.len() as u64, bytes);
        self.wall_time = t;
    }

    /// One time step with the plan's integrator.
    pub(crate) fn record_step(&mut self, r: &mut Recorder) {
        let dt = self.plan.model.dt;
        if self.plan.model.integrator == Integrator::Verlet {
            r.pass(self, "kick_drift", &self.kernels.integrate, self.particle_groups());
            // Forces at x_{n+1} see the walls at t_{n+1}.
            self.record_walls(r, (self.step + 1) as f64 * dt);
        } else {
            self.record_walls(r, self.step as f64 * dt);
        }
        self.record_broad_phase(r);
        self.record_forces(r);
        // The springs just written become the ones read next step (the t = 0 pass commits none).
        self.generation += 1;
        r.pass(self, "finish", &self.kernels.integrate, self.particle_groups());
        self.step += 1;
    }
}
