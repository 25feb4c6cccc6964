//! Video files in grey, frame by frame, through `ffmpeg` (native builds
//! only: the browser decodes its video itself).
//!
//! `ffprobe` first tells the size, the frame rate and the number of frames;
//! then `ffmpeg -f rawvideo` streams the frames through a pipe, one
//! `width × height` block of bytes each, so a long video never sits in
//! memory whole. A video in 8-bit YUV (what cameras and phones write) comes
//! as its luma plane as decoded (`-vf extractplanes=y`), made grey here as
//! the page makes the browser decoder's planes grey
//! ([`GreyImage::from_luma`]: the same bytes `-pix_fmt gray` gives, without
//! ffmpeg converting every pixel); any other kind through `-pix_fmt gray`.
//! ffmpeg turns the picture upright (phone videos carry a rotation) and the
//! size reported here is the upright one. Frames are the
//! decoded frames as they are (`-fps_mode passthrough`): frame `i` is at
//! `i / fps` seconds, exact for the constant-rate video cameras write.

use std::io::Read;
use std::path::{Path, PathBuf};
use std::process::{Child, ChildStdout, Command, Stdio};

use crate::error::Error;
use crate::image::GreyImage;

/// Where the two programs are: by default `ffmpeg` and `ffprobe` on the
/// `PATH`.
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct Ffmpeg {
    pub ffmpeg: PathBuf,
    pub ffprobe: PathBuf,
}

impl Default for Ffmpeg {
    fn default() -> Self {
        Ffmpeg { ffmpeg: "ffmpeg".into(), ffprobe: "ffprobe".into() }
    }
}

/// What `ffprobe` says of a video's first video stream.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct VideoInfo {
    /// The upright picture's size, as the frames come.
    pub width_px: u32,
    pub height_px: u32,
    /// Frames per second (the stream's average rate).
    pub fps: f64,
    /// The number of frames (packets counted by demuxing, which every
    /// container allows, not the header's count, which some lack).
    pub frame_count: usize,
}

/// The frames of a video in grey, decoded as they are read.
pub struct VideoFrames {
    pub info: VideoInfo,
    /// What ffmpeg streams.
    streamed: Streamed,
    file: String,
    child: Child,
    stdout: ChildStdout,
    stderr: Option<std::thread::JoinHandle<String>>,
    next_index: usize,
    done: bool,
}

/// What ffmpeg streams of each frame.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
enum Streamed {
    /// Its grey levels (`-pix_fmt gray`).
    Grey,
    /// Its luma plane as decoded (`-vf extractplanes=y`), full range or
    /// limited (16 black, 235 white).
    LumaPlane { full_range: bool },
}

/// The message for a program that could not be started.
fn start_error(file: &str, program: &Path, e: std::io::Error) -> Error {
    if e.kind() == std::io::ErrorKind::NotFound {
        Error::whole(file, format!("{} not found: install ffmpeg: apt-get install ffmpeg", program.display()))
    } else {
        Error::whole(file, format!("cannot run {}: {e}", program.display()))
    }
}

/// The last non-empty line of a program's error output, for a message.
fn last_line(stderr: &str) -> &str {
    stderr.lines().rev().map(str::trim).find(|l| !l.is_empty()).unwrap_or("no message")
}

/// What ffmpeg streams of frames in its pixel format `pix_fmt`: the luma
/// plane for 8-bit planar YUV (whose first plane is the luma at the
/// picture's size), full range for a `yuvj` format or `color_range` `pc`;
/// grey levels for the rest (10-bit, RGB, grey, packed), which ffmpeg
/// turns grey itself.
fn streamed_as(pix_fmt: &str, color_range: Option<&str>) -> Streamed {
    const PLANAR_YUV_8_BIT: [&str; 6] = ["yuv420p", "yuv422p", "yuv444p", "yuv440p", "yuv411p", "yuv410p"];
    let full_range_format = pix_fmt.strip_prefix("yuvj").map(|rest| format!("yuv{rest}"));
    let format = full_range_format.as_deref().unwrap_or(pix_fmt);
    if !PLANAR_YUV_8_BIT.contains(&format) {
        return Streamed::Grey;
    }
    Streamed::LumaPlane { full_range: full_range_format.is_some() || color_range == Some("pc") }
}

/// A rate such as `30000/1001` or `25`; `None` for `0/0` and the like.
fn parse_rate(text: &str) -> Option<f64> {
    let (num, den) = text.split_once('/').unwrap_or((text, "1"));
    let rate = num.trim().parse::<f64>().ok()? / den.trim().parse::<f64>().ok()?;
    (rate.is_finite() && rate > 0.0).then_some(rate)
}

impl Ffmpeg {
    /// The size, rate and length of the first video stream of `path`; an
    /// error naming the file when `ffprobe` is missing or finds no video.
    pub fn probe(&self, path: &Path) -> Result<VideoInfo, Error> {
        self.probe_stream(path).map(|(info, _)| info)
    }

    /// [`Ffmpeg::probe`], and what ffmpeg is to stream of each frame
    /// ([`streamed_as`]).
    fn probe_stream(&self, path: &Path) -> Result<(VideoInfo, Streamed), Error> {
        let file = path.display().to_string();
        if !path.is_file() {
            return Err(Error::whole(&file, "no such file"));
        }
        let output = Command::new(&self.ffprobe)
            .args(["-v", "error", "-count_packets", "-select_streams", "v:0", "-show_entries"])
            .arg("stream=width,height,avg_frame_rate,r_frame_rate,nb_read_packets,pix_fmt,color_range:stream_tags=rotate:stream_side_data=rotation")
            .args(["-of", "default=noprint_wrappers=1"])
            .arg(path)
            .stdin(Stdio::null())
            .output()
            .map_err(|e| start_error(&file, &self.ffprobe, e))?;
        let text = String::from_utf8_lossy(&output.stdout);
        if !output.status.success() {
            let stderr = String::from_utf8_lossy(&output.stderr);
            return Err(Error::whole(&file, format!("not a video ffmpeg can read: {}", last_line(&stderr))));
        }
        let field = |name: &str| {
            text.lines()
                .find_map(|l| l.strip_prefix(name).and_then(|rest| rest.strip_prefix('=')))
                .map(str::trim)
        };
        let number = |name: &str| field(name).and_then(|v| v.parse::<u64>().ok());
        let (Some(width), Some(height)) = (number("width"), number("height")) else {
            return Err(Error::whole(&file, "not a video: ffprobe finds no video stream in it"));
        };
        let fps = field("avg_frame_rate")
            .and_then(parse_rate)
            .or_else(|| field("r_frame_rate").and_then(parse_rate))
            .ok_or_else(|| Error::whole(&file, "the video states no frame rate"))?;
        let frame_count = number("nb_read_packets").unwrap_or(0) as usize;
        if frame_count == 0 {
            return Err(Error::whole(&file, "the video has no frames"));
        }
        // A quarter turn (side data "rotation", or the older "rotate" tag)
        // swaps the sides of the upright picture ffmpeg writes.
        let turn = field("rotation").or_else(|| field("TAG:rotate")).and_then(|r| r.parse::<f64>().ok());
        let quarter = turn.is_some_and(|deg| (libm::fmod(deg.abs(), 180.0) - 90.0).abs() < 1.0);
        let (width, height) = if quarter { (height, width) } else { (width, height) };
        let (width_px, height_px) = (u32::try_from(width), u32::try_from(height));
        let (Ok(width_px @ 1..), Ok(height_px @ 1..)) = (width_px, height_px) else {
            return Err(Error::whole(&file, format!("a video of {width}×{height} pixels")));
        };
        let streamed = streamed_as(field("pix_fmt").unwrap_or(""), field("color_range"));
        Ok((VideoInfo { width_px, height_px, fps, frame_count }, streamed))
    }

    /// Starts decoding `path` into grey frames (see the module's note):
    /// [`Ffmpeg::probe_file`] and one pass of [`VideoFile::frames`].
    pub fn open(&self, path: &Path) -> Result<VideoFrames, Error> {
        self.probe_file(path)?.frames()
    }

    /// `path` probed once, to be decoded as many times as its frames are
    /// read from the first ([`VideoFile::frames`]).
    pub fn probe_file(&self, path: &Path) -> Result<VideoFile, Error> {
        let (info, streamed) = self.probe_stream(path)?;
        Ok(VideoFile { info, streamed, ffmpeg: self.clone(), path: path.to_path_buf() })
    }
}

/// A video file as `ffprobe` found it: its size, rate and length, and how
/// ffmpeg is to stream its frames. Probing counts every packet, which
/// reads the whole file; this is done once, however often it is decoded.
#[derive(Clone, Debug, PartialEq)]
pub struct VideoFile {
    pub info: VideoInfo,
    streamed: Streamed,
    ffmpeg: Ffmpeg,
    path: PathBuf,
}

impl VideoFile {
    /// Starts decoding the video from its first frame, in a new ffmpeg:
    /// one pass over its frames, held one at a time.
    pub fn frames(&self) -> Result<VideoFrames, Error> {
        let (info, streamed, path) = (self.info, self.streamed, self.path.as_path());
        let file = path.display().to_string();
        let mut command = Command::new(&self.ffmpeg.ffmpeg);
        command.args(["-nostdin", "-v", "error", "-i"]).arg(path).args([
            "-map",
            "0:v:0",
            "-fps_mode",
            "passthrough",
        ]);
        if let Streamed::LumaPlane { .. } = streamed {
            command.args(["-vf", "extractplanes=y"]);
        }
        let mut child = command
            .args(["-f", "rawvideo", "-pix_fmt", "gray", "-"])
            .stdin(Stdio::null())
            .stdout(Stdio::piped())
            .stderr(Stdio::piped())
            .spawn()
            .map_err(|e| start_error(&file, &self.ffmpeg.ffmpeg, e))?;
        let (Some(stdout), Some(mut stderr)) = (child.stdout.take(), child.stderr.take()) else {
            let _ = child.kill();
            let _ = child.wait();
            return Err(Error::whole(&file, "ffmpeg's output could not be read"));
        };
        // Its messages are read aside, so that a chatty ffmpeg never blocks
        // on a full pipe while we wait for frames.
        let stderr = std::thread::spawn(move || {
            let mut text = String::new();
            let _ = stderr.read_to_string(&mut text);
            text
        });
        Ok(VideoFrames {
            info,
            streamed,
            file,
            child,
            stdout,
            stderr: Some(stderr),
            next_index: 0,
            done: false,
        })
    }
}

impl VideoFrames {
    /// The index the next frame will have.
    pub fn next_index(&self) -> usize {
        self.next_index
    }

    /// Ends ffmpeg and says why it stopped when it failed.
    fn finish(&mut self) -> Result<(), Error> {
        self.done = true;
        let status = self.child.wait().map_err(|e| Error::whole(&self.file, format!("ffmpeg: {e}")))?;
        let stderr = self.stderr.take().and_then(|h| h.join().ok()).unwrap_or_default();
        if !status.success() {
            return Err(Error::whole(
                &self.file,
                format!("ffmpeg stopped at frame {}: {}", self.next_index, last_line(&stderr)),
            ));
        }
        if self.next_index == 0 {
            return Err(Error::whole(&self.file, "ffmpeg decoded no frame of this video"));
        }
        Ok(())
    }

    /// The next frame, `None` after the last, an error when ffmpeg fails or
    /// stops in the middle of a frame.
    pub fn next_frame(&mut self) -> Option<Result<GreyImage, Error>> {
        if self.done {
            return None;
        }
        let (w, h) = (self.info.width_px, self.info.height_px);
        let mut pixels = vec![0u8; w as usize * h as usize];
        let mut filled = 0;
        while filled < pixels.len() {
            match self.stdout.read(&mut pixels[filled..]) {
                Ok(0) => break,
                Ok(n) => filled += n,
                Err(e) if e.kind() == std::io::ErrorKind::Interrupted => {}
                Err(e) => {
                    self.done = true;
                    let _ = self.child.kill();
                    let _ = self.child.wait();
                    return Some(Err(Error::whole(&self.file, format!("reading ffmpeg's frames: {e}"))));
                }
            }
        }
        if filled == 0 {
            return self.finish().err().map(Err);
        }
        if filled < pixels.len() {
            let ended = self.finish().err();
            return Some(Err(ended.unwrap_or_else(|| {
                Error::whole(&self.file, format!("the video ends in the middle of frame {}", self.next_index))
            })));
        }
        self.next_index += 1;
        Some(match self.streamed {
            Streamed::LumaPlane { full_range } => {
                GreyImage::from_luma(w, h, &pixels, w as usize, full_range, &self.file)
            }
            Streamed::Grey => GreyImage::new(w, h, pixels, &self.file),
        })
    }
}

impl Iterator for VideoFrames {
    type Item = Result<GreyImage, Error>;

    fn next(&mut self) -> Option<Self::Item> {
        self.next_frame()
    }
}

impl Drop for VideoFrames {
    /// A reader dropped before the end stops ffmpeg rather than leave it
    /// blocked on a pipe nobody reads.
    fn drop(&mut self) {
        if !self.done {
            let _ = self.child.kill();
            let _ = self.child.wait();
        }
    }
}

/// `count` frames spread evenly over a video of `frame_count` frames (the
/// first, the last and evenly between), taken from `frames` as it streams:
/// the input of a median background when there is no still of the empty
/// room. Only the kept frames are held.
pub fn sample_frames(
    frames: impl Iterator<Item = Result<GreyImage, Error>>,
    frame_count: usize,
    count: usize,
) -> Result<Vec<GreyImage>, Error> {
    let wanted = crate::image::background::sample_indices(frame_count, count);
    let mut kept = Vec::with_capacity(wanted.len());
    for (index, frame) in frames.enumerate() {
        if kept.len() == wanted.len() {
            break;
        }
        let frame = frame?;
        if index == wanted[kept.len()] {
            kept.push(frame);
        }
    }
    Ok(kept)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn rates_parse_as_ffprobe_writes_them() {
        assert_eq!(parse_rate("30/1"), Some(30.0));
        assert!((parse_rate("30000/1001").unwrap() - 29.97).abs() < 0.01);
        assert_eq!(parse_rate("0/0"), None);
        assert_eq!(parse_rate("25"), Some(25.0));
    }

    #[test]
    fn eight_bit_planar_yuv_is_read_as_its_luma_plane() {
        let luma = |full_range| Streamed::LumaPlane { full_range };
        assert_eq!(streamed_as("yuv420p", Some("unknown")), luma(false));
        assert_eq!(streamed_as("yuv420p", Some("tv")), luma(false));
        assert_eq!(streamed_as("yuv444p", Some("pc")), luma(true));
        assert_eq!(streamed_as("yuvj420p", None), luma(true));
        for other in ["yuv420p10le", "nv12", "rgb24", "gray", "yuyv422", "yuvj420p10le", ""] {
            assert_eq!(streamed_as(other, Some("tv")), Streamed::Grey, "{other}");
        }
    }

    #[test]
    fn samples_spread_from_first_to_last() {
        let frames = (0..10u8).map(|i| Ok(GreyImage::filled(1, 1, i)));
        let kept = sample_frames(frames, 10, 4).unwrap();
        assert_eq!(kept.iter().map(|f| f.pixels[0]).collect::<Vec<_>>(), vec![0, 3, 6, 9]);
        let frames = (0..3u8).map(|i| Ok(GreyImage::filled(1, 1, i)));
        assert_eq!(sample_frames(frames, 3, 9).unwrap().len(), 3);
    }
}
