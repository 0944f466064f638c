//! The fluid phase: its particles, its grid and the symplectic step.

use rayon::prelude::*;
use tumble_geom::DVec3;

use crate::buffers::{BufferBooks, exchange};
use crate::eos::Tait;
use crate::floating::{BodyMove, BodyState};
use crate::limits::{FluidFault, TimeStepLimits};
use crate::neighbours::{FluidGrid, rebuild_distance};
use crate::particles::{FluidParticles, ParticleKind};
use crate::rates::{Method, PairInputs, Rates, WallsAt, body_loads, evaluate, prepare};
use crate::settings::{FluidSettings, Viscosity, WallRole};

/// What a coupled step asks of the solids beside the fluid (held where they are over the step).
pub trait CoupledSolids: Send {
    /// Each particle's fluid fraction ε (in the particles' order; 1 for walls).
    fn fraction(&mut self, fluid: &FluidParticles) -> Vec<f64>;
    /// The solids' force on each particle (in their order), given the fractions and each
    /// particle's fluid–fluid acceleration θ at the step's start.
    fn reaction(&mut self, fluid: &FluidParticles, fraction: &[f64], theta: &[DVec3]) -> Vec<DVec3>;
}

/// The fluid's sums at one instant (the observables of an output row).
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct FluidObservables {
    pub fluid_particles: usize,
    pub mass: f64,
    pub momentum: DVec3,
    pub kinetic_energy: f64,
    /// −Σ m g·x (gravity only, not the body force).
    pub potential_energy: f64,
    /// Σ m e(ρ), the energy the equation of state stores in compression.
    pub elastic_energy: f64,
    /// max |ρ/ρ₀ − 1| over the fluid.
    pub largest_density_deviation: f64,
    pub largest_speed: f64,
}

/// How the moving walls and floating bodies carry their particles over one half step, from `t0`
/// to `t0 + half`.
struct WallMoves<'a> {
    settings: &'a FluidSettings,
    t0: f64,
    bodies: &'a [BodyMove],
}

/// Moves every particle by half a step: a fluid particle with the advection velocity `fluid`
/// returns after updating its velocity and density in place, a wall particle with its velocity,
/// or by its moving wall's motion or its floating body's move (which then give its velocity).
/// Returns the particle that moved furthest (the lowest index among equals) and how far.
fn drift(
    grid: &FluidGrid,
    p: &mut FluidParticles,
    walls: &WallMoves,
    half: f64,
    fluid: impl Fn(usize, &mut DVec3, &mut f64) -> DVec3 + Sync,
) -> (usize, f64) {
    let (wall, settings, t0) = (&p.wall, walls.settings, walls.t0);
    p.position
        .par_iter_mut()
        .zip(p.velocity.par_iter_mut())
        .zip(p.density.par_iter_mut())
        .zip(p.kind.par_iter())
        .enumerate()
        .map(|(i, (((x, v), rho), k))| {
            let step = match (k, settings.wall_role(wall[i])) {
                (ParticleKind::Fluid, _) => half * fluid(i, v, rho),
                (ParticleKind::Wall, WallRole::Moving(w)) => {
                    let motion = &settings.moving_walls[w];
                    let to = motion.advance(*x, t0, t0 + half);
                    *v = motion.velocity_at(to, t0 + half);
                    to - *x
                }
                (ParticleKind::Wall, WallRole::Body(b)) => {
                    let body = &walls.bodies[b];
                    let (step, velocity) = body.carry(grid.separation(*x, body.from));
                    *v = velocity;
                    step
                }
                (ParticleKind::Wall, WallRole::Inflow(k)) => {
                    let inflow = &settings.inflows[k];
                    let plane = settings.dimension == crate::Dimension::Two;
                    *v = inflow.velocity_at(*x, t0 + half, plane);
                    inflow.travel(*x, t0, t0 + half, plane)
                }
                (ParticleKind::Wall, WallRole::Fixed | WallRole::Outflow(_)) => half * *v,
            };
            *x = grid.wrap(*x + step);
            (i, step.length())
        })
        .reduce(|| (usize::MAX, -1.0), |a, b| if b.1 > a.1 || (b.1 == a.1 && b.0 < a.0) { b } else { a })
}

/// The fluid's section of a snapshot: everything a step reads that is not settings. The arrays
/// are kept in their sorted order, so a restored phase re-sorts exactly as the saved one would
/// have, and continues bit-identically.
#[derive(Clone, Debug, PartialEq, serde::Serialize, serde::Deserialize)]
pub struct FluidSnapshot {
    pub time: f64,
    pub steps: u64,
    pub particles: FluidParticles,
    /// The positions the neighbour lists were built from, or none when the next step rebuilds them.
    pub list_positions: Option<Vec<DVec3>>,
    /// The floating bodies, in the settings' order.
    #[serde(default)]
    pub bodies: Vec<BodyState>,
    /// What has passed through the buffers, and the id the next new particle takes.
    #[serde(default)]
    pub buffers: BufferBooks,
    #[serde(default)]
    pub next_id: u32,
}

/// A weakly compressible SPH fluid: fluid and wall particles, stepped by the symplectic scheme.
pub struct FluidPhase {
    settings: FluidSettings,
    method: Method,
    grid: FluidGrid,
    particles: FluidParticles,
    inputs: PairInputs,
    rates: Rates,
    start_velocity: Vec<DVec3>,
    start_density: Vec<f64>,
    bodies: Vec<BodyState>,
    /// The particles of the floating bodies (sorted indices, ascending), found after each sort.
    body_particles: Vec<u32>,
    buffers: BufferBooks,
    /// The id the next particle an inflow buffer makes takes.
    next_id: u32,
    /// The next step re-sorts the arrays and rebuilds the neighbour lists first.
    lists_due: bool,
    time: f64,
    steps: u64,
    /// Forces on particles by id (the coupled solids' reaction), held over each step until
    /// replaced; empty without coupling. Not in the snapshot: the coupling sets them from the
    /// state before every step.
    coupled: Vec<DVec3>,
}

impl FluidPhase {
    /// A phase over `particles`; refuses settings no step could use.
    pub fn new(settings: FluidSettings, mut particles: FluidParticles) -> Result<Self, String> {
        let positive =
            [("spacing", settings.spacing), ("smoothing length h", settings.h), ("density", settings.rho0), ("sound speed", settings.sound_speed)];
        for (name, v) in positive {
            if !(v > 0.0 && v.is_finite()) {
                return Err(format!("the fluid's {name} must be positive and finite (got {v})"));
            }
        }
        if !(settings.mu >= 0.0 && settings.mu.is_finite()) {
            return Err(format!("the fluid's viscosity must be ≥ 0 and finite (got {})", settings.mu));
        }
        if settings.viscosity == Viscosity::Laminar && settings.mu == 0.0 {
            return Err("laminar viscosity needs the fluid's viscosity μ > 0 (or choose the artificial viscosity)".into());
        }
        if particles.wall.len() != particles.len() {
            return Err("the fluid's particles lack their moving-wall numbers".into());
        }
        for body in &settings.floating {
            let inertia = body.inertia;
            let positive_definite = inertia[0].x > 0.0
                && inertia[1].y > 0.0
                && inertia[2].z > 0.0
                && glam::DMat3::from_cols(inertia[0], inertia[1], inertia[2]).determinant() > 0.0;
            if !(body.mass > 0.0 && body.mass.is_finite() && positive_definite) {
                return Err(format!("a floating body needs a positive finite mass and inertia (got {} kg)", body.mass));
            }
        }
        let reach = 2.0 * settings.h;
        let buffers = settings.inflows.iter().map(|b| &b.buffer).chain(settings.outflows.iter().map(|b| &b.buffer));
        if let Some(b) = buffers.into_iter().find(|b| b.depth().is_nan() || b.depth() < reach) {
            return Err(format!("a buffer must be at least 2h = {reach} deep along its flow (a full kernel), got {}", b.depth()));
        }
        if let Some(i) = settings.inflows.iter().find(|i| !(i.speed > 0.0 && i.speed.is_finite())) {
            return Err(format!("an inflow's speed must be positive and finite (got {})", i.speed));
        }
        let numbers = settings.wall_numbers();
        for (i, &w) in particles.wall.iter().enumerate() {
            if w as usize > numbers || (w > 0 && particles.kind[i] != ParticleKind::Wall) {
                return Err(format!(
                    "particle {i} names wall {w}; there are {numbers} moving walls, floating bodies and buffers, and only wall particles follow one"
                ));
            }
            let x = particles.position[i];
            match settings.wall_role(w) {
                WallRole::Moving(k) => particles.velocity[i] = settings.moving_walls[k].velocity_at(x, 0.0),
                WallRole::Body(k) => {
                    let body = &settings.floating[k].start;
                    particles.velocity[i] = body.velocity_at(x - body.centre);
                }
                WallRole::Inflow(k) => particles.velocity[i] = settings.inflows[k].velocity_at(x, 0.0, settings.dimension == crate::Dimension::Two),
                WallRole::Fixed | WallRole::Outflow(_) => {}
            }
        }
        let next_id = particles.id.iter().max().map_or(0, |&m| m + 1);
        let mut grid = FluidGrid::new(settings.domain, 2.0 * settings.h)?;
        for x in particles.position.iter_mut() {
            *x = grid.wrap(*x);
        }
        grid.sort(&mut particles);
        let method = Method::new(&settings);
        let bodies = settings.floating.iter().map(|b| b.start).collect();
        let body_particles = members(&particles, &settings);
        Ok(FluidPhase {
            settings,
            method,
            grid,
            particles,
            inputs: PairInputs::default(),
            rates: Rates::default(),
            start_velocity: Vec::new(),
            start_density: Vec::new(),
            bodies,
            body_particles,
            buffers: BufferBooks::default(),
            next_id,
            lists_due: false,
            time: 0.0,
            steps: 0,
            coupled: Vec::new(),
        })
    }

    pub fn settings(&self) -> &FluidSettings {
        &self.settings
    }

    pub fn particles(&self) -> &FluidParticles {
        &self.particles
    }

    pub fn time(&self) -> f64 {
        self.time
    }

    pub fn steps(&self) -> u64 {
        self.steps
    }

    /// The floating bodies, in the settings' order.
    pub fn bodies(&self) -> &[BodyState] {
        &self.bodies
    }

    /// What has passed through the inflow and outflow buffers since the start.
    pub fn buffer_books(&self) -> BufferBooks {
        self.buffers
    }

    pub fn equation_of_state(&self) -> Tait {
        self.method.eos
    }

    pub(crate) fn grid(&self) -> &FluidGrid {
        &self.grid
    }

    pub(crate) fn kernel(&self) -> crate::kernel::WendlandC2 {
        self.method.kernel
    }

    /// Bytes the phase's arrays, rates and neighbour lists hold.
    pub fn memory_bytes(&self) -> u64 {
        let p = &self.particles;
        let n = |v: usize, each: usize| (v * each) as u64;
        n(p.id.capacity(), 4)
            + n(p.wall.capacity(), 2)
            + n(p.kind.capacity(), size_of::<ParticleKind>())
            + n(p.position.capacity() + p.velocity.capacity(), 24)
            + n(p.density.capacity() + p.mass.capacity(), 8)
            + n(self.inputs.pressure.capacity() + self.inputs.pressure_term.capacity() + self.inputs.volume.capacity(), 8)
            + n(self.inputs.tensile.capacity() + self.inputs.fluid.capacity(), 8)
            + n(self.inputs.viscous_velocity.capacity(), 24)
            + n(self.rates.acceleration.capacity() + self.rates.xsph.capacity() + self.start_velocity.capacity(), 24)
            + n(self.rates.density_rate.capacity() + self.start_density.capacity(), 8)
            + n(self.body_particles.capacity(), 4)
            + self.grid.memory_bytes()
    }

    /// The fluid's state for a checkpoint.
    pub fn snapshot(&self) -> FluidSnapshot {
        FluidSnapshot {
            time: self.time,
            steps: self.steps,
            particles: self.particles.clone(),
            list_positions: (!self.lists_due).then(|| self.grid.built_positions().to_vec()),
            bodies: self.bodies.clone(),
            buffers: self.buffers,
            next_id: self.next_id,
        }
    }

    /// Continues from `snapshot` (taken from a phase with the same settings); refuses one whose
    /// arrays disagree in length or hold non-finite values, changing nothing.
    pub fn restore(&mut self, snapshot: &FluidSnapshot) -> Result<(), String> {
        // The fractions of another state's order: the next coupled step takes them afresh.
        self.inputs.fraction.clear();
        let p = &snapshot.particles;
        let n = p.position.len();
        if [p.id.len(), p.kind.len(), p.velocity.len(), p.density.len(), p.mass.len(), p.wall.len()].iter().any(|&len| len != n) {
            return Err("the fluid snapshot's arrays differ in length".into());
        }
        if !(p.position.iter().all(|x| x.is_finite()) && p.velocity.iter().all(|v| v.is_finite()) && p.density.iter().all(|r| r.is_finite())) {
            return Err("the fluid snapshot holds non-finite values".into());
        }
        if let Some(built) = &snapshot.list_positions
            && (built.len() != n || !built.iter().all(|x| x.is_finite()))
        {
            return Err("the fluid snapshot's neighbour-list positions do not match its particles".into());
        }
        if snapshot.bodies.len() != self.settings.floating.len() {
            return Err(format!(
                "the fluid snapshot holds {} floating bodies; the scene has {}",
                snapshot.bodies.len(),
                self.settings.floating.len()
            ));
        }
        self.particles = snapshot.particles.clone();
        match &snapshot.list_positions {
            Some(built) => {
                self.grid.rebuild_at(&mut self.particles, built);
                self.lists_due = false;
            }
            None => self.lists_due = true,
        }
        self.body_particles = members(&self.particles, &self.settings);
        self.bodies.clone_from(&snapshot.bodies);
        self.buffers = snapshot.buffers;
        self.next_id = snapshot.next_id.max(self.particles.id.iter().max().map_or(0, |&m| m + 1));
        self.time = snapshot.time;
        self.steps = snapshot.steps;
        Ok(())
    }

    /// The pressure of every particle at the last evaluation (walls: extrapolated).
    pub fn pressure(&self) -> &[f64] {
        &self.inputs.pressure
    }

    /// The time-step limits of the current state (its largest speed and acceleration).
    pub fn time_step_limits(&self) -> TimeStepLimits {
        let (speed, acc) = self
            .particles
            .kind
            .par_iter()
            .zip(self.particles.velocity.par_iter())
            .zip(self.rates.acceleration.par_iter())
            .filter(|((k, _), _)| **k == ParticleKind::Fluid)
            .map(|((_, v), a)| (v.length(), a.length()))
            .reduce(|| (0.0, 0.0), |x, y| (x.0.max(y.0), x.1.max(y.1)));
        TimeStepLimits::new(&self.settings, speed, acc.max(self.settings.external_acceleration().length()))
    }

    /// One step of Δt: the symplectic position-Verlet scheme of DualSPHysics (Monaghan 2005):
    /// rates at n give the half-step state; rates there give v^{n+1} = v^n + Δt a^{n+½},
    /// x^{n+1} = x^{n+½} + ½Δt v^{n+1}, ρ^{n+1} = ρ^n (2 − ε)/(2 + ε) with ε = −Δt (dρ/dt)^{n+½}/ρ^{n+½}.
    /// Floating bodies take the same scheme: their loads at n and n+½ give their velocities, and
    /// their particles drift with them.
    pub fn step(&mut self, dt: f64) -> Result<(), FluidFault> {
        self.step_with(dt, None)
    }

    /// One step of Δt coupled to `solids` (the locally averaged equations, docs/sph.md,
    /// "Coupling the particles"): their fluid fraction ε at each particle is taken first, so that
    /// a particle's density is the superficial ε ρ and its pressure that of ρ; after the first
    /// evaluation they are given the fractions and the fluid–fluid accelerations θ and answer
    /// their force on each particle, which both evaluations add (the forces held by
    /// [`FluidPhase::set_coupled_forces`] are left out).
    pub fn step_coupled(&mut self, dt: f64, solids: &mut dyn CoupledSolids) -> Result<(), FluidFault> {
        self.step_with(dt, Some(solids))
    }

    fn step_with(&mut self, dt: f64, mut solids: Option<&mut dyn CoupledSolids>) -> Result<(), FluidFault> {
        if self.lists_due {
            exchange(&self.settings, &mut self.particles, &mut self.next_id, &mut self.buffers);
            self.grid.sort(&mut self.particles);
            self.body_particles = members(&self.particles, &self.settings);
            self.lists_due = false;
        }
        let half = 0.5 * dt;
        // Beside solids the fluid's fraction enters its pressure (held over the step, as the
        // solids are).
        if let Some(solids) = solids.as_mut() {
            self.inputs.fraction = solids.fraction(&self.particles);
        }
        let walls = WallsAt { settings: &self.settings, bodies: &self.bodies, time: self.time };
        prepare(&self.method, &self.grid, &mut self.particles, &mut self.inputs, walls);
        evaluate(&self.method, &self.grid, &self.particles, &self.inputs, &mut self.rates);
        // The coupled forces as accelerations, in this step's order (fluid particles only).
        let p = &self.particles;
        let forces: Option<Vec<DVec3>> = match solids {
            Some(solids) => Some(solids.reaction(p, &self.inputs.fraction, &self.fluid_acceleration())),
            None if self.coupled.is_empty() => None,
            None => Some(p.id.iter().map(|&id| self.coupled.get(id as usize).copied().unwrap_or(DVec3::ZERO)).collect()),
        };
        let coupled: Vec<DVec3> = forces
            .map_or_else(Vec::new, |f| (0..p.len()).map(|i| if p.kind[i] == ParticleKind::Fluid { f[i] / p.mass[i] } else { DVec3::ZERO }).collect());
        // Without coupling the rates stand as they are (adding zero could turn a −0 into +0).
        let with_coupled = |i: usize, a: DVec3| coupled.get(i).map_or(a, |&c| a + c);
        self.load_bodies();
        self.start_velocity.clone_from(&self.particles.velocity);
        self.start_density.clone_from(&self.particles.density);
        let start_bodies = self.bodies.clone();
        let moves: Vec<BodyMove> = self.bodies.iter().map(|b| BodyMove::first_half(b, half)).collect();
        self.bodies = moves.iter().map(|m| m.state).collect();
        let rates = &self.rates;
        let walls = WallMoves { settings: &self.settings, t0: self.time, bodies: &moves };
        let (_, first_move) = drift(&self.grid, &mut self.particles, &walls, half, |i, v, rho| {
            let advect = *v + rates.xsph[i];
            *v += half * with_coupled(i, rates.acceleration[i]);
            *rho += half * rates.density_rate[i];
            advect
        });
        let walls = WallsAt { settings: &self.settings, bodies: &self.bodies, time: self.time + half };
        prepare(&self.method, &self.grid, &mut self.particles, &mut self.inputs, walls);
        evaluate(&self.method, &self.grid, &self.particles, &self.inputs, &mut self.rates);
        self.load_bodies();
        let moves: Vec<BodyMove> = start_bodies.iter().zip(&self.bodies).map(|(s, m)| BodyMove::second_half(s, m, dt)).collect();
        self.bodies = moves.iter().map(|m| m.state).collect();
        let rates = &self.rates;
        let (v0, rho0) = (&self.start_velocity, &self.start_density);
        let walls = WallMoves { settings: &self.settings, t0: self.time + half, bodies: &moves };
        let (fastest, second_move) = drift(&self.grid, &mut self.particles, &walls, half, |i, v, rho| {
            *v = v0[i] + dt * with_coupled(i, rates.acceleration[i]);
            let eps = -dt * rates.density_rate[i] / *rho;
            *rho = rho0[i] * (2.0 - eps) / (2.0 + eps);
            *v + rates.xsph[i]
        });
        self.time += dt;
        self.steps += 1;
        self.check(fastest, first_move + second_move, dt)?;
        self.lists_due = self.grid.largest_displacement(&self.particles.position) > rebuild_distance(self.settings.h);
        Ok(())
    }

    /// The fluid's loads on the floating bodies at the last evaluation, and the accelerations
    /// they give.
    fn load_bodies(&mut self) {
        if self.bodies.is_empty() {
            return;
        }
        let first = self.settings.body_wall_number(0);
        let loads = body_loads(&self.method, &self.grid, &self.particles, &self.inputs, &self.bodies, first, &self.body_particles);
        let s = &self.settings;
        for ((state, body), (force, torque)) in self.bodies.iter_mut().zip(&s.floating).zip(loads) {
            state.load(body, force, torque, s.gravity, s.dimension);
        }
    }

    fn check(&self, fastest: usize, moved: f64, dt: f64) -> Result<(), FluidFault> {
        let p = &self.particles;
        let bad = (0..p.len()).into_par_iter().find_first(|&i| {
            p.kind[i] == ParticleKind::Fluid && !(p.position[i].is_finite() && p.velocity[i].is_finite() && p.density[i].is_finite())
        });
        if let Some(i) = bad {
            return Err(FluidFault::NotFinite { id: p.id[i], time: self.time });
        }
        // Lists are rebuilt once a particle has moved this far; within one step it may move as
        // far again before a pair could be missed.
        let skin = rebuild_distance(self.settings.h);
        if moved > skin && fastest < p.len() {
            let speed = moved / dt;
            return Err(FluidFault::TooFast {
                id: p.id[fastest],
                time: self.time,
                speed,
                sound_speed: self.settings.sound_speed,
                dt_that_works: skin / speed,
            });
        }
        Ok(())
    }

    /// Forces on the particles, in their order as [`FluidPhase::particles`] gives it now (the
    /// coupled solids' reaction), held over the following steps until set again; an empty
    /// slice removes them.
    pub fn set_coupled_forces(&mut self, forces: &[DVec3]) {
        self.coupled.clear();
        if forces.is_empty() {
            return;
        }
        let p = &self.particles;
        let ids = p.id.iter().map(|&i| i as usize + 1).max().unwrap_or(0);
        self.coupled.resize(ids, DVec3::ZERO);
        for (i, f) in forces.iter().enumerate() {
            self.coupled[p.id[i] as usize] = *f;
        }
    }

    /// Starts the fluid beside solids whose fraction at each particle (in the particles' order)
    /// is `fraction`: each fluid particle's mass and density become ε times theirs, so the fluid
    /// fills only the space the solids leave (its volume m/ρ and pressure unchanged).
    pub fn couple(&mut self, fraction: Vec<f64>) {
        let p = &mut self.particles;
        for (i, &e) in fraction.iter().enumerate() {
            if p.kind[i] == ParticleKind::Fluid {
                p.mass[i] *= e;
                p.density[i] *= e;
            }
        }
        self.inputs.fraction = fraction;
    }

    /// Each particle's fluid fraction at its last step (in the particles' order; empty when
    /// no solids are coupled).
    pub fn fraction(&self) -> &[f64] {
        &self.inputs.fraction
    }

    /// The fluid's own density ρ at particle `i`: its density over its fluid fraction.
    pub fn intrinsic_density(&self, i: usize) -> f64 {
        self.inputs.fraction.get(i).map_or(self.particles.density[i], |e| self.particles.density[i] / e)
    }

    /// Each particle's acceleration from the fluid alone at the last evaluation (pressure,
    /// viscous and wall terms; gravity and the body force taken out), in the particles' order:
    /// the θ the particles' coupling interpolates. Zero for wall particles and before a step.
    pub fn fluid_acceleration(&self) -> Vec<DVec3> {
        let external = self.settings.external_acceleration();
        let p = &self.particles;
        (0..p.len())
            .map(|i| match (p.kind[i], self.rates.acceleration.get(i)) {
                (ParticleKind::Fluid, Some(&a)) => a - external,
                _ => DVec3::ZERO,
            })
            .collect()
    }

    /// The fluid's sums, in the particles' (deterministic) cell order.
    pub fn observables(&self) -> FluidObservables {
        let p = &self.particles;
        let eos = self.method.eos;
        let mut o = FluidObservables::default();
        for i in 0..p.len() {
            if p.kind[i] != ParticleKind::Fluid {
                continue;
            }
            let m = p.mass[i];
            let v = p.velocity[i];
            o.fluid_particles += 1;
            o.mass += m;
            o.momentum += m * v;
            o.kinetic_energy += 0.5 * m * v.length_squared();
            o.potential_energy -= m * self.settings.gravity.dot(p.position[i]);
            let rho = self.intrinsic_density(i);
            o.elastic_energy += m * eos.elastic_energy(rho);
            o.largest_density_deviation = o.largest_density_deviation.max((rho / eos.rho0 - 1.0).abs());
            o.largest_speed = o.largest_speed.max(v.length());
        }
        o
    }
}

/// The particles of floating bodies, ascending.
fn members(p: &FluidParticles, settings: &FluidSettings) -> Vec<u32> {
    (0..p.len() as u32).filter(|&i| matches!(settings.wall_role(p.wall[i as usize]), WallRole::Body(_))).collect()
}

#[cfg(test)]
mod tests;
