//! The residual's vectors, allocated once per integrator.

/// The residual's midpoint vectors (full coordinates), allocated once.
#[derive(Default)]
pub(super) struct Workspace {
    pub(super) qm: Vec<f64>,
    pub(super) vm: Vec<f64>,
    pub(super) am: Vec<f64>,
    pub(super) ma: Vec<f64>,
    /// The (element, partner) pairs the broad phase lets through with
    /// [`CANDIDATE_MARGIN`] wire radii more reach, and the coordinates they
    /// were found at (see `contact_candidates`); kept over the steps while
    /// the centerline stays within that margin.
    pub(super) contact_pairs: Vec<usize>,
    pub(super) contact_pairs_at: Vec<f64>,
    /// The pairs within reach of an adaptive step (see
    /// `Integrator::contact_within_reach`).
    pub(super) reach_pairs: Vec<usize>,
}

/// How far (wire radii) the centerline may move from where the candidate
/// contact pairs were found before the Newton iterations stop trusting
/// them and visit every pair: a step moves a falling wire by millimetres,
/// a wire radius is centimetres, so one candidate set serves many steps.
pub(super) const CANDIDATE_MARGIN: f64 = 4.0;

impl Workspace {
    pub(super) fn new(n: usize) -> Self {
        Workspace {
            qm: vec![0.0; n],
            vm: vec![0.0; n],
            am: vec![0.0; n],
            ma: vec![0.0; n],
            contact_pairs: Vec::new(),
            contact_pairs_at: Vec::new(),
            reach_pairs: Vec::new(),
        }
    }
}
