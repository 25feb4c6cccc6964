//! How large a suit file's errors are against its truth
//! (`embusen::eval::suit_errors`): what the sizes of the suit error model
//! (`embusen::synth::suit::ErrorSizes::MEASURED`) were measured with.
//!
//! ```text
//! cargo run --release --example suit_stats -- SUIT.bvh TRUTH.bvh [SUIT.bvh TRUTH.bvh …]
//! ```
//!
//! One line per pair: the fusion's lag; per axis, the noise left once the
//! lag and everything slower than ±0.5 s are taken out, by the segment's
//! angular speed (below 1, 1–2, 2–4, 4–8, over 8 rad/s); its correlation
//! one and two frames apart; the bones' spread. Both files must have the
//! same joints in the same order (a suit file of `examples/suit_grade` or
//! the shared `suit/` folder, and its truth).

use std::process::ExitCode;

use embusen::error::Error;
use embusen::eval::suit_errors::suit_errors;
use embusen::io::bvh::{Bvh, ReadOptions};

fn read(path: &str) -> Result<Bvh, Error> {
    let bytes = std::fs::read(path).map_err(|e| Error::whole(path, format!("cannot read: {e}")))?;
    Bvh::parse(&bytes, path, &ReadOptions::default())
}

/// The figures of one suit file against its truth, as one line.
fn measure(suit_path: &str, truth_path: &str) -> Result<String, Error> {
    let errors =
        suit_errors(&read(suit_path)?, &read(truth_path)?).map_err(|m| Error::whole(suit_path, m))?;
    let by_speed: Vec<String> = errors
        .noise_deg_by_speed
        .iter()
        .map(|deg| deg.map_or_else(|| "-".to_string(), |deg| format!("{deg:.2}")))
        .collect();
    Ok(format!(
        "{suit_path}: lag {:.0} ms | noise by speed {}° | one / two frames {:.2} / {:.2} | bones {:.3}",
        1000.0 * errors.lag_s,
        by_speed.join(" "),
        errors.correlation[0],
        errors.correlation[1],
        errors.bone_spread
    ))
}

fn main() -> ExitCode {
    let paths: Vec<String> = std::env::args().skip(1).collect();
    if paths.is_empty() || !paths.len().is_multiple_of(2) {
        eprintln!("usage: suit_stats SUIT.bvh TRUTH.bvh [SUIT.bvh TRUTH.bvh …]");
        return ExitCode::FAILURE;
    }
    let mut failed = false;
    for pair in paths.chunks(2) {
        match measure(&pair[0], &pair[1]) {
            Ok(line) => println!("{line}"),
            Err(e) => {
                eprintln!("error: {e}");
                failed = true;
            }
        }
    }
    if failed { ExitCode::FAILURE } else { ExitCode::SUCCESS }
}
