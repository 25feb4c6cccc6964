//! Shared helpers for the integration tests.
#![allow(dead_code)]

pub mod filmed;
pub mod image_scene;
#[cfg(not(target_arch = "wasm32"))]
pub mod optical;

use std::io::Write;
use std::path::{Path, PathBuf};

/// A directory of one test's own under the system's temporary directory
/// (named after the process and `name`, so parallel tests and runs do not
/// meet), emptied when made and removed when the test ends, but kept when
/// it fails, to look at. Derefs to its path.
#[cfg(not(target_arch = "wasm32"))]
pub struct Scratch(PathBuf);

#[cfg(not(target_arch = "wasm32"))]
impl Scratch {
    pub fn new(name: &str) -> Scratch {
        let dir = std::env::temp_dir().join(format!("embusen-test-{}-{name}", std::process::id()));
        let _ = std::fs::remove_dir_all(&dir);
        std::fs::create_dir_all(&dir).expect("a scratch directory");
        Scratch(dir)
    }
}

#[cfg(not(target_arch = "wasm32"))]
impl std::ops::Deref for Scratch {
    type Target = Path;
    fn deref(&self) -> &Path {
        &self.0
    }
}

#[cfg(not(target_arch = "wasm32"))]
impl Drop for Scratch {
    fn drop(&mut self) {
        if !std::thread::panicking() {
            let _ = std::fs::remove_dir_all(&self.0);
        }
    }
}

/// `../shared/data` beside the project, or `None` after printing
/// `SKIPPED: <path> not found; <test> did not run` to stderr, `<test>` being
/// the name of the calling test (libtest names each test's thread after it).
///
/// Panics instead when `CI=true`: CI runs with the data beside the clone, so
/// a missing folder there is a broken setup, not a reason to pass.
pub fn data_dir() -> Option<PathBuf> {
    let dir = Path::new(env!("CARGO_MANIFEST_DIR")).join("../shared/data");
    if dir.is_dir() {
        return Some(dir);
    }
    let thread = std::thread::current();
    let test = thread.name().unwrap_or("this test");
    if std::env::var("CI").is_ok_and(|ci| ci == "true") {
        panic!(
            "{} not found: CI=true needs the shared data beside the clone; {test} cannot run",
            dir.display()
        );
    }
    // Straight to the process's stderr: libtest captures `eprintln!` of a
    // passing test, which would hide the skip.
    let _ = writeln!(std::io::stderr(), "SKIPPED: {} not found; {test} did not run", dir.display());
    None
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
    skeleton: &embusen::body::skeleton::Skeleton,
    table_names: &[String],
) -> Vec<Option<usize>> {
    (0..skeleton.joint_count())
        .map(|j| {
            if skeleton.is_end_site[j] {
                let parent = &skeleton.names[skeleton.parents[j]?];
                let p = table_names.iter().position(|n| n == parent)?;
                table_names.get(p + 1).filter(|n| n.starts_with("EndSite")).map(|_| p + 1)
            } else {
                table_names.iter().position(|n| *n == skeleton.names[j])
            }
        })
        .collect()
}

/// Opens a shared recording (path relative to the data folder) as the CLI does.
pub fn open(dir: &Path, relative: &str) -> embusen::io::recording::Recording {
    let path = dir.join(relative);
    let bytes = std::fs::read(&path).unwrap_or_else(|e| panic!("{}: {e}", path.display()));
    embusen::io::recording::Recording::parse(&bytes, relative, None).unwrap_or_else(|e| panic!("{e}"))
}

/// Opens a shared accelerometer side file.
pub fn open_accel(dir: &Path, relative: &str) -> embusen::io::table::Accelerations {
    let path = dir.join(relative);
    let bytes = std::fs::read(&path).unwrap_or_else(|e| panic!("{}: {e}", path.display()));
    embusen::io::table::Accelerations::parse(&bytes, relative).unwrap_or_else(|e| panic!("{e}"))
}

/// Opens a shared RMoCap table.
pub fn open_table(dir: &Path, relative: &str) -> embusen::io::table::Table {
    let path = dir.join(relative);
    let bytes = std::fs::read(&path).unwrap_or_else(|e| panic!("{}: {e}", path.display()));
    embusen::io::table::Table::parse(&bytes, relative).unwrap_or_else(|e| panic!("{e}"))
}

/// Largest per-axis difference (cm) between the forward kinematics of a BVH
/// and the global positions of an RMoCap table, over every joint of the BVH.
pub fn max_fk_difference_cm(bvh: &embusen::io::bvh::Bvh, table: &embusen::io::table::Table) -> f64 {
    let poses = embusen::body::kinematics::forward_kinematics(&bvh.skeleton, &bvh.motion);
    let expected = table.poses();
    assert_eq!(poses.frame_count(), expected.frame_count());
    let matches = table_joint_of_each_bvh_joint(&bvh.skeleton, &table.joint_names);
    let mut max_diff: f64 = 0.0;
    for (j, table_joint) in matches.iter().enumerate() {
        let table_joint =
            table_joint.unwrap_or_else(|| panic!("the table has no joint {}", bvh.skeleton.names[j]));
        for f in 0..poses.frame_count() {
            max_diff = max_diff.max((poses.at(f, j) - expected.at(f, table_joint)).abs().max_element());
        }
    }
    max_diff
}
