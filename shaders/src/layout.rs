//! The constants the host and the WGSL kernels share: codes stored in the tables or passed as
//! override values, flag bits, table entry sizes, dispatch sizes and device capacities.
//!
//! Each is defined here once; [`crate::prelude`] declares every one of them in WGSL at the top of
//! every module, so the kernels use the names and never the numbers.

/// Declares the shared constants and [`SHARED`], the list the prelude is generated from.
macro_rules! shared {
    ($($(#[$doc:meta])* $name:ident = $value:expr;)*) => {
        $($(#[$doc])* pub const $name: u32 = $value;)*
        /// Every constant shared with WGSL, by name (the prelude declares each as `const NAME: u32`).
        pub const SHARED: &[(&str, u32)] = &[$((stringify!($name), $name)),*];
    };
}

shared! {
    // ---- Particles (props.w) ----
    /// A particle that does not move (props.w bit).
    FLAG_FIXED = 1;
    /// A particle that left the domain (props.w bit; it sorts into the removed bucket).
    FLAG_DEAD = 2;
    /// props.w holds the shape index from this bit on (polyhedra scenes).
    SHAPE_SHIFT = 16;
    /// A particle an outlet deleted: props.w holds the outlet's index + 1 in 8 bits from here.
    OUTLET_SHIFT = 8;

    // ---- Outlets (the tables buffer from params.outlet_base; OUTLET_ENTRIES vec4 each) ----
    /// vec4 entries per outlet: (kind, 0, 0, 0), (box min or plane point), (box max or plane normal).
    OUTLET_ENTRIES = 3;
    /// An axis-aligned box: particles whose centre gets inside are deleted.
    OUTLET_BOX = 0;
    /// A plane: particles whose centre gets beyond it (the side its normal points to) are deleted.
    OUTLET_PLANE = 1;
    /// The shape index of a sphere (tumble-scene's `SPHERE`).
    SPHERE_SHAPE = 0xffff;

    // ---- Dispatch ----
    /// Threads per workgroup of the particle kernels.
    WORKGROUP = 64;
    /// Threads per workgroup of the scan.
    SCAN_THREADS = 256;
    /// Values each scan thread sums.
    SCAN_PER_THREAD = 4;
    /// Values per workgroup of the scan.
    SCAN_BLOCK = SCAN_THREADS * SCAN_PER_THREAD;
    /// Values one workgroup of the output-row reduction sums (WORKGROUP threads, four each).
    REDUCE_BLOCK = WORKGROUP * 4;

    // ---- Tracked particles (reduce.wgsl) ----
    /// vec4<u32> words per gathered row: (position bits, id), (velocity bits, 1 when present),
    /// (angular velocity bits, 0), (orientation bits).
    TRACK_ROW_WORDS = 4;
    /// The track rank of an untracked particle id.
    NO_TRACK = u32::MAX;

    // ---- Drum profiles (reduce.wgsl) ----
    /// vec4 entries per drum in the reduce table: (axis point, radius), (axis, length),
    /// (down, 0), (along, 0), relative to the domain's centre.
    DRUM_ROW_WORDS = 4;
    /// Bins of the shell layer's angle histogram over (−180°, 180°] (0.1° each).
    DRUM_BINS = 3600;

    // ---- Integrators (the INTEGRATOR override) ----
    INTEGRATOR_EULER = 0;
    INTEGRATOR_SYMPLECTIC_EULER = 1;
    INTEGRATOR_VERLET = 2;
    INTEGRATOR_IMPLICIT_DRAG = 3;
    INTEGRATOR_IMPLICIT_DRAG_SYMPLECTIC = 4;

    // ---- Drag laws (the DRAG override) ----
    DRAG_NONE = 0;
    DRAG_STOKES = 1;
    DRAG_QUADRATIC = 2;

    // ---- The pair table ----
    /// vec4 entries per material pair.
    PAIR_ENTRY_WORDS = 3;
    /// Normal laws (t0.x).
    NORMAL_LINEAR = 0;
    NORMAL_HERTZ = 1;
    /// Tangential laws (t1.x).
    TANGENTIAL_NONE = 0;
    TANGENTIAL_VISCOUS_COULOMB = 1;
    TANGENTIAL_STICK_LIMITED = 2;
    TANGENTIAL_DYNAMIC_ONLY = 3;
    TANGENTIAL_HISTORY_LINEAR = 4;
    TANGENTIAL_HISTORY_MINDLIN = 5;

    // ---- The wall table ----
    /// vec4 entries per wall.
    WALL_ENTRY_WORDS = 6;
    /// Wall kinds (w0.x).
    WALL_PLANE = 0;
    WALL_QUAD = 1;
    WALL_CYLINDER = 2;
    WALL_PRISM = 3;
    /// Extras of every wall when some wall moves: (ω, group), (velocity at the domain's centre, 0).
    WALL_MOTION_WORDS = 2;
    /// A prism's first extras: (enclosing sphere), (drum axis point, inner radius), (drum axis, 0).
    PRISM_HEAD_WORDS = 3;
    /// Faces of a lifter bar, and vec4 per face (4 corners, the outward normal).
    PRISM_FACES = 6;
    PRISM_FACE_WORDS = 5;
    /// Where a prism's hull pose starts in its extras (polyhedra): after the head and the faces.
    PRISM_HULL = PRISM_HEAD_WORDS + PRISM_FACES * PRISM_FACE_WORDS;
    /// The hull pose: (centre, shape index), orientation.
    PRISM_HULL_WORDS = 2;

    // ---- Contact history ----
    /// Set in a history key that names a wall (tumble-cpu's `WALL_KEY`).
    WALL_KEY = 1 << 31;
    /// Count entries per particle after the slots of one generation.
    HISTORY_COUNT_ENTRIES = 1;
    /// Stored spring energies per 16-byte entry.
    HISTORY_ENERGIES_PER_ENTRY = 4;

    // ---- The shape table (polyhedra) ----
    /// Header words per shape.
    SHAPE_HEADER_WORDS = 4;
    /// Face-loop vertex indices per word.
    LOOP_INDICES_PER_WORD = 4;
    /// Most vertices in one face loop on the device.
    MAX_FACE_VERTICES = 16;
    /// Most vertices of one shape on the device (a manifold against a wall holds every vertex).
    MAX_VERTICES = 32;
    /// Points a manifold holds before its reduction to four: a clipped face, or every vertex.
    MANIFOLD_POINTS = 32;

    // ---- Narrow-phase queries (the polyhedra test harness) ----
    QUERY_POLYHEDRA = 0;
    QUERY_SPHERE = 1;
    QUERY_WALL = 2;
    /// Overlap-volume contacts (volume_contact.wgsl): polyhedron against polyhedron, against a wall.
    QUERY_VOLUME_PAIR = 3;
    QUERY_VOLUME_WALL = 4;
    /// 16-byte words of one answer.
    ANSWER_WORDS = 5;

    // ---- The overlap-volume contact ----
    /// Material points per edge against a cylinder (tumble-geom's `CYLINDER_EDGE_POINTS`).
    CYLINDER_EDGE_POINTS = 8;

    // ---- The SPH fluid (sph_*.wgsl) ----
    /// A fluid particle's kind (tags.x).
    SPH_FLUID = 0;
    /// A wall's dummy particle.
    SPH_WALL = 1;
    /// Method switches (FluidParams.counts.z bits): Morris's laminar viscosity (else Monaghan's artificial one).
    SPH_LAMINAR = 1;
    /// δ-SPH density diffusion.
    SPH_DIFFUSE = 2;
    /// Monaghan's tensile correction.
    SPH_TENSILE = 4;
    /// The XSPH velocity correction.
    SPH_XSPH = 8;
    /// vec4 entries per moving wall in the fluid's motion table, for one half step in device
    /// coordinates: the move over the half step (rows of [A | b], x ↦ A x + b), the velocity at
    /// its end and the acceleration at its start (rows of affine maps of the position).
    SPH_MOTION_WORDS = 9;
}

// A face clipped by a face has at most twice its vertices; a wall manifold holds every vertex.
const _: () = assert!(2 * MAX_FACE_VERTICES <= MANIFOLD_POINTS && MAX_VERTICES <= MANIFOLD_POINTS);

/// Real-valued model constants the kernels share with the host (the prelude declares each as
/// `const NAME: f32`); tumble-gpu's tests hold them equal to tumble-geom's.
pub const SHARED_F32: &[(&str, f32)] = &[("CORNER_SMOOTHING", CORNER_SMOOTHING)];
/// The corner depth's smoothing width over the smaller bounding radius (tumble-geom's `CORNER_SMOOTHING`).
pub const CORNER_SMOOTHING: f32 = 0.01;
