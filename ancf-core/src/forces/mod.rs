//! What pushes on the wire, each kind in its own module: elastic forces
//! assembled over the elements (with their Jacobians), contact with rods,
//! damping.

pub mod assembly;
pub mod contact;
pub mod damping;
