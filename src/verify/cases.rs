//! The closed-form cases (docs/verification.md, cases 1–5, 7–9).

use super::{DIVISORS, ErrorRow, scene_with, simulation_on, trajectory, trajectory_on};
use crate::Simulation;
use glam::DVec3;
use tumble_integrate::Integrator;
use tumble_scene::schema::BackendName;

pub const STOKES_DRAG: &str = include_str!("../../scenes/verify/01_stokes_drag.toml");
pub const NORMAL_COLLISION: &str = include_str!("../../scenes/verify/02_normal_collision.toml");
pub const ELASTIC_COLLISION: &str = include_str!("../../scenes/verify/02_elastic_collision.toml");
pub const SLIDING: &str = include_str!("../../scenes/verify/03_sliding.toml");
pub const COHESIVE_COLLISION: &str = include_str!("../../scenes/verify/04_cohesive_collision.toml");
pub const QUADRATIC_DRAG: &str = include_str!("../../scenes/verify/05_quadratic_drag.toml");
pub const HERTZ_IMPACT: &str = include_str!("../../scenes/verify/07_hertz_impact.toml");
pub const SLIDE_TO_ROLL: &str = include_str!("../../scenes/verify/08_slide_to_roll.toml");
pub const ENERGY_BALANCE: &str = include_str!("../../scenes/verify/09_energy_balance.toml");

const D: f64 = 0.1;
const G: f64 = 9.81;

fn light_mass() -> f64 {
    10.0 * std::f64::consts::PI / 6.0 * D * D * D
}

fn row(case: &'static str, measure: &'static str, integrator: Integrator, divisor: f64, dt: f64, error: f64, t: &super::Trajectory) -> ErrorRow {
    ErrorRow { case, measure, integrator, steps_per_scale: divisor, dt, error, particle_steps: t.particle_steps, wall_seconds: t.wall_seconds }
}

/// Case 1: Stokes drag from rest; error = max |x − x_exact| / (u τ) over 5τ.
pub fn stokes_drag(integrators: &[Integrator]) -> Vec<ErrorRow> {
    let tau = 10.0 * D * D / (18.0 * 0.00193);
    let mut rows = Vec::new();
    for &integrator in integrators {
        for divisor in DIVISORS {
            let dt = tau / divisor;
            let t = trajectory(scene_with(STOKES_DRAG, integrator, Some(dt)));
            let error =
                t.samples.iter().map(|(time, r)| (r[0].position.x - (tau * ((-time / tau).exp() - 1.0) + time)).abs() / tau).fold(0.0, f64::max);
            rows.push(row("1 stokes drag", "x(t) / (u τ)", integrator, divisor, dt, error, &t));
        }
    }
    rows
}

/// Linear collision constants (a, b, t_col) of case 2 for restitution e.
fn collision_constants(e: f64) -> (f64, f64, f64) {
    let m = light_mass();
    let eta = tumble_contact::linear_damping(e, m, 1.0e5);
    let a = -eta / (2.0 * m);
    let b = (4.0 * m * 1.0e5 - eta * eta).sqrt() / (2.0 * m);
    (a, b, std::f64::consts::PI / b)
}

/// Case 2: normal collision with a fixed particle. Returns rows for the in-contact
/// trajectory (error / (|u0|/b)) and the rebound speed (relative error).
pub fn normal_collision(restitution: f64, integrators: &[Integrator]) -> Vec<ErrorRow> {
    let text = if restitution == 1.0 { ELASTIC_COLLISION } else { NORMAL_COLLISION };
    let (case, rebound) = if restitution == 1.0 { ("2 elastic collision", "rebound speed") } else { ("2 damped collision", "rebound speed") };
    let u0 = -2.0;
    let (a, b, t_col) = collision_constants(restitution);
    let mut rows = Vec::new();
    for &integrator in integrators {
        for divisor in DIVISORS {
            let dt = t_col / divisor;
            let t = trajectory(scene_with(text, integrator, Some(dt)));
            let contact_error = t
                .samples
                .iter()
                .filter(|(time, _)| *time < t_col - 1.5 * dt)
                .map(|(time, r)| (r[0].position.x - (D + (a * time).exp() * (u0 / b) * (b * time).sin())).abs() / (u0.abs() / b))
                .fold(0.0, f64::max);
            let v_contact_error = t
                .samples
                .iter()
                .filter(|(time, _)| *time < t_col - 1.5 * dt)
                .map(|(time, r)| (r[0].velocity.x - u0 * (a * time).exp() * ((a / b) * (b * time).sin() + (b * time).cos())).abs() / u0.abs())
                .fold(0.0, f64::max);
            let v_end = t.samples.last().unwrap().1[0].velocity.x;
            let expected = -restitution * u0;
            rows.push(row(case, "x(t) in contact", integrator, divisor, dt, contact_error, &t));
            rows.push(row(case, "v(t) in contact", integrator, divisor, dt, v_contact_error, &t));
            rows.push(row(case, rebound, integrator, divisor, dt, (v_end - expected).abs() / expected, &t));
            if restitution == 1.0 {
                rows.push(row(case, "energy gain", integrator, divisor, dt, (v_end * v_end - u0 * u0) / (u0 * u0), &t));
            }
        }
    }
    rows
}

/// The collision time of case 2 with restitution e.
pub fn normal_collision_time(restitution: f64) -> f64 {
    collision_constants(restitution).2
}

/// Case 3 results at one Δt: sliding error and behaviour after the stop.
#[derive(Clone, Debug)]
pub struct SlidingResult {
    pub dt: f64,
    /// max |v − (u0 − μ g t)| while sliding, m/s.
    pub velocity_error: f64,
    /// max |x − x_exact| while sliding, m.
    pub position_error: f64,
    /// Largest speed later than 10 ms after the analytic stop, m/s.
    pub speed_after_stop: f64,
    /// Sign changes of v_x after the stop (oscillation around rest).
    pub sign_changes_after_stop: usize,
    /// Distance travelled after the stop, m.
    pub drift_after_stop: f64,
}

/// Case 3: sliding with rotation off; `tangential` replaces the scene's model when given.
pub fn sliding(integrator: Integrator, divisor: f64, dynamic_only: bool) -> SlidingResult {
    let text = if dynamic_only {
        SLIDING.replace(
            "tangential = { model = \"viscous-coulomb\", friction = 0.6, stiffness = 1.0e5 }",
            "tangential = { model = \"dynamic-only\", friction = 0.6 }",
        )
    } else {
        SLIDING.to_string()
    };
    let t_col = tumble_contact::collision_time(1.0e5, light_mass(), 0.8);
    let dt = t_col / divisor;
    let t = trajectory(scene_with(&text, integrator, Some(dt)));
    let (mu, u0) = (0.6, 1.0);
    let t_stop = u0 / (mu * G);
    let mut r =
        SlidingResult { dt, velocity_error: 0.0, position_error: 0.0, speed_after_stop: 0.0, sign_changes_after_stop: 0, drift_after_stop: 0.0 };
    let mut last_sign = 0.0;
    let mut x_at_rest = None;
    for (time, rows) in &t.samples {
        let p = &rows[0];
        // The last 0.2 ms is the viscous regime (c_t |v| < μ|F_n|) that ends the slide smoothly.
        if *time < t_stop - 2e-4 {
            r.velocity_error = r.velocity_error.max((p.velocity.x - (u0 - mu * G * time)).abs());
            r.position_error = r.position_error.max((p.position.x - (u0 * time - 0.5 * mu * G * time * time)).abs());
        } else if *time > t_stop + 0.01 {
            r.speed_after_stop = r.speed_after_stop.max(p.velocity.length());
            let s = p.velocity.x.signum();
            if last_sign != 0.0 && s != last_sign && p.velocity.x != 0.0 {
                r.sign_changes_after_stop += 1;
            }
            if p.velocity.x != 0.0 {
                last_sign = s;
            }
            let x0 = *x_at_rest.get_or_insert(p.position.x);
            r.drift_after_stop = r.drift_after_stop.max((p.position.x - x0).abs());
        }
    }
    r
}

/// Closed-form trajectory of case 4 through approach and the first contact.
pub struct CohesiveSolution {
    pub t_contact: f64,
    pub t_separation: f64,
    /// Speed when leaving contact.
    pub leave_speed: f64,
    /// Speed needed to escape the cohesive range.
    pub escape_speed: f64,
    m: f64,
    a: f64,
    b: f64,
    x_star: f64,
    v_i: f64,
    omega_c: f64,
}

const D_E: f64 = 0.15;

impl CohesiveSolution {
    pub fn new() -> Self {
        let m = light_mass();
        let (k_n, k_c, u0) = (1.0e5, 100.0, -2.0);
        let omega_c = (k_c / m).sqrt();
        let t_i = ((D - D_E) * omega_c / u0).asinh() / omega_c;
        let v_i = u0 * (omega_c * t_i).cosh();
        let eta = tumble_contact::linear_damping(0.8, m, k_n);
        let a = -eta / (2.0 * m);
        let b = (4.0 * m * (k_n - k_c) - eta * eta).sqrt() / (2.0 * m);
        let x_star = (k_n * D - k_c * D_E) / (k_n - k_c);
        let mut s = CohesiveSolution {
            t_contact: t_i,
            t_separation: 0.0,
            leave_speed: 0.0,
            escape_speed: omega_c * (D_E - D),
            m,
            a,
            b,
            x_star,
            v_i,
            omega_c,
        };
        // First return to x = d after half a damped period: bisect on x(s) − d.
        let (mut lo, mut hi) = (0.5 * std::f64::consts::PI / b, 1.5 * std::f64::consts::PI / b);
        for _ in 0..200 {
            let mid = 0.5 * (lo + hi);
            if s.contact_x(mid) < D { lo = mid } else { hi = mid }
        }
        s.t_separation = t_i + lo;
        s.leave_speed = s.contact_v(lo);
        let _ = s.m;
        s
    }

    fn contact_x(&self, s: f64) -> f64 {
        let c = D - self.x_star;
        self.x_star + (self.a * s).exp() * ((self.v_i - self.a * c) / self.b * (self.b * s).sin() + c * (self.b * s).cos())
    }

    fn contact_v(&self, s: f64) -> f64 {
        let h = 1e-9;
        (self.contact_x(s + h) - self.contact_x(s - h)) / (2.0 * h)
    }

    /// x(t) up to the first separation.
    pub fn x(&self, t: f64) -> f64 {
        if t < self.t_contact { D_E + (-2.0) * (self.omega_c * t).sinh() / self.omega_c } else { self.contact_x(t - self.t_contact) }
    }
}

impl Default for CohesiveSolution {
    fn default() -> Self {
        Self::new()
    }
}

/// Case 4: errors in the approach (smooth) and contact phases, and whether it stuck.
pub fn cohesive_collision(integrators: &[Integrator]) -> (Vec<ErrorRow>, Vec<(Integrator, f64, bool)>) {
    let sol = CohesiveSolution::new();
    let t_col = normal_collision_time(0.8);
    let mut rows = Vec::new();
    let mut stuck = Vec::new();
    for &integrator in integrators {
        for divisor in DIVISORS {
            let dt = t_col / divisor;
            let t = trajectory(scene_with(COHESIVE_COLLISION, integrator, Some(dt)));
            let err = |lo: f64, hi: f64| {
                t.samples
                    .iter()
                    .filter(|(time, _)| *time >= lo && *time <= hi)
                    .map(|(time, r)| (r[0].position.x - sol.x(*time)).abs() / (D_E - D))
                    .fold(0.0, f64::max)
            };
            rows.push(row("4 cohesive collision", "x(t) approach", integrator, divisor, dt, err(0.0, sol.t_contact - dt), &t));
            rows.push(row("4 cohesive collision", "x(t) first contact", integrator, divisor, dt, err(sol.t_contact + dt, sol.t_separation - dt), &t));
            // Stuck: after the first contact it never leaves the effect range again.
            let sticks = t.samples.iter().filter(|(time, _)| *time > sol.t_contact).all(|(_, r)| r[0].position.x < D_E);
            stuck.push((integrator, divisor, sticks));
        }
    }
    (rows, stuck)
}

/// Case 5: free fall with quadratic drag; error = max |v − v_exact| / v_terminal.
pub fn quadratic_drag(integrators: &[Integrator]) -> Vec<ErrorRow> {
    let (m, alpha) = (1.0, 0.5);
    let v_term = (m * G / alpha).sqrt();
    let time_scale = (m / (G * alpha)).sqrt();
    let mut rows = Vec::new();
    for &integrator in integrators {
        for divisor in DIVISORS {
            let dt = time_scale / divisor;
            let t = trajectory(scene_with(QUADRATIC_DRAG, integrator, Some(dt)));
            let error = t.samples.iter().map(|(time, r)| (r[0].velocity.z + v_term * (time / time_scale).tanh()).abs() / v_term).fold(0.0, f64::max);
            rows.push(row("5 quadratic drag", "v(t) / v_terminal", integrator, divisor, dt, error, &t));
        }
    }
    rows
}

/// Case 7 measurements against Hertz theory.
#[derive(Clone, Debug)]
pub struct HertzResult {
    pub dt: f64,
    pub max_overlap: (f64, f64),
    pub max_force: (f64, f64),
    pub contact_time: (f64, f64),
    pub rebound_speed: (f64, f64),
}

/// Case 7: elastic Hertz impact at the plan's default Δt (or `dt`).
pub fn hertz_impact(integrator: Integrator, dt: Option<f64>) -> HertzResult {
    hertz_impact_on(BackendName::Cpu, integrator, dt)
}

/// Case 7 on a backend.
pub fn hertz_impact_on(backend: BackendName, integrator: Integrator, dt: Option<f64>) -> HertzResult {
    let scene = scene_with(HERTZ_IMPACT, integrator, dt);
    let dt = scene.plan.model.dt;
    let (rho, e, nu, r, v) = (2500.0, 1.0e7, 0.3, 0.01, 1.0);
    let m = rho * 4.0 / 3.0 * std::f64::consts::PI * r * r * r;
    let (m_star, r_star) = (0.5 * m, 0.5 * r);
    let (e_star, _) = tumble_contact::hertz_effective_moduli(e, nu, e, nu);
    let mut sim = simulation_on(backend, scene);
    let mut series = Vec::new(); // (t, overlap, force)
    while sim.steps() < sim.plan().run.steps {
        sim.advance(1);
        let tr = sim.tracks();
        let overlap = 2.0 * r - (tr[1].position - tr[0].position).length();
        series.push((sim.time(), overlap, sim.contact_force(0).unwrap().length()));
    }
    let peak = |k: usize| {
        let idx = (0..series.len()).max_by(|&a, &b| value(&series[a], k).total_cmp(&value(&series[b], k))).unwrap();
        // A parabola through the three samples around the largest one finds the peak between steps.
        let (y0, y1, y2) = (value(&series[idx - 1], k), value(&series[idx], k), value(&series[idx + 1], k));
        let denom = y0 - 2.0 * y1 + y2;
        if denom == 0.0 { y1 } else { y1 - 0.125 * (y2 - y0).powi(2) / denom }
    };
    fn value(s: &(f64, f64, f64), k: usize) -> f64 {
        if k == 1 { s.1 } else { s.2 }
    }
    // Contact start and end by linear interpolation of the overlap's zero crossings.
    let mut crossings = Vec::new();
    for w in series.windows(2) {
        if (w[0].1 <= 0.0) != (w[1].1 <= 0.0) {
            crossings.push(w[0].0 + (w[1].0 - w[0].0) * w[0].1 / (w[0].1 - w[1].1));
        }
    }
    let tr = sim.tracks();
    let rebound = (tr[1].velocity - tr[0].velocity).dot(DVec3::X);
    HertzResult {
        dt,
        max_overlap: (peak(1), tumble_contact::hertz_max_overlap(m_star, r_star, e_star, v)),
        max_force: (peak(2), tumble_contact::hertz_max_force(m_star, r_star, e_star, v)),
        contact_time: (crossings[1] - crossings[0], tumble_contact::hertz_contact_time(m_star, r_star, e_star, v)),
        rebound_speed: (rebound, v),
    }
}

/// Case 8 measurements.
#[derive(Clone, Debug)]
pub struct RollResult {
    pub dt: f64,
    /// Final speed over v0 (theory 5/7).
    pub final_speed_ratio: f64,
    /// |v − ω r| / v0 at the end (theory 0).
    pub final_slip: f64,
    /// First time the slip falls below 1e-4 v0, and theory 2 v0/(7 μ g).
    pub roll_time: (f64, f64),
    /// max |v − (v0 − μ g t)| while sliding, over v0.
    pub sliding_error: f64,
}

/// Case 8: slide to roll with rotation on (viscous-Coulomb friction, as in the scene file).
pub fn slide_to_roll(integrator: Integrator, divisor: f64) -> RollResult {
    slide_to_roll_on(BackendName::Cpu, integrator, divisor)
}

/// Case 8 on a backend.
pub fn slide_to_roll_on(backend: BackendName, integrator: Integrator, divisor: f64) -> RollResult {
    slide_to_roll_with(backend, integrator, divisor, None)
}

/// Case 8 on a backend with the scene's tangential law replaced by `tangential` (a TOML inline table).
pub fn slide_to_roll_with(backend: BackendName, integrator: Integrator, divisor: f64, tangential: Option<&str>) -> RollResult {
    let t_col = tumble_contact::collision_time(1.0e5, light_mass(), 0.8);
    let dt = t_col / divisor;
    let text = match tangential {
        Some(t) => {
            SLIDE_TO_ROLL.replace("tangential = { model = \"viscous-coulomb\", friction = 0.5, stiffness = 1.0e5 }", &format!("tangential = {t}"))
        }
        None => SLIDE_TO_ROLL.to_string(),
    };
    assert!(tangential.is_none() || text != SLIDE_TO_ROLL, "case 8's scene no longer has the tangential line to replace");
    let t = trajectory_on(backend, scene_with(&text, integrator, Some(dt)));
    let (v0, mu, r) = (1.0, 0.5, 0.5 * D);
    let t_roll = 2.0 * v0 / (7.0 * mu * G);
    let slip = |p: &crate::TrackRow| p.velocity.x - r * p.angular_velocity.y;
    let rolled = t.samples.iter().find(|(_, rows)| slip(&rows[0]).abs() < 1e-4 * v0).map_or(f64::INFINITY, |(time, _)| *time);
    let sliding_error = t
        .samples
        .iter()
        .filter(|(time, _)| *time < t_roll - 0.002)
        .map(|(time, rows)| (rows[0].velocity.x - (v0 - mu * G * time)).abs() / v0)
        .fold(0.0, f64::max);
    let last = &t.samples.last().unwrap().1[0];
    RollResult { dt, final_speed_ratio: last.velocity.x / v0, final_slip: slip(last).abs() / v0, roll_time: (rolled, t_roll), sliding_error }
}

/// Case 9: energy balance error |E − E0| / E0 at the end, with the fraction of E0 dissipated.
pub fn energy_balance(threads: usize) -> (f64, f64) {
    let scene = scene_with(ENERGY_BALANCE, Integrator::Verlet, None);
    energy_balance_of(Simulation::new(scene, threads))
}

/// Case 9 on a backend, run for `duration` (the scene runs 0.4 s; the top layer lands at 0.19 s).
pub fn energy_balance_on(backend: BackendName, duration: f64) -> (f64, f64) {
    let text = ENERGY_BALANCE.replace("duration = 0.4\n", &format!("duration = {duration}\n"));
    assert_ne!(text, ENERGY_BALANCE, "case 9's scene no longer says duration = 0.4");
    energy_balance_of(simulation_on(backend, scene_with(&text, Integrator::Verlet, None)))
}

fn energy_balance_of(mut sim: Simulation) -> (f64, f64) {
    let steps = sim.plan().run.steps;
    let o0 = sim.observables();
    let e0 = o0.mechanical_energy();
    sim.advance(steps);
    let o = sim.observables();
    ((o.mechanical_energy() + o.dissipated_energy - e0).abs() / e0, o.dissipated_energy / e0)
}
