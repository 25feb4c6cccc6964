//! The camera trackers end to end: frames rendered from a known motion with
//! a known camera, tracked from the suit's pose, compared with the truth;
//! and on the shared scenes, the figures issues 13 and 22 ask for.

// A test may panic on what it does not expect: that is how it fails.
#![allow(clippy::unwrap_used, clippy::expect_used)]

mod common;

use common::Scratch;
use common::filmed::{film, mean_error_cm, run, run_with_scorer_apart, setup, track};
use embusen::camera::ImageSize;
use embusen::image::GreyImage;
use embusen::io::bvh::Bvh;
use embusen::io::recording::Recording;
use embusen::synth::demo::demo;
use embusen::track::fused::FusedParams;
use embusen::track::offset::estimate_offset_s;
use embusen::track::riecicky::RiecickyParams;
use embusen::track::suit_motion::VideoTiming;
use embusen::track::tracker::{TrackDetails, TrackMethod};
use embusen::track::views::{ViewSightings, fuse_views};
use glam::DVec2;
use std::path::Path;

#[test]
fn both_trackers_follow_a_filmed_body_at_another_rate_than_its_bvh() {
    // A 25 fps video of a 100 Hz recording, 400×300, four seconds.
    let size = ImageSize { width_px: 400, height_px: 300 };
    let (recording, camera, background, frames, truth) = film(25.0, 4.0, size, 0.0);
    // The paper's tracker starts at the world's origin: put the truth there.
    let paper = track(
        &recording,
        camera,
        &background,
        &frames,
        25.0,
        TrackMethod::Riecicky(RiecickyParams::default()),
    );
    let fused =
        track(&recording, camera, &background, &frames, 25.0, TrackMethod::Fused(FusedParams::default()));
    assert_eq!(fused.frames.len(), frames.len());
    let fused_cm = mean_error_cm(&fused, &truth, DVec2::ZERO);
    let paper_cm = mean_error_cm(&paper, &truth, truth[0]);
    let path_cm: f64 = truth.windows(2).map(|w| (w[1] - w[0]).length()).sum();
    eprintln!("filmed demo, {path_cm:.0} cm of path: fused {fused_cm:.2} cm, paper {paper_cm:.2} cm");
    assert!(path_cm > 50.0, "the take should move: {path_cm} cm");
    assert!(fused_cm < 6.0, "fused {fused_cm:.2} cm");
    assert!(fused.frames.iter().all(|f| f.height_cm.is_finite()));
    assert!(fused.frames.iter().filter(|f| f.confidence > 0.0).count() * 10 >= frames.len() * 9);
    // The paper's search: 25 candidates a frame, each with its energy.
    let TrackDetails::Riecicky { candidates, .. } = &paper.details else { panic!("not the paper's track") };
    assert_eq!(candidates.len(), paper.frames.len());
    assert!(candidates.iter().all(|c| c.len() == 25));
}

#[test]
fn a_video_longer_than_its_bvh_is_tracked_where_there_is_a_pose() {
    // 3 s of video, 2 s of suit recording: the last second has no pose.
    let size = ImageSize { width_px: 400, height_px: 300 };
    let (_, camera, background, frames, truth) = film(25.0, 3.0, size, 0.0);
    let demo = demo();
    let mut motion = demo.without_translation();
    motion.values.truncate(200 * motion.channel_count);
    let short =
        Recording::from_bvh(Bvh { skeleton: demo.skeleton.clone(), motion, warnings: Vec::new() }, "short");
    let fused = track(&short, camera, &background, &frames, 25.0, TrackMethod::Fused(FusedParams::default()));
    assert!(fused.warnings.iter().any(|w| w.contains("no pose")), "{:?}", fused.warnings);
    let posed = fused.frames.iter().take_while(|f| f.height_cm.is_finite()).count();
    assert!((49..=51).contains(&posed), "{posed} frames with a pose");
    let error_cm =
        fused.frames[..posed].iter().zip(&truth).map(|(f, t)| (f.floor_cm - *t).length()).sum::<f64>()
            / posed as f64;
    eprintln!("a 3 s video of a 2 s BVH: fused {error_cm:.2} cm over its {posed} frames with a pose");
    assert!(error_cm < 10.0, "fused {error_cm:.2} cm where there is a pose");
}

#[test]
fn frames_with_no_one_in_view_are_named_and_the_track_holds_where_seen() {
    // The actor walks in after 0.6 s, and is gone again for 0.6 s from
    // 2 s: those frames are the empty room.
    let size = ImageSize { width_px: 400, height_px: 300 };
    let (recording, camera, background, mut frames, truth) = film(25.0, 4.0, size, 0.0);
    for i in (0..15).chain(50..65) {
        frames[i] = background.clone();
    }
    let fused =
        track(&recording, camera, &background, &frames, 25.0, TrackMethod::Fused(FusedParams::default()));
    assert!(
        fused.warnings.iter().any(|w| w.contains("no one is in view in video frames 0–14, 50–64")),
        "{:?}",
        fused.warnings
    );
    let seen: Vec<usize> = (15..50).chain(65..100).collect();
    let error_cm =
        seen.iter().map(|&i| (fused.frames[i].floor_cm - truth[i]).length()).sum::<f64>() / seen.len() as f64;
    eprintln!("an actor out of view 1.2 s of 4: fused {error_cm:.2} cm where seen");
    assert!(error_cm < 6.0, "fused {error_cm:.2} cm where seen");
    // The frames out of view are carried by the suit's steps, and say so.
    assert!(fused.frames[..15].iter().chain(&fused.frames[50..65]).all(|f| f.confidence == 0.0));
    assert!(fused.frames.iter().all(|f| f.uncertainty_cm.is_finite()));
    // Lost while out of view, the tracker looks for the body where its best
    // guess puts it: a path scorer apart makes the frame's terms there too,
    // so the CLI and the page (which score apart) place every frame where
    // the tracker alone does.
    let apart = run_with_scorer_apart(
        setup(&recording, camera, &background, &frames, 25.0),
        FusedParams::default(),
        &frames,
    );
    let differ: Vec<usize> =
        (0..frames.len()).filter(|&i| apart.frames[i].floor_cm != fused.frames[i].floor_cm).collect();
    assert!(differ.is_empty(), "scored apart, frames {differ:?} are elsewhere");
}

/// The depth from the soles: on `walk`, whose feet are seen on the floor,
/// nothing is said; on the take filmed in code, whose suit-grade body
/// never has a foot within 3 cm of the floor (it stands 6 cm up), the
/// track says the depth rests on the silhouette.
#[test]
fn a_take_without_soles_on_the_floor_says_its_depth_rests_on_the_silhouette() {
    let said = |warnings: &[String]| warnings.iter().any(|w| w.contains("rests on the silhouette"));
    let size = ImageSize { width_px: 400, height_px: 300 };
    let (recording, camera, background, frames, _) = film(25.0, 2.0, size, 0.0);
    let method = TrackMethod::Fused(FusedParams::default());
    let filmed = track(&recording, camera, &background, &frames, 25.0, method);
    assert!(said(&filmed.warnings), "{:?}", filmed.warnings);
    let Some(dir) = common::data_dir() else { return };
    let scene = common::optical::open_scene(&dir.join("optical"), "walk");
    let walk = track(&scene.recording, scene.camera, &scene.background, &scene.frames, scene.fps, method);
    assert!(!said(&walk.warnings), "{:?}", walk.warnings);
}

#[test]
fn a_background_from_another_camera_position_is_warned_about() {
    // The still taken from a camera moved: the room's pattern a stripe
    // (23 px) over from where the video has it.
    let size = ImageSize { width_px: 400, height_px: 300 };
    let (recording, camera, background, frames, _) = film(25.0, 1.0, size, 0.0);
    let w = size.width_px as usize;
    let mut moved = background.clone();
    for (y, row) in moved.pixels.chunks_mut(w).enumerate() {
        row.copy_from_slice(&(0..w).map(|x| background.pixels[y * w + (x + 23) % w]).collect::<Vec<u8>>());
    }
    let fused = track(&recording, camera, &moved, &frames, 25.0, TrackMethod::Fused(FusedParams::default()));
    assert!(
        fused.warnings.iter().any(|w| w.contains("the background does not match video frames 0–24")),
        "{:?}",
        fused.warnings
    );
    // With the right still, no such warning.
    let fused =
        track(&recording, camera, &background, &frames, 25.0, TrackMethod::Fused(FusedParams::default()));
    assert!(
        !fused.warnings.iter().any(|w| w.contains("background") || w.contains("in view")),
        "{:?}",
        fused.warnings
    );
}

#[test]
fn the_time_offset_between_video_and_bvh_is_found() {
    // The video starts 0.3 s into the BVH: tracked as if in step, then the
    // offset estimated from every frame. The true pose is tracked here: a
    // slow kata at 25 fps pins the offset to a couple of video frames, and
    // the suit's pose, whose fusion lags, to a few more (0.45–0.49 s).
    let size = ImageSize { width_px: 400, height_px: 300 };
    let (_, camera, background, frames, truth) = film(25.0, 4.0, size, 0.3);
    let demo = demo();
    let recording = Recording::from_bvh(
        Bvh { skeleton: demo.true_skeleton.clone(), motion: demo.true_motion.clone(), warnings: Vec::new() },
        "truth",
    );
    let fused = TrackMethod::Fused(FusedParams::default());
    let at_zero = setup(&recording, camera, &background, &frames, 25.0);
    let first = run(at_zero.clone(), fused, &frames);
    let samples: Vec<(usize, GreyImage)> = (0..frames.len()).map(|i| (i, frames[i].clone())).collect();
    let estimate = estimate_offset_s(&at_zero, &first, &samples, 1.0).unwrap();
    eprintln!("offset found {:.3} s (true 0.3), {} offsets tried", estimate.offset_s, estimate.tried.len());
    assert!((estimate.offset_s - 0.3).abs() <= 0.1, "{estimate:?}");
    let mut in_step = at_zero;
    in_step.timing.offset_s = estimate.offset_s;
    let second = run(in_step, fused, &frames);
    let (before, after) =
        (mean_error_cm(&first, &truth, DVec2::ZERO), mean_error_cm(&second, &truth, DVec2::ZERO));
    eprintln!("fused at offset 0: {before:.2} cm; at the estimate: {after:.2} cm");
    assert!(after < before, "{after} vs {before}");
}

fn embusen(args: &[&std::ffi::OsStr]) -> std::process::Output {
    std::process::Command::new(env!("CARGO_BIN_EXE_embusen")).args(args).output().expect("runs embusen")
}

/// `embusen track VIDEO --bvh BVH --camera CAMERA [--background BG] -o OUT`.
fn track_cli(
    video: &Path,
    bvh: &Path,
    camera: &Path,
    background: Option<&Path>,
    out: &Path,
) -> (bool, String) {
    track_cli_with(&[], video, bvh, camera, background, out)
}

/// [`track_cli`] with `extra` arguments after the others.
fn track_cli_with(
    extra: &[&str],
    video: &Path,
    bvh: &Path,
    camera: &Path,
    background: Option<&Path>,
    out: &Path,
) -> (bool, String) {
    let mut args: Vec<&std::ffi::OsStr> = vec![
        "track".as_ref(),
        video.as_os_str(),
        "--bvh".as_ref(),
        bvh.as_os_str(),
        "--camera".as_ref(),
        camera.as_os_str(),
        "-o".as_ref(),
        out.as_os_str(),
    ];
    if let Some(background) = background {
        args.extend(["--background".as_ref(), background.as_os_str()]);
    }
    args.extend(extra.iter().map(|a| -> &std::ffi::OsStr { a.as_ref() }));
    let output = embusen(&args);
    (output.status.success(), String::from_utf8_lossy(&output.stderr).into_owned())
}

/// `embusen track` with two videos of walk (its second camera's too): one
/// track on the first video's frames, within 3 cm of the truth where each
/// view alone is 4; and what does not fit, said: a flag given for another
/// number of videos, two cameras calibrated into two worlds (the second
/// one's floor moved 60 cm).
#[test]
fn two_videos_weigh_into_one_track_and_cameras_of_two_worlds_are_refused() {
    let Some(data) = common::data_dir() else { return };
    let dir = data.join("optical");
    let scratch = Scratch::new("two-views");
    let scene = |view: &Path, suffix: &str| view.join(format!("walk{suffix}"));
    let second = dir.join("second_view");
    let out = scratch.join("walk.two.bvh");
    let run_with = |second_video: &Path, second_camera: &Path, backgrounds: usize| {
        let mut args: Vec<std::ffi::OsString> =
            vec!["track".into(), scene(&dir, ".mp4").into(), second_video.into()];
        for (flag, value) in [
            ("--bvh", scene(&dir, ".suit.bvh")),
            ("--camera", scene(&dir, ".camera.json")),
            ("--camera", second_camera.to_path_buf()),
            ("--background", scene(&dir, ".background.png")),
            ("--background", scene(&second, ".background.png")),
            ("-o", out.clone()),
        ]
        .into_iter()
        .filter(|(flag, _)| *flag != "--background" || backgrounds == 2)
        {
            args.extend([flag.into(), value.into()]);
        }
        if backgrounds == 1 {
            args.extend(["--background".into(), scene(&dir, ".background.png").into()]);
        }
        let args: Vec<&std::ffi::OsStr> = args.iter().map(|a| a.as_os_str()).collect();
        let output = embusen(&args);
        (output.status.success(), String::from_utf8_lossy(&output.stderr).into_owned())
    };
    let run = |second_camera: &Path, backgrounds: usize| {
        run_with(&scene(&second, ".mp4"), second_camera, backgrounds)
    };
    let (ok, said) = run(&scene(&second, ".camera.json"), 2);
    assert!(ok, "{said}");
    let csv = std::fs::read_to_string(scratch.join("walk.two.track.csv")).unwrap();
    let track = embusen::io::hips_csv::parse_hips_csv(&csv, "walk.two.track.csv").unwrap();
    let truth_csv = std::fs::read_to_string(scene(&dir, ".truth.csv")).unwrap();
    let truth = embusen::io::hips_csv::parse_hips_csv(&truth_csv, "walk.truth.csv").unwrap();
    assert_eq!(track.len(), truth.len());
    let floor = |s: &embusen::io::hips_csv::HipsSample| DVec2::new(s.hips_cm.x, s.hips_cm.z);
    let mean_cm = track.iter().zip(&truth).map(|(a, b)| (floor(a) - floor(b)).length()).sum::<f64>()
        / truth.len() as f64;
    eprintln!("walk, two views by the CLI: {mean_cm:.2} cm");
    assert!(mean_cm <= 3.0, "{mean_cm:.2} cm");
    let (ok, said) = run(&scene(&second, ".camera.json"), 1);
    assert!(!ok && said.contains("1 --background for 2 videos"), "{said}");
    // The second camera's world 60 cm off the first's.
    let mut moved: serde_json::Value =
        serde_json::from_str(&std::fs::read_to_string(scene(&second, ".camera.json")).unwrap()).unwrap();
    let rotation: Vec<Vec<f64>> = (0..3)
        .map(|i| (0..3).map(|j| moved["camera_from_world"][i][j].as_f64().unwrap()).collect())
        .collect();
    for i in 0..3 {
        let shift = 60.0 * rotation[i][0];
        moved["tvec_cm"][i] = (moved["tvec_cm"][i].as_f64().unwrap() + shift).into();
        moved["camera_from_world"][i][3] =
            (moved["camera_from_world"][i][3].as_f64().unwrap() + shift).into();
    }
    moved["camera_center_world_cm"][0] = (moved["camera_center_world_cm"][0].as_f64().unwrap() - 60.0).into();
    let moved_path = scratch.join("moved.camera.json");
    std::fs::write(&moved_path, moved.to_string()).unwrap();
    let (ok, said) = run(&moved_path, 2);
    assert!(
        !ok && said.contains("view 2 puts the body") && said.contains("do not agree about the floor"),
        "{said}"
    );
    // The second video 5 s long where the first is 6.5: tracked, and said.
    let short = scratch.join("walk.short.mp4");
    let cut = std::process::Command::new("ffmpeg")
        .args(["-v", "error", "-i"])
        .arg(scene(&second, ".mp4"))
        .args(["-frames:v", "150", "-c:v", "libx264", "-pix_fmt", "yuv420p"])
        .arg(&short)
        .status()
        .unwrap();
    assert!(cut.success());
    let (ok, said) = run_with(&short, &scene(&second, ".camera.json"), 2);
    assert!(
        ok && said.contains("films the recording's 0.00–5.00 s, view 1") && said.contains("0.00–6.50 s"),
        "{said}"
    );
}

/// `embusen track` on a shared scene: the corrected BVH and one CSV row per
/// video frame; and bad input as a message, never a panic.
#[test]
fn track_writes_a_bvh_and_a_row_per_frame_and_refuses_bad_input() {
    let Some(data) = common::data_dir() else { return };
    let scene = data.join("optical");
    let dir = Scratch::new("cli");
    let out = dir.join("walk.tracked.bvh");
    let path = |s: &str| scene.join(format!("walk{s}"));
    let (video, bvh, camera, background) =
        (path(".mp4"), path(".suit.bvh"), path(".camera.json"), path(".background.png"));
    let (ok, said) = track_cli(&video, &bvh, &camera, Some(&background), &out);
    assert!(ok, "{said}");
    let csv = std::fs::read_to_string(dir.join("walk.tracked.track.csv")).unwrap();
    assert_eq!(csv.lines().count(), 1 + 195, "a header and one row per video frame");
    let tracked = Recording::parse(&std::fs::read(&out).unwrap(), "tracked", None).unwrap();
    assert_eq!(tracked.frame_count(), 195);

    // The app's job on the same files, fed the decoder's luma planes as a
    // browser holds them, writes the same bytes.
    let app = app_tracks(&video, &bvh, &camera, &background);
    assert!(app.0 == std::fs::read_to_string(&out).unwrap(), "the app's corrected BVH is not the CLI's");
    assert!(app.1 == csv, "the app's hips CSV is not the CLI's");
    a_finished_take_opens_as_tracked(&out, &bvh, &camera, &csv, &app.2);
    several_takes_at_once_are_each_tracked_as_alone(&scene, &out, &csv);

    let refused = |(ok, said): (bool, String), expected: &str| {
        assert!(
            !ok && said.starts_with("error:") && said.contains(expected) && !said.contains("panicked"),
            "{said}"
        );
    };
    // A camera for another image size.
    let text = std::fs::read_to_string(&camera).unwrap();
    let small = dir.join("small.camera.json");
    std::fs::write(&small, text.replace("\"width\": 640", "\"width\": 320")).unwrap();
    refused(track_cli(&video, &bvh, &small, Some(&background), &out), "320");
    // Not a video at all.
    refused(track_cli(&bvh, &bvh, &camera, Some(&background), &out), "walk.suit.bvh");
    // A camera file without its lens matrix names the field.
    let broken = dir.join("broken.camera.json");
    std::fs::write(&broken, text.replacen("\"K\"", "\"not_K\"", 1)).unwrap();
    refused(track_cli(&video, &bvh, &broken, None, &out), "K");
    // The CLI tracks through the app's job, so the job's checks hold for
    // it too: an offset that is no time.
    let nan = track_cli_with(&["--offset-s", "NaN"], &video, &bvh, &camera, Some(&background), &out);
    refused(nan, "the time offset");
    // An output folder that is not there, said before tracking.
    let nowhere = dir.join("no such folder").join("walk.bvh");
    refused(track_cli(&video, &bvh, &camera, Some(&background), &nowhere), "does not exist");
}

/// `embusen track-takes` on a folder of two takes of walk (links to the
/// shared files under two names) tracked at once, and a third without a
/// camera: each take's files the bytes `embusen track` wrote for it alone
/// (`alone_bvh`, `alone_csv`), the one that could not be tracked named, a
/// video with no BVH beside it said to be no take, and the takes' folder
/// refused as the output.
fn several_takes_at_once_are_each_tracked_as_alone(scene: &Path, alone_bvh: &Path, alone_csv: &str) {
    let takes = Scratch::new("takes");
    let written = Scratch::new("takes-out");
    for (name, linked) in [("walk", "walk"), ("again", "walk"), ("uncalibrated", "walk"), ("board-video", "")]
    {
        let endings: &[&str] = match name {
            "uncalibrated" => &[".mp4", ".suit.bvh"],
            "board-video" => &[".mp4"],
            _ => &[".mp4", ".suit.bvh", ".camera.json", ".background.png"],
        };
        for ending in endings {
            let source = scene.join(format!("{}{ending}", if linked.is_empty() { "walk" } else { linked }));
            std::os::unix::fs::symlink(source, takes.join(format!("{name}{ending}"))).unwrap();
        }
    }
    let output = embusen(&["track-takes".as_ref(), takes.as_os_str(), "-o".as_ref(), written.as_os_str()]);
    let said = String::from_utf8_lossy(&output.stderr);
    assert!(!output.status.success(), "one take could not be tracked: {said}");
    assert!(
        said.contains("uncalibrated") && said.contains("no camera") && !said.contains("panicked"),
        "{said}"
    );
    assert!(said.contains("board-video.mp4 is not a take"), "{said}");
    assert!(said.contains("1 of 3 takes failed"), "{said}");
    // Written into the takes' own folder, a corrected BVH would be read as
    // a suit recording the next time: refused before anything is tracked.
    let into_itself = embusen(&["track-takes".as_ref(), takes.as_os_str(), "-o".as_ref(), takes.as_os_str()]);
    let said = String::from_utf8_lossy(&into_itself.stderr);
    assert!(!into_itself.status.success() && said.contains("is the output folder too"), "{said}");
    let alone = std::fs::read(alone_bvh).unwrap();
    for name in ["walk", "again"] {
        assert!(std::fs::read(written.join(format!("{name}.bvh"))).unwrap() == alone, "{name}.bvh");
        let csv = std::fs::read_to_string(written.join(format!("{name}.track.csv"))).unwrap();
        assert!(csv == alone_csv, "{name}.track.csv");
    }
}

/// `app::tracking::TrackingJob` on a video whose frames come as luma planes
/// (ffmpeg's raw yuv420p, the planes a browser's decoder gives), the
/// default method: the corrected recording and the hips CSV.
fn app_tracks(
    video: &Path,
    bvh: &Path,
    camera: &Path,
    background: &Path,
) -> (String, String, Vec<Vec<[u32; 2]>>) {
    use embusen::app::tracking::{NamedBytes, TrackingJob, VideoDescription};
    use embusen::io::video::Ffmpeg;
    let info = Ffmpeg::default().probe(video).unwrap();
    let files: Vec<(String, Vec<u8>)> = [bvh, camera, background]
        .iter()
        .map(|p| (p.display().to_string(), std::fs::read(p).unwrap()))
        .collect();
    let named = |k: usize| NamedBytes { name: &files[k].0, bytes: &files[k].1 };
    let description = VideoDescription {
        width_px: info.width_px,
        height_px: info.height_px,
        fps: info.fps,
        frame_count: info.frame_count,
    };
    let mut job = TrackingJob::open(
        named(0),
        named(1),
        named(2),
        &video.display().to_string(),
        description,
        TrackMethod::Fused(FusedParams::default()),
        0.0,
    )
    .unwrap();
    // An offset that is no time is refused, naming it.
    let refused = TrackingJob::open(
        named(0),
        named(1),
        named(2),
        "v",
        description,
        TrackMethod::Fused(FusedParams::default()),
        f64::NAN,
    );
    assert!(refused.err().unwrap().to_string().contains("the time offset"));
    let raw = std::process::Command::new("ffmpeg")
        .args(["-nostdin", "-v", "error", "-i"])
        .arg(video)
        .args(["-map", "0:v:0", "-fps_mode", "passthrough", "-f", "rawvideo", "-pix_fmt", "yuv420p", "-"])
        .output()
        .unwrap();
    assert!(raw.status.success(), "{}", String::from_utf8_lossy(&raw.stderr));
    let (w, h) = (info.width_px as usize, info.height_px as usize);
    let frame_bytes = w * h + 2 * w.div_ceil(2) * h.div_ceil(2);
    for planes in raw.stdout.chunks_exact(frame_bytes) {
        job.push_luma(&planes[..w * h], w, false).unwrap();
    }
    let (export, _) = job.finish().unwrap();
    // As the page runs it on two cores: the path search's energies left to
    // a second job of the same take, scored from the features the first
    // made (as bytes, as the page's workers pass them), handed back a few
    // frames late — the same bytes.
    let open = || {
        let (v, d) = (&video.display().to_string(), description);
        TrackingJob::open(named(0), named(1), named(2), v, d, TrackMethod::Fused(FusedParams::default()), 0.0)
            .unwrap()
    };
    let (mut tracking, mut scoring) = (open(), open());
    tracking.defer_path_energies();
    let mut late = std::collections::VecDeque::new();
    for planes in raw.stdout.chunks_exact(frame_bytes) {
        tracking.push_luma(&planes[..w * h], w, false).unwrap();
        if let Some((request, features)) = tracking.take_path_work() {
            late.push_back((request.frame, scoring.score_path(&request, &features.to_bytes()).unwrap()));
        }
        while late.len() > 3 {
            let (frame, energies) = late.pop_front().unwrap();
            tracking.set_path_energies(frame, energies).unwrap();
        }
    }
    let refused = tracking.finish().unwrap_err().to_string();
    assert!(refused.contains("3 frames still wait for their path energies"), "{refused}");
    for (frame, energies) in late {
        tracking.set_path_energies(frame, energies).unwrap();
    }
    assert!(tracking.set_path_energies(0, vec![1.0]).is_err(), "energies no request asked for");
    assert_eq!(tracking.finish().unwrap().0, export, "deferred path energies change the track");
    // The outlines the page draws over the video: one per frame, each the
    // body's contour (every frame of walk has a pose).
    let outlines = job.outlines_px();
    assert_eq!(outlines.len(), info.frame_count);
    assert!(outlines.iter().all(|o| o.len() > 50), "every frame has a pose and an outline");
    // Against the truth, as the page plots it: every frame, below the
    // suit's own 13.6 cm on walk (the fused tracker's guard elsewhere).
    let truth_path = video.with_extension("truth.csv");
    let truth = std::fs::read(&truth_path).unwrap();
    let (per_frame, figures) =
        job.against_truth(NamedBytes { name: "walk.truth.csv", bytes: &truth }).unwrap();
    assert_eq!(per_frame.len(), info.frame_count);
    assert!(figures.mean_cm < 10.0, "{figures:?}");
    assert!(job.against_truth(NamedBytes { name: "bad.csv", bytes: b"time_s,x\n1,2\n" }).is_err());
    // What the player's plots show of it: the path per recording frame, and
    // per video frame its instant (no offset: the video's own) and the
    // uncertainty the fused tracker states in every frame with a pose.
    let series = job.camera_series();
    assert_eq!(series.hips_cm.len(), 195, "a point per frame of walk.suit.bvh");
    assert_eq!(series.recording_time_s.len(), info.frame_count);
    assert_eq!(series.recording_time_s[30], 30.0 / info.fps);
    assert!(series.uncertainty_cm.iter().all(|u| u.is_finite() && *u > 0.0), "{:?}", series.uncertainty_cm);
    (export.recording_text, export.track_csv, outlines)
}

/// `app::finished_take::FinishedTake` on walk's corrected recording and
/// track CSV (`tracked`, `csv`), as the page opens a take tracked before:
/// the outlines over the video are the tracking job's (`outlines`), the
/// plots' figures the CSV's; files that are not one take's are refused,
/// saying which.
fn a_finished_take_opens_as_tracked(
    tracked: &Path,
    suit: &Path,
    camera: &Path,
    csv: &str,
    outlines: &[Vec<[u32; 2]>],
) {
    use embusen::app::finished_take::FinishedTake;
    use embusen::app::tracking::{NamedBytes, VideoDescription};
    use std::collections::HashSet;
    let video = VideoDescription { width_px: 640, height_px: 480, fps: 30.0, frame_count: 195 };
    let (tracked_bytes, suit_bytes, camera_bytes) =
        (std::fs::read(tracked).unwrap(), std::fs::read(suit).unwrap(), std::fs::read(camera).unwrap());
    let open = |recording: &[u8], camera: &[u8], csv: &str, video: VideoDescription| {
        FinishedTake::open(
            NamedBytes { name: "walk.tracked.bvh", bytes: recording },
            NamedBytes { name: "walk.camera.json", bytes: camera },
            NamedBytes { name: "walk.tracked.track.csv", bytes: csv.as_bytes() },
            "walk.mp4",
            video,
            0.0,
        )
    };
    let take = open(&tracked_bytes, &camera_bytes, csv, video).unwrap();
    assert_eq!(take.path.len(), 195);
    assert_eq!(take.series.hips_cm.len(), 195);
    let row_100: Vec<&str> = csv.lines().nth(101).unwrap().split(',').collect();
    assert_eq!(format!("{:.3}", take.path[100].confidence), row_100[5]);
    assert_eq!(format!("{:.4}", take.path[100].floor_cm.x), row_100[2]);
    assert_eq!(format!("{:.1}", take.series.uncertainty_cm[100]), row_100[6]);
    assert_eq!(take.series.recording_time_s[100], 100.0 / 30.0);
    // The CSV holds the track to 0.1 mm: the outlines are the job's, but
    // for a pixel here and there.
    let outlines_are_the_jobs = |take: &FinishedTake| {
        assert_eq!(take.outlines_px.len(), outlines.len());
        for (i, (opened, tracked)) in take.outlines_px.iter().zip(outlines).enumerate() {
            let tracked: HashSet<_> = tracked.iter().collect();
            let shared = opened.iter().filter(|p| tracked.contains(p)).count();
            assert!(
                shared * 100 >= 98 * tracked.len().max(opened.len()),
                "frame {i}: {shared} of {} pixels",
                tracked.len()
            );
        }
    };
    outlines_are_the_jobs(&take);
    // Opened as a second camera's view is (no CSV: it is on the first
    // view's frames), the corrected recording's hips place the body: the
    // same outlines, no confidence or uncertainty stated.
    let other = FinishedTake::open_other_view(
        NamedBytes { name: "walk.tracked.bvh", bytes: &tracked_bytes },
        NamedBytes { name: "walk.camera.json", bytes: &camera_bytes },
        "walk.mp4",
        video,
        0.0,
    )
    .unwrap();
    outlines_are_the_jobs(&other);
    assert!(other.series.uncertainty_cm.iter().all(|u| u.is_nan()));
    assert!((other.path[100].floor_cm - take.path[100].floor_cm).length() < 0.1);
    let refused = |result: Result<FinishedTake, embusen::error::Error>, expected: &str| {
        let said = result.unwrap_err().to_string();
        assert!(said.contains(expected), "{said}");
    };
    // The suit's own recording, not the one the track corrected.
    refused(open(&suit_bytes, &camera_bytes, csv, video), "walk.tracked.bvh: its hips are");
    // Tracked at an offset (the BVH's frames before the video carried by
    // the suit's steps up to the one at the video's first frame), opened
    // at it; at another, refused, saying so.
    let dir = tracked.parent().unwrap();
    let shifted = dir.join("walk.shifted.bvh");
    let scene = |s: &str| suit.with_file_name(format!("walk{s}"));
    let (ok, said) = track_cli_with(
        &["--offset-s", "0.1"],
        &scene(".mp4"),
        suit,
        camera,
        Some(&scene(".background.png")),
        &shifted,
    );
    assert!(ok, "{said}");
    let (shifted_bytes, shifted_csv) = (
        std::fs::read(&shifted).unwrap(),
        std::fs::read_to_string(dir.join("walk.shifted.track.csv")).unwrap(),
    );
    let at = |offset_s: f64| {
        FinishedTake::open(
            NamedBytes { name: "walk.shifted.bvh", bytes: &shifted_bytes },
            NamedBytes { name: "walk.camera.json", bytes: &camera_bytes },
            NamedBytes { name: "walk.shifted.track.csv", bytes: shifted_csv.as_bytes() },
            "walk.mp4",
            video,
            offset_s,
        )
    };
    let opened = at(0.1).unwrap();
    assert!(opened.outlines_px[194].is_empty(), "past the BVH's end at 0.1 s: no pose, no outline");
    refused(at(0.0), "or not at the offset it was tracked at (0 s here)");
    // A track with a row too few, or of a video at another rate.
    let short: String = csv.lines().take(195).map(|l| format!("{l}\n")).collect();
    refused(open(&tracked_bytes, &camera_bytes, &short, video), "has 194 rows, walk.mp4 195 frames");
    let faster = VideoDescription { fps: 60.0, ..video };
    refused(
        open(&tracked_bytes, &camera_bytes, csv, faster),
        "walk.tracked.track.csv:3:1: the row of frame 1",
    );
    // A camera for another image size; a track that is not a hips CSV.
    let small = String::from_utf8(camera_bytes.clone()).unwrap().replace("\"width\": 640", "\"width\": 320");
    refused(open(&tracked_bytes, small.as_bytes(), csv, video), "320");
    refused(open(&tracked_bytes, &camera_bytes, "frame,x\n0,1\n", video), "walk.tracked.track.csv:1:1");
}

/// A colour-less video (the same take made grey with ffmpeg) is tracked as
/// the colour one: the tracker reads the luma, and a grey video's luma is
/// the colour one's, give or take its codec.
#[test]
fn a_grey_video_is_tracked_as_its_colour_one() {
    let Some(data) = common::data_dir() else { return };
    let scene = data.join("optical");
    let dir = Scratch::new("grey");
    let path = |s: &str| scene.join(format!("slash{s}"));
    let grey = dir.join("slash.grey.mp4");
    let made = std::process::Command::new("ffmpeg")
        .args(["-loglevel", "error", "-y", "-i"])
        .arg(path(".mp4"))
        .args(["-vf", "format=gray", "-c:v", "libx264", "-pix_fmt", "yuv420p", "-crf", "18"])
        .arg(&grey)
        .status()
        .expect("runs ffmpeg");
    assert!(made.success());
    let rows = |video: &Path, name: &str| {
        let out = dir.join(format!("{name}.bvh"));
        let (ok, said) =
            track_cli(video, &path(".suit.bvh"), &path(".camera.json"), Some(&path(".background.png")), &out);
        assert!(ok && !said.contains("background does not match"), "{said}");
        let csv = std::fs::read_to_string(dir.join(format!("{name}.track.csv"))).unwrap();
        embusen::io::hips_csv::parse_hips_csv(&csv, name).unwrap()
    };
    let (colour, grey) = (rows(&path(".mp4"), "colour"), rows(&grey, "grey"));
    assert_eq!(colour.len(), grey.len());
    let apart_cm = colour.iter().zip(&grey).map(|(c, g)| (c.hips_cm - g.hips_cm).length()).sum::<f64>()
        / colour.len() as f64;
    eprintln!("slash, grey against colour: {apart_cm:.2} cm apart on average");
    assert!(apart_cm < 2.0, "{apart_cm:.2} cm");
}

/// One shared scene's figures with the true camera: the suit's own
/// translation's mean error (cm), the paper's mean (on the four scenes the
/// published method was measured on), the fused tracker's errors.
#[derive(Debug)]
struct SceneFigures {
    name: &'static str,
    suit_mean_cm: f64,
    paper_mean_cm: Option<f64>,
    fused: embusen::eval::track::TrackErrors,
    /// The first view's fused track, and the same take's second view's
    /// (`second_view/`) weighed in (issue 45).
    two_views: embusen::eval::track::TrackErrors,
}

/// The shared scenes the published method was measured on (its OpenCV
/// implementation: 44 / 17 / 11 / 28 cm), then the three hard ones.
const SHARED_SCENES: [&str; 7] =
    ["walk", "walk_turns", "run", "slash", "walk_toward", "shadow", "second_person"];

/// Per shared scene, its figures, computed once for the tests.
fn shared_scene_figures() -> Option<&'static Vec<SceneFigures>> {
    use embusen::eval::track::track_errors;
    use embusen::io::hips_csv::parse_hips_csv;
    use embusen::track::suit_motion::SuitMotion;
    static ALL: std::sync::OnceLock<Vec<SceneFigures>> = std::sync::OnceLock::new();
    let dir = common::data_dir()?.join("optical");
    Some(ALL.get_or_init(|| {
        SHARED_SCENES
            .iter()
            .enumerate()
            .map(|(k, name)| {
                let scene = common::optical::open_scene(&dir, name);
                let truth_path = dir.join(format!("{name}.truth.csv"));
                let truth = parse_hips_csv(&std::fs::read_to_string(truth_path).unwrap(), name).unwrap();
                let times: Vec<f64> = truth.iter().map(|s| s.time_s).collect();
                let truth: Vec<DVec2> = truth.iter().map(|s| DVec2::new(s.hips_cm.x, s.hips_cm.z)).collect();
                let track_view = |scene: &common::optical::OpticalScene, method| {
                    track(&scene.recording, scene.camera, &scene.background, &scene.frames, scene.fps, method)
                };
                let errors_of = |track: &embusen::track::tracker::Track| {
                    let floor: Vec<DVec2> = track.frames.iter().map(|f| f.floor_cm).collect();
                    track_errors(&floor, &truth)
                };
                let errors = |method| errors_of(&track_view(&scene, method));
                let fused = track_view(&scene, TrackMethod::Fused(FusedParams::default()));
                let second = common::optical::open_scene(&dir.join("second_view"), name);
                let second_track = track_view(&second, TrackMethod::Fused(FusedParams::default()));
                let timing = |scene: &common::optical::OpticalScene| VideoTiming {
                    fps: scene.fps,
                    frame_count: scene.frames.len(),
                    offset_s: 0.0,
                };
                let (first_timing, second_timing) = (timing(&scene), timing(&second));
                let others = [ViewSightings::of(&second_track, second_timing)];
                let two_views = errors_of(&fuse_views(&fused, &first_timing, &others));
                let suit = SuitMotion::new(&scene.recording).unwrap();
                let suit_floor = suit.suit_floor_at(&times);
                let figures = SceneFigures {
                    name,
                    suit_mean_cm: track_errors(&suit_floor, &truth).mean_cm,
                    paper_mean_cm: (k < 4)
                        .then(|| errors(TrackMethod::Riecicky(RiecickyParams::default())).mean_cm),
                    fused: errors_of(&fused),
                    two_views,
                };
                eprintln!("{figures:?}");
                figures
            })
            .collect()
    }))
}

/// The paper's method as published lands where an OpenCV implementation of
/// it does (44 / 17 / 11 / 28 cm on walk / walk_turns / run / slash): within
/// a factor two either way of those, no better than a few centimetres and no
/// worse than a lost track.
#[test]
fn the_faithful_tracker_lands_near_the_published_method() {
    let Some(figures) = shared_scene_figures() else { return };
    let reference = [44.0, 17.0, 11.0, 28.0];
    for (scene, reference) in figures.iter().zip(reference) {
        let paper = scene.paper_mean_cm.unwrap();
        assert!(
            paper > reference / 2.0 - 3.0 && paper < 2.0 * reference,
            "{}: paper {paper:.1} cm",
            scene.name
        );
    }
}

/// Issue 22's figures per scene, met: on every shared scene, the three hard
/// ones too (along the line of sight, a hard shadow at the feet, a second
/// person), the fused tracker's mean is within 8 cm and below the suit's
/// own translation's, and at most 5 % of its frames are over 20 cm off.
#[test]
fn the_fused_tracker_holds_on_every_shared_scene() {
    let Some(figures) = shared_scene_figures() else { return };
    for scene in figures {
        let fused = &scene.fused;
        assert!(fused.mean_cm <= 8.0 && fused.mean_cm < scene.suit_mean_cm, "{scene:?}");
        assert!(fused.lost_share <= 0.05, "{scene:?}");
    }
}

/// Issue 45's figures, met: with the second camera of every shared scene
/// weighed in, each scene's mean within 3 cm, the median of the means
/// within 2 cm and of the p90s within 4 cm (true cameras).
#[test]
fn two_cameras_meet_their_figures_on_every_shared_scene() {
    let Some(figures) = shared_scene_figures() else { return };
    let median = |get: fn(&SceneFigures) -> f64| {
        embusen::signal::stats::median(&figures.iter().map(get).collect::<Vec<_>>())
    };
    for scene in figures {
        assert!(scene.two_views.mean_cm <= 3.0, "{scene:?}");
        assert!(scene.two_views.mean_cm < scene.fused.mean_cm, "{scene:?}");
    }
    let (means, p90s) = (median(|s| s.two_views.mean_cm), median(|s| s.two_views.p90_cm));
    assert!(means <= 2.0 && p90s <= 4.0, "medians {means:.2} / {p90s:.2} cm: {figures:?}");
}

/// Issue 22's figures over the scenes: the median of the scenes' means
/// within 4 cm and of their p90s within 8 cm.
#[test]
#[ignore = "issue 22 acceptance, not met yet: medians 4.4 / 7.3 cm, the means' over 4 (see docs/track.md); `-- --ignored` prints the figures"]
fn the_fused_tracker_meets_the_medians_over_the_shared_scenes() {
    let Some(figures) = shared_scene_figures() else { return };
    let median = |get: fn(&SceneFigures) -> f64| {
        embusen::signal::stats::median(&figures.iter().map(get).collect::<Vec<_>>())
    };
    let (means, p90s) = (median(|s| s.fused.mean_cm), median(|s| s.fused.p90_cm));
    assert!(means <= 4.0 && p90s <= 8.0, "medians {means:.1} / {p90s:.1} cm: {figures:?}");
}

#[test]
#[ignore = "issue 13 acceptance, not met yet: the fused tracker's depth along the line of sight (see docs/track.md); `-- --ignored` prints the figures"]
fn the_fused_tracker_meets_the_acceptance_figures() {
    let Some(figures) = shared_scene_figures() else { return };
    let fused: Vec<f64> = figures[..4].iter().map(|s| s.fused.mean_cm).collect();
    assert!(embusen::signal::stats::median(&fused) <= 3.0, "{figures:?}");
    assert!(figures[..4].iter().all(|s| s.paper_mean_cm.is_some_and(|p| s.fused.mean_cm < p)), "{figures:?}");
}

/// A camera twice as fast sees the same errors twice as often, not twice
/// as many errors: the filter and the path search grow no more certain
/// per second, and a take filmed at 60 fps is tracked as well as at 30.
/// While each repeat counted as a new error: 7.6 cm at 60 fps, 5.3 at 30.
#[test]
fn a_take_filmed_at_60_fps_is_tracked_as_well_as_at_30() {
    let size = ImageSize { width_px: 400, height_px: 300 };
    let method = TrackMethod::Fused(FusedParams::default());
    let mut means_cm = Vec::new();
    for fps in [30.0, 60.0] {
        let (recording, camera, background, frames, truth) = film(fps, 3.0, size, 0.0);
        let fused = track(&recording, camera, &background, &frames, fps, method);
        let seen = fused.frames.iter().filter(|f| f.confidence > 0.0).count();
        let error_cm = mean_error_cm(&fused, &truth, DVec2::ZERO);
        eprintln!("filmed at {fps} fps: fused {error_cm:.2} cm, {seen} of {} frames seen", frames.len());
        assert!(seen * 10 >= frames.len() * 9, "{seen} of {} frames seen at {fps} fps", frames.len());
        means_cm.push(error_cm);
    }
    assert!(means_cm[1] <= 1.25 * means_cm[0] + 0.5, "{means_cm:?} cm at 30 and 60 fps");
}

/// Someone else in the room: a second body, in another instant's pose,
/// walks nearer the camera and beside the actor for the whole take, so it
/// is the lowest and the first foreground the tracker could take. The
/// actor starts 1.5 m from the floor's origin, so no guess at the origin
/// finds them either. The track must stay on the actor — the body whose
/// outline is the suit's pose — as well as without the other. (Before the
/// first frame looked at each blob of foreground, it took the other
/// person: 216 cm off.)
#[test]
fn a_second_person_nearer_the_camera_does_not_take_the_track() {
    let size = ImageSize { width_px: 400, height_px: 300 };
    let fps = 25.0;
    let method = TrackMethod::Fused(FusedParams::default());
    let (recording, camera, background, alone, truth) = film(fps, 3.0, size, 0.0);
    let (_, _, _, other_frames, _) = film(fps, 3.0, size, 1.3);
    let (w, h) = (size.width_px as i64, size.height_px as i64);
    let mut frames = alone.clone();
    for (frame, other) in frames.iter_mut().zip(&other_frames) {
        // The other take's body, moved 90 px left and 45 px down (nearer
        // the camera on the floor) and painted a little lighter.
        for y in 0..h {
            for x in 0..w {
                let (sx, sy) = (x + 90, y - 45);
                if sx >= w || sy < 0 {
                    continue;
                }
                let from = (sy * w + sx) as usize;
                if other.pixels[from] < 100 && background.pixels[from] >= 100 {
                    frame.pixels[(y * w + x) as usize] = 80;
                }
            }
        }
    }
    // The same pictures with the world's origin moved.
    let start_cm = DVec2::new(150.0, 100.0);
    let mut camera = camera;
    camera.camera_from_world *=
        glam::DAffine3::from_translation(glam::DVec3::new(-start_cm.x, 0.0, -start_cm.y));
    let truth: Vec<DVec2> = truth.iter().map(|&t| t + start_cm).collect();
    let lone = track(&recording, camera, &background, &alone, fps, method);
    let lone_cm = mean_error_cm(&lone, &truth, DVec2::ZERO);
    let fused = track(&recording, camera, &background, &frames, fps, method);
    let error_cm = mean_error_cm(&fused, &truth, DVec2::ZERO);
    eprintln!(
        "an actor 1.5 m from the origin: fused {lone_cm:.2} cm alone, {error_cm:.2} cm with a second person"
    );
    assert!(error_cm <= lone_cm + 2.0 && error_cm < 25.0, "{error_cm:.2} cm, alone {lone_cm:.2} cm");
}

/// A background still that is not quite the video's: every frame of the
/// shared walk and slash 8 % brighter or darker than the room was when its
/// still was taken (auto exposure, a still from another moment), or the
/// still taken a few pixels aside. The fused tracker brings the still to
/// each frame's position and exposure first and tracks about as it does as
/// filmed (the scenes' figures move by half a
/// centimetre between their mp4 and webm encodings alone). Subtracting the
/// still as it is turned the room into foreground: 18 m and 30 m off.
#[test]
fn a_still_at_another_exposure_or_a_few_pixels_aside_is_matched_first() {
    use embusen::eval::track::track_errors;
    use embusen::io::hips_csv::parse_hips_csv;
    let Some(dir) = common::data_dir().map(|d| d.join("optical")) else { return };
    let method = TrackMethod::Fused(FusedParams::default());
    for name in ["walk", "slash"] {
        let scene = common::optical::open_scene(&dir, name);
        let truth =
            parse_hips_csv(&std::fs::read_to_string(dir.join(format!("{name}.truth.csv"))).unwrap(), name)
                .unwrap();
        let truth: Vec<DVec2> = truth.iter().map(|s| DVec2::new(s.hips_cm.x, s.hips_cm.z)).collect();
        let mean_cm = |frames: &[GreyImage], still: &GreyImage| {
            let fused = track(&scene.recording, scene.camera, still, frames, scene.fps, method);
            let floor: Vec<DVec2> = fused.frames.iter().map(|f| f.floor_cm).collect();
            let mismatched = fused.warnings.iter().any(|w| w.contains("does not match"));
            (track_errors(&floor, &truth).mean_cm, mismatched)
        };
        let (as_filmed, _) = mean_cm(&scene.frames, &scene.background);
        for gain in [0.92, 1.08] {
            let exposed: Vec<GreyImage> = scene
                .frames
                .iter()
                .map(|f| {
                    let pixels =
                        f.pixels.iter().map(|&p| (p as f64 * gain).round().min(255.0) as u8).collect();
                    GreyImage::new(f.width_px, f.height_px, pixels, "exposed").unwrap()
                })
                .collect();
            let (error_cm, mismatched) = mean_cm(&exposed, &scene.background);
            eprintln!("{name}, exposure ×{gain}: fused {error_cm:.2} cm ({as_filmed:.2} as filmed)");
            assert!(error_cm <= as_filmed + 1.5, "{name} ×{gain}: {error_cm:.2} cm against {as_filmed:.2}");
            assert!(!mismatched, "{name} ×{gain}: the background said not to match");
        }
        // The still taken with the camera 3 px to one side and 2 px up from
        // where it filmed. (A still 2 px aside, made with ffmpeg, cost slash
        // 2.4 cm before the still was moved back: 5.89 cm against 3.45.)
        let moved = embusen::image::background::shifted(&scene.background, (3, -2));
        let (error_cm, _) = mean_cm(&scene.frames, &moved);
        eprintln!("{name}, the still 3 px aside: fused {error_cm:.2} cm ({as_filmed:.2} as filmed)");
        assert!(error_cm <= as_filmed + 1.5, "{name}, still aside: {error_cm:.2} cm against {as_filmed:.2}");
    }
}

/// Never worse than the inertial path: when the camera places the body in
/// no frame at all (here every frame is the empty room), the track is the
/// suit's own steps from the floor's origin, says so, and states the
/// uncertainty of a start it could not see — not wherever the first
/// frame's guess fell. (A take whose still was 2 px off its camera so
/// ended 353 cm off, against 68 cm for the suit's steps.)
#[test]
fn a_take_the_camera_never_places_is_the_suit_s_steps() {
    let size = ImageSize { width_px: 400, height_px: 300 };
    let fps = 25.0;
    let (recording, camera, background, frames, truth) = film(fps, 3.0, size, 0.0);
    let empty = vec![background.clone(); frames.len()];
    let fused =
        track(&recording, camera, &background, &empty, fps, TrackMethod::Fused(FusedParams::default()));
    assert!(fused.warnings.iter().any(|w| w.contains("never saw the body")), "{:?}", fused.warnings);
    assert_eq!(fused.frames[0].floor_cm, DVec2::ZERO);
    let start_cm = FusedParams::default().start_search_cm;
    assert!(fused.frames.iter().all(|f| f.uncertainty_cm >= start_cm && f.uncertainty_cm.is_finite()));
    // It walks as the suit does: its path as long as the truth's, give or
    // take the suit's stride error.
    let length = |p: &[DVec2]| p.windows(2).map(|w| (w[1] - w[0]).length()).sum::<f64>();
    let floor: Vec<DVec2> = fused.frames.iter().map(|f| f.floor_cm).collect();
    let (tracked_cm, true_cm) = (length(&floor), length(&truth));
    eprintln!("never seen: the suit's steps walk {tracked_cm:.0} cm, the truth {true_cm:.0} cm");
    assert!((tracked_cm - true_cm).abs() < 0.3 * true_cm, "{tracked_cm:.0} cm against {true_cm:.0}");
}

/// The suit's steps can put the prediction farther off than the search
/// reaches: here they jump 1.2 m across the line of sight in one frame and
/// stay there. The camera, seeing no one near the prediction, offers no fit
/// to reject; after `reacquire_after_s` without a fit used the tracker looks
/// for the body as it did in the first frame, and holds it again. (Before,
/// it fitted 35 of the 50 frames after it.) Across the line of sight it is
/// back on the actor; along it, where a silhouette barely changes, the
/// re-found fit may lie in another valley of the energy (here about 30 cm
/// off), as a first frame's may.
#[test]
fn a_track_thrown_off_by_the_suit_s_steps_finds_the_body_again() {
    let size = ImageSize { width_px: 400, height_px: 300 };
    let fps = 25.0;
    let (recording, camera, background, frames, truth) = film(fps, 4.0, size, 0.0);
    let mut thrown = setup(&recording, camera, &background, &frames, fps);
    let from = thrown.suit.bvh_fps as usize;
    for floor in std::sync::Arc::make_mut(&mut thrown.suit).inertial_floor_cm.iter_mut().skip(from) {
        *floor += DVec2::new(120.0, 0.0);
    }
    let across = camera.world_from_camera().transform_vector3(glam::DVec3::X);
    let across = DVec2::new(across.x, across.z).normalize();
    let fused = run(thrown, TrackMethod::Fused(FusedParams::default()), &frames);
    // From a second after the jump (the 0.5 s lost, with room to spare) to
    // the end.
    let settled = (2.0 * fps) as usize;
    let late: Vec<DVec2> =
        fused.frames.iter().zip(&truth).skip(settled).map(|(f, t)| f.floor_cm - *t).collect();
    let across_cm = late.iter().map(|d| d.dot(across).abs()).sum::<f64>() / late.len() as f64;
    let off_cm = late.iter().map(|d| d.length()).sum::<f64>() / late.len() as f64;
    let seen = fused.frames.iter().skip(settled).filter(|f| f.confidence > 0.0).count();
    eprintln!(
        "thrown 120 cm off: after it {across_cm:.1} cm off across the line of sight ({off_cm:.1} in all), {seen} of {} frames fitted",
        late.len()
    );
    assert!(across_cm < 10.0, "{across_cm:.1} cm across");
    assert!(seen * 10 >= late.len() * 9, "{seen} of {}", late.len());
}
