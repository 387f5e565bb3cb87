//! Numerical building blocks with no knowledge of wires: quadrature rules.

pub mod quadrature;
