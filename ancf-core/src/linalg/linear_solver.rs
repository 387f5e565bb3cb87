//! Factorization of the Newton matrix: the structural analysis is done once
//! per pattern ([`SparseSolver::new`]); every refactorization is numeric
//! only. A wire's pattern (node blocks, block tridiagonal) goes to the
//! block LU ([`BlockTridiagonalLu`]) when the matrix is non-symmetric, or a
//! dynamic one ([`SparseSolver::for_dynamics`]) with fewer than
//! `BLOCK_LU_MAX_SYMMETRIC` unknowns. Otherwise, or when a block
//! is singular, a symmetric matrix tries LLᵀ first — as a band
//! ([`BandCholesky`]: a wire's pattern is banded, and the band form was
//! several times faster than faer's sparse LLᵀ; from 2000 unknowns
//! on split in two halves for two threads, [`SplitBandCholesky`]) or, for a wider
//! pattern, faer's sparse LLᵀ. A non-symmetric matrix (friction,
//! Kelvin–Voigt damping) on a band pattern tries a band LU without pivoting
//! ([`BandLu`], 10× faster than faer's LU on the impact scene); a matrix
//! that is not positive definite (buckling), or whose band LU meets a small
//! pivot, goes to faer's pivoting sparse LU, whose symbolic analysis is
//! then also kept.

use crate::linalg::band_cholesky::BandCholesky;
use crate::linalg::band_lu::BandLu;
use crate::linalg::band_split::{SPLIT_MIN_UNKNOWNS, SplitBandCholesky};
use crate::linalg::block_tridiagonal::{BlockTridiagonalLu, Precision};
use crate::linalg::coupled::{CoupledBlock, CoupledLu};
use crate::linalg::pattern::Pattern;
use crate::linalg::separated_lu::SeparatedLu;
use crate::linalg::value_sum::{ValueSum, all_finite};
use faer::dyn_stack::{MemBuffer, MemStack, StackReq};
use faer::sparse::SparseColMatRef;
use faer::sparse::linalg::cholesky::{
    CholeskySymbolicParams, LltRef, SymbolicCholesky, SymmetricOrdering,
    factorize_symbolic_cholesky,
};
use faer::sparse::linalg::solvers::{Lu, SymbolicLu};
use faer::{ColMut, Conj, MatMut, Par, Side, linalg::solvers::Solve};

/// Largest half-bandwidth factored as a band (a wire's is 23); wider
/// patterns go to faer's sparse LLᵀ.
const MAX_BAND: usize = 48;

/// Symmetric dynamic Newton matrices up to this many unknowns go to the
/// block LU rather than the band LLᵀ: its modified-Newton steps are faster
/// up to about a thousand elements. At several thousand the split LLᵀ,
/// factoring and solving on two threads, keeps full-Newton steps faster
/// for equal modified-Newton steps.
const BLOCK_LU_MAX_SYMMETRIC: usize = 20_000;

/// Whether every value of the coupling blocks is finite.
fn coupling_finite(blocks: &[CoupledBlock]) -> bool {
    blocks.iter().all(|b| all_finite(&b.values[..]))
}

/// faer's sparse LLᵀ at its low level: the symbolic factor, the factor's
/// values and one workspace for factorization and solves, all allocated
/// once (the mid-level `Llt` allocates both on every refactorization).
struct SparseLlt {
    symbolic: SymbolicCholesky<usize>,
    values: Vec<f64>,
    workspace: MemBuffer,
}

impl SparseLlt {
    fn new(pattern: &Pattern) -> Result<Self, FactorError> {
        let symbolic = factorize_symbolic_cholesky(
            pattern.symbolic.as_ref(),
            Side::Lower,
            SymmetricOrdering::Amd,
            CholeskySymbolicParams::default(),
        )
        .map_err(|e| FactorError(format!("symbolic Cholesky: {e:?}")))?;
        let workspace = MemBuffer::try_new(StackReq::any_of(&[
            symbolic.factorize_numeric_llt_scratch::<f64>(Par::Seq, Default::default()),
            symbolic.solve_in_place_scratch::<f64>(1, Par::Seq),
        ]))
        .map_err(|e| FactorError(format!("Cholesky workspace: {e:?}")))?;
        Ok(SparseLlt {
            values: vec![0.0; symbolic.len_val()],
            symbolic,
            workspace,
        })
    }

    /// Whether the factorization succeeded (the matrix is positive definite).
    fn factorize(&mut self, mat: SparseColMatRef<'_, usize, f64>) -> bool {
        self.symbolic
            .factorize_numeric_llt(
                &mut self.values,
                mat,
                Side::Lower,
                Default::default(),
                Par::Seq,
                MemStack::new(&mut self.workspace),
                Default::default(),
            )
            .is_ok()
    }

    fn solve_in_place(&mut self, b: &mut [f64]) {
        let n = b.len();
        LltRef::new(&self.symbolic, &self.values).solve_in_place_with_conj(
            Conj::No,
            MatMut::from_column_major_slice_mut(b, n, 1),
            Par::Seq,
            MemStack::new(&mut self.workspace),
        )
    }
}

/// The LLᵀ factorization a pattern uses.
enum Cholesky {
    Band(BandCholesky),
    /// A band of at least `band_split::SPLIT_MIN_UNKNOWNS` unknowns, in two
    /// halves that run on two threads.
    SplitBand(Box<SplitBandCholesky>),
    Sparse(Box<SparseLlt>),
}

impl Cholesky {
    /// Half-bandwidth of a band pattern.
    fn band(&self) -> Option<usize> {
        match self {
            Cholesky::Band(b) => Some(b.half_bandwidth()),
            Cholesky::SplitBand(b) => Some(b.half_bandwidth()),
            Cholesky::Sparse(_) => None,
        }
    }
}

enum Factor {
    None,
    Llt,
    BlockLu,
    BandLu,
    Lu(Box<Lu<usize, f64>>),
    Separated,
    Coupled,
}

/// Which factorization the last `factorize` used.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum FactorKind {
    /// LLᵀ (band, split band or faer's sparse).
    Cholesky,
    /// LU (block tridiagonal, band, or faer's pivoting sparse LU).
    Lu,
}

/// The Newton matrix's factorization on a fixed pattern: the structure is
/// analysed once (`new`), the values factored at every refresh
/// (`factorize`) and solved with at every iteration (`solve_in_place`).
pub struct SparseSolver {
    pattern: Pattern,
    llt: Cholesky,
    /// The block-tridiagonal LU for non-symmetric matrices on a node-block
    /// pattern (every wire's), built at the first one; `Some(None)`: the
    /// pattern is not block tridiagonal.
    block_lu: Option<Option<BlockTridiagonalLu>>,
    /// The band LU for non-symmetric matrices whose block LU met a singular
    /// block, built at the first one (its storage is twice the Cholesky
    /// band's: 18 MB at 4096 elements).
    band_lu: Option<BandLu>,
    symbolic_lu: Option<SymbolicLu<usize>>,
    /// The LU of the pattern's matrix plus coupling blocks between beams
    /// around the coupled nodes, built at the first coupled matrix
    /// (`Some(None)`: the pattern is not block tridiagonal) …
    separated: Option<Option<SeparatedLu>>,
    /// … and faer's sparse LU of the same, for a pattern that is not or a
    /// block that is singular.
    coupled: Option<CoupledLu>,
    factor: Factor,
    /// Whether the matrices are (1 − α_m) M + c_k K (dynamics): the block
    /// LU then also takes symmetric ones. A stiffness alone (statics) is
    /// not mass-dominated and can be ill-conditioned (a nearly
    /// incompressible cover): it keeps the band LLᵀ.
    mass_dominated: bool,
    /// Number of numeric factorizations done.
    pub factorizations: usize,
}

/// A Newton matrix that could not be factored (not positive definite where
/// LLᵀ was expected, a zero pivot the fallback could not handle).
#[derive(Debug, Clone)]
pub struct FactorError(pub String);

impl std::fmt::Display for FactorError {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.write_str(&self.0)
    }
}

impl std::error::Error for FactorError {}

impl SparseSolver {
    /// The solver for matrices on `pattern`: the factorization it can
    /// take (band, split band, block tridiagonal, general sparse) is chosen
    /// from the structure here.
    pub fn new(pattern: &Pattern) -> Result<Self, FactorError> {
        let sym = pattern.symbolic.as_ref();
        let p = BandCholesky::bandwidth(sym.col_ptr(), sym.row_idx());
        let n = sym.nrows();
        let llt = if p <= MAX_BAND && n >= SPLIT_MIN_UNKNOWNS && n >= 3 * p {
            Cholesky::SplitBand(Box::new(SplitBandCholesky::new(
                n,
                p,
                sym.col_ptr(),
                sym.row_idx(),
            )))
        } else if p <= MAX_BAND {
            Cholesky::Band(BandCholesky::new(n, p, sym.col_ptr(), sym.row_idx()))
        } else {
            Cholesky::Sparse(Box::new(SparseLlt::new(pattern)?))
        };
        Ok(SparseSolver {
            pattern: pattern.clone(),
            llt,
            block_lu: None,
            band_lu: None,
            symbolic_lu: None,
            separated: None,
            coupled: None,
            factor: Factor::None,
            mass_dominated: false,
            factorizations: 0,
        })
    }

    /// The solver of a dynamic Newton matrix (see `mass_dominated`).
    pub fn for_dynamics(pattern: &Pattern) -> Result<Self, FactorError> {
        Ok(SparseSolver {
            mass_dominated: true,
            ..SparseSolver::new(pattern)?
        })
    }

    /// Whether a matrix goes to the block LU first: a non-symmetric one, or
    /// a dynamic symmetric one below `BLOCK_LU_MAX_SYMMETRIC` unknowns.
    fn takes_block_lu(&self, symmetric: bool) -> bool {
        let n = self.pattern.symbolic.nrows();
        !symmetric || (self.mass_dominated && n < BLOCK_LU_MAX_SYMMETRIC)
    }

    /// The block LU of the pattern, built at the first call (`None`: the
    /// pattern is not block tridiagonal).
    fn block_lu(&mut self) -> Option<&mut BlockTridiagonalLu> {
        self.block_lu
            .get_or_insert_with(|| {
                let sym = self.pattern.symbolic.as_ref();
                BlockTridiagonalLu::new(sym.nrows(), sym.col_ptr(), sym.row_idx())
            })
            .as_mut()
    }

    /// Numeric factorization of the matrix with the pattern's structure and
    /// `values`. A `symmetric` matrix tries LLᵀ first (it reads only the
    /// lower triangle); a non-symmetric one (friction) goes straight to LU.
    pub fn factorize(
        &mut self,
        values: &[f64],
        symmetric: bool,
    ) -> Result<FactorKind, FactorError> {
        if !all_finite(values) {
            return Err(FactorError(
                "the Newton matrix has non-finite entries".into(),
            ));
        }
        self.factorizations += 1;
        // A wire's pattern (node blocks): the block LU, for symmetric
        // matrices too below BLOCK_LU_MAX_SYMMETRIC unknowns, where its
        // solves beat the band LLᵀ's (they dominate modified Newton).
        if self.takes_block_lu(symmetric)
            && let Some(block) = self.block_lu()
            && block.factorize(values).is_ok()
        {
            self.factor = Factor::BlockLu;
            return Ok(FactorKind::Lu);
        }
        let mat = SparseColMatRef::new(self.pattern.symbolic.as_ref(), values);
        // A symmetric matrix that is not positive definite (buckling) fails
        // LLᵀ and falls through to LU.
        if symmetric {
            let positive_definite = match &mut self.llt {
                Cholesky::Band(band) => band.factorize(values).is_ok(),
                Cholesky::SplitBand(band) => band.factorize(values).is_ok(),
                Cholesky::Sparse(sparse) => sparse.factorize(mat),
            };
            if positive_definite {
                self.factor = Factor::Llt;
                return Ok(FactorKind::Cholesky);
            }
        } else if let Some(p) = self.llt.band()
            && self
                .band_lu
                .get_or_insert_with(|| {
                    let sym = self.pattern.symbolic.as_ref();
                    BandLu::new(sym.nrows(), p, sym.col_ptr(), sym.row_idx())
                })
                .factorize(values)
                .is_ok()
        {
            self.factor = Factor::BandLu;
            return Ok(FactorKind::Lu);
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

    /// [`SparseSolver::factorize`] of the matrix with the pattern's
    /// `values` plus `blocks` coupling two beams (contact between the wire
    /// and a member): without blocks the pattern's own factorizations,
    /// with them the block elimination around the coupled nodes
    /// ([`SeparatedLu`]), or faer's sparse LU of the combined matrix when
    /// that cannot be used.
    pub fn factorize_coupled(
        &mut self,
        values: &[f64],
        blocks: &[CoupledBlock],
        symmetric: bool,
    ) -> Result<FactorKind, FactorError> {
        if blocks.is_empty() {
            return self.factorize(values, symmetric);
        }
        if !(all_finite(values) && coupling_finite(blocks)) {
            return Err(FactorError(
                "the Newton matrix has non-finite entries".into(),
            ));
        }
        self.factorizations += 1;
        if let Some(separated) = self.separated_lu()
            && separated.factorize(values, blocks).is_ok()
        {
            self.factor = Factor::Separated;
            return Ok(FactorKind::Lu);
        }
        CoupledLu::factorize(&mut self.coupled, &self.pattern, values, blocks)?;
        self.factor = Factor::Coupled;
        Ok(FactorKind::Lu)
    }

    /// The separated LU of the pattern, built at the first call (`None`:
    /// the pattern is not block tridiagonal).
    fn separated_lu(&mut self) -> Option<&mut SeparatedLu> {
        self.separated
            .get_or_insert_with(|| {
                let sym = self.pattern.symbolic.as_ref();
                BlockTridiagonalLu::new(sym.nrows(), sym.col_ptr(), sym.row_idx())
                    .map(SeparatedLu::new)
            })
            .as_mut()
    }

    /// [`SparseSolver::factorize_coupled`] of the matrix `sum`: the block
    /// LU and the separated LU read the sum where they load each block,
    /// with nothing formed (one pass over the value arrays instead of
    /// three), and the block LU keeps its blocks in `precision`; the other
    /// factorizations, and a block or separated LU that fails, get the sum
    /// written into `formed` (sized to one value per slot here) first, and
    /// keep double precision.
    pub fn factorize_sum(
        &mut self,
        sum: &ValueSum,
        formed: &mut Vec<f64>,
        blocks: &[CoupledBlock],
        symmetric: bool,
        precision: Precision,
    ) -> Result<FactorKind, FactorError> {
        if blocks.is_empty()
            && self.takes_block_lu(symmetric)
            && let Some(block) = self.block_lu()
            && block.factorize_sum(sum, precision).is_ok()
        {
            self.factorizations += 1;
            self.factor = Factor::BlockLu;
            return Ok(FactorKind::Lu);
        }
        if !blocks.is_empty()
            && coupling_finite(blocks)
            && let Some(separated) = self.separated_lu()
            && separated.factorize_sum(sum, blocks).is_ok()
        {
            self.factorizations += 1;
            self.factor = Factor::Separated;
            return Ok(FactorKind::Lu);
        }
        formed.resize(self.pattern.nnz(), 0.0);
        sum.write(formed);
        self.factorize_coupled(formed, blocks, symmetric)
    }

    /// Symbolic analyses of coupled structures so far.
    pub fn coupled_analyses(&self) -> usize {
        self.coupled.as_ref().map_or(0, |c| c.analyses)
    }

    /// The precision the last factorization keeps its solves' blocks in:
    /// single only for a block LU asked for it (see
    /// [`SparseSolver::factorize_sum`]), double for every other.
    pub fn precision(&self) -> Precision {
        match (&self.factor, &self.block_lu) {
            (Factor::BlockLu, Some(Some(block))) => block.precision(),
            _ => Precision::Double,
        }
    }

    /// Solve A x = b in place with the last factorization.
    pub fn solve_in_place(&mut self, b: &mut [f64]) {
        match (&self.factor, &mut self.llt) {
            (Factor::Llt, Cholesky::Band(band)) => band.solve_in_place(b),
            (Factor::Llt, Cholesky::SplitBand(band)) => band.solve_in_place(b),
            (Factor::Llt, Cholesky::Sparse(sparse)) => sparse.solve_in_place(b),
            (Factor::BlockLu, _) => self
                .block_lu
                .as_mut()
                .and_then(Option::as_mut)
                .expect("block LU")
                .solve_in_place(b),
            (Factor::BandLu, _) => self.band_lu.as_ref().expect("band LU").solve_in_place(b),
            (Factor::Lu(f), _) => f.solve_in_place(ColMut::from_slice_mut(b)),
            (Factor::Separated, _) => self
                .separated
                .as_mut()
                .and_then(Option::as_mut)
                .expect("separated LU")
                .solve_in_place(b),
            (Factor::Coupled, _) => self.coupled.as_ref().expect("coupled LU").solve_in_place(b),
            (Factor::None, _) => panic!("solve before factorize"),
        }
    }
}
