//! Jacobian blocks between two beams' elements — a wire element and a
//! frame member's element in contact — kept apart from the element
//! pattern: they appear, move and vanish as the contact slides, while the
//! pattern (and the fast solvers built on it) stays that of the separate
//! beams. The linear solver adds them to the pattern's matrix when it
//! factors ([`crate::linalg::linear_solver::SparseSolver::factorize_coupled`]).

use crate::element::ElementMatrix;
use crate::linalg::coupled::CoupledBlock;
use crate::model::Model;

/// −∂Q_rows/∂q_cols and −∂Q_rows/∂v_cols between element `rows` (whose
/// force) and element `cols` (whose coordinates), row-major 24 × 24.
#[derive(Clone, Debug)]
pub struct CouplingBlock {
    /// The element whose generalized force the rows are.
    pub rows: usize,
    /// The element whose coordinates the columns are.
    pub cols: usize,
    /// −∂Q/∂q (N/m).
    pub kq: Box<ElementMatrix>,
    /// −∂Q/∂v (N s/m).
    pub kv: Box<ElementMatrix>,
}

/// The coupling blocks of one Jacobian evaluation.
#[derive(Clone, Debug, Default)]
pub struct Coupling {
    /// The blocks, each (rows, cols) pair once.
    pub blocks: Vec<CouplingBlock>,
}

impl Coupling {
    /// No blocks (the allocation kept).
    pub fn clear(&mut self) {
        self.blocks.clear();
    }

    /// Whether there are no blocks.
    pub fn is_empty(&self) -> bool {
        self.blocks.is_empty()
    }

    /// Add `kq` and `kv` to the block (`rows`, `cols`), made when new.
    pub fn add(
        &mut self,
        rows: usize,
        cols: usize,
        kq: Option<&ElementMatrix>,
        kv: Option<&ElementMatrix>,
    ) {
        let k = match self
            .blocks
            .iter()
            .position(|b| b.rows == rows && b.cols == cols)
        {
            Some(k) => k,
            None => {
                self.blocks.push(CouplingBlock {
                    rows,
                    cols,
                    kq: Box::new([0.0; 576]),
                    kv: Box::new([0.0; 576]),
                });
                self.blocks.len() - 1
            }
        };
        let b = &mut self.blocks[k];
        if let Some(kq) = kq {
            b.kq.iter_mut().zip(kq).for_each(|(a, v)| *a += v);
        }
        if let Some(kv) = kv {
            b.kv.iter_mut().zip(kv).for_each(|(a, v)| *a += v);
        }
    }

    /// The blocks of the matrix `c_q K_q + c_v K_v` on the unknowns of
    /// `model`, for the solver (`c_v` ignored when 0).
    pub fn combined(&self, model: &Model, c_q: f64, c_v: f64, out: &mut Vec<CoupledBlock>) {
        out.clear();
        for b in &self.blocks {
            let values: [f64; 576] = if c_v != 0.0 {
                std::array::from_fn(|e| c_q * b.kq[e] + c_v * b.kv[e])
            } else {
                std::array::from_fn(|e| c_q * b.kq[e])
            };
            out.push(CoupledBlock {
                rows: model.element_unknowns(b.rows),
                cols: model.element_unknowns(b.cols),
                values: Box::new(values),
            });
        }
    }
}
