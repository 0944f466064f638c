//! The Wendland C2 kernel (Wendland 1995) with support 2h, in two and three dimensions.

use std::f64::consts::PI;

/// Plane (x–z, y held at zero) or space.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Dimension {
    Two,
    Three,
}

impl Dimension {
    /// The number of spatial dimensions.
    pub fn count(self) -> i32 {
        match self {
            Dimension::Two => 2,
            Dimension::Three => 3,
        }
    }
}

/// W(r) = α (1 − q/2)⁴ (2q + 1), q = r/h, for q ≤ 2; α = 7/(4π h²) in 2D, 21/(16π h³) in 3D.
#[derive(Clone, Copy, Debug)]
pub struct WendlandC2 {
    h: f64,
    inv_h: f64,
    alpha: f64,
}

impl WendlandC2 {
    pub fn new(h: f64, dimension: Dimension) -> Self {
        let alpha = match dimension {
            Dimension::Two => 7.0 / (4.0 * PI * h * h),
            Dimension::Three => 21.0 / (16.0 * PI * h * h * h),
        };
        WendlandC2 { h, inv_h: 1.0 / h, alpha }
    }

    pub fn h(&self) -> f64 {
        self.h
    }

    /// The support radius 2h.
    pub fn support(&self) -> f64 {
        2.0 * self.h
    }

    /// W at distance `r`.
    #[inline]
    pub fn value(&self, r: f64) -> f64 {
        let q = r * self.inv_h;
        if q >= 2.0 {
            return 0.0;
        }
        let s = 1.0 - 0.5 * q;
        let s2 = s * s;
        self.alpha * s2 * s2 * (2.0 * q + 1.0)
    }

    /// (dW/dr)/r, so that ∇_a W_ab = r_ab · this; finite at r = 0.
    ///
    /// dW/dr = α (−5 q/h) (1 − q/2)³, hence (dW/dr)/r = −5 α (1 − q/2)³ / h².
    #[inline]
    pub fn gradient_over_r(&self, r: f64) -> f64 {
        let q = r * self.inv_h;
        if q >= 2.0 {
            return 0.0;
        }
        let s = 1.0 - 0.5 * q;
        -5.0 * self.alpha * s * s * s * self.inv_h * self.inv_h
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// ∫ W dV = 1 in both dimensions, by the radial quadrature of a smooth integrand.
    #[test]
    fn kernel_is_normalised_in_2d_and_3d() {
        let h = 0.37;
        for (dim, shell) in [(Dimension::Two, &(|r: f64| 2.0 * PI * r) as &dyn Fn(f64) -> f64), (Dimension::Three, &|r: f64| 4.0 * PI * r * r)] {
            let w = WendlandC2::new(h, dim);
            let n = 20_000;
            let dr = 2.0 * h / n as f64;
            // Simpson's rule on [0, 2h].
            let mut sum = 0.0;
            for i in 0..=n {
                let r = i as f64 * dr;
                let c = if i == 0 || i == n {
                    1.0
                } else if i % 2 == 1 {
                    4.0
                } else {
                    2.0
                };
                sum += c * w.value(r) * shell(r);
            }
            let integral = sum * dr / 3.0;
            assert!((integral - 1.0).abs() < 1e-10, "{dim:?}: ∫W = {integral}");
        }
    }

    /// The gradient against a central difference of the value.
    #[test]
    fn gradient_matches_the_derivative_of_the_value() {
        let w = WendlandC2::new(0.5, Dimension::Three);
        for i in 1..40 {
            let r = i as f64 * 0.025;
            let e = 1e-6;
            let numeric = (w.value(r + e) - w.value(r - e)) / (2.0 * e);
            let analytic = w.gradient_over_r(r) * r;
            assert!((numeric - analytic).abs() < 1e-7 * (1.0 + analytic.abs()), "r {r}: {numeric} vs {analytic}");
        }
        assert_eq!(w.value(1.0), 0.0);
        assert_eq!(w.gradient_over_r(1.0), 0.0);
    }
}
