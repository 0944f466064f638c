use glam::{DMat3, DQuat};

use crate::DVec3;

/// A rigid-body pose: the body frame's origin (the centre of mass) in the world and its orientation.
///
/// `to_world(p) = position + rotation * p`: body coordinates to world coordinates.
///
/// ```
/// use tumble_geom::{DVec3, Pose};
/// use glam::DQuat;
/// let pose = Pose::new(DVec3::new(1.0, 0.0, 0.0), DQuat::from_rotation_z(std::f64::consts::FRAC_PI_2));
/// let w = pose.to_world(DVec3::X);
/// assert!((w - DVec3::new(1.0, 1.0, 0.0)).length() < 1e-15);
/// assert!((pose.to_body(w) - DVec3::X).length() < 1e-15);
/// ```
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Pose {
    pub position: DVec3,
    /// Unit quaternion, body to world.
    pub rotation: DQuat,
}

impl Default for Pose {
    fn default() -> Self {
        Pose::IDENTITY
    }
}

impl Pose {
    pub const IDENTITY: Pose = Pose { position: DVec3::ZERO, rotation: DQuat::IDENTITY };

    /// A pose; the quaternion is normalised here.
    pub fn new(position: DVec3, rotation: DQuat) -> Self {
        Pose { position, rotation: rotation.normalize() }
    }

    /// A translation only.
    pub fn from_position(position: DVec3) -> Self {
        Pose { position, rotation: DQuat::IDENTITY }
    }

    /// Body point to world point.
    #[inline]
    pub fn to_world(&self, p: DVec3) -> DVec3 {
        self.position + self.rotation * p
    }

    /// World point to body point.
    #[inline]
    pub fn to_body(&self, p: DVec3) -> DVec3 {
        self.rotation.inverse() * (p - self.position)
    }

    /// Body direction to world direction.
    #[inline]
    pub fn rotate(&self, v: DVec3) -> DVec3 {
        self.rotation * v
    }

    /// World direction to body direction.
    #[inline]
    pub fn unrotate(&self, v: DVec3) -> DVec3 {
        self.rotation.inverse() * v
    }

    /// The rotation as a matrix (columns are the body axes in the world).
    #[inline]
    pub fn matrix(&self) -> DMat3 {
        DMat3::from_quat(self.rotation)
    }

    /// The pose of `other`'s body frame seen from this body's frame: `self⁻¹ ∘ other`.
    pub fn relative(&self, other: &Pose) -> Pose {
        let inv = self.rotation.inverse();
        Pose { position: inv * (other.position - self.position), rotation: (inv * other.rotation).normalize() }
    }

    /// Composition `self ∘ other` (apply `other` first).
    pub fn compose(&self, other: &Pose) -> Pose {
        Pose { position: self.to_world(other.position), rotation: (self.rotation * other.rotation).normalize() }
    }

    /// The same pose as parry3d's type (for the oracle and for callers that use parry directly).
    pub fn to_parry(&self) -> parry3d_f64::math::Pose {
        parry3d_f64::math::Pose::from_parts(self.position, self.rotation)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn relative_and_compose_are_inverse() {
        let a = Pose::new(DVec3::new(0.3, -1.0, 2.0), DQuat::from_euler(glam::EulerRot::XYZ, 0.3, -0.7, 1.1));
        let b = Pose::new(DVec3::new(-0.5, 0.2, 0.1), DQuat::from_euler(glam::EulerRot::XYZ, -1.3, 0.4, 0.2));
        let rel = a.relative(&b);
        let back = a.compose(&rel);
        assert!((back.position - b.position).length() < 1e-14);
        assert!(back.rotation.dot(b.rotation).abs() > 1.0 - 1e-14);
        let p = DVec3::new(0.1, 0.2, 0.3);
        assert!((a.to_world(rel.to_world(p)) - b.to_world(p)).length() < 1e-14);
        let pp = b.to_parry();
        assert!((pp.transform_point(p) - b.to_world(p)).length() < 1e-14);
    }
}
