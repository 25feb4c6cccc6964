//! The demo recording's truth is ground truth for translation methods, so
//! these check that it is physically consistent: planted feet hold still
//! under forward kinematics, nothing sinks into the floor, the path is real
//! and closes, and the simulated accelerometers read 1 g where the feet rest.
//! The recording itself is a suit's: its errors are what the model says,
//! the same for the same seed, and the recording parses, round-trips and
//! plays.

// A test may panic on what it does not expect: that is how it fails.
#![allow(clippy::unwrap_used, clippy::expect_used)]

use embusen::app::session::{Session, Settings};
use embusen::body::feet::{Foot, FootJoints, detect_feet};
use embusen::body::kinematics::forward_kinematics;
use embusen::body::skeleton::{Channel, Poses};
use embusen::eval::leg_length_cm;
use embusen::io::recording::Recording;
use embusen::io::recording::Source;
use embusen::synth::demo::{ANKLE_HEIGHT_CM, DEMO_FPS, DEMO_NAME, Demo, demo, demo_with_suit_seed};
use embusen::synth::suit::{MAX_SIGMAS, VENDOR_WALK_CM_PER_SQRT_S};
use glam::DVec3;

/// As documented on [`Demo`].
const FRAMES: usize = 2406;
const DOCUMENTED_DURATION_S: f64 = 24.06;

/// The true motion's poses.
fn poses(d: &Demo) -> Poses {
    forward_kinematics(&d.true_skeleton, &d.true_motion)
}

/// The BVH text of the recording the tool opens.
fn recording_text(d: &Demo) -> String {
    match d.recording().source {
        Source::Bvh(bvh) => bvh.write(),
        Source::Table(_) => panic!("the demo is a BVH"),
    }
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
    assert_eq!(d.true_motion.frame_count(), FRAMES);
    assert_eq!(d.true_skeleton.names, d.skeleton.names, "one hierarchy");
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

#[test]
fn the_same_seed_gives_the_same_bytes() {
    assert_eq!(recording_text(&demo_with_suit_seed(5)), recording_text(&demo_with_suit_seed(5)));
    assert_ne!(recording_text(&demo_with_suit_seed(5)), recording_text(&demo_with_suit_seed(6)));
    // The truth does not depend on the suit's seed.
    assert_eq!(demo_with_suit_seed(5).true_motion, demo_with_suit_seed(6).true_motion);
}

#[test]
fn the_suit_gets_the_pose_a_little_wrong() {
    let d = demo();
    let (feet, toes) = feet_and_toes(&d);
    let truth = poses(&d);
    let suit = forward_kinematics(&d.skeleton, &d.without_translation());
    // The legs' length as the eval measures it is the model's ratio, a few percent off.
    let hips = 0;
    let measured = leg_length_cm(&suit, &d.skeleton.parents, feet, hips)
        / leg_length_cm(&truth, &d.true_skeleton.parents, feet, hips);
    assert!((measured - d.leg_length_ratio).abs() < 1e-9, "{measured} vs {}", d.leg_length_ratio);
    assert!((0.01..0.08).contains(&(d.leg_length_ratio - 1.0).abs()), "{}", d.leg_length_ratio);
    // Relative to the hips, each toe is off by centimetres, not millimetres
    // nor decimetres.
    for side in Foot::BOTH {
        let off = |f: usize| {
            let relative = |p: &Poses| p.at(f, toes[side]) - p.at(f, hips);
            relative(&suit).distance(relative(&truth))
        };
        let mean_cm = (0..FRAMES).map(off).sum::<f64>() / FRAMES as f64;
        assert!((1.0..15.0).contains(&mean_cm), "toe {side:?} off by {mean_cm} cm on average");
    }
}

#[test]
fn the_vendor_translation_is_the_scaled_truth_and_a_random_walk() {
    let d = demo();
    let hips = forward_kinematics(&d.skeleton, &d.motion).trajectory(0);
    let floor = |v: DVec3| v.with_y(0.0);
    let (start, true_start) = (floor(hips[0]), floor(d.true_root_cm[0]));
    assert_eq!(start, true_start, "the vendor starts where the truth does");
    for (v, t) in hips.iter().zip(&d.true_root_cm) {
        assert!((v.y - t.y * d.leg_length_ratio).abs() < 1e-9, "the height is only scaled: {v} vs {t}");
    }
    let walk_cm: Vec<DVec3> = hips
        .iter()
        .zip(&d.true_root_cm)
        .map(|(v, t)| floor(*v) - (start + (floor(*t) - true_start) * d.leg_length_ratio))
        .collect();
    // A random walk's deviation after T is the step's times √T per axis.
    let duration_s = FRAMES as f64 / DEMO_FPS;
    let bound_cm = MAX_SIGMAS * VENDOR_WALK_CM_PER_SQRT_S * duration_s.sqrt() * 2.0;
    let last = walk_cm[FRAMES - 1];
    assert!(last.length() > 1.0 && last.length() < bound_cm, "the walk ends {last} away");
}

#[test]
fn the_recording_parses_round_trips_and_plays() {
    let d = demo();
    let text = recording_text(&d);
    let parsed = Recording::parse(text.as_bytes(), DEMO_NAME, None).expect("the demo's BVH parses");
    let opened = d.recording();
    assert_eq!(parsed.joint_names, opened.joint_names);
    assert_eq!(parsed.frame_count(), FRAMES);
    assert_eq!(parsed.poses, opened.poses, "written and read back exactly");
    let Source::Bvh(bvh) = &parsed.source else { panic!("a BVH") };
    assert_eq!(bvh.write(), text, "writing it again gives the same bytes");
    let mut session = Session::open(opened, Settings::default()).expect("the app opens the demo");
    assert_eq!(session.recording.frame_count(), FRAMES);
    assert!(session.translated.poses.positions_cm.iter().all(|p| p.is_finite()));
    assert!(
        session
            .set_settings(Settings { method: embusen::translate::MethodKind::Hachaj, ..Default::default() })
            .is_ok()
    );
}
