//! The hips' path as CSV: the shared data's `NAME.truth.csv`
//! (`time_s,hips_x_cm,hips_y_cm,hips_z_cm`, one row per video frame) and the
//! camera tracker's output, which adds `frame` first, and `confidence` and
//! `uncertainty_cm` last.
//! Columns are found by their header names, in any order; others are
//! ignored. The tracker writes `NaN` for the height in a video frame its
//! recording has no pose for (before its start or past its end at the
//! take's offset): read back as NaN. Any other number that is not finite
//! is an error.

use glam::DVec3;

use crate::error::Error;

/// One row: where the hips are at a time.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct HipsSample {
    pub time_s: f64,
    pub hips_cm: DVec3,
    /// How far the tracker trusts the camera in this frame, 0 to 1; `None`
    /// in a file without the column (a truth).
    pub confidence: Option<f64>,
    /// How far (cm, one σ) the tracker says the hips may be from where it
    /// put them on the floor; `None` where it does not say (a truth, the
    /// paper's tracker, a frame without a pose: an empty cell).
    pub uncertainty_cm: Option<f64>,
}

/// The columns every hips file has.
const REQUIRED: [&str; 4] = ["time_s", "hips_x_cm", "hips_y_cm", "hips_z_cm"];

/// Reads a hips CSV; errors name the line and column.
pub fn parse_hips_csv(text: &str, file_name: &str) -> Result<Vec<HipsSample>, Error> {
    let mut lines = text.lines().enumerate().filter(|(_, l)| !l.trim().is_empty());
    let Some((_, header)) = lines.next() else {
        return Err(Error::whole(
            file_name,
            "is empty; expected a header `time_s,hips_x_cm,hips_y_cm,hips_z_cm`",
        ));
    };
    let names: Vec<&str> = header.split(',').map(str::trim).collect();
    let column = |name: &str| names.iter().position(|n| *n == name);
    let mut required = [0usize; 4];
    for (slot, name) in required.iter_mut().zip(REQUIRED) {
        *slot = column(name)
            .ok_or_else(|| Error::at(file_name, 1, 1, format!("the header has no `{name}` column")))?;
    }
    let confidence = column("confidence");
    let uncertainty = column("uncertainty_cm");
    let mut samples = Vec::new();
    for (index, line) in lines {
        let cells: Vec<&str> = line.split(',').collect();
        // The number in column `c`, finite, or NaN where `nan_is_none_here`.
        let read = |c: usize, name: &str, nan_is_none_here: bool| -> Result<f64, Error> {
            let column_at = 1 + cells[..c.min(cells.len())].iter().map(|s| s.len() + 1).sum::<usize>();
            let cell = cells.get(c).ok_or_else(|| {
                Error::at(file_name, index + 1, line.len() + 1, format!("the row has no `{name}`"))
            })?;
            let value: f64 = cell.trim().parse().map_err(|_| {
                Error::at(
                    file_name,
                    index + 1,
                    column_at,
                    format!("`{}` is not a number ({name})", cell.trim()),
                )
            })?;
            if value.is_finite() || (value.is_nan() && nan_is_none_here) {
                Ok(value)
            } else {
                Err(Error::at(file_name, index + 1, column_at, format!("{name} must be finite")))
            }
        };
        let number = |c: usize, name: &str| read(c, name, false);
        let [t, x, y, z] = required;
        samples.push(HipsSample {
            time_s: number(t, "time_s")?,
            // No height where the recording had no pose.
            hips_cm: DVec3::new(
                number(x, "hips_x_cm")?,
                read(y, "hips_y_cm", true)?,
                number(z, "hips_z_cm")?,
            ),
            confidence: confidence.map(|c| number(c, "confidence")).transpose()?,
            uncertainty_cm: match uncertainty {
                Some(c) if cells.get(c).is_some_and(|cell| !cell.trim().is_empty()) => {
                    Some(number(c, "uncertainty_cm")?)
                }
                _ => None,
            },
        });
    }
    Ok(samples)
}

/// The tracker's CSV: a header and one row per frame, `frame, time_s,
/// hips_x_cm, hips_y_cm, hips_z_cm, confidence, uncertainty_cm`, positions
/// to 0.1 mm, times to 1 µs, the uncertainty to 1 mm or empty (the same
/// bytes on every machine).
pub fn format_hips_csv(samples: &[HipsSample]) -> String {
    let mut text = String::from("frame,time_s,hips_x_cm,hips_y_cm,hips_z_cm,confidence,uncertainty_cm\n");
    for (frame, s) in samples.iter().enumerate() {
        let p = s.hips_cm;
        text += &format!(
            "{frame},{:.6},{:.4},{:.4},{:.4},{:.3},{}\n",
            s.time_s,
            p.x,
            p.y,
            p.z,
            s.confidence.unwrap_or(0.0),
            s.uncertainty_cm.map_or(String::new(), |u| format!("{u:.1}"))
        );
    }
    text
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_truth_and_the_tracker_s_files_read_back() {
        let truth = "time_s,hips_x_cm,hips_y_cm,hips_z_cm\n0.000000,0.0000,90.2704,0.0000\n0.033333,0.2404,90.6889,3.0210\n";
        let samples = parse_hips_csv(truth, "t.csv").unwrap();
        assert_eq!(samples.len(), 2);
        assert_eq!(samples[1].hips_cm, DVec3::new(0.2404, 90.6889, 3.021));
        assert_eq!(samples[1].confidence, None);
        let tracked: Vec<HipsSample> =
            samples.iter().map(|s| HipsSample { confidence: Some(0.5), ..*s }).collect();
        let text = format_hips_csv(&tracked);
        assert!(text.starts_with(
            "frame,time_s,hips_x_cm,hips_y_cm,hips_z_cm,confidence,uncertainty_cm\n0,0.000000,"
        ));
        assert_eq!(parse_hips_csv(&text, "o.csv").unwrap(), tracked);
        let stated: Vec<HipsSample> =
            tracked.iter().map(|s| HipsSample { uncertainty_cm: Some(4.5), ..*s }).collect();
        let text = format_hips_csv(&stated);
        assert!(text.lines().nth(1).unwrap().ends_with(",0.500,4.5"), "{text}");
        assert_eq!(parse_hips_csv(&text, "o.csv").unwrap(), stated);
    }

    #[test]
    fn bad_rows_are_errors_with_their_place() {
        let error = parse_hips_csv("time_s,hips_x_cm,hips_y_cm\n", "t.csv").unwrap_err();
        assert_eq!(error.to_string(), "t.csv:1:1: the header has no `hips_z_cm` column");
        let error = parse_hips_csv("time_s,hips_x_cm,hips_y_cm,hips_z_cm\n0,1,x,3\n", "t.csv").unwrap_err();
        assert_eq!(error.to_string(), "t.csv:2:5: `x` is not a number (hips_y_cm)");
        let error = parse_hips_csv("time_s,hips_x_cm,hips_y_cm,hips_z_cm\n0,1\n", "t.csv").unwrap_err();
        assert_eq!(error.line_column, Some((2, 4)));
        assert!(parse_hips_csv("", "t.csv").is_err());
        assert!(parse_hips_csv("time_s,hips_x_cm,hips_y_cm,hips_z_cm\n0,1,inf,3\n", "t.csv").is_err());
        assert!(parse_hips_csv("time_s,hips_x_cm,hips_y_cm,hips_z_cm\n0,NaN,1,3\n", "t.csv").is_err());
        // The tracker's height in a frame without a pose.
        let no_pose = parse_hips_csv("time_s,hips_x_cm,hips_y_cm,hips_z_cm\n0,1,NaN,3\n", "t.csv").unwrap();
        assert!(no_pose[0].hips_cm.y.is_nan() && no_pose[0].hips_cm.x == 1.0);
    }
}
