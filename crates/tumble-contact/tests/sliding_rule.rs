//! The sliding rule of the tangential spring on a Hertz–Mindlin sphere–wall impact, integrated
//! here from the force laws alone (a sphere of radius R against a rigid plane, contact at −R n):
//! friction never pushes along the slip, gross sliding delivers μ∫max(F_n, 0) dt, and with
//! `no_attraction` the rebound follows rigid-body theory, β = −V'_st/V_st = χ − 1 with
//! χ = 3.5 μ (1 + e) V_n / V_st (Chung & Ooi 2011, tests 5 and 6; Maw, Barber & Fawcett 1976).

use tumble_contact::{DVec3, NormalLaw, SpringLaw, clipped_hertz_beta, hertz_contact_time, history_force, normal_force};

/// Aluminium alloy (Chung & Ooi 2011): E = 70 GPa, ν = 0.33, ρ = 2700 kg/m³, R = 0.1 m, on a rigid wall.
const RADIUS: f64 = 0.1;
const FRICTION: f64 = 0.4;

struct Impact {
    /// −V'_st / V_st of the contact point's tangential velocity.
    beta: f64,
    /// V'_n / V_n.
    restitution: f64,
    tangential_impulse: f64,
    /// ∫ max(F_n, 0) dt.
    normal_capacity_impulse: f64,
    /// Steps at the Coulomb limit, and the largest F_t · v_t among them (must not be positive).
    sliding_steps: usize,
    worst_sliding_power: f64,
}

fn impact(restitution: f64, clipped: bool, v_n: f64, v_st: f64, steps_per_contact: f64) -> Impact {
    let (e_mod, nu, rho) = (7.0e10, 0.33, 2700.0);
    let mass = rho * 4.0 / 3.0 * std::f64::consts::PI * RADIUS.powi(3);
    let inertia = 0.4 * mass * RADIUS * RADIUS;
    let (e_star, g_star) = (e_mod / (1.0 - nu * nu), e_mod / (2.0 * (2.0 - nu) * (1.0 + nu)));
    let beta = if clipped { clipped_hertz_beta(restitution) } else { tumble_contact::hertz_beta(restitution) };
    let normal_law = NormalLaw::Hertz { e_star, g_star, restitution, beta };
    let spring_law = SpringLaw::Mindlin { g_star, beta };
    let dt = hertz_contact_time(mass, RADIUS, e_star, v_n) / steps_per_contact;
    let n = DVec3::Z;
    // Centre at height z above the wall; the spin ω_y sets the contact point's tangential velocity v_x − ω_y R.
    // The centre moves tangentially at v_st / 2; the spin makes the contact point slide at v_st.
    let (mut z, mut v) = (RADIUS, DVec3::new(0.5 * v_st, 0.0, -v_n));
    let mut omega = (v.x - v_st) / RADIUS;
    let (mut xi, mut jt, mut jn) = (DVec3::ZERO, 0.0, 0.0);
    let (mut sliding_steps, mut worst) = (0usize, f64::NEG_INFINITY);
    let vt0 = v.x - omega * RADIUS;
    let mut touched = false;
    for _ in 0..(20.0 * steps_per_contact) as usize {
        let overlap = RADIUS - z;
        if overlap < 0.0 {
            if touched {
                break;
            }
            z += v.z * dt;
            continue;
        }
        touched = true;
        let vt = DVec3::new(v.x - omega * RADIUS, 0.0, 0.0);
        let nf = normal_force(&normal_law, overlap, v.z, mass, RADIUS);
        let applied = if clipped { nf.total().max(0.0) } else { nf.total() };
        let capacity = applied.max(0.0);
        let h = history_force(&spring_law, FRICTION, capacity, overlap, RADIUS, mass, xi, n, vt, dt);
        xi = h.spring;
        if h.sliding {
            sliding_steps += 1;
            worst = worst.max(h.force.dot(vt));
        }
        jt += h.force.x * dt;
        jn += capacity * dt;
        // Semi-implicit Euler: forces from the state at the step's start, positions from the new velocities.
        v += (n * applied + h.force) * (dt / mass);
        omega += -RADIUS * h.force.x / inertia * dt;
        z += v.z * dt;
    }
    let vt1 = v.x - omega * RADIUS;
    Impact {
        beta: -vt1 / vt0,
        restitution: v.z / v_n,
        tangential_impulse: jt.abs(),
        normal_capacity_impulse: jn,
        sliding_steps,
        worst_sliding_power: worst,
    }
}

#[test]
fn gross_sliding_delivers_mu_times_the_normal_capacity_and_never_pushes_along_the_slip() {
    // χ = 3.5 μ (1 + e) V_n / V_st = 0.4 … 0.8: sliding throughout at e = 0.5.
    for clipped in [false, true] {
        for chi in [0.4, 0.6, 0.8] {
            let (e, v_n) = (0.5, 0.2);
            let v_st = 3.5 * FRICTION * (1.0 + e) * v_n / chi;
            let i = impact(e, clipped, v_n, v_st, 2000.0);
            let ratio = i.tangential_impulse / (FRICTION * i.normal_capacity_impulse);
            println!(
                "χ = {chi}, clipped {clipped}: J_t/μ∫max(F_n,0)dt = {ratio:.6}, e = {:.5}, β = {:.5}, {} sliding steps",
                i.restitution, i.beta, i.sliding_steps
            );
            assert!((ratio - 1.0).abs() < 1e-2, "χ = {chi}, clipped {clipped}: J_t / μ∫max(F_n,0)dt = {ratio}");
            assert!(i.sliding_steps > 0 && i.worst_sliding_power <= 0.0, "χ = {chi}: friction pushed along the slip ({})", i.worst_sliding_power);
            if clipped {
                // The recomputed dashpot keeps e, and rigid-body theory holds in gross sliding.
                assert!((i.restitution - e).abs() < 2e-3, "clipped restitution {}", i.restitution);
                let theory = 3.5 * FRICTION * (1.0 + i.restitution) * v_n / v_st - 1.0;
                assert!((i.beta - theory).abs() < 0.01, "χ = {chi}: β = {} vs χ − 1 = {theory}", i.beta);
            }
        }
    }
}

#[test]
fn a_sticking_spring_still_reverses_the_contact_velocity() {
    // Small tangential speed (χ = 4): the spring stores energy and returns it, β > 0 (Maw et al. 1976).
    let (e, v_n) = (1.0, 0.2);
    let v_st = 3.5 * FRICTION * (1.0 + e) * v_n / 4.0;
    let i = impact(e, false, v_n, v_st, 2000.0);
    println!("χ = 4, e = 1: β = {}, e = {}", i.beta, i.restitution);
    assert!(i.beta > 0.03, "compliance reversal lost: β = {}", i.beta);
    assert!((i.restitution - 1.0).abs() < 1e-3);
}
