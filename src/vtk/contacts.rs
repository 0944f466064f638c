//! The contact network at a snapshot (`output.contacts`): one line per touching pair between
//! the two centres, with the pair's force as cell data (docs/cli.md, "Snapshots").

use super::{Array, Cells, PolyData};
use crate::State;
use tumble_cpu::network::{PairForce, pair_forces};

/// Touching pairs of `state` with their forces, recomputed in f64 by the CPU's pair kernel
/// (for a GPU run: from its f32 state widened to f64).
pub fn contact_network(plan: &tumble_scene::Plan, state: &State, walls: &[tumble_scene::Wall]) -> Vec<PairForce> {
    pair_forces(&plan.model, state, walls)
}

/// The network as PolyData: per pair two points (a's centre, and b's at the minimum image
/// beside it) and one line, with cell data `id_a`, `id_b` (a the lower id), `normal_force`
/// (F · n, n from b to a: positive when the pair pushes apart), `tangential_force` (F − (F·n) n)
/// and `force` (on a; b feels its negation).
pub fn contacts_vtp(plan: &tumble_scene::Plan, state: &State, walls: &[tumble_scene::Wall]) -> PolyData {
    let network = contact_network(plan, state, walls);
    let domain = plan.model.domain;
    let mut points = Vec::with_capacity(6 * network.len());
    for p in &network {
        let a = state.pos[p.a];
        let b = a - domain.minimum_image(a - state.pos[p.b]);
        points.extend(a.to_array());
        points.extend(b.to_array());
    }
    let normal = |p: &PairForce| p.force.dot(p.normal);
    PolyData {
        points,
        lines: Cells::of((0..network.len()).map(|k| [2 * k, 2 * k + 1])),
        cell_data: vec![
            Array::i64("id_a", network.iter().map(|p| state.id[p.a] as i64).collect()),
            Array::i64("id_b", network.iter().map(|p| state.id[p.b] as i64).collect()),
            Array::f64("normal_force", 1, network.iter().map(normal).collect()),
            Array::f64("tangential_force", 3, network.iter().flat_map(|p| (p.force - p.normal * normal(p)).to_array()).collect()),
            Array::f64("force", 3, network.iter().flat_map(|p| p.force.to_array()).collect()),
        ],
        cell_attributes: (Some("normal_force".into()), Some("tangential_force".into())),
        ..Default::default()
    }
}
