//! What a step reports, and how finely the next ones start.

use crate::forces::contact::{ContactSample, DeepestPoint};

/// Steps without a Newton failure after which [`super::Integrator::step`] tries
/// twice the sub-step size again.
pub const SUBDIVISION_HOLD: usize = 8;

/// How finely the integrator starts its steps: `depth` halvings (2^depth
/// sub-steps), held for `held` steps without a Newton failure so far.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, serde::Serialize, serde::Deserialize)]
pub struct Subdivision {
    /// Halvings each step starts with.
    pub depth: usize,
    /// Steps completed at this depth without a Newton failure.
    pub held: usize,
}

/// What the cuts of one step found (see [`super::Integrator::step`]).
pub(super) struct CutLog {
    /// The smallest depth an attempt was accepted at.
    pub(super) shallowest: usize,
    /// Whether Newton failed on an attempt (rather than a guard rejecting
    /// a converged one).
    pub(super) newton_failed: bool,
}

/// Statistics of one completed step.
#[derive(Clone, Debug, Default)]
pub struct StepInfo {
    /// Newton iterations.
    pub iterations: usize,
    /// Newton matrix factorizations.
    pub factorizations: usize,
    /// Sub-steps used (1 when no cut was needed).
    pub substeps: usize,
    /// Attempts rejected and cut in halves (their Newton iterations and
    /// factorizations are counted above: the work the step cost).
    pub rejected: usize,
    /// Converged attempts of an adaptive run tried again shorter: their
    /// local error estimate exceeded the tolerance, or they made the first
    /// contact before it was located (their work is counted above too).
    pub retried: usize,
    /// Contact at the step's generalized-α midpoint (last sub-step).
    pub contact: ContactSample,
    /// Deepest penetrating point: (element, point).
    pub deepest: Option<(usize, DeepestPoint)>,
    /// Force on each rod (normal + friction, N) at the step's midpoint.
    pub rod_forces: Vec<[f64; 3]>,
    /// The contact force the wire puts on each frame member it may touch
    /// (N, model's member order).
    pub member_forces: Vec<[f64; 3]>,
    /// Force each support exerts on the wire at its node's position r (N),
    /// at the step's midpoint, in the model's support order: the residual
    /// M a + Q − Q_ext of the held position coordinates (zero once a
    /// support has released, or for a coordinate it does not hold).
    pub reactions: Vec<[f64; 3]>,
    /// Power dissipated by damping (W) at the step's midpoint.
    pub damping_power: f64,
    /// Wall time (s) of the step's force evaluations without a Jacobian:
    /// one iteration's force, for the limit ratio.
    pub force_seconds: f64,
    /// Their number.
    pub force_evaluations: usize,
    /// Wall time (s) of the step's linear solves with a factored Newton
    /// matrix.
    pub solve_seconds: f64,
    /// Their number.
    pub solves: usize,
    /// Wall time (s) of the step's force evaluations with the Jacobian
    /// (a refresh's, or each full-Newton iteration's).
    pub jacobian_seconds: f64,
    /// Their number.
    pub jacobian_evaluations: usize,
    /// Wall time (s) of the step's factorizations of the Newton matrix
    /// (counted in `factorizations`).
    pub factorization_seconds: f64,
}

impl StepInfo {
    /// Count the work of `attempt`, a converged attempt an adaptive run
    /// threw away, in this step's.
    pub fn add_retried(&mut self, attempt: &StepInfo) {
        self.add_work(attempt);
        self.retried += 1;
    }

    /// Add `other`'s work (iterations, factorizations, rejections, timed
    /// forces, Jacobians, factorizations and solves) to this step's.
    pub fn add_work(&mut self, other: &StepInfo) {
        self.iterations += other.iterations;
        self.factorizations += other.factorizations;
        self.rejected += other.rejected;
        self.retried += other.retried;
        self.force_seconds += other.force_seconds;
        self.force_evaluations += other.force_evaluations;
        self.solve_seconds += other.solve_seconds;
        self.solves += other.solves;
        self.jacobian_seconds += other.jacobian_seconds;
        self.jacobian_evaluations += other.jacobian_evaluations;
        self.factorization_seconds += other.factorization_seconds;
    }
}
