//! LU of a block-tridiagonal matrix with node blocks, for the wire's
//! non-symmetric Newton matrices (friction, Kelvin–Voigt damping).
//!
//! Unknowns are numbered node by node and every element couples two
//! neighbouring nodes, so the Newton matrix is block tridiagonal with blocks
//! of at most 12 × 12 (a node's free coordinates). Block elimination
//! without pivoting between blocks (the same assumption as `band_lu`: the
//! mass-dominated symmetric part keeps the Schur complements regular),
//! with partial pivoting inside each diagonal block, whose inverse is kept:
//!
//!   S₀ = D₀,  Gₖ = Lₖ Sₖ⁻¹,  Sₖ₊₁ = Dₖ₊₁ − Gₖ Uₖ
//!   forward  yₖ₊₁ = bₖ₊₁ − Gₖ yₖ
//!   backward xₖ = Sₖ⁻¹ (yₖ − Uₖ xₖ₊₁)
//!
//! (Dₖ, Uₖ = A₍ₖ,ₖ₊₁₎, Lₖ = A₍ₖ₊₁,ₖ₎). Every operation is a dense 12 × 12
//! product: the solves are chains of matrix–vector products whose rows are
//! independent, where the band solve was a chain of single unknowns.
//! Blocks are stored padded to 12 × 12 (a pinned node has 9 unknowns; its
//! padding is the identity), so the kernels have fixed sizes.
//!
//! The blocks the solves read (Sₖ⁻¹, Gₖ, Uₖ: 3.4 KB a node) are kept in
//! the [`Precision`] the caller asks for. In single precision a solve
//! streams half the bytes. The factorization and the solves' arithmetic
//! stay in double precision, and each entry is rounded once, where it is
//! stored. That perturbs every entry of the factored matrix by at most
//! 6e-8 of itself: the Newton direction of a modified-Newton iteration,
//! whose matrix is already an approximation, changes by that times the
//! matrix's condition under row and column scaling. The residual that
//! decides convergence stays in double precision. Where that condition
//! reaches 1e7 (stiff sections at large steps) the rounded directions stop
//! contracting, and the integrator forms the matrix again in double
//! (`solve::dynamics`).

use crate::linalg::band_cholesky::pattern_entries;
use crate::linalg::value_sum::{SlotValues, ValueSum};
use crate::math::simd::{Arith, SimdPath, path};

/// Block size: a node's coordinates.
pub(crate) const B: usize = 12;

pub(crate) type Block = [[f64; B]; B];

pub(crate) const ZERO: Block = [[0.0; B]; B];

/// How a factorization keeps the blocks its solves read.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, serde::Serialize, serde::Deserialize)]
pub enum Precision {
    /// f64: solves to round-off (mass matrices, full Newton, statics).
    #[default]
    Double,
    /// f32 storage, f64 arithmetic: half the memory traffic of a solve,
    /// for a matrix that only gives directions (modified Newton's kept
    /// matrix, whose staleness already costs more than the rounding on a
    /// well-conditioned matrix; BENCHMARKS.md has the measurements).
    Single,
}

/// A stored block entry: f64, or f32 rounded once from the f64 result.
pub(crate) trait Stored: Copy + Default + std::fmt::Debug {
    fn store(x: f64) -> Self;
    fn load(self) -> f64;
}

impl Stored for f64 {
    #[inline(always)]
    fn store(x: f64) -> Self {
        x
    }
    #[inline(always)]
    fn load(self) -> f64 {
        self
    }
}

impl Stored for f32 {
    #[inline(always)]
    fn store(x: f64) -> Self {
        x as f32
    }
    #[inline(always)]
    fn load(self) -> f64 {
        f64::from(self)
    }
}

/// Sₖ⁻¹, Gₖ and Uₖ transposed, for the solves' column-oriented products.
/// (Sₖ⁻¹ and Gₖ themselves are needed only for the next block: the
/// factorization keeps them on the stack, 2 · 1152 bytes a node less to
/// write.)
#[derive(Clone, Debug, Default)]
struct Kept<T> {
    inverse_t: Vec<[[T; B]; B]>,
    gain_t: Vec<[[T; B]; B]>,
    upper_t: Vec<[[T; B]; B]>,
}

impl<T: Stored> Kept<T> {
    /// Zero blocks for `m` nodes.
    fn new(m: usize) -> Self {
        let zero = [[T::default(); B]; B];
        Kept {
            inverse_t: vec![zero; m],
            gain_t: vec![zero; m.saturating_sub(1)],
            upper_t: vec![zero; m.saturating_sub(1)],
        }
    }
}

/// The factorization, with the map from the sparse pattern's value slots to
/// the blocks, computed once per pattern.
#[derive(Clone, Debug)]
pub struct BlockTridiagonalLu {
    /// Node k's unknowns are starts[k] … starts[k + 1] − 1.
    starts: Vec<usize>,
    /// Node k's columns hold the value slots `node_values[k]` …
    /// `node_values[k + 1] − 1` (compressed columns: one window).
    node_values: Vec<usize>,
    /// For every value slot, its place among the three blocks of its
    /// column node k, [Uₖ₋₁, Dₖ, Lₖ] row-major one after the other (0 …
    /// 431): the factorization reads the values front to back and
    /// scatters them into three blocks on the stack. (Read in the blocks'
    /// order instead, every value was a cache line of its own: the loads
    /// missed.)
    places: Vec<u16>,
    /// Whether node k's columns fill its blocks (all but the nodes at a
    /// support or beside a gap between two beams): they are then
    /// overwritten whole, with no clearing.
    full: Vec<bool>,
    /// The matrix by blocks, for [`Self::load`] only (empty until then):
    /// the factorization loads each node's blocks where it needs them.
    input: Vec<Block>,
    /// What the solves read, in each precision (single allocated at its
    /// first use; both kept, so that switching allocates nothing), and
    /// the precision of the last factorization.
    double: Kept<f64>,
    single: Kept<f32>,
    precision: Precision,
    /// The right-hand side by blocks (padded), for the solves.
    work: Vec<[f64; B]>,
}

/// A column node's three blocks: Uₖ₋₁ = A₍ₖ₋₁,ₖ₎, Dₖ and Lₖ = A₍ₖ₊₁,ₖ₎.
type Columns = [Block; 3];

/// A diagonal block's Schur complement is singular (to round-off).
#[derive(Clone, Copy, Debug)]
pub struct SingularBlock;

impl BlockTridiagonalLu {
    /// The node blocks of an n × n pattern (compressed sparse columns, both
    /// triangles), or `None` when it is not block tridiagonal with blocks
    /// of at most 12: columns with the same first and last row form a block.
    pub fn new(n: usize, col_ptr: &[usize], row_idx: &[usize]) -> Option<Self> {
        if n == 0 {
            return None;
        }
        let range = |c: usize| {
            let rows = &row_idx[col_ptr[c]..col_ptr[c + 1]];
            (rows.iter().copied().min(), rows.iter().copied().max())
        };
        let mut starts = vec![0];
        for c in 1..n {
            if range(c) != range(c - 1) {
                starts.push(c);
            }
        }
        starts.push(n);
        let m = starts.len() - 1;
        if starts.windows(2).any(|w| w[1] - w[0] > B) {
            return None;
        }
        let mut node_of = vec![0; n];
        for k in 0..m {
            node_of[starts[k]..starts[k + 1]].fill(k);
        }
        let mut places = vec![0; row_idx.len()];
        for (v, r, c) in pattern_entries(col_ptr, row_idx) {
            let (kr, kc) = (node_of[r], node_of[c]);
            let (lr, lc) = (r - starts[kr], c - starts[kc]);
            let block = match kr as isize - kc as isize {
                -1 => 0,
                0 => 1,
                1 => 2,
                _ => return None,
            };
            places[v] = (block * B * B + lr * B + lc) as u16;
        }
        let node_values: Vec<usize> = starts.iter().map(|&c| col_ptr[c]).collect();
        let full = (0..m)
            .map(|k| {
                let blocks = 1 + usize::from(k > 0) + usize::from(k + 1 < m);
                node_values[k + 1] - node_values[k] == blocks * B * B
            })
            .collect();
        Some(BlockTridiagonalLu {
            starts,
            node_values,
            places,
            full,
            input: Vec::new(),
            double: Kept::new(m),
            single: Kept::default(),
            precision: Precision::Double,
            work: vec![[0.0; B]; m],
        })
    }

    /// Factor the matrix whose pattern values are `values` (kept in
    /// double precision).
    pub fn factorize(&mut self, values: &[f64]) -> Result<(), SingularBlock> {
        self.keep_in(Precision::Double);
        factorize(path(), self, Source::Array(values))
    }

    /// Factor the matrix `sum`, read where each block is loaded (never
    /// formed), and keep it in `precision`. A non-finite value is reported
    /// as a [`SingularBlock`].
    pub fn factorize_sum(
        &mut self,
        sum: &ValueSum,
        precision: Precision,
    ) -> Result<(), SingularBlock> {
        self.keep_in(precision);
        factorize(path(), self, Source::Sum(sum))
    }

    /// The precision the last factorization was kept in.
    pub fn precision(&self) -> Precision {
        self.precision
    }

    /// Keep the next factorization in `precision` (the single-precision
    /// blocks are allocated at their first use).
    fn keep_in(&mut self, precision: Precision) {
        let m = self.nodes();
        if precision == Precision::Single && self.single.inverse_t.len() != m {
            self.single = Kept::new(m);
        }
        self.precision = precision;
    }

    /// The number of node blocks.
    fn nodes(&self) -> usize {
        self.starts.len() - 1
    }

    /// Solve A x = b in place with the last factorization.
    pub fn solve_in_place(&mut self, b: &mut [f64]) {
        solve(path(), self, b)
    }

    /// Node k's unknowns are `starts()[k]` … `starts()[k + 1] − 1`.
    pub(crate) fn starts(&self) -> &[usize] {
        &self.starts
    }

    /// The matrix with pattern values `values` by blocks, padded (a
    /// node's missing unknowns have the identity): the diagonal blocks
    /// Dₖ, the upper Uₖ = A₍ₖ,ₖ₊₁₎ and the lower Lₖ = A₍ₖ₊₁,ₖ₎.
    pub(crate) fn load(&mut self, values: &[f64]) -> (&[Block], &[Block], &[Block]) {
        let m = self.nodes();
        self.input.resize(3 * m - 2, ZERO);
        let mut columns = [ZERO; 3];
        for k in 0..m {
            load_node(self, k, values, &mut columns);
            self.input[k] = columns[1];
            if k > 0 {
                self.input[m + k - 1] = columns[0];
            }
            if k + 1 < m {
                self.input[2 * m - 1 + k] = columns[2];
            }
        }
        let (diag, rest) = self.input.split_at(m);
        let (upper, lower) = rest.split_at(m - 1);
        (diag, upper, lower)
    }
}

/// Where a factorization reads the matrix's values.
#[derive(Clone, Copy)]
enum Source<'a> {
    Array(&'a [f64]),
    Sum(&'a ValueSum<'a>),
}

/// Node k's columns of the matrix with slot values `values` into its
/// three blocks [Uₖ₋₁, Dₖ, Lₖ] (`out`, written over), padded: a node's
/// missing unknowns have the identity on Dₖ; entries outside the pattern
/// are zero (Uₖ₋₁ of the first node and Lₖ of the last are left as they
/// were). False when a value is not finite.
#[inline(always)]
fn load_node<V: SlotValues + ?Sized>(
    lu: &BlockTridiagonalLu,
    k: usize,
    values: &V,
    out: &mut Columns,
) -> bool {
    let slots = lu.node_values[k]..lu.node_values[k + 1];
    if !lu.full[k] {
        *out = [ZERO; 3];
        for r in lu.starts[k + 1] - lu.starts[k]..B {
            out[1][r][r] = 1.0;
        }
    }
    let places = &lu.places[slots.clone()];
    values.scatter(slots, places, out.as_flattened_mut().as_flattened_mut())
}

crate::simd_dispatch! {
    fn factorize(lu: &mut BlockTridiagonalLu, values: Source) -> Result<(), SingularBlock> = factorize_with;
}

crate::simd_dispatch! {
    fn solve_on(lu: &mut BlockTridiagonalLu, b: &mut [f64]) = solve_with;
}

/// The solves on `path`, except that the AVX-512 path runs the AVX2 code:
/// their 12-lane matrix–vector products, chained block after block, run
/// faster as three 256-bit vectors than as a 512-bit and a 256-bit one.
/// Both are the fused path's operations: the same bits.
fn solve(path: SimdPath, lu: &mut BlockTridiagonalLu, b: &mut [f64]) {
    let path = if path == SimdPath::Avx512 {
        SimdPath::Avx2
    } else {
        path
    };
    solve_on(path, lu, b)
}

/// c −= a b (12 × 12 blocks).
#[inline(always)]
pub(crate) fn sub_product<F: Arith>(c: &mut Block, a: &Block, b: &Block) {
    for i in 0..B {
        let mut row = c[i];
        for k in 0..B {
            let aik = a[i][k];
            for j in 0..B {
                row[j] = F::mul_add(-aik, b[k][j], row[j]);
            }
        }
        c[i] = row;
    }
}

/// c = a b (12 × 12 blocks), written over c.
#[inline(always)]
pub(crate) fn product<F: Arith>(a: &Block, b: &Block, c: &mut Block) {
    for i in 0..B {
        let mut row = [0.0; B];
        for k in 0..B {
            let aik = a[i][k];
            for j in 0..B {
                row[j] = F::mul_add(aik, b[k][j], row[j]);
            }
        }
        c[i] = row;
    }
}

/// a x from aᵀ (`at`), column by column: twelve lanes of multiply-adds in
/// two independent halves (a row-by-row dot product waits on each sum).
#[inline(always)]
fn matvec_t<F: Arith, T: Stored>(at: &[[T; B]; B], x: &[f64; B]) -> [f64; B] {
    let (mut lo, mut hi) = ([0.0; B], [0.0; B]);
    for k in 0..B / 2 {
        let (xa, xb) = (x[k], x[k + B / 2]);
        for i in 0..B {
            lo[i] = F::mul_add(at[k][i].load(), xa, lo[i]);
            hi[i] = F::mul_add(at[k + B / 2][i].load(), xb, hi[i]);
        }
    }
    for i in 0..B {
        lo[i] += hi[i];
    }
    lo
}

/// t = aᵀ, written over t (each entry rounded to t's precision).
#[inline(always)]
fn transpose<T: Stored>(a: &Block, t: &mut [[T; B]; B]) {
    for i in 0..B {
        for j in 0..B {
            t[j][i] = T::store(a[i][j]);
        }
    }
}

/// The inverse of `s`, written over `inv`, by Gauss–Jordan elimination
/// with partial pivoting, on the augmented rows [s | I] (one 24-wide row
/// operation per elimination instead of two 12-wide ones; the same
/// operations).
#[inline(always)]
pub(crate) fn invert<F: Arith>(s: &Block, inv: &mut Block) -> Result<(), SingularBlock> {
    let mut m = [[0.0f64; 2 * B]; B];
    for (i, row) in m.iter_mut().enumerate() {
        row[..B].copy_from_slice(&s[i]);
        row[B + i] = 1.0;
    }
    // max |s_ij| in twelve running maxima, one per column (the maximum is
    // exact in any order; one running maximum waited on each compare).
    let mut column_max = [0.0f64; B];
    for row in s {
        for (m, v) in column_max.iter_mut().zip(row) {
            *m = m.max(v.abs());
        }
    }
    let scale = column_max.iter().fold(0.0f64, |m, v| m.max(*v));
    for col in 0..B {
        let pivot_row = (col..B)
            .max_by(|&p, &q| m[p][col].abs().total_cmp(&m[q][col].abs()))
            .unwrap_or(col);
        let pivot = m[pivot_row][col];
        if !pivot.is_finite() || pivot.abs() <= 1e-14 * scale {
            return Err(SingularBlock);
        }
        // (Only when needed: a row swapped with itself was a 24-wide load
        // and store that waited on the elimination's stores, perf.)
        if pivot_row != col {
            m.swap(col, pivot_row);
        }
        let p = 1.0 / pivot;
        for x in m[col].iter_mut() {
            *x *= p;
        }
        let pr = m[col];
        for (r, row) in m.iter_mut().enumerate() {
            if r != col {
                let f = row[col];
                for (x, y) in row.iter_mut().zip(&pr) {
                    *x = F::mul_add(-f, *y, *x);
                }
            }
        }
    }
    for (i, row) in inv.iter_mut().enumerate() {
        row.copy_from_slice(&m[i][B..]);
    }
    Ok(())
}

#[inline(always)]
fn factorize_with<F: Arith>(
    lu: &mut BlockTridiagonalLu,
    values: Source,
) -> Result<(), SingularBlock> {
    match lu.precision {
        Precision::Double => factorize_kept::<F, f64>(lu, values, |lu| &mut lu.double),
        Precision::Single => factorize_kept::<F, f32>(lu, values, |lu| &mut lu.single),
    }
}

/// The elimination into the blocks `kept` picks out of `lu` (taken out
/// for its duration: the elimination reads `lu`'s maps).
#[inline(always)]
fn factorize_kept<F: Arith, T: Stored>(
    lu: &mut BlockTridiagonalLu,
    values: Source,
    kept: fn(&mut BlockTridiagonalLu) -> &mut Kept<T>,
) -> Result<(), SingularBlock> {
    let mut blocks = std::mem::take(kept(lu));
    let done = match values {
        Source::Array(a) => factorize_from::<F, [f64], T>(lu, &mut blocks, a),
        Source::Sum(s) => factorize_from::<F, ValueSum, T>(lu, &mut blocks, s),
    };
    *kept(lu) = blocks;
    done
}

/// The elimination, node k's columns [Uₖ₋₁, Dₖ, Lₖ] loaded at step k
/// (into the stack: the blocks are never stored whole).
#[inline(always)]
fn factorize_from<F: Arith, V: SlotValues + ?Sized, T: Stored>(
    lu: &BlockTridiagonalLu,
    kept: &mut Kept<T>,
    values: &V,
) -> Result<(), SingularBlock> {
    let m = lu.nodes();
    let mut columns = [ZERO; 3];
    let (mut inverse, mut gain) = (ZERO, ZERO);
    for k in 0..m {
        if !load_node(lu, k, values, &mut columns) {
            return Err(SingularBlock);
        }
        let [upper, s, lower] = &mut columns;
        if k > 0 {
            // Sₖ = Dₖ − Gₖ₋₁ Uₖ₋₁ (`gain` is Gₖ₋₁ here).
            sub_product::<F>(s, &gain, upper);
            transpose(upper, &mut kept.upper_t[k - 1]);
        }
        // Results written in place: returned by value, each 1152-byte
        // block was a memcpy more.
        invert::<F>(s, &mut inverse)?;
        transpose(&inverse, &mut kept.inverse_t[k]);
        if k + 1 < m {
            product::<F>(lower, &inverse, &mut gain);
            transpose(&gain, &mut kept.gain_t[k]);
        }
    }
    Ok(())
}

#[inline(always)]
fn solve_with<F: Arith>(lu: &mut BlockTridiagonalLu, b: &mut [f64]) {
    let (starts, y) = (&lu.starts, &mut lu.work);
    match lu.precision {
        Precision::Double => solve_kept::<F, f64>(starts, &lu.double, y, b),
        Precision::Single => solve_kept::<F, f32>(starts, &lu.single, y, b),
    }
}

/// The forward and backward chains with the kept blocks; `y` is the
/// right-hand side by blocks.
#[inline(always)]
fn solve_kept<F: Arith, T: Stored>(
    starts: &[usize],
    kept: &Kept<T>,
    y: &mut [[f64; B]],
    b: &mut [f64],
) {
    let m = starts.len() - 1;
    // Full blocks copied as fixed-size arrays (a copy of a run-time length
    // was a call to memmove per block: 1.4 % of the span-break scene).
    for k in 0..m {
        let part = &b[starts[k]..starts[k + 1]];
        y[k] = <[f64; B]>::try_from(part).unwrap_or_else(|_| {
            let mut padded = [0.0; B];
            padded[..part.len()].copy_from_slice(part);
            padded
        });
    }
    for k in 1..m {
        let g = matvec_t::<F, T>(&kept.gain_t[k - 1], &y[k - 1]);
        for i in 0..B {
            y[k][i] -= g[i];
        }
    }
    y[m - 1] = matvec_t::<F, T>(&kept.inverse_t[m - 1], &y[m - 1]);
    for k in (0..m - 1).rev() {
        let mut rest = y[k];
        let u = matvec_t::<F, T>(&kept.upper_t[k], &y[k + 1]);
        for i in 0..B {
            rest[i] -= u[i];
        }
        y[k] = matvec_t::<F, T>(&kept.inverse_t[k], &rest);
    }
    for k in 0..m {
        let part = &mut b[starts[k]..starts[k + 1]];
        match <&mut [f64; B]>::try_from(&mut *part) {
            Ok(full) => *full = y[k],
            Err(_) => part.copy_from_slice(&y[k][..part.len()]),
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::linalg::band_cholesky::tests::TestMatrix;
    use crate::linalg::band_cholesky::tests::{assert_paths_agree, block_tridiagonal};

    /// A block-tridiagonal matrix with node blocks of `sizes` (a pinned
    /// node has 9 unknowns): `diagonal` on the diagonal, off-diagonal
    /// entries in [−0.5, 0.5) varied by `seed`.
    fn uneven_blocks(sizes: &[usize], diagonal: f64, seed: usize) -> TestMatrix {
        let n: usize = sizes.iter().sum();
        let mut node = Vec::new();
        for (k, s) in sizes.iter().enumerate() {
            node.extend(std::iter::repeat_n(k, *s));
        }
        let coupled = |r: usize, c: usize| node[r].abs_diff(node[c]) <= 1;
        let mut dense = vec![0.0; n * n];
        for r in 0..n {
            for c in (0..n).filter(|&c| coupled(r, c)) {
                dense[r * n + c] = if r == c {
                    diagonal
                } else {
                    ((r * 13 + c * 7 + seed * 5) % 17) as f64 / 17.0 - 0.5
                };
            }
        }
        TestMatrix::new(n, dense, coupled)
    }

    /// The factorization's blocks, bit for bit.
    fn factor_bits(lu: &BlockTridiagonalLu) -> Vec<u64> {
        fn bits<T: Stored>(k: &Kept<T>, bits: impl Fn(T) -> u64) -> Vec<u64> {
            let blocks = k.inverse_t.iter().chain(&k.gain_t).chain(&k.upper_t);
            blocks.flatten().flatten().map(|&v| bits(v)).collect()
        }
        match lu.precision {
            Precision::Double => bits(&lu.double, f64::to_bits),
            Precision::Single => bits(&lu.single, |v| u64::from(v.to_bits())),
        }
    }

    #[test]
    fn finds_the_node_blocks_and_solves_to_round_off() {
        for (blocks, size) in [(1, 5), (3, 12), (6, 4), (20, 12)] {
            let a = block_tridiagonal(blocks, size, false);
            let mut lu =
                BlockTridiagonalLu::new(a.n, &a.col_ptr, &a.row_idx).expect("block tridiagonal");
            assert_eq!(lu.starts.len() - 1, blocks, "{blocks} blocks of {size}");
            let x: Vec<f64> = (0..a.n).map(|i| (i as f64 * 0.37).cos()).collect();
            assert_paths_agree(&a, &x, |path, b| {
                factorize(path, &mut lu, Source::Array(&a.values)).expect("regular");
                solve(path, &mut lu, b);
            });
        }
    }

    /// Blocks of different sizes (a pinned node has 9 unknowns), against
    /// the band LU on the same matrix.
    #[test]
    fn uneven_blocks_agree_with_the_band_lu() {
        let a = uneven_blocks(&[9, 12, 12, 12, 12], 40.0, 0);
        let n = a.n;
        let mut lu = BlockTridiagonalLu::new(n, &a.col_ptr, &a.row_idx).expect("block tridiagonal");
        assert_eq!(lu.starts, vec![0, 9, 21, 33, 45, 57]);
        lu.factorize(&a.values).unwrap();
        let mut band =
            crate::linalg::band_lu::BandLu::new(n, a.bandwidth(), &a.col_ptr, &a.row_idx);
        band.factorize(&a.values).unwrap();
        let b: Vec<f64> = (0..n).map(|i| (i as f64).sin()).collect();
        let (mut x1, mut x2) = (b.clone(), b.clone());
        lu.solve_in_place(&mut x1);
        band.solve_in_place(&mut x2);
        let diff = x1
            .iter()
            .zip(&x2)
            .map(|(p, q)| (p - q).abs())
            .fold(0.0, f64::max);
        assert!(diff < 1e-13, "{diff:e}");
    }

    /// A refactorization keeps nothing of the previous matrix (the blocks
    /// are not cleared in between): a factorization of B after one of A
    /// equals a fresh one of B bit for bit, padded nodes included.
    #[test]
    fn refactorization_keeps_nothing_of_the_previous_matrix() {
        let sizes = [9, 12, 12, 10, 12];
        let matrix = |seed: usize| uneven_blocks(&sizes, 30.0 + seed as f64, seed);
        let (a, b) = (matrix(1), matrix(4));
        let mut reused = BlockTridiagonalLu::new(a.n, &a.col_ptr, &a.row_idx).unwrap();
        reused.factorize(&a.values).unwrap();
        reused.factorize(&b.values).unwrap();
        let mut fresh = BlockTridiagonalLu::new(b.n, &b.col_ptr, &b.row_idx).unwrap();
        fresh.factorize(&b.values).unwrap();
        assert_eq!(factor_bits(&reused), factor_bits(&fresh));
        let rhs: Vec<f64> = (0..b.n).map(|i| (i as f64).cos()).collect();
        let (mut x1, mut x2) = (rhs.clone(), rhs);
        reused.solve_in_place(&mut x1);
        fresh.solve_in_place(&mut x2);
        assert_eq!(x1, x2);
    }

    /// A sum read where each block is loaded factors to the same bits as
    /// the sum written out; a non-finite part is refused.
    #[test]
    fn a_sum_factors_as_its_written_values() {
        let sizes = [9, 12, 12, 10, 12];
        let matrix = |seed: usize, diagonal: f64| uneven_blocks(&sizes, diagonal, seed);
        let (mass, stiffness, damping) = (matrix(1, 30.0), matrix(2, 3.0), matrix(3, 1.0));
        let parts = [&mass.values[..], &stiffness.values, &damping.values];
        let n = mass.n;
        let nnz = mass.values.len();
        for third_slots in [0..0, 40..300, 0..nnz] {
            let sum = ValueSum {
                parts,
                weights: [0.6, 0.37, 0.11],
                third_slots,
            };
            let mut written = vec![0.0; nnz];
            sum.write(&mut written);
            let mut from_sum = BlockTridiagonalLu::new(n, &mass.col_ptr, &mass.row_idx).unwrap();
            let mut from_array = from_sum.clone();
            from_sum.factorize_sum(&sum, Precision::Double).unwrap();
            from_array.factorize(&written).unwrap();
            assert_eq!(factor_bits(&from_sum), factor_bits(&from_array));
        }
        let mut broken = damping.values.clone();
        broken[nnz - 1] = f64::NAN;
        let sum = ValueSum {
            parts: [&mass.values, &stiffness.values, &broken],
            weights: [0.6, 0.37, 0.11],
            third_slots: 0..nnz,
        };
        let mut lu = BlockTridiagonalLu::new(n, &mass.col_ptr, &mass.row_idx).unwrap();
        assert!(lu.factorize_sum(&sum, Precision::Double).is_err());
        // Outside the third part's slots its values are not read.
        let sum = ValueSum {
            third_slots: 0..nnz - 1,
            ..sum
        };
        assert!(lu.factorize_sum(&sum, Precision::Double).is_ok());
    }

    /// Single precision keeps each entry of the double factorization
    /// rounded once (the elimination itself is the same), solves to f32's
    /// accuracy times the matrix's condition, and a double factorization
    /// after it has the bits of a fresh one.
    #[test]
    fn single_precision_keeps_the_double_factor_rounded_once() {
        let sizes = [9, 12, 12, 10, 12, 12];
        let (mass, stiffness) = (
            uneven_blocks(&sizes, 30.0, 1),
            uneven_blocks(&sizes, 3.0, 2),
        );
        let sum = ValueSum {
            parts: [&mass.values, &stiffness.values, &stiffness.values],
            weights: [0.6, 0.37, 0.0],
            third_slots: 0..0,
        };
        let n = mass.n;
        let mut double = BlockTridiagonalLu::new(n, &mass.col_ptr, &mass.row_idx).unwrap();
        let mut single = double.clone();
        double.factorize_sum(&sum, Precision::Double).unwrap();
        single.factorize_sum(&sum, Precision::Single).unwrap();
        assert_eq!(single.precision(), Precision::Single);
        let rounded: Vec<u64> = (factor_bits(&double).into_iter())
            .map(|b| u64::from((f64::from_bits(b) as f32).to_bits()))
            .collect();
        assert_eq!(factor_bits(&single), rounded);
        let b: Vec<f64> = (0..n).map(|i| (i as f64 * 0.7).sin() + 0.2).collect();
        let (mut x1, mut x2) = (b.clone(), b);
        double.solve_in_place(&mut x1);
        single.solve_in_place(&mut x2);
        let size = x1.iter().fold(0.0f64, |m, x| m.max(x.abs()));
        let diff = x1
            .iter()
            .zip(&x2)
            .fold(0.0f64, |m, (p, q)| m.max((p - q).abs()));
        // Rounded entries: a difference of f32's order, not of f64's.
        assert!(
            diff > 1e-12 * size && diff < 1e-6 * size,
            "{diff:e} of {size:e}"
        );
        let mut fresh = double.clone();
        single.factorize_sum(&sum, Precision::Double).unwrap();
        fresh.factorize_sum(&sum, Precision::Double).unwrap();
        assert_eq!(factor_bits(&single), factor_bits(&fresh));
        // `factorize` of an array keeps double precision.
        single.factorize_sum(&sum, Precision::Single).unwrap();
        let mut written = vec![0.0; mass.values.len()];
        sum.write(&mut written);
        single.factorize(&written).unwrap();
        assert_eq!(single.precision(), Precision::Double);
        assert_eq!(factor_bits(&single), factor_bits(&fresh));
    }

    #[test]
    fn refuses_what_is_not_block_tridiagonal_or_singular() {
        // Two coupled blocks of 12 look like one of 24 (every column spans
        // every row): refused, and the band LU takes such a one-element wire.
        let a = block_tridiagonal(2, 12, false);
        assert!(BlockTridiagonalLu::new(a.n, &a.col_ptr, &a.row_idx).is_none());
        // Column 0 couples rows 0 and 2 only: blocks {0}, {1}, {2} with a
        // (2, 0) entry two blocks away.
        let col_ptr = [0, 2, 3, 5];
        let row_idx = [0, 2, 1, 0, 2];
        assert!(BlockTridiagonalLu::new(3, &col_ptr, &row_idx).is_none());
        // A zero 2 × 2 block.
        let mut lu = BlockTridiagonalLu::new(2, &[0, 2, 4], &[0, 1, 0, 1]).unwrap();
        assert!(lu.factorize(&[0.0; 4]).is_err());
    }
}
