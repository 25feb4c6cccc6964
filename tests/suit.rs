//! The contact method on suit-grade input (`../shared/data/suit`: the
//! ground-truth files through an inertial-suit error model), scored against
//! the true motion. What the method reaches today is guarded; issue 12's
//! acceptance figures that it does not reach yet are `#[ignore]`d tests that
//! say how far off they are (`cargo test --test suit -- --ignored`).

// A test may panic on what it does not expect: that is how it fails.
#![allow(clippy::unwrap_used, clippy::expect_used)]

mod common;

use std::sync::OnceLock;

use embusen::eval::suit::{
    SuitFileAccuracy, SuitSummary, evaluate_suit_file, summarise_suit, truth_file_name,
};
use embusen::io::recording::Source;

/// Every shared suit file, evaluated by both methods once for all the tests;
/// `None` (the calling test said it is skipped) without the data.
fn evaluate_all() -> Option<&'static (Vec<SuitFileAccuracy>, SuitSummary)> {
    static ALL: OnceLock<(Vec<SuitFileAccuracy>, SuitSummary)> = OnceLock::new();
    let dir = common::data_dir()?;
    Some(ALL.get_or_init(|| {
        let bvh = |relative: &str| match common::open(&dir, relative).source {
            Source::Bvh(bvh) => bvh,
            Source::Table(_) => panic!("{relative}: a BVH"),
        };
        let files: Vec<SuitFileAccuracy> = common::files_with_extension(&dir.join("suit"), "bvh")
            .iter()
            .map(|path| {
                let name = path.file_name().map(|n| n.to_string_lossy().into_owned()).unwrap_or_default();
                let truth = truth_file_name(&name).unwrap_or_else(|| panic!("{name}: not a suit file name"));
                let file = evaluate_suit_file(
                    &bvh(&format!("suit/{name}")),
                    &bvh(&format!("groundtruth/{truth}")),
                    &name,
                )
                .unwrap();
                eprintln!(
                    "{name}: paper {:.2} %, contact {:.2} % (path ratio {:.3})",
                    file.file.paper.mean_error_pct,
                    file.file.contact.mean_error_pct,
                    file.file.contact.path_ratio
                );
                file
            })
            .collect();
        assert!(files.len() >= 14, "only {} suit files in {}", files.len(), dir.join("suit").display());
        let summary = summarise_suit(&files);
        (files, summary)
    }))
}

/// The contact method's median mean error (%) for `motion` at `level`.
fn contact_median_pct(summary: &SuitSummary, level: &str, motion: &str) -> f64 {
    let level =
        summary.levels.iter().find(|l| l.level == level).unwrap_or_else(|| panic!("no level {level}"));
    let (_, medians) = level
        .by_motion_type
        .iter()
        .find(|(m, _)| m == motion)
        .unwrap_or_else(|| panic!("no {motion} at {level:?}"));
    medians.methods.contact.mean_error_pct
}

/// What the noise measured on the pose and smoothed away before the choice
/// of contacts holds: without it, level 1 walks were off by 24 / 22 % and
/// level 0.5 walks by 9 / 9 % (today about 5 and 3 %).
#[test]
fn suit_grade_walks_keep_their_strides() {
    let Some((_, summary)) = evaluate_all() else { return };
    for (level, limit_pct) in [("1", 8.0), ("0.5", 5.0)] {
        for motion in ["walk", "walk-right"] {
            let pct = contact_median_pct(summary, level, motion);
            assert!(pct <= limit_pct, "level {level} {motion}: {pct:.2} % > {limit_pct} %");
        }
    }
}

/// Runs keep most of their strides at half the suit's error level (29 / 31 %
/// without the noise smoothing, about 7 / 10 % with it).
#[test]
fn suit_grade_runs_at_half_the_error_stay_within_fifteen_percent() {
    let Some((_, summary)) = evaluate_all() else { return };
    for motion in ["run", "dash"] {
        let pct = contact_median_pct(summary, "0.5", motion);
        assert!(pct <= 15.0, "level 0.5 {motion}: {pct:.2} %");
    }
}

#[test]
#[ignore = "issue 12 acceptance not met: level 1 medians walks 5.1/5.5 % (≤ 3), run 18.8 (≤ 5), dash 14.5 (≤ 5), kick 12.7 (≤ 5), dance 7.5 (≤ 5)"]
fn suit_grade_level_1_meets_the_acceptance_figures() {
    let Some((_, summary)) = evaluate_all() else { return };
    for (motion, limit_pct) in
        [("walk", 3.0), ("walk-right", 3.0), ("run", 5.0), ("dash", 5.0), ("kick", 5.0), ("dance-short", 5.0)]
    {
        let pct = contact_median_pct(summary, "1", motion);
        assert!(pct <= limit_pct, "level 1 {motion}: {pct:.2} % > {limit_pct} %");
    }
}

#[test]
#[ignore = "issue 12 acceptance not met: level 0.5 medians walks 3.0/3.2 % (≤ 2), run 6.8 (≤ 3), dash 9.7 (≤ 3)"]
fn suit_grade_level_half_meets_the_acceptance_figures() {
    let Some((_, summary)) = evaluate_all() else { return };
    for (motion, limit_pct) in [("walk", 2.0), ("walk-right", 2.0), ("run", 3.0), ("dash", 3.0)] {
        let pct = contact_median_pct(summary, "0.5", motion);
        assert!(pct <= limit_pct, "level 0.5 {motion}: {pct:.2} % > {limit_pct} %");
    }
}

#[test]
#[ignore = "issue 12 acceptance not met: contact beats paper on 16 of 24 moving suit files; 16 of 28 path ratios outside 0.9-1.15 (0.58-2.05)"]
fn suit_grade_contact_beats_paper_on_every_file_within_a_sane_path_ratio() {
    let Some((files, _)) = evaluate_all() else { return };
    for file in files {
        let (paper, contact) = (&file.file.paper, &file.file.contact);
        if contact.true_path_cm >= embusen::eval::summary::MOVING_MIN_PATH_CM {
            assert!(
                contact.mean_error_pct < paper.mean_error_pct,
                "{}: {contact:?} vs {paper:?}",
                file.file.name
            );
        }
        assert!((0.9..=1.15).contains(&contact.path_ratio), "{}: {contact:?}", file.file.name);
    }
}
