//! Contacts of polyhedral particles, in one of two models (`PolyhedronContact`):
//!
//! - volume (default): the normal law at δ_V = V / A_ref, V the overlap volume and A_ref the
//!   pair's reference area, along V's gradient (tumble-geom's `VolumeContact`), so the normal
//!   force derives from a potential and elastic contacts conserve energy; the tangential law at
//!   the point on the force's line of action nearest the overlap's centroid, twisting friction
//!   over a disc of the contact's area.
//! - depth: one contact per pair at the depth-weighted point of the manifold with the SAT depth
//!   (a tilted face contact's point moves towards its deeper side, which rights it), twisting
//!   friction over the manifold; the torques are those of the whole force about each centre.
//!
//! Spheres meet polyhedra at the closest point in both (a distance potential already).

use crate::forces::{ContactForce, ContactInputs, PairOut, tangential_part};
use glam::DVec3;
use smallvec::SmallVec;
use tumble_contact::{normal_force, rolling_torque};
use tumble_geom::{
    MeshWall, PatchContact, PolyContact, Polyhedron, Pose, VolumeContact, polyhedron_polyhedron, polyhedron_polyhedron_volume, sphere_polyhedron,
};
use tumble_integrate::world_inverse_inertia_times;
use tumble_plan::{PairParams, PolyhedronContact};
use tumble_plan::{SPHERE, Wall};
use tumble_state::{MESH_KEY, Spring, WALL_KEY};

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

/// The patch radius r̄ of twisting friction for a depth contact: the depth-weighted mean distance of
/// the manifold points from the contact point (what point forces ∝ depth, each at its Coulomb
/// limit, exert against a pure spin). A one-point contact has none.
#[inline(always)]
fn manifold_spread(k: &PolyContact) -> f64 {
    let points = k.manifold();
    if points.len() < 2 {
        return 0.0;
    }
    let total: f64 = points.iter().map(|m| m.depth).sum();
    points.iter().map(|m| m.depth * (m.point - k.point).length()).sum::<f64>() / total
}

/// The patch radius r̄ of twisting friction for a volume contact: the mean distance from the
/// centre of a disc of the contact's area, (2/3)√(|S|/π) (a square patch's is within 2 % of it).
#[inline(always)]
pub(crate) fn area_spread(area: f64) -> f64 {
    (2.0 / 3.0) * (area / std::f64::consts::PI).sqrt()
}

/// The rolling part of a relative spin: its component across the normal `n` (a polyhedron's spin
/// about the normal meets twisting friction instead).
#[inline(always)]
pub(crate) fn rolling_part(spin: DVec3, n: DVec3) -> DVec3 {
    spin - n * spin.dot(n)
}

/// Coulomb friction against the relative spin about the normal `n` on a contact patch of radius
/// `spread`: μ |F_n| r̄, capped so that it never reverses the relative spin within a step.
#[inline(always)]
fn twisting_torque(spread: f64, n: DVec3, friction: f64, normal: f64, spin_rel: DVec3, inv_inertia_sum: f64, dt: f64) -> DVec3 {
    if spread <= 0.0 || friction == 0.0 {
        return DVec3::ZERO;
    }
    rolling_torque(friction, spread, normal, n * spin_rel.dot(n), inv_inertia_sum, dt)
}

/// The overlap-volume force on body A (docs/polyhedra.md): the normal law at the depth
/// δ_V = V / A_ref with the rate −V̇ / A_ref along the volume's gradient (force `push`, torques
/// `turn_a`, `turn_b` per unit w'(V)); the law at each corner's and edge point's depth, times its
/// weight, along its gradient at the point; every part damped as the law at m* / `weight` (the
/// pair's face-on weight, so a face-on impact keeps the restitution); and the tangential law at
/// the contact point with the normal force's magnitude along the normal. Returns the force on A
/// and the torques about A's and B's centres.
#[allow(clippy::too_many_arguments)]
#[inline(always)]
fn volume_force<const HIST: bool>(
    params: &PairParams,
    k: &VolumeContact,
    a_ref: f64,
    weight: f64,
    volume_rate: f64,
    v_at: impl Fn(DVec3) -> DVec3,
    xa: DVec3,
    xb: DVec3,
    m_star: f64,
    r_star: f64,
    dt: f64,
    spring: &mut Spring,
) -> (ContactForce, DVec3, DVec3) {
    let old_spring = if HIST { std::mem::take(spring) } else { Spring::default() };
    let law = |depth: f64, vn: f64, share: f64| {
        let nf = normal_force(&params.normal, depth, vn, m_star / weight, r_star);
        let applied = share * if params.no_attraction { nf.total().max(0.0) } else { nf.total() };
        (applied, share * nf.energy, -(applied - share * nf.elastic) * vn, nf.stiffness)
    };
    let depth = k.volume / a_ref;
    let vn = -volume_rate / a_ref;
    let (applied, mut elastic, mut dissipation, stiffness) = law(depth, vn, 1.0);
    let gain = k.push.length() / a_ref;
    // The contact's normal stiffness (for tangential laws timed by t_col): every part's.
    let mut stiffness = stiffness * gain * gain;
    let per_volume = applied / a_ref;
    let mut normal_force = k.push * per_volume;
    let (mut torque_a, mut torque_b) = (k.turn_a * per_volume, k.turn_b * per_volume);
    for c in &k.points {
        let (applied, energy, loss, point_stiffness) = law(c.depth, c.normal.dot(v_at(c.point)), c.weight);
        stiffness += c.weight * point_stiffness * c.normal.length_squared();
        let f = c.normal * applied;
        normal_force += f;
        torque_a += (c.point - xa).cross(f);
        torque_b -= (c.point - xb).cross(f);
        elastic += energy;
        dissipation += loss;
    }
    let n = k.normal;
    let normal = normal_force.dot(n).max(0.0);
    let v = v_at(k.point);
    let t = tangential_part::<HIST>(params, normal, stiffness, depth, r_star, m_star, n, v - n * v.dot(n), dt, old_spring, spring);
    let out =
        ContactForce { force: normal_force + t.force, tangential: t.force, normal, elastic: elastic + t.energy, dissipation: dissipation + t.loss };
    torque_a += (k.point - xa).cross(t.force);
    torque_b -= (k.point - xb).cross(t.force);
    (out, torque_a, torque_b)
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

/// The overlap-volume contact's reference area of particle `i` (a sphere has none).
#[inline(always)]
fn contact_area(c: &ContactInputs, i: usize) -> f64 {
    match c.state.shape[i] {
        SPHERE => f64::INFINITY,
        k => c.model.shapes[k as usize].contact_area,
    }
}

/// The face-on weight of particle `i` (`tumble_geom::face_on_weight`; a sphere has none).
#[inline(always)]
fn face_on_weight(c: &ContactInputs, i: usize) -> f64 {
    match c.state.shape[i] {
        SPHERE => 1.0,
        k => c.model.shapes[k as usize].face_on_weight,
    }
}

/// Pair (a, b), a with the lower id, at least one a polyhedron; `d` = x_a − x_b (minimum image).
#[inline(always)]
pub(crate) fn polyhedron_pair<const HIST: bool>(c: &ContactInputs, a: usize, b: usize, d: DVec3, spring: &mut Spring) -> PairOut {
    let s = c.state;
    let mut out = PairOut { overlap_ratio: -1.0, ..Default::default() };
    let (xa, xb) = (s.pos[a], s.pos[a] - d);
    let v_at = |p: DVec3| c.vel[a] + c.omega[a].cross(p - xa) - c.vel[b] - c.omega[b].cross(p - xb);
    let params = c.model.pair(s.material[a], s.material[b]);
    let m_star = 1.0 / (s.inv_mass[a] + s.inv_mass[b]);
    let (ra, rb) = (equivalent_radius(c, a), equivalent_radius(c, b));
    let r_star = ra * rb / (ra + rb);
    let (f, torque_a, torque_b, n, spread, depth) = match (body(c, a, xa), body(c, b, xb)) {
        (Some((pa, qa)), Some((pb, qb))) if c.model.polyhedron_contact == PolyhedronContact::Volume => {
            let Some(k) = polyhedron_polyhedron_volume(pa, &qa, pb, &qb) else { return out };
            if HIST {
                *spring = s.history.find(a, s.id[b]);
            }
            let rate = k.volume_rate(c.vel[a] - c.vel[b], c.omega[a], c.omega[b]);
            let a_ref = contact_area(c, a).min(contact_area(c, b));
            let weight = face_on_weight(c, a).max(face_on_weight(c, b));
            let (f, ta, tb) = volume_force::<HIST>(params, &k, a_ref, weight, rate, v_at, xa, xb, m_star, r_star, c.model.dt, spring);
            (f, ta, tb, k.normal, area_spread(k.area), k.depth)
        }
        bodies => {
            let contact = match bodies {
                (Some((pa, qa)), Some((pb, qb))) => polyhedron_polyhedron(pa, &qa, pb, &qb),
                (None, Some((pb, qb))) => sphere_polyhedron(xa, s.radius[a], pb, &qb),
                (Some((pa, qa)), None) => sphere_polyhedron(xb, s.radius[b], pa, &qa).map(PolyContact::flipped),
                (None, None) => unreachable!("sphere pairs take the sphere path"),
            };
            let Some(k) = contact else { return out };
            if HIST {
                *spring = s.history.find(a, s.id[b]);
            }
            let (f, ta, tb) = polyhedron_force::<HIST>(params, &k, v_at, xa, xb, m_star, r_star, c.model.dt, spring);
            (f, ta, tb, k.normal, manifold_spread(&k), k.depth)
        }
    };
    out.force = f.force;
    out.torque_a = torque_a;
    out.torque_b = torque_b;
    let spin = c.omega[a] - c.omega[b];
    let inv_n = inverse_inertia_about(c, a, n) + inverse_inertia_about(c, b, n);
    let twist = twisting_torque(spread, n, params.tangential.friction(), f.normal, spin, inv_n, c.model.dt);
    out.torque_a += twist;
    out.torque_b -= twist;
    out.dissipation -= twist.dot(spin);
    if params.rolling > 0.0 {
        // Rolling only: the spin about the normal is twisting friction's (two caps on one axis could reverse it).
        let relative = rolling_part(c.omega[a] - c.omega[b], n);
        let roll = rolling_torque(params.rolling, r_star, f.normal, relative, s.inv_inertia[a] + s.inv_inertia[b], c.model.dt);
        out.torque_a += roll;
        out.torque_b -= roll;
        out.dissipation -= roll.dot(relative);
    }
    out.elastic = f.elastic;
    out.dissipation += f.dissipation;
    out.overlap_ratio = depth / ra.min(rb);
    out
}

/// One wall contact of a polyhedral particle.
#[derive(Clone, Copy)]
pub(crate) struct PolyhedronWallContact {
    /// Where the contact's tangential force acts (the wall's velocity there enters v_rel).
    pub point: DVec3,
    pub depth: f64,
    pub force: ContactForce,
    /// About the particle's centre, twisting friction included.
    pub torque: DVec3,
    /// The contact normal (from the wall to the particle).
    pub normal: DVec3,
    /// Power the wall's spin Ω delivers through the part of the torque that F at `point` does
    /// not explain: Ω · (τ − (point − x) × F); the caller adds F · v_wall(point).
    pub spin_power: f64,
}

/// A polyhedral particle against one wall: the contact, the force, the torque about the centre
/// (twisting friction included) and the power the wall's spin delivers beyond F · v_wall(point).
/// A mesh wall gives one contact per flat patch: see [`polyhedron_mesh`].
#[inline(always)]
pub(crate) fn polyhedron_wall<const HIST: bool>(c: &ContactInputs, i: usize, w: &Wall, spring: &mut Spring) -> Option<PolyhedronWallContact> {
    let s = c.state;
    let (poly, pose) = body(c, i, s.pos[i])?;
    if c.model.polyhedron_contact == PolyhedronContact::Volume {
        let k = w.shape.polyhedron_volume(poly, &pose)?;
        return Some(volume_wall_contact::<HIST>(c, i, w, &k, spring));
    }
    let xi = s.pos[i];
    let k = w.shape.polyhedron_contact(poly, &pose)?;
    let v_at = |p: DVec3| c.vel[i] + c.omega[i].cross(p - xi) - w.contact_velocity(p, k.normal);
    let params = c.model.pair(s.material[i], w.material);
    let (f, torque, _) = polyhedron_force::<HIST>(params, &k, v_at, xi, xi, s.mass[i], equivalent_radius(c, i), c.model.dt, spring);
    Some(wall_contact(c, i, w, k.point, k.depth, f, torque, k.normal, manifold_spread(&k)))
}

/// Particle `i`'s overlap-volume contact `k` with wall `w`: the force law, then [`wall_contact`].
#[inline(always)]
fn volume_wall_contact<const HIST: bool>(c: &ContactInputs, i: usize, w: &Wall, k: &VolumeContact, spring: &mut Spring) -> PolyhedronWallContact {
    let s = c.state;
    let xi = s.pos[i];
    let v_at = |p: DVec3| c.vel[i] + c.omega[i].cross(p - xi) - w.contact_velocity(p, k.normal);
    let params = c.model.pair(s.material[i], w.material);
    let rate = k.volume_rate(c.vel[i] - w.contact_velocity(xi, k.normal), c.omega[i] - w.angular_velocity(), DVec3::ZERO);
    let (m, r) = (s.mass[i], equivalent_radius(c, i));
    let (f, torque, _) = volume_force::<HIST>(params, k, contact_area(c, i), face_on_weight(c, i), rate, v_at, xi, xi, m, r, c.model.dt, spring);
    wall_contact(c, i, w, k.point, k.depth, f, torque, k.normal, area_spread(k.area))
}

/// A wall contact from its force law's result: twisting friction added, the wall spin's power.
#[allow(clippy::too_many_arguments)]
#[inline(always)]
fn wall_contact(
    c: &ContactInputs,
    i: usize,
    w: &Wall,
    point: DVec3,
    depth: f64,
    mut f: ContactForce,
    torque: DVec3,
    n: DVec3,
    spread: f64,
) -> PolyhedronWallContact {
    let s = c.state;
    let params = c.model.pair(s.material[i], w.material);
    let wall_spin = w.angular_velocity();
    let spin = c.omega[i] - wall_spin;
    let twist = twisting_torque(spread, n, params.tangential.friction(), f.normal, spin, inverse_inertia_about(c, i, n), c.model.dt);
    f.dissipation -= twist.dot(spin);
    let torque = torque + twist;
    let spin_power = wall_spin.dot(torque - (point - s.pos[i]).cross(f.force));
    PolyhedronWallContact { point, depth, force: f, torque, normal: n, spin_power }
}

/// One contact of a polyhedral particle with a mesh wall's flat patch.
pub(crate) struct PatchWallContact {
    pub contact: PolyhedronWallContact,
    /// The patch's spring key: WALL_KEY | MESH_KEY | (the mesh's first key + the patch).
    pub key: u32,
    /// The spring to keep (zero without history or when it ended).
    pub spring: Spring,
    /// The triangles under the overlap with their shares of its volume (they sum to one).
    pub triangles: SmallVec<[(u32, f64); 4]>,
}

thread_local! {
    /// The patch contacts of one particle with one mesh, reused from call to call.
    static PATCHES: std::cell::RefCell<Vec<PatchContact>> = const { std::cell::RefCell::new(Vec::new()) };
}

/// Polyhedral particle `i` against mesh wall `w` (shape `mesh`), in the volume model: one contact
/// per flat patch it overlaps, in patch order, each with its own spring (a patch border is a
/// ridge: a contact crossing it starts afresh on the next patch), appended to `out`.
#[inline(always)]
pub(crate) fn polyhedron_mesh<const HIST: bool>(c: &ContactInputs, i: usize, w: &Wall, mesh: &MeshWall, out: &mut SmallVec<[PatchWallContact; 2]>) {
    let s = c.state;
    let Some((poly, pose)) = body(c, i, s.pos[i]) else { return };
    PATCHES.with_borrow_mut(|patches| {
        mesh.polyhedron_volumes(poly, &pose, patches);
        for p in patches.drain(..) {
            let key = WALL_KEY | MESH_KEY | (mesh.body.first_key + p.patch);
            let mut spring = if HIST { s.history.find(i, key) } else { Spring::default() };
            let contact = volume_wall_contact::<HIST>(c, i, w, &p.contact, &mut spring);
            out.push(PatchWallContact { contact, key, spring, triangles: p.triangles });
        }
    });
}
