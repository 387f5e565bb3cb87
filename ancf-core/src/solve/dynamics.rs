//! Implicit generalized-α time integration (Chung–Hulbert, SPEC §6), Newton
//! on the accelerations, with full or modified Newton and step cutting.

use crate::check::{ParameterError, count_in, positive, refuse};
use crate::forces::assembly::{centerline_shift, contact_candidates, mass_values};
use crate::forces::contact::{ContactSample, DeepestPoint};
use crate::forces::sum::{At, ForceSum};
use crate::linalg::linear_solver::{FactorError, SparseSolver};
use crate::math::simd::{Arith, Plain, dot, path};
use crate::model::Model;
use std::sync::Arc;

/// How often the Newton matrix is refactorized.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum NewtonKind {
    /// Fresh Jacobian and factorization every iteration.
    Full,
    /// Keep the factorization across iterations and steps while Newton
    /// converges well (contraction ≤ 0.25 per iteration, ≤ 6 iterations);
    /// refactor otherwise. The default: on the pendulum it needs the same
    /// steps at a fraction of the factorizations.
    Modified,
}

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
    /// Newton iterations allowed per step before the step is cut. Default 25.
    pub max_iterations: usize,
    /// Relative residual tolerance. Default 1e-10.
    pub tolerance: f64,
    /// How many times a step may be halved before the run fails. Default 10.
    pub max_cuts: usize,
}

/// ρ∞ unless said otherwise: 0.9 damps the unresolved axial modes of a
/// stiff wire a little, which a scene's loads do not feel.
pub const DEFAULT_SPECTRAL_RADIUS: f64 = 0.9;

/// The most time steps a run may ask for (a run of this length takes days).
pub const MAX_STEPS: f64 = 1e8;

impl DynamicSettings {
    /// Whether the integrator can run with these settings: h and the end
    /// time > 0, h ≤ end time, at most [`MAX_STEPS`] steps, ρ∞ ∈ [0, 1], a
    /// relative tolerance in (0, 1), at least one Newton iteration.
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
        check_tolerance(self.tolerance)?;
        count_in("max_iterations", self.max_iterations, 1..=10_000)?;
        Ok(())
    }
}

/// A Newton relative tolerance: in (0, 1).
pub(crate) fn check_tolerance(t: f64) -> Result<f64, ParameterError> {
    let t = positive("tolerance", t)?;
    if t >= 1.0 {
        return refuse(
            "tolerance",
            format!("a relative tolerance must be < 1, got {t}"),
        );
    }
    Ok(t)
}

impl Default for DynamicSettings {
    fn default() -> Self {
        DynamicSettings {
            time_step: 1e-3,
            end_time: 1.0,
            spectral_radius: DEFAULT_SPECTRAL_RADIUS,
            newton: NewtonKind::Modified,
            max_iterations: 25,
            tolerance: 1e-10,
            max_cuts: 10,
        }
    }
}

/// Generalized-α parameters from ρ∞.
#[derive(Clone, Copy, Debug)]
pub struct AlphaParameters {
    /// α_m.
    pub alpha_m: f64,
    /// α_f.
    pub alpha_f: f64,
    /// Newmark β.
    pub beta: f64,
    /// Newmark γ.
    pub gamma: f64,
}

impl AlphaParameters {
    /// One coordinate's q₁ and v₁ for a step of size h from (q, v, a) that
    /// ends with acceleration a₁ (Newmark's update, SPEC §6).
    #[inline(always)]
    fn newmark(&self, h: f64, q: f64, v: f64, a: f64, a1: f64) -> (f64, f64) {
        let (beta, gamma) = (self.beta, self.gamma);
        let q1 = q + h * v + h * h * ((0.5 - beta) * a + beta * a1);
        let v1 = v + h * ((1.0 - gamma) * a + gamma * a1);
        (q1, v1)
    }

    /// The state's coordinates with a₁, for Newmark's update: (q, v, a, a₁).
    fn coordinates<'a>(
        s: &'a State,
        a1: &'a [f64],
    ) -> impl Iterator<Item = (f64, f64, f64, f64)> + 'a {
        (s.q.iter().zip(&s.v).zip(&s.a).zip(a1)).map(|(((&q, &v), &a), &a1)| (q, v, a, a1))
    }

    /// The parameters of Chung & Hulbert for spectral radius ρ∞ ∈ [0, 1].
    pub fn new(rho_inf: f64) -> Self {
        let alpha_m = (2.0 * rho_inf - 1.0) / (rho_inf + 1.0);
        let alpha_f = rho_inf / (rho_inf + 1.0);
        let gamma = 0.5 - alpha_m + alpha_f;
        let beta = 0.25 * (1.0 - alpha_m + alpha_f).powi(2);
        AlphaParameters {
            alpha_m,
            alpha_f,
            beta,
            gamma,
        }
    }
}

/// State in full coordinates.
#[derive(Clone, Debug, PartialEq, serde::Serialize, serde::Deserialize)]
pub struct State {
    /// Time (s).
    pub time: f64,
    /// Coordinates, full (m and dimensionless gradients).
    pub q: Vec<f64>,
    /// Velocities, full.
    pub v: Vec<f64>,
    /// Accelerations, full.
    pub a: Vec<f64>,
    /// Energy dissipated by friction and damping since t = 0, J.
    pub dissipated: f64,
    /// The step that produced this state: its size and the acceleration at
    /// its start (the Newton predictor of the next step, see
    /// [`predict`]). `None` at t = 0 and after a restart from equilibrium;
    /// checkpoints written before it existed read as `None`.
    #[serde(default)]
    pub previous: Option<PreviousStep>,
    /// Contact damping's memory: per (element, rod) pair (index
    /// `element × rods + rod`), the approach speed (m/s) at which the pair's
    /// current contact event began, 0 where it is apart or its event began
    /// this step. Empty without contact damping. An event begins at the
    /// first accepted step in which the pair touches (at the step's
    /// generalized-α midpoint, the approach speed is the largest rate of
    /// penetration over the pair's active points) and ends at the first in
    /// which it does not.
    #[serde(default)]
    pub contact_events: Vec<f64>,
}

/// The contact events after a step: `old` carried where the pair still
/// touches, begun where it touches for the first time, cleared where it
/// no longer touches.
fn next_contact_events(old: &[f64], touching: &[Option<f64>]) -> Vec<f64> {
    touching
        .iter()
        .enumerate()
        .map(|(i, t)| match t {
            None => 0.0,
            Some(rate) => match old.get(i).copied().unwrap_or(0.0) {
                speed if speed > 0.0 => speed,
                // A pair that touches without approaching (a settling wire)
                // still begins an event: a positive speed, which the damping
                // factor raises to `contact.min_impact_speed`.
                _ => rate.max(f64::MIN_POSITIVE),
            },
        })
        .collect()
}

/// Size (s) and start acceleration (full coordinates) of the step that led
/// to a state.
#[derive(Clone, Debug, PartialEq, serde::Serialize, serde::Deserialize)]
pub struct PreviousStep {
    /// Its step size (s).
    pub h: f64,
    /// The acceleration at its start.
    pub a: Vec<f64>,
}

/// The Newton predictor for a₁ (full coordinates):
/// a₁ = (1 − ρ∞) a₀ + ρ∞ a₋₁, with a₋₁ the acceleration one step further
/// back, when that step had the same size h; else a₀.
///
/// Why: generalized-α (Chung–Hulbert) does not resolve the modes with
/// ω h ≫ 1 (axial and shear modes of short elements); all its amplification
/// eigenvalues for them tend to −ρ∞, so their acceleration goes
/// a₋₁ → −ρ∞ a₋₁ → ρ∞² a₋₁ over two steps. The weights above are the ones
/// that predict both that sequence and a constant acceleration exactly; a
/// smooth part changing at rate ȧ is off by (1 + ρ∞) h ȧ instead of h ȧ.
/// With ρ∞ = 1 (no numerical damping) those modes flip sign forever, and
/// the a₀ predictor is off by twice their amplitude: on the pendulum the flip
/// sits at the node next to the pin, and it sets the residual Newton starts
/// from, so that modified Newton needs more iterations and, on fine meshes,
/// refactorizations; this predictor removes it. Only unknowns are predicted; prescribed
/// coordinates keep a₀.
pub fn predict(model: &Model, s: &State, h: f64, spectral_radius: f64) -> Vec<f64> {
    let mut a1 = s.a.clone();
    let rho = spectral_radius;
    if let Some(prev) = s
        .previous
        .as_ref()
        .filter(|p| p.h == h && p.a.len() == a1.len() && rho > 0.0)
    {
        for run in model.free_coordinates() {
            let (a0, am1) = (&s.a[run.clone()], &prev.a[run.clone()]);
            for ((a1, a0), am1) in a1[run.clone()].iter_mut().zip(a0).zip(am1) {
                *a1 = (1.0 - rho) * a0 + rho * am1;
            }
        }
    }
    a1
}

/// Energies of a state (J).
#[derive(Clone, Copy, Debug, Default, PartialEq, serde::Serialize, serde::Deserialize)]
pub struct Energies {
    /// Kinetic energy (J).
    pub kinetic: f64,
    /// Strain energy (J).
    pub strain: f64,
    /// Potential of gravity (J).
    pub gravity: f64,
    /// Potential of the point loads (J).
    pub loads: f64,
    /// Contact penalty energy.
    pub contact: f64,
    /// Dissipated by friction and damping since t = 0 (not part of `total`).
    pub dissipated: f64,
}

impl Energies {
    /// Mechanical energy: kinetic + strain + potentials + contact penalty.
    pub fn total(&self) -> f64 {
        self.kinetic + self.strain + self.gravity + self.loads + self.contact
    }

    /// The energy in play, every term counted positive (J): the energy
    /// guard's scale (the potentials may be negative).
    pub fn in_play(&self) -> f64 {
        self.kinetic + self.strain + self.gravity.abs() + self.loads.abs() + self.contact
    }
}

/// Steps without a Newton failure after which [`Integrator::step`] tries
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

/// What the cuts of one step found (see [`Integrator::step`]).
struct CutLog {
    /// The smallest depth an attempt was accepted at.
    shallowest: usize,
    /// Whether Newton failed on an attempt (rather than a guard rejecting
    /// a converged one).
    newton_failed: bool,
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
    /// Contact at the step's generalized-α midpoint (last sub-step).
    pub contact: ContactSample,
    /// Deepest penetrating point: (element, point).
    pub deepest: Option<(usize, DeepestPoint)>,
    /// Force on each rod (normal + friction, N) at the step's midpoint.
    pub rod_forces: Vec<[f64; 3]>,
    /// Power dissipated by damping (W) at the step's midpoint.
    pub damping_power: f64,
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
            StepError::NonFinite => {
                "an element turned inside out or a time step far too large; reduce analysis.time_step"
            }
            StepError::Penetration { .. } => {
                "a contact too soft for the blow or a time step too coarse for it; raise the rod's \
                 contact_stiffness or reduce analysis.time_step"
            }
            StepError::EnergyGain { .. } => {
                "a time step too coarse for the contact (for a line or hertz rod `ancf check` warns when \
                 h √(ε_L / ρA) > 3): reduce analysis.time_step; or, with the contact resolved, the energy \
                 error each step's Newton tolerance leaves, added up over many steps: tighten \
                 analysis.tolerance (the impact scene with the hertz law at 12.5 µs failed at 0.8 s with \
                 1e-4 and completed with 1e-8)"
            }
            StepError::Factorization { .. } => {
                "a singular matrix: too few supports (a free rigid motion) or an element turned inside out"
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
            StepError::Invalid(message) => f.write_str(message),
        }
    }
}

impl std::error::Error for StepError {}

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
    /// How finely steps start, after the last cuts (see [`Integrator::step`]).
    subdivision: Subdivision,
    /// The external force's norm on the unknowns (N; a residual scale,
    /// constant, so computed once).
    ext_norm: f64,
    /// Residual entries below this are round-off (N), see [`Model::roundoff_force`].
    roundoff: f64,
    /// Total + dissipated energy at the initial state (J), for the energy guard.
    energy_start: f64,
    /// Largest kinetic + strain + |potentials| + contact seen so far (J).
    energy_scale: f64,
    /// Energy below which changes are round-off (J): 1e-9 of the model's
    /// weight times its length (or 1e-12 J without gravity).
    energy_floor: f64,
    /// Newton-matrix workspaces in pattern slots, allocated once: −∂Q/∂q,
    /// −∂Q/∂v and the matrix (1 − α_m) M + c_k K + c_d D itself (at 4096
    /// elements each is 14 MB; allocating and zeroing them every step was
    /// ≈ 10 % of a step, perf).
    kq: Vec<f64>,
    kv: Vec<f64>,
    newton_matrix: Vec<f64>,
    work: Workspace,
}

/// The residual's midpoint vectors (full coordinates), allocated once.
#[derive(Default)]
struct Workspace {
    qm: Vec<f64>,
    vm: Vec<f64>,
    am: Vec<f64>,
    ma: Vec<f64>,
    /// The (element, rod) pairs the broad phase lets through at the step's
    /// start with [`CANDIDATE_MARGIN`] wire radii more reach, and the start
    /// coordinates they were found at (see `contact_candidates`).
    contact_pairs: Vec<usize>,
    contact_pairs_at: Vec<f64>,
}

/// Whether two vectors are equal bit for bit: integer compares, eight at a
/// time without an exit inside (so they vectorize; `==` on f64 branches on
/// NaN at every entry, `all` on every entry).
fn same_bits(a: &[f64], b: &[f64]) -> bool {
    a.len() == b.len()
        && a.chunks(8).zip(b.chunks(8)).all(|(x, y)| {
            x.iter()
                .zip(y)
                .fold(true, |same, (x, y)| same & (x.to_bits() == y.to_bits()))
        })
}

/// How far (wire radii) the centerline may move within a step before its
/// Newton iterations stop trusting the step's candidate contact pairs and
/// run the whole broad phase: a step moves a falling wire by millimetres,
/// a wire radius is centimetres.
const CANDIDATE_MARGIN: f64 = 4.0;

impl Workspace {
    fn new(n: usize) -> Self {
        Workspace {
            qm: vec![0.0; n],
            vm: vec![0.0; n],
            am: vec![0.0; n],
            ma: vec![0.0; n],
            contact_pairs: Vec::new(),
            contact_pairs_at: Vec::new(),
        }
    }
}

crate::simd_dispatch! {
    fn midpoint(params: &AlphaParameters, h: f64, state: [&[f64]; 4], out: [&mut [f64]; 3]) = midpoint_with;
}

/// The generalized-α midpoint (q_m, v_m, a_m) of the step from
/// `state` = (q, v, a) ending with acceleration a₁, over all coordinates.
/// Plain multiplications and additions on every path (no fused ones, so
/// the bits do not depend on the path); the AVX paths gain the wider
/// registers. Zipped, without indices, so that the loop vectorizes
/// (indexed, its bounds checks and spills made it ≈ 5 % of the span-break
/// scene).
// `F` unused: `simd_dispatch!` instantiates the loop per path, and this
// one computes with plain arithmetic on every path.
#[allow(clippy::extra_unused_type_parameters)]
#[inline(always)]
fn midpoint_with<F: Arith>(
    params: &AlphaParameters,
    h: f64,
    [q, v, a, a1]: [&[f64]; 4],
    [qm, vm, am]: [&mut [f64]; 3],
) {
    let (alpha_m, alpha_f) = (params.alpha_m, params.alpha_f);
    let state = q.iter().zip(v).zip(a).zip(a1);
    let midpoint = qm.iter_mut().zip(vm.iter_mut()).zip(am.iter_mut());
    for (((qm, vm), am), (((&q, &v), &a), &a1)) in midpoint.zip(state) {
        let (q1, v1) = params.newmark(h, q, v, a, a1);
        *qm = (1.0 - alpha_f) * q1 + alpha_f * q;
        *vm = (1.0 - alpha_f) * v1 + alpha_f * v;
        *am = (1.0 - alpha_m) * a1 + alpha_m * a;
    }
}

crate::simd_dispatch! {
    fn newton_matrix(a: &mut [f64], parts: [&[f64]; 3], c: [f64; 3], velocity_jacobian: bool) = newton_matrix_with;
}

/// The Newton matrix's values A = c₀ M + c₁ Kq (+ c₂ Kv with a velocity
/// Jacobian) over the pattern, in one pass. Plain multiplications and
/// additions on every path, as in `midpoint_with`.
#[allow(clippy::extra_unused_type_parameters)] // as in `midpoint_with`
#[inline(always)]
fn newton_matrix_with<F: Arith>(
    a: &mut [f64],
    [m, kq, kv]: [&[f64]; 3],
    [c_m, c_k, c_d]: [f64; 3],
    velocity_jacobian: bool,
) {
    let parts = a.iter_mut().zip(m).zip(kq);
    if velocity_jacobian {
        for (((a, m), k), d) in parts.zip(kv) {
            *a = (c_m * m + c_k * k) + c_d * d;
        }
    } else {
        for ((a, m), k) in parts {
            *a = c_m * m + c_k * k;
        }
    }
}

/// Zero −∂Q/∂v when it is used (−∂Q/∂q is written over by `assemble`).
fn clear_velocity_jacobian(kv: &mut [f64], velocity_jacobian: bool) {
    if velocity_jacobian {
        kv.fill(0.0);
    }
}

fn norm(v: &[f64]) -> f64 {
    sum_of_squares(v).sqrt()
}

/// Σ vᵢ² with `simd::dot`'s partial sums (one running sum waits on each
/// addition's latency at every entry; only the norms' last bits depend on
/// the order).
fn sum_of_squares(v: &[f64]) -> f64 {
    dot::<Plain>(v, v)
}

/// max |vᵢ| in eight interleaved partial maxima (exact in any order).
fn norm_inf(v: &[f64]) -> f64 {
    const LANES: usize = 8;
    let mut acc = [0.0f64; LANES];
    let chunks = v.chunks_exact(LANES);
    let tail = chunks.remainder();
    for c in chunks {
        for (a, x) in acc.iter_mut().zip(c) {
            *a = a.max(x.abs());
        }
    }
    tail.iter().chain(&acc).fold(0.0, |m, x| m.max(x.abs()))
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
            subdivision: Subdivision::default(),
            ext_norm: norm(&model.gather(forces.external())),
            roundoff: model.roundoff_force(),
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
            newton_matrix: pattern.zeros(),
            work: Workspace::new(model.reference.len()),
            forces,
        })
    }

    /// State at `q0` with velocities `v0` and the consistent initial
    /// acceleration M a₀ = Q_ext − Q(q₀, v₀) − Q_d(q₀, v₀).
    pub fn initial_state(&mut self, q0: Vec<f64>, v0: Vec<f64>) -> Result<State, StepError> {
        let model = Arc::clone(&self.model);
        self.forces
            .evaluate(&model, At::moving(&q0, &v0), None, None);
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
        let state = State {
            time: 0.0,
            q: q0,
            v: v0,
            a: a_full,
            dissipated: 0.0,
            previous: None,
            contact_events: Vec::new(),
        };
        self.set_energy_reference(&state);
        Ok(state)
    }

    /// Drop the kept factorization: the next step refactors. Checkpointed
    /// runs call it after every checkpoint, so a resumed run (which starts
    /// without a factorization) repeats the same iterations, bit for bit.
    pub fn refresh_factorization(&mut self) {
        self.factored_for = None;
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
        self.energy_start = e.total() + e.dissipated;
        self.energy_scale = self.energy_scale.max(e.in_play());
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
            .potentials_visiting(&self.model, &s.q, &s.v, pairs);
        let mv = self.model.mass_times(&s.v);
        let kinetic = 0.5 * s.v.iter().zip(&mv).map(|(a, b)| a * b).sum::<f64>();
        Energies {
            kinetic,
            strain: p.strain,
            gravity: p.gravity,
            loads: p.loads,
            contact: p.contact,
            dissipated: s.dissipated,
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
            // The step's contact candidates hold at its end too when the
            // centerline moved less than their margin (the energy then has
            // the same bits as over every pair, at a fraction of the
            // broad phase: it ran over all pairs twice a step).
            let w = &self.work;
            let candidates = same_bits(&w.contact_pairs_at, &s.q)
                && centerline_shift(&self.model, &s.q, &next.q) <= CANDIDATE_MARGIN * c.wire_radius;
            let e1 = self.energies_visiting(&next, candidates.then_some(&w.contact_pairs[..]));
            let scale = self.energy_scale.max(e1.in_play());
            let gain = (e1.total() + e1.dissipated) - self.energy_start;
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

    /// Residual R(a₁) on the unknowns at the generalized-α midpoint, and its
    /// scale; when `jac` is given, also −∂Q/∂q (elastic and contact) into
    /// `jac.0` and −∂Q_c/∂v (friction) into `jac.1`.
    fn residual(
        &mut self,
        s: &State,
        h: f64,
        a1: &[f64],
        jac: Option<(&mut [f64], &mut [f64])>,
        info: &mut StepInfo,
    ) -> (Vec<f64>, f64) {
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
        // The step's candidate contact pairs, found once at its start; an
        // iterate that moved farther than their margin visits all pairs.
        let pairs = match self.forces.contact_evaluator() {
            Some(c) => {
                let margin = CANDIDATE_MARGIN * c.wire_radius;
                if !same_bits(&w.contact_pairs_at, &s.q) {
                    contact_candidates(model, c, &s.q, margin, &mut w.contact_pairs);
                    w.contact_pairs_at.clone_from(&s.q);
                }
                (centerline_shift(model, &s.q, qm) <= margin).then_some(&w.contact_pairs[..])
            }
            None => None,
        };
        let at = At {
            q: qm,
            v: Some(vm),
            events: &s.contact_events,
            pairs,
        };
        self.forces.evaluate(model, at, kq, kv);
        if let Some(cf) = self.forces.contact() {
            info.contact = cf.total;
            info.deepest = cf.deepest;
            info.rod_forces.clone_from(&cf.rod_forces);
        }
        let (q, ext) = (self.forces.internal(), self.forces.external());
        model.mass_times_into(&w.am, &mut w.ma);
        let ma = &w.ma;
        // R, ‖M a‖ and ‖Q‖ on the unknowns, run of free coordinates after
        // run (unknowns are numbered in coordinate order, `Model::dof_map`):
        // contiguous slices, so the loops vectorize.
        let mut r = Vec::with_capacity(model.n_unknowns);
        let (mut ma2, mut q2) = (0.0, 0.0);
        for run in model.free_coordinates() {
            let (ma, q, ext) = (&ma[run.clone()], &q[run.clone()], &ext[run.clone()]);
            r.extend(ma.iter().zip(q).zip(ext).map(|((ma, q), ext)| ma + q - ext));
            ma2 += sum_of_squares(ma);
            q2 += sum_of_squares(q);
        }
        let scale = ma2.sqrt().max(self.ext_norm).max(q2.sqrt());
        if let Some((qd, power)) = self.forces.damping() {
            r.iter_mut().zip(qd).for_each(|(a, b)| *a += b);
            info.damping_power = power;
        }
        self.work = w;
        (r, scale)
    }

    /// One generalized-α step of size h without cutting: damped Newton on
    /// a₁. A full step that does not reduce ‖R‖ is first retried with a
    /// fresh Jacobian (modified Newton), then halved (backtracking): the
    /// regularized Coulomb law saturates, and undamped Newton cycles across
    /// stick (measured on the impact scene: ‖R‖ alternating 1.074e3 ↔
    /// 1.075e3 N for 25 iterations at h = 8e-6 s).
    fn try_step(&mut self, s: &State, h: f64, info: &mut StepInfo) -> Result<State, StepError> {
        let (mut kq, mut kv) = (std::mem::take(&mut self.kq), std::mem::take(&mut self.kv));
        let result = self.newton(s, h, &mut kq, &mut kv, info);
        (self.kq, self.kv) = (kq, kv);
        result
    }

    /// The Newton loop of `try_step`, with the Jacobian workspaces.
    fn newton(
        &mut self,
        s: &State,
        h: f64,
        kq: &mut [f64],
        kv: &mut [f64],
        info: &mut StepInfo,
    ) -> Result<State, StepError> {
        let AlphaParameters {
            alpha_m,
            alpha_f,
            beta,
            gamma,
        } = self.params;
        let model = Arc::clone(&self.model);
        let model = &*model;
        let symmetric = ForceSum::symmetric(model);
        let velocity_jacobian = ForceSum::velocity_dependent(model);
        let c_k = (1.0 - alpha_f) * beta * h * h;
        let c_d = (1.0 - alpha_f) * gamma * h;
        // Predictor (see `predict`); `base` is the last accepted iterate.
        let mut a1 = predict(model, s, h, self.settings.spectral_radius);
        let mut base_a1 = a1.clone();
        let mut base_rn = f64::INFINITY;
        let mut da: Vec<f64> = Vec::new();
        let mut alpha = 1.0;
        // Whether the factorization was computed at `base_a1` in this step.
        let mut fresh = false;
        let mut evaluations = 0;
        let max_evaluations = 4 * self.settings.max_iterations;
        let mut iterations = 0;
        loop {
            let need_k = self.settings.newton == NewtonKind::Full || self.factored_for != Some(h);
            // Full Newton: the residual alone first, so that the converged
            // iterate costs no Jacobian (the element force is ≈ 1/5 of a
            // force-and-Jacobian evaluation).
            let k_with_residual = need_k && self.settings.newton != NewtonKind::Full;
            if k_with_residual {
                clear_velocity_jacobian(kv, velocity_jacobian);
            }
            let (r, scale) = self.residual(
                s,
                h,
                &a1,
                k_with_residual.then_some((&mut *kq, &mut *kv)),
                info,
            );
            evaluations += 1;
            let rn = norm(&r);
            if iterations > 0
                && rn.is_finite()
                && (rn <= self.settings.tolerance * scale || norm_inf(&r) <= self.roundoff)
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
                let (q1, v1) = AlphaParameters::coordinates(s, &a1)
                    .map(|(q, v, a, a1)| self.params.newmark(h, q, v, a, a1))
                    .unzip();
                return Ok(State {
                    time: s.time + h,
                    q: q1,
                    v: v1,
                    a: a1,
                    dissipated,
                    previous: Some(PreviousStep { h, a: s.a.clone() }),
                    contact_events,
                });
            }
            if evaluations >= max_evaluations || iterations >= self.settings.max_iterations {
                break;
            }
            let decreased = rn.is_finite() && rn <= (1.0 - 1e-4 * alpha) * base_rn;
            if !decreased && iterations > 0 {
                if !fresh {
                    // Stale modified-Newton matrix: refresh it at the last accepted iterate.
                    self.factored_for = None;
                    a1.copy_from_slice(&base_a1);
                    alpha = 1.0;
                    base_rn = f64::INFINITY;
                    continue;
                }
                if alpha > 1.0 / 64.0 {
                    alpha *= 0.5;
                    a1.copy_from_slice(&base_a1);
                    model.scatter_add(&da, -alpha, &mut a1);
                    continue;
                }
                // Backtracking exhausted: take the short step and go on.
            }
            if !rn.is_finite() {
                self.factored_for = None;
                return Err(StepError::NonFinite);
            }
            // Modified Newton contracting slowly (< 4× per iteration): refresh here.
            if !need_k && iterations > 0 && rn > 0.25 * base_rn {
                self.factored_for = None;
                continue;
            }
            // Accept the iterate and take a new Newton direction from it.
            if need_k {
                if !k_with_residual {
                    // Full Newton: the Jacobian at this (accepted) iterate.
                    clear_velocity_jacobian(kv, velocity_jacobian);
                    let mut scratch = StepInfo::default();
                    self.residual(s, h, &a1, Some((&mut *kq, &mut *kv)), &mut scratch);
                }
                newton_matrix(
                    path(),
                    &mut self.newton_matrix,
                    [&self.mass, kq, kv],
                    [1.0 - alpha_m, c_k, c_d],
                    velocity_jacobian,
                );
                self.solver
                    .factorize(&self.newton_matrix, symmetric)
                    .map_err(|error| StepError::Factorization {
                        matrix: Matrix::Newton,
                        error,
                    })?;
                info.factorizations += 1;
                self.factored_for = Some(h);
                fresh = true;
            } else {
                fresh = self.settings.newton == NewtonKind::Full;
            }
            base_a1.copy_from_slice(&a1);
            base_rn = rn;
            da = r;
            self.solver.solve_in_place(&mut da);
            alpha = 1.0;
            model.scatter_add(&da, -1.0, &mut a1);
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
