//! Resizing the device's particle arrays: growing them by the plan's chunk when the sources need
//! more slots than reserved, and matching a snapshot's slot count and grid before a restore.
//!
//! New buffers are made, the old contents copied on the device (slot- and id-indexed arrays keep
//! their prefix; the history's three sections move to their new offsets), and the same pipelines
//! are bound to them. The new slots are empty, each holding the id it will be given, so every
//! slot still holds a distinct id below the slot count.

use crate::GpuSimulation;
use crate::buffers::{Buffers, history_entries_per_particle};
use crate::context::GpuError;
use crate::kernels::Kernels;
use crate::reduce::Reduction;
use crate::shaders::Switches;
use crate::upload::{self, Grid, ParticleArrays};

/// Buffers, bind groups and reductions for another slot count or grid, filled and ready to
/// replace the simulation's ([`GpuSimulation::commit`]); dropping it changes nothing.
pub(crate) struct Resized {
    slots: u32,
    grid: Grid,
    pub(crate) buffers: Buffers,
    kernels: Kernels,
    reduction: Reduction,
}

impl GpuSimulation {
    /// The simulation's buffers remade for `slots` slots on `grid`, their contents copied over
    /// (slots beyond the old count empty, holding their ids; per-cell arrays kept only when the
    /// grid is the same).
    pub(crate) fn resized(&self, slots: u32, grid: Grid) -> Result<Resized, GpuError> {
        let plan = &self.plan;
        let mut arrays = ParticleArrays::default();
        arrays.pad_to(slots as usize, plan);
        let (tables, params) = upload::tables_and_params(plan, &self.hulls, &grid, slots)?;
        let new = Buffers::new(&self.gpu, &arrays, &tables, &params, &grid, upload::history_slots(plan), self.wall_buffers)?;
        let old = &self.buffers;
        let mut encoder = self.gpu.device.create_command_encoder(&wgpu::CommandEncoderDescriptor { label: Some("resize") });
        let mut prefix = |from: &wgpu::Buffer, to: &wgpu::Buffer, bytes: u64| {
            let bytes = bytes.min(from.size()).min(to.size());
            if bytes > 0 {
                encoder.copy_buffer_to_buffer(from, 0, to, 0, bytes);
            }
        };
        let kept = self.slots.min(slots) as u64;
        for (from, to, width) in [
            (&old.pos, &new.pos, 16),
            (&old.vel, &new.vel, 16),
            (&old.omega, &new.omega, 16),
            (&old.acc, &new.acc, 16),
            (&old.alpha, &new.alpha, 16),
            (&old.props, &new.props, 16),
            (&old.energy, &new.energy, 16),
            (&old.force, &new.force, 16),
            (&old.torque, &new.torque, 16),
            (&old.stats, &new.stats, 8),
            (&old.cell, &new.cell, 4),
            (&old.cell_list, &new.cell_list, 4),
        ] {
            prefix(from, to, width * kept);
        }
        if old.oriented {
            prefix(&old.orient, &new.orient, 16 * kept);
        }
        if old.imaged {
            prefix(&old.image, &new.image, 16 * kept);
        }
        // Per id and wall group, id-major.
        let groups = self.wall_buffers.groups;
        prefix(&old.wall_load, &new.wall_load, 32 * groups * kept);
        prefix(&old.wall_work, &new.wall_work, 8 * self.wall_buffers.work_groups * kept);
        prefix(&old.tables, &new.tables, old.tables.size());
        if grid == self.grid {
            for (from, to) in [(&old.count, &new.count), (&old.cursor, &new.cursor), (&old.cell_start, &new.cell_start)] {
                prefix(from, to, from.size());
            }
            for (from, to) in old.scan_levels.iter().zip(&new.scan_levels) {
                prefix(from, to, from.size());
            }
        }
        let history_slots = upload::history_slots(plan) as u64;
        if history_slots > 0 {
            // Sections of one generation (history.wgsl): slots, counts, energies, each n entries per id.
            let counts = tumble_shaders::HISTORY_COUNT_ENTRIES as u64;
            let energies = history_entries_per_particle(history_slots as usize) - history_slots - counts;
            let (n_old, n_new) = (self.slots as u64, slots as u64);
            for (from, to) in old.history.iter().zip(&new.history) {
                let mut at = (0, 0);
                for per_id in [history_slots, counts, energies] {
                    if kept > 0 {
                        encoder.copy_buffer_to_buffer(from, 16 * at.0, to, 16 * at.1, 16 * per_id * kept);
                    }
                    at = (at.0 + per_id * n_old, at.1 + per_id * n_new);
                }
            }
        }
        self.gpu.queue.submit([encoder.finish()]);
        let kernels = self.kernels.rebound(&self.gpu, &new, &Switches::from_plan(plan));
        let mut track = self.track.clone();
        track.resize(slots as usize, false);
        let reduction = Reduction::new(&self.gpu, &new, &kernels, plan, slots, &track);
        Ok(Resized { slots, grid, buffers: new, kernels, reduction })
    }

    /// Replaces the buffers, bind groups and reductions with `r`'s.
    pub(crate) fn commit(&mut self, r: Resized) {
        self.wait();
        self.slots = r.slots;
        self.grid = r.grid;
        self.buffers = r.buffers;
        self.kernels = r.kernels;
        self.reduction = r.reduction;
        self.group.resize(self.slots as usize, 0);
        self.track.resize(self.slots as usize, false);
        *self.departed.borrow_mut() = None;
        *self.waiting.borrow_mut() = None;
    }

    /// Grows the arrays by whole chunks until id `last` has a slot; refused, changing nothing,
    /// past 2^31 slots or the device's buffer limits.
    pub(crate) fn grow_to_hold(&mut self, last: u32) -> Result<(), String> {
        if last < self.slots {
            return Ok(());
        }
        let chunk = self.plan.tuning.capacity_chunk.max(1);
        let slots = self.slots as u64 + chunk * (last as u64 + 1 - self.slots as u64).div_ceil(chunk);
        if slots > u32::MAX as u64 / 2 {
            return Err(format!("the sources asked for particle id {last}; the GPU backend holds at most 2^31 particle slots"));
        }
        let r = self.resized(slots as u32, self.grid).map_err(|e| {
            format!("the sources need {slots} particle slots on the GPU ({} reserved so far) and the device refused them: {e}", self.slots)
        })?;
        self.commit(r);
        self.grown += 1;
        Ok(())
    }
}
