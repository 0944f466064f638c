//! Backend tuning: neighbour-search cell and skin, re-sort interval, history slots and the
//! memory estimate per particle.

use crate::SceneError;
use crate::particles::InitialParticles;
use crate::plan::PhysicsModel;
use crate::schema::Scene;
use tumble_geom::PeriodicBox;
use tumble_integrate::Integrator;

/// Default contacts with history per particle: a sphere among equal ones touches at most 12.
const DEFAULT_HISTORY_SLOTS: usize = 16;

/// Default neighbour-list skin, as a fraction of the largest interaction diameter.
const DEFAULT_SKIN: f64 = 0.1;

/// Default steps between re-sorts into cell order.
const DEFAULT_RESORT_INTERVAL: u32 = 25;

/// The most spring slots a particle may have: a sphere touches at most 12 of its own size, and
/// even a large one in a bed of spheres ten times smaller far fewer than this.
const MAX_HISTORY_SLOTS: u32 = 1024;

/// Contacts with history each particle can hold.
pub(super) fn history_slots(scene: &Scene) -> Result<usize, SceneError> {
    match scene.contact().history_slots {
        Some(0) => Err(SceneError::field("contact.history_slots", "must be at least 1 (contacts with history per particle)")),
        Some(k) if k > MAX_HISTORY_SLOTS => Err(SceneError::field(
            "contact.history_slots",
            format!("must be at most {MAX_HISTORY_SLOTS} (contacts with history per particle), got {k}"),
        )),
        Some(k) => Ok(k as usize),
        None => Ok(DEFAULT_HISTORY_SLOTS),
    }
}

/// The search cell (largest interaction diameter) and the Verlet skin; a periodic axis must hold two of them.
pub(super) fn search(scene: &Scene, particles: &InitialParticles, cohesion: bool, domain: &PeriodicBox) -> Result<(f64, f64), SceneError> {
    let max_reach = (0..particles.len())
        .map(|i| if cohesion { particles.effect_radius[i].max(particles.radius[i]) } else { particles.radius[i] })
        .fold(0.0, f64::max);
    // A scene of fluid alone has no particle to reach: a few cells span the domain, empty.
    let cell_size = if max_reach > 0.0 { 2.0 * max_reach } else { domain.extent().min_element() / 4.0 };
    let skin_fraction = scene.run.skin.unwrap_or(DEFAULT_SKIN);
    if !(skin_fraction > 0.0 && skin_fraction <= 1.0) {
        return Err(SceneError::field("run.skin", format!("must lie in (0, 1] (a fraction of the interaction diameter), got {skin_fraction}")));
    }
    let skin = skin_fraction * cell_size;
    for k in 0..3 {
        if domain.periodic[k] && domain.extent()[k] < 2.0 * (cell_size + skin) {
            return Err(SceneError::field(
                "domain.periodic",
                format!(
                    "axis {k} is periodic but only {} m long; it must be at least two interaction diameters plus skin ({} m)",
                    domain.extent()[k],
                    2.0 * (cell_size + skin)
                ),
            ));
        }
    }
    Ok((cell_size, skin))
}

pub(super) fn resort_interval(scene: &Scene) -> Result<u32, SceneError> {
    match scene.run.resort_interval {
        Some(0) => Err(SceneError::field("run.resort_interval", "must be at least 1 step")),
        Some(r) => Ok(r),
        None => Ok(DEFAULT_RESORT_INTERVAL),
    }
}

/// Default chunk: an eighth of what the sources may insert, at least 1,024 slots (growing
/// copies every per-particle array on the device, so a few large chunks beat many small ones).
const MIN_CAPACITY_CHUNK: u64 = 1024;

/// Slots per growth of the device arrays: `run.capacity_chunk`, or the default, never more than
/// the sources may insert (0 without sources).
pub(super) fn capacity_chunk(scene: &Scene, inserted_at_most: u64, sources: bool) -> Result<u64, SceneError> {
    match scene.run.capacity_chunk {
        Some(0) => Err(SceneError::field("run.capacity_chunk", "must be at least 1 particle slot")),
        Some(c) if c > 1 << 30 => Err(SceneError::field("run.capacity_chunk", "must be at most 2^30 particle slots")),
        _ if !sources => Ok(0),
        Some(c) => Ok(c),
        None => Ok(inserted_at_most.div_ceil(8).max(MIN_CAPACITY_CHUNK).min(inserted_at_most).max(1)),
    }
}

/// Memory per particle on the CPU backend, for the model's state.
pub(super) fn bytes_per_particle(model: &PhysicsModel, history_slots: usize) -> usize {
    let rotation = model.rotation;
    8 * (3 * 3 + 6) // position, velocity, acceleration; radius, effect, inverse mass, mass, dissipation, elastic
        + 8 * 4 + 8 * 3 // sorted position and reach for the broad phase, reference position of the neighbour list
        + 6 * (4 * 2 + 4 * 2) + 6 * if rotation { 72 } else { 48 } // ~6 listed pairs: indices, incidence, pair results
        + 2 + 2 + 4 + 4 + 4 + 4 + 8 // material, group, id, flags, order, cell, overlap
        + if rotation { 8 * 7 } else { 0 } // angular velocity and acceleration, inverse inertia
        + if model.integrator == Integrator::Verlet { 24 * if rotation { 2 } else { 1 } } else { 0 }
        + if model.fluid.is_some() { 8 } else { 0 }
        + if model.history { 2 * (2 + history_slots * (4 + 64)) } else { 0 } // two generations of spring slots: count, neighbour id, ξ, the rolling torque and their energies
        + if model.polyhedra { 2 + 32 + 24 } else { 0 } // shape index, orientation, principal inverse inertia
}
