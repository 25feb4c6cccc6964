//! The per-file table of `embusen eval` on ground-truth recordings and its
//! summary: medians of each figure per motion type and over all files, for
//! the paper method and the contact method side by side.

use crate::error::Error;
use crate::eval::{Accuracy, evaluate_groundtruth, motion_type};
use crate::io::bvh::Bvh;
use crate::signal::stats::median;
use crate::translate::Method;
use crate::translate::hachaj::HachajParams;

/// A file whose true hips path is shorter than this (cm) stays in place (a
/// bow): percentages of its path say nothing, so the medians of those leave
/// it out. Its path ratio does say something: how far noise makes a body
/// that stands wander (issue 23 asks ≤ 1.3).
pub const MOVING_MIN_PATH_CM: f64 = 50.0;

/// Both methods' accuracy on one ground-truth file.
#[derive(Clone, Debug, PartialEq)]
pub struct FileAccuracy {
    /// The file name, as the table shows it.
    pub name: String,
    pub hachaj: Accuracy,
    pub contact: Accuracy,
}

/// Medians over a group of files: per method, an [`Accuracy`] each field of
/// which is the median of that field over the group (see [`medians`]).
#[derive(Clone, Debug, PartialEq)]
pub struct GroupMedians {
    /// Every file of the group, moving or not.
    pub file_count: usize,
    pub hachaj: Accuracy,
    pub contact: Accuracy,
}

/// The summary of a ground-truth evaluation.
#[derive(Clone, Debug, PartialEq)]
pub struct Summary {
    /// Per motion type (see [`motion_type`]), in the types' sorted order.
    pub by_motion_type: Vec<(String, GroupMedians)>,
    /// Over every file.
    pub all: GroupMedians,
    /// Files whose true hips path is at least [`MOVING_MIN_PATH_CM`].
    pub moving_file_count: usize,
    /// Of those, the files where the contact method's mean error is below
    /// the paper method's.
    pub contact_better_count: usize,
}

/// Evaluates a ground-truth BVH (see [`evaluate_groundtruth`]) with the paper
/// method and the contact method, each with its default parameters.
pub fn evaluate_file(bvh: &Bvh, name: &str) -> Result<FileAccuracy, Error> {
    let hachaj = evaluate_groundtruth(bvh, name, &Method::Hachaj(HachajParams::default()))?;
    let contact = evaluate_groundtruth(bvh, name, &Method::default())?;
    Ok(FileAccuracy { name: name.to_string(), hachaj, contact })
}

pub(super) fn is_moving(a: &Accuracy) -> bool {
    a.true_path_cm >= MOVING_MIN_PATH_CM
}

/// The median of each field of one method's `accuracies` (NaN ones left
/// out, see [`median`]): the percentages over the moving files only (see
/// [`MOVING_MIN_PATH_CM`]), the path ratio, the true path, the skating and
/// the vertical error over all. NaN when nothing is left to take the median of.
pub fn medians(accuracies: &[&Accuracy]) -> Accuracy {
    let of = |figure: fn(&Accuracy) -> f64, moving_only: bool| {
        let values: Vec<f64> =
            accuracies.iter().filter(|a| !moving_only || is_moving(a)).map(|a| figure(a)).collect();
        median(&values)
    };
    Accuracy {
        true_path_cm: of(|a| a.true_path_cm, false),
        mean_error_pct: of(|a| a.mean_error_pct, true),
        final_error_pct: of(|a| a.final_error_pct, true),
        path_ratio: of(|a| a.path_ratio, false),
        skating_cm_per_s: of(|a| a.skating_cm_per_s, false),
        truth_skating_cm_per_s: of(|a| a.truth_skating_cm_per_s, false),
        vertical_error_cm: of(|a| a.vertical_error_cm, false),
    }
}

pub(super) fn group_medians(files: &[&FileAccuracy]) -> GroupMedians {
    let hachaj: Vec<&Accuracy> = files.iter().map(|f| &f.hachaj).collect();
    let contact: Vec<&Accuracy> = files.iter().map(|f| &f.contact).collect();
    GroupMedians { file_count: files.len(), hachaj: medians(&hachaj), contact: medians(&contact) }
}

/// The medians of `files` per motion type and over all, and how often the
/// contact method beats the paper method on the moving files. Each method's
/// file counts as moving by its own `true_path_cm` (the same truth for both).
pub fn summarise(files: &[FileAccuracy]) -> Summary {
    let by_motion_type =
        by_motion_type(files, |f| f).into_iter().map(|(t, group)| (t, group_medians(&group))).collect();
    let (moving_file_count, contact_better_count) = contact_better(files.iter());
    Summary {
        by_motion_type,
        all: group_medians(&files.iter().collect::<Vec<_>>()),
        moving_file_count,
        contact_better_count,
    }
}

/// `items` grouped by the motion type (see [`motion_type`]) of the file each
/// holds (`file_of`), in the types' sorted order; each group in `items`' order.
pub(super) fn by_motion_type<T>(
    items: &[T],
    file_of: impl Fn(&T) -> &FileAccuracy,
) -> Vec<(String, Vec<&T>)> {
    let mut types: Vec<String> = items.iter().map(|i| motion_type(&file_of(i).name)).collect();
    types.sort();
    types.dedup();
    types
        .into_iter()
        .map(|t| {
            let group = items.iter().filter(|i| motion_type(&file_of(i).name) == t).collect();
            (t, group)
        })
        .collect()
}

/// Of `files`, how many are moving (by the contact method's `true_path_cm`,
/// the same truth for both), and of those, on how many the contact method's
/// mean error is below the paper method's.
pub(super) fn contact_better<'a>(files: impl Iterator<Item = &'a FileAccuracy>) -> (usize, usize) {
    let moving: Vec<&FileAccuracy> = files.filter(|f| is_moving(&f.contact)).collect();
    let better = moving.iter().filter(|f| f.contact.mean_error_pct < f.hachaj.mean_error_pct).count();
    (moving.len(), better)
}

/// How wide the ground-truth table's first column (the file name) is.
const FILE_WIDTH: usize = 36;

/// The table's title and column header, two lines without a final line end.
pub fn format_header() -> String {
    format!(
        "ground truth: translation frozen root→hips, re-estimated, compared with the truth\n{}",
        format_columns(FILE_WIDTH)
    )
}

/// The column header of both methods' figures, the first column (the file
/// name) `label_width` wide; no line end.
pub(super) fn format_columns(label_width: usize) -> String {
    format!(
        "{:<label_width$} {:>8} | {:>17} | {:>17} | {:>13} | {:>20} | {:>13}",
        "file",
        "path m",
        "mean err % p/c",
        "final err % p/c",
        "ratio p/c",
        "skate cm/s p/c truth",
        "vert cm p/c"
    )
}

/// One line of the table: `label` (padded to `label_width`), then `second`
/// (the true path in m of a file, or the file count of a group), then both
/// methods' figures side by side (the truth's skating from `contact`'s).
pub(super) fn format_line(
    label_width: usize,
    label: &str,
    second: &str,
    hachaj: &Accuracy,
    contact: &Accuracy,
) -> String {
    format!(
        "{:<label_width$} {:>8} | {:>8.2} {:>8.2} | {:>8.2} {:>8.2} | {:>6.3} {:>6.3} | {:>6.2} {:>6.2} {:>6.2} | {:>6.1} {:>6.1}",
        label,
        second,
        hachaj.mean_error_pct,
        contact.mean_error_pct,
        hachaj.final_error_pct,
        contact.final_error_pct,
        hachaj.path_ratio,
        contact.path_ratio,
        hachaj.skating_cm_per_s,
        contact.skating_cm_per_s,
        contact.truth_skating_cm_per_s,
        hachaj.vertical_error_cm,
        contact.vertical_error_cm
    )
}

/// A file's line of the table, without a line end.
pub fn format_file(file: &FileAccuracy) -> String {
    format_file_line(FILE_WIDTH, file)
}

/// A file's line with its name padded to `label_width`, without a line end.
pub(super) fn format_file_line(label_width: usize, file: &FileAccuracy) -> String {
    let path_m = format!("{:.2}", file.contact.true_path_cm / 100.0);
    format_line(label_width, &file.name, &path_m, &file.hachaj, &file.contact)
}

/// The summary's lines, each ending in a line end: a heading, one line per
/// motion type, one for all files, and the count of files where contact wins.
pub fn format_summary(summary: &Summary) -> String {
    let group = |label: &str, g: &GroupMedians| {
        format_line(FILE_WIDTH, label, &g.file_count.to_string(), &g.hachaj, &g.contact)
    };
    let counts = (summary.moving_file_count, summary.contact_better_count);
    MEDIANS_HEADING.to_string() + &format_groups(&summary.by_motion_type, &summary.all, counts, "", group)
}

/// The first line of a table's medians, with its line end.
pub(super) const MEDIANS_HEADING: &str = "medians (percentages over files whose hips travel ≥ 0.5 m, the rest over all; the count is all files):\n";

/// One set of medians, each line ending in a line end: per motion type
/// `line("  TYPE", medians)`, then `line("  all", all)`, then (after
/// `count_indent`) on how many of the moving files (`counts`: moving, won)
/// contact beats paper.
pub(super) fn format_groups<G>(
    by_motion_type: &[(String, G)],
    all: &G,
    (moving_file_count, contact_better_count): (usize, usize),
    count_indent: &str,
    line: impl Fn(&str, &G) -> String,
) -> String {
    let mut text = String::new();
    for (motion, medians) in by_motion_type {
        text += &(line(&format!("  {motion}"), medians) + "\n");
    }
    text += &(line("  all", all) + "\n");
    text += &format!(
        "{count_indent}contact beats paper on mean error in {contact_better_count} of {moving_file_count} files \
         whose hips travel ≥ 0.5 m\n"
    );
    text
}

#[cfg(test)]
mod tests {
    use super::*;

    fn accuracy(true_path_cm: f64, mean_error_pct: f64, skating_cm_per_s: f64) -> Accuracy {
        Accuracy {
            true_path_cm,
            mean_error_pct,
            final_error_pct: 2.0 * mean_error_pct,
            path_ratio: 1.0 + mean_error_pct / 100.0,
            skating_cm_per_s,
            truth_skating_cm_per_s: 1.0,
            vertical_error_cm: skating_cm_per_s / 2.0,
        }
    }

    fn file(name: &str, true_path_cm: f64, paper_pct: f64, contact_pct: f64) -> FileAccuracy {
        FileAccuracy {
            name: name.to_string(),
            hachaj: accuracy(true_path_cm, paper_pct, 10.0 * paper_pct),
            contact: accuracy(true_path_cm, contact_pct, 10.0 * contact_pct),
        }
    }

    #[test]
    fn percentages_leave_out_files_that_stay_in_place() {
        let files = [
            file("a_walk_x_001.bvh", 400.0, 4.0, 1.0),
            file("a_walk_x_002.bvh", 300.0, 6.0, 3.0),
            file("a_bow_x_001.bvh", 20.0, 50.0, 90.0),
        ];
        let s = summarise(&files);
        let types: Vec<&str> = s.by_motion_type.iter().map(|(t, _)| t.as_str()).collect();
        assert_eq!(types, ["bow", "walk"]);
        let (_, walk) = &s.by_motion_type[1];
        assert_eq!(walk.file_count, 2);
        assert_eq!(walk.contact.mean_error_pct, median(&[1.0, 3.0]));
        assert_eq!(walk.hachaj.final_error_pct, median(&[8.0, 12.0]));
        // The bow alone has no moving file to take a percentage of; its path
        // ratio, how far it wanders, it has.
        let (_, bow) = &s.by_motion_type[0];
        assert!(bow.contact.mean_error_pct.is_nan() && bow.hachaj.final_error_pct.is_nan());
        assert_eq!(bow.contact.path_ratio, 1.9);
        assert_eq!(bow.contact.skating_cm_per_s, 900.0);
        assert_eq!(s.all.contact.path_ratio, median(&[1.01, 1.03, 1.9]));
        // Over all: the bow counts, and counts in the path ratio, skating and
        // vertical error only.
        assert_eq!(s.all.file_count, 3);
        assert_eq!(s.all.hachaj.true_path_cm, 300.0);
        assert_eq!(s.all.contact.mean_error_pct, median(&[1.0, 3.0]));
        assert_eq!(s.all.contact.skating_cm_per_s, median(&[10.0, 30.0, 900.0]));
        assert_eq!(s.all.hachaj.vertical_error_cm, median(&[20.0, 30.0, 250.0]));
        assert_eq!((s.contact_better_count, s.moving_file_count), (2, 2));
    }

    #[test]
    fn the_summary_has_a_line_per_type_and_one_for_all() {
        let files = [file("a_run_x_001.bvh", 500.0, 9.0, 2.0), file("b_dash_y_001.bvh", 800.0, 3.0, 4.0)];
        let text = format_summary(&summarise(&files));
        let lines: Vec<&str> = text.lines().collect();
        assert_eq!(lines.len(), 5, "{text}");
        assert!(
            lines[1].starts_with("  dash ")
                && lines[2].starts_with("  run ")
                && lines[3].starts_with("  all ")
        );
        assert!(lines[4].starts_with("contact beats paper on mean error in 1 of 2 files"), "{text}");
        // The group lines' columns line up with the file lines'.
        let row = format_file(&files[0]);
        assert_eq!(row.len(), lines[2].len(), "{row}\n{}", lines[2]);
        assert!(row.starts_with("a_run_x_001.bvh"), "{row}");
    }
}
