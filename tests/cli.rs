//! The `embusen` binary as a user runs it: the demo, `info` and `translate` on
//! every shared recording, corrupted files, many files at once, exit codes.

// A test may panic on what it does not expect: that is how it fails.
#![allow(clippy::unwrap_used, clippy::expect_used)]

mod common;

use common::Scratch;

use std::path::{Path, PathBuf};
use std::process::{Command, Output};

use embusen::io::recording::Recording;

fn embusen(args: &[&str]) -> Output {
    Command::new(env!("CARGO_BIN_EXE_embusen")).args(args).output().expect("runs embusen")
}

fn text(bytes: &[u8]) -> String {
    String::from_utf8_lossy(bytes).into_owned()
}

/// The shared BVHs (each folder must have some) and the Heian Shodan tables.
fn shared_recordings(dir: &Path) -> Vec<PathBuf> {
    let mut files = Vec::new();
    for sub in ["karate", "groundtruth"] {
        let found = common::files_with_extension(&dir.join(sub), "bvh");
        assert!(!found.is_empty(), "no BVH in {}", dir.join(sub).display());
        files.extend(found);
    }
    files.push(dir.join("karate/heian_shodan.csv"));
    files.push(dir.join("karate/heian_shodan.paper-reference.csv"));
    files
}

#[test]
fn no_arguments_runs_the_demo() {
    let out = embusen(&[]);
    assert!(out.status.success(), "{}", text(&out.stderr));
    let stdout = text(&out.stdout);
    assert!(stdout.contains("built-in demo") && stdout.contains("hips error against the truth"), "{stdout}");
    // Both methods' mean and final errors, and which of them is better.
    for method in ["contact", "paper"] {
        assert!(
            stdout.lines().any(|l| l.trim_start().starts_with(method) && l.contains("final")),
            "{stdout}"
        );
    }
    assert!(stdout.contains("is better on this demo"), "{stdout}");
}

#[test]
fn bad_usage_exits_with_2() {
    assert_eq!(embusen(&["translate"]).status.code(), Some(2));
    assert_eq!(embusen(&["translate", "x.bvh", "--smoothing", "wobbly"]).status.code(), Some(2));
    assert_eq!(embusen(&["frobnicate"]).status.code(), Some(2));
}

#[test]
fn every_shared_file_opens_with_info() {
    let Some(dir) = common::data_dir() else {
        return;
    };
    for path in shared_recordings(&dir) {
        let out = embusen(&["info", path.to_str().unwrap()]);
        let stdout = text(&out.stdout);
        assert!(out.status.success(), "{}: {}", path.display(), text(&out.stderr));
        assert!(stdout.contains("frames:") && stdout.contains("feet:"), "{stdout}");
        assert!(!stdout.contains("not detected"), "{}: feet not detected", path.display());
        if path.ends_with("mae_geri_left.bvh") {
            assert!(stdout.contains("warning:  Frame Time is 0"), "{stdout}");
        }
    }
}

#[test]
fn every_shared_file_translates() {
    let Some(dir) = common::data_dir() else {
        return;
    };
    let out_dir = Scratch::new("all");
    let inputs = shared_recordings(&dir);
    let mut args = vec!["translate".to_string()];
    args.extend(inputs.iter().map(|p| p.display().to_string()));
    args.extend(["-o".to_string(), out_dir.display().to_string()]);
    let out = embusen(&args.iter().map(String::as_str).collect::<Vec<_>>());
    assert!(out.status.success(), "{}", text(&out.stderr));
    let summary = text(&out.stdout) + &text(&out.stderr);
    for input in &inputs {
        let stem = input.file_stem().unwrap().to_str().unwrap();
        let ext = input.extension().unwrap().to_str().unwrap();
        let written = out_dir.join(format!("{stem}.embusen.{ext}"));
        let bytes = std::fs::read(&written).unwrap_or_else(|e| panic!("{}: {e}", written.display()));
        let again = Recording::parse(&bytes, &written.display().to_string(), Some(100.0)).unwrap();
        assert!(again.frame_count() > 10);
        assert!(summary.contains(stem), "no summary line for {stem}: {summary}");
    }
    // heian_shodan.bvh found its side file; heian_nidan.bvh has none.
    assert!(
        summary.lines().any(|l| l.contains("heian_shodan.bvh") && l.contains("accelerometers")),
        "{summary}"
    );
    assert!(summary.lines().any(|l| l.contains("heian_nidan.bvh") && l.contains("kinematics")), "{summary}");
}

/// Corrupted copies of a real file: each gives one `error: file:line:column:`
/// line, exit code 1, and no panic.
#[test]
fn corrupted_files_give_one_clear_error_each() {
    let Some(dir) = common::data_dir() else {
        return;
    };
    let work = Scratch::new("corrupt");
    let original = std::fs::read_to_string(dir.join("karate/empi_right.bvh")).unwrap();
    let motion = original.find("MOTION").unwrap();
    let first_row = original[motion..].find("\n\n").unwrap() + motion + 2;
    let corruptions: Vec<(&str, String)> = vec![
        ("truncated", original[..original.len() * 2 / 3].to_string()),
        ("truncated_hierarchy", original[..motion / 2].to_string()),
        ("letter_in_number", format!("{}1.2q3{}", &original[..first_row], &original[first_row + 1..])),
        ("missing_brace", original.replacen("{", "", 3)),
        ("wrong_channel_count", original.replacen("CHANNELS 3", "CHANNELS 4", 1)),
        ("bad_table", "Time,Hips.Dx,Hips.Dy,Hips.Dz\n0,1,2,3\n0.01,1,2x,3\n".to_string()),
        ("empty", String::new()),
    ];
    for (name, content) in &corruptions {
        let path = work.join(format!("{name}.bvh"));
        std::fs::write(&path, content).unwrap();
        for command in ["info", "translate"] {
            let out = embusen(
                &[command, path.to_str().unwrap(), "-o", work.join("out").to_str().unwrap()]
                    [..if command == "info" { 2 } else { 4 }],
            );
            let stderr = text(&out.stderr);
            assert_eq!(out.status.code(), Some(1), "{name} {command}: {stderr}");
            assert!(!stderr.contains("panicked"), "{name}: {stderr}");
            let errors: Vec<&str> = stderr.lines().filter(|l| l.starts_with("error: ")).collect();
            assert_eq!(errors.len(), 1, "{name} {command}: {stderr}");
            assert!(errors[0].starts_with(&format!("error: {}", path.display())), "{}", errors[0]);
            eprintln!("{name}: {}", errors[0]);
            // Errors inside the text say where (file:line:column:).
            if *name != "empty" {
                let after = &errors[0][format!("error: {}:", path.display()).len()..];
                let mut parts = after.splitn(3, ':');
                let line_ok = parts.next().is_some_and(|l| l.parse::<usize>().is_ok());
                let column_ok = parts.next().is_some_and(|c| c.parse::<usize>().is_ok());
                assert!(line_ok && column_ok, "{name}: no line:column in {}", errors[0]);
            }
        }
    }
}

#[test]
fn one_bad_file_does_not_stop_the_others() {
    let Some(dir) = common::data_dir() else {
        return;
    };
    let work = Scratch::new("mixed");
    let bad = work.join("bad.bvh");
    std::fs::write(&bad, "HIERARCHY\nROOT Hips\n{\n").unwrap();
    let good = dir.join("karate/mae_geri_left.bvh");
    let out =
        embusen(&["translate", bad.to_str().unwrap(), good.to_str().unwrap(), "-o", work.to_str().unwrap()]);
    assert_eq!(out.status.code(), Some(1));
    assert!(work.join("mae_geri_left.embusen.bvh").exists());
    assert!(text(&out.stderr).contains("1 of 2 files failed"), "{}", text(&out.stderr));
}

/// A suit file finds its truth in `../groundtruth/` from its folder, or in
/// `--truth DIR`; one whose truth is nowhere is an error for that file alone.
#[test]
fn eval_pairs_suit_files_with_their_truth() {
    let Some(dir) = common::data_dir() else { return };
    let suit = dir.join("suit/bandai1_walk_active_001.suit-l1-s1.bvh");
    let out = embusen(&["eval", suit.to_str().unwrap()]);
    let stdout = text(&out.stdout);
    assert!(out.status.success(), "{}", text(&out.stderr));
    assert!(stdout.starts_with("suit grade:") && !stdout.contains("ground truth:"), "{stdout}");
    assert!(
        stdout.contains("bandai1_walk_active_001.suit-l1-s1.bvh") && stdout.contains("level 1:"),
        "{stdout}"
    );
    assert!(stdout.contains("contact beats paper on mean error in"), "{stdout}");

    // Elsewhere, the truth is not found unless named.
    let scratch = Scratch::new("suit-truth");
    let copy = scratch.join("x_walk_y_001.suit-l0.5-s9.bvh");
    std::fs::copy(&suit, &copy).unwrap();
    let out = embusen(&["eval", copy.to_str().unwrap(), suit.to_str().unwrap()]);
    let stderr = text(&out.stderr);
    assert_eq!(out.status.code(), Some(1), "{stderr}");
    assert!(stderr.contains("x_walk_y_001.suit-l0.5-s9.bvh: its truth is not found"), "{stderr}");
    assert!(
        text(&out.stdout).contains("bandai1_walk_active_001.suit-l1-s1.bvh "),
        "the other file still runs"
    );
    let truth = dir.join("groundtruth/bandai1_walk_active_001.bvh");
    let out = embusen(&["eval", "--pair", copy.to_str().unwrap(), truth.to_str().unwrap()]);
    assert!(out.status.success(), "{}", text(&out.stderr));
    assert!(text(&out.stdout).contains("level 0.5:"), "{}", text(&out.stdout));
    std::fs::copy(&truth, scratch.join("x_walk_y_001.bvh")).unwrap();
    let out = embusen(&["eval", copy.to_str().unwrap(), "--truth", scratch.to_str().unwrap()]);
    assert!(out.status.success(), "{}", text(&out.stderr));
}
