//! The coupling of a scene's particles and its fluid: whether they act on each other (a 3D
//! fluid beside particles), the drag law, and the particles' sub-steps within each fluid step.

use crate::SceneError;
use crate::particles::InitialParticles;
use crate::plan::{CouplingPlan, SphPlan};
use crate::schema::*;
use tumble_geom::PeriodicBox;
use tumble_sph::coupling::{Coupling, DragFluid, DragLaw};
use tumble_sph::{Dimension, FluidSettings};

/// The coupling of a scene with particles and a 3D fluid (its sub-steps are set once Δt is
/// known); a plane fluid leaves the particles alone, with a warning.
pub(super) fn coupling(
    scene: &Scene,
    settings: &FluidSettings,
    domain: &PeriodicBox,
    warnings: &mut Vec<String>,
) -> Result<Option<CouplingPlan>, SceneError> {
    let Some(s) = &scene.sph else { return Ok(None) };
    let dimension = settings.dimension;
    if !scene.has_particles() {
        return Ok(None);
    }
    if dimension == Dimension::Two {
        warnings.push(
            "sph: the particles and this plane (2D) fluid do not act on each other: only a 3D fluid has a volume fraction of spheres; use sph.dimension = 3".into(),
        );
        return Ok(None);
    }
    if scene.fluid.is_some() {
        return Err(SceneError::field(
            "fluid",
            "the particles feel the [sph] fluid through the coupling; a prescribed [fluid] flow beside it would drag them twice: remove one",
        ));
    }
    let drag = match s.coupling.drag {
        SphDragLaw::Gidaspow => DragLaw::Gidaspow,
        SphDragLaw::DiFelice => DragLaw::DiFelice,
    };
    let fluid = DragFluid { density: settings.rho0, viscosity: settings.mu };
    Coupling::new(settings.h, dimension, *domain, drag, fluid).map_err(|e| SceneError::field("sph.coupling", e))?;
    if settings.mu <= 0.0 {
        return Err(SceneError::field("sph.viscosity", "the drag on the particles needs the fluid's viscosity: give it in Pa s (water: 1e-3)"));
    }
    let front = s.coupling.front.map(|d| crate::compile::unit("sph.coupling.front", d)).transpose()?;
    Ok(Some(CouplingPlan { drag, substeps: 1, drag_limit: f64::INFINITY, front }))
}

/// The particles' steps of `dt` within each fluid step of a coupled fluid (1 uncoupled), set
/// in its plan. The fluid's forces are held over its step, which must be short beside the
/// particles' drag relaxation time ρ_p/k: shortest in a dense bed (Ergun at ε = 0.4 without
/// slip: ρ_p d² / (225 μ)); a quarter of it keeps the held drag monotone and stable.
pub(super) fn substeps(sph: &mut SphPlan, kinds: &InitialParticles, densities: &[f64], dt: f64) -> u64 {
    let (limit, mu) = (sph.limits.dt(), sph.settings.mu);
    let Some(c) = sph.coupling.as_mut() else { return 1 };
    let rho_d2 = (0..kinds.len())
        .filter(|&i| !kinds.fixed[i])
        .map(|i| densities[kinds.material[i] as usize] * (2.0 * kinds.radius[i]).powi(2))
        .fold(f64::INFINITY, f64::min);
    c.drag_limit = rho_d2 / (900.0 * mu);
    c.substeps = ((limit.min(c.drag_limit) / dt) * (1.0 + 1e-12)).floor().max(1.0) as u64;
    c.substeps
}
