//! The RMoCap / Motion Shadow table: one CSV row per frame with global joint
//! positions (`<Joint>.Dx/.Dy/.Dz`, cm), rotations (`<Joint>.Rx/.Ry/.Rz`,
//! degrees), accelerometer readings (`<Sensor>.ax/.ay/.az`, g) and an optional
//! `Time` column (s). Any subset of these columns may be present; columns we do
//! not recognise are kept as plain numbers and written back unchanged.
//!
//! The reader is hand-rolled rather than built on the `csv` crate so that every
//! error can point at the exact line and column of the offending byte.
//!
//! Accepted: a UTF-8 byte-order mark, LF or CRLF line ends, blank lines (skipped),
//! quoted fields with `""` escapes (R's `write.csv` quotes every name), and R's
//! unnamed leading row-number column (header `""`), which is dropped with a
//! warning. Every value must be a finite number: R's `NA` (and `NaN`, `Inf`)
//! are rejected with their position, because a missing sample would silently
//! poison the smoothing and cumulative sums of the translation methods.

use std::collections::HashMap;
use std::fmt::Write as _;

use glam::DVec3;

use crate::body::skeleton::Poses;
use crate::error::{Error, line_column_of};

/// A parsed table: the named numeric columns, row by row.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct Table {
    /// The file name as the user gave it, for messages.
    pub file: String,
    /// Column names in file order (quotes removed, the row-number column dropped).
    pub headers: Vec<String>,
    /// Frame-major values: frame `f` is `values[f * headers.len()..(f + 1) * headers.len()]`.
    pub values: Vec<f64>,
    /// Joints that have all three of `.Dx`, `.Dy`, `.Dz`, in the order their
    /// first position column appears.
    pub joint_names: Vec<String>,
    /// For each of `joint_names`, the column indices of its `.Dx`, `.Dy`, `.Dz`.
    pub position_columns: Vec<[usize; 3]>,
    /// Things the reader tolerated but the user may want to know about.
    pub warnings: Vec<String>,
}

/// Accelerometer readings, per sensor and frame: the side file that goes with
/// a BVH (`heian_shodan.accel.csv`), or the `.a*` columns of a full table.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct Accelerations {
    pub file: String,
    /// Sensors that have all three of `.ax`, `.ay`, `.az`, in first-appearance order.
    pub sensor_names: Vec<String>,
    /// `accel_g[s][f]`: sensor `s`'s reading in frame `f`, in g, axes as exported.
    pub accel_g: Vec<Vec<DVec3>>,
}

/// One field of a CSV record, as byte offsets into the text.
#[derive(Clone, Copy, Debug)]
struct Field {
    /// Where the field starts (its opening quote, if quoted).
    start: usize,
    /// Just past the field (past its closing quote, if quoted).
    end: usize,
    /// The content, without quotes (escaped `""` still doubled).
    content: (usize, usize),
    quoted: bool,
}

/// Builds errors at byte offsets of one text.
struct Located<'a> {
    text: &'a [u8],
    file: &'a str,
}

impl Located<'_> {
    fn at(&self, offset: usize, message: impl Into<String>) -> Error {
        let (line, column) = line_column_of(self.text, offset);
        Error::at(self.file, line, column, message)
    }
}

/// Up to 40 characters of `bytes`, for quoting bad input in a message.
fn excerpt(bytes: &[u8]) -> String {
    let text = String::from_utf8_lossy(bytes);
    match text.char_indices().nth(40) {
        Some((cut, _)) => format!("{}…", &text[..cut]),
        None => text.into_owned(),
    }
}

/// True when the line starting at `pos` is empty (LF or CRLF right away).
fn is_blank_line(text: &[u8], pos: usize) -> bool {
    match text.get(pos) {
        Some(b'\n') => true,
        Some(b'\r') => matches!(text.get(pos + 1), Some(b'\n') | None),
        _ => false,
    }
}

/// Position just past the line end that starts at `pos` (`\n`, `\r\n`, or
/// the end of the text).
fn past_line_end(text: &[u8], pos: usize) -> usize {
    match text.get(pos) {
        Some(b'\r') if text.get(pos + 1) == Some(&b'\n') => pos + 2,
        Some(_) => pos + 1,
        None => pos,
    }
}

/// Reads the record starting at `pos` into `fields` (cleared first) and
/// returns the position of the next line.
fn read_record(located: &Located, mut pos: usize, fields: &mut Vec<Field>) -> Result<usize, Error> {
    let text = located.text;
    fields.clear();
    loop {
        let start = pos;
        if text.get(pos) == Some(&b'"') {
            let mut i = pos + 1;
            let close = loop {
                match text[i..].iter().position(|&b| b == b'"') {
                    None => {
                        return Err(located.at(start, "quoted field never closes: expected a `\"`"));
                    }
                    Some(q) if text.get(i + q + 1) == Some(&b'"') => i += q + 2,
                    Some(q) => break i + q,
                }
            };
            pos = close + 1;
            fields.push(Field { start, end: pos, content: (start + 1, close), quoted: true });
            match text.get(pos) {
                Some(b',') => pos += 1,
                None | Some(b'\n') => return Ok(past_line_end(text, pos)),
                Some(b'\r') if matches!(text.get(pos + 1), Some(b'\n') | None) => {
                    return Ok(past_line_end(text, pos));
                }
                Some(_) => {
                    return Err(located.at(pos, "expected `,` or the end of the line after a closing `\"`"));
                }
            }
        } else {
            let stop =
                text[pos..].iter().position(|&b| b == b',' || b == b'\n').map_or(text.len(), |p| pos + p);
            let at_comma = text.get(stop) == Some(&b',');
            let mut end = stop;
            if !at_comma && end > start && text[end - 1] == b'\r' {
                end -= 1;
            }
            fields.push(Field { start, end, content: (start, end), quoted: false });
            if at_comma {
                pos = stop + 1;
            } else {
                return Ok(past_line_end(text, stop));
            }
        }
    }
}

/// A column name from a header field: quotes unescaped, UTF-8 checked,
/// surrounding blanks of unquoted names trimmed.
fn header_name(located: &Located, field: &Field) -> Result<String, Error> {
    let raw = &located.text[field.content.0..field.content.1];
    let name = std::str::from_utf8(raw)
        .map_err(|e| located.at(field.content.0 + e.valid_up_to(), "expected a UTF-8 column name"))?;
    Ok(if field.quoted { name.replace("\"\"", "\"") } else { name.trim_matches([' ', '\t']).to_string() })
}

/// The number in one data field.
fn parse_number(located: &Located, field: &Field) -> Result<f64, Error> {
    let text = located.text;
    let (mut start, mut end) = field.content;
    while start < end && matches!(text[start], b' ' | b'\t') {
        start += 1;
    }
    while end > start && matches!(text[end - 1], b' ' | b'\t') {
        end -= 1;
    }
    let bytes = &text[start..end];
    if bytes.is_empty() {
        return Err(located.at(field.start, "expected a number, found an empty field"));
    }
    if bytes == b"NA" {
        return Err(located
            .at(start, "expected a number, found `NA` (a missing value): every frame needs every value"));
    }
    match fast_float2::parse_partial::<f64, _>(bytes) {
        Ok((value, used)) if used == bytes.len() => {
            if value.is_finite() {
                Ok(value)
            } else {
                Err(located.at(start, format!("expected a finite number, found `{}`", excerpt(bytes))))
            }
        }
        // Point at the first byte that is not part of the number.
        Ok((_, used)) => {
            Err(located.at(start + used, format!("expected a number, found `{}`", excerpt(bytes))))
        }
        Err(_) => Err(located.at(start, format!("expected a number, found `{}`", excerpt(bytes)))),
    }
}

/// Splits `Joint.Dx` into (`Joint`, `Dx`).
fn split_suffix(header: &str) -> Option<(&str, &str)> {
    header.rsplit_once('.').filter(|(name, _)| !name.is_empty())
}

/// Groups columns `<name>.<s0>`, `<name>.<s1>`, `<name>.<s2>` by name, in the
/// order each name first appears. Returns the complete triples and a warning
/// for each incomplete one.
fn triples(headers: &[String], suffixes: [&str; 3]) -> (Vec<String>, Vec<[usize; 3]>, Vec<String>) {
    let mut order: Vec<(&str, [Option<usize>; 3])> = Vec::new();
    let mut index: HashMap<&str, usize> = HashMap::new();
    for (column, header) in headers.iter().enumerate() {
        let Some((name, suffix)) = split_suffix(header) else {
            continue;
        };
        let Some(axis) = suffixes.iter().position(|&s| s == suffix) else {
            continue;
        };
        let slot = *index.entry(name).or_insert_with(|| {
            order.push((name, [None; 3]));
            order.len() - 1
        });
        order[slot].1[axis] = Some(column);
    }
    let mut names = Vec::new();
    let mut columns = Vec::new();
    let mut warnings = Vec::new();
    for (name, found) in order {
        if let [Some(x), Some(y), Some(z)] = found {
            names.push(name.to_string());
            columns.push([x, y, z]);
        } else {
            let missing: Vec<String> =
                (0..3).filter(|&a| found[a].is_none()).map(|a| format!("{name}.{}", suffixes[a])).collect();
            warnings.push(format!("`{name}` is ignored: it has no {} column", missing.join(" or ")));
        }
    }
    (names, columns, warnings)
}

/// Quotes a column name for writing when CSV needs it to.
fn csv_name(name: &str) -> String {
    if name.contains([',', '"', '\n', '\r']) || name.starts_with([' ', '\t']) || name.ends_with([' ', '\t']) {
        format!("\"{}\"", name.replace('"', "\"\""))
    } else {
        name.to_string()
    }
}

impl Table {
    /// Parses a table; see the module documentation for what is accepted.
    ///
    /// Errors (with line and column): an empty file, a header field that is
    /// empty (other than the first) or repeated, a row whose number of fields
    /// differs from the header's, a field that is not a finite number, a
    /// header with no rows under it.
    pub fn parse(text: &[u8], file: &str) -> Result<Table, Error> {
        let located = Located { text, file };
        let mut pos = if text.starts_with(b"\xEF\xBB\xBF") { 3 } else { 0 };
        while pos < text.len() && is_blank_line(text, pos) {
            pos = past_line_end(text, pos);
        }
        if pos >= text.len() {
            return Err(located.at(pos, "the file is empty: expected a header row of column names"));
        }

        let mut fields = Vec::new();
        pos = read_record(&located, pos, &mut fields)?;
        let header_fields = fields.clone();
        let mut warnings = Vec::new();
        let first_name = header_name(&located, &header_fields[0])?;
        // R's write.csv writes row names as an unnamed first column.
        let row_numbers = first_name.is_empty() && header_fields.len() > 1;
        if row_numbers {
            warnings.push("the first column has no name: taken as R's row numbers and dropped".to_string());
        }
        let skip = usize::from(row_numbers);
        let mut headers: Vec<String> = Vec::with_capacity(header_fields.len() - skip);
        let mut seen: HashMap<String, usize> = HashMap::new();
        for (column, field) in header_fields.iter().enumerate().skip(skip) {
            let name = header_name(&located, field)?;
            if name.is_empty() {
                return Err(located.at(field.start, "expected a column name, found an empty field"));
            }
            if let Some(first) = seen.insert(name.clone(), column + 1) {
                return Err(located.at(
                    field.start,
                    format!("column name `{name}` appears twice (first as column {first})"),
                ));
            }
            headers.push(name);
        }
        let header_end = pos;

        let field_count = header_fields.len();
        let column_count = headers.len();
        let mut values = Vec::with_capacity(column_count * (text.len() / (8 * field_count)).max(1));
        while pos < text.len() {
            if is_blank_line(text, pos) {
                pos = past_line_end(text, pos);
                continue;
            }
            pos = read_record(&located, pos, &mut fields)?;
            if fields.len() != field_count {
                let offset = if fields.len() < field_count {
                    fields.last().map_or(pos, |f| f.end)
                } else {
                    fields[field_count].start
                };
                return Err(
                    located.at(offset, format!("expected {field_count} fields, found {}", fields.len()))
                );
            }
            for field in &fields[skip..] {
                values.push(parse_number(&located, field)?);
            }
        }
        if values.is_empty() {
            return Err(located.at(header_end, "expected rows of numbers after the header, found none"));
        }

        let (joint_names, position_columns, position_warnings) = triples(&headers, ["Dx", "Dy", "Dz"]);
        warnings.extend(position_warnings);
        let (_, _, accel_warnings) = triples(&headers, ["ax", "ay", "az"]);
        warnings.extend(accel_warnings);
        Ok(Table { file: file.to_string(), headers, values, joint_names, position_columns, warnings })
    }

    pub fn frame_count(&self) -> usize {
        self.values.len().checked_div(self.headers.len()).unwrap_or(0)
    }

    /// Frame `f`'s values, one per header.
    pub fn row(&self, f: usize) -> &[f64] {
        let n = self.headers.len();
        &self.values[f * n..(f + 1) * n]
    }

    /// The index of the column called `name` (exact match).
    pub fn column_index(&self, name: &str) -> Option<usize> {
        self.headers.iter().position(|h| h == name)
    }

    /// The seconds between frames: the median difference of the `Time` column.
    /// `None` without a `Time` column, with fewer than two frames, or when the
    /// times do not strictly increase.
    pub fn frame_time_s(&self) -> Option<f64> {
        let time = self.column("Time")?;
        let steps: Vec<f64> = time.windows(2).map(|w| w[1] - w[0]).collect();
        if steps.is_empty() || steps.iter().any(|&d| d.is_nan() || d <= 0.0) {
            return None;
        }
        Some(crate::signal::stats::median(&steps))
    }

    /// Global positions of the joints in `joint_names`, in that order.
    pub fn poses(&self) -> Poses {
        let frame_count = self.frame_count();
        let mut positions_cm = Vec::with_capacity(frame_count * self.position_columns.len());
        for f in 0..frame_count {
            let row = self.row(f);
            positions_cm
                .extend(self.position_columns.iter().map(|&[x, y, z]| DVec3::new(row[x], row[y], row[z])));
        }
        Poses { joint_count: self.position_columns.len(), positions_cm }
    }

    /// The values of the column called `name`, one per frame.
    pub fn column(&self, name: &str) -> Option<Vec<f64>> {
        let c = self.column_index(name)?;
        Some(self.values.iter().skip(c).step_by(self.headers.len()).copied().collect())
    }

    /// `<sensor>.ax/.ay/.az` per frame, in g; `None` unless all three exist.
    pub fn accel_g(&self, sensor: &str) -> Option<Vec<DVec3>> {
        let [x, y, z] = ["ax", "ay", "az"].map(|a| self.column_index(&format!("{sensor}.{a}")));
        let (x, y, z) = (x?, y?, z?);
        Some(
            (0..self.frame_count())
                .map(|f| {
                    let row = self.row(f);
                    DVec3::new(row[x], row[y], row[z])
                })
                .collect(),
        )
    }

    /// A copy with `shift_cm[f]` added to every `.Dx`, `.Dy`, `.Dz` column of
    /// frame `f` (including those of joints missing an axis, as RMoCap does).
    /// Frames past the end of `shift_cm` are left as they are.
    pub fn with_shift(&self, shift_cm: &[DVec3]) -> Table {
        let axes: Vec<(usize, usize)> = self
            .headers
            .iter()
            .enumerate()
            .filter_map(|(c, h)| {
                let (_, suffix) = split_suffix(h)?;
                let axis = ["Dx", "Dy", "Dz"].iter().position(|&s| s == suffix)?;
                Some((c, axis))
            })
            .collect();
        let mut out = self.clone();
        let n = self.headers.len().max(1);
        for (row, shift) in out.values.chunks_mut(n).zip(shift_cm) {
            for &(c, axis) in &axes {
                row[c] += shift[axis];
            }
        }
        out
    }

    /// The table as CSV: the same headers (quoted only where CSV requires),
    /// `\n` line ends, and numbers in Rust's shortest round-trip form, so
    /// parsing the output gives back the same table.
    pub fn write(&self) -> String {
        let mut out = String::with_capacity(self.values.len() * 20 + self.headers.len() * 16);
        let names: Vec<String> = self.headers.iter().map(|h| csv_name(h)).collect();
        out.push_str(&names.join(","));
        out.push('\n');
        for f in 0..self.frame_count() {
            for (i, v) in self.row(f).iter().enumerate() {
                if i > 0 {
                    out.push(',');
                }
                // Writing to a String cannot fail.
                let _ = write!(out, "{v}");
            }
            out.push('\n');
        }
        out
    }
}

impl Accelerations {
    /// Parses an accelerometer file (any table with `<Sensor>.ax/.ay/.az`
    /// columns). Errors as [`Table::parse`], and when no sensor has all three.
    pub fn parse(text: &[u8], file: &str) -> Result<Self, Error> {
        let accelerations = Accelerations::from_table(&Table::parse(text, file)?);
        if accelerations.sensor_names.is_empty() {
            return Err(Error::whole(file, "expected `<Sensor>.ax`, `.ay` and `.az` columns, found none"));
        }
        Ok(accelerations)
    }

    /// The sensors of a table that have all three of `.ax`, `.ay`, `.az`.
    pub fn from_table(table: &Table) -> Self {
        let (sensor_names, columns, _) = triples(&table.headers, ["ax", "ay", "az"]);
        let accel_g = columns
            .iter()
            .map(|&[x, y, z]| {
                (0..table.frame_count())
                    .map(|f| {
                        let row = table.row(f);
                        DVec3::new(row[x], row[y], row[z])
                    })
                    .collect()
            })
            .collect();
        Accelerations { file: table.file.clone(), sensor_names, accel_g }
    }

    pub fn frame_count(&self) -> usize {
        self.accel_g.first().map_or(0, Vec::len)
    }

    /// The readings of the sensor called `name`, one per frame.
    pub fn sensor(&self, name: &str) -> Option<&[DVec3]> {
        let s = self.sensor_names.iter().position(|n| n == name)?;
        Some(&self.accel_g[s])
    }
}
