//! Contact geometry for tumble: where two bodies touch, along which normal and how deep.
//!
//! Everything here is pure geometry in `f64`: no masses, no forces, no scenes.
//! The narrow phase has one file per shape pair behind [`SurfaceShape::sphere_contact`].
//!
//! Convex polyhedra ([`Polyhedron`], posed by [`Pose`]) meet each other through
//! [`polyhedron_polyhedron`], spheres through [`sphere_polyhedron`] and walls through
//! [`SurfaceShape::polyhedron_contact`]; every such contact is a [`PolyContact`] with the normal
//! from B (the second body, or the wall) to A, a depth ≥ 0 and up to four manifold points.
//! parry3d-f64 computes hulls and mass properties and is the oracle of the property tests.
//!
//! ```
//! use tumble_geom::{DVec3, Plane, SurfaceShape};
//! let floor = SurfaceShape::Plane(Plane::new(DVec3::ZERO, DVec3::Z));
//! let c = floor.sphere_contact(DVec3::new(0.0, 0.0, 0.04), 0.05).unwrap();
//! assert!((c.overlap - 0.01).abs() < 1e-15);
//! assert_eq!(c.normal, DVec3::Z);
//! ```

pub use glam::{DQuat, DVec3};

mod contact_mass;
mod enclosing_sphere;
mod mesh;
mod mesh_distance;
mod mesh_grid;
mod mesh_wall;
mod motion;
mod overlap_volume;
mod periodic;
mod polyhedron;
mod polyhedron_cylinder;
mod polyhedron_mesh;
mod polyhedron_plane;
mod polyhedron_polyhedron;
mod polyhedron_quad;
mod pose;
mod sphere_cylinder;
mod sphere_mesh;
mod sphere_plane;
mod sphere_polyhedron;
mod sphere_prism;
mod sphere_quad;
mod sphere_sphere;
mod surface;
mod volume_contact;
mod volume_walls;

pub use enclosing_sphere::{Ball, best_ball, enclosing_sphere_of_points, enclosing_sphere_of_spheres, tangent_balls};
pub use mesh::{DEFAULT_CURVATURE, EdgeKind, MeshError, MeshReport, OPEN, TriangleMesh, box_triangles, box_triangles_subdivided};
pub use mesh_grid::TriangleGrid;
pub use mesh_wall::{MeshBody, MeshWall, MeshWallContact};
pub use motion::{Motion, Timing};
pub use overlap_volume::{OverlapVolume, overlap_volume, overlap_volume_about};
pub use periodic::PeriodicBox;
pub use polyhedron::{Edge, Face, Polyhedron};
pub use polyhedron_mesh::{MeshPatches, PatchContact};
pub use polyhedron_polyhedron::{
    ContactFeature, ManifoldPoint, PolyContact, SAT_MAX_EDGE_PAIRS, SeparationCache, polyhedron_polyhedron, polyhedron_polyhedron_cached,
    polyhedron_polyhedron_gjk, polyhedron_polyhedron_sat, segment_closest_points,
};
pub use pose::Pose;
pub use sphere_cylinder::Cylinder;
pub use sphere_mesh::{MeshContact, NO_CONTACT, Region, closest_point_on_triangle};
pub use sphere_plane::Plane;
pub use sphere_polyhedron::{closest_point_on_polyhedron, sphere_polyhedron};
pub use sphere_prism::Prism;
pub use sphere_quad::Quad;
pub use sphere_sphere::{SpherePair, sphere_sphere};
pub use surface::{SurfaceContact, SurfaceShape};
pub use volume_contact::{
    CORNER_SMOOTHING, PenetratingPoint, VolumeContact, edge_density, face_on_weight, polyhedron_polyhedron_volume, wall_hull_volume,
};
pub use volume_walls::CYLINDER_EDGE_POINTS;
