//! The [sph] section's inflow and outflow buffers: their boxes, the flow through them, the
//! inflows' particles, and the fluid cleared from the inflows.

use super::finite3;
use super::sph::plane_box;
use crate::SceneError;
use crate::schema::*;
use glam::DVec3;
use tumble_geom::{PeriodicBox, Timing};
use tumble_sph::{Aabb, BufferBox, Dimension, FluidParticles, FluidSettings, Inflow, InflowProfile, Outflow, ParticleKind, add_inflow};

/// The buffers into `settings`, the inflows' particles added and the fluid inside them cleared.
pub(super) fn add_buffers(
    s: &SphSection,
    settings: &mut FluidSettings,
    domain: &PeriodicBox,
    particles: &mut FluidParticles,
) -> Result<(), SceneError> {
    for (k, b) in s.inflows.iter().enumerate() {
        let f = |x: &str| format!("sph.inflows[{k}].{x}");
        let velocity = finite3(&f("velocity"), b.velocity)?;
        let (axis, sign) = along_axis(&f("velocity"), velocity, settings.dimension)?;
        let buffer = buffer_box(&f("box"), &b.box_, axis, sign, settings, domain)?;
        if !(b.ramp.is_finite() && b.ramp >= 0.0) {
            return Err(SceneError::field(f("ramp"), format!("must be a duration in seconds, 0 or more, got {}", b.ramp)));
        }
        let profile = match b.profile {
            SphInflowProfile::Uniform => InflowProfile::Uniform,
            SphInflowProfile::Parabolic => InflowProfile::Parabolic,
        };
        let timing = Timing { start: 0.0, ramp: b.ramp, stop: f64::INFINITY };
        settings.inflows.push(Inflow { buffer, speed: velocity[axis].abs(), profile, timing });
    }
    for (k, b) in s.outflows.iter().enumerate() {
        let f = |x: &str| format!("sph.outflows[{k}].{x}");
        let direction = finite3(&f("direction"), b.direction)?;
        let (axis, sign) = along_axis(&f("direction"), direction, settings.dimension)?;
        if !b.pressure.is_finite() {
            return Err(SceneError::field(f("pressure"), format!("must be a finite pressure in Pa, got {}", b.pressure)));
        }
        let buffer = buffer_box(&f("box"), &b.box_, axis, sign, settings, domain)?;
        settings.outflows.push(Outflow { buffer, pressure: b.pressure });
    }
    let plane = settings.dimension == Dimension::Two;
    let inflows = settings.inflows.clone();
    particles.retain(|kind, x| {
        kind == ParticleKind::Wall
            || !inflows.iter().any(|i| i.buffer.past_entry(x) >= 0.0 && i.buffer.past_exit(x) < 0.0 && i.buffer.across(x, plane))
    });
    for k in 0..settings.inflows.len() {
        add_inflow(particles, settings, k);
    }
    Ok(())
}

/// The axis a vector lies along and its sign; in 2D x or z.
fn along_axis(field: &str, v: DVec3, dimension: Dimension) -> Result<(usize, f64), SceneError> {
    let axis = (0..3).find(|&a| v[a] != 0.0 && (0..3).all(|b| b == a || v[b] == 0.0));
    match axis {
        Some(a) if !(dimension == Dimension::Two && a == 1) => Ok((a, v[a].signum())),
        _ => Err(SceneError::field(field, format!("must be a non-zero vector along x, y or z (in 2D, x or z), got {v}"))),
    }
}

/// A buffer's box, checked: inside the domain, positive on every axis, at least 2h deep along
/// the flow (a full kernel of buffer particles behind the face).
fn buffer_box(
    field: &str,
    b: &SphBoxSection,
    axis: usize,
    sign: f64,
    settings: &FluidSettings,
    domain: &PeriodicBox,
) -> Result<BufferBox, SceneError> {
    let plane = settings.dimension == Dimension::Two;
    let Aabb { min, max } = plane_box(field, b, settings.dimension)?;
    let slack = 1e-9 * (domain.max - domain.min).max_element();
    if (0..3).any(|a| !(plane && a == 1) && (min[a] < domain.min[a] - slack || max[a] > domain.max[a] + slack)) {
        return Err(SceneError::field(field, "must lie inside the domain"));
    }
    let reach = 2.0 * settings.h;
    if max[axis] - min[axis] < reach * (1.0 - 1e-9) {
        return Err(SceneError::field(
            field,
            format!("must be at least 2h = {reach} m deep along the flow (a full kernel of buffer particles), got {} m", max[axis] - min[axis]),
        ));
    }
    Ok(BufferBox { region: Aabb::new(min, max), axis, sign })
}
