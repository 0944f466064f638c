//! Contacts of polyhedral particles: one contact per pair (normal, depth and the depth-weighted
//! point of the manifold), the same force laws as spheres, and the torque of the whole force
//! about each centre (a normal force on a polyhedron need not pass through its centre).

use crate::forces::{ContactForce, ContactInputs, PairOut, contact_force};
use crate::history::Spring;
use glam::DVec3;
use tumble_contact::rolling_torque;
use tumble_geom::{PolyContact, Polyhedron, Pose, polyhedron_polyhedron, sphere_polyhedron};
use tumble_integrate::world_inverse_inertia_times;
use tumble_scene::{SPHERE, Wall};

/// Particle `i`'s polyhedron and pose, when it is one.
#[inline(always)]
fn body<'a>(c: &ContactInputs<'a>, i: usize, position: DVec3) -> Option<(&'a Polyhedron, Pose)> {
    let s = c.state;
    (s.shape[i] != SPHERE).then(|| (&c.plan.shapes[s.shape[i] as usize].body, Pose::new(position, s.orient[i])))
}

/// R* and overlap-ratio radius of particle `i`: the radius of the sphere of equal volume.
#[inline(always)]
pub(crate) fn equivalent_radius(c: &ContactInputs, i: usize) -> f64 {
    match c.state.shape[i] {
        SPHERE => c.state.radius[i],
        k => c.plan.shapes[k as usize].equivalent_radius,
    }
}

/// n · I_w⁻¹ n of particle `i`: its inverse moment of inertia about the axis `n`.
#[inline(always)]
fn inverse_inertia_about(c: &ContactInputs, i: usize, n: DVec3) -> f64 {
    let s = c.state;
    if s.shape[i] == SPHERE { s.inv_inertia[i] } else { world_inverse_inertia_times(s.orient[i], s.inv_inertia_body[i], n).dot(n) }
}

/// Coulomb friction against the relative spin about the normal, on a contact patch: μ |F_n| r̄ with
/// r̄ the depth-weighted mean distance of the manifold points from the contact point (what
/// point forces ∝ depth, each at its Coulomb limit, exert against a pure spin). A one-point
/// contact has none. Capped so that it never reverses the relative spin within a step.
#[inline(always)]
fn twisting_torque(k: &PolyContact, friction: f64, normal: f64, spin_rel: DVec3, inv_inertia_sum: f64, dt: f64) -> DVec3 {
    let points = k.manifold();
    if points.len() < 2 || friction == 0.0 {
        return DVec3::ZERO;
    }
    let total: f64 = points.iter().map(|m| m.depth).sum();
    let spread = points.iter().map(|m| m.depth * (m.point - k.point).length()).sum::<f64>() / total;
    rolling_torque(friction, spread, normal, k.normal * spin_rel.dot(k.normal), inv_inertia_sum, dt)
}

/// Pair (a, b), a with the lower id, at least one a polyhedron; `d` = x_a − x_b (minimum image).
#[inline(always)]
pub(crate) fn polyhedron_pair<const HIST: bool>(c: &ContactInputs, a: usize, b: usize, d: DVec3, spring: &mut Spring) -> PairOut {
    let s = c.state;
    let mut out = PairOut { overlap_ratio: -1.0, ..Default::default() };
    let (xa, xb) = (s.pos[a], s.pos[a] - d);
    let contact = match (body(c, a, xa), body(c, b, xb)) {
        (Some((pa, qa)), Some((pb, qb))) => polyhedron_polyhedron(pa, &qa, pb, &qb),
        (None, Some((pb, qb))) => sphere_polyhedron(xa, s.radius[a], pb, &qb),
        (Some((pa, qa)), None) => sphere_polyhedron(xb, s.radius[b], pa, &qa).map(PolyContact::flipped),
        (None, None) => unreachable!("sphere pairs take the sphere path"),
    };
    let Some(k) = contact else { return out };
    let (arm_a, arm_b) = (k.point - xa, k.point - xb);
    let v_rel = c.vel[a] + c.omega[a].cross(arm_a) - c.vel[b] - c.omega[b].cross(arm_b);
    let params = c.plan.pair(s.material[a], s.material[b]);
    let m_star = 1.0 / (s.inv_mass[a] + s.inv_mass[b]);
    let (ra, rb) = (equivalent_radius(c, a), equivalent_radius(c, b));
    let r_star = ra * rb / (ra + rb);
    if HIST {
        *spring = s.history.find(a, s.id[b]);
    }
    let f = contact_force::<false, HIST>(params, k.normal, k.depth, 0.0, v_rel, m_star, r_star, c.plan.dt, spring);
    out.force = f.force;
    out.torque_a = arm_a.cross(f.force);
    out.torque_b = arm_b.cross(-f.force);
    let spin = c.omega[a] - c.omega[b];
    let inv_n = inverse_inertia_about(c, a, k.normal) + inverse_inertia_about(c, b, k.normal);
    let twist = twisting_torque(&k, params.tangential.friction(), f.normal, spin, inv_n, c.plan.dt);
    out.torque_a += twist;
    out.torque_b -= twist;
    out.dissipation -= twist.dot(spin);
    if params.rolling > 0.0 {
        let relative = c.omega[a] - c.omega[b];
        let roll = rolling_torque(params.rolling, r_star, f.normal, relative, s.inv_inertia[a] + s.inv_inertia[b], c.plan.dt);
        out.torque_a += roll;
        out.torque_b -= roll;
        out.dissipation -= roll.dot(relative);
    }
    out.elastic = f.elastic;
    out.dissipation += f.dissipation;
    out.overlap_ratio = k.depth / ra.min(rb);
    out
}

/// A polyhedral particle against one wall: the contact, the force, the torque about the centre
/// (twisting friction included) and the power that torque's twisting part draws from the wall's spin.
#[inline(always)]
pub(crate) fn polyhedron_wall<const HIST: bool>(
    c: &ContactInputs,
    i: usize,
    w: &Wall,
    spring: &mut Spring,
) -> Option<(PolyContact, ContactForce, DVec3, f64)> {
    let s = c.state;
    let (poly, pose) = body(c, i, s.pos[i])?;
    let k = w.shape.polyhedron_contact(poly, &pose)?;
    let arm = k.point - s.pos[i];
    let v_rel = c.vel[i] + c.omega[i].cross(arm) - w.velocity_at(k.point);
    let params = c.plan.pair(s.material[i], w.material);
    let mut f = contact_force::<false, HIST>(params, k.normal, k.depth, 0.0, v_rel, s.mass[i], equivalent_radius(c, i), c.plan.dt, spring);
    let wall_spin = w.angular_velocity();
    let spin = c.omega[i] - wall_spin;
    let twist = twisting_torque(&k, params.tangential.friction(), f.normal, spin, inverse_inertia_about(c, i, k.normal), c.plan.dt);
    f.dissipation -= twist.dot(spin);
    let torque = arm.cross(f.force) + twist;
    Some((k, f, torque, twist.dot(wall_spin)))
}
