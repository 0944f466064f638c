use crate::DVec3;

/// Geometry of two spheres i and j (see docs/physics.md, "Pair geometry").
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct SpherePair {
    /// Unit normal from j to i.
    pub normal: DVec3,
    /// Centre distance |d|.
    pub distance: f64,
    /// Body overlap δ = r_i + r_j − |d|.
    pub overlap: f64,
    /// Lever arm from i's centre to the contact point, c − x_i.
    pub arm_i: DVec3,
    /// Lever arm from j's centre to the contact point, c − x_j.
    pub arm_j: DVec3,
}

/// Pair geometry from the separation `d = x_i − x_j` (already the minimum image).
///
/// Returns `None` for coincident centres, which have no normal.
pub fn sphere_sphere(d: DVec3, r_i: f64, r_j: f64) -> Option<SpherePair> {
    let distance = d.length();
    if distance <= 0.0 {
        return None;
    }
    let normal = d / distance;
    let overlap = r_i + r_j - distance;
    // c = x_i − (r_i − δ/2) n, so c − x_i and c − x_j = c − x_i + d.
    let arm_i = -normal * (r_i - 0.5 * overlap);
    let arm_j = arm_i + d;
    Some(SpherePair { normal, distance, overlap, arm_i, arm_j })
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn contact_point_is_halfway_through_the_overlap() {
        let p = sphere_sphere(DVec3::new(0.18, 0.0, 0.0), 0.1, 0.1).unwrap();
        assert!((p.overlap - 0.02).abs() < 1e-15);
        assert!((p.arm_i - DVec3::new(-0.09, 0.0, 0.0)).length() < 1e-15);
        assert!((p.arm_j - DVec3::new(0.09, 0.0, 0.0)).length() < 1e-15);
    }
}
