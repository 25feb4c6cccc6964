//! A recording as the tool sees it: whatever file it came from (BVH, BVH plus
//! accelerometer side file, or an RMoCap table), its global joint positions,
//! its rate, and its foot accelerations. The CLI, the tests and the wasm app
//! all go through this one type, so they all compute the same thing.

use glam::DVec3;

use crate::body::feet::{Foot, FootJoints, PerFoot, hips_joint, resolve_feet};
use crate::body::kinematics::forward_kinematics;
use crate::body::skeleton::{Poses, infer_parents};
use crate::error::Error;
use crate::io::bvh::{Bvh, ReadOptions};
use crate::io::table::{Accelerations, Table};
use crate::signal::accel::{kinematic_accel_magnitude_g, magnitudes};

/// Where a recording came from, kept so the result is written in the same form.
#[derive(Clone, Debug)]
pub enum Source {
    Bvh(Bvh),
    Table(Table),
}

/// A loaded recording.
#[derive(Clone, Debug)]
pub struct Recording {
    /// The file name shown to the user.
    pub name: String,
    pub source: Source,
    /// Joint names, in the order of `poses`.
    pub joint_names: Vec<String>,
    /// Parent of each joint (`None` for roots): the file's hierarchy, or for
    /// a table, which stores none, the one inferred from the motion
    /// ([`infer_parents`]).
    pub parents: Vec<Option<usize>>,
    /// Global joint positions, as recorded.
    pub poses: Poses,
    pub fps: f64,
    /// Accelerometer readings, from the table itself or a side file.
    pub accel: Option<Accelerations>,
    pub warnings: Vec<String>,
}

/// Where the foot accelerations that drive the paper method came from.
#[derive(Clone, Debug, PartialEq, Eq, serde::Serialize)]
pub enum AccelSource {
    /// The suit's accelerometers on these two sensors.
    Accelerometer { left: String, right: String },
    /// Second derivative of the foot positions (root translation removed) plus
    /// gravity: used when there is no accelerometer data.
    Kinematic,
}

impl std::fmt::Display for AccelSource {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        match self {
            AccelSource::Accelerometer { left, right } => {
                write!(f, "accelerometers {left}/{right}")
            }
            AccelSource::Kinematic => write!(f, "kinematics (no accelerometer data)"),
        }
    }
}

/// Which joints are the feet: detected from their names unless given.
#[derive(Clone, Debug, Default, PartialEq, Eq)]
pub struct FeetChoice {
    pub left: Option<String>,
    pub right: Option<String>,
}

/// The file name at the end of `path` as the user gave it (after the last
/// `/` or `\`, whichever system it came from).
pub fn base_name(path: &str) -> &str {
    path.rsplit(['/', '\\']).next().unwrap_or(path)
}

/// `base_name(path)` without a `.bvh` ending (in any case); `None` for a
/// name that has none.
pub fn bvh_stem(path: &str) -> Option<&str> {
    let base = base_name(path);
    let n = base.len().checked_sub(4).filter(|&n| base.is_char_boundary(n))?;
    base[n..].eq_ignore_ascii_case(".bvh").then_some(&base[..n])
}

/// True when the bytes look like a BVH file rather than a CSV table.
pub fn looks_like_bvh(bytes: &[u8]) -> bool {
    let start = bytes.iter().position(|b| !b.is_ascii_whitespace()).unwrap_or(bytes.len());
    bytes[start..].len() >= 9 && bytes[start..start + 9].eq_ignore_ascii_case(b"HIERARCHY")
}

impl Recording {
    /// Reads a BVH or an RMoCap table from its bytes (the format is told by the
    /// content, not the name). `fps` is used when the file does not say.
    pub fn parse(bytes: &[u8], name: &str, fps: Option<f64>) -> Result<Recording, Error> {
        if looks_like_bvh(bytes) {
            let bvh = Bvh::parse(bytes, name, &ReadOptions { fps })?;
            Ok(Recording::from_bvh(bvh, name))
        } else {
            let table = Table::parse(bytes, name)?;
            Recording::from_table(table, name, fps)
        }
    }

    pub fn from_bvh(bvh: Bvh, name: &str) -> Recording {
        let poses = forward_kinematics(&bvh.skeleton, &bvh.motion);
        Recording {
            name: name.to_string(),
            joint_names: bvh.skeleton.names.clone(),
            parents: bvh.skeleton.parents.clone(),
            poses,
            fps: bvh.motion.fps(),
            accel: None,
            warnings: bvh.warnings.clone(),
            source: Source::Bvh(bvh),
        }
    }

    pub fn from_table(table: Table, name: &str, fps: Option<f64>) -> Result<Recording, Error> {
        if table.joint_names.is_empty() {
            return Err(Error::whole(name, "the table has no `<Joint>.Dx/.Dy/.Dz` position columns"));
        }
        let mut warnings = table.warnings.clone();
        let fps = match (table.frame_time_s(), fps) {
            (Some(dt), _) => 1.0 / dt,
            (None, Some(fps)) => fps,
            (None, None) => {
                warnings.push(format!(
                    "no usable Time column; assuming {} Hz (set it with --fps)",
                    crate::io::bvh::DEFAULT_FPS
                ));
                crate::io::bvh::DEFAULT_FPS
            }
        };
        let accel = Accelerations::from_table(&table);
        let poses = table.poses();
        Ok(Recording {
            name: name.to_string(),
            joint_names: table.joint_names.clone(),
            parents: infer_parents(&poses),
            poses,
            fps,
            accel: (!accel.sensor_names.is_empty()).then_some(accel),
            warnings,
            source: Source::Table(table),
        })
    }

    /// Attaches an accelerometer side file; its rows must match the frames.
    pub fn attach_accel(&mut self, accel: Accelerations) -> Result<(), Error> {
        if accel.frame_count() != self.frame_count() {
            return Err(Error::whole(
                &accel.file,
                format!(
                    "has {} rows but {} has {} frames; they must be the same recording",
                    accel.frame_count(),
                    self.name,
                    self.frame_count()
                ),
            ));
        }
        self.accel = Some(accel);
        Ok(())
    }

    pub fn frame_count(&self) -> usize {
        self.poses.frame_count()
    }

    pub fn duration_s(&self) -> f64 {
        self.frame_count() as f64 / self.fps
    }

    /// The feet, detected or as chosen.
    pub fn feet(&self, choice: &FeetChoice) -> Result<FootJoints, Error> {
        resolve_feet(&self.joint_names, choice.left.as_deref(), choice.right.as_deref())
            .map_err(|message| Error::whole(&self.name, message))
    }

    /// The hips joint (see [`hips_joint`]), for these feet.
    pub fn hips(&self, feet: FootJoints) -> usize {
        hips_joint(&self.parents, feet)
    }

    /// The feet's accelerometer magnitudes in g, when sensors named like the
    /// foot joints were recorded.
    pub fn foot_accelerometers_g(&self, feet: FootJoints) -> Option<(PerFoot<Vec<f64>>, AccelSource)> {
        let left_name = &self.joint_names[feet.left];
        let right_name = &self.joint_names[feet.right];
        let accel = self.accel.as_ref()?;
        let (l, r) = (accel.sensor(left_name)?, accel.sensor(right_name)?);
        Some((
            PerFoot::new(magnitudes(l), magnitudes(r)),
            AccelSource::Accelerometer { left: left_name.clone(), right: right_name.clone() },
        ))
    }

    /// Acceleration magnitudes of the two feet in g: from the
    /// accelerometers named like the foot joints when there are any, else from
    /// the kinematics.
    pub fn foot_accel_g(&self, feet: FootJoints) -> (PerFoot<Vec<f64>>, AccelSource) {
        if let Some(measured) = self.foot_accelerometers_g(feet) {
            return measured;
        }
        // The hips' own motion is the vendor's translation guess; remove it so
        // the kinematic acceleration reflects the legs only.
        let root = self.poses.trajectory(self.hips(feet));
        let relative = |foot: Foot| -> Vec<DVec3> {
            let joint = feet[foot];
            (0..self.frame_count()).map(|f| self.poses.at(f, joint) - root[f]).collect()
        };
        (
            PerFoot::from_fn(|foot| kinematic_accel_magnitude_g(&relative(foot), self.fps)),
            AccelSource::Kinematic,
        )
    }

    /// The recording with every frame moved by `shift_cm`, in its own format
    /// (BVH text or CSV table text).
    pub fn write_shifted(&self, shift_cm: &[DVec3]) -> String {
        match &self.source {
            Source::Bvh(bvh) => {
                let mut out = bvh.clone();
                out.shift_root(shift_cm);
                out.write()
            }
            Source::Table(table) => table.with_shift(shift_cm).write(),
        }
    }

    /// True when the recording stands along +Z rather than +Y (some Z-up
    /// exporters): in frame 0 the hips sit above the feet mostly along Z.
    /// The app uses it to stand such recordings upright; the translation
    /// methods assume Y up, as the suit's software writes.
    pub fn up_axis_is_z(&self) -> bool {
        let Ok(feet) = self.feet(&FeetChoice::default()) else { return false };
        if self.frame_count() == 0 {
            return false;
        }
        let feet_mid = (self.poses.at(0, feet.left) + self.poses.at(0, feet.right)) * 0.5;
        let up = self.poses.at(0, self.hips(feet)) - feet_mid;
        up.z > up.y.abs() && up.z > up.x.abs()
    }

    /// The file extension of the format it came in.
    pub fn extension(&self) -> &'static str {
        match self.source {
            Source::Bvh(_) => "bvh",
            Source::Table(_) => "csv",
        }
    }
}
