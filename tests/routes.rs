//! The whole path a user takes — file in, [`Recording`], method, file out —
//! checked against the authors' reference on both input routes, and the
//! built-in demo checked against its own true translation.

// A test may panic on what it does not expect: that is how it fails.
#![allow(clippy::unwrap_used, clippy::expect_used)]

mod common;

use embusen::eval::metrics::{floor_closure_cm, floor_path_cm, mean_floor_error_cm};
use embusen::io::bvh::{Bvh, ReadOptions};
use embusen::io::recording::{AccelSource, FeetChoice};
use embusen::io::table::Table;
use embusen::synth::demo::demo;
use embusen::translate::hachaj::HachajParams;

#[test]
fn table_route_matches_the_reference_after_writing() {
    let Some(dir) = common::data_dir() else { return };
    let recording = common::open(&dir, "karate/heian_shodan.csv");
    let translated = recording.translate_hachaj(&FeetChoice::default(), &HachajParams::default()).unwrap();
    assert!(matches!(translated.accel_source, AccelSource::Accelerometer { .. }));
    let written = recording.write_shifted(&translated.shift_cm);
    let output = Table::parse(written.as_bytes(), "out.csv").unwrap();
    let reference = common::open_table(&dir, "karate/heian_shodan.paper-reference.csv");
    assert_eq!(output.headers, reference.headers);
    let mut max_diff: f64 = 0.0;
    for (f, column) in
        (0..reference.frame_count()).flat_map(|f| (0..reference.headers.len()).map(move |c| (f, c)))
    {
        let d = output.row(f)[column] - reference.row(f)[column];
        max_diff = max_diff.max(d.abs());
    }
    // Every column is compared: the positions are corrected, the rest untouched.
    eprintln!("table route (written CSV) vs reference: max |diff| = {max_diff:e} cm");
    assert!(max_diff <= 1e-6, "{max_diff}");
}

#[test]
fn bvh_and_side_file_route_matches_the_reference() {
    let Some(dir) = common::data_dir() else { return };
    let mut recording = common::open(&dir, "karate/heian_shodan.bvh");
    recording.attach_accel(common::open_accel(&dir, "karate/heian_shodan.accel.csv")).unwrap();
    let translated = recording.translate_hachaj(&FeetChoice::default(), &HachajParams::default()).unwrap();
    assert!(matches!(translated.accel_source, AccelSource::Accelerometer { .. }));
    // Write the BVH, read it back, and compare its forward kinematics.
    let written = recording.write_shifted(&translated.shift_cm);
    let output = Bvh::parse(written.as_bytes(), "out.bvh", &ReadOptions::default()).unwrap();
    let reference = common::open_table(&dir, "karate/heian_shodan.paper-reference.csv");
    let max_diff = common::max_fk_difference_cm(&output, &reference);
    eprintln!("BVH + side file route (written BVH, FK) vs reference: max |diff| = {max_diff:e} cm");
    assert!(max_diff <= 1e-6, "{max_diff}");
}

#[test]
fn a_side_file_of_the_wrong_length_names_both_lengths() {
    let Some(dir) = common::data_dir() else { return };
    let mut recording = common::open(&dir, "karate/heian_nidan.bvh");
    let e = recording.attach_accel(common::open_accel(&dir, "karate/heian_shodan.accel.csv")).unwrap_err();
    let e = e.to_string();
    assert!(e.contains("2600") && e.contains("2689"), "{e}");
    assert!(recording.accel.is_none());
}

#[test]
fn without_accelerometer_the_kinematics_drive_the_method() {
    let Some(dir) = common::data_dir() else { return };
    let recording = common::open(&dir, "karate/heian_nidan.bvh");
    let feet = recording.feet(&FeetChoice::default()).unwrap();
    let (accel, source) = recording.foot_accel_g(feet);
    let (left, right) = (accel.left, accel.right);
    assert_eq!(source, AccelSource::Kinematic);
    // At rest (stances between techniques) the magnitude is 1 g: the calmest
    // tenth of the frames sits near it, and steps reach several g.
    let mut sorted = left.clone();
    sorted.sort_by(f64::total_cmp);
    let (p10, p90) = (sorted[sorted.len() / 10], sorted[sorted.len() * 9 / 10]);
    assert!((p10 - 1.0).abs() < 0.1, "10th percentile {p10}");
    assert!(p90 > 2.0, "90th percentile {p90}");
    assert_eq!(right.len(), recording.frame_count());
    let translated = recording.translate_hachaj(&FeetChoice::default(), &HachajParams::default()).unwrap();
    assert!(translated.hachaj().expect("paper").pass1_pinned.iter().any(|p| p.is_some()));
}

#[test]
fn katas_close_better_than_the_vendor_translation() {
    let Some(dir) = common::data_dir() else { return };
    let recording = common::open(&dir, "karate/heian_shodan.csv");
    let translated = recording.translate_hachaj(&FeetChoice::default(), &HachajParams::default()).unwrap();
    let vendor = floor_closure_cm(&recording.poses.trajectory(0));
    let paper = floor_closure_cm(&translated.poses.trajectory(0));
    eprintln!("Heian Shodan closure: vendor {vendor:.1} cm, paper {paper:.1} cm");
    // The data README: the vendor misses by 3.7 m, the paper's method by about 16 cm.
    assert!(vendor > 300.0 && paper < 25.0, "vendor {vendor}, paper {paper}");
}

#[test]
fn demo_translation_is_recovered() {
    let demo = demo();
    let recording = demo.recording();
    assert_eq!(recording.frame_count(), demo.true_root_cm.len());
    let translated = recording.translate_hachaj(&FeetChoice::default(), &HachajParams::default()).unwrap();
    let estimated = translated.poses.trajectory(0);
    let truth = &demo.true_root_cm;
    let path_cm = floor_path_cm(truth);
    let mean_error_cm = mean_floor_error_cm(&estimated, truth);
    let mean_vertical_cm =
        estimated.iter().zip(truth).map(|(e, t)| (e.y - t.y).abs()).sum::<f64>() / truth.len() as f64;
    eprintln!(
        "demo: path {path_cm:.0} cm, mean horizontal error {mean_error_cm:.1} cm, mean vertical error {mean_vertical_cm:.1} cm"
    );
    // The stripped input does not move at all; the estimate must follow the
    // true path closely (the method never pins in its zeroed tails, so a few
    // percent of the path is its honest error).
    assert!(mean_error_cm < 0.03 * path_cm, "{mean_error_cm} cm of {path_cm} cm");
    assert!(mean_vertical_cm < 5.0, "{mean_vertical_cm}");
}

#[test]
fn every_shared_recording_stands_y_up_and_has_its_hips_found() {
    let Some(dir) = common::data_dir() else { return };
    for sub in ["karate", "groundtruth"] {
        let files = common::files_with_extension(&dir.join(sub), "bvh");
        assert!(!files.is_empty(), "no BVH in {}", dir.join(sub).display());
        for path in files {
            let recording =
                common::open(&dir, &format!("{sub}/{}", path.file_name().unwrap().to_string_lossy()));
            let feet = recording.feet(&FeetChoice::default()).expect("feet");
            let hips = recording.hips(feet);
            // The optical files put a static `joint_Root` on the floor above `Hips`.
            assert_eq!(recording.joint_names[hips], "Hips", "{}", path.display());
            assert!(!recording.up_axis_is_z(), "{} is Y-up", path.display());
        }
    }
}
