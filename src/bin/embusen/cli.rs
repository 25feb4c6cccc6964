//! The `embusen` command line: `info`, `translate`, and (with no arguments) a
//! run on the built-in demo recording.

use std::path::{Path, PathBuf};
use std::process::ExitCode;

use clap::{Parser, Subcommand, ValueEnum};
use embusen::metrics::{floor_path_cm, mean_floor_error_cm};
use embusen::paper::{PaperParams, Smoothing};
use embusen::recording::{FeetChoice, Recording, Translated};
use embusen::table::Accelerations;
use embusen::{Error, demo};

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
}

#[derive(Clone, Copy, ValueEnum)]
enum Method {
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
    #[arg(long, value_enum, default_value = "paper")]
    method: Method,
    #[arg(long, value_enum, default_value = "faithful")]
    smoothing: SmoothingArg,
    /// Smoothing window in seconds.
    #[arg(long, default_value_t = PaperParams::default().window_s)]
    window_s: f64,
    /// Minimum smoothed foot height difference (cm) for pass 2 to pin the lower foot.
    #[arg(long, default_value_t = PaperParams::default().dy_eps_cm)]
    dy_eps: f64,
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
    }
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
    let params = PaperParams {
        window_s: args.window_s,
        dy_eps_cm: args.dy_eps,
        smoothing: match args.smoothing {
            SmoothingArg::Faithful => Smoothing::Faithful,
            SmoothingArg::Clean => Smoothing::Clean,
        },
        ..PaperParams::default()
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
        match translate_one(input, args, &params, &feet, many) {
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
    params: &PaperParams,
    feet: &FeetChoice,
    many: bool,
) -> Result<String, Error> {
    let mut recording = load(input, args.fps)?;
    if let Some(accel_path) = accel_path_for(input, args.accel.as_ref()) {
        recording.attach_accel(load_accel(&accel_path)?)?;
    }
    let translated = match args.method {
        Method::Paper => recording.translate_paper(feet, params)?,
    };
    let out_path = output_path_for(input, args.output.as_ref(), many, recording.extension());
    std::fs::write(&out_path, recording.write_shifted(&translated.shift_cm))
        .map_err(|e| Error::whole(&out_path.display().to_string(), format!("cannot write: {e}")))?;
    Ok(format!("{} → {}: {}", recording.name, out_path.display(), describe(&recording, &translated)))
}

/// One line on what the method did.
fn describe(recording: &Recording, t: &Translated) -> String {
    let frames = recording.frame_count().max(1);
    let pinned = |pass: &[Option<embusen::feet::Foot>]| pass.iter().filter(|p| p.is_some()).count();
    let hips_before = floor_path_cm(&recording.poses.trajectory(t.hips));
    let hips_after = floor_path_cm(&t.poses.trajectory(t.hips));
    format!(
        "{} frames at {} Hz, feet {}/{}, accel from {}; pinned in {:.0}% (pass 1) and {:.0}% (pass 2) of frames; hips floor path {:.2} m → {:.2} m{}",
        recording.frame_count(),
        hz(recording.fps),
        recording.joint_names[t.feet.left],
        recording.joint_names[t.feet.right],
        t.accel_source,
        100.0 * pinned(&t.paper.pass1_pinned) as f64 / frames as f64,
        100.0 * pinned(&t.paper.pass2_pinned) as f64 / frames as f64,
        hips_before / 100.0,
        hips_after / 100.0,
        t.paper.warnings.iter().map(|w| format!("; warning: {w}")).collect::<String>(),
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
        "  {} frames at {} Hz ({:.1} s); its true translation was removed and is now estimated again",
        recording.frame_count(),
        hz(recording.fps),
        recording.duration_s()
    );
    let translated = match recording.translate_paper(&FeetChoice::default(), &PaperParams::default()) {
        Ok(t) => t,
        Err(e) => {
            eprintln!("error: {e}");
            return ExitCode::FAILURE;
        }
    };
    println!("  method paper: {}", describe(&recording, &translated));
    let estimated = translated.poses.trajectory(translated.hips);
    let truth = &demo.true_root_cm;
    let mean_error_cm = mean_floor_error_cm(&estimated, truth);
    println!(
        "  true hips floor path {:.2} m; mean horizontal error of the estimate {:.1} cm",
        floor_path_cm(truth) / 100.0,
        mean_error_cm
    );
    println!("  try: embusen translate FILE.bvh   (see embusen --help)");
    ExitCode::SUCCESS
}
