//! Drum charge profiles from the device's reduction (reduce.wgsl): per drum, the charge mass
//! and Σ m·radial summed like the observables, and a histogram of the shell layer's angles in
//! `DRUM_BINS` bins of 0.1°, from which the toe and shoulder percentiles are read (to within
//! half a bin of the exact angles' percentiles that `tumble_state::drum_profiles` takes).

use crate::reduce::Partial;
use glam::DVec3;
use tumble_plan::Plan;
use tumble_shaders::{DRUM_BINS, DRUM_ROW_WORDS};
use tumble_state::{DrumFrame, DrumProfile, no_drum_profile, quantile_rank};

/// The drums' rows of the reduce table, relative to the device's origin: (axis point,
/// radius), (axis, length), (down, 0), (along, 0) (zeros without gravity across the axis).
pub(crate) fn drum_rows(plan: &Plan) -> Vec<[f32; 4]> {
    let origin = crate::upload::centre(plan);
    let v = |v: DVec3, w: f64| [v.x as f32, v.y as f32, v.z as f32, w as f32];
    let rows: Vec<[f32; 4]> = plan
        .model
        .drums
        .iter()
        .flat_map(|d| {
            let f = DrumFrame::of(d, plan.model.gravity);
            let (down, along) = f.map_or((DVec3::ZERO, DVec3::ZERO), |f| (f.down, f.along));
            [v(d.point - origin, d.radius), v(d.axis, d.length), v(down, 0.0), v(along, 0.0)]
        })
        .collect();
    debug_assert_eq!(rows.len(), DRUM_ROW_WORDS as usize * plan.model.drums.len());
    rows
}

/// The angle at the centre of histogram bin `b`, degrees.
fn bin_centre(b: usize) -> f64 {
    -180.0 + (b as f64 + 0.5) * 360.0 / DRUM_BINS as f64
}

/// The `q`-quantile of the angles counted in `bins` (NaN when there are none), taken at the
/// same rank as the exact profile takes it.
pub(crate) fn histogram_quantile(bins: &[u32], q: f64) -> f64 {
    let n: u64 = bins.iter().map(|&c| c as u64).sum();
    if n == 0 {
        return f64::NAN;
    }
    let rank = quantile_rank(q, n as usize) as u64;
    let mut below = 0u64;
    for (b, &c) in bins.iter().enumerate() {
        below += c as u64;
        if below > rank {
            return bin_centre(b);
        }
    }
    unreachable!("the rank is below the count")
}

/// Each drum's profile from its lane (charge mass, Σ m·radial) and its histogram.
pub(crate) fn profiles(plan: &Plan, t: f64, lanes: &[Partial], bins: &[u32]) -> Vec<DrumProfile> {
    plan.model
        .drums
        .iter()
        .enumerate()
        .map(|(k, d)| {
            let Some(frame) = DrumFrame::of(d, plan.model.gravity) else { return no_drum_profile() };
            let lane = &lanes[k];
            let counts = &bins[k * DRUM_BINS as usize..(k + 1) * DRUM_BINS as usize];
            let moment = DVec3::new(lane.sum(1), lane.sum(2), lane.sum(3));
            frame.profile(d, t, lane.sum(0), moment, histogram_quantile(counts, 0.05), histogram_quantile(counts, 0.95))
        })
        .collect()
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn histogram_quantiles_take_the_exact_profiles_rank() {
        // Angles −90.03, 10.02 (twice), 170.0: sorted ranks 0..3; q = 0.05 → rank 0, 0.95 → rank 3.
        let mut bins = vec![0u32; DRUM_BINS as usize];
        let bin = |a: f64| ((a + 180.0) / 360.0 * DRUM_BINS as f64) as usize;
        for a in [10.02, -90.03, 170.0, 10.02] {
            bins[bin(a)] += 1;
        }
        assert!((histogram_quantile(&bins, 0.05) - -90.05).abs() < 1e-9);
        assert!((histogram_quantile(&bins, 0.5) - 10.05).abs() < 1e-9);
        assert!((histogram_quantile(&bins, 0.95) - 170.05).abs() < 1e-9);
        assert!(histogram_quantile(&[0; 4], 0.5).is_nan());
    }
}
