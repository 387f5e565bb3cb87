//! The force each support exerts on the body it holds, written once for
//! statics (at rest) and dynamics (with the inertia of the held
//! coordinates).

use crate::model::{Model, NODE_DOFS};

/// The force each support of `model` exerts on the body (N), from the
/// balance M a + Q − Q_ext on the held coordinates of its node's position
/// (`ma`: M a on all coordinates, `None` at rest; zero on a coordinate the
/// support no longer holds), an elastic support's from its springs and
/// dashpot at `at` (coordinates, velocities): into `out`, in the model's
/// support order.
pub(crate) fn support_forces(
    model: &Model,
    at: (&[f64], Option<&[f64]>),
    ma: Option<&[f64]>,
    q: &[f64],
    ext: &[f64],
    out: &mut Vec<[f64; 3]>,
) {
    out.clear();
    let springs = model.springs();
    out.extend(model.supports.iter().enumerate().map(|(i, sup)| {
        if let Some(s) = springs.iter().find(|s| s.support == i) {
            return s.force_on_body(at.0, at.1);
        }
        std::array::from_fn(|k| {
            let c = NODE_DOFS * sup.node + k;
            match (model.dof_map[c], ma) {
                (Some(_), _) => 0.0,
                (None, Some(ma)) => ma[c] + q[c] - ext[c],
                (None, None) => q[c] - ext[c],
            }
        })
    }));
}
