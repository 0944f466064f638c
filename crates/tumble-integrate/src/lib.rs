//! Time integrators (docs/physics.md, "Integrators") as per-particle update rules.
//!
//! A backend calls them in the order [`Integrator::forces_first`] says:
//! Verlet drifts before the force pass, the others update after it.
//!
//! ```
//! use tumble_integrate::{Integrator, symplectic_euler};
//! use glam::DVec3;
//! let (x, v) = symplectic_euler(DVec3::ZERO, DVec3::X, DVec3::Y, 0.1);
//! assert_eq!(v, DVec3::new(1.0, 0.1, 0.0));
//! assert_eq!(x, v * 0.1);
//! assert_eq!(Integrator::Verlet.order(), 2);
//! ```

use glam::{DQuat, DVec3};

/// The time integration scheme of a run.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub enum Integrator {
    /// Forward Euler: first order; gains energy on an undamped spring at any Δt.
    Euler,
    /// Symplectic (semi-implicit) Euler: first order, stable for Δt < 2/ω.
    SymplecticEuler,
    /// Velocity Verlet with one force evaluation per step: second order.
    Verlet,
    /// Andrews' implicit drag with the trapezoid position update (unstable on undamped springs).
    ImplicitDrag,
    /// Implicit drag with the symplectic position update x ← x + v_new Δt (stable alternative).
    ImplicitDragSymplectic,
}

impl Integrator {
    pub const ALL: [Integrator; 5] =
        [Integrator::Euler, Integrator::SymplecticEuler, Integrator::Verlet, Integrator::ImplicitDrag, Integrator::ImplicitDragSymplectic];

    /// The name used in scene files.
    pub fn name(self) -> &'static str {
        match self {
            Integrator::Euler => "euler",
            Integrator::SymplecticEuler => "symplectic-euler",
            Integrator::Verlet => "verlet",
            Integrator::ImplicitDrag => "implicit-drag",
            Integrator::ImplicitDragSymplectic => "implicit-drag-symplectic",
        }
    }

    pub fn from_name(name: &str) -> Option<Self> {
        Self::ALL.into_iter().find(|i| i.name() == name)
    }

    /// Theoretical global order of accuracy for smooth forces.
    pub fn order(self) -> u32 {
        match self {
            Integrator::Verlet => 2,
            _ => 1,
        }
    }

    /// True when the force pass comes before the update (all but Verlet).
    pub fn forces_first(self) -> bool {
        self != Integrator::Verlet
    }

    /// True when drag is integrated implicitly inside the update rather than added as a force.
    pub fn implicit_drag(self) -> bool {
        matches!(self, Integrator::ImplicitDrag | Integrator::ImplicitDragSymplectic)
    }
}

/// Forward Euler: x ← x + v Δt, v ← v + a Δt (both from the old state).
#[inline]
pub fn euler(x: DVec3, v: DVec3, a: DVec3, dt: f64) -> (DVec3, DVec3) {
    (x + v * dt, v + a * dt)
}

/// Symplectic Euler: v ← v + a Δt, then x ← x + v_new Δt.
#[inline]
pub fn symplectic_euler(x: DVec3, v: DVec3, a: DVec3, dt: f64) -> (DVec3, DVec3) {
    let v = v + a * dt;
    (x + v * dt, v)
}

/// Verlet's first half: kick by the old acceleration for Δt/2, then drift a full step.
#[inline]
pub fn verlet_kick_drift(x: DVec3, v: DVec3, a: DVec3, dt: f64) -> (DVec3, DVec3) {
    let v_half = v + a * (0.5 * dt);
    (x + v_half * dt, v_half)
}

/// Verlet's second half: kick by the new acceleration for Δt/2.
#[inline]
pub fn verlet_kick(v_half: DVec3, a: DVec3, dt: f64) -> DVec3 {
    v_half + a * (0.5 * dt)
}

/// The velocity Verlet hands to velocity-dependent forces (damping, drag, friction):
/// v_half + a_old Δt/2 = v_n + a_n Δt, a second-order estimate of v_{n+1}, which
/// keeps the scheme second order when forces depend on velocity.
#[inline]
pub fn verlet_force_velocity(v_half: DVec3, a_old: DVec3, dt: f64) -> DVec3 {
    v_half + a_old * (0.5 * dt)
}

/// Implicit drag (Andrews): v_new = (τ v + τ Δt a_c + u_f Δt)/(τ + Δt), with a_c the
/// explicit acceleration. Position by the trapezoid rule, or by v_new when `symplectic`.
/// `tau = f64::INFINITY` means no drag.
#[inline]
pub fn implicit_drag(x: DVec3, v: DVec3, a_c: DVec3, tau: f64, u_f: DVec3, dt: f64, symplectic: bool) -> (DVec3, DVec3) {
    let v_new = if tau.is_finite() { (v * tau + a_c * (tau * dt) + u_f * dt) / (tau + dt) } else { v + a_c * dt };
    let x_new = if symplectic { x + v_new * dt } else { x + (v + v_new) * (0.5 * dt) };
    (x_new, v_new)
}

/// Advances a unit quaternion by the world-frame angular velocity ω over Δt:
/// q ← normalise(Δq ⊗ q), Δq = (cos(|ω|Δt/2), sin(|ω|Δt/2) ω/|ω|).
#[inline]
pub fn rotate_orientation(q: DQuat, omega: DVec3, dt: f64) -> DQuat {
    let w = omega.length();
    if w == 0.0 {
        return q;
    }
    let half = 0.5 * w * dt;
    let axis = omega / w;
    let dq = DQuat::from_xyzw(axis.x * half.sin(), axis.y * half.sin(), axis.z * half.sin(), half.cos());
    (dq * q).normalize()
}

/// World-frame angular acceleration I⁻¹(M − ω × (I ω)) of a body with principal
/// inertia `inertia` (body frame) and orientation `q`. For spheres the gyroscopic term vanishes.
#[inline]
pub fn angular_acceleration(q: DQuat, inertia: DVec3, omega: DVec3, torque: DVec3) -> DVec3 {
    let omega_body = q.inverse() * omega;
    let torque_body = q.inverse() * torque;
    let l_body = inertia * omega_body;
    q * ((torque_body - omega_body.cross(l_body)) / inertia)
}

/// World-frame I⁻¹ v for a body with principal inverse inertia `inv_inertia` (body frame) at orientation `q`.
#[inline]
pub fn world_inverse_inertia_times(q: DQuat, inv_inertia: DVec3, v: DVec3) -> DVec3 {
    q * (inv_inertia * (q.inverse() * v))
}

/// Torque-free motion of a rigid body over Δt: the world angular momentum L = I_w(q) ω stays
/// fixed while the body turns, so a body spinning about its intermediate axis tumbles.
///
/// Symmetric splitting of the free-body Hamiltonian H = Σ L_k²/2I_k into exact rotations about
/// the body axes, x(Δt/2) y(Δt/2) z(Δt) y(Δt/2) x(Δt/2) (Dullweber, Leimkuhler and McLachlan;
/// LAMMPS's NO_SQUISH): L is conserved to round-off, the energy error is O(Δt²) and bounded.
/// An isotropic body (a sphere) turns about ω exactly.
///
/// ```
/// use glam::{DQuat, DVec3};
/// let inv_inertia = DVec3::new(1.0, 0.5, 1.0 / 3.0);
/// let (q, w0) = (DQuat::IDENTITY, DVec3::new(0.01, 1.0, 0.0));
/// let (q1, w1) = tumble_integrate::free_rotation(q, inv_inertia, w0, 1e-3);
/// let l = |q: DQuat, w: DVec3| q * ((q.inverse() * w) / inv_inertia);
/// assert!((l(q1, w1) - l(q, w0)).length() < 1e-14);
/// ```
pub fn free_rotation(q: DQuat, inv_inertia: DVec3, omega: DVec3, dt: f64) -> (DQuat, DVec3) {
    // Equal principal moments to round-off (a cube, a regular solid) turn about ω exactly.
    if inv_inertia.max_element() - inv_inertia.min_element() <= 1e-12 * inv_inertia.max_element() {
        return (rotate_orientation(q, omega, dt), omega);
    }
    let mut l_body = (q.inverse() * omega) / inv_inertia;
    let mut q = q;
    let axes = [DVec3::X, DVec3::Y, DVec3::Z];
    for (k, h) in [(0, 0.5), (1, 0.5), (2, 1.0), (1, 0.5), (0, 0.5)] {
        // The flow of L_k²/2I_k: the body turns about its axis k by φ, L in the body frame by −φ.
        let phi = l_body[k] * inv_inertia[k] * h * dt;
        let turn = DQuat::from_axis_angle(axes[k], phi);
        q *= turn;
        l_body = turn.inverse() * l_body;
    }
    let q = q.normalize();
    (q, q * (inv_inertia * l_body))
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Harmonic oscillator x'' = −x from (1, 0), integrated to t = 1.
    fn oscillator_error(integrator: Integrator, steps: usize) -> f64 {
        let dt = 1.0 / steps as f64;
        let (mut x, mut v) = (DVec3::X, DVec3::ZERO);
        let mut a = -x;
        for _ in 0..steps {
            (x, v) = match integrator {
                Integrator::Euler => euler(x, v, -x, dt),
                Integrator::SymplecticEuler => symplectic_euler(x, v, -x, dt),
                Integrator::Verlet => {
                    let (x1, vh) = verlet_kick_drift(x, v, a, dt);
                    a = -x1;
                    (x1, verlet_kick(vh, a, dt))
                }
                Integrator::ImplicitDrag => implicit_drag(x, v, -x, f64::INFINITY, DVec3::ZERO, dt, false),
                Integrator::ImplicitDragSymplectic => implicit_drag(x, v, -x, f64::INFINITY, DVec3::ZERO, dt, true),
            };
        }
        (x.x - 1f64.cos()).abs()
    }

    #[test]
    fn orders_on_the_harmonic_oscillator() {
        for integrator in Integrator::ALL {
            let order = (oscillator_error(integrator, 200) / oscillator_error(integrator, 400)).log2();
            assert!((order - integrator.order() as f64).abs() < 0.15, "{integrator:?}: {order}");
        }
    }

    #[test]
    fn quaternion_turns_once_per_period() {
        let omega = DVec3::new(std::f64::consts::TAU, 0.0, 0.0);
        let mut q = DQuat::IDENTITY;
        for _ in 0..1000 {
            q = rotate_orientation(q, omega, 1e-3);
        }
        assert!((q * DVec3::Y - DVec3::Y).length() < 1e-9);
        assert!((q.length() - 1.0).abs() < 1e-12);
    }

    #[test]
    fn gyroscopic_term_vanishes_for_isotropic_bodies() {
        let q = DQuat::from_rotation_y(0.3);
        let a = angular_acceleration(q, DVec3::splat(2.0), DVec3::new(1.0, 2.0, 3.0), DVec3::new(0.0, 0.0, 4.0));
        assert!((a - DVec3::new(0.0, 0.0, 2.0)).length() < 1e-12);
    }

    /// Kinetic energy and world angular momentum of a free body.
    fn energy_momentum(q: DQuat, inv_inertia: DVec3, omega: DVec3) -> (f64, DVec3) {
        let l_body = (q.inverse() * omega) / inv_inertia;
        (0.5 * l_body.dot(l_body * inv_inertia), q * l_body)
    }

    /// Spin about the intermediate axis with a small perturbation, integrated over `t`.
    fn tumble(dt: f64, t: f64) -> (f64, f64, f64) {
        let inv_inertia = DVec3::new(1.0, 0.5, 1.0 / 3.0);
        let (mut q, mut w) = (DQuat::IDENTITY, DVec3::new(1e-3, 2.0, 1e-3));
        let (e0, l0) = energy_momentum(q, inv_inertia, w);
        let (mut worst_e, mut min_axis) = (0.0f64, 1.0f64);
        for _ in 0..(t / dt).round() as usize {
            (q, w) = free_rotation(q, inv_inertia, w, dt);
            let (e, l) = energy_momentum(q, inv_inertia, w);
            assert!((l - l0).length() < 1e-10 * l0.length(), "angular momentum drifts: {:e}", (l - l0).length() / l0.length());
            worst_e = worst_e.max((e / e0 - 1.0).abs());
            // The body y axis against its start: it flips over as the body tumbles.
            min_axis = min_axis.min((q * DVec3::Y).dot(DVec3::Y));
        }
        (worst_e, min_axis, (q.length() - 1.0).abs())
    }

    #[test]
    fn intermediate_axis_spin_tumbles_with_energy_and_momentum_conserved() {
        let (e_coarse, flip, norm) = tumble(2e-3, 20.0);
        assert!(flip < -0.9, "spin about the intermediate axis must flip over: min cos = {flip}");
        assert!(norm < 1e-12);
        let (e_fine, _, _) = tumble(1e-3, 20.0);
        // Second order: halving Δt quarters the (bounded) energy error.
        let order = (e_coarse / e_fine).log2();
        eprintln!("tumbling: energy error {e_coarse:e} at 2e-3, {e_fine:e} at 1e-3, order {order:.3}, min cos {flip:.4}");
        assert!((order - 2.0).abs() < 0.3, "energy error order {order} ({e_coarse:e} → {e_fine:e})");
        assert!(e_fine < 1e-5, "energy error {e_fine:e}");
    }

    #[test]
    fn spin_about_a_major_or_minor_axis_is_stable() {
        let inv_inertia = DVec3::new(1.0, 0.5, 1.0 / 3.0);
        for axis in [DVec3::X, DVec3::Z] {
            let (mut q, mut w) = (DQuat::IDENTITY, axis * 2.0 + DVec3::splat(1e-3));
            for _ in 0..10_000 {
                (q, w) = free_rotation(q, inv_inertia, w, 2e-3);
            }
            assert!((q * axis).dot(axis) > 0.99, "spin about {axis} stays put");
        }
    }

    #[test]
    fn isotropic_free_rotation_turns_about_omega() {
        let w = DVec3::new(0.0, 0.0, std::f64::consts::TAU);
        let (mut q, mut omega) = (DQuat::IDENTITY, w);
        for _ in 0..1000 {
            (q, omega) = free_rotation(q, DVec3::splat(2.0), omega, 1e-3);
        }
        assert_eq!(omega, w);
        assert!((q * DVec3::X - DVec3::X).length() < 1e-9);
    }
}
