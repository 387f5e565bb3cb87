//! # ancf-core
//!
//! Absolute nodal coordinate formulation (ANCF) beams for electrical wires
//! and cables: the fully parameterized 24-DOF element with a multilayer
//! circular cross section (Lan, Tian & Yu 2020). Data flows one way:
//! scene → model → assembly → solver → outputs. See ARCHITECTURE.md.
//!
//! Units are SI throughout (m, kg, s, N, Pa).

pub mod assembly;
pub mod dynamics;
pub mod element;
pub mod linear_solver;
pub mod material;
pub mod model;
pub mod quadrature;
pub mod scene;
pub mod section;
pub mod statics;
pub mod contact;
