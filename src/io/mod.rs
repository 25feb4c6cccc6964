//! Reading and writing recordings: BVH, RMoCap/Shadow tables, accelerometer
//! side files and the hips path as CSV, each error with its `file:line:column`,
//! and the [`Recording`] they all become. May import `body` (the skeleton and poses a file holds),
//! `signal` and `error`; nothing above.
//!
//! [`Recording`]: recording::Recording

pub mod bvh;
pub mod hips_csv;
pub mod recording;
pub mod table;
