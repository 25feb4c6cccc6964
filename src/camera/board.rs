//! The ChArUco board: its layout as OpenCV draws it, where it lies in the
//! world, and its file `NAME.board.json`.
//!
//! Layout, OpenCV's (`cv::aruco::CharucoBoard`, the modern pattern):
//! `squares_x × squares_y` squares, the top-left one black; the markers sit
//! on the white squares, numbered row by row from the top left. **Board
//! coordinates** (cm): the origin at the outer corner of the top-left
//! square, X along the first row, Y down the first column, Z into the board.
//! The **inner corners** (where four squares meet) are numbered as OpenCV
//! numbers its ChArUco corners: corner `(i, j)`, 1 ≤ i < squares_x,
//! 1 ≤ j < squares_y, lies at `(i, j) · square_cm` and has the id
//! `(j − 1) · (squares_x − 1) + (i − 1)`.

use glam::{DAffine3, DMat3, DVec2, DVec3};
use serde::Deserialize;

use crate::error::{Error, line_column_of};

/// OpenCV's predefined dictionaries that a board may use, with the number
/// of markers each holds.
pub const DICTIONARIES: [(&str, u32); 22] = [
    ("DICT_4X4_50", 50),
    ("DICT_4X4_100", 100),
    ("DICT_4X4_250", 250),
    ("DICT_4X4_1000", 1000),
    ("DICT_5X5_50", 50),
    ("DICT_5X5_100", 100),
    ("DICT_5X5_250", 250),
    ("DICT_5X5_1000", 1000),
    ("DICT_6X6_50", 50),
    ("DICT_6X6_100", 100),
    ("DICT_6X6_250", 250),
    ("DICT_6X6_1000", 1000),
    ("DICT_7X7_50", 50),
    ("DICT_7X7_100", 100),
    ("DICT_7X7_250", 250),
    ("DICT_7X7_1000", 1000),
    ("DICT_ARUCO_ORIGINAL", 1024),
    ("DICT_APRILTAG_16h5", 30),
    ("DICT_APRILTAG_25h9", 35),
    ("DICT_APRILTAG_36h10", 2320),
    ("DICT_APRILTAG_36h11", 587),
    ("DICT_ARUCO_MIP_36h12", 250),
];

/// A ChArUco board and how it lies in the world.
#[derive(Clone, Debug, PartialEq)]
pub struct Board {
    /// The OpenCV name of its marker dictionary, one of [`DICTIONARIES`].
    pub dictionary: &'static str,
    pub squares_x: u32,
    pub squares_y: u32,
    pub square_cm: f64,
    pub marker_cm: f64,
    /// OpenCV's `setLegacyPattern(true)`: for an even `squares_y` the
    /// top-left square is white. (For an odd `squares_y` both patterns are
    /// the same board.)
    pub legacy_pattern: bool,
    /// Board cm → world cm.
    pub world_from_board: DAffine3,
    /// How the board lies, in words (kept from the file; not interpreted).
    pub placement: String,
}

/// An inner corner of a board seen in an image.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct BoardCorner {
    /// OpenCV's ChArUco corner id (see the module documentation).
    pub id: u32,
    pub pixel: DVec2,
}

/// The board lying face up on the floor with its origin at the world
/// origin: board X = world +X, board Y = world +Z, board Z = world −Y, so a
/// board point (X, Y, 0) is the world point (X, 0, Y).
pub fn floor_from_board() -> DAffine3 {
    DAffine3::from_mat3(DMat3::from_cols(DVec3::X, DVec3::Z, DVec3::NEG_Y))
}

impl Board {
    /// A board lying on the floor as [`floor_from_board`] places it, checked
    /// as a file's board would be (`source` names the input in errors).
    pub fn on_floor(
        dictionary: &str,
        squares_x: u32,
        squares_y: u32,
        square_cm: f64,
        marker_cm: f64,
        source: &str,
    ) -> Result<Board, Error> {
        let board = Board {
            dictionary: dictionary_name(dictionary)
                .ok_or_else(|| Error::whole(source, unknown_dictionary(dictionary)))?,
            squares_x,
            squares_y,
            square_cm,
            marker_cm,
            legacy_pattern: false,
            world_from_board: floor_from_board(),
            placement: String::new(),
        };
        board.check().map_err(|(_, message)| Error::whole(source, message))?;
        Ok(board)
    }

    /// Reads a `NAME.board.json`. `dictionary`, `squares_x`, `squares_y`,
    /// `square_cm` and `marker_cm` are required; `legacy_pattern` defaults
    /// to false, `world_from_board` (a 3×3 rotation, rows first) to
    /// [`floor_from_board`]; other fields are ignored. An error names the
    /// field and its line:column.
    pub fn from_json(text: &str, file_name: &str) -> Result<Board, Error> {
        let raw: RawBoard = serde_json::from_str(text).map_err(|e| json_error(&e, file_name))?;
        let board = Board {
            // Checked while reading (see `known_dictionary`).
            dictionary: dictionary_name(&raw.dictionary).unwrap_or("DICT_4X4_50"),
            squares_x: raw.squares_x,
            squares_y: raw.squares_y,
            square_cm: raw.square_cm,
            marker_cm: raw.marker_cm,
            legacy_pattern: raw.legacy_pattern,
            world_from_board: raw.world_from_board.map_or_else(floor_from_board, |rows| {
                DAffine3::from_mat3(DMat3::from_cols_array_2d(&rows).transpose())
            }),
            placement: raw.placement,
        };
        board.check().map_err(|(field, message)| match field_position(text, field) {
            Some((line, column)) => Error::at(file_name, line, column, message),
            None => Error::whole(file_name, message),
        })?;
        Ok(board)
    }

    /// The board as `NAME.board.json` text (the fields [`Board::from_json`]
    /// reads).
    pub fn to_json(&self) -> String {
        let m = self.world_from_board.matrix3.transpose().to_cols_array_2d();
        let rows: Vec<String> = m.iter().map(|r| format!("[{}, {}, {}]", r[0], r[1], r[2])).collect();
        format!(
            "{{\n \"dictionary\": \"{}\",\n \"squares_x\": {},\n \"squares_y\": {},\n \"square_cm\": {},\n \
             \"marker_cm\": {},\n \"legacy_pattern\": {},\n \"world_from_board\": [{}],\n \"placement\": {}\n}}\n",
            self.dictionary,
            self.squares_x,
            self.squares_y,
            self.square_cm,
            self.marker_cm,
            self.legacy_pattern,
            rows.join(", "),
            serde_json::Value::String(self.placement.clone()),
        )
    }

    /// The number of inner corners, `(squares_x − 1)(squares_y − 1)`.
    pub fn corner_count(&self) -> u32 {
        (self.squares_x - 1) * (self.squares_y - 1)
    }

    /// The number of markers, one per white square.
    pub fn marker_count(&self) -> u32 {
        let squares = self.squares_x * self.squares_y;
        if self.top_left_is_white() { squares.div_ceil(2) } else { squares / 2 }
    }

    /// Whether the top-left square carries a marker (OpenCV's legacy
    /// pattern with an even number of rows).
    pub fn top_left_is_white(&self) -> bool {
        self.legacy_pattern && self.squares_y.is_multiple_of(2)
    }

    /// Inner corner `id`'s place on the board (cm, z = 0), or `None` for an
    /// id the board does not have.
    pub fn corner_on_board(&self, id: u32) -> Option<DVec2> {
        let per_row = self.squares_x - 1;
        (id < self.corner_count())
            .then(|| DVec2::new((id % per_row + 1) as f64, (id / per_row + 1) as f64) * self.square_cm)
    }

    /// Inner corner `id` in the world (cm).
    pub fn corner_in_world(&self, id: u32) -> Option<DVec3> {
        self.corner_on_board(id).map(|p| self.world_from_board.transform_point3(p.extend(0.0)))
    }

    /// The id of the inner corner `(i, j)` (in squares from the origin).
    pub fn corner_id(&self, i: u32, j: u32) -> Option<u32> {
        (i >= 1 && j >= 1 && i < self.squares_x && j < self.squares_y)
            .then(|| (j - 1) * (self.squares_x - 1) + (i - 1))
    }

    /// What is wrong with the layout, as the field to blame and a message.
    fn check(&self) -> Result<(), (&'static str, String)> {
        if self.squares_x < 2 || self.squares_y < 2 {
            let field = if self.squares_x < 2 { "squares_x" } else { "squares_y" };
            return Err((field, format!("{field}: a board has at least 2 squares each way")));
        }
        if self.squares_x > 1000 || self.squares_y > 1000 {
            return Err(("squares_x", "squares_x, squares_y: at most 1000 squares each way".into()));
        }
        if !(self.square_cm.is_finite() && self.square_cm > 0.0) {
            return Err((
                "square_cm",
                format!("square_cm: expected a size > 0 cm, found {}", self.square_cm),
            ));
        }
        if !(self.marker_cm.is_finite() && self.marker_cm > 0.0 && self.marker_cm < self.square_cm) {
            return Err((
                "marker_cm",
                format!(
                    "marker_cm: expected a size between 0 and square_cm ({} cm), found {}",
                    self.square_cm, self.marker_cm
                ),
            ));
        }
        let available = DICTIONARIES.iter().find(|(n, _)| *n == self.dictionary).map_or(0, |d| d.1);
        if self.marker_count() > available {
            return Err((
                "dictionary",
                format!(
                    "dictionary: {} holds {available} markers, the board needs {}",
                    self.dictionary,
                    self.marker_count()
                ),
            ));
        }
        let m = self.world_from_board.matrix3;
        let off =
            (m.transpose() * m - DMat3::IDENTITY).to_cols_array().iter().fold(0.0f64, |a, v| a.max(v.abs()));
        if off.is_nan() || off > 1e-6 || (m.determinant() - 1.0).abs() > 1e-6 {
            return Err((
                "world_from_board",
                "world_from_board: expected a rotation (orthonormal rows, determinant +1)".into(),
            ));
        }
        if self.legacy_pattern && self.squares_y.is_multiple_of(2) {
            // The detector knows OpenCV's modern pattern only; with an odd
            // number of rows the legacy one is the same board.
            return Err((
                "legacy_pattern",
                "legacy_pattern: the legacy pattern with an even squares_y is not supported; print the board without it"
                    .into(),
            ));
        }
        Ok(())
    }
}

/// The board file as written, before its layout is checked.
#[derive(Deserialize)]
struct RawBoard {
    #[serde(deserialize_with = "known_dictionary")]
    dictionary: String,
    squares_x: u32,
    squares_y: u32,
    square_cm: f64,
    marker_cm: f64,
    #[serde(default)]
    legacy_pattern: bool,
    #[serde(default)]
    world_from_board: Option<[[f64; 3]; 3]>,
    #[serde(default)]
    placement: String,
}

/// A dictionary name, checked where it stands in the file so that the
/// error's position is the field's.
fn known_dictionary<'de, D: serde::Deserializer<'de>>(d: D) -> Result<String, D::Error> {
    let name = String::deserialize(d)?;
    match dictionary_name(&name) {
        Some(_) => Ok(name),
        None => Err(serde::de::Error::custom(format!("dictionary: {}", unknown_dictionary(&name)))),
    }
}

/// The table's spelling of `name` (`DICT_4X4_50`, or `4X4_50`, any case).
fn dictionary_name(name: &str) -> Option<&'static str> {
    let wanted = name.trim();
    DICTIONARIES.iter().map(|d| d.0).find(|n| {
        n.eq_ignore_ascii_case(wanted)
            || n.strip_prefix("DICT_").is_some_and(|s| s.eq_ignore_ascii_case(wanted))
    })
}

fn unknown_dictionary(name: &str) -> String {
    format!("unknown dictionary {name:?}; expected one of OpenCV's, e.g. DICT_4X4_50")
}

/// serde_json's message without its own " at line L column C" tail, placed
/// as our errors are.
fn json_error(e: &serde_json::Error, file_name: &str) -> Error {
    let text = e.to_string();
    let message = match text.rfind(" at line ") {
        Some(cut) => &text[..cut],
        None => &text[..],
    };
    if e.line() == 0 {
        Error::whole(file_name, message)
    } else {
        Error::at(file_name, e.line(), e.column(), message)
    }
}

/// Line and column of the value of the first `"field":` in `text`.
fn field_position(text: &str, field: &str) -> Option<(usize, usize)> {
    let key = format!("\"{field}\"");
    let mut from = 0;
    while let Some(found) = text[from..].find(&key) {
        let after = from + found + key.len();
        let rest = &text[after..];
        let gap = rest.len() - rest.trim_start().len();
        if rest.trim_start().starts_with(':') {
            let value = &rest[gap + 1..];
            let start = after + gap + 1 + (value.len() - value.trim_start().len());
            return Some(line_column_of(text.as_bytes(), start));
        }
        from = after;
    }
    None
}

#[cfg(test)]
mod tests {
    use super::*;

    const SHARED: &str = r#"{
 "dictionary": "DICT_4X4_50",
 "squares_x": 7,
 "squares_y": 5,
 "square_cm": 30.0,
 "marker_cm": 23.0,
 "legacy_pattern": false,
 "world_from_board": [[1.0, 0.0, 0.0], [0.0, 0.0, -1.0], [0.0, 1.0, 0.0]],
 "placement": "lying face up on the floor"
}"#;

    #[test]
    fn the_shared_board_reads_and_places_corners_as_opencv() {
        let board = Board::from_json(SHARED, "b.json").unwrap();
        assert_eq!((board.corner_count(), board.marker_count()), (24, 17));
        // Corner 0 is one square in from the origin each way; ids run along X.
        assert_eq!(board.corner_on_board(0), Some(DVec2::new(30.0, 30.0)));
        assert_eq!(board.corner_on_board(7), Some(DVec2::new(60.0, 60.0)));
        assert_eq!(board.corner_on_board(23), Some(DVec2::new(180.0, 120.0)));
        assert_eq!(board.corner_on_board(24), None);
        assert_eq!(board.corner_id(2, 2), Some(7));
        // A board point (X, Y, 0) is the world point (X, 0, Y).
        assert!((board.corner_in_world(23).unwrap() - DVec3::new(180.0, 0.0, 120.0)).length() < 1e-12);
        assert_eq!(board.world_from_board, floor_from_board());
        assert_eq!(Board::from_json(&board.to_json(), "again.json").unwrap(), board);
    }

    #[test]
    fn a_wrong_or_missing_field_is_named_with_its_place() {
        let missing = SHARED.replace(" \"squares_x\": 7,\n", "");
        let e = Board::from_json(&missing, "b.json").unwrap_err();
        assert!(e.message.contains("squares_x") && e.line_column.is_some(), "{e}");

        let e = Board::from_json(&SHARED.replace("DICT_4X4_50", "DICT_9X9_5"), "b.json").unwrap_err();
        assert_eq!(e.line_column.map(|p| p.0), Some(2), "{e}");
        assert!(e.message.contains("dictionary"), "{e}");

        let e = Board::from_json(&SHARED.replace("23.0", "31.0"), "b.json").unwrap_err();
        assert_eq!(e.line_column, Some((6, 15)), "{e}");
        assert!(e.message.starts_with("marker_cm"), "{e}");

        let e = Board::from_json(&SHARED.replace("-1.0", "1.0"), "b.json").unwrap_err();
        assert!(e.message.starts_with("world_from_board") && e.line_column.map(|p| p.0) == Some(8), "{e}");

        let e = Board::from_json(&SHARED.replace("\"squares_y\": 5", "\"squares_y\": \"5\""), "b.json")
            .unwrap_err();
        assert_eq!(e.line_column.map(|p| p.0), Some(4), "{e}");

        let big = SHARED.replace("\"squares_x\": 7", "\"squares_x\": 21");
        let e = Board::from_json(&big, "b.json").unwrap_err();
        assert!(e.message.contains("holds 50 markers"), "{e}");

        let legacy = SHARED.replace("\"squares_y\": 5", "\"squares_y\": 6").replace("false", "true");
        assert!(Board::from_json(&legacy, "b.json").unwrap_err().message.starts_with("legacy_pattern"));
        // With an odd number of rows the legacy pattern is the modern one.
        assert!(Board::from_json(&SHARED.replace("false", "true"), "b.json").is_ok());
    }

    #[test]
    fn flags_make_the_same_board_as_the_file() {
        let from_flags = Board::on_floor("4x4_50", 7, 5, 30.0, 23.0, "<flags>").unwrap();
        let mut from_file = Board::from_json(SHARED, "b.json").unwrap();
        from_file.placement.clear();
        assert_eq!(from_flags, from_file);
        assert!(Board::on_floor("DICT_4X4_50", 7, 1, 30.0, 23.0, "<flags>").is_err());
        assert!(Board::on_floor("nope", 7, 5, 30.0, 23.0, "<flags>").is_err());
    }
}
