//! Numerical building blocks with no knowledge of wires: quadrature rules,
//! 3-vector helpers, a section's twist and the run-time choice of
//! instruction set.

pub mod quadrature;
pub mod simd;
pub mod twist;
pub mod vec3;
