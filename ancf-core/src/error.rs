//! One error type for programs built on the core: every fallible
//! front-door call — reading a scene, building a model, the static
//! equilibrium, a simulation's setup and steps — converts into [`Error`]
//! with `?`, and a caller matches the kind it can handle:
//!
//! * bad input: [`Error::Scene`] (the scene file's field) or [`Error::Model`]
//!   (the model's part, for models built in code);
//! * [`Error::Static`]: the static equilibrium did not converge (its last
//!   converged state is kept);
//! * [`Error::Simulation`]: a dynamic run could not start or go on —
//!   [`SimulationError::Step`] names the step and the time, and its
//!   [`StepError`](crate::solve::dynamics::StepError) the kind: Newton not
//!   converged, a non-finite residual, a step rejected for its penetration
//!   or its energy gain, a factorization.

use crate::model::ModelError;
#[cfg(feature = "scene")]
use crate::scene::SceneError;
use crate::solve::simulation::SimulationError;
use crate::solve::statics::StaticError;

/// Every error of the core's front door.
#[derive(Clone, Debug)]
pub enum Error {
    /// A scene that cannot be run: the field (TOML path) and why.
    #[cfg(feature = "scene")]
    Scene(SceneError),
    /// A model built in code that cannot be made: the part and why.
    Model(ModelError),
    /// A static solve that did not converge.
    Static(StaticError),
    /// A dynamic simulation that could not start or go on.
    Simulation(SimulationError),
}

impl std::fmt::Display for Error {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        match self {
            #[cfg(feature = "scene")]
            Error::Scene(e) => write!(f, "{e}"),
            Error::Model(e) => write!(f, "{e}"),
            Error::Static(e) => write!(f, "{e}"),
            Error::Simulation(e) => write!(f, "{e}"),
        }
    }
}

impl std::error::Error for Error {
    fn source(&self) -> Option<&(dyn std::error::Error + 'static)> {
        match self {
            #[cfg(feature = "scene")]
            Error::Scene(e) => Some(e),
            Error::Model(e) => Some(e),
            Error::Static(e) => Some(e),
            Error::Simulation(e) => Some(e),
        }
    }
}

#[cfg(feature = "scene")]
impl From<SceneError> for Error {
    fn from(e: SceneError) -> Self {
        Error::Scene(e)
    }
}

impl From<ModelError> for Error {
    fn from(e: ModelError) -> Self {
        Error::Model(e)
    }
}

impl From<StaticError> for Error {
    fn from(e: StaticError) -> Self {
        Error::Static(e)
    }
}

impl From<SimulationError> for Error {
    fn from(e: SimulationError) -> Self {
        Error::Simulation(e)
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::prelude::*;
    use crate::solve::dynamics::StepError;

    /// A program's pipeline with `?` into [`Error`], and a caller matching
    /// the step failure's kind: a 1 m steel wire on a rod far too soft for
    /// it, with the penetration limit tight, fails by penetration.
    fn run(stiffness: f64) -> Result<(), Error> {
        let steel = Material::st_venant_kirchhoff(7800.0, 2e11, 0.3, 1.0);
        let model = WireBuilder::new(1.0, 4)
            .layer(steel, 0.01)
            .support(0, SupportKind::Pin)
            .gravity([0.0, 0.0, -9.81])
            .rod(Rod::line(
                [0.8, 0.0, -0.05],
                [0.0, 1.0, 0.0],
                0.02,
                stiffness,
            ))
            .build()?;
        let settings = DynamicSettings {
            time_step: 1e-3,
            end_time: 0.3,
            max_cuts: 2,
            ..Default::default()
        };
        let mut sim = Simulation::new(&model, settings, Initial::Reference)?;
        while !sim.is_finished() {
            sim.step()?;
        }
        Ok(())
    }

    #[test]
    fn a_caller_matches_the_kind_of_failure() {
        assert!(run(5e7).is_ok());
        match run(1.0) {
            Err(Error::Simulation(SimulationError::Step { step, time, error })) => {
                assert!(step > 0 && time > 0.0);
                assert!(
                    matches!(error.cause(), StepError::Penetration { .. }),
                    "{error}"
                );
                assert!(error.likely_cause().contains("contact_stiffness"));
            }
            other => panic!("expected a penetration failure, got {other:?}"),
        }
        let bad = WireBuilder::new(-1.0, 4).build().map_err(Error::from);
        assert!(matches!(bad, Err(Error::Model(ModelError::Wire { .. }))));
    }
}
