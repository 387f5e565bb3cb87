//! The Newton matrix of beams coupled by contact, solved around the node
//! blocks: the element pattern's block-tridiagonal matrix A plus coupling
//! blocks C between a few nodes of two beams (the wire's and a member's
//! where they touch).
//!
//! The coupled nodes are a *separator*: without them the beams fall apart
//! into runs of consecutive nodes ("segments"), each block tridiagonal and
//! coupled to the rest only through the separator nodes at its two ends.
//! Each segment T is eliminated by the block LU's recurrences (see
//! `block_tridiagonal`); what it leaves on its end nodes a, b is
//!
//!   S_aa −= U_a (T⁻¹)_uu L_a,   S_ab −= U_a (T⁻¹)_uv U_v,
//!   S_ba −= L_v (T⁻¹)_vu L_a,   S_bb −= L_v (T⁻¹)_vv U_v
//!
//! (u, v the segment's first and last node, a = u − 1, b = v + 1), with
//! T⁻¹'s corner blocks from one forward and one backward sweep of block
//! columns. The separator's matrix S — its own blocks of A, the coupling
//! blocks and those contributions — is small and dense, factored with
//! partial pivoting. A solve eliminates each segment's right-hand side onto
//! S, solves S, and back-substitutes into the segments: two segment solves.
//! All of it is a block LU's work, a few times over, in place of a general
//! sparse LU of the whole (whose fill-reducing ordering does not see the
//! beams: several times slower on the frame scene).

use crate::linalg::block_tridiagonal::{
    B, Block, BlockTridiagonalLu, SingularBlock, ZERO, invert, product, sub_product,
};
use crate::linalg::coupled::CoupledBlock;
use crate::math::simd::Plain;
use faer::Mat;
use faer::linalg::solvers::{PartialPivLu, SolveCore};

/// A run of consecutive nodes outside the separator.
#[derive(Clone, Copy, Debug)]
struct Segment {
    /// First and last node.
    first: usize,
    last: usize,
    /// The separator index of node first − 1 and of node last + 1.
    left: Option<usize>,
    right: Option<usize>,
}

/// The factorization of a coupled Newton matrix around its separator.
pub struct SeparatedLu {
    /// The pattern's node blocks (its slot map and starts).
    blocks: BlockTridiagonalLu,
    /// The separator's nodes, increasing.
    separator: Vec<usize>,
    segments: Vec<Segment>,
    /// Per node: Sₖ⁻¹ of its segment's elimination, and Gₖ = Lₖ Sₖ⁻¹.
    inverse: Vec<Block>,
    gain: Vec<Block>,
    /// The blocks Uₖ and Lₖ of the last matrix (the solves need them).
    upper: Vec<Block>,
    lower: Vec<Block>,
    /// The separator's matrix, factored.
    dense: Option<PartialPivLu<f64>>,
    /// Right-hand side by blocks (padded), for the solves.
    work: Vec<[f64; B]>,
}

impl SeparatedLu {
    /// The solver for matrices on the node blocks of `blocks` (a block
    /// tridiagonal pattern's, see [`BlockTridiagonalLu::new`]).
    pub fn new(blocks: BlockTridiagonalLu) -> Self {
        let m = blocks.starts().len() - 1;
        SeparatedLu {
            blocks,
            separator: Vec::new(),
            segments: Vec::new(),
            inverse: vec![ZERO; m],
            gain: vec![ZERO; m],
            upper: Vec::new(),
            lower: Vec::new(),
            dense: None,
            work: vec![[0.0; B]; m],
        }
    }

    /// The node (block) of unknown `j`.
    fn node_of(&self, j: usize) -> usize {
        self.blocks.starts().partition_point(|&s| s <= j) - 1
    }

    /// Factor the pattern's matrix `values` plus `coupling`.
    pub fn factorize(
        &mut self,
        values: &[f64],
        coupling: &[CoupledBlock],
    ) -> Result<(), SingularBlock> {
        let m = self.inverse.len();
        // The separator: every node a coupling block touches.
        let mut separator: Vec<usize> = coupling
            .iter()
            .flat_map(|b| b.rows.iter().chain(&b.cols).flatten())
            .map(|&j| self.node_of(j))
            .collect();
        separator.sort_unstable();
        separator.dedup();
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
        let (diag, upper, lower) = self.blocks.load(values);
        self.upper.clear();
        self.upper.extend_from_slice(upper);
        self.lower.clear();
        self.lower.extend_from_slice(lower);
        let diag = diag.to_vec();
        // Each segment's elimination.
        for seg in &segments {
            let mut s = diag[seg.first];
            for k in seg.first..=seg.last {
                if k > seg.first {
                    s = diag[k];
                    let g = self.gain[k - 1];
                    sub_product::<Plain>(&mut s, &g, &self.upper[k - 1]);
                }
                let mut inv = ZERO;
                invert::<Plain>(&s, &mut inv)?;
                self.inverse[k] = inv;
                if k < seg.last {
                    let mut g = ZERO;
                    product::<Plain>(&self.lower[k], &inv, &mut g);
                    self.gain[k] = g;
                }
            }
        }
        // The separator's matrix.
        let p = separator.len();
        let mut dense = Mat::<f64>::zeros(B * p, B * p);
        let add = |dense: &mut Mat<f64>, i: usize, j: usize, blk: &Block, sign: f64| {
            for r in 0..B {
                for c in 0..B {
                    dense[(B * i + r, B * j + c)] += sign * blk[r][c];
                }
            }
        };
        for (i, &k) in separator.iter().enumerate() {
            add(&mut dense, i, i, &diag[k], 1.0);
            if i + 1 < p && separator[i + 1] == k + 1 {
                add(&mut dense, i, i + 1, &self.upper[k], 1.0);
                add(&mut dense, i + 1, i, &self.lower[k], 1.0);
            }
        }
        let starts = self.blocks.starts();
        for b in coupling {
            for (r, row) in b.rows.iter().enumerate() {
                let Some(row) = *row else { continue };
                let kr = starts.partition_point(|&s| s <= row) - 1;
                let ir = separator.binary_search(&kr).expect("a separator node");
                for (c, col) in b.cols.iter().enumerate() {
                    let Some(col) = *col else { continue };
                    let kc = starts.partition_point(|&s| s <= col) - 1;
                    let ic = separator.binary_search(&kc).expect("a separator node");
                    dense[(B * ir + row - starts[kr], B * ic + col - starts[kc])] +=
                        b.values[r * 24 + c];
                }
            }
        }
        for seg in &segments {
            let (u, v) = (seg.first, seg.last);
            // T⁻¹'s last block column: x_v = S_v⁻¹, x_k = −S_k⁻¹ U_k x_{k+1}.
            let corner_right = |this: &Self| {
                let xv = this.inverse[v];
                let mut x = xv;
                for k in (u..v).rev() {
                    let (mut ux, mut next) = (ZERO, ZERO);
                    product::<Plain>(&this.upper[k], &x, &mut ux);
                    product::<Plain>(&this.inverse[k], &ux, &mut next);
                    next.iter_mut().flatten().for_each(|e| *e = -*e);
                    x = next;
                }
                (x, xv)
            };
            // T⁻¹'s first block column: forward y_u = I, y_{k+1} = −G_k y_k;
            // backward x_v = S_v⁻¹ y_v, x_k = S_k⁻¹ (y_k − U_k x_{k+1}).
            let corner_left = |this: &Self| {
                let mut y = vec![ZERO; v - u + 1];
                for (i, row) in y[0].iter_mut().enumerate() {
                    row[i] = 1.0;
                }
                for k in u..v {
                    let mut gy = ZERO;
                    product::<Plain>(&this.gain[k], &y[k - u], &mut gy);
                    gy.iter_mut().flatten().for_each(|e| *e = -*e);
                    y[k + 1 - u] = gy;
                }
                let mut x = ZERO;
                product::<Plain>(&this.inverse[v], &y[v - u], &mut x);
                let xv = x;
                for k in (u..v).rev() {
                    let mut rest = y[k - u];
                    sub_product::<Plain>(&mut rest, &this.upper[k], &x);
                    product::<Plain>(&this.inverse[k], &rest, &mut x);
                }
                (x, xv)
            };
            if let Some(ia) = seg.left {
                let a = u - 1;
                let (xuu, xvu) = corner_left(self);
                // S_aa −= U_a X_uu L_a
                let mut t = ZERO;
                let mut w = ZERO;
                product::<Plain>(&self.upper[a], &xuu, &mut t);
                product::<Plain>(&t, &self.lower[a], &mut w);
                add(&mut dense, ia, ia, &w, -1.0);
                if let Some(ib) = seg.right {
                    // S_ba −= L_v X_vu L_a
                    product::<Plain>(&self.lower[v], &xvu, &mut t);
                    product::<Plain>(&t, &self.lower[a], &mut w);
                    add(&mut dense, ib, ia, &w, -1.0);
                }
            }
            if let Some(ib) = seg.right {
                let (xuv, xvv) = corner_right(self);
                let (mut t, mut w) = (ZERO, ZERO);
                // S_bb −= L_v X_vv U_v
                product::<Plain>(&self.lower[v], &xvv, &mut t);
                product::<Plain>(&t, &self.upper[v], &mut w);
                add(&mut dense, ib, ib, &w, -1.0);
                if let Some(ia) = seg.left {
                    // S_ab −= U_a X_uv U_v
                    product::<Plain>(&self.upper[u - 1], &xuv, &mut t);
                    product::<Plain>(&t, &self.upper[v], &mut w);
                    add(&mut dense, ia, ib, &w, -1.0);
                }
            }
        }
        let lu = dense.as_ref().partial_piv_lu();
        self.separator = separator;
        self.segments = segments;
        self.dense = Some(lu);
        Ok(())
    }

    /// Solve T x = y in place on one segment (y by blocks, padded).
    fn segment_solve(&self, seg: &Segment, y: &mut [[f64; B]]) {
        let (u, v) = (seg.first, seg.last);
        for k in u..v {
            let yk = y[k];
            let g = &self.gain[k];
            for (i, row) in g.iter().enumerate() {
                y[k + 1][i] -= row.iter().zip(&yk).map(|(a, b)| a * b).sum::<f64>();
            }
        }
        let apply = |blk: &Block, x: &[f64; B]| -> [f64; B] {
            std::array::from_fn(|i| blk[i].iter().zip(x).map(|(a, b)| a * b).sum())
        };
        y[v] = apply(&self.inverse[v], &y[v]);
        for k in (u..v).rev() {
            let ux = apply(&self.upper[k], &y[k + 1]);
            let rest: [f64; B] = std::array::from_fn(|i| y[k][i] - ux[i]);
            y[k] = apply(&self.inverse[k], &rest);
        }
    }

    /// Solve A x = b in place with the last factorization.
    pub fn solve_in_place(&mut self, b: &mut [f64]) {
        let starts = self.blocks.starts().to_vec();
        let m = starts.len() - 1;
        let mut y = std::mem::take(&mut self.work);
        for k in 0..m {
            let part = &b[starts[k]..starts[k + 1]];
            y[k] = [0.0; B];
            y[k][..part.len()].copy_from_slice(part);
        }
        let rhs = y.clone();
        let apply = |blk: &Block, x: &[f64; B]| -> [f64; B] {
            std::array::from_fn(|i| blk[i].iter().zip(x).map(|(a, b)| a * b).sum())
        };
        // Each segment's T⁻¹ b onto the separator's right-hand side.
        let p = self.separator.len();
        let mut s_rhs = Mat::<f64>::zeros(B * p, 1);
        for (i, &k) in self.separator.iter().enumerate() {
            for r in 0..B {
                s_rhs[(B * i + r, 0)] = rhs[k][r];
            }
        }
        for seg in &self.segments {
            self.segment_solve(seg, &mut y);
            if let Some(ia) = seg.left {
                let w = apply(&self.upper[seg.first - 1], &y[seg.first]);
                for r in 0..B {
                    s_rhs[(B * ia + r, 0)] -= w[r];
                }
            }
            if let Some(ib) = seg.right {
                let w = apply(&self.lower[seg.last], &y[seg.last]);
                for r in 0..B {
                    s_rhs[(B * ib + r, 0)] -= w[r];
                }
            }
        }
        self.dense
            .as_ref()
            .expect("factorize before solve")
            .solve_in_place_with_conj(faer::Conj::No, s_rhs.as_mut());
        let xs: Vec<[f64; B]> = (0..p)
            .map(|i| std::array::from_fn(|r| s_rhs[(B * i + r, 0)]))
            .collect();
        for (i, &k) in self.separator.iter().enumerate() {
            y[k] = xs[i];
        }
        // Back-substitution: T x = b_T − (the separator's share).
        for seg in &self.segments {
            y[seg.first..=seg.last].copy_from_slice(&rhs[seg.first..=seg.last]);
            if let Some(ia) = seg.left {
                let w = apply(&self.lower[seg.first - 1], &xs[ia]);
                for r in 0..B {
                    y[seg.first][r] -= w[r];
                }
            }
            if let Some(ib) = seg.right {
                let w = apply(&self.upper[seg.last], &xs[ib]);
                for r in 0..B {
                    y[seg.last][r] -= w[r];
                }
            }
            self.segment_solve(seg, &mut y);
        }
        for k in 0..m {
            let part = &mut b[starts[k]..starts[k + 1]];
            let len = part.len();
            part.copy_from_slice(&y[k][..len]);
        }
        self.work = y;
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::linalg::band_cholesky::tests::TestMatrix;

    /// A block-tridiagonal matrix of nodes `sizes` (a held node has fewer
    /// unknowns) with coupling blocks between far nodes, solved around the
    /// separator, against a dense solve of the same matrix.
    #[test]
    fn coupled_blocks_solve_as_the_dense_matrix() {
        // Separators inside (segments coupled at both ends) and reaching
        // the last node; separators adjacent; a segment at the end.
        coupled_solve(&[(2, 9), (9, 2), (5, 12), (12, 5)]);
        coupled_solve(&[(2, 9), (9, 2), (4, 11), (11, 4)]);
    }

    fn coupled_solve(pairs: &[(usize, usize)]) {
        let sizes = [12usize, 9, 12, 12, 12, 12, 12, 12, 12, 6, 12, 12, 12, 12];
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
        let coupled = |r: usize, c: usize| node[r].abs_diff(node[c]) <= 1;
        let mut dense = vec![0.0; n * n];
        for r in 0..n {
            for c in (0..n).filter(|&c| coupled(r, c)) {
                dense[r * n + c] = if r == c {
                    40.0 + (r % 5) as f64
                } else {
                    ((r * 13 + c * 7) % 17) as f64 / 17.0 - 0.5
                };
            }
        }
        let a = TestMatrix::new(n, dense.clone(), coupled);
        let blocks = BlockTridiagonalLu::new(n, &a.col_ptr, &a.row_idx).expect("block tridiagonal");
        // Coupling "elements" (two nodes each, both ways); unknowns of
        // node k from starts.
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
        // Solve (matrix) x = b for a known x with `lu`: the largest error.
        let x: Vec<f64> = (0..n).map(|i| (i as f64 * 0.37).cos()).collect();
        let error = |lu: &mut SeparatedLu, matrix: &[f64]| {
            let mut b: Vec<f64> = (0..n)
                .map(|r| (0..n).map(|c| matrix[r * n + c] * x[c]).sum())
                .collect();
            lu.solve_in_place(&mut b);
            b.iter()
                .zip(&x)
                .map(|(p, q)| (p - q).abs())
                .fold(0.0, f64::max)
        };
        let mut lu = SeparatedLu::new(blocks);
        lu.factorize(&a.values, &coupling).expect("regular");
        let err = error(&mut lu, &full);
        assert!(err < 1e-12, "{err:e}");
        // Without coupling: the segments alone (no separator).
        let mut plain = SeparatedLu::new(
            BlockTridiagonalLu::new(n, &a.col_ptr, &a.row_idx).expect("block tridiagonal"),
        );
        plain.factorize(&a.values, &[]).expect("regular");
        let err = error(&mut plain, &a.dense);
        assert!(err < 1e-12, "{err:e}");
    }
}
