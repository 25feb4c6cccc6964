//! The camera trackers: where the actor is on the floor, from one calibrated
//! camera filming the suit's pose. [`tracker`] runs one of two over a
//! video, each frame's features computed once ([`setup`]) at the scale the
//! measurement needs ([`working_scale`]): Riečický et
//! al.'s as published ([`riecicky`]) or embusen's ([`fused`]: the contact
//! method's floor path predicts, [`smoother`] weighs it against the camera,
//! [`path`] searches the whole path along the lines of sight,
//! [`soles`] sees the planted feet, [`depth`] takes the path's depth
//! from them; [`path_scorer`] scores the path's energies apart). Both score a
//! body's silhouette ([`silhouette`], rendered on the CPU from
//! `body::shape`) against the frame ([`energy`]); [`take`] makes a take
//! and writes its track, [`offset`] finds the video's time offset, and
//! [`views`] weighs several cameras' tracks of one take into one. May
//! import `signal`, `error`, `image`, `body`, `camera`, `io` and
//! `translate`.

pub mod depth;
pub mod energy;
pub mod fused;
pub mod measurement;
pub mod offset;
pub mod path;
pub mod path_scorer;
pub mod riecicky;
pub mod search;
pub mod setup;
pub mod silhouette;
pub mod smoother;
pub mod soles;
pub mod suit_motion;
pub mod take;
pub mod tracker;
pub mod views;
pub mod working_scale;
