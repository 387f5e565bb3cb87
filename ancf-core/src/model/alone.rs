//! One beam of a model on its own: what the beam keeps when everything
//! else is taken away. A member's permanent set is its rest shape with the
//! wire lifted off, under its own weight on its own supports; this model
//! is the problem that rest shape solves.

use super::{Effect, Model, NODE_DOFS, free_runs};

impl Model {
    /// Beam `beam` alone: the supports holding it in `self` (a release
    /// phase's model has let go of those released) and its springs, gravity and its
    /// elasticity, every other beam's coordinates held where a solve's
    /// start puts them, and no point loads, contact or damping. The
    /// elements, the reference and the yielding points' layout are
    /// `self`'s, so coordinates and plastic states carry over both ways.
    ///
    /// # Panics
    /// If `beam` is not one of the model's beams.
    pub fn alone(&self, beam: usize) -> Model {
        let nodes = self.beams[beam].nodes.clone();
        let own = NODE_DOFS * nodes.start..NODE_DOFS * nodes.end;
        let mut dof_map = vec![None; self.dof_map.len()];
        let mut n_unknowns = 0;
        for c in own {
            if self.dof_map[c].is_some() {
                dof_map[c] = Some(n_unknowns);
                n_unknowns += 1;
            }
        }
        let effects = (self.effects.iter())
            .filter(|e| {
                matches!(
                    e,
                    Effect::Elasticity { .. } | Effect::Gravity { .. } | Effect::Springs(_)
                )
            })
            .cloned()
            .collect();
        Model {
            free: free_runs(&dof_map),
            dof_map,
            n_unknowns,
            effects,
            ..self.clone()
        }
    }

    /// Whether every coordinate of beam `beam` is held (eliminated).
    pub(crate) fn fully_held(&self, beam: usize) -> bool {
        let nodes = &self.beams[beam].nodes;
        self.dof_map[NODE_DOFS * nodes.start..NODE_DOFS * nodes.end]
            .iter()
            .all(Option::is_none)
    }
}
