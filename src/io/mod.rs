//! Reading and writing recordings: BVH, RMoCap/Shadow tables and accelerometer
//! side files, each error with its `file:line:column`, and the [`Recording`]
//! they all become. May import `body` (the skeleton and poses a file holds),
//! `signal` and `error`; nothing above.
//!
//! [`Recording`]: recording::Recording

pub mod bvh;
pub mod recording;
pub mod table;
