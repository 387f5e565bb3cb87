//! What pushes on the wire, each kind in its own module: elastic forces
//! assembled over the elements (with their Jacobians), contact with rods,
//! damping; [`sum`] adds up those a model names, for every solver.

pub mod assembly;
pub mod contact;
pub mod damping;
pub mod sum;
