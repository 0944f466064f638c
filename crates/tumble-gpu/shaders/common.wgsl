// Shared by every tumble kernel (prepended to each kernel file by shaders.rs):
// the step parameters, the plan's feature switches and the index helpers.
//
// Positions are relative to the domain's centre (the best f32 precision): the
// domain spans [-extent/2, extent/2];
// every per-particle array is an array of vec4 so one permutation kernel can
// re-sort them all.

// Feature switches, set per pipeline from the plan (pipeline-overridable
// constants): code behind a false switch is removed when the pipeline is built.
override ROTATION: bool = true;
override COHESION: bool = true;
override PERIODIC: bool = true;
override LINEAR: bool = true;
override HERTZ: bool = true;
override TANGENTIAL: bool = true;
override WALLS: bool = true;
// Convex polyhedral particles (polyhedra.wgsl): orientations, the shape table, twisting friction.
override POLYHEDRA: bool = false;
// Tangential springs with history and rolling resistance (history.wgsl).
override HISTORY: bool = false;
override ROLLING: bool = false;
// Moving walls (velocities, per-step poses, wall power) and lifter prisms (walls_moving.wgsl).
override MOVING: bool = false;
override PRISMS: bool = false;
// 0: no fluid, 1: Stokes drag, 2: quadratic drag.
override DRAG: u32 = 0u;
override TAYLOR_GREEN: bool = false;
// 0 euler, 1 symplectic-euler, 2 verlet, 3 implicit-drag, 4 implicit-drag-symplectic.
override INTEGRATOR: u32 = 0u;

const WORKGROUP: u32 = 64u;

// Particle flags (props.w, low 16 bits); the high 16 bits hold the shape index
// (SPHERE_SHAPE for a sphere; only read with POLYHEDRA).
const FLAG_FIXED: u32 = 1u;
const FLAG_DEAD: u32 = 2u;
const SPHERE_SHAPE: u32 = 0xffffu;

struct Params {
    // n (particle slots), live cells (the removed-particle bucket is index `cells`), walls, materials.
    counts: vec4<u32>,
    // Cells per axis; w: threads per dispatch row (x groups * WORKGROUP).
    dims: vec4<u32>,
    // 1 where the axis is periodic; w: contact-history slots per particle (0 without history).
    periodic: vec4<u32>,
    // Inverse cell widths per axis; w: Δt.
    inv_cell: vec4<f32>,
    // Domain extent per axis (the domain spans [-extent/2, extent/2] in these coordinates); w unused.
    extent: vec4<f32>,
    // Gravity; w: the first word of the shape table in `tables` (polyhedra, a whole number).
    gravity: vec4<f32>,
    // Uniform flow velocity (xyz), or Taylor–Green amplitude (x) and frequency (y).
    flow: vec4<f32>,
    // The domain's centre in world coordinates (for the flow field); w: wall groups.
    origin: vec4<f32>,
}

// The flat invocation index of a (possibly 2D) dispatch.
fn flat_index(gid: vec3<u32>) -> u32 {
    return gid.x + gid.y * params.dims.w;
}
