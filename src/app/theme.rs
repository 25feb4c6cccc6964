//! Every colour the app paints, in the plots and in the 3D view, named by what
//! it shows. Both views take them from here, so a thing looks alike in both:
//! the left foot is one red, the corrected hips one yellow, the original hips
//! one blue, the camera track one magenta.

use crate::body::feet::PerFoot;

/// An sRGB colour with straight (not premultiplied) alpha, each 0–255.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub struct Rgba(pub u8, pub u8, pub u8, pub u8);

impl Rgba {
    /// The same colour with alpha `alpha` (0–255).
    pub const fn with_alpha(self, alpha: u8) -> Rgba {
        Rgba(self.0, self.1, self.2, alpha)
    }

    /// The colour as a CSS string, `rgba(r,g,b,a)` with `a` from 0 to 1, as
    /// canvas fill and stroke styles take it.
    pub fn to_css(self) -> String {
        let Rgba(r, g, b, a) = self;
        // Three decimals tell all 256 alpha levels apart.
        format!("rgba({r},{g},{b},{:.3})", f32::from(a) / 255.0)
    }
}

// --- Both views ------------------------------------------------------------------

/// Each foot: its lines and dots in every plot panel, and the 3D view's
/// marker on the pinned foot. Left red, right green.
pub const FEET: PerFoot<Rgba> = PerFoot { left: Rgba(255, 99, 92, 255), right: Rgba(72, 200, 120, 255) };
/// The corrected hips, yellow: the top view's path and the 3D view's trail.
pub const CORRECTED: Rgba = Rgba(255, 200, 40, 255);
/// The original (uncorrected) hips, blue: the top view's dashed path and the
/// 3D view's trail.
pub const ORIGINAL: Rgba = Rgba(90, 140, 255, 200);
/// A camera-tracked take's hips, magenta: the 3D view's trail, the camera's
/// frustum, and their legend entry.
pub const CAMERA: Rgba = Rgba(236, 96, 226, 255);

// --- The 3D view -----------------------------------------------------------------

/// The corrected skeleton, solid.
pub const CORRECTED_SKELETON: Rgba = Rgba(235, 235, 240, 255);
/// The original skeleton, a translucent lighter blue than [`ORIGINAL`] so the
/// trail under it still shows.
pub const ORIGINAL_SKELETON: Rgba = Rgba(120, 160, 255, 90);
/// The lines of the floor grid.
pub const FLOOR_GRID: Rgba = Rgba(70, 74, 82, 255);
/// The soft shadow each joint of the body casts straight down on the
/// floor, at its darkest (a joint on the floor); fainter and wider the
/// higher the joint, so that the body's height above the floor reads.
pub const FLOOR_SHADOW: Rgba = Rgba(0, 0, 0, 190);
/// Behind the scene.
pub const VIEW_BACKGROUND: Rgba = Rgba(28, 31, 36, 255);

// --- The plots -------------------------------------------------------------------

/// "Before correction" foot series are drawn in their foot's colour at this alpha.
pub const BEFORE_ALPHA: u8 = 115;
/// The time cursor's line.
pub const CURSOR: Rgba = Rgba(255, 255, 255, 220);
/// Titles, legend entries and the cursor read-out.
pub const TEXT: Rgba = Rgba(230, 230, 234, 255);
/// Axis titles, tick labels and legend group labels.
pub const MUTED_TEXT: Rgba = Rgba(154, 160, 170, 255);
/// Grid lines across a plot.
pub const PLOT_GRID: Rgba = Rgba(255, 255, 255, 26);
/// Tick marks under a plot.
pub const TICK: Rgba = Rgba(154, 160, 170, 160);
/// A faint wash behind each plot area, so empty plots still show where they are.
pub const PLOT_BACKGROUND: Rgba = Rgba(255, 255, 255, 9);
/// A dark ring under cursor dots, so they stand out on any line.
pub const HALO: Rgba = Rgba(0, 0, 0, 170);

// The stance strip: each foot keeps its hue, light to dark with the evidence.

/// A foot pinned by the paper's acceleration pass only.
pub const FEET_LIGHT: PerFoot<Rgba> =
    PerFoot { left: Rgba(255, 176, 168, 255), right: Rgba(166, 232, 190, 255) };
/// A foot pinned by both of the paper's passes.
pub const FEET_DARK: PerFoot<Rgba> = PerFoot { left: Rgba(186, 38, 46, 255), right: Rgba(22, 128, 68, 255) };
/// No foot pinned.
pub const NO_FOOT_PINNED: Rgba = Rgba(88, 93, 104, 255);
/// Neither foot on the floor.
pub const FLIGHT: Rgba = Rgba(164, 124, 255, 255);
/// Both feet on the floor (the contact method's double support).
pub const DOUBLE_SUPPORT: Rgba = Rgba(226, 221, 204, 255);

// --- The camera panel ------------------------------------------------------------

/// Behind the camera panel's plots (the top view, the series, the paper's
/// candidates).
pub const CAMERA_PLOT_BACKGROUND: Rgba = Rgba(30, 33, 38, 255);
/// The frame around each series of the camera panel's plot.
pub const CAMERA_PLOT_FRAME: Rgba = Rgba(58, 63, 71, 255);
/// The camera's confidence per frame; a candidate of the lowest energy; the
/// board's corners found over the video.
pub const CONFIDENCE: Rgba = Rgba(74, 222, 128, 255);
/// The track's error against the truth; a candidate of the highest energy.
pub const TRACK_ERROR: Rgba = Rgba(248, 113, 113, 255);
/// A candidate where the body could not be placed (no finite energy).
pub const NO_ENERGY: Rgba = Rgba(85, 85, 85, 255);
/// The floor grid over the video: the corrected hips' yellow, see-through.
pub const VIDEO_FLOOR_GRID: Rgba = CORRECTED.with_alpha(140);
/// The body's outline over the video, and (see-through) the foreground mask.
pub const BODY_OUTLINE: Rgba = Rgba(56, 189, 248, 255);
/// The foreground mask over the video.
pub const FOREGROUND_MASK: Rgba = BODY_OUTLINE.with_alpha(120);
/// Canny's edges over the video.
pub const EDGES: Rgba = Rgba(255, 90, 90, 255);
/// The floor corners clicked on the video.
pub const CLICKED_CORNER: Rgba = Rgba(244, 114, 182, 255);

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn css_strings() {
        assert_eq!(Rgba(255, 99, 92, 255).to_css(), "rgba(255,99,92,1.000)");
        assert_eq!(Rgba(0, 0, 0, 0).to_css(), "rgba(0,0,0,0.000)");
    }
}
