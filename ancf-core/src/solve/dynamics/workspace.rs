//! The residual's vectors, allocated once per integrator.

use crate::forces::assembly::centerline_shift;
use crate::model::Model;

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

/// A Newton step's vectors, kept over the steps so that no step allocates
/// (and clears) them: the residual and the Newton direction (unknowns),
/// which trade places at every iteration, full Newton's residual for its
/// Jacobian, and the last accepted iterate a₁ (full coordinates).
#[derive(Default)]
pub(super) struct NewtonVectors {
    pub(super) r: Vec<f64>,
    pub(super) da: Vec<f64>,
    pub(super) jacobian_r: Vec<f64>,
    pub(super) base_a1: Vec<f64>,
}

/// How far (wire radii) the centerline may move from where the candidate
/// contact pairs were found before the Newton iterations stop trusting
/// them and visit every pair: a step moves a falling wire by millimetres,
/// a wire radius is centimetres, so one candidate set serves many steps.
pub(super) const CANDIDATE_MARGIN: f64 = 4.0;

impl Workspace {
    /// The contact candidates if they hold at `q` (full coordinates): its
    /// centerline lies within `reach` (m) of where they were found
    /// ([`centerline_shift`]). With `reach` up to their margin, every pair
    /// that can touch at `q` is among them, and visiting only them gives
    /// the same bits as visiting every pair.
    pub(super) fn candidates_at(&self, model: &Model, q: &[f64], reach: f64) -> Option<&[usize]> {
        let at = &self.contact_pairs_at;
        let hold = at.len() == q.len() && centerline_shift(model, at, q) <= reach;
        hold.then_some(&self.contact_pairs[..])
    }

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
