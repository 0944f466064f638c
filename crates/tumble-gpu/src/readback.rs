//! Reading the device state back: particle arrays in id order, and output rows from the
//! device's reductions (reduce.rs), with the arrays at snapshot times; `full_frame` and the
//! snapshot's frame sum the full arrays on the host in f64, in id order, instead.

use crate::GpuSimulation;
use crate::context::Gpu;
use crate::upload::FLAG_DEAD;
use bytemuck::Pod;
use glam::DVec3;
use tumble_state::{Frame, Observables, State, TrackRow};

/// Everything the device holds per particle, in f32 as it is there.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct DeviceArrays {
    pub pos: Vec<[f32; 4]>,
    pub vel: Vec<[f32; 4]>,
    pub omega: Vec<[f32; 4]>,
    pub acc: Vec<[f32; 4]>,
    pub alpha: Vec<[f32; 4]>,
    pub props: Vec<[u32; 4]>,
    pub energy: Vec<[f32; 4]>,
    pub force: Vec<[f32; 4]>,
    pub torque: Vec<[f32; 4]>,
    pub stats: Vec<[u32; 2]>,
    /// Orientations (polyhedra scenes; empty otherwise).
    pub orient: Vec<[f32; 4]>,
    /// Periodic images by original id, not slot (scenes with a periodic axis; empty otherwise).
    pub image: Vec<[i32; 4]>,
}

impl DeviceArrays {
    /// The arrays from their bytes, in field order ([`GpuSimulation::array_parts`]).
    pub(crate) fn from_bytes(bytes: [&[u8]; 12]) -> DeviceArrays {
        fn cast<T: Pod>(bytes: &[u8]) -> Vec<T> {
            bytemuck::pod_collect_to_vec(bytes)
        }
        DeviceArrays {
            pos: cast(bytes[0]),
            vel: cast(bytes[1]),
            omega: cast(bytes[2]),
            acc: cast(bytes[3]),
            alpha: cast(bytes[4]),
            props: cast(bytes[5]),
            energy: cast(bytes[6]),
            force: cast(bytes[7]),
            torque: cast(bytes[8]),
            stats: cast(bytes[9]),
            orient: cast(bytes[10]),
            image: cast(bytes[11]),
        }
    }

    /// Slots of the particles still in the domain, by id.
    pub fn alive_by_id(&self) -> Vec<usize> {
        let mut order: Vec<usize> = (0..self.pos.len()).filter(|&i| self.props[i][3] & FLAG_DEAD == 0).collect();
        order.sort_by_key(|&i| self.props[i][2]);
        order
    }
}

fn v3(a: [f32; 4]) -> DVec3 {
    DVec3::new(a[0] as f64, a[1] as f64, a[2] as f64)
}

/// Copies the first bytes of several buffers back to the host, after what `record` records, in
/// one submission and one mapping.
pub(crate) fn read_back(gpu: &Gpu, record: impl FnOnce(&mut wgpu::CommandEncoder), parts: &[(&wgpu::Buffer, u64)]) -> Vec<Vec<u8>> {
    let total: u64 = parts.iter().map(|p| p.1).sum();
    if total == 0 {
        return parts.iter().map(|_| Vec::new()).collect();
    }
    let device = &gpu.device;
    let staging = device.create_buffer(&wgpu::BufferDescriptor {
        label: Some("readback"),
        size: total,
        usage: wgpu::BufferUsages::MAP_READ | wgpu::BufferUsages::COPY_DST,
        mapped_at_creation: false,
    });
    let mut encoder = device.create_command_encoder(&wgpu::CommandEncoderDescriptor { label: Some("readback") });
    record(&mut encoder);
    let mut offset = 0;
    for (buffer, bytes) in parts {
        if *bytes > 0 {
            encoder.copy_buffer_to_buffer(buffer, 0, &staging, offset, *bytes);
        }
        offset += bytes;
    }
    gpu.queue.submit([encoder.finish()]);
    staging.slice(..).map_async(wgpu::MapMode::Read, |r| r.expect("mapping a readback buffer"));
    device.poll(wgpu::PollType::Wait { submission_index: None, timeout: None }).expect("waiting for the device");
    let view = staging.slice(..).get_mapped_range().expect("mapped readback");
    let mut out = Vec::new();
    let mut offset = 0;
    for (_, bytes) in parts {
        out.push(view[offset as usize..(offset + bytes) as usize].to_vec());
        offset += bytes;
    }
    drop(view);
    staging.unmap();
    out
}

impl GpuSimulation {
    /// Copies `count` elements of `buffer` back to the host.
    pub(crate) fn read<T: Pod>(&self, buffer: &wgpu::Buffer, count: usize) -> Vec<T> {
        let bytes = self.read_bytes(&[(buffer, (count * std::mem::size_of::<T>()) as u64)]);
        bytemuck::pod_collect_to_vec::<u8, T>(&bytes[0])
    }

    /// Copies the first bytes of several buffers back in one submission and one mapping.
    pub(crate) fn read_bytes(&self, parts: &[(&wgpu::Buffer, u64)]) -> Vec<Vec<u8>> {
        self.read_bytes_after(|_| {}, parts)
    }

    /// Like [`GpuSimulation::read_bytes`], the copies recorded after what `record` records.
    pub(crate) fn read_bytes_after(&self, record: impl FnOnce(&mut wgpu::CommandEncoder), parts: &[(&wgpu::Buffer, u64)]) -> Vec<Vec<u8>> {
        let total: u64 = parts.iter().map(|p| p.1).sum();
        self.readbacks.set(self.readbacks.get() + 1);
        self.readback_bytes.set(self.readback_bytes.get() + total);
        read_back(&self.gpu, record, parts)
    }

    /// Every per-particle array as the device holds it (slot order).
    pub fn device_arrays(&self) -> DeviceArrays {
        self.read_arrays(&[]).0
    }

    /// The buffers of [`DeviceArrays`], in its field order, with the bytes of each it holds.
    pub(crate) fn array_parts(&self) -> [(&wgpu::Buffer, u64); 12] {
        let b = &self.buffers;
        let n = self.slots as u64;
        [
            (&b.pos, 16 * n),
            (&b.vel, 16 * n),
            (&b.omega, 16 * n),
            (&b.acc, 16 * n),
            (&b.alpha, 16 * n),
            (&b.props, 16 * n),
            (&b.energy, 16 * n),
            (&b.force, 16 * n),
            (&b.torque, 16 * n),
            (&b.stats, 8 * n),
            (&b.orient, if b.oriented { 16 * n } else { 0 }),
            (&b.image, if b.imaged { 16 * n } else { 0 }),
        ]
    }

    /// The particle arrays and `extra` buffer prefixes, in one read-back.
    fn read_arrays(&self, extra: &[(&wgpu::Buffer, u64)]) -> (DeviceArrays, Vec<Vec<u8>>) {
        let mut parts = self.array_parts().to_vec();
        parts.extend_from_slice(extra);
        let mut v = self.read_bytes(&parts);
        let rest = v.split_off(12);
        (DeviceArrays::from_bytes(std::array::from_fn(|k| v[k].as_slice())), rest)
    }

    /// One output row from one read-back: the device's sums, track rows and drum profiles
    /// (reduce.rs), with the particle arrays when `with_state` (snapshot times).
    pub fn frame(&self, with_state: bool) -> Frame<'static> {
        self.reduced_frame(with_state)
    }

    /// An output row from the particle arrays and the wall entries, in one read-back, summed on
    /// the host in f64 (the oracle the device's reductions are checked against).
    pub fn full_frame(&self, with_state: bool) -> Frame<'static> {
        let load_bytes = self.wall_load_bytes();
        let work_bytes = self.wall_entry_bytes(8);
        let (a, walls) = self.read_arrays(&[(&self.buffers.wall_load, load_bytes), (&self.buffers.wall_work, work_bytes)]);
        self.frame_from(&a, &walls[0], &walls[1], with_state)
    }

    /// An output row from read-back particle arrays and wall load and work entries.
    pub(crate) fn frame_from(&self, a: &DeviceArrays, load: &[u8], work: &[u8], with_state: bool) -> Frame<'static> {
        let (wall_power, wall_force, torque_about_origin) = self.group_loads(load);
        let wall_torque = self.torques_about_references(&torque_about_origin, &wall_force);
        let wall_work = self.group_sums_of(work, crate::walls::wall_work_value);
        let s = self.state_from(a);
        let observables = self.observables_of(a, &s, &wall_work);
        let drums = if self.plan.model.drums.is_empty() { Vec::new() } else { tumble_state::drum_profiles(&self.plan, &s, self.time()) };
        Frame {
            observables,
            tracks: tumble_state::tracks(&s),
            wall_power,
            wall_work,
            wall_force,
            wall_torque,
            servo_offset: Vec::new(),
            drums,
            state: with_state.then_some(std::borrow::Cow::Owned(s)),
        }
    }

    /// The particles still in the domain as a host [`State`] in f64, in id order.
    pub fn state(&self) -> State {
        let a = self.device_arrays();
        // An insertion right after this read (the feeder's) finds its slots here, not in another read-back.
        *self.waiting.borrow_mut() = Some((self.step, self.waiting_slots(&a.props)));
        self.state_from(&a)
    }

    pub(crate) fn state_from(&self, a: &DeviceArrays) -> State {
        let origin = crate::upload::centre(&self.plan);
        let mut s = State::default();
        for i in a.alive_by_id() {
            let id = a.props[i][2];
            s.id.push(id);
            s.pos.push(v3(a.pos[i]) + origin);
            s.vel.push(v3(a.vel[i]));
            s.acc.push(v3(a.acc[i]));
            s.radius.push(a.pos[i][3] as f64);
            s.reach.push(f32::from_bits(a.props[i][0]) as f64);
            s.mass.push(a.alpha[i][3] as f64);
            s.inv_mass.push(a.vel[i][3] as f64);
            s.material.push(a.props[i][1] as u16);
            s.group.push(self.group[id as usize]);
            s.track.push(self.track[id as usize]);
            s.dissipated.push(a.energy[i][0] as f64);
            if let Some(n) = a.image.get(id as usize) {
                s.image.push([n[0], n[1], n[2]]);
            }
            if self.plan.model.rotation {
                s.omega.push(v3(a.omega[i]));
                s.alpha.push(v3(a.alpha[i]));
                s.inv_inertia.push(a.omega[i][3] as f64);
            }
            if self.plan.model.fluid.is_some() {
                s.fluid_work.push(a.energy[i][1] as f64);
                s.drag.push(a.acc[i][3] as f64);
            }
            if self.plan.model.polyhedra {
                let shape = (a.props[i][3] >> crate::upload::SHAPE_SHIFT) as u16;
                let o = a.orient[i];
                s.shape.push(shape);
                s.orient.push(glam::DQuat::from_xyzw(o[0] as f64, o[1] as f64, o[2] as f64, o[3] as f64));
                // The principal inverse inertia as the CPU holds it (from the plan, in f64).
                let fixed = a.vel[i][3] == 0.0;
                let inv = match shape {
                    _ if fixed => DVec3::ZERO,
                    tumble_plan::SPHERE => DVec3::splat(a.omega[i][3] as f64),
                    k => self.plan.model.shapes[k as usize].body.principal_inertia(self.plan.model.materials[a.props[i][1] as usize].density).recip(),
                };
                s.inv_inertia_body.push(inv);
            }
        }
        self.alive.set(Some(s.len()));
        s
    }

    /// Whole-system observables of the output row (one read-back; see [`GpuSimulation::frame`]).
    pub fn observables(&self) -> Observables {
        self.frame(false).observables
    }

    fn observables_of(&self, a: &DeviceArrays, s: &State, wall_work: &[f64]) -> Observables {
        let mut o = Observables::of_particles(s, self.plan.model.gravity, self.plan.model.domain.extent(), self.time());
        for i in a.alive_by_id() {
            o.add_contacts(a.force[i][3] as f64, a.stats[i][0] as u64, f32::from_bits(a.stats[i][1]) as f64);
        }
        o.finish(wall_work)
    }

    /// Tracked particles, by id, with their orientations (one read-back).
    pub fn tracks(&self) -> Vec<TrackRow> {
        self.frame(false).tracks
    }

    /// The broad phase's tables after the last binning: cell of each slot, cell starts
    /// (cells + 2 entries: the removed bucket, then the total) and the slots in cell order.
    pub fn cell_tables(&self) -> (Vec<u32>, Vec<u32>, Vec<u32>) {
        let b = &self.buffers;
        let n = self.slots as u64;
        let cells = b.scan_sizes[0] as u64;
        let v = self.read_bytes(&[(&b.cell, 4 * n), (&b.cell_start, 4 * cells), (&b.cell_list, 4 * n)]);
        (bytemuck::pod_collect_to_vec(&v[0]), bytemuck::pod_collect_to_vec(&v[1]), bytemuck::pod_collect_to_vec(&v[2]))
    }

    /// Levels of the prefix sum over the cell counts.
    pub fn scan_levels(&self) -> usize {
        self.buffers.scan_sizes.len()
    }

    /// Contact force on the particle with id `id` in the last force pass, if it is still in the domain.
    pub fn contact_force(&self, id: u32) -> Option<DVec3> {
        let n = self.slots as usize;
        let props: Vec<[u32; 4]> = self.read(&self.buffers.props, n);
        let slot = (0..n).find(|&i| props[i][2] == id && props[i][3] & FLAG_DEAD == 0)?;
        let force: Vec<[f32; 4]> = self.read(&self.buffers.force, n);
        Some(v3(force[slot]))
    }
}
