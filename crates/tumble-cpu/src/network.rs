//! The contact network of a state: every touching pair's force, recomputed in f64 with the
//! step's own pair kernel from the positions, velocities and stored springs alone (so any
//! backend's read-back state can be given; a GPU's is its f32 state widened).

use crate::forces::{ContactInputs, pair_contact};
use glam::DVec3;
use tumble_broad::{CellGrid, grid_pairs};
use tumble_plan::{PhysicsModel, Wall};
use tumble_state::{Spring, State};

/// One touching pair: slots `a` (the lower id) and `b`, and the force on a (b feels its negation).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct PairForce {
    pub a: usize,
    pub b: usize,
    pub force: DVec3,
    /// Unit vector from b's centre to a's (minimum image): the contact normal of two spheres.
    pub normal: DVec3,
}

/// Every pair of `state` whose bodies touch (overlap ≥ 0), with its force: the kernel of the
/// step evaluated once at the state's velocities (not Verlet's predicted ones), springs read
/// from the state and advanced by this evaluation's slip; in id order of (a, b).
pub fn pair_forces(model: &PhysicsModel, state: &State, walls: &[Wall]) -> Vec<PairForce> {
    let n = state.len();
    let domain = model.domain;
    let reach = &state.reach;
    let cell = 2.0 * reach.iter().copied().fold(0.0, f64::max);
    let mut pairs = if n < 2 || cell <= 0.0 {
        Vec::new()
    } else {
        // The particles' bounding box along non-periodic axes, so a sparse domain stays cheap.
        let mut bounds = domain;
        for k in 0..3 {
            if !domain.periodic[k] {
                bounds.min[k] = state.pos.iter().map(|x| x[k]).fold(f64::INFINITY, f64::min);
                bounds.max[k] = state.pos.iter().map(|x| x[k]).fold(f64::NEG_INFINITY, f64::max).max(bounds.min[k] + cell);
            }
        }
        let mut grid = CellGrid::new(&bounds, cell);
        grid.build(&state.pos);
        grid_pairs(&grid, &state.pos, reach, &domain)
    };
    // Canonical order: the lower id first, as the step computes each pair.
    for p in &mut pairs {
        if state.id[p.0 as usize] > state.id[p.1 as usize] {
            *p = (p.1, p.0);
        }
    }
    pairs.sort_unstable_by_key(|&(a, b)| (state.id[a as usize], state.id[b as usize]));
    let zeros = vec![DVec3::ZERO; if state.omega.is_empty() { n } else { 0 }];
    let omega = if state.omega.is_empty() { &zeros } else { &state.omega };
    let inputs = ContactInputs { model, state, vel: &state.vel, omega, walls };
    let hist = model.history && state.history.slots > 0 && state.history.count.len() == n;
    let poly = model.polyhedra && state.shape.len() == n;
    let evaluate = |a: usize, b: usize| {
        let mut spring = Spring::default();
        macro_rules! with {
            ($coh:literal, $hist:literal, $poly:literal) => {
                pair_contact::<true, $coh, true, $hist, $poly>(&inputs, a, b, &mut spring)
            };
        }
        match (model.cohesion, hist, poly) {
            (false, false, false) => with!(false, false, false),
            (false, true, false) => with!(false, true, false),
            (true, false, false) => with!(true, false, false),
            (true, true, false) => with!(true, true, false),
            (_, false, true) => with!(false, false, true),
            (_, true, true) => with!(false, true, true),
        }
    };
    pairs
        .into_iter()
        .filter_map(|(a, b)| {
            let (a, b) = (a as usize, b as usize);
            let out = evaluate(a, b);
            let touching = out.overlap_ratio >= 0.0;
            let d = domain.minimum_image(state.pos[a] - state.pos[b]);
            touching.then(|| PairForce { a, b, force: out.force, normal: d.normalize_or_zero() })
        })
        .collect()
}

/// The force the particles of `state` press on each triangle of each mesh wall (empty for the
/// other walls), recomputed as [`pair_forces`] does: the step's wall kernel at the state's
/// velocities with its stored springs, summed over particles in id order (the same for any
/// thread count and backend). A polyhedron's contact with a flat patch is shared among the
/// patch's triangles under it in proportion to the overlap volume over each.
pub fn mesh_loads(model: &PhysicsModel, state: &State, walls: &[Wall]) -> Vec<Vec<DVec3>> {
    use crate::forces::{contact_force, mesh_contacts};
    use crate::polyhedra::polyhedron_mesh;
    use tumble_geom::SurfaceShape;
    let mut loads: Vec<Vec<DVec3>> = walls
        .iter()
        .map(|w| match &w.shape {
            SurfaceShape::Mesh(m) => vec![DVec3::ZERO; m.body.mesh.triangles.len()],
            _ => Vec::new(),
        })
        .collect();
    if loads.iter().all(Vec::is_empty) {
        return loads;
    }
    let hist = model.history && state.history.slots > 0 && state.history.count.len() == state.len();
    let mut order: Vec<usize> = (0..state.len()).collect();
    order.sort_unstable_by_key(|&i| state.id[i]);
    let mut touching = smallvec::SmallVec::new();
    let mut carried = smallvec::SmallVec::new();
    let mut patches = smallvec::SmallVec::new();
    let zeros = vec![DVec3::ZERO; if state.omega.is_empty() { state.len() } else { 0 }];
    let omegas = if state.omega.is_empty() { &zeros } else { &state.omega };
    let inputs = ContactInputs { model, state, vel: &state.vel, omega: omegas, walls };
    let poly = model.polyhedra && state.shape.len() == state.len();
    for i in order {
        if poly && state.shape[i] != tumble_plan::SPHERE {
            // A polyhedron's patch contact spreads its force over the patch's triangles by volume share.
            for (w, wall) in walls.iter().enumerate() {
                let SurfaceShape::Mesh(mesh) = &wall.shape else { continue };
                patches.clear();
                if hist {
                    polyhedron_mesh::<true>(&inputs, i, wall, mesh, &mut patches);
                } else {
                    polyhedron_mesh::<false>(&inputs, i, wall, mesh, &mut patches);
                }
                for p in &patches {
                    for &(t, share) in &p.triangles {
                        loads[w][t as usize] -= share * p.contact.force.force;
                    }
                }
            }
            continue;
        }
        let (x, r) = (state.pos[i], state.radius[i]);
        let extra = state.reach[i] - r;
        let omega = state.omega.get(i).copied().unwrap_or(DVec3::ZERO);
        for (w, wall) in walls.iter().enumerate() {
            let SurfaceShape::Mesh(mesh) = &wall.shape else { continue };
            touching.clear();
            if hist {
                mesh_contacts::<true>(state, i, mesh, x, r, extra, &mut touching, &mut carried);
            } else {
                mesh_contacts::<false>(state, i, mesh, x, r, extra, &mut touching, &mut carried);
            }
            let params = model.pair(state.material[i], wall.material);
            for (k, key, mut spring) in touching.drain(..) {
                let effect_overlap = k.overlap + extra;
                if k.overlap <= 0.0 && (!model.cohesion || effect_overlap <= 0.0) {
                    continue;
                }
                let v_rel = state.vel[i] - wall.contact_velocity(k.point, k.normal) + omega.cross(k.point - x);
                let (m, dt) = (state.mass[i], model.dt);
                let f = match (model.cohesion, hist) {
                    (false, false) => contact_force::<false, false>(params, k.normal, k.overlap, effect_overlap, v_rel, m, r, dt, &mut spring),
                    (false, true) => contact_force::<false, true>(params, k.normal, k.overlap, effect_overlap, v_rel, m, r, dt, &mut spring),
                    (true, false) => contact_force::<true, false>(params, k.normal, k.overlap, effect_overlap, v_rel, m, r, dt, &mut spring),
                    (true, true) => contact_force::<true, true>(params, k.normal, k.overlap, effect_overlap, v_rel, m, r, dt, &mut spring),
                };
                let t = (key & !(tumble_state::WALL_KEY | tumble_state::MESH_KEY)) - mesh.body.first_key;
                loads[w][t as usize] -= f.force;
            }
        }
    }
    loads
}
