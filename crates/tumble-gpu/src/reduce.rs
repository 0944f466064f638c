//! The output row's read-back kept small: the observables' particle sums, each wall group's
//! power and work and each drum's charge profile reduced on the device, and the tracked
//! particles gathered there (reduce.wgsl), so a row reads back one 80-byte partial per lane
//! (observables, wall groups, drums), one 64-byte row per tracked particle and
//! `DRUM_BINS` counts per drum, whatever the number of particles.
//!
//! The reduction is a fixed-shape tree: each workgroup sums `REDUCE_BLOCK` slots into one
//! partial, each level above sums `REDUCE_BLOCK` partials of the one below, until one is left;
//! every lane runs the same tree. There are no float atomics, so a run gives bit-identical sums
//! every time on one device (the drums' angle histograms count with integer atomics, which give
//! the same counts in any order).
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
//! movable mass, is added on the host in f64. Wall power and work are the same tree over the
//! per-(id, group) entries; a drum's toe and shoulder are read from its histogram, to within
//! half a bin (0.05°) of the percentiles of the exact angles (drums.rs).

use crate::GpuSimulation;
use crate::buffers::Buffers;
use crate::context::Gpu;
use crate::kernels::{Kernels, bind};
use crate::shaders::{MODULES, ShaderSource, Switches};
use crate::upload::{WORKGROUP, dispatch};
use bytemuck::{Pod, Zeroable};
use glam::{DQuat, DVec3};
use tumble_plan::Plan;
use tumble_shaders::{DRUM_BINS, NO_TRACK, REDUCE_BLOCK, TRACK_ROW_WORDS};
use tumble_state::{Frame, Observables, TrackRow};
use wgpu::util::DeviceExt;

/// The sums of a range of slots in one lane (reduce.wgsl's `Partial`, field for field).
#[repr(C)]
#[derive(Clone, Copy, Debug, Default, PartialEq, Pod, Zeroable)]
pub(crate) struct Partial {
    /// (hi, lo) pairs: in lane 0 indexed by the `SUM_*` constants; a wall group's power, work,
    /// force and torque about the device's origin; a drum's charge mass and Σ m·radial.
    sums: [[f32; 2]; 8],
    /// Lane 0: contacts, largest overlap ratio (f32 bits), finite (1 or 0), particles in the domain.
    counts: [u32; 4],
}

impl Partial {
    /// Sum `k` as f64 (hi + lo).
    pub(crate) fn sum(&self, k: usize) -> f64 {
        self.sums[k][0] as f64 + self.sums[k][1] as f64
    }
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
    lanes: u32,
    wall_groups: u32,
    drums: u32,
    drum_rows: u32,
    first: u32,
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
/// them: two vec4 per row, the high and the low f32 parts (polyhedra scenes; none otherwise).
fn body_inertia(plan: &Plan) -> Vec<[f32; 4]> {
    let mut out = Vec::new();
    if !plan.model.polyhedra {
        return out;
    }
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
    /// Lanes of every level: the observables, each wall group, each drum.
    lanes: u32,
    /// Wall groups with a lane (all of them with walls, none otherwise).
    wall_lanes: usize,
    /// The partials each level writes, `lanes` per workgroup; the last holds the whole sums.
    partials: Vec<wgpu::Buffer>,
    /// One per level (level 0 also serves the gather).
    groups: Vec<wgpu::BindGroup>,
    /// The gathered rows, by rank.
    tracks: wgpu::Buffer,
    tracked: usize,
    /// Each drum's shell-angle histogram (`DRUM_BINS` counts).
    drum_bins: wgpu::Buffer,
    /// Buffers only the bind groups refer to.
    _bound: Vec<wgpu::Buffer>,
}

impl Reduction {
    /// The buffers and bind groups for `plan` over `buffers`, `track` by particle id.
    pub(crate) fn new(gpu: &Gpu, buffers: &Buffers, kernels: &Kernels, plan: &Plan, slots: u32, track: &[bool]) -> Reduction {
        let switches = Switches::from_plan(plan);
        let module = MODULES.iter().find(|m| m.name == "reduce").expect("the reduce module");
        let shader = ShaderSource::new(module, &switches);
        let layout = kernels.pipeline("reduce_rows").get_bind_group_layout(0);
        let levels = levels(slots);
        let drums = plan.model.drums.len();
        assert!(drums == 0 || switches.moving, "a drum is a rotating wall");
        let wall_lanes = if switches.walls { plan.model.wall_groups.len() } else { 0 };
        let lanes = (1 + wall_lanes + drums) as u32;
        let partials: Vec<wgpu::Buffer> = levels
            .iter()
            .map(|&(_, groups)| storage(gpu, "reduce partials", &vec![0; (PARTIAL_BYTES * groups as u64 * lanes as u64) as usize]))
            .collect();
        // Level 0 reads no partials, but its binding needs a buffer other than the one it writes.
        let stand_in = storage(gpu, "reduce stand-in", &[0; PARTIAL_BYTES as usize]);
        let (ranks, tracked) = track_ranks(track);
        let track_rank = storage(gpu, "track rank", bytemuck::cast_slice(&ranks));
        let tracks = storage(gpu, "tracks", &vec![0; (TRACK_ROW_BYTES * tracked as u64) as usize]);
        let mut table = body_inertia(plan);
        let drum_rows = table.len() as u32;
        table.extend(crate::drums::drum_rows(plan));
        let table = storage(gpu, "reduce table", bytemuck::cast_slice(&table));
        let drum_bins = storage(gpu, "drum bins", &vec![0; 4 * DRUM_BINS as usize * drums]);
        let uniforms: Vec<wgpu::Buffer> = levels
            .iter()
            .enumerate()
            .map(|(l, &(inputs, groups))| {
                let g = plan.model.gravity.to_array().map(two_float);
                let p = ReduceParams {
                    inputs,
                    groups,
                    materials: plan.model.materials.len() as u32,
                    lanes,
                    wall_groups: wall_lanes as u32,
                    drums: drums as u32,
                    drum_rows,
                    first: u32::from(l == 0),
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
                    "reduce_table" => Some(&table),
                    "drum_bins" => Some(&drum_bins),
                    "track_rank" => Some(&track_rank),
                    "tracks" => Some(&tracks),
                    _ => b.named(n),
                })
            })
            .collect();
        let mut bound = uniforms;
        bound.extend([stand_in, track_rank, table]);
        Reduction { levels, lanes, wall_lanes, partials, groups, tracks, tracked, drum_bins, _bound: bound }
    }
}

fn v3(bits: &[u32]) -> DVec3 {
    DVec3::new(f32::from_bits(bits[0]) as f64, f32::from_bits(bits[1]) as f64, f32::from_bits(bits[2]) as f64)
}

impl GpuSimulation {
    /// Records the tree reduction (every lane) and the track gather.
    fn record_reduction(&self, encoder: &mut wgpu::CommandEncoder) {
        let r = &self.reduction;
        encoder.clear_buffer(&r.tracks, 0, None);
        encoder.clear_buffer(&r.drum_bins, 0, None);
        // One pass per dispatch, as the scan does: each level reads what the one below wrote.
        let mut run = |entry: &str, group: &wgpu::BindGroup, (x, y): (u32, u32), z: u32| {
            let mut pass = encoder.begin_compute_pass(&wgpu::ComputePassDescriptor { label: Some(entry), timestamp_writes: None });
            pass.set_pipeline(self.kernels.pipeline(entry));
            pass.set_bind_group(0, group, &[]);
            pass.dispatch_workgroups(x, y, z);
        };
        for (l, &(_, groups)) in r.levels.iter().enumerate() {
            run("reduce_rows", &r.groups[l], dispatch(groups, 1), r.lanes);
        }
        if r.tracked > 0 {
            run("gather_tracks", &r.groups[0], dispatch(self.slots, WORKGROUP), 1);
        }
    }

    /// An output row: the device's sums, track rows and drum histograms, and with `with_state`
    /// the particle arrays, in one read-back (without the arrays its size does not depend on
    /// the number of particles).
    pub(crate) fn reduced_frame(&self, with_state: bool) -> Frame<'static> {
        let r = &self.reduction;
        let drums = self.plan.model.drums.len() as u64;
        let mut parts = vec![
            (r.partials.last().expect("a reduction level"), PARTIAL_BYTES * r.lanes as u64),
            (&r.tracks, TRACK_ROW_BYTES * r.tracked as u64),
            (&r.drum_bins, 4 * DRUM_BINS as u64 * drums),
        ];
        if with_state {
            parts.extend(self.array_parts());
        }
        let v = self.read_bytes_after(|e| self.record_reduction(e), &parts);
        let lanes: Vec<Partial> = bytemuck::pod_collect_to_vec(&v[0]);
        let groups = self.plan.model.wall_groups.len();
        let wall_lane = |g: usize, k: usize| if g < r.wall_lanes { lanes[1 + g].sum(k) } else { 0.0 };
        let wall_power: Vec<f64> = (0..groups).map(|g| wall_lane(g, 0)).collect();
        let wall_work: Vec<f64> = (0..groups).map(|g| wall_lane(g, 1)).collect();
        let wall_force: Vec<DVec3> = (0..groups).map(|g| DVec3::new(wall_lane(g, 2), wall_lane(g, 3), wall_lane(g, 4))).collect();
        let about_origin: Vec<DVec3> = (0..groups).map(|g| DVec3::new(wall_lane(g, 5), wall_lane(g, 6), wall_lane(g, 7))).collect();
        let wall_torque = self.torques_about_references(&about_origin, &wall_force);
        let observables = self.observables_of_partial(&lanes[0], &wall_work);
        self.alive.set(Some(observables.particles));
        let tracks = self.track_rows(&bytemuck::pod_collect_to_vec(&v[1]));
        let drums = crate::drums::profiles(&self.plan, self.time(), &lanes[1 + r.wall_lanes..], &bytemuck::pod_collect_to_vec(&v[2]));
        let state = with_state.then(|| {
            let arrays = crate::readback::DeviceArrays::from_bytes(std::array::from_fn(|k| v[3 + k].as_slice()));
            std::borrow::Cow::Owned(self.state_from(&arrays))
        });
        Frame { observables, tracks, wall_power, wall_work, wall_force, wall_torque, servo_offset: Vec::new(), drums, state }
    }

    fn observables_of_partial(&self, p: &Partial, wall_work: &[f64]) -> Observables {
        let sum = |k: usize| p.sum(k);
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
