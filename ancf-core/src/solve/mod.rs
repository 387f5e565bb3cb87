//! Solvers: static equilibrium, generalized-α time steps, and the
//! [`simulation::Simulation`] that runs a scene's dynamics through its phases.

pub mod cancel;
pub mod dynamics;
mod reactions;
pub mod simulation;
pub mod statics;
