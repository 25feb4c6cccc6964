//! The human body as the methods see it: the skeleton and its motion
//! channels, forward kinematics to global joint positions ([`skeleton::Poses`]),
//! which joints are the feet, the sole of each foot, the centre of mass, and
//! the body's surface (spheres and cones on the joints, [`shape`]: its
//! default [`proportions`], built by [`default_shape`], drawn as a
//! [`mesh`]).
//! May import `signal`; nothing above (no file formats, no methods).

pub mod com;
pub mod default_shape;
pub mod feet;
pub mod kinematics;
pub mod mesh;
pub mod proportions;
pub mod shape;
pub mod skeleton;
pub mod sole;
