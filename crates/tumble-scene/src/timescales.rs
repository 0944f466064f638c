//! Time scales of a scene: contact durations, stability limits and the step the plan picks
//! (docs/physics.md, "Time step").

use crate::particles::InitialParticles;
use crate::plan::{Fluid, Material, PairParams, PolyhedronContact, Wall};
use crate::{Drag, ParticleShape, SPHERE};
use glam::DVec3;
use tumble_contact::{NormalLaw, SpringLaw, TangentialLaw, ViscousParameter, collision_time, rayleigh_time, stokes_relaxation_time};
use tumble_geom::PeriodicBox;
use tumble_integrate::Integrator;
pub use tumble_plan::{ACCURATE_STEPS_PER_COLLISION, ImpactSpeed, STEPS_PER_COLLISION, TANGENTIAL_STEP_SHARE, Timescales};

/// The scene's time scales; `shapes` is the plan's shape table (a polyhedron's contact mass is
/// its effective mass at its worst vertex, not its mass); the default step also respects the
/// moving-geometry limit `wall_step_limit`.
#[allow(clippy::too_many_arguments)]
pub(crate) fn timescales(
    p: &InitialParticles,
    shapes: &[ParticleShape],
    materials: &[Material],
    pairs: &[PairParams],
    walls: &[Wall],
    fluid: Option<&Fluid>,
    integrator: Integrator,
    gravity: DVec3,
    domain: &PeriodicBox,
    rotation: bool,
    wall_step_limit: Option<f64>,
    polyhedron_contact: PolyhedronContact,
) -> Timescales {
    let n_mat = materials.len();
    let mass = |i: usize| materials[p.material[i] as usize].density * p.volume[i];
    // The overlap-volume model meets a face lying on a face with the law face_on_weight times at
    // the full mass: as stiff as the law at that fraction of it.
    let fractions: Vec<f64> = shapes
        .iter()
        .map(|s| match polyhedron_contact {
            PolyhedronContact::Volume => s.body.contact_mass_fraction().min(1.0 / s.face_on_weight),
            PolyhedronContact::Depth => s.body.contact_mass_fraction(),
        })
        .collect();
    let contact_mass = |i: usize| if p.shape[i] == SPHERE { mass(i) } else { mass(i) * fractions[p.shape[i] as usize] };
    // Lightest movable particle and smallest radius per material; materials that only fixed particles or walls use.
    let mut lightest = vec![f64::INFINITY; n_mat];
    let mut smallest = vec![f64::INFINITY; n_mat];
    let mut movable = vec![0usize; n_mat];
    // Materials of surfaces a movable particle can hit: walls and fixed particles (m* = m).
    let mut obstacle = vec![false; n_mat];
    for i in 0..p.len() {
        let m = p.material[i] as usize;
        if p.fixed[i] {
            obstacle[m] = true;
        } else {
            movable[m] += 1;
            lightest[m] = lightest[m].min(contact_mass(i));
            smallest[m] = smallest[m].min(p.equivalent_radius(i));
        }
    }
    for w in walls {
        obstacle[w.material as usize] = true;
    }
    let mut ts = Timescales { impact: ImpactSpeed::default(), ..Timescales::default() };
    let mut limit = f64::INFINITY;
    let mut t_col = f64::INFINITY;
    let mut t_col_linear = f64::INFINITY;
    let mut t_hertz = f64::INFINITY;
    let mut rayleigh = f64::INFINITY;
    let mut tangential = f64::INFINITY;
    let mut spring_period = f64::INFINITY;
    let impact = impact_speed(p, gravity, domain, walls);
    let speed = impact.speed;
    for a in 0..n_mat {
        if !lightest[a].is_finite() {
            continue;
        }
        for b in 0..n_mat {
            let mut m_stars = Vec::new();
            // Two movable particles can meet only if there are two of them.
            if movable[b] > usize::from(a == b) {
                m_stars.push(lightest[a] * lightest[b] / (lightest[a] + lightest[b]));
            }
            if obstacle[b] {
                m_stars.push(lightest[a]);
            }
            for m_star in m_stars {
                // The explicit viscous tangential force relaxes slip at rate c_t / m*_t, where
                // m*_t = (2/7) m* for rolling spheres: stable for Δt < 2 m*_t / c_t per contact.
                if let TangentialLaw::ViscousCoulomb { viscous, .. } = pairs[a * n_mat + b].tangential {
                    let c_t = match (viscous, pairs[a * n_mat + b].normal) {
                        (ViscousParameter::Coefficient(c), _) => c,
                        (ViscousParameter::Stiffness(k_f), NormalLaw::Linear { stiffness, restitution, .. }) => {
                            k_f * collision_time(stiffness, m_star, restitution)
                        }
                        (ViscousParameter::Stiffness(k_f), NormalLaw::Hertz { e_star, restitution, .. }) => {
                            // Hertz has no single t_col: take the tangent stiffness at an overlap of 1 % of r.
                            let r = smallest[a];
                            k_f * collision_time(2.0 * e_star * (r * 0.01 * r).sqrt(), m_star, restitution)
                        }
                    };
                    let m_t = if rotation { 2.0 / 7.0 * m_star } else { m_star };
                    tangential = tangential.min(m_t / c_t);
                }
                // A tangential spring oscillates at ω_t = √(k_t / m*_t): the same limit 2/ω as a normal spring.
                if let TangentialLaw::History { spring: SpringLaw::Linear { stiffness: k_t, .. }, .. } = pairs[a * n_mat + b].tangential {
                    let m_t = if rotation { 2.0 / 7.0 * m_star } else { m_star };
                    let omega_t = (k_t / m_t).sqrt();
                    limit = limit.min(2.0 / omega_t);
                    spring_period = spring_period.min(std::f64::consts::PI / omega_t);
                }
                match pairs[a * n_mat + b].normal {
                    NormalLaw::Linear { stiffness, restitution, .. } => {
                        t_col_linear = t_col_linear.min(collision_time(stiffness, m_star, restitution));
                        t_col = t_col.min(t_col_linear);
                        limit = limit.min(2.0 / (stiffness / m_star).sqrt());
                    }
                    NormalLaw::Hertz { e_star, .. } => {
                        let r = smallest[a];
                        let (e, nu) = (materials[a].youngs_modulus.unwrap(), materials[a].poisson_ratio.unwrap());
                        rayleigh = rayleigh.min(rayleigh_time(r, materials[a].density, e, nu));
                        let r_star = if lightest[b].is_finite() && m_star < lightest[a] { r * smallest[b] / (r + smallest[b]) } else { r };
                        t_hertz = t_hertz.min(tumble_contact::hertz_contact_time(m_star, r_star, e_star, speed));
                        t_col = t_col.min(t_hertz);
                    }
                }
            }
        }
    }
    let mut default_dt = f64::INFINITY;
    if t_col.is_finite() {
        ts.collision_time = Some(t_col);
    }
    // Linear contacts: t_col / 50; Hertz: 0.2 Δt_R and t_H / 50 at the impact speed (docs/physics.md, "Time step").
    if t_col_linear.is_finite() {
        default_dt = t_col_linear / STEPS_PER_COLLISION;
    }
    if t_hertz.is_finite() {
        default_dt = default_dt.min(t_hertz / STEPS_PER_COLLISION);
    }
    if spring_period.is_finite() {
        default_dt = default_dt.min(spring_period / STEPS_PER_COLLISION);
    }
    if tangential.is_finite() {
        ts.tangential_time = Some(tangential);
        limit = limit.min(2.0 * tangential);
        // A particle in a packing has several contacts whose viscous rates add up.
        default_dt = default_dt.min(tangential * TANGENTIAL_STEP_SHARE);
    }
    if rayleigh.is_finite() {
        ts.rayleigh_time = Some(rayleigh);
        default_dt = default_dt.min(0.2 * rayleigh);
        limit = limit.min(rayleigh);
    }
    if let Some(f) = fluid {
        let tau = (0..p.len())
            .filter(|&i| !p.fixed[i])
            .map(|i| match f.drag {
                Drag::Stokes { viscosity } => stokes_relaxation_time(materials[p.material[i] as usize].density, 2.0 * p.radius[i], viscosity),
                // Linearised at the characteristic speed: τ = m / (α v).
                Drag::Quadratic { coefficient } => mass(i) / (coefficient * speed.max(1e-3)),
            })
            .fold(f64::INFINITY, f64::min);
        if tau.is_finite() {
            ts.drag_time = Some(tau);
            default_dt = default_dt.min(tau / 50.0);
            if !integrator.implicit_drag() {
                limit = limit.min(2.0 * tau);
            }
        }
    }
    if limit.is_finite() {
        ts.stability_limit = Some(limit);
    }
    let default_dt = if default_dt.is_finite() { default_dt } else { 1e-3 };
    ts.default_dt = wall_step_limit.map_or(default_dt, |w| default_dt.min(w));
    ts.impact = impact;
    ts
}

/// The impact speed estimate: energy conservation bounds a lone particle's speed by
/// v_p = √(v_0² + 2 g h); two such particles, or one and a moving wall, can meet head on.
fn impact_speed(p: &InitialParticles, gravity: DVec3, domain: &PeriodicBox, walls: &[Wall]) -> ImpactSpeed {
    let movable = || (0..p.len()).filter(|&i| !p.fixed[i]);
    let initial = movable().map(|i| p.velocity[i].length()).fold(0.0, f64::max);
    let wall = walls.iter().map(|w| w.surface_speed).fold(0.0, f64::max);
    let g = gravity.length();
    let drop_height = if g > 0.0 {
        let down = gravity / g;
        // Height of x above the domain's lowest corner along g.
        let lowest = DVec3::from_array([0, 1, 2].map(|k| if down[k] > 0.0 { domain.max[k] } else { domain.min[k] }));
        if wall > 0.0 {
            (domain.extent() * down.abs()).element_sum()
        } else {
            movable().map(|i| (lowest - p.position[i]).dot(down).max(0.0)).fold(0.0, f64::max)
        }
    } else {
        0.0
    };
    let particle = (initial * initial + 2.0 * g * drop_height).sqrt();
    let speed = (2.0 * particle).max(particle + wall).max(0.1);
    ImpactSpeed { speed, initial, drop_height, wall }
}
