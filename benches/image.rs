//! `cargo bench --bench image`: ms per frame for each stage of the image
//! pipeline and for the whole: on the synthetic 640×480 scene the wasm test
//! times in the browser (`tests/image.rs`), on a real frame of the shared
//! `walk` scene against its background still (640×480), and on that frame
//! scaled up to 1280×720 and 1920×1080 (with a noise of their own), so the
//! figures show how it scales. Prints figures; asserts nothing.

// A benchmark may panic on what it does not expect.
#![allow(clippy::unwrap_used, clippy::expect_used)]

use std::hint::black_box;
use std::path::Path;
use std::sync::OnceLock;
use std::time::Instant;

use embusen::image::GreyImage;
use embusen::image::background::median_background;
use embusen::io::image_file::open_png_grey;
use embusen::io::video::{Ffmpeg, sample_frames};
use embusen::synth::rng::XorShift64;

#[path = "../tests/common/image_scene.rs"]
mod image_scene;

/// The benchmark's clock: ms since the first call.
fn now_ms() -> f64 {
    static START: OnceLock<Instant> = OnceLock::new();
    START.get_or_init(Instant::now).elapsed().as_secs_f64() * 1e3
}

/// `image` resampled to `width_px × height_px` (bilinear, pixel centres
/// matched) with a fresh sensor noise of σ = 1.5 levels seeded by `seed`: a
/// larger frame of the same scene whose noise is per pixel, as a real
/// camera's is (a scaled-up noise would be blobs the opening keeps).
fn resized(image: &GreyImage, width_px: u32, height_px: u32, seed: u64) -> GreyImage {
    let mut rng = XorShift64(seed);
    let (sw, sh) = (image.width_px as f64, image.height_px as f64);
    let mut pixels = Vec::with_capacity(width_px as usize * height_px as usize);
    for y in 0..height_px {
        let fy = ((y as f64 + 0.5) * sh / height_px as f64 - 0.5).clamp(0.0, sh - 1.0);
        for x in 0..width_px {
            let fx = ((x as f64 + 0.5) * sw / width_px as f64 - 0.5).clamp(0.0, sw - 1.0);
            let (x0, y0) = (fx as u32, fy as u32);
            let (x1, y1) = ((x0 + 1).min(image.width_px - 1), (y0 + 1).min(image.height_px - 1));
            let (ax, ay) = (fx - x0 as f64, fy - y0 as f64);
            let top = image.at(x0, y0) as f64 * (1.0 - ax) + image.at(x1, y0) as f64 * ax;
            let bottom = image.at(x0, y1) as f64 * (1.0 - ax) + image.at(x1, y1) as f64 * ax;
            let level = top * (1.0 - ay) + bottom * ay + 1.5 * rng.gaussian();
            pixels.push(level.round().clamp(0.0, 255.0) as u8);
        }
    }
    GreyImage::new(width_px, height_px, pixels, "resized").unwrap()
}

fn print_stages(label: &str, frame: &GreyImage, background: &GreyImage) {
    for (stage, ms) in image_scene::stage_times(frame, background, &now_ms) {
        println!("{label:>22}  {stage:<18} {ms:7.3} ms");
    }
}

fn main() {
    // The scene the wasm test times in the browser, for the two side by side.
    let (frame, background) = image_scene::synthetic_scene(640, 480);
    println!("image pipeline, ms per frame (the fastest of 9 batches of 3 runs):");
    print_stages("synthetic 640×480", &frame, &background);
    let data = Path::new(env!("CARGO_MANIFEST_DIR")).join("../shared/data/optical");
    if !data.is_dir() {
        // A benchmark is not a test: without the data it has nothing more
        // to measure, says so and ends, in CI too.
        eprintln!("SKIPPED: {} not found; the benchmarks on a real frame did not run", data.display());
        return;
    }
    let background = open_png_grey(&data.join("walk.background.png")).unwrap();
    let mut video = match Ffmpeg::default().open(&data.join("walk.mp4")) {
        Ok(video) => video,
        Err(e) => {
            eprintln!("SKIPPED: {e}; the benchmarks on a real frame did not run");
            return;
        }
    };
    let count = video.info.frame_count;
    // Frame 60: the actor well inside the picture.
    let frame = video.nth(60).unwrap().unwrap();
    print_stages("walk.mp4 640×480", &frame, &background);
    for (w, h) in [(1280, 720), (1920, 1080)] {
        let label = format!("walk scaled {w}×{h}");
        print_stages(&label, &resized(&frame, w, h, 1), &resized(&background, w, h, 2));
    }
    let t = Instant::now();
    let sampled = sample_frames(Ffmpeg::default().open(&data.join("walk.mp4")).unwrap(), count, 15).unwrap();
    let decode = t.elapsed();
    let t = Instant::now();
    black_box(median_background(&sampled, "walk.mp4").unwrap());
    let median = t.elapsed();
    println!(
        "median background of 15 frames of 640×480: {:.1} ms (decoding all {count} frames to pick them: {:.0} ms, {:.2} ms per frame)",
        median.as_secs_f64() * 1e3,
        decode.as_secs_f64() * 1e3,
        decode.as_secs_f64() * 1e3 / count as f64
    );
}
