//! Mass flow through the scene's flow planes ([output] flow_planes), counted from
//! particle crossings between two outputs.

use crate::Simulation;
use tumble_scene::Plan;
use tumble_state::State;

/// Net mass carried through each flow plane, positive along its normal.
pub struct FlowCounter {
    /// Side of each plane each particle was on at the last count, by particle id (−1, 0, +1).
    side: Vec<Vec<i8>>,
    /// Net mass through each plane since t = 0, kg.
    pub mass: Vec<f64>,
    last_mass: Vec<f64>,
    last_time: f64,
}

impl FlowCounter {
    pub fn new(sim: &Simulation) -> Self {
        Self::from_state(sim.plan(), &sim.state(), sim.time())
    }

    /// Starts counting from state `s` of a run of `plan` at `time`.
    pub fn from_state(plan: &Plan, s: &State, time: f64) -> Self {
        let planes = plan.model.flow_planes.len();
        let mut c = FlowCounter { side: vec![Vec::new(); planes], mass: vec![0.0; planes], last_mass: vec![0.0; planes], last_time: time };
        c.count(plan, s);
        c
    }

    /// Books the crossings since the last call; returns (flow rate kg/s since then, mass since t = 0 kg) per plane.
    /// A particle counts when its centre changed side; one that left the domain in between is not counted.
    pub fn update(&mut self, sim: &Simulation) -> Vec<(f64, f64)> {
        self.update_state(sim.plan(), &sim.state(), sim.time())
    }

    /// [`FlowCounter::update`] from state `s` at `time`.
    pub fn update_state(&mut self, plan: &Plan, s: &State, time: f64) -> Vec<(f64, f64)> {
        self.count(plan, s);
        let dt = time - self.last_time;
        let rows = self.mass.iter().zip(&self.last_mass).map(|(&m, &m0)| (if dt > 0.0 { (m - m0) / dt } else { 0.0 }, m)).collect();
        self.last_mass.clone_from(&self.mass);
        self.last_time = time;
        rows
    }

    fn count(&mut self, plan: &Plan, s: &State) {
        let max_id = s.id.iter().copied().max().map_or(0, |m| m as usize + 1);
        for (k, plane) in plan.model.flow_planes.iter().enumerate() {
            let side = &mut self.side[k];
            let fresh = side.is_empty();
            if side.len() < max_id {
                side.resize(max_id, 0);
            }
            for i in 0..s.len() {
                if s.inv_mass[i] == 0.0 {
                    continue;
                }
                let h = plane.plane.signed_distance(s.pos[i]);
                let now = if h > 0.0 { 1 } else { -1 };
                let before = &mut side[s.id[i] as usize];
                if !fresh && *before != 0 && *before != now {
                    self.mass[k] += s.mass[i] * now as f64;
                }
                *before = now;
            }
        }
    }
}
