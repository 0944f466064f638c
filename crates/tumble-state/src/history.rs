//! Contact history: fixed-capacity spring slots per particle, keyed by the
//! neighbour's id (or a wall's index with [`WALL_KEY`] set), so they survive
//! the re-sort by cell. Both sides of a pair hold the same spring with
//! opposite sign; the pair pass reads the lower id's copy.

use glam::DVec3;
use serde::{Deserialize, Serialize};

/// Marks a key as a wall index rather than a particle id.
pub const WALL_KEY: u32 = 1 << 31;

/// With [`WALL_KEY`], marks a key as a mesh triangle (numbered across the scene's meshes)
/// rather than a wall index.
pub const MESH_KEY: u32 = 1 << 30;

/// One contact's tangential spring, its rolling spring (EPSD2), and the energies they store.
#[derive(Clone, Copy, Debug, Default, PartialEq, Serialize, Deserialize)]
pub struct Spring {
    pub xi: DVec3,
    /// ½ k_t |ξ|² as booked at the last step: what is dissipated if the contact ends now.
    pub energy: f64,
    /// The rolling torque on the holder (zero unless the pair's rolling model is EPSD2).
    pub roll: DVec3,
    /// ½ |M_r|² / k_r as booked at the last step.
    pub roll_energy: f64,
}

impl Spring {
    /// The spring as the other side of the pair holds it: ξ and the rolling torque negated.
    pub fn mirrored(self) -> Spring {
        Spring { xi: -self.xi, roll: -self.roll, ..self }
    }

    /// True when the contact keeps something: a tangential or a rolling spring.
    pub fn is_loaded(&self) -> bool {
        self.xi != DVec3::ZERO || self.roll != DVec3::ZERO
    }

    /// Everything the contact stores, dissipated if it ends now.
    pub fn stored_energy(&self) -> f64 {
        self.energy + self.roll_energy
    }
}

/// The tangential half of a stored [`Spring`]: what every contact with history keeps.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct TangentialHalf {
    pub xi: DVec3,
    pub energy: f64,
}

/// The rolling half of a stored [`Spring`], kept only by plans with EPSD2 rolling springs.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct RollingHalf {
    pub roll: DVec3,
    pub roll_energy: f64,
}

impl Spring {
    #[inline(always)]
    pub fn tangential(&self) -> TangentialHalf {
        TangentialHalf { xi: self.xi, energy: self.energy }
    }

    #[inline(always)]
    pub fn rolling(&self) -> RollingHalf {
        RollingHalf { roll: self.roll, roll_energy: self.roll_energy }
    }

    #[inline(always)]
    pub fn from_parts(t: TangentialHalf, r: RollingHalf) -> Spring {
        Spring { xi: t.xi, energy: t.energy, roll: r.roll, roll_energy: r.roll_energy }
    }
}

/// One generation of spring slots: `slots` per particle, the first `count[i]` in use.
///
/// The tangential halves and the rolling halves lie in separate arrays, and the rolling array
/// is empty unless the plan keeps rolling springs (EPSD2): a scene without them moves half the
/// bytes per contact through the step.
///
/// Serialised compactly, with the slots in use only (a packed bed uses about a third of
/// them): what is beyond `count[i]` is never read, so a restore may leave it zero. The
/// serialised form holds whole [`Spring`]s (rolling halves zero when not kept) whatever the
/// arrays' layout.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct HistorySlots {
    pub slots: usize,
    pub count: Vec<u16>,
    pub key: Vec<u32>,
    pub spring: Vec<TangentialHalf>,
    /// Empty, or one per slot when rolling springs are kept.
    pub roll: Vec<RollingHalf>,
    /// Whether rolling halves are kept.
    pub rolling: bool,
}

/// [`HistorySlots`] as serialised: the counts, then the keys and springs in use, particle by particle.
#[derive(Serialize, Deserialize)]
struct UsedSlots {
    slots: usize,
    count: Vec<u16>,
    key: Vec<u32>,
    spring: Vec<Spring>,
}

impl Serialize for HistorySlots {
    fn serialize<S: serde::Serializer>(&self, serializer: S) -> Result<S::Ok, S::Error> {
        let n = self.count.len();
        let used = (0..n).flat_map(|i| i * self.slots..i * self.slots + self.count[i] as usize);
        let (key, spring) = used.map(|k| (self.key[k], self.get(k))).unzip();
        UsedSlots { slots: self.slots, count: self.count.clone(), key, spring }.serialize(serializer)
    }
}

impl<'de> Deserialize<'de> for HistorySlots {
    /// Keeps the rolling halves when any is loaded; [`HistorySlots::keep_rolling`] then sets the
    /// layout the plan asks for.
    fn deserialize<D: serde::Deserializer<'de>>(deserializer: D) -> Result<Self, D::Error> {
        let used = UsedSlots::deserialize(deserializer)?;
        let total: usize = used.count.iter().map(|&c| c as usize).sum();
        if used.count.iter().any(|&c| c as usize > used.slots) || used.key.len() != total || used.spring.len() != total {
            return Err(serde::de::Error::custom("contact history: slot counts do not match the springs"));
        }
        let rolling = used.spring.iter().any(|s| s.rolling() != RollingHalf::default());
        let mut slots = HistorySlots::new(used.count.len(), used.slots, rolling);
        let mut next = 0;
        for (i, &c) in used.count.iter().enumerate() {
            let base = i * used.slots;
            slots.key[base..base + c as usize].copy_from_slice(&used.key[next..next + c as usize]);
            for (k, s) in used.spring[next..next + c as usize].iter().enumerate() {
                slots.set(base + k, *s);
            }
            next += c as usize;
        }
        slots.count = used.count;
        Ok(slots)
    }
}

impl HistorySlots {
    /// Empty slots for `n` particles (`slots` = 0 when the plan has no history), with rolling
    /// halves when `rolling`.
    pub fn new(n: usize, slots: usize, rolling: bool) -> Self {
        HistorySlots {
            slots,
            count: vec![0; if slots > 0 { n } else { 0 }],
            key: vec![0; n * slots],
            spring: vec![TangentialHalf::default(); n * slots],
            roll: vec![RollingHalf::default(); if rolling { n * slots } else { 0 }],
            rolling,
        }
    }

    /// Keeps the rolling halves (zero where none was stored) or drops them, as a plan asks.
    pub fn keep_rolling(&mut self, rolling: bool) {
        self.rolling = rolling;
        if rolling {
            self.roll.resize(self.key.len(), RollingHalf::default());
        } else {
            self.roll = Vec::new();
        }
    }

    /// The whole spring in slot `k`.
    #[inline(always)]
    pub fn get(&self, k: usize) -> Spring {
        Spring::from_parts(self.spring[k], self.roll.get(k).copied().unwrap_or_default())
    }

    /// Stores `spring` in slot `k` (its rolling half only where rolling halves are kept).
    #[inline(always)]
    pub fn set(&mut self, k: usize, spring: Spring) {
        self.spring[k] = spring.tangential();
        if let Some(r) = self.roll.get_mut(k) {
            *r = spring.rolling();
        }
    }

    /// The spring particle `i` holds for `key`, zero when the contact is new.
    #[inline]
    pub fn find(&self, i: usize, key: u32) -> Spring {
        let base = i * self.slots;
        let used = self.count[i] as usize;
        match self.key[base..base + used].iter().position(|&k| k == key) {
            Some(s) => self.get(base + s),
            None => Spring::default(),
        }
    }

    /// Particle `i`'s springs: (key, spring) in slot order.
    pub fn of(&self, i: usize) -> impl Iterator<Item = (u32, Spring)> + '_ {
        let base = i * self.slots;
        (base..base + self.count[i] as usize).map(|s| (self.key[s], self.get(s)))
    }

    /// Springs held in all, each pair counted from both sides.
    pub fn total(&self) -> usize {
        self.count.iter().map(|&c| c as usize).sum()
    }

    /// Reorders whole particles' slot blocks by `order` (new slot k holds old particle order[k]);
    /// particles missing from `order` are dropped.
    pub fn permute(&mut self, order: &[u32]) {
        if self.slots == 0 {
            return;
        }
        self.count = order.iter().map(|&o| self.count[o as usize]).collect();
        fn blocks<T: Copy>(v: &[T], order: &[u32], slots: usize) -> Vec<T> {
            order.iter().flat_map(|&o| v[o as usize * slots..(o as usize + 1) * slots].iter().copied()).collect()
        }
        self.key = blocks(&self.key, order, self.slots);
        self.spring = blocks(&self.spring, order, self.slots);
        if self.rolling {
            self.roll = blocks(&self.roll, order, self.slots);
        }
    }

    /// Keeps the blocks of the particles for which `keep` is true.
    pub fn retain(&mut self, keep: &[bool]) {
        if self.slots == 0 {
            return;
        }
        let order: Vec<u32> = (0..keep.len() as u32).filter(|&i| keep[i as usize]).collect();
        self.permute(&order);
    }

    /// Makes room for `n` particles (contents are overwritten by the next gather).
    pub fn resize(&mut self, n: usize) {
        if self.slots > 0 {
            self.count.resize(n, 0);
            self.key.resize(n * self.slots, 0);
            self.spring.resize(n * self.slots, TangentialHalf::default());
            if self.rolling {
                self.roll.resize(n * self.slots, RollingHalf::default());
            }
        }
    }
}

/// A particle had more contacts with history than it has slots.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Serialize, Deserialize)]
pub struct HistoryOverflow {
    pub id: u32,
    pub contacts: usize,
    pub slots: usize,
    pub step: u64,
}

impl std::fmt::Display for HistoryOverflow {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        write!(
            f,
            "contact history overflow at step {}: particle {} has {} contacts with a tangential spring but contact.history_slots = {}; \
             set contact.history_slots to at least {} (no history was dropped: the run stopped)",
            self.step, self.id, self.contacts, self.slots, self.contacts
        )
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn blocks_follow_their_particle_through_a_permutation_and_removal() {
        let mut h = HistorySlots::new(3, 2, false);
        for i in 0..3 {
            h.count[i] = 1;
            h.key[2 * i] = 10 + i as u32;
            h.set(2 * i, Spring { xi: DVec3::splat(i as f64), energy: i as f64, ..Default::default() });
        }
        h.permute(&[2, 0, 1]);
        assert_eq!(h.find(0, 12).xi, DVec3::splat(2.0));
        assert_eq!(h.find(1, 10).xi, DVec3::splat(0.0));
        assert_eq!(h.find(1, 12), Spring::default());
        h.retain(&[false, true, true]);
        assert_eq!(h.count.len(), 2);
        assert_eq!(h.find(1, 11).energy, 1.0);
    }
}
