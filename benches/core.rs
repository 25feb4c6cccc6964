//! `cargo bench`: throughput of the readers and speed of both translation
//! methods on the shared karate recordings. Prints figures; asserts nothing (speed goals
//! are read off this output, not enforced by timed tests).

// A benchmark may panic on what it does not expect.
#![allow(clippy::unwrap_used, clippy::expect_used)]

use std::path::Path;
use std::time::{Duration, Instant};

use embusen::body::kinematics::forward_kinematics;
use embusen::io::bvh::{Bvh, ReadOptions};
use embusen::io::recording::{FeetChoice, Recording};
use embusen::io::table::Table;
use embusen::translate::contact::ContactParams;
use embusen::translate::hachaj::HachajParams;

/// Median wall time of `f` over enough runs to fill about half a second.
fn median_time(mut f: impl FnMut()) -> Duration {
    f(); // warm up caches and the allocator
    let mut times = Vec::new();
    let start = Instant::now();
    while times.len() < 5 || (start.elapsed() < Duration::from_millis(500) && times.len() < 1000) {
        let t = Instant::now();
        f();
        times.push(t.elapsed());
    }
    times.sort();
    times[times.len() / 2]
}

fn mb_per_s(bytes: usize, t: Duration) -> f64 {
    bytes as f64 / 1e6 / t.as_secs_f64()
}

fn main() {
    let data = Path::new(env!("CARGO_MANIFEST_DIR")).join("../shared/data/karate");
    if !data.is_dir() {
        // A benchmark is not a test: without the data it has nothing to
        // measure, says so and ends, in CI too.
        eprintln!("SKIPPED: {} not found; the benchmarks did not run", data.display());
        return;
    }
    let read = |name: &str| std::fs::read(data.join(name)).expect("shared data file");

    let nidan = read("heian_nidan.bvh");
    let t = median_time(|| {
        std::hint::black_box(Bvh::parse(&nidan, "heian_nidan.bvh", &ReadOptions::default()).expect("parses"));
    });
    println!(
        "BVH read      heian_nidan.bvh ({:.2} MB): {:7.3} ms  {:7.1} MB/s",
        nidan.len() as f64 / 1e6,
        t.as_secs_f64() * 1e3,
        mb_per_s(nidan.len(), t)
    );
    let bvh = Bvh::parse(&nidan, "heian_nidan.bvh", &ReadOptions::default()).expect("parses");
    let t = median_time(|| {
        std::hint::black_box(forward_kinematics(&bvh.skeleton, &bvh.motion));
    });
    println!(
        "FK            heian_nidan.bvh ({} frames): {:7.3} ms  {:7.0} frames/s",
        bvh.motion.frame_count(),
        t.as_secs_f64() * 1e3,
        bvh.motion.frame_count() as f64 / t.as_secs_f64()
    );

    let table_bytes = read("heian_shodan.csv");
    let t = median_time(|| {
        std::hint::black_box(Table::parse(&table_bytes, "heian_shodan.csv").expect("parses"));
    });
    println!(
        "table read    heian_shodan.csv ({:.2} MB): {:7.3} ms  {:7.1} MB/s",
        table_bytes.len() as f64 / 1e6,
        t.as_secs_f64() * 1e3,
        mb_per_s(table_bytes.len(), t)
    );

    let recording = Recording::parse(&table_bytes, "heian_shodan.csv", None).expect("parses");
    let params = HachajParams::default();
    let feet = FeetChoice::default();
    let t = median_time(|| {
        std::hint::black_box(recording.translate_hachaj(&feet, &params).expect("runs"));
    });
    println!(
        "paper method  heian_shodan.csv ({} frames, faithful): {:7.3} ms  {:9.0} frames/s",
        recording.frame_count(),
        t.as_secs_f64() * 1e3,
        recording.frame_count() as f64 / t.as_secs_f64()
    );

    // The contact method estimates the sole depth by solving once per
    // candidate depth; with the depth given it solves once.
    let paper_t = t;
    for (label, sole_depth_cm) in [("estimated sole", None), ("sole given", Some(2.0))] {
        let params = ContactParams { sole_depth_cm, ..ContactParams::default() };
        let t = median_time(|| {
            std::hint::black_box(recording.translate_contact(&feet, &params).expect("runs"));
        });
        println!(
            "contact method heian_shodan.csv ({label}): {:7.3} ms  {:9.0} frames/s  ({:.1}x the paper method)",
            t.as_secs_f64() * 1e3,
            recording.frame_count() as f64 / t.as_secs_f64(),
            t.as_secs_f64() / paper_t.as_secs_f64()
        );
    }
}
