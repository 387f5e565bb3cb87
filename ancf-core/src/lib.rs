//! # ancf-core
//!
//! Absolute nodal coordinate formulation (ANCF) beams for electrical wires
//! and cables: the fully parameterized 24-DOF element with a multilayer
//! circular cross section (Lan, Tian & Yu 2020). Data flows one way:
//! scene → model → forces → linear algebra → solver → loads and outputs.
//! See ARCHITECTURE.md.
//!
//! Units are SI throughout (m, kg, s, N, Pa).

// Index loops over nodes, directions and Voigt components read like the
// formulas they implement (Σ_i e[3i+k] g[i][a]); iterator chains would not.
#![allow(clippy::needless_range_loop)]

// The folders follow the data flow: scene → model → forces → linear algebra
// → solvers → loads. `math`, `element`, `material` and `section` are what a
// model is made of.
pub mod element;
pub mod forces;
pub mod linalg;
pub mod loads;
pub mod material;
pub mod math;
pub mod model;
pub mod scene;
pub mod section;
pub mod solve;

#[cfg(test)]
mod tests {
    /// Every error the core returns works with `?` in a caller's
    /// `Box<dyn Error + Send + Sync>` (issue 15): this does not compile otherwise.
    #[test]
    fn errors_are_std_errors() {
        fn is_error<E: std::error::Error + Send + Sync + 'static>() {}
        is_error::<crate::solve::dynamics::StepError>();
        is_error::<crate::linalg::linear_solver::FactorError>();
        is_error::<crate::solve::statics::StaticError>();
        is_error::<crate::model::ModelError>();
        is_error::<crate::scene::SceneError>();
    }
}
