//! The accuracy evaluation on the shared ground-truth recordings: the contact
//! method against the paper's, on issue 4's acceptance figures. Figures that
//! are met are asserted; the ones that are not yet met are `#[ignore]`d tests
//! that say so, so `cargo test -- --ignored` shows how far off they are.

// A test may panic on what it does not expect: that is how it fails.
#![allow(clippy::unwrap_used, clippy::expect_used)]

mod common;

use std::sync::OnceLock;

use embusen::body::skeleton::Poses;
use embusen::eval::summary::{FileAccuracy, evaluate_file};
use embusen::eval::{accuracy, freeze_translation, kata_closure_cm};
use embusen::io::recording::{FeetChoice, Recording, Source};
use embusen::signal::stats::median;
use embusen::translate::Method;

/// Every ground-truth file, evaluated by both methods once for all the tests
/// that read it; `None` (the calling test said it is skipped) without the data.
fn evaluate_all() -> Option<&'static [FileAccuracy]> {
    static ALL: OnceLock<Vec<FileAccuracy>> = OnceLock::new();
    let dir = common::data_dir()?;
    Some(ALL.get_or_init(|| {
        let files = common::files_with_extension(&dir.join("groundtruth"), "bvh");
        assert!(!files.is_empty(), "no BVH in {}", dir.join("groundtruth").display());
        files
            .iter()
            .map(|path| {
                let name = path.file_name().map(|n| n.to_string_lossy().into_owned()).unwrap_or_default();
                let recording = common::open(&dir, &format!("groundtruth/{name}"));
                let Source::Bvh(bvh) = &recording.source else { panic!("{name}: a BVH") };
                let file = evaluate_file(bvh, &name).unwrap();
                eprintln!("{name}:\n  paper   {:?}\n  contact {:?}", file.hachaj, file.contact);
                file
            })
            .collect()
    }))
}

fn is(name: &str, motion: &str) -> bool {
    embusen::eval::motion_type(name) == motion
}

#[test]
fn contact_beats_paper_on_every_groundtruth_file() {
    let Some(all) = evaluate_all() else { return };
    for FileAccuracy { name, hachaj, contact } in all {
        assert!(contact.mean_error_pct < hachaj.mean_error_pct, "{name}: {contact:?} vs {hachaj:?}");
    }
}

#[test]
fn runs_and_dashes_stay_within_five_percent() {
    let Some(all) = evaluate_all() else { return };
    let fast: Vec<_> = all.iter().filter(|f| is(&f.name, "run") || is(&f.name, "dash")).collect();
    assert!(!fast.is_empty(), "no run or dash among the ground-truth files");
    for FileAccuracy { name, contact, .. } in fast {
        assert!(contact.mean_error_pct <= 5.0, "{name}: {contact:?}");
        assert!((0.9..=1.1).contains(&contact.path_ratio), "{name}: {contact:?}");
    }
}

/// Skating is measured on the joints the truth holds still, whose own
/// tracking jitter (1-2 cm/s at 30 fps) is the reference: over the files
/// where a foot is ever planted, the median excess over it.
#[test]
fn feet_planted_in_the_truth_skate_no_more_than_its_jitter() {
    let Some(all) = evaluate_all() else { return };
    let excess: Vec<f64> = all
        .iter()
        .map(|f| f.contact.skating_cm_per_s - f.contact.truth_skating_cm_per_s)
        .filter(|e| !e.is_nan())
        .collect();
    assert!(!excess.is_empty(), "no file has a planted foot");
    let median_excess = median(&excess);
    assert!(median_excess <= 0.5, "median skating above the truth's jitter {median_excess} cm/s: {excess:?}");
}

#[test]
fn walks_meet_the_acceptance_figures() {
    let Some(all) = evaluate_all() else { return };
    let walks: Vec<_> = all.iter().filter(|f| f.name.contains("walk")).collect();
    assert!(!walks.is_empty(), "no walk among the ground-truth files");
    for FileAccuracy { name, contact, .. } in walks {
        assert!(contact.mean_error_pct <= 1.0, "{name}: {contact:?}");
        assert!(contact.final_error_pct <= 2.0, "{name}: {contact:?}");
        assert!((0.97..=1.03).contains(&contact.path_ratio), "{name}: {contact:?}");
    }
}

/// The closure (cm) of both katas, Heian Shodan then Heian Nidan, by the
/// paper and the contact method, vendor translation removed, Heian Shodan
/// with its accelerometers; computed once for all the tests that read it.
fn kata_closures() -> Option<[(f64, f64); 2]> {
    static CLOSURES: OnceLock<[(f64, f64); 2]> = OnceLock::new();
    let dir = common::data_dir()?;
    Some(*CLOSURES.get_or_init(|| {
        let mut shodan = common::open(&dir, "karate/heian_shodan.bvh");
        shodan.attach_accel(common::open_accel(&dir, "karate/heian_shodan.accel.csv")).unwrap();
        let nidan = common::open(&dir, "karate/heian_nidan.bvh");
        [shodan, nidan].map(|kata| {
            let hachaj = kata_closure_cm(&kata, &Method::Hachaj(Default::default())).unwrap();
            let contact = kata_closure_cm(&kata, &Method::default()).unwrap();
            eprintln!("{} closure: paper {hachaj:.1} cm, contact {contact:.1} cm", kata.name);
            (hachaj, contact)
        })
    }))
}

/// A guard against breakage, not the goal: the vendor's own translation
/// misses Heian Shodan's start by 3.7 m. The suit's two planted feet drift
/// apart at a median 17-21 cm/s (5 cm/s in the optical files), so which one
/// is taken to hold still in a long stance is hard to tell; Heian Shodan
/// closes to ~32 cm (stable within 3 cm under half a millimetre of noise).
#[test]
fn katas_end_within_forty_centimetres_of_their_start() {
    let Some(closures) = kata_closures() else { return };
    for (_, contact) in closures {
        assert!(contact < 40.0, "{closures:?}");
    }
}

#[test]
fn heian_nidan_closes_within_fifteen_centimetres() {
    let Some([_, (_, nidan)]) = kata_closures() else { return };
    assert!(nidan <= 15.0, "{nidan}");
}

#[test]
#[ignore = "issue 4 acceptance not met: contact closes Heian Shodan to ~32 cm (Heian Nidan: 14.3 cm, met)"]
fn heian_shodan_closes_within_fifteen_centimetres() {
    let Some([(_, shodan), _]) = kata_closures() else { return };
    assert!(shodan <= 15.0, "{shodan}");
}

/// `poses` with `k` frames for each one, linearly between them (the last
/// frame kept): every `k`-th frame is an original one.
fn denser(poses: &Poses, k: usize) -> Poses {
    let n = poses.frame_count();
    let mut positions_cm = Vec::new();
    for f in 0..(n - 1) * k + 1 {
        let (a, t) = (f / k, (f % k) as f64 / k as f64);
        let b = (a + 1).min(n - 1);
        positions_cm.extend((0..poses.joint_count).map(|j| poses.at(a, j).lerp(poses.at(b, j), t)));
    }
    Poses { joint_count: poses.joint_count, positions_cm }
}

/// The method's parameters are in seconds and centimetres so that a
/// recording's rate does not change its answer: the walks and the run, made
/// three times as dense (90 fps), still meet their acceptance figures.
#[test]
fn a_denser_recording_meets_the_same_figures() {
    let Some(dir) = common::data_dir() else { return };
    for name in [
        "bandai1_walk_active_001.bvh",
        "bandai1_walk-right_normal_001.bvh",
        "bandai1_run_masculinity_001.bvh",
    ] {
        let recording = common::open(&dir, &format!("groundtruth/{name}"));
        let Source::Bvh(bvh) = &recording.source else { panic!("{name}: a BVH") };
        let feet = recording.feet(&FeetChoice::default()).unwrap();
        let mut frozen = Recording::from_bvh(freeze_translation(bvh, recording.hips(feet)), name);
        frozen.poses = denser(&frozen.poses, 3);
        frozen.fps = recording.fps * 3.0;
        let estimated = frozen.translate(&FeetChoice::default(), &Method::default()).unwrap();
        let contact = accuracy(&estimated, &denser(&recording.poses, 3), &recording.parents, frozen.fps);
        eprintln!("{name} at {} fps: {contact:?}", frozen.fps);
        let (mean, ratio) = if is(name, "run") { (5.0, 0.9..=1.1) } else { (1.0, 0.97..=1.03) };
        assert!(contact.mean_error_pct <= mean, "{name}: {contact:?}");
        assert!(ratio.contains(&contact.path_ratio), "{name}: {contact:?}");
    }
}

/// `poses` without its first `k` frames.
fn from_frame(poses: &Poses, k: usize) -> Poses {
    Poses {
        joint_count: poses.joint_count,
        positions_cm: poses.positions_cm[k * poses.joint_count..].to_vec(),
    }
}

/// A take that starts mid-stride keeps its strides. Cut off the start of
/// the clean run (a whole stride, 0–24 frames) and dash (0–8 frames; it has
/// 19), the first frames can be in the air, or on a foot still landing, with
/// no velocity to carry on. Forward alone, the first frames' pins went
/// unchecked: the run came out up to 39 % off and the dash 83 %; with each
/// start also read from what follows it, at most 2.4 and 5.4 %; with a
/// coast from the start whose velocity the first pin sets, checked against
/// its own next move (`solve.rs`), at most 1.5 and 3.6 %. Issue 23 asks the
/// held-out clean runs and dashes ≤ 3 % at the 90th percentile and ≤ 10 %
/// at the worst: every cut of the run within the first, of the dash within
/// the second.
#[test]
fn a_take_cut_mid_stride_keeps_its_strides() {
    let Some(dir) = common::data_dir() else { return };
    for (name, cuts, most_pct) in
        [("bandai1_run_masculinity_001.bvh", 24, 3.0), ("bandai1_dash_normal_001.bvh", 8, 10.0)]
    {
        let recording = common::open(&dir, &format!("groundtruth/{name}"));
        let Source::Bvh(bvh) = &recording.source else { panic!("{name}: a BVH") };
        let feet = recording.feet(&FeetChoice::default()).unwrap();
        let frozen = Recording::from_bvh(freeze_translation(bvh, recording.hips(feet)), name);
        for cut in 0..=cuts {
            let mut take = frozen.clone();
            take.poses = from_frame(&frozen.poses, cut);
            let estimated = take.translate(&FeetChoice::default(), &Method::default()).unwrap();
            let truth = from_frame(&recording.poses, cut);
            let contact = accuracy(&estimated, &truth, &recording.parents, take.fps);
            eprintln!("{name} from frame {cut}: {:.2} %", contact.mean_error_pct);
            assert!(contact.mean_error_pct <= most_pct, "{name} from frame {cut}: {contact:?}");
        }
    }
}
