//! BVH reader/writer and forward kinematics: real-file quirks, round trips,
//! error positions, and the FK parity with the vendor's global positions.

// A test may panic on what it does not expect: that is how it fails.
#![allow(clippy::unwrap_used, clippy::expect_used)]

mod common;

use embusen::body::kinematics::forward_kinematics;
use embusen::body::skeleton::Channel;
use embusen::io::bvh::{Bvh, ReadOptions};
use glam::DVec3;
use proptest::prelude::*;

fn parse(text: &str) -> Result<Bvh, embusen::Error> {
    Bvh::parse(text.as_bytes(), "t.bvh", &ReadOptions::default())
}

/// A two-joint file whose data rows are given.
fn two_joint(channels_root: &str, channels_leg: &str, frames_line: &str, rows: &str) -> String {
    format!(
        "HIERARCHY\nROOT Hips\n{{\n  OFFSET 1 2 3\n  CHANNELS {channels_root}\n  JOINT Leg\n  {{\n    OFFSET 0 -10 0\n    CHANNELS {channels_leg}\n    End Site\n    {{\n      OFFSET 0 -5 0\n    }}\n  }}\n}}\nMOTION\n{frames_line}\nFrame Time: 0.01\n{rows}"
    )
}

#[test]
fn crlf_tabs_blank_lines_scientific_and_negative_zero() {
    let text = two_joint(
        "6 Xposition Yposition Zposition Zrotation Xrotation Yrotation",
        "3 Zrotation Xrotation Yrotation",
        "Frames: 2",
        "\n1e1\t-0 2.5E-1 0 0 0 0 0 0\n\n-0.0 0 0 90 0 0 1 2 3\n\n",
    )
    .replace('\n', "\r\n");
    let bvh = parse(&text).unwrap();
    assert_eq!(bvh.motion.frame_count(), 2);
    assert_eq!(bvh.motion.frame(0)[0], 10.0);
    assert!(bvh.motion.frame(0)[1] == 0.0 && bvh.motion.frame(0)[1].is_sign_negative());
    assert_eq!(bvh.motion.frame(0)[2], 0.25);
    assert!(bvh.warnings.is_empty(), "{:?}", bvh.warnings);
}

#[test]
fn any_channel_count_and_order() {
    // Root with rotations only (0 position channels), leg with 6 channels.
    let text = two_joint(
        "3 Yrotation Xrotation Zrotation",
        "6 Zrotation Xposition Yposition Zposition Yrotation Xrotation",
        "Frames: 1",
        "0 0 0 0 1 -7 2 0 0\n",
    );
    let bvh = parse(&text).unwrap();
    assert_eq!(
        bvh.skeleton.channels[1],
        [
            Channel::Zrotation,
            Channel::Xposition,
            Channel::Yposition,
            Channel::Zposition,
            Channel::Yrotation,
            Channel::Xrotation
        ]
    );
    let poses = forward_kinematics(&bvh.skeleton, &bvh.motion);
    // Root keeps its OFFSET; the leg's position channels replace its OFFSET.
    assert_eq!(poses.at(0, 0), DVec3::new(1.0, 2.0, 3.0));
    assert_eq!(poses.at(0, 1), DVec3::new(2.0, -5.0, 5.0));
    // A joint with no channels at all is fine too.
    let text = two_joint("0", "3 Zrotation Xrotation Yrotation", "Frames: 1", "0 0 0\n");
    assert_eq!(parse(&text).unwrap().motion.channel_count, 3);
}

#[test]
fn leaf_joint_without_end_site() {
    let text = "HIERARCHY\nROOT Hips\n{\n OFFSET 0 0 0\n CHANNELS 3 Xposition Yposition Zposition\n JOINT Hand\n {\n  OFFSET 0 1 0\n  CHANNELS 3 Zrotation Xrotation Yrotation\n }\n}\nMOTION\nFrames: 1\nFrame Time: 0.01\n0 0 0 0 0 0\n";
    let bvh = parse(text).unwrap();
    assert_eq!(bvh.skeleton.names, ["Hips", "Hand"]);
}

#[test]
fn rotation_order_composes_in_file_order() {
    // Zrotation 90 then Xrotation 90 applied to the leg's OFFSET (0,-10,0):
    // R = Rz(90) * Rx(90); Rx(90) (0,-10,0) = (0,0,-10); Rz(90) (0,0,-10) = (0,0,-10).
    // With the other order, Rx(90) Rz(90) (0,-10,0) = Rx(90) (10,0,0) = (10,0,0).
    let zx = two_joint(
        "6 Xposition Yposition Zposition Zrotation Xrotation Yrotation",
        "3 Zrotation Xrotation Yrotation",
        "Frames: 1",
        "0 0 0 90 90 0 0 0 0\n",
    );
    let xz = two_joint(
        "6 Xposition Yposition Zposition Xrotation Zrotation Yrotation",
        "3 Zrotation Xrotation Yrotation",
        "Frames: 1",
        "0 0 0 90 90 0 0 0 0\n",
    );
    let leg = |text: &str| {
        let b = parse(text).unwrap();
        forward_kinematics(&b.skeleton, &b.motion).at(0, 1)
    };
    assert!((leg(&zx) - DVec3::new(0.0, 0.0, -10.0)).length() < 1e-12, "{}", leg(&zx));
    assert!((leg(&xz) - DVec3::new(10.0, 0.0, 0.0)).length() < 1e-12, "{}", leg(&xz));
}

#[test]
fn frame_time_zero_warns_and_uses_fps() {
    let text = two_joint("3 Xposition Yposition Zposition", "0", "Frames: 1", "0 0 0\n")
        .replace("Frame Time: 0.01", "Frame Time: 0.0");
    let bvh = parse(&text).unwrap();
    assert_eq!(bvh.motion.fps(), 100.0);
    assert!(bvh.warnings[0].contains("assuming 100 Hz"), "{:?}", bvh.warnings);
    let bvh = Bvh::parse(text.as_bytes(), "t.bvh", &ReadOptions { fps: Some(30.0) }).unwrap();
    assert!((bvh.motion.fps() - 30.0).abs() < 1e-9);
    assert!(bvh.warnings[0].contains("30 Hz"));
}

#[test]
fn frame_count_mismatch_is_a_warning() {
    let fewer = two_joint("3 Xposition Yposition Zposition", "0", "Frames: 3", "0 0 0\n1 1 1\n");
    let bvh = parse(&fewer).unwrap();
    assert_eq!(bvh.motion.frame_count(), 2);
    assert!(bvh.warnings[0].contains("says 3 but the file has 2"));
    let more = two_joint("3 Xposition Yposition Zposition", "0", "Frames:\t1", "0 0 0\n1 1 1\n");
    assert_eq!(parse(&more).unwrap().motion.frame_count(), 2);
}

#[test]
fn errors_say_where_and_what() {
    let good = two_joint(
        "3 Xposition Yposition Zposition",
        "3 Zrotation Xrotation Yrotation",
        "Frames: 1",
        "0 0 0 0 0 0\n",
    );
    let cases = [
        (good.replace("0 0 0 0 0 0\n", "0 0 0 0 0 0.5x\n"), (19, 11), "expected a number, found `0.5x`"),
        (good.replace("0 0 0 0 0 0\n", "0 0 0 0 0\n"), (19, 1), "expected 6 values in frame 1"),
        (good.replace("0 0 0 0 0 0\n", "0 0 0 0 0 0 0\n"), (19, 13), "found more"),
        (good.replace("  {\n    OFFSET 0 -10", "    OFFSET 0 -10"), (7, 5), "expected `{` after joint `Leg`"),
        (good.replace("OFFSET 1 2 3", "OFFSET 1 2 z"), (4, 14), "expected a number in the OFFSET of `Hips`"),
        (
            good.replace("CHANNELS 3 Xposition Yposition Zposition", "CHANNELS 3 Xposition Yposition"),
            (6, 3),
            "expected a channel name",
        ),
        (good.replace("Frame Time: 0.01", "Frame Time: soon"), (18, 13), "expected the frame time"),
        (good.replace("0 0 0 0 0 0\n", "0 0 0 0 0 nan\n"), (19, 11), "expected a number"),
        (good[..good.find("MOTION").unwrap()].to_string(), (16, 1), "expected `MOTION`"),
        ("HIERARCH".to_string(), (1, 1), "expected `HIERARCHY`"),
    ];
    for (text, (line, column), message) in cases {
        let e = parse(&text).unwrap_err();
        assert_eq!(e.line_column, Some((line, column)), "{e}");
        assert!(e.message.contains(message), "{e}");
        assert!(e.to_string().starts_with(&format!("t.bvh:{line}:{column}: ")), "{e}");
    }
    // Truncated in the middle of the hierarchy: names the end of the file,
    // and points just past the last character.
    let truncated = &good[..60];
    let e = parse(truncated).unwrap_err();
    assert!(e.message.ends_with("found the end of the file"), "{e}");
    let last_line = truncated.rsplit('\n').next().unwrap();
    let end = (truncated.lines().count(), last_line.chars().count() + 1);
    assert_eq!(e.line_column, Some(end), "{e}");
}

#[test]
fn round_trip_and_root_shift() {
    let text = two_joint(
        "3 Zrotation Xrotation Yrotation",
        "3 Zrotation Xrotation Yrotation",
        "Frames: 2",
        "1.5 -2.25e-3 3 4 5 6\n7 8 9 10 11 12.000000000000004\n",
    );
    let bvh = parse(&text).unwrap();
    let again = parse(&bvh.write()).unwrap();
    assert_eq!(again, bvh);
    // A root without position channels gets them, and the body moves by the shift.
    let mut shifted = bvh.clone();
    shifted.shift_root(&[DVec3::new(1.0, 0.0, 0.0), DVec3::new(0.0, 0.0, -2.0)]);
    assert_eq!(
        &shifted.skeleton.channels[0][..3],
        &[Channel::Xposition, Channel::Yposition, Channel::Zposition]
    );
    let before = forward_kinematics(&bvh.skeleton, &bvh.motion);
    let after = forward_kinematics(&shifted.skeleton, &shifted.motion);
    for j in 0..3 {
        assert!((after.at(0, j) - before.at(0, j) - DVec3::X).length() < 1e-12);
        assert!((after.at(1, j) - before.at(1, j) + 2.0 * DVec3::Z).length() < 1e-12);
    }
    let reread = parse(&shifted.write()).unwrap();
    assert_eq!(reread, shifted);
}

#[test]
fn every_real_bvh_reads_and_round_trips() {
    let Some(dir) = common::data_dir() else {
        return;
    };
    let mut files = common::files_with_extension(&dir.join("karate"), "bvh");
    files.extend(common::files_with_extension(&dir.join("groundtruth"), "bvh"));
    assert!(files.len() >= 11, "expected the shared BVH files, found {files:?}");
    for path in files {
        let text = std::fs::read(&path).unwrap();
        let name = path.display().to_string();
        let bvh = Bvh::parse(&text, &name, &ReadOptions::default()).unwrap_or_else(|e| panic!("{e}"));
        assert!(bvh.motion.frame_count() > 10, "{name}");
        let again = Bvh::parse(bvh.write().as_bytes(), &name, &ReadOptions::default()).unwrap();
        assert_eq!(again.skeleton, bvh.skeleton, "{name}");
        assert_eq!(again.motion.values, bvh.motion.values, "{name}");
        let says_zero = name.contains("mae_geri") || name.contains("empi");
        assert_eq!(
            bvh.warnings.iter().any(|w| w.contains("Frame Time is 0")),
            says_zero,
            "{name}: {:?}",
            bvh.warnings
        );
    }
}

#[test]
fn heian_nidan_quirks() {
    let Some(dir) = common::data_dir() else {
        return;
    };
    let text = std::fs::read(dir.join("karate/heian_nidan.bvh")).unwrap();
    let bvh = Bvh::parse(&text, "heian_nidan.bvh", &ReadOptions::default()).unwrap();
    assert_eq!(bvh.motion.frame_count(), 2689);
    assert_eq!(bvh.motion.fps(), 100.0);
    // Hand joints are leaves without an End Site.
    let hand = bvh.skeleton.joint("LeftHand").expect("LeftHand");
    assert!(!bvh.skeleton.parents.contains(&Some(hand)));
}

#[test]
fn forward_kinematics_matches_the_vendor_positions() {
    let Some(dir) = common::data_dir() else { return };
    let bvh_text = std::fs::read(dir.join("karate/heian_shodan.bvh")).unwrap();
    let bvh = Bvh::parse(&bvh_text, "heian_shodan.bvh", &ReadOptions::default()).unwrap();
    let table = common::open_table(&dir, "karate/heian_shodan.csv");
    // The BVH lacks the two hand end sites the table has; every other joint is compared.
    assert_eq!(bvh.skeleton.joint_count(), table.joint_names.len() - 2);
    let max_diff = common::max_fk_difference_cm(&bvh, &table);
    eprintln!("FK vs heian_shodan.csv: max |diff| = {max_diff:e} cm");
    assert!(max_diff <= 1e-9, "max diff {max_diff}");
}

proptest! {
    #![proptest_config(ProptestConfig::with_cases(2000))]
    #[test]
    fn reader_never_panics_on_arbitrary_bytes(bytes in proptest::collection::vec(any::<u8>(), 0..400)) {
        let _ = Bvh::parse(&bytes, "fuzz.bvh", &ReadOptions::default());
    }

    #[test]
    fn reader_never_panics_on_mutated_bvh(cut in 0usize..400, at in 0usize..400, byte in any::<u8>()) {
        let mut text = two_joint("6 Xposition Yposition Zposition Zrotation Xrotation Yrotation", "3 Zrotation Xrotation Yrotation", "Frames: 2", "1 2 3 4 5 6 7 8 9\n1 2 3 4 5 6 7 8 9\n").into_bytes();
        let at = at % text.len();
        text[at] = byte;
        text.truncate(cut.min(text.len()));
        let _ = Bvh::parse(&text, "fuzz.bvh", &ReadOptions::default());
    }
}
