//! A take filmed in code, for the tracker tests native and in the browser:
//! the built-in demo's true motion rendered with a known camera over a
//! textured room, and the helpers that track it.

use embusen::body::shape::BodyShape;
use embusen::camera::{Camera, Distortion, ImageSize, Intrinsics};
use embusen::image::GreyImage;
use embusen::image::pipeline::PipelineParams;
use embusen::io::bvh::Bvh;
use embusen::io::recording::{FeetChoice, Recording};
use embusen::synth::demo::demo;
use embusen::track::fused::FusedParams;
use embusen::track::path_scorer::PathScorer;
use embusen::track::setup::TrackSetup;
use embusen::track::silhouette::SilhouetteRenderer;
use embusen::track::suit_motion::{SuitMotion, VideoTiming};
use embusen::track::tracker::{Track, TrackMethod, Tracker};
use glam::{DAffine3, DMat3, DVec2, DVec3};

/// A camera 6 m from `target` along −Z and 1.6 m up, looking at it, with a
/// mild barrel lens, for images of `size` (not 640×480 on purpose).
pub fn camera_looking_at(target: DVec3, size: ImageSize) -> Camera {
    let centre = target + DVec3::new(80.0, 160.0 - target.y, -600.0);
    let forward = (target - centre).normalize();
    let right = forward.cross(DVec3::Y).normalize();
    let down = forward.cross(right);
    let world_from_camera = DAffine3::from_mat3_translation(DMat3::from_cols(right, down, forward), centre);
    let focal = 0.9 * size.width_px as f64;
    Camera {
        image_size: size,
        intrinsics: Intrinsics {
            fx_px: focal,
            fy_px: focal,
            cx_px: (size.width_px as f64 - 1.0) / 2.0,
            cy_px: (size.height_px as f64 - 1.0) / 2.0,
        },
        distortion: Distortion { k1: -0.03, ..Distortion::default() },
        camera_from_world: world_from_camera.inverse(),
    }
}

/// A textured room: smooth shading and a pattern, so that edges are not only
/// the actor's.
pub fn room(size: ImageSize) -> GreyImage {
    let (w, h) = (size.width_px, size.height_px);
    let pixels = (0..h)
        .flat_map(|y| {
            (0..w).map(move |x| {
                let stripe = if (x / 23 + y / 31) % 2 == 0 { 12.0 } else { 0.0 };
                (150.0 + 30.0 * (y as f64 / h as f64) + stripe) as u8
            })
        })
        .collect();
    GreyImage::new(w, h, pixels, "room").unwrap()
}

/// The demo's true motion filmed: per video frame (at `video_fps`, the BVH
/// at 100 Hz) the true body's silhouette painted dark over the room, and the
/// true hips' floor position; the video starts `offset_s` into the BVH.
pub fn film(
    video_fps: f64,
    seconds: f64,
    size: ImageSize,
    offset_s: f64,
) -> (Recording, Camera, GreyImage, Vec<GreyImage>, Vec<DVec2>) {
    let demo = demo();
    let truth = Recording::from_bvh(
        Bvh { skeleton: demo.true_skeleton.clone(), motion: demo.true_motion.clone(), warnings: Vec::new() },
        "truth",
    );
    let feet = truth.feet(&FeetChoice::default()).unwrap();
    let hips = truth.hips(feet);
    let start = truth.poses.at(0, hips);
    let camera = camera_looking_at(DVec3::new(start.x, 90.0, start.z), size);
    let shape = BodyShape::standard(&truth.joint_names, &truth.parents, truth.poses.frame(0)).unwrap();
    let mut renderer = SilhouetteRenderer::new(&camera);
    let background = room(size);
    let mut frames = Vec::new();
    let mut true_floor = Vec::new();
    let count = (seconds * video_fps) as usize;
    for i in 0..count {
        let f = ((i as f64 / video_fps + offset_s) * truth.fps).round() as usize;
        let body = shape.pose(truth.poses.frame(f), DVec3::ZERO).unwrap();
        let silhouette = renderer.render(&body, DVec3::ZERO);
        let mut frame = background.clone();
        for span in &silhouette.spans {
            let row = span.row as usize * size.width_px as usize;
            for x in span.start..span.end {
                frame.pixels[row + x as usize] = 60 + (x % 5) as u8;
            }
        }
        frames.push(frame);
        let p = truth.poses.at(f, hips);
        true_floor.push(DVec2::new(p.x, p.z));
    }
    (demo.recording(), camera, background, frames, true_floor)
}

pub fn setup(
    recording: &Recording,
    camera: Camera,
    background: &GreyImage,
    frames: &[GreyImage],
    fps: f64,
) -> TrackSetup {
    let suit = SuitMotion::new(recording).unwrap();
    let shape =
        BodyShape::standard(&recording.joint_names, &recording.parents, recording.poses.frame(0)).unwrap();
    TrackSetup {
        camera,
        suit: suit.into(),
        shape,
        timing: VideoTiming { fps, frame_count: frames.len(), offset_s: 0.0 },
        background: background.clone(),
        pipeline: PipelineParams::default(),
    }
}

pub fn track(
    recording: &Recording,
    camera: Camera,
    background: &GreyImage,
    frames: &[GreyImage],
    fps: f64,
    method: TrackMethod,
) -> Track {
    run(setup(recording, camera, background, frames, fps), method, frames)
}

pub fn run(setup: TrackSetup, method: TrackMethod, frames: &[GreyImage]) -> Track {
    let mut tracker = Tracker::new(setup, method).unwrap();
    for frame in frames {
        tracker.push_frame(frame).unwrap();
    }
    tracker.finish()
}

/// [`run`] with the fused tracker's path energies scored apart, from each
/// frame, by a [`PathScorer`] of the same take (as the page's second worker
/// and the CLI's second thread score them), handed back at once.
pub fn run_with_scorer_apart(setup: TrackSetup, params: FusedParams, frames: &[GreyImage]) -> Track {
    let mut scorer = PathScorer::new(setup.clone(), params);
    let mut tracker = Tracker::new(setup, TrackMethod::Fused(params)).unwrap();
    tracker.defer_path_energies();
    for frame in frames {
        tracker.push_frame(frame).unwrap();
        if let Some((request, _)) = tracker.take_path_work() {
            let energies = scorer.energies(&request, frame).unwrap();
            tracker.set_path_energies(request.frame, energies).unwrap();
        }
    }
    tracker.finish()
}

pub fn mean_error_cm(track: &Track, truth: &[DVec2], start_offset: DVec2) -> f64 {
    track.frames.iter().zip(truth).map(|(f, t)| (f.floor_cm - (*t - start_offset)).length()).sum::<f64>()
        / truth.len() as f64
}
