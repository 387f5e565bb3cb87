//! Loads as impact engineers report them: the CFC filter, a rod's force
//! history (peaks, impulse, duration) and the run's contact record (first
//! touch, largest force and penetration).

pub mod cfc;
pub mod contact_record;
pub mod rod_load;
