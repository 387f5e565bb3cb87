//! The `ancf` program's library: running a scene and writing what users
//! look at (CSV, JSON, plots). The physics lives in `ancf-core`.

pub mod bench;
pub mod build_info;
pub mod output;
pub mod plot;
pub mod run;
pub mod study;
pub mod sweep;
pub mod vtk;
