//! `cargo bench --bench track`: ms per 640×480 frame of the shared `walk`
//! scene for the image pipeline alone and for each tracker (pipeline
//! included), side by side, the fused tracker's ratio to the faithful
//! one, and the fused tracker over walk's two views (both tracked, then
//! weighed: `track::views`) against one view. Native; `tests/track_browser.rs` prints the same trackers' times in
//! the browser. Prints figures; asserts nothing.

// A benchmark may panic on what it does not expect.
#![allow(clippy::unwrap_used, clippy::expect_used)]

use std::path::Path;
use std::time::Instant;

use embusen::image::pipeline::{PipelineParams, features};
use embusen::track::fused::FusedParams;
use embusen::track::riecicky::RiecickyParams;
use embusen::track::suit_motion::VideoTiming;
use embusen::track::tracker::TrackMethod;
use embusen::track::views::{ViewSightings, fuse_views};

#[allow(dead_code)]
#[path = "../tests/common/filmed.rs"]
mod filmed;
#[path = "../tests/common/optical.rs"]
mod optical;

fn main() {
    let dir = Path::new(env!("CARGO_MANIFEST_DIR")).join("../shared/data/optical");
    if !dir.is_dir() {
        println!("SKIPPED: {} not found; the tracker bench did not run", dir.display());
        return;
    }
    let scene = optical::open_scene(&dir, "walk");
    let (frames, background) = (&scene.frames, &scene.background);
    let n = frames.len();
    let started = Instant::now();
    for frame in frames {
        std::hint::black_box(features(frame, background, &PipelineParams::default(), "frame").unwrap());
    }
    let pipeline_ms = 1e3 * started.elapsed().as_secs_f64() / n as f64;
    let per_frame_ms = |method: TrackMethod| {
        let setup = filmed::setup(&scene.recording, scene.camera, background, frames, scene.fps);
        let started = Instant::now();
        std::hint::black_box(filmed::run(setup, method, frames));
        1e3 * started.elapsed().as_secs_f64() / n as f64
    };
    let paper_ms = per_frame_ms(TrackMethod::Riecicky(RiecickyParams::default()));
    let fused_ms = per_frame_ms(TrackMethod::Fused(FusedParams::default()));
    let size = scene.camera.image_size;
    println!("walk, {n} frames of {}×{}, native, ms per frame:", size.width_px, size.height_px);
    println!("  image pipeline {pipeline_ms:7.2}");
    println!("  paper tracker  {paper_ms:7.2}  (pipeline included)");
    println!(
        "  fused tracker  {fused_ms:7.2}  (pipeline included); fused / paper = {:.2}",
        fused_ms / paper_ms
    );
    let second_dir = dir.join("second_view");
    if !second_dir.is_dir() {
        println!("SKIPPED: {} not found; no two-view figure", second_dir.display());
        return;
    }
    // Two views: each tracked as one is, then weighed together; the time
    // per frame of the first view's video, both views' work in it.
    let second = optical::open_scene(&second_dir, "walk");
    let fused = TrackMethod::Fused(FusedParams::default());
    let started = Instant::now();
    let tracks = [&scene, &second].map(|s| {
        let setup = filmed::setup(&s.recording, s.camera, &s.background, &s.frames, s.fps);
        filmed::run(setup, fused, &s.frames)
    });
    let timings =
        [&scene, &second].map(|s| VideoTiming { fps: s.fps, frame_count: s.frames.len(), offset_s: 0.0 });
    std::hint::black_box(fuse_views(&tracks[0], &timings[0], &[ViewSightings::of(&tracks[1], timings[1])]));
    let two_ms = 1e3 * started.elapsed().as_secs_f64() / n as f64;
    println!(
        "  two views      {two_ms:7.2}  (both pipelines and trackers); two / one view = {:.2}",
        two_ms / fused_ms
    );
}
