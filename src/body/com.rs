//! The body's centre of mass, from its joints: what the floor pushes and
//! gravity pulls, so what Newton's law holds for (the hips joint swings
//! around it).
//!
//! The legs' segments are weighed with Dempster's segment masses
//! (W. T. Dempster, *Space requirements of the seated operator*, WADC
//! Technical Report 55-159, 1955; as tabulated in D. A. Winter,
//! *Biomechanics and Motor Control of Human Movement*), each at its segment's
//! middle. The rest of the body (trunk, head and arms) is put at the mean of
//! the joints that are in neither leg nor above the hips: an unweighted mean
//! of all joints would give the arms a third of the body's mass instead of a
//! tenth.

use glam::DVec3;

use crate::body::feet::{Foot, FootJoints, above_hips, foot_points};
use crate::body::skeleton::Poses;

/// A thigh's mass, as a fraction of the body's (Dempster): at the middle of
/// hip joint and knee.
pub const THIGH_MASS_FRACTION: f64 = 0.10;

/// A shank's mass, as a fraction of the body's (Dempster): at the middle of
/// knee and ankle.
pub const SHANK_MASS_FRACTION: f64 = 0.0465;

/// A foot's mass, as a fraction of the body's (Dempster): at the ankle.
pub const FOOT_MASS_FRACTION: f64 = 0.0145;

/// The offset from the hips joint to the body's centre of mass, per frame
/// (cm): both legs' segments at their Dempster fractions, and the rest of the
/// mass (68% with both legs whole) at the mean of the other joints, not
/// counting those above `hips`. A leg without a knee is weighed as its foot
/// only; with no other joints the legs alone are averaged.
pub fn hips_to_com_cm(poses: &Poses, parents: &[Option<usize>], feet: FootJoints, hips: usize) -> Vec<DVec3> {
    let legs = feet.map(|foot_joint| leg(parents, foot_joint, hips));
    let toes = feet.map(|foot_joint| foot_points(parents, foot_joint));
    let above = above_hips(parents, hips);
    let in_a_leg =
        |j: usize| Foot::BOTH.iter().any(|&foot| legs[foot].contains(&j) || toes[foot].contains(&j));
    let rest: Vec<usize> = (0..poses.joint_count).filter(|&j| !in_a_leg(j) && !above.contains(&j)).collect();
    (0..poses.frame_count())
        .map(|f| {
            let at = |j: usize| poses.at(f, j);
            let mut com = DVec3::ZERO;
            let mut mass = 0.0;
            for foot in Foot::BOTH {
                let chain = &legs[foot];
                let (foot_joint, knee, hip) = (chain[0], chain.get(1).copied(), chain.get(2).copied());
                com += FOOT_MASS_FRACTION * at(foot_joint);
                mass += FOOT_MASS_FRACTION;
                if let Some(knee) = knee {
                    com += SHANK_MASS_FRACTION * (at(knee) + at(foot_joint)) * 0.5;
                    mass += SHANK_MASS_FRACTION;
                    let hip_at = hip.map_or(at(hips), at);
                    com += THIGH_MASS_FRACTION * (hip_at + at(knee)) * 0.5;
                    mass += THIGH_MASS_FRACTION;
                }
            }
            if !rest.is_empty() {
                let upper = 1.0 - mass;
                com += upper * rest.iter().map(|&j| at(j)).sum::<DVec3>() / rest.len() as f64;
                mass = 1.0;
            }
            com / mass - at(hips)
        })
        .collect()
}

/// A leg: the joints from `foot_joint` up to, not including, `hips`: foot,
/// knee, hip joint, … (never empty).
fn leg(parents: &[Option<usize>], foot_joint: usize, hips: usize) -> Vec<usize> {
    let mut chain = vec![foot_joint];
    while let Some(parent) = parents.get(*chain.last().unwrap_or(&hips)).copied().flatten() {
        if parent == hips || chain.contains(&parent) {
            break;
        }
        chain.push(parent);
    }
    chain
}
