//! Sphere diameters: one value, uniform, normal, log-normal or a sieve table — checked,
//! sampled from the run's generator, and their moments for fill and mass estimates.
//!
//! Normal and log-normal are truncated at ±3 standard deviations (of d, or of ln d), so every
//! diameter is positive and bounded and Δt and the cell size can be planned from the extremes.

use crate::rng::Rng;
use serde::Deserialize;

/// Standard deviations at which the normal and log-normal are cut.
pub const TRUNCATION: f64 = 3.0;

/// A sphere's diameter: one value or a distribution (sampled here).
#[derive(Clone, Debug, Deserialize, PartialEq)]
#[serde(untagged)]
pub enum DiameterSpec {
    Fixed(f64),
    /// `{ min, max }`: uniform in diameter.
    Uniform(DiameterRange),
    /// `{ normal = { mean, std } }`, truncated at mean ± 3 std.
    Normal(NormalWrapper),
    /// `{ log_normal = { median, sigma } }`: ln d normal around ln median with `sigma`, truncated at ±3 sigma.
    LogNormal(LogNormalWrapper),
    /// `{ sieve = [[d_lo, d_hi, mass_fraction], …] }`: a sieve analysis; uniform in d within a class.
    Sieve(SieveWrapper),
}

#[derive(Clone, Copy, Debug, Deserialize, PartialEq)]
#[serde(deny_unknown_fields)]
pub struct NormalWrapper {
    pub normal: NormalSize,
}

#[derive(Clone, Copy, Debug, Deserialize, PartialEq)]
#[serde(deny_unknown_fields)]
pub struct NormalSize {
    pub mean: f64,
    pub std: f64,
}

#[derive(Clone, Copy, Debug, Deserialize, PartialEq)]
#[serde(deny_unknown_fields)]
pub struct LogNormalWrapper {
    pub log_normal: LogNormalSize,
}

#[derive(Clone, Copy, Debug, Deserialize, PartialEq)]
#[serde(deny_unknown_fields)]
pub struct LogNormalSize {
    pub median: f64,
    pub sigma: f64,
}

#[derive(Clone, Debug, Deserialize, PartialEq)]
#[serde(deny_unknown_fields)]
pub struct SieveWrapper {
    pub sieve: Vec<[f64; 3]>,
}

#[derive(Clone, Copy, Debug, Deserialize, PartialEq)]
#[serde(deny_unknown_fields)]
pub struct DiameterRange {
    pub min: f64,
    pub max: f64,
}

impl DiameterSpec {
    /// One diameter from `rng` (one or more draws; the same sequence on every machine).
    pub fn sample(&self, rng: &mut Rng) -> f64 {
        match self {
            DiameterSpec::Fixed(d) => *d,
            DiameterSpec::Uniform(r) => rng.range(r.min, r.max),
            DiameterSpec::Normal(n) => n.normal.mean + n.normal.std * truncated_normal(rng),
            DiameterSpec::LogNormal(l) => l.log_normal.median * (l.log_normal.sigma * truncated_normal(rng)).exp(),
            DiameterSpec::Sieve(s) => {
                let weights = sieve_number_weights(&s.sieve);
                let total: f64 = weights.iter().sum();
                let mut u = rng.uniform() * total;
                let mut class = weights.len() - 1;
                for (k, w) in weights.iter().enumerate() {
                    if u < *w {
                        class = k;
                        break;
                    }
                    u -= w;
                }
                let [lo, hi, _] = s.sieve[class];
                rng.range(lo, hi)
            }
        }
    }

    /// ⟨d³⟩ over the diameters the spec gives. Not inlined: inlined into a match on a group's
    /// shape, rustc 1.95 hoisted this match's load above the shape check (rust-lang/rust#159035).
    #[inline(never)]
    pub fn mean_cube(&self) -> f64 {
        match self {
            DiameterSpec::Fixed(d) => d * d * d,
            DiameterSpec::Uniform(r) => class_mean_cube(r.min, r.max),
            DiameterSpec::Normal(n) => truncated_mean(|z| (n.normal.mean + n.normal.std * z).powi(3)),
            DiameterSpec::LogNormal(l) => truncated_mean(|z| (l.log_normal.median * (l.log_normal.sigma * z).exp()).powi(3)),
            DiameterSpec::Sieve(s) => {
                let weights = sieve_number_weights(&s.sieve);
                let total: f64 = weights.iter().sum();
                s.sieve.iter().zip(&weights).map(|(c, w)| w * class_mean_cube(c[0], c[1])).sum::<f64>() / total
            }
        }
    }

    /// The smallest diameter the spec gives.
    #[inline(never)]
    pub fn min(&self) -> f64 {
        match self {
            DiameterSpec::Fixed(d) => *d,
            DiameterSpec::Uniform(r) => r.min,
            DiameterSpec::Normal(n) => n.normal.mean - TRUNCATION * n.normal.std,
            DiameterSpec::LogNormal(l) => l.log_normal.median * (-TRUNCATION * l.log_normal.sigma).exp(),
            DiameterSpec::Sieve(s) => s.sieve.iter().filter(|c| c[2] > 0.0).map(|c| c[0]).fold(f64::INFINITY, f64::min),
        }
    }

    /// The largest diameter the spec gives.
    #[inline(never)]
    pub fn max(&self) -> f64 {
        match self {
            DiameterSpec::Fixed(d) => *d,
            DiameterSpec::Uniform(r) => r.max,
            DiameterSpec::Normal(n) => n.normal.mean + TRUNCATION * n.normal.std,
            DiameterSpec::LogNormal(l) => l.log_normal.median * (TRUNCATION * l.log_normal.sigma).exp(),
            DiameterSpec::Sieve(s) => s.sieve.iter().filter(|c| c[2] > 0.0).map(|c| c[1]).fold(0.0, f64::max),
        }
    }
}

/// A standard normal draw cut at ±[`TRUNCATION`] (redrawn outside, 0.27 % of draws).
fn truncated_normal(rng: &mut Rng) -> f64 {
    loop {
        let z = rng.normal();
        if z.abs() <= TRUNCATION {
            return z;
        }
    }
}

/// ⟨f(z)⟩ over the standard normal cut at ±[`TRUNCATION`] (Simpson's rule, 600 intervals:
/// relative error far below 1e-9 for the smooth integrands here).
fn truncated_mean(f: impl Fn(f64) -> f64) -> f64 {
    const N: usize = 600;
    let h = 2.0 * TRUNCATION / N as f64;
    let (mut num, mut den) = (0.0, 0.0);
    for k in 0..=N {
        let z = -TRUNCATION + k as f64 * h;
        let w = if k == 0 || k == N {
            1.0
        } else if k % 2 == 1 {
            4.0
        } else {
            2.0
        };
        let p = (-0.5 * z * z).exp();
        num += w * p * f(z);
        den += w * p;
    }
    num / den
}

/// ⟨d³⟩ of d uniform on [lo, hi].
fn class_mean_cube(lo: f64, hi: f64) -> f64 {
    if hi > lo { (hi.powi(4) - lo.powi(4)) / (4.0 * (hi - lo)) } else { lo.powi(3) }
}

/// Each sieve class's share by number: its mass fraction over its mean particle volume.
fn sieve_number_weights(classes: &[[f64; 3]]) -> Vec<f64> {
    classes.iter().map(|c| c[2] / class_mean_cube(c[0], c[1])).collect()
}
