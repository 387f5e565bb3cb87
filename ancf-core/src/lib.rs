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
//! A wire in code: 1 m of a two-layer conductor pinned at one end, released
//! horizontally under gravity onto a rod across its path, stepped for
//! 0.15 s with the tip and the force on the rod printed every millisecond —
//! no scene file, no output files.
//!
//! ```
//! use ancf_core::prelude::*;
//! use std::ops::ControlFlow;
//!
//! let steel = Material::st_venant_kirchhoff(7800.0, 2e11, 0.3, 1.0);
//! let rubber = Material::st_venant_kirchhoff(1200.0, 5e7, 0.3, 1.0);
//! let model = WireBuilder::new(1.0, 8)
//!     .layer(steel, 0.005)
//!     .layer(rubber, 0.01)
//!     .support(0, SupportKind::Pin)
//!     .gravity([0.0, 0.0, -9.81])
//!     // A 1 cm rod along y, 2 cm below the wire at x = 0.8 m; line law, ε_L = 5e7 N/m².
//!     .rod(Rod::line([0.8, 0.0, -0.04], [0.0, 1.0, 0.0], 0.01, 5e7))
//!     .build()?;
//! let settings = DynamicSettings { time_step: 1e-4, end_time: 0.15, ..Default::default() };
//! let mut sim = Simulation::new(&model, settings, Initial::Reference)?;
//! let mut largest = 0.0_f64;
//! sim.run_until(0.15, |sim, info| {
//!     let force = ancf_core::math::vec3::norm(info.rod_forces[0]);
//!     largest = largest.max(force);
//!     if sim.steps().0 % 10 == 0 {
//!         let tip = model.node_position(&sim.state().q, model.n_elements);
//!         println!("{:.3} s: tip z {:.4} m, rod {force:.1} N", sim.state().time, tip[2]);
//!     }
//!     ControlFlow::Continue(())
//! })?;
//! // The wire reaches the rod (its point at x = 0.8 m falls 2 cm), which
//! // then carries it.
//! let first = sim.contact().and_then(|c| c.first_time).expect("the wire touches the rod");
//! assert!(first > 0.02 && first < 0.15, "first contact at {first} s");
//! assert!(largest > 0.0);
//! # Ok::<(), ancf_core::Error>(())
//! ```

// Index loops over nodes, directions and Voigt components read like the
// formulas they implement (Σ_i e[3i+k] g[i][a]); iterator chains would not.
#![allow(clippy::needless_range_loop)]
#![warn(missing_docs)]

// The folders follow the data flow: scene → model → forces → linear algebra
// → solvers → loads. `math`, `element`, `material` and `section` are what a
// model is made of.
pub mod check;
pub mod element;
pub mod error;
pub mod forces;
pub mod linalg;
pub mod loads;
pub mod material;
pub mod math;
pub mod model;
pub mod plausibility;
#[cfg(feature = "scene")]
pub mod scene;
pub mod section;
pub mod solve;

pub use error::Error;
pub use material::Material;
pub use model::contact::{ContactLaw, ContactSettings, RestitutionModel, Rod};
pub use model::damping::Damping;
pub use model::{Model, ModelError, SupportKind, WireBuilder};
#[cfg(feature = "scene")]
pub use scene::{Scene, SceneError};
pub use solve::cancel::CancelToken;
pub use solve::dynamics::{DynamicSettings, NewtonKind};
pub use solve::simulation::{Initial, Simulation, SimulationError};
pub use solve::statics::{StaticSettings, solve_static};

/// What most programs need: `use ancf_core::prelude::*;` — the builder and
/// what it takes (materials, rods, supports, damping, contact settings),
/// the solver settings, the simulation, scenes and the errors.
pub mod prelude {
    pub use crate::error::Error;
    pub use crate::material::Material;
    pub use crate::math::simd::SimdPath;
    pub use crate::model::contact::{
        BeamContact, ContactLaw, ContactSettings, RestitutionModel, Rod,
    };
    pub use crate::model::damping::Damping;
    pub use crate::model::{
        BeamBuilder, Model, ModelError, PointLoad, Support, SupportKind, WireBuilder,
    };
    #[cfg(feature = "scene")]
    pub use crate::scene::{Analysis, Scene, SceneError};
    pub use crate::solve::cancel::CancelToken;
    pub use crate::solve::dynamics::{DynamicSettings, Energies, NewtonKind};
    pub use crate::solve::simulation::{Initial, Simulation, SimulationError};
    pub use crate::solve::statics::{StaticSettings, solve_static};
}

#[cfg(test)]
mod tests {
    /// Every error the core returns works with `?` in a caller's
    /// `Box<dyn Error + Send + Sync>`: this does not compile otherwise.
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
