//! Particle shapes: each polyhedral particle group has one entry in the plan's shape table.

use glam::DQuat;
use tumble_geom::Polyhedron;

/// Shape index of a sphere (any other value indexes `Plan::shapes`).
pub const SPHERE: u16 = u16::MAX;

/// Radius of the sphere with volume `volume`: a polyhedron's R* and overlap-ratio radius.
pub fn equivalent_radius(volume: f64) -> f64 {
    (3.0 * volume / (4.0 * std::f64::consts::PI)).cbrt()
}

/// A polyhedral particle type: the body (centre of mass at the origin, principal axes along
/// the body axes) and the rotation that takes the shape as the scene gave it to the body frame.
#[derive(Clone, Debug, PartialEq)]
pub struct ParticleShape {
    /// Where the shape came from (`particles[g].shape.cube`), for messages and outputs.
    pub name: String,
    pub body: Polyhedron,
    /// The radius of the sphere of equal volume: R* of the contact laws and the overlap ratio.
    pub equivalent_radius: f64,
    /// The largest face area: the overlap-volume contact's reference area (a face lying flat on
    /// another body or a wall meets the normal law's stiffness at this area).
    pub contact_area: f64,
    /// How many times a face lying on a larger face meets the normal law in that model
    /// (`tumble_geom::face_on_weight`): its parts are damped at m* over it.
    pub face_on_weight: f64,
    /// Orientation of the body frame in the frame the shape was given in (a particle with this
    /// orientation shows the shape as written in the scene).
    pub as_given: DQuat,
}

impl ParticleShape {
    /// The shape of `body`, named `name`.
    pub fn new(name: String, body: Polyhedron) -> ParticleShape {
        let equivalent_radius = equivalent_radius(body.volume());
        let as_given = body.input_to_body().rotation.inverse();
        let contact_area = body.largest_face_area();
        let face_on_weight = tumble_geom::face_on_weight(&body);
        ParticleShape { name, body, equivalent_radius, contact_area, face_on_weight, as_given }
    }
}
