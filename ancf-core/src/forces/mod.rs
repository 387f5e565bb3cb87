//! What pushes on the wire, each kind in its own module: elastic forces
//! assembled over the elements (with their Jacobians), contact with rods
//! and frame members (with the blocks coupling two beams), damping; [`sum`] adds up those a model names, for every solver.

pub mod assembly;
pub mod contact;
pub mod coupling;
pub mod damping;
pub mod moment;
pub mod plastic;
pub mod sum;
