//! The WGSL modules (tumble-shaders) and the plan's feature switches (pipeline-overridable
//! constants).
//!
//! Each module is assembled from the prelude of shared constants, its binding declarations and
//! its files; the switches are WGSL `override` constants set per pipeline from the plan, so
//! code behind a switch that is off is removed when the pipeline is built, and a buffer only
//! a switched-off feature uses is not bound at all. `tests/naga_validation.rs` validates every
//! source and every combination of switches a plan can produce.

use tumble_integrate::Integrator;
use tumble_plan::{Drag, Plan};
pub use tumble_shaders::{Feature, MODULES, Module, POLYHEDRA_TEST_MODULE, prelude};

/// One shader module as a plan's pipelines build it: its name, the text that decides which
/// switches it uses, and the complete source.
#[derive(Clone, Debug)]
pub struct ShaderSource {
    pub name: &'static str,
    /// The module's text apart from common.wgsl's declarations (decides which switches it uses).
    pub body: String,
    pub source: String,
    pub entry_points: &'static [&'static str],
    pub module: Module,
}

impl ShaderSource {
    /// `module` with the buffers `switches` needs bound.
    pub fn new(module: &Module, switches: &Switches) -> Self {
        ShaderSource {
            name: module.name,
            body: module.own_text(),
            source: module.source(|f| switches.feature(f)),
            entry_points: module.entry_points,
            module: *module,
        }
    }

    /// Storage buffers the module binds.
    pub fn storage_buffers(&self, switches: &Switches) -> u32 {
        self.module.storage_buffers(|f| switches.feature(f))
    }
}

/// Every shader module of the backend with every feature's buffers bound.
pub fn sources() -> Vec<ShaderSource> {
    sources_for(&Switches::everything())
}

/// Every shader module of the backend as `switches` builds it.
pub fn sources_for(switches: &Switches) -> Vec<ShaderSource> {
    MODULES.iter().map(|m| ShaderSource::new(m, switches)).collect()
}

/// The polyhedra narrow phase with its test harness (entry point `evaluate`; no overrides).
pub fn polyhedra_test_source() -> String {
    POLYHEDRA_TEST_MODULE.source(|_| true)
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
    /// Polyhedra meet through the overlap-volume model (else the separating-axis depth).
    pub volume: bool,
    /// DRAG_NONE, DRAG_STOKES or DRAG_QUADRATIC (tumble-shaders' codes).
    pub drag: u32,
    pub taylor_green: bool,
    pub integrator: Integrator,
}

/// Integrator codes of the shaders (the INTEGRATOR override).
pub fn integrator_code(i: Integrator) -> u32 {
    match i {
        Integrator::Euler => tumble_shaders::INTEGRATOR_EULER,
        Integrator::SymplecticEuler => tumble_shaders::INTEGRATOR_SYMPLECTIC_EULER,
        Integrator::Verlet => tumble_shaders::INTEGRATOR_VERLET,
        Integrator::ImplicitDrag => tumble_shaders::INTEGRATOR_IMPLICIT_DRAG,
        Integrator::ImplicitDragSymplectic => tumble_shaders::INTEGRATOR_IMPLICIT_DRAG_SYMPLECTIC,
    }
}

impl Switches {
    /// The switches a plan needs: features it does not use are off.
    pub fn from_plan(plan: &Plan) -> Self {
        use tumble_contact::{NormalLaw, TangentialLaw};
        Switches {
            rotation: plan.model.rotation,
            cohesion: plan.model.cohesion,
            periodic: plan.model.domain.periodic.iter().any(|&p| p),
            linear: plan.model.pairs.iter().any(|p| matches!(p.normal, NormalLaw::Linear { .. })),
            hertz: plan.model.pairs.iter().any(|p| matches!(p.normal, NormalLaw::Hertz { .. })),
            tangential: plan.model.pairs.iter().any(|p| p.tangential != TangentialLaw::None),
            walls: !plan.model.walls.is_empty(),
            history: plan.model.history,
            rolling: plan.model.rolling && plan.model.rotation,
            moving: crate::upload::moving_walls(plan),
            prisms: plan.model.walls.iter().any(|w| matches!(w.shape, tumble_geom::SurfaceShape::Prism(_))),
            polyhedra: plan.model.polyhedra,
            volume: plan.model.polyhedra && plan.model.polyhedron_contact == tumble_plan::PolyhedronContact::Volume,
            drag: match plan.model.fluid.map(|f| f.drag) {
                None => tumble_shaders::DRAG_NONE,
                Some(Drag::Stokes { .. }) => tumble_shaders::DRAG_STOKES,
                Some(Drag::Quadratic { .. }) => tumble_shaders::DRAG_QUADRATIC,
            },
            taylor_green: matches!(plan.model.fluid.map(|f| f.flow), Some(tumble_contact::FlowField::TaylorGreen { .. })),
            integrator: plan.model.integrator,
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
            use tumble_shaders::{DRAG_NONE, DRAG_QUADRATIC, DRAG_STOKES};
            let drags = [
                (DRAG_NONE, false, false, false),
                (DRAG_STOKES, false, false, false),
                (DRAG_STOKES, true, false, false),
                (DRAG_QUADRATIC, false, false, false),
                (DRAG_NONE, false, true, false),
                (DRAG_NONE, false, true, true),
            ];
            for (drag, taylor_green, polyhedra, volume) in drags {
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
                        volume,
                        drag,
                        taylor_green,
                        integrator,
                    });
                }
            }
        }
        out
    }

    /// Every feature on (every binding of every module declared).
    pub fn everything() -> Switches {
        Switches {
            rotation: true,
            cohesion: true,
            periodic: true,
            linear: true,
            hertz: true,
            tangential: true,
            walls: true,
            history: true,
            rolling: true,
            moving: true,
            prisms: true,
            polyhedra: true,
            volume: true,
            drag: tumble_shaders::DRAG_STOKES,
            taylor_green: true,
            integrator: Integrator::Verlet,
        }
    }

    /// Whether the buffers of `feature` are bound.
    pub fn feature(&self, feature: Feature) -> bool {
        match feature {
            Feature::Always => true,
            Feature::History => self.history,
            Feature::Walls => self.walls,
            Feature::Moving => self.moving,
            Feature::Polyhedra => self.polyhedra,
            Feature::Periodic => self.periodic,
        }
    }

    /// All override values by name.
    pub fn constants(&self) -> [(&'static str, f64); 16] {
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
            ("VOLUME", f(self.volume)),
            ("DRAG", self.drag as f64),
            ("TAYLOR_GREEN", f(self.taylor_green)),
            ("INTEGRATOR", integrator_code(self.integrator) as f64),
        ]
    }

    /// The override values a module uses (those named in its own kernel text).
    pub fn constants_for(&self, shader: &ShaderSource) -> Vec<(&'static str, f64)> {
        self.constants().into_iter().filter(|(name, _)| uses(&shader.body, name)).collect()
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

    #[test]
    fn every_switch_is_an_override_and_modules_get_only_the_ones_they_use() {
        let all = Switches::all();
        for (name, _) in all[0].constants() {
            assert!(tumble_shaders::COMMON.contains(&format!("override {name}:")), "{name}");
        }
        let broad = sources().into_iter().find(|s| s.name == "broad").unwrap();
        assert!(all[0].constants_for(&broad).is_empty());
        let forces = sources().into_iter().find(|s| s.name == "forces").unwrap();
        assert!(all[0].constants_for(&forces).iter().any(|(n, _)| *n == "COHESION"));
    }

    #[test]
    fn a_feature_that_is_off_binds_nothing() {
        let off = Switches { history: false, moving: false, polyhedra: false, ..Switches::everything() };
        let forces = |s: &Switches| sources_for(s).into_iter().find(|m| m.name == "forces").unwrap();
        assert_eq!(forces(&Switches::everything()).storage_buffers(&Switches::everything()), 18);
        // Static walls bind their loads (wall_load) and nothing else of the moving walls.
        assert_eq!(forces(&off).storage_buffers(&off), 14);
        let source = forces(&off).source;
        assert!(source.contains("var<private> hist_old: array<vec4<u32>, 1>;") && !source.contains("@binding(14)"), "{source}");
        assert!(source.contains("@group(0) @binding(13) var<storage, read_write> stats_out: array<vec2<u32>>;"));
    }
}
