//! embusen: gives inertial motion-capture recordings their place on the floor.
//!
//! The crate is layered; each folder imports only the ones below it (see
//! `ARCHITECTURE.md`), and everything but `web` is free of browser code so
//! that the CLI, the tests and the wasm app share it:
//! - [`signal`]: smoothing, accelerations, statistics of per-frame signals;
//! - [`image`]: grey images, background subtraction, Canny edges, distance transforms;
//! - [`body`]: skeleton, forward kinematics, feet, soles;
//! - [`camera`]: the camera that films the actor, its file and calibration;
//! - [`io`]: BVH and table readers and writers, and the [`io::recording::Recording`] they make;
//! - [`translate`]: Hachaj & Ogiela's method and embusen's contact method;
//! - [`track`]: the camera trackers (Riečický et al.'s and embusen's fused
//!   one): where the actor is, from one calibrated camera and the suit's pose;
//! - [`eval`]: both measured against recordings whose true motion is known;
//! - [`synth`]: the built-in synthetic demo;
//! - [`app`]: what the app shows (session, plots, theme) and the camera-tracking
//!   job the CLI shares, still browser-free;
//! - `web`: the browser app's wasm modules (wasm builds only).

pub mod app;
pub mod body;
pub mod camera;
pub mod error;
pub mod eval;
pub mod image;
pub mod io;
pub mod signal;
pub mod synth;
pub mod track;
pub mod translate;

pub use error::Error;

// The browser app: only in the wasm build, so the core stays browser-free.
#[cfg(target_arch = "wasm32")]
pub mod web;
