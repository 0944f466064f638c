//! Contacts of polyhedral particles: one contact per pair at the depth-weighted point of the
//! manifold with the SAT depth (a tilted face contact's point moves towards its deeper side,
//! which rights it), the same normal and tangential laws as spheres, and twisting friction
//! over the manifold. Torques are those of the whole
//! force about each centre (a normal force on a polyhedron need not pass through its centre).

use crate::forces::{ContactForce, ContactInputs, PairOut, tangential_part};
use glam::DVec3;
use tumble_contact::{normal_force, rolling_torque};
use tumble_geom::{PolyContact, Polyhedron, Pose, polyhedron_polyhedron, sphere_polyhedron};
use tumble_integrate::world_inverse_inertia_times;
use tumble_scene::PairParams;
use tumble_scene::{SPHERE, Wall};
use tumble_state::Spring;

/// Particle `i`'s polyhedron and pose, when it is one.
#[inline(always)]
fn body<'a>(c: &ContactInputs<'a>, i: usize, position: DVec3) -> Option<(&'a Polyhedron, Pose)> {
    let s = c.state;
    (s.shape[i] != SPHERE).then(|| (&c.model.shapes[s.shape[i] as usize].body, Pose::new(position, s.orient[i])))
}

/// R* and overlap-ratio radius of particle `i`: the radius of the sphere of equal volume.
#[inline(always)]
pub(crate) fn equivalent_radius(c: &ContactInputs, i: usize) -> f64 {
    match c.state.shape[i] {
        SPHERE => c.state.radius[i],
        k => c.model.shapes[k as usize].equivalent_radius,
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

/// The force of a polyhedron contact on body A (at `xa`), with its torque about `xa` and, when B is
/// a body, about `xb` (one contact point: the manifold's depth-weighted point, the SAT depth). `v_at(p)` is the velocity of A relative to B at the point p.
#[allow(clippy::too_many_arguments)]
#[inline(always)]
fn polyhedron_force<const HIST: bool>(
    params: &PairParams,
    k: &PolyContact,
    v_at: impl Fn(DVec3) -> DVec3,
    xa: DVec3,
    xb: DVec3,
    m_star: f64,
    r_star: f64,
    dt: f64,
    spring: &mut Spring,
) -> (ContactForce, DVec3, DVec3) {
    let n = k.normal;
    let old_spring = if HIST { std::mem::take(spring) } else { Spring::default() };
    let mut out = ContactForce { force: DVec3::ZERO, tangential: DVec3::ZERO, normal: 0.0, elastic: 0.0, dissipation: 0.0 };
    // One normal spring per pair at the depth-weighted point with the SAT depth (spec; a spring per
    // manifold point was tried: its energy jumps when an edge–edge contact becomes a face contact).
    let v = v_at(k.point);
    let vn = v.dot(n);
    let nf = normal_force(&params.normal, k.depth, vn, m_star, r_star);
    let applied = if params.no_attraction { nf.total().max(0.0) } else { nf.total() };
    out.force = n * applied;
    out.normal = applied.max(0.0);
    out.elastic = nf.energy;
    out.dissipation = -(applied - nf.elastic) * vn;
    let stiffness = nf.stiffness;
    let t = tangential_part::<HIST>(params, out.normal, stiffness, k.depth, r_star, m_star, n, v - n * vn, dt, old_spring, spring);
    out.force += t.force;
    out.tangential = t.force;
    out.elastic += t.energy;
    out.dissipation += t.loss;
    // The whole force acts at the contact point.
    let (torque_a, torque_b) = ((k.point - xa).cross(out.force), (k.point - xb).cross(-out.force));
    (out, torque_a, torque_b)
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
    let v_at = |p: DVec3| c.vel[a] + c.omega[a].cross(p - xa) - c.vel[b] - c.omega[b].cross(p - xb);
    let params = c.model.pair(s.material[a], s.material[b]);
    let m_star = 1.0 / (s.inv_mass[a] + s.inv_mass[b]);
    let (ra, rb) = (equivalent_radius(c, a), equivalent_radius(c, b));
    let r_star = ra * rb / (ra + rb);
    if HIST {
        *spring = s.history.find(a, s.id[b]);
    }
    let (f, torque_a, torque_b) = polyhedron_force::<HIST>(params, &k, v_at, xa, xb, m_star, r_star, c.model.dt, spring);
    out.force = f.force;
    out.torque_a = torque_a;
    out.torque_b = torque_b;
    let spin = c.omega[a] - c.omega[b];
    let inv_n = inverse_inertia_about(c, a, k.normal) + inverse_inertia_about(c, b, k.normal);
    let twist = twisting_torque(&k, params.tangential.friction(), f.normal, spin, inv_n, c.model.dt);
    out.torque_a += twist;
    out.torque_b -= twist;
    out.dissipation -= twist.dot(spin);
    if params.rolling > 0.0 {
        let relative = c.omega[a] - c.omega[b];
        let roll = rolling_torque(params.rolling, r_star, f.normal, relative, s.inv_inertia[a] + s.inv_inertia[b], c.model.dt);
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
    let xi = s.pos[i];
    let v_at = |p: DVec3| c.vel[i] + c.omega[i].cross(p - xi) - w.velocity_at(p);
    let params = c.model.pair(s.material[i], w.material);
    let (mut f, torque, _) = polyhedron_force::<HIST>(params, &k, v_at, xi, xi, s.mass[i], equivalent_radius(c, i), c.model.dt, spring);
    let wall_spin = w.angular_velocity();
    let spin = c.omega[i] - wall_spin;
    let twist = twisting_torque(&k, params.tangential.friction(), f.normal, spin, inverse_inertia_about(c, i, k.normal), c.model.dt);
    f.dissipation -= twist.dot(spin);
    Some((k, f, torque + twist, twist.dot(wall_spin)))
}
