//! Mass flow through the scene's flow planes ([output] flow_planes), counted from
//! particle crossings between two outputs.
//!
//! A plane whose normal lies along a periodic axis is crossed again each time a particle goes
//! once round that axis, so there each particle's level is floor(h / L) of its unwrapped signed
//! distance h (one level per image of the plane, L the period): the net crossings between two
//! counts are the change of level, however many times the particle wrapped in between. On any
//! other plane the level is the side (0 behind, 1 in front).

use crate::Simulation;
use tumble_scene::Plan;
use tumble_state::State;

/// Net mass carried through each flow plane, positive along its normal.
#[derive(serde::Serialize, serde::Deserialize)]
pub struct FlowCounter {
    /// Level of each particle at the last count for each plane, by particle id ([`UNSEEN`] before the first).
    level: Vec<Vec<i64>>,
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
        let mut c = FlowCounter { level: vec![Vec::new(); planes], mass: vec![0.0; planes], last_mass: vec![0.0; planes], last_time: time };
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
        let domain = &plan.model.domain;
        let extent = domain.extent();
        for (k, plane) in plan.model.flow_planes.iter().enumerate() {
            let period = periodic_period(domain, plane.plane.normal);
            let level = &mut self.level[k];
            if level.len() < max_id {
                level.resize(max_id, UNSEEN);
            }
            for i in 0..s.len() {
                if s.inv_mass[i] == 0.0 {
                    continue;
                }
                let now = match period {
                    Some(l) => (plane.plane.signed_distance(s.unwrapped(i, extent)) / l).floor() as i64,
                    None => (plane.plane.signed_distance(s.pos[i]) > 0.0) as i64,
                };
                let before = &mut level[s.id[i] as usize];
                if *before != UNSEEN {
                    self.mass[k] += s.mass[i] * (now - *before) as f64;
                }
                *before = now;
            }
        }
    }
}

/// The level of a particle no count has seen yet.
const UNSEEN: i64 = i64::MIN;

/// The period along `normal` when it lies along a periodic axis of `domain`.
fn periodic_period(domain: &tumble_geom::PeriodicBox, normal: glam::DVec3) -> Option<f64> {
    let l = domain.extent();
    (0..3).find(|&k| domain.periodic[k] && (normal[k].abs() - 1.0).abs() < 1e-12).map(|k| l[k])
}
