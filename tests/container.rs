//! The demuxer the browser decodes video through (`io::container`): on the
//! shared scenes and on clips made here with ffmpeg, every frame ffprobe
//! lists is found, in the same (decoding) order, with its size, its
//! presentation time and whether it is a keyframe; the codec strings are
//! WebCodecs'; and no input makes it panic.

// A test may panic on what it does not expect: that is how it fails.
#![allow(clippy::unwrap_used, clippy::expect_used)]

mod common;

use std::path::{Path, PathBuf};
use std::process::Command;

use embusen::io::container::{demux, nominal_fps};
use proptest::prelude::*;

/// ffprobe's packets of the first video stream: (presentation time in µs,
/// size, keyframe), in decoding order.
fn ffprobe_packets(path: &Path) -> Vec<(i64, u32, bool)> {
    let out = Command::new("ffprobe")
        .args([
            "-v",
            "error",
            "-select_streams",
            "v:0",
            "-show_entries",
            "packet=pts_time,size,flags",
            "-of",
            "csv",
        ])
        .arg(path)
        .output()
        .unwrap();
    assert!(out.status.success(), "{}", String::from_utf8_lossy(&out.stderr));
    String::from_utf8(out.stdout)
        .unwrap()
        .lines()
        .map(|l| {
            let f: Vec<&str> = l.split(',').collect();
            (
                (f[1].parse::<f64>().unwrap() * 1e6).round() as i64,
                f[2].parse().unwrap(),
                f[3].starts_with('K'),
            )
        })
        .collect()
}

fn check(path: &Path, codec_prefix: &str) {
    let bytes = std::fs::read(path).unwrap();
    let name = path.display().to_string();
    let video = demux(&bytes, &name).unwrap();
    let packets = ffprobe_packets(path);
    assert!(video.codec.starts_with(codec_prefix), "{name}: {}", video.codec);
    assert_eq!(video.frames.len(), packets.len(), "{name}: frames");
    for (k, (f, &(pts_us, size, key))) in video.frames.iter().zip(&packets).enumerate() {
        assert_eq!((f.size, f.keyframe), (size, key), "{name}: frame {k} in decoding order");
        assert!(
            (f.timestamp_us - pts_us).abs() <= 1,
            "{name}: frame {k} at {} µs, ffprobe {pts_us}",
            f.timestamp_us
        );
    }
    assert_eq!(nominal_fps(video.fps()), 30.0, "{name}: {} fps measured", video.fps());
}

/// A clip made with ffmpeg in a scratch folder.
fn clip(name: &str, codec: &[&str]) -> PathBuf {
    let dir = Path::new(env!("CARGO_TARGET_TMPDIR")).join("container");
    std::fs::create_dir_all(&dir).unwrap();
    let path = dir.join(name);
    let status = Command::new("ffmpeg")
        .args(["-v", "error", "-y", "-f", "lavfi", "-i", "testsrc2=size=160x120:rate=30:duration=3"])
        .args(codec)
        .arg(&path)
        .status()
        .unwrap();
    assert!(status.success());
    path
}

#[test]
fn the_shared_scenes_frames_are_ffprobes() {
    let Some(data) = common::data_dir() else { return };
    check(&data.join("optical/walk.mp4"), "avc1.");
    check(&data.join("optical/walk.webm"), "vp09.");
}

#[test]
fn clips_with_b_frames_and_several_keyframes_are_read_whole() {
    // H.264 with B-frames (shown out of decoding order) in MP4 and in
    // Matroska, VP9 and VP8 in WebM, a keyframe a second.
    check(&clip("b.mp4", &["-c:v", "libx264", "-bf", "2", "-g", "30", "-pix_fmt", "yuv420p"]), "avc1.");
    check(&clip("b.mkv", &["-c:v", "libx264", "-bf", "2", "-g", "30", "-pix_fmt", "yuv420p"]), "avc1.");
    check(&clip("v.webm", &["-c:v", "libvpx-vp9", "-g", "30", "-b:v", "300k"]), "vp09.");
    check(&clip("v8.webm", &["-c:v", "libvpx", "-g", "30", "-b:v", "300k"]), "vp8");
    // A file cut short is an error (or its frames before the cut), never a panic.
    let bytes =
        std::fs::read(clip("cut.mp4", &["-c:v", "libx264", "-g", "30", "-pix_fmt", "yuv420p"])).unwrap();
    for cut in (0..bytes.len()).step_by(997) {
        let _ = demux(&bytes[..cut], "cut.mp4");
    }
    let e = demux(b"not a video", "notes.mp4").unwrap_err().to_string();
    assert!(e.starts_with("notes.mp4: neither MP4/MOV nor WebM/Matroska"), "{e}");
}

#[test]
fn measured_rates_go_to_the_nearest_common_rate_when_near_one() {
    assert_eq!(nominal_fps(29.998), 30.0);
    assert_eq!(nominal_fps(29.9701), 30000.0 / 1001.0);
    assert_eq!(nominal_fps(30.0188), 30.0);
    assert_eq!(nominal_fps(59.95), 60000.0 / 1001.0);
    assert_eq!(nominal_fps(27.0), 27.0, "no common rate near: as measured");
    assert!(nominal_fps(f64::NAN).is_nan());
}

proptest! {
    #[test]
    fn the_demuxer_never_panics(bytes in proptest::collection::vec(any::<u8>(), 0..600), kind in 0..3u8) {
        // Random bytes behind each signature, so the parsers themselves are reached.
        let mut input = match kind {
            0 => vec![0, 0, 0, 16, b'f', b't', b'y', b'p', b'i', b's', b'o', b'm', 0, 0, 0, 0],
            1 => vec![0x1a, 0x45, 0xdf, 0xa3],
            _ => Vec::new(),
        };
        input.extend(bytes);
        let _ = demux(&input, "random");
    }
}
