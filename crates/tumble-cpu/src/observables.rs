//! Whole-system observables of the CPU state, summed serially in array order (deterministic).

use crate::CpuSimulation;
use tumble_state::{DrumProfile, Observables, TrackRow};

impl CpuSimulation {
    pub fn observables(&self) -> Observables {
        let mut o = Observables::of_particles(self.state(), self.plan().model.gravity, self.plan().model.domain.extent(), self.time());
        for c in self.contact_sums() {
            o.add_contacts(c.elastic, c.contacts as u64, c.max_overlap_ratio);
        }
        o.finish(self.wall_work())
    }

    /// The charge profile of each drum of the plan (NaN angles without gravity across the axis).
    pub fn drum_profiles(&self) -> Vec<DrumProfile> {
        tumble_state::drum_profiles(self.plan(), self.state(), self.time())
    }

    /// Tracked particles, by id.
    pub fn tracks(&self) -> Vec<TrackRow> {
        tumble_state::tracks(self.state())
    }
}
