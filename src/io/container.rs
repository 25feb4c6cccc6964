//! The encoded frames of a video file, without decoding them: where each
//! frame's bytes lie, when it is shown, whether it is a keyframe, and the
//! codec's configuration — what a browser's WebCodecs `VideoDecoder` needs to
//! decode the frames one after another, each once. (Seeking a `<video>` to
//! every frame decodes from the keyframe before it each time: a whole GOP per
//! frame.) MP4/MOV (ISO base media: the first video track's sample tables)
//! and WebM/Matroska (the first video track's blocks).
//!
//! Frames are listed in decoding order with their presentation times; a
//! decoder gives them back in presentation order, which is the order
//! `ffmpeg -fps_mode passthrough` writes them in, so the k-th frame out is
//! the CLI's frame k. Errors name the file and the byte offset.

use crate::error::Error;

/// One encoded frame.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct EncodedFrame {
    /// Where its bytes start in the file, and how many there are.
    pub offset: u64,
    pub size: u32,
    /// When it is shown (µs from the stream's start, after any edit list).
    pub timestamp_us: i64,
    /// Whether decoding may start at it.
    pub keyframe: bool,
}

/// A video file's first video stream, demuxed.
#[derive(Clone, Debug, PartialEq)]
pub struct EncodedVideo {
    /// The codec as WebCodecs names it: `avc1.64001f`, `vp09.00.10.08`,
    /// `vp8`, `av01.0.04M.08`.
    pub codec: String,
    /// The decoder's configuration record (the `avcC` of H.264, the `av1C`
    /// of AV1), none for VP8 and VP9.
    pub description: Option<Vec<u8>>,
    pub width_px: u32,
    pub height_px: u32,
    /// The frames in decoding order.
    pub frames: Vec<EncodedFrame>,
}

impl EncodedVideo {
    /// The frame rate: frames per second over the span of their
    /// presentation times (each frame lasting the mean step), NaN for fewer
    /// than two frames.
    pub fn fps(&self) -> f64 {
        let (mut first, mut last) = (i64::MAX, i64::MIN);
        for f in &self.frames {
            first = first.min(f.timestamp_us);
            last = last.max(f.timestamp_us);
        }
        let n = self.frames.len();
        if n < 2 || last <= first {
            return f64::NAN;
        }
        (n - 1) as f64 * 1e6 / (last - first) as f64
    }
}

/// The rates cameras record at (frames per second).
const COMMON_FPS: [f64; 12] = [
    24000.0 / 1001.0,
    24.0,
    25.0,
    30000.0 / 1001.0,
    30.0,
    48.0,
    50.0,
    60000.0 / 1001.0,
    60.0,
    100.0,
    120000.0 / 1001.0,
    120.0,
];

/// The rate a video was recorded at, from one measured off its timestamps:
/// the nearest of the rates cameras use when within 0.3 % of it (timestamps
/// are rounded to a container's time base, a millisecond in WebM;
/// 30000/1001 and 30, 0.1 % apart, go to the nearer), else the measured
/// rate itself. What `ffprobe` reports for such a video, so the page and
/// `embusen track` time its frames alike.
pub fn nominal_fps(measured: f64) -> f64 {
    let nearest = COMMON_FPS.iter().copied().fold(f64::NAN, |best, r| {
        if best.is_nan() || (measured - r).abs() < (measured - best).abs() { r } else { best }
    });
    if (measured - nearest).abs() <= 3e-3 * nearest { nearest } else { measured }
}

/// Demuxes `bytes`, an MP4/MOV or WebM/Matroska file named `name`.
pub fn demux(bytes: &[u8], name: &str) -> Result<EncodedVideo, Error> {
    let video = if bytes.len() >= 8 && &bytes[4..8] == b"ftyp" {
        mp4::demux(bytes, name)?
    } else if bytes.starts_with(&[0x1a, 0x45, 0xdf, 0xa3]) {
        matroska::demux(bytes, name)?
    } else {
        return Err(Error::whole(
            name,
            "neither MP4/MOV nor WebM/Matroska: no frames can be read from it here",
        ));
    };
    if video.frames.is_empty() {
        return Err(Error::whole(name, "its video track has no frames"));
    }
    if let Some(f) = video.frames.iter().find(|f| f.offset.saturating_add(f.size as u64) > bytes.len() as u64)
    {
        return Err(Error::whole(
            name,
            format!("a frame at byte {} runs past the end of the file (a truncated file?)", f.offset),
        ));
    }
    Ok(video)
}

/// Big-endian reads that fail instead of panicking.
fn be(bytes: &[u8], at: usize, n: usize) -> Option<u64> {
    let field = bytes.get(at..at.checked_add(n)?)?;
    Some(field.iter().fold(0u64, |v, &b| (v << 8) | b as u64))
}

mod mp4 {
    use super::{EncodedFrame, EncodedVideo, be};
    use crate::error::Error;

    /// A box: its type, and its payload's range in the file.
    #[derive(Clone, Copy)]
    struct Box4 {
        kind: [u8; 4],
        start: usize,
        end: usize,
    }

    /// The boxes directly inside `bytes[start..end]`.
    fn children(bytes: &[u8], start: usize, end: usize, name: &str) -> Result<Vec<Box4>, Error> {
        let mut out = Vec::new();
        let mut at = start;
        while at + 8 <= end {
            let bad =
                || Error::whole(name, format!("at byte {at}: a box whose size does not fit its parent"));
            let size32 = be(bytes, at, 4).ok_or_else(bad)?;
            let mut kind = [0u8; 4];
            kind.copy_from_slice(&bytes[at + 4..at + 8]);
            let (header, size) = match size32 {
                0 => (8, (end - at) as u64),
                1 => (16, be(bytes, at + 8, 8).ok_or_else(bad)?),
                s => (8, s),
            };
            let size = usize::try_from(size).map_err(|_| bad())?;
            if size < header || at.checked_add(size).is_none_or(|e| e > end) {
                return Err(bad());
            }
            out.push(Box4 { kind, start: at + header, end: at + size });
            at += size;
        }
        Ok(out)
    }

    fn find(list: &[Box4], kind: &[u8; 4]) -> Option<Box4> {
        list.iter().copied().find(|b| &b.kind == kind)
    }

    pub fn demux(bytes: &[u8], name: &str) -> Result<EncodedVideo, Error> {
        let missing =
            |what: &str| Error::whole(name, format!("no {what} box: not a video MP4 can be read from"));
        let top = children(bytes, 0, bytes.len(), name)?;
        let moov =
            find(&top, b"moov").ok_or_else(|| missing("moov (the index, perhaps at a truncated end)"))?;
        for trak in children(bytes, moov.start, moov.end, name)?.into_iter().filter(|b| &b.kind == b"trak") {
            let inside = children(bytes, trak.start, trak.end, name)?;
            let Some(mdia) = find(&inside, b"mdia") else { continue };
            let media = children(bytes, mdia.start, mdia.end, name)?;
            let is_video =
                find(&media, b"hdlr").is_some_and(|h| bytes.get(h.start + 8..h.start + 12) == Some(b"vide"));
            if !is_video {
                continue;
            }
            let mdhd = find(&media, b"mdhd").ok_or_else(|| missing("mdhd"))?;
            let timescale = match bytes.get(mdhd.start) {
                Some(1) => be(bytes, mdhd.start + 20, 4),
                _ => be(bytes, mdhd.start + 12, 4),
            }
            .filter(|&t| t > 0)
            .ok_or_else(|| Error::whole(name, "the video track has no time scale"))?;
            let media_start = edit_start(bytes, &inside, name)?;
            let minf = find(&media, b"minf").ok_or_else(|| missing("minf"))?;
            let stbl = find(&children(bytes, minf.start, minf.end, name)?, b"stbl")
                .ok_or_else(|| missing("stbl"))?;
            return track(bytes, stbl, timescale, media_start, name);
        }
        Err(Error::whole(name, "the MP4 has no video track"))
    }

    /// The media time the presentation starts at (the first edit of `edts`).
    fn edit_start(bytes: &[u8], trak: &[Box4], name: &str) -> Result<i64, Error> {
        let Some(edts) = find(trak, b"edts") else { return Ok(0) };
        let Some(elst) = find(&children(bytes, edts.start, edts.end, name)?, b"elst") else { return Ok(0) };
        let version = bytes.get(elst.start).copied().unwrap_or(0);
        let count = be(bytes, elst.start + 4, 4).unwrap_or(0);
        let mut at = elst.start + 8;
        for _ in 0..count.min(16) {
            let (media_time, step) = if version == 1 {
                (be(bytes, at + 8, 8).map(|v| v as i64), 20)
            } else {
                (be(bytes, at + 4, 4).map(|v| v as u32 as i32 as i64), 12)
            };
            match media_time {
                // An empty edit (−1) delays the start; the frames keep their times.
                Some(-1) => at += step,
                Some(t) => return Ok(t),
                None => break,
            }
        }
        Ok(0)
    }

    fn track(
        bytes: &[u8],
        stbl: Box4,
        timescale: u64,
        media_start: i64,
        name: &str,
    ) -> Result<EncodedVideo, Error> {
        let tables = children(bytes, stbl.start, stbl.end, name)?;
        let need = |k: &[u8; 4]| {
            find(&tables, k).ok_or_else(|| {
                Error::whole(name, format!("no {} table in the video track", String::from_utf8_lossy(k)))
            })
        };
        let short = |what: &str| Error::whole(name, format!("the {what} table is cut short"));
        // The sample description: the codec and its configuration record.
        let stsd = need(b"stsd")?;
        let entry = children(bytes, stsd.start + 8, stsd.end, name)?
            .into_iter()
            .next()
            .ok_or_else(|| Error::whole(name, "the video track describes no codec"))?;
        let width_px = be(bytes, entry.start + 24, 2).ok_or_else(|| short("stsd"))? as u32;
        let height_px = be(bytes, entry.start + 26, 2).ok_or_else(|| short("stsd"))? as u32;
        let config = children(bytes, (entry.start + 78).min(entry.end), entry.end, name)?;
        let record = |k: &[u8; 4]| find(&config, k).map(|b| bytes[b.start..b.end].to_vec());
        let (codec, description) = match &entry.kind {
            b"avc1" | b"avc3" => {
                let avcc =
                    record(b"avcC").ok_or_else(|| Error::whole(name, "an H.264 track without its avcC"))?;
                let [_, profile, compat, level, ..] = avcc[..] else {
                    return Err(short("avcC"));
                };
                (format!("avc1.{profile:02x}{compat:02x}{level:02x}"), Some(avcc))
            }
            b"vp09" => {
                let vpcc = record(b"vpcC").unwrap_or_default();
                let (profile, level, depth) = match vpcc.get(4..7) {
                    Some(&[p, l, d]) => (p, l, d >> 4),
                    _ => (0, 10, 8),
                };
                (format!("vp09.{profile:02}.{level:02}.{depth:02}"), None)
            }
            b"vp08" => ("vp8".to_string(), None),
            b"av01" => {
                let av1c =
                    record(b"av1C").ok_or_else(|| Error::whole(name, "an AV1 track without its av1C"))?;
                (av1_codec(&av1c).ok_or_else(|| short("av1C"))?, Some(av1c))
            }
            other => {
                return Err(Error::whole(
                    name,
                    format!(
                        "video in {} is not read here (H.264, VP8, VP9 and AV1 are)",
                        String::from_utf8_lossy(other)
                    ),
                ));
            }
        };
        // Sizes.
        let stsz = need(b"stsz")?;
        let fixed = be(bytes, stsz.start + 4, 4).ok_or_else(|| short("stsz"))?;
        let count = be(bytes, stsz.start + 8, 4).ok_or_else(|| short("stsz"))? as usize;
        // Every frame takes at least a byte of the file: a count beyond that
        // is a broken table, not a reason to allocate.
        if (fixed == 0 && count > (stsz.end - stsz.start) / 4)
            || count.saturating_mul(fixed.max(1) as usize) > bytes.len()
        {
            return Err(short("stsz"));
        }
        let size_of = |i: usize| if fixed > 0 { Some(fixed) } else { be(bytes, stsz.start + 12 + 4 * i, 4) };
        // Decoding times.
        let stts = need(b"stts")?;
        let mut decode_times = Vec::with_capacity(count);
        let mut t: i64 = 0;
        for k in 0..be(bytes, stts.start + 4, 4).ok_or_else(|| short("stts"))? as usize {
            let n = be(bytes, stts.start + 8 + 8 * k, 4).ok_or_else(|| short("stts"))?;
            let delta = be(bytes, stts.start + 12 + 8 * k, 4).ok_or_else(|| short("stts"))? as i64;
            for _ in 0..n.min((count - decode_times.len().min(count)) as u64) {
                decode_times.push(t);
                t += delta;
            }
        }
        // Composition offsets (B-frames shown after later-decoded ones).
        let mut offsets = vec![0i64; count];
        if let Some(ctts) = find(&tables, b"ctts") {
            let signed = bytes.get(ctts.start) == Some(&1);
            let mut i = 0;
            for k in 0..be(bytes, ctts.start + 4, 4).ok_or_else(|| short("ctts"))? as usize {
                let n = be(bytes, ctts.start + 8 + 8 * k, 4).ok_or_else(|| short("ctts"))?;
                let raw = be(bytes, ctts.start + 12 + 8 * k, 4).ok_or_else(|| short("ctts"))?;
                let offset = if signed { raw as u32 as i32 as i64 } else { raw as i64 };
                for _ in 0..n {
                    if i >= count {
                        break;
                    }
                    offsets[i] = offset;
                    i += 1;
                }
            }
        }
        // Where each sample lies: chunks of samples at the chunk offsets.
        let chunk_offsets: Vec<u64> = match (find(&tables, b"stco"), find(&tables, b"co64")) {
            (Some(b), _) => (0..be(bytes, b.start + 4, 4).ok_or_else(|| short("stco"))? as usize)
                .map(|k| be(bytes, b.start + 8 + 4 * k, 4).ok_or_else(|| short("stco")))
                .collect::<Result<_, _>>()?,
            (None, Some(b)) => (0..be(bytes, b.start + 4, 4).ok_or_else(|| short("co64"))? as usize)
                .map(|k| be(bytes, b.start + 8 + 8 * k, 8).ok_or_else(|| short("co64")))
                .collect::<Result<_, _>>()?,
            (None, None) => {
                return Err(Error::whole(name, "no chunk offsets (stco or co64) in the video track"));
            }
        };
        let stsc = need(b"stsc")?;
        let runs: Vec<(u64, u64)> = (0..be(bytes, stsc.start + 4, 4).ok_or_else(|| short("stsc"))? as usize)
            .map(|k| {
                let first = be(bytes, stsc.start + 8 + 12 * k, 4)?;
                let per_chunk = be(bytes, stsc.start + 12 + 12 * k, 4)?;
                Some((first, per_chunk))
            })
            .collect::<Option<_>>()
            .ok_or_else(|| short("stsc"))?;
        let sync: Option<Vec<u64>> = find(&tables, b"stss").map(|b| {
            let listed = be(bytes, b.start + 4, 4).unwrap_or(0) as usize;
            (0..listed.min((b.end - b.start) / 4)).filter_map(|k| be(bytes, b.start + 8 + 4 * k, 4)).collect()
        });
        let mut frames = Vec::with_capacity(count);
        let mut sample = 0usize;
        for (chunk, &chunk_offset) in chunk_offsets.iter().enumerate() {
            let number = chunk as u64 + 1;
            let per_chunk = runs.iter().rev().find(|(first, _)| *first <= number).map_or(0, |r| r.1);
            let mut at = chunk_offset;
            for _ in 0..per_chunk {
                if sample >= count {
                    break;
                }
                let size = size_of(sample).ok_or_else(|| short("stsz"))?;
                let decode = *decode_times.get(sample).ok_or_else(|| short("stts"))?;
                let shown = decode + offsets[sample] - media_start;
                frames.push(EncodedFrame {
                    offset: at,
                    size: u32::try_from(size).map_err(|_| short("stsz"))?,
                    timestamp_us: (shown as i128 * 1_000_000 / timescale as i128) as i64,
                    keyframe: sync.as_ref().is_none_or(|s| s.binary_search(&(sample as u64 + 1)).is_ok()),
                });
                at += size;
                sample += 1;
            }
        }
        Ok(EncodedVideo { codec, description, width_px, height_px, frames })
    }

    /// `av01.P.LLT.DD` from an AV1 configuration record.
    fn av1_codec(av1c: &[u8]) -> Option<String> {
        let (b1, b2) = (*av1c.get(1)?, *av1c.get(2)?);
        let profile = b1 >> 5;
        let level = b1 & 0x1f;
        let tier = if b2 & 0x80 != 0 { 'H' } else { 'M' };
        let depth = match (b2 & 0x40 != 0, b2 & 0x20 != 0) {
            (true, true) => 12,
            (true, false) => 10,
            _ => 8,
        };
        Some(format!("av01.{profile}.{level:02}{tier}.{depth:02}"))
    }
}

mod matroska {
    use super::{EncodedFrame, EncodedVideo};
    use crate::error::Error;

    const SEGMENT: u32 = 0x1853_8067;
    const INFO: u32 = 0x1549_a966;
    const TIMECODE_SCALE: u32 = 0x2a_d7b1;
    const TRACKS: u32 = 0x1654_ae6b;
    const TRACK_ENTRY: u32 = 0xae;
    const TRACK_NUMBER: u32 = 0xd7;
    const TRACK_TYPE: u32 = 0x83;
    const CODEC_ID: u32 = 0x86;
    const CODEC_PRIVATE: u32 = 0x63a2;
    const VIDEO: u32 = 0xe0;
    const PIXEL_WIDTH: u32 = 0xb0;
    const PIXEL_HEIGHT: u32 = 0xba;
    const CLUSTER: u32 = 0x1f43_b675;
    const CLUSTER_TIMECODE: u32 = 0xe7;
    const SIMPLE_BLOCK: u32 = 0xa3;
    const BLOCK_GROUP: u32 = 0xa0;
    const BLOCK: u32 = 0xa1;
    const REFERENCE_BLOCK: u32 = 0xfb;

    /// An element: its id, and its payload's range (`end` is the parent's
    /// end for an element of unknown size).
    #[derive(Clone, Copy)]
    struct Element {
        id: u32,
        start: usize,
        end: usize,
        sized: bool,
    }

    /// A variable-length integer at `at`: its value (the length marker
    /// removed when `strip`), its length, and whether it is all ones
    /// (an unknown size).
    fn vint(bytes: &[u8], at: usize, strip: bool) -> Option<(u64, usize, bool)> {
        let first = *bytes.get(at)?;
        let len = first.leading_zeros() as usize + 1;
        if len > 8 {
            return None;
        }
        let mut value = if strip { (first as u64) & (0xff >> len) } else { first as u64 };
        for k in 1..len {
            value = (value << 8) | *bytes.get(at + k)? as u64;
        }
        let all_ones = strip && value == (1u64 << (7 * len)) - 1;
        Some((value, len, all_ones))
    }

    fn element(bytes: &[u8], at: usize, parent_end: usize) -> Option<Element> {
        let (id, id_len, _) = vint(bytes, at, false)?;
        let (size, size_len, unknown) = vint(bytes, at + id_len, true)?;
        let start = at + id_len + size_len;
        let end = if unknown { parent_end } else { start.checked_add(usize::try_from(size).ok()?)? };
        (start <= parent_end && end <= parent_end).then_some(Element {
            id: id as u32,
            start,
            end,
            sized: !unknown,
        })
    }

    fn uint(bytes: &[u8], e: Element) -> u64 {
        bytes[e.start..e.end].iter().take(8).fold(0, |v, &b| (v << 8) | b as u64)
    }

    /// The elements in `start..end`; one of unknown size (a live
    /// recording's cluster) ends where an element that cannot be inside it
    /// starts.
    fn children(bytes: &[u8], start: usize, end: usize, name: &str) -> Result<Vec<Element>, Error> {
        let mut out = Vec::new();
        let mut at = start;
        while at < end {
            let Some(e) = element(bytes, at, end) else {
                // A file cut short mid-element: keep what came before.
                if out.is_empty() {
                    return Err(Error::whole(name, format!("at byte {at}: not a Matroska element")));
                }
                break;
            };
            if e.sized || e.id != CLUSTER {
                // Unknown size other than a cluster's (a live recording's
                // segment): to the parent's end.
                out.push(e);
                at = e.end;
            } else {
                // Unknown size: it ends at the next cluster (or the end).
                let mut next = e.start;
                while next < end {
                    let Some(inner) = element(bytes, next, end) else { break };
                    if inner.id == CLUSTER || !inner.sized {
                        break;
                    }
                    next = inner.end;
                }
                out.push(Element { end: next, ..e });
                if next <= at {
                    break;
                }
                at = next;
            }
        }
        Ok(out)
    }

    pub fn demux(bytes: &[u8], name: &str) -> Result<EncodedVideo, Error> {
        let top = children(bytes, 0, bytes.len(), name)?;
        let segment = top
            .iter()
            .find(|e| e.id == SEGMENT)
            .ok_or_else(|| Error::whole(name, "no Matroska segment in the file"))?;
        let mut scale_ns: u64 = 1_000_000;
        // The video track's number, and the track with no frames yet.
        let mut video: Option<(u64, EncodedVideo)> = None;
        let mut frames = Vec::new();
        for e in children(bytes, segment.start, segment.end, name)? {
            match e.id {
                INFO => {
                    for i in children(bytes, e.start, e.end, name)? {
                        if i.id == TIMECODE_SCALE {
                            scale_ns = uint(bytes, i).max(1);
                        }
                    }
                }
                TRACKS if video.is_none() => {
                    for t in
                        children(bytes, e.start, e.end, name)?.into_iter().filter(|t| t.id == TRACK_ENTRY)
                    {
                        let fields = children(bytes, t.start, t.end, name)?;
                        let get = |id: u32| fields.iter().copied().find(|f| f.id == id);
                        if get(TRACK_TYPE).map(|f| uint(bytes, f)) != Some(1) {
                            continue;
                        }
                        let number = get(TRACK_NUMBER).map_or(0, |f| uint(bytes, f));
                        let codec_id = get(CODEC_ID)
                            .map(|f| {
                                String::from_utf8_lossy(&bytes[f.start..f.end])
                                    .trim_end_matches('\0')
                                    .to_string()
                            })
                            .unwrap_or_default();
                        let private = get(CODEC_PRIVATE).map(|f| bytes[f.start..f.end].to_vec());
                        let (mut w, mut h) = (0, 0);
                        if let Some(v) = get(VIDEO) {
                            for f in children(bytes, v.start, v.end, name)? {
                                match f.id {
                                    PIXEL_WIDTH => w = uint(bytes, f) as u32,
                                    PIXEL_HEIGHT => h = uint(bytes, f) as u32,
                                    _ => {}
                                }
                            }
                        }
                        let (codec, description) = match codec_id.as_str() {
                            "V_VP9" => ("vp09.00.10.08".to_string(), None),
                            "V_VP8" => ("vp8".to_string(), None),
                            "V_AV1" => ("av01.0.04M.08".to_string(), private),
                            "V_MPEG4/ISO/AVC" => {
                                let avcc = private.ok_or_else(|| {
                                    Error::whole(name, "an H.264 track without its configuration")
                                })?;
                                let [_, p, c, l, ..] = avcc[..] else {
                                    return Err(Error::whole(name, "the H.264 configuration is cut short"));
                                };
                                (format!("avc1.{p:02x}{c:02x}{l:02x}"), Some(avcc))
                            }
                            other => {
                                return Err(Error::whole(
                                    name,
                                    format!(
                                        "video in {other} is not read here (H.264, VP8, VP9 and AV1 are)"
                                    ),
                                ));
                            }
                        };
                        video = Some((
                            number,
                            EncodedVideo {
                                codec,
                                description,
                                width_px: w,
                                height_px: h,
                                frames: Vec::new(),
                            },
                        ));
                        break;
                    }
                }
                CLUSTER => {
                    let Some((track, ..)) = &video else { continue };
                    let inside = children(bytes, e.start, e.end, name)?;
                    let cluster_time =
                        inside.iter().find(|c| c.id == CLUSTER_TIMECODE).map_or(0, |c| uint(bytes, *c));
                    for c in inside {
                        let (block, keyframe_flag) = match c.id {
                            SIMPLE_BLOCK => (c, None),
                            BLOCK_GROUP => {
                                let parts = children(bytes, c.start, c.end, name)?;
                                let Some(b) = parts.iter().copied().find(|p| p.id == BLOCK) else { continue };
                                (b, Some(!parts.iter().any(|p| p.id == REFERENCE_BLOCK)))
                            }
                            _ => continue,
                        };
                        let Some((number, len, _)) = vint(bytes, block.start, true) else { continue };
                        if number != *track || block.start + len + 3 > block.end {
                            continue;
                        }
                        let relative =
                            i16::from_be_bytes([bytes[block.start + len], bytes[block.start + len + 1]]);
                        let flags = bytes[block.start + len + 2];
                        if flags & 0x06 != 0 {
                            return Err(Error::whole(
                                name,
                                format!("at byte {}: laced video frames are not read here", block.start),
                            ));
                        }
                        let data = block.start + len + 3;
                        let ticks = cluster_time as i64 + relative as i64;
                        frames.push(EncodedFrame {
                            offset: data as u64,
                            size: (block.end - data) as u32,
                            timestamp_us: (ticks as i128 * scale_ns as i128 / 1000) as i64,
                            keyframe: keyframe_flag.unwrap_or(flags & 0x80 != 0),
                        });
                    }
                }
                _ => {}
            }
        }
        let (_, video) = video.ok_or_else(|| Error::whole(name, "the file has no video track"))?;
        Ok(EncodedVideo { frames, ..video })
    }
}
