//! The GPU simulation behind the run loop's [`Backend`] seam.

use crate::GpuSimulation;
use glam::DVec3;
use std::any::Any;
use std::borrow::Cow;
use tumble_scene::{Plan, Wall};
use tumble_state::{AdapterInfo, Backend, BackendInfo, Fault, Frame, SNAPSHOT_VERSION, Snapshot, SnapshotError, State, WallState};

impl Backend for GpuSimulation {
    fn plan(&self) -> &Plan {
        GpuSimulation::plan(self)
    }

    fn info(&self) -> BackendInfo {
        let a = self.adapter();
        BackendInfo {
            name: "gpu",
            precision: "f32",
            device: a.to_string(),
            adapter: Some(AdapterInfo { name: a.name.clone(), backend: a.backend.clone(), driver: a.driver.clone(), device_type: a.device_type.clone() }),
        }
    }

    fn advance(&mut self, steps: u64) {
        GpuSimulation::advance(self, steps)
    }

    fn steps(&self) -> u64 {
        GpuSimulation::steps(self)
    }

    fn particles(&self) -> usize {
        GpuSimulation::particles(self)
    }

    fn removed(&self) -> usize {
        GpuSimulation::removed(self)
    }

    fn fault(&self) -> Option<Fault> {
        self.history_overflow().map(Fault::from)
    }

    fn frame(&self, with_state: bool) -> Frame<'_> {
        GpuSimulation::frame(self, with_state)
    }

    fn state(&self) -> Cow<'_, State> {
        Cow::Owned(GpuSimulation::state(self))
    }

    fn wall_power(&self) -> Vec<f64> {
        GpuSimulation::wall_power(self)
    }

    fn wall_work(&self) -> Vec<f64> {
        GpuSimulation::wall_work(self)
    }

    fn walls(&self) -> Cow<'_, [Wall]> {
        Cow::Owned(GpuSimulation::walls(self))
    }

    fn contact_force(&self, id: u32) -> Option<DVec3> {
        GpuSimulation::contact_force(self, id)
    }

    fn memory_bytes(&self) -> u64 {
        GpuSimulation::memory_bytes(self)
    }

    fn bytes_per_particle(&self) -> u64 {
        crate::bytes_per_particle(self.plan())
    }

    /// The read-back state in id order, widened to f64, with the walls' books. The device's
    /// own order, springs and Kahan terms are not in it yet, so it cannot be restored.
    fn snapshot(&self) -> Snapshot {
        let frame = self.frame(true);
        Snapshot {
            version: SNAPSHOT_VERSION,
            scene: self.plan().name.clone(),
            dt: self.plan().dt,
            backend: "gpu".into(),
            precision: "f32".into(),
            step: self.steps(),
            time: self.time(),
            removed: self.removed() as u64,
            state: frame.state.map(Cow::into_owned).unwrap_or_default(),
            last_pass: Vec::new(),
            walls: WallState { time: self.wall_time, built_at: self.wall_time, power: frame.wall_power, work: frame.wall_work, work_compensation: Vec::new() },
            neighbours: None,
            last_resort: self.last_resort,
            fault: self.fault(),
            rng: Vec::new(),
        }
    }

    fn restore(&mut self, _snapshot: &Snapshot) -> Result<(), SnapshotError> {
        Err(SnapshotError::Unsupported(
            "the GPU backend cannot continue from a snapshot yet (its device order, springs and Kahan terms are not captured); \
             checkpoint and restart on the CPU backend"
                .into(),
        ))
    }

    fn as_any(&self) -> &dyn Any {
        self
    }

    fn as_any_mut(&mut self) -> &mut dyn Any {
        self
    }
}
