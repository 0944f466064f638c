//! Contact history on the host side: the overflow check and reading the springs
//! back (history.wgsl holds the layout: slots per ORIGINAL id, two generations).

use crate::GpuSimulation;
use crate::buffers::history_entries_per_particle;
use crate::upload::history_slots;
use std::collections::BTreeMap;
use tumble_state::HistoryOverflow;

impl GpuSimulation {
    /// The generation the last committed contact pass wrote (the one read next).
    fn latest_history(&self) -> &wgpu::Buffer {
        &self.buffers.history[(self.generation % 2) as usize]
    }

    /// The count entries (in use, needed this step, most ever needed, unused) by id.
    fn history_counts(&self) -> Vec<[u32; 4]> {
        let n = self.slots as usize;
        let slots = history_slots(&self.plan);
        let all: Vec<[u32; 4]> = self.read(self.latest_history(), n * (slots + tumble_shaders::HISTORY_COUNT_ENTRIES as usize));
        all[n * slots..].to_vec()
    }

    /// Reads the slot counts; records the first overflow (the run then stops).
    pub(crate) fn check_history(&self) {
        if self.overflow.get().is_some() || !self.plan.model.history {
            return;
        }
        let slots = history_slots(&self.plan);
        let counts = self.history_counts();
        // The particle (lowest id) that needed the most slots.
        if let Some((id, c)) = counts.iter().enumerate().filter(|(_, c)| c[2] as usize > slots).max_by_key(|(id, c)| (c[2], std::cmp::Reverse(*id))) {
            self.overflow.set(Some(HistoryOverflow { id: id as u32, contacts: c[2] as usize, slots, step: self.step }));
        }
    }

    /// A particle had more contacts with a tangential spring than `contact.history_slots`.
    /// The device records it every pass; the host reads the record every 256 steps and at
    /// the end of `advance`, so `step` is where it was found (at most 256 steps late).
    pub fn history_overflow(&self) -> Option<HistoryOverflow> {
        self.overflow.get()
    }

    /// Writes `history` (springs by particle id, from a [`tumble_state::State`] in id order) into
    /// the generation the next contact pass reads: a run started from another run's springs.
    pub(crate) fn upload_springs(&self, history: &tumble_state::HistorySlots) {
        let n = self.slots as usize;
        let slots = history_slots(&self.plan);
        let per_entry = tumble_shaders::HISTORY_ENERGIES_PER_ENTRY as usize;
        let rows = slots.div_ceil(per_entry);
        let counts = n * slots;
        let energies = n * (slots + tumble_shaders::HISTORY_COUNT_ENTRIES as usize);
        let mut all = vec![[0u32; 4]; n * history_entries_per_particle(slots) as usize];
        for id in 0..n.min(history.count.len()) {
            let mut used = 0;
            for (k, (key, s)) in history.of(id).take(slots).enumerate() {
                all[id * slots + k] = [(s.xi.x as f32).to_bits(), (s.xi.y as f32).to_bits(), (s.xi.z as f32).to_bits(), key];
                all[energies + id * rows + k / per_entry][k % per_entry] = (s.energy as f32).to_bits();
                used += 1;
            }
            all[counts + id] = [used, used, used, 0];
        }
        self.gpu.queue.write_buffer(self.latest_history(), 0, bytemuck::cast_slice(&all));
    }

    /// Every stored spring as the device holds it: (owner id, key) → ξ (f32 bits),
    /// key = the neighbour's id or `WALL_KEY | wall`. Empty without history.
    pub fn springs(&self) -> BTreeMap<(u32, u32), [u32; 3]> {
        self.stored_springs().into_iter().map(|(k, (xi, _))| (k, xi)).collect()
    }

    /// The energy each stored spring holds, ½ k_t |ξ|² (f32 bits), keyed as [`GpuSimulation::springs`]:
    /// what is booked as dissipated if its contact ends. Empty without history.
    pub fn spring_energies(&self) -> BTreeMap<(u32, u32), u32> {
        self.stored_springs().into_iter().map(|(k, (_, energy))| (k, energy)).collect()
    }

    /// (owner id, key) → (ξ, stored energy) as f32 bits, from the latest generation.
    pub(crate) fn stored_springs(&self) -> BTreeMap<(u32, u32), ([u32; 3], u32)> {
        let mut out = BTreeMap::new();
        if !self.plan.model.history {
            return out;
        }
        let n = self.slots as usize;
        let slots = history_slots(&self.plan);
        let all: Vec<[u32; 4]> = self.read(self.latest_history(), n * history_entries_per_particle(slots) as usize);
        // Energies follow the count entries, ceil(slots / per entry) entries per id (history.wgsl).
        let per_entry = tumble_shaders::HISTORY_ENERGIES_PER_ENTRY as usize;
        let energies = &all[n * (slots + tumble_shaders::HISTORY_COUNT_ENTRIES as usize)..];
        let rows = slots.div_ceil(per_entry);
        for id in 0..n {
            let used = (all[n * slots + id][0] as usize).min(slots);
            for (k, e) in all[id * slots..id * slots + used].iter().enumerate() {
                let energy = energies[id * rows + k / per_entry][k % per_entry];
                out.insert((id as u32, e[3]), ([e[0], e[1], e[2]], energy));
            }
        }
        out
    }
}
