//! Quantiles of a sweep's design numbers with bootstrap confidence
//! intervals: how high a load goes in 90 % or 95 % of the perturbed
//! scenes, and how well the variants run pin that down.
//!
//! Quantiles interpolate linearly between order statistics (Hyndman & Fan
//! type 7, NumPy's and R's default). The interval is the percentile
//! bootstrap (Efron & Tibshirani, "An Introduction to the Bootstrap",
//! 1993, ch. 13): the quantile recomputed on [`RESAMPLES`] samples drawn
//! with replacement, its 2.5 % and 97.5 % quantiles. The generator is
//! seeded, so a report is the same every time it is written. With few
//! variants an upper quantile's interval reaches the largest value: the
//! ensemble is too small to say more.

use rand_core::{Rng, SeedableRng};
use rand_xorshift::XorShiftRng;

/// Bootstrap resamples per interval.
pub const RESAMPLES: usize = 2000;

/// The confidence level of the intervals.
pub const CONFIDENCE: f64 = 0.95;

/// The `p` quantile (0 ≤ p ≤ 1) of `sorted` (ascending, not empty).
pub fn quantile(sorted: &[f64], p: f64) -> f64 {
    let h = (sorted.len() - 1) as f64 * p;
    let (lo, hi) = (h.floor() as usize, h.ceil() as usize);
    sorted[lo] + (h - lo as f64) * (sorted[hi] - sorted[lo])
}

/// The `p` quantile of `values` (not empty) and its [`CONFIDENCE`]
/// percentile-bootstrap interval: (estimate, low, high).
pub fn with_interval(values: &[f64], p: f64) -> (f64, f64, f64) {
    let mut sorted = values.to_vec();
    sorted.sort_by(f64::total_cmp);
    let estimate = quantile(&sorted, p);
    let mut rng = XorShiftRng::seed_from_u64(0x5eed_0000 + values.len() as u64);
    let n = values.len();
    let mut sample = vec![0.0; n];
    let mut estimates: Vec<f64> = (0..RESAMPLES)
        .map(|_| {
            for x in sample.iter_mut() {
                // Uniform index: the top bits of a 64-bit draw times n.
                let i = ((rng.next_u64() >> 11) as f64 * (n as f64) / (1u64 << 53) as f64) as usize;
                *x = sorted[i.min(n - 1)];
            }
            sample.sort_by(f64::total_cmp);
            quantile(&sample, p)
        })
        .collect();
    estimates.sort_by(f64::total_cmp);
    let tail = 0.5 * (1.0 - CONFIDENCE);
    (
        estimate,
        quantile(&estimates, tail),
        quantile(&estimates, 1.0 - tail),
    )
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn quantiles_interpolate_between_order_statistics() {
        let v = [1.0, 2.0, 3.0, 4.0, 5.0];
        assert_eq!(quantile(&v, 0.5), 3.0);
        assert_eq!(quantile(&v, 0.0), 1.0);
        assert_eq!(quantile(&v, 1.0), 5.0);
        assert!((quantile(&v, 0.9) - 4.6).abs() < 1e-12);
        assert_eq!(quantile(&[7.0], 0.95), 7.0);
    }

    /// A deterministic sample with the quantiles of a uniform variable on [0, 1).
    fn uniform(n: usize) -> Vec<f64> {
        let mut rng = XorShiftRng::seed_from_u64(n as u64);
        (0..n)
            .map(|_| (rng.next_u64() >> 11) as f64 / (1u64 << 53) as f64)
            .collect()
    }

    #[test]
    fn the_interval_holds_the_estimate_and_narrows_as_one_over_root_n() {
        let width = |n: usize| {
            let (q, lo, hi) = with_interval(&uniform(n), 0.9);
            assert!(lo <= q && q <= hi, "{lo} ≤ {q} ≤ {hi}");
            // The true 90 % quantile of the uniform law is 0.9.
            assert!(
                lo <= 0.9 + 0.02 && hi >= 0.9 - 0.02,
                "[{lo}, {hi}] misses 0.9"
            );
            hi - lo
        };
        let (w1, w4) = (width(400), width(1600));
        // Four times the variants: half the width (√4), within sampling scatter.
        assert!(
            (w1 / w4 - 2.0).abs() < 0.5,
            "widths {w1:.4} and {w4:.4} (ratio {:.2})",
            w1 / w4
        );
    }

    #[test]
    fn a_small_ensembles_upper_interval_reaches_its_largest_value_and_is_reproducible() {
        let v = [3.0, 1.0, 4.0, 1.5, 5.0];
        let (q, lo, hi) = with_interval(&v, 0.95);
        assert!((q - 4.8).abs() < 1e-12);
        assert_eq!(hi, 5.0);
        assert!(lo < q);
        assert_eq!(
            with_interval(&v, 0.95),
            (q, lo, hi),
            "seeded: the same every time"
        );
    }
}
