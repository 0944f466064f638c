//! Particle arrays (structure of arrays), re-sorted by cell for locality.

use crate::history::HistorySlots;
use glam::{DQuat, DVec3};
use serde::{Deserialize, Serialize};
use tumble_broad::permute;
use tumble_plan::{CompiledScene, Drag};

/// Per-particle state. Arrays the plan does not need (rotation, drag) stay empty.
#[derive(Clone, Debug, Default, PartialEq, Serialize, Deserialize)]
pub struct State {
    pub id: Vec<u32>,
    pub pos: Vec<DVec3>,
    pub vel: Vec<DVec3>,
    /// Acceleration from the last force pass (contact, gravity, explicit drag).
    pub acc: Vec<DVec3>,
    pub omega: Vec<DVec3>,
    pub alpha: Vec<DVec3>,
    pub radius: Vec<f64>,
    /// Search reach: effect radius with cohesion, body radius without.
    pub reach: Vec<f64>,
    pub mass: Vec<f64>,
    /// Zero for fixed particles (infinite mass).
    pub inv_mass: Vec<f64>,
    pub inv_inertia: Vec<f64>,
    pub material: Vec<u16>,
    pub group: Vec<u16>,
    pub track: Vec<bool>,
    /// Stokes relaxation time τ_p, or the quadratic drag coefficient over mass.
    pub drag: Vec<f64>,
    /// Energy dissipated in this particle's contacts so far (each pair counted once).
    pub dissipated: Vec<f64>,
    /// Work done on this particle by the fluid so far.
    pub fluid_work: Vec<f64>,
    /// Tangential springs of this particle's contacts (empty without history).
    pub history: HistorySlots,
    /// Polyhedra only (empty in sphere-only scenes): shape index (`tumble_plan::SPHERE` for a
    /// sphere), body-to-world orientation and principal inverse inertia (zero for fixed bodies).
    pub shape: Vec<u16>,
    pub orient: Vec<DQuat>,
    pub inv_inertia_body: Vec<DVec3>,
    /// Periodic images: how many box lengths each particle has been wrapped back by, per axis
    /// (+1 when it left through the max side), so `pos + image ∘ L` is its unwrapped position.
    /// Empty when no axis is periodic.
    pub image: Vec<[i32; 3]>,
}

impl State {
    pub fn from_scene(scene: &CompiledScene) -> State {
        State::from_particles(&scene.plan, &scene.particles, 0)
    }

    /// The arrays of particles `p` of `plan`'s model, with ids from `first_id` on.
    pub fn from_particles(plan: &tumble_plan::Plan, p: &tumble_plan::InitialParticles, first_id: u32) -> State {
        let n = p.len();
        let mut s = State::default();
        for i in 0..n {
            let density = plan.model.materials[p.material[i] as usize].density;
            let m = density * p.volume[i];
            s.id.push(first_id + i as u32);
            s.pos.push(p.position[i]);
            s.vel.push(p.velocity[i]);
            s.acc.push(DVec3::ZERO);
            s.radius.push(p.radius[i]);
            s.reach.push(if plan.model.cohesion { p.effect_radius[i].max(p.radius[i]) } else { p.radius[i] });
            s.mass.push(m);
            s.inv_mass.push(if p.fixed[i] { 0.0 } else { 1.0 / m });
            s.material.push(p.material[i]);
            s.group.push(p.group[i]);
            s.track.push(p.track[i]);
            s.dissipated.push(0.0);
            if plan.model.rotation {
                s.omega.push(p.angular_velocity[i]);
                s.alpha.push(DVec3::ZERO);
                let principal = match p.shape[i] {
                    tumble_plan::SPHERE => DVec3::splat(0.4 * m * p.radius[i] * p.radius[i]),
                    k => plan.model.shapes[k as usize].body.principal_inertia(density),
                };
                let inv = if p.fixed[i] { DVec3::ZERO } else { principal.recip() };
                // The scalar serves spheres and caps the rolling couple: the largest (softest) axis.
                s.inv_inertia.push(inv.max_element());
                if plan.model.polyhedra {
                    s.shape.push(p.shape[i]);
                    s.orient.push(p.orientation[i]);
                    s.inv_inertia_body.push(inv);
                }
            }
            if plan.fluid_works_on_particles() {
                s.fluid_work.push(0.0);
            }
            if let Some(f) = &plan.model.fluid {
                s.drag.push(match f.drag {
                    Drag::Stokes { viscosity } => {
                        tumble_contact::stokes_relaxation_time(plan.model.materials[p.material[i] as usize].density, 2.0 * p.radius[i], viscosity)
                    }
                    Drag::Quadratic { coefficient } => coefficient / m,
                });
            }
        }
        if plan.model.domain.periodic.iter().any(|&p| p) {
            s.image = vec![[0; 3]; n];
        }
        s.history = HistorySlots::new(n, if plan.model.history { plan.tuning.history_slots } else { 0 }, plan.model.rolling_springs());
        s
    }

    /// Rotational kinetic energy ½ ω·I ω of movable particle `i` (principal inertia for polyhedra).
    pub fn rotational_energy(&self, i: usize) -> f64 {
        if self.orient.is_empty() {
            return 0.5 * self.omega[i].length_squared() / self.inv_inertia[i];
        }
        let w = self.orient[i].inverse() * self.omega[i];
        0.5 * (w * w / self.inv_inertia_body[i]).element_sum()
    }

    /// Angular momentum I ω about the centre of movable particle `i` (world frame).
    pub fn spin_momentum(&self, i: usize) -> DVec3 {
        if self.orient.is_empty() {
            return self.omega[i] / self.inv_inertia[i];
        }
        let q = self.orient[i];
        q * ((q.inverse() * self.omega[i]) / self.inv_inertia_body[i])
    }

    /// The unwrapped position of particle `i` in a domain of extent `l` (its position where no
    /// axis is periodic).
    #[inline]
    pub fn unwrapped(&self, i: usize, l: DVec3) -> DVec3 {
        match self.image.get(i) {
            Some(n) => self.pos[i] + DVec3::new(n[0] as f64, n[1] as f64, n[2] as f64) * l,
            None => self.pos[i],
        }
    }

    pub fn len(&self) -> usize {
        self.pos.len()
    }

    pub fn is_empty(&self) -> bool {
        self.pos.is_empty()
    }

    /// Applies `f` to every per-particle array, so reorderings cannot miss one.
    fn for_each_array(
        &mut self,
        mut f3: impl FnMut(&mut Vec<DVec3>),
        mut f1: impl FnMut(&mut Vec<f64>),
        mut fu: impl FnMut(&mut Vec<u32>),
        mut fs: impl FnMut(&mut Vec<u16>),
        mut fb: impl FnMut(&mut Vec<bool>),
        mut fq: impl FnMut(&mut Vec<DQuat>),
        mut fi: impl FnMut(&mut Vec<[i32; 3]>),
    ) {
        for v in [&mut self.pos, &mut self.vel, &mut self.acc, &mut self.omega, &mut self.alpha, &mut self.inv_inertia_body] {
            if !v.is_empty() {
                f3(v);
            }
        }
        for v in [
            &mut self.radius,
            &mut self.reach,
            &mut self.mass,
            &mut self.inv_mass,
            &mut self.inv_inertia,
            &mut self.drag,
            &mut self.dissipated,
            &mut self.fluid_work,
        ] {
            if !v.is_empty() {
                f1(v);
            }
        }
        fu(&mut self.id);
        fs(&mut self.material);
        fs(&mut self.group);
        if !self.shape.is_empty() {
            fs(&mut self.shape);
        }
        fq(&mut self.orient);
        fb(&mut self.track);
        if !self.image.is_empty() {
            fi(&mut self.image);
        }
    }

    /// Reorders every array by `order` (new slot k holds old particle order[k]).
    pub fn permute(&mut self, order: &[u32]) {
        self.for_each_array(
            |v| permute(v, order),
            |v| permute(v, order),
            |v| permute(v, order),
            |v| permute(v, order),
            |v| permute(v, order),
            |v| {
                if !v.is_empty() {
                    permute(v, order)
                }
            },
            |v| permute(v, order),
        );
        self.history.permute(order);
    }

    /// The id the next particle added gets: after every id held, and at least the count.
    pub fn next_id(&self) -> u32 {
        self.id.iter().map(|&id| id + 1).max().unwrap_or(0).max(self.len() as u32)
    }

    /// Appends `other`'s particles (arrays of the same model) after this state's; they hold no springs.
    pub fn append(&mut self, mut other: State) {
        let n = self.len() + other.len();
        self.pos.append(&mut other.pos);
        self.vel.append(&mut other.vel);
        self.acc.append(&mut other.acc);
        self.omega.append(&mut other.omega);
        self.alpha.append(&mut other.alpha);
        self.inv_inertia_body.append(&mut other.inv_inertia_body);
        self.radius.append(&mut other.radius);
        self.reach.append(&mut other.reach);
        self.mass.append(&mut other.mass);
        self.inv_mass.append(&mut other.inv_mass);
        self.inv_inertia.append(&mut other.inv_inertia);
        self.drag.append(&mut other.drag);
        self.dissipated.append(&mut other.dissipated);
        self.fluid_work.append(&mut other.fluid_work);
        self.id.append(&mut other.id);
        self.material.append(&mut other.material);
        self.group.append(&mut other.group);
        self.shape.append(&mut other.shape);
        self.orient.append(&mut other.orient);
        self.track.append(&mut other.track);
        self.image.append(&mut other.image);
        self.history.resize(n);
    }

    /// Keeps only the particles for which `keep` is true, preserving order.
    pub fn retain(&mut self, keep: &[bool]) {
        fn filter<T: Copy>(v: &mut Vec<T>, keep: &[bool]) {
            let mut k = 0;
            v.retain(|_| {
                k += 1;
                keep[k - 1]
            });
        }
        self.for_each_array(
            |v| filter(v, keep),
            |v| filter(v, keep),
            |v| filter(v, keep),
            |v| filter(v, keep),
            |v| filter(v, keep),
            |v| filter(v, keep),
            |v| filter(v, keep),
        );
        self.history.retain(keep);
    }
}
