//! The table of `embusen eval` on suit-grade recordings: files named
//! `NAME.suit-TAG.bvh`, a ground-truth `NAME.bvh` passed through an
//! inertial-suit error model (`TAG` is `l<level>-s<seed>`), each scored
//! against its own truth. Beside both methods' figures stands the leg-length
//! oracle (see [`SuitAccuracy`]), the floor a method without the true leg
//! length cannot go below, the contacts oracle (the truth's own contact
//! decisions on the suit's pose: how much error the pose itself carries)
//! and the grounded oracle (the same, with nothing known in the air but
//! what the stances around tell); medians per level and motion type, per
//! level, and over all.

use crate::error::Error;
use crate::eval::summary::{
    FileAccuracy, GroupMedians, MEDIANS_HEADING, by_motion_type, contact_better, format_columns,
    format_file_line, format_groups, format_line, group_medians, is_moving,
};
use crate::eval::{SuitAccuracy, evaluate_suit};
use crate::io::bvh::Bvh;
use crate::io::recording::bvh_stem;
use crate::signal::stats::median;
use crate::translate::Method;
use crate::translate::hachaj::HachajParams;

/// What separates a suit file's truth name from its tag: `NAME.suit-TAG.bvh`.
const SUIT_MARK: &str = ".suit-";

/// The level of a file whose name has no `l<level>` in its tag.
pub const UNKNOWN_LEVEL: &str = "?";

/// How wide the suit table's first column (the file name) is: the longest
/// shared name, `bandai1_dance-short_normal_001.suit-l0.5-s1.bvh`, fits.
const FILE_WIDTH: usize = 48;

/// Both methods' accuracy on one suit-grade file, and the leg-length oracle.
#[derive(Clone, Debug, PartialEq)]
pub struct SuitFileAccuracy {
    /// Both methods against the true motion; `name` is the suit file's.
    pub file: FileAccuracy,
    /// The error model's level (`1`, `0.5`), from the name (see [`suit_level`]).
    pub level: String,
    /// See [`SuitAccuracy::leg_oracle_mean_error_pct`].
    pub leg_oracle_mean_error_pct: f64,
    /// Suit leg length / true leg length.
    pub leg_length_ratio: f64,
    /// See [`SuitAccuracy::contacts_oracle_mean_error_pct`].
    pub contacts_oracle_mean_error_pct: f64,
    /// See [`SuitAccuracy::grounded_oracle_mean_error_pct`].
    pub grounded_oracle_mean_error_pct: f64,
    /// See [`SuitAccuracy::contacts_oracle_path_ratio`].
    pub contacts_oracle_path_ratio: f64,
    /// See [`SuitAccuracy::grounded_oracle_path_ratio`].
    pub grounded_oracle_path_ratio: f64,
}

/// Medians over a group of suit files: both methods' (see
/// [`crate::eval::summary::medians`]), the oracle's mean error (over the moving
/// files, like every percentage) and the leg-length ratio (over all).
#[derive(Clone, Debug, PartialEq)]
pub struct SuitGroupMedians {
    pub methods: GroupMedians,
    pub leg_oracle_mean_error_pct: f64,
    pub leg_length_ratio: f64,
    pub contacts_oracle_mean_error_pct: f64,
    pub grounded_oracle_mean_error_pct: f64,
    /// Over all files, as the methods' path ratios.
    pub contacts_oracle_path_ratio: f64,
    pub grounded_oracle_path_ratio: f64,
}

/// The medians of one level's files.
#[derive(Clone, Debug, PartialEq)]
pub struct LevelSummary {
    pub level: String,
    /// Per motion type, in the types' sorted order.
    pub by_motion_type: Vec<(String, SuitGroupMedians)>,
    pub all: SuitGroupMedians,
    /// Files whose true hips path is at least
    /// [`crate::eval::summary::MOVING_MIN_PATH_CM`].
    pub moving_file_count: usize,
    /// Of those, the files where the contact method's mean error is below
    /// the paper method's.
    pub contact_better_count: usize,
}

/// The summary of a suit evaluation.
#[derive(Clone, Debug, PartialEq)]
pub struct SuitSummary {
    /// Per level, from the highest (the real suit's errors) down; a level
    /// that is no number last.
    pub levels: Vec<LevelSummary>,
    /// Over every file of every level.
    pub all: SuitGroupMedians,
}

/// The truth's name and the tag of a suit file's name:
/// `dir/NAME.suit-TAG.bvh` → (`NAME`, `TAG`); `None` for any other name.
pub fn suit_name_parts(file_name: &str) -> Option<(&str, &str)> {
    let stem = bvh_stem(file_name)?;
    let (truth, tag) = stem.rsplit_once(SUIT_MARK)?;
    (!truth.is_empty() && !tag.is_empty()).then_some((truth, tag))
}

/// The file name of a suit file's truth: `NAME.suit-TAG.bvh` → `NAME.bvh`.
pub fn truth_file_name(suit_file_name: &str) -> Option<String> {
    suit_name_parts(suit_file_name).map(|(truth, _)| format!("{truth}.bvh"))
}

/// The error model's level of a suit file, from the `l<level>` part of its
/// tag (`NAME.suit-l0.5-s2.bvh` → `0.5`); [`UNKNOWN_LEVEL`] when there is none.
pub fn suit_level(file_name: &str) -> String {
    suit_name_parts(file_name)
        .and_then(|(_, tag)| tag.split('-').find_map(|part| part.strip_prefix('l').filter(|l| !l.is_empty())))
        .unwrap_or(UNKNOWN_LEVEL)
        .to_string()
}

/// Evaluates a suit-grade BVH against its true motion (see [`evaluate_suit`])
/// with the paper method and the contact method, each with its defaults.
pub fn evaluate_suit_file(suit: &Bvh, truth: &Bvh, name: &str) -> Result<SuitFileAccuracy, Error> {
    let SuitAccuracy { accuracy: hachaj, .. } =
        evaluate_suit(suit, truth, name, &Method::Hachaj(HachajParams::default()))?;
    let contact = evaluate_suit(suit, truth, name, &Method::default())?;
    Ok(SuitFileAccuracy {
        file: FileAccuracy { name: name.to_string(), hachaj, contact: contact.accuracy },
        level: suit_level(name),
        leg_oracle_mean_error_pct: contact.leg_oracle_mean_error_pct,
        leg_length_ratio: contact.leg_length_ratio,
        contacts_oracle_mean_error_pct: contact.contacts_oracle_mean_error_pct,
        grounded_oracle_mean_error_pct: contact.grounded_oracle_mean_error_pct,
        contacts_oracle_path_ratio: contact.contacts_oracle_path_ratio,
        grounded_oracle_path_ratio: contact.grounded_oracle_path_ratio,
    })
}

fn suit_group_medians(files: &[&SuitFileAccuracy]) -> SuitGroupMedians {
    let methods: Vec<&FileAccuracy> = files.iter().map(|f| &f.file).collect();
    let moving_median = |pct: fn(&SuitFileAccuracy) -> f64| {
        median(&files.iter().filter(|f| is_moving(&f.file.contact)).map(|f| pct(f)).collect::<Vec<_>>())
    };
    let all_median =
        |figure: fn(&SuitFileAccuracy) -> f64| median(&files.iter().map(|f| figure(f)).collect::<Vec<_>>());
    SuitGroupMedians {
        methods: group_medians(&methods),
        leg_oracle_mean_error_pct: moving_median(|f| f.leg_oracle_mean_error_pct),
        leg_length_ratio: all_median(|f| f.leg_length_ratio),
        contacts_oracle_mean_error_pct: moving_median(|f| f.contacts_oracle_mean_error_pct),
        grounded_oracle_mean_error_pct: moving_median(|f| f.grounded_oracle_mean_error_pct),
        contacts_oracle_path_ratio: all_median(|f| f.contacts_oracle_path_ratio),
        grounded_oracle_path_ratio: all_median(|f| f.grounded_oracle_path_ratio),
    }
}

/// The medians of `files` per level and motion type, per level, and over all,
/// and per level how often the contact method beats the paper method.
pub fn summarise_suit(files: &[SuitFileAccuracy]) -> SuitSummary {
    let mut levels: Vec<String> = files.iter().map(|f| f.level.clone()).collect();
    // Highest level first; one that is no number (NaN) after every number.
    let key = |level: &String| level.parse::<f64>().ok().filter(|l| !l.is_nan()).unwrap_or(f64::NEG_INFINITY);
    levels.sort_by(|a, b| key(b).total_cmp(&key(a)).then_with(|| a.cmp(b)));
    levels.dedup();
    let levels = levels
        .into_iter()
        .map(|level| {
            let of_level: Vec<SuitFileAccuracy> =
                files.iter().filter(|f| f.level == level).cloned().collect();
            let by_motion_type = by_motion_type(&of_level, |f| &f.file)
                .into_iter()
                .map(|(t, group)| (t, suit_group_medians(&group)))
                .collect();
            let (moving_file_count, contact_better_count) = contact_better(of_level.iter().map(|f| &f.file));
            LevelSummary {
                all: suit_group_medians(&of_level.iter().collect::<Vec<_>>()),
                level,
                by_motion_type,
                moving_file_count,
                contact_better_count,
            }
        })
        .collect();
    SuitSummary { levels, all: suit_group_medians(&files.iter().collect::<Vec<_>>()) }
}

/// The suit table's title and column header, three lines without a final line end.
pub fn format_suit_header() -> String {
    format!(
        "suit grade: the suit's translation frozen root→hips, re-estimated, compared with the true motion;\n\
         oracle: the true path scaled by the suit/true leg-length ratio, the floor without the true legs;\n\
         contacts: the suit's pose pinned at the foot joint the truth holds still (the truth's own decisions);\n\
         grounded: the same, but in the air the velocity the stances around give, not the truth's\n\
         {} | {:>8} {:>9} {:>10} {:>10} | {:>10} {:>10}",
        format_columns(FILE_WIDTH),
        "oracle %",
        "leg ratio",
        "contacts %",
        "grounded %",
        "contacts ×",
        "grounded ×"
    )
}

/// The oracles' columns, appended to a line of both methods' figures: the
/// leg-length oracle's error and ratio, the contacts and grounded oracles'
/// errors, then their path ratios (their path over the true one).
struct OracleFigures {
    leg_oracle_mean_error_pct: f64,
    leg_length_ratio: f64,
    contacts_oracle_pct: f64,
    grounded_oracle_pct: f64,
    contacts_oracle_path_ratio: f64,
    grounded_oracle_path_ratio: f64,
}

impl OracleFigures {
    fn columns(&self) -> String {
        format!(
            " | {:>8.2} {:>9.3} {:>10.2} {:>10.2} | {:>10.3} {:>10.3}",
            self.leg_oracle_mean_error_pct,
            self.leg_length_ratio,
            self.contacts_oracle_pct,
            self.grounded_oracle_pct,
            self.contacts_oracle_path_ratio,
            self.grounded_oracle_path_ratio
        )
    }
}

/// A suit file's line of the table, without a line end.
pub fn format_suit_file(file: &SuitFileAccuracy) -> String {
    let oracles = OracleFigures {
        leg_oracle_mean_error_pct: file.leg_oracle_mean_error_pct,
        leg_length_ratio: file.leg_length_ratio,
        contacts_oracle_pct: file.contacts_oracle_mean_error_pct,
        grounded_oracle_pct: file.grounded_oracle_mean_error_pct,
        contacts_oracle_path_ratio: file.contacts_oracle_path_ratio,
        grounded_oracle_path_ratio: file.grounded_oracle_path_ratio,
    };
    format_file_line(FILE_WIDTH, &file.file) + &oracles.columns()
}

/// The summary's lines, each ending in a line end: per level a heading, a
/// line per motion type, one for the level's files and the count of files
/// where contact wins; then one line for every file of every level.
pub fn format_suit_summary(summary: &SuitSummary) -> String {
    let group = |label: &str, g: &SuitGroupMedians| {
        let methods = &g.methods;
        let oracles = OracleFigures {
            leg_oracle_mean_error_pct: g.leg_oracle_mean_error_pct,
            leg_length_ratio: g.leg_length_ratio,
            contacts_oracle_pct: g.contacts_oracle_mean_error_pct,
            grounded_oracle_pct: g.grounded_oracle_mean_error_pct,
            contacts_oracle_path_ratio: g.contacts_oracle_path_ratio,
            grounded_oracle_path_ratio: g.grounded_oracle_path_ratio,
        };
        format_line(FILE_WIDTH, label, &methods.file_count.to_string(), &methods.hachaj, &methods.contact)
            + &oracles.columns()
    };
    let mut text = MEDIANS_HEADING.to_string();
    for level in &summary.levels {
        text += &format!("level {}:\n", level.level);
        let counts = (level.moving_file_count, level.contact_better_count);
        text += &format_groups(&level.by_motion_type, &level.all, counts, "  ", group);
    }
    text += &(group("all levels", &summary.all) + "\n");
    text
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::eval::Accuracy;

    #[test]
    fn suit_names_give_their_truth_and_level() {
        let name = "bandai1_walk-right_normal_001.suit-l0.5-s2.bvh";
        assert_eq!(suit_name_parts(name), Some(("bandai1_walk-right_normal_001", "l0.5-s2")));
        assert_eq!(
            truth_file_name(&format!("../shared/data/suit/{name}")).unwrap(),
            "bandai1_walk-right_normal_001.bvh"
        );
        assert_eq!(suit_level(name), "0.5");
        assert_eq!(suit_level("a_kick_x_001.suit-l1-s1.BVH"), "1");
        assert_eq!(suit_level("a.suit-s3.bvh"), UNKNOWN_LEVEL);
        for not_suit in ["bandai1_walk_active_001.bvh", "x.suit-.bvh", ".suit-l1.bvh", "x.suit-l1.csv", "bvh"]
        {
            assert_eq!(suit_name_parts(not_suit), None, "{not_suit}");
        }
    }

    fn accuracy(true_path_cm: f64, mean_error_pct: f64) -> Accuracy {
        Accuracy {
            true_path_cm,
            mean_error_pct,
            final_error_pct: 2.0 * mean_error_pct,
            path_ratio: 1.0,
            skating_cm_per_s: mean_error_pct,
            truth_skating_cm_per_s: 1.0,
            vertical_error_cm: 1.0,
        }
    }

    fn file(
        name: &str,
        true_path_cm: f64,
        paper_pct: f64,
        contact_pct: f64,
        oracle_pct: f64,
    ) -> SuitFileAccuracy {
        SuitFileAccuracy {
            file: FileAccuracy {
                name: name.to_string(),
                hachaj: accuracy(true_path_cm, paper_pct),
                contact: accuracy(true_path_cm, contact_pct),
            },
            level: suit_level(name),
            leg_oracle_mean_error_pct: oracle_pct,
            leg_length_ratio: 1.0 + oracle_pct / 100.0,
            contacts_oracle_mean_error_pct: 2.0 * oracle_pct,
            grounded_oracle_mean_error_pct: 3.0 * oracle_pct,
            contacts_oracle_path_ratio: 1.0 + oracle_pct / 50.0,
            grounded_oracle_path_ratio: 1.0 + oracle_pct / 25.0,
        }
    }

    /// Made-up files: three levels (`?` has none in its name), in level 1 a
    /// bow that stays in place and a run that contact loses.
    fn rows() -> [SuitFileAccuracy; 6] {
        [
            file("bandai1_walk_active_001.suit-l0.5-s1.bvh", 400.0, 10.0, 2.0, 1.0),
            file("a_walk_x_001.suit-l1-s1.bvh", 400.0, 20.0, 4.0, 2.0),
            file("a_walk_x_001.suit-l1-s2.bvh", 400.0, 30.0, 6.0, 3.0),
            file("a_bow_x_001.suit-l1-s1.bvh", 20.0, 50.0, 90.0, 40.0),
            file("a_run_x_001.suit-l1-s1.bvh", 900.0, 5.0, 8.0, 1.5),
            file("c_dash_y_001.bvh", 800.0, 3.0, 4.0, 1.0),
        ]
    }

    #[test]
    fn medians_go_per_level_and_motion_type() {
        let s = summarise_suit(&rows());
        let levels: Vec<&str> = s.levels.iter().map(|l| l.level.as_str()).collect();
        assert_eq!(levels, ["1", "0.5", UNKNOWN_LEVEL]);
        let one = &s.levels[0];
        let types: Vec<&str> = one.by_motion_type.iter().map(|(t, _)| t.as_str()).collect();
        assert_eq!(types, ["bow", "run", "walk"]);
        let (_, walk) = &one.by_motion_type[2];
        assert_eq!(walk.methods.file_count, 2);
        assert_eq!(walk.methods.contact.mean_error_pct, median(&[4.0, 6.0]));
        assert_eq!(walk.leg_oracle_mean_error_pct, median(&[2.0, 3.0]));
        assert_eq!(walk.grounded_oracle_mean_error_pct, median(&[6.0, 9.0]));
        // The bow stays in place: no percentage, but its leg ratio counts.
        let (_, bow) = &one.by_motion_type[0];
        assert!(bow.leg_oracle_mean_error_pct.is_nan() && bow.methods.hachaj.mean_error_pct.is_nan());
        assert_eq!(bow.leg_length_ratio, 1.4);
        assert_eq!(one.all.methods.file_count, 4);
        assert_eq!(one.all.leg_oracle_mean_error_pct, median(&[2.0, 3.0, 1.5]));
        assert_eq!(one.all.leg_length_ratio, median(&[1.02, 1.03, 1.4, 1.015]));
        // The oracles' path ratios over every file, moving or not.
        assert_eq!(one.all.contacts_oracle_path_ratio, median(&[1.04, 1.06, 1.8, 1.03]));
        assert_eq!(one.all.grounded_oracle_path_ratio, median(&[1.08, 1.12, 2.6, 1.06]));
        assert_eq!((one.contact_better_count, one.moving_file_count), (2, 3));
        assert_eq!((s.levels[1].contact_better_count, s.levels[1].moving_file_count), (1, 1));
        assert_eq!((s.levels[2].contact_better_count, s.levels[2].moving_file_count), (0, 1));
        assert_eq!(s.all.methods.file_count, 6);
        assert_eq!(s.all.methods.hachaj.mean_error_pct, median(&[10.0, 20.0, 30.0, 5.0, 3.0]));
    }

    #[test]
    fn the_summary_lines_up_with_the_files() {
        let files = rows();
        let text = format_suit_summary(&summarise_suit(&files));
        let lines: Vec<&str> = text.lines().collect();
        // Heading; per level its name, its types, all, the count; all levels.
        assert_eq!(lines.len(), 1 + (3 + 3) + (1 + 3) + (1 + 3) + 1, "{text}");
        assert_eq!(lines[1], "level 1:");
        assert!(lines[2].starts_with("  bow ") && lines[5].starts_with("  all "), "{text}");
        assert!(lines[6].starts_with("  contact beats paper on mean error in 2 of 3 files"), "{text}");
        assert_eq!(lines[7], "level 0.5:");
        assert_eq!(lines[11], "level ?:");
        assert!(lines[13].starts_with("  all ") && lines[15].starts_with("all levels "), "{text}");
        let row = format_suit_file(&files[0]);
        assert_eq!(row.chars().count(), lines[8].chars().count(), "{row}\n{}", lines[8]);
        let header = format_suit_header();
        let columns = header.lines().last().unwrap();
        assert_eq!(row.chars().count(), columns.chars().count(), "{row}\n{columns}");
    }
}
