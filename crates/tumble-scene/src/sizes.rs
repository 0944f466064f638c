//! Checking sphere diameters as a scene gives them (the distributions themselves, their draws
//! and moments are tumble-plan's `DiameterSpec`).

use crate::SceneError;
use crate::schema::DiameterSpec;
use tumble_plan::TRUNCATION;

/// The scene's check of a diameter spec.
pub(crate) trait CheckDiameter {
    /// Refuses a spec that gives no positive, finite diameters; `field` names it.
    fn check(&self, field: &str) -> Result<(), SceneError>;
}

impl CheckDiameter for DiameterSpec {
    fn check(&self, field: &str) -> Result<(), SceneError> {
        let bad = |what: String| Err(SceneError::field(field, what));
        match self {
            DiameterSpec::Fixed(d) if !(d.is_finite() && *d > 0.0) => bad(format!("must be a positive number, got {d}")),
            DiameterSpec::Uniform(r) if !(r.min.is_finite() && r.min > 0.0) => bad(format!("min must be a positive number, got {}", r.min)),
            DiameterSpec::Uniform(r) if !(r.max >= r.min && r.max.is_finite()) => bad(format!("max must be at least min = {}, got {}", r.min, r.max)),
            DiameterSpec::Normal(n) if !(n.normal.std.is_finite() && n.normal.std >= 0.0) => {
                bad(format!("normal.std must be zero or positive, got {}", n.normal.std))
            }
            DiameterSpec::Normal(n) if !(n.normal.mean - TRUNCATION * n.normal.std > 0.0 && n.normal.mean.is_finite()) => bad(format!(
                "normal: mean − 3 std must be positive (the distribution is cut at ±3 std), got mean {} and std {}",
                n.normal.mean, n.normal.std
            )),
            DiameterSpec::LogNormal(l) if !(l.log_normal.median.is_finite() && l.log_normal.median > 0.0) => {
                bad(format!("log_normal.median must be a positive number, got {}", l.log_normal.median))
            }
            DiameterSpec::LogNormal(l) if !(l.log_normal.sigma.is_finite() && (0.0..=2.0).contains(&l.log_normal.sigma)) => {
                bad(format!("log_normal.sigma (of ln d) must be from 0 to 2, got {}", l.log_normal.sigma))
            }
            DiameterSpec::Sieve(s) => {
                if s.sieve.is_empty() {
                    return bad("sieve: give at least one class [d_lo, d_hi, mass_fraction]".into());
                }
                for (k, [lo, hi, f]) in s.sieve.iter().copied().enumerate() {
                    if !(lo.is_finite() && lo > 0.0 && hi >= lo && hi.is_finite()) {
                        return bad(format!("sieve[{k}]: need 0 < d_lo <= d_hi, got [{lo}, {hi}]"));
                    }
                    if !(f.is_finite() && f >= 0.0) {
                        return bad(format!("sieve[{k}]: the mass fraction must be zero or positive, got {f}"));
                    }
                }
                let sum: f64 = s.sieve.iter().map(|c| c[2]).sum();
                if (sum - 1.0).abs() > 1e-6 {
                    return bad(format!("sieve: the mass fractions must add up to 1, they add up to {sum}"));
                }
                Ok(())
            }
            _ => Ok(()),
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::rng::Rng;
    use crate::schema::{DiameterRange, LogNormalSize, LogNormalWrapper, NormalSize, NormalWrapper, SieveWrapper};

    fn sample_moments(spec: &DiameterSpec, n: usize) -> (f64, f64, f64, f64) {
        let mut rng = Rng::new(7);
        let d: Vec<f64> = (0..n).map(|_| spec.sample(&mut rng)).collect();
        let mean = d.iter().sum::<f64>() / n as f64;
        let cube = d.iter().map(|x| x.powi(3)).sum::<f64>() / n as f64;
        (mean, cube, d.iter().copied().fold(f64::INFINITY, f64::min), d.iter().copied().fold(0.0, f64::max))
    }

    #[test]
    fn every_distribution_draws_its_mean_cube_within_sampling_error() {
        let specs = [
            DiameterSpec::Uniform(DiameterRange { min: 1.0, max: 3.0 }),
            DiameterSpec::Normal(NormalWrapper { normal: NormalSize { mean: 2.0, std: 0.3 } }),
            DiameterSpec::LogNormal(LogNormalWrapper { log_normal: LogNormalSize { median: 2.0, sigma: 0.25 } }),
            DiameterSpec::Sieve(SieveWrapper { sieve: vec![[1.0, 1.5, 0.2], [1.5, 2.0, 0.5], [2.0, 4.0, 0.3]] }),
        ];
        for spec in specs {
            spec.check("d").unwrap();
            let n = 200_000;
            let (_, cube, lo, hi) = sample_moments(&spec, n);
            // ⟨d³⟩'s standard error is below 0.5 % here; 1.5 % catches a missing weight or a wrong cut.
            assert!((cube / spec.mean_cube() - 1.0).abs() < 0.015, "{spec:?}: sampled {cube}, expected {}", spec.mean_cube());
            assert!(lo >= spec.min() && hi <= spec.max(), "{spec:?}: [{lo}, {hi}] outside [{}, {}]", spec.min(), spec.max());
            // The extremes are nearly reached: a distribution cut too early would not.
            assert!(lo < spec.min() * 1.05 && hi > spec.max() * 0.95, "{spec:?}: [{lo}, {hi}]");
        }
    }

    #[test]
    fn a_normal_draw_has_its_mean_and_std_and_a_log_normal_its_median() {
        let spec = DiameterSpec::Normal(NormalWrapper { normal: NormalSize { mean: 2.0, std: 0.3 } });
        let mut rng = Rng::new(3);
        let d: Vec<f64> = (0..100_000).map(|_| spec.sample(&mut rng)).collect();
        let mean = d.iter().sum::<f64>() / d.len() as f64;
        let std = (d.iter().map(|x| (x - mean).powi(2)).sum::<f64>() / d.len() as f64).sqrt();
        assert!((mean - 2.0).abs() < 0.005, "{mean}");
        // Cut at ±3σ the std is 0.9865 σ.
        assert!((std / 0.3 - 0.9865).abs() < 0.01, "{std}");
        let spec = DiameterSpec::LogNormal(LogNormalWrapper { log_normal: LogNormalSize { median: 2.0, sigma: 0.4 } });
        let mut d: Vec<f64> = (0..100_001).map(|_| spec.sample(&mut rng)).collect();
        d.sort_by(f64::total_cmp);
        assert!((d[50_000] / 2.0 - 1.0).abs() < 0.01, "median {}", d[50_000]);
    }

    #[test]
    fn sieve_mass_fractions_are_met_within_sampling_error() {
        let classes = vec![[1.0, 1.5, 0.2], [1.5, 2.0, 0.5], [2.0, 4.0, 0.3]];
        let spec = DiameterSpec::Sieve(SieveWrapper { sieve: classes.clone() });
        let mut rng = Rng::new(11);
        let mut mass = [0.0; 3];
        for _ in 0..100_000 {
            let d = spec.sample(&mut rng);
            let k = classes.iter().position(|c| d >= c[0] && d < c[1]).unwrap_or(2);
            mass[k] += d.powi(3);
        }
        let total: f64 = mass.iter().sum();
        for (k, c) in classes.iter().enumerate() {
            assert!((mass[k] / total - c[2]).abs() < 0.01, "class {k}: {} against {}", mass[k] / total, c[2]);
        }
    }

    #[test]
    fn bad_distributions_are_refused_with_their_field() {
        let cases = [
            (DiameterSpec::Normal(NormalWrapper { normal: NormalSize { mean: 1.0, std: 0.5 } }), "mean − 3 std must be positive"),
            (DiameterSpec::LogNormal(LogNormalWrapper { log_normal: LogNormalSize { median: -1.0, sigma: 0.1 } }), "median must be"),
            (DiameterSpec::Sieve(SieveWrapper { sieve: vec![[1.0, 2.0, 0.5]] }), "add up to 1"),
            (DiameterSpec::Sieve(SieveWrapper { sieve: vec![[2.0, 1.0, 1.0]] }), "sieve[0]"),
        ];
        for (spec, says) in cases {
            let e = spec.check("sources[0].shape.sphere.diameter").unwrap_err().to_string();
            assert!(e.starts_with("sources[0].shape.sphere.diameter") && e.contains(says), "{e}");
        }
    }
}
