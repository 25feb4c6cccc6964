//! A camera frame made in code, for the image pipeline's tests and bench
//! (the same pixels on every target), and the time of each stage, measured
//! the same way natively (`cargo bench --bench image`) and in the browser
//! (the wasm test).

use std::hint::black_box;

use embusen::image::GreyImage;
use embusen::image::background::{difference, foreground};
use embusen::image::canny::{CannyParams, canny};
use embusen::image::distance::distance_to;
use embusen::image::pipeline::{Features, PipelineParams, canny_input, clean_mask, features};
use embusen::synth::rng::XorShift64;

/// A room and the same room with an actor in it, made in code: a plank
/// floor under a lit wall, Gaussian sensor noise (σ = 2 levels) drawn anew
/// for each image, and in the frame an elliptic body with a head, an arm
/// across it brighter than the body, and a faint shadow at its feet.
pub fn synthetic_scene(width_px: u32, height_px: u32) -> (GreyImage, GreyImage) {
    let mut rng = XorShift64(0x9e37_79b9_7f4a_7c15);
    let (w, h) = (width_px as f64, height_px as f64);
    let room = |x: f64, y: f64| {
        if y < 0.3 * h { 170.0 + 20.0 * x / w } else { 90.0 + 25.0 * ((x / 9.0 + y / 3.0) as i64 % 3) as f64 }
    };
    let noisy =
        |level: f64, rng: &mut XorShift64| (level + 2.0 * rng.gaussian()).round().clamp(0.0, 255.0) as u8;
    let mut background = Vec::new();
    let mut frame = Vec::new();
    let (cx, cy) = (0.45 * w, 0.55 * h);
    // Squares as products, not `powi`: the same bits on every target.
    let square = |v: f64| v * v;
    for y in 0..height_px {
        for x in 0..width_px {
            let (x, y) = (x as f64, y as f64);
            background.push(noisy(room(x, y), &mut rng));
            let body = square((x - cx) / (0.08 * w)) + square((y - cy) / (0.25 * h)) <= 1.0;
            let head = square(x - cx) + square(y - (cy - 0.32 * h)) <= square(0.05 * h);
            let arm = (y - (cy - 0.05 * h)).abs() < 0.025 * h && (x - (cx + 0.04 * w)).abs() < 0.1 * w;
            let shadow =
                square((x - cx - 0.05 * w) / (0.12 * w)) + square((y - cy - 0.26 * h) / (0.03 * h)) <= 1.0;
            let level = if arm {
                200.0
            } else if body || head {
                40.0
            } else if shadow {
                room(x, y) - 15.0
            } else {
                room(x, y)
            };
            frame.push(noisy(level, &mut rng));
        }
    }
    (
        GreyImage::new(width_px, height_px, frame, "synthetic frame").unwrap(),
        GreyImage::new(width_px, height_px, background, "synthetic background").unwrap(),
    )
}

/// The mean ms of one run of `f` in the fastest of 9 batches of 3 runs,
/// after one to warm up: batches, because a browser's clock is coarse; the
/// fastest, because a shared machine is seldom idle throughout, and what
/// the code costs is what it takes when nothing else runs.
fn batch_ms(now_ms: &dyn Fn() -> f64, mut f: impl FnMut()) -> f64 {
    f();
    (0..9)
        .map(|_| {
            let start = now_ms();
            for _ in 0..3 {
                f();
            }
            (now_ms() - start) / 3.0
        })
        .fold(f64::INFINITY, f64::min)
}

/// Each stage of the default pipeline on `frame` against `background`, and
/// the whole, in ms per run, timed by the clock `now_ms`.
pub fn stage_times(
    frame: &GreyImage,
    background: &GreyImage,
    now_ms: &dyn Fn() -> f64,
) -> Vec<(&'static str, f64)> {
    let params = PipelineParams::default();
    let d = difference(frame, background, "frame").unwrap();
    let level = params.threshold.level(&d);
    let raw = foreground(&d, level);
    let mask = clean_mask(&raw, &params);
    let input = canny_input(&d, &mask, params.edges_of);
    let canny_params = CannyParams {
        sigma_px: params.canny_sigma_px,
        low_step: level as f32 / 2.0,
        high_step: level as f32,
    };
    let edges = canny(&input, &canny_params);
    let made = features(frame, background, &params, "frame").unwrap();
    let bytes = made.to_bytes();
    vec![
        ("difference", batch_ms(now_ms, || drop(black_box(difference(frame, background, "frame").unwrap())))),
        ("noise + threshold", batch_ms(now_ms, || _ = black_box(params.threshold.level(black_box(&d))))),
        ("foreground", batch_ms(now_ms, || drop(black_box(foreground(&d, level))))),
        ("open + close", batch_ms(now_ms, || drop(black_box(clean_mask(&raw, &params))))),
        ("canny", batch_ms(now_ms, || drop(black_box(canny(&input, &canny_params))))),
        ("edge distance", batch_ms(now_ms, || drop(black_box(distance_to(&edges))))),
        ("outside distance", batch_ms(now_ms, || drop(black_box(distance_to(&mask))))),
        (
            "whole pipeline",
            batch_ms(now_ms, || drop(black_box(features(frame, background, &params, "frame").unwrap()))),
        ),
        // What the page's tracker hands its path scorer, and what that reads.
        ("features → bytes", batch_ms(now_ms, || drop(black_box(made.to_bytes())))),
        (
            "bytes → features",
            batch_ms(now_ms, || drop(black_box(Features::from_bytes(&bytes, "frame").unwrap()))),
        ),
    ]
}
