//! The residual's vectors, allocated once per integrator.

/// The residual's midpoint vectors (full coordinates), allocated once.
#[derive(Default)]
pub(super) struct Workspace {
    pub(super) qm: Vec<f64>,
    pub(super) vm: Vec<f64>,
    pub(super) am: Vec<f64>,
    pub(super) ma: Vec<f64>,
    /// The (element, rod) pairs the broad phase lets through at the step's
    /// start with [`CANDIDATE_MARGIN`] wire radii more reach, and the start
    /// coordinates they were found at (see `contact_candidates`).
    pub(super) contact_pairs: Vec<usize>,
    pub(super) contact_pairs_at: Vec<f64>,
    /// The pairs within reach of an adaptive step (see
    /// `Integrator::contact_within_reach`).
    pub(super) reach_pairs: Vec<usize>,
}

/// Whether two vectors are equal bit for bit: integer compares, eight at a
/// time without an exit inside (so they vectorize; `==` on f64 branches on
/// NaN at every entry, `all` on every entry).
pub(super) fn same_bits(a: &[f64], b: &[f64]) -> bool {
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
