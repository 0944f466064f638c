//! The CPU backend: the reference implementation of the step in f64.
//!
//! Each step: broad phase (cell grid by counting sort, arrays re-sorted by cell
//! every few steps), the contact pass gather style in parallel, body forces,
//! then the integrator. Every parallel loop writes only its own particle and
//! every sum over particles runs serially in array order, so results are
//! bit-identical for any thread count.
//!
//! ```
//! let scene = tumble_scene::parse_scene(r#"
//! name = "fall"
//! [run]
//! duration = 0.1
//! dt = 1.0e-3
//! [domain]
//! min = [-1.0, -1.0, -1.0]
//! max = [1.0, 1.0, 1.0]
//! [gravity]
//! acceleration = [0.0, 0.0, -10.0]
//! [[materials]]
//! name = "glass"
//! density = 2500.0
//! [contact]
//! normal = { model = "linear", stiffness = 1.0e5 }
//! restitution = 0.8
//! [[particles]]
//! material = "glass"
//! shape = { sphere = { diameter = 0.1 } }
//! positions = [[0.0, 0.0, 0.0]]
//! "#).unwrap();
//! let mut sim = tumble_cpu::CpuSimulation::new(tumble_scene::compile(&scene).unwrap(), 1);
//! sim.advance(100);
//! assert!((sim.state().vel[0].z + 1.0).abs() < 1e-12);
//! ```

mod backend;
mod forces;
mod neighbours;
pub mod network;
mod observables;
mod polyhedra;
mod servo;
mod step;

pub use tumble_state::{ContactSum, DrumProfile, HistoryOverflow, HistorySlots, Observables, Spring, State, TrackRow, WALL_KEY, drum_profiles};

use forces::{PairOut, SortedEntry};
use glam::DVec3;
use neighbours::NeighbourList;
use tumble_broad::CellGrid;
use tumble_plan::{CompiledScene, Plan};

/// A running CPU simulation.
pub struct CpuSimulation {
    plan: Plan,
    pool: std::sync::Arc<rayon::ThreadPool>,
    state: State,
    grid: CellGrid,
    sorted: Vec<SortedEntry>,
    sums: Vec<ContactSum>,
    neighbours: NeighbourList,
    pair_out: Vec<PairOut>,
    /// Each listed pair's new spring as its lower id holds it (history only): the tangential
    /// halves, and the rolling halves when the plan keeps rolling springs.
    pair_spring: Vec<tumble_state::TangentialHalf>,
    pair_roll: Vec<tumble_state::RollingHalf>,
    /// The next generation of spring slots, written by the gather and then swapped in.
    history_next: HistorySlots,
    history_overflow: Option<HistoryOverflow>,
    last_resort: Option<u64>,
    eval_vel: Vec<DVec3>,
    eval_omega: Vec<DVec3>,
    step: u64,
    removed: usize,
    /// Per outlet: particles deleted and their mass.
    outlet_tally: Vec<tumble_state::OutletTally>,
    threads: usize,
    /// The walls in their pose at `walls_time` (moving ones updated every step).
    walls: Vec<tumble_plan::Wall>,
    moving_walls: bool,
    /// Some wall does work (it moves, or it is a conveyor): integrate the groups' power.
    working_walls: bool,
    walls_time: f64,
    /// `walls_time` at the last neighbour-list build.
    walls_built_at: f64,
    /// Per wall candidate (parallel to the list's wall entries): power, force and torque on the wall.
    candidate_loads: Vec<forces::WallLoad>,
    /// Per wall group: power at the last force pass and work done since t = 0.
    group_power: Vec<f64>,
    group_work: Vec<f64>,
    /// Per wall group at the last force pass: force on it, torque on it about the origin.
    group_force: Vec<DVec3>,
    group_torque: Vec<DVec3>,
    /// Per wall group: its servo's offset, offset at the last list build and speed (servo.rs).
    servos: Vec<tumble_state::ServoState>,
    /// Some mesh wall accumulates Archard wear.
    wearing: bool,
    /// Per wall: the volume worn off each of its triangles since t = 0 (empty without wear).
    wear: Vec<Vec<f64>>,
    /// Per wall candidate (parallel to the list's wall entries): the wear its contacts booked.
    candidate_worn: Vec<forces::Worn>,
    /// Forces held on the particles, by id (a coupled fluid's; empty without them).
    external: Vec<DVec3>,
}

impl CpuSimulation {
    /// Sets up the state and evaluates the initial forces, on `threads` worker threads.
    pub fn new(scene: CompiledScene, threads: usize) -> Self {
        let state = State::from_scene(&scene);
        Self::from_state(scene, state, threads)
    }

    /// Sets up `scene` starting from `state` (a state of the same model: [`State::from_scene`]'s
    /// arrays, springs included) instead of the scene's particles.
    pub fn from_state(scene: CompiledScene, mut state: State, threads: usize) -> Self {
        let threads = threads.max(1);
        let rolling = scene.plan.model.rolling_springs();
        state.history.keep_rolling(rolling);
        let pool = std::sync::Arc::new(rayon::ThreadPoolBuilder::new().num_threads(threads).build().expect("thread pool"));
        let slots = state.history.slots;
        // A one-cell placeholder: the first broad phase sizes the real grid to the particles.
        let grid = CellGrid::new(&scene.plan.model.domain, scene.plan.model.domain.extent().max_element());
        let neighbours = NeighbourList::new(scene.plan.tuning.skin);
        let walls = scene.plan.model.walls.clone();
        let moving_walls = walls.iter().any(|w| w.motion.is_some()) || scene.plan.model.wall_groups.iter().any(|g| g.servo.is_some());
        let working_walls = scene.plan.model.wall_groups.iter().any(|g| g.moving);
        let groups = scene.plan.model.wall_groups.len();
        let wearing = walls.iter().any(|w| w.wear > 0.0);
        let wear = walls.iter().map(|w| if w.wear > 0.0 { vec![0.0; triangles(&w.shape)] } else { Vec::new() }).collect();
        let outlets = scene.plan.model.outlets.len();
        let mut sim = CpuSimulation {
            plan: scene.plan,
            pool,
            state,
            grid,
            sorted: Vec::new(),
            sums: Vec::new(),
            neighbours,
            pair_out: Vec::new(),
            pair_spring: Vec::new(),
            pair_roll: Vec::new(),
            history_next: HistorySlots::new(0, slots, rolling),
            history_overflow: None,
            last_resort: None,
            eval_vel: Vec::new(),
            eval_omega: Vec::new(),
            step: 0,
            removed: 0,
            outlet_tally: vec![Default::default(); outlets],
            threads,
            walls,
            moving_walls,
            working_walls,
            walls_time: 0.0,
            walls_built_at: 0.0,
            candidate_loads: Vec::new(),
            group_power: vec![0.0; groups],
            group_work: vec![0.0; groups],
            group_force: vec![DVec3::ZERO; groups],
            group_torque: vec![DVec3::ZERO; groups],
            servos: vec![Default::default(); groups],
            wearing,
            wear,
            candidate_worn: Vec::new(),
            external: Vec::new(),
        };
        sim.broad_phase();
        sim.initial_forces();
        sim
    }

    pub fn plan(&self) -> &Plan {
        &self.plan
    }

    pub fn state(&self) -> &State {
        &self.state
    }

    pub fn threads(&self) -> usize {
        self.threads
    }

    /// Steps taken so far.
    pub fn steps(&self) -> u64 {
        self.step
    }

    /// Simulated time.
    pub fn time(&self) -> f64 {
        self.step as f64 * self.plan.model.dt
    }

    /// Particles that left the domain through a non-periodic side.
    pub fn removed(&self) -> usize {
        self.removed
    }

    /// Adds particles (ids after every id so far, overlapping nothing, no springs) before the
    /// next step. Touching nothing, their acceleration is gravity's.
    pub fn insert(&mut self, mut new: State) {
        let g = self.plan.model.gravity;
        new.acc.iter_mut().zip(&new.inv_mass).filter(|(_, m)| **m != 0.0).for_each(|(a, _)| *a = g);
        self.state.append(new);
        // Everything indexed by the old arrays is stale until the next list build and force pass.
        self.neighbours.invalidate();
        self.sums.clear();
        self.pair_out.clear();
    }

    /// Holds `forces` (N, by particle id) on the particles from the next step on (see
    /// [`tumble_state::Backend::set_external_forces`]): the last pass's accelerations take the
    /// change now, so Verlet's first half kick already sees the new forces.
    pub fn set_external_forces(&mut self, forces: &[DVec3]) {
        let s = &mut self.state;
        let old = &self.external;
        for i in 0..s.len() {
            let id = s.id[i] as usize;
            let change = forces.get(id).copied().unwrap_or(DVec3::ZERO) - old.get(id).copied().unwrap_or(DVec3::ZERO);
            if s.inv_mass[i] != 0.0 && change != DVec3::ZERO {
                s.acc[i] += change * s.inv_mass[i];
            }
        }
        self.external.clear();
        self.external.extend_from_slice(forces);
    }

    /// The forces held on the particles, by id (empty without them).
    pub fn external_forces(&self) -> &[DVec3] {
        &self.external
    }

    /// Advances `steps` steps, or fewer when a particle runs out of history slots
    /// (see [`CpuSimulation::history_overflow`]): the run cannot go on without losing a spring.
    pub fn advance(&mut self, steps: u64) {
        // One hand-over to the pool for all the steps; the passes' own installs then run inline.
        let pool = self.pool.clone();
        pool.install(|| {
            for _ in 0..steps {
                if self.history_overflow.is_some() {
                    break;
                }
                self.step_once();
            }
        });
    }

    /// The first particle that had more contacts with history than slots, if any.
    pub fn history_overflow(&self) -> Option<HistoryOverflow> {
        self.history_overflow
    }

    /// Index of the particle with id `id`, if it is still in the domain.
    pub fn index_of(&self, id: u32) -> Option<usize> {
        self.state.id.iter().position(|&k| k == id)
    }

    /// Neighbour-list rebuilds so far.
    pub fn neighbour_builds(&self) -> u64 {
        self.neighbours.builds
    }

    /// Particle pairs (by id, lower first) whose bodies touched in the last force pass.
    pub fn touching_pairs(&self) -> Vec<(u32, u32)> {
        let id = &self.state.id;
        let mut pairs: Vec<(u32, u32)> = self
            .neighbours
            .pairs
            .iter()
            .zip(&self.pair_out)
            .filter(|(_, out)| out.overlap_ratio >= 0.0)
            .map(|(p, _)| (id[p[0] as usize], id[p[1] as usize]))
            .collect();
        pairs.sort_unstable();
        pairs
    }

    /// The walls in their current pose.
    pub fn walls(&self) -> &[tumble_plan::Wall] {
        &self.walls
    }

    /// Power delivered to the particles by each wall group at the last force pass,
    /// Σ F_on_particle · v_wall (positive when the wall drives the particles; zero for static walls).
    pub fn wall_power(&self) -> &[f64] {
        &self.group_power
    }

    /// Work done on the particles by each wall group since t = 0.
    pub fn wall_work(&self) -> &[f64] {
        &self.group_work
    }

    /// Per wall group: the particles' force on it at the last force pass.
    pub fn wall_force(&self) -> &[DVec3] {
        &self.group_force
    }

    /// Per wall group: the particles' torque on it at the last force pass, about the group's
    /// reference point (Σ (p − r) × F = Σ p × F − r × Σ F).
    pub fn wall_torque(&self) -> Vec<DVec3> {
        let model = &self.plan.model;
        (0..self.group_torque.len()).map(|g| self.group_torque[g] - model.wall_group_reference(g).cross(self.group_force[g])).collect()
    }

    /// The contact sums of the last force pass, by array index.
    pub fn contact_sums(&self) -> &[ContactSum] {
        &self.sums
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use std::collections::BTreeMap;

    /// Springs by (owner id, key), whatever the array order.
    fn springs(sim: &CpuSimulation) -> BTreeMap<(u32, u32), [u64; 3]> {
        let (s, h) = (&sim.state, &sim.state.history);
        let mut map = BTreeMap::new();
        for i in 0..s.len() {
            for k in 0..h.count[i] as usize {
                map.insert((s.id[i], h.key[i * h.slots + k]), h.spring[i * h.slots + k].xi.to_array().map(f64::to_bits));
            }
        }
        map
    }

    #[test]
    fn springs_survive_a_re_sort_of_the_particle_arrays() {
        // The shared test scene, read from the repository (tumble-testkit depends on this crate).
        let root = std::path::Path::new(env!("CARGO_MANIFEST_DIR")).ancestors().nth(2).unwrap();
        let path = root.join("scenes/test/pile.toml");
        let text = std::fs::read_to_string(&path).unwrap_or_else(|e| panic!("{}: {e}", path.display()));
        let scene = tumble_scene::parse_scene(&text).unwrap();
        let mut sim = CpuSimulation::new(tumble_scene::compile(&scene).unwrap(), 1);
        sim.advance(15000);
        let before = springs(&sim);
        assert!(before.len() > 50, "the pile should hold springs: {}", before.len());
        assert!(before.keys().any(|k| k.1 & WALL_KEY != 0) && before.keys().any(|k| k.1 & WALL_KEY == 0));
        // Reverse the arrays, as a re-sort by cell would shuffle them.
        let order: Vec<u32> = (0..sim.state.len() as u32).rev().collect();
        sim.state.permute(&order);
        sim.neighbours.invalidate();
        assert_eq!(before, springs(&sim));
        sim.broad_phase();
        sim.advance(1);
        assert_eq!(before.keys().collect::<Vec<_>>(), springs(&sim).keys().collect::<Vec<_>>(), "no contact lost or gained in one step at rest");
    }
}

/// Triangles of a mesh surface (0 for any other).
fn triangles(shape: &tumble_geom::SurfaceShape) -> usize {
    if let tumble_geom::SurfaceShape::Mesh(m) = shape { m.body.mesh.triangles.len() } else { 0 }
}
