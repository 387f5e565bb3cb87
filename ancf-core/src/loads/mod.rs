//! Loads as impact engineers report them: the CFC filter and a rod's force
//! history (peaks, impulse, duration).

pub mod cfc;
pub mod rod_load;
