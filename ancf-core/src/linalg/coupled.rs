//! The Newton matrix of beams coupled by contact: the element pattern's
//! matrix plus blocks between two beams' elements
//! ([`crate::forces::coupling`]). The combined structure and faer's
//! symbolic LU are redone only when a block appears that the last
//! structure lacks (the structure keeps the blocks it had, as zeros, so a
//! contact sliding back and forth does not redo it); every other
//! factorization is numeric only.

use crate::linalg::linear_solver::FactorError;
use crate::linalg::pattern::Pattern;
use faer::sparse::linalg::solvers::{Lu, SymbolicLu};
use faer::sparse::{SparseColMatRef, SymbolicSparseColMat};
use faer::{ColMut, linalg::solvers::Solve};

/// One coupling block on the unknowns: entry (i, j) adds `values[i * 24 + j]`
/// at (`rows[i]`, `cols[j]`) where both are unknowns.
#[derive(Clone, Debug)]
pub struct CoupledBlock {
    /// The unknowns of the rows (`None`: a held coordinate).
    pub rows: [Option<usize>; 24],
    /// The unknowns of the columns.
    pub cols: [Option<usize>; 24],
    /// Row-major 24 × 24.
    pub values: Box<[f64; 576]>,
}

/// Where a block's rows and columns are, for comparing structures.
type BlockKey = ([Option<usize>; 24], [Option<usize>; 24]);

/// Above this many blocks the kept structure is dropped for the current
/// blocks alone (the kept ones no longer pay).
const MAX_KEPT_BLOCKS: usize = 256;

/// The combined matrix's structure and LU factorization.
pub struct CoupledLu {
    keys: Vec<BlockKey>,
    symbolic: SymbolicSparseColMat<usize>,
    symbolic_lu: SymbolicLu<usize>,
    /// The combined slot of each of the pattern's slots.
    base_slots: Vec<usize>,
    values: Vec<f64>,
    lu: Option<Lu<usize, f64>>,
    /// Symbolic analyses done.
    pub analyses: usize,
}

impl CoupledLu {
    /// The structure of `pattern` with the blocks at `keys`.
    fn analyse(pattern: &Pattern, keys: Vec<BlockKey>) -> Result<Self, FactorError> {
        let base = pattern.symbolic.as_ref();
        let n = base.nrows();
        let mut cols: Vec<Vec<usize>> = (0..n)
            .map(|j| base.row_idx()[base.col_ptr()[j]..base.col_ptr()[j + 1]].to_vec())
            .collect();
        for (rows, columns) in &keys {
            for c in columns.iter().flatten() {
                cols[*c].extend(rows.iter().flatten());
            }
        }
        let mut col_ptr = vec![0];
        let mut row_idx = Vec::new();
        for c in cols.iter_mut() {
            c.sort_unstable();
            c.dedup();
            row_idx.extend_from_slice(c);
            col_ptr.push(row_idx.len());
        }
        let mut base_slots = Vec::with_capacity(pattern.nnz());
        for j in 0..n {
            let rows = &row_idx[col_ptr[j]..col_ptr[j + 1]];
            for r in &base.row_idx()[base.col_ptr()[j]..base.col_ptr()[j + 1]] {
                base_slots.push(col_ptr[j] + rows.binary_search(r).expect("a pattern entry"));
            }
        }
        let nnz = row_idx.len();
        let symbolic = SymbolicSparseColMat::new_checked(n, n, col_ptr, None, row_idx);
        let symbolic_lu = SymbolicLu::try_new(symbolic.as_ref())
            .map_err(|e| FactorError(format!("symbolic LU of the coupled beams: {e:?}")))?;
        Ok(CoupledLu {
            keys,
            symbolic,
            symbolic_lu,
            base_slots,
            values: vec![0.0; nnz],
            lu: None,
            analyses: 1,
        })
    }

    /// Factor the pattern's matrix `values` plus `blocks`, analysing the
    /// structure again (into `this`) when a block is new to it.
    pub fn factorize(
        this: &mut Option<CoupledLu>,
        pattern: &Pattern,
        values: &[f64],
        blocks: &[CoupledBlock],
    ) -> Result<(), FactorError> {
        let keys: Vec<BlockKey> = blocks.iter().map(|b| (b.rows, b.cols)).collect();
        let fits = this
            .as_ref()
            .is_some_and(|c| keys.iter().all(|k| c.keys.contains(k)));
        if !fits {
            let analyses = this.as_ref().map_or(0, |c| c.analyses);
            let mut kept = this.take().map(|c| c.keys).unwrap_or_default();
            if kept.len() + keys.len() > MAX_KEPT_BLOCKS {
                kept.clear();
            }
            for k in keys {
                if !kept.contains(&k) {
                    kept.push(k);
                }
            }
            let mut fresh = CoupledLu::analyse(pattern, kept)?;
            fresh.analyses += analyses;
            *this = Some(fresh);
        }
        let c = this.as_mut().expect("analysed above");
        c.values.fill(0.0);
        for (slot, v) in c.base_slots.iter().zip(values) {
            c.values[*slot] = *v;
        }
        let (col_ptr, row_idx) = (c.symbolic.col_ptr(), c.symbolic.row_idx());
        for b in blocks {
            for (j, col) in b.cols.iter().enumerate() {
                let Some(col) = col else { continue };
                let rows = &row_idx[col_ptr[*col]..col_ptr[*col + 1]];
                for (i, row) in b.rows.iter().enumerate() {
                    let Some(row) = row else { continue };
                    let slot = col_ptr[*col] + rows.binary_search(row).expect("a block entry");
                    c.values[slot] += b.values[i * 24 + j];
                }
            }
        }
        let mat = SparseColMatRef::new(c.symbolic.as_ref(), &c.values);
        c.lu = Some(
            Lu::try_new_with_symbolic(c.symbolic_lu.clone(), mat).map_err(|e| {
                FactorError(format!(
                    "LU factorization of the coupled beams failed (singular Newton matrix?): {e:?}"
                ))
            })?,
        );
        Ok(())
    }

    /// Solve A x = b in place with the last factorization.
    pub fn solve_in_place(&self, b: &mut [f64]) {
        self.lu
            .as_ref()
            .expect("factorize before solve")
            .solve_in_place(ColMut::from_slice_mut(b));
    }
}
