//! Running a scene and writing what users look at: summary.json,
//! timeseries.csv and the other CSV files, ParaView (VTK) frames, PNG plots
//! and checkpoints to resume from. The physics lives in `ancf-core`; the
//! `ancf` program and the Python package both run scenes through here.

pub mod build_info;
pub mod lock;
pub mod output;
pub mod plot;
pub mod run;
pub mod vtk;
