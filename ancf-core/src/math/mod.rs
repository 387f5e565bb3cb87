//! Numerical building blocks with no knowledge of wires: quadrature rules
//! and 3-vector helpers.

pub mod quadrature;
pub mod vec3;
