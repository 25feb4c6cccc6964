//! The translation methods never panic, whatever skeleton and motion they are
//! given: feet without toes, toes with several children, zero-length bones,
//! joints on top of each other, one frame or none, at rates whose grid
//! step is longer than the recording.

// A test may panic on what it does not expect: that is how it fails.
#![allow(clippy::unwrap_used, clippy::expect_used)]

use embusen::body::feet::{FootJoints, PerFoot, hips_joint};
use embusen::body::skeleton::Poses;
use embusen::translate::contact::{ContactParams, contact_translation};
use embusen::translate::hachaj::{HachajParams, hachaj_translation};
use glam::DVec3;
use proptest::prelude::*;

/// A random skeleton (each joint's parent comes before it) and motion.
fn skeleton_and_motion() -> impl Strategy<Value = (Vec<Option<usize>>, Poses)> {
    (2usize..9, 0usize..30).prop_flat_map(|(joints, frames)| {
        let parents = (1..joints).map(|j| 0..j).collect::<Vec<_>>();
        // Coordinates from a few values, so that points often coincide.
        let coordinate = prop_oneof![Just(0.0), Just(5.0), -100.0f64..100.0];
        let positions =
            proptest::collection::vec((coordinate.clone(), coordinate.clone(), coordinate), joints * frames);
        (parents, positions).prop_map(move |(parents, positions)| {
            let parents = std::iter::once(None).chain(parents.into_iter().map(Some)).collect();
            let positions_cm = positions.into_iter().map(|(x, y, z)| DVec3::new(x, y, z)).collect();
            (parents, Poses { joint_count: joints, positions_cm })
        })
    })
}

proptest! {
    #![proptest_config(ProptestConfig::with_cases(3000))]
    #[test]
    fn never_panics(
        (parents, poses) in skeleton_and_motion(),
        left in 0usize..9,
        right in 0usize..9,
        depth in prop_oneof![Just(None), (0.0f64..20.0).prop_map(Some)],
        with_accel in any::<bool>(),
        fps in prop_oneof![Just(30.0), Just(60.0), Just(100.0), Just(1.0e4), 1.0f64..1000.0],
    ) {
        let n = poses.joint_count;
        let feet = FootJoints { left: left % n, right: right % n };
        let hips = hips_joint(&parents, feet);
        let frames = poses.frame_count();
        let accel = vec![1.0; frames];
        let accel = with_accel.then_some(PerFoot::new(accel.as_slice(), accel.as_slice()));
        let params = ContactParams { sole_depth_cm: depth, ..ContactParams::default() };
        if let Ok(result) = contact_translation(&poses, &parents, feet, hips, accel, fps, &params) {
            prop_assert_eq!(result.shift_cm.len(), frames);
            prop_assert!(result.shift_cm.iter().all(|s| s.is_finite()), "{:?}", result.shift_cm);
        }
        let ones = vec![1.0; frames];
        if let Ok(result) = hachaj_translation(&poses, feet, PerFoot::new(&ones[..], &ones[..]), fps, &HachajParams::default()) {
            prop_assert_eq!(result.shift_cm.len(), frames);
        }
    }
}
