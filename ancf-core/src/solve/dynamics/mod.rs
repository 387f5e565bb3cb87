//! Implicit generalized-α time integration (Chung–Hulbert, SPEC §6), Newton
//! on the accelerations, with full or modified Newton and step cutting.
//! The integrator (the Newton step) is here; its settings, state,
//! predictor, Broyden updates, energies, errors, step statistics and vector loops each have
//! a file of their own.

mod alpha;
mod broyden;
mod energies;
mod error;
mod kept_rotation;
mod predictor;
mod settings;
mod state;
mod step_info;
pub mod step_size;
mod vectors;
mod workspace;

pub use alpha::AlphaParameters;
pub use energies::Energies;
pub use error::{Matrix, StepError};
pub use predictor::predict;
pub use settings::{DEFAULT_SPECTRAL_RADIUS, DynamicSettings, MAX_STEPS, NewtonKind};
pub use state::{FactorizationOrigin, PreviousStep, State};
pub use step_info::{SUBDIVISION_HOLD, StepInfo, Subdivision};
pub use step_size::StepControl;

use crate::forces::assembly::{centerline_shift, contact_candidates, mass_values};
use crate::forces::plastic::plastic_step;
use crate::forces::sum::{At, ForceSum};
use crate::linalg::block_tridiagonal::Precision;
use crate::linalg::linear_solver::SparseSolver;
use crate::linalg::value_sum::ValueSum;
use crate::material::beam_plasticity::PlasticState;
use crate::math::simd::path;
use crate::model::Model;
use crate::solve::reactions::support_forces;
use broyden::Broyden;
use kept_rotation::KeptRotation;
use state::next_contact_events;
use std::sync::Arc;
use step_info::CutLog;
use vectors::{balance, clear_velocity_jacobian, midpoint, norm};
use workspace::{CANDIDATE_MARGIN, NewtonVectors, Workspace};

/// Modified Newton refreshes a kept matrix whose iteration reduced the
/// residual by less than this factor. A refresh (Jacobian and
/// factorization) costs about ten iterations (force and solve), so a
/// matrix that still halves the residual is kept: fewer factorizations
/// for somewhat more iterations than at 0.25, faster on the span breaks
/// and the pendulum, a little slower on the small impact (BENCHMARKS.md).
const SLOW_CONTRACTION: f64 = 0.5;

/// A fresh single-precision matrix whose first iteration reduced the
/// residual by less than this factor is formed again in double: a fresh
/// matrix of a well-conditioned step contracts far more (33 → 3e-4 times
/// the tolerance in one iteration on the span break).
const FRESH_CONTRACTION: f64 = 0.25;

/// The integrator: owns the model's force sum (with the pattern), the
/// symbolic factorization and the constant mass values, computed once per
/// model.
pub struct Integrator {
    /// The model it integrates (shared: a simulation keeps one per phase).
    pub model: Arc<Model>,
    /// The settings it runs with.
    pub settings: DynamicSettings,
    params: AlphaParameters,
    forces: ForceSum,
    mass: Vec<f64>,
    solver: SparseSolver,
    /// Step size of the current factorization, if it is valid for reuse.
    factored_for: Option<f64>,
    /// Where that factorization was formed (kept for checkpoints).
    factored_at: Option<FactorizationOrigin>,
    /// How finely steps start, after the last cuts (see [`Integrator::step`]).
    subdivision: Subdivision,
    /// The loads' size on the unknowns (N; [`load_norm`], a residual
    /// scale, constant, so computed once).
    ext_norm: f64,
    /// Residual entries below these are round-off (N), one per unknown, see
    /// [`Model::roundoff_forces`].
    roundoff: Vec<f64>,
    /// Total + dissipated energy at the initial state (J), for the energy guard.
    energy_start: f64,
    /// Largest kinetic + strain + |potentials| + contact seen so far (J).
    energy_scale: f64,
    /// Energy below which changes are round-off (J): 1e-9 of the model's
    /// weight times its length (or 1e-12 J without gravity).
    energy_floor: f64,
    /// Newton-matrix workspaces in pattern slots, allocated once: −∂Q/∂q,
    /// −∂Q/∂v (at 4096 elements each is 14 MB; allocating and zeroing them
    /// every step was ≈ 10 % of a step, perf), and the matrix
    /// (1 − α_m) M + c_k K + c_d D itself, allocated only when a
    /// factorization needs it written out (the block LU reads the sum).
    kq: Vec<f64>,
    kv: Vec<f64>,
    newton_matrix: Vec<f64>,
    /// The value slots of `kv` the last Jacobian evaluation may have
    /// written (all of them with structural or support damping; with
    /// friction or contact damping alone, the columns of the elements in
    /// contact; none without a velocity Jacobian): the part to clear
    /// before the next one, and the only part the Newton matrix adds.
    kv_written: std::ops::Range<usize>,
    /// The Newton matrix's blocks coupling two beams in contact (outside
    /// the pattern; empty without them).
    coupled_blocks: Vec<crate::linalg::coupled::CoupledBlock>,
    work: Workspace,
    newton_vectors: NewtonVectors,
    /// The current step's Newton directions, for Broyden's updates.
    broyden: Broyden,
    /// The nodes' frames where the kept matrix was formed, by which modified
    /// Newton turns it to the current iterate (see [`kept_rotation`]).
    rotation: KeptRotation,
    /// Each support's force on the body in the last
    /// [`Integrator::initial_state`] (N).
    initial_reactions: Vec<[f64; 3]>,
}

/// The size of what loads `model` (N, on the unknowns): ‖Q_ext‖ and, with
/// moment loads, their forces at the reference (whose size turning does
/// not change), which sit in Q rather than Q_ext.
fn load_norm(model: &Model, external: &[f64]) -> f64 {
    let ext = norm(&model.gather(external));
    let moments = crate::forces::moment::load_forces(model, &model.reference, 1.0);
    if moments.is_empty() {
        return ext;
    }
    let m2: f64 = moments.iter().flat_map(|(_, f)| f).map(|v| v * v).sum();
    (ext * ext + m2).sqrt()
}

impl Integrator {
    /// An integrator for `model` (pattern and symbolic factorization built here).
    pub fn new(model: Arc<Model>, settings: DynamicSettings) -> Result<Self, StepError> {
        let forces = ForceSum::new(&model);
        let pattern = forces.pattern();
        let solver =
            SparseSolver::for_dynamics(pattern).map_err(|error| StepError::Factorization {
                matrix: Matrix::Pattern,
                error,
            })?;
        let mass = mass_values(&model, pattern);
        Ok(Integrator {
            params: AlphaParameters::new(settings.spectral_radius),
            model: Arc::clone(&model),
            settings,
            mass,
            solver,
            factored_for: None,
            factored_at: None,
            subdivision: Subdivision::default(),
            ext_norm: load_norm(&model, forces.external()),
            roundoff: model.roundoff_forces(),
            energy_start: 0.0,
            energy_scale: 0.0,
            energy_floor: match model.gravity_acceleration() {
                Some(g) => {
                    let length = model.length();
                    let g = g.iter().map(|x| x * x).sum::<f64>().sqrt();
                    1e-9 * model.total_mass() * g * length + 1e-12
                }
                None => 1e-12,
            },
            kq: pattern.zeros(),
            kv: pattern.zeros(),
            newton_matrix: Vec::new(),
            kv_written: 0..0,
            coupled_blocks: Vec::new(),
            work: Workspace::new(model.reference.len()),
            newton_vectors: NewtonVectors::default(),
            broyden: Broyden::default(),
            rotation: KeptRotation::new(&model),
            initial_reactions: Vec::new(),
            forces,
        })
    }

    /// State at `q0` with velocities `v0` and the consistent initial
    /// acceleration M a₀ = Q_ext − Q(q₀, v₀) − Q_d(q₀, v₀).
    pub fn initial_state(&mut self, q0: Vec<f64>, v0: Vec<f64>) -> Result<State, StepError> {
        self.initial_state_with(q0, v0, (Vec::new(), Vec::new()))
    }

    /// [`Integrator::initial_state`] with the yielding points' states and
    /// the plastic work per beam a path already reached (a static start's,
    /// the state before a release; empty: virgin).
    pub fn initial_state_with(
        &mut self,
        q0: Vec<f64>,
        v0: Vec<f64>,
        (plastic, plastic_work): (Vec<PlasticState>, Vec<f64>),
    ) -> Result<State, StepError> {
        let model = Arc::clone(&self.model);
        let at = At {
            plastic: &plastic,
            ..At::moving(&q0, &v0)
        };
        self.forces.evaluate(&model, at, None, None);
        let rhs_full: Vec<f64> = (self.forces.external().iter())
            .zip(self.forces.internal())
            .map(|(a, b)| a - b)
            .collect();
        let mut a = model.gather(&rhs_full);
        if let Some((qd, _)) = self.forces.damping() {
            a.iter_mut().zip(qd).for_each(|(r, f)| *r -= f);
        }
        // Subtract the mass coupling to prescribed velocities' rates (zero: supports are fixed).
        self.solver
            .factorize(&self.mass, true)
            .map_err(|error| StepError::Factorization {
                matrix: Matrix::Mass,
                error,
            })?;
        self.factored_for = None;
        self.solver.solve_in_place(&mut a);
        let mut a_full = vec![0.0; q0.len()];
        self.model.scatter_add(&a, 1.0, &mut a_full);
        let mut ma = vec![0.0; q0.len()];
        model.mass_times_into(&a_full, &mut ma);
        let (q, ext) = (self.forces.internal(), self.forces.external());
        support_forces(
            &model,
            (&q0, Some(&v0)),
            Some(&ma),
            q,
            ext,
            &mut self.initial_reactions,
        );
        let state = State {
            time: 0.0,
            q: q0,
            v: v0,
            a: a_full,
            dissipated: 0.0,
            previous: None,
            contact_events: Vec::new(),
            plastic,
            plastic_work,
            moment_work: 0.0,
        };
        self.set_energy_reference(&state);
        Ok(state)
    }

    /// Each support's force on the body (N) in the state the last
    /// [`Integrator::initial_state`] returned: M a₀ + Q − Q_ext on the held
    /// position coordinates. From a static equilibrium (a₀ = 0) it is the
    /// static reaction.
    pub fn initial_reactions(&self) -> &[[f64; 3]] {
        &self.initial_reactions
    }

    /// Drop the kept factorization: the next step refactors.
    pub fn refresh_factorization(&mut self) {
        self.factored_for = None;
    }

    /// Where the kept factorization was formed (`None` without a valid one),
    /// for checkpoints.
    pub fn factorization_origin(&self) -> Option<FactorizationOrigin> {
        self.factored_for.and(self.factored_at.clone())
    }

    /// Refactor the Newton matrix where `origin` says (a checkpoint's), so
    /// that the next steps repeat the checkpointed run's iterations.
    pub fn restore_factorization(&mut self, origin: &FactorizationOrigin) -> Result<(), StepError> {
        let (mut kq, mut kv) = (std::mem::take(&mut self.kq), std::mem::take(&mut self.kv));
        clear_velocity_jacobian(&mut kv, self.kv_written.clone());
        let mut scratch = StepInfo::default();
        let (s, a1, h) = (&origin.state, &origin.a1, origin.h);
        self.find_contact_candidates(s);
        let mut r = Vec::new();
        self.residual(s, h, a1, Some((&mut kq, &mut kv)), &mut r, &mut scratch);
        let factored = self.factor_newton_matrix(&kq, &kv, origin.clone());
        (self.kq, self.kv) = (kq, kv);
        factored
    }

    /// Factor the Newton matrix (1 − α_m) M + c_k K_q + c_d K_v, with the
    /// coupling blocks of the same evaluation, from the Jacobians `kq`, `kv`
    /// evaluated where `origin` says, and keep it for steps of `origin.h`.
    fn factor_newton_matrix(
        &mut self,
        kq: &[f64],
        kv: &[f64],
        origin: FactorizationOrigin,
    ) -> Result<(), StepError> {
        let model = Arc::clone(&self.model);
        let AlphaParameters {
            alpha_m,
            alpha_f,
            beta,
            gamma,
        } = self.params;
        let h = origin.h;
        let symmetric = ForceSum::symmetric(&model);
        let velocity_jacobian = ForceSum::velocity_dependent(&model);
        let c_k = (1.0 - alpha_f) * beta * h * h;
        let c_d = (1.0 - alpha_f) * gamma * h;
        // K_v is zero outside the slots the last evaluation wrote, and
        // everywhere without a velocity Jacobian (an empty range).
        let sum = ValueSum {
            parts: [&self.mass, kq, kv],
            weights: [1.0 - alpha_m, c_k, c_d],
            third_slots: self.kv_written.clone(),
        };
        let c_v = if velocity_jacobian { c_d } else { 0.0 };
        (self.forces.coupling()).combined(&model, c_k, c_v, &mut self.coupled_blocks);
        let blocks = &self.coupled_blocks;
        let precision = origin.precision;
        self.solver
            .factorize_sum(&sum, &mut self.newton_matrix, blocks, symmetric, precision)
            .map_err(|error| StepError::Factorization {
                matrix: Matrix::Newton,
                error,
            })?;
        self.factored_for = Some(h);
        self.factored_at = Some(origin);
        // Every caller evaluated the Jacobian just before: the workspace
        // holds its midpoint coordinates. Only a kept matrix is turned.
        if self.settings.newton == NewtonKind::Modified {
            self.rotation.form(&self.work.qm);
        }
        Ok(())
    }

    /// The energy guard's reference (start, scale), for checkpoints.
    pub fn energy_reference(&self) -> (f64, f64) {
        (self.energy_start, self.energy_scale)
    }

    /// Restore the energy guard's reference from a checkpoint.
    pub fn restore_energy_reference(&mut self, reference: (f64, f64)) {
        (self.energy_start, self.energy_scale) = reference;
    }

    /// The state the energy guard measures gains from (total + dissipated),
    /// set by `initial_state`; call it again when a run continues from a
    /// state carrying dissipation (a release phase).
    pub fn set_energy_reference(&mut self, s: &State) {
        let e = self.energies(s);
        self.energy_start = e.balance();
        self.energy_scale = self.energy_scale.max(e.in_play());
    }

    /// Whether every step's energy is checked here (the energy guard of a
    /// model with rods: finite, and no gain above its budget).
    pub fn guards_energy(&self) -> bool {
        self.model.contact().is_some()
    }

    /// Whether the energy of a state the integrator accepted is finite,
    /// at the least cost that decides it: known where the guard computed it
    /// (rods); evaluated where a law can overflow for a finite state (a
    /// Mooney–Rivlin layer of an element turned inside out); elsewhere a
    /// polynomial of the coordinates and velocities, finite when they are.
    pub fn energy_is_finite(&self, s: &State) -> bool {
        if self.guards_energy() {
            return true;
        }
        let mooney_rivlin = self.model.effects.iter().any(|e| {
            matches!(
                e,
                crate::model::Effect::Elasticity {
                    mooney_rivlin: true,
                    ..
                }
            )
        });
        if mooney_rivlin {
            self.energies(s).total().is_finite()
        } else {
            s.q.iter().chain(&s.v).all(|x| x.is_finite())
        }
    }

    /// The local error estimate (m) of the step of `h` s from `s` to
    /// `next`, see [`step_size`].
    pub fn local_error(&self, h: f64, s: &State, next: &State) -> f64 {
        let rho = self.settings.spectral_radius;
        step_size::local_error(&self.model, &self.params, rho, h, s, next)
    }

    /// Whether a step of `h` s from `s` may bring the wire into contact:
    /// the broad phase lets a pair through with twice the reach of the
    /// centerline's predicted move h v + h²/2 a, plus a wire radius. False
    /// without contact.
    pub fn contact_within_reach(&mut self, s: &State, h: f64) -> bool {
        let Some(c) = self.forces.contact_evaluator() else {
            return false;
        };
        let w = &mut self.work;
        w.qm.clear();
        w.qm.extend(
            (s.q.iter().zip(&s.v).zip(&s.a)).map(|((q, v), a)| q + h * v + 0.5 * h * h * a),
        );
        let reach = 2.0 * centerline_shift(&self.model, &s.q, &w.qm) + c.wire_radius;
        contact_candidates(&self.model, c, &s.q, reach, &mut w.reach_pairs);
        !w.reach_pairs.is_empty()
    }

    /// Energies of a state.
    pub fn energies(&self, s: &State) -> Energies {
        self.energies_visiting(s, None)
    }

    /// [`Integrator::energies`] with the contact energy over `pairs` only
    /// (see [`ForceSum::potentials_visiting`]).
    fn energies_visiting(&self, s: &State, pairs: Option<&[usize]>) -> Energies {
        let p = self
            .forces
            .potentials_visiting(&self.model, &s.q, &s.v, pairs, &s.plastic);
        let mv = self.model.mass_times(&s.v);
        let kinetic = 0.5 * s.v.iter().zip(&mv).map(|(a, b)| a * b).sum::<f64>();
        Energies {
            kinetic,
            strain: p.strain,
            gravity: p.gravity,
            loads: p.loads - s.moment_work,
            contact: p.contact,
            dissipated: s.dissipated,
            plastic: s.plastic_work.iter().sum(),
        }
    }

    /// Advance by one step of size `h`, cutting it in halves on failure.
    ///
    /// When Newton failed on an attempt (no convergence, a non-finite
    /// residual, or a converged state holding more new energy than the
    /// whole run has in play: a wrong root, measured 5.7 kJ on a 17 J
    /// swing), the next steps start at the sub-step size that worked
    /// instead of failing again at the full size, and try twice that size
    /// after [`SUBDIVISION_HOLD`] steps without such a failure. Other rejections
    /// (the energy guard's 1 % budget, the penetration limit) leave the
    /// next step's start alone: trying the full size first is what lets a
    /// run on the budget find a step that keeps it (holding the sub-steps
    /// there makes stiff-contact runs fail). A run without
    /// cuts never subdivides.
    pub fn step(&mut self, s: &State, h: f64) -> Result<(State, StepInfo), StepError> {
        let mut info = StepInfo::default();
        let mut log = CutLog {
            shallowest: usize::MAX,
            newton_failed: false,
        };
        let next = self.step_cut(s, h, 0, &mut info, &mut log)?;
        let sub = &mut self.subdivision;
        if log.newton_failed {
            // Attempts start at `sub.depth` or deeper, so this never coarsens.
            *sub = Subdivision {
                depth: log.shallowest,
                held: 0,
            };
        } else if sub.depth > 0 {
            sub.held += 1;
            if sub.held >= SUBDIVISION_HOLD {
                *sub = Subdivision {
                    depth: sub.depth - 1,
                    held: 0,
                };
            }
        }
        Ok((next, info))
    }

    /// How finely steps start now (see [`Integrator::step`]), for checkpoints.
    pub fn subdivision(&self) -> Subdivision {
        self.subdivision
    }

    /// Restore the step subdivision from a checkpoint.
    pub fn restore_subdivision(&mut self, subdivision: Subdivision) {
        self.subdivision = subdivision;
    }

    /// One attempt at `h` (`depth` halvings below the step), or its two
    /// halves if it fails or if steps start finer than `depth`. The work
    /// of rejected attempts is counted in `info`.
    fn step_cut(
        &mut self,
        s: &State,
        h: f64,
        depth: usize,
        info: &mut StepInfo,
        log: &mut CutLog,
    ) -> Result<State, StepError> {
        if depth < self.subdivision.depth {
            let mid = self.step_cut(s, 0.5 * h, depth + 1, info, log)?;
            return self.step_cut(&mid, 0.5 * h, depth + 1, info, log);
        }
        let attempt = self.try_step(s, h, info).and_then(|next| {
            // A node whose gradients turned over is no state of a solid
            // (Green–Lagrange strain does not see it).
            if let Some(node) = self.model.inverted_node(&next.q) {
                return Err(StepError::Inverted { node });
            }
            let Some(c) = self.model.contact() else {
                return Ok(next);
            };
            // A converged step that drove the wire deep into a rod was too coarse for the contact.
            if info.contact.max_penetration > c.settings.max_penetration * c.wire_radius {
                return Err(StepError::Penetration {
                    depth: info.contact.max_penetration,
                    limit: c.settings.max_penetration,
                });
            }
            // Nor may the run create energy: loads are constant and the
            // scheme conservative or dissipative, so total + dissipated
            // rising more than 1 % of the largest energy in play above its
            // value at the start means the contact was not resolved
            // (measured: h = 1e-2 s in the impact scene gained 196 J on an
            // 8 J swing before Newton failed). It runs every step: a coarse
            // step can also create energy away from any rod (a released end
            // whipping with 5 cm elements at h = 1 ms gained 6e13 J within 47
            // steps once the check was skipped outside contact).
            // The contact candidates hold at the step's end too when the
            // centerline lies within their margin of where they were found
            // (the energy then has the same bits as over every pair, at a
            // fraction of the broad phase).
            let margin = CANDIDATE_MARGIN * c.wire_radius;
            let pairs = self.work.candidates_at(&self.model, &next.q, margin);
            let e1 = self.energies_visiting(&next, pairs);
            let scale = self.energy_scale.max(e1.in_play());
            let gain = e1.balance() - self.energy_start;
            if !gain.is_finite() {
                return Err(StepError::NonFiniteEnergy);
            }
            if gain > 0.01 * scale + self.energy_floor {
                return Err(StepError::EnergyGain { gain });
            }
            self.energy_scale = scale;
            Ok(next)
        });
        match attempt {
            Ok(next) => {
                info.substeps += 1;
                log.shallowest = log.shallowest.min(depth);
                Ok(next)
            }
            Err(e) if depth < self.settings.max_cuts => {
                log.newton_failed |= match e {
                    StepError::NotConverged { .. } | StepError::NonFinite => true,
                    StepError::EnergyGain { gain } => gain > self.energy_scale,
                    _ => false,
                };
                info.rejected += 1;
                self.factored_for = None;
                let mid = self.step_cut(s, 0.5 * h, depth + 1, info, log)?;
                self.step_cut(&mid, 0.5 * h, depth + 1, info, log)
            }
            Err(e) => Err(StepError::Halved {
                cuts: depth,
                h,
                cause: Box::new(e),
            }),
        }
    }

    /// The yielding points' states at the end `q1` of a step of `h` from
    /// `s`, and the plastic work per beam since t = 0 (both empty without
    /// a yielding layer).
    fn plastic_step(&self, s: &State, q1: &[f64], h: f64) -> (Vec<PlasticState>, Vec<f64>) {
        let layout = self.forces.plastic_layout();
        if layout.is_empty() {
            return (Vec::new(), Vec::new());
        }
        let history = self.forces.history(&s.plastic, Some(h));
        let mut states = Vec::new();
        let steps = plastic_step(&self.model, layout, q1, history, &mut states);
        let work = (steps.iter().enumerate())
            .map(|(b, step)| s.plastic_work.get(b).copied().unwrap_or(0.0) + step.work)
            .collect();
        (states, work)
    }

    /// Find the contact candidates for the step from `s` (see
    /// `contact_candidates`) unless those found earlier still hold there
    /// with half their margin to spare: once a step, before its residuals.
    /// A candidate set serves every configuration whose centerline lies
    /// within its margin of where it was found, so a wire that moves
    /// millimetres a step runs the broad phase (every element against
    /// every partner) once in many steps, not once a step.
    fn find_contact_candidates(&mut self, s: &State) {
        let Some(c) = self.forces.contact_evaluator() else {
            return;
        };
        let margin = CANDIDATE_MARGIN * c.wire_radius;
        let w = &mut self.work;
        if w.candidates_at(&self.model, &s.q, 0.5 * margin).is_none() {
            contact_candidates(&self.model, c, &s.q, margin, &mut w.contact_pairs);
            w.contact_pairs_at.clone_from(&s.q);
        }
    }

    /// Residual R(a₁) on the unknowns at the generalized-α midpoint, written
    /// over `r`, and its scale (returned); when `jac` is given, also −∂Q/∂q
    /// (elastic and contact) into `jac.0` and −∂Q_c/∂v (friction) into
    /// `jac.1`. The caller keeps `r`, so that no iteration allocates it.
    fn residual(
        &mut self,
        s: &State,
        h: f64,
        a1: &[f64],
        jac: Option<(&mut [f64], &mut [f64])>,
        r: &mut Vec<f64>,
        info: &mut StepInfo,
    ) -> f64 {
        let params = self.params;
        let model = Arc::clone(&self.model);
        let model = &*model;
        // Midpoint vectors in workspaces allocated once (at 4096 elements
        // each is 390 KB; allocating six of them per residual showed up as
        // page clearing in perf).
        let mut w = std::mem::take(&mut self.work);
        midpoint(
            path(),
            &params,
            h,
            [&s.q, &s.v, &s.a, a1],
            [&mut w.qm, &mut w.vm, &mut w.am],
        );
        let (qm, vm) = (&w.qm[..], &w.vm[..]);
        let (kq, kv) = match jac {
            Some((kq, kv)) => (Some(kq), Some(kv)),
            None => (None, None),
        };
        // The contact candidates (see `find_contact_candidates`); an
        // iterate that moved farther than their margin from where they
        // were found visits all pairs.
        let pairs = (self.forces.contact_evaluator())
            .and_then(|c| w.candidates_at(model, qm, CANDIDATE_MARGIN * c.wire_radius));
        let at = At {
            q: qm,
            v: Some(vm),
            events: &s.contact_events,
            pairs,
            plastic: &s.plastic,
            dt: Some(h),
        };
        let with_jacobian = kq.is_some();
        let started = std::time::Instant::now();
        let velocity_jacobian = kv.is_some() && ForceSum::velocity_dependent(model);
        self.forces.evaluate(model, at, kq, kv);
        if velocity_jacobian {
            self.kv_written = self.forces.velocity_jacobian_slots(model);
        }
        let seconds = started.elapsed().as_secs_f64();
        if with_jacobian {
            info.jacobian_seconds += seconds;
            info.jacobian_evaluations += 1;
        } else {
            info.force_seconds += seconds;
            info.force_evaluations += 1;
        }
        if let Some(cf) = self.forces.contact() {
            info.contact = cf.total;
            info.deepest = cf.deepest;
            info.rod_forces.clone_from(&cf.rod_forces);
            info.member_forces.clone_from(&cf.member_forces);
        }
        let (q, ext) = (self.forces.internal(), self.forces.external());
        model.mass_times_into(&w.am, &mut w.ma);
        let ma = &w.ma;
        // R, ‖M a‖ and ‖Q‖ on the unknowns, run of free coordinates after
        // run (unknowns are numbered in coordinate order, `Model::dof_map`):
        // contiguous slices, so the loops vectorize.
        let (ma2, q2) = balance(model.free_coordinates(), [ma, q, ext], r);
        let scale = ma2.sqrt().max(self.ext_norm).max(q2.sqrt());
        // The supports' forces: the same balance on the held coordinates
        // of each supported node's position (damping acts on unknowns only).
        support_forces(model, (qm, Some(vm)), Some(ma), q, ext, &mut info.reactions);
        if let Some((qd, power)) = self.forces.damping() {
            r.iter_mut().zip(qd).for_each(|(a, b)| *a += b);
            info.damping_power = power;
        }
        self.work = w;
        scale
    }

    /// One generalized-α step of size h without cutting: damped Newton on
    /// a₁. A full step that does not reduce ‖R‖ is first retried with a
    /// fresh Jacobian (modified Newton), then halved (backtracking): the
    /// regularized Coulomb law saturates, and undamped Newton cycles across
    /// stick (measured on the impact scene: ‖R‖ alternating 1.074e3 ↔
    /// 1.075e3 N for 25 iterations at h = 8e-6 s).
    fn try_step(&mut self, s: &State, h: f64, info: &mut StepInfo) -> Result<State, StepError> {
        let (mut kq, mut kv) = (std::mem::take(&mut self.kq), std::mem::take(&mut self.kv));
        let mut vectors = std::mem::take(&mut self.newton_vectors);
        let result = self.newton(s, h, &mut kq, &mut kv, &mut vectors, info);
        (self.kq, self.kv, self.newton_vectors) = (kq, kv, vectors);
        result
    }

    /// The Newton loop of `try_step`, with the Jacobian workspaces.
    fn newton(
        &mut self,
        s: &State,
        h: f64,
        kq: &mut [f64],
        kv: &mut [f64],
        vectors: &mut NewtonVectors,
        info: &mut StepInfo,
    ) -> Result<State, StepError> {
        let model = Arc::clone(&self.model);
        let model = &*model;
        // Predictor (see `predict`); `base` is the last accepted iterate.
        self.find_contact_candidates(s);
        let mut a1 = predict(model, s, h, self.settings.spectral_radius);
        let NewtonVectors {
            r,
            da,
            jacobian_r,
            base_a1,
        } = vectors;
        base_a1.clone_from(&a1);
        let mut base_rn = f64::INFINITY;
        let mut alpha = 1.0;
        // Whether the factorization was computed at `base_a1` in this step.
        let mut fresh = false;
        // Whether the kept matrix was formed before this step (and turned
        // to it, at its first iteration): one rotation serves the step.
        let mut kept_turned = None;
        let mut evaluations = 0;
        let max_evaluations = 4 * self.settings.max_iterations;
        let mut iterations = 0;
        // Modified Newton's matrix only gives directions (it is kept over
        // iterations and steps at which it is already stale), so its blocks
        // are kept in single precision, which halves what each solve reads.
        // A fresh one that then fails to contract 4× may be spoiled by the
        // rounding (an ill-conditioned matrix: large steps, stiff sections):
        // it is formed again in double precision for the rest of the step.
        // Full Newton keeps its quadratic convergence in double precision.
        let mut precision = match self.settings.newton {
            NewtonKind::Modified => Precision::Single,
            NewtonKind::Full => Precision::Double,
        };
        self.broyden.restart();
        loop {
            let need_k = self.settings.newton == NewtonKind::Full || self.factored_for != Some(h);
            // Full Newton: the residual alone first, so that the converged
            // iterate costs no Jacobian (the element force is ≈ 1/5 of a
            // force-and-Jacobian evaluation).
            let k_with_residual = need_k && self.settings.newton != NewtonKind::Full;
            if k_with_residual {
                clear_velocity_jacobian(kv, self.kv_written.clone());
            }
            let scale = self.residual(
                s,
                h,
                &a1,
                k_with_residual.then_some((&mut *kq, &mut *kv)),
                r,
                info,
            );
            evaluations += 1;
            let rn = norm(r);
            if iterations > 0
                && rn.is_finite()
                && (rn <= self.settings.tolerance * scale
                    || crate::solve::at_roundoff(r, &self.roundoff))
            {
                if self.settings.newton == NewtonKind::Modified && iterations > 6 {
                    self.factored_for = None;
                }
                let dissipated = s.dissipated
                    + h * (info.contact.friction_power
                        + info.contact.damping_power
                        + info.damping_power);
                let contact_events = match self.forces.contact() {
                    Some(cf) if !cf.touching.is_empty() => {
                        next_contact_events(&s.contact_events, &cf.touching)
                    }
                    _ => Vec::new(),
                };
                let (q1, v1): (Vec<f64>, Vec<f64>) = AlphaParameters::coordinates(s, &a1)
                    .map(|(q, v, a, a1)| self.params.newmark(h, q, v, a, a1))
                    .unzip();
                let (plastic, plastic_work) = self.plastic_step(s, &q1, h);
                let moment_work =
                    s.moment_work + crate::forces::moment::work_along(&self.model, &s.q, &q1, 1.0);
                return Ok(State {
                    time: s.time + h,
                    q: q1,
                    v: v1,
                    a: a1,
                    dissipated,
                    previous: Some(PreviousStep { h, a: s.a.clone() }),
                    contact_events,
                    plastic,
                    plastic_work,
                    moment_work,
                });
            }
            if evaluations >= max_evaluations || iterations >= self.settings.max_iterations {
                break;
            }
            let decreased = rn.is_finite() && rn <= (1.0 - 1e-4 * alpha) * base_rn;
            // The last direction came from a fresh, rounded matrix.
            let rounded = fresh && self.solver.precision() == Precision::Single;
            let contracted = rn <= FRESH_CONTRACTION * base_rn;
            if rounded && !contracted {
                precision = Precision::Double;
            }
            if !decreased && iterations > 0 {
                if !fresh || rounded {
                    // Stale modified-Newton matrix (or a rounded one):
                    // refresh it at the last accepted iterate.
                    self.factored_for = None;
                    a1.copy_from_slice(base_a1);
                    alpha = 1.0;
                    base_rn = f64::INFINITY;
                    continue;
                }
                if alpha > 1.0 / 64.0 {
                    alpha *= 0.5;
                    model.scatter_add_to(base_a1, da, -alpha, &mut a1);
                    continue;
                }
                // Backtracking exhausted: take the short step and go on.
            }
            if !rn.is_finite() {
                self.factored_for = None;
                return Err(StepError::NonFinite);
            }
            // Modified Newton contracting slowly (< 2× per iteration): refresh here.
            if !need_k && iterations > 0 && rn > SLOW_CONTRACTION * base_rn {
                self.factored_for = None;
                continue;
            }
            // Accept the iterate and take a new Newton direction from it.
            if need_k {
                if !k_with_residual {
                    // Full Newton: the Jacobian at this (accepted) iterate.
                    clear_velocity_jacobian(kv, self.kv_written.clone());
                    let mut scratch = StepInfo::default();
                    let jac = Some((&mut *kq, &mut *kv));
                    self.residual(s, h, &a1, jac, jacobian_r, &mut scratch);
                    info.jacobian_seconds += scratch.jacobian_seconds;
                    info.jacobian_evaluations += scratch.jacobian_evaluations;
                }
                let origin = FactorizationOrigin {
                    state: s.clone(),
                    a1: a1.clone(),
                    h,
                    precision,
                };
                let started = std::time::Instant::now();
                self.factor_newton_matrix(kq, kv, origin)?;
                info.factorization_seconds += started.elapsed().as_secs_f64();
                info.factorizations += 1;
                fresh = true;
            } else {
                fresh = self.settings.newton == NewtonKind::Full;
            }
            // `base_a1` takes the accepted iterate; `a1` (the same held
            // coordinates) is written over with the next one below.
            std::mem::swap(base_a1, &mut a1);
            base_rn = rn;
            std::mem::swap(da, r);
            // A matrix kept from an earlier step, turned with the nodes to
            // the midpoint of this step's first iterate (the last residual's)
            // for all of the step: the rotations change little between
            // iterates, and one matrix per step is what Broyden's updates
            // assume. A matrix formed in this step is not turned.
            if need_k {
                kept_turned = Some(false);
            }
            let turned = *kept_turned.get_or_insert_with(|| self.rotation.turn(&self.work.qm));
            if turned {
                self.rotation.to_formed(da);
            }
            let started = std::time::Instant::now();
            self.solver.solve_in_place(da);
            info.solve_seconds += started.elapsed().as_secs_f64();
            info.solves += 1;
            if turned {
                self.rotation.to_current(da);
            }
            if self.settings.broyden {
                // The update assumes the matrix and the full steps since it
                // was formed: a refactorization or a shortened step restarts it.
                if need_k || alpha != 1.0 {
                    self.broyden.restart();
                }
                self.broyden.direct(da);
            }
            alpha = 1.0;
            model.scatter_add_to(base_a1, da, -1.0, &mut a1);
            iterations += 1;
            info.iterations += 1;
        }
        self.factored_for = None;
        Err(StepError::NotConverged {
            iterations: self.settings.max_iterations,
            tolerance: self.settings.tolerance,
        })
    }
}
