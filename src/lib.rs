//! The `ancf` program's library: benchmarks, the accuracy study and
//! sweeps. The physics lives in `ancf-core`, a scene's run and its outputs
//! in `ancf-output`.

pub mod bench;
pub mod study;
pub mod sweep;

// The run loop and its writers live in `ancf-output` (the Python package
// uses them too); the program's modules reach them by these names.
pub use ancf_output::{build_info, output, plot, run, vtk};
