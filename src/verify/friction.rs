//! Friction studies (issue: contact history): oblique impacts on a wall, creep on
//! an incline without rotation, and rolling on an incline, for every tangential
//! model. One sphere on a floor; the scene is tilted by tilting gravity.

use crate::Simulation;
use glam::DVec3;
use tumble_scene::schema::BackendName;
use tumble_scene::{CompiledScene, compile, parse_scene};

/// The tangential models compared.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum FrictionModel {
    /// Cundall–Strack spring, k_t = 2/7 k_n.
    History,
    /// Viscous-Coulomb with k_f = k_n (c_t = k_f t_col).
    ViscousCoulomb,
    StickLimited,
    DynamicOnly,
}

impl FrictionModel {
    pub const ALL: [FrictionModel; 4] =
        [FrictionModel::History, FrictionModel::ViscousCoulomb, FrictionModel::StickLimited, FrictionModel::DynamicOnly];

    pub fn name(self) -> &'static str {
        match self {
            FrictionModel::History => "history",
            FrictionModel::ViscousCoulomb => "viscous-coulomb",
            FrictionModel::StickLimited => "stick-limited",
            FrictionModel::DynamicOnly => "dynamic-only",
        }
    }

    fn toml(self, mu: f64) -> String {
        match self {
            FrictionModel::ViscousCoulomb => format!("{{ model = \"viscous-coulomb\", friction = {mu}, stiffness = {K_N:e} }}"),
            m => format!("{{ model = \"{}\", friction = {mu} }}", m.name()),
        }
    }
}

/// The sphere: d = 0.1 m, ρ = 10 kg/m³, k_n = 1e5 N/m (verification case 8's).
pub const DIAMETER: f64 = 0.1;
const DENSITY: f64 = 10.0;
const K_N: f64 = 1.0e5;
pub const G: f64 = 9.81;

pub fn sphere_mass() -> f64 {
    DENSITY * std::f64::consts::PI / 6.0 * DIAMETER.powi(3)
}

/// c_t = k_f t_col of the viscous-Coulomb model against the floor (k_f = k_n).
pub fn viscous_coefficient(restitution: f64) -> f64 {
    K_N * tumble_contact::collision_time(K_N, sphere_mass(), restitution)
}

/// The step these studies run at: t_col / 50 against the floor.
pub fn floor_dt(restitution: f64) -> f64 {
    tumble_contact::collision_time(K_N, sphere_mass(), restitution) / 50.0
}

/// One sphere on the floor z = 0, with the given friction, gravity and start.
pub struct FloorScene {
    pub model: FrictionModel,
    pub friction: f64,
    pub restitution: f64,
    pub rolling_friction: f64,
    pub rotation: bool,
    /// Hertz normal law (E = 1e7 Pa, ν = 0.3; history becomes Hertz–Mindlin) instead of linear.
    pub hertz: bool,
    pub gravity: DVec3,
    pub position: DVec3,
    pub velocity: DVec3,
    pub duration: f64,
}

impl FloorScene {
    /// A sphere at rest on an incline of `angle_deg` (gravity tilted), at its equilibrium overlap.
    pub fn incline(model: FrictionModel, friction: f64, angle_deg: f64, duration: f64) -> Self {
        let t = angle_deg.to_radians();
        let gravity = G * DVec3::new(t.sin(), 0.0, -t.cos());
        let overlap = sphere_mass() * G * t.cos() / K_N;
        FloorScene {
            model,
            friction,
            restitution: 0.8,
            rolling_friction: 0.0,
            rotation: true,
            hertz: false,
            gravity,
            position: DVec3::new(0.0, 0.0, 0.5 * DIAMETER - overlap),
            velocity: DVec3::ZERO,
            duration,
        }
    }

    pub fn compile(&self) -> CompiledScene {
        compile(&self.parsed()).expect("friction study scene compiles")
    }

    /// The scene before compilation, for studies that change a setting the fields do not carry.
    pub fn parsed(&self) -> tumble_scene::schema::Scene {
        let v = |x: DVec3| format!("[{:e}, {:e}, {:e}]", x.x, x.y, x.z);
        let mut text = format!(
            "name = \"friction-study\"\n[run]\nduration = {}\ndt = {{ collision_fraction = 50 }}\nintegrator = \"verlet\"\nrotation = \"{}\"\n\
             [domain]\nmin = [-10.0, -1.0, -1.0]\nmax = [10.0, 1.0, 1.0]\n[gravity]\nacceleration = {}\n\
             [[materials]]\nname = \"light\"\ndensity = {DENSITY}\n{}\
             [contact]\nnormal = {}\nrestitution = {}\ntangential = {}\n",
            self.duration,
            if self.rotation { "on" } else { "off" },
            v(self.gravity),
            if self.hertz { "youngs_modulus = 1.0e7\npoisson_ratio = 0.3\n" } else { "" },
            if self.hertz { "{ model = \"hertz\" }".to_string() } else { format!("{{ model = \"linear\", stiffness = {K_N:e} }}") },
            self.restitution,
            self.model.toml(self.friction),
        );
        if self.rolling_friction > 0.0 {
            text += &format!("rolling_friction = {}\n", self.rolling_friction);
        }
        text += &format!(
            "[[particles]]\nmaterial = \"light\"\nshape = {{ sphere = {{ diameter = {DIAMETER} }} }}\npositions = [{}]\nvelocity = {}\ntrack = true\n\
             [[walls]]\nname = \"floor\"\nmaterial = \"light\"\nplane = {{ point = [0.0, 0.0, 0.0], normal = [0.0, 0.0, 1.0] }}\n",
            v(self.position),
            v(self.velocity)
        );
        let mut scene = parse_scene(&text).expect("friction study scene parses");
        scene.run.monitor.enabled = false;
        scene
    }
}

/// Rebound of one oblique impact, as ratios to the impact's components.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Impact {
    /// Angle between the impact velocity and the wall normal, degrees.
    pub angle_deg: f64,
    /// v_t' / v_t.
    pub tangential: f64,
    /// R ω' / v_t.
    pub spin: f64,
    /// v_n' / v_n.
    pub normal: f64,
}

/// Rigid-body Coulomb theory for an impact that slides throughout: (v_t'/v_t, R ω'/v_t).
/// Valid while tan θ ≥ 7/2 μ (1 + e); below, a rigid sphere ends rolling at 5/7 v_t.
pub fn coulomb_impact(angle_deg: f64, friction: f64, restitution: f64) -> (f64, f64) {
    let t = angle_deg.to_radians().tan();
    if t >= 3.5 * friction * (1.0 + restitution) {
        (1.0 - friction * (1.0 + restitution) / t, 2.5 * friction * (1.0 + restitution) / t)
    } else {
        (5.0 / 7.0, 5.0 / 7.0)
    }
}

/// A sphere hits the floor at 1 m/s and `angle_deg` from the normal, without gravity
/// (linear normal law, or Hertz with `hertz`).
pub fn oblique_impact(model: FrictionModel, hertz: bool, friction: f64, restitution: f64, angle_deg: f64) -> Impact {
    oblique_impact_on(BackendName::Cpu, model, hertz, friction, restitution, angle_deg)
}

/// [`oblique_impact`] on a chosen backend.
pub fn oblique_impact_on(backend: BackendName, model: FrictionModel, hertz: bool, friction: f64, restitution: f64, angle_deg: f64) -> Impact {
    oblique_impact_with(backend, model, hertz, friction, restitution, angle_deg, false)
}

/// [`oblique_impact_on`] with the normal force clipped at zero (`no_attraction`) when asked.
pub fn oblique_impact_with(
    backend: BackendName,
    model: FrictionModel,
    hertz: bool,
    friction: f64,
    restitution: f64,
    angle_deg: f64,
    no_attraction: bool,
) -> Impact {
    let t = angle_deg.to_radians();
    let speed = 1.0;
    let (vt, vn) = (speed * t.sin(), speed * t.cos());
    let t_col = tumble_contact::collision_time(K_N, sphere_mass(), restitution);
    let gap = 1e-4;
    let scene = FloorScene {
        model,
        friction,
        restitution,
        rolling_friction: 0.0,
        rotation: true,
        hertz,
        gravity: DVec3::ZERO,
        position: DVec3::new(0.0, 0.0, 0.5 * DIAMETER + gap),
        velocity: DVec3::new(vt, 0.0, -vn),
        // Hertz contacts at 1 m/s are shorter than the linear ones here.
        duration: gap / vn + 2.0 * t_col,
    };
    let mut parsed = scene.parsed();
    parsed.contact.as_mut().expect("the case has a [contact] table").no_attraction = no_attraction;
    let compiled = compile(&parsed).expect("oblique impact scene compiles");
    let steps = compiled.plan.run.steps;
    let mut sim = on(backend, compiled);
    sim.advance(steps);
    let r = sim.tracks()[0];
    Impact { angle_deg, tangential: r.velocity.x / vt, spin: 0.5 * DIAMETER * r.angular_velocity.y / vt, normal: r.velocity.z / vn }
}

/// Mean speed down an incline over [duration/2, duration] for a sphere that cannot roll.
pub fn creep_speed(model: FrictionModel, friction: f64, angle_deg: f64, duration: f64) -> f64 {
    creep_speed_on(BackendName::Cpu, model, friction, angle_deg, duration)
}

/// [`creep_speed`] on a chosen backend.
pub fn creep_speed_on(backend: BackendName, model: FrictionModel, friction: f64, angle_deg: f64, duration: f64) -> f64 {
    let mut scene = FloorScene::incline(model, friction, angle_deg, duration);
    scene.rotation = false;
    let (x0, x1) = positions_at(backend, scene.compile(), duration);
    (x1 - x0) / (0.5 * duration)
}

/// x at half the duration and at the end.
fn positions_at(backend: BackendName, compiled: CompiledScene, duration: f64) -> (f64, f64) {
    let steps = compiled.plan.run.steps;
    let half = (0.5 * duration / compiled.plan.model.dt).round() as u64;
    let mut sim = on(backend, compiled);
    sim.advance(half);
    let x0 = sim.tracks()[0].position.x;
    sim.advance(steps - half);
    (x0, sim.tracks()[0].position.x)
}

/// Motion on an incline with rotation: accelerations fitted between two times.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct InclineMotion {
    /// dv/dt down the slope.
    pub acceleration: f64,
    /// R dω/dt.
    pub spin_acceleration: f64,
    /// |v − ω R| at the end.
    pub slip: f64,
    /// Distance travelled over the whole run.
    pub distance: f64,
}

/// A sphere released at rest on an incline, rotation on, over `duration`.
pub fn incline_motion(model: FrictionModel, friction: f64, rolling_friction: f64, angle_deg: f64, duration: f64) -> InclineMotion {
    incline_motion_on(BackendName::Cpu, model, friction, rolling_friction, angle_deg, duration)
}

/// [`incline_motion`] on a chosen backend.
pub fn incline_motion_on(
    backend: BackendName,
    model: FrictionModel,
    friction: f64,
    rolling_friction: f64,
    angle_deg: f64,
    duration: f64,
) -> InclineMotion {
    let mut scene = FloorScene::incline(model, friction, angle_deg, duration);
    scene.rolling_friction = rolling_friction;
    let compiled = scene.compile();
    let steps = compiled.plan.run.steps;
    let r = 0.5 * DIAMETER;
    let x_start = scene.position.x;
    let mut sim = on(backend, compiled);
    // Skip the first fifth: the contact settles from its equilibrium estimate.
    let first = steps / 5;
    sim.advance(first);
    let (t0, a) = (sim.time(), sim.tracks()[0]);
    sim.advance(steps - first);
    let (t1, b) = (sim.time(), sim.tracks()[0]);
    InclineMotion {
        acceleration: (b.velocity.x - a.velocity.x) / (t1 - t0),
        spin_acceleration: r * (b.angular_velocity.y - a.angular_velocity.y) / (t1 - t0),
        slip: (b.velocity.x - r * b.angular_velocity.y).abs(),
        distance: b.position.x - x_start,
    }
}

/// A one-thread simulation on `backend` (panics when the backend cannot run the scene).
fn on(backend: BackendName, compiled: CompiledScene) -> Simulation {
    Simulation::on(backend, compiled, 1).unwrap_or_else(|e| panic!("{backend:?}: {e}"))
}
