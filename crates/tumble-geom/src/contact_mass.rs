//! How much lighter a polyhedron feels to a contact off its centre: the effective mass that
//! sets the contact's period, and so the time step (a corner hit turns the body as it pushes it).

use crate::{DVec3, Polyhedron};

impl Polyhedron {
    /// The smallest effective mass of a contact at a vertex, as a fraction of the mass:
    /// min over vertices v and unit normals n of 1 / (1 + m (v × n)ᵀ I⁻¹ (v × n)).
    ///
    /// A push along n at v accelerates the contact point by (1/m + (v × n)ᵀ I⁻¹ (v × n)) F, so a
    /// contact there oscillates as if the body had this fraction of its mass. Density cancels.
    ///
    /// ```
    /// use tumble_geom::Polyhedron;
    /// // Cube of edge a: m |v|² / I = (3a²/4) / (a²/6) = 4.5 at a corner, with n ⊥ v.
    /// let f = Polyhedron::cube(0.3).contact_mass_fraction();
    /// assert!((f - 1.0 / 5.5).abs() < 1e-12);
    /// ```
    pub fn contact_mass_fraction(&self) -> f64 {
        let inverse = self.unit_inertia().recip();
        let mass = self.volume();
        self.vertices().iter().map(|&v| 1.0 / (1.0 + mass * v.length_squared() * largest_across(inverse, v))).fold(1.0, f64::min)
    }
}

/// The largest value of uᵀ diag(d) u over unit vectors u perpendicular to v (v × n with |n| = 1
/// spans the disc of radius |v| in the plane perpendicular to v).
fn largest_across(d: DVec3, v: DVec3) -> f64 {
    if v.length_squared() == 0.0 {
        return 0.0;
    }
    let (e1, e2) = v.normalize().any_orthonormal_pair();
    let (a, b, c) = ((e1 * d).dot(e1), (e1 * d).dot(e2), (e2 * d).dot(e2));
    0.5 * (a + c) + (0.25 * (a - c) * (a - c) + b * b).sqrt()
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Brute force over normals: the closed-form maximum is attained and never exceeded.
    #[test]
    fn contact_mass_fraction_matches_a_search_over_normals() {
        let body = Polyhedron::cuboid(DVec3::new(0.1, 0.25, 0.4));
        let inverse = body.unit_inertia().recip();
        let mut worst = 1.0f64;
        for &v in body.vertices() {
            for i in 0..400 {
                let (theta, phi) = (std::f64::consts::PI * (i / 20) as f64 / 20.0, std::f64::consts::TAU * (i % 20) as f64 / 20.0);
                let n = DVec3::new(theta.sin() * phi.cos(), theta.sin() * phi.sin(), theta.cos());
                let u = v.cross(n);
                worst = worst.min(1.0 / (1.0 + body.volume() * (u * inverse).dot(u)));
            }
        }
        let exact = body.contact_mass_fraction();
        assert!(exact <= worst + 1e-12 && exact > 0.97 * worst, "closed form {exact}, search {worst}");
    }
}
