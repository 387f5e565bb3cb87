//! Numerical building blocks with no knowledge of wires: quadrature rules,
//! 3-vector helpers and the run-time choice of instruction set.

pub mod quadrature;
pub mod simd;
pub mod vec3;
