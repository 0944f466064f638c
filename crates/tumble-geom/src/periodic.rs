use crate::DVec3;

/// An axis-aligned domain, periodic along any subset of its axes.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct PeriodicBox {
    pub min: DVec3,
    pub max: DVec3,
    pub periodic: [bool; 3],
}

impl PeriodicBox {
    pub fn extent(&self) -> DVec3 {
        self.max - self.min
    }

    /// The minimum image of a separation vector along the periodic axes.
    #[inline]
    pub fn minimum_image(&self, mut d: DVec3) -> DVec3 {
        let l = self.extent();
        for k in 0..3 {
            if self.periodic[k] {
                let half = 0.5 * l[k];
                if d[k] > half {
                    d[k] -= l[k];
                } else if d[k] < -half {
                    d[k] += l[k];
                }
            }
        }
        d
    }

    /// Wraps a position back into the box along the periodic axes.
    #[inline]
    pub fn wrap(&self, mut x: DVec3) -> DVec3 {
        let l = self.extent();
        for k in 0..3 {
            if self.periodic[k] {
                if x[k] >= self.max[k] {
                    x[k] -= l[k];
                } else if x[k] < self.min[k] {
                    x[k] += l[k];
                }
                // A particle moved more than a box length in one step: wrap fully.
                if x[k] >= self.max[k] || x[k] < self.min[k] {
                    x[k] = self.min[k] + (x[k] - self.min[k]).rem_euclid(l[k]);
                }
            }
        }
        x
    }

    /// True when `x` lies inside along every non-periodic axis.
    pub fn contains(&self, x: DVec3) -> bool {
        (0..3).all(|k| self.periodic[k] || (x[k] >= self.min[k] && x[k] <= self.max[k]))
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use proptest::prelude::*;

    fn domain() -> PeriodicBox {
        PeriodicBox { min: DVec3::splat(-1.0), max: DVec3::new(1.0, 2.0, 3.0), periodic: [true, true, false] }
    }

    proptest! {
        #[test]
        fn minimum_image_is_shortest(dx in -1.99f64..1.99, dy in -2.99f64..2.99, dz in -4.0f64..4.0) {
            let b = domain();
            let m = b.minimum_image(DVec3::new(dx, dy, dz));
            prop_assert!(m.x.abs() <= 1.0 + 1e-12 && m.y.abs() <= 1.5 + 1e-12);
            prop_assert_eq!(m.z, dz);
        }

        #[test]
        fn wrap_lands_inside(x in -10.0f64..10.0, y in -10.0f64..10.0) {
            let w = domain().wrap(DVec3::new(x, y, 0.5));
            prop_assert!(w.x >= -1.0 && w.x < 1.0 && w.y >= -1.0 && w.y < 2.0);
        }
    }
}
