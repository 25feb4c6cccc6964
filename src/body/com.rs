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
/// mass (68% with both legs whole) at the mean of the other joints, the
/// hips joint among them, not counting those above `hips`. A leg without a
/// knee is weighed as its foot only; with no other joints the legs alone are
/// averaged.
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

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_legs_weigh_their_dempster_fractions_and_the_rest_the_remainder() {
        // Hips (0) at 90 cm; knees (1, 3) at 50 cm and feet (2, 4) at 10 cm,
        // 10 cm either side; a head (5) at 160 cm.
        let parents = [None, Some(0), Some(1), Some(0), Some(3), Some(0)];
        let positions_cm = vec![
            DVec3::new(0.0, 90.0, 0.0),
            DVec3::new(-10.0, 50.0, 0.0),
            DVec3::new(-10.0, 10.0, 0.0),
            DVec3::new(10.0, 50.0, 0.0),
            DVec3::new(10.0, 10.0, 0.0),
            DVec3::new(0.0, 160.0, 0.0),
        ];
        let poses = Poses { joint_count: 6, positions_cm };
        let com = hips_to_com_cm(&poses, &parents, FootJoints { left: 2, right: 4 }, 0);
        // Per leg: the foot at 10 cm, the shank at 30, the thigh at 70; the
        // other 67.8% at the mean of the hips and the head, 125 cm.
        let leg_cm = FOOT_MASS_FRACTION * 10.0 + SHANK_MASS_FRACTION * 30.0 + THIGH_MASS_FRACTION * 70.0;
        let rest = 1.0 - 2.0 * (FOOT_MASS_FRACTION + SHANK_MASS_FRACTION + THIGH_MASS_FRACTION);
        assert!((rest - 0.678).abs() < 1e-12);
        let expected = DVec3::new(0.0, 2.0 * leg_cm + rest * 125.0 - 90.0, 0.0);
        assert!((com[0] - expected).length() < 1e-9, "{} against {expected}", com[0]);
    }
}
