//! The human body as the methods see it: the skeleton and its motion
//! channels, forward kinematics to global joint positions ([`skeleton::Poses`]),
//! which joints are the feet, the sole of each foot, and the centre of mass.
//! May import `signal`; nothing above (no file formats, no methods).

pub mod com;
pub mod feet;
pub mod kinematics;
pub mod skeleton;
pub mod sole;
