//! The plan: the smallest model a scene needs, and why (ARCHITECTURE.md, "The plan"). Its
//! parts are the physics the kernels run, the run's schedule, the backends' tuning and the
//! report `tumble plan` prints; `compile` builds them.

use crate::particles::InitialParticles;
use crate::run_options::{BackendName, EndWhenSection, MonitorSection, SnapshotFormat};
use crate::targets::Targets;
pub use crate::timescales::Timescales;
use glam::DVec3;
use tumble_contact::{FlowField, NormalLaw, RollingModel, TangentialLaw};
pub use tumble_geom::{Motion, Timing};
use tumble_geom::{PeriodicBox, Plane, SurfaceShape};
use tumble_integrate::Integrator;

/// Contact parameters of one material pair.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct PairParams {
    pub normal: NormalLaw,
    pub tangential: TangentialLaw,
    /// Cohesion stiffness k_c (0: no cohesion).
    pub cohesion: f64,
    pub no_attraction: bool,
    /// Rolling resistance μ_r (0: none).
    pub rolling: f64,
    /// How μ_r acts: a constant torque, or an EPSD2 rolling spring capped at μ_r R* F_n.
    pub rolling_model: RollingModel,
}

impl PairParams {
    /// (k_c, k_n) when linear cohesion is at least as stiff as the normal spring: the net force on
    /// a bonded contact then grows more attractive with overlap, at any Δt.
    pub fn cohesion_over_stiffness(&self) -> Option<(f64, f64)> {
        match self.normal {
            NormalLaw::Linear { stiffness, .. } if self.cohesion > 0.0 && self.cohesion >= stiffness => Some((self.cohesion, stiffness)),
            _ => None,
        }
    }
}

/// How polyhedra meet each other and the walls (docs/polyhedra.md).
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub enum PolyhedronContact {
    /// The normal law at the depth V / A_ref of the overlap volume V spread over the pair's
    /// reference area, along the volume's gradient: a potential, so elastic contacts conserve energy.
    #[default]
    Volume,
    /// The normal law at the separating-axis depth, at the manifold's depth-weighted point (not a
    /// potential: elastic contacts gain or lose energy as the contact's feature changes).
    Depth,
}

/// Drag law of the fluid.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum Drag {
    /// Stokes drag with dynamic viscosity μ_f.
    Stokes { viscosity: f64 },
    /// −α|v|v.
    Quadratic { coefficient: f64 },
}

#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Fluid {
    pub drag: Drag,
    pub flow: FlowField,
}

#[derive(Clone, Debug, PartialEq)]
pub struct Material {
    pub name: String,
    pub density: f64,
    pub youngs_modulus: Option<f64>,
    pub poisson_ratio: Option<f64>,
}

/// A world surface with its material; `shape` is its pose at t = 0.
#[derive(Clone, Debug, PartialEq)]
pub struct Wall {
    pub name: String,
    pub material: u16,
    pub shape: SurfaceShape,
    /// None: static.
    pub motion: Option<Motion>,
    /// A conveyor's surface velocity (zero for any other wall): the material moves along the
    /// surface, the geometry stays.
    pub surface_velocity: DVec3,
    /// When the motion runs (always, for a static wall).
    pub timing: Timing,
    /// The scene wall ([[walls]] entry) this surface belongs to: index into `PhysicsModel::wall_groups`.
    pub group: u16,
    /// Largest speed at which its surface sweeps through space (0 when the motion leaves
    /// the surface where it is, as a drum shell turning about its own axis); bounds the
    /// travel between neighbour-list rebuilds.
    pub travel_speed: f64,
    /// Largest speed of a point of its surface (the moving-geometry Δt limit).
    pub surface_speed: f64,
    /// Archard's wear coefficient over the hardness, K/H in 1/Pa: the volume worn per unit of
    /// normal force times sliding distance (0: no wear is accumulated; mesh walls only).
    pub wear: f64,
}

impl Wall {
    /// The surface at time `t`.
    pub fn shape_at(&self, t: f64) -> SurfaceShape {
        match self.motion {
            None => self.shape.clone(),
            Some(m) => {
                let (pivot, rotation, shift) = m.pose(self.timing.elapsed(t));
                self.shape.moved(pivot, rotation, shift)
            }
        }
    }

    /// The wall at time `t`: its surface there, and its motion as the velocities of that
    /// instant (a rotation at its current ω, any translation at its current velocity).
    pub fn posed(&self, t: f64) -> Wall {
        match self.motion {
            None => self.clone(),
            Some(_) => Wall { shape: self.shape_at(t), motion: self.motion_at(t), ..self.clone() },
        }
    }

    /// The motion at time `t` as that instant's velocities (what [`Wall::posed`] carries).
    pub fn motion_at(&self, t: f64) -> Option<Motion> {
        self.motion.map(|m| m.instant(self.timing.elapsed(t), self.timing.rate(t)))
    }

    /// Velocity of the wall's motion at point `x` (zero for a static wall; contacts use
    /// [`Wall::contact_velocity`], which adds a conveyor's surface velocity).
    #[inline]
    pub fn velocity_at(&self, x: DVec3) -> DVec3 {
        self.motion.map_or(DVec3::ZERO, |m| m.velocity_at(x))
    }

    /// Velocity of the wall material at contact point `x` with normal `normal`: its motion's,
    /// plus a conveyor's surface velocity with its part along the normal dropped (a belt
    /// moves along itself whatever way the user wrote it, and never pushes through a face).
    #[inline]
    pub fn contact_velocity(&self, x: DVec3, normal: DVec3) -> DVec3 {
        let s = self.surface_velocity;
        self.velocity_at(x) + (s - normal * s.dot(normal))
    }

    /// Angular velocity of the wall (zero unless it rotates).
    #[inline]
    pub fn angular_velocity(&self) -> DVec3 {
        match self.motion {
            Some(Motion::Rotate { axis, omega, .. }) => axis * omega,
            _ => DVec3::ZERO,
        }
    }
}

/// A scene wall ([[walls]] entry): box faces and lifter bars are several surfaces of one group.
#[derive(Clone, Debug, PartialEq)]
pub struct WallGroup {
    pub name: String,
    pub moving: bool,
    /// A servo moving the whole group (one [[walls]] entry) to hold a target force.
    pub servo: Option<Servo>,
}

/// A servo wall's controller: each step the wall's speed along `direction` is
/// `gain · (force − load)`, clamped to ±`max_speed`, where `load` is the particles' push on
/// the wall against `direction` at the last force pass. The wall's position integrates its
/// speed, so proportional control alone holds the target on a load at rest.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Servo {
    /// Unit direction the wall moves to press on the particles.
    pub direction: DVec3,
    /// Target force, N (> 0).
    pub force: f64,
    pub max_speed: f64,
    /// m/s per N of force error.
    pub gain: f64,
}

impl Servo {
    /// The speed along `direction` for the group's contact force `wall_force` (on the wall).
    #[inline]
    pub fn speed(&self, wall_force: DVec3) -> f64 {
        let load = -wall_force.dot(self.direction);
        (self.gain * (self.force - load)).clamp(-self.max_speed, self.max_speed)
    }
}

/// An inside cylinder turning about its own axis: a drum or mill, with its charge profile reported.
#[derive(Clone, Debug, PartialEq)]
pub struct Drum {
    /// Name of its wall group.
    pub name: String,
    pub point: DVec3,
    pub axis: DVec3,
    pub radius: f64,
    pub length: f64,
    /// Signed angular speed about `axis` at full speed, rad/s.
    pub omega: f64,
    /// When it turns: `omega` × `timing.rate(t)` at time t.
    pub timing: Timing,
}

/// A plane whose mass flow is reported.
#[derive(Clone, Debug, PartialEq)]
pub struct FlowPlane {
    pub name: String,
    pub plane: Plane,
}

/// The step limit from moving geometry: Δt ≤ 0.025 r_min / v_wall (docs/physics.md, "Time step").
#[derive(Clone, Debug, PartialEq)]
pub struct WallStepLimit {
    pub dt: f64,
    pub wall: String,
    pub speed: f64,
    pub r_min: f64,
}

/// Largest advance of a moving wall per step, as a fraction of the smallest radius.
pub const WALL_ADVANCE_FRACTION: f64 = 0.025;

/// One model feature and the reason it is on or off.
#[derive(Clone, Debug, PartialEq)]
pub struct Feature {
    pub name: &'static str,
    pub active: bool,
    pub reason: String,
}

/// The compiled scene: what runs, with which parameters.
#[derive(Clone, Debug)]
pub struct Plan {
    pub model: PhysicsModel,
    pub run: RunSettings,
    pub tuning: Tuning,
    pub report: PlanReport,
    /// The SPH fluid's phase, when the scene has one.
    pub sph: Option<SphPlan>,
}

/// What the SPH fluid phase is built from, besides its starting particles.
#[derive(Clone, Debug)]
pub struct SphPlan {
    pub settings: tumble_sph::FluidSettings,
    /// The limits on Δt at the expected speed and the external acceleration.
    pub limits: tumble_sph::TimeStepLimits,
    /// The largest flow speed the sound speed was chosen for, m/s.
    pub expected_speed: f64,
    pub fluid_particles: usize,
    pub wall_particles: usize,
    pub probes: Vec<SphProbe>,
    /// The names of the floating bodies, in the order of `settings.floating`.
    pub floating: Vec<String>,
    /// What `tumble plan` warns about the method's settings.
    pub warnings: Vec<String>,
    /// How the particles and the fluid act on each other, when they do.
    pub coupling: Option<CouplingPlan>,
}

/// The unresolved SPH–DEM coupling of a scene with particles and a 3D fluid.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct CouplingPlan {
    pub drag: tumble_sph::coupling::DragLaw,
    /// The particles' steps within each of the fluid's (the fluid steps `substeps` × Δt).
    pub substeps: u64,
    /// The longest fluid step over which the particles' drag may be held: a quarter of their
    /// shortest drag relaxation time, s.
    pub drag_limit: f64,
    /// The unit direction along which coupling.csv reports the particles' front.
    pub front: Option<glam::DVec3>,
}

/// A measurement of the fluid written at every output row (probe_<name>.csv).
#[derive(Clone, Debug, PartialEq)]
pub struct SphProbe {
    pub name: String,
    pub kind: SphProbeKind,
}

#[derive(Clone, Copy, Debug, PartialEq)]
pub enum SphProbeKind {
    /// Pressure at a point, Pa.
    Pressure(DVec3),
    /// Velocity at a point, m/s.
    Velocity(DVec3),
    /// Water height on the vertical line from `from` up to z = `top`, m.
    Gauge { from: DVec3, top: f64 },
    /// The fluid's largest extent along a unit vector, m.
    Front(DVec3),
}

/// What the force and integration kernels need to advance the particles by one step.
///
/// The step Δt and the integrator live here, not in [`RunSettings`]: the contact laws
/// integrate over the step (tangential spring increments, rolling and twisting limits,
/// dissipation per step) and implicit drag changes the drag force, so a kernel that has
/// the model has everything it reads.
#[derive(Clone, Debug)]
pub struct PhysicsModel {
    pub dt: f64,
    pub integrator: Integrator,
    pub rotation: bool,
    /// Some particle is a convex polyhedron: bodies carry an orientation and a shape index.
    pub polyhedra: bool,
    /// Polyhedral particle types, indexed by `InitialParticles::shape`.
    pub shapes: Vec<crate::ParticleShape>,
    /// The polyhedron contact model (only read when `polyhedra`).
    pub polyhedron_contact: PolyhedronContact,
    pub cohesion: bool,
    /// Some pair keeps a tangential spring per contact.
    pub history: bool,
    /// Some pair has rolling resistance.
    pub rolling: bool,
    pub fluid: Option<Fluid>,
    pub gravity: DVec3,
    pub domain: PeriodicBox,
    pub materials: Vec<Material>,
    /// Row-major [a * materials + b].
    pub pairs: Vec<PairParams>,
    pub walls: Vec<Wall>,
    /// One per [[walls]] entry.
    pub wall_groups: Vec<WallGroup>,
    pub drums: Vec<Drum>,
    pub flow_planes: Vec<FlowPlane>,
    /// The `[[particles]]` groups, then one group per source.
    pub group_names: Vec<String>,
    /// Particles added during the run.
    pub sources: Vec<crate::Source>,
    /// Regions that delete the particles entering them.
    pub outlets: Vec<crate::Outlet>,
}

impl PhysicsModel {
    /// Some pair keeps an EPSD2 rolling spring beside its tangential one.
    pub fn rolling_springs(&self) -> bool {
        self.history && self.pairs.iter().any(|p| p.rolling > 0.0 && p.rolling_model == RollingModel::Epsd2)
    }

    /// The lifter bars among the walls, in wall order, at their t = 0 pose.
    pub fn lifter_bars(&self) -> impl Iterator<Item = &tumble_geom::Prism> {
        self.walls.iter().filter_map(|w| match &w.shape {
            SurfaceShape::Prism(p) => Some(&**p),
            _ => None,
        })
    }

    /// Contact parameters of materials `a` and `b`.
    #[inline]
    pub fn pair(&self, a: u16, b: u16) -> &PairParams {
        &self.pairs[a as usize * self.materials.len() + b as usize]
    }

    /// The point wall group `g`'s torque is taken about: the rotation centre of its rotating
    /// surfaces, else a static cylinder's axis point, else the origin.
    pub fn wall_group_reference(&self, g: usize) -> DVec3 {
        let mine = || self.walls.iter().filter(move |w| w.group as usize == g);
        let rotation = mine().find_map(|w| match w.motion {
            Some(Motion::Rotate { point, .. }) => Some(point),
            _ => None,
        });
        let axis = || {
            mine().find_map(|w| match &w.shape {
                SurfaceShape::Cylinder(c) => Some(c.point),
                _ => None,
            })
        };
        rotation.or_else(axis).unwrap_or(DVec3::ZERO)
    }
}

/// The run's schedule and bookkeeping: how long, how often to write, where to run.
#[derive(Clone, Debug)]
pub struct RunSettings {
    pub name: String,
    pub duration: f64,
    pub steps: u64,
    pub output_every: u64,
    pub snapshot_every: Option<u64>,
    /// Steps between checkpoints (`tumble resume`), when the scene asks for them.
    pub checkpoint_every: Option<u64>,
    /// Newest checkpoints kept.
    pub checkpoint_keep: usize,
    /// A checkpoint (file or run folder) whose particles replace the scene's at t = 0.
    pub start_from: Option<String>,
    /// End the run early once the particles rest.
    pub end_when: Option<EndWhenSection>,
    pub backend: BackendName,
    pub monitor: MonitorSection,
    /// Write agglomerates.csv at every output interval.
    pub agglomerates: bool,
    /// Largest share of the particles that may leave the domain before the run stops.
    pub max_lost_fraction: f64,
    /// Largest share of the particles one outlet may delete in one output interval.
    pub max_outlet_fraction: f64,
    /// A source that never found room does not fail the run.
    pub allow_idle_sources: bool,
    /// Encoding of the snapshot .vtp files.
    pub snapshot_format: SnapshotFormat,
    /// Write the contact network at every snapshot.
    pub contacts: bool,
}

/// How the backends organise the work: neighbour search, memory layout (not physics: the
/// results do not depend on them beyond round-off of the summation order).
#[derive(Clone, Debug)]
pub struct Tuning {
    /// Largest interaction diameter (body, or effect with cohesion).
    pub cell_size: f64,
    /// Verlet-list skin: pairs within reach + skin are listed; rebuilt after a move of skin/2.
    pub skin: f64,
    /// Steps between re-sorts of the particles into cell order.
    pub resort_interval: u32,
    /// Contacts with history each particle can hold.
    pub history_slots: usize,
    pub bytes_per_particle: usize,
    /// Slots a backend with device arrays reserves for inserted particles at a time (0 without
    /// sources): it starts with one chunk beyond the initial particles and grows by chunks.
    pub capacity_chunk: u64,
}

/// What the plan found about the scene, for people: time scales, features and why, warnings.
#[derive(Clone, Debug)]
pub struct PlanReport {
    pub timescales: Timescales,
    /// The moving-geometry step limit, when a wall moves.
    pub wall_step_limit: Option<WallStepLimit>,
    pub features: Vec<Feature>,
    pub warnings: Vec<String>,
    /// Stk and Sy, with the scales they were taken at (Taylor–Green flows, cohesive scenes).
    pub targets: Targets,
}

impl Plan {
    /// The coupling of the particles and the fluid, when the scene has both and they act on
    /// each other.
    pub fn coupling(&self) -> Option<&CouplingPlan> {
        self.sph.as_ref().and_then(|s| s.coupling.as_ref())
    }

    /// Whether a fluid, prescribed (`[fluid]`) or coupled, does work on the particles: their
    /// books keep that work, and their energy may grow by it.
    pub fn fluid_works_on_particles(&self) -> bool {
        self.model.fluid.is_some() || self.coupling().is_some()
    }

    /// Memory estimate for `n` particles on the CPU backend, in bytes: an upper bound, with
    /// the cell grid as large as the domain (it spans the particles' bounding box).
    pub fn memory_bytes(&self, n: usize) -> usize {
        let [cx, cy, cz] = self.grid_dims();
        // CellGrid::layout caps the grid at 2^26 cells.
        n * self.tuning.bytes_per_particle + (cx * cy * cz + 1) * 4
    }

    /// The CPU grid when the particles fill the domain (it spans the particles' bounding box).
    pub fn grid_dims(&self) -> [usize; 3] {
        tumble_broad::CellGrid::layout(&self.model.domain, (self.tuning.cell_size + self.tuning.skin).max(f64::MIN_POSITIVE)).0
    }

    /// Particles the sources may insert over the run at most (the run's capacity beyond its
    /// initial particles).
    pub fn inserted_at_most(&self) -> u64 {
        crate::sources::inserted_at_most(&self.model.sources, self.model.dt)
    }

    /// Steps per shortest collision, when there is one.
    pub fn steps_per_collision(&self) -> Option<f64> {
        self.report.timescales.collision_time.map(|t| t / self.model.dt)
    }
}

/// A scene ready to run: its plan and its initial particles.
#[derive(Clone, Debug)]
pub struct CompiledScene {
    pub plan: Plan,
    pub particles: InitialParticles,
    /// The SPH fluid's starting particles (fluid and walls), with `plan.sph`.
    pub fluid: Option<tumble_sph::FluidParticles>,
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_posed_wall_moves_at_the_velocity_it_reports() {
        let shape = SurfaceShape::Plane(tumble_geom::Plane::new(DVec3::ZERO, DVec3::Z));
        let motions =
            [Motion::Oscillate { direction: DVec3::Z, amplitude: 0.002, omega: 31.4 }, Motion::Translate { velocity: DVec3::new(0.0, 0.0, 0.3) }];
        for motion in motions {
            let wall = Wall {
                name: "w".into(),
                material: 0,
                shape: shape.clone(),
                motion: Some(motion),
                surface_velocity: DVec3::ZERO,
                timing: Timing { start: 0.1, ramp: 0.2, stop: 0.8 },
                group: 0,
                travel_speed: 0.0,
                surface_speed: 0.0,
                wear: 0.0,
            };
            let height = |t: f64| match wall.shape_at(t) {
                SurfaceShape::Plane(p) => p.point.dot(p.normal),
                _ => unreachable!(),
            };
            for t in [0.05, 0.15, 0.25, 0.31, 0.5, 0.79, 0.85] {
                let h = 1e-6;
                let rate = (height(t + h) - height(t - h)) / (2.0 * h);
                let v = wall.posed(t).velocity_at(DVec3::ZERO).z;
                assert!((rate - v).abs() < 1e-6, "{motion:?} at t = {t}: the pose moves at {rate}, the wall reports {v}");
            }
        }
    }
}
