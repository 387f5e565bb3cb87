//! A member's permanent set: how far its rest shape after a run lies from
//! its rest shape before. Each rest shape is a static equilibrium of the
//! member alone ([`Model::alone`]: its supports, springs and own weight,
//! the wire lifted off); the one after starts from the run's end with the
//! yielding points' states the run left, so the member springs back
//! elastically (or yields again in reverse) from wherever it stopped. A
//! displacement read at the run's end instead holds vibration and the
//! wire's weight, and a run is rarely long enough to end at rest.

use crate::material::beam_plasticity::PlasticState;
use crate::math::vec3::{norm, sub};
use crate::model::Model;
use crate::solve::statics::{StaticError, StaticSettings, solve_static_continuing};

/// A member's permanent set.
#[derive(Clone, Debug, PartialEq)]
pub struct PermanentSet {
    /// The largest distance between a node's rest positions after and
    /// before (m).
    pub set: f64,
    /// Where: the node's arc length from the member's first node (m).
    pub at: f64,
    /// Each node's rest position after, less its rest position before (m).
    pub displacement: Vec<[f64; 3]>,
}

/// The permanent set of beam `beam` of `model` at the end of a run whose
/// coordinates are `end.0` and the yielding points' states `end.1`
/// (empty: virgin, an elastic member's set is then zero). `model` is the
/// one holding at the run's end ([`Model::holding_at`]). Each static solve
/// uses `settings` (one load step suffices: the member's weight is what
/// loads it).
///
/// # Errors
/// A static solve that fails: the member is not held on its own, or
/// springs back into no equilibrium.
pub fn permanent_set(
    model: &Model,
    beam: usize,
    (q, plastic): (&[f64], &[PlasticState]),
    settings: &StaticSettings,
) -> Result<PermanentSet, StaticError> {
    let alone = model.alone(beam);
    let before = solve_static_continuing(
        &alone,
        settings,
        (model.initial_coordinates(), vec![]),
        None,
    )?;
    let after = solve_static_continuing(&alone, settings, (q.to_vec(), plastic.to_vec()), None)?;
    let nodes = model.beams[beam].nodes.clone();
    let start = model.node_arc(nodes.start);
    let mut out = PermanentSet {
        set: 0.0,
        at: 0.0,
        displacement: Vec::with_capacity(nodes.len()),
    };
    for n in nodes {
        let d = sub(
            model.node_position(&after.q, n),
            model.node_position(&before.q, n),
        );
        let size = norm(d);
        if size > out.set {
            (out.set, out.at) = (size, model.node_arc(n) - start);
        }
        out.displacement.push(d);
    }
    Ok(out)
}
