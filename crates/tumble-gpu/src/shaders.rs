//! The WGSL sources and the plan's feature switches (pipeline-overridable constants).
//!
//! Each kernel file is assembled with the shared declarations it needs; the
//! switches are WGSL `override` constants set per pipeline from the plan, so
//! code behind a switch that is off is removed when the pipeline is built.
//! `tests/naga_validation.rs` validates every source and every combination of
//! switches a plan can produce.

use tumble_integrate::Integrator;
use tumble_scene::{Drag, Plan};

/// Step parameters, switches and index helpers shared by the particle kernels.
pub const COMMON: &str = include_str!("../shaders/common.wgsl");
/// Sphere–wall proximity and the minimum image.
pub const GEOMETRY: &str = include_str!("../shaders/geometry.wgsl");
/// Cell index and counting sort.
pub const BROAD: &str = include_str!("../shaders/broad.wgsl");
/// Reduce-then-scan prefix sum.
pub const SCAN: &str = include_str!("../shaders/scan.wgsl");
/// Re-sort of per-particle arrays by cell.
pub const REORDER: &str = include_str!("../shaders/reorder.wgsl");
/// The gather-style contact pass.
pub const FORCES: &str = include_str!("../shaders/forces.wgsl");
/// Contact history slots, the tangential spring and rolling resistance (used by the contact pass).
pub const HISTORY: &str = include_str!("../shaders/history.wgsl");
/// Moving world geometry: wall velocities, wall power and lifter prisms (used by the contact pass).
pub const WALLS_MOVING: &str = include_str!("../shaders/walls_moving.wgsl");
/// Quaternions and the rigid-body rotation updates.
pub const QUATERNION: &str = include_str!("../shaders/quaternion.wgsl");
/// Convex polyhedra: the shape table and the narrow phase (needs QUATERNION).
pub const POLYHEDRA: &str = include_str!("../shaders/polyhedra.wgsl");
/// The test harness of the polyhedra narrow phase ([`crate::shapes::evaluate`]).
pub const POLYHEDRA_TEST: &str = include_str!("../shaders/polyhedra_test.wgsl");
/// Body forces and the integrators.
pub const INTEGRATE: &str = include_str!("../shaders/integrate.wgsl");

/// One shader module: its name, its own text, and the complete source.
#[derive(Clone, Debug)]
pub struct ShaderSource {
    pub name: &'static str,
    /// The kernel file alone (decides which switches the module uses).
    pub body: &'static str,
    pub source: String,
    pub entry_points: &'static [&'static str],
}

/// Every shader module of the backend.
pub fn sources() -> Vec<ShaderSource> {
    let with_common = |name, body: &'static str, prefix: &[&str], entry_points| ShaderSource {
        name,
        body,
        source: prefix.iter().copied().chain([body]).collect::<Vec<_>>().join("\n"),
        entry_points,
    };
    vec![
        with_common("broad", BROAD, &[COMMON], &["bin", "scatter", "order_cells"]),
        with_common("scan", SCAN, &[], &["reduce", "scan_block"]),
        with_common("reorder", REORDER, &[COMMON], &["permute"]),
        with_common("forces", FORCES, &[COMMON, GEOMETRY, HISTORY, WALLS_MOVING, QUATERNION, POLYHEDRA], &["forces"]),
        with_common("integrate", INTEGRATE, &[COMMON, QUATERNION, POLYHEDRA], &["initial", "kick_drift", "finish"]),
    ]
}

/// The polyhedra narrow phase with its test harness (entry point `evaluate`; no overrides).
pub fn polyhedra_test_source() -> String {
    [QUATERNION, POLYHEDRA, POLYHEDRA_TEST].join("\n")
}

/// The plan's feature switches, one per WGSL `override` in common.wgsl.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub struct Switches {
    pub rotation: bool,
    pub cohesion: bool,
    pub periodic: bool,
    pub linear: bool,
    pub hertz: bool,
    pub tangential: bool,
    pub walls: bool,
    /// Tangential springs with history (the slots are bound and used).
    pub history: bool,
    /// Rolling resistance.
    pub rolling: bool,
    /// Moving walls: wall velocities in the contact laws, poses uploaded every step, wall power.
    pub moving: bool,
    /// Lifter bars (sphere–prism contacts; polyhedra meet their hulls).
    pub prisms: bool,
    /// Convex polyhedral particles (orientations, the shape table); always with rotation,
    /// never with cohesion or drag (the plan refuses those with polyhedra).
    pub polyhedra: bool,
    /// 0: no fluid, 1: Stokes, 2: quadratic.
    pub drag: u32,
    pub taylor_green: bool,
    pub integrator: Integrator,
}

/// Integrator codes of the shaders (common.wgsl).
pub fn integrator_code(i: Integrator) -> u32 {
    match i {
        Integrator::Euler => 0,
        Integrator::SymplecticEuler => 1,
        Integrator::Verlet => 2,
        Integrator::ImplicitDrag => 3,
        Integrator::ImplicitDragSymplectic => 4,
    }
}

impl Switches {
    /// The switches a plan needs: features it does not use are off.
    pub fn from_plan(plan: &Plan) -> Self {
        use tumble_contact::{NormalLaw, TangentialLaw};
        Switches {
            rotation: plan.rotation,
            cohesion: plan.cohesion,
            periodic: plan.domain.periodic.iter().any(|&p| p),
            linear: plan.pairs.iter().any(|p| matches!(p.normal, NormalLaw::Linear { .. })),
            hertz: plan.pairs.iter().any(|p| matches!(p.normal, NormalLaw::Hertz { .. })),
            tangential: plan.pairs.iter().any(|p| p.tangential != TangentialLaw::None),
            walls: !plan.walls.is_empty(),
            history: plan.history,
            rolling: plan.rolling && plan.rotation,
            moving: crate::upload::moving_walls(plan),
            prisms: plan.walls.iter().any(|w| matches!(w.shape, tumble_geom::SurfaceShape::Prism(_))),
            polyhedra: plan.polyhedra,
            drag: match plan.fluid.map(|f| f.drag) {
                None => 0,
                Some(Drag::Stokes { .. }) => 1,
                Some(Drag::Quadratic { .. }) => 2,
            },
            taylor_green: matches!(plan.fluid.map(|f| f.flow), Some(tumble_contact::FlowField::TaylorGreen { .. })),
            integrator: plan.integrator,
        }
    }

    /// Every combination a plan can produce (Taylor–Green only with Stokes drag).
    pub fn all() -> Vec<Switches> {
        let mut out = Vec::new();
        for bits in 0..2048u32 {
            let b = |k: u32| bits & (1 << k) != 0;
            // History is a tangential law; rolling resistance needs rotation; moving walls and prisms are walls.
            if (b(7) && !b(5)) || (b(8) && !b(0)) || ((b(9) || b(10)) && !b(6)) {
                continue;
            }
            for (drag, taylor_green, polyhedra) in [(0, false, false), (1, false, false), (1, true, false), (2, false, false), (0, false, true)] {
                // Polyhedra rotate and neither cohere nor feel drag.
                if polyhedra && (!b(0) || b(1)) {
                    continue;
                }
                for integrator in Integrator::ALL {
                    out.push(Switches {
                        rotation: b(0),
                        cohesion: b(1),
                        periodic: b(2),
                        linear: b(3),
                        hertz: b(4),
                        tangential: b(5),
                        walls: b(6),
                        history: b(7),
                        rolling: b(8),
                        moving: b(9),
                        prisms: b(10),
                        polyhedra,
                        drag,
                        taylor_green,
                        integrator,
                    });
                }
            }
        }
        out
    }

    /// All override values by name.
    pub fn constants(&self) -> [(&'static str, f64); 15] {
        let f = |b: bool| if b { 1.0 } else { 0.0 };
        [
            ("ROTATION", f(self.rotation)),
            ("COHESION", f(self.cohesion)),
            ("PERIODIC", f(self.periodic)),
            ("LINEAR", f(self.linear)),
            ("HERTZ", f(self.hertz)),
            ("TANGENTIAL", f(self.tangential)),
            ("WALLS", f(self.walls)),
            ("HISTORY", f(self.history)),
            ("ROLLING", f(self.rolling)),
            ("MOVING", f(self.moving)),
            ("PRISMS", f(self.prisms)),
            ("POLYHEDRA", f(self.polyhedra)),
            ("DRAG", self.drag as f64),
            ("TAYLOR_GREEN", f(self.taylor_green)),
            ("INTEGRATOR", integrator_code(self.integrator) as f64),
        ]
    }

    /// The override values a module uses (those named in its own kernel text).
    pub fn constants_for(&self, shader: &ShaderSource) -> Vec<(&'static str, f64)> {
        self.constants().into_iter().filter(|(name, _)| uses(shader.body, name)).collect()
    }
}

/// True when `text` names `ident` as a whole word.
fn uses(text: &str, ident: &str) -> bool {
    text.match_indices(ident).any(|(k, _)| {
        let before = text[..k].chars().next_back();
        let after = text[k + ident.len()..].chars().next();
        let word = |c: Option<char>| c.is_some_and(|c| c.is_alphanumeric() || c == '_');
        !word(before) && !word(after)
    })
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::upload::{SCAN_BLOCK, SCAN_THREADS, WORKGROUP};

    #[test]
    fn host_and_shader_constants_agree() {
        assert!(COMMON.contains(&format!("const WORKGROUP: u32 = {WORKGROUP}u;")));
        assert!(SCAN.contains(&format!("const BLOCK: u32 = {SCAN_BLOCK}u;")));
        assert!(SCAN.contains(&format!("const SCAN_THREADS: u32 = {SCAN_THREADS}u;")));
        assert!(COMMON.contains(&format!("const FLAG_DEAD: u32 = {}u;", crate::upload::FLAG_DEAD)));
        assert!(COMMON.contains(&format!("const FLAG_FIXED: u32 = {}u;", crate::upload::FLAG_FIXED)));
        assert!(POLYHEDRA.contains(&format!("const SHAPE_HEADER_WORDS: u32 = {}u;", crate::shapes::HEADER_WORDS)));
    }

    #[test]
    fn every_switch_is_an_override_and_modules_get_only_the_ones_they_use() {
        let all = Switches::all();
        for (name, _) in all[0].constants() {
            assert!(COMMON.contains(&format!("override {name}:")), "{name}");
        }
        let broad = sources().into_iter().find(|s| s.name == "broad").unwrap();
        assert!(all[0].constants_for(&broad).is_empty());
        let forces = sources().into_iter().find(|s| s.name == "forces").unwrap();
        assert!(all[0].constants_for(&forces).iter().any(|(n, _)| *n == "COHESION"));
    }
}
