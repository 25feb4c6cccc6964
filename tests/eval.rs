//! The accuracy evaluation on the shared ground-truth recordings: the contact
//! method against the paper's, on what each is for.

mod common;

use embusen::eval::{evaluate_groundtruth, kata_closure_cm};
use embusen::recording::{Method, Source};

#[test]
fn contact_beats_paper_on_the_walks() {
    let Some(dir) = common::data_dir() else { return };
    for name in ["bandai1_walk_active_001.bvh", "bandai1_walk-right_normal_001.bvh"] {
        let recording = common::open(&dir, &format!("groundtruth/{name}"));
        let Source::Bvh(bvh) = &recording.source else { panic!("a BVH") };
        let paper = evaluate_groundtruth(bvh, name, &Method::Paper(Default::default())).unwrap();
        let contact = evaluate_groundtruth(bvh, name, &Method::default()).unwrap();
        eprintln!("{name}: paper {paper:?}\n  contact {contact:?}");
        assert!(contact.mean_error_pct < paper.mean_error_pct / 4.0, "{name}");
        assert!((0.9..1.1).contains(&contact.path_ratio), "{name}: {}", contact.path_ratio);
        assert!(contact.skating_cm_per_s < 2.0, "{name}: {}", contact.skating_cm_per_s);
    }
}

#[test]
fn contact_closes_heian_shodan_better_than_paper() {
    let Some(dir) = common::data_dir() else { return };
    let mut recording = common::open(&dir, "karate/heian_shodan.bvh");
    recording.attach_accel(common::open_accel(&dir, "karate/heian_shodan.accel.csv")).unwrap();
    let paper = kata_closure_cm(&recording, &Method::Paper(Default::default())).unwrap();
    let contact = kata_closure_cm(&recording, &Method::default()).unwrap();
    eprintln!("heian_shodan closure: paper {paper:.1} cm, contact {contact:.1} cm");
    assert!(contact < paper && contact < 15.0, "{contact} vs {paper}");
}
