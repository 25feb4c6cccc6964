//! Shared helpers for the integration tests.
#![allow(dead_code)]

use std::path::{Path, PathBuf};

/// `../shared/data` beside the project, or `None` after saying loudly that the
/// tests needing it are skipped (they must never pass silently).
pub fn data_dir() -> Option<PathBuf> {
    let dir = Path::new(env!("CARGO_MANIFEST_DIR")).join("../shared/data");
    if dir.is_dir() {
        Some(dir)
    } else {
        eprintln!(
            "SKIPPED: {} not found; tests on the real recordings did not run",
            dir.display()
        );
        None
    }
}

/// The files in `dir` ending in `.ext`, sorted.
pub fn files_with_extension(dir: &Path, ext: &str) -> Vec<PathBuf> {
    let mut files: Vec<PathBuf> = std::fs::read_dir(dir)
        .map(|entries| {
            entries
                .filter_map(|e| e.ok().map(|e| e.path()))
                .filter(|p| p.extension().is_some_and(|e| e == ext))
                .collect()
        })
        .unwrap_or_default();
    files.sort();
    files
}

/// For each joint of a BVH skeleton, its column-joint in an RMoCap table.
/// Joints match by name; end sites (whose `EndSite<k>` numbers differ when a
/// file lacks some end sites, as `heian_shodan.bvh` lacks the hands') match by
/// their parent: in a table, an end site follows its parent joint.
pub fn table_joint_of_each_bvh_joint(
    skeleton: &embusen::skeleton::Skeleton,
    table_names: &[String],
) -> Vec<Option<usize>> {
    (0..skeleton.joint_count())
        .map(|j| {
            if skeleton.is_end_site[j] {
                let parent = &skeleton.names[skeleton.parents[j]?];
                let p = table_names.iter().position(|n| n == parent)?;
                table_names
                    .get(p + 1)
                    .filter(|n| n.starts_with("EndSite"))
                    .map(|_| p + 1)
            } else {
                table_names.iter().position(|n| *n == skeleton.names[j])
            }
        })
        .collect()
}
