//! Synthetic recordings made in code: the built-in demo, a karate-like
//! sequence of stances with a known true translation, as an inertial suit
//! would record it (`suit`: the suit's error model). May import `io`,
//! `body`, `signal` (it builds a BVH and its accelerometer readings); not the
//! methods it is meant to be measured with.

pub mod demo;
pub mod rng;
pub mod suit;
