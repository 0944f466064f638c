//! Force laws for tumble as pure functions (docs/physics.md).
//!
//! Sign conventions: `n` points from j to i, forces act on i, the normal force
//! is a signed magnitude along `n` (positive pushes i away from j).
//!
//! ```
//! use tumble_contact::{NormalLaw, normal_force, collision_time};
//! let law = NormalLaw::linear(1.0e5, 0.8);
//! let f = normal_force(&law, 1.0e-4, -1.0, 0.01, 0.05);
//! assert!(f.total() > 10.0); // spring 10 N plus damping against the approach
//! assert!(collision_time(1.0e5, 0.01, 0.8) > 0.0);
//! ```

pub use glam::DVec3;

mod cohesion;
mod drag;
mod history;
mod normal;
mod params;
mod rolling;
mod tangential;

pub use cohesion::{cohesion_energy, cohesion_force, stickiness_number};
pub use drag::{FlowField, quadratic_drag, stokes_drag, stokes_relaxation_time};
pub use history::{SpringForce, SpringLaw, history_force, rolling_torque};
pub use normal::{NormalForce, NormalLaw, normal_force};
pub use params::{
    MIN_CLIPPED_RESTITUTION, clipped_damping_ratio, clipped_hertz_beta, collision_time, damping_ratio, hertz_beta, hertz_contact_time,
    hertz_effective_moduli, hertz_max_force, hertz_max_overlap, linear_damping, rayleigh_time,
};
pub use rolling::{RollingModel, RollingSpring, epsd2_torque, rolling_stiffness};
pub use tangential::{TangentialLaw, ViscousParameter, tangential_force};
