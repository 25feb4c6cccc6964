//! `embusen track`: where the actor is, from a video of the suit session
//! and a calibrated camera; and what `track-takes` and `eval-track` read a
//! take with.

use std::path::{Path, PathBuf};
use std::process::ExitCode;
use std::sync::mpsc;
use std::time::Instant;

use embusen::Error;
use embusen::app::tracking::{Background, TakeInputs, TrackingJob, VideoDescription};
use embusen::camera::Camera;
use embusen::image::GreyImage;
use embusen::image::background::MEDIAN_FRAMES;
use embusen::image::pipeline::Features;
use embusen::io::image_file::{ImageSequence, open_png_grey};
use embusen::io::recording::Recording;
use embusen::io::video::{Ffmpeg, VideoFile, VideoFrames, sample_frames};
use embusen::track::path::PathRequest;
use embusen::track::path_scorer::PathScorer;
use embusen::track::take::TakeExport;
use embusen::track::tracker::TrackMethod;

#[derive(clap::Args, Clone)]
pub struct TrackArgs {
    /// The video (anything ffmpeg reads), or a folder of PNG frames (with
    /// --fps); several: one per camera filming the take, each with its own
    /// --camera (or --board) and --background, in the same order, weighed
    /// into one track on the first video's frames.
    #[arg(required = true, num_args = 1..)]
    pub video: Vec<PathBuf>,
    /// The suit's recording of the same take.
    #[arg(long)]
    pub bvh: PathBuf,
    /// The calibrated camera (camera.json), one per video.
    #[arg(long, required_unless_present = "board", conflicts_with = "board")]
    pub camera: Vec<PathBuf>,
    /// A still of the ChArUco board on the floor (its layout in BOARD.json
    /// beside it), one per video: each camera is calibrated from its own.
    #[arg(long, value_name = "BOARD.png")]
    pub board: Vec<PathBuf>,
    /// With --board: the lens (camera.json) to pose, one per board; without,
    /// the focal length is estimated from the still.
    #[arg(long, requires = "board", value_name = "CAMERA.json")]
    pub intrinsics: Vec<PathBuf>,
    /// A still of the empty room, one per video; without, the per-pixel
    /// median of frames spread over each video.
    #[arg(long, value_name = "BG.png")]
    pub background: Vec<PathBuf>,
    #[arg(long, value_parser = method_parser(), default_value = "fused")]
    pub method: TrackMethod,
    /// How far the BVH's clock runs ahead of the video's (s): once for every
    /// video, or once per video.
    #[arg(long, allow_hyphen_values = true)]
    pub offset_s: Vec<f64>,
    /// Refine --offset-s from the video itself, within a quarter of a
    /// second either way (a stride takes at least half a second, so a
    /// walk or run a whole stride out of step fits as well: give the offset
    /// to that precision): track, find the offset at which the pose fits 60
    /// frames spread over the take best, and track again at it.
    #[arg(long)]
    pub estimate_offset: bool,
    /// Frame rate of a folder of PNG frames.
    #[arg(long)]
    pub fps: Option<f64>,
    /// The corrected BVH; the hips track goes beside it as `OUT.track.csv`.
    #[arg(short, long, value_name = "OUT.bvh")]
    pub output: PathBuf,
}

/// `--method paper|fused`: a tracker by its name ([`TrackMethod::named`]),
/// with its defaults; `--help` lists each with its summary.
pub fn method_parser() -> impl clap::builder::TypedValueParser<Value = TrackMethod> {
    use clap::builder::TypedValueParser;
    let names = TrackMethod::ALL.map(|m| clap::builder::PossibleValue::new(m.name()).help(m.summary()));
    clap::builder::PossibleValuesParser::new(names)
        .try_map(|name| TrackMethod::named(&name).ok_or_else(|| format!("no tracker is named {name}")))
}

/// A take's video, opened once: a file ffmpeg reads (probed once for its
/// size, rate and length) or a folder of PNG frames at `--fps`. What a
/// command reads of a take's frames it reads here, in passes
/// ([`Video::frames`]): each from the first frame, decoding anew, holding
/// one frame at a time, so a long 1080×1920 take never sits in memory.
///
/// The passes a take may need, each one decode:
/// - tracking ([`Video::track`]), always;
/// - the median background ([`Video::background`]), before it, when there
///   is no still of the empty room: the job needs its background before
///   its first frame, and the median's frames are spread over the whole
///   take, the last frame among them; the frames in between cannot wait
///   for it without holding the whole take;
/// - tracking again at an estimated offset (`--estimate-offset`): the
///   offset is known only once every frame has been tracked, and the
///   frames are gone by then, for the same reason.
pub(crate) struct Video {
    source: Source,
    name: String,
    description: VideoDescription,
}

/// Where a video's frames come from.
enum Source {
    File(VideoFile),
    Folder(ImageSequence),
}

impl Video {
    /// The video at `path`, or the folder of frames at `fps`; an error
    /// naming it when it cannot be read or has no frames.
    pub(crate) fn open(path: &Path, fps: Option<f64>) -> Result<Video, Error> {
        let name = path.display().to_string();
        let source = if path.is_dir() {
            let fps =
                fps.ok_or_else(|| Error::whole(&name, "a folder of frames needs its rate: give --fps"))?;
            Source::Folder(ImageSequence::open(path, fps)?)
        } else {
            Source::File(Ffmpeg::default().probe_file(path)?)
        };
        // The frames' size: as ffprobe reports it, or the first PNG's.
        let (width_px, height_px, fps, frame_count) = match &source {
            Source::File(file) => {
                (file.info.width_px, file.info.height_px, file.info.fps, file.info.frame_count)
            }
            Source::Folder(sequence) => {
                let first = sequence.frame(0)?;
                (first.width_px, first.height_px, sequence.fps, sequence.frame_count())
            }
        };
        if frame_count == 0 {
            return Err(Error::whole(&name, "has no frames"));
        }
        let description = VideoDescription { width_px, height_px, fps, frame_count };
        Ok(Video { source, name, description })
    }

    /// The video's name in what is said of it.
    pub(crate) fn name(&self) -> &str {
        &self.name
    }

    /// A pass over the frames, from the first.
    pub(crate) fn frames(&self) -> Result<Frames<'_>, Error> {
        Ok(match &self.source {
            Source::File(file) => Frames::File(file.frames()?),
            Source::Folder(sequence) => Frames::Folder { sequence, next: 0 },
        })
    }

    /// The background: the still when given (no pass), else the median of
    /// [`MEDIAN_FRAMES`] frames spread over the video, in a pass of its
    /// own (see [`Video`]) that keeps only those.
    pub(crate) fn background(&self, still: Option<&Path>) -> Result<Background, Error> {
        if let Some(still) = still {
            return open_png_grey(still).map(Background::still);
        }
        let sampled = sample_frames(self.frames()?, self.description.frame_count, MEDIAN_FRAMES)?;
        Background::median_of(&sampled, &self.name)
    }

    /// The tracking job of this video, the BVH `offset_s` ahead of it.
    pub(crate) fn job(
        &self,
        inputs: TakeInputs,
        method: TrackMethod,
        offset_s: f64,
    ) -> Result<TrackingJob, Error> {
        TrackingJob::new(inputs, &self.name, self.description, method, offset_s)
    }

    /// A tracking pass: every frame fed to `job`, and the job finished
    /// ([`run_job`]); a progress bar with `progress`.
    pub(crate) fn track(&self, job: &mut TrackingJob, progress: bool) -> Result<JobRun, Error> {
        run_job(job, &mut self.frames()?, progress)
    }
}

/// One pass over a [`Video`]'s frames.
pub(crate) enum Frames<'a> {
    File(VideoFrames),
    Folder { sequence: &'a ImageSequence, next: usize },
}

impl Frames<'_> {
    fn frame_count(&self) -> usize {
        match self {
            Frames::File(v) => v.info.frame_count,
            Frames::Folder { sequence, .. } => sequence.frame_count(),
        }
    }

    pub(crate) fn next_frame(&mut self) -> Option<Result<GreyImage, Error>> {
        match self {
            Frames::File(v) => v.next_frame(),
            Frames::Folder { sequence, next } => (*next < sequence.frame_count()).then(|| {
                *next += 1;
                sequence.frame(*next - 1)
            }),
        }
    }
}

impl Iterator for Frames<'_> {
    type Item = Result<GreyImage, Error>;
    fn next(&mut self) -> Option<Self::Item> {
        self.next_frame()
    }
}

pub(crate) fn read_text(path: &Path) -> Result<String, Error> {
    std::fs::read_to_string(path)
        .map_err(|e| Error::whole(&path.display().to_string(), format!("cannot read: {e}")))
}

pub(crate) fn read_camera(path: &Path) -> Result<Camera, Error> {
    Camera::from_json(&read_text(path)?, &path.display().to_string())
}

pub(crate) fn read_recording(path: &Path) -> Result<Recording, Error> {
    let name = path.display().to_string();
    let bytes = std::fs::read(path).map_err(|e| Error::whole(&name, format!("cannot read: {e}")))?;
    Recording::parse(&bytes, &name, None)
}

/// The camera from a board still, posed with `lens` or with its focal
/// length estimated.
#[cfg(feature = "board")]
pub(crate) fn camera_from_board(still: &Path, lens: Option<&Camera>) -> Result<Camera, Error> {
    crate::calibrate::camera_from_still(still, lens)
}

#[cfg(not(feature = "board"))]
pub(crate) fn camera_from_board(still: &Path, _lens: Option<&Camera>) -> Result<Camera, Error> {
    Err(Error::whole(
        &still.display().to_string(),
        "this build has no board detector (cargo feature `board`)",
    ))
}

/// What a tracking job wrote, the milliseconds per frame the tracking took
/// (not counting the decoding), and the warnings the tracking added.
pub(crate) type JobRun = (TakeExport, f64, Vec<String>);

/// Frames read ahead of the path scorer at most: each frame's features
/// wait there whole (23 MB at 1080×1920: two distance images in f32, the
/// difference and two masks), and the tracker gains nothing by running
/// further ahead of it.
const FRAMES_AHEAD_OF_SCORER: usize = 4;

/// Feeds `frames` to `job` and finishes it. The fused tracker's path
/// energies are scored on a second thread, from the same frames, as the
/// page's second worker scores them: the same bits, the two cores at work.
fn run_job(job: &mut TrackingJob, frames: &mut Frames, progress: bool) -> Result<JobRun, Error> {
    let count = frames.frame_count();
    let bar =
        if progress { indicatif::ProgressBar::new(count as u64) } else { indicatif::ProgressBar::hidden() };
    bar.set_style(
        indicatif::ProgressStyle::with_template("{bar:30} {pos}/{len} frames {msg}")
            .unwrap_or_else(|_| indicatif::ProgressStyle::default_bar()),
    );
    let busy_s = match job.path_scorer_apart() {
        Some(scorer) => track_beside_scorer(job, frames, scorer, &bar)?,
        None => {
            let mut busy_s = 0.0;
            while let Some(frame) = frames.next_frame() {
                let frame = frame?;
                let started = Instant::now();
                job.push_grey(&frame)?;
                busy_s += started.elapsed().as_secs_f64();
                bar.inc(1);
            }
            busy_s
        }
    };
    bar.finish_and_clear();
    let n = job.frames_done().max(1);
    let ms_per_frame = 1000.0 * busy_s / n as f64;
    let (export, warnings) = job.finish()?;
    Ok((export, ms_per_frame, warnings))
}

/// Tracks `frames` in `job` on this thread while `scorer` scores each
/// frame's path request on another; every energy is back in the job when
/// this returns. The seconds spent, the decoding not counted.
fn track_beside_scorer(
    job: &mut TrackingJob,
    frames: &mut Frames,
    mut scorer: PathScorer,
    bar: &indicatif::ProgressBar,
) -> Result<f64, Error> {
    job.defer_path_energies();
    std::thread::scope(|threads| {
        let (to_scorer, requests) = mpsc::sync_channel::<(PathRequest, Features)>(FRAMES_AHEAD_OF_SCORER);
        let (to_tracker, scored) = mpsc::channel::<Result<(usize, Vec<f64>), Error>>();
        threads.spawn(move || {
            for (request, features) in requests {
                let energies = scorer.energies_with(&request, &features).map(|e| (request.frame, e));
                if to_tracker.send(energies).is_err() {
                    return; // the tracker stopped on an error of its own
                }
            }
        });
        let hand_back = |job: &mut TrackingJob, energies: Result<(usize, Vec<f64>), Error>| {
            let (frame, energies) = energies?;
            job.set_path_energies(frame, energies)
        };
        let mut busy_s = 0.0;
        while let Some(frame) = frames.next_frame() {
            let frame = frame?;
            let started = Instant::now();
            job.push_grey(&frame)?;
            if let Some(work) = job.take_path_work() {
                // An error here: the scorer stopped, its error waits below.
                if to_scorer.send(work).is_err() {
                    break;
                }
            }
            while let Ok(energies) = scored.try_recv() {
                hand_back(job, energies)?;
            }
            busy_s += started.elapsed().as_secs_f64();
            bar.inc(1);
        }
        let started = Instant::now();
        drop(to_scorer);
        scored.into_iter().try_for_each(|energies| hand_back(job, energies))?;
        Ok(busy_s + started.elapsed().as_secs_f64())
    })
}

/// The endings of the video files a folder of takes or scenes is searched
/// for.
pub const VIDEO_EXTENSIONS: [&str; 5] = ["mp4", "webm", "mkv", "mov", "avi"];

/// `OUT.bvh` → `OUT.track.csv`.
fn csv_path(output: &Path) -> PathBuf {
    output.with_extension("track.csv")
}

/// `output`'s folder is there to write into: checked before the take is
/// tracked, which may take minutes, not after.
fn output_folder_exists(output: &Path) -> Result<(), Error> {
    let folder = output.parent().filter(|p| !p.as_os_str().is_empty()).unwrap_or(Path::new("."));
    if folder.is_dir() {
        return Ok(());
    }
    Err(Error::whole(
        &output.display().to_string(),
        format!("cannot be written: its folder {} does not exist (nothing was tracked)", folder.display()),
    ))
}

pub fn run_track(args: &TrackArgs) -> ExitCode {
    match track(args, "", true) {
        Ok(()) => ExitCode::SUCCESS,
        Err(e) => {
            eprintln!("error: {e}");
            ExitCode::FAILURE
        }
    }
}

/// The `i`-th of `list`, when given.
fn nth(list: &[PathBuf], i: usize) -> Option<&Path> {
    list.get(i).map(PathBuf::as_path)
}

/// One camera's view of the take, as the command line gives it.
struct ViewArgs<'a> {
    video: &'a Path,
    camera: Option<&'a Path>,
    board: Option<&'a Path>,
    intrinsics: Option<&'a Path>,
    background: Option<&'a Path>,
    offset_s: f64,
}

/// The views the command line gives: the i-th --camera (or --board,
/// --intrinsics), --background and --offset-s belong to the i-th video.
/// An error names the flag given another number of times.
fn views_of(args: &TrackArgs) -> Result<Vec<ViewArgs<'_>>, Error> {
    let videos = args.video.len();
    let per_view = |flag: &str, given: usize, may_be_absent: bool| {
        if given == videos || (may_be_absent && given == 0) {
            return Ok(());
        }
        Err(Error::whole(
            "embusen track",
            format!("{given} --{flag} for {videos} videos: give one per video, the i-th for the i-th video"),
        ))
    };
    if args.board.is_empty() {
        per_view("camera", args.camera.len(), false)?;
    } else {
        per_view("board", args.board.len(), false)?;
        per_view("intrinsics", args.intrinsics.len(), true)?;
    }
    per_view("background", args.background.len(), true)?;
    if args.offset_s.len() > 1 {
        per_view("offset-s", args.offset_s.len(), false)?;
    }
    Ok((0..videos)
        .map(|i| ViewArgs {
            video: &args.video[i],
            camera: nth(&args.camera, i),
            board: nth(&args.board, i),
            intrinsics: nth(&args.intrinsics, i),
            background: nth(&args.background, i),
            offset_s: args.offset_s.get(i).or(args.offset_s.first()).copied().unwrap_or(0.0),
        })
        .collect())
}

/// Tracks the take `args` gives and writes its files. What it says begins
/// with `said` (which take, when there are several); a progress bar with
/// `progress`.
pub fn track(args: &TrackArgs, said: &str, progress: bool) -> Result<(), Error> {
    output_folder_exists(&args.output)?;
    let views = views_of(args)?;
    let recording = read_recording(&args.bvh)?;
    let mut jobs = if let [view] = views.as_slice() {
        vec![track_view(view, &recording, args, said, progress)?]
    } else {
        track_views_at_once(&views, &recording, args, said)?
    };
    let ms_per_frame: f64 = jobs.iter().map(|(_, _, ms)| ms).sum();
    let views_said = if jobs.len() > 1 { format!(" by {} cameras", jobs.len()) } else { String::new() };
    let others = jobs.iter().skip(1).map(|(job, _, _)| job.finished_view()).collect::<Result<Vec<_>, _>>()?;
    let Some((first_job, first_export, _)) = jobs.first_mut() else {
        return Err(Error::whole("embusen track", "no video to track"));
    };
    let export = if others.is_empty() {
        first_export.clone()
    } else {
        let (export, warnings) = first_job.weigh(&others)?;
        for w in &warnings {
            eprintln!("warning: {said}{w}");
        }
        export
    };
    let track = first_job
        .track()
        .ok_or_else(|| Error::whole(&args.video[0].display().to_string(), "the tracking did not finish"))?;
    let out_name = args.output.display().to_string();
    std::fs::write(&args.output, &export.recording_text)
        .map_err(|e| Error::whole(&out_name, format!("cannot write: {e}")))?;
    let csv = csv_path(&args.output);
    std::fs::write(&csv, &export.track_csv)
        .map_err(|e| Error::whole(&csv.display().to_string(), format!("cannot write: {e}")))?;
    let seen = track.frames.iter().filter(|f| f.confidence > 0.0).count();
    println!(
        "{said}{}: {} frames tracked{views_said} ({} seen by the camera), {ms_per_frame:.1} ms per frame; wrote {out_name} and {}",
        track.method().name(),
        track.frames.len(),
        seen,
        csv.display()
    );
    Ok(())
}

/// Several views of one take, each tracked on its own thread (beside its
/// own path scorer): the views are independent until they are weighed, so
/// a take filmed by two cameras takes about as long as the longer of them
/// wherever there are cores for both. No progress bars (they would
/// overwrite each other); what each view says names it.
fn track_views_at_once(
    views: &[ViewArgs],
    recording: &Recording,
    args: &TrackArgs,
    take_said: &str,
) -> Result<Vec<(TrackingJob, TakeExport, f64)>, Error> {
    for (k, view) in views.iter().enumerate() {
        println!("{take_said}view {}: {}", k + 1, view.video.display());
    }
    std::thread::scope(|scope| {
        let running: Vec<_> = views
            .iter()
            .enumerate()
            .map(|(k, view)| {
                let said = format!("{take_said}view {} ({}): ", k + 1, view.video.display());
                scope.spawn(move || track_view(view, recording, args, &said, false))
            })
            .collect();
        // Every thread joined before the first error is returned.
        let finished: Vec<_> = running
            .into_iter()
            .zip(views)
            .map(|(thread, view)| {
                thread.join().unwrap_or_else(|_| {
                    Err(Error::whole(&view.video.display().to_string(), "its tracking thread failed"))
                })
            })
            .collect();
        finished.into_iter().collect()
    })
}

/// One view tracked to the end (its offset estimated again and tracked at
/// it, when asked): its job, what it alone writes, its ms a frame. What it
/// says begins with `said` (which view, when there are several); a
/// progress bar with `progress`.
fn track_view(
    view: &ViewArgs,
    recording: &Recording,
    args: &TrackArgs,
    said: &str,
    progress: bool,
) -> Result<(TrackingJob, TakeExport, f64), Error> {
    let camera = match (view.camera, view.board) {
        (Some(path), _) => read_camera(path)?,
        (None, Some(still)) => {
            let lens = view.intrinsics.map(read_camera).transpose()?;
            camera_from_board(still, lens.as_ref())?
        }
        (None, None) => return Err(Error::whole("embusen track", "give --camera or --board")),
    };
    let video = Video::open(view.video, args.fps)?;
    let background = video.background(view.background)?;
    let inputs = TakeInputs { recording: recording.clone(), camera, background };
    let mut job = video.job(inputs, args.method, view.offset_s)?;
    for w in job.warnings() {
        eprintln!("warning: {said}{w}");
    }
    if args.estimate_offset {
        job.keep_offset_samples();
    }
    let (mut export, mut ms_per_frame, mut warnings) = video.track(&mut job, progress)?;
    if args.estimate_offset {
        match job.estimate_offset()? {
            Some(estimate) => {
                println!(
                    "{said}estimated offset: the BVH runs {:.3} s ahead of the video",
                    estimate.offset_s
                );
                if let Some(again) = job.retrack_at(&estimate)? {
                    job = again;
                    (export, ms_per_frame, warnings) = video.track(&mut job, progress)?;
                }
            }
            None => {
                eprintln!(
                    "warning: {said}the offset could not be estimated: no sampled frame had a pose to fit"
                )
            }
        }
    }
    for w in &warnings {
        eprintln!("warning: {said}{w}");
    }
    Ok((job, export, ms_per_frame))
}
