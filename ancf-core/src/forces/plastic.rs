//! The history of a model's yielding points: where each element's states
//! sit in one vector, what the force evaluation reads from it, and the
//! step that writes it once a solver accepts a configuration.
//!
//! The states are the solver's (a dynamic [`crate::solve::dynamics::State`]
//! carries them, so checkpoints and snapshots carry them too); forces only
//! read them, so that a Newton iteration is a pure function of the iterate
//! and the last accepted step.

use crate::element::{PlasticInput, PlasticStep};
use crate::material::beam_plasticity::PlasticState;
use crate::model::Model;

/// Where each element's yielding points sit in the model's history.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct PlasticLayout {
    /// `offsets[el]..offsets[el + 1]`: element `el`'s states; empty when no
    /// layer yields.
    offsets: Vec<usize>,
}

impl PlasticLayout {
    /// The layout of `model`'s yielding points (empty without any).
    pub fn of(model: &Model) -> Self {
        if !model.groups.iter().any(|g| g.integration.plan.is_plastic()) {
            return PlasticLayout::default();
        }
        let mut offsets = Vec::with_capacity(model.n_elements + 1);
        offsets.push(0);
        let mut at = 0;
        for el in 0..model.n_elements {
            if !model.is_gap(el) {
                at += model.element(el).plastic_points();
            }
            offsets.push(at);
        }
        PlasticLayout { offsets }
    }

    /// Whether any point yields.
    pub fn is_empty(&self) -> bool {
        self.offsets.last().is_none_or(|&n| n == 0)
    }

    /// The number of states (0 without yielding points).
    pub fn len(&self) -> usize {
        self.offsets.last().copied().unwrap_or(0)
    }

    /// The virgin history: every point unstrained.
    pub fn virgin(&self) -> Vec<PlasticState> {
        vec![PlasticState::default(); self.len()]
    }

    /// Element `el`'s states in `states` (empty where it has none, or
    /// where `states` is empty: the virgin state).
    pub fn element<'a>(&self, states: &'a [PlasticState], el: usize) -> &'a [PlasticState] {
        match self.offsets.get(el..el + 2) {
            Some(&[a, b]) if b <= states.len() => &states[a..b],
            _ => &[],
        }
    }

    /// Element `el`'s yielding points (0 for an elastic element or a gap).
    pub fn points(&self, el: usize) -> usize {
        self.range(el).len()
    }

    /// The element indices the layout covers (none when empty).
    pub fn elements(&self) -> usize {
        self.offsets.len().saturating_sub(1)
    }

    /// Element `el`'s range in the history.
    fn range(&self, el: usize) -> std::ops::Range<usize> {
        match self.offsets.get(el..el + 2) {
            Some(&[a, b]) => a..b,
            _ => 0..0,
        }
    }
}

/// What a force evaluation reads of the history: the states of the last
/// accepted step and the step being taken.
#[derive(Clone, Copy, Debug, Default)]
pub struct History<'a> {
    /// The layout (`None`: no yielding point, or the virgin state).
    pub layout: Option<&'a PlasticLayout>,
    /// The states, as the layout places them (empty: virgin).
    pub states: &'a [PlasticState],
    /// The step (s) for the rate law; `None`: rate-independent.
    pub dt: Option<f64>,
}

impl<'a> History<'a> {
    /// `states` placed by `layout`, over a step `dt`.
    pub fn of(layout: &'a PlasticLayout, states: &'a [PlasticState], dt: Option<f64>) -> Self {
        History {
            layout: (!layout.is_empty()).then_some(layout),
            states,
            dt,
        }
    }

    /// Element `el`'s part.
    pub fn element(&self, el: usize) -> PlasticInput<'a> {
        PlasticInput {
            states: self.layout.map_or(&[], |l| l.element(self.states, el)),
            dt: self.dt,
        }
    }
}

/// What an accepted step did at the yielding points of one beam.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct BeamPlasticStep {
    /// The step's plastic work (J).
    pub work: f64,
    /// The largest equivalent plastic strain after it …
    pub max_equivalent: f64,
    /// … its element, and ξ ∈ [0, 1] along it.
    pub max_element: usize,
    /// See `max_element`.
    pub max_xi: f64,
}

/// The states `model`'s yielding points keep at the accepted `q` from
/// `history` (written over `out`, sized by the layout), and what the step
/// did on each beam (indexed by beam).
pub fn plastic_step(
    model: &Model,
    layout: &PlasticLayout,
    q: &[f64],
    history: History<'_>,
    out: &mut Vec<PlasticState>,
) -> Vec<BeamPlasticStep> {
    out.resize(layout.len(), PlasticState::default());
    let mut beams = vec![BeamPlasticStep::default(); model.beams.len()];
    for (b, beam) in model.beams.iter().enumerate() {
        for el in beam.elements.clone() {
            let range = layout.range(el);
            if range.is_empty() {
                continue;
            }
            let e = model.element_coordinates(q, el);
            let step: PlasticStep =
                model
                    .element(el)
                    .plastic_step(&e, history.element(el), &mut out[range]);
            let sum = &mut beams[b];
            sum.work += step.work;
            if step.max_equivalent > sum.max_equivalent {
                sum.max_equivalent = step.max_equivalent;
                sum.max_element = el;
                sum.max_xi = step.max_at;
            }
        }
    }
    beams
}
