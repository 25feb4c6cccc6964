//! Images and the per-frame pipeline of the camera tracker (Riečický et al.):
//! background subtraction against a still of the empty room (or a per-pixel
//! median of frames) brought to each frame's exposure, a threshold set from
//! the image's own noise, Canny edges, and exact Euclidean distance
//! transforms. Knows nothing of bodies, cameras or files: it imports only
//! `error`, so the CLI, the tests and the wasm app compute the same bytes
//! from the same frame (integer arithmetic throughout, IEEE `sqrt` the only
//! floating-point step that reaches a pixel).
//!
//! Pixels are row-major, `(0, 0)` the top-left pixel, x right, y down, a
//! pixel's value standing for its centre (the convention of `camera`).

pub mod background;
pub mod canny;
pub mod components;
pub mod distance;
pub mod grey;
pub mod morphology;
pub mod pipeline;
pub mod shrink;

pub use grey::{DistanceImage, GreyImage, Mask, PixelBox, fnv1a};
pub use shrink::Shrink;
