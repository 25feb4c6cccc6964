//! One camera frame made into what the trackers match a body against, as
//! Riečický et al. do it: background subtraction → threshold → Canny →
//! distance transform; and beside it the foreground mask's own distance
//! transform, for a tracker that also wants the silhouette inside the mask.

use crate::error::Error;
use crate::image::background::{Threshold, difference, foreground, matched_difference, noise_sd};
use crate::image::canny::{CannyParams, canny};
use crate::image::distance::{distance_to, distance_to_truncated};
use crate::image::morphology::open_close;
use crate::image::{DistanceImage, GreyImage, Mask};

/// Which image Canny looks at.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub enum EdgesOf {
    /// The difference image, zero off the foreground (the paper's): the
    /// mask's outline and, inside it, wherever the difference changes by a
    /// step (a limb across the body, but also the room's own pattern behind
    /// a plain body).
    #[default]
    Difference,
    /// The mask alone: its outline only.
    Mask,
}

/// The pipeline's settings.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct PipelineParams {
    pub threshold: Threshold,
    /// The foreground is opened by a square of this radius (px; 0: not at
    /// all): the specks of noise above the threshold go.
    pub open_px: u32,
    /// Then closed by one of this radius (px; 0: not at all): gaps where
    /// the actor matches the room behind fill.
    pub close_px: u32,
    pub edges_of: EdgesOf,
    /// Canny's smoothing (px).
    pub canny_sigma_px: f32,
    /// Canny's `(low, high)` step heights in grey levels; `None`: the
    /// foreground threshold and half of it, so that the mask's border (a
    /// step from 0 to above the threshold) is always an edge and the
    /// detector is as sensitive as the threshold, in any light.
    pub canny_steps: Option<(f32, f32)>,
    /// `None`: the distance transforms exact everywhere (the paper's
    /// chamfer sums distances however far). `Some(max_px)`: capped at
    /// `max_px`, and computed only near the foreground, a few times faster
    /// (see `distance::distance_to_truncated`).
    pub truncate_px: Option<f32>,
    /// Whether the background still is first brought to each frame: moved
    /// by the camera's shift of a few pixels since it was taken and scaled
    /// to the frame's exposure (`background::matched_difference`).
    /// Riečický et al. subtract the still as it is.
    pub match_still: bool,
}

impl Default for PipelineParams {
    fn default() -> Self {
        PipelineParams {
            threshold: Threshold::default(),
            // Specks of one or two pixels go; a limb 3 px wide stays.
            open_px: 1,
            // Gaps up to 4 px close (on the shared scenes, a skirting board
            // 2 px high the actor's trousers match in grey).
            close_px: 2,
            edges_of: EdgesOf::default(),
            // Smooths the sensor noise and the codec's blocks without
            // rounding off a limb a few pixels wide.
            canny_sigma_px: 1.0,
            canny_steps: None,
            truncate_px: None,
            match_still: true,
        }
    }
}

/// What one frame becomes.
#[derive(Clone, Debug, PartialEq)]
pub struct Features {
    /// `|frame − background|`.
    pub difference: GreyImage,
    /// The noise measured on `difference` (grey levels, one σ).
    pub noise_sd: f32,
    /// The threshold used: foreground is a difference above it.
    pub threshold_level: u8,
    /// The pixels above the threshold, opened and closed.
    pub foreground: Mask,
    /// Canny's edges (of [`PipelineParams::edges_of`]).
    pub edges: Mask,
    /// Distance (px) from each pixel to the nearest edge pixel (capped at
    /// [`PipelineParams::truncate_px`]).
    pub edge_distance: DistanceImage,
    /// Distance (px) from each pixel to the nearest foreground pixel: 0 on
    /// the foreground, how far outside it elsewhere (the cost of a body's
    /// silhouette pixel where the camera saw only the room; capped too).
    pub outside_distance: DistanceImage,
}

/// The thresholded pixels opened then closed as `params` say.
pub fn clean_mask(raw: &Mask, params: &PipelineParams) -> Mask {
    open_close(raw, params.open_px, params.close_px)
}

/// What Canny looks at: the difference where it is foreground, 0 elsewhere
/// (or 255 and 0 for [`EdgesOf::Mask`]).
pub fn canny_input(difference: &GreyImage, foreground: &Mask, edges_of: EdgesOf) -> GreyImage {
    let pixels = match edges_of {
        EdgesOf::Difference => {
            difference.pixels.iter().zip(&foreground.on).map(|(&d, &on)| if on { d } else { 0 }).collect()
        }
        EdgesOf::Mask => return foreground.to_grey(),
    };
    GreyImage { width_px: difference.width_px, height_px: difference.height_px, pixels }
}

/// Runs the whole pipeline on `frame` against `background`; an error for
/// `label` (the frame's name) when their sizes differ.
pub fn features(
    frame: &GreyImage,
    background: &GreyImage,
    params: &PipelineParams,
    label: &str,
) -> Result<Features, Error> {
    let difference = if params.match_still {
        matched_difference(frame, background, label)?
    } else {
        difference(frame, background, label)?
    };
    let noise_sd = noise_sd(&difference);
    let threshold_level = params.threshold.level_at(noise_sd);
    let foreground = clean_mask(&foreground(&difference, threshold_level), params);
    let (low_step, high_step) =
        params.canny_steps.unwrap_or((threshold_level as f32 / 2.0, threshold_level as f32));
    let canny_params = CannyParams { sigma_px: params.canny_sigma_px, low_step, high_step };
    let edges = canny(&canny_input(&difference, &foreground, params.edges_of), &canny_params);
    let distance = |mask: &Mask| match params.truncate_px {
        None => distance_to(mask),
        Some(max_px) => distance_to_truncated(mask, max_px),
    };
    let edge_distance = distance(&edges);
    let outside_distance = distance(&foreground);
    Ok(Features { difference, noise_sd, threshold_level, foreground, edges, edge_distance, outside_distance })
}

impl Features {
    /// The digest of every stage, in pipeline order (difference, foreground,
    /// edges, edge distance, outside distance): what the wasm test compares.
    pub fn digests(&self) -> [u64; 5] {
        [
            self.difference.digest(),
            self.foreground.digest(),
            self.edges.digest(),
            self.edge_distance.digest(),
            self.outside_distance.digest(),
        ]
    }
}

/// The bytes before a frame's planes in [`Features::to_bytes`].
const FEATURES_HEADER_BYTES: usize = 16;

/// The bytes a pixel takes in [`Features::to_bytes`]: the difference, the
/// foreground and the edges one each, the two distances four each.
const FEATURES_BYTES_PER_PIXEL: usize = 3 + 2 * 4;

impl Features {
    /// The features as bytes, for a path scorer in another worker, which
    /// shares no memory with the tracker that made them: the width and
    /// the height (u32), the noise (f32), the threshold (u8) and three
    /// bytes of padding, then the planes row by row — the difference, the
    /// foreground and the edges (a byte a pixel, 1 on and 0 off), the edge
    /// and the outside distances (f32) — all little-endian.
    /// [`Features::from_bytes`] gives back the same bits.
    pub fn to_bytes(&self) -> Vec<u8> {
        let count = self.difference.pixels.len();
        // Sized first and filled plane by plane: each loop a plain copy
        // (a frame's features are megabytes, handed over every frame).
        let mut bytes = vec![0u8; FEATURES_HEADER_BYTES + FEATURES_BYTES_PER_PIXEL * count];
        let (header, planes) = bytes.split_at_mut(FEATURES_HEADER_BYTES);
        header[0..4].copy_from_slice(&self.difference.width_px.to_le_bytes());
        header[4..8].copy_from_slice(&self.difference.height_px.to_le_bytes());
        header[8..12].copy_from_slice(&self.noise_sd.to_le_bytes());
        header[12] = self.threshold_level;
        let (difference, planes) = planes.split_at_mut(count);
        difference.copy_from_slice(&self.difference.pixels);
        let (foreground, planes) = planes.split_at_mut(count);
        let (edges, distances) = planes.split_at_mut(count);
        for (to, mask) in [(foreground, &self.foreground), (edges, &self.edges)] {
            for (byte, &on) in to.iter_mut().zip(&mask.on) {
                *byte = u8::from(on);
            }
        }
        let (edge_distance, outside_distance) = distances.split_at_mut(4 * count);
        for (to, from) in [(edge_distance, &self.edge_distance), (outside_distance, &self.outside_distance)] {
            for (word, d) in to.chunks_exact_mut(4).zip(&from.distance_px) {
                word.copy_from_slice(&d.to_le_bytes());
            }
        }
        bytes
    }

    /// The features [`Features::to_bytes`] wrote; an error for `label`
    /// when the bytes are not such (too few or too many for their size, a
    /// mask byte neither 0 nor 1).
    pub fn from_bytes(bytes: &[u8], label: &str) -> Result<Features, Error> {
        let word = |at: usize| bytes.get(at..at + 4).and_then(|b| <[u8; 4]>::try_from(b).ok());
        let (Some(width), Some(height), Some(noise), Some(&threshold_level)) =
            (word(0), word(4), word(8), bytes.get(12))
        else {
            return Err(Error::whole(
                label,
                format!("{} bytes of features: too few for the header", bytes.len()),
            ));
        };
        let (width_px, height_px) = (u32::from_le_bytes(width), u32::from_le_bytes(height));
        // Checked: a header's size need not fit a 32-bit target's memory.
        let count = (width_px as usize).checked_mul(height_px as usize);
        let expected = count
            .and_then(|n| n.checked_mul(FEATURES_BYTES_PER_PIXEL))
            .and_then(|n| n.checked_add(FEATURES_HEADER_BYTES));
        let (Some(count), true) = (count, expected == Some(bytes.len())) else {
            return Err(Error::whole(
                label,
                format!("{} bytes of features for a {width_px}×{height_px} frame", bytes.len()),
            ));
        };
        let planes = &bytes[FEATURES_HEADER_BYTES..];
        let (difference, rest) = planes.split_at(count);
        let (foreground, rest) = rest.split_at(count);
        let (edges, distances) = rest.split_at(count);
        let difference = GreyImage::new(width_px, height_px, difference.to_vec(), label)?;
        let mask = |on: &[u8], what: &str| {
            if let Some(k) = on.iter().position(|&b| b > 1) {
                return Err(Error::whole(label, format!("{what} byte {k} is {}, not 0 or 1", on[k])));
            }
            Ok(Mask { width_px, height_px, on: on.iter().map(|&b| b == 1).collect() })
        };
        let distance = |plane: &[u8]| DistanceImage {
            width_px,
            height_px,
            distance_px: plane
                .chunks_exact(4)
                .map(|b| f32::from_le_bytes([b[0], b[1], b[2], b[3]]))
                .collect(),
        };
        let (edge_distance, outside_distance) = distances.split_at(4 * count);
        Ok(Features {
            difference,
            noise_sd: f32::from_le_bytes(noise),
            threshold_level,
            foreground: mask(foreground, "the foreground's")?,
            edges: mask(edges, "the edges'")?,
            edge_distance: distance(edge_distance),
            outside_distance: distance(outside_distance),
        })
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// A frame's features with every plane different, made by the pipeline.
    fn some_features() -> Features {
        let (w, h) = (23u32, 17u32);
        let background = GreyImage::filled(w, h, 60);
        let mut frame = background.clone();
        for y in 4..13 {
            for x in 6..15 {
                frame.pixels[(y * w + x) as usize] = 180 + (x * y % 50) as u8;
            }
        }
        let params = PipelineParams { truncate_px: Some(5.0), ..PipelineParams::default() };
        features(&frame, &background, &params, "frame").unwrap()
    }

    #[test]
    fn features_come_back_from_their_bytes_bit_for_bit() {
        let features = some_features();
        assert!(features.foreground.count() > 0 && features.edges.count() > 0);
        let bytes = features.to_bytes();
        assert_eq!(bytes.len(), 16 + 11 * 23 * 17);
        let back = Features::from_bytes(&bytes, "frame 3").unwrap();
        assert_eq!(back.digests(), features.digests());
        assert_eq!(back.noise_sd.to_bits(), features.noise_sd.to_bits());
        assert_eq!(back.threshold_level, features.threshold_level);
    }

    #[test]
    fn bytes_that_are_not_features_are_refused_naming_the_frame() {
        let bytes = some_features().to_bytes();
        let refused = |bytes: &[u8]| Features::from_bytes(bytes, "frame 3").unwrap_err().to_string();
        let mut too_large = bytes.clone();
        too_large[..8].copy_from_slice(&[255; 8]); // 4294967295 × 4294967295 pixels
        for said in [refused(&bytes[..10]), refused(&bytes[..bytes.len() - 1]), refused(&too_large)] {
            assert!(said.contains("frame 3") && said.contains("bytes of features"), "{said}");
        }
        let mut wrong_mask = bytes.clone();
        wrong_mask[16 + 23 * 17 + 5] = 2; // the foreground's sixth pixel
        let said = refused(&wrong_mask);
        assert!(said.contains("foreground") && said.contains("byte 5 is 2"), "{said}");
    }
}
