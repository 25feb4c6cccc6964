//! Per-frame signals, knowing nothing of bodies or files: Gaussian smoothing
//! (the R `smoother` port the paper's parity rests on), accelerations as an
//! accelerometer reads them, and statistics. The bottom layer: it imports
//! nothing of the crate.

pub mod accel;
pub mod smoothing;
pub mod stats;
