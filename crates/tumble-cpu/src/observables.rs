//! Whole-system observables, summed serially in array order (deterministic).

use crate::CpuSimulation;
use glam::DVec3;

/// One row of observables.csv.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct Observables {
    pub time: f64,
    pub kinetic_energy: f64,
    pub rotational_energy: f64,
    /// −Σ m g·x over movable particles.
    pub potential_energy: f64,
    /// Energy stored in contact springs and cohesive bonds at the last force pass.
    pub elastic_energy: f64,
    /// Energy dissipated by contact damping and friction so far.
    pub dissipated_energy: f64,
    /// Work done by the fluid on the particles so far (a source or sink).
    pub fluid_work: f64,
    pub contacts: u64,
    pub max_overlap_ratio: f64,
    pub particles: usize,
    /// True when every position and velocity is finite.
    pub finite: bool,
}

impl Observables {
    /// Kinetic + rotational + potential + elastic energy.
    pub fn mechanical_energy(&self) -> f64 {
        self.kinetic_energy + self.rotational_energy + self.potential_energy + self.elastic_energy
    }
}

/// One row of tracks.csv.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct TrackRow {
    pub id: u32,
    pub position: DVec3,
    pub velocity: DVec3,
    pub angular_velocity: DVec3,
}

impl CpuSimulation {
    pub fn observables(&self) -> Observables {
        let s = self.state();
        let g = self.plan().gravity;
        let mut o = Observables { time: self.time(), particles: s.len(), finite: true, ..Default::default() };
        for i in 0..s.len() {
            o.finite &= s.pos[i].is_finite() && s.vel[i].is_finite();
            if s.inv_mass[i] != 0.0 {
                o.kinetic_energy += 0.5 * s.mass[i] * s.vel[i].length_squared();
                o.potential_energy -= s.mass[i] * g.dot(s.pos[i]);
                if !s.omega.is_empty() {
                    o.finite &= s.omega[i].is_finite();
                    o.rotational_energy += 0.5 * s.omega[i].length_squared() / s.inv_inertia[i];
                }
            }
            o.dissipated_energy += s.dissipated[i];
            if !s.fluid_work.is_empty() {
                o.fluid_work += s.fluid_work[i];
            }
        }
        for c in self.contact_sums() {
            o.elastic_energy += c.elastic;
            o.contacts += c.contacts as u64;
            o.max_overlap_ratio = o.max_overlap_ratio.max(c.max_overlap_ratio);
        }
        o.finite &= o.elastic_energy.is_finite() && o.dissipated_energy.is_finite();
        o
    }

    /// Tracked particles, by id.
    pub fn tracks(&self) -> Vec<TrackRow> {
        let s = self.state();
        let mut rows: Vec<TrackRow> = (0..s.len())
            .filter(|&i| s.track[i])
            .map(|i| TrackRow {
                id: s.id[i],
                position: s.pos[i],
                velocity: s.vel[i],
                angular_velocity: if s.omega.is_empty() { DVec3::ZERO } else { s.omega[i] },
            })
            .collect();
        rows.sort_by_key(|r| r.id);
        rows
    }
}
