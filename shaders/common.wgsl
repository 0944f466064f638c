// Shared by every particle kernel (assembled after the prelude and the binding declarations,
// tumble-shaders' lib.rs): the step parameters, the plan's feature switches and the index helpers.
//
// Positions are relative to the domain's centre (the best f32 precision): the
// domain spans [-extent/2, extent/2];
// every per-particle array is an array of vec4 so one permutation kernel can
// re-sort them all. Particle flags (props.w, low 16 bits: FLAG_FIXED, FLAG_DEAD) and the
// shape index (from bit SHAPE_SHIFT; SPHERE_SHAPE for a sphere; only read with POLYHEDRA)
// are prelude constants.

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
// Polyhedra meet through the overlap-volume model (else the separating-axis depth).
override VOLUME: bool = false;
// Tangential springs with history and rolling resistance (history.wgsl).
override HISTORY: bool = false;
override ROLLING: bool = false;
// Moving walls (velocities, per-step poses, wall power) and lifter prisms (walls_moving.wgsl).
override MOVING: bool = false;
override PRISMS: bool = false;
// DRAG_NONE, DRAG_STOKES or DRAG_QUADRATIC.
override DRAG: u32 = DRAG_NONE;
override TAYLOR_GREEN: bool = false;
// INTEGRATOR_EULER, _SYMPLECTIC_EULER, _VERLET, _IMPLICIT_DRAG or _IMPLICIT_DRAG_SYMPLECTIC.
override INTEGRATOR: u32 = INTEGRATOR_EULER;

// The step parameters (tumble-gpu's upload::Params, field for field; a test compares the offsets).
struct Params {
    // Particle slots (removed particles keep theirs, flagged).
    particles: u32,
    // Live cells (the removed-particle bucket is index `cells`).
    cells: u32,
    walls: u32,
    materials: u32,
    // Contact-history slots per particle (0 without history).
    history_slots: u32,
    // Wall groups (moving walls: wall power is booked per group).
    wall_groups: u32,
    // The first word of the shape table in `tables` (polyhedra).
    shape_base: u32,
    // Threads per dispatch row (x groups * WORKGROUP).
    row_threads: u32,
    // Cells per axis.
    dims: vec3<u32>,
    _pad_dims: u32,
    // 1 where the axis is periodic.
    periodic: vec3<u32>,
    _pad_periodic: u32,
    // The time step.
    dt: f32,
    // Taylor–Green flow: amplitude and wave number.
    taylor_green_amplitude: f32,
    taylor_green_frequency: f32,
    _pad_scalars: f32,
    // Inverse cell widths per axis.
    inv_cell: vec3<f32>,
    _pad_inv_cell: f32,
    // Domain extent per axis (the domain spans [-extent/2, extent/2] in these coordinates).
    extent: vec3<f32>,
    _pad_extent: f32,
    gravity: vec3<f32>,
    _pad_gravity: f32,
    // Uniform flow velocity.
    flow: vec3<f32>,
    _pad_flow: f32,
    // The domain's centre in world coordinates (for the flow field).
    origin: vec3<f32>,
    _pad_origin: f32,
    // Outlets, and the first entry of their table in `tables`.
    outlets: u32,
    outlet_base: u32,
    _pad_outlets0: u32,
    _pad_outlets1: u32,
}

// The flat invocation index of a (possibly 2D) dispatch.
fn flat_index(gid: vec3<u32>) -> u32 {
    return gid.x + gid.y * params.row_threads;
}
