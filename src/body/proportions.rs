//! The body's default proportions: the part of the body a joint's name
//! says (by role, not by one rig's exact names), each part's radius as a
//! fraction of stature, and the stature estimated from the legs' bone
//! lengths. `default_shape` builds the default body from them.
//!
//! **Sources.** Segment lengths as fractions of stature `H` are Drillis &
//! Contini's (R. Drillis, R. Contini, *Body segment parameters*, Tech. Rep.
//! 1166-03, New York University, 1966; as drawn in D. A. Winter,
//! *Biomechanics and Motor Control of Human Movement*, 4th ed., Fig. 4.1):
//! thigh 0.245 H, shank 0.246 H, hand 0.108 H, foot 0.152 H, head and neck
//! from the shoulders 0.182 H. Girths, breadths and depths are the means of
//! the 2012 US Army survey, ANSUR II (C. C. Gordon et al., *2012
//! Anthropometric Survey of U.S. Army Personnel: Methods and Summary
//! Statistics*, NATICK/TR-15/007, 2014), men's and women's averaged and
//! divided by their mean stature (1.69 m), rounded to a few per mille: a
//! limb's radius is its girth over 2π (a limb's section is nearly round), the
//! trunk's is the mean of its half-breadth and half-depth (a circle between
//! the two widths the camera sees, front-on and side-on).

use glam::DVec3;

use crate::body::feet::detect_feet;

/// What a sphere of the body stands for: its default radius and where its
/// centre sits follow from it.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash, serde::Serialize, serde::Deserialize)]
pub enum Part {
    /// The hips joint: the pelvis.
    Pelvis,
    /// A joint of the spine between the hips and the neck.
    Trunk,
    Neck,
    /// The head's joint at the top of the neck.
    HeadJoint,
    /// The skull, beyond the head's joint.
    Skull,
    /// The joint at the inner end of the collar bone.
    Clavicle,
    /// The shoulder joint, with the deltoid around it.
    Shoulder,
    Elbow,
    Wrist,
    /// The middle of the hand, beyond the wrist.
    Palm,
    /// A finger joint.
    Finger,
    /// The end of the fingers.
    Fingertip,
    /// The hip joint, the thigh's top.
    Hip,
    Knee,
    Ankle,
    /// The ball of the foot (the toes' joint).
    Toes,
    /// The tip of the foot.
    ToeTip,
    /// A joint of no part we recognise: a small sphere.
    Other,
}

/// Default radius of each part, as a fraction of stature (sources in the
/// module's documentation).
pub(super) fn radius_fraction(part: Part, trunk_t: f64) -> f64 {
    match part {
        // Hip breadth 0.204 H, buttock depth 0.145 H.
        Part::Pelvis => 0.087,
        Part::Trunk => trunk_fraction(trunk_t),
        // Neck circumference at its base 0.24 H (above it 0.22 H).
        Part::Neck => 0.038,
        Part::HeadJoint => 0.034,
        // Head breadth 0.091 H, head length 0.117 H: the mean of the halves.
        Part::Skull => 0.052,
        Part::Clavicle => 0.035,
        // Shoulder joints sit 0.10 H off the midline, bideltoid breadth is
        // 0.28 H: the deltoid reaches 0.04 H beyond the joint.
        Part::Shoulder => 0.040,
        // Forearm circumference 0.165 H near the elbow.
        Part::Elbow => 0.026,
        // Wrist circumference 0.098 H.
        Part::Wrist => 0.016,
        // Hand breadth 0.049 H, thickness about 0.017 H.
        Part::Palm => 0.021,
        Part::Finger => 0.010,
        Part::Fingertip => 0.010,
        // Thigh circumference 0.35 H, just below the hip joint.
        Part::Hip => 0.055,
        // Knee circumference 0.22 H (the calf, 0.225 H, is just below).
        Part::Knee => 0.035,
        // Ankle circumference 0.13 H; the heel and malleoli add to it.
        Part::Ankle => 0.024,
        // Foot breadth 0.06 H at the ball, its height there about 0.03 H.
        Part::Toes => 0.021,
        Part::ToeTip => 0.012,
        Part::Other => 0.015,
    }
}

/// The trunk's radius (fraction of stature) at `t` of the way from the hips
/// joint (0) to the neck (1): pelvis, waist (breadth 0.18 H, depth
/// 0.135 H), chest (breadth 0.19 H, depth 0.145 H), linear between.
fn trunk_fraction(t: f64) -> f64 {
    const PROFILE: [(f64, f64); 3] = [(0.0, 0.087), (0.4, 0.079), (0.75, 0.084)];
    let t = t.clamp(0.0, 1.0);
    let mut previous = PROFILE[0];
    for point in PROFILE {
        if t <= point.0 {
            let span = point.0 - previous.0;
            return if span > 0.0 {
                previous.1 + (point.1 - previous.1) * (t - previous.0) / span
            } else {
                point.1
            };
        }
        previous = point;
    }
    previous.1
}

/// Thigh plus shank, as a fraction of stature (Drillis & Contini).
pub(super) const LEG_FRACTION: f64 = 0.245 + 0.246;
/// Joints closer than this to their parent (fraction of stature) get no
/// sphere of their own: Bandai's end sites sit exactly on their joints.
pub(super) const COINCIDENT_FRACTION: f64 = 0.01;
/// Where the top of the head lies beyond the head's joint when the skeleton
/// has no head end site to say so (fraction of stature): from the top of the
/// neck (Bandai's `Head`, at the skull's base, a little above the chin) to
/// the vertex; the head is 0.13 H from chin to vertex.
pub(super) const HEAD_JOINT_TO_VERTEX: f64 = 0.125;
/// A child this far from a limb's last joint (fraction of stature) already
/// gives the hand, foot or head its extent; a shorter one (or none) does not.
pub(super) const EXTENT_CHILD_FRACTION: f64 = 0.03;
/// Beyond the wrist along the forearm: the palm's centre and the fingertips'
/// (the hand is 0.108 H long), as fractions of stature.
pub(super) const WRIST_TO_PALM: f64 = 0.04;
pub(super) const WRIST_TO_FINGERTIP: f64 = 0.085;
/// Beyond the ball of the foot along the foot: the toes' tip.
pub(super) const TOES_TO_TIP: f64 = 0.035;

/// The lower-cased letters and digits of a joint's name after any namespace
/// (`mixamorig:LeftArm` → `leftarm`).
pub(super) fn name_key(name: &str) -> String {
    let base = name.rsplit([':', '|']).next().unwrap_or(name);
    base.chars().filter(char::is_ascii_alphanumeric).map(|c| c.to_ascii_lowercase()).collect()
}

/// The part a joint's name says, or `None`. Words are tried in an order that
/// keeps them apart: `forearm` before `arm`, `upleg` before `leg`, finger
/// names before `hand` (`LeftHandIndex1`).
pub(super) fn part_of_name(name: &str) -> Option<Part> {
    const WORDS: [(&[&str], Part); 12] = [
        (&["thumb", "index", "middle", "ring", "pinky", "little", "finger"], Part::Finger),
        (&["toe"], Part::Toes),
        (&["foot", "ankle"], Part::Ankle),
        (&["forearm", "lowerarm", "elbow"], Part::Elbow),
        (&["hand", "wrist", "palm"], Part::Wrist),
        (&["arm", "humerus"], Part::Shoulder),
        (&["clavicle", "collar", "shoulder", "scapula"], Part::Clavicle),
        (&["thigh", "upleg", "upperleg", "hip"], Part::Hip),
        (&["shin", "calf", "lowerleg", "knee", "leg"], Part::Knee),
        (&["head"], Part::HeadJoint),
        (&["neck"], Part::Neck),
        (&["spine", "chest", "abdomen", "torso", "back", "waist", "thorax", "belly"], Part::Trunk),
    ];
    let key = name_key(name);
    WORDS.iter().find(|(words, _)| words.iter().any(|w| key.contains(w))).map(|(_, part)| *part)
}

/// The body's stature (cm) estimated from its bones: thigh plus shank over
/// their share of stature, averaged over both legs; without recognisable
/// legs, the largest distance between two joints of the pose (a standing
/// body's height, a T-pose's span: both near the stature). `pose_cm` is any
/// frame (bone lengths do not change).
pub fn estimate_stature_cm(joint_names: &[String], parents: &[Option<usize>], pose_cm: &[DVec3]) -> f64 {
    let bone = |j: usize| -> Option<f64> {
        let p = parents.get(j).copied().flatten()?;
        Some(pose_cm.get(j)?.distance(*pose_cm.get(p)?))
    };
    let leg = |ankle: usize| -> Option<f64> {
        let knee = parents.get(ankle).copied().flatten()?;
        let length = bone(ankle)? + bone(knee)?;
        (length > 0.0).then_some(length)
    };
    if let Some(feet) = detect_feet(joint_names)
        && let (Some(left), Some(right)) = (leg(feet.left), leg(feet.right))
    {
        return 0.5 * (left + right) / LEG_FRACTION;
    }
    let mut widest: f64 = 0.0;
    for (i, a) in pose_cm.iter().enumerate() {
        for b in &pose_cm[i + 1..] {
            widest = widest.max(a.distance(*b));
        }
    }
    widest
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn parts_are_told_by_role_across_rigs() {
        let cases = [
            ("UpperArm_L", Part::Shoulder),
            ("LeftArm", Part::Shoulder),
            ("mixamorig:LeftForeArm", Part::Elbow),
            ("LowerArm_R", Part::Elbow),
            ("Shoulder_L", Part::Clavicle),
            ("LeftShoulder", Part::Clavicle),
            ("UpperLeg_L", Part::Hip),
            ("LeftThigh", Part::Hip),
            ("RightUpLeg", Part::Hip),
            ("LowerLeg_L", Part::Knee),
            ("LeftLeg", Part::Knee),
            ("Foot_L", Part::Ankle),
            ("Toes_R", Part::Toes),
            ("LeftHandIndex1", Part::Finger),
            ("Hand_L", Part::Wrist),
            ("SpineMid", Part::Trunk),
            ("Chest", Part::Trunk),
            ("Head", Part::HeadJoint),
        ];
        for (name, part) in cases {
            assert_eq!(part_of_name(name), Some(part), "{name}");
        }
        assert_eq!(part_of_name("EndSite6"), None);
    }

    #[test]
    fn trunk_profile_is_continuous() {
        assert_eq!(trunk_fraction(0.0), 0.087);
        assert!((trunk_fraction(0.4) - 0.079).abs() < 1e-12);
        assert_eq!(trunk_fraction(1.0), 0.084);
        assert!(trunk_fraction(0.2) < 0.087 && trunk_fraction(0.2) > 0.079);
    }
}
