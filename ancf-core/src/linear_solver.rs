//! Sparse factorization of the Newton matrix with faer: the symbolic
//! analysis is done once per pattern ([`SparseSolver::new`]); every
//! refactorization is numeric only. LLᵀ is tried first (2–4× cheaper on the
//! beam pattern, see CRATES.md); a matrix that is not positive definite
//! (buckling, contact with friction) falls back to LU, whose symbolic
//! analysis is then also kept.

use crate::assembly::Pattern;
use faer::sparse::SparseColMatRef;
use faer::sparse::linalg::solvers::{Llt, Lu, SymbolicLlt, SymbolicLu};
use faer::{ColMut, Side, linalg::solvers::Solve};

enum Factor {
    None,
    Llt(Llt<usize, f64>),
    Lu(Box<Lu<usize, f64>>),
}

/// Which factorization the last `factorize` used.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum FactorKind {
    Cholesky,
    Lu,
}

pub struct SparseSolver {
    pattern: Pattern,
    symbolic_llt: SymbolicLlt<usize>,
    symbolic_lu: Option<SymbolicLu<usize>>,
    factor: Factor,
    /// Number of numeric factorizations done.
    pub factorizations: usize,
}

#[derive(Debug, Clone)]
pub struct FactorError(pub String);

impl SparseSolver {
    pub fn new(pattern: &Pattern) -> Result<Self, FactorError> {
        let symbolic_llt = SymbolicLlt::try_new(pattern.symbolic.as_ref(), Side::Lower)
            .map_err(|e| FactorError(format!("symbolic Cholesky: {e:?}")))?;
        Ok(SparseSolver {
            pattern: pattern.clone(),
            symbolic_llt,
            symbolic_lu: None,
            factor: Factor::None,
            factorizations: 0,
        })
    }

    /// Numeric factorization of the matrix with the pattern's structure and
    /// `values`. A `symmetric` matrix tries LLᵀ first (it reads only the
    /// lower triangle); a non-symmetric one (friction) goes straight to LU.
    pub fn factorize(
        &mut self,
        values: &[f64],
        symmetric: bool,
    ) -> Result<FactorKind, FactorError> {
        if values.iter().any(|v| !v.is_finite()) {
            return Err(FactorError(
                "the Newton matrix has non-finite entries".into(),
            ));
        }
        self.factorizations += 1;
        let mat = SparseColMatRef::new(self.pattern.symbolic.as_ref(), values);
        // A symmetric matrix that is not positive definite (buckling) fails
        // LLᵀ and falls through to LU.
        if symmetric
            && let Ok(llt) = Llt::try_new_with_symbolic(self.symbolic_llt.clone(), mat, Side::Lower)
        {
            self.factor = Factor::Llt(llt);
            return Ok(FactorKind::Cholesky);
        }
        if self.symbolic_lu.is_none() {
            self.symbolic_lu = Some(
                SymbolicLu::try_new(self.pattern.symbolic.as_ref())
                    .map_err(|e| FactorError(format!("symbolic LU: {e:?}")))?,
            );
        }
        let lu =
            Lu::try_new_with_symbolic(self.symbolic_lu.clone().unwrap(), mat).map_err(|e| {
                FactorError(format!(
                    "LU factorization failed (singular Newton matrix?): {e:?}"
                ))
            })?;
        self.factor = Factor::Lu(Box::new(lu));
        Ok(FactorKind::Lu)
    }

    /// Solve A x = b in place with the last factorization.
    pub fn solve_in_place(&self, b: &mut [f64]) {
        let col = ColMut::from_slice_mut(b);
        match &self.factor {
            Factor::Llt(f) => f.solve_in_place(col),
            Factor::Lu(f) => f.solve_in_place(col),
            Factor::None => panic!("solve before factorize"),
        }
    }
}
