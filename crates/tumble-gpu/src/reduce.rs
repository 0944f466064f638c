//! The output row's read-back kept small: the observables' particle sums reduced on the
//! device, and the tracked particles gathered there (reduce.wgsl), so a row reads back one
//! 80-byte partial and one 64-byte row per tracked particle (plus the moving walls' entries),
//! whatever the number of particles.
//!
//! The reduction is a fixed-shape tree: each workgroup sums `REDUCE_BLOCK` slots into one
//! partial, each level above sums `REDUCE_BLOCK` partials of the one below, until one is left.
//! There are no atomics, so a run gives bit-identical sums every time on one device.
//!
//! Accuracy: each particle's term is formed in f32 from the f32 arrays (gravity and the
//! polyhedra's principal inertia from the host's f64, the body-frame rotation in the host's
//! formula) and the tree sums pairwise, so an energy is within about (a few + log₂ n)·2⁻²⁴ of
//! Σ|term| of the host's f64 sum of the same arrays; contacts, particles, the largest overlap
//! ratio and the finite flag are exact. The terms and sums are written as two-float (hi, lo)
//! values (fma products, TwoSum additions), which would bring that to about 1e-12 where the
//! shader compiler keeps IEEE order, but naga marks no operation exact and lavapipe's
//! compiler folds the compensation away: measured there, 1e-8 to 1.1e-7 of Σ|term|
//! (`tests/backends/reduced_rows.rs`, which allows 1e-6). The potential is summed relative to
//! the device's origin (the domain's centre); the origin's term, −M g·origin with M the
//! movable mass, is added on the host in f64.

use crate::GpuSimulation;
use crate::buffers::Buffers;
use crate::context::Gpu;
use crate::kernels::{Kernels, bind};
use crate::shaders::{MODULES, ShaderSource, Switches};
use crate::upload::{WORKGROUP, dispatch};
use bytemuck::{Pod, Zeroable};
use glam::{DQuat, DVec3};
use tumble_scene::Plan;
use tumble_shaders::{NO_TRACK, REDUCE_BLOCK, TRACK_ROW_WORDS};
use tumble_state::{Frame, Observables, TrackRow};
use wgpu::util::DeviceExt;

/// The sums of a range of slots (reduce.wgsl's `Partial`, field for field).
#[repr(C)]
#[derive(Clone, Copy, Debug, Default, PartialEq, Pod, Zeroable)]
pub(crate) struct Partial {
    /// (hi, lo) pairs, indexed by the `SUM_*` constants.
    sums: [[f32; 2]; 8],
    /// Contacts, largest overlap ratio (f32 bits), finite (1 or 0), particles in the domain.
    counts: [u32; 4],
}

const SUM_KINETIC: usize = 0;
const SUM_ROTATIONAL: usize = 1;
const SUM_POTENTIAL: usize = 2;
const SUM_MASS: usize = 3;
const SUM_ELASTIC: usize = 4;
const SUM_DISSIPATED: usize = 5;
const SUM_FLUID: usize = 6;

/// Bytes of one partial on the device.
pub(crate) const PARTIAL_BYTES: u64 = std::mem::size_of::<Partial>() as u64;

/// Bytes of one gathered track row.
pub(crate) const TRACK_ROW_BYTES: u64 = 16 * TRACK_ROW_WORDS as u64;

/// reduce.wgsl's `ReduceParams`: one level's inputs and partials.
#[repr(C)]
#[derive(Clone, Copy, Debug, Pod, Zeroable)]
struct ReduceParams {
    inputs: u32,
    groups: u32,
    materials: u32,
    _pad: u32,
    gravity_hi: [f32; 4],
    gravity_lo: [f32; 4],
}

/// `x` as two f32, hi + lo (about 48 bits).
fn two_float(x: f64) -> [f32; 2] {
    let hi = x as f32;
    [hi, (x - hi as f64) as f32]
}

/// (inputs, partials) of each level of the tree over `slots` slots; the last level writes one.
pub(crate) fn levels(slots: u32) -> Vec<(u32, u32)> {
    let mut out = Vec::new();
    let mut inputs = slots;
    loop {
        let groups = inputs.div_ceil(REDUCE_BLOCK).max(1);
        out.push((inputs, groups));
        if groups == 1 {
            return out;
        }
        inputs = groups;
    }
}

/// Track rank by particle id: the tracked ids in ascending order get 0, 1, …; others `NO_TRACK`.
pub(crate) fn track_ranks(track: &[bool]) -> (Vec<u32>, usize) {
    let mut next = 0u32;
    let ranks = track
        .iter()
        .map(|&t| {
            if !t {
                return NO_TRACK;
            }
            next += 1;
            next - 1
        })
        .collect();
    (ranks, next as usize)
}

/// Principal moments of inertia per (shape, material), body frame, as the host's state takes
/// them: two vec4 per row, the high and the low f32 parts.
fn body_inertia(plan: &Plan) -> Vec<[f32; 4]> {
    let mut out = Vec::new();
    for shape in &plan.model.shapes {
        for material in &plan.model.materials {
            let i = shape.body.principal_inertia(material.density).to_array().map(two_float);
            out.push([i[0][0], i[1][0], i[2][0], 0.0]);
            out.push([i[0][1], i[1][1], i[2][1], 0.0]);
        }
    }
    out
}

fn storage(gpu: &Gpu, label: &str, contents: &[u8]) -> wgpu::Buffer {
    // Bindings must not be empty.
    let mut data = contents.to_vec();
    data.resize(data.len().max(16), 0);
    gpu.device.create_buffer_init(&wgpu::util::BufferInitDescriptor {
        label: Some(label),
        contents: &data,
        usage: wgpu::BufferUsages::STORAGE | wgpu::BufferUsages::COPY_SRC | wgpu::BufferUsages::COPY_DST,
    })
}

/// The reduction's buffers and bind groups of one simulation.
pub(crate) struct Reduction {
    levels: Vec<(u32, u32)>,
    /// The partials each level writes; the last holds the whole sum.
    partials: Vec<wgpu::Buffer>,
    /// One per level (level 0 also serves the gather).
    groups: Vec<wgpu::BindGroup>,
    /// The gathered rows, by rank.
    tracks: wgpu::Buffer,
    tracked: usize,
    /// Buffers only the bind groups refer to.
    _bound: Vec<wgpu::Buffer>,
}

impl Reduction {
    /// The buffers and bind groups for `plan` over `buffers`, `track` by particle id.
    pub(crate) fn new(gpu: &Gpu, buffers: &Buffers, kernels: &Kernels, plan: &Plan, slots: u32, track: &[bool]) -> Reduction {
        let switches = Switches::from_plan(plan);
        let module = MODULES.iter().find(|m| m.name == "reduce").expect("the reduce module");
        let shader = ShaderSource::new(module, &switches);
        let layout = kernels.pipeline("reduce_particles").get_bind_group_layout(0);
        let levels = levels(slots);
        let partials: Vec<wgpu::Buffer> =
            levels.iter().map(|&(_, groups)| storage(gpu, "reduce partials", &vec![0; (PARTIAL_BYTES * groups as u64) as usize])).collect();
        // Level 0 reads no partials, but its binding needs a buffer other than the one it writes.
        let stand_in = storage(gpu, "reduce stand-in", &[0; PARTIAL_BYTES as usize]);
        let (ranks, tracked) = track_ranks(track);
        let track_rank = storage(gpu, "track rank", bytemuck::cast_slice(&ranks));
        let tracks = storage(gpu, "tracks", &vec![0; (TRACK_ROW_BYTES * tracked as u64) as usize]);
        let inertia = storage(gpu, "body inertia", bytemuck::cast_slice(&body_inertia(plan)));
        let uniforms: Vec<wgpu::Buffer> = levels
            .iter()
            .map(|&(inputs, groups)| {
                let g = plan.model.gravity.to_array().map(two_float);
                let p = ReduceParams {
                    inputs,
                    groups,
                    materials: plan.model.materials.len() as u32,
                    _pad: 0,
                    gravity_hi: [g[0][0], g[1][0], g[2][0], 0.0],
                    gravity_lo: [g[0][1], g[1][1], g[2][1], 0.0],
                };
                gpu.device.create_buffer_init(&wgpu::util::BufferInitDescriptor {
                    label: Some("reduce params"),
                    contents: bytemuck::bytes_of(&p),
                    usage: wgpu::BufferUsages::UNIFORM,
                })
            })
            .collect();
        let b = buffers;
        let groups = (0..levels.len())
            .map(|l| {
                bind(gpu, (&shader, &layout), &switches, |n| match n {
                    "reduce_level" => Some(&uniforms[l]),
                    "partials_in" => Some(if l == 0 { &stand_in } else { &partials[l - 1] }),
                    "partials_out" => Some(&partials[l]),
                    "force" => Some(&b.force),
                    "stats" => Some(&b.stats),
                    "body_inertia" => Some(&inertia),
                    "track_rank" => Some(&track_rank),
                    "tracks" => Some(&tracks),
                    _ => b.named(n),
                })
            })
            .collect();
        let mut bound = uniforms;
        bound.extend([stand_in, track_rank, inertia]);
        Reduction { levels, partials, groups, tracks, tracked, _bound: bound }
    }
}

fn v3(bits: &[u32]) -> DVec3 {
    DVec3::new(f32::from_bits(bits[0]) as f64, f32::from_bits(bits[1]) as f64, f32::from_bits(bits[2]) as f64)
}

impl GpuSimulation {
    /// Records the tree reduction and the track gather.
    fn record_reduction(&self, encoder: &mut wgpu::CommandEncoder) {
        let r = &self.reduction;
        encoder.clear_buffer(&r.tracks, 0, None);
        // One pass per dispatch, as the scan does: each level reads what the one below wrote.
        let mut run = |entry: &str, group: &wgpu::BindGroup, (x, y): (u32, u32)| {
            let mut pass = encoder.begin_compute_pass(&wgpu::ComputePassDescriptor { label: Some(entry), timestamp_writes: None });
            pass.set_pipeline(self.kernels.pipeline(entry));
            pass.set_bind_group(0, group, &[]);
            pass.dispatch_workgroups(x, y, 1);
        };
        for (l, &(_, groups)) in r.levels.iter().enumerate() {
            run(if l == 0 { "reduce_particles" } else { "reduce_partials" }, &r.groups[l], dispatch(groups, 1));
        }
        if r.tracked > 0 {
            run("gather_tracks", &r.groups[0], dispatch(self.slots, WORKGROUP));
        }
    }

    /// An output row without the particle arrays: the device's sums and track rows and the
    /// wall entries, in one read-back whose size does not depend on the number of particles.
    pub(crate) fn reduced_frame(&self) -> Frame<'static> {
        let r = &self.reduction;
        let parts = [
            (r.partials.last().expect("a reduction level"), PARTIAL_BYTES),
            (&r.tracks, TRACK_ROW_BYTES * r.tracked as u64),
            (&self.buffers.wall_power, self.wall_entry_bytes(4)),
            (&self.buffers.wall_work, self.wall_entry_bytes(8)),
        ];
        let v = self.read_bytes_after(|e| self.record_reduction(e), &parts);
        let partial: Partial = bytemuck::pod_read_unaligned(&v[0]);
        let wall_power = self.group_sums_of(&v[2], crate::walls::wall_power_value);
        let wall_work = self.group_sums_of(&v[3], crate::walls::wall_work_value);
        let observables = self.observables_of_partial(&partial, &wall_work);
        self.alive.set(Some(observables.particles));
        let tracks = self.track_rows(&bytemuck::pod_collect_to_vec(&v[1]));
        Frame { observables, tracks, wall_power, wall_work, drums: Vec::new(), state: None }
    }

    fn observables_of_partial(&self, p: &Partial, wall_work: &[f64]) -> Observables {
        let sum = |k: usize| p.sums[k][0] as f64 + p.sums[k][1] as f64;
        let origin = crate::upload::centre(&self.plan);
        let o = Observables {
            time: self.time(),
            kinetic_energy: sum(SUM_KINETIC),
            rotational_energy: sum(SUM_ROTATIONAL),
            potential_energy: sum(SUM_POTENTIAL) - sum(SUM_MASS) * self.plan.model.gravity.dot(origin),
            elastic_energy: sum(SUM_ELASTIC),
            dissipated_energy: sum(SUM_DISSIPATED),
            fluid_work: sum(SUM_FLUID),
            wall_work: 0.0,
            contacts: p.counts[0] as u64,
            max_overlap_ratio: f32::from_bits(p.counts[1]) as f64,
            particles: p.counts[3] as usize,
            finite: p.counts[2] != 0,
        };
        o.finish(wall_work)
    }

    /// The gathered rows present (a removed particle's row stays cleared), in rank = id order.
    fn track_rows(&self, words: &[[u32; 4]]) -> Vec<TrackRow> {
        let origin = crate::upload::centre(&self.plan);
        words
            .chunks(TRACK_ROW_WORDS as usize)
            .filter(|row| row[1][3] == 1)
            .map(|row| TrackRow {
                id: row[0][3],
                position: v3(&row[0]) + origin,
                velocity: v3(&row[1]),
                angular_velocity: if self.plan.model.rotation { v3(&row[2]) } else { DVec3::ZERO },
                orientation: if self.plan.model.polyhedra {
                    let q = row[3].map(|w| f32::from_bits(w) as f64);
                    DQuat::from_xyzw(q[0], q[1], q[2], q[3])
                } else {
                    DQuat::IDENTITY
                },
            })
            .collect()
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_tree_has_fixed_levels_ending_in_one_partial() {
        assert_eq!(levels(1), vec![(1, 1)]);
        assert_eq!(levels(REDUCE_BLOCK), vec![(REDUCE_BLOCK, 1)]);
        assert_eq!(levels(REDUCE_BLOCK + 1), vec![(REDUCE_BLOCK + 1, 2), (2, 1)]);
        let big = REDUCE_BLOCK * REDUCE_BLOCK * 3;
        assert_eq!(levels(big), vec![(big, REDUCE_BLOCK * 3), (REDUCE_BLOCK * 3, 3), (3, 1)]);
        assert_eq!(PARTIAL_BYTES, 80);
    }

    #[test]
    fn tracked_ids_get_ranks_in_id_order() {
        let (ranks, n) = track_ranks(&[false, true, false, true, true]);
        assert_eq!((ranks, n), (vec![NO_TRACK, 0, NO_TRACK, 1, 2], 3));
    }
}
