//! Why a step, or the integrator's setup, failed: kinds a caller can match.

use crate::linalg::linear_solver::FactorError;

/// The matrix a factorization error is about.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Matrix {
    /// The symbolic analysis of the Newton matrix's pattern.
    Pattern,
    /// The mass matrix (the initial acceleration).
    Mass,
    /// The Newton matrix (1 − α_m) M + … of a step.
    Newton,
}

/// Why a time step (or the solver's setup) failed: kinds a caller can
/// match; [`StepError::cause`] looks through the step halvings.
#[derive(Clone, Debug)]
pub enum StepError {
    /// Newton's relative residual stayed above `tolerance` for `iterations`
    /// iterations.
    NotConverged {
        /// The iteration limit.
        iterations: usize,
        /// The relative residual tolerance.
        tolerance: f64,
    },
    /// The residual became NaN or infinite.
    NonFinite,
    /// A converged step's energy is NaN or infinite.
    NonFiniteEnergy,
    /// A converged step turned a node's gradients over (their
    /// determinant changed sign, [`crate::model::Model::inverted_node`]):
    /// the element there was crushed through itself. Rejected.
    Inverted {
        /// The node, counted over the model.
        node: usize,
    },
    /// A converged step drove the wire `depth` m into a rod, deeper than
    /// `limit` wire radii (`contact.max_penetration`): rejected.
    Penetration {
        /// Deepest penetration, m.
        depth: f64,
        /// The limit, wire radii.
        limit: f64,
    },
    /// A converged step would raise total + dissipated energy by `gain` J
    /// above its start: rejected (the contact was not resolved).
    EnergyGain {
        /// The gain, J.
        gain: f64,
    },
    /// A matrix could not be factored.
    Factorization {
        /// Which matrix.
        matrix: Matrix,
        /// The factorization's error.
        error: FactorError,
    },
    /// The step was halved `cuts` times, down to `h` (s), and still failed
    /// with `cause`.
    Halved {
        /// How many times the step was halved.
        cuts: usize,
        /// The last step size tried, s.
        h: f64,
        /// The last failure.
        cause: Box<StepError>,
    },
    /// An adaptive run's local error estimate stayed above the tolerance
    /// down to a step of `h` s.
    ErrorEstimate {
        /// The shortest step tried, s.
        h: f64,
        /// Its local error estimate, m.
        error: f64,
        /// The tolerance, m.
        allowed: f64,
    },
    /// Something else: a snapshot that does not fit the model.
    Invalid(String),
}

impl StepError {
    /// The failure itself, through any step halvings.
    pub fn cause(&self) -> &StepError {
        match self {
            StepError::Halved { cause, .. } => cause.cause(),
            other => other,
        }
    }

    /// What usually causes this kind of failure, and what to change (scene
    /// field names): for messages to a user.
    pub fn likely_cause(&self) -> &'static str {
        match self.cause() {
            StepError::NotConverged { .. } | StepError::Halved { .. } => {
                "a time step too large for the stiffness (material penalty, contact) or an unstable \
                 configuration; reduce analysis.time_step"
            }
            StepError::NonFinite | StepError::NonFiniteEnergy => {
                "an element turned inside out or a time step far too large; reduce analysis.time_step"
            }
            StepError::Inverted { .. } => {
                "a blow or a load beyond what the member's section carries, or a time step too \
                 coarse for the blow; reduce analysis.time_step, then check the member's section \
                 and material"
            }
            StepError::Penetration { .. } => {
                "a contact too soft for the blow or a time step too coarse for it; raise the rod's \
                 contact_stiffness or reduce analysis.time_step"
            }
            StepError::EnergyGain { .. } => {
                "a time step too coarse for the contact (for a line or hertz rod `ancf check` warns when \
                 h √(ε_L / ρA) > 3): reduce analysis.time_step; or, with the contact resolved, the energy \
                 error each step's Newton tolerance leaves, added up over many steps: tighten \
                 analysis.tolerance"
            }
            StepError::Factorization { .. } => {
                "a singular matrix: too few supports (a free rigid motion) or an element turned inside out"
            }
            StepError::ErrorEstimate { .. } => {
                "a tolerance too tight for the motion (analysis.error_tolerance), or a motion the \
                 estimate cannot follow (an element turned inside out, a contact too stiff); loosen \
                 analysis.error_tolerance or give a fixed analysis.time_step"
            }
            StepError::Invalid(_) => "a checkpoint or snapshot that does not belong to this scene",
        }
    }
}

impl std::fmt::Display for StepError {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        match self {
            StepError::NotConverged {
                iterations,
                tolerance,
            } => write!(
                f,
                "Newton did not converge in {iterations} iterations (relative residual at the end above {tolerance:.0e})"
            ),
            StepError::NonFinite => f.write_str("non-finite residual (NaN or overflow)"),
            StepError::NonFiniteEnergy => f.write_str("the energy is not finite (NaN or overflow)"),
            StepError::Inverted { node } => write!(
                f,
                "node {node}'s gradients turned over: the element there was crushed through itself"
            ),
            StepError::Penetration { depth, limit } => write!(
                f,
                "penetration {depth:.3e} m exceeds {limit} wire radii (contact.max_penetration)"
            ),
            StepError::EnergyGain { gain } => write!(
                f,
                "the step would raise the energy {gain:.3e} J above its start, past the energy guard's 1 % of \
                 the energy in play"
            ),
            StepError::Factorization { matrix, error } => match matrix {
                Matrix::Mass => write!(f, "mass matrix: {error}"),
                Matrix::Pattern | Matrix::Newton => write!(f, "{error}"),
            },
            StepError::Halved { cuts, h, cause } => write!(
                f,
                "{cause} (after halving the step {cuts} times, h = {h:.3e} s)"
            ),
            StepError::ErrorEstimate { h, error, allowed } => write!(
                f,
                "the local error estimate {error:.3e} m stays above analysis.error_tolerance = \
                 {allowed:.3e} m down to h = {h:.3e} s"
            ),
            StepError::Invalid(message) => f.write_str(message),
        }
    }
}

impl std::error::Error for StepError {}
