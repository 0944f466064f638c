//! The starting particles as a scene compiles them, indexed by particle id.

use crate::SPHERE;
use glam::{DQuat, DVec3};

/// Initial state of every particle, indexed by particle id.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct InitialParticles {
    pub position: Vec<DVec3>,
    pub velocity: Vec<DVec3>,
    pub angular_velocity: Vec<DVec3>,
    /// Sphere radius, or a polyhedron's bounding radius (its reach in the broad phase).
    pub radius: Vec<f64>,
    /// Body volume (mass = density × volume).
    pub volume: Vec<f64>,
    /// [`SPHERE`] or an index into the plan's shape table.
    pub shape: Vec<u16>,
    /// Body-to-world rotation (identity for spheres).
    pub orientation: Vec<DQuat>,
    /// Cohesion effect radius (= radius without cohesion).
    pub effect_radius: Vec<f64>,
    pub material: Vec<u16>,
    pub group: Vec<u16>,
    pub fixed: Vec<bool>,
    pub track: Vec<bool>,
}

impl InitialParticles {
    pub fn len(&self) -> usize {
        self.position.len()
    }

    pub fn is_empty(&self) -> bool {
        self.position.is_empty()
    }

    /// Appends a movable, untracked particle: `body` at `position` with `velocity`, no spin.
    pub fn push_body(&mut self, position: DVec3, velocity: DVec3, body: &crate::Body, material: u16, group: u16) {
        self.position.push(position);
        self.velocity.push(velocity);
        self.angular_velocity.push(DVec3::ZERO);
        self.radius.push(body.radius);
        self.volume.push(body.volume);
        self.shape.push(body.shape);
        self.orientation.push(body.orientation);
        self.effect_radius.push(body.effect_radius);
        self.material.push(material);
        self.group.push(group);
        self.fixed.push(false);
        self.track.push(false);
    }

    /// Appends `other`'s particles after these.
    pub fn append(&mut self, other: &InitialParticles) {
        self.position.extend(&other.position);
        self.velocity.extend(&other.velocity);
        self.angular_velocity.extend(&other.angular_velocity);
        self.radius.extend(&other.radius);
        self.volume.extend(&other.volume);
        self.shape.extend(&other.shape);
        self.orientation.extend(&other.orientation);
        self.effect_radius.extend(&other.effect_radius);
        self.material.extend(&other.material);
        self.group.extend(&other.group);
        self.fixed.extend(&other.fixed);
        self.track.extend(&other.track);
    }

    /// Radius of the sphere of equal volume (the radius itself for spheres).
    pub fn equivalent_radius(&self, i: usize) -> f64 {
        if self.shape[i] == SPHERE { self.radius[i] } else { crate::shapes::equivalent_radius(self.volume[i]) }
    }
}
