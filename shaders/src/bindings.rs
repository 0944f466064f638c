//! The buffers each kernel module binds, defined once: the WGSL declarations are generated from
//! these tables ([`declarations`]) and the host builds its bind group layouts from the same ones.
//! Binding number = position in the table, all in group 0.

/// How a kernel accesses a binding.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Access {
    Uniform,
    Read,
    ReadWrite,
}

/// The plan feature a binding is for. Without it the module declares a private stand-in of the
/// same name instead (only ever touched behind the feature's switch), so the pipeline binds
/// nothing for it: adapters with few storage buffers per stage run the plans that need few.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub enum Feature {
    Always,
    /// Contact history (the HISTORY switch).
    History,
    /// Walls (the WALLS switch).
    Walls,
    /// Moving walls (the MOVING switch).
    Moving,
    /// Polyhedral particles (the POLYHEDRA switch).
    Polyhedra,
    /// A periodic axis (the PERIODIC switch).
    Periodic,
}

/// One binding of a kernel module.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct Binding {
    pub name: &'static str,
    /// The WGSL type (a struct for uniforms, a runtime-sized array for storage).
    pub ty: &'static str,
    pub access: Access,
    pub feature: Feature,
}

const fn b(name: &'static str, ty: &'static str, access: Access, feature: Feature) -> Binding {
    Binding { name, ty, access, feature }
}

use Access::{Read, ReadWrite, Uniform};
use Feature::{Always, History, Moving, Periodic, Polyhedra, Walls};

const V4F: &str = "array<vec4<f32>>";
const V4U: &str = "array<vec4<u32>>";
const U32S: &str = "array<u32>";
const ATOMICS: &str = "array<atomic<u32>>";
const IMAGES: &str = "array<vec4<i32>>";

/// broad.wgsl: cell index and counting sort.
pub const BROAD: &[Binding] = &[
    b("params", "Params", Uniform, Always),
    b("pos", V4F, Read, Always),
    b("props", V4U, Read, Always),
    b("cell", U32S, ReadWrite, Always),
    b("count", ATOMICS, ReadWrite, Always),
    b("cell_start", U32S, Read, Always),
    b("cursor", ATOMICS, ReadWrite, Always),
    b("cell_list", U32S, ReadWrite, Always),
];

/// scan.wgsl: one level of the prefix sum.
pub const SCAN: &[Binding] = &[b("scan", "ScanParams", Uniform, Always), b("data", U32S, ReadWrite, Always), b("sums", U32S, ReadWrite, Always)];

/// reorder.wgsl: one per-particle array into cell order.
pub const REORDER: &[Binding] =
    &[b("params", "Params", Uniform, Always), b("cell_list", U32S, Read, Always), b("src", V4U, Read, Always), b("dst", V4U, ReadWrite, Always)];

/// forces.wgsl: the contact pass.
pub const FORCES: &[Binding] = &[
    b("params", "Params", Uniform, Always),
    b("pos", V4F, Read, Always),
    b("vel", V4F, Read, Always),
    b("omega", V4F, Read, Always),
    b("acc", V4F, Read, Always),
    b("alpha", V4F, Read, Always),
    b("props", V4U, Read, Always),
    b("cell", U32S, Read, Always),
    b("cell_start", U32S, Read, Always),
    b("cell_list", U32S, Read, Always),
    b("tables", V4F, Read, Always),
    // Force (xyz) and elastic energy owned (w).
    b("force_out", V4F, ReadWrite, Always),
    // Torque (xyz) and dissipated power owned (w).
    b("torque_out", V4F, ReadWrite, Always),
    // Contacts owned, largest overlap ratio (f32 bits).
    b("stats_out", "array<vec2<u32>>", ReadWrite, Always),
    // The two generations of contact-history slots (history.wgsl).
    b("hist_old", V4U, Read, History),
    b("hist_new", V4U, ReadWrite, History),
    // Per particle id and wall group: the wall's load (force, power; torque) and work (walls_moving.wgsl).
    b("wall_load", V4F, ReadWrite, Walls),
    b("wall_work", "array<vec2<f32>>", ReadWrite, Moving),
    // Orientation (unit quaternion x, y, z, w, body to world).
    b("orient", V4F, Read, Polyhedra),
];

/// integrate.wgsl: body forces and the integrators.
pub const INTEGRATE: &[Binding] = &[
    b("params", "Params", Uniform, Always),
    // Position (xyz, relative to the domain's centre) and radius.
    b("pos", V4F, ReadWrite, Always),
    // Velocity and inverse mass (0: fixed).
    b("vel", V4F, ReadWrite, Always),
    // Angular velocity and inverse moment of inertia.
    b("omega", V4F, ReadWrite, Always),
    // Acceleration of the last force pass and the drag parameter (τ_p, or α/m).
    b("acc", V4F, ReadWrite, Always),
    // Angular acceleration and mass.
    b("alpha", V4F, ReadWrite, Always),
    b("props", V4U, ReadWrite, Always),
    b("force_in", V4F, Read, Always),
    b("torque_in", V4F, Read, Always),
    // Dissipated energy, fluid work, and their compensation terms (Kahan sums).
    b("energy", V4F, ReadWrite, Always),
    b("orient", V4F, ReadWrite, Polyhedra),
    // The pair and wall tables, then the shape table (polyhedra).
    b("tables", V4F, Read, Always),
    // Periodic images per ORIGINAL id: box lengths wrapped off each axis (xyz), so the re-sort never moves them.
    b("image", IMAGES, ReadWrite, Periodic),
];

/// reduce.wgsl: the output row's reductions (observables, wall groups, drums) and the
/// tracked-particle gather. Every level of the reduction binds the same table (level 0 reads
/// the particle arrays, the levels above read `partials_in`).
pub const REDUCE: &[Binding] = &[
    b("params", "Params", Uniform, Always),
    b("reduce_level", "ReduceParams", Uniform, Always),
    b("pos", V4F, Read, Always),
    b("vel", V4F, Read, Always),
    b("omega", V4F, Read, Always),
    b("alpha", V4F, Read, Always),
    b("props", V4U, Read, Always),
    b("energy", V4F, Read, Always),
    b("force", V4F, Read, Always),
    b("stats", "array<vec2<u32>>", Read, Always),
    b("orient", V4F, Read, Polyhedra),
    // Principal moments of inertia per (shape, material), body frame (polyhedra), then the
    // drums (DRUM_ROW_WORDS each, from ReduceParams.drum_rows).
    b("reduce_table", V4F, Read, Always),
    b("wall_load", V4F, Read, Walls),
    b("wall_work", "array<vec2<f32>>", Read, Moving),
    // Per block, one partial per lane: the observables, then each wall group, then each drum.
    b("partials_in", "array<Partial>", Read, Always),
    b("partials_out", "array<Partial>", ReadWrite, Always),
    // Per drum, DRUM_BINS counts of the shell layer's angles (integer atomics: any order sums alike).
    b("drum_bins", ATOMICS, ReadWrite, Moving),
    // Track rank by particle id (NO_TRACK when untracked), and the gathered rows by rank.
    b("track_rank", U32S, Read, Always),
    b("tracks", V4U, ReadWrite, Always),
    // Periodic images per original id (integrate.wgsl): the potential uses unwrapped positions.
    b("image", IMAGES, Read, Periodic),
];

/// sph_sort.wgsl: the fluid's counting sort by cell and the permutation of its arrays.
pub const SPH_SORT: &[Binding] = &[
    b("fluid", "FluidParams", Uniform, Always),
    // Position relative to the domain's centre (xyz) and mass.
    b("pos", V4F, Read, Always),
    // Velocity (a wall particle's: its wall's) and density.
    b("vel", V4F, Read, Always),
    // Kind (SPH_FLUID, SPH_WALL), id, wall number, cell.
    b("tags", V4U, Read, Always),
    b("cell", U32S, ReadWrite, Always),
    b("count", ATOMICS, ReadWrite, Always),
    b("cell_start", U32S, Read, Always),
    b("cursor", ATOMICS, ReadWrite, Always),
    b("cell_list", U32S, ReadWrite, Always),
    b("pos_sorted", V4F, ReadWrite, Always),
    b("vel_sorted", V4F, ReadWrite, Always),
    b("tags_sorted", V4U, ReadWrite, Always),
];

/// sph_step.wgsl: the fluid's evaluations and the halves of its step, on the sorted arrays.
pub const SPH_STEP: &[Binding] = &[
    b("fluid", "FluidParams", Uniform, Always),
    b("pos", V4F, ReadWrite, Always),
    b("vel", V4F, ReadWrite, Always),
    b("tags", V4U, Read, Always),
    b("cell_start", U32S, Read, Always),
    // Pressure, P/ρ², m/ρ, the tensile term R.
    b("state", V4F, ReadWrite, Always),
    // The velocity the viscous terms see (a wall's: Adami's 2 v_w − ṽ), and 1 for fluid, 0 for a wall.
    b("viscous", V4F, ReadWrite, Always),
    // Acceleration and density rate.
    b("rate", V4F, ReadWrite, Always),
    b("xsph", V4F, ReadWrite, Always),
    // Velocity and density at the step's start.
    b("start", V4F, ReadWrite, Always),
    // Per moving wall and floating body, the current half step's motion table (SPH_MOTION_WORDS
    // entries each), then each body's centre.
    b("motions", V4F, Read, Always),
    // Per floating body, the fluid's force on it and its moment about the centre.
    b("body_sums", V4F, ReadWrite, Always),
];

/// polyhedra_test.wgsl: the narrow-phase harness.
pub const POLYHEDRA_TEST: &[Binding] = &[
    b("count", "vec4<u32>", Uniform, Always),
    b("shapes", V4F, Read, Always),
    b("queries", "array<Query>", Read, Always),
    b("answers", V4F, ReadWrite, Always),
];

/// The WGSL declarations of `bindings`; a binding whose feature is off becomes a private (for
/// atomics, workgroup) one-element stand-in.
pub fn declarations(bindings: &[Binding], enabled: impl Fn(Feature) -> bool) -> String {
    let mut out = String::new();
    for (k, binding) in bindings.iter().enumerate() {
        let Binding { name, ty, access, feature } = *binding;
        let line = if enabled(feature) {
            let space = match access {
                Uniform => "uniform",
                Read => "storage, read",
                ReadWrite => "storage, read_write",
            };
            format!("@group(0) @binding({k}) var<{space}> {name}: {ty};\n")
        } else {
            let element = ty.strip_prefix("array<").and_then(|t| t.strip_suffix('>')).expect("only storage arrays depend on a feature");
            // Atomics live only in storage or workgroup memory.
            let space = if element.starts_with("atomic") { "workgroup" } else { "private" };
            format!("var<{space}> {name}: array<{element}, 1>;\n")
        };
        out.push_str(&line);
    }
    out
}

/// Storage buffers a module binds with the features `enabled` has on.
pub fn storage_buffers(bindings: &[Binding], enabled: impl Fn(Feature) -> bool) -> u32 {
    bindings.iter().filter(|b| b.access != Uniform && enabled(b.feature)).count() as u32
}
