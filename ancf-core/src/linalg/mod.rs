//! The Newton matrix's linear algebra: band LLᵀ and LU (the wire's matrix is
//! block tridiagonal), the split band factorization for two threads, the
//! solver choice, the coupled beams' general LU, the Newton matrix as a sum read where
//! it is factored, and the work sharing of the short parallel sections.

pub mod band_cholesky;
pub mod band_lu;
pub mod band_split;
pub mod block_tridiagonal;
pub mod coupled;
pub mod linear_solver;
pub(crate) mod parallel;
pub mod pattern;
pub mod separated_lu;
pub mod value_sum;
