//! The step: broad phase, contacts, body forces, integration (ARCHITECTURE.md, "The step (CPU)").

use crate::CpuSimulation;
use crate::forces::{ContactInputs, PairOut, PairSprings, SortedEntry, SpringSlots, WORN_SLOTS, WallLoad, Worn, gather, pair_contact};
use crate::neighbours::NeighbourList;
use glam::DVec3;
use rayon::prelude::*;
use tumble_broad::CellGrid;
use tumble_contact::{FlowField, quadratic_drag};
use tumble_geom::PeriodicBox;
use tumble_integrate::{
    Integrator, euler, free_rotation, implicit_drag, symplectic_euler, verlet_force_velocity, verlet_kick, verlet_kick_drift,
    world_inverse_inertia_times,
};
use tumble_plan::Drag;
use tumble_state::{HistoryOverflow, RollingHalf, Spring, TangentialHalf};

/// Per-particle body-force context, copied out of the plan once per pass.
#[derive(Clone, Copy)]
struct Body {
    gravity: DVec3,
    drag: Option<(Drag, FlowField)>,
}

impl Body {
    /// Explicit drag acceleration and force at (x, v) for a particle with drag parameter `k`.
    #[inline]
    fn drag_acc(&self, x: DVec3, v: DVec3, k: f64) -> DVec3 {
        match self.drag {
            None => DVec3::ZERO,
            Some((Drag::Stokes { .. }, flow)) => (flow.velocity(x) - v) / k,
            Some((Drag::Quadratic { .. }, _)) => quadratic_drag(k, v),
        }
    }
}

impl CpuSimulation {
    fn body(&self) -> Body {
        Body { gravity: self.plan.model.gravity, drag: self.plan.model.fluid.map(|f| (f.drag, f.flow)) }
    }

    /// Rebuilds the neighbour list when a particle may have crossed the skin;
    /// at a rebuild at least `resort_interval` steps after the last re-sort, the
    /// particle arrays are re-sorted by cell first.
    pub(crate) fn broad_phase(&mut self) {
        let domain = self.plan.model.domain;
        // Particle moves ≤ skin/2 and wall sweeps ≤ skin/2 keep every listed candidate valid.
        if !self.walls_moved_too_far() && !self.pool.install(|| self.neighbours.needs_rebuild(&self.state.pos, &domain)) {
            return;
        }
        if self.last_resort.is_none_or(|last| self.step >= last + self.plan.tuning.resort_interval as u64) {
            self.grid = CellGrid::new(&self.grid_bounds(), self.plan.tuning.cell_size + self.plan.tuning.skin);
            self.grid.build(&self.state.pos);
            let order = self.grid.order().to_vec();
            self.state.permute(&order);
            self.last_resort = Some(self.step);
        }
        self.build_list();
    }

    /// Builds the neighbour list over the current positions and array order (no re-sort):
    /// a function of the positions, the array order and the walls' pose alone.
    pub(crate) fn build_list(&mut self) {
        let domain = self.plan.model.domain;
        self.grid = CellGrid::new(&self.grid_bounds(), self.plan.tuning.cell_size + self.plan.tuning.skin);
        self.grid.build(&self.state.pos);
        let (pos, reach) = (&self.state.pos, &self.state.reach);
        let order = self.grid.order();
        let sorted = &mut self.sorted;
        let (grid, state, list, walls) = (&self.grid, &self.state, &mut self.neighbours, &self.walls);
        self.pool.install(|| {
            order.par_iter().map(|&i| SortedEntry { pos: pos[i as usize], reach: reach[i as usize] }).collect_into_vec(sorted);
            list.build(grid, sorted, state, &domain, walls);
        });
        self.walls_built_at = self.walls_time;
        for s in &mut self.servos {
            s.built_offset = s.offset;
        }
    }

    /// Moves the walls to their pose at time `t` (servo walls to their current offset, or with
    /// `built` to their offset at the last list build).
    pub(crate) fn place_walls_as(&mut self, t: f64, built: bool) {
        self.walls_time = t;
        if self.moving_walls {
            self.pose_moving_walls(t, built);
        }
    }

    /// [`CpuSimulation::place_walls_as`] for the walls that move (kept out of line: the step's
    /// hot loops do not need it inlined beside them).
    #[inline(never)]
    fn pose_moving_walls(&mut self, t: f64, built: bool) {
        let mut walls = std::mem::take(&mut self.walls);
        for (now, wall) in walls.iter_mut().zip(&self.plan.model.walls) {
            if wall.motion.is_some() {
                now.shape = wall.shape_at(t);
                now.motion = wall.motion_at(t);
            } else {
                self.place_servo_wall(now, wall, built);
            }
        }
        self.walls = walls;
    }

    /// Moves the walls to their pose at time `t`.
    pub(crate) fn place_walls(&mut self, t: f64) {
        self.place_walls_as(t, false);
    }

    /// True when some wall may have swept more than half the skin since the last list build.
    fn walls_moved_too_far(&self) -> bool {
        let elapsed = self.walls_time - self.walls_built_at;
        self.moving_walls && self.plan.model.walls.iter().any(|w| w.travel_speed * elapsed > 0.5 * self.plan.tuning.skin)
    }

    /// The region the grid must cover: the whole domain along periodic axes (cells must tile
    /// it), the particles' bounding box along the others, so a large, sparse domain stays cheap.
    fn grid_bounds(&self) -> PeriodicBox {
        let domain = self.plan.model.domain;
        let (lo, hi) = self.pool.install(|| {
            self.state
                .pos
                .par_iter()
                .fold(|| (DVec3::INFINITY, DVec3::NEG_INFINITY), |(lo, hi), &x| (lo.min(x), hi.max(x)))
                .reduce(|| (DVec3::INFINITY, DVec3::NEG_INFINITY), |(a, b), (c, d)| (a.min(c), b.max(d)))
        });
        let mut bounds = domain;
        for k in 0..3 {
            if !domain.periodic[k] && lo[k] <= hi[k] {
                bounds.min[k] = lo[k].max(domain.min[k]);
                bounds.max[k] = hi[k].min(domain.max[k]).max(bounds.min[k] + self.plan.tuning.cell_size + self.plan.tuning.skin);
            }
        }
        bounds
    }

    /// The contact pass: every listed pair once, then each particle gathers its own sum.
    /// `commit` swaps in the springs it computed (the t = 0 pass only seeds forces).
    fn contact_pass(&mut self, use_eval: bool, commit: bool) {
        let periodic = self.plan.model.domain.periodic.iter().any(|&p| p);
        // Monomorphised on the plan's features: a scene without them runs none of their code.
        macro_rules! dispatch {
            ($($rot:literal, $coh:literal, $per:literal);*) => {
                match (self.plan.model.rotation, self.plan.model.cohesion, periodic, self.plan.model.history) {
                    $(
                        ($rot, $coh, $per, false) => self.contact_pass_with::<$rot, $coh, $per, false, false>(use_eval),
                        ($rot, $coh, $per, true) => self.contact_pass_with::<$rot, $coh, $per, true, false>(use_eval),
                    )*
                }
            };
        }
        if self.plan.model.polyhedra {
            // Polyhedra always rotate and never cohere (the plan refuses cohesion with them).
            match (periodic, self.plan.model.history) {
                (false, false) => self.contact_pass_with::<true, false, false, false, true>(use_eval),
                (false, true) => self.contact_pass_with::<true, false, false, true, true>(use_eval),
                (true, false) => self.contact_pass_with::<true, false, true, false, true>(use_eval),
                (true, true) => self.contact_pass_with::<true, false, true, true, true>(use_eval),
            }
        } else {
            dispatch!(false, false, false; true, false, false; false, true, false; true, true, false;
                      false, false, true; true, false, true; false, true, true; true, true, true);
        }
        if self.plan.model.history && commit {
            std::mem::swap(&mut self.state.history, &mut self.history_next);
            self.check_history_capacity();
        }
        if !self.plan.model.walls.is_empty() {
            // Serial, in array order: the same sums for any thread count.
            self.group_power.fill(0.0);
            self.group_force.fill(DVec3::ZERO);
            self.group_torque.fill(DVec3::ZERO);
            for (&w, load) in self.neighbours.wall_entries.iter().zip(&self.candidate_loads) {
                let g = self.plan.model.walls[w as usize].group as usize;
                self.group_power[g] += load.power;
                self.group_force[g] += load.force;
                self.group_torque[g] += load.torque;
            }
        }
        if commit && self.has_servos() {
            self.drive_servos();
        }
        if commit && self.wearing {
            // Serial, in array order: the same sums for any thread count.
            for (&w, worn) in self.neighbours.wall_entries.iter().zip(&self.candidate_worn) {
                for &(t, volume) in worn.iter().filter(|e| e.1 > 0.0) {
                    self.wear[w as usize][t as usize] += volume;
                }
            }
        }
        if self.working_walls && commit {
            let dt = self.plan.model.dt;
            for (work, p) in self.group_work.iter_mut().zip(&self.group_power) {
                *work += p * dt;
            }
        }
    }

    fn contact_pass_with<const ROT: bool, const COH: bool, const PERIODIC: bool, const HIST: bool, const POLY: bool>(&mut self, use_eval: bool) {
        let (vel, omega) = if use_eval { (&self.eval_vel, &self.eval_omega) } else { (&self.state.vel, &self.state.omega) };
        let inputs = ContactInputs { model: &self.plan.model, state: &self.state, vel, omega, walls: &self.walls };
        let n = self.state.len();
        let (list, pair_out, pair_spring, pair_roll, sums) =
            (&self.neighbours, &mut self.pair_out, &mut self.pair_spring, &mut self.pair_roll, &mut self.sums);
        let next = &mut self.history_next;
        // Each particle's share of the wall-load slots (empty without walls).
        let loads = &mut self.candidate_loads;
        loads.clear();
        if !self.walls.is_empty() {
            loads.resize(list.wall_entries.len(), WallLoad::default());
        }
        // Each particle's share of the wear slots (empty unless a wall wears).
        let worn = &mut self.candidate_worn;
        worn.clear();
        if self.wearing {
            worn.resize(list.wall_entries.len(), [(0, 0.0); WORN_SLOTS]);
        }
        let chunks = per_particle(loads, worn, list, n);
        self.pool.install(|| {
            let pairs = list.pairs.par_iter().with_min_len(1024);
            if HIST {
                if next.rolling {
                    // Three outputs per pair: written in place, in list order.
                    let m = list.pairs.len();
                    pair_out.resize(m, PairOut::default());
                    pair_spring.resize(m, TangentialHalf::default());
                    pair_roll.resize(m, RollingHalf::default());
                    pair_out.par_iter_mut().zip(pair_spring.par_iter_mut()).zip(pair_roll.par_iter_mut()).zip(pairs).for_each(
                        |(((out, t), r), p)| {
                            let mut spring = Spring::default();
                            *out = pair_contact::<ROT, COH, PERIODIC, HIST, POLY>(&inputs, p[0] as usize, p[1] as usize, &mut spring);
                            *t = spring.tangential();
                            *r = spring.rolling();
                        },
                    );
                } else {
                    pair_roll.clear();
                    pairs
                        .map(|p| {
                            let mut spring = Spring::default();
                            (pair_contact::<ROT, COH, PERIODIC, HIST, POLY>(&inputs, p[0] as usize, p[1] as usize, &mut spring), spring.tangential())
                        })
                        .unzip_into_vecs(pair_out, pair_spring);
                }
                let springs = PairSprings { spring: pair_spring, roll: pair_roll };
                next.resize(n);
                let slots = next.slots;
                // Each particle's rolling slots, or empty ones when the plan keeps none.
                let rolls = if next.rolling {
                    rayon::iter::Either::Left(next.roll.par_chunks_mut(slots))
                } else {
                    rayon::iter::Either::Right((0..n).into_par_iter().map(|_| <&mut [RollingHalf]>::default()))
                };
                (0..n)
                    .into_par_iter()
                    .zip(next.key.par_chunks_mut(slots))
                    .zip(next.spring.par_chunks_mut(slots))
                    .zip(rolls)
                    .zip(next.count.par_iter_mut())
                    .zip(chunks.into_par_iter())
                    .with_min_len(512)
                    .map(|(((((i, key), spring), roll), count), (power, worn))| {
                        let sum = gather::<ROT, COH, HIST, POLY>(&inputs, list, pair_out, springs, i, SpringSlots { key, spring, roll }, power, worn);
                        *count = sum.springs.min(slots as u32) as u16;
                        sum
                    })
                    .collect_into_vec(sums);
            } else {
                pairs
                    .map(|p| pair_contact::<ROT, COH, PERIODIC, HIST, POLY>(&inputs, p[0] as usize, p[1] as usize, &mut Spring::default()))
                    .collect_into_vec(pair_out);
                (0..n)
                    .into_par_iter()
                    .zip(chunks.into_par_iter())
                    .with_min_len(512)
                    .map(|(i, (power, worn))| {
                        gather::<ROT, COH, HIST, POLY>(
                            &inputs,
                            list,
                            pair_out,
                            PairSprings { spring: &[], roll: &[] },
                            i,
                            SpringSlots { key: &mut [], spring: &mut [], roll: &mut [] },
                            power,
                            worn,
                        )
                    })
                    .collect_into_vec(sums);
            }
        });
    }

    /// Stops the run (see `advance`) when a particle kept more springs than it has slots.
    fn check_history_capacity(&mut self) {
        let slots = self.history_next.slots;
        // In parallel: this runs every step; position_first keeps the answer independent of threads.
        let sums = &self.sums;
        if let Some(i) = self.pool.install(|| sums.par_iter().with_min_len(4096).position_first(|s| s.springs as usize > slots)) {
            self.history_overflow = Some(HistoryOverflow { id: self.state.id[i], contacts: self.sums[i].springs as usize, slots, step: self.step });
        }
    }

    /// Accelerations from contact sums plus gravity and explicit drag, at velocities `vel`.
    fn accelerations(&mut self, use_eval: bool, drag_explicit: bool) {
        let body = self.body();
        let dt = self.plan.model.dt;
        let s = &mut self.state;
        let vel = if use_eval { &self.eval_vel } else { &s.vel };
        let sums = &self.sums;
        let (pos, inv_mass, drag) = (&s.pos, &s.inv_mass, &s.drag);
        let fluid_work = &mut s.fluid_work;
        let external = &self.external;
        self.pool.install(|| {
            s.acc.par_iter_mut().enumerate().for_each(|(i, a)| {
                *a = if inv_mass[i] == 0.0 { DVec3::ZERO } else { sums[i].force * inv_mass[i] + body.gravity };
            });
            if drag_explicit && body.drag.is_some() {
                s.acc.par_iter_mut().zip(fluid_work.par_iter_mut()).enumerate().for_each(|(i, (a, w))| {
                    if inv_mass[i] != 0.0 {
                        let ad = body.drag_acc(pos[i], vel[i], drag[i]);
                        *a += ad;
                        *w += ad.dot(vel[i]) / inv_mass[i] * dt;
                    }
                });
            }
            if !external.is_empty() {
                // Held forces (a coupled fluid's), with their work booked as the fluid's.
                let id = &s.id;
                s.acc.par_iter_mut().zip(fluid_work.par_iter_mut()).enumerate().for_each(|(i, (a, w))| {
                    if let Some(&f) = external.get(id[i] as usize)
                        && inv_mass[i] != 0.0
                    {
                        *a += f * inv_mass[i];
                        *w += f.dot(vel[i]) * dt;
                    }
                });
            }
            if !s.orient.is_empty() {
                // α = R I⁻¹ Rᵀ τ; the gyroscopic term lives in the torque-free drift (free_rotation).
                let (orient, inv_body) = (&s.orient, &s.inv_inertia_body);
                s.alpha.par_iter_mut().enumerate().for_each(|(i, al)| *al = world_inverse_inertia_times(orient[i], inv_body[i], sums[i].torque));
            } else if !s.alpha.is_empty() {
                let inv_inertia = &s.inv_inertia;
                s.alpha.par_iter_mut().enumerate().for_each(|(i, al)| *al = sums[i].torque * inv_inertia[i]);
            }
        });
        for (d, sum) in s.dissipated.iter_mut().zip(sums) {
            *d += sum.dissipation * dt;
        }
    }

    /// Forces at t = 0, so Verlet's first half kick has an acceleration.
    pub(crate) fn initial_forces(&mut self) {
        self.place_walls(self.time());
        self.contact_pass(false, false);
        let explicit = !self.plan.model.integrator.implicit_drag();
        // The t = 0 pass only seeds accelerations: it must not count dissipation or fluid work.
        let saved = (self.state.dissipated.clone(), self.state.fluid_work.clone());
        self.accelerations(false, explicit);
        (self.state.dissipated, self.state.fluid_work) = saved;
    }

    /// One time step with the plan's integrator.
    pub fn step_once(&mut self) {
        let dt = self.plan.model.dt;
        self.advance_servos();
        match self.plan.model.integrator {
            Integrator::Verlet => {
                {
                    let s = &mut self.state;
                    let (acc, alpha) = (&s.acc, &s.alpha);
                    let inv_mass = &s.inv_mass;
                    self.pool.install(|| {
                        s.pos.par_iter_mut().zip(s.vel.par_iter_mut()).enumerate().for_each(|(i, (x, v))| {
                            if inv_mass[i] != 0.0 {
                                (*x, *v) = verlet_kick_drift(*x, *v, acc[i], dt);
                            }
                        });
                        s.omega.par_iter_mut().enumerate().for_each(|(i, w)| *w += alpha[i] * (0.5 * dt));
                    });
                }
                self.drift_orientations(dt);
                self.boundaries();
                // Forces at x_{n+1} see the walls at t_{n+1}.
                self.place_walls((self.step + 1) as f64 * dt);
                self.broad_phase();
                // Velocity-dependent forces see the second-order estimate of v_{n+1}.
                let s = &self.state;
                let (eval_vel, eval_omega) = (&mut self.eval_vel, &mut self.eval_omega);
                self.pool.install(|| {
                    s.vel.par_iter().zip(&s.acc).map(|(&v, &a)| verlet_force_velocity(v, a, dt)).collect_into_vec(eval_vel);
                    s.omega.par_iter().zip(&s.alpha).map(|(&w, &a)| verlet_force_velocity(w, a, dt)).collect_into_vec(eval_omega);
                });
                self.contact_pass(true, true);
                self.accelerations(true, true);
                let s = &mut self.state;
                let (acc, alpha, inv_mass) = (&s.acc, &s.alpha, &s.inv_mass);
                self.pool.install(|| {
                    s.vel.par_iter_mut().enumerate().for_each(|(i, v)| {
                        if inv_mass[i] != 0.0 {
                            *v = verlet_kick(*v, acc[i], dt);
                        }
                    });
                    s.omega.par_iter_mut().enumerate().for_each(|(i, w)| *w += alpha[i] * (0.5 * dt));
                });
            }
            integrator => {
                self.place_walls(self.step as f64 * dt);
                self.broad_phase();
                self.contact_pass(false, true);
                let implicit = integrator.implicit_drag();
                self.accelerations(false, !implicit);
                let body = self.body();
                let s = &mut self.state;
                let (acc, inv_mass, drag) = (&s.acc, &s.inv_mass, &s.drag);
                let symplectic = integrator == Integrator::ImplicitDragSymplectic;
                let mut work = Vec::new();
                self.pool.install(|| {
                    s.pos
                        .par_iter_mut()
                        .zip(s.vel.par_iter_mut())
                        .enumerate()
                        .map(|(i, (x, v))| {
                            if inv_mass[i] == 0.0 {
                                return 0.0;
                            }
                            let v_old = *v;
                            match integrator {
                                Integrator::Euler => (*x, *v) = euler(*x, *v, acc[i], dt),
                                Integrator::SymplecticEuler => (*x, *v) = symplectic_euler(*x, *v, acc[i], dt),
                                _ => {
                                    let (tau, u) = match body.drag {
                                        None => (f64::INFINITY, DVec3::ZERO),
                                        Some((Drag::Stokes { .. }, flow)) => (drag[i], flow.velocity(*x)),
                                        // Quadratic drag linearised at the current speed: τ = m / (α|v|).
                                        Some((Drag::Quadratic { .. }, _)) => (1.0 / (drag[i] * v.length()), DVec3::ZERO),
                                    };
                                    (*x, *v) = implicit_drag(*x, *v, acc[i], tau, u, dt, symplectic);
                                    if tau.is_finite() {
                                        // Work of the implicit drag m(u − v_new)/τ over the step.
                                        return (u - *v).dot(v_old + *v) * (0.5 * dt / (tau * inv_mass[i]));
                                    }
                                }
                            }
                            0.0
                        })
                        .collect_into_vec(&mut work);
                    s.omega.par_iter_mut().zip(s.alpha.par_iter()).for_each(|(w, a)| *w += *a * dt);
                });
                if implicit && body.drag.is_some() {
                    for (w, dw) in s.fluid_work.iter_mut().zip(&work) {
                        *w += dw;
                    }
                }
                self.drift_orientations(dt);
            }
        }
        self.step += 1;
        if self.plan.model.integrator.forces_first() {
            self.boundaries();
        }
    }

    /// Turns every body by its spin over Δt, torque-free (polyhedra only): the world angular
    /// momentum is held while the orientation and ω follow the free-body motion.
    fn drift_orientations(&mut self, dt: f64) {
        let s = &mut self.state;
        if s.orient.is_empty() {
            return;
        }
        let inv_body = &s.inv_inertia_body;
        self.pool.install(|| {
            s.orient.par_iter_mut().zip(s.omega.par_iter_mut()).enumerate().for_each(|(i, (q, w))| {
                if inv_body[i] != DVec3::ZERO {
                    (*q, *w) = free_rotation(*q, inv_body[i], *w, dt);
                }
            });
        });
    }

    /// Wraps periodic axes, removes particles that left through other sides and deletes those
    /// inside an outlet (booked per outlet in slot order, the same for any thread count).
    fn boundaries(&mut self) {
        let domain = self.plan.model.domain;
        let outlets = &self.plan.model.outlets;
        let s = &mut self.state;
        if domain.periodic.iter().any(|&p| p) {
            let image = &mut s.image;
            self.pool.install(|| s.pos.par_iter_mut().zip(image.par_iter_mut()).for_each(|(x, n)| *x = domain.wrap_counting(*x, n)));
        }
        if domain.periodic.iter().all(|&p| p) && outlets.is_empty() {
            return;
        }
        let stays = |x: DVec3| domain.contains(x) && !outlets.iter().any(|o| o.region.contains(x));
        if self.pool.install(|| s.pos.par_iter().all(|&x| stays(x))) {
            return;
        }
        let keep: Vec<bool> = s.pos.iter().map(|&x| stays(x)).collect();
        for (i, _) in keep.iter().enumerate().filter(|(_, k)| !**k) {
            // Outside the domain it is removed, whatever outlet also holds it.
            match outlets.iter().position(|o| o.region.contains(s.pos[i])).filter(|_| domain.contains(s.pos[i])) {
                Some(k) => {
                    self.outlet_tally[k].count += 1;
                    self.outlet_tally[k].mass += s.mass[i];
                }
                None => self.removed += 1,
            }
        }
        s.retain(&keep);
        // Everything indexed by the old arrays is stale until the next list build and force pass.
        self.neighbours.invalidate();
        self.sums.clear();
        self.pair_out.clear();
    }
}

/// `loads` and `worn` (each one entry per wall candidate of the list, or empty) cut into each
/// particle's shares, in one pass.
fn per_particle<'a>(loads: &'a mut [WallLoad], worn: &'a mut [Worn], list: &NeighbourList, n: usize) -> Vec<(&'a mut [WallLoad], &'a mut [Worn])> {
    let mut chunks = Vec::with_capacity(n);
    let (mut loads, mut worn) = (loads, worn);
    for i in 0..n {
        let len = if loads.is_empty() { 0 } else { (list.wall_start[i + 1] - list.wall_start[i]) as usize };
        let (mine, tail) = std::mem::take(&mut loads).split_at_mut(len);
        let wear_len = if worn.is_empty() { 0 } else { len };
        let (my_wear, wear_tail) = std::mem::take(&mut worn).split_at_mut(wear_len);
        chunks.push((mine, my_wear));
        (loads, worn) = (tail, wear_tail);
    }
    chunks
}
