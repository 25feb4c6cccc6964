//! `embusen track-takes`: every take in some folders, several tracked at
//! once. A take is tracked as `embusen track` tracks it (the same bytes);
//! the takes are independent, so a session's takes take about as long as
//! the longest of them on each core.

use std::path::{Path, PathBuf};
use std::process::ExitCode;
use std::sync::Mutex;
use std::sync::atomic::{AtomicUsize, Ordering};

use embusen::Error;
use embusen::track::tracker::TrackMethod;

use crate::track::{TrackArgs, VIDEO_EXTENSIONS, method_parser, track};

#[derive(clap::Args)]
pub struct TrackTakesArgs {
    /// Folders of takes: each video `NAME.mp4` (or `.webm`, `.mkv`, `.mov`,
    /// `.avi`) with the suit's `NAME.bvh` (or `NAME.suit.bvh`) and its
    /// camera, `NAME.camera.json` or a still of the board on the floor
    /// `NAME.board.png`; `NAME.background.png` when there is one. A video
    /// with no BVH beside it is not a take (it is named, and left).
    #[arg(required = true)]
    folders: Vec<PathBuf>,
    /// The folder the corrected BVHs and hips tracks go to, as `NAME.bvh`
    /// and `NAME.track.csv`.
    #[arg(short, long, value_name = "FOLDER")]
    output: PathBuf,
    #[arg(long, value_parser = method_parser(), default_value = "fused")]
    method: TrackMethod,
    /// How many takes are tracked at once (each on two threads: the
    /// tracker and its path scorer); by default as many as there are cores.
    #[arg(long, value_parser = clap::value_parser!(u16).range(1..))]
    at_once: Option<u16>,
}

pub fn run_track_takes(args: &TrackTakesArgs) -> ExitCode {
    match track_takes(args) {
        Ok(()) => ExitCode::SUCCESS,
        Err(e) => {
            eprintln!("error: {e}");
            ExitCode::FAILURE
        }
    }
}

/// One take found in a folder.
struct Take {
    name: String,
    video: PathBuf,
    bvh: PathBuf,
    /// `NAME.camera.json` when there is one (it is used), and
    /// `NAME.board.png` (used where there is no camera).
    camera: Option<PathBuf>,
    board: Option<PathBuf>,
    background: Option<PathBuf>,
}

/// The takes in `folder`, by name; a video without a BVH said and left.
fn takes_in(folder: &Path) -> Result<Vec<Take>, Error> {
    let folder_name = folder.display().to_string();
    let entries =
        std::fs::read_dir(folder).map_err(|e| Error::whole(&folder_name, format!("cannot read: {e}")))?;
    // Each video by name, the first of VIDEO_EXTENSIONS's endings where a
    // take has several (walk.mp4 and walk.webm: walk.mp4).
    let mut videos: Vec<(String, usize, PathBuf)> = entries
        .filter_map(|entry| {
            let path = entry.ok()?.path();
            let name = path.file_stem()?.to_str()?.to_string();
            let extension = path.extension()?.to_str()?.to_ascii_lowercase();
            let rank = VIDEO_EXTENSIONS.iter().position(|e| *e == extension)?;
            path.is_file().then_some((name, rank, path))
        })
        .collect();
    videos.sort();
    videos.dedup_by(|later, first| {
        let same_take = later.0 == first.0;
        if same_take {
            eprintln!("note: {} is left: {} is this take's video", later.2.display(), first.2.display());
        }
        same_take
    });
    let existing = |name: &str, endings: &[&str]| {
        endings.iter().map(|ending| folder.join(format!("{name}{ending}"))).find(|p| p.is_file())
    };
    let mut takes = Vec::new();
    for (name, _, video) in videos {
        let Some(bvh) = existing(&name, &[".bvh", ".suit.bvh"]) else {
            eprintln!("note: {} is not a take: no {name}.bvh or {name}.suit.bvh beside it", video.display());
            continue;
        };
        takes.push(Take {
            camera: existing(&name, &[".camera.json"]),
            board: existing(&name, &[".board.png"]),
            background: existing(&name, &[".background.png"]),
            name,
            video,
            bvh,
        });
    }
    Ok(takes)
}

/// `take`'s `embusen track` arguments, writing into `output`.
fn track_args_of(take: &Take, output: &Path, method: TrackMethod) -> Result<TrackArgs, Error> {
    let out_bvh = output.join(format!("{}.bvh", take.name));
    let same_file =
        |a: &Path, b: &Path| a.canonicalize().ok().is_some_and(|a| b.canonicalize().ok() == Some(a));
    if same_file(&out_bvh, &take.bvh) {
        return Err(Error::whole(
            &take.bvh.display().to_string(),
            "is this take's suit recording and its output: write the takes into another folder",
        ));
    }
    let (camera, board) = match (&take.camera, &take.board) {
        (Some(camera), _) => (vec![camera.clone()], vec![]),
        (None, Some(board)) => (vec![], vec![board.clone()]),
        (None, None) => {
            return Err(Error::whole(
                &take.video.display().to_string(),
                format!("no camera: {0}.camera.json or {0}.board.png beside it", take.name),
            ));
        }
    };
    Ok(TrackArgs {
        video: vec![take.video.clone()],
        bvh: take.bvh.clone(),
        camera,
        board,
        intrinsics: vec![],
        background: take.background.iter().cloned().collect(),
        method,
        offset_s: vec![],
        estimate_offset: false,
        fps: None,
        output: out_bvh,
    })
}

fn track_takes(args: &TrackTakesArgs) -> Result<(), Error> {
    if !args.output.is_dir() {
        return Err(Error::whole(
            &args.output.display().to_string(),
            "is not a folder to write the takes into (nothing was tracked)",
        ));
    }
    // Each folder once, and never the output: a take's corrected BVH
    // would sit where its suit recording is, and be read as one next time.
    let output = args.output.canonicalize().unwrap_or_else(|_| args.output.clone());
    let mut folders: Vec<PathBuf> = Vec::new();
    for folder in &args.folders {
        let canonical = folder.canonicalize().unwrap_or_else(|_| folder.clone());
        if canonical == output {
            return Err(Error::whole(
                &folder.display().to_string(),
                "is the output folder too: write the takes into another folder (nothing was tracked)",
            ));
        }
        if !folders.contains(&canonical) {
            folders.push(canonical);
        }
    }
    let mut takes = Vec::new();
    for folder in &folders {
        takes.extend(takes_in(folder)?);
    }
    // Two takes of one name would write the same files.
    let mut names: Vec<&str> = takes.iter().map(|t| t.name.as_str()).collect();
    names.sort_unstable();
    if let Some(pair) = names.windows(2).find(|pair| pair[0] == pair[1]) {
        return Err(Error::whole("embusen track-takes", format!("two takes named {}: rename one", pair[0])));
    }
    if takes.is_empty() {
        return Err(Error::whole(
            "embusen track-takes",
            "no take (a video with NAME.bvh beside it) in the folders",
        ));
    }
    let cores = std::thread::available_parallelism().map_or(1, |n| n.get());
    let at_once = args.at_once.map_or(cores, usize::from).min(takes.len());
    println!("{} takes, {at_once} at once", takes.len());
    let failed = track_at_once(&takes, at_once, |take| {
        let said = format!("{}: ", take.name);
        let tracked = track_args_of(take, &args.output, args.method)
            .and_then(|track_args| track(&track_args, &said, false));
        if let Err(e) = &tracked {
            eprintln!("error: {said}{e}");
        }
        tracked
    });
    if failed.is_empty() {
        return Ok(());
    }
    let others = if failed.len() < takes.len() { " (the others are written)" } else { "" };
    Err(Error::whole(
        "embusen track-takes",
        format!("{} of {} takes failed{others}", failed.len(), takes.len()),
    ))
}

/// Runs `track_one` on every take, `at_once` threads taking the next take
/// as each finishes one; the takes that failed, with their errors, in
/// order. A take that panics fails alone: the others are tracked and the
/// failures listed.
fn track_at_once(
    takes: &[Take],
    at_once: usize,
    track_one: impl Fn(&Take) -> Result<(), Error> + Sync,
) -> Vec<(&Take, Error)> {
    let next = AtomicUsize::new(0);
    let failed = Mutex::new(Vec::new());
    std::thread::scope(|scope| {
        for _ in 0..at_once.max(1) {
            scope.spawn(|| {
                while let Some(take) = takes.get(next.fetch_add(1, Ordering::Relaxed)) {
                    let tracked = std::panic::catch_unwind(std::panic::AssertUnwindSafe(|| track_one(take)))
                        .unwrap_or_else(|_| {
                            Err(Error::whole(&take.video.display().to_string(), "its tracking thread failed"))
                        });
                    if let Err(e) = tracked {
                        failed.lock().unwrap_or_else(|poisoned| poisoned.into_inner()).push((take, e));
                    }
                }
            });
        }
    });
    let mut failed = failed.into_inner().unwrap_or_else(|poisoned| poisoned.into_inner());
    failed.sort_by(|a, b| a.0.name.cmp(&b.0.name));
    failed
}
