//! Whole-system observables, drum charge profiles and tracked particles, from
//! any backend's state. Sums run serially in the state's array order, so they
//! are deterministic.

use crate::State;
use glam::{DQuat, DVec3};
use serde::{Deserialize, Serialize};

/// One row of observables.csv.
#[derive(Clone, Copy, Debug, Default, PartialEq, Serialize, Deserialize)]
pub struct Observables {
    pub time: f64,
    pub kinetic_energy: f64,
    pub rotational_energy: f64,
    /// −Σ m g·x over movable particles, x unwrapped across periodic boundaries (so it is
    /// continuous when a particle wraps along a periodic axis that gravity has a component on).
    pub potential_energy: f64,
    /// Energy stored in contact springs and cohesive bonds at the last force pass.
    pub elastic_energy: f64,
    /// Energy dissipated by contact damping and friction so far.
    pub dissipated_energy: f64,
    /// Work done by the fluid on the particles so far (a source or sink).
    pub fluid_work: f64,
    /// Work done on the particles by moving walls so far (a source).
    pub wall_work: f64,
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

    /// The particle sums (energies, dissipation, fluid work, finiteness) of `s` at `time` in a
    /// domain of extent `extent` (the period of its periodic axes); contacts are added with
    /// [`Observables::add_contacts`], walls with [`Observables::finish`].
    pub fn of_particles(s: &State, gravity: DVec3, extent: DVec3, time: f64) -> Observables {
        let mut o = Observables { time, particles: s.len(), finite: true, ..Default::default() };
        for i in 0..s.len() {
            o.finite &= s.pos[i].is_finite() && s.vel[i].is_finite();
            if s.inv_mass[i] != 0.0 {
                o.kinetic_energy += 0.5 * s.mass[i] * s.vel[i].length_squared();
                o.potential_energy -= s.mass[i] * gravity.dot(s.unwrapped(i, extent));
                if !s.omega.is_empty() {
                    o.finite &= s.omega[i].is_finite();
                    o.rotational_energy += s.rotational_energy(i);
                }
            }
            o.dissipated_energy += s.dissipated[i];
            if !s.fluid_work.is_empty() {
                o.fluid_work += s.fluid_work[i];
            }
        }
        o
    }

    /// Adds one particle's contacts of the last force pass (call in a fixed particle order).
    #[inline]
    pub fn add_contacts(&mut self, elastic: f64, contacts: u64, max_overlap_ratio: f64) {
        self.elastic_energy += elastic;
        self.contacts += contacts;
        self.max_overlap_ratio = self.max_overlap_ratio.max(max_overlap_ratio);
    }

    /// Books the walls' work by group (summed in group order) and the finiteness of the sums.
    pub fn finish(mut self, wall_work: &[f64]) -> Observables {
        self.wall_work = wall_work.iter().sum();
        self.finite &= self.elastic_energy.is_finite() && self.dissipated_energy.is_finite();
        self
    }
}

/// The charge of a drum (docs/mill.md, "Charge profile"). Angles in degrees, measured
/// in the drum's cross-section from straight down (gravity projected on the cross-section),
/// positive in the direction the shell moves at the bottom, so the rising side is positive.
#[derive(Clone, Copy, Debug, Default, PartialEq, Serialize, Deserialize)]
pub struct DrumProfile {
    /// Movable particles whose centre lies inside the drum (between its ends, within its radius).
    pub charge_mass: f64,
    /// Angle of the charge's centre of mass.
    pub com_angle: f64,
    /// Distance of the charge's centre of mass from the axis, m.
    pub com_radius: f64,
    /// 5th and 95th percentiles of the angles of the shell layer (particles whose surface is
    /// within half a radius of the shell): where the charge meets the shell at the bottom (toe,
    /// negative) and where it leaves the shell on the rising side (shoulder, positive).
    pub toe: f64,
    pub shoulder: f64,
    /// Torque-arm estimate of the drive power, M g r_com sin(θ_com) |ω|, W.
    pub torque_arm_power: f64,
}

/// One row of tracks.csv.
#[derive(Clone, Copy, Debug, PartialEq, Serialize, Deserialize)]
pub struct TrackRow {
    pub id: u32,
    pub position: DVec3,
    pub velocity: DVec3,
    pub angular_velocity: DVec3,
    /// Body-to-world rotation (identity for spheres).
    pub orientation: DQuat,
}

/// The tracked particles of `s`, by id.
pub fn tracks(s: &State) -> Vec<TrackRow> {
    let mut rows: Vec<TrackRow> = (0..s.len())
        .filter(|&i| s.track[i])
        .map(|i| TrackRow {
            id: s.id[i],
            position: s.pos[i],
            velocity: s.vel[i],
            angular_velocity: if s.omega.is_empty() { DVec3::ZERO } else { s.omega[i] },
            orientation: if s.orient.is_empty() { DQuat::IDENTITY } else { s.orient[i] },
        })
        .collect();
    rows.sort_by_key(|r| r.id);
    rows
}

/// A drum's directions across its axis: `down` (gravity's part across the axis, unit) and
/// `along` (the shell's motion at the bottom), with |g across the axis|; `None` when gravity
/// is along the axis (no profile).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct DrumFrame {
    pub down: DVec3,
    pub along: DVec3,
    pub g_across: f64,
}

impl DrumFrame {
    pub fn of(d: &tumble_plan::Drum, g: DVec3) -> Option<DrumFrame> {
        let g_plane = g - d.axis * g.dot(d.axis);
        if g_plane.length() <= 1e-12 * g.length().max(1e-300) {
            return None;
        }
        let down = g_plane.normalize();
        Some(DrumFrame { down, along: (d.axis * d.omega.signum()).cross(down), g_across: g_plane.length() })
    }

    /// Angle of `radial` (across the axis) from `down` towards `along`, degrees in (−180, 180].
    pub fn angle(&self, radial: DVec3) -> f64 {
        radial.dot(self.along).atan2(radial.dot(self.down)).to_degrees()
    }

    /// Whether a particle of radius `r` whose centre is `rho` from the axis is in the shell
    /// layer (its surface within half a radius of a shell of radius `shell`).
    pub fn in_shell_layer(shell: f64, rho: f64, r: f64) -> bool {
        shell - rho - r <= 0.5 * r
    }

    /// The profile from the charge's mass, Σ m·radial and the shell layer's 5th and 95th
    /// percentile angles (NaN when the layer is empty).
    pub fn profile(&self, d: &tumble_plan::Drum, t: f64, charge_mass: f64, moment: DVec3, toe: f64, shoulder: f64) -> DrumProfile {
        let mut p = DrumProfile { charge_mass, com_angle: f64::NAN, toe, shoulder, ..Default::default() };
        if charge_mass > 0.0 {
            let com = moment / charge_mass;
            p.com_radius = com.length();
            let theta = com.dot(self.along).atan2(com.dot(self.down));
            p.com_angle = theta.to_degrees();
            p.torque_arm_power = charge_mass * self.g_across * p.com_radius * theta.sin() * d.omega.abs() * d.timing.rate(t);
        }
        p
    }
}

/// The profile reported for a drum without gravity across its axis.
pub fn no_drum_profile() -> DrumProfile {
    DrumProfile { com_angle: f64::NAN, toe: f64::NAN, shoulder: f64::NAN, ..Default::default() }
}

/// The `q`-quantile of `n` sorted values as the profiles take it: the value of rank round(q (n − 1)).
pub fn quantile_rank(q: f64, n: usize) -> usize {
    ((q * (n - 1) as f64).round() as usize).min(n - 1)
}

/// The charge profile of each drum of `plan` from any backend's state at time `t` (NaN angles
/// without gravity across the axis).
pub fn drum_profiles(plan: &tumble_plan::Plan, s: &State, t: f64) -> Vec<DrumProfile> {
    plan.model
        .drums
        .iter()
        .map(|d| {
            let Some(frame) = DrumFrame::of(d, plan.model.gravity) else { return no_drum_profile() };
            let (mut mass, mut moment) = (0.0, DVec3::ZERO);
            let mut shell = Vec::new();
            for i in 0..s.len() {
                if s.inv_mass[i] == 0.0 {
                    continue;
                }
                let rel = s.pos[i] - d.point;
                let z = rel.dot(d.axis);
                let radial = rel - d.axis * z;
                let rho = radial.length();
                if z < 0.0 || z > d.length || rho > d.radius {
                    continue;
                }
                mass += s.mass[i];
                moment += radial * s.mass[i];
                if DrumFrame::in_shell_layer(d.radius, rho, s.radius[i]) {
                    shell.push(frame.angle(radial));
                }
            }
            shell.sort_by(f64::total_cmp);
            let pick = |q: f64| if shell.is_empty() { f64::NAN } else { shell[quantile_rank(q, shell.len())] };
            frame.profile(d, t, mass, moment, pick(0.05), pick(0.95))
        })
        .collect()
}
