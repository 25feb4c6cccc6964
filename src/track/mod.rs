//! The camera tracker: where the actor is on the floor, from one calibrated
//! camera filming the suit's pose, the contact method its inertial
//! prediction; [`silhouette`] renders the body model of `body::shape` as
//! the camera sees it, on the CPU. May import `signal`, `error`, `image`,
//! `body`, `camera`, `io` and `translate`.

pub mod energy;
pub mod offset;
pub mod paper;
pub mod path;
pub mod search;
pub mod silhouette;
pub mod smoother;
pub mod suit_motion;
pub mod take;
pub mod tracker;
