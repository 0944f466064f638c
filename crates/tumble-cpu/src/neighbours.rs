//! Verlet neighbour list: candidate pairs within reach + skin, rebuilt from the
//! cell grid only when some particle has moved more than half the skin.
//!
//! Each pair is stored once, in canonical order (lower id first), and each
//! particle keeps the list of pairs it belongs to (CSR, in pair order), so the
//! contact pass computes every pair once and each particle gathers its own sum
//! in a fixed order: no atomics, the same result for any thread count.

use crate::forces::SortedEntry;
use glam::DVec3;
use rayon::prelude::*;
use tumble_broad::CellGrid;
use tumble_geom::PeriodicBox;
use tumble_plan::Wall;
use tumble_state::State;

/// Pairs that may touch before the next rebuild, and each particle's share of them.
#[derive(Clone, Debug, Default)]
pub struct NeighbourList {
    pub skin: f64,
    /// (a, b) array indices with id[a] < id[b].
    pub pairs: Vec<[u32; 2]>,
    /// CSR offsets into `entries`, one per particle plus one.
    pub start: Vec<u32>,
    /// Pair index × 2, plus 1 where the particle is the pair's b side.
    pub entries: Vec<u32>,
    /// CSR offsets into `wall_entries`, one per particle plus one.
    pub wall_start: Vec<u32>,
    /// Walls each particle may touch before the next rebuild.
    pub wall_entries: Vec<u16>,
    reference: Vec<DVec3>,
    valid: bool,
    /// Rebuilds so far.
    pub builds: u64,
}

impl NeighbourList {
    pub fn new(skin: f64) -> Self {
        NeighbourList { skin, ..Default::default() }
    }

    /// Positions at the last build, in array order.
    pub fn reference(&self) -> &[DVec3] {
        &self.reference
    }

    /// False once invalidated: the next check rebuilds.
    pub fn is_valid(&self) -> bool {
        self.valid
    }

    /// Forces a rebuild at the next check (particles were reordered or removed).
    pub fn invalidate(&mut self) {
        self.valid = false;
    }

    /// True when the list may miss a pair: some particle moved more than half the skin.
    pub fn needs_rebuild(&self, pos: &[DVec3], domain: &PeriodicBox) -> bool {
        if !self.valid || pos.len() != self.reference.len() {
            return true;
        }
        let limit = 0.25 * self.skin * self.skin;
        let periodic = domain.periodic.iter().any(|&p| p);
        pos.par_iter().zip(&self.reference).any(|(&x, &r)| {
            let d = if periodic { domain.minimum_image(x - r) } else { x - r };
            d.length_squared() > limit
        })
    }

    /// Rebuilds from a grid built over `state.pos` (cells at least reach + skin wide).
    pub fn build(&mut self, grid: &CellGrid, sorted: &[SortedEntry], state: &State, domain: &PeriodicBox, walls: &[Wall]) {
        let order = grid.order();
        let periodic = domain.periodic.iter().any(|&p| p);
        let skin = self.skin;
        let per_particle: Vec<Vec<u32>> = (0..state.len())
            .into_par_iter()
            .map(|i| {
                let (xi, reach_i, id_i, fixed_i) = (state.pos[i], state.reach[i], state.id[i], state.inv_mass[i] == 0.0);
                let mut mine = Vec::new();
                grid.for_each_neighbour_run(grid.cell_of(i), |start, end| {
                    for slot in start..end {
                        let j = order[slot] as usize;
                        if state.id[j] <= id_i || (fixed_i && state.inv_mass[j] == 0.0) {
                            continue;
                        }
                        let e = sorted[slot];
                        let d = if periodic { domain.minimum_image(xi - e.pos) } else { xi - e.pos };
                        let cutoff = reach_i + e.reach + skin;
                        if d.length_squared() <= cutoff * cutoff {
                            mine.push(j as u32);
                        }
                    }
                });
                // Pair order within a particle is fixed by index, whatever the cell visiting order.
                mine.sort_unstable();
                mine
            })
            .collect();
        self.pairs.clear();
        for (i, list) in per_particle.iter().enumerate() {
            self.pairs.extend(list.iter().map(|&j| [i as u32, j]));
        }
        let n = state.len();
        self.start.clear();
        self.start.resize(n + 1, 0);
        for p in &self.pairs {
            self.start[p[0] as usize + 1] += 1;
            self.start[p[1] as usize + 1] += 1;
        }
        for i in 0..n {
            self.start[i + 1] += self.start[i];
        }
        self.entries.resize(2 * self.pairs.len(), 0);
        let mut cursor = self.start[..n].to_vec();
        for (k, p) in self.pairs.iter().enumerate() {
            for (side, &idx) in p.iter().enumerate() {
                let c = &mut cursor[idx as usize];
                self.entries[*c as usize] = (2 * k + side) as u32;
                *c += 1;
            }
        }
        // Walls within reach + skin of each movable particle.
        let near: Vec<Vec<u16>> = (0..n)
            .into_par_iter()
            .map(|i| {
                if state.inv_mass[i] == 0.0 {
                    return Vec::new();
                }
                let (x, r, extra) = (state.pos[i], state.radius[i], state.reach[i] - state.radius[i] + skin);
                (0..walls.len()).filter(|&w| walls[w].shape.sphere_proximity(x, r, extra).is_some()).map(|w| w as u16).collect()
            })
            .collect();
        self.wall_start.clear();
        self.wall_start.push(0);
        self.wall_entries.clear();
        for list in &near {
            self.wall_entries.extend_from_slice(list);
            self.wall_start.push(self.wall_entries.len() as u32);
        }
        self.reference.clear();
        self.reference.extend_from_slice(&state.pos);
        self.valid = true;
        self.builds += 1;
    }
}
