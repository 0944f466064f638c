//! Starting a run from another run's particles (`run.start.from`): a charge settled once
//! serves many studies (docs/cli.md, "Starting from another run").
//!
//! The scene declares its particles as usual; the checkpoint's particles then replace them by
//! id, with their positions, velocities, spins, orientations and contact springs. Each one must
//! be the scene's particle of that id (same size to f32 rounding, material and shape; the scene's
//! size and mass are kept); particles the other run
//! lost are left out. Its time, walls and energy books start afresh at t = 0.

use crate::checkpoint;
use std::path::Path;
use tumble_scene::CompiledScene;
use tumble_state::{HistorySlots, MESH_KEY, State, WALL_KEY};

/// The checkpoint `from` names (a checkpoint file, or a run folder's newest) and its particles.
pub fn read_state(from: &Path) -> Result<State, String> {
    let cp = match from.is_dir() {
        true => checkpoint::newest(from)?.1,
        false => checkpoint::read(from)?,
    };
    // A device checkpoint's `state` holds its particles widened to f64, in id order.
    Ok(cp.snapshot.state)
}

/// The scene's particles replaced by `from`'s, and the starting state with `from`'s springs;
/// the warnings say what was not carried over.
pub fn seeded(mut compiled: CompiledScene, from: &State) -> Result<(CompiledScene, State, Vec<String>), String> {
    let declared = compiled.particles.len();
    let mut order: Vec<usize> = (0..from.len()).collect();
    order.sort_by_key(|&k| from.id[k]);
    let p = &mut compiled.particles;
    // New index of each kept particle, by its id in `from`.
    let mut index = vec![u32::MAX; declared];
    for (new, &k) in order.iter().enumerate() {
        let id = from.id[k] as usize;
        if id >= declared {
            return Err(format!(
                "the checkpoint holds particle {id}, but this scene declares {declared}: declare the particles of the run that wrote it"
            ));
        }
        let shape = from.shape.get(k).copied().unwrap_or(tumble_scene::SPHERE);
        // A device's checkpoint holds its radii in f32: equal within its rounding.
        if (from.radius[k] - p.radius[id]).abs() > 1e-6 * p.radius[id] || from.material[k] != p.material[id] || shape != p.shape[id] {
            return Err(format!(
                "particle {id}: radius {} m, material {}, shape {} in the checkpoint, but radius {} m, material {}, shape {} in this scene: declare the particles of the run that wrote it",
                from.radius[k], from.material[k], shape, p.radius[id], p.material[id], p.shape[id]
            ));
        }
        index[id] = new as u32;
    }
    let keep: Vec<usize> = order.iter().map(|&k| from.id[k] as usize).collect();
    macro_rules! pick {
        ($($field:ident),*) => { $(p.$field = keep.iter().map(|&i| p.$field[i]).collect();)* };
    }
    pick!(radius, volume, shape, effect_radius, material, group, fixed, track, orientation, angular_velocity);
    p.position = order.iter().map(|&k| from.pos[k]).collect();
    p.velocity = order.iter().map(|&k| from.vel[k]).collect();
    if !from.omega.is_empty() {
        p.angular_velocity = order.iter().map(|&k| from.omega[k]).collect();
    }
    if !from.orient.is_empty() {
        p.orientation = order.iter().map(|&k| from.orient[k]).collect();
    }
    let mut warnings = Vec::new();
    if keep.len() < declared {
        warnings.push(format!("the checkpoint holds {} of the {declared} particles this scene declares; the others had left its run", keep.len()));
    }
    let mut state = State::from_scene(&compiled);
    let slots = state.history.slots;
    if slots > 0 && from.history.slots > 0 {
        let mesh_triangles = compiled.plan.model.walls.iter().map(|w| match &w.shape {
            tumble_geom::SurfaceShape::Mesh(m) => m.body.mesh.triangles.len(),
            _ => 0,
        });
        let walls = (compiled.plan.model.walls.len(), mesh_triangles.sum());
        state.history = carried_springs(from, &order, &index, slots, walls, &mut warnings)?;
    }
    Ok((compiled, state, warnings))
}

/// `from`'s springs for the kept particles, keyed by the new indices (ids are renumbered).
fn carried_springs(
    from: &State,
    order: &[usize],
    index: &[u32],
    slots: usize,
    (walls, mesh_triangles): (usize, usize),
    warnings: &mut Vec<String>,
) -> Result<HistorySlots, String> {
    let mut out = HistorySlots::new(order.len(), slots, from.history.rolling);
    let mut dropped = 0;
    for (new, &k) in order.iter().enumerate() {
        for (key, spring) in from.history.of(k) {
            let key = match key & WALL_KEY {
                0 => match index.get(key as usize) {
                    Some(&i) if i != u32::MAX => i,
                    _ => continue,
                },
                // A wall's spring keeps its wall index, a mesh's its triangle: the scene must keep
                // the walls and the meshes' triangles in order.
                _ if key & MESH_KEY != 0 && ((key & !(WALL_KEY | MESH_KEY)) as usize) < mesh_triangles => key,
                _ if key & MESH_KEY == 0 && ((key & !WALL_KEY) as usize) < walls => key,
                _ => {
                    dropped += 1;
                    continue;
                }
            };
            let used = out.count[new] as usize;
            if used == slots {
                return Err(format!("particle {} holds more springs than contact.history_slots = {slots}; raise it", from.id[k]));
            }
            out.key[new * slots + used] = key;
            out.set(new * slots + used, spring);
            out.count[new] += 1;
        }
    }
    if dropped > 0 {
        warnings.push(format!("{dropped} springs with walls this scene does not have were dropped"));
    }
    Ok(out)
}
