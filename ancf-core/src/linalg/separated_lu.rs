//! The Newton matrix of beams coupled by contact, solved around the node
//! blocks: the element pattern's block-tridiagonal matrix A plus coupling
//! blocks C between a few nodes of two beams (the wire's and a member's
//! where they touch).
//!
//! The coupled nodes are a *separator*: without them the beams fall apart
//! into runs of consecutive nodes ("segments"), each block tridiagonal and
//! coupled to the rest only through the separator nodes at its two ends.
//! Each segment is eliminated by the block LU's recurrences (see
//! `block_tridiagonal`) *towards* a separator node next to it, the "near"
//! one: its right neighbour, or its left one when it has no right one.
//! What the elimination leaves on the near node s from the segment's last
//! eliminated node e is one block, S_ss −= A_se Sₑ⁻¹ A_es. A segment
//! between two separators also couples its first node to the "far" one f
//! on its left; eliminating the segment carries that coupling along as
//! fill (a spike):
//!
//!   Fₖ = A₍ₖ,f₎ − Gₚ Fₚ,  Rₖ = A₍f,ₖ₎ − Kₚ A₍ₚ,ₖ₎,  Kₖ = Rₖ Sₖ⁻¹,
//!   S_ff −= Σ Kₖ Fₖ,  S_sf −= A_se Sₑ⁻¹ Fₑ,  S_fs −= Kₑ A_es
//!
//! (p the node eliminated before k). The separator's matrix S — its own
//! blocks of A, the coupling blocks and those contributions — is small and
//! dense, factored with partial pivoting. A solve is one forward pass along
//! each segment (which leaves A_se Sₑ⁻¹ yₑ and Σ Kₖ yₖ on the separator's
//! right-hand side), the dense solve, and one backward pass
//! xₖ = Sₖ⁻¹ (yₖ − A₍ₖ,ₙ₎ xₙ − Fₖ x_f) (n the node eliminated after k, or
//! s): three 12 × 12 matrix–vector products a node as in the block LU,
//! five between two separators. All of it is a block LU's work in place of
//! a general sparse LU of the whole (whose fill-reducing ordering does not
//! see the beams: several times slower on the frame scene).
//!
//! Segments are independent, but of very unequal size: a wire touching a
//! tube near one end leaves one long run. From [`TWIST_MIN_NODES`] nodes
//! on, one node splits the segments into two groups of about equal work (a
//! separator node of its own where it falls inside a segment), wherever
//! that takes at least a fifth off the serial work, and the two groups'
//! eliminations and passes run on two threads. The cut is chosen from the
//! sizes alone, so results do not depend on the thread count.

use crate::linalg::block_tridiagonal::{
    B, Block, BlockTridiagonalLu, SingularBlock, TWIST_MIN_NODES, ZERO, invert_transposed,
    load_block, matvec_t, product, store_block, sub_product, transpose,
};
use crate::linalg::coupled::CoupledBlock;
use crate::linalg::parallel::run_tasks;
use crate::linalg::value_sum::{SlotValues, ValueSum};
use crate::math::simd::{Arith, SimdPath, path};
use faer::Mat;
use faer::linalg::solvers::{PartialPivLu, SolveCore};

/// A run of consecutive nodes outside the separator.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
struct Segment {
    /// First and last node.
    first: usize,
    last: usize,
    /// The separator index of node first − 1 and of node last + 1.
    left: Option<usize>,
    right: Option<usize>,
}

impl Segment {
    fn len(&self) -> usize {
        self.last + 1 - self.first
    }

    /// Eliminated from `last` down to `first`: towards a separator on the
    /// left when there is none on the right.
    fn reversed(&self) -> bool {
        self.right.is_none() && self.left.is_some()
    }

    /// The separator next to the node eliminated last.
    fn near(&self) -> Option<usize> {
        self.right.or(self.left)
    }

    /// The separator next to the node eliminated first, for a segment
    /// between two separators.
    fn far(&self) -> Option<usize> {
        self.right.and(self.left)
    }

    /// The node eliminated `i`-th.
    fn node(&self, i: usize) -> usize {
        if self.reversed() {
            self.last - i
        } else {
            self.first + i
        }
    }

    /// A solve's work on it, in 12 × 12 matrix–vector products.
    fn cost(&self) -> usize {
        self.len() * if self.far().is_some() { 5 } else { 3 }
    }
}

/// The segments of `m` nodes around the (increasing) `separator`.
fn segments(m: usize, separator: &[usize]) -> Vec<Segment> {
    let index_of = |k: usize| separator.binary_search(&k).ok();
    let mut segments = Vec::new();
    let mut k = 0;
    while k < m {
        if index_of(k).is_some() {
            k += 1;
            continue;
        }
        let first = k;
        while k < m && index_of(k).is_none() {
            k += 1;
        }
        let last = k - 1;
        segments.push(Segment {
            first,
            last,
            left: first.checked_sub(1).and_then(index_of),
            right: (last + 1 < m).then(|| index_of(last + 1)).flatten(),
        });
    }
    segments
}

/// What a new separator node costs against the segments' work: its
/// share of the dense solve and of the forward and backward hand-over,
/// in the units of [`Segment::cost`].
const NEW_SEPARATOR_COST: usize = 24;

/// The node that splits the segments of `m` nodes around `separator` into
/// two groups of the least larger work (a separator node, or a node to
/// become one), or `None` when no cut takes a fifth off the serial work.
fn balanced_cut(m: usize, separator: &[usize]) -> Option<usize> {
    let segments = segments(m, separator);
    let total: usize = segments.iter().map(Segment::cost).sum();
    let mut best: Option<(usize, usize)> = None;
    let mut consider = |c: usize, span: usize| {
        if best.is_none_or(|(_, b)| span < b) {
            best = Some((c, span));
        }
    };
    let per_node = |between_two: bool| if between_two { 5 } else { 3 };
    let mut before = 0;
    for seg in &segments {
        if seg.first > 0 && separator.binary_search(&(seg.first - 1)).is_ok() {
            consider(seg.first - 1, before.max(total - before));
        }
        let after = total - before - seg.cost();
        // Node c as a new separator: the nodes before it form a segment
        // with the old left side, those after it one with the old right.
        for c in seg.first..=seg.last {
            let head = (c - seg.first) * per_node(seg.left.is_some());
            let tail = (seg.last - c) * per_node(seg.right.is_some());
            consider(c, (before + head).max(tail + after) + NEW_SEPARATOR_COST);
        }
        before += seg.cost();
    }
    best.filter(|&(_, span)| 5 * span < 4 * total)
        .map(|(c, _)| c)
}

/// Per node, transposed for the solves' column-oriented products: its
/// Schur complement's inverse, its gain A₍ₙ,ₖ₎ Sₖ⁻¹ and coupling A₍ₖ,ₙ₎
/// towards the node n eliminated after it (or the near separator node),
/// and, between two separators, its fill Fₖ and far gain Kₖ.
#[derive(Clone, Copy)]
struct NodeFactor {
    inverse_t: Block,
    gain_t: Block,
    couple_t: Block,
    fill_t: Block,
    far_gain_t: Block,
}

const NODE_ZERO: NodeFactor = NodeFactor {
    inverse_t: ZERO,
    gain_t: ZERO,
    couple_t: ZERO,
    fill_t: ZERO,
    far_gain_t: ZERO,
};

/// The matrix by blocks (see [`BlockTridiagonalLu::load`]).
#[derive(Clone, Copy)]
struct Blocks<'a> {
    diag: &'a [Block],
    upper: &'a [Block],
    lower: &'a [Block],
}

impl Blocks<'_> {
    /// A₍ₙ,ₖ₎ and A₍ₖ,ₙ₎ for node k and the node n eliminated after it in
    /// `seg`'s order (its neighbour on the side away from the start).
    fn towards_next(&self, seg: &Segment, k: usize) -> (&Block, &Block) {
        if seg.reversed() {
            (&self.upper[k - 1], &self.lower[k - 1])
        } else {
            (&self.lower[k], &self.upper[k])
        }
    }
}

/// What a segment's elimination leaves on its separator nodes, already
/// negated: on (near, near), (near, far), (far, near) and (far, far).
struct Leaves([Block; 4]);

/// One group of segments and its window of the node factors (nodes
/// `offset` …).
struct FactorPart<'a> {
    segments: &'a [Segment],
    offset: usize,
    factors: &'a mut [NodeFactor],
}

/// One group of segments in a solve: its window of the node factors, of
/// the right-hand side by blocks and of the right-hand side itself (nodes
/// `offset` … with unknowns from `starts[0]` on).
struct SolvePart<'a> {
    segments: &'a [Segment],
    offset: usize,
    factors: &'a [NodeFactor],
    y: &'a mut [[f64; B]],
    starts: &'a [usize],
    b: &'a mut [f64],
}

crate::simd_dispatch! {
    fn eliminate(matrix: Blocks, part: FactorPart) -> Result<Vec<Leaves>, SingularBlock> = eliminate_with;
}

#[inline(always)]
fn eliminate_with<F: Arith>(
    matrix: Blocks,
    part: FactorPart,
) -> Result<Vec<Leaves>, SingularBlock> {
    let FactorPart {
        segments,
        offset,
        factors,
    } = part;
    // A loop, not an iterator adapter: the adapter's code is not inlined
    // into the dispatched function, and its multiply-adds became calls.
    let mut leaves = Vec::with_capacity(segments.len());
    for seg in segments {
        leaves.push(eliminate_segment::<F>(&matrix, seg, offset, factors)?);
    }
    Ok(leaves)
}

/// One segment's elimination (module doc), its node factors into
/// `factors` (node k at k − `offset`).
#[inline(always)]
fn eliminate_segment<F: Arith>(
    a: &Blocks,
    seg: &Segment,
    offset: usize,
    factors: &mut [NodeFactor],
) -> Result<Leaves, SingularBlock> {
    let n = seg.len();
    let two_sided = seg.far().is_some();
    let mut leaves = Leaves([ZERO; 4]);
    let (mut inverse, mut gain, mut far_gain, mut t) = (ZERO, ZERO, ZERO, ZERO);
    // Fₖ and Rₖ: the first node's couplings to the far node (left of it).
    let (mut fill, mut far_row) = if two_sided {
        (a.lower[seg.first - 1], a.upper[seg.first - 1])
    } else {
        (ZERO, ZERO)
    };
    for i in 0..n {
        let k = seg.node(i);
        let mut s = a.diag[k];
        if i > 0 {
            let p = seg.node(i - 1);
            let (_, incoming) = a.towards_next(seg, p);
            // Sₖ = Dₖ − Gₚ A₍ₚ,ₖ₎ (`gain` and `far_gain` are p's here).
            sub_product::<F>(&mut s, &gain, incoming);
            if two_sided {
                // Fₖ = −Gₚ Fₚ, Rₖ = −Kₚ A₍ₚ,ₖ₎.
                product::<F>(&gain, &fill, &mut t);
                fill = negated(&t);
                product::<F>(&far_gain, incoming, &mut t);
                far_row = negated(&t);
            }
        }
        // The inverse's transpose is what the node keeps; the inverse
        // itself serves the products below.
        let node = &mut factors[k - offset];
        transpose(&s, &mut t);
        invert_transposed::<F>(&t, &mut node.inverse_t)?;
        transpose(&node.inverse_t, &mut inverse);
        if two_sided {
            product::<F>(&far_row, &inverse, &mut far_gain);
            transpose(&far_gain, &mut node.far_gain_t);
            transpose(&fill, &mut node.fill_t);
            sub_product::<F>(&mut leaves.0[3], &far_gain, &fill);
        }
        if i + 1 < n || seg.near().is_some() {
            let (outgoing, incoming) = a.towards_next(seg, k);
            product::<F>(outgoing, &inverse, &mut gain);
            transpose(&gain, &mut node.gain_t);
            transpose(incoming, &mut node.couple_t);
        }
    }
    if seg.near().is_some() {
        // `gain` is A_se Sₑ⁻¹ here, `fill` and `far_gain` node e's.
        let (_, incoming) = a.towards_next(seg, seg.node(n - 1));
        sub_product::<F>(&mut leaves.0[0], &gain, incoming);
        if two_sided {
            sub_product::<F>(&mut leaves.0[1], &gain, &fill);
            sub_product::<F>(&mut leaves.0[2], &far_gain, incoming);
        }
    }
    Ok(leaves)
}

fn negated(a: &Block) -> Block {
    a.map(|row| row.map(|x| -x))
}

crate::simd_dispatch! {
    fn forward(part: SolvePart) -> Vec<[[f64; B]; 2]> = forward_with;
}

crate::simd_dispatch! {
    fn backward(part: SolvePart, separator: &[[f64; B]]) = backward_with;
}

/// The part's right-hand side into its blocks, and the forward pass of
/// each of its segments; per segment, what it leaves on its near and far
/// separator nodes' right-hand sides (to subtract).
#[inline(always)]
fn forward_with<F: Arith>(part: SolvePart) -> Vec<[[f64; B]; 2]> {
    let SolvePart {
        segments,
        offset,
        factors,
        y,
        starts,
        b,
    } = part;
    let s0 = starts[0];
    for (k, w) in starts.windows(2).enumerate() {
        y[k] = load_block(&b[w[0] - s0..w[1] - s0]);
    }
    let mut leaves = Vec::with_capacity(segments.len());
    for seg in segments {
        let two_sided = seg.far().is_some();
        let mut far = [0.0; B];
        let mut previous: Option<usize> = None;
        for i in 0..seg.len() {
            let k = seg.node(i) - offset;
            if let Some(p) = previous {
                let g = matvec_t::<F, f64>(&factors[p].gain_t, &y[p]);
                for (y, g) in y[k].iter_mut().zip(g) {
                    *y -= g;
                }
            }
            if two_sided {
                let g = matvec_t::<F, f64>(&factors[k].far_gain_t, &y[k]);
                for (f, g) in far.iter_mut().zip(g) {
                    *f += g;
                }
            }
            previous = Some(k);
        }
        let e = seg.node(seg.len() - 1) - offset;
        let near = match seg.near() {
            Some(_) => matvec_t::<F, f64>(&factors[e].gain_t, &y[e]),
            None => [0.0; B],
        };
        leaves.push([near, far]);
    }
    leaves
}

/// The backward pass of each of the part's segments from the separator's
/// solution (`separator`, by separator index), into `b`.
#[inline(always)]
fn backward_with<F: Arith>(part: SolvePart, separator: &[[f64; B]]) {
    let SolvePart {
        segments,
        offset,
        factors,
        y,
        starts,
        b,
    } = part;
    for seg in segments {
        let far = seg.far().map(|f| separator[f]);
        let mut next = seg.near().map(|s| separator[s]);
        for i in (0..seg.len()).rev() {
            let k = seg.node(i) - offset;
            let mut rest = y[k];
            if let Some(x) = &next {
                let u = matvec_t::<F, f64>(&factors[k].couple_t, x);
                for (r, u) in rest.iter_mut().zip(u) {
                    *r -= u;
                }
            }
            if let Some(x) = &far {
                let u = matvec_t::<F, f64>(&factors[k].fill_t, x);
                for (r, u) in rest.iter_mut().zip(u) {
                    *r -= u;
                }
            }
            y[k] = matvec_t::<F, f64>(&factors[k].inverse_t, &rest);
            next = Some(y[k]);
        }
        let s0 = starts[0];
        for k in seg.first..=seg.last {
            let (lo, hi) = (starts[k - offset] - s0, starts[k - offset + 1] - s0);
            store_block(&mut b[lo..hi], &y[k - offset]);
        }
    }
}

/// The node (block) of unknown `j`, node k's unknowns being `starts[k]` …
/// `starts[k + 1] − 1`.
fn node_of(starts: &[usize], j: usize) -> usize {
    starts.partition_point(|&s| s <= j) - 1
}

/// The groups of `segments` of `m` nodes: all of them, or those before and
/// after the `cut` node, with their nodes.
fn groups(
    segments: &[Segment],
    cut: Option<usize>,
    m: usize,
) -> Vec<(&[Segment], std::ops::Range<usize>)> {
    match cut {
        None => vec![(segments, 0..m)],
        Some(c) => {
            let (before, after) = segments.split_at(segments.partition_point(|s| s.last < c));
            vec![(before, 0..c), (after, c..m)]
        }
    }
}

/// The factorization of a coupled Newton matrix around its separator.
pub struct SeparatedLu {
    /// The pattern's node blocks (its slot map and starts).
    blocks: BlockTridiagonalLu,
    /// Node k's unknowns are starts[k] … starts[k + 1] − 1.
    starts: Vec<usize>,
    /// From this many nodes on, the segments are cut into two groups.
    cut_from: usize,
    /// The separator's nodes, increasing.
    separator: Vec<usize>,
    segments: Vec<Segment>,
    /// The node between the two groups of segments (a separator node).
    cut: Option<usize>,
    factors: Vec<NodeFactor>,
    /// The separator's matrix, factored.
    dense: Option<PartialPivLu<f64>>,
    /// Right-hand side by blocks (padded), for the solves.
    work: Vec<[f64; B]>,
}

impl SeparatedLu {
    /// The solver for matrices on the node blocks of `blocks` (a block
    /// tridiagonal pattern's, see [`BlockTridiagonalLu::new`]).
    pub fn new(blocks: BlockTridiagonalLu) -> Self {
        let starts = blocks.starts().to_vec();
        let m = starts.len() - 1;
        SeparatedLu {
            blocks,
            starts,
            cut_from: TWIST_MIN_NODES,
            separator: Vec::new(),
            segments: Vec::new(),
            cut: None,
            factors: vec![NODE_ZERO; m],
            dense: None,
            work: vec![[0.0; B]; m],
        }
    }

    fn nodes(&self) -> usize {
        self.starts.len() - 1
    }

    /// Factor the pattern's matrix `values` plus `coupling`.
    pub fn factorize(
        &mut self,
        values: &[f64],
        coupling: &[CoupledBlock],
    ) -> Result<(), SingularBlock> {
        self.factorize_on(path(), values, coupling)
    }

    /// [`SeparatedLu::factorize`] of the pattern's matrix `sum`, read
    /// where each block is loaded (never formed). A non-finite value is
    /// reported as a [`SingularBlock`].
    pub fn factorize_sum(
        &mut self,
        sum: &ValueSum,
        coupling: &[CoupledBlock],
    ) -> Result<(), SingularBlock> {
        self.factorize_on(path(), sum, coupling)
    }

    /// [`SeparatedLu::factorize`] on the SIMD path `simd`, of the slot
    /// values `values` (an array or a sum).
    fn factorize_on<V: SlotValues + ?Sized + Sync>(
        &mut self,
        simd: SimdPath,
        values: &V,
        coupling: &[CoupledBlock],
    ) -> Result<(), SingularBlock> {
        let m = self.nodes();
        // The separator: every node a coupling block touches, and the cut.
        let mut separator: Vec<usize> = coupling
            .iter()
            .flat_map(|b| b.rows.iter().chain(&b.cols).flatten())
            .map(|&j| node_of(&self.starts, j))
            .collect();
        separator.sort_unstable();
        separator.dedup();
        self.cut = (m >= self.cut_from)
            .then(|| balanced_cut(m, &separator))
            .flatten();
        if let Some(c) = self.cut
            && let Err(at) = separator.binary_search(&c)
        {
            separator.insert(at, c);
        }
        self.segments = segments(m, &separator);
        self.separator = separator;
        let (diag, upper, lower) = self.blocks.load(values).ok_or(SingularBlock)?;
        let matrix = Blocks { diag, upper, lower };
        // Each group's eliminations.
        let mut factors = std::mem::take(&mut self.factors);
        let mut parts = Vec::new();
        let mut rest = &mut factors[..];
        let mut taken = 0;
        for (segments, nodes) in groups(&self.segments, self.cut, m) {
            let (window, tail) = std::mem::take(&mut rest).split_at_mut(nodes.end - taken);
            (rest, taken) = (tail, nodes.end);
            parts.push(FactorPart {
                segments,
                offset: nodes.start,
                factors: window,
            });
        }
        let leaves = run_tasks(parts, |part| eliminate(simd, matrix, part));
        self.factors = factors;
        let leaves: Vec<Leaves> = leaves
            .into_iter()
            .collect::<Result<Vec<_>, _>>()?
            .into_iter()
            .flatten()
            .collect();
        // The separator's matrix.
        let separator = &self.separator;
        let p = separator.len();
        let mut dense = Mat::<f64>::zeros(B * p, B * p);
        let add = |dense: &mut Mat<f64>, i: usize, j: usize, blk: &Block| {
            for r in 0..B {
                for c in 0..B {
                    dense[(B * i + r, B * j + c)] += blk[r][c];
                }
            }
        };
        for (i, &k) in separator.iter().enumerate() {
            add(&mut dense, i, i, &diag[k]);
            if i + 1 < p && separator[i + 1] == k + 1 {
                add(&mut dense, i, i + 1, &upper[k]);
                add(&mut dense, i + 1, i, &lower[k]);
            }
        }
        let starts = &self.starts;
        for b in coupling {
            for (r, row) in b.rows.iter().enumerate() {
                let Some(row) = *row else { continue };
                let kr = node_of(starts, row);
                let ir = separator.binary_search(&kr).expect("a separator node");
                for (c, col) in b.cols.iter().enumerate() {
                    let Some(col) = *col else { continue };
                    let kc = node_of(starts, col);
                    let ic = separator.binary_search(&kc).expect("a separator node");
                    dense[(B * ir + row - starts[kr], B * ic + col - starts[kc])] +=
                        b.values[r * 24 + c];
                }
            }
        }
        for (seg, Leaves(blocks)) in self.segments.iter().zip(&leaves) {
            if let Some(s) = seg.near() {
                add(&mut dense, s, s, &blocks[0]);
                if let Some(f) = seg.far() {
                    add(&mut dense, s, f, &blocks[1]);
                    add(&mut dense, f, s, &blocks[2]);
                    add(&mut dense, f, f, &blocks[3]);
                }
            }
        }
        self.dense = Some(dense.as_ref().partial_piv_lu());
        Ok(())
    }

    /// The groups' windows for a solve of `b`.
    fn solve_parts<'a>(
        groups: &[(&'a [Segment], std::ops::Range<usize>)],
        factors: &'a [NodeFactor],
        work: &'a mut [[f64; B]],
        starts: &'a [usize],
        b: &'a mut [f64],
    ) -> Vec<SolvePart<'a>> {
        let mut parts = Vec::new();
        let (mut y_rest, mut b_rest) = (work, b);
        for (segments, nodes) in groups {
            let (y, y_tail) = std::mem::take(&mut y_rest).split_at_mut(nodes.len());
            let unknowns = starts[nodes.end] - starts[nodes.start];
            let (b, b_tail) = std::mem::take(&mut b_rest).split_at_mut(unknowns);
            (y_rest, b_rest) = (y_tail, b_tail);
            parts.push(SolvePart {
                segments,
                offset: nodes.start,
                factors: &factors[nodes.clone()],
                y,
                starts: &starts[nodes.start..=nodes.end],
                b,
            });
        }
        parts
    }

    /// Solve A x = b in place with the last factorization.
    pub fn solve_in_place(&mut self, b: &mut [f64]) {
        self.solve_on(path(), b)
    }

    /// [`SeparatedLu::solve_in_place`] on the SIMD path `simd` (the AVX2
    /// code on the AVX-512 path, as the block LU's solves).
    fn solve_on(&mut self, simd: SimdPath, b: &mut [f64]) {
        let simd = match simd {
            SimdPath::Avx512 => SimdPath::Avx2,
            other => other,
        };
        let mut work = std::mem::take(&mut self.work);
        let groups = groups(&self.segments, self.cut, self.nodes());
        let parts = Self::solve_parts(&groups, &self.factors, &mut work, &self.starts, b);
        let leaves = run_tasks(parts, |part| forward(simd, part));
        // The separator's right-hand side, its solve.
        let p = self.separator.len();
        let mut rhs = Mat::<f64>::zeros(B * p, 1);
        for (i, &k) in self.separator.iter().enumerate() {
            for r in 0..B {
                rhs[(B * i + r, 0)] = work[k][r];
            }
        }
        for (seg, [near, far]) in self.segments.iter().zip(leaves.iter().flatten()) {
            for (i, leaf) in [(seg.near(), near), (seg.far(), far)] {
                if let Some(i) = i {
                    for r in 0..B {
                        rhs[(B * i + r, 0)] -= leaf[r];
                    }
                }
            }
        }
        self.dense
            .as_ref()
            .expect("factorize before solve")
            .solve_in_place_with_conj(faer::Conj::No, rhs.as_mut());
        let xs: Vec<[f64; B]> = (0..p)
            .map(|i| std::array::from_fn(|r| rhs[(B * i + r, 0)]))
            .collect();
        let parts = Self::solve_parts(&groups, &self.factors, &mut work, &self.starts, b);
        run_tasks(parts, |part| backward(simd, part, &xs));
        for (x, &k) in xs.iter().zip(&self.separator) {
            store_block(&mut b[self.starts[k]..self.starts[k + 1]], x);
        }
        drop(groups);
        self.work = work;
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::linalg::band_cholesky::tests::TestMatrix;
    use crate::linalg::parallel::with_threads;

    /// A block-tridiagonal matrix of `m` nodes (a held node, every
    /// seventh, has 9 unknowns; one node 6) with coupling blocks between
    /// the node pairs `pairs` (each coupling two nodes on either side,
    /// both ways), and the same matrix dense.
    struct Coupled {
        n: usize,
        a: TestMatrix,
        coupling: Vec<CoupledBlock>,
        full: Vec<f64>,
    }

    fn coupled(m: usize, pairs: &[(usize, usize)]) -> Coupled {
        let sizes: Vec<usize> = (0..m)
            .map(|k| match k {
                _ if k % 7 == 1 => 9,
                9 => 6,
                _ => 12,
            })
            .collect();
        let n: usize = sizes.iter().sum();
        let mut node = Vec::new();
        for (k, s) in sizes.iter().enumerate() {
            node.extend(std::iter::repeat_n(k, *s));
        }
        let starts: Vec<usize> = std::iter::once(0)
            .chain(sizes.iter().scan(0, |a, s| {
                *a += s;
                Some(*a)
            }))
            .collect();
        let near = |r: usize, c: usize| node[r].abs_diff(node[c]) <= 1;
        let mut dense = vec![0.0; n * n];
        for r in 0..n {
            for c in (0..n).filter(|&c| near(r, c)) {
                dense[r * n + c] = if r == c {
                    40.0 + (r % 5) as f64
                } else {
                    ((r * 13 + c * 7) % 17) as f64 / 17.0 - 0.5
                };
            }
        }
        let a = TestMatrix::new(n, dense.clone(), near);
        // Coupling "elements" (two nodes each); unknowns of node k from starts.
        let unknowns = |el: usize| -> [Option<usize>; 24] {
            let (a, b) = (starts[el], starts[el + 2]);
            std::array::from_fn(|i| (a + i < b).then_some(a + i))
        };
        let mut full = dense;
        let mut coupling = Vec::new();
        for &(x, y) in pairs {
            let values: Box<[f64; 576]> = Box::new(std::array::from_fn(|e| {
                ((e * 31 + x * 7 + y) % 23) as f64 / 23.0 - 0.5
            }));
            let (rows, cols) = (unknowns(x), unknowns(y));
            for (i, r) in rows.iter().enumerate() {
                for (j, c) in cols.iter().enumerate() {
                    if let (Some(r), Some(c)) = (r, c) {
                        full[r * n + c] += values[i * 24 + j];
                    }
                }
            }
            coupling.push(CoupledBlock { rows, cols, values });
        }
        Coupled {
            n,
            a,
            coupling,
            full,
        }
    }

    impl Coupled {
        /// The solver of the pattern, cutting from `cut_from` nodes on.
        fn solver(&self, cut_from: usize) -> SeparatedLu {
            let a = &self.a;
            let blocks =
                BlockTridiagonalLu::new(self.n, &a.col_ptr, &a.row_idx).expect("block tridiagonal");
            let mut lu = SeparatedLu::new(blocks);
            lu.cut_from = cut_from;
            lu
        }

        /// x = (i 0.37).cos(), and b = `matrix` x.
        fn problem(&self, matrix: &[f64]) -> (Vec<f64>, Vec<f64>) {
            let n = self.n;
            let x: Vec<f64> = (0..n).map(|i| (i as f64 * 0.37).cos()).collect();
            let b = (0..n)
                .map(|r| (0..n).map(|c| matrix[r * n + c] * x[c]).sum())
                .collect();
            (x, b)
        }

        /// The solution of the coupled matrix by `lu` and its largest error.
        fn solve(&self, lu: &mut SeparatedLu, coupled: bool) -> (Vec<f64>, f64) {
            let matrix = if coupled { &self.full } else { &self.a.dense };
            let coupling = if coupled { &self.coupling[..] } else { &[] };
            lu.factorize(&self.a.values, coupling).expect("regular");
            let (x, mut b) = self.problem(matrix);
            lu.solve_in_place(&mut b);
            let err = (b.iter().zip(&x))
                .map(|(p, q)| (p - q).abs())
                .fold(0.0, f64::max);
            (b, err)
        }
    }

    /// Solved around the separator, the coupled matrix's solution is the
    /// dense one's: separators inside (segments between two of them) and
    /// at the last node; adjacent separators; a segment at either end
    /// (eliminated towards its only separator, left or right); segments
    /// of one node; without coupling, the segments alone; each without
    /// and with a cut into two groups.
    #[test]
    fn coupled_blocks_solve_as_the_dense_matrix() {
        let cases: [(usize, &[(usize, usize)]); 5] = [
            (14, &[(2, 9), (9, 2), (5, 12), (12, 5)]),
            (14, &[(2, 9), (9, 2), (4, 11), (11, 4)]),
            (14, &[(3, 5), (5, 3)]),
            (40, &[(30, 5), (5, 30)]),
            (40, &[(0, 37), (37, 0), (18, 21)]),
        ];
        for (m, pairs) in cases {
            let c = coupled(m, pairs);
            for cut_from in [usize::MAX, 0] {
                let mut lu = c.solver(cut_from);
                let (_, err) = c.solve(&mut lu, true);
                assert!(
                    err < 1e-12,
                    "{m} nodes, {pairs:?}, cut {:?}: {err:e}",
                    lu.cut
                );
                if cut_from == usize::MAX {
                    assert_eq!(lu.cut, None);
                } else if m == 40 {
                    assert!(lu.cut.is_some(), "{pairs:?}");
                }
                let (_, err) = c.solve(&mut lu, false);
                assert!(
                    err < 1e-12,
                    "{m} nodes, uncoupled, cut {:?}: {err:e}",
                    lu.cut
                );
            }
        }
    }

    /// With a cut the two groups run on two threads, with the bits of one.
    #[test]
    fn two_threads_give_the_bits_of_one() {
        let c = coupled(40, &[(30, 5), (5, 30)]);
        let solve = |threads| {
            with_threads(threads, || {
                let mut lu = c.solver(0);
                let solved = c.solve(&mut lu, true);
                assert!(lu.cut.is_some(), "cut");
                solved
            })
        };
        let (one, err) = solve(1);
        assert!(err < 1e-12, "{err:e}");
        let (two, _) = solve(2);
        assert!(
            one.iter()
                .zip(&two)
                .all(|(a, b)| a.to_bits() == b.to_bits())
        );
    }

    /// A sum read where the blocks are loaded gives the bits of the sum
    /// written out first (split into halves from 256 nodes as well); a
    /// value that is not finite is refused.
    #[test]
    fn a_sum_loads_as_its_written_values() {
        for m in [40, 300] {
            let c = coupled(m, &[(30, 5), (5, 30)]);
            let other: Vec<f64> = (c.a.values.iter().enumerate())
                .map(|(i, v)| v * (1.0 + 0.01 * (i % 7) as f64))
                .collect();
            let third = vec![0.5; other.len()];
            let sum = ValueSum {
                parts: [&c.a.values, &other, &third],
                weights: [0.3, 0.7, 1e-3],
                third_slots: 10..other.len() / 2,
            };
            let mut formed = vec![0.0; other.len()];
            sum.write(&mut formed);
            let (_, b) = c.problem(&c.full);
            let solve = |lu: &mut SeparatedLu| {
                let mut x = b.clone();
                lu.solve_in_place(&mut x);
                x
            };
            let mut read = c.solver(TWIST_MIN_NODES);
            read.factorize_sum(&sum, &c.coupling).expect("regular");
            let mut written = c.solver(TWIST_MIN_NODES);
            written.factorize(&formed, &c.coupling).expect("regular");
            let (x, y) = (solve(&mut read), solve(&mut written));
            assert!(
                x.iter().zip(&y).all(|(a, b)| a.to_bits() == b.to_bits()),
                "{m}"
            );
            let mut bad = other.clone();
            bad[other.len() / 3] = f64::NAN;
            let sum = ValueSum {
                parts: [&c.a.values, &bad, &third],
                ..sum
            };
            assert!(read.factorize_sum(&sum, &c.coupling).is_err(), "{m}");
        }
    }

    /// Every SIMD path solves to round-off and agrees with the baseline.
    #[test]
    fn every_simd_path_agrees_with_the_baseline() {
        let c = coupled(40, &[(30, 5), (5, 30)]);
        let (x, b) = c.problem(&c.full);
        let mut reference: Option<Vec<f64>> = None;
        for simd in SimdPath::ALL.into_iter().filter(|p| p.supported()) {
            let mut lu = c.solver(0);
            (lu.factorize_on(simd, &c.a.values[..], &c.coupling)).expect("regular");
            let mut got = b.clone();
            lu.solve_on(simd, &mut got);
            let err = got.iter().zip(&x).map(|(p, q)| (p - q).abs());
            let err = err.fold(0.0, f64::max);
            assert!(err < 1e-12, "{}: {err:e}", simd.name());
            let base = reference.get_or_insert(got.clone());
            let diff = got.iter().zip(base.iter()).map(|(g, b)| (g - b).abs());
            let diff = diff.fold(0.0, f64::max);
            assert!(diff < 1e-13, "{} against baseline: {diff:e}", simd.name());
        }
    }

    /// The cut balances the groups' work: a wire of 1001 nodes touching a
    /// member at node 720 (its member's nodes after it), or nowhere.
    #[test]
    fn the_cut_balances_the_work() {
        let span = |m: usize, separator: &[usize], cut: usize| {
            let mut separator = separator.to_vec();
            if let Err(at) = separator.binary_search(&cut) {
                separator.insert(at, cut);
            }
            let segs = segments(m, &separator);
            let total: usize = segs.iter().map(Segment::cost).sum();
            let before: usize = segs
                .iter()
                .filter(|s| s.last < cut)
                .map(Segment::cost)
                .sum();
            (before, total - before)
        };
        for separator in [&[720, 721, 1010][..], &[960, 1030], &[]] {
            let cut = balanced_cut(1052, separator).expect("a cut");
            let (before, after) = span(1052, separator, cut);
            let unbalance = before.abs_diff(after) as f64 / (before + after) as f64;
            assert!(
                unbalance < 0.01,
                "{separator:?}: cut at {cut}, {before} + {after}"
            );
        }
        // Too little to gain: a new separator node costs more than it saves.
        assert_eq!(balanced_cut(4, &[]), None);
        // An existing separator node costs nothing.
        assert_eq!(balanced_cut(4, &[1]), Some(1));
    }
}
