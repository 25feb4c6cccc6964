//! The `embusen` command line: `info`, `translate`, `eval`, `calibrate`, and
//! (with no arguments) a run on the built-in demo recording.

use std::path::{Path, PathBuf};
use std::process::ExitCode;

use clap::{Parser, Subcommand, ValueEnum};
use embusen::Error;
use embusen::eval::demo::{PathError, evaluate_demo, vendor_error};
use embusen::eval::metrics::floor_path_cm;
use embusen::io::recording::{FeetChoice, Recording};
use embusen::io::table::Accelerations;
use embusen::synth::demo;
use embusen::translate::contact::{ContactParams, Support};
use embusen::translate::hachaj::{HachajParams, Smoothing};
use embusen::translate::{Decisions, Method, Translated};

#[derive(Parser)]
#[command(
    name = "embusen",
    version,
    about = "Gives inertial motion-capture recordings their place on the floor."
)]
struct Cli {
    #[command(subcommand)]
    command: Option<Command>,
}

#[derive(Subcommand)]
enum Command {
    /// The camera from stills of a ChArUco board (its layout from BOARD.json
    /// beside each still, or from flags), written as camera.json.
    #[cfg(feature = "board")]
    Calibrate(crate::calibrate::CalibrateArgs),
    /// Track the actor on the floor from a video and the suit's BVH of the
    /// same take, with a calibrated camera: writes the corrected BVH and the
    /// hips track (CSV, with the camera's confidence per frame).
    Track(crate::track::TrackArgs),
    /// Track every take in some folders, several at once (as many as there
    /// are cores): each as `track` would, its corrected BVH and hips track
    /// written into one output folder.
    TrackTakes(crate::takes::TrackTakesArgs),
    /// Measure the trackers on scenes whose true hips path is known: per
    /// scene and as medians, the suit's own translation, `paper` and `fused`.
    EvalTrack(crate::eval_track::EvalTrackArgs),
    /// Recompute the floor translation of recordings (BVH in → BVH out, table in → table out).
    Translate(TranslateArgs),
    /// Print joints, frames, rate, duration, detected feet and reader warnings.
    Info {
        #[arg(required = true)]
        inputs: Vec<PathBuf>,
        /// Frame rate for files that do not state one (`Frame Time: 0`).
        #[arg(long)]
        fps: Option<f64>,
    },
    /// Measure both methods: ground-truth BVHs (translation removed and
    /// re-estimated, compared with the truth), suit-grade BVHs (the same,
    /// compared with their own truth, beside the leg-length oracle) and katas
    /// (how far the hips end from where they started). Directories are
    /// searched for `.bvh` files.
    Eval {
        /// Ground-truth BVHs, suit-grade BVHs (any named `NAME.suit-TAG.bvh`,
        /// whose truth is `NAME.bvh`), or directories of them.
        #[arg(required_unless_present = "pair")]
        inputs: Vec<PathBuf>,
        /// Recordings that end where they start (katas): BVH (with
        /// `<name>.accel.csv` beside it, if any) or tables, or directories.
        #[arg(long, num_args = 1..)]
        closure: Vec<PathBuf>,
        /// Folder of the suit files' truths. Default: `../groundtruth/` from
        /// the suit file's folder, else the suit file's own folder.
        #[arg(long, value_name = "DIR")]
        truth: Option<PathBuf>,
        /// A suit-grade BVH and its truth, whatever their names (repeatable).
        #[arg(long, num_args = 2, value_names = ["SUIT", "TRUTH"])]
        pair: Vec<PathBuf>,
    },
}

#[derive(Clone, Copy, ValueEnum)]
enum MethodArg {
    /// Foot contacts frame by frame, with flight (embusen's own).
    Contact,
    /// Hachaj & Ogiela's heuristic, as the authors' R code computes it.
    Paper,
}

#[derive(Clone, Copy, ValueEnum)]
enum SmoothingArg {
    /// R `smoother` exactly: window in samples from its formula, zeroed tails.
    Faithful,
    /// Gaussian with the window in seconds, renormalised at the edges.
    Clean,
}

#[derive(clap::Args)]
struct TranslateArgs {
    /// BVH files or RMoCap/Shadow CSV tables.
    #[arg(required = true)]
    inputs: Vec<PathBuf>,
    /// Accelerometer side file for a single BVH input (by default
    /// `<name>.accel.csv` next to a BVH is used when it exists).
    #[arg(long)]
    accel: Option<PathBuf>,
    /// Output file (one input) or directory (any number of inputs). Default:
    /// `<name>.embusen.<ext>` next to each input.
    #[arg(short, long)]
    output: Option<PathBuf>,
    #[arg(long, value_enum, default_value = "contact")]
    method: MethodArg,
    /// Paper method: smoothing mode.
    #[arg(long, value_enum, default_value = "faithful")]
    smoothing: SmoothingArg,
    /// Paper method: smoothing window in seconds.
    #[arg(long, default_value_t = HachajParams::default().window_s)]
    window_s: f64,
    /// Paper method: minimum smoothed foot height difference (cm) for pass 2 to pin the lower foot.
    #[arg(long, default_value_t = HachajParams::default().dy_eps_cm)]
    dy_eps: f64,
    /// Contact method: how far (cm) the sole lies below the foot's lowest
    /// joint when the foot stands flat (0 when that joint is a toe end site on
    /// the skin). Estimated from the recording when not given.
    #[arg(long)]
    sole_depth_cm: Option<f64>,
    /// Frame rate for files that do not state one.
    #[arg(long)]
    fps: Option<f64>,
    /// Name of the left foot joint (detected from common names by default).
    #[arg(long)]
    left_foot: Option<String>,
    /// Name of the right foot joint.
    #[arg(long)]
    right_foot: Option<String>,
}

pub fn main() -> ExitCode {
    let cli = Cli::parse();
    match cli.command {
        None => run_demo(),
        Some(Command::Info { inputs, fps }) => run_info(&inputs, fps),
        Some(Command::Translate(args)) => run_translate(&args),
        #[cfg(feature = "board")]
        Some(Command::Calibrate(args)) => crate::calibrate::run(&args),
        Some(Command::Track(args)) => crate::track::run_track(&args),
        Some(Command::TrackTakes(args)) => crate::takes::run_track_takes(&args),
        Some(Command::EvalTrack(args)) => crate::eval_track::run_eval_track(&args),
        Some(Command::Eval { inputs, closure, truth, pair }) => {
            run_eval(&inputs, &closure, truth.as_deref(), &pair)
        }
    }
}

/// Files named on the command line, with directories replaced by their
/// `.bvh` files (sorted).
fn expand(inputs: &[PathBuf]) -> Vec<PathBuf> {
    let mut files = Vec::new();
    for input in inputs {
        match std::fs::read_dir(input) {
            Ok(entries) => {
                let mut found: Vec<PathBuf> = entries
                    .filter_map(|e| e.ok().map(|e| e.path()))
                    .filter(|p| p.extension().is_some_and(|e| e.eq_ignore_ascii_case("bvh")))
                    .collect();
                found.sort();
                files.extend(found);
            }
            Err(_) => files.push(input.clone()),
        }
    }
    files
}

/// The last part of `path` (its file name, without the folders), as the
/// tables show it.
fn base_name(path: &Path) -> String {
    path.file_name().map_or(path.display().to_string(), |n| n.to_string_lossy().into_owned())
}

/// Reads a BVH, naming it `name` in the error if it is a table (`why`: what
/// a BVH is needed for).
fn load_bvh(path: &Path, name: &str, why: &str) -> Result<embusen::io::bvh::Bvh, Error> {
    match load(path, None)?.source {
        embusen::io::recording::Source::Bvh(bvh) => Ok(bvh),
        embusen::io::recording::Source::Table(_) => Err(Error::whole(name, why)),
    }
}

/// The truth of the suit file `suit` (`NAME.suit-TAG.bvh`): `NAME.bvh` in
/// `truth_dir` if given, else in `../groundtruth/` from the suit file's
/// folder, else beside it.
fn truth_path_for(suit: &Path, truth_dir: Option<&Path>) -> Result<PathBuf, Error> {
    let name = base_name(suit);
    let Some(truth_name) = embusen::eval::suit::truth_file_name(&name) else {
        return Err(Error::whole(&suit.display().to_string(), "is not named NAME.suit-TAG.bvh"));
    };
    let folder = suit.parent().unwrap_or(Path::new(""));
    let candidates = match truth_dir {
        Some(dir) => vec![dir.join(&truth_name)],
        None => vec![folder.join("..").join("groundtruth").join(&truth_name), folder.join(&truth_name)],
    };
    candidates.iter().find(|c| c.is_file()).cloned().ok_or_else(|| {
        let looked: Vec<String> = candidates.iter().map(|c| c.display().to_string()).collect();
        Error::whole(
            &suit.display().to_string(),
            format!(
                "its truth is not found (looked for {}); give --truth DIR or --pair SUIT TRUTH",
                looked.join(" and ")
            ),
        )
    })
}

fn run_eval(
    inputs: &[PathBuf],
    closure: &[PathBuf],
    truth_dir: Option<&Path>,
    pairs: &[PathBuf],
) -> ExitCode {
    use embusen::eval::kata_closure_cm;
    let (suits, groundtruths): (Vec<PathBuf>, Vec<PathBuf>) = expand(inputs)
        .into_iter()
        .partition(|p| embusen::eval::suit::suit_name_parts(&base_name(p)).is_some());
    // Each suit file with its truth, or why it has none.
    let mut suit_pairs: Vec<(PathBuf, Result<PathBuf, Error>)> =
        suits.into_iter().map(|s| (s.clone(), truth_path_for(&s, truth_dir))).collect();
    suit_pairs.extend(pairs.chunks_exact(2).map(|p| (p[0].clone(), Ok(p[1].clone()))));
    let mut failed = 0;
    // Without suit files the ground-truth table is printed even when empty: its header says what was asked for.
    if !groundtruths.is_empty() || suit_pairs.is_empty() {
        failed += eval_groundtruth(&groundtruths);
    }
    if !suit_pairs.is_empty() {
        failed += eval_suits(&suit_pairs);
    }
    let methods = [Method::Hachaj(HachajParams::default()), Method::default()];
    let closure_files = expand(closure);
    if !closure_files.is_empty() {
        println!("katas: hips floor distance between the first and last frame, vendor translation removed");
        println!("{:<36} {:>10} {:>10}", "file", "paper cm", "contact cm");
    }
    for path in closure_files {
        let result = load(&path, None).and_then(|mut recording| {
            if let Some(accel) = accel_path_for(&path, None) {
                recording.attach_accel(load_accel(&accel)?)?;
            }
            Ok([kata_closure_cm(&recording, &methods[0])?, kata_closure_cm(&recording, &methods[1])?])
        });
        match result {
            Ok([p, c]) => println!("{:<36} {:>10.1} {:>10.1}", path.display(), p, c),
            Err(e) => {
                eprintln!("error: {e}");
                failed += 1;
            }
        }
    }
    if failed > 0 { ExitCode::FAILURE } else { ExitCode::SUCCESS }
}

/// Prints the ground-truth table and its medians; returns how many files failed.
fn eval_groundtruth(paths: &[PathBuf]) -> usize {
    use embusen::eval::summary::{evaluate_file, format_file, format_header, format_summary, summarise};
    let mut failed = 0;
    let mut files = Vec::new();
    println!("{}", format_header());
    for path in paths {
        let name = base_name(path);
        let result = load_bvh(path, &name, "ground truth must be a BVH (its root channels are the truth)")
            .and_then(|bvh| evaluate_file(&bvh, &name));
        match result {
            Ok(file) => {
                println!("{}", format_file(&file));
                files.push(file);
            }
            Err(e) => {
                eprintln!("error: {e}");
                failed += 1;
            }
        }
    }
    if !files.is_empty() {
        print!("{}", format_summary(&summarise(&files)));
    }
    failed
}

/// Prints the suit table (each suit file against its truth, or the error of
/// finding that) and its medians; returns how many files failed.
fn eval_suits(pairs: &[(PathBuf, Result<PathBuf, Error>)]) -> usize {
    use embusen::eval::suit::{
        evaluate_suit_file, format_suit_file, format_suit_header, format_suit_summary, summarise_suit,
    };
    let mut failed = 0;
    let mut files = Vec::new();
    println!("{}", format_suit_header());
    for (suit_path, truth_path) in pairs {
        let name = base_name(suit_path);
        let result = truth_path.clone().and_then(|truth_path| {
            let suit =
                load_bvh(suit_path, &name, "a suit file must be a BVH (its pose is what is measured)")?;
            let truth = load_bvh(
                &truth_path,
                &base_name(&truth_path),
                "a truth must be a BVH (its root channels are the truth)",
            )?;
            evaluate_suit_file(&suit, &truth, &name)
        });
        match result {
            Ok(file) => {
                println!("{}", format_suit_file(&file));
                files.push(file);
            }
            Err(e) => {
                eprintln!("error: {e}");
                failed += 1;
            }
        }
    }
    if !files.is_empty() {
        print!("{}", format_suit_summary(&summarise_suit(&files)));
    }
    failed
}

/// Reads a file into a [`Recording`], naming the file in any error.
fn load(path: &Path, fps: Option<f64>) -> Result<Recording, Error> {
    let name = path.display().to_string();
    let bytes = std::fs::read(path).map_err(|e| Error::whole(&name, format!("cannot read: {e}")))?;
    Recording::parse(&bytes, &name, fps)
}

fn load_accel(path: &Path) -> Result<Accelerations, Error> {
    let name = path.display().to_string();
    let bytes = std::fs::read(path).map_err(|e| Error::whole(&name, format!("cannot read: {e}")))?;
    Accelerations::parse(&bytes, &name)
}

fn run_info(inputs: &[PathBuf], fps: Option<f64>) -> ExitCode {
    let mut failed = false;
    for path in inputs {
        match load(path, fps) {
            Ok(recording) => print_info(&recording),
            Err(e) => {
                eprintln!("error: {e}");
                failed = true;
            }
        }
    }
    if failed { ExitCode::FAILURE } else { ExitCode::SUCCESS }
}

fn print_info(r: &Recording) {
    println!("{}", r.name);
    println!("  format:   {}", if r.extension() == "bvh" { "BVH" } else { "RMoCap/Shadow table" });
    println!("  frames:   {}", r.frame_count());
    println!("  rate:     {} Hz", hz(r.fps));
    println!("  duration: {:.2} s", r.duration_s());
    println!("  joints:   {} ({})", r.joint_names.len(), r.joint_names.join(", "));
    match r.feet(&FeetChoice::default()) {
        Ok(feet) => println!("  feet:     {} / {}", r.joint_names[feet.left], r.joint_names[feet.right]),
        Err(_) => println!("  feet:     not detected (use --left-foot/--right-foot)"),
    }
    match &r.accel {
        Some(a) => println!("  accel:    {} sensors", a.sensor_names.len()),
        None => println!("  accel:    none (the paper method will use the kinematics)"),
    }
    for w in &r.warnings {
        println!("  warning:  {w}");
    }
}

/// The accelerometer file for `input`: the one given, or `<stem>.accel.csv`.
fn accel_path_for(input: &Path, given: Option<&PathBuf>) -> Option<PathBuf> {
    if let Some(p) = given {
        return Some(p.clone());
    }
    let stem = input.file_stem()?.to_str()?;
    let candidate = input.with_file_name(format!("{stem}.accel.csv"));
    (input.extension().is_some_and(|e| e.eq_ignore_ascii_case("bvh")) && candidate.exists())
        .then_some(candidate)
}

fn output_path_for(input: &Path, output: Option<&PathBuf>, many: bool, extension: &str) -> PathBuf {
    let stem = input.file_stem().and_then(|s| s.to_str()).unwrap_or("out");
    let file_name = format!("{stem}.embusen.{extension}");
    match output {
        Some(o) if many || o.is_dir() => o.join(file_name),
        Some(o) => o.clone(),
        None => input.with_file_name(file_name),
    }
}

fn run_translate(args: &TranslateArgs) -> ExitCode {
    if args.accel.is_some() && args.inputs.len() > 1 {
        eprintln!("error: --accel names the side file of one BVH; give one input with it");
        return ExitCode::from(2);
    }
    let many = args.inputs.len() > 1;
    if let Some(dir) = args.output.as_ref().filter(|_| many)
        && let Err(e) = std::fs::create_dir_all(dir)
    {
        eprintln!("error: {}: cannot create the output directory: {e}", dir.display());
        return ExitCode::FAILURE;
    }
    let method = match args.method {
        MethodArg::Contact => {
            let params = ContactParams { sole_depth_cm: args.sole_depth_cm, ..ContactParams::default() };
            if let Err(message) = params.check() {
                eprintln!("error: --sole-depth-cm: {message}");
                return ExitCode::from(2);
            }
            Method::Contact(params)
        }
        MethodArg::Paper => Method::Hachaj(HachajParams {
            window_s: args.window_s,
            dy_eps_cm: args.dy_eps,
            smoothing: match args.smoothing {
                SmoothingArg::Faithful => Smoothing::Faithful,
                SmoothingArg::Clean => Smoothing::Clean,
            },
            ..HachajParams::default()
        }),
    };
    let feet = FeetChoice { left: args.left_foot.clone(), right: args.right_foot.clone() };
    let bar = indicatif::ProgressBar::new(args.inputs.len() as u64);
    bar.set_style(
        indicatif::ProgressStyle::with_template("{bar:30} {pos}/{len} {msg}")
            .unwrap_or_else(|_| indicatif::ProgressStyle::default_bar()),
    );
    let mut failed = 0;
    for input in &args.inputs {
        bar.set_message(input.display().to_string());
        match translate_one(input, args, &method, &feet, many) {
            // `suspend` keeps the bar from overdrawing the line; a hidden bar
            // (output not a terminal) would swallow `bar.println`.
            Ok(summary) => bar.suspend(|| println!("{summary}")),
            Err(e) => {
                bar.suspend(|| eprintln!("error: {e}"));
                failed += 1;
            }
        }
        bar.inc(1);
    }
    bar.finish_and_clear();
    if failed > 0 {
        eprintln!("{failed} of {} files failed", args.inputs.len());
        ExitCode::FAILURE
    } else {
        ExitCode::SUCCESS
    }
}

fn translate_one(
    input: &Path,
    args: &TranslateArgs,
    method: &Method,
    feet: &FeetChoice,
    many: bool,
) -> Result<String, Error> {
    let mut recording = load(input, args.fps)?;
    if let Some(accel_path) = accel_path_for(input, args.accel.as_ref()) {
        recording.attach_accel(load_accel(&accel_path)?)?;
    }
    let translated = recording.translate(feet, method)?;
    let out_path = output_path_for(input, args.output.as_ref(), many, recording.extension());
    std::fs::write(&out_path, recording.write_shifted(&translated.shift_cm))
        .map_err(|e| Error::whole(&out_path.display().to_string(), format!("cannot write: {e}")))?;
    Ok(format!("{} → {}: {}", recording.name, out_path.display(), describe(&recording, &translated)))
}

/// One line on what the method did.
fn describe(recording: &Recording, t: &Translated) -> String {
    let frames = recording.frame_count().max(1);
    let percent = |count: usize| 100.0 * count as f64 / frames as f64;
    let decided = match &t.decisions {
        Decisions::Hachaj(p) => {
            let pinned =
                |pass: &[Option<embusen::body::feet::Foot>]| pass.iter().filter(|p| p.is_some()).count();
            format!(
                "method paper: pinned in {:.0}% (pass 1) and {:.0}% (pass 2) of frames",
                percent(pinned(&p.pass1_pinned)),
                percent(pinned(&p.pass2_pinned))
            )
        }
        Decisions::Contact(c) => {
            let count = |want: fn(&Support) -> bool| c.support.iter().filter(|s| want(s)).count();
            format!(
                "method contact: one foot down in {:.0}%, both in {:.0}%, flight in {:.0}% of frames, {}",
                percent(count(|s| matches!(s, Support::Single(_)))),
                percent(count(|s| matches!(s, Support::Double))),
                percent(count(|s| matches!(s, Support::Flight))),
                c.sole_depth_cm.map_or("feet without toes (ankles pinned)".to_string(), |d| format!(
                    "sole {d} cm below the lowest foot joint"
                ))
            )
        }
    };
    format!(
        "{} frames at {} Hz, feet {}/{}, accel from {}; {decided}; hips floor path {:.2} m → {:.2} m{}",
        recording.frame_count(),
        hz(recording.fps),
        recording.joint_names[t.feet.left],
        recording.joint_names[t.feet.right],
        t.accel_source,
        floor_path_cm(&recording.poses.trajectory(t.hips)) / 100.0,
        floor_path_cm(&t.poses.trajectory(t.hips)) / 100.0,
        t.decisions.warnings().iter().map(|w| format!("; warning: {w}")).collect::<String>(),
    )
}

/// A frame rate as people write it: `30` for 30.00003 (a `Frame Time` of
/// 0.0333333), `29.97` for NTSC.
fn hz(fps: f64) -> String {
    let text = format!("{fps:.2}");
    text.trim_end_matches('0').trim_end_matches('.').to_string()
}

fn run_demo() -> ExitCode {
    let demo = demo::demo();
    let recording = demo.recording();
    println!("embusen on the built-in demo: {}", demo::DEMO_NAME);
    println!(
        "  {} frames at {} Hz ({:.1} s) of a kata as an inertial suit records it (orientation errors, \
         bones {:+.1}% in the legs); the suit's translation was removed and is now estimated again",
        recording.frame_count(),
        hz(recording.fps),
        recording.duration_s(),
        100.0 * (demo.leg_length_ratio - 1.0)
    );
    println!("  true hips floor path {:.2} m", floor_path_cm(&demo.true_root_cm) / 100.0);
    let mut errors = Vec::new();
    for method in [Method::default(), Method::Hachaj(HachajParams::default())] {
        let (translated, error) = match evaluate_demo(&demo, &method) {
            Ok(t) => t,
            Err(e) => {
                eprintln!("error: {e}");
                return ExitCode::FAILURE;
            }
        };
        println!("  {}", describe(&recording, &translated));
        errors.push((method.name(), error));
    }
    println!(
        "  hips error against the truth, on the floor (% of the true path), and the path's length over the truth's:"
    );
    let line = |name: &str, e: &PathError| {
        println!(
            "    {name:<7} mean {:5.1} cm ({:.2}%), final {:5.1} cm ({:.2}%), path {:.2} ×",
            e.mean_cm,
            e.mean_pct(),
            e.final_cm,
            e.final_pct(),
            e.path_ratio
        )
    };
    for (name, error) in &errors {
        line(name, error);
    }
    line("vendor", &vendor_error(&demo));
    errors.sort_by(|a, b| a.1.mean_cm.total_cmp(&b.1.mean_cm));
    if let [(best, b), (other, o)] = errors.as_slice() {
        println!(
            "  {best} is better on this demo: its mean error is {:.1} cm, {other}'s {:.1} cm",
            b.mean_cm, o.mean_cm
        );
    }
    println!("  try: embusen translate FILE.bvh   (see embusen --help)");
    ExitCode::SUCCESS
}
