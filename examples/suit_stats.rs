//! How large a suit file's errors are against its truth: what the sizes of
//! the suit error model (`embusen::synth::suit::ErrorSizes`) were measured
//! with.
//!
//! ```text
//! cargo run --release --example suit_stats -- SUIT.bvh TRUTH.bvh [SUIT.bvh TRUTH.bvh …]
//! ```
//!
//! Per pair, over the sensed segments (every joint below the root but the
//! toes and end sites), of the error rotation `world_from_suit ·
//! world_from_true⁻¹` as a rotation vector:
//! - `lag`: the least-squares lag that explains it as the segment's angular
//!   velocity times a delay (a fusion filter answering late);
//! - `noise by speed`: per axis, what is left once that lag and everything
//!   slower than ±0.5 s (a centred mean of 31 frames at 30 fps, whatever
//!   the rate) are taken out, in bins of the true segment's angular speed
//!   (below 1, 1–2, 2–4, 4–8, over 8 rad/s);
//! - `one / two frames`: the correlation of that rest one and two frames
//!   apart (white noise reads about 0, less the centred mean's share);
//! - `bones`: the spread (standard deviation of the log) of the bones'
//!   length ratios, suit over truth, in the first frame.
//!
//! Both files must have the same joints in the same order (a suit file of
//! `examples/suit_grade` or the shared `suit/` folder and its truth).

use std::f64::consts::PI;
use std::process::ExitCode;

use embusen::body::kinematics::{forward_kinematics, local_rotation};
use embusen::body::skeleton::{Motion, Skeleton};
use embusen::error::Error;
use embusen::io::bvh::{Bvh, ReadOptions};
use glam::{DMat3, DQuat, DVec3};

/// The bins' upper edges of angular speed (rad/s); the last bin is open.
const SPEED_EDGES_RAD_PER_S: [f64; 4] = [1.0, 2.0, 4.0, 8.0];

/// Everything slower than this either side of a frame is taken out (s).
const SLOW_HALF_WINDOW_S: f64 = 0.5;

/// Frame-major, per frame and joint, the joint's global rotation.
fn world_rotations(skeleton: &Skeleton, motion: &Motion) -> Vec<DQuat> {
    let n = skeleton.joint_count();
    let mut world: Vec<DQuat> = Vec::with_capacity(n * motion.frame_count());
    for f in 0..motion.frame_count() {
        let values = motion.frame(f);
        let start = world.len();
        for j in 0..n {
            let first = skeleton.first_channel[j];
            let channels = &skeleton.channels[j];
            let local = local_rotation(channels, &values[first..first + channels.len()]);
            let parent = skeleton.parents[j].map_or(DMat3::IDENTITY, |p| DMat3::from_quat(world[start + p]));
            world.push(DQuat::from_mat3(&(parent * local)).normalize());
        }
    }
    world
}

/// A rotation as its rotation vector (rad), the short way round.
fn rotation_vector(q: DQuat) -> DVec3 {
    if q.w < 0.0 { (-q).to_scaled_axis() } else { q.to_scaled_axis() }
}

/// `values` less their centred mean over `half` frames either side.
fn less_slow(values: &[DVec3], half: usize) -> Vec<DVec3> {
    let n = values.len();
    (0..n)
        .map(|f| {
            let (a, b) = (f.saturating_sub(half), (f + half).min(n - 1));
            values[f] - values[a..=b].iter().sum::<DVec3>() / (b - a + 1) as f64
        })
        .collect()
}

fn read(path: &str) -> Result<Bvh, Error> {
    let bytes = std::fs::read(path).map_err(|e| Error::whole(path, format!("cannot read: {e}")))?;
    Bvh::parse(&bytes, path, &ReadOptions::default())
}

/// The figures of one suit file against its truth, as one line.
fn measure(suit_path: &str, truth_path: &str) -> Result<String, Error> {
    let (suit, truth) = (read(suit_path)?, read(truth_path)?);
    let names = &truth.skeleton.names;
    if suit.skeleton.names != *names {
        return Err(Error::whole(suit_path, format!("its joints are not those of {truth_path}")));
    }
    let fps = truth.motion.fps();
    let n = truth.skeleton.joint_count();
    let frames = truth.motion.frame_count().min(suit.motion.frame_count());
    let half = (SLOW_HALF_WINDOW_S * fps).round() as usize;
    if frames <= 2 * half + 2 {
        return Err(Error::whole(truth_path, format!("too short: {frames} frames, {} needed", 2 * half + 3)));
    }
    let (suit_world, true_world) =
        (world_rotations(&suit.skeleton, &suit.motion), world_rotations(&truth.skeleton, &truth.motion));
    let sensed: Vec<usize> = (0..n)
        .filter(|&j| {
            truth.skeleton.parents[j].is_some() && !truth.skeleton.is_end_site[j] && !names[j].contains("Toe")
        })
        .collect();
    // Per sensed segment: the error and the true angular velocity.
    let per_segment: Vec<(Vec<DVec3>, Vec<DVec3>)> = sensed
        .iter()
        .map(|&j| {
            let error =
                (0..frames).map(|f| rotation_vector(suit_world[f * n + j] * true_world[f * n + j].inverse()));
            let velocity = (0..frames).map(|f| {
                let (a, b) = (f.saturating_sub(1), (f + 1).min(frames - 1));
                rotation_vector(true_world[b * n + j] * true_world[a * n + j].inverse()) * fps
                    / (b - a) as f64
            });
            (error.collect(), velocity.collect())
        })
        .collect();
    // The lag: error ≈ −lag · angular velocity, on the error less its slow part.
    let (mut along, mut speed_squared) = (0.0, 0.0);
    for (error, velocity) in &per_segment {
        for (e, w) in less_slow(error, half).iter().zip(velocity).skip(half).take(frames - 2 * half) {
            along -= e.dot(*w);
            speed_squared += w.length_squared();
        }
    }
    let lag_s = if speed_squared > 0.0 { along / speed_squared } else { 0.0 };
    let mut bins = [(0.0, 0usize); SPEED_EDGES_RAD_PER_S.len() + 1];
    let mut products = [0.0; 3];
    for (error, velocity) in &per_segment {
        let lagged: Vec<DVec3> = error.iter().zip(velocity).map(|(e, w)| *e + *w * lag_s).collect();
        let rest = less_slow(&lagged, half);
        for f in half..frames - half {
            let bin = SPEED_EDGES_RAD_PER_S.iter().take_while(|&&edge| velocity[f].length() >= edge).count();
            bins[bin].0 += rest[f].length_squared() / 3.0;
            bins[bin].1 += 1;
            for (k, product) in products.iter_mut().enumerate() {
                if f + k < frames - half {
                    *product += rest[f].dot(rest[f + k]);
                }
            }
        }
    }
    let degrees = 180.0 / PI;
    let by_speed: Vec<String> = bins
        .iter()
        .map(
            |&(sum, count)| {
                if count > 0 { format!("{:.2}", (sum / count as f64).sqrt() * degrees) } else { "-".into() }
            },
        )
        .collect();
    // The bones: joint to parent in the first frame, below the hips.
    let (suit_poses, true_poses) = (
        forward_kinematics(&suit.skeleton, &suit.motion),
        forward_kinematics(&truth.skeleton, &truth.motion),
    );
    let logs: Vec<f64> = sensed
        .iter()
        .filter_map(|&j| {
            truth.skeleton.parents[j].filter(|&p| truth.skeleton.parents[p].is_some()).map(|p| (j, p))
        })
        .filter_map(|(j, p)| {
            let length = |poses: &embusen::body::skeleton::Poses| (poses.at(0, j) - poses.at(0, p)).length();
            let (true_cm, suit_cm) = (length(&true_poses), length(&suit_poses));
            (true_cm > 3.0).then(|| (suit_cm / true_cm).ln())
        })
        .collect();
    let mean = logs.iter().sum::<f64>() / logs.len().max(1) as f64;
    let spread =
        (logs.iter().map(|x| (x - mean) * (x - mean)).sum::<f64>() / logs.len().max(1) as f64).sqrt();
    Ok(format!(
        "{suit_path}: lag {:.0} ms | noise by speed {}° | one / two frames {:.2} / {:.2} | bones {:.3}",
        1000.0 * lag_s,
        by_speed.join(" "),
        products[1] / products[0],
        products[2] / products[0],
        spread
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
