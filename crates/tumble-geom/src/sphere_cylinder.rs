use crate::{DVec3, SurfaceContact};

/// A finite open cylinder wall: the inside of a drum shell or the outside of a pipe.
///
/// Contacts count only where the sphere centre projects onto the axis within
/// the length; end caps are separate walls.
#[derive(Clone, Debug, PartialEq)]
pub struct Cylinder {
    /// Centre of the first end of the axis segment.
    pub point: DVec3,
    /// Unit axis direction.
    pub axis: DVec3,
    pub radius: f64,
    pub length: f64,
    /// True: particles are inside (drum); false: particles are outside.
    pub inside: bool,
}

impl Cylinder {
    pub fn new(point: DVec3, axis: DVec3, radius: f64, length: f64, inside: bool) -> Self {
        Cylinder { point, axis: axis.normalize(), radius, length, inside }
    }

    pub fn sphere_proximity(&self, centre: DVec3, radius: f64, reach: f64) -> Option<SurfaceContact> {
        let rel = centre - self.point;
        let s = rel.dot(self.axis);
        if s < 0.0 || s > self.length {
            return None;
        }
        let radial = rel - self.axis * s;
        let rho = radial.length();
        if rho < 1e-12 * self.radius {
            return None; // on the axis: no defined direction, and far from an inside shell
        }
        let out = radial / rho;
        let (normal, overlap) = if self.inside { (-out, radius - (self.radius - rho)) } else { (out, radius - (rho - self.radius)) };
        (overlap > -reach).then(|| SurfaceContact {
            normal,
            overlap,
            point: self.point + self.axis * s + out * self.radius - normal * (0.5 * overlap.max(0.0)),
        })
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn inside_and_outside_overlaps() {
        let drum = Cylinder::new(DVec3::ZERO, DVec3::Z, 1.0, 2.0, true);
        let c = drum.sphere_proximity(DVec3::new(0.95, 0.0, 1.0), 0.1, 0.0).unwrap();
        assert!((c.overlap - 0.05).abs() < 1e-12);
        assert!((c.normal + DVec3::X).length() < 1e-12);
        assert!(drum.sphere_proximity(DVec3::new(0.95, 0.0, 2.5), 0.1, 0.0).is_none());

        let pipe = Cylinder { inside: false, ..drum };
        let c = pipe.sphere_proximity(DVec3::new(0.0, 1.05, 1.0), 0.1, 0.0).unwrap();
        assert!((c.overlap - 0.05).abs() < 1e-12);
        assert!((c.normal - DVec3::Y).length() < 1e-12);
    }
}
