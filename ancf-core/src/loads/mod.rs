//! Loads as impact engineers report them: the CFC filter, a rod's force
//! history (peaks, impulse, duration) and the run's contact record (first
//! touch, largest force and penetration); how close the wire came to each
//! clearance zone; a frame member's largest bending moment and stress;
//! each beam's largest strains; what an oscillator of a structure's
//! frequency feels from a support's force; a tube's utilization (EN 1993-1-1).

pub mod cfc;
pub mod clearance_record;
pub mod contact_record;
pub mod design_check;
pub mod member_load;
pub mod response;
pub mod rod_load;
pub mod strain_record;
