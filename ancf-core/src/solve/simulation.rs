//! A dynamic simulation of one wire: the front door for programs (the CLI,
//! the study, Python). It owns the phase models (one per support release),
//! the integrator of the current phase and the state, switches phase at
//! release times, truncates the last step at the end time, and keeps every
//! step's rod loads. A [`Snapshot`] is what a checkpoint needs to continue
//! bit for bit.
//!
//! ```
//! use ancf_core::prelude::*;
//! let steel = Material::st_venant_kirchhoff(7800.0, 2e11, 0.3, 1.0);
//! let model = WireBuilder::new(1.0, 8)
//!     .layer(steel, 0.01)
//!     .support(0, SupportKind::Pin)
//!     .gravity([0.0, 0.0, -9.81])
//!     .build()?;
//! let settings = DynamicSettings { time_step: 1e-3, end_time: 1.0, ..Default::default() };
//! let mut sim = Simulation::new(&model, settings, Initial::Reference)?;
//! // Step to 0.1 s, watching the tip after every step.
//! let mut lowest = 0.0_f64;
//! sim.run_until(0.1, |sim, _info| {
//!     let tip = sim.model().node_position(&sim.state().q, sim.model().n_elements);
//!     lowest = lowest.min(tip[2]);
//!     std::ops::ControlFlow::Continue(())
//! })?;
//! assert!(lowest < 0.0, "the pendulum swings down");
//! assert_eq!(sim.steps(), (100, 1000));
//! # Ok::<(), ancf_core::Error>(())
//! ```

use crate::loads::contact_record::ContactRecord;
use crate::loads::rod_load::LoadHistory;
use crate::model::Model;
use crate::solve::cancel::CancelToken;
use crate::solve::dynamics::step_size::{Verdict, judge, towards_event};
use crate::solve::dynamics::{
    DynamicSettings, Energies, Integrator, State, StepError, StepInfo, Subdivision,
};
use crate::solve::statics::{StaticError, StaticSettings, solve_static_cancellable};
use std::ops::ControlFlow;
use std::sync::Arc;

/// The shortest step an adaptive run may take, as a fraction of its end time.
const MIN_STEP_FRACTION: f64 = 1e-12;

/// The step (as a fraction of the contact's resolution limit, or of the
/// longest step without one) to which an adaptive run's first contact is
/// located.
pub const LOCATE_FRACTION: f64 = 1.0 / 32.0;

/// Where a simulation starts.
#[derive(Clone, Debug, PartialEq)]
pub enum Initial {
    /// At rest in the initial coordinates (the supports' positions, else the reference).
    Reference,
    /// At rest in static equilibrium with every support holding, reached in
    /// `load_steps` load increments.
    /// The static equilibrium under the scene's loads, in `load_steps` increments.
    Static {
        /// Equal load increments (≥ 1).
        load_steps: usize,
    },
}

/// Why a simulation could not start or go on.
#[derive(Clone, Debug)]
pub enum SimulationError {
    /// The initial static equilibrium failed; its last converged state is kept.
    Static(StaticError),
    /// The solver could not be set up, or the acceleration of a state not
    /// found (`what` says which, at the start or after a release).
    Setup {
        /// What was being set up.
        what: &'static str,
        /// Why it failed.
        error: StepError,
    },
    /// Step `step` (1-based), which was to end at `time` (s), failed after
    /// every allowed cut.
    Step {
        /// The step (1-based).
        step: usize,
        /// The time it was to end at (s).
        time: f64,
        /// Why it failed.
        error: StepError,
    },
}

impl std::fmt::Display for SimulationError {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        match self {
            SimulationError::Static(e) => write!(f, "initial static equilibrium: {e}"),
            SimulationError::Setup { what, error } => write!(f, "{what}: {error}"),
            SimulationError::Step { step, time, error } => {
                write!(f, "step {step} at t = {time:.6} s: {error}")
            }
        }
    }
}

impl std::error::Error for SimulationError {}

impl SimulationError {
    /// What usually causes this failure and what to change (scene field
    /// names), for messages to a user.
    pub fn likely_cause(&self) -> &'static str {
        match self {
            SimulationError::Static(e) => e.likely_cause(),
            SimulationError::Setup { error, .. } | SimulationError::Step { error, .. } => {
                error.likely_cause()
            }
        }
    }
}

/// Everything a simulation accumulates: what a checkpoint saves and a
/// resumed simulation starts from.
#[derive(Clone, Debug, serde::Serialize, serde::Deserialize)]
pub struct Snapshot {
    /// Steps completed.
    pub step: usize,
    /// Current phase (number of release times passed).
    pub phase: usize,
    /// The state after `step` steps.
    pub state: State,
    /// The energy guard's reference (see [`Integrator::energy_reference`]).
    pub energy_reference: (f64, f64),
    /// Where the kept factorization was formed (`None`: none kept; absent in
    /// checkpoints of earlier versions): a resumed run refactors there.
    #[serde(default)]
    pub factorization: Option<crate::solve::dynamics::FactorizationOrigin>,
    /// How finely steps start (see [`Integrator::step`]; absent in
    /// checkpoints written before it existed: none).
    #[serde(default)]
    pub subdivision: Subdivision,
    /// Newton iterations so far.
    pub newton_iterations: usize,
    /// Factorizations so far.
    pub factorizations: usize,
    /// Step attempts rejected so far (each cut in halves; their work is in
    /// the two counts above).
    #[serde(default)]
    pub step_cuts: usize,
    /// An adaptive run's converged attempts tried again shorter: their
    /// error estimate was over the tolerance, or they made the first
    /// contact before it was located (their work is in the counts above).
    #[serde(default)]
    pub step_retries: usize,
    /// An adaptive run's next step (s); `None` for fixed steps.
    #[serde(default)]
    pub step_size: Option<f64>,
    /// The shortest and the longest step completed so far (s; `None`
    /// before the first).
    #[serde(default)]
    pub step_range: Option<[f64; 2]>,
    /// Support releases done.
    pub released: usize,
    /// The force on each rod at every step.
    pub rod_loads: Vec<LoadHistory>,
    /// The contact force the wire puts on each frame member at every step,
    /// in the model's member order.
    #[serde(default)]
    pub member_loads: Vec<LoadHistory>,
    /// The force each support exerts on the wire at every step, in the
    /// model's support order (empty in a snapshot from before they were
    /// recorded: recorded from there on).
    #[serde(default)]
    pub support_loads: Vec<LoadHistory>,
    /// The moment each support's rotational and torsional springs exert on
    /// the body at t = 0 and at the end of every step (N m, model's support
    /// order; zero for a support without them), kept only when a support
    /// has them.
    #[serde(default, skip_serializing_if = "Vec::is_empty")]
    pub support_moments: Vec<LoadHistory>,
    /// The force each support exerts on the wire in the initial state (N,
    /// model's support order): from an initial static equilibrium, the
    /// static reaction that a support's peak is compared with.
    #[serde(default)]
    pub initial_support_forces: Vec<[f64; 3]>,
    /// Contact so far (`None` without rods).
    #[serde(default)]
    pub contact: Option<ContactRecord>,
}

/// How many support moment histories `model` keeps: one per support when
/// any has a rotational or torsional spring, else none.
fn moment_supports(model: &Model) -> usize {
    if model.springs().iter().any(|s| s.carries_moment()) {
        model.supports.len()
    } else {
        0
    }
}

/// Each support's springs' moment at coordinates `q` and time `t` (s) onto
/// its history (zero for a support without such springs; none kept when
/// `histories` is empty).
fn push_support_moments(model: &Model, q: &[f64], t: f64, histories: &mut [LoadHistory]) {
    for (i, history) in histories.iter_mut().enumerate() {
        let m = model
            .moment_spring(i)
            .map_or([0.0; 3], |s| s.moment_on_body(q));
        history.push(t, m);
    }
}

/// A running dynamic simulation.
pub struct Simulation {
    /// Newton iterations per load step of the initial static equilibrium
    /// (empty when starting from the reference).
    pub static_iterations: Vec<usize>,
    phases: Vec<Arc<Model>>,
    phase_starts: Vec<f64>,
    settings: DynamicSettings,
    integrator: Integrator,
    steps: usize,
    progress: Snapshot,
}

impl Simulation {
    /// Starts `model` with `settings` from `initial`.
    pub fn new(
        model: &Model,
        settings: DynamicSettings,
        initial: Initial,
    ) -> Result<Self, SimulationError> {
        Self::new_cancellable(model, settings, initial, None)
    }

    /// [`Simulation::new`] whose static start `cancel` can stop (Ctrl-C, a
    /// termination signal): the error is then a [`StaticError`] that says
    /// it was interrupted.
    pub fn new_cancellable(
        model: &Model,
        settings: DynamicSettings,
        initial: Initial,
        cancel: Option<&CancelToken>,
    ) -> Result<Self, SimulationError> {
        let (q0, static_iterations, static_reactions, plastic) = match initial {
            Initial::Reference => (
                model.initial_coordinates(),
                Vec::new(),
                None,
                Default::default(),
            ),
            Initial::Static { load_steps } => {
                let st = StaticSettings {
                    load_steps,
                    ..Default::default()
                };
                let res = solve_static_cancellable(model, &st, model.initial_coordinates(), cancel)
                    .map_err(SimulationError::Static)?;
                let reactions = res.reactions.iter().map(|(_, f)| *f).collect::<Vec<_>>();
                let plastic = (res.plastic, res.plastic_work);
                (res.q, res.iterations, Some(reactions), plastic)
            }
        };
        let (phases, phase_starts) = Self::phases(model, &settings);
        let mut integrator =
            Integrator::new(phases[0].clone(), settings.clone()).map_err(|error| {
                SimulationError::Setup {
                    what: "setting up the solver",
                    error,
                }
            })?;
        let v0 = vec![0.0; q0.len()];
        let state = integrator
            .initial_state_with(q0, v0, plastic)
            .map_err(|error| SimulationError::Setup {
                what: "initial acceleration",
                error,
            })?;
        let rods = model.contact().map_or(0, |c| c.rods.len());
        let members = model.contact().map_or(0, |c| c.members.len());
        // The springs' moments start with the initial state's (t = 0).
        let mut support_moments = vec![LoadHistory::default(); moment_supports(model)];
        push_support_moments(model, &state.q, 0.0, &mut support_moments);
        Ok(Simulation {
            static_iterations,
            steps: Self::step_count(&settings),
            progress: Snapshot {
                step: 0,
                phase: 0,
                energy_reference: integrator.energy_reference(),
                factorization: None,
                subdivision: integrator.subdivision(),
                state,
                newton_iterations: 0,
                factorizations: 0,
                step_cuts: 0,
                step_retries: 0,
                step_size: settings.step_control.as_ref().map(|_| settings.time_step),
                step_range: None,
                released: 0,
                rod_loads: vec![LoadHistory::default(); rods],
                member_loads: vec![LoadHistory::default(); members],
                support_loads: vec![LoadHistory::default(); model.supports.len()],
                support_moments: vec![LoadHistory::default(); moment_supports(model)],
                // Every support holds in the static equilibrium, those
                // released at t = 0 too: their force before the break.
                initial_support_forces: static_reactions
                    .unwrap_or_else(|| integrator.initial_reactions().to_vec()),
                contact: model.contact().map(|_| ContactRecord::default()),
            },
            phases,
            phase_starts,
            settings,
            integrator,
        })
    }

    /// Continues from a snapshot of the same model and settings; it ends bit
    /// for bit like the simulation the snapshot was taken of (the kept
    /// factorization is formed again where the snapshot says).
    pub fn resume(
        model: &Model,
        settings: DynamicSettings,
        mut snapshot: Snapshot,
    ) -> Result<Self, SimulationError> {
        // A snapshot from before contact was recorded: record from here on.
        if model.contact().is_some() && snapshot.contact.is_none() {
            snapshot.contact = Some(ContactRecord::default());
        }
        if snapshot.support_loads.len() != model.supports.len() {
            snapshot.support_loads = vec![LoadHistory::default(); model.supports.len()];
        }
        if snapshot.support_moments.len() != moment_supports(model) {
            snapshot.support_moments = vec![LoadHistory::default(); moment_supports(model)];
        }
        Self::check_snapshot(model, &settings, &snapshot).map_err(|message| {
            SimulationError::Setup {
                what: "resuming",
                error: StepError::Invalid(message),
            }
        })?;
        let (phases, phase_starts) = Self::phases(model, &settings);
        let phase = phases
            .get(snapshot.phase)
            .ok_or_else(|| SimulationError::Setup {
                what: "resuming",
                error: StepError::Invalid(format!(
                    "the snapshot's phase {} does not exist",
                    snapshot.phase
                )),
            })?;
        let mut integrator = Integrator::new(phase.clone(), settings.clone()).map_err(|error| {
            SimulationError::Setup {
                what: "setting up the solver",
                error,
            }
        })?;
        integrator.restore_energy_reference(snapshot.energy_reference);
        integrator.restore_subdivision(snapshot.subdivision);
        if let Some(origin) = &snapshot.factorization {
            integrator
                .restore_factorization(origin)
                .map_err(|error| SimulationError::Setup {
                    what: "resuming",
                    error,
                })?;
        }
        Ok(Simulation {
            static_iterations: Vec::new(),
            steps: Self::step_count(&settings),
            progress: snapshot,
            phases,
            phase_starts,
            settings,
            integrator,
        })
    }

    /// A snapshot that fits `model` and `settings`: every vector as long as
    /// the model's coordinates, counters within the run, finite values, a
    /// record per rod. A damaged or foreign checkpoint is refused naming
    /// the field, never used.
    fn check_snapshot(
        model: &Model,
        settings: &DynamicSettings,
        s: &Snapshot,
    ) -> Result<(), String> {
        let n = model.reference.len();
        let state = &s.state;
        for (name, v) in [
            ("state.q", &state.q),
            ("state.v", &state.v),
            ("state.a", &state.a),
        ] {
            if v.len() != n {
                return Err(format!(
                    "{name} has {} entries, the model has {n} coordinates",
                    v.len()
                ));
            }
            if let Some(i) = v.iter().position(|x| !x.is_finite()) {
                return Err(format!("{name}[{i}] is not finite"));
            }
        }
        let points = crate::forces::plastic::PlasticLayout::of(model).len();
        if !(state.plastic.is_empty() || state.plastic.len() == points) {
            return Err(format!(
                "state.plastic has {} points, the model's yielding layers have {points}",
                state.plastic.len()
            ));
        }
        let finite = |p: &crate::material::beam_plasticity::PlasticState| {
            (p.plastic_strain
                .iter()
                .chain(&p.back_stress)
                .chain(&p.stress))
            .chain(std::iter::once(&p.equivalent))
            .all(|x| x.is_finite())
        };
        if let Some(i) = state.plastic.iter().position(|p| !finite(p)) {
            return Err(format!("state.plastic[{i}] is not finite"));
        }
        let beams = model.beams.len();
        if !(state.plastic_work.is_empty() || state.plastic_work.len() == beams) {
            return Err(format!(
                "state.plastic_work has {} entries, the model has {beams} beams",
                state.plastic_work.len()
            ));
        }
        if let Some(p) = &state.previous
            && p.a.len() != n
        {
            return Err(format!(
                "state.previous.a has {} entries, the model has {n} coordinates",
                p.a.len()
            ));
        }
        if settings.step_control.is_some() {
            if !(state.time >= 0.0 && state.time <= settings.end_time) {
                return Err(format!(
                    "state.time = {} s is outside the run's 0 … {} s",
                    state.time, settings.end_time
                ));
            }
            if !s.step_size.is_some_and(|h| h > 0.0 && h.is_finite()) {
                return Err(
                    "step_size: an adaptive run's next step is missing or not positive".into(),
                );
            }
        } else {
            let steps = Self::step_count(settings);
            if s.step > steps {
                return Err(format!("step {} is beyond the run's {steps} steps", s.step));
            }
            let t = s.step as f64 * settings.time_step;
            if !(state.time.is_finite()
                && (state.time - t.min(settings.end_time)).abs()
                    <= 1e-6 * settings.time_step.max(t))
            {
                return Err(format!(
                    "state.time = {} s does not match step {} of {} s",
                    state.time, s.step, settings.time_step
                ));
            }
        }
        if s.subdivision.depth > settings.max_cuts {
            return Err(format!(
                "subdivision.depth = {} exceeds the {} halvings a step may take",
                s.subdivision.depth, settings.max_cuts
            ));
        }
        let rods = model.contact().map_or(0, |c| c.rods.len());
        if s.rod_loads.len() != rods {
            return Err(format!(
                "rod_loads has {} entries, the model has {rods} rods",
                s.rod_loads.len()
            ));
        }
        if let Some(f) = &s.factorization {
            let n = model.reference.len();
            let lengths = [
                f.state.q.len(),
                f.state.v.len(),
                f.state.a.len(),
                f.a1.len(),
            ];
            let finite = (f
                .state
                .q
                .iter()
                .chain(&f.state.v)
                .chain(&f.state.a)
                .chain(&f.a1))
            .all(|x| x.is_finite());
            if lengths.iter().any(|&l| l != n) || !finite || !(f.h > 0.0 && f.h.is_finite()) {
                return Err(format!(
                    "factorization: its state, iterate or step does not fit the model's {n} \
                     coordinates (or is not finite)"
                ));
            }
        }
        let members = model.contact().map_or(0, |c| c.members.len());
        if s.member_loads.len() != members {
            return Err(format!(
                "member_loads has {} entries, the wire may touch {members} members",
                s.member_loads.len()
            ));
        }
        Ok(())
    }

    /// The phase models: the supports still holding between release times.
    fn phases(model: &Model, settings: &DynamicSettings) -> (Vec<Arc<Model>>, Vec<f64>) {
        let mut starts = vec![0.0];
        starts.extend(
            model
                .release_times()
                .into_iter()
                .filter(|t| *t < settings.end_time && *t > 0.0),
        );
        let phases = starts
            .iter()
            .map(|t| Arc::new(model.holding_at(*t)))
            .collect();
        (phases, starts)
    }

    fn step_count(settings: &DynamicSettings) -> usize {
        (settings.end_time / settings.time_step - 1e-9).ceil() as usize
    }

    /// Advances one time step (the last one ends at the end time), first
    /// switching phase when a support's release time has come. Returns the
    /// step's statistics; an error leaves the simulation at its last
    /// completed step.
    pub fn step(&mut self) -> Result<StepInfo, SimulationError> {
        let h = self.settings.time_step;
        let p = &mut self.progress;
        // A release inside this step: switch to the next phase at its start.
        while p.phase + 1 < self.phases.len()
            && self.phase_starts[p.phase + 1] <= p.state.time + 1e-12 * h
        {
            let next = p.phase + 1;
            let mut integrator = Integrator::new(self.phases[next].clone(), self.settings.clone())
                .map_err(|error| SimulationError::Setup {
                    what: "setting up the solver after a release",
                    error,
                })?;
            let mut s = integrator
                .initial_state_with(
                    p.state.q.clone(),
                    p.state.v.clone(),
                    (p.state.plastic.clone(), p.state.plastic_work.clone()),
                )
                .map_err(|error| SimulationError::Setup {
                    what: "acceleration after a release",
                    error,
                })?;
            s.time = p.state.time;
            s.dissipated = p.state.dissipated;
            integrator.set_energy_reference(&s);
            self.integrator = integrator;
            p.phase = next;
            p.state = s;
            p.released += 1;
        }
        let k = p.step + 1;
        let (next, info) = if self.settings.step_control.is_some() {
            self.adaptive_step(k)?
        } else {
            let hk = if k == self.steps {
                self.settings.end_time - p.state.time
            } else {
                h
            };
            let failed = |error| SimulationError::Step {
                step: k,
                time: p.state.time + hk,
                error,
            };
            self.integrator.step(&p.state, hk).map_err(failed)?
        };
        let p = &mut self.progress;
        let failed = |error| SimulationError::Step {
            step: k,
            time: next.time,
            error,
        };
        // Every step's energy is finite, whatever the run writes.
        if !self.integrator.energy_is_finite(&next) {
            return Err(failed(StepError::NonFiniteEnergy));
        }
        let hk = next.time - p.state.time;
        p.step_range = Some(
            p.step_range
                .map_or([hk, hk], |[a, b]| [a.min(hk), b.max(hk)]),
        );
        p.state = next;
        p.step = k;
        p.newton_iterations += info.iterations;
        p.factorizations += info.factorizations;
        p.step_cuts += info.rejected;
        p.step_retries += info.retried;
        for (history, force) in p.rod_loads.iter_mut().zip(&info.rod_forces) {
            history.push(p.state.time, *force);
        }
        for (history, force) in p.member_loads.iter_mut().zip(&info.member_forces) {
            history.push(p.state.time, *force);
        }
        for (history, force) in p.support_loads.iter_mut().zip(&info.reactions) {
            history.push(p.state.time, *force);
        }
        let model = &self.integrator.model;
        push_support_moments(model, &p.state.q, p.state.time, &mut p.support_moments);
        if let Some(record) = p.contact.as_mut() {
            record.push(p.state.time, &info.contact, info.deepest);
        }
        Ok(info)
    }

    /// One step of an adaptive run (step `k`): from the controller's step,
    /// shortened to end at the next release or the end time and, while a
    /// rod or member is within reach, to the contact's resolution limit;
    /// tried again shorter while its local error estimate exceeds the
    /// tolerance ([`crate::solve::dynamics::step_size`]), and halved while
    /// it makes the run's first contact and is longer than
    /// [`LOCATE_FRACTION`] of that limit (the contact's start is then known
    /// to that fraction of a resolved step).
    /// Sets the controller's next step.
    fn adaptive_step(&mut self, k: usize) -> Result<(State, StepInfo), SimulationError> {
        let Some(control) = self.settings.step_control.clone() else {
            unreachable!("adaptive_step is called for adaptive runs only")
        };
        let end = self.settings.end_time;
        let p = &mut self.progress;
        let t = p.state.time;
        let event = (self.phase_starts.get(p.phase + 1).copied())
            .unwrap_or(end)
            .min(end);
        let limit = self.integrator.model.contact_step_limit();
        // The run's first contact is located: an attempt that makes it is
        // halved until it is this short.
        let locating = p.contact.as_ref().is_some_and(|c| c.first_time.is_none());
        let locate = limit.unwrap_or(control.max_step) * LOCATE_FRACTION;
        let mut h = p.step_size.unwrap_or(self.settings.time_step);
        let mut info = StepInfo::default();
        loop {
            let mut h_try = towards_event(t, h, event);
            if let Some(limit) = limit
                && h_try > limit
                && self.integrator.contact_within_reach(&p.state, h_try)
            {
                h_try = limit;
            }
            let at_event = h_try == event - t;
            let failed = |error| SimulationError::Step {
                step: k,
                time: t + h_try,
                error,
            };
            let (mut next, attempt) = self.integrator.step(&p.state, h_try).map_err(failed)?;
            if locating && attempt.contact.active > 0 && h_try > locate {
                info.add_retried(&attempt);
                h = 0.5 * h_try;
                continue;
            }
            // Newton needed shorter steps: keep what converged, go on at the
            // sub-steps' size (no estimate: the step was taken in pieces).
            let error = (attempt.rejected == 0)
                .then(|| self.integrator.local_error(h_try, &p.state, &next));
            let verdict = match error {
                None => Verdict::Accept {
                    next: h_try / attempt.substeps.max(1) as f64,
                },
                Some(error) => judge(&control, h_try, error),
            };
            match verdict {
                Verdict::Accept { next: h_next } => {
                    if at_event {
                        next.time = event;
                    }
                    let retried = std::mem::replace(&mut info, attempt);
                    info.add_work(&retried);
                    p.step_size = Some(h_next);
                    return Ok((next, info));
                }
                Verdict::Retry { h: shorter } => {
                    if shorter < MIN_STEP_FRACTION * end {
                        return Err(failed(StepError::ErrorEstimate {
                            h: h_try,
                            error: error.unwrap_or(f64::NAN),
                            allowed: control.tolerance,
                        }));
                    }
                    info.add_retried(&attempt);
                    h = shorter;
                }
            }
        }
    }

    /// Steps until `time` (s) or the end time, whichever comes first,
    /// calling `observer` after every step with the simulation and the
    /// step's statistics; the observer ends the run early with
    /// `ControlFlow::Break(())`. A failing step ends it with its error,
    /// leaving the simulation at its last completed step.
    pub fn run_until(
        &mut self,
        time: f64,
        mut observer: impl FnMut(&Simulation, &StepInfo) -> ControlFlow<()>,
    ) -> Result<(), SimulationError> {
        while !self.has_reached(time) {
            let info = self.step()?;
            if observer(self, &info).is_break() {
                break;
            }
        }
        Ok(())
    }

    /// Whether every step up to the end time is done.
    pub fn is_finished(&self) -> bool {
        match self.progress.step_size {
            Some(_) => self.progress.state.time >= self.settings.end_time,
            None => self.progress.step >= self.steps,
        }
    }

    /// Whether the simulation has reached `time` (s; within round-off of
    /// the step times) or its end time.
    pub fn has_reached(&self, time: f64) -> bool {
        self.is_finished() || self.progress.state.time >= time - 1e-9 * self.settings.time_step
    }

    /// The current state (time, coordinates, velocities, accelerations).
    pub fn state(&self) -> &State {
        &self.progress.state
    }

    /// The model of the current phase (its unknowns reflect released supports).
    pub fn model(&self) -> &Model {
        &self.integrator.model
    }

    /// Energies of the current state, J.
    pub fn energies(&self) -> Energies {
        self.integrator.energies(&self.progress.state)
    }

    /// Steps completed and steps in all.
    /// An adaptive run's total is an estimate: those done and the rest
    /// at the next step's size.
    pub fn steps(&self) -> (usize, usize) {
        let p = &self.progress;
        match p.step_size {
            Some(h) => {
                let left = ((self.settings.end_time - p.state.time) / h - 1e-9).ceil();
                (p.step, p.step + left.max(0.0) as usize)
            }
            None => (p.step, self.steps),
        }
    }

    /// The force on each rod at every step.
    pub fn rod_loads(&self) -> &[LoadHistory] {
        &self.progress.rod_loads
    }

    /// The contact force the wire put on each frame member at every
    /// completed step (model's member order; empty without members).
    pub fn member_loads(&self) -> &[LoadHistory] {
        &self.progress.member_loads
    }

    /// The force each support exerts on the wire at every step (N, at the
    /// step's generalized-α midpoint), in the model's support order: after
    /// a span breaks, the remaining support's history is the tower's
    /// broken-wire load.
    pub fn support_loads(&self) -> &[LoadHistory] {
        &self.progress.support_loads
    }

    /// The moment each support's springs exert on the body at every step,
    /// N m (model's support order; empty when no support has a rotational
    /// or torsional spring).
    pub fn support_moments(&self) -> &[LoadHistory] {
        &self.progress.support_moments
    }

    /// The force each support exerts on the wire at t = 0 (N), in the
    /// model's support order: the static reaction when the run starts from
    /// a static equilibrium ([`Initial::Static`], every support holding,
    /// those released at t = 0 too), else the reaction that the reference
    /// state's initial acceleration implies.
    pub fn initial_support_forces(&self) -> &[[f64; 3]] {
        &self.progress.initial_support_forces
    }

    /// The wire's contact so far: first touch, largest normal force and
    /// penetration (`None` without rods; per rod, see [`Self::rod_loads`]).
    pub fn contact(&self) -> Option<&ContactRecord> {
        self.progress.contact.as_ref()
    }

    /// Everything accumulated so far (statistics, loads), see [`Snapshot`].
    pub fn progress(&self) -> &Snapshot {
        &self.progress
    }

    /// A snapshot to resume from: a run resumed from it repeats this one's
    /// iterations bit for bit (it carries where the kept factorization was
    /// formed, and the resumed run refactors there).
    pub fn snapshot(&self) -> Snapshot {
        Snapshot {
            energy_reference: self.integrator.energy_reference(),
            subdivision: self.integrator.subdivision(),
            factorization: self.integrator.factorization_origin(),
            ..self.progress.clone()
        }
    }

    /// Drops the kept factorization: the next step refactors (a run that
    /// does so no longer repeats an uninterrupted one's last bits).
    pub fn refresh_factorization(&mut self) {
        self.integrator.refresh_factorization();
    }

    /// A checkpoint: the snapshot to resume from. The run goes on as it
    /// would without one, and a run resumed from it repeats the same
    /// iterations, bit for bit: results do not depend on how often a run
    /// checkpoints.
    pub fn checkpoint(&mut self) -> Snapshot {
        self.snapshot()
    }
}
