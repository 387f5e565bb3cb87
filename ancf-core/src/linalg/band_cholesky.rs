//! Cholesky factorization of a symmetric positive definite band matrix.
//!
//! The wire's Newton matrix is banded by construction: unknowns are
//! numbered node by node and every element, contact and damping term couples
//! two neighbouring nodes only, so the half-bandwidth is at most 23 (two
//! 12-coordinate nodes). A band factorization costs n p² / 2 multiply-adds
//! with contiguous inner products and no index lookups; faer's general
//! sparse LLᵀ (simplicial or supernodal) on the same matrices is several
//! times slower, which is why this file exists.
//!
//! Storage (LAPACK's lower band layout): column j of L keeps the rows
//! j … j + p contiguously at `l[j (p + 1) + (i − j)]` (rows past n − 1 stay
//! zero). The factorization is right-looking: each column, once scaled,
//! updates the next p columns with contiguous multiply-adds that do not
//! wait on each other (a row-by-row, dot-product form was latency-bound).

use crate::math::simd::{Arith, dot, path};

/// L of A = L Lᵀ for a band matrix, with the map from the sparse pattern's
/// value slots to the band, computed once per pattern.
#[derive(Clone, Debug)]
pub struct BandCholesky {
    n: usize,
    /// Half-bandwidth p: A_ij = 0 for |i − j| > p.
    p: usize,
    /// (pattern value index, band index) for every lower-triangle entry.
    slots: Vec<(usize, usize)>,
    /// Rows of column j below the diagonal that can be non-zero in L (the
    /// envelope, ≤ p): a block-tridiagonal matrix with 12 × 12 blocks fills
    /// 12 … 23 of the 23, so the work is 40 % less than the full band's.
    below: Vec<usize>,
    l: Vec<f64>,
    /// 1 / L_jj: the solves multiply (a division on their sequential
    /// critical path cost 20 % of a 4096-element solve).
    inv_diag: Vec<f64>,
}

/// The factorization met a non-positive pivot: the matrix is not positive
/// definite (or is singular to round-off).
#[derive(Clone, Copy, Debug)]
pub struct NotPositiveDefinite {
    /// The row whose pivot was not positive.
    pub row: usize,
}

impl BandCholesky {
    /// The half-bandwidth of a symmetric pattern given column by column
    /// (compressed sparse columns: `col_ptr`, `row_idx`).
    pub fn bandwidth(col_ptr: &[usize], row_idx: &[usize]) -> usize {
        (0..col_ptr.len().saturating_sub(1))
            .flat_map(|c| {
                row_idx[col_ptr[c]..col_ptr[c + 1]]
                    .iter()
                    .map(move |&r| r.abs_diff(c))
            })
            .max()
            .unwrap_or(0)
    }

    /// The band structure of a symmetric n × n pattern (compressed sparse
    /// columns, both triangles or the lower one) of half-bandwidth `p`
    /// ([`BandCholesky::bandwidth`]).
    pub fn new(n: usize, p: usize, col_ptr: &[usize], row_idx: &[usize]) -> Self {
        Self::from_entries(n, p, pattern_entries(col_ptr, row_idx))
    }

    /// The band structure of an n × n symmetric matrix whose entries are
    /// (pattern value index, row, column), both triangles or the lower one
    /// given (a part of a larger pattern in its own numbering, for
    /// [`crate::linalg::band_split`]).
    pub(crate) fn from_entries(
        n: usize,
        p: usize,
        entries: impl Iterator<Item = (usize, usize, usize)>,
    ) -> Self {
        let w = p + 1;
        let entries: Vec<(usize, usize, usize)> = entries.collect();
        let slots = entries
            .iter()
            .filter(|&&(_, r, c)| r >= c)
            .map(|&(k, r, c)| {
                debug_assert!(r - c <= p, "entry ({r}, {c}) outside the band {p}");
                (k, c * w + (r - c))
            })
            .collect();
        BandCholesky {
            n,
            p,
            below: envelope(n, entries.iter().map(|&(_, r, c)| (r, c))),
            slots,
            l: vec![0.0; n * w],
            inv_diag: vec![0.0; n],
        }
    }

    /// Half-bandwidth p.
    pub fn half_bandwidth(&self) -> usize {
        self.p
    }

    /// Factor the matrix whose pattern values are `values` (only the lower
    /// triangle is read).
    pub fn factorize(&mut self, values: &[f64]) -> Result<(), NotPositiveDefinite> {
        self.factorize_columns(values, self.n)
    }

    /// Load `values` and eliminate the first `m` columns only: the trailing
    /// (n − m) × (n − m) block is left holding its Schur complement (read it
    /// with [`BandCholesky::trailing`]).
    pub(crate) fn factorize_columns(
        &mut self,
        values: &[f64],
        m: usize,
    ) -> Result<(), NotPositiveDefinite> {
        factorize_columns(path(), self, values, m)
    }

    /// Entry (i, j), i ≥ j ≥ m, of the trailing block after
    /// [`BandCholesky::factorize_columns`] with `m` columns.
    pub(crate) fn trailing(&self, i: usize, j: usize) -> f64 {
        if i - j > self.p {
            0.0
        } else {
            self.l[j * (self.p + 1) + (i - j)]
        }
    }

    /// Solve A x = b in place with the last factorization.
    pub fn solve_in_place(&self, b: &mut [f64]) {
        self.forward(b, self.n);
        self.backward(b, self.n);
    }

    /// L y = b over the first `m` columns: y_0 … y_{m−1}, removed from the
    /// rows below (rows m … n − 1 keep b minus those contributions).
    pub(crate) fn forward(&self, b: &mut [f64], m: usize) {
        forward(path(), self, b, m)
    }

    /// Lᵀ x = y for rows m − 1 … 0, with x_m … x_{n−1} already in `b`.
    pub(crate) fn backward(&self, b: &mut [f64], m: usize) {
        backward(path(), self, b, m)
    }
}

crate::simd_dispatch! {
    fn factorize_columns(c: &mut BandCholesky, values: &[f64], m: usize) -> Result<(), NotPositiveDefinite> = factorize_columns_with;
}

crate::simd_dispatch! {
    fn forward(c: &BandCholesky, b: &mut [f64], m: usize) = forward_with;
}

crate::simd_dispatch! {
    fn backward(c: &BandCholesky, b: &mut [f64], m: usize) = backward_with;
}

/// `BandCholesky::factorize_columns` with the multiply-adds of `F`.
#[inline(always)]
fn factorize_columns_with<F: Arith>(
    c: &mut BandCholesky,
    values: &[f64],
    m: usize,
) -> Result<(), NotPositiveDefinite> {
    let w = c.p + 1;
    c.l.fill(0.0);
    for &(v, b) in &c.slots {
        c.l[b] = values[v];
    }
    let l = &mut c.l;
    for j in 0..m {
        let d = l[j * w];
        if d <= 0.0 || !d.is_finite() {
            return Err(NotPositiveDefinite { row: j });
        }
        let d = d.sqrt();
        l[j * w] = d;
        let inv = 1.0 / d;
        c.inv_diag[j] = inv;
        let (done, rest) = l.split_at_mut((j + 1) * w);
        let len = c.below[j];
        let col = &mut done[j * w + 1..j * w + 1 + len];
        col.iter_mut().for_each(|x| *x *= inv);
        // Columns k = j + 1 … j + len: A[i][k] −= L[i][j] L[k][j] for i ≥ k.
        for (m, &lkj) in col.iter().enumerate() {
            let k = j + 1 + m;
            let target = &mut rest[(k - j - 1) * w..(k - j - 1) * w + (len - m)];
            for (t, &lij) in target.iter_mut().zip(&col[m..]) {
                *t = F::mul_add(-lij, lkj, *t);
            }
        }
    }
    Ok(())
}

/// `BandCholesky::forward` with the multiply-adds of `F`.
#[inline(always)]
fn forward_with<F: Arith>(c: &BandCholesky, b: &mut [f64], m: usize) {
    let w = c.p + 1;
    let l = &c.l;
    for j in 0..m {
        let yj = b[j] * c.inv_diag[j];
        b[j] = yj;
        let below = c.below[j];
        for (y, a) in b[j + 1..j + 1 + below].iter_mut().zip(&l[j * w + 1..]) {
            *y = F::mul_add(-a, yj, *y);
        }
    }
}

/// `BandCholesky::backward` with the multiply-adds of `F`.
#[inline(always)]
fn backward_with<F: Arith>(c: &BandCholesky, b: &mut [f64], m: usize) {
    let w = c.p + 1;
    let l = &c.l;
    for j in (0..m).rev() {
        let below = c.below[j];
        if below == 0 {
            b[j] *= c.inv_diag[j];
            continue;
        }
        // x_{j+1}, just computed, enters last (as in band_lu's solves):
        // the products with the older x's do not wait for it, so the
        // chain from row to row is one multiply-add and one multiply.
        // With x_{j+1} inside the four-way dot the backward solve was
        // latency-bound: 16.7 % of a 4096-element modified-Newton run
        // against the forward solve's 9.5 %; now 11.0 % (perf).
        let col = &l[j * w + 1..j * w + 1 + below];
        let older = dot::<F>(&col[1..], &b[j + 2..j + 1 + below]);
        b[j] = F::mul_add(-col[0], b[j + 1], b[j] - older) * c.inv_diag[j];
    }
}

/// (pattern value index, row, column) of every entry of a compressed-column
/// pattern, column by column.
pub(crate) fn pattern_entries<'a>(
    col_ptr: &'a [usize],
    row_idx: &'a [usize],
) -> impl Iterator<Item = (usize, usize, usize)> + 'a {
    (0..col_ptr.len().saturating_sub(1))
        .flat_map(move |c| (col_ptr[c]..col_ptr[c + 1]).map(move |k| (k, row_idx[k], c)))
}

/// For each column j of an n × n symmetric pattern given by its (row,
/// column) entries (both triangles or one), how many rows below the
/// diagonal its Cholesky or LU factor can fill: the last non-zero row of
/// columns 0 … j (fill stays inside that envelope), minus j.
pub(crate) fn envelope(n: usize, entries: impl Iterator<Item = (usize, usize)>) -> Vec<usize> {
    // Last non-zero row of each column; an entry above the diagonal stands
    // for its mirror image.
    let mut last: Vec<usize> = (0..n).collect();
    for (r, c) in entries {
        let (lo, hi) = (r.min(c), r.max(c));
        last[lo] = last[lo].max(hi);
    }
    let mut reach = 0;
    last.iter()
        .enumerate()
        .map(|(j, &l)| {
            reach = reach.max(l);
            reach - j
        })
        .collect()
}

#[cfg(test)]
pub(crate) mod tests {
    use super::*;

    /// A test matrix: dense (row-major) and as compressed columns (values,
    /// column pointers, row indices) over the entries `keep(row, column)`.
    pub(crate) struct TestMatrix {
        pub n: usize,
        pub dense: Vec<f64>,
        pub col_ptr: Vec<usize>,
        pub row_idx: Vec<usize>,
        pub values: Vec<f64>,
    }

    impl TestMatrix {
        pub fn new(n: usize, dense: Vec<f64>, keep: impl Fn(usize, usize) -> bool) -> Self {
            let (mut col_ptr, mut row_idx, mut values) = (vec![0], Vec::new(), Vec::new());
            for c in 0..n {
                for r in (0..n).filter(|&r| keep(r, c)) {
                    row_idx.push(r);
                    values.push(dense[r * n + c]);
                }
                col_ptr.push(row_idx.len());
            }
            TestMatrix {
                n,
                dense,
                col_ptr,
                row_idx,
                values,
            }
        }

        pub fn bandwidth(&self) -> usize {
            BandCholesky::bandwidth(&self.col_ptr, &self.row_idx)
        }

        /// Largest error of `solve` on A x = b for a known x.
        pub fn solve_error(&self, x: &[f64], solve: impl FnOnce(&mut [f64])) -> f64 {
            let n = self.n;
            let mut b: Vec<f64> = (0..n)
                .map(|i| (0..n).map(|j| self.dense[i * n + j] * x[j]).sum())
                .collect();
            solve(&mut b);
            b.iter()
                .zip(x)
                .map(|(u, v)| (u - v).abs())
                .fold(0.0, f64::max)
        }
    }

    /// Uniform numbers in [−0.5, 0.5) from a seed (a linear congruential
    /// generator: reproducible, no dependency).
    pub(crate) fn uniform(seed: u64) -> impl FnMut() -> f64 {
        let mut state = seed;
        move || {
            state = state
                .wrapping_mul(6364136223846793005)
                .wrapping_add(1442695040888963407);
            (state >> 11) as f64 / (1u64 << 53) as f64 - 0.5
        }
    }

    /// A random symmetric positive definite band matrix.
    pub(crate) fn band_spd(n: usize, p: usize, seed: u64) -> TestMatrix {
        let mut rand = uniform(seed);
        let mut a = vec![0.0; n * n];
        for i in 0..n {
            for j in 0..i {
                if i - j <= p {
                    let v = rand();
                    a[i * n + j] = v;
                    a[j * n + i] = v;
                }
            }
            a[i * n + i] = 2.0 * p as f64 + 1.0;
        }
        TestMatrix::new(n, a, |r, c| r.abs_diff(c) <= p)
    }

    #[test]
    fn solves_band_systems_to_round_off() {
        for (n, p) in [(1, 0), (5, 1), (40, 7), (60, 23), (10, 23)] {
            let a = band_spd(n, p, 7 + n as u64);
            let mut chol = BandCholesky::new(n, a.bandwidth(), &a.col_ptr, &a.row_idx);
            assert_eq!(chol.half_bandwidth(), p.min(n.saturating_sub(1)));
            chol.factorize(&a.values).expect("positive definite");
            let x: Vec<f64> = (0..n).map(|i| (i as f64 * 0.7).sin()).collect();
            let err = a.solve_error(&x, |b| chol.solve_in_place(b));
            assert!(err < 1e-12, "n {n}, p {p}: error {err:e}");
        }
    }

    /// On every instruction-set path this CPU runs, `factor_solve(path, b)`
    /// (factor `a`, then solve in place) solves `a` to 1e-12 and agrees
    /// with the baseline path to 1e-13 (the paths round differently: fused
    /// multiply-adds).
    pub(crate) fn assert_paths_agree(
        a: &TestMatrix,
        x: &[f64],
        mut factor_solve: impl FnMut(crate::math::simd::SimdPath, &mut [f64]),
    ) {
        use crate::math::simd::SimdPath;
        let mut reference: Option<Vec<f64>> = None;
        for path in SimdPath::ALL.into_iter().filter(|p| p.supported()) {
            let mut got = Vec::new();
            let err = a.solve_error(x, |b| {
                factor_solve(path, b);
                got = b.to_vec();
            });
            assert!(err < 1e-12, "{}: error {err:e}", path.name());
            let base = reference.get_or_insert(got.clone());
            let diff = got
                .iter()
                .zip(base.iter())
                .map(|(g, b)| (g - b).abs())
                .fold(0.0, f64::max);
            assert!(diff < 1e-13, "{} against baseline: {diff:e}", path.name());
        }
    }

    /// Every path agrees with the baseline, through the split solves'
    /// pieces as well.
    #[test]
    fn every_simd_path_agrees_with_the_baseline() {
        let a = block_tridiagonal(20, 12, true);
        let mut chol = BandCholesky::new(a.n, a.bandwidth(), &a.col_ptr, &a.row_idx);
        let x: Vec<f64> = (0..a.n).map(|i| (i as f64 * 0.7).sin()).collect();
        assert_paths_agree(&a, &x, |path, b| {
            factorize_columns(path, &mut chol, &a.values, a.n).expect("positive definite");
            forward(path, &chol, b, a.n);
            backward(path, &chol, b, a.n);
        });
    }

    /// A block-tridiagonal matrix (blocks of `b`, as a wire's nodes),
    /// symmetric positive definite or not: its envelope is narrower than
    /// its band, which the factors must use.
    pub(crate) fn block_tridiagonal(blocks: usize, b: usize, symmetric: bool) -> TestMatrix {
        let n = blocks * b;
        let coupled = |r: usize, c: usize| (r / b).abs_diff(c / b) <= 1;
        let mut a = vec![0.0; n * n];
        for r in 0..n {
            for c in (0..n).filter(|&c| coupled(r, c)) {
                let v = ((r * 7 + c * 3) % 11) as f64 / 11.0 - 0.5;
                let w = ((c * 7 + r * 3) % 11) as f64 / 11.0 - 0.5;
                a[r * n + c] = if r == c {
                    4.0 * b as f64
                } else if symmetric {
                    0.5 * (v + w)
                } else {
                    v
                };
            }
        }
        TestMatrix::new(n, a, coupled)
    }

    #[test]
    fn uses_the_envelope_of_a_block_tridiagonal_matrix() {
        let a = block_tridiagonal(6, 4, true);
        let n = a.n;
        let entries = pattern_entries(&a.col_ptr, &a.row_idx);
        let below = envelope(n, entries.map(|(_, r, c)| (r, c)));
        assert_eq!(&below[..4], &[7, 6, 5, 4], "rows to the next block's end");
        assert_eq!(below[n - 1], 0);
        assert_eq!(a.bandwidth(), 7);
        let mut chol = BandCholesky::new(n, a.bandwidth(), &a.col_ptr, &a.row_idx);
        chol.factorize(&a.values).expect("positive definite");
        let x: Vec<f64> = (0..n).map(|i| 1.0 + i as f64).collect();
        let err = a.solve_error(&x, |b| chol.solve_in_place(b));
        assert!(err < 1e-12, "error {err:e}");
    }

    #[test]
    fn refuses_an_indefinite_matrix() {
        let mut a = band_spd(6, 2, 3);
        // Make the (3, 3) pivot negative.
        let diag = (a.col_ptr[3]..a.col_ptr[4])
            .find(|&k| a.row_idx[k] == 3)
            .unwrap();
        a.values[diag] = -1.0;
        let mut chol = BandCholesky::new(6, a.bandwidth(), &a.col_ptr, &a.row_idx);
        assert!(chol.factorize(&a.values).is_err());
    }
}
