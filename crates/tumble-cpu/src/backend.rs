//! The CPU simulation behind the run loop's [`Backend`] seam, and its snapshots.

use crate::CpuSimulation;
use glam::DVec3;
use std::any::Any;
use std::borrow::Cow;
use tumble_plan::{Plan, Wall};
use tumble_state::{
    Backend, BackendInfo, Fault, Frame, NeighbourState, NeighbourStateRef, SNAPSHOT_VERSION, Snapshot, SnapshotError, SnapshotRef, State, WallState,
};

impl CpuSimulation {
    /// Everything needed to continue this run bit-identically (arrays in memory order).
    pub fn snapshot(&self) -> Snapshot {
        let r = self.snapshot_ref();
        Snapshot {
            version: r.version,
            scene: r.scene.to_string(),
            dt: r.dt,
            backend: r.backend.into(),
            precision: r.precision.into(),
            step: r.step,
            time: r.time,
            removed: r.removed,
            outlets: self.outlet_tally.clone(),
            state: self.state.clone(),
            last_pass: self.sums.clone(),
            walls: r.walls,
            neighbours: r.neighbours.map(|n| NeighbourState { reference: n.reference.to_vec(), valid: n.valid, builds: n.builds }),
            last_resort: r.last_resort,
            fault: r.fault,
            rng: Vec::new(),
            external: self.external.clone(),
            device: None,
        }
    }

    /// The snapshot borrowed from this simulation's arrays (what [`CpuSimulation::snapshot`] copies).
    pub fn snapshot_ref(&self) -> SnapshotRef<'_> {
        SnapshotRef {
            version: SNAPSHOT_VERSION,
            scene: &self.plan.run.name,
            dt: self.plan.model.dt,
            backend: "cpu",
            precision: "f64",
            step: self.step,
            time: self.time(),
            removed: self.removed as u64,
            outlets: &self.outlet_tally,
            state: &self.state,
            last_pass: &self.sums,
            walls: WallState {
                time: self.walls_time,
                built_at: self.walls_built_at,
                power: self.group_power.clone(),
                work: self.group_work.clone(),
                work_compensation: Vec::new(),
                servos: self.servos.clone(),
                wear: self.wear.clone(),
            },
            neighbours: Some(NeighbourStateRef {
                reference: self.neighbours.reference(),
                valid: self.neighbours.is_valid(),
                builds: self.neighbours.builds,
            }),
            last_resort: self.last_resort,
            fault: self.history_overflow.map(Fault::from),
            rng: &[],
            external: &self.external,
            device: None,
        }
    }

    /// Continues from a snapshot this backend wrote for the same scene: the next steps are
    /// bit-identical to those of the run that wrote it (the neighbour list is rebuilt from its
    /// reference positions in the same array order, so every pair and sum keeps its order).
    pub fn restore(&mut self, snap: &Snapshot) -> Result<(), SnapshotError> {
        snap.check_fits(&self.plan)?;
        if snap.backend != "cpu" {
            return Err(SnapshotError::Mismatch(format!("written by the {} backend; restore it there", snap.backend)));
        }
        let s = &snap.state;
        let n = s.len();
        let consistent =
            [s.id.len(), s.vel.len(), s.acc.len(), s.radius.len(), s.reach.len(), s.mass.len(), s.inv_mass.len()].iter().all(|&l| l == n)
                && s.omega.len() == if self.plan.model.rotation { n } else { 0 }
                && s.orient.len() == if self.plan.model.polyhedra { n } else { 0 }
                && s.history.slots == self.state.history.slots
                && (snap.last_pass.is_empty() || snap.last_pass.len() == n)
                && snap.walls.power.len() == self.group_power.len()
                && (snap.walls.servos.len() == self.servos.len() || !self.has_servos())
                && (snap.walls.wear.iter().map(Vec::len).eq(self.wear.iter().map(Vec::len)) || !self.wearing);
        if !consistent {
            return Err(SnapshotError::Mismatch(
                "its arrays do not match this plan's model (rotation, polyhedra, history slots, wall groups, servos, wear)".into(),
            ));
        }
        self.state = snap.state.clone();
        self.state.history.keep_rolling(self.plan.model.rolling_springs());
        self.step = snap.step;
        self.removed = snap.removed as usize;
        self.outlet_tally.clone_from(&snap.outlets);
        self.sums = snap.last_pass.clone();
        self.pair_out.clear();
        self.history_overflow = snap.fault.map(|Fault::HistoryOverflow(o)| o);
        self.last_resort = snap.last_resort;
        self.group_power.clone_from(&snap.walls.power);
        self.group_work.clone_from(&snap.walls.work);
        if snap.walls.servos.len() == self.servos.len() {
            self.servos.clone_from(&snap.walls.servos);
        }
        if self.wearing {
            self.wear.clone_from(&snap.walls.wear);
        }
        self.external.clone_from(&snap.external);
        self.neighbours.invalidate();
        if let Some(list) = &snap.neighbours {
            if list.valid && list.reference.len() == n {
                // The list as it was built: positions of that build, walls in that build's pose.
                self.place_walls_as(snap.walls.built_at, true);
                let now = std::mem::replace(&mut self.state.pos, list.reference.clone());
                self.build_list();
                self.state.pos = now;
            }
            self.neighbours.builds = list.builds;
        }
        self.place_walls(snap.walls.time);
        self.walls_built_at = snap.walls.built_at;
        Ok(())
    }
}

impl Backend for CpuSimulation {
    fn plan(&self) -> &Plan {
        &self.plan
    }

    fn info(&self) -> BackendInfo {
        BackendInfo { name: "cpu", precision: "f64", device: format!("CPU, {} threads", self.threads), adapter: None }
    }

    fn advance(&mut self, steps: u64) {
        CpuSimulation::advance(self, steps)
    }

    fn steps(&self) -> u64 {
        self.step
    }

    fn particles(&self) -> usize {
        self.state.len()
    }

    fn removed(&self) -> usize {
        self.removed
    }
    fn outlet_tallies(&self) -> Vec<tumble_state::OutletTally> {
        self.outlet_tally.clone()
    }
    fn insert(&mut self, particles: State) -> Result<(), String> {
        CpuSimulation::insert(self, particles);
        Ok(())
    }

    fn fault(&self) -> Option<Fault> {
        self.history_overflow.map(Fault::from)
    }

    fn frame(&self, with_state: bool) -> Frame<'_> {
        Frame {
            observables: self.observables(),
            tracks: self.tracks(),
            wall_power: self.group_power.clone(),
            wall_work: self.group_work.clone(),
            wall_force: self.group_force.clone(),
            wall_torque: self.wall_torque(),
            servo_offset: self.servo_offsets(),
            drums: self.drum_profiles(),
            state: with_state.then_some(Cow::Borrowed(&self.state)),
        }
    }

    fn state(&self) -> Cow<'_, State> {
        Cow::Borrowed(&self.state)
    }

    fn wall_power(&self) -> Vec<f64> {
        self.group_power.clone()
    }

    fn wall_work(&self) -> Vec<f64> {
        self.group_work.clone()
    }

    fn walls(&self) -> Cow<'_, [Wall]> {
        Cow::Borrowed(&self.walls)
    }

    fn mesh_wear(&self) -> Vec<Vec<f64>> {
        self.wear.clone()
    }

    fn contact_force(&self, id: u32) -> Option<DVec3> {
        self.index_of(id).and_then(|i| self.sums.get(i)).map(|s| s.force)
    }

    fn neighbour_builds(&self) -> Option<u64> {
        Some(self.neighbours.builds)
    }

    fn memory_bytes(&self) -> u64 {
        self.plan.memory_bytes(self.state.len()) as u64
    }

    fn bytes_per_particle(&self) -> u64 {
        self.plan.tuning.bytes_per_particle as u64
    }

    fn set_external_forces(&mut self, forces: &[DVec3]) -> Result<(), String> {
        CpuSimulation::set_external_forces(self, forces);
        Ok(())
    }

    fn external_forces(&self) -> &[DVec3] {
        CpuSimulation::external_forces(self)
    }

    fn snapshot(&self) -> Snapshot {
        CpuSimulation::snapshot(self)
    }

    fn write_snapshot(&self, w: &mut dyn std::io::Write) -> std::io::Result<()> {
        self.snapshot_ref().write_to(w).map(|_| ())
    }

    fn restore(&mut self, snapshot: &Snapshot) -> Result<(), SnapshotError> {
        CpuSimulation::restore(self, snapshot)
    }

    fn as_any(&self) -> &dyn Any {
        self
    }

    fn as_any_mut(&mut self) -> &mut dyn Any {
        self
    }
}
