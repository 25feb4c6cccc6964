//! The contact method on suit-grade input (`../shared/data/suit`: the
//! ground-truth files through an inertial-suit error model), scored against
//! the true motion. What the method reaches today is guarded; issue 12's
//! acceptance figures that it does not reach are `#[ignore]`d tests that say
//! how far off they are (`cargo test --test suit -- --ignored`). Several of
//! them lie below what the truth's own contact decisions give on the suit's
//! pose (the contacts oracle), so no choice of contacts reaches them.

// A test may panic on what it does not expect: that is how it fails.
#![allow(clippy::unwrap_used, clippy::expect_used)]

mod common;

use std::sync::OnceLock;

use embusen::eval::suit::{
    SuitFileAccuracy, SuitSummary, evaluate_suit_file, summarise_suit, truth_file_name,
};
use embusen::eval::{contacts_oracle_path, grounded_oracle_path, oracle_pinned_steps};
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
                    file.file.hachaj.mean_error_pct,
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

/// The contact method's medians for `motion` at `level`.
fn contact_medians<'a>(summary: &'a SuitSummary, level: &str, motion: &str) -> &'a embusen::eval::Accuracy {
    let level =
        summary.levels.iter().find(|l| l.level == level).unwrap_or_else(|| panic!("no level {level}"));
    let (_, medians) = level
        .by_motion_type
        .iter()
        .find(|(m, _)| m == motion)
        .unwrap_or_else(|| panic!("no {motion} at {level:?}"));
    &medians.methods.contact
}

/// The contact method's median mean error (%) for `motion` at `level`.
fn contact_median_pct(summary: &SuitSummary, level: &str, motion: &str) -> f64 {
    contact_medians(summary, level, motion).mean_error_pct
}

/// With the pose's noise measured and smoothed away before the choice of
/// contacts, a suit's walk keeps its strides: the paper method is off by
/// about 20 % on these files.
/// Every median of `limits` (motion, most %) at `level`, all failures named.
fn assert_medians_within(summary: &SuitSummary, level: &str, limits: &[(&str, f64)]) {
    let failures: Vec<String> = limits
        .iter()
        .map(|&(motion, limit_pct)| (motion, limit_pct, contact_median_pct(summary, level, motion)))
        .filter(|&(_, limit_pct, pct)| pct > limit_pct)
        .map(|(motion, limit_pct, pct)| format!("level {level} {motion}: {pct:.2} % > {limit_pct} %"))
        .collect();
    assert!(failures.is_empty(), "{}", failures.join("\n"));
}

/// The leg-length oracle only rescales the true path: it stays close to it,
/// whatever the methods do, and the suits' legs are a few percent off.
#[test]
fn the_leg_length_oracle_stays_near_the_truth() {
    let Some((files, summary)) = evaluate_all() else { return };
    for file in files {
        assert!(
            file.leg_oracle_mean_error_pct.is_finite() && file.leg_oracle_mean_error_pct < 3.0,
            "{}: oracle {:.2} %",
            file.file.name,
            file.leg_oracle_mean_error_pct
        );
        assert!(
            (0.9..=1.1).contains(&file.leg_length_ratio),
            "{}: {}",
            file.file.name,
            file.leg_length_ratio
        );
    }
    let levels: Vec<&str> = summary.levels.iter().map(|l| l.level.as_str()).collect();
    assert_eq!(levels, ["1", "0.5"]);
}

/// The contacts oracle's own bias: on a clean pose (the truth pinned at its
/// own still joints) it pins joints, not the rolling sole, and lands within
/// 2 % on every moving ground-truth file; on the suit files it is a number.
/// The grounded oracle, which carries the stances' velocity through the
/// air, within 6 %: a clean runner's stances tell its flights' velocity
/// (the run 2.0 %), less so a dash that speeds up from rest (5.5 %; a mean
/// of the stances around lags a body that gains speed, where the contact
/// method, carrying the take-off's own velocity, does 1.4 %).
#[test]
fn the_contacts_oracle_is_near_exact_on_a_clean_pose() {
    let Some(dir) = common::data_dir() else { return };
    let Some((files, _)) = evaluate_all() else { return };
    let mut checked = 0;
    for path in common::files_with_extension(&dir.join("groundtruth"), "bvh") {
        let relative = format!("groundtruth/{}", path.file_name().unwrap().to_string_lossy());
        let truth = common::open(&dir, &relative);
        let feet = truth.feet(&embusen::io::recording::FeetChoice::default()).unwrap();
        let hips = truth.hips(feet);
        let path_cm = embusen::eval::metrics::floor_path_cm(&truth.poses.trajectory(hips));
        if path_cm < embusen::eval::summary::MOVING_MIN_PATH_CM {
            continue;
        }
        let pinned = oracle_pinned_steps(&truth.poses, &truth.poses, &truth.parents, feet, hips, truth.fps);
        let oracle = contacts_oracle_path(&pinned, &truth.poses, hips);
        let error_pct = 100.0
            * embusen::eval::metrics::mean_floor_error_cm(&oracle, &truth.poses.trajectory(hips))
            / path_cm;
        let grounded = grounded_oracle_path(&pinned, &truth.poses, hips, truth.fps);
        let grounded_pct = 100.0
            * embusen::eval::metrics::mean_floor_error_cm(&grounded, &truth.poses.trajectory(hips))
            / path_cm;
        eprintln!(
            "{relative}: contacts oracle on the clean pose {error_pct:.2} %, grounded {grounded_pct:.2} %"
        );
        assert!(error_pct < 2.0, "{relative}: {error_pct:.2} %");
        assert!(grounded_pct < 6.0, "{relative}: grounded {grounded_pct:.2} %");
        checked += 1;
    }
    assert!(checked >= 5, "only {checked} moving ground-truth files");
    assert!(files.iter().all(|f| f.contacts_oracle_mean_error_pct.is_finite()));
    assert!(files.iter().all(|f| f.grounded_oracle_mean_error_pct.is_finite()));
    // Their paths' lengths over the truth's: positive numbers.
    let ratios = files.iter().flat_map(|f| [f.contacts_oracle_path_ratio, f.grounded_oracle_path_ratio]);
    assert!(ratios.clone().all(|r| r.is_finite() && r > 0.0), "{:?}", ratios.collect::<Vec<_>>());
}

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

/// Runs keep most of their strides at half the suit's error level (the paper
/// method loses 35-40 % on these files).
#[test]
fn suit_grade_runs_at_half_the_error_stay_within_fifteen_percent() {
    let Some((_, summary)) = evaluate_all() else { return };
    for motion in ["run", "dash"] {
        let pct = contact_median_pct(summary, "0.5", motion);
        assert!(pct <= 15.0, "level 0.5 {motion}: {pct:.2} %");
    }
}

/// A body that bows in place stays in place: the pose's noise, smoothed
/// out where the body moves slowly beside it (`contact/still.rs`), no
/// longer walks its hips about. Issue 23 asks ≤ 1.3 × the true path; at
/// half the suit's error the bow's median was 1.26, now 1.04.
#[test]
fn suit_grade_bodies_in_place_stay_in_place_at_half_the_error() {
    let Some((_, summary)) = evaluate_all() else { return };
    let ratio = contact_medians(summary, "0.5", "bow").path_ratio;
    assert!(ratio <= 1.3, "level 0.5 bow: path {ratio:.3} × the truth's");
}

/// A body that stands on one foot while the other kicks stays where it
/// stands: the kick's fast segments make the suit's noise burst to four
/// to eight times the recording's median, and where the choice's smoothing
/// widens to it (`Grid::widen_where_noise_bursts`) the support foot is
/// pinned through the kick instead of coasted over. At half the suit's
/// error the kicks' median was 12.4 %, now 3.6 (their contacts oracle 2.7).
#[test]
fn suit_grade_kicks_keep_their_place_at_half_the_error() {
    let Some((_, summary)) = evaluate_all() else { return };
    let pct = contact_median_pct(summary, "0.5", "kick");
    assert!(pct <= 6.0, "level 0.5 kick: {pct:.2} %");
}

/// The same at the suit's full error: the bow's noise is correlated over a
/// few frames, and read on frames twice as far apart, as it moves a
/// standing body's hips, it holds the path to 1.26 × the truth's (2.0
/// before `contact/still.rs`, 1.31 with the nearer reading; 0.97 since a
/// body in place no longer coasts).
#[test]
fn suit_grade_bodies_in_place_stay_in_place_at_full_error() {
    let Some((_, summary)) = evaluate_all() else { return };
    let ratio = contact_medians(summary, "1", "bow").path_ratio;
    assert!(ratio <= 1.3, "level 1 bow: path {ratio:.3} × the truth's");
}

/// Where a noisy pose's body barely progresses it does not coast
/// (`contact::still::in_place`): the dances coasted through a quarter of
/// their frames while the truth stood on one foot, carrying the velocity
/// the pose's noise gave the last pin. The dances' medians were 8.4 %
/// (level 1) and 6.2 % (level 0.5), now 3.5 and 2.4 (their contacts oracle
/// 2.1 and 1.8); the kicks' at level 1 was 14.7, now 6.2 (oracle 6.5).
#[test]
fn suit_grade_bodies_in_place_do_not_coast() {
    let Some((_, summary)) = evaluate_all() else { return };
    for (level, motion, limit) in [("1", "dance-short", 4.5), ("0.5", "dance-short", 3.5), ("1", "kick", 8.0)]
    {
        let pct = contact_median_pct(summary, level, motion);
        assert!(pct <= limit, "level {level} {motion}: {pct:.2} %, more than {limit}");
    }
}

/// A coast carries its smoothed velocity scaled by how much faster the
/// stances around it end, read from the stances themselves
/// (`contact/carry.rs`): the choice's smoothing reaches across a short
/// stance into the swing and reads it slow. Medians before: walk at level 1
/// 5.05 %, run 18.76 and 6.80, dash at level 0.5 9.69; now 4.15, 14.96,
/// 5.60 and 7.74.
#[test]
fn suit_grade_coasts_carry_their_stances_speed() {
    let Some((_, summary)) = evaluate_all() else { return };
    for (level, motion, limit) in
        [("1", "walk", 4.5), ("1", "run", 16.0), ("0.5", "run", 6.0), ("0.5", "dash", 8.5)]
    {
        let pct = contact_median_pct(summary, level, motion);
        assert!(pct <= limit, "level {level} {motion}: {pct:.2} %, more than {limit}");
    }
}

#[test]
#[ignore = "issue 12 acceptance, blocked: several limits lie below the contacts oracle (`embusen eval ../shared/data/suit`, column `contacts %`); `-- --ignored` prints the medians"]
fn suit_grade_level_1_meets_the_acceptance_figures() {
    let Some((_, summary)) = evaluate_all() else { return };
    let limits = [
        ("walk", 3.0),
        ("walk-right", 3.0),
        ("run", 5.0),
        ("dash", 5.0),
        ("kick", 5.0),
        ("dance-short", 5.0),
    ];
    assert_medians_within(summary, "1", &limits);
}

#[test]
#[ignore = "issue 12 acceptance, blocked: several limits lie below the contacts oracle (`embusen eval ../shared/data/suit`, column `contacts %`); `-- --ignored` prints the medians"]
fn suit_grade_level_half_meets_the_acceptance_figures() {
    let Some((_, summary)) = evaluate_all() else { return };
    assert_medians_within(summary, "0.5", &[("walk", 2.0), ("walk-right", 2.0), ("run", 3.0), ("dash", 3.0)]);
}

#[test]
#[ignore = "issue 12 acceptance, blocked with the medians (see docs/contact.md); `-- --ignored` prints each file that fails"]
fn suit_grade_contact_beats_paper_on_every_file_within_a_sane_path_ratio() {
    let Some((files, _)) = evaluate_all() else { return };
    for file in files {
        let (hachaj, contact) = (&file.file.hachaj, &file.file.contact);
        if contact.true_path_cm >= embusen::eval::summary::MOVING_MIN_PATH_CM {
            assert!(
                contact.mean_error_pct < hachaj.mean_error_pct,
                "{}: {contact:?} vs {hachaj:?}",
                file.file.name
            );
        }
        assert!((0.9..=1.15).contains(&contact.path_ratio), "{}: {contact:?}", file.file.name);
    }
}

/// The suit model's measured sizes (`ErrorSizes::MEASURED`) read like the
/// shared suit files they were measured on: per bin of angular speed, the
/// noise of one draw of the model within 0.7–1.45 times the mean of the
/// shared files' two seeds, and correlated from frame to frame as they are.
/// The README's sizes read less than 0.65 times their noise below 2 rad/s:
/// why the model's held-out files were gentler than the shared ones.
#[test]
fn the_measured_suit_sizes_read_like_the_shared_suit_files() {
    use embusen::body::feet::resolve_feet;
    use embusen::eval::suit_errors::{SuitErrors, suit_errors};
    use embusen::io::bvh::Bvh;
    use embusen::synth::suit::{self, ErrorSizes, SuitBody};
    let Some(dir) = common::data_dir() else { return };
    let bvh = |relative: &str| match common::open(&dir, relative).source {
        Source::Bvh(bvh) => bvh,
        Source::Table(_) => panic!("{relative}: a BVH"),
    };
    let through = |truth: &Bvh, sizes: &ErrorSizes| {
        let feet = resolve_feet(&truth.skeleton.names, None, None).unwrap();
        let body = SuitBody::from_feet(&truth.skeleton, feet);
        let graded = suit::apply(&truth.skeleton, &truth.motion, &body, sizes, 3, suit::REAL_SUIT_LEVEL);
        Bvh { skeleton: graded.skeleton, motion: graded.motion, warnings: Vec::new() }
    };
    let mut failures = Vec::new();
    for motion in ["walk_active", "run_masculinity", "bow_normal", "kick_normal", "dance-short_normal"] {
        let truth = bvh(&format!("groundtruth/bandai1_{motion}_001.bvh"));
        let shared: Vec<SuitErrors> = (1..=2)
            .map(|seed| {
                suit_errors(&bvh(&format!("suit/bandai1_{motion}_001.suit-l1-s{seed}.bvh")), &truth).unwrap()
            })
            .collect();
        let measured = suit_errors(&through(&truth, &ErrorSizes::MEASURED), &truth).unwrap();
        let described = suit_errors(&through(&truth, &ErrorSizes::DESCRIBED), &truth).unwrap();
        for bin in 0..measured.noise_deg_by_speed.len() {
            let Some(shared_deg) = shared.iter().map(|e| e.noise_deg_by_speed[bin]).sum::<Option<f64>>()
            else {
                continue;
            };
            let shared_deg = shared_deg / 2.0;
            let model_deg = measured.noise_deg_by_speed[bin].unwrap();
            if !(0.7..=1.45).contains(&(model_deg / shared_deg)) {
                failures.push(format!("{motion} bin {bin}: model {model_deg:.2}° against {shared_deg:.2}°"));
            }
            let described_deg = described.noise_deg_by_speed[bin].unwrap();
            if bin < 2 && described_deg > 0.65 * shared_deg {
                failures.push(format!(
                    "{motion} bin {bin}: README's sizes {described_deg:.2}° against {shared_deg:.2}°"
                ));
            }
        }
        let shared_correlation = (shared[0].correlation[0] + shared[1].correlation[0]) / 2.0;
        if (measured.correlation[0] - shared_correlation).abs() > 0.1 {
            failures.push(format!(
                "{motion}: correlated {:.2} from frame to frame against {shared_correlation:.2}",
                measured.correlation[0]
            ));
        }
        eprintln!(
            "{motion}: shared {:?} / model {:?}",
            shared.iter().map(|e| e.noise_deg_by_speed).collect::<Vec<_>>(),
            measured.noise_deg_by_speed
        );
    }
    assert!(failures.is_empty(), "{}", failures.join("\n"));
}
