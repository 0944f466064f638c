//! The particles and a 3D fluid acting on each other (docs/sph.md, "Coupling the particles"):
//! each of the fluid's steps evaluates `tumble_sph::coupling` on the particles as they are at
//! its start, adds the solids' reaction to the fluid's two evaluations, and holds each solid's
//! fluid force over the particles' sub-steps to the same time. Force and reaction act over the
//! same interval, so the momentum of fluid and particles together is conserved.
//!
//! As a phase it writes `coupling.csv`: the sums of the last evaluation.

use glam::DVec3;
use serde::{Deserialize, Serialize};
use std::time::Instant;
use tumble_scene::Plan;
use tumble_sph::coupling::{Coupling, CouplingForces, DragFluid, Solids};
use tumble_sph::{CoupledSolids, FluidParticles};
use tumble_state::{OutputRequest, Phase, PhaseOutput, PhaseStop, PhaseTable, State};

/// The coupling of a run and what its last evaluation gave.
pub struct Coupler {
    coupling: Coupling,
    /// The particles' steps per fluid step.
    substeps: u64,
    /// Each particle's volume-equivalent radius is its mass over its material's density
    /// (polyhedra); spheres use their radius.
    polyhedra: bool,
    densities: Vec<f64>,
    /// The direction of the particles' front in coupling.csv, if the scene asks for it.
    front: Option<DVec3>,
    /// By particle id: the fluid's force at the last evaluation, N (what the particles hold).
    force: Vec<DVec3>,
    last: Sums,
    seconds: StepSeconds,
}

/// Where a coupled run's time went, in seconds of wall time since it started (or resumed):
/// He et al. (2018) find the fluid takes more than ten times the particles.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct StepSeconds {
    /// The fluid's own steps, the coupling's evaluations left out.
    pub fluid: f64,
    /// The coupling's evaluations: the fraction, the interpolations, the forces and reaction.
    pub coupling: f64,
    /// The particles' sub-steps.
    pub particles: f64,
}

/// What `coupling.csv` reports of one evaluation.
#[derive(Clone, Copy, Debug, Default, Serialize, Deserialize)]
pub struct Sums {
    /// Solids with fluid within reach.
    pub wetted: usize,
    /// The fluid's force on them, and its drag part, N.
    pub force: DVec3,
    pub drag: DVec3,
    /// Mean and least fluid fraction at the wetted solids.
    pub mean_fraction: f64,
    pub least_fraction: f64,
    /// The largest slip |u − v| of a wetted solid, m/s.
    pub largest_slip: f64,
    /// The particles' largest extent along the front's direction, m.
    pub solid_front: f64,
}

impl Coupler {
    /// The coupling of `plan`, when it has one.
    pub fn of(plan: &Plan) -> Result<Option<Self>, String> {
        let (Some(sph), Some(c)) = (plan.sph.as_ref(), plan.coupling()) else { return Ok(None) };
        let f = &sph.settings;
        let fluid = DragFluid { density: f.rho0, viscosity: f.mu };
        let coupling = Coupling::new(f.h, f.dimension, plan.model.domain, c.drag, fluid)?;
        Ok(Some(Coupler {
            coupling,
            substeps: c.substeps,
            polyhedra: plan.model.polyhedra,
            densities: plan.model.materials.iter().map(|m| m.density).collect(),
            front: c.front,
            force: Vec::new(),
            last: Sums::default(),
            seconds: StepSeconds::default(),
        }))
    }

    /// The particles' steps per fluid step.
    pub fn substeps(&self) -> u64 {
        self.substeps
    }

    /// By particle id: the fluid's force at the last evaluation, N.
    pub fn forces(&self) -> &[DVec3] {
        &self.force
    }

    /// The sums of the last evaluation (coupling.csv's row).
    pub fn sums(&self) -> &Sums {
        &self.last
    }

    /// Where the run's time went so far.
    pub fn seconds(&self) -> StepSeconds {
        self.seconds
    }

    /// Books time spent on the fluid's steps with the coupling's evaluations in them (booked
    /// to the coupling as they run, and taken off the fluid's there), on handing the particles'
    /// state and forces between the phases, and on the particles' sub-steps.
    pub(crate) fn book(&mut self, fluid_and_evaluations: f64, exchange: f64, particles: f64) {
        self.seconds.fluid += fluid_and_evaluations;
        self.seconds.coupling += exchange;
        self.seconds.particles += particles;
    }

    /// The coupling with the particles `solids` as they are now, for one fluid step.
    pub fn with<'a>(&'a mut self, solids: &'a State) -> CoupledStep<'a> {
        let radius = match self.polyhedra {
            false => solids.radius.clone(),
            true => {
                (0..solids.len()).map(|i| tumble_scene::equivalent_radius(solids.mass[i] / self.densities[solids.material[i] as usize])).collect()
            }
        };
        CoupledStep { coupler: self, state: solids, radius }
    }
}

/// The coupling over one fluid step, the particles held where they are.
pub struct CoupledStep<'a> {
    coupler: &'a mut Coupler,
    state: &'a State,
    /// Each particle's volume-equivalent radius.
    radius: Vec<f64>,
}

impl CoupledStep<'_> {
    fn solids(&self) -> Solids<'_> {
        Solids { position: &self.state.pos, velocity: &self.state.vel, radius: &self.radius }
    }

    /// Moves the time since `start` from the fluid's books to the coupling's.
    fn took(&mut self, start: Instant) {
        let s = start.elapsed().as_secs_f64();
        self.coupler.seconds.coupling += s;
        self.coupler.seconds.fluid -= s;
    }
}

impl CoupledSolids for CoupledStep<'_> {
    fn fraction(&mut self, fluid: &FluidParticles) -> Vec<f64> {
        let start = Instant::now();
        let fraction = self.coupler.coupling.fraction(fluid, self.solids());
        self.took(start);
        fraction
    }

    /// Keeps each particle's force by id and answers the reaction on each fluid particle.
    fn reaction(&mut self, fluid: &FluidParticles, fraction: &[f64], theta: &[DVec3]) -> Vec<DVec3> {
        let start = Instant::now();
        let out = self.coupler.coupling.forces(fluid, fraction.to_vec(), theta, self.solids());
        let solids = self.state;
        let c = &mut *self.coupler;
        let ids = solids.id.iter().map(|&i| i as usize + 1).max().unwrap_or(0);
        c.force.clear();
        c.force.resize(ids, DVec3::ZERO);
        for (i, &id) in solids.id.iter().enumerate() {
            c.force[id as usize] = out.force[i];
        }
        c.last = sums(&out, &solids.vel);
        if let Some(d) = c.front {
            c.last.solid_front = solids.pos.iter().map(|x| x.dot(d)).fold(f64::NEG_INFINITY, f64::max);
        }
        self.took(start);
        out.reaction
    }
}

/// The sums of one evaluation, over the solids in their (fixed) array order.
fn sums(out: &CouplingForces, velocity: &[DVec3]) -> Sums {
    let mut s = Sums { least_fraction: 1.0, ..Sums::default() };
    for (i, (&force, &drag)) in out.force.iter().zip(&out.drag).enumerate() {
        s.force += force;
        s.drag += drag;
        // A solid out of the fluid's reach reads fraction 1 and its own velocity.
        if force != DVec3::ZERO {
            s.wetted += 1;
            s.mean_fraction += out.solid_fraction[i];
            s.least_fraction = s.least_fraction.min(out.solid_fraction[i]);
            s.largest_slip = s.largest_slip.max((out.fluid_velocity[i] - velocity[i]).length());
        }
    }
    s.mean_fraction = if s.wetted > 0 { s.mean_fraction / s.wetted as f64 } else { 1.0 };
    s
}

const COLUMNS: [&str; 10] = [
    "wetted_particles",
    "fluid_force_x",
    "fluid_force_y",
    "fluid_force_z",
    "drag_x",
    "drag_y",
    "drag_z",
    "mean_fluid_fraction",
    "least_fluid_fraction",
    "largest_slip",
];

impl Phase for Coupler {
    fn name(&self) -> &'static str {
        "coupling"
    }

    /// The run steps the coupling with the phases it couples (see `Simulation::advance`).
    fn advance(&mut self, _steps: u64, _dt: f64) -> Result<(), PhaseStop> {
        Ok(())
    }

    fn particles(&self) -> usize {
        0
    }

    fn memory_bytes(&self) -> u64 {
        (self.force.len() * size_of::<DVec3>()) as u64
    }

    fn output(&mut self, request: OutputRequest) -> Result<PhaseOutput, PhaseStop> {
        let mut out = PhaseOutput::default();
        if request.row {
            let s = &self.last;
            let values = vec![
                s.wetted as f64,
                s.force.x,
                s.force.y,
                s.force.z,
                s.drag.x,
                s.drag.y,
                s.drag.z,
                s.mean_fraction,
                s.least_fraction,
                s.largest_slip,
            ];
            let mut columns = COLUMNS.to_vec();
            let mut values = values;
            if self.front.is_some() {
                columns.push("solid_front");
                values.push(s.solid_front);
            }
            out.tables.push(PhaseTable::line("coupling.csv", &columns, values));
        }
        Ok(out)
    }

    fn summary(&self) -> Vec<(String, f64)> {
        vec![("substeps".into(), self.substeps as f64), ("wetted_particles".into(), self.last.wetted as f64)]
    }

    /// Every output row and checkpoint falls between two fluid steps, where the next step
    /// evaluates the coupling afresh: only the last row's sums are kept.
    fn snapshot(&self) -> Vec<u8> {
        postcard::to_stdvec(&self.last).expect("the sums always encode")
    }

    fn restore(&mut self, bytes: &[u8]) -> Result<(), String> {
        self.last = postcard::from_bytes(bytes).map_err(|e| format!("the coupling's books cannot be decoded: {e}"))?;
        Ok(())
    }

    fn as_any(&self) -> &dyn std::any::Any {
        self
    }

    fn as_any_mut(&mut self) -> &mut dyn std::any::Any {
        self
    }
}
