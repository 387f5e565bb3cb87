//! # ancf-core
//!
//! Absolute nodal coordinate formulation (ANCF) beams for electrical wires
//! and cables: the fully parameterized 24-DOF element with a multilayer
//! circular cross section (Lan, Tian & Yu 2020). Data flows one way:
//! scene → model → forces → linear algebra → solver → loads and outputs.
//! See ARCHITECTURE.md.
//!
//! Units are SI throughout (m, kg, s, N, Pa).
//!
//! A pendulum in code: a 1 m two-layer wire pinned at one end, released
//! horizontally under gravity, stepped for 0.1 s, its tip read.
//!
//! ```
//! use ancf_core::prelude::*;
//!
//! let steel = Material::st_venant_kirchhoff(7800.0, 2e11, 0.3, 1.0);
//! let rubber = Material::st_venant_kirchhoff(1200.0, 5e7, 0.3, 1.0);
//! let model = WireBuilder::new(1.0, 8)
//!     .layer(steel, 0.005)
//!     .layer(rubber, 0.01)
//!     .support(0, SupportKind::Pin)
//!     .gravity([0.0, 0.0, -9.81])
//!     .build()?;
//! let settings = DynamicSettings { time_step: 1e-3, end_time: 0.1, ..Default::default() };
//! let mut sim = Simulation::new(&model, settings, Initial::Reference)?;
//! while !sim.is_finished() {
//!     sim.step()?;
//! }
//! let tip = model.node_position(&sim.state().q, model.n_elements);
//! // Free fall for 0.1 s would be 4.9 cm; the pinned wire's tip falls more
//! // (it swings about the pin), its x barely moves yet.
//! assert!(tip[2] < -0.049 && tip[0] > 0.99, "{tip:?}");
//! # Ok::<(), ancf_core::Error>(())
//! ```

// Index loops over nodes, directions and Voigt components read like the
// formulas they implement (Σ_i e[3i+k] g[i][a]); iterator chains would not.
#![allow(clippy::needless_range_loop)]
#![warn(missing_docs)]

// The folders follow the data flow: scene → model → forces → linear algebra
// → solvers → loads. `math`, `element`, `material` and `section` are what a
// model is made of.
pub mod element;
pub mod error;
pub mod forces;
pub(crate) mod linalg;
pub mod loads;
pub mod material;
pub mod math;
pub mod model;
#[cfg(feature = "scene")]
pub mod scene;
pub mod section;
pub mod solve;

pub use error::Error;

/// What most programs need: `use ancf_core::prelude::*;`.
pub mod prelude {
    pub use crate::error::Error;
    pub use crate::forces::contact::{ContactLaw, RestitutionModel, Rod};
    pub use crate::material::Material;
    pub use crate::math::simd::SimdPath;
    pub use crate::model::{Model, SupportKind, WireBuilder};
    #[cfg(feature = "scene")]
    pub use crate::scene::{Analysis, Scene, SceneError};
    pub use crate::solve::dynamics::{DynamicSettings, Energies, NewtonKind};
    pub use crate::solve::simulation::{Initial, Simulation, SimulationError};
    pub use crate::solve::statics::{StaticSettings, solve_static};
}

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
        #[cfg(feature = "scene")]
        is_error::<crate::scene::SceneError>();
    }
}
