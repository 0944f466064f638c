//! Contact geometry for tumble: where two bodies touch, along which normal and how deep.
//!
//! Everything here is pure geometry in `f64`: no masses, no forces, no scenes.
//! The narrow phase has one file per shape pair behind [`SurfaceShape::sphere_contact`].
//!
//! ```
//! use tumble_geom::{DVec3, Plane, SurfaceShape};
//! let floor = SurfaceShape::Plane(Plane::new(DVec3::ZERO, DVec3::Z));
//! let c = floor.sphere_contact(DVec3::new(0.0, 0.0, 0.04), 0.05).unwrap();
//! assert!((c.overlap - 0.01).abs() < 1e-15);
//! assert_eq!(c.normal, DVec3::Z);
//! ```

pub use glam::{DQuat, DVec3};

mod periodic;
mod sphere_cylinder;
mod sphere_plane;
mod sphere_prism;
mod sphere_quad;
mod sphere_sphere;
mod surface;

pub use periodic::PeriodicBox;
pub use sphere_cylinder::Cylinder;
pub use sphere_plane::Plane;
pub use sphere_prism::Prism;
pub use sphere_quad::Quad;
pub use sphere_sphere::{SpherePair, sphere_sphere};
pub use surface::{SurfaceContact, SurfaceShape};
