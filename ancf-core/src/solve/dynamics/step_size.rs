//! Adaptive time steps: the local error of a generalized-α step, and the
//! rule that accepts a step or asks for a shorter one and picks the next.
//!
//! The estimate is Zienkiewicz & Xie's a-posteriori one for Newmark-type
//! schemes (O. C. Zienkiewicz, Y. M. Xie, "A simple error estimator and
//! adaptive time stepping procedure for dynamic analysis", Earthquake
//! Engineering and Structural Dynamics 20 (1991) 871–887): the update
//! q₁ = q₀ + h v₀ + h² ((½ − β) a₀ + β a₁) differs from the Taylor series
//! q₀ + h v₀ + h²/2 a₀ + h³/6 ȧ by (β − 1/6) h³ ȧ, and h ȧ is estimated
//! from the step's accelerations. Generalized-α's β (from ρ∞) is used.
//!
//! One change makes it usable on a wire: ZX take h ȧ ≈ a₁ − a₀, but the
//! modes a step does not resolve (axial and shear modes of short elements,
//! ω h ≫ 1) flip their acceleration every step, a → −ρ∞ a, and a₁ − a₀
//! would then report twice their acceleration as an error and drive h down
//! to resolve vibrations whose displacement is sub-micrometre. The
//! acceleration is compared instead with the Newton predictor's
//! extrapolation a* = (1 − ρ∞) a₀ + ρ∞ a₋₁ (see [`super::predict`]), which
//! follows such a flip exactly; for a smooth acceleration a₁ − a* =
//! (h + ρ∞ h₋₁) ȧ, so
//!
//! e = |β − 1/6| h² ‖a₁ − a*‖ · h / (h + ρ∞ h₋₁),
//!
//! which is ZX's estimate when ρ∞ = 0 or on the first step. Its norm is the
//! largest over the nodes of the position error (m), gradients left out.
//! It is right to leading order but lags: it fits ȧ over the last two
//! steps, while the error's leading term has it at the step's end (for
//! ρ∞ = 1, h³ ȧ(t₁)/12), so a step in which ȧ passes through zero is
//! underestimated — on a rigid body on a spring by up to 2.1 × (ancf-core's
//! adaptive tests measure it).
//!
//! The rule controls the error per step, as ODE codes do: a step is kept
//! when its estimate is at most `tolerance` (m). The estimate grows as h³,
//! so a step of h (0.5 / r)^⅓ lands at half the tolerance, r being the
//! ratio of estimate to tolerance. h is kept while r ≥ 1/10 (an unchanged h
//! keeps the factorization and the predictor's history valid); only below
//! does it grow, at most twofold per step. Errors of many steps add up
//! (a phase error grows with time), so a run's error is larger than one
//! step's: over a fixed time it falls as h², that is as tolerance^⅔.

use super::{AlphaParameters, PreviousStep, State};
use crate::check::{ParameterError, positive, refuse};
use crate::model::{Model, NODE_DOFS};

/// Error control of an adaptive run ([`super::DynamicSettings::step_control`]).
#[derive(Clone, Debug, PartialEq)]
pub struct StepControl {
    /// The position error (m) one step may add.
    pub tolerance: f64,
    /// The longest step (s).
    pub max_step: f64,
}

impl StepControl {
    /// A tolerance > 0 and a longest step > 0 (s).
    pub fn check(&self) -> Result<(), ParameterError> {
        positive("error_tolerance", self.tolerance)?;
        positive("max_time_step", self.max_step)?;
        Ok(())
    }

    /// The stepping that the keys ask for, the one rule every way in
    /// (scene, Python) follows: a fixed step `Some(h)` takes neither an
    /// error tolerance nor a longest step; `None` (`"auto"`) needs the
    /// tolerance (m), takes a longest step (s; default
    /// [`StepControl::default_max_step`]), and starts at
    /// [`StepControl::first_step`]. Returns the first step (s) and the
    /// control of an adaptive run; the fixed step's range is
    /// [`super::DynamicSettings::check`]'s.
    pub fn from_keys(
        time_step: Option<f64>,
        end_time: f64,
        error_tolerance: Option<f64>,
        max_time_step: Option<f64>,
    ) -> Result<(f64, Option<StepControl>), ParameterError> {
        let Some(tolerance) = error_tolerance else {
            return match time_step {
                Some(h) if max_time_step.is_none() => Ok((h, None)),
                Some(_) => refuse("max_time_step", "only for time_step = \"auto\""),
                None => refuse(
                    "error_tolerance",
                    "missing (m), required with time_step = \"auto\": the position error a \
                     step may add",
                ),
            };
        };
        if time_step.is_some() {
            return refuse("error_tolerance", "only for time_step = \"auto\"");
        }
        positive("error_tolerance", tolerance)?;
        if let Some(h) = max_time_step {
            positive("max_time_step", h)?;
        }
        let control = StepControl {
            tolerance,
            max_step: max_time_step.unwrap_or_else(|| StepControl::default_max_step(end_time)),
        };
        Ok((control.first_step(end_time), Some(control)))
    }

    /// The longest step of a run of `end_time` s unless the scene says:
    /// a hundredth of the run, so that its histories have at least a
    /// hundred points.
    pub fn default_max_step(end_time: f64) -> f64 {
        end_time / 100.0
    }

    /// The first step of an adaptive run of `end_time` s: short enough
    /// that the first estimate is met (steps grow twofold from there).
    pub fn first_step(&self, end_time: f64) -> f64 {
        (end_time * 1e-4).min(self.max_step)
    }
}

/// What the rule decides about a step.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum Verdict {
    /// Keep the step; the next one is `next` s long.
    Accept {
        /// The next step (s).
        next: f64,
    },
    /// Reject it and try again with a step of `h` s.
    Retry {
        /// The shorter step (s).
        h: f64,
    },
}

/// The ratio of a step's local error estimate to the tolerance above
/// which the step is rejected (see the module).
const REJECT_ABOVE: f64 = 1.0;
/// The ratio below which the step grows.
const GROW_BELOW: f64 = 0.1;
/// The ratio a new step aims at.
const TARGET: f64 = 0.5;

/// The verdict on a step of `h` s with local error estimate `error` (m),
/// see the module.
pub fn judge(control: &StepControl, h: f64, error: f64) -> Verdict {
    let r = error / control.tolerance;
    if !r.is_finite() || r > REJECT_ABOVE {
        let factor = if r.is_finite() {
            (TARGET / r).cbrt().max(0.2)
        } else {
            0.2
        };
        return Verdict::Retry { h: h * factor };
    }
    let next = if r < GROW_BELOW {
        h * (TARGET / r).cbrt().min(2.0)
    } else {
        h
    };
    Verdict::Accept {
        next: next.min(control.max_step),
    }
}

/// The local error estimate (m) of the step from `s` to `next` of size `h`,
/// see the module.
pub fn local_error(
    model: &Model,
    params: &AlphaParameters,
    spectral_radius: f64,
    h: f64,
    s: &State,
    next: &State,
) -> f64 {
    let rho = spectral_radius;
    let (a0, a1) = (&s.a, &next.a);
    let previous = s
        .previous
        .as_ref()
        .filter(|p: &&PreviousStep| p.a.len() == a0.len() && rho > 0.0);
    let (weight, am1) = match previous {
        Some(p) => (h / (h + rho * p.h), Some(&p.a)),
        None => (1.0, None),
    };
    let coefficient = (params.beta - 1.0 / 6.0).abs() * h * h * weight;
    let mut largest = 0.0f64;
    for n in 0..model.n_nodes() {
        let mut sum = 0.0;
        for k in NODE_DOFS * n..NODE_DOFS * n + 3 {
            let predicted = match am1 {
                Some(am1) => (1.0 - rho) * a0[k] + rho * am1[k],
                None => a0[k],
            };
            let d = a1[k] - predicted;
            sum += d * d;
        }
        largest = largest.max(sum);
    }
    coefficient * largest.sqrt()
}

/// A step that would end within this fraction of a step before an event
/// ends at it instead (no sliver of a step is left).
const SLIVER: f64 = 0.25;

/// The step (s) to take from `time` towards the controller's `h` when the
/// next event (a support's release, the end) is at `event` s: it ends
/// exactly at the event when it would reach or nearly reach it, and it is
/// half the way there when a full `h` would leave a sliver.
pub fn towards_event(time: f64, h: f64, event: f64) -> f64 {
    let left = event - time;
    if left <= h * (1.0 + SLIVER) {
        left
    } else if left < 2.0 * h {
        0.5 * left
    } else {
        h
    }
}

/// Refuse a step control whose longest step exceeds the run.
pub fn check_against_run(control: &StepControl, end_time: f64) -> Result<(), ParameterError> {
    control.check()?;
    if control.max_step > end_time {
        return refuse(
            "max_time_step",
            format!(
                "{} s is longer than end_time {end_time} s",
                control.max_step
            ),
        );
    }
    Ok(())
}

#[cfg(test)]
mod tests {
    use super::*;

    fn control() -> StepControl {
        StepControl {
            tolerance: 1e-3,
            max_step: 0.01,
        }
    }

    #[test]
    fn a_step_over_the_tolerance_is_retried_shorter_by_the_h_cubed_rule() {
        // r = 4e-3 / 1e-3 = 4: (0.5 / 4)^⅓ = 1/2.
        match judge(&control(), 1e-3, 4e-3) {
            Verdict::Retry { h } => assert!((h - 0.5e-3).abs() < 1e-15),
            v => panic!("{v:?}"),
        }
        assert_eq!(
            judge(&control(), 1e-3, f64::NAN),
            Verdict::Retry { h: 2e-4 }
        );
    }

    #[test]
    fn a_step_within_the_tolerance_keeps_h_and_a_small_error_grows_it_at_most_twofold() {
        assert_eq!(
            judge(&control(), 1e-3, 0.5e-3),
            Verdict::Accept { next: 1e-3 }
        );
        assert_eq!(judge(&control(), 1e-3, 0.0), Verdict::Accept { next: 2e-3 });
        // r = 0.0625: (0.5 / 0.0625)^⅓ = 2.
        match judge(&control(), 1e-3, 0.0625e-3) {
            Verdict::Accept { next } => assert!((next - 2e-3).abs() < 1e-15),
            v => panic!("{v:?}"),
        }
        // Never beyond the longest step.
        assert_eq!(judge(&control(), 8e-3, 0.0), Verdict::Accept { next: 0.01 });
    }

    #[test]
    fn steps_end_at_events_without_slivers() {
        assert_eq!(towards_event(0.0, 0.1, 1.0), 0.1);
        assert_eq!(towards_event(0.9, 0.1, 1.0), 1.0 - 0.9);
        assert_eq!(towards_event(0.88, 0.1, 1.0), 1.0 - 0.88);
        assert!((towards_event(0.85, 0.1, 1.0) - 0.075).abs() < 1e-12);
    }
}
