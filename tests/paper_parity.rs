//! Parity with the authors' own R implementation (`RMoCap::calculate.kinematic`)
//! on their Heian Shodan recording, and the clean variant's sanity.

// A test may panic on what it does not expect: that is how it fails.
#![allow(clippy::unwrap_used, clippy::expect_used)]

use std::path::{Path, PathBuf};
use std::time::Instant;

use embusen::body::feet::{Foot, FootJoints, PerFoot};
use embusen::io::table::{Accelerations, Table};
use embusen::signal::accel::magnitudes;
use embusen::translate::hachaj::{HachajParams, HachajResult, Smoothing, hachaj_translation};

mod common;

/// The karate folder, or `None` (after saying so) when the data is absent.
fn karate() -> Option<PathBuf> {
    common::data_dir().map(|d| d.join("karate"))
}

fn read_table(path: &Path) -> Table {
    let bytes = std::fs::read(path).unwrap_or_else(|e| panic!("{}: {e}", path.display()));
    Table::parse(&bytes, &path.display().to_string()).unwrap_or_else(|e| panic!("{e}"))
}

fn joint(table: &Table, name: &str) -> usize {
    table.joint_names.iter().position(|n| n == name).unwrap_or_else(|| panic!("no joint {name}"))
}

/// Runs the paper method on the table the way RMoCap does.
fn run(table: &Table, smoothing: Smoothing) -> HachajResult {
    let feet = FootJoints { left: joint(table, "LeftFoot"), right: joint(table, "RightFoot") };
    let left = magnitudes(&table.accel_g("LeftFoot").expect("LeftFoot.a*"));
    let right = magnitudes(&table.accel_g("RightFoot").expect("RightFoot.a*"));
    let fps = 1.0 / table.frame_time_s().expect("a Time column");
    let params = HachajParams { smoothing, ..HachajParams::default() };
    let poses = table.poses();
    let start = Instant::now();
    let result = hachaj_translation(&poses, feet, PerFoot::new(&left[..], &right[..]), fps, &params)
        .unwrap_or_else(|e| panic!("{e}"));
    eprintln!(
        "hachaj_translation ({smoothing:?}) on {} frames: {:.3} ms",
        poses.frame_count(),
        start.elapsed().as_secs_f64() * 1e3
    );
    result
}

#[test]
fn faithful_mode_matches_rmocap_on_heian_shodan() {
    let Some(dir) = karate() else { return };
    let start = Instant::now();
    let input = read_table(&dir.join("heian_shodan.csv"));
    eprintln!("Table::parse heian_shodan.csv: {:.1} ms", start.elapsed().as_secs_f64() * 1e3);
    let reference = read_table(&dir.join("heian_shodan.paper-reference.csv"));
    assert_eq!(input.frame_count(), 2600);
    assert_eq!(reference.headers, input.headers);
    assert_eq!(reference.frame_count(), input.frame_count());

    let result = run(&input, Smoothing::Faithful);
    let corrected = input.with_shift(&result.shift_cm);

    let mut max_diff_cm = 0.0_f64;
    let mut worst = (0, String::new());
    let mut compared = 0;
    for (c, name) in input.headers.iter().enumerate() {
        if !(name.ends_with(".Dx") || name.ends_with(".Dy") || name.ends_with(".Dz")) {
            continue;
        }
        for f in 0..input.frame_count() {
            let diff = (corrected.row(f)[c] - reference.row(f)[c]).abs();
            compared += 1;
            // NaN counts as the worst difference.
            if diff > max_diff_cm || diff.is_nan() {
                max_diff_cm = diff;
                worst = (f, name.clone());
            }
        }
    }
    eprintln!(
        "paper parity: max |diff| = {max_diff_cm:.3e} cm over {compared} position values (worst: frame {} {})",
        worst.0, worst.1
    );
    assert_eq!(compared, 75 * 2600);
    assert!(max_diff_cm <= 1e-6, "max |diff| {max_diff_cm} cm at frame {} {}", worst.0, worst.1);

    // The other columns are untouched, as in R.
    for name in ["Time", "Hips.Rx", "LeftFoot.ax"] {
        assert_eq!(corrected.column(name), input.column(name), "{name}");
    }
    // R's zeroed tails: no pinning in the first and last half window, and the
    // left foot taken as grounded there.
    assert!(result.pass1_pinned[..51].iter().all(Option::is_none));
    assert!(result.pass1_pinned[2550..].iter().all(Option::is_none));
    assert!(result.ground_foot[..50].iter().all(|&g| g == Foot::Left));
    assert!(result.pass1_pinned.iter().filter(|p| p.is_some()).count() > 1000);
}

#[test]
fn clean_mode_differs_mildly_and_pins_feet_at_the_ends() {
    let Some(dir) = karate() else { return };
    let input = read_table(&dir.join("heian_shodan.csv"));
    let faithful = run(&input, Smoothing::Faithful);
    let clean = run(&input, Smoothing::Clean);
    let n = input.frame_count();
    let half_second = 50;

    // Clean smoothing has no zeroed tails, so feet are pinned at both ends.
    let pinned =
        |range: std::ops::Range<usize>| clean.pass1_pinned[range].iter().filter(|p| p.is_some()).count();
    assert!(pinned(1..half_second) > half_second / 2, "{}", pinned(1..half_second));
    assert!(pinned(n - half_second..n) > half_second / 2, "{}", pinned(n - half_second..n));
    assert!(clean.accel_smoothed_g.iter().all(|(_, s)| s.iter().all(|&v| v > 0.5)));

    // The hips path: the two modes agree closely in the middle of the kata.
    let hips = joint(&input, "Hips");
    let path = |r: &HachajResult| input.poses().shifted(&r.shift_cm).trajectory(hips);
    let (a, b) = (path(&faithful), path(&clean));
    let floor_gap = |f: usize| {
        let d = a[f] - b[f];
        (d.x * d.x + d.z * d.z).sqrt()
    };
    let max_gap_cm = (0..n).map(floor_gap).fold(0.0, f64::max);
    let mean_gap_cm = (0..n).map(floor_gap).sum::<f64>() / n as f64;
    // Both are anchored at frame 0; compare the distance each travels.
    let travelled = |p: &[glam::DVec3]| {
        p.windows(2)
            .map(|w| {
                let d = w[1] - w[0];
                (d.x * d.x + d.z * d.z).sqrt()
            })
            .sum::<f64>()
    };
    let (ta, tb) = (travelled(&a), travelled(&b));
    eprintln!(
        "clean vs faithful hips on the floor: max gap {max_gap_cm:.1} cm, mean {mean_gap_cm:.1} cm; path {ta:.0} vs {tb:.0} cm"
    );
    assert!(max_gap_cm > 0.0, "clean mode should differ");
    assert!(mean_gap_cm < 50.0, "mean gap {mean_gap_cm} cm");
    assert!((ta - tb).abs() < 0.2 * ta, "path {ta} vs {tb} cm");
}

#[test]
fn accel_side_file_equals_the_tables_accelerometer_columns() {
    let Some(dir) = karate() else { return };
    let input = read_table(&dir.join("heian_shodan.csv"));
    let path = dir.join("heian_shodan.accel.csv");
    let bytes = std::fs::read(&path).expect("heian_shodan.accel.csv");
    let side = Accelerations::parse(&bytes, "heian_shodan.accel.csv").unwrap_or_else(|e| panic!("{e}"));
    let from_table = Accelerations::from_table(&input);
    assert_eq!(side.sensor_names.len(), 19);
    assert_eq!(side.sensor_names, from_table.sensor_names);
    assert_eq!(side.frame_count(), 2600);
    assert_eq!(side.accel_g, from_table.accel_g);
    // The side file's own Time column agrees too.
    let side_table = Table::parse(&bytes, "heian_shodan.accel.csv").unwrap();
    assert_eq!(side_table.column("Time"), input.column("Time"));
}
