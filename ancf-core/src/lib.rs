//! # ancf-core
//!
//! Absolute nodal coordinate formulation (ANCF) beams for electrical wires
//! and cables: the fully parameterized 24-DOF element with a multilayer
//! circular cross section (Lan, Tian & Yu 2020). Data flows one way:
//! scene → model → assembly → solver → outputs. See ARCHITECTURE.md.
//!
//! Units are SI throughout (m, kg, s, N, Pa).

pub mod element;
pub mod material;
pub mod quadrature;
pub mod section;
