//! The WGSL sources of tumble's GPU backend (the `.wgsl` files beside this package's
//! `Cargo.toml`), the constants they share with the host ([`layout`]), the buffers each module
//! binds ([`bindings`]) and the assembly of every module: the [`prelude`] (the shared constants
//! in WGSL), the module's binding declarations, then its files.
//!
//! Nothing here knows a scene or a device: tumble-gpu picks the features from the plan and
//! builds the pipelines.

pub mod bindings;
pub mod layout;

pub use bindings::{Access, Binding, Feature};
pub use layout::*;

/// Step parameters, feature switches and index helpers shared by the particle kernels.
pub const COMMON: &str = include_str!("../common.wgsl");
/// Sphere–wall proximity and the minimum image.
pub const GEOMETRY: &str = include_str!("../geometry.wgsl");
/// Cell index and counting sort.
pub const BROAD: &str = include_str!("../broad.wgsl");
/// The counting sort's last step: a cell's range sorted by slot (needs `cell_list`).
pub const CELL_ORDER: &str = include_str!("../cell_order.wgsl");
/// Reduce-then-scan prefix sum.
pub const SCAN: &str = include_str!("../scan.wgsl");
/// Re-sort of per-particle arrays by cell.
pub const REORDER: &str = include_str!("../reorder.wgsl");
/// The gather-style contact pass.
pub const FORCES: &str = include_str!("../forces.wgsl");
/// The contact pass's pairs and walls with a polyhedron.
pub const FORCES_POLYHEDRA: &str = include_str!("../forces_polyhedra.wgsl");
/// Contact history slots, the tangential spring and rolling resistance (used by the contact pass).
pub const HISTORY: &str = include_str!("../history.wgsl");
/// Moving world geometry: wall velocities, wall power and lifter prisms (used by the contact pass).
pub const WALLS_MOVING: &str = include_str!("../walls_moving.wgsl");
/// Quaternions and the rigid-body rotation updates.
pub const QUATERNION: &str = include_str!("../quaternion.wgsl");
/// Convex polyhedra: contacts, the shape table and manifolds (needs QUATERNION).
pub const POLYHEDRA: &str = include_str!("../polyhedra.wgsl");
/// Polyhedron against polyhedron (separating axes, clipped manifold).
pub const POLYHEDRON_POLYHEDRON: &str = include_str!("../polyhedron_polyhedron.wgsl");
/// Sphere against polyhedron.
pub const SPHERE_POLYHEDRON: &str = include_str!("../sphere_polyhedron.wgsl");
/// Polyhedron against plane, quad and cylinder walls.
pub const POLYHEDRON_WALLS: &str = include_str!("../polyhedron_walls.wgsl");
/// Overlap-volume contacts: polyhedron against polyhedron and against walls (needs POLYHEDRA).
pub const VOLUME_CONTACT: &str = include_str!("../volume_contact.wgsl");
/// The test harness of the polyhedra narrow phase.
pub const POLYHEDRA_TEST: &str = include_str!("../polyhedra_test.wgsl");
/// The output row's reductions (observables, wall groups, drums) and tracked-particle gather.
pub const REDUCE: &str = include_str!("../reduce.wgsl");
/// Body forces and the integrators.
pub const INTEGRATE: &str = include_str!("../integrate.wgsl");
/// The SPH fluid's parameters, grid, kernel and equation of state.
pub const SPH_COMMON: &str = include_str!("../sph_common.wgsl");
/// The fluid's counting sort by cell.
pub const SPH_SORT: &str = include_str!("../sph_sort.wgsl");
/// The fluid's evaluations and symplectic step.
pub const SPH_STEP: &str = include_str!("../sph_step.wgsl");

/// Every WGSL file, by file name.
pub const FILES: &[(&str, &str)] = &[
    ("common.wgsl", COMMON),
    ("geometry.wgsl", GEOMETRY),
    ("broad.wgsl", BROAD),
    ("cell_order.wgsl", CELL_ORDER),
    ("scan.wgsl", SCAN),
    ("reorder.wgsl", REORDER),
    ("forces.wgsl", FORCES),
    ("forces_polyhedra.wgsl", FORCES_POLYHEDRA),
    ("history.wgsl", HISTORY),
    ("walls_moving.wgsl", WALLS_MOVING),
    ("quaternion.wgsl", QUATERNION),
    ("polyhedra.wgsl", POLYHEDRA),
    ("polyhedron_polyhedron.wgsl", POLYHEDRON_POLYHEDRON),
    ("sphere_polyhedron.wgsl", SPHERE_POLYHEDRON),
    ("polyhedron_walls.wgsl", POLYHEDRON_WALLS),
    ("volume_contact.wgsl", VOLUME_CONTACT),
    ("polyhedra_test.wgsl", POLYHEDRA_TEST),
    ("integrate.wgsl", INTEGRATE),
    ("reduce.wgsl", REDUCE),
    ("sph_common.wgsl", SPH_COMMON),
    ("sph_sort.wgsl", SPH_SORT),
    ("sph_step.wgsl", SPH_STEP),
];

const NARROW_PHASE: [&str; 6] = [QUATERNION, POLYHEDRA, POLYHEDRON_POLYHEDRON, SPHERE_POLYHEDRON, POLYHEDRON_WALLS, VOLUME_CONTACT];

/// One shader module: its files in order, its bindings and its entry points.
#[derive(Clone, Copy, Debug)]
pub struct Module {
    pub name: &'static str,
    pub files: &'static [&'static str],
    pub bindings: &'static [Binding],
    pub entry_points: &'static [&'static str],
}

/// The modules of a simulation, one pipeline per entry point.
pub const MODULES: &[Module] = &[
    Module { name: "broad", files: &[COMMON, CELL_ORDER, BROAD], bindings: bindings::BROAD, entry_points: &["bin", "scatter", "order_cells"] },
    Module { name: "scan", files: &[SCAN], bindings: bindings::SCAN, entry_points: &["reduce", "scan_block"] },
    Module { name: "reorder", files: &[COMMON, REORDER], bindings: bindings::REORDER, entry_points: &["permute"] },
    Module {
        name: "forces",
        files: &[
            COMMON,
            GEOMETRY,
            HISTORY,
            WALLS_MOVING,
            QUATERNION,
            POLYHEDRA,
            POLYHEDRON_POLYHEDRON,
            SPHERE_POLYHEDRON,
            POLYHEDRON_WALLS,
            VOLUME_CONTACT,
            FORCES_POLYHEDRA,
            FORCES,
        ],
        bindings: bindings::FORCES,
        entry_points: &["forces"],
    },
    Module {
        name: "integrate",
        files: &[COMMON, QUATERNION, POLYHEDRA, POLYHEDRON_POLYHEDRON, SPHERE_POLYHEDRON, POLYHEDRON_WALLS, INTEGRATE],
        bindings: bindings::INTEGRATE,
        entry_points: &["initial", "kick_drift", "finish"],
    },
    Module { name: "reduce", files: &[COMMON, QUATERNION, REDUCE], bindings: bindings::REDUCE, entry_points: &["reduce_rows", "gather_tracks"] },
];

/// The SPH fluid's modules (one variant each: the method's switches are uniform bits), with the
/// scan of [`MODULES`] for its cell starts.
pub const FLUID_MODULES: &[Module] = &[
    Module {
        name: "fluid sort",
        files: &[SPH_COMMON, CELL_ORDER, SPH_SORT],
        bindings: bindings::SPH_SORT,
        entry_points: &["fluid_bin", "fluid_scatter", "fluid_order_cells", "fluid_permute"],
    },
    Module {
        name: "fluid step",
        files: &[SPH_COMMON, SPH_STEP],
        bindings: bindings::SPH_STEP,
        entry_points: &["fluid_wall_state", "fluid_rates", "fluid_body_sums", "fluid_first_half", "fluid_second_half"],
    },
];

/// The polyhedra narrow phase with its test harness (entry point `evaluate`; no overrides).
pub const POLYHEDRA_TEST_MODULE: Module = Module {
    name: "polyhedra test",
    files: &[NARROW_PHASE[0], NARROW_PHASE[1], NARROW_PHASE[2], NARROW_PHASE[3], NARROW_PHASE[4], NARROW_PHASE[5], POLYHEDRA_TEST],
    bindings: bindings::POLYHEDRA_TEST,
    entry_points: &["evaluate"],
};

impl Module {
    /// The complete source with the features `enabled` has on: the prelude, the binding
    /// declarations, then the files.
    pub fn source(&self, enabled: impl Fn(Feature) -> bool) -> String {
        let mut parts = vec![prelude(), bindings::declarations(self.bindings, enabled)];
        parts.extend(self.files.iter().map(|f| f.to_string()));
        parts.join("\n")
    }

    /// The module's text apart from the declarations of common.wgsl: what decides which
    /// switches (override constants) it uses.
    pub fn own_text(&self) -> String {
        self.files.iter().filter(|f| **f != COMMON).copied().collect::<Vec<_>>().join("\n")
    }

    /// Storage buffers the module binds with the features `enabled` has on.
    pub fn storage_buffers(&self, enabled: impl Fn(Feature) -> bool) -> u32 {
        bindings::storage_buffers(self.bindings, enabled)
    }
}

/// The WGSL declaration of every shared constant ([`layout::SHARED`]), prepended to every module.
pub fn prelude() -> String {
    let mut out = String::from("// The constants shared with the host (tumble-shaders' layout.rs), generated.\n");
    for (name, value) in layout::SHARED {
        out.push_str(&format!("const {name}: u32 = {value}u;\n"));
    }
    for (name, value) in layout::SHARED_F32 {
        out.push_str(&format!("const {name}: f32 = {value:?};\n"));
    }
    out
}

#[cfg(test)]
mod tests;
