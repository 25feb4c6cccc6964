//! embusen: gives inertial motion-capture recordings their place on the floor.
//!
//! The core (this crate without the `web` module) is free of browser code so
//! that the CLI, the tests and the wasm app share it:
//! - [`bvh`] and [`table`] read and write recordings,
//! - [`kinematics`] turns channels into global joint positions ([`skeleton::Poses`]),
//! - [`signals`] smooths and differentiates per-frame signals,
//! - [`paper`] is Hachaj & Ogiela's translation method,
//! - [`contact`] is embusen's own: foot contacts chosen over the whole
//!   recording, with flight; [`sole`] is its model of the foot's floor points,
//! - [`eval`] measures both against recordings whose true root motion is known,
//! - [`metrics`] measures floor paths (length, error, closure),
//! - [`recording`] ties a file to the method and writes the result back,
//! - [`demo`] generates the built-in synthetic recording.

pub mod bvh;
pub mod contact;
pub mod demo;
pub mod error;
pub mod eval;
pub mod feet;
pub mod kinematics;
pub mod metrics;
pub mod paper;
pub mod plot;
pub mod recording;
pub mod session;
pub mod signals;
pub mod skeleton;
pub mod sole;
pub mod table;

pub use error::Error;

// The browser app: only in the wasm build, so the core stays browser-free.
#[cfg(target_arch = "wasm32")]
pub mod web;
