//! The camera tracker: where the actor is on the floor, from one calibrated
//! camera filming the suit's pose, the contact method its inertial
//! prediction. May import `signal`, `error`, `image`,
//! `body`, `camera`, `io` and `translate`.

pub mod paper;
pub mod search;
pub mod smoother;
pub mod suit_motion;
