//! The physics model's sections: domain, gravity, flow planes, integrator, and which
//! mechanics (rotation, cohesion, history, rolling, polyhedra) the kernels must carry.

use super::{finite3, unit};
use crate::particles::InitialParticles;
use crate::plan::{FlowPlane, Fluid, PairParams};
use crate::schema::*;
use crate::{ParticleShape, SceneError};
use glam::DVec3;
use tumble_contact::TangentialLaw;
use tumble_geom::{PeriodicBox, Plane};
use tumble_integrate::Integrator;

/// Largest extent of the domain along an axis, m.
const MAX_DOMAIN_EXTENT: f64 = 1.0e6;

pub(super) fn domain(scene: &Scene) -> Result<PeriodicBox, SceneError> {
    let domain =
        PeriodicBox { min: finite3("domain.min", scene.domain.min)?, max: finite3("domain.max", scene.domain.max)?, periodic: scene.domain.periodic };
    if (0..3).any(|k| domain.max[k] <= domain.min[k]) {
        return Err(SceneError::field("domain", "max must exceed min on every axis (the domain is empty)"));
    }
    // Beyond it lengths lose the digits contacts need, and ±1e308 overflows to ∞ (a periodic
    // image at ∞, a potential energy of NaN).
    let extent = domain.extent();
    if let Some(k) = (0..3).find(|&k| extent[k].is_nan() || extent[k] > MAX_DOMAIN_EXTENT) {
        return Err(SceneError::field(
            "domain",
            format!(
                "max − min along {} is {:e} m; the domain's extent must be a finite length of at most {MAX_DOMAIN_EXTENT:e} m on every axis",
                ["x", "y", "z"][k],
                extent[k]
            ),
        ));
    }
    Ok(domain)
}

pub(super) fn flow_planes(scene: &Scene) -> Result<Vec<FlowPlane>, SceneError> {
    let mut flow_planes: Vec<FlowPlane> = Vec::new();
    for (k, fp) in scene.output.flow_planes.iter().enumerate() {
        let f = |x: &str| format!("output.flow_planes[{k}].{x}");
        if fp.name.trim().is_empty() || flow_planes.iter().any(|p| p.name == fp.name) {
            return Err(SceneError::field(f("name"), format!("each flow plane needs its own non-empty name, got \"{}\"", fp.name)));
        }
        flow_planes.push(FlowPlane { name: fp.name.clone(), plane: Plane::new(finite3(&f("point"), fp.point)?, unit(&f("normal"), fp.normal)?) });
    }
    Ok(flow_planes)
}

pub(super) fn gravity(scene: &Scene) -> Result<DVec3, SceneError> {
    match &scene.gravity {
        Some(g) => finite3("gravity.acceleration", g.acceleration),
        None => Ok(DVec3::ZERO),
    }
}

pub(super) fn integrator(scene: &Scene) -> Integrator {
    Integrator::from_name(match scene.run.integrator {
        IntegratorName::Euler => "euler",
        IntegratorName::SymplecticEuler => "symplectic-euler",
        IntegratorName::Verlet => "verlet",
        IntegratorName::ImplicitDrag => "implicit-drag",
        IntegratorName::ImplicitDragSymplectic => "implicit-drag-symplectic",
    })
    .expect("every integrator name in the schema is known")
}

/// Which mechanics the kernels carry, with the reason rotation is on or off.
pub(super) struct Mechanics {
    pub rotation: bool,
    pub rotation_reason: String,
    pub polyhedra: bool,
    pub cohesion: bool,
    pub history: bool,
    pub rolling: bool,
    /// Some pair has a tangential force.
    pub any_friction: bool,
    /// Some particle is not fixed.
    pub movable: bool,
}

/// The mechanics the pair table, the shapes and the fluid call for; refuses combinations
/// the kernels do not model.
pub(super) fn mechanics(
    scene: &Scene,
    pairs: &[PairParams],
    shapes: &[ParticleShape],
    particles: &InitialParticles,
    fluid: Option<&Fluid>,
) -> Result<Mechanics, SceneError> {
    let movable = particles.fixed.iter().any(|f| !f);
    let any_friction = pairs.iter().any(|p| p.tangential != TangentialLaw::None);
    let history = pairs.iter().any(|p| p.tangential.has_history());
    let rolling = pairs.iter().any(|p| p.rolling > 0.0);
    let polyhedra = !shapes.is_empty();
    let (rotation, rotation_reason) = match scene.run.rotation {
        RotationMode::Off if polyhedra => {
            return Err(SceneError::field(
                "run.rotation",
                "polyhedra turn under their contact forces (the normal force does not pass through the centre); remove run.rotation = \"off\"",
            ));
        }
        _ if polyhedra => (true, "polyhedra: normal forces act off the centre of mass, so every body carries an orientation".to_string()),
        RotationMode::On => (true, "run.rotation = \"on\"".to_string()),
        RotationMode::Off if rolling => {
            return Err(SceneError::field(
                "run.rotation",
                "rolling_friction is a torque and needs rotation; remove run.rotation = \"off\" or the rolling friction",
            ));
        }
        RotationMode::Off => (false, "run.rotation = \"off\" (tangential forces act on the centre only)".to_string()),
        RotationMode::Auto if rolling && movable => (true, "rolling resistance exerts torques".to_string()),
        RotationMode::Auto if any_friction && movable => (true, "tangential friction exerts torques".to_string()),
        RotationMode::Auto => (false, "no tangential force, so no torque: no rotation state is carried".to_string()),
    };
    let cohesion = pairs.iter().any(|p| p.cohesion > 0.0);
    if polyhedra && cohesion {
        return Err(SceneError::field("contact.cohesion", "cohesion acts between spheres only; this scene has polyhedral particles"));
    }
    if polyhedra && pairs.iter().any(|p| p.rolling > 0.0 && p.rolling_model == tumble_contact::RollingModel::Epsd2) {
        return Err(SceneError::field(
            "contact.rolling_model",
            "\"epsd2\" is modelled for spheres only; this scene has polyhedral particles (use \"constant\")",
        ));
    }
    if polyhedra && fluid.is_some() {
        return Err(SceneError::field("fluid", "fluid drag is modelled for spheres only; this scene has polyhedral particles"));
    }
    Ok(Mechanics { rotation, rotation_reason, polyhedra, cohesion, history, rolling, any_friction, movable })
}
