//! The contact pass, gather style: each particle sums only its own force and
//! torque. A pair is computed in canonical order (lower id first) and negated
//! for the other side, so pair forces are exactly equal and opposite.

use crate::neighbours::NeighbourList;
use crate::polyhedra::{PatchWallContact, equivalent_radius, polyhedron_mesh, polyhedron_pair, polyhedron_wall};
use glam::DVec3;
use smallvec::SmallVec;
use tumble_contact::{
    RollingModel, TangentialLaw, ViscousParameter, cohesion_energy, cohesion_force, collision_time, epsd2_torque, history_force, normal_force,
    rolling_stiffness, rolling_torque, tangential_force,
};
use tumble_geom::{MeshWall, NO_CONTACT, SurfaceContact, SurfaceShape, sphere_sphere};
use tumble_plan::{PairParams, PhysicsModel, SPHERE, Wall};
use tumble_state::{ContactSum, MESH_KEY, RollingHalf, Spring, State, TangentialHalf, WALL_KEY};

/// A particle's copy in cell order, for the candidate scan.
#[derive(Clone, Copy, Debug, Default)]
pub struct SortedEntry {
    pub pos: DVec3,
    pub reach: f64,
}

/// Read-only inputs of the contact pass.
pub struct ContactInputs<'a> {
    /// The physics the pair and wall kernels read (laws, Δt, domain, shapes).
    pub model: &'a PhysicsModel,
    pub state: &'a State,
    /// Velocities the forces see (Verlet: the predicted v_{n+1}).
    pub vel: &'a [DVec3],
    pub omega: &'a [DVec3],
    /// The walls at the time of this pass (moving ones in their current pose).
    pub walls: &'a [Wall],
}

/// One pair's contribution, computed once in canonical order (a has the lower id).
#[derive(Clone, Copy, Debug, Default)]
pub struct PairOut {
    /// Force on a; b receives the negation.
    pub force: DVec3,
    pub torque_a: DVec3,
    pub torque_b: DVec3,
    pub elastic: f64,
    pub dissipation: f64,
    /// δ / min(r_a, r_b), or negative when the bodies do not touch.
    pub overlap_ratio: f64,
}

/// What one wall contact does to the wall: the power it takes from it (F_on_particle · v_wall
/// and the couples' Ω_wall · τ), the force on it and the torque on it about the origin.
#[derive(Clone, Copy, Debug, Default)]
pub struct WallLoad {
    pub power: f64,
    pub force: DVec3,
    pub torque: DVec3,
}

/// Contacts of one particle with one mesh wall that book wear: per contact (triangle, worn
/// volume this step); a fifth and later contact (rare: a sphere in a mesh's corner touches three)
/// books on the fourth's triangle.
pub type Worn = [(u32, f64); WORN_SLOTS];
pub const WORN_SLOTS: usize = 4;

/// Force of one contact on body a, from the contact normal n (b to a), the
/// overlaps and the relative velocity of a against b at the contact point.
#[derive(Clone, Copy)]
pub(crate) struct ContactForce {
    pub force: DVec3,
    pub tangential: DVec3,
    /// max(F_n, 0): the friction capacity's normal force, and the rolling torque's.
    pub normal: f64,
    pub elastic: f64,
    pub dissipation: f64,
}

/// `spring` holds the contact's tangential spring on entry (zero for a new contact)
/// and the spring to keep on return (zero when the contact has ended). The dissipation
/// books the work done on the spring less what it stores now over what it stored at the
/// last step, so the energy balance closes even as a Mindlin k_t changes with δ.
#[allow(clippy::too_many_arguments)]
#[inline(always)]
pub(crate) fn contact_force<const COH: bool, const HIST: bool>(
    p: &PairParams,
    n: DVec3,
    overlap: f64,
    effect_overlap: f64,
    v_rel: DVec3,
    m_star: f64,
    r_star: f64,
    dt: f64,
    spring: &mut Spring,
) -> ContactForce {
    let mut out = ContactForce { force: DVec3::ZERO, tangential: DVec3::ZERO, normal: 0.0, elastic: 0.0, dissipation: 0.0 };
    let old_spring = if HIST { std::mem::take(spring) } else { Spring::default() };
    if COH && p.cohesion > 0.0 && effect_overlap > 0.0 {
        out.force = n * cohesion_force(p.cohesion, effect_overlap);
        out.elastic = cohesion_energy(p.cohesion, effect_overlap);
    }
    if overlap >= 0.0 {
        let vn = v_rel.dot(n);
        let nf = normal_force(&p.normal, overlap, vn, m_star, r_star);
        let applied = if p.no_attraction { nf.total().max(0.0) } else { nf.total() };
        out.normal = applied.max(0.0);
        let t = tangential_part::<HIST>(p, out.normal, nf.stiffness, overlap, r_star, m_star, n, v_rel - n * vn, dt, old_spring, spring);
        out.force += n * applied + t.force;
        out.tangential = t.force;
        out.elastic += nf.energy + t.energy;
        out.dissipation = -(applied - nf.elastic) * vn + t.loss;
    }
    out
}

/// The tangential force of one contact: its force, the energy its spring stores and the power it dissipates.
pub(crate) struct TangentialPart {
    pub force: DVec3,
    pub energy: f64,
    pub loss: f64,
}

/// The tangential law of `p` for a contact pressed by `normal` (|F_n|) with tangent slip velocity `vt`;
/// `stiffness` is the normal law's tangent stiffness (for laws whose time scale is t_col).
#[allow(clippy::too_many_arguments)]
#[inline(always)]
pub(crate) fn tangential_part<const HIST: bool>(
    p: &PairParams,
    normal: f64,
    stiffness: f64,
    overlap: f64,
    r_star: f64,
    m_star: f64,
    n: DVec3,
    vt: DVec3,
    dt: f64,
    old_spring: Spring,
    spring: &mut Spring,
) -> TangentialPart {
    match p.tangential {
        TangentialLaw::History { friction, spring: law } if HIST => {
            let h = history_force(&law, friction, normal, overlap, r_star, m_star, old_spring.xi, n, vt, dt);
            // The rolling spring passes through; the rolling pass advances it.
            *spring = Spring { xi: h.spring, energy: h.energy, ..old_spring };
            let loss = if dt > 0.0 { -h.force.dot(vt) - (h.energy - old_spring.energy) / dt } else { 0.0 };
            TangentialPart { force: h.force, energy: h.energy, loss }
        }
        law => {
            let t_col = match law {
                TangentialLaw::ViscousCoulomb { viscous: ViscousParameter::Stiffness(_), .. } => {
                    collision_time(stiffness, m_star, p.normal.restitution())
                }
                _ => 0.0,
            };
            let ft = tangential_force(&law, normal, vt, m_star, dt, t_col);
            TangentialPart { force: ft, energy: 0.0, loss: -ft.dot(vt) }
        }
    }
}

/// The contact of pair (a, b), a with the lower id; zero when out of range.
/// With history, `spring` receives the pair's new spring as a holds it.
#[inline(always)]
pub fn pair_contact<const ROT: bool, const COH: bool, const PERIODIC: bool, const HIST: bool, const POLY: bool>(
    c: &ContactInputs,
    a: usize,
    b: usize,
    spring: &mut Spring,
) -> PairOut {
    let s = c.state;
    let model = c.model;
    let mut out = PairOut { overlap_ratio: -1.0, ..Default::default() };
    let d = if PERIODIC { model.domain.minimum_image(s.pos[a] - s.pos[b]) } else { s.pos[a] - s.pos[b] };
    let cutoff = s.reach[a] + s.reach[b];
    // Touching (δ = 0) counts: a contact that starts at zero overlap feels its damping at once.
    if d.length_squared() > cutoff * cutoff {
        return out;
    }
    if POLY && (s.shape[a] != SPHERE || s.shape[b] != SPHERE) {
        return polyhedron_pair::<HIST>(c, a, b, d, spring);
    }
    let Some(g) = sphere_sphere(d, s.radius[a], s.radius[b]) else { return out };
    let effect_overlap = if COH { cutoff - g.distance } else { 0.0 };
    if g.overlap < 0.0 && (!COH || effect_overlap <= 0.0) {
        return out;
    }
    let params = model.pair(s.material[a], s.material[b]);
    let mut v_rel = c.vel[a] - c.vel[b];
    if ROT {
        v_rel += c.omega[a].cross(g.arm_i) - c.omega[b].cross(g.arm_j);
    }
    let m_star = 1.0 / (s.inv_mass[a] + s.inv_mass[b]);
    let r_star = s.radius[a] * s.radius[b] / (s.radius[a] + s.radius[b]);
    if HIST {
        *spring = s.history.find(a, s.id[b]);
    }
    let f = contact_force::<COH, HIST>(params, g.normal, g.overlap, effect_overlap, v_rel, m_star, r_star, model.dt, spring);
    out.force = f.force;
    if ROT {
        out.torque_a = g.arm_i.cross(f.tangential);
        out.torque_b = g.arm_j.cross(-f.tangential);
        if params.rolling > 0.0 {
            let relative = c.omega[a] - c.omega[b];
            let roll = if HIST && params.rolling_model == RollingModel::Epsd2 {
                let r = epsd2_couple(params, g.overlap, r_star, f.normal, g.normal, relative, model.dt, spring);
                out.elastic += r.energy;
                out.dissipation += r.dissipation;
                r.torque
            } else {
                let roll = rolling_torque(params.rolling, r_star, f.normal, relative, s.inv_inertia[a] + s.inv_inertia[b], model.dt);
                // The couple opposes the relative rolling: all its work is dissipated.
                out.dissipation -= roll.dot(relative);
                roll
            };
            out.torque_a += roll;
            out.torque_b -= roll;
        }
    }
    out.elastic += f.elastic;
    out.dissipation += f.dissipation;
    if g.overlap >= 0.0 {
        out.overlap_ratio = g.overlap / s.radius[a].min(s.radius[b]);
    }
    out
}

/// Where a particle writes the springs it keeps this step (empty without history; `roll`
/// empty unless the plan keeps rolling springs).
pub struct SpringSlots<'a> {
    pub key: &'a mut [u32],
    pub spring: &'a mut [TangentialHalf],
    pub roll: &'a mut [RollingHalf],
}

impl SpringSlots<'_> {
    /// Stores one spring in slot `*used`, if there is room; counts it either way.
    #[inline(always)]
    fn keep(&mut self, used: &mut u32, key: u32, spring: Spring) {
        if let Some(k) = self.key.get_mut(*used as usize) {
            *k = key;
            self.spring[*used as usize] = spring.tangential();
            if let Some(r) = self.roll.get_mut(*used as usize) {
                *r = spring.rolling();
            }
        }
        *used += 1;
    }
}

/// The listed pairs' new springs as their lower ids hold them: tangential halves, and rolling
/// halves when the plan keeps rolling springs (else empty).
#[derive(Clone, Copy)]
pub struct PairSprings<'a> {
    pub spring: &'a [TangentialHalf],
    pub roll: &'a [RollingHalf],
}

impl PairSprings<'_> {
    #[inline(always)]
    fn get(&self, k: usize) -> Spring {
        Spring::from_parts(self.spring[k], self.roll.get(k).copied().unwrap_or_default())
    }
}

/// Particle `i`'s sum: its pairs, gathered in list order, then the walls.
/// With history it also writes the springs it keeps into `slots` (a sees +ξ, b sees −ξ).
/// `wall_loads` is empty, or one slot per wall candidate of `i` (its share of
/// `list.wall_entries`), which receives that contact's [`WallLoad`]; `worn` likewise (or empty
/// when no wall wears) receives the wear its mesh contacts book (Archard: K/H · F_n · slip · Δt).
#[allow(clippy::too_many_arguments)]
#[inline(always)]
pub fn gather<const ROT: bool, const COH: bool, const HIST: bool, const POLY: bool>(
    c: &ContactInputs,
    list: &NeighbourList,
    pairs: &[PairOut],
    springs: PairSprings,
    i: usize,
    mut slots: SpringSlots,
    wall_loads: &mut [WallLoad],
    worn: &mut [Worn],
) -> ContactSum {
    let mut sum = ContactSum::default();
    for &e in &list.entries[list.start[i] as usize..list.start[i + 1] as usize] {
        let k = (e >> 1) as usize;
        let p = &pairs[k];
        if HIST && springs.get(k).is_loaded() {
            let [a, b] = list.pairs[k];
            let sp = springs.get(k);
            let (other, kept) = if e & 1 == 0 { (b, sp) } else { (a, sp.mirrored()) };
            slots.keep(&mut sum.springs, c.state.id[other as usize], kept);
        }
        if e & 1 == 0 {
            sum.force += p.force;
            if ROT {
                sum.torque += p.torque_a;
            }
            // Energies and contacts are booked on the canonical side only.
            sum.elastic += p.elastic;
            sum.dissipation += p.dissipation;
            sum.contacts += (p.overlap_ratio > 0.0) as u32;
        } else {
            sum.force -= p.force;
            if ROT {
                sum.torque += p.torque_b;
            }
        }
        sum.max_overlap_ratio = sum.max_overlap_ratio.max(p.overlap_ratio);
    }
    let s = c.state;
    let model = c.model;
    let near = &list.wall_entries[list.wall_start[i] as usize..list.wall_start[i + 1] as usize];
    if near.is_empty() {
        if HIST {
            book_ended_springs(c, i, &slots, &[], &mut sum);
        }
        return sum;
    }
    // Walls: infinite mass, R* = r_i; a moving wall's velocity at the contact point enters v_rel.
    let xi = s.pos[i];
    let r = s.radius[i];
    let extra = s.reach[i] - r;
    let poly = POLY && s.shape[i] != SPHERE;
    // Mesh springs carried over to a contact under a new triangle's key: not ended.
    let mut carried: SmallVec<[u32; 4]> = SmallVec::new();
    wall_loads.fill(WallLoad::default());
    worn.fill([(0, 0.0); WORN_SLOTS]);
    for (slot, &wall) in near.iter().enumerate() {
        let wall = wall as u32;
        let w = &c.walls[wall as usize];
        let params = model.pair(s.material[i], w.material);
        // Each contact of the particle with this wall: (contact, key, spring); a mesh may give several.
        let mut touching: SmallVec<[(SurfaceContact, u32, Spring); 2]> = SmallVec::new();
        // A polyhedron's contacts with a mesh's flat patches, computed whole (one per `touching` entry).
        let mut patches: SmallVec<[PatchWallContact; 2]> = SmallVec::new();
        let placeholder = SurfaceContact { normal: DVec3::ZERO, overlap: 0.0, point: xi };
        if poly {
            if let SurfaceShape::Mesh(mesh) = &w.shape {
                polyhedron_mesh::<HIST>(c, i, w, mesh, &mut patches);
                touching.extend(patches.iter().map(|p| (placeholder, p.key, p.spring)));
            } else {
                touching.push((placeholder, WALL_KEY | wall, Spring::default()));
            }
        } else if let SurfaceShape::Mesh(mesh) = &w.shape {
            mesh_contacts::<HIST>(s, i, mesh, xi, r, extra, &mut touching, &mut carried);
        } else if let Some(k) = w.shape.sphere_proximity(xi, r, extra) {
            let key = WALL_KEY | wall;
            touching.push((k, key, if HIST { s.history.find(i, key) } else { Spring::default() }));
        }
        let mut load = WallLoad::default();
        let mut wears = 0;
        for (n, (k, key, mut spring)) in touching.into_iter().enumerate() {
            // (wall velocity at the contact, body overlap, force, torque about the centre, R* for the
            // rolling couple); a polyhedron's spin about the normal meets twisting friction, not rolling.
            let mut power = 0.0;
            let mut twist_axis = None;
            let (v_wall, overlap, f, torque, r_roll) = if poly {
                let k = if let Some(p) = patches.get(n) {
                    p.contact
                } else {
                    if HIST {
                        spring = s.history.find(i, key);
                    }
                    let Some(k) = polyhedron_wall::<HIST>(c, i, w, &mut spring) else { continue };
                    k
                };
                power = k.spin_power;
                twist_axis = Some(k.normal);
                let v_wall = w.contact_velocity(k.point, k.normal);
                if let Some(out) = worn.get_mut(slot)
                    && w.wear > 0.0
                    && let Some(p) = patches.get(n)
                {
                    let v_rel = c.vel[i] + c.omega[i].cross(k.point - xi) - v_wall;
                    book_shared_wear(out, &mut wears, &p.triangles, w.wear * k.force.normal * tangential_speed(v_rel, k.normal) * model.dt);
                }
                (v_wall, k.depth, k.force, k.torque, equivalent_radius(c, i))
            } else {
                let effect_overlap = k.overlap + extra;
                if k.overlap <= 0.0 && (!COH || effect_overlap <= 0.0) {
                    continue;
                }
                let arm = k.point - xi;
                let v_wall = w.contact_velocity(k.point, k.normal);
                let mut v_rel = c.vel[i] - v_wall;
                if ROT {
                    v_rel += c.omega[i].cross(arm);
                }
                let f = contact_force::<COH, HIST>(params, k.normal, k.overlap, effect_overlap, v_rel, s.mass[i], r, model.dt, &mut spring);
                if let Some(out) = worn.get_mut(slot)
                    && w.wear > 0.0
                {
                    book_wear(out, &mut wears, w, key, k.normal, v_rel, f.normal, model.dt);
                }
                let torque = arm.cross(f.tangential);
                (v_wall, k.overlap, f, torque, r)
            };
            sum.force += f.force;
            power += f.force.dot(v_wall);
            let mut couple = torque;
            if ROT {
                sum.torque += torque;
                if params.rolling > 0.0 {
                    // Rolling relative to the wall; the couple on the particle does work Ω_wall · τ.
                    let spin = w.angular_velocity();
                    let relative = c.omega[i] - spin;
                    let relative = twist_axis.map_or(relative, |n| crate::polyhedra::rolling_part(relative, n));
                    let roll = if HIST && params.rolling_model == RollingModel::Epsd2 && !poly {
                        let e = epsd2_couple(params, overlap, r_roll, f.normal, k.normal, relative, model.dt, &mut spring);
                        sum.elastic += e.energy;
                        sum.dissipation += e.dissipation;
                        e.torque
                    } else {
                        let roll = rolling_torque(params.rolling, r_roll, f.normal, relative, s.inv_inertia[i], model.dt);
                        sum.dissipation -= roll.dot(relative);
                        roll
                    };
                    sum.torque += roll;
                    couple += roll;
                    power += roll.dot(spin);
                }
            }
            if HIST && spring.is_loaded() {
                slots.keep(&mut sum.springs, key, spring);
            }
            // The wall takes the reaction: −F, and −(x × F + τ) about the origin, so the contact's
            // momentum and angular momentum balance exactly.
            load.power += power;
            load.force -= f.force;
            load.torque -= xi.cross(f.force) + couple;
            sum.elastic += f.elastic;
            sum.dissipation += f.dissipation;
            if overlap > 0.0 {
                sum.contacts += 1;
                sum.max_overlap_ratio = sum.max_overlap_ratio.max(overlap / r_roll);
            }
        }
        if let Some(l) = wall_loads.get_mut(slot) {
            *l = load;
        }
    }
    if HIST {
        book_ended_springs(c, i, &slots, &carried, &mut sum);
    }
    sum
}

/// Books Archard's wear of one mesh contact (spring key `key`, normal `n`, relative velocity
/// `v_rel` at the contact, normal force `normal`) into its particle's slot `out`: K/H · F_n ·
/// slip speed · Δt on the contact's triangle; `wears` counts the contacts booked so far.
#[allow(clippy::too_many_arguments)]
#[cold]
#[inline(never)]
fn book_wear(out: &mut Worn, wears: &mut usize, w: &Wall, key: u32, n: DVec3, v_rel: DVec3, normal: f64, dt: f64) {
    let slip = tangential_speed(v_rel, n);
    let slot = (*wears).min(WORN_SLOTS - 1);
    let triangle = if *wears < WORN_SLOTS { (key & !(WALL_KEY | MESH_KEY)) - mesh_first_key(w) } else { out[slot].0 };
    out[slot] = (triangle, out[slot].1 + w.wear * normal * slip * dt);
    *wears += 1;
}

/// Books the worn volume `amount` of one polyhedron–patch contact on the patch's triangles,
/// each its share; past the slots, the rest lumps on the last slot's triangle.
#[cold]
#[inline(never)]
fn book_shared_wear(out: &mut Worn, wears: &mut usize, triangles: &[(u32, f64)], amount: f64) {
    for &(t, share) in triangles {
        let slot = (*wears).min(WORN_SLOTS - 1);
        let triangle = if *wears < WORN_SLOTS { t } else { out[slot].0 };
        out[slot] = (triangle, out[slot].1 + amount * share);
        *wears += 1;
    }
}

/// |v − n (v · n)|: the speed of `v` across the unit normal `n`.
#[inline(always)]
fn tangential_speed(v: DVec3, n: DVec3) -> f64 {
    (v - n * v.dot(n)).length()
}

/// The first spring key of a mesh wall's triangles (0 for other walls).
fn mesh_first_key(w: &Wall) -> u32 {
    if let SurfaceShape::Mesh(m) = &w.shape { m.body.first_key } else { 0 }
}

/// A sphere's contacts with a mesh wall, each with its spring. A spring follows its contact
/// from triangle to triangle. Each contact first takes the particle's spring on its own
/// triangle; then a contact without one takes a spring on another triangle of its smooth group
/// (it slid across a flat edge); then one on a triangle that shares a corner with its own and
/// is still within reach without a contact of its own (it rolled over a ridge or corner). Each
/// old spring goes to one contact at most; those carried to a new key are listed in `carried`
/// (they have not ended).
#[allow(clippy::too_many_arguments)]
#[inline(never)]
pub(crate) fn mesh_contacts<const HIST: bool>(
    s: &State,
    i: usize,
    mesh: &MeshWall,
    x: DVec3,
    r: f64,
    extra: f64,
    out: &mut SmallVec<[(SurfaceContact, u32, Spring); 2]>,
    carried: &mut SmallVec<[u32; 4]>,
) {
    let mut groups = SmallVec::new();
    let contacts = mesh.sphere_contacts(x, r, extra, &mut groups);
    let first = mesh.body.first_key;
    let key_of = |t: u32| WALL_KEY | MESH_KEY | (first + t);
    let count = mesh.body.mesh.triangles.len() as u32;
    // This mesh's springs of the particle: (triangle, spring, taken).
    let mut old: SmallVec<[(u32, Spring, bool); 4]> = SmallVec::new();
    if HIST {
        for (key, spring) in s.history.of(i) {
            let global = key & !(WALL_KEY | MESH_KEY);
            if key & (WALL_KEY | MESH_KEY) == WALL_KEY | MESH_KEY && (first..first + count).contains(&global) {
                old.push((global - first, spring, false));
            }
        }
    }
    let mut springs: SmallVec<[Spring; 4]> = contacts.iter().map(|_| Spring::default()).collect();
    if !old.is_empty() {
        let group_of = |t: u32| groups.iter().find(|g| g.0 == t).map(|g| g.1);
        let rules: [&dyn Fn(u32, usize) -> bool; 3] = [&|t, n| t == contacts[n].triangle, &|t, n| group_of(t) == Some(n as u8), &|t, n| {
            group_of(t) == Some(NO_CONTACT) && mesh.share_a_corner(t, contacts[n].triangle)
        }];
        let mut served: SmallVec<[bool; 4]> = contacts.iter().map(|_| false).collect();
        for rule in rules {
            for n in 0..contacts.len() {
                if served[n] {
                    continue;
                }
                if let Some(o) = old.iter_mut().find(|o| !o.2 && rule(o.0, n)) {
                    o.2 = true;
                    served[n] = true;
                    springs[n] = o.1;
                    if o.0 != contacts[n].triangle {
                        carried.push(key_of(o.0));
                    }
                }
            }
        }
    }
    for (c, spring) in contacts.iter().zip(springs) {
        out.push((c.contact, key_of(c.triangle), spring));
    }
}

/// The EPSD2 rolling spring of a contact with normal `n` (b to a): advances `spring.roll` (zero
/// when the contact has ended: its stored energy is then booked by [`book_ended_springs`]).
#[allow(clippy::too_many_arguments)]
#[inline(always)]
fn epsd2_couple(
    p: &PairParams,
    overlap: f64,
    r_star: f64,
    normal: f64,
    n: DVec3,
    relative: DVec3,
    dt: f64,
    spring: &mut Spring,
) -> tumble_contact::RollingSpring {
    if overlap < 0.0 {
        return tumble_contact::RollingSpring { torque: DVec3::ZERO, energy: 0.0, dissipation: 0.0, rolling: false };
    }
    let k_r = rolling_stiffness(&p.normal, overlap, p.rolling, r_star);
    let r = epsd2_torque(k_r, p.rolling * r_star * normal, spring.roll, spring.roll_energy, n, relative, dt);
    spring.roll = r.torque;
    spring.roll_energy = r.energy;
    r
}

/// A contact that ended takes its spring's stored energy with it: book it as dissipated,
/// once per pair (on the lower id's side; walls on the particle's).
#[inline(always)]
fn book_ended_springs(c: &ContactInputs, i: usize, slots: &SpringSlots, carried: &[u32], sum: &mut ContactSum) {
    let kept = &slots.key[..(sum.springs as usize).min(slots.key.len())];
    let me = c.state.id[i];
    for (key, spring) in c.state.history.of(i) {
        if (key & WALL_KEY != 0 || me < key) && !kept.contains(&key) && !carried.contains(&key) {
            sum.dissipation += spring.stored_energy() / c.model.dt;
        }
    }
}
