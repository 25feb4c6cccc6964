//! Reading and writing recordings: BVH, RMoCap/Shadow tables, accelerometer
//! side files and the hips path as CSV, each error with its `file:line:column`,
//! and the [`Recording`] they all become; and the camera's pictures: PNG stills, image sequences,
//! (native only) video through ffmpeg, and the encoded frames of MP4 and WebM
//! files for a browser's decoder. May import `body` (the skeleton and
//! poses a file holds), `image` (the grey images pictures become), `signal`
//! and `error`; nothing above.
//!
//! [`Recording`]: recording::Recording

pub mod bvh;
pub mod container;
pub mod hips_csv;
pub mod image_file;
pub mod recording;
pub mod table;
#[cfg(not(target_arch = "wasm32"))]
pub mod video;
