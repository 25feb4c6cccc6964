//! `cargo bench --bench track`: ms per 640×480 frame of the shared `walk`
//! scene for the image pipeline alone and for each tracker (pipeline
//! included), side by side, and the fused tracker's ratio to the faithful
//! one. Native only; the trackers do not run in the browser yet. Prints
//! figures; asserts nothing.

// A benchmark may panic on what it does not expect.
#![allow(clippy::unwrap_used, clippy::expect_used)]

use std::path::Path;
use std::time::Instant;

use embusen::body::shape::BodyShape;
use embusen::camera::Camera;
use embusen::image::pipeline::{PipelineParams, features};
use embusen::io::image_file::open_png_grey;
use embusen::io::recording::Recording;
use embusen::io::video::Ffmpeg;
use embusen::track::paper::PaperTrackParams;
use embusen::track::suit_motion::{SuitMotion, VideoTiming};
use embusen::track::tracker::{FusedParams, TrackMethod, TrackSetup, Tracker};

fn main() {
    let dir = Path::new(env!("CARGO_MANIFEST_DIR")).join("../shared/data/optical");
    if !dir.is_dir() {
        println!("SKIPPED: {} not found; the tracker bench did not run", dir.display());
        return;
    }
    let path = |s: &str| dir.join(format!("walk{s}"));
    let camera = Camera::from_json(&std::fs::read_to_string(path(".camera.json")).unwrap(), "walk").unwrap();
    let recording = Recording::parse(&std::fs::read(path(".suit.bvh")).unwrap(), "walk", None).unwrap();
    let background = open_png_grey(&path(".background.png")).unwrap();
    let mut video = Ffmpeg::default().open(&path(".mp4")).unwrap();
    let fps = video.info.fps;
    let mut frames = Vec::new();
    while let Some(frame) = video.next_frame() {
        frames.push(frame.unwrap());
    }
    let suit = SuitMotion::new(&recording).unwrap();
    let shape =
        BodyShape::standard(&recording.joint_names, &recording.parents, recording.poses.frame(0)).unwrap();
    let n = frames.len();
    let started = Instant::now();
    for frame in &frames {
        std::hint::black_box(features(frame, &background, &PipelineParams::default(), "frame").unwrap());
    }
    let pipeline_ms = 1e3 * started.elapsed().as_secs_f64() / n as f64;
    let per_frame_ms = |method: TrackMethod| {
        let setup = TrackSetup {
            camera,
            suit: suit.clone(),
            shape: shape.clone(),
            timing: VideoTiming { fps, frame_count: n, offset_s: 0.0 },
            background: background.clone(),
            pipeline: PipelineParams::default(),
            method,
        };
        let mut tracker = Tracker::new(setup).unwrap();
        let started = Instant::now();
        for frame in &frames {
            tracker.push_frame(frame).unwrap();
        }
        std::hint::black_box(tracker.finish());
        1e3 * started.elapsed().as_secs_f64() / n as f64
    };
    let paper_ms = per_frame_ms(TrackMethod::Paper(PaperTrackParams::default()));
    let fused_ms = per_frame_ms(TrackMethod::Fused(FusedParams::default()));
    println!(
        "walk, {n} frames of {}×{}, native, ms per frame:",
        camera.image_size.width_px, camera.image_size.height_px
    );
    println!("  image pipeline {pipeline_ms:7.2}");
    println!("  paper tracker  {paper_ms:7.2}  (pipeline included)");
    println!(
        "  fused tracker  {fused_ms:7.2}  (pipeline included); fused / paper = {:.2}",
        fused_ms / paper_ms
    );
}
