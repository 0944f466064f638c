//! The fluid's probes: where and what each measures at every output row (probe_<name>.csv).

use super::finite3;
use super::sph::{file_name, in_plane};
use crate::SceneError;
use crate::plan::{SphProbe, SphProbeKind};
use crate::schema::*;
use glam::DVec3;
use tumble_geom::PeriodicBox;
use tumble_sph::Dimension;

/// The probes of `[sph]`, checked: unique names, inside the domain, one kind each.
pub(super) fn probes(s: &SphSection, dimension: Dimension, domain: &PeriodicBox) -> Result<Vec<SphProbe>, SceneError> {
    let mut out: Vec<SphProbe> = Vec::new();
    for (k, p) in s.probes.iter().enumerate() {
        let f = |x: &str| format!("sph.probes[{k}].{x}");
        let taken: Vec<&str> = out.iter().map(|q| q.name.as_str()).collect();
        file_name(f("name"), &p.name, &taken, "the probe's", "probe_<name>.csv")?;
        let inside = |field: &str, x: DVec3| {
            let out = (0..3).any(|a| !(dimension == Dimension::Two && a == 1) && (x[a] < domain.min[a] || x[a] > domain.max[a]));
            if out { Err(SceneError::field(f(field), format!("{x} lies outside the domain"))) } else { Ok(()) }
        };
        let flatten = |x: DVec3| in_plane(dimension, x);
        let given = [p.pressure.is_some(), p.velocity.is_some(), p.gauge.is_some(), p.front.is_some()];
        let kind = match (given.iter().filter(|&&g| g).count(), p) {
            (1, SphProbeSection { pressure: Some(x), .. }) => {
                let x = flatten(finite3(&f("pressure"), *x)?);
                inside("pressure", x)?;
                SphProbeKind::Pressure(x)
            }
            (1, SphProbeSection { velocity: Some(x), .. }) => {
                let x = flatten(finite3(&f("velocity"), *x)?);
                inside("velocity", x)?;
                SphProbeKind::Velocity(x)
            }
            (1, SphProbeSection { gauge: Some(g), .. }) => {
                let from = flatten(finite3(&f("gauge.from"), g.from)?);
                inside("gauge.from", from)?;
                if !(g.to_z.is_finite() && g.to_z > from.z && g.to_z <= domain.max.z) {
                    return Err(SceneError::field(
                        f("gauge.to_z"),
                        format!("must be above gauge.from's z = {} and at most the domain's top {}, got {}", from.z, domain.max.z, g.to_z),
                    ));
                }
                SphProbeKind::Gauge { from, top: g.to_z }
            }
            (1, SphProbeSection { front: Some(d), .. }) => {
                let d = flatten(finite3(&f("front"), *d)?);
                if d.length() == 0.0 {
                    return Err(SceneError::field(f("front"), "the direction must not be zero (in 2D, have an x or z part)"));
                }
                SphProbeKind::Front(d.normalize())
            }
            _ => return Err(SceneError::field(format!("sph.probes[{k}]"), "give exactly one of pressure, velocity, gauge or front")),
        };
        out.push(SphProbe { name: p.name.clone(), kind });
    }
    Ok(out)
}
