//! BVH reading and writing.
//!
//! The reader accepts the files people really have: any channel order, 0, 3 or
//! 6 channels on any joint (see [`crate::body::kinematics`] for the position-channel
//! rule), `End Site` blocks and leaf joints without one, CRLF, tabs, blank
//! lines, scientific notation, `Frame Time: 0`, and a `Frames:` count that
//! disagrees with the rows that follow. Every error names file:line:column and
//! says what was expected there.

use glam::DVec3;

use crate::body::skeleton::{Channel, Motion, Skeleton};
use crate::error::{Error, line_column_of};

/// The frame rate used when a file says `Frame Time: 0` and the user gave none.
pub const DEFAULT_FPS: f64 = 100.0;

/// A parsed BVH file.
#[derive(Clone, Debug, PartialEq)]
pub struct Bvh {
    pub skeleton: Skeleton,
    pub motion: Motion,
    /// Things the reader tolerated but the user should know about.
    pub warnings: Vec<String>,
}

/// What the reader cannot learn from the file itself.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct ReadOptions {
    /// Frame rate to use when the file's `Frame Time` is 0 or missing
    /// (`--fps`); [`DEFAULT_FPS`] with a warning when `None`.
    pub fps: Option<f64>,
}

/// A cursor over the text that knows where it is, for error messages.
struct Cursor<'a> {
    text: &'a [u8],
    pos: usize,
    file: &'a str,
}

impl<'a> Cursor<'a> {
    fn error_at(&self, offset: usize, message: impl Into<String>) -> Error {
        let (line, column) = line_column_of(self.text, offset);
        Error::at(self.file, line, column, message)
    }

    fn skip_whitespace(&mut self) {
        while self.pos < self.text.len() && self.text[self.pos].is_ascii_whitespace() {
            self.pos += 1;
        }
    }

    /// The next whitespace-separated word and its offset ("" at the end).
    fn word(&mut self) -> (usize, &'a str) {
        self.skip_whitespace();
        let start = self.pos;
        while self.pos < self.text.len() && !self.text[self.pos].is_ascii_whitespace() {
            self.pos += 1;
        }
        // Non-UTF-8 words show up as an empty word, which every caller rejects.
        (start, std::str::from_utf8(&self.text[start..self.pos]).unwrap_or("\u{fffd}"))
    }

    /// The rest of the current line, trimmed: joint names may contain spaces.
    fn rest_of_line(&mut self) -> (usize, &'a str) {
        while self.pos < self.text.len() && matches!(self.text[self.pos], b' ' | b'\t') {
            self.pos += 1;
        }
        let start = self.pos;
        while self.pos < self.text.len() && self.text[self.pos] != b'\n' {
            self.pos += 1;
        }
        let line = std::str::from_utf8(&self.text[start..self.pos]).unwrap_or("");
        (start, line.trim())
    }

    fn expect_word(&mut self, wanted: &str, context: &str) -> Result<(), Error> {
        let (at, word) = self.word();
        if word.eq_ignore_ascii_case(wanted) {
            Ok(())
        } else {
            Err(self.error_at(at, format!("expected `{wanted}` {context}, found {}", shown(word))))
        }
    }

    fn number(&mut self, what: &str) -> Result<f64, Error> {
        let (at, word) = self.word();
        parse_finite(word).ok_or_else(|| self.error_at(at, format!("expected {what}, found {}", shown(word))))
    }
}

/// How a word is quoted in an error message.
fn shown(word: &str) -> String {
    if word.is_empty() { "the end of the file".to_string() } else { format!("`{word}`") }
}

fn parse_finite(word: &str) -> Option<f64> {
    let v: f64 = fast_float2::parse(word).ok()?;
    v.is_finite().then_some(v)
}

impl Bvh {
    /// Parses a BVH text. `file` is the name used in errors and warnings.
    pub fn parse(text: &[u8], file: &str, options: &ReadOptions) -> Result<Bvh, Error> {
        let mut cursor = Cursor { text, pos: 0, file };
        let mut warnings = Vec::new();
        cursor.expect_word("HIERARCHY", "at the start of a BVH file")?;
        let (at, word) = cursor.word();
        if !word.eq_ignore_ascii_case("ROOT") {
            return Err(cursor.error_at(at, format!("expected `ROOT`, found {}", shown(word))));
        }
        let mut skeleton = Skeleton::default();
        parse_joint(&mut cursor, &mut skeleton, None)?;
        let (at, word) = cursor.word();
        if word.eq_ignore_ascii_case("ROOT") {
            return Err(cursor.error_at(at, "only one ROOT is supported; this file has a second"));
        }
        if !word.eq_ignore_ascii_case("MOTION") {
            return Err(
                cursor.error_at(at, format!("expected `MOTION` after the hierarchy, found {}", shown(word)))
            );
        }
        let declared_frames = parse_frames_line(&mut cursor)?;
        let frame_time_s = parse_frame_time_line(&mut cursor)?;
        let frame_time_s = if frame_time_s > 0.0 {
            frame_time_s
        } else {
            let fps = options.fps.unwrap_or(DEFAULT_FPS);
            warnings.push(match options.fps {
                Some(_) => format!("Frame Time is {frame_time_s} (an exporter bug); using {fps} Hz as given"),
                None => format!(
                    "Frame Time is {frame_time_s} (an exporter bug); assuming {fps} Hz (set it with --fps)"
                ),
            });
            1.0 / fps
        };
        let channel_count = skeleton.channel_count();
        let values = parse_motion_rows(&mut cursor, channel_count, declared_frames)?;
        let frame_count = values.len().checked_div(channel_count).unwrap_or(0);
        if frame_count == 0 {
            return Err(Error::whole(file, "the MOTION section has no frames"));
        }
        if frame_count != declared_frames {
            warnings.push(format!(
                "`Frames:` says {declared_frames} but the file has {frame_count} rows; using {frame_count}"
            ));
        }
        Ok(Bvh { skeleton, motion: Motion { channel_count, frame_time_s, values }, warnings })
    }

    /// Writes the recording as BVH text: tabs for nesting, `End Site` for end
    /// sites, and numbers in Rust's shortest round-trip form, so that reading
    /// the output gives back exactly the same values.
    pub fn write(&self) -> String {
        let s = &self.skeleton;
        let mut out = String::with_capacity(self.motion.values.len() * 10 + 4096);
        out.push_str("HIERARCHY\n");
        // Children of each joint, in index order (the order they were read).
        let mut children: Vec<Vec<usize>> = vec![Vec::new(); s.joint_count()];
        for (j, parent) in s.parents.iter().enumerate() {
            if let Some(p) = parent {
                children[*p].push(j);
            }
        }
        for root in (0..s.joint_count()).filter(|&j| s.parents[j].is_none()) {
            write_joint(&mut out, s, &children, root, 0);
        }
        out.push_str("MOTION\n");
        out.push_str(&format!("Frames: {}\n", self.motion.frame_count()));
        out.push_str(&format!("Frame Time: {}\n", self.motion.frame_time_s));
        let mut buffer = ryu::Buffer::new();
        for f in 0..self.motion.frame_count() {
            for (i, v) in self.motion.frame(f).iter().enumerate() {
                if i > 0 {
                    out.push(' ');
                }
                out.push_str(format_number(&mut buffer, *v));
            }
            out.push('\n');
        }
        out
    }

    /// Moves the whole body of frame `f` by `shift_cm[f]`, through the root's
    /// position channels (added, with the OFFSET as their value, if the root
    /// has none). This is how a translation method's result becomes a BVH.
    pub fn shift_root(&mut self, shift_cm: &[DVec3]) {
        let root = 0;
        self.ensure_position_channels(root);
        let first = self.skeleton.first_channel[root];
        let channels = self.skeleton.channels[root].clone();
        for (f, shift) in shift_cm.iter().enumerate().take(self.motion.frame_count()) {
            let values = self.motion.frame_mut(f);
            for (i, channel) in channels.iter().enumerate() {
                if channel.is_position() {
                    values[first + i] += shift[channel.axis()];
                }
            }
        }
    }

    /// Gives `joint` all three position channels, inserting missing ones at the
    /// front of its channel list with the OFFSET's value in every frame, so the
    /// pose is unchanged.
    pub fn ensure_position_channels(&mut self, joint: usize) {
        let present: Vec<Channel> = self.skeleton.channels[joint].clone();
        let missing: Vec<Channel> = [Channel::Xposition, Channel::Yposition, Channel::Zposition]
            .into_iter()
            .filter(|c| !present.contains(c))
            .collect();
        if missing.is_empty() {
            return;
        }
        let offset = self.skeleton.offsets_cm[joint];
        let insert_at = self.skeleton.first_channel[joint];
        let old_count = self.motion.channel_count;
        let new_count = old_count + missing.len();
        let frames = self.motion.frame_count();
        let mut values = Vec::with_capacity(frames * new_count);
        for f in 0..frames {
            let row = self.motion.frame(f);
            values.extend_from_slice(&row[..insert_at]);
            values.extend(missing.iter().map(|c| offset[c.axis()]));
            values.extend_from_slice(&row[insert_at..]);
        }
        let mut channels = missing;
        channels.extend(present);
        self.skeleton.channels[joint] = channels;
        self.skeleton.renumber_channels();
        self.motion.channel_count = new_count;
        self.motion.values = values;
    }
}

/// Shortest round-trip text of a number, without ryu's trailing `.0`.
fn format_number(buffer: &mut ryu::Buffer, v: f64) -> &str {
    let text = buffer.format(v);
    text.strip_suffix(".0").unwrap_or(text)
}

fn write_joint(out: &mut String, s: &Skeleton, children: &[Vec<usize>], j: usize, depth: usize) {
    let indent = "\t".repeat(depth);
    let mut buffer = ryu::Buffer::new();
    let offset = s.offsets_cm[j];
    let offset_text = format!(
        "{} {} {}",
        format_number(&mut buffer, offset.x),
        format_number(&mut ryu::Buffer::new(), offset.y),
        format_number(&mut ryu::Buffer::new(), offset.z)
    );
    if s.is_end_site[j] {
        out.push_str(&format!("{indent}End Site\n{indent}{{\n{indent}\tOFFSET {offset_text}\n{indent}}}\n"));
        return;
    }
    let keyword = if s.parents[j].is_none() { "ROOT" } else { "JOINT" };
    out.push_str(&format!("{indent}{keyword} {}\n{indent}{{\n", s.names[j]));
    out.push_str(&format!("{indent}\tOFFSET {offset_text}\n"));
    let names: Vec<&str> = s.channels[j].iter().map(|c| c.name()).collect();
    out.push_str(&format!("{indent}\tCHANNELS {}", names.len()));
    for name in names {
        out.push(' ');
        out.push_str(name);
    }
    out.push('\n');
    for &child in &children[j] {
        write_joint(out, s, children, child, depth + 1);
    }
    out.push_str(&format!("{indent}}}\n"));
}

/// Parses a joint after its `ROOT`/`JOINT` keyword: name, `{`, OFFSET,
/// CHANNELS, children, `}`.
fn parse_joint(cursor: &mut Cursor, skeleton: &mut Skeleton, parent: Option<usize>) -> Result<(), Error> {
    let (at, mut name) = cursor.rest_of_line();
    // Some writers put the brace on the name's line: `JOINT Hips {`.
    let mut brace_on_name_line = false;
    if let Some(stripped) = name.strip_suffix('{') {
        name = stripped.trim_end();
        brace_on_name_line = true;
    }
    if name.is_empty() {
        return Err(cursor.error_at(at, "expected a joint name"));
    }
    if !brace_on_name_line {
        cursor.expect_word("{", &format!("after joint `{name}`"))?;
    }
    cursor.expect_word("OFFSET", &format!("in joint `{name}`"))?;
    let offset = parse_vec3(cursor, &format!("a number in the OFFSET of `{name}`"))?;
    // CHANNELS is optional: a joint without it has no channels.
    let saved = cursor.pos;
    let (_, word) = cursor.word();
    let mut channels = Vec::new();
    if word.eq_ignore_ascii_case("CHANNELS") {
        let (at, count_word) = cursor.word();
        let count: usize = count_word.parse().map_err(|_| {
            cursor
                .error_at(at, format!("expected the channel count of `{name}`, found {}", shown(count_word)))
        })?;
        if count > 6 {
            return Err(cursor.error_at(at, format!("expected at most 6 channels, found {count}")));
        }
        for _ in 0..count {
            let (at, word) = cursor.word();
            let channel = Channel::parse(word).ok_or_else(|| {
                cursor.error_at(
                    at,
                    format!(
                        "expected a channel name (Xposition … Zrotation) — `{name}` declares {count} channels — found {}",
                        shown(word)
                    ),
                )
            })?;
            if channels.contains(&channel) {
                return Err(cursor.error_at(at, format!("channel {word} appears twice in `{name}`")));
            }
            channels.push(channel);
        }
    } else {
        cursor.pos = saved;
    }
    let joint = skeleton.push_joint(name.to_string(), parent, offset, channels, false);
    loop {
        let (at, word) = cursor.word();
        if word == "}" {
            return Ok(());
        } else if word.eq_ignore_ascii_case("JOINT") {
            parse_joint(cursor, skeleton, Some(joint))?;
        } else if word.eq_ignore_ascii_case("End") {
            cursor.expect_word("Site", "after `End`")?;
            cursor.expect_word("{", "after `End Site`")?;
            cursor.expect_word("OFFSET", "in an End Site")?;
            let offset = parse_vec3(cursor, "a number in an End Site OFFSET")?;
            cursor.expect_word("}", "to close the End Site")?;
            let index = skeleton.joint_count();
            skeleton.push_joint(format!("EndSite{index}"), Some(joint), offset, Vec::new(), true);
        } else {
            return Err(cursor.error_at(
                at,
                format!("expected `JOINT`, `End Site` or `}}` in joint `{name}`, found {}", shown(word)),
            ));
        }
    }
}

fn parse_vec3(cursor: &mut Cursor, what: &str) -> Result<DVec3, Error> {
    Ok(DVec3::new(cursor.number(what)?, cursor.number(what)?, cursor.number(what)?))
}

/// `Frames: N` (the colon may be glued to the number or spaced).
fn parse_frames_line(cursor: &mut Cursor) -> Result<usize, Error> {
    let (at, word) = cursor.word();
    let glued = word.strip_prefix("Frames:").or_else(|| word.strip_prefix("frames:"));
    let (at, count_word) = match glued {
        Some("") => cursor.word(),
        Some(rest) => (at + "Frames:".len(), rest),
        None => {
            return Err(
                cursor.error_at(at, format!("expected `Frames:` after MOTION, found {}", shown(word)))
            );
        }
    };
    count_word.parse().map_err(|_| {
        cursor.error_at(at, format!("expected the number of frames, found {}", shown(count_word)))
    })
}

/// `Frame Time: T`.
fn parse_frame_time_line(cursor: &mut Cursor) -> Result<f64, Error> {
    cursor.expect_word("Frame", "after the Frames line")?;
    let (at, word) = cursor.word();
    let glued = word.strip_prefix("Time:").or_else(|| word.strip_prefix("time:"));
    let (at, value_word) = match glued {
        Some("") => cursor.word(),
        Some(rest) => (at + "Time:".len(), rest),
        None => return Err(cursor.error_at(at, format!("expected `Time:`, found {}", shown(word)))),
    };
    match parse_finite(value_word) {
        Some(t) if t >= 0.0 => Ok(t),
        _ => {
            Err(cursor
                .error_at(at, format!("expected the frame time in seconds, found {}", shown(value_word))))
        }
    }
}

/// The data rows: one frame per non-blank line, `channel_count` numbers each.
/// This loop is the reader's hot path (≈ all of a file's bytes), so it works on
/// bytes and computes line/column only when it reports an error.
fn parse_motion_rows(
    cursor: &mut Cursor,
    channel_count: usize,
    declared_frames: usize,
) -> Result<Vec<f64>, Error> {
    let text = cursor.text;
    let mut pos = cursor.pos;
    // Finish the Frame Time line.
    while pos < text.len() && text[pos] != b'\n' {
        if !text[pos].is_ascii_whitespace() {
            let end =
                text[pos..].iter().position(|b| b.is_ascii_whitespace()).map_or(text.len(), |e| pos + e);
            let word = String::from_utf8_lossy(&text[pos..end]).into_owned();
            return Err(
                cursor.error_at(pos, format!("expected the end of the Frame Time line, found `{word}`"))
            );
        }
        pos += 1;
    }
    let mut values = Vec::with_capacity(channel_count.saturating_mul(declared_frames.min(10_000_000)));
    let mut row_start_offset = pos;
    let mut in_row = 0usize;
    let mut frame = 0usize;
    loop {
        // Skip spaces, noticing line ends.
        while pos < text.len() {
            match text[pos] {
                b' ' | b'\t' | b'\r' | b',' => pos += 1,
                b'\n' => {
                    if in_row > 0 {
                        finish_row(cursor, in_row, channel_count, frame, row_start_offset)?;
                        frame += 1;
                        in_row = 0;
                    }
                    pos += 1;
                    row_start_offset = pos;
                }
                _ => break,
            }
        }
        if pos >= text.len() {
            if in_row > 0 {
                finish_row(cursor, in_row, channel_count, frame, row_start_offset)?;
            }
            break;
        }
        match fast_float2::parse_partial::<f64, _>(&text[pos..]) {
            Ok((v, len))
                if v.is_finite()
                    && (pos + len == text.len()
                        || matches!(text[pos + len], b' ' | b'\t' | b'\r' | b'\n' | b',')) =>
            {
                if in_row == channel_count {
                    return Err(cursor.error_at(
                        pos,
                        format!("expected {channel_count} values in frame {}, found more", frame + 1),
                    ));
                }
                values.push(v);
                in_row += 1;
                pos += len;
            }
            _ => {
                let end =
                    text[pos..].iter().position(|b| b.is_ascii_whitespace()).map_or(text.len(), |e| pos + e);
                let word = String::from_utf8_lossy(&text[pos..end]).into_owned();
                return Err(cursor.error_at(pos, format!("expected a number, found `{word}`")));
            }
        }
    }
    cursor.pos = pos;
    Ok(values)
}

fn finish_row(
    cursor: &Cursor,
    found: usize,
    expected: usize,
    frame: usize,
    row_start: usize,
) -> Result<(), Error> {
    if found == expected {
        Ok(())
    } else {
        Err(cursor.error_at(
            row_start,
            format!("expected {expected} values in frame {} (one per channel), found {found}", frame + 1),
        ))
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    const SMALL: &str = "HIERARCHY\nROOT Hips\n{\n\tOFFSET 0 0 0\n\tCHANNELS 6 Xposition Yposition Zposition Zrotation Xrotation Yrotation\n\tJOINT Leg\n\t{\n\t\tOFFSET 0 -10 0\n\t\tCHANNELS 3 Zrotation Xrotation Yrotation\n\t\tEnd Site\n\t\t{\n\t\t\tOFFSET 0 -10 0\n\t\t}\n\t}\n}\nMOTION\nFrames: 2\nFrame Time: 0.01\n1 2 3 0 0 0 0 0 0\n4 5 6 90 0 0 0 0 0\n";

    fn parse(text: &str) -> Result<Bvh, Error> {
        Bvh::parse(text.as_bytes(), "t.bvh", &ReadOptions::default())
    }

    #[test]
    fn reads_a_small_file() {
        let bvh = parse(SMALL).unwrap();
        assert_eq!(bvh.skeleton.names, ["Hips", "Leg", "EndSite2"]);
        assert_eq!(bvh.skeleton.parents, [None, Some(0), Some(1)]);
        assert_eq!(bvh.motion.frame_count(), 2);
        assert_eq!(bvh.motion.channel_count, 9);
        assert_eq!(bvh.motion.frame(1)[3], 90.0);
        assert!(bvh.warnings.is_empty());
    }

    #[test]
    fn error_positions() {
        let bad = SMALL.replace("4 5 6 90", "4 5 x6 90");
        assert_eq!(parse(&bad).unwrap_err().to_string(), "t.bvh:20:5: expected a number, found `x6`");
        let bad = SMALL.replace("CHANNELS 3 Zrotation Xrotation Yrotation", "CHANNELS 3 Zrotation Xrotation");
        let e = parse(&bad).unwrap_err();
        assert_eq!(e.line_column, Some((10, 3)), "{e}");
        assert!(e.message.contains("expected a channel name"), "{e}");
        let bad = SMALL.replace("1 2 3 0 0 0 0 0 0", "1 2 3 0 0 0 0 0");
        assert!(parse(&bad).unwrap_err().to_string().starts_with("t.bvh:19:1: expected 9 values in frame 1"));
    }
}
