//! The particle-impact benchmarks of Chung & Ooi (2011, Granular Matter 13:643–656):
//! normal Hertz impacts (sphere–sphere, sphere–wall, different sizes, different e) and
//! oblique impacts with and without spin, measured per step and compared with Hertz
//! theory and rigid-body Coulomb theory (docs/chung-ooi.md).
//!
//! Geometry: the contact normal is +z. Body `a` is above, moving down onto the wall
//! z = 0 or onto body `b` below. Tangential motion is along x, spin about y.

use super::FrictionModel;
use crate::{Simulation, TrackRow};
pub use glam::DVec3;
use tumble_scene::schema::{BackendName, DtSpec};
use tumble_scene::{compile, parse_scene};

/// An elastic solid of the paper.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Material {
    pub name: &'static str,
    pub density: f64,
    pub youngs_modulus: f64,
    pub poisson_ratio: f64,
}

pub const GLASS: Material = Material { name: "glass", density: 2800.0, youngs_modulus: 4.8e10, poisson_ratio: 0.2 };
pub const LIMESTONE: Material = Material { name: "limestone", density: 2500.0, youngs_modulus: 2.0e10, poisson_ratio: 0.25 };
pub const ALUMINIUM_ALLOY: Material = Material { name: "aluminium-alloy", density: 2700.0, youngs_modulus: 7.0e10, poisson_ratio: 0.33 };
pub const MAGNESIUM_ALLOY: Material = Material { name: "magnesium-alloy", density: 1800.0, youngs_modulus: 4.0e10, poisson_ratio: 0.35 };
pub const ALUMINIUM_OXIDE: Material = Material { name: "aluminium-oxide", density: 4000.0, youngs_modulus: 3.8e11, poisson_ratio: 0.23 };

/// The wall: the paper's plane is rigid; here it is 1000 times stiffer than the sphere.
fn wall_material(m: Material) -> Material {
    Material { name: "wall", youngs_modulus: 1000.0 * m.youngs_modulus, ..m }
}

/// One sphere's start.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Body {
    pub material: Material,
    pub radius: f64,
    pub velocity: DVec3,
    pub angular_velocity: DVec3,
}

impl Body {
    pub fn new(material: Material, radius: f64, velocity: DVec3, angular_velocity: DVec3) -> Self {
        Body { material, radius, velocity, angular_velocity }
    }
    pub fn mass(&self) -> f64 {
        self.material.density * 4.0 / 3.0 * std::f64::consts::PI * self.radius.powi(3)
    }
    fn inertia(&self) -> f64 {
        0.4 * self.mass() * self.radius * self.radius
    }
}

/// One impact: `a` onto the wall (`b = None`) or onto sphere `b`.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct ImpactSetup {
    pub model: FrictionModel,
    pub friction: f64,
    pub restitution: f64,
    pub no_attraction: bool,
    pub a: Body,
    pub b: Option<Body>,
    /// Steps per Hertz contact time.
    pub steps_per_contact: f64,
}

impl ImpactSetup {
    pub fn new(model: FrictionModel, friction: f64, restitution: f64, a: Body, b: Option<Body>) -> Self {
        ImpactSetup { model, friction, restitution, no_attraction: false, a, b, steps_per_contact: 100.0 }
    }

    /// (m*, R*, E*) of the pair.
    pub fn effective(&self) -> (f64, f64, f64) {
        let (ma, ra) = (self.a.mass(), self.a.radius);
        let (mb, rb, wb) = match self.b {
            Some(b) => (b.mass(), b.radius, b.material),
            None => (f64::INFINITY, f64::INFINITY, wall_material(self.a.material)),
        };
        let m_star = if mb.is_infinite() { ma } else { ma * mb / (ma + mb) };
        let r_star = if rb.is_infinite() { ra } else { ra * rb / (ra + rb) };
        let am = self.a.material;
        let (e_star, _) = tumble_contact::hertz_effective_moduli(am.youngs_modulus, am.poisson_ratio, wb.youngs_modulus, wb.poisson_ratio);
        (m_star, r_star, e_star)
    }

    /// Normal approach speed of a towards b (> 0).
    pub fn approach_speed(&self) -> f64 {
        -(self.a.velocity.z - self.b.map_or(0.0, |b| b.velocity.z))
    }

    /// Hertz theory (t_H, δ_max, F_max) for the elastic impact.
    pub fn hertz(&self) -> (f64, f64, f64) {
        let (m, r, e) = self.effective();
        let v = self.approach_speed();
        (tumble_contact::hertz_contact_time(m, r, e, v), tumble_contact::hertz_max_overlap(m, r, e, v), tumble_contact::hertz_max_force(m, r, e, v))
    }

    /// (K_n, K_t): normal and tangential compliances 1/m_a + 1/m_b and + R²/I of both.
    pub fn compliances(&self) -> (f64, f64) {
        let mut k_n = 1.0 / self.a.mass();
        let mut k_t = k_n + self.a.radius.powi(2) / self.a.inertia();
        if let Some(b) = self.b {
            k_n += 1.0 / b.mass();
            k_t += 1.0 / b.mass() + b.radius.powi(2) / b.inertia();
        }
        (k_n, k_t)
    }

    /// Tangential slip velocity of a's contact point relative to b's (x component).
    pub fn slip(&self, a: &Kinematics, b: Option<&Kinematics>) -> f64 {
        // a's contact point is at −R_a ẑ from its centre, b's at +R_b ẑ.
        let pa = a.velocity + a.angular_velocity.cross(-self.a.radius * DVec3::Z);
        let pb = match (b, self.b) {
            (Some(k), Some(body)) => k.velocity + k.angular_velocity.cross(body.radius * DVec3::Z),
            _ => DVec3::ZERO,
        };
        (pa - pb).x
    }

    /// χ = μ (1 + e) V_n K_t / (K_n V_st): gross sliding throughout while χ < 1 (3.5 μ (1+e) V_n / V_st on a wall).
    pub fn chi(&self, restitution: f64) -> f64 {
        let (k_n, k_t) = self.compliances();
        let v_st = self.slip(&Kinematics::start(&self.a), self.b.as_ref().map(Kinematics::start).as_ref());
        self.friction * (1.0 + restitution) * self.approach_speed() * k_t / (k_n * v_st.abs())
    }

    fn toml(&self) -> String {
        let v = |x: DVec3| format!("[{:e}, {:e}, {:e}]", x.x, x.y, x.z);
        let mat = |m: Material, name: &str| {
            format!(
                "[[materials]]\nname = \"{name}\"\ndensity = {:e}\nyoungs_modulus = {:e}\npoisson_ratio = {}\n",
                m.density, m.youngs_modulus, m.poisson_ratio
            )
        };
        let (t_h, _, _) = self.hertz();
        let gap = 0.2 * self.approach_speed() * t_h;
        let tangential = match self.model {
            FrictionModel::ViscousCoulomb => {
                // c_t = k t_H with the Hertz secant stiffness F_max/δ_max: the history-free analogue of k_f t_col.
                let (_, d, f) = self.hertz();
                format!("{{ model = \"viscous-coulomb\", friction = {}, viscous = {:e} }}", self.friction, f / d * t_h)
            }
            m => format!("{{ model = \"{}\", friction = {} }}", m.name(), self.friction),
        };
        let span = 4.0 * self.a.radius + self.b.map_or(0.0, |b| 4.0 * b.radius);
        let mut text = format!(
            "name = \"chung-ooi\"\n[run]\nduration = 1.0\nintegrator = \"verlet\"\n[domain]\nmin = [{:e}, {:e}, {:e}]\nmax = [{:e}, {:e}, {:e}]\n{}",
            -span,
            -span,
            -span,
            span,
            span,
            span,
            mat(self.a.material, "a"),
        );
        let a_z = gap + self.a.radius;
        let particle = |name: &str, b: &Body, z: f64| {
            format!(
                "[[particles]]\nmaterial = \"{name}\"\nshape = {{ sphere = {{ diameter = {:e} }} }}\npositions = [[0.0, 0.0, {z:e}]]\nvelocity = {}\nangular_velocity = {}\ntrack = true\n",
                2.0 * b.radius,
                v(b.velocity),
                v(b.angular_velocity)
            )
        };
        match self.b {
            Some(b) => text += &mat(b.material, "b"),
            None => text += &mat(wall_material(self.a.material), "wall"),
        }
        text += &format!("[contact]\nnormal = {{ model = \"hertz\" }}\nrestitution = {}\ntangential = {tangential}\n", self.restitution);
        text += &particle("a", &self.a, a_z);
        match self.b {
            Some(b) => text += &particle("b", &b, -b.radius),
            None => text += "[[walls]]\nname = \"floor\"\nmaterial = \"wall\"\nplane = { point = [0.0, 0.0, 0.0], normal = [0.0, 0.0, 1.0] }\n",
        }
        text
    }

    /// Runs the impact on the CPU.
    pub fn run(&self) -> ImpactResult {
        self.run_on(BackendName::Cpu)
    }

    /// Runs the impact on `backend` until well after separation, sampling every step.
    pub fn run_on(&self, backend: BackendName) -> ImpactResult {
        let (t_h, _, _) = self.hertz();
        let dt = t_h / self.steps_per_contact;
        let mut scene = parse_scene(&self.toml()).expect("chung-ooi scene parses");
        scene.run.dt = Some(DtSpec::Seconds(dt));
        scene.run.output_interval = Some(dt);
        scene.run.duration = 0.2 * t_h + 1.6 * t_h;
        scene.run.monitor.enabled = false;
        scene.run.allow_unstable_dt = true;
        scene.contact.as_mut().expect("the case has a [contact] table").no_attraction = self.no_attraction;
        let compiled = compile(&scene).expect("chung-ooi scene compiles");
        let steps = compiled.plan.run.steps;
        let mut sim = Simulation::on(backend, compiled, 1).unwrap_or_else(|e| panic!("{backend:?}: {e}"));
        let mut series = Vec::with_capacity(steps as usize); // (t, overlap, F_z on a)
        let mut compressive_impulse = 0.0;
        for _ in 0..steps {
            sim.advance(1);
            let tr = sim.tracks();
            let overlap = match self.b {
                Some(b) => self.a.radius + b.radius - (tr[0].position - tr[1].position).length(),
                None => self.a.radius - tr[0].position.z,
            };
            let f = sim.contact_force(0).unwrap_or(DVec3::ZERO);
            compressive_impulse += f.z.max(0.0) * dt;
            series.push((sim.time(), overlap, f.z));
        }
        let mut crossings = Vec::new();
        for w in series.windows(2) {
            if (w[0].1 <= 0.0) != (w[1].1 <= 0.0) {
                crossings.push(w[0].0 + (w[1].0 - w[0].0) * w[0].1 / (w[0].1 - w[1].1));
            }
        }
        let tr = sim.tracks();
        let a = Kinematics::from(&tr[0]);
        let b = self.b.map(|_| Kinematics::from(&tr[1]));
        let (a0, b0) = (Kinematics::start(&self.a), self.b.as_ref().map(Kinematics::start));
        let rel_n = |a: &Kinematics, b: Option<&Kinematics>| a.velocity.z - b.map_or(0.0, |k| k.velocity.z);
        let m = self.a.mass();
        ImpactResult {
            dt,
            steps,
            contact_time: if crossings.len() >= 2 { crossings[1] - crossings[0] } else { f64::NAN },
            max_overlap: series.iter().map(|s| s.1).fold(f64::MIN, f64::max),
            max_force: series.iter().map(|s| s.2).fold(f64::MIN, f64::max),
            restitution: -rel_n(&a, b.as_ref()) / rel_n(&a0, b0.as_ref()),
            normal_impulse: m * (a.velocity.z - a0.velocity.z),
            tangential_impulse: m * (a.velocity.x - a0.velocity.x),
            compressive_impulse,
            slip_before: self.slip(&a0, b0.as_ref()),
            slip_after: self.slip(&a, b.as_ref()),
            a,
            b,
        }
    }
}

/// Velocity and spin of one body.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Kinematics {
    pub velocity: DVec3,
    pub angular_velocity: DVec3,
}

impl Kinematics {
    fn start(b: &Body) -> Self {
        Kinematics { velocity: b.velocity, angular_velocity: b.angular_velocity }
    }
    fn from(r: &TrackRow) -> Self {
        Kinematics { velocity: r.velocity, angular_velocity: r.angular_velocity }
    }
}

/// What one impact measured.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct ImpactResult {
    pub dt: f64,
    pub steps: u64,
    /// Between the overlap's zero crossings.
    pub contact_time: f64,
    /// Largest sampled overlap and normal force on a.
    pub max_overlap: f64,
    pub max_force: f64,
    /// −V_n'/V_n of the relative normal velocity.
    pub restitution: f64,
    /// m_a Δv_z and m_a Δv_x of body a: J_n and J_t.
    pub normal_impulse: f64,
    pub tangential_impulse: f64,
    /// ∫ max(F_n, 0) dt on a (what a Coulomb limit μ max(F_n, 0) can take).
    pub compressive_impulse: f64,
    /// Contact-point slip V_st before and after.
    pub slip_before: f64,
    pub slip_after: f64,
    pub a: Kinematics,
    pub b: Option<Kinematics>,
}

impl ImpactResult {
    /// β = −V_st'/V_st.
    pub fn beta(&self) -> f64 {
        -self.slip_after / self.slip_before
    }
    /// |J_t| / (μ J_n): 1 in gross sliding.
    pub fn friction_ratio(&self, friction: f64) -> f64 {
        self.tangential_impulse.abs() / (friction * self.normal_impulse)
    }
}

/// Rigid-body theory for β: χ − 1 in gross sliding (χ < 1); a rigid sphere sticks (β = 0) otherwise.
pub fn rigid_beta(chi: f64) -> f64 {
    if chi < 1.0 { chi - 1.0 } else { 0.0 }
}

/// Tests 4–6 material: aluminium oxide, R = 2.5 mm, μ = 0.092 (Yade's and the paper's).
pub const OXIDE_RADIUS: f64 = 0.0025;
pub const OXIDE_FRICTION: f64 = 0.092;

/// Test 4: a sphere hits the wall at 3.9 m/s, `angle_deg` from the normal.
pub fn oblique_at_angle(model: FrictionModel, restitution: f64, angle_deg: f64) -> ImpactSetup {
    let t = angle_deg.to_radians();
    let a = Body::new(ALUMINIUM_OXIDE, OXIDE_RADIUS, 3.9 * DVec3::new(t.sin(), 0.0, -t.cos()), DVec3::ZERO);
    ImpactSetup::new(model, OXIDE_FRICTION, restitution, a, None)
}

/// Test 5: normal speed 5 m/s, tangential `v_t`.
pub fn oblique_with_tangential(model: FrictionModel, restitution: f64, v_t: f64) -> ImpactSetup {
    let a = Body::new(ALUMINIUM_OXIDE, OXIDE_RADIUS, DVec3::new(v_t, 0.0, -5.0), DVec3::ZERO);
    ImpactSetup::new(model, OXIDE_FRICTION, restitution, a, None)
}

/// Test 6: normal speed 3.9 m/s, no tangential velocity, spin ω about y.
pub fn spinning_onto_wall(model: FrictionModel, restitution: f64, spin: f64) -> ImpactSetup {
    let a = Body::new(ALUMINIUM_OXIDE, OXIDE_RADIUS, DVec3::new(0.0, 0.0, -3.9), DVec3::new(0.0, spin, 0.0));
    ImpactSetup::new(model, OXIDE_FRICTION, restitution, a, None)
}

/// Test 7: two aluminium-alloy spheres (R = 0.1 m) head-on at ±0.2 m/s, both spinning at ω about y:
/// equal and opposite spins seen from the contact, whose points slide against each other at 2ωR.
pub fn spinning_pair(model: FrictionModel, restitution: f64, spin: f64) -> ImpactSetup {
    let body = |s: f64| Body::new(ALUMINIUM_ALLOY, 0.1, DVec3::new(0.0, 0.0, 0.2 * s), DVec3::new(0.0, spin, 0.0));
    ImpactSetup::new(model, 0.4, restitution, body(-1.0), Some(body(1.0)))
}

/// Test 8: a spinning aluminium-alloy sphere (R = 0.1 m) hits one of R = 0.2 m obliquely.
pub fn unequal_spinning_pair(model: FrictionModel, restitution: f64, v_t: f64, spin: f64) -> ImpactSetup {
    let a = Body::new(ALUMINIUM_ALLOY, 0.1, DVec3::new(v_t, 0.0, -0.2), DVec3::new(0.0, spin, 0.0));
    let b = Body::new(ALUMINIUM_ALLOY, 0.2, DVec3::ZERO, DVec3::ZERO);
    ImpactSetup::new(model, 0.4, restitution, a, Some(b))
}
