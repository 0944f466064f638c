use crate::{DVec3, SurfaceContact};

/// An infinite plane; particles live on the side its normal points to.
#[derive(Clone, Debug, PartialEq)]
pub struct Plane {
    pub point: DVec3,
    /// Unit normal.
    pub normal: DVec3,
}

impl Plane {
    /// A plane through `point`; `normal` is normalised here.
    pub fn new(point: DVec3, normal: DVec3) -> Self {
        Plane { point, normal: normal.normalize() }
    }

    /// Signed distance of `p` from the plane (positive on the normal's side).
    pub fn signed_distance(&self, p: DVec3) -> f64 {
        self.normal.dot(p - self.point)
    }

    pub fn sphere_proximity(&self, centre: DVec3, radius: f64, reach: f64) -> Option<SurfaceContact> {
        let h = self.signed_distance(centre);
        let overlap = radius - h;
        // A sphere whose centre crossed the plane is still pushed back out along the normal.
        (overlap > -reach).then(|| SurfaceContact { normal: self.normal, overlap, point: centre - self.normal * (h + 0.5 * overlap.max(0.0)) })
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn overlap_is_radius_minus_height() {
        let p = Plane::new(DVec3::new(0.0, 0.0, 1.0), DVec3::new(0.0, 0.0, 2.0));
        let c = p.sphere_proximity(DVec3::new(3.0, 4.0, 1.5), 0.6, 0.0).unwrap();
        assert!((c.overlap - 0.1).abs() < 1e-12);
        assert!((c.point - DVec3::new(3.0, 4.0, 0.95)).length() < 1e-12);
        assert!(p.sphere_proximity(DVec3::new(0.0, 0.0, 1.7), 0.6, 0.0).is_none());
    }
}
