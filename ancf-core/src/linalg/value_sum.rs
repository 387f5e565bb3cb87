//! A matrix on a pattern given as a weighted sum of value arrays over that
//! pattern — the dynamic Newton matrix (1 − α_m) M + c_k K_q + c_d K_v —
//! read slot by slot, so that a factorization that loads its own blocks
//! ([`crate::linalg::block_tridiagonal::BlockTridiagonalLu`],
//! [`crate::linalg::separated_lu::SeparatedLu`]) never needs
//! the sum written out: on a 1000-element wire that array is 3.5 MB
//! written, checked and read back at every refactorization.

use crate::math::simd::Arith;
use std::ops::Range;

/// A = w₀ P₀ + w₁ P₁ (+ w₂ P₂ in `third_slots`, where P₂ may be nonzero;
/// it is zero elsewhere) over one pattern's value slots.
#[derive(Clone, Debug)]
pub struct ValueSum<'a> {
    /// P₀, P₁, P₂: one value per slot each.
    pub parts: [&'a [f64]; 3],
    /// w₀, w₁, w₂.
    pub weights: [f64; 3],
    /// The slots where the third part is added (empty: never).
    pub third_slots: Range<usize>,
}

/// A matrix's values read slot by slot: an array over the pattern, or a
/// [`ValueSum`] never formed.
pub trait SlotValues {
    /// The values of `slots`, in order, written to `out[places[i]]`.
    /// (Whether they are finite is for the caller to check on `out`, with
    /// [`all_finite`]: a test per value took a quarter of the block LU's
    /// loading, perf.)
    fn scatter(&self, slots: Range<usize>, places: &[u16], out: &mut [f64]);

    /// The values of the slots from `start` on, in order, written over
    /// `out`: a run of slots to a run of places, the block LU's column of
    /// a block (of fixed length, so that the loop is unrolled).
    fn copy_run<const N: usize>(&self, start: usize, out: &mut [f64; N]);
}

/// Whether every value is finite: exponent bits tested on all of them
/// (no early exit, so that the loop vectorizes).
#[inline(always)]
pub fn all_finite(values: &[f64]) -> bool {
    const EXPONENT: u64 = 0x7ff0_0000_0000_0000;
    let special = values
        .iter()
        .fold(false, |any, x| any | (x.to_bits() & EXPONENT == EXPONENT));
    !special
}

/// `values` to `out` at `places`.
#[inline(always)]
fn scatter(values: impl Iterator<Item = f64>, places: &[u16], out: &mut [f64]) {
    for (x, &at) in values.zip(places) {
        out[at as usize] = x;
    }
}

impl SlotValues for [f64] {
    #[inline(always)]
    fn scatter(&self, slots: Range<usize>, places: &[u16], out: &mut [f64]) {
        scatter(self[slots].iter().copied(), places, out)
    }

    #[inline(always)]
    fn copy_run<const N: usize>(&self, start: usize, out: &mut [f64; N]) {
        out.copy_from_slice(&self[start..start + N]);
    }
}

impl SlotValues for ValueSum<'_> {
    /// The same operations, in the same order, as [`ValueSum::write`]:
    /// the same bits.
    #[inline(always)]
    fn scatter(&self, slots: Range<usize>, places: &[u16], out: &mut [f64]) {
        let [w0, w1, w2] = self.weights;
        let [p0, p1, p2] = self.parts;
        // The slots before, in and after the third part's.
        let third = &self.third_slots;
        let lo = third.start.clamp(slots.start, slots.end);
        let hi = third.end.clamp(lo, slots.end);
        let two = |r: Range<usize>| {
            let (x, y) = (&p0[r.clone()], &p1[r]);
            x.iter().zip(y).map(move |(x, y)| w0 * x + w1 * y)
        };
        let (x, y, z) = (&p0[lo..hi], &p1[lo..hi], &p2[lo..hi]);
        let three = x.iter().zip(y).zip(z);
        let three = three.map(|((x, y), z)| (w0 * x + w1 * y) + w2 * z);
        let (before, rest) = places.split_at(lo - slots.start);
        let (within, after) = rest.split_at(hi - lo);
        scatter(two(slots.start..lo), before, out);
        scatter(three, within, out);
        scatter(two(hi..slots.end), after, out);
    }

    /// The same operations as [`SlotValues::scatter`], written in order.
    #[inline(always)]
    fn copy_run<const N: usize>(&self, start: usize, out: &mut [f64; N]) {
        let [w0, w1, w2] = self.weights;
        let part = |p: &[f64]| -> [f64; N] { p[start..start + N].try_into().expect("N slots") };
        let (x, y) = (part(self.parts[0]), part(self.parts[1]));
        let third = &self.third_slots;
        if start + N <= third.start || third.end <= start {
            for i in 0..N {
                out[i] = w0 * x[i] + w1 * y[i];
            }
        } else if third.start <= start && start + N <= third.end {
            let z = part(self.parts[2]);
            for i in 0..N {
                out[i] = (w0 * x[i] + w1 * y[i]) + w2 * z[i];
            }
        } else {
            for i in 0..N {
                let two = w0 * x[i] + w1 * y[i];
                out[i] = if third.contains(&(start + i)) {
                    two + w2 * self.parts[2][start + i]
                } else {
                    two
                };
            }
        }
    }
}

impl ValueSum<'_> {
    /// The sum written over `out` (one value per slot), for the
    /// factorizations that take an array.
    pub fn write(&self, out: &mut [f64]) {
        write(crate::math::simd::path(), self, out)
    }
}

crate::simd_dispatch! {
    fn write(sum: &ValueSum, out: &mut [f64]) = write_with;
}

/// Plain multiplications and additions on every path (no fused ones, so
/// that the bits equal [`SlotValues::scatter`]'s and do not depend on the path);
/// the AVX paths gain the wider registers. Zipped, without indices, so that
/// the loops vectorize.
// `F` unused: `simd_dispatch!` instantiates the loop per path.
#[allow(clippy::extra_unused_type_parameters)]
#[inline(always)]
fn write_with<F: Arith>(sum: &ValueSum, out: &mut [f64]) {
    let [w0, w1, w2] = sum.weights;
    let [p0, p1, p2] = sum.parts;
    let r = sum.third_slots.clone();
    let two = |out: &mut [f64], p0: &[f64], p1: &[f64]| {
        for ((a, x), y) in out.iter_mut().zip(p0).zip(p1) {
            *a = w0 * x + w1 * y;
        }
    };
    two(&mut out[..r.start], &p0[..r.start], &p1[..r.start]);
    let parts = out[r.clone()]
        .iter_mut()
        .zip(&p0[r.clone()])
        .zip(&p1[r.clone()]);
    for (((a, x), y), z) in parts.zip(&p2[r.clone()]) {
        *a = (w0 * x + w1 * y) + w2 * z;
    }
    two(&mut out[r.end..], &p0[r.end..], &p1[r.end..]);
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Infinities and NaNs anywhere are found; the largest finite values,
    /// subnormals and zeros of either sign are finite.
    #[test]
    fn all_finite_finds_every_special_value() {
        let mut v: Vec<f64> = (0..37).map(|i| (i as f64 - 18.0) * 1e300).collect();
        v.extend([f64::MAX, f64::MIN, f64::MIN_POSITIVE / 4.0, 0.0, -0.0]);
        assert!(all_finite(&v));
        for bad in [f64::INFINITY, f64::NEG_INFINITY, f64::NAN, -f64::NAN] {
            for at in [0, 17, v.len() - 1] {
                let mut w = v.clone();
                w[at] = bad;
                assert!(!all_finite(&w), "{bad} at {at}");
            }
        }
    }

    /// Slot by slot and written out: the same bits, with and without the
    /// third part's range, at its ends and beyond the vector width.
    #[test]
    fn read_and_written_values_agree_bit_for_bit() {
        let n = 37;
        let part = |s: f64| {
            (0..n)
                .map(|i| (i as f64 * s).sin() * 1e3)
                .collect::<Vec<_>>()
        };
        let (p0, p1, p2) = (part(0.7), part(1.3), part(2.9));
        for third_slots in [0..0, 0..n, 5..6, 3..29, 36..37] {
            let sum = ValueSum {
                parts: [&p0, &p1, &p2],
                weights: [0.55, 1.7e-8, 3.1e-4],
                third_slots: third_slots.clone(),
            };
            let mut out = vec![f64::NAN; n];
            sum.write(&mut out);
            // Read in two pieces, scattered in reverse.
            let mut read = vec![f64::NAN; n];
            let places: Vec<u16> = (0..n as u16).rev().collect();
            let (a, b) = places.split_at(11);
            sum.scatter(0..11, a, &mut read);
            sum.scatter(11..n, b, &mut read);
            read.reverse();
            for (slot, v) in out.iter().enumerate() {
                assert_eq!(v.to_bits(), read[slot].to_bits(), "{third_slots:?} {slot}");
                let expected = 0.55 * p0[slot]
                    + 1.7e-8 * p1[slot]
                    + if third_slots.contains(&slot) {
                        3.1e-4 * p2[slot]
                    } else {
                        0.0
                    };
                assert!((v - expected).abs() <= 1e-12 * expected.abs().max(1.0));
            }
        }
    }
}
