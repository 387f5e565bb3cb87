//! Solvers: static equilibrium, generalized-α time steps, and the
//! [`simulation::Simulation`] that runs a scene's dynamics through its phases.

pub mod cancel;
pub mod dynamics;
pub mod permanent_set;
mod reactions;
pub mod simulation;
pub mod statics;

/// Whether every residual entry (N) is within its round-off
/// ([`crate::model::Model::roundoff_forces`]): no iteration can reduce it further.
pub(crate) fn at_roundoff(r: &[f64], roundoff: &[f64]) -> bool {
    r.iter().zip(roundoff).all(|(v, t)| v.abs() <= *t)
}
