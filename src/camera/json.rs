//! `camera.json`: a [`Camera`] as a file, the format of the shared data, so
//! that a calibration is made once and reused across sessions, and so that
//! OpenCV users can read ours and we theirs.
//!
//! ```text
//! {
//!   "image_size": {"width": 640, "height": 480},
//!   "K": [[fx, 0, cx], [0, fy, cy], [0, 0, 1]],                  px
//!   "dist": {"k1": …, "k2": …, "p1": …, "p2": …, "k3": …},
//!   "dist_opencv": [k1, k2, p1, p2, k3],                          the same, as OpenCV's list
//!   "rvec": [3], "tvec_cm": [3],                                  world → camera (Rodrigues, cm)
//!   "camera_from_world": [[R, t], [0, 0, 0, 1]],                 4×4, the same pose
//!   "camera_center_world_cm": [3],                               −Rᵀt
//!   "conventions": "…"
//! }
//! ```
//!
//! Reading takes what a file from elsewhere may hold: unknown fields are
//! ignored; the lens may be `dist` or `dist_opencv` (4 coefficients, or more
//! whose extra ones are zero); the pose may be `camera_from_world` or
//! `rvec` + `tvec_cm`. What is redundant must agree (else it is an error
//! that says which fields disagree and by how much: a hand-edited file whose
//! two poses differ has no right answer). Writing writes every field, so
//! both kinds of reader find theirs, in one fixed layout with the shortest
//! decimal that reads back to the same `f64` (ryu), so the CLI and the
//! browser write the same bytes and a file read and written again is the
//! same camera bit for bit.

use glam::{DAffine3, DMat3, DVec3};
use serde::Deserialize;

use super::rotation::{angle_between, rodrigues_from_rotation, rotation_from_rodrigues};
use super::{Camera, Distortion, ImageSize, Intrinsics};
use crate::error::{Error, line_column_of};

/// How far (rad) `rvec` may turn from `camera_from_world`'s rotation, and how
/// far (cm) `tvec_cm` and `camera_center_world_cm` may move from theirs, and
/// still be the same pose: well above rounding to 6 decimals, far below any
/// calibration's precision.
const SAME_ANGLE_RAD: f64 = 1e-6;
const SAME_POSITION_CM: f64 = 1e-3;
/// How far `camera_from_world`'s 3×3 part may be from a rotation
/// (`max |RᵀR − I|`).
const ROTATION_TOLERANCE: f64 = 1e-6;
/// How far `dist` and `dist_opencv` may differ, per coefficient.
const SAME_DISTORTION: f64 = 1e-6;

/// What [`Camera::to_json`] writes as `conventions`: the folder's
/// conventions, for a reader who has only the file.
pub const CONVENTIONS: &str = "OpenCV pinhole model: x_cam = R x_world + t (rvec = Rodrigues(R), \
tvec_cm = t, cm); camera axes x right, y down, z forward (optical axis); pixel (0,0) is the centre \
of the top-left pixel; distortion (k1,k2,p1,p2,k3) as in cv2.projectPoints. World: the BVH world, \
Y up, centimetres, floor at y=0. camera_from_world = [[R, t],[0,0,0,1]] maps homogeneous world cm \
to camera cm; camera_center_world_cm = -R^T t.";

#[derive(Deserialize)]
struct SizeField {
    width: u32,
    height: u32,
}

#[derive(Deserialize)]
struct DistField {
    k1: f64,
    k2: f64,
    p1: f64,
    p2: f64,
    k3: f64,
}

/// The file as it is read: what may be absent is an `Option`, checked after.
#[derive(Deserialize)]
#[serde(rename = "camera")]
struct CameraFile {
    image_size: SizeField,
    #[serde(rename = "K")]
    k: [[f64; 3]; 3],
    dist: Option<DistField>,
    dist_opencv: Option<Vec<f64>>,
    rvec: Option<[f64; 3]>,
    tvec_cm: Option<[f64; 3]>,
    camera_from_world: Option<[[f64; 4]; 4]>,
    camera_center_world_cm: Option<[f64; 3]>,
    // Read so that a non-string is named, not otherwise used.
    #[serde(rename = "conventions")]
    _conventions: Option<String>,
}

impl Camera {
    /// The camera in the `camera.json` text `text`; `file_name` is what the
    /// error names. Errors say the field and its line:column: a syntax
    /// error, a missing or mistyped field, a `K` that is not a pinhole's
    /// (non-zero skew or bottom row, focal lengths not positive), an empty
    /// image, a pose that is not a rotation, redundant fields that disagree.
    pub fn from_json(text: &str, file_name: &str) -> Result<Camera, Error> {
        let file = parse(text, file_name)?;
        let at = |key: &str, message: String| {
            let (line, column) = key_line_column(text, key);
            Error::at(file_name, line, column, message)
        };
        let at_end = |message: String| {
            let (line, column) = line_column_of(text.as_bytes(), text.trim_end().len().saturating_sub(1));
            Error::at(file_name, line, column, message)
        };

        let SizeField { width, height } = file.image_size;
        if width == 0 || height == 0 {
            return Err(at("image_size", format!("image_size must be positive, not {width}×{height} px")));
        }

        let intrinsics = intrinsics_of(&file.k).map_err(|m| at("K", m))?;

        let distortion = match (&file.dist, &file.dist_opencv) {
            (None, None) => return Err(at_end("missing field `dist` (or `dist_opencv`): the lens".into())),
            (Some(d), opencv) => {
                let dist = Distortion { k1: d.k1, k2: d.k2, p1: d.p1, p2: d.p2, k3: d.k3 };
                if let Some(list) = opencv {
                    let other = distortion_of_list(list).map_err(|m| at("dist_opencv", m))?;
                    let names = ["k1", "k2", "p1", "p2", "k3"];
                    let (a, b) = (distortion_list(&dist), distortion_list(&other));
                    if let Some(i) = (0..5).find(|&i| (a[i] - b[i]).abs() > SAME_DISTORTION) {
                        return Err(at(
                            "dist_opencv",
                            format!(
                                "dist and dist_opencv disagree ({} = {} vs {}); give one, or both the same",
                                names[i], a[i], b[i]
                            ),
                        ));
                    }
                }
                dist
            }
            (None, Some(list)) => distortion_of_list(list).map_err(|m| at("dist_opencv", m))?,
        };

        let from_rvec = match (file.rvec, file.tvec_cm) {
            (Some(r), Some(t)) => Some(DAffine3::from_mat3_translation(
                rotation_from_rodrigues(DVec3::from_array(r)),
                DVec3::from_array(t),
            )),
            (Some(_), None) => {
                return Err(at("rvec", "`rvec` without `tvec_cm`: give both, or `camera_from_world`".into()));
            }
            (None, Some(_)) => {
                return Err(at(
                    "tvec_cm",
                    "`tvec_cm` without `rvec`: give both, or `camera_from_world`".into(),
                ));
            }
            (None, None) => None,
        };
        let from_matrix = match &file.camera_from_world {
            Some(m) => Some(pose_of_matrix(m).map_err(|m| at("camera_from_world", m))?),
            None => None,
        };
        // The matrix when there is one: it is what `Camera` keeps, so a
        // file we wrote reads back bit for bit.
        let camera_from_world = match (from_matrix, from_rvec) {
            (Some(matrix), Some(rvec)) => {
                let angle_rad = angle_between(matrix.matrix3, rvec.matrix3);
                let moved_cm = (matrix.translation - rvec.translation).length();
                if !(angle_rad <= SAME_ANGLE_RAD && moved_cm <= SAME_POSITION_CM) {
                    return Err(at(
                        "rvec",
                        format!(
                            "rvec/tvec_cm and camera_from_world disagree by {:.3e}° and {:.3e} cm; \
                             give one of them, or both the same",
                            angle_rad.to_degrees(),
                            moved_cm
                        ),
                    ));
                }
                matrix
            }
            (Some(pose), None) | (None, Some(pose)) => pose,
            (None, None) => {
                return Err(at_end(
                    "missing the pose: give `camera_from_world`, or `rvec` and `tvec_cm`".into(),
                ));
            }
        };

        let camera = Camera {
            image_size: ImageSize { width_px: width, height_px: height },
            intrinsics,
            distortion,
            camera_from_world,
        };
        if let Some(centre) = file.camera_center_world_cm {
            let ours = camera.center_in_world();
            let moved_cm = (DVec3::from_array(centre) - ours).length();
            if moved_cm.is_nan() || moved_cm > SAME_POSITION_CM {
                return Err(at(
                    "camera_center_world_cm",
                    format!(
                        "camera_center_world_cm is {moved_cm:.3e} cm from the pose's centre \
                         ({:.4}, {:.4}, {:.4}); fix it or leave it out",
                        ours.x, ours.y, ours.z
                    ),
                ));
            }
        }
        Ok(camera)
    }

    /// The camera as `camera.json` text: every field of the format, in a
    /// fixed layout (two-space indent, a matrix row per line), each number
    /// the shortest decimal that reads back to the same `f64`. The same
    /// camera gives the same bytes on every target. A non-finite number
    /// (which no reader of ours produces) is written `null`, so that the
    /// file fails to load rather than load wrong.
    pub fn to_json(&self) -> String {
        let Intrinsics { fx_px, fy_px, cx_px, cy_px } = self.intrinsics;
        let rotation = self.camera_from_world.matrix3;
        let t = self.camera_from_world.translation;
        let rows = |i: usize| rotation.row(i).extend(t[i]).to_array();
        let dist = distortion_list(&self.distortion);
        let mut out = String::from("{\n");
        let size = self.image_size;
        out +=
            &format!("  \"image_size\": {{\"width\": {}, \"height\": {}}},\n", size.width_px, size.height_px);
        out += &format!(
            "  \"K\": [\n    {},\n    {},\n    {}\n  ],\n",
            list(&[fx_px, 0.0, cx_px]),
            list(&[0.0, fy_px, cy_px]),
            list(&[0.0, 0.0, 1.0])
        );
        let d = &self.distortion;
        out += &format!(
            "  \"dist\": {{\"k1\": {}, \"k2\": {}, \"p1\": {}, \"p2\": {}, \"k3\": {}}},\n",
            number(d.k1),
            number(d.k2),
            number(d.p1),
            number(d.p2),
            number(d.k3)
        );
        out += &format!("  \"dist_opencv\": {},\n", list(&dist));
        out += &format!("  \"rvec\": {},\n", list(&rodrigues_from_rotation(rotation).to_array()));
        out += &format!("  \"tvec_cm\": {},\n", list(&t.to_array()));
        out += &format!(
            "  \"camera_from_world\": [\n    {},\n    {},\n    {},\n    {}\n  ],\n",
            list(&rows(0)),
            list(&rows(1)),
            list(&rows(2)),
            list(&[0.0, 0.0, 0.0, 1.0])
        );
        out += &format!("  \"camera_center_world_cm\": {},\n", list(&self.center_in_world().to_array()));
        // A fixed ASCII text: JSON-escaping it is quoting it.
        out += &format!(
            "  \"conventions\": \"{}\"\n}}\n",
            CONVENTIONS.replace('\\', "\\\\").replace('"', "\\\"")
        );
        out
    }
}

/// The file's fields, or the error serde_json found, with the field's path
/// (`K[0][1]`, `image_size: missing field `width``) and its line:column.
fn parse(text: &str, file_name: &str) -> Result<CameraFile, Error> {
    let mut deserializer = serde_json::Deserializer::from_str(text);
    let error = match serde_path_to_error::deserialize::<_, CameraFile>(&mut deserializer) {
        Ok(file) => match deserializer.end() {
            Ok(()) => return Ok(file),
            Err(e) => return Err(json_error(file_name, &e, None)),
        },
        Err(e) => e,
    };
    let path = error.path().to_string();
    Err(json_error(file_name, error.inner(), (path != ".").then_some(path)))
}

fn json_error(file_name: &str, error: &serde_json::Error, path: Option<String>) -> Error {
    let (line, column) = (error.line(), error.column());
    // serde_json's text ends with " at line L column C"; we say it first.
    let full = error.to_string();
    let message = full.strip_suffix(&format!(" at line {line} column {column}")).unwrap_or(&full);
    let message = match path {
        Some(path) => format!("{path}: {message}"),
        None => message.to_string(),
    };
    Error::at(file_name, line.max(1), column.max(1), message)
}

/// The intrinsics of `K` (rows), or what is wrong with it.
fn intrinsics_of(k: &[[f64; 3]; 3]) -> Result<Intrinsics, String> {
    let [[fx, skew, cx], [k10, fy, cy], [k20, k21, k22]] = *k;
    if !(fx > 0.0 && fy > 0.0) {
        return Err(format!("K's focal lengths K[0][0] and K[1][1] must be positive, not {fx} and {fy}"));
    }
    // Exact zeros in files from OpenCV; a hair of rounding is tolerated.
    let zero = 1e-9 * fx.max(fy);
    for (value, name) in [(skew, "K[0][1]"), (k10, "K[1][0]"), (k20, "K[2][0]"), (k21, "K[2][1]")] {
        if value.abs() > zero {
            return Err(format!("{name} must be 0 in a pinhole's K, not {value}"));
        }
    }
    if (k22 - 1.0).abs() > 1e-12 {
        return Err(format!("K[2][2] must be 1, not {k22}"));
    }
    Ok(Intrinsics { fx_px: fx, fy_px: fy, cx_px: cx, cy_px: cy })
}

/// OpenCV's list: `k1 k2 p1 p2` and optionally `k3`; a longer list (the
/// rational or thin-prism models) only when its extra terms are zero,
/// since this camera has no such terms.
fn distortion_of_list(list: &[f64]) -> Result<Distortion, String> {
    let coefficient = |i: usize| list.get(i).copied().unwrap_or(0.0);
    if list.len() < 4 {
        return Err(format!("dist_opencv must list at least k1, k2, p1, p2, not {} numbers", list.len()));
    }
    if let Some(i) = (5..list.len()).find(|&i| list[i] != 0.0) {
        return Err(format!(
            "dist_opencv[{i}] is {}: this camera model has k1, k2, p1, p2, k3 only",
            list[i]
        ));
    }
    Ok(Distortion {
        k1: coefficient(0),
        k2: coefficient(1),
        p1: coefficient(2),
        p2: coefficient(3),
        k3: coefficient(4),
    })
}

fn distortion_list(d: &Distortion) -> [f64; 5] {
    [d.k1, d.k2, d.p1, d.p2, d.k3]
}

/// The pose of a 4×4 `camera_from_world` (rows), or what is wrong with it.
fn pose_of_matrix(m: &[[f64; 4]; 4]) -> Result<DAffine3, String> {
    if m[3] != [0.0, 0.0, 0.0, 1.0] {
        return Err(format!("camera_from_world's last row must be [0, 0, 0, 1], not {:?}", m[3]));
    }
    let rotation = DMat3::from_cols_array_2d(&[
        [m[0][0], m[1][0], m[2][0]],
        [m[0][1], m[1][1], m[2][1]],
        [m[0][2], m[1][2], m[2][2]],
    ]);
    let off = (rotation.transpose() * rotation - DMat3::IDENTITY)
        .to_cols_array()
        .iter()
        .fold(0.0f64, |worst, d| worst.max(d.abs()));
    if off.is_nan() || off > ROTATION_TOLERANCE {
        return Err(format!(
            "camera_from_world's 3×3 part is not a rotation (RᵀR is {off:.1e} off the identity)"
        ));
    }
    if rotation.determinant() < 0.0 {
        return Err("camera_from_world's 3×3 part is a reflection (determinant −1), not a rotation".into());
    }
    Ok(DAffine3::from_mat3_translation(rotation, DVec3::new(m[0][3], m[1][3], m[2][3])))
}

/// The line:column of the top-level key `"key"` in the JSON `text` (which
/// serde_json has already accepted), or 1:1 when it is not there: the place
/// an error about that field's value points at.
fn key_line_column(text: &str, key: &str) -> (usize, usize) {
    let bytes = text.as_bytes();
    let mut depth = 0usize;
    let mut i = 0;
    while i < bytes.len() {
        match bytes[i] {
            b'{' | b'[' => depth += 1,
            b'}' | b']' => depth = depth.saturating_sub(1),
            b'"' => {
                let start = i;
                i += 1;
                while i < bytes.len() && bytes[i] != b'"' {
                    i += if bytes[i] == b'\\' { 2 } else { 1 };
                }
                let after = text.get(i + 1..).unwrap_or("");
                let is_key = after.trim_start_matches([' ', '\t', '\r', '\n']).starts_with(':');
                if depth == 1 && is_key && text.get(start + 1..i) == Some(key) {
                    return line_column_of(bytes, start);
                }
            }
            _ => {}
        }
        i += 1;
    }
    (1, 1)
}

/// `values` as a JSON list on one line.
fn list(values: &[f64]) -> String {
    let items: Vec<String> = values.iter().map(|&v| number(v)).collect();
    format!("[{}]", items.join(", "))
}

/// The shortest decimal that reads back to `value` (ryu), `null` when it is
/// not finite.
fn number(value: f64) -> String {
    if value.is_finite() { ryu::Buffer::new().format_finite(value).to_string() } else { "null".into() }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn camera() -> Camera {
        Camera {
            image_size: ImageSize { width_px: 1920, height_px: 1080 },
            intrinsics: Intrinsics { fx_px: 1400.25, fy_px: 1401.0, cx_px: 959.5, cy_px: 539.5 },
            distortion: Distortion { k1: -0.1, k2: 0.02, p1: 1e-4, p2: -2e-4, k3: 0.0 },
            camera_from_world: DAffine3::from_mat3_translation(
                rotation_from_rodrigues(DVec3::new(2.2, 0.3, -0.1)),
                DVec3::new(10.0, 120.5, 480.0),
            ),
        }
    }

    #[test]
    fn written_then_read_is_the_same_camera_and_the_same_bytes() {
        let text = camera().to_json();
        let back = Camera::from_json(&text, "c.json").unwrap();
        assert_eq!(back, camera());
        assert_eq!(back.to_json(), text);
    }

    #[test]
    fn errors_name_the_field_and_its_place() {
        let text = camera().to_json();
        let skewed = text.replacen("[1400.25, 0.0,", "[1400.25, 0.5,", 1);
        let e = Camera::from_json(&skewed, "c.json").unwrap_err();
        assert_eq!(e.line_column, Some((3, 3)), "{e}");
        assert!(e.message.contains("K[0][1]"), "{e}");

        let typo = text.replacen("\"height\": 1080", "\"height\": \"1080\"", 1);
        let e = Camera::from_json(&typo, "c.json").unwrap_err();
        assert!(e.to_string().starts_with("c.json:2:"), "{e}");
        assert!(e.message.starts_with("image_size.height: invalid type"), "{e}");

        let moved = text.replacen("\"tvec_cm\": [10.0", "\"tvec_cm\": [11.0", 1);
        let e = Camera::from_json(&moved, "c.json").unwrap_err();
        assert!(e.message.contains("disagree"), "{e}");

        let e = Camera::from_json("{\"K\": [[1, 0, 0], [0, 1, 0], [0, 0, 1]]}", "c.json").unwrap_err();
        assert_eq!(e.to_string(), "c.json:1:40: missing field `image_size`");
        let e = Camera::from_json("", "c.json").unwrap_err();
        assert_eq!(e.line_column, Some((1, 1)), "{e}");
    }

    #[test]
    fn a_key_is_found_at_the_top_level_only() {
        let text = "{\"a\": {\"K\": 1}, \"s\": \"\\\"K\", \"K\" : 2}";
        assert_eq!(key_line_column(text, "K"), (1, 29));
    }
}
