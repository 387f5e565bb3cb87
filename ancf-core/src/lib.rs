//! # ancf-core
//!
//! Absolute nodal coordinate formulation (ANCF) beams for electrical wires
//! and cables: the fully parameterized 24-DOF element with a multilayer
//! circular cross section (Lan, Tian & Yu 2020). Data flows one way:
//! scene → model → assembly → solver → outputs. See ARCHITECTURE.md.
//!
//! Units are SI throughout (m, kg, s, N, Pa).

// Index loops over nodes, directions and Voigt components read like the
// formulas they implement (Σ_i e[3i+k] g[i][a]); iterator chains would not.
#![allow(clippy::needless_range_loop)]

pub mod assembly;
pub mod band_cholesky;
pub mod band_lu;
pub mod band_split;
pub mod cfc;
pub mod contact;
pub mod damping;
pub mod dynamics;
pub mod element;
pub mod linear_solver;
pub mod material;
pub mod model;
pub mod parallel;
pub mod preintegration;
pub mod quadrature;
pub mod rod_load;
pub mod scene;
pub mod section;
pub mod simulation;
pub mod statics;

#[cfg(test)]
mod tests {
    /// Every error the core returns works with `?` in a caller's
    /// `Box<dyn Error + Send + Sync>` (issue 15): this does not compile otherwise.
    #[test]
    fn errors_are_std_errors() {
        fn is_error<E: std::error::Error + Send + Sync + 'static>() {}
        is_error::<crate::dynamics::StepError>();
        is_error::<crate::linear_solver::FactorError>();
        is_error::<crate::statics::StaticError>();
        is_error::<crate::model::ModelError>();
        is_error::<crate::scene::SceneError>();
    }
}
