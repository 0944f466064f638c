use crate::DVec3;

/// An axis-aligned domain, periodic along any subset of its axes.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct PeriodicBox {
    pub min: DVec3,
    pub max: DVec3,
    pub periodic: [bool; 3],
}

impl PeriodicBox {
    #[inline]
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
    pub fn wrap(&self, x: DVec3) -> DVec3 {
        let mut image = [0; 3];
        self.wrap_counting(x, &mut image)
    }

    /// [`PeriodicBox::wrap`] that also counts the box lengths taken off each axis into `image`
    /// (+1 per length subtracted), so the unwrapped position `x + image ∘ L` is kept.
    #[inline]
    pub fn wrap_counting(&self, mut x: DVec3, image: &mut [i32; 3]) -> DVec3 {
        let l = self.extent();
        for k in 0..3 {
            if self.periodic[k] {
                if x[k] >= self.max[k] {
                    x[k] -= l[k];
                    image[k] = image[k].saturating_add(1);
                } else if x[k] < self.min[k] {
                    x[k] += l[k];
                    image[k] = image[k].saturating_sub(1);
                }
                // A particle moved more than a box length in one step: wrap fully.
                if x[k] >= self.max[k] || x[k] < self.min[k] {
                    let lengths = ((x[k] - self.min[k]) / l[k]).floor();
                    x[k] = self.min[k] + (x[k] - self.min[k]).rem_euclid(l[k]);
                    // Saturates for a particle that has flown off to a non-finite distance (the monitor stops that run).
                    image[k] = image[k].saturating_add(lengths as i32);
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
        fn wrap_counting_keeps_the_unwrapped_position(x in -10.0f64..10.0, y in -10.0f64..10.0, z in -4.0f64..4.0) {
            let d = domain();
            let x0 = DVec3::new(x, y, z);
            let mut image = [0; 3];
            let w = d.wrap_counting(x0, &mut image);
            let l = d.extent();
            let back = w + DVec3::new(image[0] as f64, image[1] as f64, image[2] as f64) * l;
            prop_assert!((back - x0).abs().max_element() < 1e-12, "{x0} wrapped to {w} with {image:?}");
            prop_assert_eq!(image[2], 0);
            prop_assert_eq!(w, d.wrap(x0));
        }

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
