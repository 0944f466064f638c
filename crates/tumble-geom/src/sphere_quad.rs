use crate::surface::contact_from_closest;
use crate::{DVec3, SurfaceContact};

/// A planar convex quadrilateral wall with face, edge and corner contacts.
///
/// One-sided quads (box faces) push only towards their normal side; two-sided
/// quads push a sphere away on whichever side its centre is.
#[derive(Clone, Debug, PartialEq)]
pub struct Quad {
    pub corners: [DVec3; 4],
    /// Unit normal, right-handed with the corner order.
    pub normal: DVec3,
    pub two_sided: bool,
}

impl Quad {
    /// A quad from four coplanar corners in order around the edge.
    pub fn new(corners: [DVec3; 4], two_sided: bool) -> Self {
        let normal = (corners[1] - corners[0]).cross(corners[2] - corners[0]).normalize();
        Quad { corners, normal, two_sided }
    }

    /// Largest distance of a corner from the plane through the first three, relative to the size.
    pub fn planarity_error(&self) -> f64 {
        let size = (self.corners[2] - self.corners[0]).length();
        (self.normal.dot(self.corners[3] - self.corners[0])).abs() / size
    }

    /// The six inward-facing one-sided faces of an axis-aligned box.
    pub fn box_faces(min: DVec3, max: DVec3) -> [Quad; 6] {
        let c = |x: f64, y: f64, z: f64| DVec3::new(x, y, z);
        let (a, b) = (min, max);
        [
            // -x face, normal +x
            Quad::new([c(a.x, a.y, a.z), c(a.x, b.y, a.z), c(a.x, b.y, b.z), c(a.x, a.y, b.z)], false),
            // +x face, normal -x
            Quad::new([c(b.x, a.y, a.z), c(b.x, a.y, b.z), c(b.x, b.y, b.z), c(b.x, b.y, a.z)], false),
            // -y face, normal +y
            Quad::new([c(a.x, a.y, a.z), c(a.x, a.y, b.z), c(b.x, a.y, b.z), c(b.x, a.y, a.z)], false),
            // +y face, normal -y
            Quad::new([c(a.x, b.y, a.z), c(b.x, b.y, a.z), c(b.x, b.y, b.z), c(a.x, b.y, b.z)], false),
            // -z face, normal +z
            Quad::new([c(a.x, a.y, a.z), c(b.x, a.y, a.z), c(b.x, b.y, a.z), c(a.x, b.y, a.z)], false),
            // +z face, normal -z
            Quad::new([c(a.x, a.y, b.z), c(a.x, b.y, b.z), c(b.x, b.y, b.z), c(b.x, a.y, b.z)], false),
        ]
    }

    fn foot_inside(&self, foot: DVec3) -> bool {
        (0..4).all(|k| {
            let (p, q) = (self.corners[k], self.corners[(k + 1) % 4]);
            (q - p).cross(foot - p).dot(self.normal) >= 0.0
        })
    }

    /// Closest point of the quad to `p`: the foot of the perpendicular, or on an edge.
    pub fn closest_point(&self, p: DVec3) -> DVec3 {
        let foot = p - self.normal * self.normal.dot(p - self.corners[0]);
        if self.foot_inside(foot) {
            return foot;
        }
        (0..4)
            .map(|k| closest_on_segment(self.corners[k], self.corners[(k + 1) % 4], p))
            .min_by(|a, b| (*a - p).length_squared().total_cmp(&(*b - p).length_squared()))
            .unwrap()
    }

    pub fn sphere_proximity(&self, centre: DVec3, radius: f64, reach: f64) -> Option<SurfaceContact> {
        let h = self.normal.dot(centre - self.corners[0]);
        if h.abs() >= radius + reach || (!self.two_sided && h <= -radius) {
            return None;
        }
        let foot = centre - self.normal * h;
        let side = if self.two_sided && h < 0.0 { -self.normal } else { self.normal };
        if self.foot_inside(foot) {
            let overlap = radius - side.dot(centre - self.corners[0]);
            return (overlap > -reach).then(|| SurfaceContact { normal: side, overlap, point: foot - side * (0.5 * overlap.max(0.0)) });
        }
        // Edge or corner region: a one-sided quad is not touched from behind.
        if !self.two_sided && h <= 0.0 {
            return None;
        }
        let closest = (0..4)
            .map(|k| closest_on_segment(self.corners[k], self.corners[(k + 1) % 4], centre))
            .min_by(|a, b| (*a - centre).length_squared().total_cmp(&(*b - centre).length_squared()))?;
        contact_from_closest(centre, radius, reach, closest, side)
    }
}

/// Closest point to `p` on the segment from `a` to `b`.
pub(crate) fn closest_on_segment(a: DVec3, b: DVec3, p: DVec3) -> DVec3 {
    let ab = b - a;
    let t = ((p - a).dot(ab) / ab.length_squared()).clamp(0.0, 1.0);
    a + ab * t
}

#[cfg(test)]
mod tests {
    use super::*;

    fn unit_square() -> Quad {
        Quad::new([DVec3::ZERO, DVec3::X, DVec3::new(1.0, 1.0, 0.0), DVec3::Y], false)
    }

    #[test]
    fn face_contact_uses_the_quad_normal() {
        let c = unit_square().sphere_proximity(DVec3::new(0.5, 0.5, 0.08), 0.1, 0.0).unwrap();
        assert_eq!(c.normal, DVec3::Z);
        assert!((c.overlap - 0.02).abs() < 1e-12);
    }

    #[test]
    fn edge_contact_points_from_the_edge() {
        // Centre beyond the x = 1 edge, above the plane: closest point is on the edge.
        let centre = DVec3::new(1.06, 0.5, 0.06);
        let c = unit_square().sphere_proximity(centre, 0.1, 0.0).unwrap();
        let expected = DVec3::new(0.06, 0.0, 0.06).normalize();
        assert!((c.normal - expected).length() < 1e-12);
        assert!((c.overlap - (0.1 - 0.06 * 2f64.sqrt())).abs() < 1e-12);
    }

    #[test]
    fn corner_contact_points_from_the_corner() {
        let centre = DVec3::new(-0.05, -0.05, 0.05);
        let c = unit_square().sphere_proximity(centre, 0.1, 0.0).unwrap();
        assert!((c.normal - centre.normalize()).length() < 1e-12);
        assert!((c.overlap - (0.1 - centre.length())).abs() < 1e-12);
    }

    #[test]
    fn one_sided_quad_ignores_spheres_behind_it_outside_the_face() {
        assert!(unit_square().sphere_proximity(DVec3::new(1.05, 0.5, -0.05), 0.1, 0.0).is_none());
        let two = Quad { two_sided: true, ..unit_square() };
        let c = two.sphere_proximity(DVec3::new(0.5, 0.5, -0.05), 0.1, 0.0).unwrap();
        assert_eq!(c.normal, -DVec3::Z);
        assert!((c.overlap - 0.05).abs() < 1e-12);
    }

    #[test]
    fn box_faces_point_inwards() {
        let faces = Quad::box_faces(DVec3::ZERO, DVec3::ONE);
        let centre = DVec3::splat(0.5);
        for f in &faces {
            assert!(f.normal.dot(centre - f.corners[0]) > 0.0, "{f:?}");
            assert!(f.planarity_error() < 1e-15);
        }
    }
}
