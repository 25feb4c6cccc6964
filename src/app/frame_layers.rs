//! What the page lays over a video frame to show what the tracker sees in
//! it: the foreground mask, Canny's edges, or the distance to the nearest
//! edge — the stages of `image::pipeline`, made from the frame's luma plane
//! exactly as the tracker makes them, painted as RGBA pictures of the
//! frame's size (row by row from the top, straight alpha).

use crate::app::theme;
use crate::app::theme::Rgba;
use crate::error::Error;
use crate::image::GreyImage;
use crate::image::pipeline::{Features, PipelineParams, features};
use crate::io::image_file::png_to_grey;

/// One stage of the pipeline, as a picture.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Layer {
    /// The foreground (the difference from the background above its
    /// threshold, opened and closed), tinted; the rest clear.
    Mask,
    /// Canny's edges, opaque; the rest clear.
    Edges,
    /// The distance to the nearest edge, white on an edge fading to black
    /// at [`DISTANCE_SHOWN_PX`], nearly opaque: what the paper's energy sums.
    Distance,
}

/// The distance (px) at which the distance layer turns black: about a
/// limb's width at a few metres, where an edge stops explaining a pixel.
pub const DISTANCE_SHOWN_PX: f32 = 32.0;

const MASK_RGBA: [u8; 4] = rgba(theme::FOREGROUND_MASK);
const EDGE_RGBA: [u8; 4] = rgba(theme::EDGES);

const fn rgba(c: Rgba) -> [u8; 4] {
    [c.0, c.1, c.2, c.3]
}
const DISTANCE_ALPHA: u8 = 220;

/// A take's background, ready to make the layers of its frames.
#[derive(Clone, Debug)]
pub struct FrameLayers {
    background: GreyImage,
    pipeline: PipelineParams,
}

impl FrameLayers {
    /// From the background still's PNG bytes (the error names the file).
    pub fn new(background_name: &str, background_png: &[u8]) -> Result<FrameLayers, Error> {
        let background = png_to_grey(background_png, background_name)?;
        Ok(FrameLayers { background, pipeline: PipelineParams::default() })
    }

    /// The pipeline's stages of a frame from its luma plane (see
    /// [`GreyImage::from_luma`]); an error for `label` when its size is not
    /// the background's.
    pub fn features(
        &self,
        luma: &[u8],
        stride: usize,
        full_range: bool,
        label: &str,
    ) -> Result<Features, Error> {
        let (w, h) = (self.background.width_px, self.background.height_px);
        let frame = GreyImage::from_luma(w, h, luma, stride, full_range, label)?;
        features(&frame, &self.background, &self.pipeline, label)
    }
}

/// `layer` of `features` as RGBA pixels.
pub fn layer_rgba(features: &Features, layer: Layer) -> Vec<u8> {
    let paint = |on: &[bool], rgba: [u8; 4]| on.iter().flat_map(|&o| if o { rgba } else { [0; 4] }).collect();
    match layer {
        Layer::Mask => paint(&features.foreground.on, MASK_RGBA),
        Layer::Edges => paint(&features.edges.on, EDGE_RGBA),
        Layer::Distance => features
            .edge_distance
            .distance_px
            .iter()
            .flat_map(|&d| {
                // Infinity (no edge at all) is black too.
                let near = 1.0 - d.min(DISTANCE_SHOWN_PX) / DISTANCE_SHOWN_PX;
                let v = (255.0 * near).round() as u8;
                [v, v, v, DISTANCE_ALPHA]
            })
            .collect(),
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::image::{DistanceImage, Mask};

    #[test]
    fn each_layer_paints_its_stage() {
        let mask = |on: Vec<bool>| Mask { width_px: 2, height_px: 1, on };
        let features = Features {
            difference: GreyImage { width_px: 2, height_px: 1, pixels: vec![0, 50] },
            noise_sd: 1.0,
            threshold_level: 10,
            foreground: mask(vec![false, true]),
            edges: mask(vec![true, false]),
            edge_distance: DistanceImage { width_px: 2, height_px: 1, distance_px: vec![0.0, 16.0] },
            outside_distance: DistanceImage { width_px: 2, height_px: 1, distance_px: vec![1.0, 0.0] },
        };
        assert_eq!(layer_rgba(&features, Layer::Mask), [[0; 4], MASK_RGBA].concat());
        assert_eq!(layer_rgba(&features, Layer::Edges), [EDGE_RGBA, [0; 4]].concat());
        assert_eq!(layer_rgba(&features, Layer::Distance), [255, 255, 255, 220, 128, 128, 128, 220]);
    }
}
