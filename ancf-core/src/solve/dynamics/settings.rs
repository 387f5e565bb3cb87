//! The integrator's settings, checked once, with their defaults.

use super::step_size::{StepControl, check_against_run};
use crate::check::{ParameterError, count_in, positive, refuse};

/// How often the Newton matrix is refactorized.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum NewtonKind {
    /// Fresh Jacobian and factorization every iteration.
    Full,
    /// Keep the factorization across iterations and steps while Newton
    /// converges well (contraction ≤ 0.5 per iteration, ≤ 6 iterations);
    /// refactor otherwise. The default: on the pendulum it needs the same
    /// steps at a fraction of the factorizations. A wire's kept matrix is
    /// stored in single precision (its arithmetic and the residual stay in
    /// double; a fresh one that does not contract 4× is formed again in
    /// double; see `linalg::block_tridiagonal::Precision`).
    Modified,
}

/// Settings of the dynamic solver.
#[derive(Clone, Debug)]
pub struct DynamicSettings {
    /// Time step h, s.
    pub time_step: f64,
    /// End time, s.
    pub end_time: f64,
    /// Spectral radius at infinite frequency ρ∞ ∈ [0, 1]; 1 = no numerical
    /// damping (energy conserved; verification runs use it). Default
    /// [`DEFAULT_SPECTRAL_RADIUS`].
    pub spectral_radius: f64,
    /// Full or modified Newton.
    pub newton: NewtonKind,
    /// Modified Newton: correct the kept factorization's directions within
    /// a step by Broyden's rank-one updates (Kelley 1995, §7.3), so that a
    /// stale matrix contracts faster and is refactored less often. Default
    /// false. Results agree with plain modified Newton to the tolerance.
    pub broyden: bool,
    /// Newton iterations allowed per step before the step is cut. Default 25.
    pub max_iterations: usize,
    /// Relative residual tolerance. Default 1e-10.
    pub tolerance: f64,
    /// How many times a step may be halved before the run fails. Default 10.
    pub max_cuts: usize,
    /// Adaptive steps: `Some` chooses each step from a local error estimate
    /// ([`super::step_size`]), `time_step` being the first; `None` (the
    /// default) steps `time_step` throughout.
    pub step_control: Option<StepControl>,
}

/// ρ∞ unless said otherwise: 0.9 damps the unresolved axial modes of a
/// stiff wire a little, which a scene's loads do not feel.
pub const DEFAULT_SPECTRAL_RADIUS: f64 = 0.9;

/// The most time steps a run may ask for (a run of this length takes days).
pub const MAX_STEPS: f64 = 1e8;

/// Below this relative tolerance Newton's residual is at double
/// precision's round-off on a beam model: it cannot be met reliably.
pub const ROUNDOFF_TOLERANCE: f64 = 1e-12;

/// Fewer Newton iterations a step than this leave a contact step no room.
pub const FEW_ITERATIONS: usize = 4;

impl DynamicSettings {
    /// When Newton fails to converge: whether its own settings are the
    /// likely cause (a tolerance below round-off, too few iterations), and
    /// what to change, naming the fields; `None` when they are sound.
    pub fn newton_note(&self) -> Option<String> {
        if self.tolerance < ROUNDOFF_TOLERANCE {
            return Some(format!(
                "analysis.tolerance = {:e} lies below what double precision resolves in the \
                 residual (about {ROUNDOFF_TOLERANCE:e}); loosen it (the default is {:e})",
                self.tolerance,
                DynamicSettings::default().tolerance
            ));
        }
        if self.max_iterations < FEW_ITERATIONS {
            return Some(format!(
                "analysis.max_iterations = {} leaves Newton too few iterations a step; raise it \
                 (the default is {})",
                self.max_iterations,
                DynamicSettings::default().max_iterations
            ));
        }
        None
    }

    /// Whether the integrator can run with these settings: h and the end
    /// time > 0, h ≤ end time, at most [`MAX_STEPS`] steps, ρ∞ ∈ [0, 1], a
    /// relative tolerance in (0, 1), at least one Newton iteration, Broyden
    /// updates only with modified Newton.
    pub fn check(&self) -> Result<(), ParameterError> {
        let end_time = positive("end_time", self.end_time)?;
        let h = positive("time_step", self.time_step)?;
        if h > end_time {
            return refuse(
                "time_step",
                format!("{h} s is longer than end_time {end_time} s"),
            );
        }
        // A step so small that the run could never finish is a typo, not a plan.
        let steps = end_time / h;
        if steps > MAX_STEPS {
            return refuse(
                "time_step",
                format!(
                    "{h} s makes {steps:.3e} steps to end_time {end_time} s (more than {MAX_STEPS:.0e}); check the units"
                ),
            );
        }
        let rho = crate::check::finite("spectral_radius", self.spectral_radius)?;
        if !(0.0..=1.0).contains(&rho) {
            return refuse("spectral_radius", format!("must be in [0, 1], got {rho}"));
        }
        crate::check::relative_tolerance("tolerance", self.tolerance)?;
        count_in("max_iterations", self.max_iterations, 1..=10_000)?;
        if self.broyden && self.newton == NewtonKind::Full {
            return refuse(
                "broyden",
                "updates a kept Newton matrix: it needs newton = \"modified\" (full Newton refactors every iteration)",
            );
        }
        if let Some(control) = &self.step_control {
            check_against_run(control, end_time)?;
        }
        Ok(())
    }
}

impl Default for DynamicSettings {
    fn default() -> Self {
        DynamicSettings {
            time_step: 1e-3,
            end_time: 1.0,
            spectral_radius: DEFAULT_SPECTRAL_RADIUS,
            newton: NewtonKind::Modified,
            broyden: false,
            max_iterations: 25,
            tolerance: 1e-10,
            max_cuts: 10,
            step_control: None,
        }
    }
}
