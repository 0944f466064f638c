//! The GPU simulation behind the run loop's [`Backend`] seam.

use crate::GpuSimulation;
use glam::DVec3;
use std::any::Any;
use std::borrow::Cow;
use tumble_plan::{Plan, Wall};
use tumble_state::{AdapterInfo, Backend, BackendInfo, Fault, Frame, Snapshot, SnapshotError, State};

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
            adapter: Some(AdapterInfo {
                name: a.name.clone(),
                backend: a.backend.clone(),
                driver: a.driver.clone(),
                device_type: a.device_type.clone(),
            }),
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

    fn outlet_tallies(&self) -> Vec<tumble_state::OutletTally> {
        GpuSimulation::outlet_tallies(self)
    }

    fn insert(&mut self, particles: State) -> Result<(), String> {
        GpuSimulation::insert(self, &particles)
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

    fn snapshot(&self) -> Snapshot {
        GpuSimulation::snapshot(self)
    }

    fn restore(&mut self, snapshot: &Snapshot) -> Result<(), SnapshotError> {
        GpuSimulation::restore(self, snapshot)
    }

    fn as_any(&self) -> &dyn Any {
        self
    }

    fn as_any_mut(&mut self) -> &mut dyn Any {
        self
    }
}
