//! The plan: the smallest model a scene needs, and why (ARCHITECTURE.md, "The plan").

use crate::SceneError;
use crate::particles::{InitialParticles, generate};
use crate::schema::*;
pub use crate::timescales::Timescales;
use glam::DVec3;
use std::collections::HashMap;
use std::fmt::Write as _;
use tumble_contact::{FlowField, NormalLaw, SpringLaw, TangentialLaw, ViscousParameter, hertz_effective_moduli};
use tumble_geom::{DQuat, PeriodicBox, Plane, SurfaceShape};
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
    /// The scene wall ([[walls]] entry) this surface belongs to: index into `Plan::wall_groups`.
    pub group: u16,
    /// Largest speed at which its surface sweeps through space (0 when the motion leaves
    /// the surface where it is, as a drum shell turning about its own axis); bounds the
    /// travel between neighbour-list rebuilds.
    pub travel_speed: f64,
    /// Largest speed of a point of its surface (the moving-geometry Δt limit).
    pub surface_speed: f64,
}

impl Wall {
    /// The surface at time `t`.
    pub fn shape_at(&self, t: f64) -> SurfaceShape {
        match self.motion {
            None => self.shape.clone(),
            Some(m) => {
                let (pivot, rotation, shift) = m.pose(t);
                self.shape.moved(pivot, rotation, shift)
            }
        }
    }

    /// Velocity of the wall material at point `x` (zero for a static wall).
    #[inline]
    pub fn velocity_at(&self, x: DVec3) -> DVec3 {
        self.motion.map_or(DVec3::ZERO, |m| m.velocity_at(x))
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

/// Prescribed rigid motion of a wall.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum Motion {
    /// Rotation about the axis through `point` along unit `axis` at `omega` rad/s (right-handed).
    Rotate {
        point: DVec3,
        axis: DVec3,
        omega: f64,
    },
    Translate {
        velocity: DVec3,
    },
}

impl Motion {
    #[inline]
    pub fn velocity_at(&self, x: DVec3) -> DVec3 {
        match *self {
            Motion::Rotate { point, axis, omega } => (axis * omega).cross(x - point),
            Motion::Translate { velocity } => velocity,
        }
    }

    /// (pivot, rotation about the pivot, shift) taking the t = 0 pose to time t.
    pub fn pose(&self, t: f64) -> (DVec3, DQuat, DVec3) {
        match *self {
            Motion::Rotate { point, axis, omega } => (point, DQuat::from_axis_angle(axis, omega * t), DVec3::ZERO),
            Motion::Translate { velocity } => (DVec3::ZERO, DQuat::IDENTITY, velocity * t),
        }
    }
}

/// A scene wall ([[walls]] entry): box faces and lifter bars are several surfaces of one group.
#[derive(Clone, Debug, PartialEq)]
pub struct WallGroup {
    pub name: String,
    pub moving: bool,
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
    /// Signed angular speed about `axis`, rad/s.
    pub omega: f64,
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
    pub name: String,
    pub duration: f64,
    pub dt: f64,
    pub steps: u64,
    pub output_every: u64,
    pub snapshot_every: Option<u64>,
    pub integrator: Integrator,
    pub backend: BackendName,
    pub rotation: bool,
    /// Some particle is a convex polyhedron: bodies carry an orientation and a shape index.
    pub polyhedra: bool,
    /// Polyhedral particle types, indexed by `InitialParticles::shape`.
    pub shapes: Vec<crate::ParticleShape>,
    pub cohesion: bool,
    /// Some pair keeps a tangential spring per contact.
    pub history: bool,
    /// Contacts with history each particle can hold.
    pub history_slots: usize,
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
    /// The moving-geometry step limit, when a wall moves.
    pub wall_step_limit: Option<WallStepLimit>,
    pub group_names: Vec<String>,
    /// Largest interaction diameter (body, or effect with cohesion).
    pub cell_size: f64,
    /// Verlet-list skin: pairs within reach + skin are listed; rebuilt after a move of skin/2.
    pub skin: f64,
    pub timescales: Timescales,
    pub features: Vec<Feature>,
    pub warnings: Vec<String>,
    pub resort_interval: u32,
    pub monitor: MonitorSection,
    pub bytes_per_particle: usize,
    /// Write agglomerates.csv at every output interval.
    pub agglomerates: bool,
    /// Stk and Sy, with the scales they were taken at (Taylor–Green flows, cohesive scenes).
    pub targets: crate::targets::Targets,
}

impl Plan {
    #[inline]
    pub fn pair(&self, a: u16, b: u16) -> &PairParams {
        &self.pairs[a as usize * self.materials.len() + b as usize]
    }

    /// Memory estimate for `n` particles on the CPU backend, in bytes.
    pub fn memory_bytes(&self, n: usize) -> usize {
        let [cx, cy, cz] = self.grid_dims();
        n * self.bytes_per_particle + (cx * cy * cz + 1) * 4
    }

    fn grid_dims(&self) -> [usize; 3] {
        let e = self.domain.extent();
        [0, 1, 2].map(|k| ((e[k] / (self.cell_size + self.skin)).floor() as usize).clamp(1, 1 << 21))
    }

    /// Steps per shortest collision, when there is one.
    pub fn steps_per_collision(&self) -> Option<f64> {
        self.timescales.collision_time.map(|t| t / self.dt)
    }

    /// The plan as text, for `tumble plan`.
    pub fn describe(&self, particles: usize) -> String {
        let mut s = String::new();
        let _ = writeln!(s, "scene        {}", self.name);
        let _ = writeln!(s, "particles    {particles}");
        let _ = writeln!(s, "integrator   {}", self.integrator.name());
        let _ = writeln!(s, "dt           {:.6e} s ({} steps to t = {} s)", self.dt, self.steps, self.duration);
        if let Some(t) = self.timescales.collision_time {
            let _ = writeln!(s, "t_col        {:.6e} s ({:.1} steps per collision)", t, t / self.dt);
        }
        if let Some(t) = self.timescales.rayleigh_time {
            let _ = writeln!(s, "rayleigh     {t:.6e} s");
        }
        if let Some(t) = self.timescales.tangential_time {
            let _ = writeln!(s, "tau_t        {t:.6e} s (viscous tangential relaxation m*_t / c_t)");
        }
        if let Some(t) = self.timescales.drag_time {
            let _ = writeln!(s, "tau_p        {t:.6e} s (shortest drag relaxation time)");
        }
        if let Some(t) = self.timescales.stability_limit {
            let _ = writeln!(s, "limit        {t:.6e} s (largest stable dt)");
        }
        if let Some(w) = &self.wall_step_limit {
            let _ = writeln!(
                s,
                "wall limit   {:.6e} s (moving geometry: wall \"{}\" moves at up to {:.4} m/s; dt <= {} r_min / v_wall with r_min = {:.4e} m)",
                w.dt, w.wall, w.speed, WALL_ADVANCE_FRACTION, w.r_min
            );
        }
        let _ = writeln!(s, "cell size    {:.6e} m + skin {:.3e} m, grid {:?}", self.cell_size, self.skin, self.grid_dims());
        let _ = writeln!(
            s,
            "memory       {:.1} MiB ({} bytes per particle)",
            self.memory_bytes(particles) as f64 / (1 << 20) as f64,
            self.bytes_per_particle
        );
        let _ = writeln!(s, "features");
        for f in &self.features {
            let _ = writeln!(s, "  {:<12} {:<4} {}", f.name, if f.active { "on" } else { "off" }, f.reason);
        }
        if let Some(tg) = &self.targets.taylor_green {
            let _ = write!(s, "taylor-green u_0 = {:.6} m/s (mean |u|), l_0 = pi/a = {:.6} m", tg.mean_flow_speed, tg.vortex_size);
            match (tg.stokes_number, tg.viscosity) {
                (Some(stk), Some(mu)) => {
                    let _ = writeln!(s, ", Stk = {stk:.6} (mu = {mu:.6e} Pa s)");
                }
                _ => {
                    let _ = writeln!(s);
                }
            }
        }
        if let Some(sy) = &self.targets.stickiness {
            let _ = writeln!(
                s,
                "stickiness   Sy = {:.6} (k_c = {:.6e} N/m, e = {}, L_e = {:.4e} m, m* = {:.4e} kg, collision speed {:.6} m/s)",
                sy.number, sy.stiffness, sy.restitution, sy.effect_length, sy.reduced_mass, sy.collision_speed
            );
        }
        for w in &self.warnings {
            let _ = writeln!(s, "warning: {w}");
        }
        s
    }
}

/// A scene ready to run: its plan and its initial particles.
#[derive(Clone, Debug)]
pub struct CompiledScene {
    pub plan: Plan,
    pub particles: InitialParticles,
}

pub(crate) fn positive(field: &str, v: f64) -> Result<f64, SceneError> {
    if v.is_finite() && v > 0.0 { Ok(v) } else { Err(SceneError::field(field, format!("must be a positive number, got {v}"))) }
}

fn non_negative(field: &str, v: f64) -> Result<f64, SceneError> {
    if v.is_finite() && v >= 0.0 { Ok(v) } else { Err(SceneError::field(field, format!("must be zero or positive, got {v}"))) }
}

pub(crate) fn finite3(field: &str, v: V3) -> Result<DVec3, SceneError> {
    if v.iter().all(|c| c.is_finite()) { Ok(DVec3::from_array(v)) } else { Err(SceneError::field(field, "every component must be a finite number")) }
}

pub(crate) fn unit(field: &str, v: V3) -> Result<DVec3, SceneError> {
    let d = finite3(field, v)?;
    if d.length() > 0.0 { Ok(d.normalize()) } else { Err(SceneError::field(field, "must be a non-zero direction")) }
}

/// Validates a scene, generates its particles and compiles the plan.
pub fn compile(scene: &Scene) -> Result<CompiledScene, SceneError> {
    if scene.name.trim().is_empty() {
        return Err(SceneError::field("name", "must not be empty"));
    }
    // Materials.
    if scene.materials.is_empty() {
        return Err(SceneError::field("materials", "define at least one [[materials]] entry with a name and a density"));
    }
    let mut material_index = HashMap::new();
    let mut materials = Vec::new();
    for (k, m) in scene.materials.iter().enumerate() {
        let f = |x: &str| format!("materials[{k}].{x}");
        if material_index.insert(m.name.clone(), k as u16).is_some() {
            return Err(SceneError::field(f("name"), format!("material \"{}\" is defined twice", m.name)));
        }
        positive(&f("density"), m.density)?;
        if let Some(e) = m.youngs_modulus {
            positive(&f("youngs_modulus"), e)?;
        }
        if let Some(nu) = m.poisson_ratio
            && !(nu > -1.0 && nu < 0.5)
        {
            return Err(SceneError::field(f("poisson_ratio"), format!("must lie in (-1, 0.5), got {nu}")));
        }
        materials.push(Material { name: m.name.clone(), density: m.density, youngs_modulus: m.youngs_modulus, poisson_ratio: m.poisson_ratio });
    }
    let lookup = |field: String, name: &str| -> Result<u16, SceneError> {
        material_index.get(name).copied().ok_or_else(|| {
            let known: Vec<&str> = scene.materials.iter().map(|m| m.name.as_str()).collect();
            SceneError::field(field, format!("unknown material \"{name}\"; defined materials: {}", known.join(", ")))
        })
    };

    // Domain.
    let domain =
        PeriodicBox { min: finite3("domain.min", scene.domain.min)?, max: finite3("domain.max", scene.domain.max)?, periodic: scene.domain.periodic };
    if (0..3).any(|k| domain.max[k] <= domain.min[k]) {
        return Err(SceneError::field("domain", "max must exceed min on every axis (the domain is empty)"));
    }

    // Contact laws per material pair.
    let n_mat = materials.len();
    let mut pairs = Vec::with_capacity(n_mat * n_mat);
    let mut cohesion_specs = Vec::with_capacity(n_mat * n_mat);
    for a in 0..n_mat {
        for b in 0..n_mat {
            let over = scene.contact.pairs.iter().enumerate().find(|(_, p)| {
                let (x, y) = (p.materials[0].as_str(), p.materials[1].as_str());
                (x == materials[a].name && y == materials[b].name) || (y == materials[a].name && x == materials[b].name)
            });
            let field_root = over.map_or("contact".to_string(), |(k, _)| format!("contact.pairs[{k}]"));
            let p = over.map(|(_, p)| p);
            let normal = p.and_then(|p| p.normal.as_ref()).unwrap_or(&scene.contact.normal);
            let e = p.and_then(|p| p.restitution).unwrap_or(scene.contact.restitution);
            let tangential = p.and_then(|p| p.tangential.as_ref()).unwrap_or(&scene.contact.tangential);
            let cohesion = p.and_then(|p| p.cohesion.as_ref()).or(scene.contact.cohesion.as_ref());
            cohesion_specs.push((field_root.clone(), cohesion.cloned()));
            let mut params = pair_params(&field_root, normal, e, tangential, cohesion, scene.contact.no_attraction, &materials[a], &materials[b])?;
            let rolling_root = if p.and_then(|p| p.rolling_friction).is_some() { field_root.as_str() } else { "contact" };
            params.rolling = non_negative(
                &format!("{rolling_root}.rolling_friction"),
                p.and_then(|p| p.rolling_friction).or(scene.contact.rolling_friction).unwrap_or(0.0),
            )?;
            pairs.push(params);
        }
    }
    for (k, p) in scene.contact.pairs.iter().enumerate() {
        for (s, name) in p.materials.iter().enumerate() {
            lookup(format!("contact.pairs[{k}].materials[{s}]"), name)?;
        }
    }

    // Particles.
    let mut shapes = Vec::new();
    let mut group_shape = Vec::with_capacity(scene.particles.len());
    for (g, group) in scene.particles.iter().enumerate() {
        group_shape.push(crate::shapes::group_shape(group, g)?.map(|s| {
            shapes.push(s);
            (shapes.len() - 1) as u16
        }));
    }
    let particles = generate(scene, &material_index, &group_shape, &shapes)?;
    for (g, group) in scene.particles.iter().enumerate() {
        let ShapeSection::Sphere(s) = &group.shape else { continue };
        let f = |x: &str| format!("particles[{g}].shape.sphere.{x}");
        match s.diameter {
            DiameterSpec::Fixed(d) => {
                positive(&f("diameter"), d)?;
            }
            DiameterSpec::Uniform(r) => {
                positive(&f("diameter.min"), r.min)?;
                if !(r.max >= r.min) {
                    return Err(SceneError::field(f("diameter.max"), format!("must be at least diameter.min = {}, got {}", r.min, r.max)));
                }
            }
        }
        if let Some(de) = s.effect_diameter {
            let d_max = match s.diameter {
                DiameterSpec::Fixed(d) => d,
                DiameterSpec::Uniform(r) => r.max,
            };
            if !(de >= d_max) {
                return Err(SceneError::field(f("effect_diameter"), format!("must be at least the body diameter {d_max}, got {de}")));
            }
        }
        if let Some(ratio) = s.effect_ratio
            && !(ratio >= 1.0)
        {
            return Err(SceneError::field(f("effect_ratio"), format!("must be at least 1, got {ratio}")));
        }
        if let Some(VelocitySpec::Random(r)) = &group.velocity {
            non_negative(&format!("particles[{g}].velocity.random.mean_speed"), r.random.mean_speed)?;
            non_negative(&format!("particles[{g}].velocity.random.std"), r.random.std)?;
        }
    }
    if particles.is_empty() {
        return Err(SceneError::field("particles", "the scene has no particles; add a [[particles]] group"));
    }
    for i in 0..particles.len() {
        if !particles.position[i].is_finite() || !particles.velocity[i].is_finite() {
            return Err(SceneError::field(format!("particles[{}]", particles.group[i]), "positions and velocities must be finite numbers"));
        }
        if !domain.contains(particles.position[i]) {
            let p = particles.position[i];
            return Err(SceneError::field(
                format!("particles[{}]", particles.group[i]),
                format!("particle at [{}, {}, {}] lies outside the domain [{:?} .. {:?}]", p.x, p.y, p.z, scene.domain.min, scene.domain.max),
            ));
        }
    }
    check_explicit_overlaps(scene, &particles, &shapes, &domain)?;

    // Walls.
    let (walls, wall_groups, drums) = crate::walls::compile_walls(scene, &lookup, &domain)?;
    let mut flow_planes: Vec<FlowPlane> = Vec::new();
    for (k, fp) in scene.output.flow_planes.iter().enumerate() {
        let f = |x: &str| format!("output.flow_planes[{k}].{x}");
        if fp.name.trim().is_empty() || flow_planes.iter().any(|p| p.name == fp.name) {
            return Err(SceneError::field(f("name"), format!("each flow plane needs its own non-empty name, got \"{}\"", fp.name)));
        }
        flow_planes.push(FlowPlane { name: fp.name.clone(), plane: Plane::new(finite3(&f("point"), fp.point)?, unit(&f("normal"), fp.normal)?) });
    }

    // Fluid.
    let fluid = match &scene.fluid {
        None => None,
        Some(fl) => {
            let drag = match fl.drag {
                DragName::Stokes => Drag::Stokes {
                    viscosity: match fl.viscosity {
                        Some(ViscositySpec::PascalSeconds(mu)) => positive("fluid.viscosity", mu)?,
                        Some(ViscositySpec::Target(_)) => f64::NAN, // from the Stokes number, in targets::resolve
                        None => {
                            return Err(SceneError::field(
                                "fluid.viscosity",
                                "Stokes drag needs the dynamic viscosity in Pa s or { stokes_number = Stk }",
                            ));
                        }
                    },
                },
                DragName::Quadratic => Drag::Quadratic {
                    coefficient: positive(
                        "fluid.coefficient",
                        fl.coefficient.ok_or_else(|| SceneError::field("fluid.coefficient", "quadratic drag needs the coefficient α in kg/m"))?,
                    )?,
                },
            };
            let flow = match &fl.flow {
                FlowSection::Uniform(u) => FlowField::Uniform(finite3("fluid.flow.uniform", *u)?),
                FlowSection::TaylorGreen(tg) => FlowField::TaylorGreen {
                    amplitude: finite3("fluid.flow.taylor_green.amplitude", [tg.amplitude, 0.0, 0.0])?.x,
                    frequency: positive("fluid.flow.taylor_green.frequency", tg.frequency)?,
                },
            };
            Some(Fluid { drag, flow })
        }
    };
    let mut fluid = fluid;
    let targets = crate::targets::resolve(scene, &particles, &materials, &mut pairs, &cohesion_specs, &mut fluid)?;
    let gravity = match &scene.gravity {
        Some(g) => finite3("gravity.acceleration", g.acceleration)?,
        None => DVec3::ZERO,
    };

    // Features.
    let movable = particles.fixed.iter().any(|f| !f);
    let any_friction = pairs.iter().any(|p| p.tangential != TangentialLaw::None);
    let history = pairs.iter().any(|p| p.tangential.has_history());
    let rolling = pairs.iter().any(|p| p.rolling > 0.0);
    let history_slots = match scene.contact.history_slots {
        Some(0) => return Err(SceneError::field("contact.history_slots", "must be at least 1 (contacts with history per particle)")),
        Some(k) => k as usize,
        None => DEFAULT_HISTORY_SLOTS,
    };
    let polyhedra = !shapes.is_empty();
    let (rotation, rotation_reason) = match scene.run.rotation {
        RotationMode::Off if polyhedra => {
            return Err(SceneError::field(
                "run.rotation",
                "polyhedra turn under their contact forces (the normal force does not pass through the centre); remove run.rotation = \"off\"",
            ));
        }
        _ if polyhedra => (true, "polyhedra: normal forces act off the centre of mass, so every body carries an orientation".to_string()),
        RotationMode::On => (true, "run.rotation = \"on\"".to_string()),
        RotationMode::Off if rolling => {
            return Err(SceneError::field(
                "run.rotation",
                "rolling_friction is a torque and needs rotation; remove run.rotation = \"off\" or the rolling friction",
            ));
        }
        RotationMode::Off => (false, "run.rotation = \"off\" (tangential forces act on the centre only)".to_string()),
        RotationMode::Auto if rolling && movable => (true, "rolling resistance exerts torques".to_string()),
        RotationMode::Auto if any_friction && movable => (true, "tangential friction exerts torques".to_string()),
        RotationMode::Auto => (false, "no tangential force, so no torque: no rotation state is carried".to_string()),
    };
    let cohesion = pairs.iter().any(|p| p.cohesion > 0.0);
    if polyhedra && cohesion {
        return Err(SceneError::field("contact.cohesion", "cohesion acts between spheres only; this scene has polyhedral particles"));
    }
    if polyhedra && fluid.is_some() {
        return Err(SceneError::field("fluid", "fluid drag is modelled for spheres only; this scene has polyhedral particles"));
    }
    let max_reach = (0..particles.len())
        .map(|i| if cohesion { particles.effect_radius[i].max(particles.radius[i]) } else { particles.radius[i] })
        .fold(0.0, f64::max);
    let cell_size = 2.0 * max_reach;
    let skin_fraction = scene.run.skin.unwrap_or(DEFAULT_SKIN);
    if !(skin_fraction > 0.0 && skin_fraction <= 1.0) {
        return Err(SceneError::field("run.skin", format!("must lie in (0, 1] (a fraction of the interaction diameter), got {skin_fraction}")));
    }
    let skin = skin_fraction * cell_size;
    for k in 0..3 {
        if domain.periodic[k] && domain.extent()[k] < 2.0 * (cell_size + skin) {
            return Err(SceneError::field(
                "domain.periodic",
                format!(
                    "axis {k} is periodic but only {} m long; it must be at least two interaction diameters plus skin ({} m)",
                    domain.extent()[k],
                    2.0 * (cell_size + skin)
                ),
            ));
        }
    }

    // Time scales.
    let run = &scene.run;
    positive("run.duration", run.duration)?;
    let integrator = Integrator::from_name(match run.integrator {
        IntegratorName::Euler => "euler",
        IntegratorName::SymplecticEuler => "symplectic-euler",
        IntegratorName::Verlet => "verlet",
        IntegratorName::ImplicitDrag => "implicit-drag",
        IntegratorName::ImplicitDragSymplectic => "implicit-drag-symplectic",
    })
    .unwrap();
    let mut timescales =
        crate::timescales::timescales(&particles, &shapes, &materials, &pairs, &walls, fluid.as_ref(), integrator, gravity, &domain, rotation);
    // Moving geometry: a wall must not advance more than 0.025 r_min per step.
    let wall_step_limit = walls.iter().filter(|w| w.surface_speed > 0.0).max_by(|a, b| a.surface_speed.total_cmp(&b.surface_speed)).and_then(|w| {
        let r_min = (0..particles.len()).filter(|&i| !particles.fixed[i]).map(|i| particles.radius[i]).fold(f64::INFINITY, f64::min);
        r_min.is_finite().then(|| WallStepLimit {
            dt: WALL_ADVANCE_FRACTION * r_min / w.surface_speed,
            wall: wall_groups[w.group as usize].name.clone(),
            speed: w.surface_speed,
            r_min,
        })
    });
    if let Some(w) = &wall_step_limit {
        timescales.default_dt = timescales.default_dt.min(w.dt);
    }
    let dt = match run.dt {
        None => timescales.default_dt.min(run.duration),
        Some(DtSpec::Seconds(dt)) => positive("run.dt", dt)?,
        Some(DtSpec::Fraction(f)) => {
            positive("run.dt.collision_fraction", f.collision_fraction)?;
            let t = timescales
                .collision_time
                .ok_or_else(|| SceneError::field("run.dt.collision_fraction", "this scene has no contact time to divide; give dt in seconds"))?;
            t / f.collision_fraction
        }
    };
    if let Some(limit) = timescales.stability_limit
        && dt > limit
        && !run.allow_unstable_dt
    {
        return Err(SceneError::field(
            "run.dt",
            format!(
                "dt = {dt:.4e} s is above the stability limit {limit:.4e} s of this scene; use dt <= {limit:.4e} (the plan's default is {:.4e}) or set run.allow_unstable_dt = true",
                timescales.default_dt
            ),
        ));
    }
    if let Some(w) = &wall_step_limit
        && dt > w.dt
        && !run.allow_unstable_dt
    {
        return Err(SceneError::field(
            "run.dt",
            format!(
                "dt = {dt:.4e} s lets wall \"{}\" (moving at {:.4} m/s) advance more than {WALL_ADVANCE_FRACTION} r_min = {:.3e} m per step; use dt <= {:.4e} or set run.allow_unstable_dt = true",
                w.wall,
                w.speed,
                WALL_ADVANCE_FRACTION * w.r_min,
                w.dt
            ),
        ));
    }
    let steps = (run.duration / dt - 1e-9).ceil().max(1.0) as u64;
    let output_interval = run.output_interval.unwrap_or(run.duration / 100.0);
    positive("run.output_interval", output_interval)?;
    let output_every = ((output_interval / dt).round() as u64).max(1);
    let snapshot_every = match run.snapshot_interval {
        Some(s) => Some(((positive("run.snapshot_interval", s)? / dt).round() as u64).max(1)),
        None => None,
    };
    if let Some(r) = run.resort_interval
        && r == 0
    {
        return Err(SceneError::field("run.resort_interval", "must be at least 1 step"));
    }
    positive("run.monitor.max_overlap_ratio", run.monitor.max_overlap_ratio)?;
    positive("run.monitor.energy_growth", run.monitor.energy_growth)?;

    let mut features = vec![
        Feature { name: "rotation", active: rotation, reason: rotation_reason },
        Feature {
            name: "polyhedra",
            active: polyhedra,
            reason: if polyhedra {
                let names: Vec<String> = shapes.iter().map(|s| format!("{} ({} faces)", s.name, s.body.faces().len())).collect();
                format!("convex polyhedra: {}; bounding radius sets the search reach", names.join(", "))
            } else {
                "every particle is a sphere: no orientation or shape is carried".into()
            },
        },
        Feature {
            name: "cohesion",
            active: cohesion,
            reason: if cohesion {
                format!("a contact has cohesion stiffness; the search reaches the effect diameter (cell {cell_size:.4e} m)")
            } else {
                "no cohesion in [contact]: the search stops at body contact".into()
            },
        },
        Feature {
            name: "drag",
            active: fluid.is_some(),
            reason: match &fluid {
                Some(f) => format!(
                    "[fluid] {:?}, {}",
                    f.drag,
                    if integrator.implicit_drag() { "integrated implicitly" } else { "added as an explicit force" }
                ),
                None => "no [fluid] section: no drag pass".into(),
            },
        },
        Feature {
            name: "gravity",
            active: gravity != DVec3::ZERO,
            reason: if gravity != DVec3::ZERO { format!("{:?} m/s²", gravity.to_array()) } else { "no [gravity] section".into() },
        },
        Feature {
            name: "walls",
            active: !walls.is_empty(),
            reason: {
                let moving = walls.iter().filter(|w| w.motion.is_some()).count();
                let mut r = format!("{} static surfaces", walls.len() - moving);
                if moving > 0 {
                    let _ = write!(r, ", {moving} moving (wall velocity enters the contact; rebuild when a wall sweeps skin/2)");
                }
                if !drums.is_empty() {
                    let _ = write!(r, "; drums {}", drums.iter().map(|d| d.name.as_str()).collect::<Vec<_>>().join(", "));
                }
                r
            },
        },
        Feature {
            name: "periodic",
            active: domain.periodic.iter().any(|&p| p),
            reason: format!("periodic axes {:?}; particles leaving other sides are removed", domain.periodic),
        },
        Feature { name: "normal", active: true, reason: describe_law(&pairs[0].normal) },
        Feature { name: "tangential", active: any_friction, reason: describe_tangential(&pairs[0].tangential) },
        Feature {
            name: "history",
            active: history,
            reason: if history {
                format!("tangential model \"history\": {history_slots} spring slots per particle, keyed by neighbour id")
            } else {
                "no tangential spring: no per-contact state is carried".into()
            },
        },
        Feature {
            name: "rolling",
            active: rolling,
            reason: if rolling {
                format!("rolling resistance μ_r = {} (constant directional torque)", pairs.iter().map(|p| p.rolling).fold(0.0, f64::max))
            } else {
                "no rolling_friction: no rolling torque".into()
            },
        },
    ];
    let agglomerates = scene.run.agglomerates.unwrap_or(cohesion);
    features.push(Feature {
        name: "agglomerates",
        active: agglomerates,
        reason: match scene.run.agglomerates {
            Some(true) => "run.agglomerates = true: agglomerates.csv at every output interval".into(),
            Some(false) => "run.agglomerates = false".into(),
            None if cohesion => "cohesion is on: agglomerates.csv at every output interval (run.agglomerates = false turns it off)".into(),
            None => "no cohesion (run.agglomerates = true writes agglomerates.csv anyway)".into(),
        },
    });
    if !movable {
        features.push(Feature { name: "motion", active: false, reason: "every particle is fixed".into() });
    }
    let mut warnings = Vec::new();
    if let Some(t) = timescales.collision_time
        && t / dt < 10.0
    {
        warnings.push(format!("only {:.1} steps per collision; results will be inaccurate (50 is the default)", t / dt));
    }
    if let Some(t) = timescales.tangential_time
        && dt > t / 6.0
    {
        warnings.push(format!(
                "dt is more than 1/6 of the viscous tangential relaxation time {t:.3e} s: dense packings may chatter (energy booked as dissipated while at rest); use dt <= {:.3e} or a smaller c_t",
                t / 6.0
            ));
    }
    if looks_quasi_static(&particles, &pairs, gravity, &walls, fluid.as_ref()) {
        warnings.push(
            "this scene looks quasi-static (gravity, walls, particles starting at rest, no fluid) but its friction is history-free: \
             piles and slopes creep at the speed where the viscous force balances gravity; use tangential model = \"history\" to hold static loads"
                .into(),
        );
    }
    let bytes_per_particle = 8 * (3 * 3 + 6) // position, velocity, acceleration; radius, effect, inverse mass, mass, dissipation, elastic
        + 8 * 4 + 8 * 3 // sorted position and reach for the broad phase, reference position of the neighbour list
        + 6 * (4 * 2 + 4 * 2) + 6 * if rotation { 72 } else { 48 } // ~6 listed pairs: indices, incidence, pair results
        + 2 + 2 + 4 + 4 + 4 + 4 + 8 // material, group, id, flags, order, cell, overlap
        + if rotation { 8 * 7 } else { 0 } // angular velocity and acceleration, inverse inertia
        + if integrator == Integrator::Verlet { 24 * if rotation { 2 } else { 1 } } else { 0 }
        + if fluid.is_some() { 8 } else { 0 }
        + if history { 2 * (2 + history_slots * (4 + 32)) } else { 0 } // two generations of spring slots: count, neighbour id, ξ and its energy
        + if polyhedra { 2 + 32 + 24 } else { 0 }; // shape index, orientation, principal inverse inertia

    Ok(CompiledScene {
        plan: Plan {
            name: scene.name.clone(),
            duration: run.duration,
            dt,
            steps,
            output_every,
            snapshot_every,
            integrator,
            backend: run.backend,
            rotation,
            polyhedra,
            shapes,
            cohesion,
            history,
            history_slots,
            rolling,
            fluid,
            gravity,
            domain,
            materials,
            pairs,
            walls,
            wall_groups,
            drums,
            flow_planes,
            wall_step_limit,
            group_names: scene.particles.iter().enumerate().map(|(g, p)| p.name.clone().unwrap_or_else(|| format!("group{g}"))).collect(),
            cell_size,
            skin,
            timescales,
            features,
            warnings,
            resort_interval: run.resort_interval.unwrap_or(25),
            monitor: run.monitor,
            bytes_per_particle,
            agglomerates,
            targets,
        },
        particles,
    })
}

/// Gravity pressing particles that start at rest onto walls, with history-free friction.
fn looks_quasi_static(p: &InitialParticles, pairs: &[PairParams], gravity: DVec3, walls: &[Wall], fluid: Option<&Fluid>) -> bool {
    let history_free = pairs.iter().any(|p| p.tangential.friction() > 0.0 && !p.tangential.has_history());
    let at_rest = p.velocity.iter().all(|v| *v == DVec3::ZERO);
    history_free && gravity != DVec3::ZERO && !walls.is_empty() && fluid.is_none() && at_rest
}

fn describe_law(law: &NormalLaw) -> String {
    match law {
        NormalLaw::Linear { stiffness, restitution, .. } => format!("linear spring-dashpot, k_n = {stiffness:e} N/m, e = {restitution}"),
        NormalLaw::Hertz { e_star, restitution, .. } => format!("Hertz with Tsuji damping, E* = {e_star:e} Pa, e = {restitution}"),
    }
}

fn describe_tangential(law: &TangentialLaw) -> String {
    match law {
        TangentialLaw::None => "none: no tangential force".into(),
        TangentialLaw::ViscousCoulomb { friction, viscous: ViscousParameter::Coefficient(c) } => {
            format!("viscous-Coulomb, μ = {friction}, c_t = {c:e} N s/m (history-free)")
        }
        TangentialLaw::ViscousCoulomb { friction, viscous: ViscousParameter::Stiffness(k) } => {
            format!("viscous-Coulomb, μ = {friction}, c_t = k_f t_col with k_f = {k:e} N/m (history-free)")
        }
        TangentialLaw::StickLimited { friction } => format!("stick-limited, μ = {friction} (history-free)"),
        TangentialLaw::DynamicOnly { friction } => format!("dynamic-only, μ = {friction}: oscillates around rest (a documented failure case)"),
        TangentialLaw::History { friction, spring: SpringLaw::Linear { stiffness, damping, damping_ratio } } => {
            let eta = if *damping_ratio > 0.0 { format!("damping ratio {damping_ratio:.4}") } else { format!("η_t = {damping:e} N s/m") };
            format!("history (Cundall–Strack), μ = {friction}, k_t = {stiffness:e} N/m, {eta}: a spring per contact holds static loads")
        }
        TangentialLaw::History { friction, spring: SpringLaw::Mindlin { g_star, .. } } => {
            format!("history (Hertz–Mindlin), μ = {friction}, k_t = 8 G* √(R* δ) with G* = {g_star:e} Pa: a spring per contact holds static loads")
        }
    }
}

#[allow(clippy::too_many_arguments)]
fn pair_params(
    root: &str,
    normal: &NormalSection,
    e: f64,
    tangential: &TangentialSection,
    cohesion: Option<&CohesionSection>,
    no_attraction: bool,
    a: &Material,
    b: &Material,
) -> Result<PairParams, SceneError> {
    if !(e > 0.0 && e <= 1.0) {
        return Err(SceneError::field(format!("{root}.restitution"), format!("must lie in (0, 1], got {e}")));
    }
    let normal = match normal {
        NormalSection::Linear { stiffness } => NormalLaw::linear(positive(&format!("{root}.normal.stiffness"), *stiffness)?, e),
        NormalSection::Hertz {} => {
            let need = |m: &Material| -> Result<(f64, f64), SceneError> {
                match (m.youngs_modulus, m.poisson_ratio) {
                    (Some(y), Some(nu)) => Ok((y, nu)),
                    _ => Err(SceneError::field(
                        format!("{root}.normal"),
                        format!("the Hertz model needs youngs_modulus and poisson_ratio on material \"{}\"", m.name),
                    )),
                }
            };
            let ((ea, na), (eb, nb)) = (need(a)?, need(b)?);
            let (e_star, g_star) = hertz_effective_moduli(ea, na, eb, nb);
            NormalLaw::hertz(e_star, g_star, e)
        }
    };
    let mu = |f: f64| -> Result<f64, SceneError> { non_negative(&format!("{root}.tangential.friction"), f) };
    let tangential = match tangential {
        TangentialSection::None => TangentialLaw::None,
        TangentialSection::ViscousCoulomb { friction, stiffness, viscous } => {
            let viscous = match (stiffness, viscous) {
                (Some(k), None) => ViscousParameter::Stiffness(positive(&format!("{root}.tangential.stiffness"), *k)?),
                (None, Some(c)) => ViscousParameter::Coefficient(positive(&format!("{root}.tangential.viscous"), *c)?),
                _ => {
                    return Err(SceneError::field(
                        format!("{root}.tangential"),
                        "viscous-coulomb needs exactly one of stiffness (k_f, N/m) or viscous (c_t, N s/m)",
                    ));
                }
            };
            TangentialLaw::ViscousCoulomb { friction: mu(*friction)?, viscous }
        }
        TangentialSection::StickLimited { friction } => TangentialLaw::StickLimited { friction: mu(*friction)? },
        TangentialSection::DynamicOnly { friction } => TangentialLaw::DynamicOnly { friction: mu(*friction)? },
        TangentialSection::History { friction, stiffness, damping } => {
            let stiffness = stiffness.map(|k| positive(&format!("{root}.tangential.stiffness"), k)).transpose()?;
            let damping = damping.map(|c| non_negative(&format!("{root}.tangential.damping"), c)).transpose()?;
            let spring = match (normal, stiffness) {
                (NormalLaw::Hertz { g_star, beta, .. }, None) => {
                    if damping.is_some() {
                        return Err(SceneError::field(
                            format!("{root}.tangential.damping"),
                            "Hertz–Mindlin derives η_t from G* and e; give damping only with an explicit stiffness (Cundall–Strack)",
                        ));
                    }
                    SpringLaw::Mindlin { g_star, beta }
                }
                (NormalLaw::Linear { stiffness: k_n, damping_ratio, .. }, k_t) => {
                    linear_spring(k_t.unwrap_or(2.0 / 7.0 * k_n), damping, damping_ratio)
                }
                (NormalLaw::Hertz { beta, .. }, Some(k_t)) => linear_spring(k_t, damping, -beta),
            };
            TangentialLaw::History { friction: mu(*friction)?, spring }
        }
    };
    let cohesion = match cohesion {
        Some(CohesionSection { stiffness: Some(k), stickiness_number: None, .. }) => positive(&format!("{root}.cohesion.stiffness"), *k)?,
        // Derived from Sy once the particles are known (targets::resolve).
        Some(CohesionSection { stiffness: None, stickiness_number: Some(_), .. }) => f64::NAN,
        Some(_) => {
            return Err(SceneError::field(format!("{root}.cohesion"), "give exactly one of stiffness (k_c, N/m) or stickiness_number (Sy)"));
        }
        None => 0.0,
    };
    Ok(PairParams { normal, tangential, cohesion, no_attraction, rolling: 0.0 })
}

/// Cundall–Strack spring: the given η_t, or the normal law's damping ratio applied to k_t.
fn linear_spring(stiffness: f64, damping: Option<f64>, damping_ratio: f64) -> SpringLaw {
    match damping {
        Some(damping) => SpringLaw::Linear { stiffness, damping, damping_ratio: 0.0 },
        None => SpringLaw::Linear { stiffness, damping: 0.0, damping_ratio },
    }
}

/// Default contacts with history per particle: a sphere among equal ones touches at most 12.
const DEFAULT_HISTORY_SLOTS: usize = 16;

/// Default neighbour-list skin, as a fraction of the largest interaction diameter.
const DEFAULT_SKIN: f64 = 0.1;

/// Body contacts closer than this fraction of the smaller diameter count as overlapping.
const OVERLAP_TOLERANCE: f64 = 1e-9;

fn check_explicit_overlaps(scene: &Scene, p: &InitialParticles, shapes: &[crate::ParticleShape], domain: &PeriodicBox) -> Result<(), SceneError> {
    use tumble_geom::{Pose, polyhedron_polyhedron, sphere_polyhedron};
    // Depth of the body overlap of i and j (bounding spheres are only a first test for polyhedra).
    let body_overlap = |i: usize, j: usize, d: DVec3, sphere_overlap: f64| -> f64 {
        let pose = |k: usize, x: DVec3| (&shapes[p.shape[k] as usize].body, Pose::new(x, p.orientation[k]));
        let (xi, xj) = (p.position[i], p.position[i] - d);
        let contact = match (p.shape[i] != crate::SPHERE, p.shape[j] != crate::SPHERE) {
            (false, false) => return sphere_overlap,
            (true, true) => {
                let ((a, pa), (b, pb)) = (pose(i, xi), pose(j, xj));
                polyhedron_polyhedron(a, &pa, b, &pb)
            }
            (true, false) => {
                let (a, pa) = pose(i, xi);
                sphere_polyhedron(xj, p.radius[j], a, &pa)
            }
            (false, true) => {
                let (b, pb) = pose(j, xj);
                sphere_polyhedron(xi, p.radius[i], b, &pb)
            }
        };
        contact.map_or(-1.0, |c| c.depth)
    };
    let explicit: Vec<usize> = (0..p.len()).filter(|&i| scene.particles[p.group[i] as usize].positions.is_some()).collect();
    if explicit.len() > 20_000 {
        return Ok(()); // too many to check pairwise; lattice and random groups are safe by construction
    }
    for (a, &i) in explicit.iter().enumerate() {
        for &j in &explicit[a + 1..] {
            let dv = domain.minimum_image(p.position[i] - p.position[j]);
            let mut overlap = p.radius[i] + p.radius[j] - dv.length();
            if overlap > 0.0 {
                overlap = body_overlap(i, j, dv, overlap);
            }
            if overlap > OVERLAP_TOLERANCE * 2.0 * p.radius[i].min(p.radius[j]) {
                return Err(SceneError::field(
                    format!("particles[{}].positions", p.group[j]),
                    format!(
                        "particle at {:?} overlaps the particle at {:?} by {overlap:.3e} m; explicit particles must not overlap",
                        p.position[j].to_array(),
                        p.position[i].to_array()
                    ),
                ));
            }
        }
    }
    Ok(())
}
