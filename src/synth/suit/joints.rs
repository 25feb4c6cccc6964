//! What the suit makes of each joint of a skeleton: which have a sensor,
//! which carry the vendor's translation, the template's bone scales, and
//! the channels that hold still.

use glam::DMat3;

use crate::body::feet::{FootJoints, above_hips, hips_joint};
use crate::body::kinematics::rotation_channel_degrees;
use crate::body::skeleton::{Channel, Motion, Skeleton};
use crate::signal::stats::median;
use crate::synth::rng::XorShift64;

use super::errors::{BODY_SCALE_DEVIATION, ErrorSizes, clamped};

/// The joints the model must know by their part in the body.
#[derive(Clone, Debug, PartialEq)]
pub struct SuitBody {
    /// Where the legs meet ([`hips_joint`]): the point whose path the
    /// vendor's translation guesses. Joints above it are no body segment.
    pub hips: usize,
    /// The joints whose bones make one leg (the knee's and the ankle's
    /// OFFSET or position channels: thigh and shank), for the leg-length
    /// ratio the vendor's translation is scaled by.
    pub leg_bones: Vec<usize>,
}

impl SuitBody {
    /// The hips and the left leg's bones of a skeleton whose ankle-level
    /// joints are `feet`: the foot's own bone (the shank) and its parent's
    /// (the thigh), the bones `eval::leg_length_cm` measures a leg by.
    pub fn from_feet(skeleton: &Skeleton, feet: FootJoints) -> SuitBody {
        let hips = hips_joint(&skeleton.parents, feet);
        let knee = skeleton.parents.get(feet.left).copied().flatten().filter(|&knee| knee != hips);
        SuitBody { hips, leg_bones: knee.into_iter().chain([feet.left]).collect() }
    }
}

/// What the suit makes of a joint.
#[derive(Clone, Copy, Debug, PartialEq)]
pub(super) enum Part {
    /// A segment with a sensor: its rotation is the suit's estimate.
    Sensed,
    /// A segment without a sensor (a toe, [`has_no_sensor`]): each of its
    /// rotation channels holds the median of its true values over the take,
    /// the toe's usual bend. (The shared suit files do this; the rest pose
    /// would straighten a toe that is never straight, Bandai's bend 17–25°.)
    Unsensed,
    /// Above the hips: no part of the body but what an exporter puts over
    /// it (Bandai's `joint_Root` on the floor): no sensor and no bone; its
    /// channels hold their first frame's values.
    AboveHips,
}

/// Whether a joint is a segment no suit puts a sensor on: a toe (a name
/// with `toe` in it, in any case: `Toes_L`, `LeftToeBase`). The karate
/// suit's 17 sensors have none on the toes; the demo's skeleton, the karate
/// suit's, has no toe joint (each foot is one segment, ankle to toe end
/// site, with its own sensor).
fn has_no_sensor(name: &str) -> bool {
    name.to_ascii_lowercase().contains("toe")
}

pub(super) fn parts(skeleton: &Skeleton, hips: usize) -> Vec<Part> {
    let above = above_hips(&skeleton.parents, hips);
    (0..skeleton.joint_count())
        .map(|j| {
            if above.contains(&j) {
                Part::AboveHips
            } else if !skeleton.is_end_site[j] && has_no_sensor(&skeleton.names[j]) {
                Part::Unsensed
            } else {
                Part::Sensed
            }
        })
        .collect()
}

/// The joint whose position channels carry the vendor's translation: the
/// hips if they have any (the demo's and the karate suit's root; Bandai's
/// `Hips` below its `joint_Root`), else the nearest joint above them that
/// has; `None` when no joint from the root down to the hips has a position
/// channel (a recording without translation).
///
/// Why the hips even when the joint above them moves too (Bandai's
/// `dash_normal_001` runs forward in `joint_Root` and bobs in place in
/// `Hips`): a suit's vendor guesses where the pelvis is, one path, not an
/// exporter's split of it. So the joints above the hips hold their first
/// frame, and the hips' channels take the whole guessed path, as in the
/// shared suit files.
pub fn translation_joint(skeleton: &Skeleton, hips: usize) -> Option<usize> {
    std::iter::once(hips)
        .chain(above_hips(&skeleton.parents, hips))
        .find(|&j| skeleton.channels[j].iter().any(|c| c.is_position()))
}

/// A joint's name without its side, so that the two sides name one bone of
/// the template: `LeftLeg` and `RightLeg` are `Leg`, `UpperLeg_L` and
/// `UpperLeg_R` are `UpperLeg`, `thigh.l` and `thigh.r` are `thigh`; an
/// exporter's namespace (`mixamorig:`) is dropped first.
fn sideless(name: &str) -> &str {
    const PREFIXES: [&str; 4] = ["Left", "Right", "left", "right"];
    const SUFFIXES: [&str; 8] = ["_L", "_R", ".L", ".R", "_l", "_r", ".l", ".r"];
    let base = name.rsplit(':').next().unwrap_or(name);
    PREFIXES
        .iter()
        .find_map(|p| base.strip_prefix(p))
        .or_else(|| SUFFIXES.iter().find_map(|s| base.strip_suffix(s)))
        .filter(|rest| !rest.is_empty())
        .unwrap_or(base)
}

/// The bone a joint's offset is, without its side (see [`sideless`]); an
/// end site is its parent's end.
fn bone_key(skeleton: &Skeleton, joint: usize) -> String {
    match (skeleton.is_end_site[joint], skeleton.parents[joint]) {
        (true, Some(parent)) => format!("{} end", bone_key(skeleton, parent)),
        _ => sideless(&skeleton.names[joint]).to_string(),
    }
}

/// The template's scale of every joint's bone: one scale per bone (left and
/// right alike) times one for the whole body, deviations `level` times
/// `sizes`'. Drawn for every joint, bone or not, in the joints' order, so
/// that a seed draws the same numbers whatever the skeleton's bones are.
pub(super) fn bone_scales(
    skeleton: &Skeleton,
    rng: &mut XorShift64,
    sizes: &ErrorSizes,
    level: f64,
) -> Vec<f64> {
    let body = 1.0 + BODY_SCALE_DEVIATION * level * clamped(rng);
    let mut scales: Vec<(String, f64)> = Vec::new();
    (0..skeleton.joint_count())
        .map(|joint| {
            let key = bone_key(skeleton, joint);
            match scales.iter().find(|(k, _)| *k == key) {
                Some(&(_, s)) => s,
                None => {
                    let s = body * (1.0 + sizes.bone_scale_deviation * level * clamped(rng));
                    scales.push((key, s));
                    s
                }
            }
        })
        .collect()
}

/// The skeleton with every bone's OFFSET scaled by its joint's `scales`;
/// the hips and the joints above them are no bones and keep theirs.
pub(super) fn scaled_skeleton(skeleton: &Skeleton, scales: &[f64], is_bone: &[bool]) -> Skeleton {
    let mut scaled = skeleton.clone();
    for (j, offset_cm) in scaled.offsets_cm.iter_mut().enumerate() {
        if is_bone[j] {
            *offset_cm *= scales[j];
        }
    }
    scaled
}

/// The indices, within a joint's channels, of its rotation channels when it
/// has exactly three (whether the model can write them is
/// [`rotation_channel_degrees`]'s to say).
pub(super) fn rotation_channel_indices(channels: &[Channel]) -> Option<[usize; 3]> {
    let rotations: Vec<usize> = (0..channels.len()).filter(|&i| !channels[i].is_position()).collect();
    rotations.try_into().ok()
}

/// The joints whose rotation is a sensor's (not the end sites, which have
/// none): every one below the hips `hips` but the toes.
pub fn sensed_joints(skeleton: &Skeleton, hips: usize) -> Vec<usize> {
    let parts = parts(skeleton, hips);
    (0..skeleton.joint_count()).filter(|&j| parts[j] == Part::Sensed && !skeleton.is_end_site[j]).collect()
}

/// The joints with a sensor whose rotation channels the model cannot write
/// (one or two of them, or one axis twice): they keep their true rotations
/// (see [`apply`](super::apply)), so a caller can say so.
pub fn joints_kept_true(skeleton: &Skeleton, body: &SuitBody) -> Vec<usize> {
    let parts = parts(skeleton, body.hips);
    (0..skeleton.joint_count())
        .filter(|&j| parts[j] == Part::Sensed && skeleton.channels[j].iter().any(|c| !c.is_position()))
        .filter(|&j| {
            let channels = &skeleton.channels[j];
            let order = rotation_channel_indices(channels).map(|indices| indices.map(|i| channels[i]));
            order.and_then(|order| rotation_channel_degrees(order, DMat3::IDENTITY)).is_none()
        })
        .collect()
}

/// The values that stay the same in every frame, as (index in a frame,
/// value): an unsensed joint's rotation channels at their medians over the
/// take, and every channel of the joints above the hips at its first frame,
/// but for the translation carrier's positions (the vendor's to write).
pub(super) fn held_channels(
    skeleton: &Skeleton,
    motion: &Motion,
    parts: &[Part],
    carrier: Option<usize>,
) -> Vec<(usize, f64)> {
    let mut held = Vec::new();
    for (j, part) in parts.iter().enumerate() {
        let first = skeleton.first_channel[j];
        for (i, channel) in skeleton.channels[j].iter().enumerate() {
            let index = first + i;
            let over_take =
                || (0..motion.frame_count()).map(|f| motion.frame(f)[index]).collect::<Vec<f64>>();
            match part {
                Part::Unsensed if !channel.is_position() => held.push((index, median(&over_take()))),
                Part::AboveHips if !(channel.is_position() && Some(j) == carrier) => {
                    held.push((index, motion.frame(0)[index]))
                }
                _ => {}
            }
        }
    }
    held
}

/// Scales every bone's position channels (in every frame) by its joint's
/// `scales`, as its OFFSET is: a skeleton whose bones are position channels
/// (Bandai's) gets the template's bone lengths too.
pub(super) fn scale_position_bones(
    skeleton: &Skeleton,
    motion: &mut Motion,
    scales: &[f64],
    is_bone: &[bool],
) {
    let indices: Vec<(usize, f64)> = (0..skeleton.joint_count())
        .filter(|&j| is_bone[j])
        .flat_map(|j| {
            let first = skeleton.first_channel[j];
            let channels = &skeleton.channels[j];
            (0..channels.len()).filter(|&i| channels[i].is_position()).map(move |i| (first + i, scales[j]))
        })
        .collect();
    if indices.is_empty() {
        return;
    }
    for f in 0..motion.frame_count() {
        let values = motion.frame_mut(f);
        for &(index, scale) in &indices {
            values[index] *= scale;
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::synth::suit::REAL_SUIT_LEVEL;
    use glam::DVec3;

    #[test]
    fn left_and_right_are_one_bone() {
        let mut s = Skeleton::default();
        let root = s.push_joint("Hips".into(), None, DVec3::ZERO, vec![], false);
        let left = s.push_joint("LeftLeg".into(), Some(root), DVec3::new(0.0, -40.0, 0.0), vec![], false);
        let right = s.push_joint("RightLeg".into(), Some(root), DVec3::new(0.0, -40.0, 0.0), vec![], false);
        let end_l = s.push_joint("EndSite3".into(), Some(left), DVec3::new(0.0, -10.0, 0.0), vec![], true);
        let end_r = s.push_joint("EndSite4".into(), Some(right), DVec3::new(0.0, -10.0, 0.0), vec![], true);
        let scales = bone_scales(&s, &mut XorShift64(3), &ErrorSizes::MEASURED, REAL_SUIT_LEVEL);
        let scaled = scaled_skeleton(&s, &scales, &[false, true, true, true, true]);
        assert_eq!(scaled.offsets_cm[left], scaled.offsets_cm[right]);
        assert_eq!(scaled.offsets_cm[end_l], scaled.offsets_cm[end_r]);
        assert_ne!(scaled.offsets_cm[left], s.offsets_cm[left]);
    }

    #[test]
    fn side_marks_name_one_bone() {
        for (left, right, bone) in [
            ("LeftUpLeg", "RightUpLeg", "UpLeg"),
            ("UpperLeg_L", "UpperLeg_R", "UpperLeg"),
            ("thigh.l", "thigh.r", "thigh"),
            ("mixamorig:LeftFoot", "mixamorig:RightFoot", "Foot"),
        ] {
            assert_eq!((sideless(left), sideless(right)), (bone, bone));
        }
        for unsided in ["Hips", "Spine", "Left", "_L", "Chest"] {
            assert_eq!(sideless(unsided), unsided);
        }
    }
}
