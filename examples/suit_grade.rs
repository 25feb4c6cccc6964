//! Suit-grade versions of ground-truth BVHs: each input through the
//! inertial-suit error model (`embusen::synth::suit`) at every level and
//! seed asked for, written as `OUTDIR/NAME.suit-l{LEVEL}-s{SEED}.bvh`, the
//! names `embusen eval` pairs with their truth `NAME.bvh` (it looks in
//! `OUTDIR/../groundtruth/` or takes `--truth DIR`).
//!
//! ```text
//! cargo run --release --example suit_grade -- --levels 1,0.5 --seeds 3-12 OUTDIR IN.bvh...
//! ```
//!
//! The feet are found by their names (`LeftFoot`, `Foot_L`, …) unless
//! given; the leg-length ratio the vendor's translation is scaled by is the
//! left leg's (thigh and shank, left and right are scaled alike).
//!
//! What a seed draws: the model's generator starts from the seed mixed with
//! the input's name ([`draw_state`]), so each motion of a seed has its own
//! suit (as in the shared suit files: one leg-length error per file), and
//! the seeds 1, 2, 3… draw as unlike suits as any. One seed's levels are one
//! draw: level 0.5 of seed 3 has exactly half of each error of level 1 of
//! seed 3, so levels compare pair by pair.
//!
//! The errors' sizes are by default the ones the shared suit files measure
//! (`ErrorSizes::MEASURED`); `--sizes described` gives the README's words'
//! (`ErrorSizes::DESCRIBED`), the files this example wrote before 2026-12-05.

use std::path::{Path, PathBuf};
use std::process::ExitCode;

use clap::Parser;
use embusen::body::feet::resolve_feet;
use embusen::error::Error;
use embusen::io::bvh::{Bvh, ReadOptions};
use embusen::io::recording::bvh_stem;
use embusen::synth::rng::mixed_state;
use embusen::synth::suit::{self, ErrorSizes, SuitBody};

#[derive(Parser)]
#[command(about = "Writes suit-grade versions of ground-truth BVHs (the inertial-suit error model).")]
struct Args {
    /// Error levels, comma-separated: 1 is the real suit's errors, 0.5 half
    /// of every one; any number ≥ 0.
    #[arg(long, default_value = "1")]
    levels: String,
    /// Seeds: whole numbers and ranges, comma-separated (`3-12`, `1,4,9-11`).
    #[arg(long)]
    seeds: String,
    /// The errors' sizes: `measured` (on the shared suit files) or
    /// `described` (by their README).
    #[arg(long, default_value = "measured", value_parser = ["measured", "described"])]
    sizes: String,
    /// Frame rate for files whose `Frame Time` is 0.
    #[arg(long)]
    fps: Option<f64>,
    /// Name of the left foot joint (detected from common names by default).
    #[arg(long)]
    left_foot: Option<String>,
    /// Name of the right foot joint.
    #[arg(long)]
    right_foot: Option<String>,
    /// Folder the suit files are written to (made if missing).
    out_dir: PathBuf,
    /// Ground-truth BVH files.
    #[arg(required = true)]
    inputs: Vec<PathBuf>,
}

/// The most seeds one run takes: 100000 files an input is already more
/// than any evaluation reads.
const MAX_SEEDS: u64 = 100_000;

/// `1,0.5` → [1.0, 0.5]: finite, ≥ 0, none twice.
fn parse_levels(text: &str) -> Result<Vec<f64>, String> {
    let mut levels: Vec<f64> = Vec::new();
    for word in text.split(',').map(str::trim) {
        let level: f64 = word.parse().map_err(|_| format!("--levels: `{word}` is no number"))?;
        if !level.is_finite() || level < 0.0 {
            return Err(format!("--levels: {word} is not a level (a number ≥ 0: 1 the real suit, 0.5 half)"));
        }
        if !levels.contains(&level) {
            levels.push(level);
        }
    }
    Ok(levels)
}

/// `3-12`, `1,4,9-11` → the seeds, in the order given, none twice; at most
/// [`MAX_SEEDS`].
fn parse_seeds(text: &str) -> Result<Vec<u64>, String> {
    let number = |word: &str| -> Result<u64, String> {
        word.trim().parse().map_err(|_| format!("--seeds: `{}` is no whole number", word.trim()))
    };
    let mut seeds: Vec<u64> = Vec::new();
    let mut seen = std::collections::HashSet::new();
    for item in text.split(',') {
        let (first, last) = match item.split_once('-') {
            Some((a, b)) => (number(a)?, number(b)?),
            None => (number(item)?, number(item)?),
        };
        if last < first {
            return Err(format!("--seeds: `{}` runs backwards", item.trim()));
        }
        if last - first >= MAX_SEEDS || seeds.len() as u64 + (last - first) >= MAX_SEEDS {
            return Err(format!("--seeds: more than {MAX_SEEDS} seeds"));
        }
        seeds.extend((first..=last).filter(|&seed| seen.insert(seed)));
    }
    Ok(seeds)
}

/// The generator's state for `seed` of the input named `stem`: its name's
/// 64-bit FNV-1a hash and the seed, mixed. Hashed by the name, not the
/// path, so that a file gives the same suits wherever it lies.
fn draw_state(stem: &str, seed: u64) -> u64 {
    let name_hash = stem.bytes().fold(0xCBF2_9CE4_8422_2325_u64, |hash, byte| {
        (hash ^ u64::from(byte)).wrapping_mul(0x0000_0100_0000_01B3)
    });
    mixed_state(name_hash ^ seed)
}

/// Writes every level and seed of one input; returns how many files.
fn grade(args: &Args, input: &Path, levels: &[f64], seeds: &[u64]) -> Result<usize, Error> {
    let name = input.display().to_string();
    let stem = bvh_stem(&name)
        .ok_or_else(|| Error::whole(&name, "is not named NAME.bvh (its suit files are NAME.suit-TAG.bvh)"))?
        .to_string();
    let bytes = std::fs::read(input).map_err(|e| Error::whole(&name, format!("cannot read: {e}")))?;
    let truth = Bvh::parse(&bytes, &name, &ReadOptions { fps: args.fps })?;
    for warning in &truth.warnings {
        eprintln!("warning: {name}: {warning}");
    }
    let skeleton = &truth.skeleton;
    let feet = resolve_feet(&skeleton.names, args.left_foot.as_deref(), args.right_foot.as_deref())
        .map_err(|message| Error::whole(&name, message))?;
    let body = SuitBody::from_feet(skeleton, feet);
    for j in suit::joints_kept_true(skeleton, &body) {
        let channels: Vec<&str> = skeleton.channels[j].iter().map(|c| c.name()).collect();
        eprintln!(
            "warning: {name}: joint `{}` has rotation channels {} (not three axes): it keeps its true rotation",
            skeleton.names[j],
            channels.join(" ")
        );
    }
    let sizes = if args.sizes == "described" { &ErrorSizes::DESCRIBED } else { &ErrorSizes::MEASURED };
    let mut ratios: Vec<f64> = Vec::new();
    for &level in levels {
        for &seed in seeds {
            let graded = suit::apply(skeleton, &truth.motion, &body, sizes, draw_state(&stem, seed), level);
            let out_path = args.out_dir.join(format!("{stem}.suit-l{level}-s{seed}.bvh"));
            let text = Bvh { skeleton: graded.skeleton, motion: graded.motion, warnings: Vec::new() }.write();
            std::fs::write(&out_path, text)
                .map_err(|e| Error::whole(&out_path.display().to_string(), format!("cannot write: {e}")))?;
            ratios.push(graded.leg_length_ratio);
        }
    }
    let (low, high) =
        ratios.iter().fold((f64::INFINITY, f64::NEG_INFINITY), |(l, h), r| (l.min(*r), h.max(*r)));
    println!(
        "{stem}: {} files, {} frames, hips `{}`, leg-length ratios {low:.3}–{high:.3}",
        ratios.len(),
        truth.motion.frame_count(),
        skeleton.names[body.hips]
    );
    Ok(ratios.len())
}

fn main() -> ExitCode {
    let args = Args::parse();
    let (levels, seeds) = match (parse_levels(&args.levels), parse_seeds(&args.seeds)) {
        (Ok(levels), Ok(seeds)) => (levels, seeds),
        (Err(e), _) | (_, Err(e)) => {
            eprintln!("error: {e}");
            return ExitCode::FAILURE;
        }
    };
    if let Err(e) = std::fs::create_dir_all(&args.out_dir) {
        eprintln!("error: {}: cannot make the folder: {e}", args.out_dir.display());
        return ExitCode::FAILURE;
    }
    let mut failed = 0;
    let mut written = 0;
    for input in &args.inputs {
        match grade(&args, input, &levels, &seeds) {
            Ok(count) => written += count,
            Err(e) => {
                eprintln!("error: {e}");
                failed += 1;
            }
        }
    }
    println!("{written} suit files in {}", args.out_dir.display());
    if failed > 0 { ExitCode::FAILURE } else { ExitCode::SUCCESS }
}
