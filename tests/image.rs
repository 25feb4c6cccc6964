//! The image pipeline: every stage the same bytes natively and in the
//! browser (a digest per stage, checked on both targets), the distance
//! transform exact against brute force, the readers' bad input errors and
//! not panics, and on the shared optical scenes the foreground and the edges
//! where the true camera puts the true actor.

// A test may panic on what it does not expect: that is how it fails.
#![allow(clippy::unwrap_used, clippy::expect_used)]

use embusen::image::pipeline::{Features, PipelineParams, features};
use embusen::image::{Mask, distance};
use embusen::synth::rng::XorShift64;

mod common;

use common::image_scene::synthetic_scene;

#[cfg(target_arch = "wasm32")]
wasm_bindgen_test::wasm_bindgen_test_configure!(run_in_browser);

fn synthetic_features() -> Features {
    let (frame, background) = synthetic_scene(161, 117);
    features(&frame, &background, &PipelineParams::default(), "synthetic").unwrap()
}

/// The digests the native build computes of each stage of the synthetic
/// scene (difference, foreground, edges, edge distance, outside distance);
/// the wasm test checks that the browser computes the same. Not results to
/// keep: a change to the pipeline changes them, and they are updated from
/// the native test's message.
const STAGE_DIGESTS: [u64; 5] = [
    0x486a_3776_cbd2_1372,
    0x44e9_0789_40e4_1195,
    0x90fd_5a86_64d0_4df8,
    0x835c_694f_a080_d60d,
    0xbe3e_061d_9dac_6501,
];

#[cfg_attr(not(target_arch = "wasm32"), test)]
#[cfg_attr(target_arch = "wasm32", wasm_bindgen_test::wasm_bindgen_test)]
fn every_stage_is_the_same_bytes_on_every_target() {
    let features = synthetic_features();
    let digests = features.digests();
    let stages = ["difference", "foreground", "edges", "edge distance", "outside distance"];
    for ((stage, got), want) in stages.iter().zip(digests).zip(STAGE_DIGESTS) {
        assert_eq!(got, want, "{stage}: digest {got:#018x}, committed {want:#018x}; all: {digests:#018x?}");
    }
}

#[cfg_attr(not(target_arch = "wasm32"), test)]
#[cfg_attr(target_arch = "wasm32", wasm_bindgen_test::wasm_bindgen_test)]
fn the_synthetic_actor_is_found_and_the_noise_is_measured() {
    let f = synthetic_features();
    // σ of a difference of two images with σ = 2 each: 2√2.
    assert!((f.noise_sd - 2.83).abs() < 0.3, "noise {}", f.noise_sd);
    assert_eq!(f.threshold_level, (4.0 * f.noise_sd).ceil() as u8);
    let (w, h) = (161.0, 117.0);
    let centre = ((0.45 * w) as u32, (0.55 * h) as u32);
    assert!(f.foreground.at(centre.0, centre.1));
    assert!(!f.foreground.at(2, 2) && !f.foreground.at(158, 114));
    assert!(f.edges.count() > 100, "{} edge pixels", f.edges.count());
    assert!(f.edge_distance.at(centre.0, centre.1) > 0.0);
    assert_eq!(f.outside_distance.at(centre.0, centre.1), 0.0);
    assert!(f.outside_distance.at(2, 2) > 20.0);
}

/// The squared distance to the nearest on pixel by trying them all.
fn brute_force_px2(mask: &Mask) -> Vec<u32> {
    let w = mask.width_px as i64;
    let on: Vec<(i64, i64)> =
        (0..mask.on.len() as i64).filter(|&i| mask.on[i as usize]).map(|i| (i % w, i / w)).collect();
    (0..mask.on.len() as i64)
        .map(|i| {
            let (x, y) = (i % w, i / w);
            on.iter().map(|&(a, b)| ((x - a).pow(2) + (y - b).pow(2)) as u32).min().unwrap_or(distance::NONE)
        })
        .collect()
}

#[cfg_attr(not(target_arch = "wasm32"), test)]
#[cfg_attr(target_arch = "wasm32", wasm_bindgen_test::wasm_bindgen_test)]
fn the_distance_transform_is_exact() {
    let mut rng = XorShift64(0x2545_f491_4f6c_dd1d);
    let mut uniform = |n: f64| ((rng.symmetric() + 1.0) / 2.0 * n) as u32;
    for case in 0..400 {
        let (w, h) = (1 + uniform(29.0), 1 + uniform(23.0));
        // From nearly empty to nearly full, and now and then all empty.
        let density = uniform(70.0) as f64 / 100.0;
        let mut on_rng = XorShift64(0x1234_5678 + case);
        let on = (0..w * h).map(|_| (on_rng.symmetric() + 1.0) / 2.0 < density).collect();
        let mask = Mask { width_px: w, height_px: h, on };
        let exact = distance::squared_distance_px2(&mask);
        assert_eq!(exact, brute_force_px2(&mask), "case {case}: {w}×{h}, density {density}");
        let rooted = distance::distance_to(&mask);
        for (d, d2) in rooted.distance_px.iter().zip(&exact) {
            let want = if *d2 == distance::NONE { f32::INFINITY } else { (*d2 as f64).sqrt() as f32 };
            assert_eq!(*d, want);
        }
        for max_px in [0.0, 1.0, 2.5, 7.0, 100.0] {
            let truncated = distance::distance_to_truncated(&mask, max_px);
            assert_eq!(truncated, rooted.truncated(max_px), "case {case}: truncated at {max_px}");
        }
    }
}

/// The time of each stage per 640×480 frame of the synthetic scene in the
/// browser, printed (run with `-- --nocapture`) beside what
/// `cargo bench --bench image` prints for the same scene natively. Asserts
/// nothing of the times: a test is no benchmark.
#[cfg(target_arch = "wasm32")]
#[wasm_bindgen_test::wasm_bindgen_test]
fn the_stage_times_in_the_browser() {
    use wasm_bindgen::JsCast;
    let performance = js_sys::Reflect::get(&js_sys::global(), &"performance".into()).unwrap();
    let now: js_sys::Function =
        js_sys::Reflect::get(&performance, &"now".into()).unwrap().dyn_into().unwrap();
    let now_ms = || now.call0(&performance).unwrap().as_f64().unwrap();
    let (frame, background) = synthetic_scene(640, 480);
    for (stage, ms) in common::image_scene::stage_times(&frame, &background, &now_ms) {
        wasm_bindgen_test::console_log!("wasm synthetic 640×480  {stage:<18} {ms:7.3} ms");
    }
}

/// The readers, and the shared scenes (native: files and ffmpeg).
#[cfg(not(target_arch = "wasm32"))]
mod native {
    use std::path::{Path, PathBuf};

    use crate::common::Scratch;

    use embusen::camera::Camera;
    use embusen::image::pipeline::{PipelineParams, features};
    use embusen::image::{GreyImage, background};
    use embusen::io::image_file::{ImageSequence, open_png_grey, png_to_grey};
    use embusen::io::video::{Ffmpeg, sample_frames};
    use glam::{DVec2, DVec3};

    fn png_bytes(image: &GreyImage) -> Vec<u8> {
        let mut bytes = Vec::new();
        let mut encoder = png::Encoder::new(&mut bytes, image.width_px, image.height_px);
        encoder.set_color(png::ColorType::Grayscale);
        let mut writer = encoder.write_header().unwrap();
        writer.write_image_data(&image.pixels).unwrap();
        writer.finish().unwrap();
        bytes
    }

    fn optical() -> Option<PathBuf> {
        Some(crate::common::data_dir()?.join("optical"))
    }

    #[test]
    fn a_truncated_png_is_an_error_naming_the_file() {
        let (frame, _) = super::synthetic_scene(40, 30);
        let bytes = png_bytes(&frame);
        // Cut anywhere before the closing 12-byte IEND chunk (without it the
        // pixels are all there, and the still is taken).
        for cut in (0..bytes.len() - 12).step_by(7) {
            let e = png_to_grey(&bytes[..cut], "still.png").unwrap_err();
            assert!(e.to_string().starts_with("still.png: "), "cut at {cut}: {e}");
        }
        assert_eq!(png_to_grey(&bytes, "still.png").unwrap(), frame);
        let e = open_png_grey(Path::new("/no/such/still.png")).unwrap_err();
        assert!(e.to_string().starts_with("/no/such/still.png: cannot read"), "{e}");
    }

    #[test]
    fn an_image_sequence_is_its_pngs_in_name_order() {
        let dir = Scratch::new("sequence");
        let frames: Vec<GreyImage> = (0..3u8).map(|i| GreyImage::filled(5, 4, 10 * i)).collect();
        // Written out of order, with a file that is not a frame.
        for (i, name) in [(2, "f10.png"), (0, "f08.png"), (1, "f09.PNG")] {
            std::fs::write(dir.join(name), png_bytes(&frames[i])).unwrap();
        }
        std::fs::write(dir.join("notes.txt"), "not a frame").unwrap();
        let sequence = ImageSequence::open(&dir, 24.0).unwrap();
        assert_eq!(sequence.frame_count(), 3);
        for (i, frame) in frames.iter().enumerate() {
            assert_eq!(&sequence.frame(i).unwrap(), frame);
        }
        assert!(sequence.frame(3).is_err());
        std::fs::write(dir.join("f11.png"), png_bytes(&GreyImage::filled(4, 4, 0))).unwrap();
        let e = ImageSequence::open(&dir, 24.0).unwrap().frame(3).unwrap_err();
        assert!(
            e.to_string().contains("f11.png: 4×4 pixels, where the sequence's first frame has 5×4"),
            "{e}"
        );
        assert!(ImageSequence::open(&dir, 0.0).is_err());
        assert!(
            ImageSequence::open(&Scratch::new("empty_sequence"), 30.0)
                .unwrap_err()
                .to_string()
                .contains("no .png")
        );
    }

    /// The browser reads a frame's luma plane from its decoder and makes it
    /// grey in Rust (`GreyImage::from_luma`), and so does the CLI from the
    /// plane ffmpeg decodes: that must be the grey `ffmpeg -pix_fmt gray`
    /// makes, for every luma level, in limited and in full range, or the
    /// tracks would depend on who converted the frames.
    #[test]
    fn grey_from_a_luma_plane_is_ffmpegs_grey_for_every_level() {
        let (w, h) = (256usize, 2usize);
        let luma: Vec<u8> = (0..w * h).map(|i| (i % w) as u8).collect();
        let dir = Scratch::new("luma");
        for (range, full) in [("LIMITED", false), ("FULL", true)] {
            // YUV4MPEG2: a header, then each frame's planes (4:2:0).
            let mut y4m =
                format!("YUV4MPEG2 W{w} H{h} F30:1 Ip A1:1 C420jpeg XCOLORRANGE={range}\n").into_bytes();
            for _ in 0..2 {
                y4m.extend_from_slice(b"FRAME\n");
                y4m.extend_from_slice(&luma);
                y4m.extend(std::iter::repeat_n(128u8, 2 * (w / 2) * (h / 2)));
            }
            let path = dir.join(format!("ramp-{range}.y4m"));
            std::fs::write(&path, y4m).unwrap();
            // ffmpeg is installed by ./build.sh, as for every video test.
            let converted = std::process::Command::new("ffmpeg")
                .args(["-nostdin", "-v", "error", "-i"])
                .arg(&path)
                .args(["-frames:v", "1", "-f", "rawvideo", "-pix_fmt", "gray", "-"])
                .output()
                .unwrap();
            assert!(converted.status.success(), "{}", String::from_utf8_lossy(&converted.stderr));
            let from_ffmpeg = GreyImage::new(w as u32, h as u32, converted.stdout, "ramp").unwrap();
            let ours = GreyImage::from_luma(w as u32, h as u32, &luma, w, full, "ramp").unwrap();
            assert_eq!(ours, from_ffmpeg, "{range}");
            let mut video = Ffmpeg::default().open(&path).unwrap();
            assert_eq!(video.next_frame().unwrap().unwrap(), from_ffmpeg, "{range}: the CLI's reader");
        }
        // Rows farther apart than the width (a decoder's padding) are read
        // row by row; a plane too short is an error.
        let padded: Vec<u8> = (0..3 * 8).map(|i| if i % 8 < 5 { 100 } else { 0 }).collect();
        let grey = GreyImage::from_luma(5, 3, &padded, 8, true, "padded").unwrap();
        assert!(grey.pixels.iter().all(|&g| g == 100));
        assert!(GreyImage::from_luma(5, 3, &padded[..20], 8, true, "short").is_err());
    }

    #[test]
    fn a_missing_ffmpeg_says_how_to_install_it() {
        let Some(dir) = optical() else { return };
        let missing = Ffmpeg { ffmpeg: "/no/such/ffmpeg".into(), ffprobe: "/no/such/ffprobe".into() };
        let video = dir.join("walk.mp4");
        let e = missing.probe(&video).unwrap_err().to_string();
        assert!(e.contains("/no/such/ffprobe not found") && e.contains("apt-get install ffmpeg"), "{e}");
        let only_probe = Ffmpeg { ffmpeg: "/no/such/ffmpeg".into(), ..Ffmpeg::default() };
        let e = only_probe.open(&video).err().unwrap().to_string();
        assert!(e.contains("/no/such/ffmpeg not found"), "{e}");
    }

    #[test]
    fn what_is_not_a_video_is_an_error_naming_the_file() {
        let dir = Scratch::new("not_video");
        let text = dir.join("notes.mp4");
        std::fs::write(&text, "these are words, not frames\n").unwrap();
        let e = Ffmpeg::default().open(&text).err().unwrap().to_string();
        assert!(e.starts_with(&format!("{}: not a video", text.display())), "{e}");
        let e = Ffmpeg::default().open(&dir.join("absent.mp4")).err().unwrap().to_string();
        assert!(e.ends_with("absent.mp4: no such file"), "{e}");
        // A video cut in half: frames up to the cut, then the end or an
        // error, never a panic.
        let Some(optical) = optical() else { return };
        let bytes = std::fs::read(optical.join("walk.webm")).unwrap();
        let cut = dir.join("cut.webm");
        std::fs::write(&cut, &bytes[..bytes.len() / 2]).unwrap();
        if let Ok(frames) = Ffmpeg::default().open(&cut) {
            let results: Vec<_> = frames.collect();
            assert!(results.iter().take_while(|r| r.is_ok()).count() > 10);
        }
    }

    #[test]
    fn a_video_streams_its_frames_and_a_median_of_them_is_the_room() {
        let Some(dir) = optical() else { return };
        let video = Ffmpeg::default().open(&dir.join("walk.mp4")).unwrap();
        let info = video.info;
        assert_eq!((info.width_px, info.height_px, info.fps), (640, 480, 30.0));
        let sampled = sample_frames(video, info.frame_count, 15).unwrap();
        assert_eq!(sampled.len(), 15);
        let median = background::median_background(&sampled, "walk.mp4").unwrap();
        let still = open_png_grey(&dir.join("walk.background.png")).unwrap();
        // The median room is the still but for the noise and the codec:
        // their difference is mostly within the threshold.
        let difference = background::difference(&median, &still, "median").unwrap();
        let level = background::Threshold::default().level(&difference);
        let off = background::foreground(&difference, level).count();
        assert!(off < still.pixels.len() / 100, "{off} pixels of the median differ from the still");
        // Every frame is read, in order, none held back.
        let frames = Ffmpeg::default().open(&dir.join("walk.webm")).unwrap();
        let read: Vec<usize> = frames.map(|f| f.unwrap().pixels.len()).collect();
        assert_eq!(read.len(), info.frame_count);
        assert!(read.iter().all(|&n| n == 640 * 480));
    }

    /// A shared scene's true camera, read from its `camera.json`.
    fn true_camera(path: &Path) -> Camera {
        Camera::from_json(&std::fs::read_to_string(path).unwrap(), &path.display().to_string()).unwrap()
    }

    /// The true hips (cm, world) per video frame.
    fn true_hips(path: &Path) -> Vec<DVec3> {
        let text = std::fs::read_to_string(path).unwrap();
        text.lines()
            .skip(1)
            .filter(|l| !l.trim().is_empty())
            .map(|l| {
                let v: Vec<f64> = l.split(',').map(|x| x.trim().parse().unwrap()).collect();
                DVec3::new(v[1], v[2], v[3])
            })
            .collect()
    }

    /// The share of on pixels of `mask` within `radius_px` of `centre`.
    fn share_on(mask: &embusen::image::Mask, centre: DVec2, radius_px: f64) -> f64 {
        let (mut on, mut all) = (0, 0);
        let r = radius_px.ceil() as i64;
        for dy in -r..=r {
            for dx in -r..=r {
                let (x, y) = (centre.x.round() as i64 + dx, centre.y.round() as i64 + dy);
                let inside = x >= 0 && y >= 0 && x < mask.width_px as i64 && y < mask.height_px as i64;
                if inside && ((dx * dx + dy * dy) as f64) <= radius_px * radius_px {
                    all += 1;
                    on += mask.at(x as u32, y as u32) as usize;
                }
            }
        }
        on as f64 / all.max(1) as f64
    }

    #[test]
    fn on_the_shared_scenes_the_foreground_and_the_edges_are_the_actor() {
        let Some(dir) = optical() else { return };
        let params = PipelineParams::default();
        for scene in ["walk", "walk_turns", "run", "slash"] {
            let camera = true_camera(&dir.join(format!("{scene}.camera.json")));
            let hips = true_hips(&dir.join(format!("{scene}.truth.csv")));
            let still = open_png_grey(&dir.join(format!("{scene}.background.png"))).unwrap();
            let video = Ffmpeg::default().open(&dir.join(format!("{scene}.mp4"))).unwrap();
            let (w, h) = (video.info.width_px as f64, video.info.height_px as f64);
            let mut checked = 0;
            for (f, frame) in video.enumerate().step_by(10) {
                let frame = frame.unwrap();
                let features = features(&frame, &still, &params, &format!("{scene} frame {f}")).unwrap();
                let Some(pixel) = camera.point_in_image(hips[f]) else { continue };
                if !camera.sees_pixel(pixel) {
                    continue;
                }
                // 8 cm about the hips centre lies within the pelvis from any
                // side; in pixels, from how far 8 cm across the view moves it.
                // Over 90 % of it is foreground on every frame of the four
                // scenes but 4 of 1 000 (82–88 %: the shirt's grey matches
                // the brick wall behind it).
                let across = camera.world_from_camera().transform_vector3(DVec3::X);
                let beside = camera.point_in_image(hips[f] + 8.0 * across).unwrap();
                let radius_px = (beside - pixel).length();
                let label = format!("{scene} frame {f}: hips at {pixel:.1}, {radius_px:.1} px about it");
                let x = pixel.x.round() as u32;
                let y = pixel.y.round() as u32;
                assert!(features.foreground.at(x, y), "{label}: the hips' pixel is not foreground");
                let share = share_on(&features.foreground, pixel, radius_px);
                assert!(share > 0.8, "{label}: {:.0} % foreground", 100.0 * share);
                // The corners a third of the image away from the hips: the room.
                for corner in [
                    DVec2::ZERO,
                    DVec2::new(w - 1.0, 0.0),
                    DVec2::new(0.0, h - 1.0),
                    DVec2::new(w - 1.0, h - 1.0),
                ] {
                    if (corner - pixel).length() > h / 3.0 {
                        let share = share_on(&features.foreground, corner, h / 20.0);
                        assert!(
                            share < 0.02,
                            "{label}: the corner {corner} is {:.1} % foreground",
                            100.0 * share
                        );
                    }
                }
                // Left and right along the hips' row, where the foreground
                // ends, Canny has an edge within 3 px (on every frame of the
                // four scenes: 1–2 px but for 7 frames of 1 000 at 2.2–3 px,
                // where the row leaves the body through a gap the closing
                // filled).
                for step in [-1i64, 1] {
                    let mut end = x as i64;
                    while (0..w as i64).contains(&(end + step))
                        && features.foreground.at((end + step) as u32, y)
                    {
                        end += step;
                    }
                    let d = features.edge_distance.at(end as u32, y);
                    assert!(d <= 3.0, "{label}: the outline at x = {end} is {d} px from an edge");
                }
                checked += 1;
            }
            assert!(checked >= 10, "{scene}: only {checked} frames with the hips in view");
        }
    }
}
