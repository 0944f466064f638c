//! Tangential laws (docs/physics.md, "Tangential force"): the history-free ones here,
//! the spring with history in `history.rs`.

use crate::SpringLaw;
use glam::DVec3;

/// How the viscous coefficient of the viscous-Coulomb law is given.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum ViscousParameter {
    /// c_t in N s/m.
    Coefficient(f64),
    /// Estimated-displacement stiffness k_f in N/m: c_t = k_f t_col of the contact.
    Stiffness(f64),
}

/// A tangential law with its parameters for one material pair.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum TangentialLaw {
    None,
    /// F_t = −min(μ|F_n|, c_t|v_t|) t̂ (Blaze-DEM).
    ViscousCoulomb {
        friction: f64,
        viscous: ViscousParameter,
    },
    /// F_t = −min(μ|F_n|, m*|v_t|/Δt) t̂.
    StickLimited {
        friction: f64,
    },
    /// F_t = −μ|F_n| t̂: no static part; oscillates around rest (a documented failure case).
    DynamicOnly {
        friction: f64,
    },
    /// Tangential spring with history, capped at μ|F_n| (see [`crate::history_force`]).
    History {
        friction: f64,
        spring: SpringLaw,
    },
}

impl TangentialLaw {
    pub fn friction(&self) -> f64 {
        match *self {
            TangentialLaw::None => 0.0,
            TangentialLaw::ViscousCoulomb { friction, .. }
            | TangentialLaw::StickLimited { friction }
            | TangentialLaw::DynamicOnly { friction }
            | TangentialLaw::History { friction, .. } => friction,
        }
    }

    /// True for the law that keeps a spring per contact.
    pub fn has_history(&self) -> bool {
        matches!(self, TangentialLaw::History { .. })
    }
}

/// Tangential force on i for the tangential relative velocity `vt`.
///
/// `normal` is |F_n|; `collision_time` is the contact's t_col, used only when
/// the viscous coefficient is given as a stiffness. The history law needs its
/// spring and is computed by [`crate::history_force`]; here it gives zero.
#[inline]
pub fn tangential_force(law: &TangentialLaw, normal: f64, vt: DVec3, m_star: f64, dt: f64, collision_time: f64) -> DVec3 {
    let speed = vt.length();
    if speed == 0.0 {
        return DVec3::ZERO;
    }
    let coulomb = match *law {
        TangentialLaw::None | TangentialLaw::History { .. } => return DVec3::ZERO,
        TangentialLaw::ViscousCoulomb { friction, .. } | TangentialLaw::StickLimited { friction } | TangentialLaw::DynamicOnly { friction } => {
            friction * normal
        }
    };
    let magnitude = match *law {
        TangentialLaw::ViscousCoulomb { viscous, .. } => {
            let c_t = match viscous {
                ViscousParameter::Coefficient(c) => c,
                ViscousParameter::Stiffness(k_f) => k_f * collision_time,
            };
            coulomb.min(c_t * speed)
        }
        TangentialLaw::StickLimited { .. } => coulomb.min(m_star * speed / dt),
        _ => coulomb,
    };
    vt * (-magnitude / speed)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn viscous_then_coulomb() {
        let law = TangentialLaw::ViscousCoulomb { friction: 0.5, viscous: ViscousParameter::Coefficient(10.0) };
        let slow = tangential_force(&law, 2.0, DVec3::new(0.01, 0.0, 0.0), 1.0, 1e-3, 1e-3);
        assert!((slow + DVec3::new(0.1, 0.0, 0.0)).length() < 1e-15);
        let fast = tangential_force(&law, 2.0, DVec3::new(0.0, 3.0, 0.0), 1.0, 1e-3, 1e-3);
        assert!((fast + DVec3::new(0.0, 1.0, 0.0)).length() < 1e-15);
    }

    #[test]
    fn stiffness_form_is_the_viscous_form_with_ct_equal_kf_tcol() {
        let a = TangentialLaw::ViscousCoulomb { friction: 1.0, viscous: ViscousParameter::Stiffness(1e5) };
        let b = TangentialLaw::ViscousCoulomb { friction: 1.0, viscous: ViscousParameter::Coefficient(1e5 * 2e-3) };
        let v = DVec3::new(1e-4, 2e-4, 0.0);
        assert_eq!(tangential_force(&a, 100.0, v, 1.0, 1e-5, 2e-3), tangential_force(&b, 100.0, v, 1.0, 1e-5, 2e-3));
    }

    #[test]
    fn stick_limited_cancels_slip_in_one_step() {
        let law = TangentialLaw::StickLimited { friction: 1.0 };
        let f = tangential_force(&law, 1e3, DVec3::new(0.2, 0.0, 0.0), 0.5, 1e-3, 0.0);
        assert!((f.x + 0.5 * 0.2 / 1e-3).abs() < 1e-9);
    }
}
