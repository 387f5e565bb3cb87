//! The integrator's state in full coordinates, and what it remembers of
//! the step that produced it.

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
    /// [`super::predict`]). `None` at t = 0 and after a restart from equilibrium;
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
    /// The yielding points' states (see
    /// [`crate::forces::plastic::PlasticLayout`]); empty without a
    /// yielding layer.
    #[serde(default)]
    pub plastic: Vec<crate::material::beam_plasticity::PlasticState>,
    /// Plastic work since t = 0 per beam (J); empty without a yielding
    /// layer.
    #[serde(default)]
    pub plastic_work: Vec<f64>,
    /// The moment loads' work since t = 0 (J), summed step by step: a
    /// moment of fixed direction has no potential ([`crate::forces::moment`]).
    #[serde(default)]
    pub moment_work: f64,
}

/// The contact events after a step: `old` carried where the pair still
/// touches, begun where it touches for the first time, cleared where it
/// no longer touches.
pub(super) fn next_contact_events(old: &[f64], touching: &[Option<f64>]) -> Vec<f64> {
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

/// Where the kept factorization of the Newton matrix was formed: the step's
/// start state, the iterate a₁ of the Jacobian, the step h and the
/// precision it was kept in. A checkpoint
/// carries it, so a resumed run refactors the same matrix and repeats the
/// uninterrupted run's iterations bit for bit.
#[derive(Clone, Debug, PartialEq, serde::Serialize, serde::Deserialize)]
pub struct FactorizationOrigin {
    /// The step's start.
    pub state: State,
    /// The iterate (full coordinates) the Jacobian was evaluated at.
    pub a1: Vec<f64>,
    /// The step, s.
    pub h: f64,
    /// The precision the factorization keeps its blocks in (absent in
    /// checkpoints written before it existed, which kept double).
    #[serde(default)]
    pub precision: crate::linalg::block_tridiagonal::Precision,
}
