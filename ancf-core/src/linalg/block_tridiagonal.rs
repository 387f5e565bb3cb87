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
//! The elimination runs on the transposes of these recurrences, which is
//! what the solves keep (their products go column by column) and how the
//! compressed columns load (a column's part of a block is one run of
//! slots); every entry is the same sum in the same order as untransposed.
//!
//! From [`TWIST_MIN_NODES`] nodes on, the elimination runs from both ends
//! towards the middle node t (a "twisted" factorization): the top chain as
//! above over nodes 0 … t − 1, the bottom chain the same recurrences on
//! the reversed matrix over m − 1 … t + 1 (Tₖ = Dₖ − Hₖ₊₁ Lₖ, Hₖ = Uₖ₋₁
//! Tₖ⁻¹), and node t last, Sₜ = Dₜ − Gₜ₋₁ Uₜ₋₁ − Hₜ₊₁ Lₜ. The two chains
//! are independent, and so are their halves of each solve's forward and
//! backward passes: they run on two threads. Below that size the meeting
//! node is the last one, which is the single chain above.
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
use crate::linalg::parallel::run_tasks;
use crate::linalg::value_sum::{SlotValues, ValueSum, all_finite};
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

/// Per node k, transposed for the solves' column-oriented products: its
/// Schur complement's inverse, its gain towards the meeting node (Gₖ or
/// Hₖ; none at the meeting node), and its coupling to the node eliminated
/// after it (Uₖ in the top chain, Lₖ₋₁ in the bottom one; none at the
/// meeting node). (The untransposed Sₖ⁻¹ and Gₖ are needed only for the
/// next block: the factorization keeps them on the stack, 2 · 1152 bytes a
/// node less to write.)
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
            gain_t: vec![zero; m],
            upper_t: vec![zero; m],
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
    /// column node k, transposed, [Uₖ₋₁ᵀ, Dₖᵀ, Lₖᵀ] row-major one after
    /// the other (0 … 431): the factorization reads the values front to
    /// back into three blocks on the stack. Transposed, a column's part in
    /// one block is a contiguous run. (Read in the blocks' order instead,
    /// every value was a cache line of its own: the loads missed.)
    places: Vec<u16>,
    /// Whether node k's columns fill its blocks in runs of twelve slots to
    /// twelve places (all but the nodes at a support or beside a gap
    /// between two beams): they are then copied run by run and
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
    /// The node where the two chains of the elimination meet
    /// ([`meeting_node`]).
    meet: usize,
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
            places[v] = (block * B * B + lc * B + lr) as u16;
        }
        let node_values: Vec<usize> = starts.iter().map(|&c| col_ptr[c]).collect();
        let full = (0..m)
            .map(|k| {
                let blocks = 1 + usize::from(k > 0) + usize::from(k + 1 < m);
                let node = &places[node_values[k]..node_values[k + 1]];
                node.len() == blocks * B * B
                    && (node.chunks(B)).all(|run| run.iter().zip(run[0]..).all(|(&p, q)| p == q))
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
            meet: meeting_node(m),
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

    /// The matrix with slot values `values` (an array over the pattern,
    /// or a [`ValueSum`] never formed) by blocks, padded (a node's missing
    /// unknowns have the identity): the diagonal blocks Dₖ, the upper
    /// Uₖ = A₍ₖ,ₖ₊₁₎ and the lower Lₖ = A₍ₖ₊₁,ₖ₎ (untransposed, for the
    /// separated LU); `None` when a value is not finite. From
    /// [`TWIST_MIN_NODES`] nodes on, in two halves on two threads.
    #[allow(clippy::type_complexity)]
    pub(crate) fn load<V: SlotValues + ?Sized + Sync>(
        &mut self,
        values: &V,
    ) -> Option<(&[Block], &[Block], &[Block])> {
        let m = self.nodes();
        let mut input = std::mem::take(&mut self.input);
        input.resize(3 * m - 2, ZERO);
        let (diag, rest) = input.split_at_mut(m);
        let (upper, lower) = rest.split_at_mut(m - 1);
        // Node k writes Dₖ, Uₖ₋₁ and Lₖ: the halves' windows are disjoint.
        let half = if m >= TWIST_MIN_NODES { m / 2 } else { m };
        let (diag_a, diag_b) = diag.split_at_mut(half);
        let (upper_a, upper_b) = upper.split_at_mut(half.saturating_sub(1));
        let (lower_a, lower_b) = lower.split_at_mut(half.min(m - 1));
        let mut halves = vec![(0..half, diag_a, upper_a, lower_a)];
        if half < m {
            halves.push((half..m, diag_b, upper_b, lower_b));
        }
        let lu = &*self;
        let finite = run_tasks(halves, |(nodes, diag, upper, lower)| {
            let first = nodes.start;
            let mut columns = [ZERO; 3];
            let mut finite = true;
            for k in nodes {
                finite &= load_node(lu, k, values, &mut columns);
                transpose(&columns[1], &mut diag[k - first]);
                if k > 0 {
                    transpose(&columns[0], &mut upper[k - first.max(1)]);
                }
                if k + 1 < m {
                    transpose(&columns[2], &mut lower[k - first]);
                }
            }
            finite
        });
        self.input = input;
        if !finite.into_iter().all(|f| f) {
            return None;
        }
        let (diag, rest) = self.input.split_at(m);
        let (upper, lower) = rest.split_at(m - 1);
        Some((diag, upper, lower))
    }
}

/// Where a factorization reads the matrix's values.
#[derive(Clone, Copy)]
enum Source<'a> {
    Array(&'a [f64]),
    Sum(&'a ValueSum<'a>),
}

/// Node k's columns of the matrix with slot values `values` into its
/// three blocks, transposed, [Uₖ₋₁ᵀ, Dₖᵀ, Lₖᵀ] (`out`, written over),
/// padded: a node's missing unknowns have the identity on Dₖ; entries
/// outside the pattern are zero (Uₖ₋₁ of the first node and Lₖ of the last
/// are left as they were). False when a value is not finite.
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
    let out = out.as_flattened_mut().as_flattened_mut();
    if lu.full[k] {
        for (start, run) in slots.step_by(B).zip(places.chunks(B)) {
            let at = usize::from(run[0]);
            let run: &mut [f64; B] = (&mut out[at..at + B]).try_into().expect("a run of B");
            values.copy_run(start, run);
        }
    } else {
        values.scatter(slots, places, out);
    }
    // The blocks not written keep finite values: the padding's, or those
    // of a node loaded and checked before.
    all_finite(out)
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
pub(crate) fn matvec_t<F: Arith, T: Stored>(at: &[[T; B]; B], x: &[f64; B]) -> [f64; B] {
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

/// `a` kept in t's precision (each entry rounded once), written over t.
#[inline(always)]
fn keep<T: Stored>(a: &Block, t: &mut [[T; B]; B]) {
    for (a, t) in a.iter().zip(t.iter_mut()) {
        for (a, t) in a.iter().zip(t.iter_mut()) {
            *t = T::store(*a);
        }
    }
}

/// t = aᵀ, written over t (each entry rounded to t's precision).
#[inline(always)]
pub(crate) fn transpose<T: Stored>(a: &Block, t: &mut [[T; B]; B]) {
    for i in 0..B {
        for j in 0..B {
            t[j][i] = T::store(a[i][j]);
        }
    }
}

/// Row `c`: ones but for a zero at column c ([`invert_transposed`]'s
/// pivot position).
const KEEP: Block = {
    let mut t = [[1.0; B]; B];
    let mut c = 0;
    while c < B {
        t[c][c] = 0.0;
        c += 1;
    }
    t
};

/// Row `c`: the unit row e_c (the identity's).
const UNIT: Block = {
    let mut t = ZERO;
    let mut c = 0;
    while c < B {
        t[c][c] = 1.0;
        c += 1;
    }
    t
};

/// (S⁻¹)ᵀ from `st` = Sᵀ, written over `inv_t`: Gauss–Jordan elimination
/// of S with partial pivoting (rows of S), carried out on Sᵀ, whose rows
/// are S's columns. Each row operation on S, row r −= S₍ᵣ,c₎ · (pivot row),
/// is on Sᵀ one multiply-add of every row i by its own scalar (S's scaled
/// pivot-row entry, Sᵀ₍ᵢ,c₎ / pivot) with the same vector of multipliers
/// (Sᵀ's row c): twelve-wide, in place, each entry the same operation on
/// the same values as [S | I] reduced to [I | S⁻¹] (the column a pivot
/// clears holds from then on the column of the inverse that the identity's
/// column of the pivot row becomes; that form is half zeros and ones).
/// Row swaps of S are column swaps of Sᵀ, and, undone last in reverse
/// order, row swaps of (S⁻¹)ᵀ.
#[inline(always)]
pub(crate) fn invert_transposed<F: Arith>(
    st: &Block,
    inv_t: &mut Block,
) -> Result<(), SingularBlock> {
    let m = inv_t;
    *m = *st;
    // max |s_ij| in twelve running maxima (the maximum is exact in any
    // order; one running maximum waited on each compare).
    let mut column_max = [0.0f64; B];
    for row in st {
        for (m, v) in column_max.iter_mut().zip(row) {
            *m = m.max(v.abs());
        }
    }
    let scale = column_max.iter().fold(0.0f64, |m, v| m.max(*v));
    let mut pivot_rows = [0usize; B];
    for col in 0..B {
        // S's column `col` is Sᵀ's row.
        let pivot_row = (col..B)
            .max_by(|&p, &q| m[col][p].abs().total_cmp(&m[col][q].abs()))
            .unwrap_or(col);
        let pivot = m[col][pivot_row];
        if !pivot.is_finite() || pivot.abs() <= 1e-14 * scale {
            return Err(SingularBlock);
        }
        if pivot_row != col {
            for row in m.iter_mut() {
                row.swap(col, pivot_row);
            }
        }
        pivot_rows[col] = pivot_row;
        let p = 1.0 / pivot;
        // The negated multipliers −S₍ᵣ,c₎ (Sᵀ's row c before it is
        // cleared), and 1 at r = c, where the pivot row's entry s is kept:
        // 1 · s + 0. (Tables, not a branch on r, which turns the rows
        // scalar, nor a store into the row, which stalls its vector load.)
        let mut neg_f = [0.0; B];
        for (((n, f), k), u) in neg_f
            .iter_mut()
            .zip(&m[col])
            .zip(&KEEP[col])
            .zip(&UNIT[col])
        {
            *n = u - f * k;
        }
        for (i, row) in m.iter_mut().enumerate() {
            // S's pivot row, scaled: its entry i (the identity's 1 at
            // i = c), and the cleared column (i = c) starting from 0.
            let (s, keep) = if i == col {
                (p, &[0.0; B])
            } else {
                (row[col] * p, &KEEP[col])
            };
            for ((x, n), k) in row.iter_mut().zip(&neg_f).zip(keep) {
                *x = F::mul_add(*n, s, *x * k);
            }
        }
    }
    for col in (0..B).rev() {
        let p = pivot_rows[col];
        if p != col {
            m.swap(col, p);
        }
    }
    Ok(())
}

/// From this many nodes on, the factorization eliminates from both ends
/// towards the middle node, and the two chains — the factorization's and
/// each solve's forward and backward passes — run on two threads. Decided
/// by the size alone, so that results never depend on the thread count.
/// (≈ 250 elements of a wire: a solve of the 1000-element span break takes
/// ≈ 160 µs, so a half there is long against a hand-off to the helper
/// thread; shorter models keep the one chain.)
pub const TWIST_MIN_NODES: usize = 256;

/// The node where the two chains meet: the middle from
/// [`TWIST_MIN_NODES`] on, else the last node (one chain, from the first).
fn meeting_node(m: usize) -> usize {
    if m >= TWIST_MIN_NODES { m / 2 } else { m - 1 }
}

/// One chain's windows of the kept blocks, indexed by node − `first`:
/// the top chain's nodes 0 … t − 1, eliminated in increasing order, or the
/// bottom chain's t + 1 … m − 1, eliminated in decreasing order.
struct Chain<'a, T> {
    first: usize,
    reversed: bool,
    inverse_t: &'a mut [[[T; B]; B]],
    gain_t: &'a mut [[[T; B]; B]],
    upper_t: &'a mut [[[T; B]; B]],
}

impl<T> Chain<'_, T> {
    fn len(&self) -> usize {
        self.inverse_t.len()
    }
    /// The chain's nodes in the order of elimination.
    fn nodes(&self) -> impl Iterator<Item = usize> + use<T> {
        let (first, n, reversed) = (self.first, self.len(), self.reversed);
        (0..n).map(move |i| {
            if reversed {
                first + n - 1 - i
            } else {
                first + i
            }
        })
    }
}

/// The two chains of `kept` around the meeting node `t`, and the meeting
/// node's inverse.
#[allow(clippy::type_complexity)]
fn chains<T>(kept: &mut Kept<T>, t: usize) -> (Chain<'_, T>, Chain<'_, T>, &mut [[T; B]; B]) {
    let (inverse_top, inverse_rest) = kept.inverse_t.split_at_mut(t);
    let (inverse_meet, inverse_bottom) = inverse_rest.split_first_mut().expect("meeting node");
    let (gain_top, gain_rest) = kept.gain_t.split_at_mut(t);
    let (upper_top, upper_rest) = kept.upper_t.split_at_mut(t);
    let top = Chain {
        first: 0,
        reversed: false,
        inverse_t: inverse_top,
        gain_t: gain_top,
        upper_t: upper_top,
    };
    let bottom = Chain {
        first: t + 1,
        reversed: true,
        inverse_t: inverse_bottom,
        gain_t: &mut gain_rest[1..],
        upper_t: &mut upper_rest[1..],
    };
    (top, bottom, inverse_meet)
}

/// A chain's windows in either precision, for the dispatched kernels.
enum AnyChain<'a> {
    Double(Chain<'a, f64>),
    Single(Chain<'a, f32>),
}

crate::simd_dispatch! {
    fn eliminate(lu: &BlockTridiagonalLu, values: Source, chain: AnyChain) -> Result<Block, SingularBlock> = eliminate_with;
}

#[inline(always)]
fn eliminate_with<F: Arith>(
    lu: &BlockTridiagonalLu,
    values: Source,
    chain: AnyChain,
) -> Result<Block, SingularBlock> {
    match (values, chain) {
        (Source::Array(a), AnyChain::Double(c)) => eliminate_chain::<F, [f64], f64>(lu, a, c),
        (Source::Array(a), AnyChain::Single(c)) => eliminate_chain::<F, [f64], f32>(lu, a, c),
        (Source::Sum(s), AnyChain::Double(c)) => eliminate_chain::<F, ValueSum, f64>(lu, s, c),
        (Source::Sum(s), AnyChain::Single(c)) => eliminate_chain::<F, ValueSum, f32>(lu, s, c),
    }
}

/// One chain's elimination, node k's columns [Uₖ₋₁, Dₖ, Lₖ] loaded at its
/// step (into the stack: the blocks are never stored whole). The top chain
/// is the recurrence of the module doc; the bottom chain the same on the
/// reversed matrix, where Lₖ couples a node to the one eliminated before it
/// and Uₖ₋₁ to the one after:
///
///   Tₖ = Dₖ − Hₖ₊₁ Lₖ,  Hₖ = Uₖ₋₁ Tₖ⁻¹.
///
/// Each node keeps its inverse and its gain towards the meeting node, and
/// the node eliminated before it its coupling to this one (for the
/// backward pass). The recurrence runs on the transposes, which are what
/// the solves keep and what loads in runs: Sₖᵀ = Dₖᵀ − Uₖ₋₁ᵀ Gₖ₋₁ᵀ,
/// Gₖᵀ = Sₖ⁻ᵀ Lₖᵀ, each entry the same sum in the same order as
/// untransposed. Returns the last gain's transpose (Gₜ₋₁ᵀ or Hₜ₊₁ᵀ)
/// unrounded, for the meeting node.
#[inline(always)]
fn eliminate_chain<F: Arith, V: SlotValues + ?Sized, T: Stored>(
    lu: &BlockTridiagonalLu,
    values: &V,
    chain: Chain<T>,
) -> Result<Block, SingularBlock> {
    let mut columns = [ZERO; 3];
    let (mut inverse, mut gain) = (ZERO, ZERO);
    let mut previous = None;
    for k in chain.nodes() {
        if !load_node(lu, k, values, &mut columns) {
            return Err(SingularBlock);
        }
        let [upper, s, lower] = &mut columns;
        let (incoming, outgoing) = if chain.reversed {
            (&*lower, &*upper)
        } else {
            (&*upper, &*lower)
        };
        if let Some(p) = previous {
            // Sₖᵀ = Dₖᵀ − Uₖ₋₁ᵀ Gₖ₋₁ᵀ (`gain` is the previous node's here).
            sub_product::<F>(s, incoming, &gain);
            keep(incoming, &mut chain.upper_t[p - chain.first]);
        }
        // Results written in place: returned by value, each 1152-byte
        // block was a memcpy more.
        invert_transposed::<F>(s, &mut inverse)?;
        keep(&inverse, &mut chain.inverse_t[k - chain.first]);
        product::<F>(&inverse, outgoing, &mut gain);
        keep(&gain, &mut chain.gain_t[k - chain.first]);
        previous = Some(k);
    }
    Ok(gain)
}

crate::simd_dispatch! {
    fn meet(lu: &BlockTridiagonalLu, values: Source, gains: [Option<&Block>; 2], out: MeetOut) -> Result<(), SingularBlock> = meet_with;
}

/// Where the meeting node's elimination writes: its inverse, and the
/// couplings to it that the two chains' backward passes read.
enum MeetOut<'a> {
    Double([Option<&'a mut [[f64; B]; B]>; 3]),
    Single([Option<&'a mut [[f32; B]; B]>; 3]),
}

/// The meeting node t: Sₜ = Dₜ − Gₜ₋₁ Uₜ₋₁ − Hₜ₊₁ Lₜ, inverted, with
/// the gains of the two chains' last nodes (`gains`, transposed, None for
/// an empty chain), on the transposes as the chains. `out` is [Sₜ⁻¹ᵀ,
/// slot of Uₜ₋₁ᵀ, slot of Lₜᵀ].
#[inline(always)]
fn meet_with<F: Arith>(
    lu: &BlockTridiagonalLu,
    values: Source,
    gains: [Option<&Block>; 2],
    out: MeetOut,
) -> Result<(), SingularBlock> {
    let mut columns = [ZERO; 3];
    let loaded = match values {
        Source::Array(a) => load_node(lu, lu.meet, a, &mut columns),
        Source::Sum(s) => load_node(lu, lu.meet, s, &mut columns),
    };
    if !loaded {
        return Err(SingularBlock);
    }
    let [upper, s, lower] = &mut columns;
    if let Some(g) = gains[0] {
        sub_product::<F>(s, upper, g);
    }
    if let Some(h) = gains[1] {
        sub_product::<F>(s, lower, h);
    }
    let mut inverse = ZERO;
    invert_transposed::<F>(s, &mut inverse)?;
    match out {
        MeetOut::Double([inv, u, l]) => store_meet(&inverse, upper, lower, [inv, u, l]),
        MeetOut::Single([inv, u, l]) => store_meet(&inverse, upper, lower, [inv, u, l]),
    }
    Ok(())
}

/// The meeting node's kept blocks (all three transposed already).
#[inline(always)]
fn store_meet<T: Stored>(
    inverse: &Block,
    upper: &Block,
    lower: &Block,
    [inv, u, l]: [Option<&mut [[T; B]; B]>; 3],
) {
    if let Some(inv) = inv {
        keep(inverse, inv);
    }
    if let Some(u) = u {
        keep(upper, u);
    }
    if let Some(l) = l {
        keep(lower, l);
    }
}

/// The kept blocks' precisions, for the dispatched kernels.
trait Keep: Stored + Send + Sync {
    fn kept(lu: &mut BlockTridiagonalLu) -> &mut Kept<Self>;
    fn chain(c: Chain<'_, Self>) -> AnyChain<'_>;
    fn meet_out<'a>(out: [Option<&'a mut [[Self; B]; B]>; 3]) -> MeetOut<'a>;
}

impl Keep for f64 {
    fn kept(lu: &mut BlockTridiagonalLu) -> &mut Kept<Self> {
        &mut lu.double
    }
    fn chain(c: Chain<'_, Self>) -> AnyChain<'_> {
        AnyChain::Double(c)
    }
    fn meet_out<'a>(out: [Option<&'a mut [[Self; B]; B]>; 3]) -> MeetOut<'a> {
        MeetOut::Double(out)
    }
}

impl Keep for f32 {
    fn kept(lu: &mut BlockTridiagonalLu) -> &mut Kept<Self> {
        &mut lu.single
    }
    fn chain(c: Chain<'_, Self>) -> AnyChain<'_> {
        AnyChain::Single(c)
    }
    fn meet_out<'a>(out: [Option<&'a mut [[Self; B]; B]>; 3]) -> MeetOut<'a> {
        MeetOut::Single(out)
    }
}

/// The factorization: the two chains (in parallel when both are there),
/// then the meeting node.
fn factorize(
    path: SimdPath,
    lu: &mut BlockTridiagonalLu,
    values: Source,
) -> Result<(), SingularBlock> {
    match lu.precision {
        Precision::Double => factorize_kept::<f64>(path, lu, values),
        Precision::Single => factorize_kept::<f32>(path, lu, values),
    }
}

/// The elimination into the blocks of precision `T` (taken out of `lu` for
/// its duration: the elimination reads `lu`'s maps).
fn factorize_kept<T: Keep>(
    path: SimdPath,
    lu: &mut BlockTridiagonalLu,
    values: Source,
) -> Result<(), SingularBlock> {
    let mut blocks = std::mem::take(T::kept(lu));
    let done = factorize_into(path, lu, values, &mut blocks);
    *T::kept(lu) = blocks;
    done
}

fn factorize_into<T: Keep>(
    path: SimdPath,
    lu: &BlockTridiagonalLu,
    values: Source,
    blocks: &mut Kept<T>,
) -> Result<(), SingularBlock> {
    let (t, m) = (lu.meet, lu.nodes());
    let (top, bottom, _) = chains(blocks, t);
    let gains = if bottom.len() == 0 {
        vec![eliminate(path, lu, values, T::chain(top))]
    } else {
        let chains = vec![T::chain(top), T::chain(bottom)];
        run_tasks(chains, |c| eliminate(path, lu, values, c))
    };
    let mut gains = gains
        .into_iter()
        .collect::<Result<Vec<_>, _>>()?
        .into_iter();
    let top_gain = if t > 0 { gains.next() } else { None };
    let bottom_gain = if t + 1 < m { gains.next() } else { None };
    let (top, bottom, inverse) = chains(blocks, t);
    let out = [
        Some(inverse),
        top.upper_t.last_mut(),
        bottom.upper_t.first_mut(),
    ];
    let gains = [top_gain.as_ref(), bottom_gain.as_ref()];
    meet(path, lu, values, gains, T::meet_out(out))
}

/// One chain's part of a solve: its kept blocks (see [`Chain`]) and its
/// nodes' blocks of the right-hand side, `y` by node and `b` as given.
struct ChainSolve<'a, T> {
    reversed: bool,
    inverse_t: &'a [[[T; B]; B]],
    gain_t: &'a [[[T; B]; B]],
    upper_t: &'a [[[T; B]; B]],
    /// The chain's node starts (one more than its nodes); its window of
    /// `b` begins at the first.
    starts: &'a [usize],
    y: &'a mut [[f64; B]],
    b: &'a mut [f64],
}

impl<T> ChainSolve<'_, T> {
    /// Local node indices in the order of elimination.
    fn order(&self) -> impl DoubleEndedIterator<Item = usize> + use<T> {
        let (n, reversed) = (self.y.len(), self.reversed);
        (0..n).map(move |i| if reversed { n - 1 - i } else { i })
    }
}

/// A chain's part of a solve in either precision, for the dispatched kernels.
enum AnyChainSolve<'a> {
    Double(ChainSolve<'a, f64>),
    Single(ChainSolve<'a, f32>),
}

/// The meeting node's part of a solve.
struct MeetSolve<'a> {
    inverse: MeetInverse<'a>,
    b: &'a mut [f64],
}

enum MeetInverse<'a> {
    Double(&'a [[f64; B]; B]),
    Single(&'a [[f32; B]; B]),
}

/// The solve's windows: the two chains and the meeting node.
fn chain_solves<'a>(
    lu: &'a mut BlockTridiagonalLu,
    b: &'a mut [f64],
) -> (AnyChainSolve<'a>, AnyChainSolve<'a>, MeetSolve<'a>) {
    let (t, starts) = (lu.meet, &lu.starts);
    let (b_top, b_rest) = b.split_at_mut(starts[t]);
    let (b_meet, b_bottom) = b_rest.split_at_mut(starts[t + 1] - starts[t]);
    let (y_top, y_rest) = lu.work.split_at_mut(t);
    let y_bottom = &mut y_rest[1..];
    let (starts_top, starts_bottom) = (&starts[..=t], &starts[t + 1..]);
    fn split<'a, T>(
        kept: &'a Kept<T>,
        t: usize,
        [starts_top, starts_bottom]: [&'a [usize]; 2],
        [y_top, y_bottom]: [&'a mut [[f64; B]]; 2],
        [b_top, b_bottom]: [&'a mut [f64]; 2],
    ) -> [ChainSolve<'a, T>; 2] {
        [
            ChainSolve {
                reversed: false,
                inverse_t: &kept.inverse_t[..t],
                gain_t: &kept.gain_t[..t],
                upper_t: &kept.upper_t[..t],
                starts: starts_top,
                y: y_top,
                b: b_top,
            },
            ChainSolve {
                reversed: true,
                inverse_t: &kept.inverse_t[t + 1..],
                gain_t: &kept.gain_t[t + 1..],
                upper_t: &kept.upper_t[t + 1..],
                starts: starts_bottom,
                y: y_bottom,
                b: b_bottom,
            },
        ]
    }
    let parts = (
        [starts_top, starts_bottom],
        [y_top, y_bottom],
        [b_top, b_bottom],
    );
    let (top, bottom, inverse) = match lu.precision {
        Precision::Double => {
            let [top, bottom] = split(&lu.double, t, parts.0, parts.1, parts.2);
            let inverse = MeetInverse::Double(&lu.double.inverse_t[t]);
            (
                AnyChainSolve::Double(top),
                AnyChainSolve::Double(bottom),
                inverse,
            )
        }
        Precision::Single => {
            let [top, bottom] = split(&lu.single, t, parts.0, parts.1, parts.2);
            let inverse = MeetInverse::Single(&lu.single.inverse_t[t]);
            (
                AnyChainSolve::Single(top),
                AnyChainSolve::Single(bottom),
                inverse,
            )
        }
    };
    let meet = MeetSolve { inverse, b: b_meet };
    (top, bottom, meet)
}

crate::simd_dispatch! {
    fn forward(chain: AnyChainSolve) -> Option<[f64; B]> = forward_with;
}

crate::simd_dispatch! {
    fn backward(chain: AnyChainSolve, x: &[f64; B]) = backward_with;
}

crate::simd_dispatch! {
    fn meet_solve(meet: MeetSolve, parts: [Option<[f64; B]>; 2]) -> [f64; B] = meet_solve_with;
}

#[inline(always)]
fn forward_with<F: Arith>(chain: AnyChainSolve) -> Option<[f64; B]> {
    match chain {
        AnyChainSolve::Double(c) => forward_chain::<F, f64>(c),
        AnyChainSolve::Single(c) => forward_chain::<F, f32>(c),
    }
}

#[inline(always)]
fn backward_with<F: Arith>(chain: AnyChainSolve, x: &[f64; B]) {
    match chain {
        AnyChainSolve::Double(c) => backward_chain::<F, f64>(c, x),
        AnyChainSolve::Single(c) => backward_chain::<F, f32>(c, x),
    }
}

/// The right-hand side's blocks into `y` (padded), and the forward pass
/// along the chain: yₖ −= Gₚ yₚ (p the node eliminated before k). Returns
/// what the chain's last node leaves on the meeting node, G y of that node
/// (None for an empty chain).
#[inline(always)]
fn forward_chain<F: Arith, T: Stored>(c: ChainSolve<T>) -> Option<[f64; B]> {
    let s0 = c.starts[0];
    for (k, w) in c.starts.windows(2).enumerate() {
        c.y[k] = load_block(&c.b[w[0] - s0..w[1] - s0]);
    }
    let mut previous: Option<usize> = None;
    for k in c.order() {
        if let Some(p) = previous {
            let g = matvec_t::<F, T>(&c.gain_t[p], &c.y[p]);
            for i in 0..B {
                c.y[k][i] -= g[i];
            }
        }
        previous = Some(k);
    }
    // A match, not `Option::map`: the closure was not inlined into the
    // dispatched function, and its multiply-adds became calls.
    match previous {
        Some(p) => Some(matvec_t::<F, T>(&c.gain_t[p], &c.y[p])),
        None => None,
    }
}

/// The backward pass from the meeting node's solution `x`, in the reverse
/// order of elimination: xₖ = Sₖ⁻¹ (yₖ − Cₖ xₙ) (n the node eliminated
/// after k, Cₖ the coupling stored at k), and the result into `b`.
#[inline(always)]
fn backward_chain<F: Arith, T: Stored>(c: ChainSolve<T>, x: &[f64; B]) {
    let mut next = *x;
    for k in c.order().rev() {
        let mut rest = c.y[k];
        let u = matvec_t::<F, T>(&c.upper_t[k], &next);
        for i in 0..B {
            rest[i] -= u[i];
        }
        c.y[k] = matvec_t::<F, T>(&c.inverse_t[k], &rest);
        next = c.y[k];
    }
    let s0 = c.starts[0];
    for (k, w) in c.starts.windows(2).enumerate() {
        store_block(&mut c.b[w[0] - s0..w[1] - s0], &c.y[k]);
    }
}

/// A node's part of a right-hand side as a padded block. Full blocks are
/// copied as fixed-size arrays (a copy of a run-time length was a call to
/// memmove per block: 1.4 % of the span-break scene).
#[inline(always)]
pub(crate) fn load_block(part: &[f64]) -> [f64; B] {
    <[f64; B]>::try_from(part).unwrap_or_else(|_| {
        let mut padded = [0.0; B];
        padded[..part.len()].copy_from_slice(part);
        padded
    })
}

/// A padded block back into a node's part of a vector (see [`load_block`]).
#[inline(always)]
pub(crate) fn store_block(part: &mut [f64], y: &[f64; B]) {
    match <&mut [f64; B]>::try_from(&mut *part) {
        Ok(full) => *full = *y,
        Err(_) => part.copy_from_slice(&y[..part.len()]),
    }
}

/// The meeting node: yₜ −= what the two chains left on it, xₜ = Sₜ⁻¹ yₜ,
/// into `b` and returned.
#[inline(always)]
fn meet_solve_with<F: Arith>(meet: MeetSolve, parts: [Option<[f64; B]>; 2]) -> [f64; B] {
    let mut y = load_block(meet.b);
    for g in parts.into_iter().flatten() {
        for i in 0..B {
            y[i] -= g[i];
        }
    }
    let x = match meet.inverse {
        MeetInverse::Double(inv) => matvec_t::<F, f64>(inv, &y),
        MeetInverse::Single(inv) => matvec_t::<F, f32>(inv, &y),
    };
    store_block(meet.b, &x);
    x
}

/// The solves on `path`, except that the AVX-512 path runs the AVX2 code:
/// their 12-lane matrix–vector products, chained block after block, run
/// faster as three 256-bit vectors than as a 512-bit and a 256-bit one.
/// Both are the fused path's operations: the same bits. The two chains'
/// forward passes run in parallel, then the meeting node, then their
/// backward passes in parallel.
fn solve(path: SimdPath, lu: &mut BlockTridiagonalLu, b: &mut [f64]) {
    let path = if path == SimdPath::Avx512 {
        SimdPath::Avx2
    } else {
        path
    };
    let twisted = lu.meet + 1 < lu.nodes();
    let (top, bottom, meet) = chain_solves(lu, b);
    let parts = if twisted {
        let parts = run_tasks(vec![top, bottom], |c| forward(path, c));
        [parts[0], parts[1]]
    } else {
        [forward(path, top), None]
    };
    let x = meet_solve(path, meet, parts);
    let (top, bottom, _) = chain_solves(lu, b);
    if twisted {
        run_tasks(vec![top, bottom], |c| backward(path, c, &x));
    } else {
        backward(path, top, &x);
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

    /// [S | I] reduced to [I | S⁻¹], the textbook form of [`invert_transposed`].
    fn invert_augmented(s: &Block) -> Option<Block> {
        let mut m = [[0.0f64; 2 * B]; B];
        for (i, row) in m.iter_mut().enumerate() {
            row[..B].copy_from_slice(&s[i]);
            row[B + i] = 1.0;
        }
        let scale = s.iter().flatten().fold(0.0f64, |m, v| m.max(v.abs()));
        for col in 0..B {
            let pivot_row = (col..B)
                .max_by(|&p, &q| m[p][col].abs().total_cmp(&m[q][col].abs()))
                .unwrap_or(col);
            let pivot = m[pivot_row][col];
            if !pivot.is_finite() || pivot.abs() <= 1e-14 * scale {
                return None;
            }
            m.swap(col, pivot_row);
            let p = 1.0 / pivot;
            m[col].iter_mut().for_each(|x| *x *= p);
            let pr = m[col];
            for (r, row) in m.iter_mut().enumerate() {
                if r != col {
                    let f = row[col];
                    row.iter_mut()
                        .zip(&pr)
                        .for_each(|(x, y)| *x = (-f).mul_add(*y, *x));
                }
            }
        }
        let mut inv = ZERO;
        for (i, row) in inv.iter_mut().enumerate() {
            row.copy_from_slice(&m[i][B..]);
        }
        Some(inv)
    }

    #[test]
    fn inverts_in_place_as_the_augmented_reduction_does() {
        use crate::math::simd::Fused;
        let mut pivoted = 0;
        for seed in 0..200u64 {
            // Entries in [−1, 1) from a linear congruential sequence; every
            // fourth matrix with a weak diagonal, so that rows are swapped.
            let mut state = seed
                .wrapping_mul(6364136223846793005)
                .wrapping_add(1442695040888963407);
            let mut next = || {
                state = state
                    .wrapping_mul(6364136223846793005)
                    .wrapping_add(1442695040888963407);
                (state >> 11) as f64 / (1u64 << 53) as f64 * 2.0 - 1.0
            };
            let mut s = ZERO;
            for i in 0..B {
                for j in 0..B {
                    s[i][j] = next();
                }
                if seed % 4 != 0 {
                    s[i][i] += 6.0;
                }
            }
            let expected = invert_augmented(&s).expect("regular");
            let (mut st, mut inv_t, mut inv) = (ZERO, ZERO, ZERO);
            transpose(&s, &mut st);
            invert_transposed::<Fused>(&st, &mut inv_t).expect("regular");
            transpose(&inv_t, &mut inv);
            // Equal values (a zero's sign may differ: the augmented form
            // scales zeros by negative pivots).
            assert_eq!(inv, expected, "seed {seed}");
            for i in 0..B {
                for j in 0..B {
                    let sij: f64 = (0..B).map(|k| s[i][k] * inv[k][j]).sum();
                    let delta = if i == j { 1.0 } else { 0.0 };
                    assert!(
                        (sij - delta).abs() < 1e-12,
                        "seed {seed}: (S S⁻¹)[{i}][{j}] = {sij}"
                    );
                }
            }
            pivoted += usize::from(
                (0..B).any(|c| s[c][c].abs() < s.iter().map(|r| r[c].abs()).fold(0.0, f64::max)),
            );
        }
        assert!(pivoted > 20, "only {pivoted} matrices needed row swaps");
        let mut singular = ZERO;
        singular[3][3] = 1.0;
        assert!(invert_transposed::<Fused>(&singular, &mut ZERO.clone()).is_err());
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

    /// Node sizes of a model long enough for two chains: a pinned first
    /// node, uneven interior nodes (the padding inside both chains and at
    /// the meeting node), a pinned last node.
    fn long_sizes(m: usize) -> Vec<usize> {
        (0..m)
            .map(|k| match k {
                0 => 3,
                _ if k + 1 == m => 2,
                _ => 2 + (k * 7) % 4,
            })
            .collect()
    }

    /// From `TWIST_MIN_NODES` on the elimination runs from both ends to the
    /// middle node; it solves to round-off on every path, as the band LU
    /// does, for an odd and an even number of nodes.
    #[test]
    fn two_chains_solve_to_round_off_on_every_path() {
        for m in [TWIST_MIN_NODES, TWIST_MIN_NODES + 1] {
            let a = uneven_blocks(&long_sizes(m), 12.0, 3);
            let mut lu = BlockTridiagonalLu::new(a.n, &a.col_ptr, &a.row_idx).unwrap();
            assert_eq!((lu.nodes(), lu.meet), (m, m / 2));
            let x: Vec<f64> = (0..a.n).map(|i| (i as f64 * 0.37).cos()).collect();
            assert_paths_agree(&a, &x, |path, b| {
                factorize(path, &mut lu, Source::Array(&a.values)).expect("regular");
                solve(path, &mut lu, b);
            });
            let mut band =
                crate::linalg::band_lu::BandLu::new(a.n, a.bandwidth(), &a.col_ptr, &a.row_idx);
            band.factorize(&a.values).unwrap();
            let b: Vec<f64> = (0..a.n).map(|i| (i as f64).sin()).collect();
            let (mut x1, mut x2) = (b.clone(), b);
            lu.factorize(&a.values).unwrap();
            lu.solve_in_place(&mut x1);
            band.solve_in_place(&mut x2);
            let diff = x1
                .iter()
                .zip(&x2)
                .fold(0.0f64, |d, (p, q)| d.max((p - q).abs()));
            assert!(diff < 1e-12, "{m} nodes: {diff:e}");
        }
    }

    /// The two chains on two threads give the bits of one thread, in both
    /// precisions, factorization and solve.
    #[test]
    fn two_threads_give_the_bits_of_one() {
        let m = TWIST_MIN_NODES + 9;
        let sizes = long_sizes(m);
        let (mass, stiffness) = (
            uneven_blocks(&sizes, 30.0, 1),
            uneven_blocks(&sizes, 3.0, 2),
        );
        let sum = ValueSum {
            parts: [&mass.values, &stiffness.values, &stiffness.values],
            weights: [0.6, 0.37, 0.0],
            third_slots: 0..0,
        };
        let b: Vec<f64> = (0..mass.n).map(|i| (i as f64 * 0.7).sin() + 0.2).collect();
        for precision in [Precision::Double, Precision::Single] {
            let run = |threads: usize| {
                crate::linalg::parallel::with_threads(threads, || {
                    let mut lu =
                        BlockTridiagonalLu::new(mass.n, &mass.col_ptr, &mass.row_idx).unwrap();
                    lu.factorize_sum(&sum, precision).unwrap();
                    let mut x = b.clone();
                    lu.solve_in_place(&mut x);
                    let x: Vec<u64> = x.iter().map(|v| v.to_bits()).collect();
                    (factor_bits(&lu), x)
                })
            };
            assert!(run(1) == run(2), "{precision:?}");
        }
    }
}
