//! LU factorization without pivoting of a band matrix, for the wire's
//! non-symmetric Newton matrices (friction, Kelvin–Voigt damping).
//!
//! Those matrices are (1 − α_m) M + c_k K + c_d D: the mass matrix is
//! symmetric positive definite and at the time steps contact needs it
//! dominates, so the symmetric part stays positive definite and elimination
//! in the natural order is stable. A pivot that is not finite or falls below
//! 1e-10 of the largest diagonal entry is refused and the caller falls back
//! to faer's pivoting sparse LU, whose general sparse factorization and
//! solves cost the contact scenes most of their time.
//!
//! Storage: row i keeps the columns i − p … i + p at
//! `a[i (2p + 1) + (j − i + p)]`; L (unit diagonal, not stored) and U
//! overwrite A. Row operations are contiguous multiply-adds.

use crate::linalg::band_cholesky::{envelope, pattern_entries};
use crate::math::simd::{Arith, path};

/// L U of a band matrix with the map from the sparse pattern's value slots
/// to the band, computed once per pattern.
#[derive(Clone, Debug)]
pub struct BandLu {
    n: usize,
    /// Half-bandwidth p (both sides): A_ij = 0 for |i − j| > p.
    p: usize,
    /// (pattern value index, band index) for every entry.
    slots: Vec<(usize, usize)>,
    /// The envelope (`band_cholesky::envelope`): rows of L below the
    /// diagonal in column j, and columns of U right of it in row j (the
    /// pattern is symmetric).
    below: Vec<usize>,
    /// First column of row i inside the envelope.
    first: Vec<usize>,
    a: Vec<f64>,
    /// 1 / U_ii.
    inv_pivot: Vec<f64>,
    /// The factors again by columns, for the solves (`p` slots per column,
    /// zero where the envelope ends): column j of L below the diagonal
    /// (slot i − j − 1 for rows j + 1 … j + p) and of U above it (slot
    /// i + p − j for rows j − p … j − 1).
    lower_columns: Vec<f64>,
    upper_columns: Vec<f64>,
}

/// Elimination met a pivot that is zero, tiny or not finite (the caller
/// falls back to a pivoting LU).
#[derive(Clone, Copy, Debug)]
pub struct SmallPivot;

impl BandLu {
    /// The band structure of an n × n pattern with both triangles stored
    /// (compressed sparse columns) and half-bandwidth `p`.
    pub fn new(n: usize, p: usize, col_ptr: &[usize], row_idx: &[usize]) -> Self {
        let w = 2 * p + 1;
        let slots = pattern_entries(col_ptr, row_idx)
            .map(|(k, r, c)| {
                assert!(r.abs_diff(c) <= p, "entry ({r}, {c}) outside the band");
                (k, r * w + (c + p - r))
            })
            .collect();
        let below = envelope(n, pattern_entries(col_ptr, row_idx).map(|(_, r, c)| (r, c)));
        let mut first = vec![0; n];
        let mut j = 0;
        for (i, f) in first.iter_mut().enumerate() {
            while j + below[j] < i {
                j += 1;
            }
            *f = j;
        }
        BandLu {
            n,
            p,
            below,
            first,
            slots,
            a: vec![0.0; n * w],
            inv_pivot: vec![0.0; n],
            lower_columns: vec![0.0; n * p],
            upper_columns: vec![0.0; n * p],
        }
    }

    /// Factor the matrix whose pattern values are `values`.
    pub fn factorize(&mut self, values: &[f64]) -> Result<(), SmallPivot> {
        factorize(path(), self, values)
    }

    /// Solve A x = b in place with the last factorization.
    pub fn solve_in_place(&self, b: &mut [f64]) {
        solve(path(), self, b)
    }
}

crate::simd_dispatch! {
    fn factorize(lu: &mut BandLu, values: &[f64]) -> Result<(), SmallPivot> = factorize_with;
}

crate::simd_dispatch! {
    fn solve(lu: &BandLu, b: &mut [f64]) = solve_with;
}
/// `BandLu::factorize` with the multiply-adds of `F`.
#[inline(always)]
fn factorize_with<F: Arith>(lu: &mut BandLu, values: &[f64]) -> Result<(), SmallPivot> {
    let (n, p, w) = (lu.n, lu.p, 2 * lu.p + 1);
    lu.a.fill(0.0);
    for &(v, b) in &lu.slots {
        lu.a[b] = values[v];
    }
    let a = &mut lu.a;
    let scale = (0..n).map(|i| a[i * w + p].abs()).fold(0.0, f64::max);
    for j in 0..n {
        let pivot = a[j * w + p];
        if !pivot.is_finite() || pivot.abs() <= 1e-10 * scale {
            return Err(SmallPivot);
        }
        let inv = 1.0 / pivot;
        lu.inv_pivot[j] = inv;
        let len = lu.below[j];
        let (upper, lower) = a.split_at_mut((j + 1) * w);
        // Row j right of the diagonal: columns j + 1 … j + len.
        let row_j = &upper[j * w + p + 1..j * w + p + 1 + len];
        for i in j + 1..=j + len {
            let row_i = &mut lower[(i - j - 1) * w..(i - j) * w];
            // A_ij sits at j − i + p; the columns j + 1 … follow it.
            let at = j + p - i;
            let l = row_i[at] * inv;
            row_i[at] = l;
            for (x, u) in row_i[at + 1..at + 1 + len].iter_mut().zip(row_j) {
                *x = F::mul_add(-l, *u, *x);
            }
        }
    }
    // The columns for the solves.
    for j in 0..n {
        for k in 1..=lu.below[j] {
            lu.lower_columns[j * p + k - 1] = a[(j + k) * w + p - k];
        }
        let slot = first_slot(lu.first[j], p, j);
        for (k, i) in (lu.first[j]..j).enumerate() {
            lu.upper_columns[j * p + slot + k] = a[i * w + p + (j - i)];
        }
    }
    Ok(())
}

/// Slot of row `first` in U's column j (see `BandLu::upper_columns`).
#[inline(always)]
fn first_slot(first: usize, p: usize, j: usize) -> usize {
    first + p - j
}

/// `BandLu::solve_in_place` with the multiply-adds of `F`, by columns: each
/// unknown, once known, leaves its column's multiple in the rows below (L)
/// or above (U), independent multiply-adds, so that from one unknown to the
/// next only one multiply-add is on the critical path (the row-oriented
/// form waited on a dot product every other row: 17.8 → 15 % of the
/// 64-element impact run, perf). Four columns at a time, to load and
/// store each row once per four, measured slower (16.1 against 12.8 µs
/// per solve at 780 unknowns, p = 23, same process, interleaved).
#[inline(always)]
fn solve_with<F: Arith>(lu: &BandLu, b: &mut [f64]) {
    let (n, p) = (lu.n, lu.p);
    for j in 0..n {
        let yj = b[j];
        let column = &lu.lower_columns[j * p..j * p + p.min(n - 1 - j)];
        for (bi, l) in b[j + 1..].iter_mut().zip(column) {
            *bi = F::mul_add(-l, yj, *bi);
        }
    }
    for j in (0..n).rev() {
        let xj = b[j] * lu.inv_pivot[j];
        b[j] = xj;
        let first = j.saturating_sub(p);
        let column = &lu.upper_columns[j * p + first + p - j..j * p + p];
        for (bi, u) in b[first..j].iter_mut().zip(column) {
            *bi = F::mul_add(-u, xj, *bi);
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::linalg::band_cholesky::tests::{
        TestMatrix, assert_paths_agree, block_tridiagonal, uniform,
    };

    #[test]
    fn solves_nonsymmetric_band_systems_to_round_off() {
        for (n, p) in [(1, 0), (6, 1), (40, 7), (60, 23), (10, 23)] {
            let mut rand = uniform(11 + n as u64);
            let mut dense = vec![0.0; n * n];
            for c in 0..n {
                for r in (0..n).filter(|&r| r.abs_diff(c) <= p) {
                    dense[r * n + c] = if r == c { 2.0 * p as f64 + 1.0 } else { rand() };
                }
            }
            let a = TestMatrix::new(n, dense, |r, c| r.abs_diff(c) <= p);
            let mut lu = BandLu::new(n, p.min(n - 1), &a.col_ptr, &a.row_idx);
            lu.factorize(&a.values).expect("non-singular");
            let x: Vec<f64> = (0..n).map(|i| (i as f64 * 0.3).cos()).collect();
            let err = a.solve_error(&x, |b| lu.solve_in_place(b));
            assert!(err < 1e-12, "n {n}, p {p}: error {err:e}");
        }
    }

    /// Every instruction-set path this CPU runs solves to round-off and
    /// agrees with the baseline path to round-off (they round differently:
    /// fused multiply-adds).
    #[test]
    fn every_simd_path_agrees_with_the_baseline() {
        let a = block_tridiagonal(20, 12, false);
        let mut lu = BandLu::new(a.n, a.bandwidth(), &a.col_ptr, &a.row_idx);
        let x: Vec<f64> = (0..a.n).map(|i| (i as f64 * 0.3).cos()).collect();
        assert_paths_agree(&a, &x, |path, b| {
            factorize(path, &mut lu, &a.values).expect("non-singular");
            solve(path, &lu, b);
        });
    }

    #[test]
    fn solves_a_nonsymmetric_block_tridiagonal_system() {
        let a = block_tridiagonal(6, 4, false);
        let mut lu = BandLu::new(a.n, 7, &a.col_ptr, &a.row_idx);
        lu.factorize(&a.values).expect("non-singular");
        let x: Vec<f64> = (0..a.n).map(|i| (i as f64).sqrt()).collect();
        let err = a.solve_error(&x, |b| lu.solve_in_place(b));
        assert!(err < 1e-12, "error {err:e}");
    }

    #[test]
    fn refuses_a_zero_pivot() {
        // [[0, 1], [1, 0]] needs pivoting.
        let col_ptr = [0, 2, 4];
        let row_idx = [0, 1, 0, 1];
        let mut lu = BandLu::new(2, 1, &col_ptr, &row_idx);
        assert!(lu.factorize(&[0.0, 1.0, 1.0, 0.0]).is_err());
    }
}
