//! `embusen eval-track`: the trackers measured on scenes whose true hips
//! path is known, per scene and as medians.

use std::path::{Path, PathBuf};
use std::process::ExitCode;
use std::time::Instant;

use embusen::Error;
use embusen::app::tracking::TakeInputs;
use embusen::eval::track::{TrackErrors, share_within_uncertainty, track_errors};
use embusen::io::hips_csv::parse_hips_csv;
use embusen::io::recording::Recording;
use embusen::signal::stats::median;
use embusen::track::fused::FusedParams;
use embusen::track::riecicky::RiecickyParams;
use embusen::track::suit_motion::{SuitMotion, VideoTiming};
use embusen::track::tracker::{Track, TrackMethod};
use embusen::track::views::{ViewSightings, fuse_views};
use glam::DVec2;

use crate::track::{
    VIDEO_EXTENSIONS, Video, camera_from_board, method_parser, read_camera, read_recording, read_text,
};

#[derive(clap::Args)]
pub struct EvalTrackArgs {
    /// Folders of scenes: each `NAME.truth.csv` with `NAME.suit.bvh`,
    /// `NAME.camera.json`, `NAME.mp4` (or `.webm`), and `NAME.background.png`
    /// and `NAME.board.png` when there are.
    #[arg(required = true)]
    dirs: Vec<PathBuf>,
    /// Calibrate each scene's camera from its `NAME.board.png` (with the
    /// true lens) instead of reading `NAME.camera.json`'s pose.
    #[arg(long)]
    board_camera: bool,
    /// Only the scenes with these names.
    #[arg(long, num_args = 1..)]
    only: Vec<String>,
    /// Also the camera's best: per frame the least of the fused energy
    /// searched densely around the true position (`oracle` rows; slow).
    #[arg(long)]
    camera_oracle: bool,
    /// Only these trackers (`paper`, `fused`); both when not given.
    #[arg(long = "method", value_parser = method_parser())]
    methods: Vec<TrackMethod>,
}

/// One scene's figures for one way of placing the hips.
struct SceneRow {
    scene: String,
    method: &'static str,
    errors: TrackErrors,
    ms_per_frame: f64,
    /// The share of frames within the uncertainty the tracker stated (NaN:
    /// none stated).
    within_uncertainty: f64,
}

pub fn run_eval_track(args: &EvalTrackArgs) -> ExitCode {
    match eval_track(args) {
        Ok(()) => ExitCode::SUCCESS,
        Err(e) => {
            eprintln!("error: {e}");
            ExitCode::FAILURE
        }
    }
}

fn scenes(dirs: &[PathBuf], only: &[String]) -> Result<Vec<(PathBuf, String)>, Error> {
    let mut out = Vec::new();
    for dir in dirs {
        let name = dir.display().to_string();
        let entries = std::fs::read_dir(dir).map_err(|e| Error::whole(&name, format!("cannot read: {e}")))?;
        let mut found: Vec<String> = entries
            .filter_map(|e| e.ok())
            .filter_map(|e| {
                e.file_name().to_str().and_then(|n| n.strip_suffix(".truth.csv")).map(String::from)
            })
            .filter(|n| only.is_empty() || only.contains(n))
            .collect();
        found.sort();
        out.extend(found.into_iter().map(|n| (dir.clone(), n)));
    }
    if out.is_empty() {
        return Err(Error::whole("eval-track", "no scene (NAME.truth.csv) in the folders given"));
    }
    Ok(out)
}

fn scene_video(dir: &Path, name: &str) -> Result<PathBuf, Error> {
    VIDEO_EXTENSIONS.iter().map(|ext| dir.join(format!("{name}.{ext}"))).find(|p| p.is_file()).ok_or_else(
        || Error::whole(&dir.join(name).display().to_string(), "no video (.mp4, .webm, …) for this scene"),
    )
}

/// How far along the line of sight `--camera-oracle` searches either side
/// of the truth (cm): farther than any tracker here strays.
const ORACLE_REACH_CM: f64 = 80.0;

fn eval_track(args: &EvalTrackArgs) -> Result<(), Error> {
    let mut rows: Vec<SceneRow> = Vec::new();
    for (dir, name) in scenes(&args.dirs, &args.only)? {
        let path = |suffix: &str| dir.join(format!("{name}{suffix}"));
        let truth_path = path(".truth.csv");
        let truth = parse_hips_csv(&read_text(&truth_path)?, &truth_path.display().to_string())?;
        let truth_floor: Vec<DVec2> = truth.iter().map(|s| DVec2::new(s.hips_cm.x, s.hips_cm.z)).collect();
        let recording = read_recording(&path(".suit.bvh"))?;
        let true_camera = read_camera(&path(".camera.json"))?;
        let camera = if args.board_camera {
            camera_from_board(&path(".board.png"), Some(&true_camera))?
        } else {
            true_camera
        };
        let video = scene_video(&dir, &name)?;
        let background_still = path(".background.png");
        // The suit's own translation, read at the video's frames.
        let suit = SuitMotion::new(&recording)?;
        let times_s: Vec<f64> = truth.iter().map(|s| s.time_s).collect();
        let suit_floor = suit.suit_floor_at(&times_s);
        rows.push(SceneRow {
            scene: name.clone(),
            method: "suit",
            errors: track_errors(&suit_floor, &truth_floor),
            ms_per_frame: 0.0,
            within_uncertainty: f64::NAN,
        });
        let video = Video::open(&video, None)?;
        let room = video.background(background_still.is_file().then_some(background_still.as_path()))?;
        let wanted =
            |m: &TrackMethod| args.methods.is_empty() || args.methods.iter().any(|w| w.name() == m.name());
        // The first view's fused track, to weigh a second view's against.
        let mut first_view: Option<(Track, VideoTiming)> = None;
        let methods =
            [TrackMethod::Riecicky(RiecickyParams::default()), TrackMethod::Fused(FusedParams::default())];
        for method in methods.into_iter().filter(wanted) {
            let inputs = TakeInputs { recording: recording.clone(), camera, background: room.clone() };
            let mut job = video.job(inputs, method, 0.0)?;
            let (_, ms_per_frame, _) = video.track(&mut job, false)?;
            let Some(track) = job.track() else { continue };
            let row = scene_row(&name, track.method().name(), track, &truth_floor, ms_per_frame);
            print_row(&row);
            rows.push(row);
            if matches!(method, TrackMethod::Fused(_)) {
                first_view = Some((track.clone(), job.timing()));
            }
        }
        // A second camera (`second_view/` beside the scenes): tracked
        // alone, then weighed with the first.
        let second = dir.join("second_view");
        if let Some(first) =
            first_view.as_ref().filter(|_| second.join(format!("{name}.camera.json")).is_file())
        {
            let first_ms = rows
                .iter()
                .rev()
                .find(|r| r.scene == name && r.method == "fused")
                .map_or(0.0, |r| r.ms_per_frame);
            for row in second_view_rows(
                &second,
                &name,
                &recording,
                args.board_camera,
                first,
                (&truth_floor, first_ms),
            )? {
                print_row(&row);
                rows.push(row);
            }
        }
        if args.camera_oracle {
            let method = TrackMethod::Fused(FusedParams::default());
            let inputs = TakeInputs { recording: recording.clone(), camera, background: room.clone() };
            let mut job = video.job(inputs, method, 0.0)?;
            let mut frames = video.frames()?;
            let started = Instant::now();
            let mut floor = Vec::new();
            let mut i = 0;
            while let Some(frame) = frames.next_frame() {
                let frame = frame?;
                let Some(&around) = truth_floor.get(i) else { break };
                floor.push(job.camera_oracle(&frame, i, around, ORACLE_REACH_CM)?.unwrap_or(DVec2::NAN));
                i += 1;
            }
            let row = SceneRow {
                scene: name.clone(),
                method: "oracle",
                errors: track_errors(&floor, &truth_floor),
                ms_per_frame: 1e3 * started.elapsed().as_secs_f64() / floor.len().max(1) as f64,
                within_uncertainty: f64::NAN,
            };
            print_row(&row);
            rows.push(row);
        }
    }
    println!();
    println!(
        "{:<12} {:<6} {:>8} {:>8} {:>8} {:>8} {:>8} {:>8} {:>9} {:>7}",
        "scene", "method", "mean cm", "median", "p90", "max", "final", ">20 cm", "ms/frame", "in 1σ"
    );
    for row in &rows {
        print_row(row);
    }
    println!("medians over the scenes:");
    for method in ["suit", "paper", "fused", "view2", "2views", "oracle"] {
        let of: Vec<&SceneRow> = rows.iter().filter(|r| r.method == method).collect();
        if of.is_empty() {
            continue;
        }
        let errors = TrackErrors::medians(&of.iter().map(|r| &r.errors).collect::<Vec<_>>());
        let ms = median(&of.iter().map(|r| r.ms_per_frame).collect::<Vec<_>>());
        let within = median(&of.iter().map(|r| r.within_uncertainty).collect::<Vec<_>>());
        print_row(&SceneRow {
            scene: "median".into(),
            method: of.first().map_or("?", |r| r.method),
            errors,
            ms_per_frame: ms,
            within_uncertainty: within,
        });
    }
    Ok(())
}

/// A track's row against `truth_floor` (the truth per video frame).
fn scene_row(
    scene: &str,
    method: &'static str,
    track: &Track,
    truth_floor: &[DVec2],
    ms_per_frame: f64,
) -> SceneRow {
    let floor: Vec<DVec2> = track.frames.iter().map(|f| f.floor_cm).collect();
    let uncertainty: Vec<f64> = track.frames.iter().map(|f| f.uncertainty_cm).collect();
    SceneRow {
        scene: scene.to_string(),
        method,
        errors: track_errors(&floor, truth_floor),
        ms_per_frame,
        within_uncertainty: share_within_uncertainty(&floor, &uncertainty, truth_floor),
    }
}

/// The rows of scene `name`'s second view (in `dir`): alone against its
/// own truth (`view2`), and weighed with the first view's fused track
/// `first` (`2views`, against the first's truth and with its ms a frame
/// added, `first_figures`). The CLI's check that the two cameras agree
/// about the floor is not made here: the scenes' cameras are true, or
/// calibrated from the one board.
fn second_view_rows(
    dir: &Path,
    name: &str,
    recording: &Recording,
    board_camera: bool,
    (first, first_timing): &(Track, VideoTiming),
    (truth_floor, first_ms): (&[DVec2], f64),
) -> Result<Vec<SceneRow>, Error> {
    let (view_track, view_timing, ms_per_frame) = track_second_view(dir, name, recording, board_camera)?;
    let view_path = dir.join(format!("{name}.truth.csv"));
    let view_truth = parse_hips_csv(&read_text(&view_path)?, &view_path.display().to_string())?;
    let view_truth: Vec<DVec2> = view_truth.iter().map(|s| DVec2::new(s.hips_cm.x, s.hips_cm.z)).collect();
    let mut rows = vec![scene_row(name, "view2", &view_track, &view_truth, ms_per_frame)];
    let fused = fuse_views(first, first_timing, &[ViewSightings::of(&view_track, view_timing)]);
    rows.push(scene_row(name, "2views", &fused, truth_floor, first_ms + ms_per_frame));
    Ok(rows)
}

/// Scene `name`'s second view in `dir` (its video, camera, background,
/// and board when `board_camera`) tracked by the fused tracker alone: the
/// track, its timing, the ms a frame.
fn track_second_view(
    dir: &Path,
    name: &str,
    recording: &Recording,
    board_camera: bool,
) -> Result<(Track, VideoTiming, f64), Error> {
    let path = |suffix: &str| dir.join(format!("{name}{suffix}"));
    let true_camera = read_camera(&path(".camera.json"))?;
    let camera =
        if board_camera { camera_from_board(&path(".board.png"), Some(&true_camera))? } else { true_camera };
    let video = Video::open(&scene_video(dir, name)?, None)?;
    let still = path(".background.png");
    let room = video.background(still.is_file().then_some(still.as_path()))?;
    let inputs = TakeInputs { recording: recording.clone(), camera, background: room };
    let mut job = video.job(inputs, TrackMethod::Fused(FusedParams::default()), 0.0)?;
    let (_, ms_per_frame, _) = video.track(&mut job, false)?;
    let track =
        job.track().cloned().ok_or_else(|| Error::whole(video.name(), "the second view was not tracked"))?;
    Ok((track, job.timing(), ms_per_frame))
}

fn print_row(row: &SceneRow) {
    let e = &row.errors;
    println!(
        "{:<12} {:<6} {:>8.1} {:>8.1} {:>8.1} {:>8.1} {:>8.1} {:>7.1}% {:>9.2} {:>7}",
        row.scene,
        row.method,
        e.mean_cm,
        e.median_cm,
        e.p90_cm,
        e.max_cm,
        e.final_cm,
        100.0 * e.lost_share,
        row.ms_per_frame,
        if row.within_uncertainty.is_finite() {
            format!("{:.1}%", 100.0 * row.within_uncertainty)
        } else {
            "—".to_string()
        }
    );
}
