//! Cholesky factorization of a symmetric positive definite band matrix in
//! two halves that run on two threads.
//!
//! A band matrix of half-bandwidth p falls apart when p consecutive
//! unknowns are taken out: nothing couples an unknown above them with one
//! below (|i − j| > p). Ordering that separator last (nested dissection
//! with one separator) gives
//!
//! ```text
//!     [ A_TT   0    A_TS ]        L_T  = chol(A_TT)            (band, top)
//!     [  0    A_BB  A_BS ]        L_B  = chol(A_BB)            (band, bottom)
//!     [ A_ST  A_SB  A_SS ]        L_S  = chol(A_SS − L_ST L_STᵀ − L_SB L_SBᵀ)   (dense p × p)
//! ```
//!
//! The two band factorizations are independent, and so are the two halves
//! of each solve: the serial band factorization and solves are a third of a
//! full-Newton step at a few hundred elements and a quarter of a
//! modified-Newton step at thousands, and no other part of a step can use
//! the second core there. The top half is the matrix's own rows 0 … s + p − 1
//! (the separator at its end); the bottom half is rows s … n − 1 in reverse
//! order (the separator, reversed, at its end), so both are ordinary
//! [`BandCholesky`] factors eliminated up to their separator rows. The
//! separator's own block A_SS is loaded into the top half only.
//!
//! The arithmetic does not depend on whether the halves run in parallel:
//! one thread and two give the same bits.

use crate::linalg::band_cholesky::{BandCholesky, NotPositiveDefinite, pattern_entries};
use crate::linalg::parallel::run_tasks;

/// From this many unknowns on, [`crate::linalg::linear_solver`] uses the split
/// factorization (decided by the size alone, so results never depend on
/// the thread count), and its two halves run on two threads: from a few
/// hundred elements the split gains on two threads and costs nothing on
/// one (the reversed copy of the bottom half's right-hand side is cheap).
/// ≈ 170 wire elements.
pub const SPLIT_MIN_UNKNOWNS: usize = 2000;

/// Solves split their halves over two threads only from this many unknowns
/// (a solve is ≈ 10× cheaper than a factorization):
/// modified-Newton steps (solves only) on 2 threads were 0.98–1.06× at
/// 12 297 unknowns and 1.40–1.49× at 49 161.
const PARALLEL_SOLVE_MIN_UNKNOWNS: usize = 20_000;

/// Largest half-bandwidth (= separator size) split: the separator's
/// right-hand side lives on the stack (a wire's is 23; `linear_solver`
/// takes bands up to 48).
pub const MAX_SEPARATOR: usize = 64;

/// L of A = L Lᵀ in the separator ordering, with the maps from the sparse
/// pattern's value slots to both halves, computed once per pattern.
#[derive(Clone, Debug)]
pub struct SplitBandCholesky {
    n: usize,
    p: usize,
    /// First separator unknown s; the separator is s … s + p − 1.
    s: usize,
    /// Unknowns 0 … s + p − 1, eliminated up to column s.
    top: BandCholesky,
    /// Unknowns n − 1 … s (bottom local index i ↔ unknown n − 1 − i),
    /// eliminated up to column n − s − p.
    bottom: BandCholesky,
    /// L_S, dense p × p, row-major (lower triangle).
    separator: Vec<f64>,
    /// The bottom half's right-hand side in its own (reversed) numbering.
    work: Vec<f64>,
}

impl SplitBandCholesky {
    /// The split structure of a symmetric n × n pattern (compressed sparse
    /// columns, both triangles) of half-bandwidth 1 ≤ `p` ≤ [`MAX_SEPARATOR`],
    /// n ≥ 3 p.
    pub fn new(n: usize, p: usize, col_ptr: &[usize], row_idx: &[usize]) -> Self {
        assert!(
            (1..=MAX_SEPARATOR).contains(&p) && n >= 3 * p,
            "split needs 1 ≤ p ≤ {MAX_SEPARATOR} and n ≥ 3p (n = {n}, p = {p})"
        );
        let s = (n - p) / 2;
        let entries = || pattern_entries(col_ptr, row_idx);
        let in_separator = |i: usize| (s..s + p).contains(&i);
        let top = BandCholesky::from_entries(
            s + p,
            p,
            entries().filter(|&(_, r, c)| r < s + p && c < s + p),
        );
        let bottom = BandCholesky::from_entries(
            n - s,
            p,
            entries()
                .filter(|&(_, r, c)| r >= s && c >= s && !(in_separator(r) && in_separator(c)))
                .map(|(k, r, c)| (k, n - 1 - r, n - 1 - c)),
        );
        SplitBandCholesky {
            n,
            p,
            s,
            top,
            bottom,
            separator: vec![0.0; p * p],
            work: vec![0.0; n - s],
        }
    }

    /// Half-bandwidth p.
    pub fn half_bandwidth(&self) -> usize {
        self.p
    }

    /// Factor the matrix whose pattern values are `values` (lower triangle
    /// read). The error names the unknown whose pivot was not positive.
    pub fn factorize(&mut self, values: &[f64]) -> Result<(), NotPositiveDefinite> {
        let (n, p, s) = (self.n, self.p, self.s);
        let (top, bottom) = (&mut self.top, &mut self.bottom);
        let halves = vec![(top, s), (bottom, n - s - p)];
        let done = run_tasks(halves, |(half, m)| half.factorize_columns(values, m));
        done[0]?;
        done[1].map_err(|e| NotPositiveDefinite { row: n - 1 - e.row })?;
        // S = A_SS − L_ST L_STᵀ − L_SB L_SBᵀ: the two trailing blocks, the
        // bottom's in reversed order (its local n − s − 1 − a ↔ separator a).
        let sep = &mut self.separator;
        let nb = n - s;
        for a in 0..p {
            for c in 0..=a {
                let from_top = self.top.trailing(s + a, s + c);
                let from_bottom = self.bottom.trailing(nb - 1 - c, nb - 1 - a);
                sep[a * p + c] = from_top + from_bottom;
            }
        }
        dense_cholesky(sep, p).map_err(|a| NotPositiveDefinite { row: s + a })
    }

    /// Solve A x = b in place with the last factorization.
    pub fn solve_in_place(&mut self, b: &mut [f64]) {
        let (n, p, s) = (self.n, self.p, self.s);
        let nb = n - s;
        let (top, bottom) = (&self.top, &self.bottom);
        let work = &mut self.work;
        // The bottom's right-hand side: its own rows reversed, the
        // separator rows zero (they gather only the bottom's updates).
        for (i, w) in work.iter_mut().enumerate().take(nb - p) {
            *w = b[n - 1 - i];
        }
        work[nb - p..].fill(0.0);
        let (b_top, _) = b.split_at_mut(s + p);
        let parallel = n >= PARALLEL_SOLVE_MIN_UNKNOWNS;
        halves(
            parallel,
            (top, &mut b_top[..], s),
            (bottom, &mut work[..], nb - p),
            |(half, b, m)| half.forward(b, m),
        );
        // Separator: L_S L_Sᵀ x_S = b_S − L_ST y_T − L_SB y_B.
        let mut x_s = [0.0; MAX_SEPARATOR];
        let x_s = &mut x_s[..p];
        for (a, x) in x_s.iter_mut().enumerate() {
            *x = b_top[s + a] + work[nb - 1 - a];
        }
        dense_solve(&self.separator, p, x_s);
        for (a, &x) in x_s.iter().enumerate() {
            b_top[s + a] = x;
            work[nb - 1 - a] = x;
        }
        halves(
            parallel,
            (top, &mut b_top[..], s),
            (bottom, &mut work[..], nb - p),
            |(half, b, m)| half.backward(b, m),
        );
        for (i, &w) in work.iter().enumerate().take(nb - p) {
            b[n - 1 - i] = w;
        }
    }
}

/// A solve pass over both halves: (factor, right-hand side, columns).
type SolveHalf<'a> = (&'a BandCholesky, &'a mut [f64], usize);

/// `pass` on both halves, on two threads when `parallel` (same arithmetic).
fn halves(parallel: bool, top: SolveHalf, bottom: SolveHalf, pass: impl Fn(SolveHalf) + Sync) {
    if parallel {
        run_tasks(vec![top, bottom], pass);
    } else {
        pass(top);
        pass(bottom);
    }
}

/// In-place Cholesky of a dense p × p matrix (row-major, lower triangle);
/// the error is the row of a non-positive pivot.
fn dense_cholesky(a: &mut [f64], p: usize) -> Result<(), usize> {
    for j in 0..p {
        let d = a[j * p + j] - (0..j).map(|k| a[j * p + k] * a[j * p + k]).sum::<f64>();
        if d <= 0.0 || !d.is_finite() {
            return Err(j);
        }
        let d = d.sqrt();
        a[j * p + j] = d;
        for i in j + 1..p {
            let v = a[i * p + j] - (0..j).map(|k| a[i * p + k] * a[j * p + k]).sum::<f64>();
            a[i * p + j] = v / d;
        }
    }
    Ok(())
}

/// Solve L Lᵀ x = b in place with the factor of [`dense_cholesky`].
fn dense_solve(l: &[f64], p: usize, x: &mut [f64]) {
    for i in 0..p {
        let s: f64 = (0..i).map(|k| l[i * p + k] * x[k]).sum();
        x[i] = (x[i] - s) / l[i * p + i];
    }
    for i in (0..p).rev() {
        let s: f64 = (i + 1..p).map(|k| l[k * p + i] * x[k]).sum();
        x[i] = (x[i] - s) / l[i * p + i];
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::linalg::band_cholesky::tests::{band_spd, block_tridiagonal};

    #[test]
    fn solves_band_systems_to_round_off() {
        for (n, p) in [(3, 1), (9, 3), (10, 3), (70, 7), (100, 23), (257, 23)] {
            let a = band_spd(n, p, 11 + n as u64);
            let mut chol = SplitBandCholesky::new(n, a.bandwidth(), &a.col_ptr, &a.row_idx);
            chol.factorize(&a.values).expect("positive definite");
            let x: Vec<f64> = (0..n).map(|i| (i as f64 * 0.7).sin()).collect();
            let err = a.solve_error(&x, |b| chol.solve_in_place(b));
            assert!(err < 1e-12, "n {n}, p {p}: error {err:e}");
        }
    }

    /// A wire-like matrix (12 × 12 blocks, block tridiagonal): the split's
    /// answer equals the one-piece band factorization's to round-off.
    #[test]
    fn agrees_with_the_band_factorization_on_a_block_tridiagonal_matrix() {
        let a = block_tridiagonal(40, 12, true);
        let (n, p) = (a.n, a.bandwidth());
        let mut split = SplitBandCholesky::new(n, p, &a.col_ptr, &a.row_idx);
        let mut band = BandCholesky::new(n, p, &a.col_ptr, &a.row_idx);
        split.factorize(&a.values).expect("positive definite");
        band.factorize(&a.values).expect("positive definite");
        let rhs: Vec<f64> = (0..n).map(|i| 1.0 + (i as f64).cos()).collect();
        let (mut x1, mut x2) = (rhs.clone(), rhs);
        split.solve_in_place(&mut x1);
        band.solve_in_place(&mut x2);
        let d = x1
            .iter()
            .zip(&x2)
            .map(|(u, v)| (u - v).abs())
            .fold(0.0, f64::max);
        assert!(d < 1e-13, "split and band differ by {d:e}");
        let x: Vec<f64> = (0..n).map(|i| 1.0 + i as f64).collect();
        assert!(a.solve_error(&x, |b| split.solve_in_place(b)) < 1e-12);
    }

    /// The answer has the same bits with the halves run on one thread or two
    /// (large enough for both the factorization and the solves to split).
    #[test]
    fn same_bits_on_one_and_two_threads() {
        let (n, p) = (PARALLEL_SOLVE_MIN_UNKNOWNS + 5, 5);
        // A band SPD matrix as compressed columns, without a dense copy.
        let mut rand = crate::linalg::band_cholesky::tests::uniform(3);
        let (mut col_ptr, mut row_idx, mut values) = (vec![0], Vec::new(), Vec::new());
        let mut lower = vec![0.0; n * (p + 1)];
        for c in 0..n {
            for r in c.saturating_sub(p)..(c + p + 1).min(n) {
                let v = if r == c {
                    2.0 * p as f64 + 1.0
                } else if r > c {
                    let v = rand();
                    lower[c * (p + 1) + (r - c)] = v;
                    v
                } else {
                    lower[r * (p + 1) + (c - r)]
                };
                row_idx.push(r);
                values.push(v);
            }
            col_ptr.push(row_idx.len());
        }
        let run = |threads: usize| {
            let pool = rayon::ThreadPoolBuilder::new()
                .num_threads(threads)
                .build()
                .unwrap();
            pool.install(|| {
                let mut chol = SplitBandCholesky::new(n, p, &col_ptr, &row_idx);
                chol.factorize(&values).unwrap();
                let mut b: Vec<f64> = (0..n).map(|i| (i as f64).sin()).collect();
                chol.solve_in_place(&mut b);
                b
            })
        };
        let (one, two) = (run(1), run(2));
        assert!(
            one.iter()
                .zip(&two)
                .all(|(u, v)| u.to_bits() == v.to_bits())
        );
        // And it solves the system: A x = b to round-off.
        let mut ax = vec![0.0; n];
        for c in 0..n {
            for k in col_ptr[c]..col_ptr[c + 1] {
                ax[row_idx[k]] += values[k] * one[c];
            }
        }
        let err = (0..n)
            .map(|i| (ax[i] - (i as f64).sin()).abs())
            .fold(0.0, f64::max);
        assert!(err < 1e-12, "residual {err:e}");
    }

    /// A negative pivot in either half or in the separator is refused and
    /// named by its unknown.
    #[test]
    fn refuses_an_indefinite_matrix_in_each_part() {
        let n = 60;
        for bad in [3, 58, 29] {
            let mut a = band_spd(n, 4, 5);
            let diag = (a.col_ptr[bad]..a.col_ptr[bad + 1])
                .find(|&k| a.row_idx[k] == bad)
                .unwrap();
            a.values[diag] = -50.0;
            let mut chol = SplitBandCholesky::new(n, a.bandwidth(), &a.col_ptr, &a.row_idx);
            let err = chol.factorize(&a.values).expect_err("indefinite");
            assert!(
                err.row.abs_diff(bad) <= 4,
                "pivot {bad} reported at {}",
                err.row
            );
        }
    }
}
