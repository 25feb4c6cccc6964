//! The demo recording is ground truth for translation methods, so these check
//! that it is physically consistent: planted feet hold still under forward
//! kinematics, nothing sinks into the floor, the path is real and closes, and
//! the simulated accelerometers read 1 g where the feet rest.

// A test may panic on what it does not expect: that is how it fails.
#![allow(clippy::unwrap_used, clippy::expect_used)]

use embusen::body::feet::{Foot, FootJoints, detect_feet};
use embusen::body::kinematics::forward_kinematics;
use embusen::body::skeleton::{Channel, Poses};
use embusen::synth::demo::{ANKLE_HEIGHT_CM, DEMO_FPS, Demo, demo};
use glam::DVec3;

/// As documented on [`Demo`].
const FRAMES: usize = 2406;
const DOCUMENTED_DURATION_S: f64 = 24.06;

fn poses(d: &Demo) -> Poses {
    forward_kinematics(&d.skeleton, &d.motion)
}

/// The foot joints, and the toe end site under each.
fn feet_and_toes(d: &Demo) -> (FootJoints, FootJoints) {
    let feet = detect_feet(&d.skeleton.names).expect("the demo names its feet LeftFoot and RightFoot");
    let toes = feet.map(|foot| {
        (0..d.skeleton.joint_count())
            .find(|&j| d.skeleton.parents[j] == Some(foot) && d.skeleton.is_end_site[j])
            .expect("each foot has a toe end site")
    });
    (feet, toes)
}

#[test]
fn sizes_and_rate_are_as_documented() {
    let d = demo();
    assert_eq!(d.motion.frame_count(), FRAMES);
    // The recording the tool opens takes its rate from the motion's frame time.
    let recording = d.recording();
    assert_eq!(recording.fps, DEMO_FPS);
    assert_eq!(recording.frame_count(), FRAMES);
    assert!((recording.duration_s() - DOCUMENTED_DURATION_S).abs() < 1e-9, "{} s", recording.duration_s());
    assert_eq!(d.true_root_cm.len(), FRAMES);
    assert_eq!(d.stance.len(), FRAMES);
    assert_eq!(d.foot_accel_g.left.len(), FRAMES);
    assert_eq!(d.foot_accel_g.right.len(), FRAMES);
    assert_eq!(d.motion.channel_count, d.skeleton.channel_count());
}

#[test]
fn skeleton_is_the_karate_suit_hierarchy() {
    let d = demo();
    let s = &d.skeleton;
    assert_eq!(s.names[0], "Hips");
    assert_eq!(s.channels[0].len(), 6);
    assert!(s.channels[0][..3].iter().all(|c| c.is_position()));
    for name in [
        "LeftThigh",
        "LeftLeg",
        "LeftFoot",
        "RightThigh",
        "RightLeg",
        "RightFoot",
        "SpineLow",
        "SpineMid",
        "Chest",
        "Neck",
        "Head",
        "LeftShoulder",
        "LeftArm",
        "LeftForearm",
        "LeftHand",
        "RightShoulder",
        "RightArm",
        "RightForearm",
        "RightHand",
    ] {
        let j = s.joint(name).unwrap_or_else(|| panic!("no joint {name}"));
        assert_eq!(s.channels[j], [Channel::Zrotation, Channel::Yrotation, Channel::Xrotation], "{name}");
    }
    for j in 0..s.joint_count() {
        if s.is_end_site[j] {
            assert_eq!(s.names[j], format!("EndSite{j}"));
            assert!(s.channels[j].is_empty());
        }
    }
    // Toes, head and both hands.
    assert_eq!(s.is_end_site.iter().filter(|&&e| e).count(), 5);
}

#[test]
fn planted_feet_do_not_slide_and_rest_on_the_floor() {
    let d = demo();
    let p = poses(&d);
    let (feet, _) = feet_and_toes(&d);
    for (side, &foot) in feet.iter() {
        let mut anchor: Option<DVec3> = None;
        let mut swing_frames = 0;
        for f in 0..FRAMES {
            let ankle = p.at(f, foot);
            if !d.stance[f][side] {
                anchor = None;
                swing_frames += 1;
                continue;
            }
            let planted = *anchor.get_or_insert(ankle);
            let slide_cm = ankle.distance(planted);
            assert!(slide_cm < 0.01, "foot {side:?} slid {slide_cm} cm by frame {f}");
            assert!(
                (ankle.y - ANKLE_HEIGHT_CM).abs() < 0.01,
                "foot {side:?} planted at y {} in frame {f}",
                ankle.y
            );
        }
        // Every step counts: the recording really walks on both feet.
        assert!(swing_frames > 300, "foot {side:?} swings in only {swing_frames} frames");
    }
}

#[test]
fn toes_and_soles_stay_above_the_floor() {
    let d = demo();
    let p = poses(&d);
    let (feet, toes) = feet_and_toes(&d);
    for f in 0..FRAMES {
        for side in Foot::BOTH {
            let sole_cm = p.at(f, feet[side]).y - ANKLE_HEIGHT_CM;
            let toe_cm = p.at(f, toes[side]).y;
            assert!(sole_cm > -1.0, "sole {side:?} at {sole_cm} cm in frame {f}");
            assert!(toe_cm > -1.0, "toe {side:?} at {toe_cm} cm in frame {f}");
        }
    }
}

#[test]
fn hips_travel_a_closed_path() {
    let d = demo();
    let p = poses(&d);
    for (f, root) in d.true_root_cm.iter().enumerate() {
        assert!(p.at(f, 0).distance(*root) < 1e-9, "true root differs from the Hips in frame {f}");
    }
    let floor = |v: DVec3| v.with_y(0.0);
    let gap_cm = floor(d.true_root_cm[0]).distance(floor(d.true_root_cm[FRAMES - 1]));
    assert!(gap_cm < 5.0, "path ends {gap_cm} cm from its start");
    let path_cm: f64 = d.true_root_cm.windows(2).map(|w| floor(w[0]).distance(floor(w[1]))).sum();
    assert!(path_cm > 300.0, "path only {path_cm} cm long");
    // Lower in stances than when standing, but always a standing figure.
    let heights: Vec<f64> = d.true_root_cm.iter().map(|r| r.y).collect();
    let (low, high) = heights.iter().fold((f64::MAX, f64::MIN), |(lo, hi), &h| (lo.min(h), hi.max(h)));
    assert!(high - low > 5.0 && low > 60.0 && high < 95.0, "hips between {low} and {high} cm");
}

#[test]
fn demo_is_deterministic() {
    assert_eq!(demo(), demo());
}

#[test]
fn accelerometers_read_one_g_at_rest_and_more_in_swing() {
    let d = demo();
    for (side, accel) in d.foot_accel_g.iter() {
        let mut at_rest = 0;
        let mut largest_deviation_g: f64 = 0.0;
        for (f, reading) in accel.iter().enumerate().take(FRAMES - 1).skip(1) {
            let deviation_g = reading.distance(DVec3::Y);
            largest_deviation_g = largest_deviation_g.max(deviation_g);
            // A central difference sees the neighbours too.
            if (f - 1..=f + 1).all(|g| d.stance[g][side]) {
                at_rest += 1;
                assert!(deviation_g < 0.02, "foot {side:?} at rest reads {reading} in frame {f}");
            }
        }
        assert!(at_rest > FRAMES / 2, "foot {side:?} rests in only {at_rest} frames");
        assert!(largest_deviation_g > 0.2, "foot {side:?} never accelerates: {largest_deviation_g} g");
    }
}

#[test]
fn without_translation_freezes_only_the_root_position() {
    let d = demo();
    let frozen = d.without_translation();
    assert_eq!(frozen.frame_count(), FRAMES);
    let start = &d.motion.frame(0)[..3];
    for f in 0..FRAMES {
        assert_eq!(&frozen.frame(f)[..3], start, "frame {f}");
        assert_eq!(frozen.frame(f)[3..], d.motion.frame(f)[3..], "frame {f}");
    }
}
