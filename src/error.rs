//! The one error type of the core: every failure says which file it is about
//! and, when the problem sits at a place in the text, the line and column.

use std::fmt;

/// An error shown to the user as `file:line:column: message` (or `file: message`
/// when there is no position, such as a missing file or a length mismatch).
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct Error {
    /// The file name as the user gave it (or a label such as `<demo>`).
    pub file: String,
    /// 1-based line and column of the offending text, when there is one.
    pub line_column: Option<(usize, usize)>,
    /// What was wrong, phrased as what was expected.
    pub message: String,
}

impl Error {
    /// An error at a place in a text file.
    pub fn at(file: &str, line: usize, column: usize, message: impl Into<String>) -> Self {
        Error { file: file.to_string(), line_column: Some((line, column)), message: message.into() }
    }

    /// An error about a whole file (or input), with no position.
    pub fn whole(file: &str, message: impl Into<String>) -> Self {
        Error { file: file.to_string(), line_column: None, message: message.into() }
    }
}

impl fmt::Display for Error {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self.line_column {
            Some((line, column)) => {
                write!(f, "{}:{}:{}: {}", self.file, line, column, self.message)
            }
            None => write!(f, "{}: {}", self.file, self.message),
        }
    }
}

impl std::error::Error for Error {}

/// 1-based line and column of byte `offset` in `text`, counted the way editors
/// do (columns in bytes; good enough for the ASCII formats we read). Only called
/// on the error path, so the linear scan costs nothing on good input.
pub fn line_column_of(text: &[u8], offset: usize) -> (usize, usize) {
    let offset = offset.min(text.len());
    let before = &text[..offset];
    let line = 1 + before.iter().filter(|&&b| b == b'\n').count();
    let line_start = before.iter().rposition(|&b| b == b'\n').map_or(0, |p| p + 1);
    (line, offset - line_start + 1)
}
