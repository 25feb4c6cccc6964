//! The three kinds of image the pipeline passes along: grey levels, masks
//! and distances, each row-major with its size in pixels.

use crate::error::Error;
use crate::image::shrink::{Shrink, area_resampled};

/// An 8-bit grey image: pixel `(x, y)` is `pixels[y · width_px + x]`.
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct GreyImage {
    pub width_px: u32,
    pub height_px: u32,
    pub pixels: Vec<u8>,
}

/// A binary image (foreground, edges): pixel `(x, y)` is on when
/// `on[y · width_px + x]`.
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct Mask {
    pub width_px: u32,
    pub height_px: u32,
    pub on: Vec<bool>,
}

/// A distance in pixels per pixel (a distance transform): pixel `(x, y)` is
/// `distance_px[y · width_px + x]`, `f32::INFINITY` where there was nothing
/// to be near.
#[derive(Clone, Debug, PartialEq)]
pub struct DistanceImage {
    pub width_px: u32,
    pub height_px: u32,
    pub distance_px: Vec<f32>,
}

/// The pixel count of a `width_px × height_px` image, or an error for `label`
/// when it is empty or too large to address.
fn pixel_count(width_px: u32, height_px: u32, label: &str) -> Result<usize, Error> {
    let count = (width_px as u64) * (height_px as u64);
    // 2³¹ pixels bounds every index and every squared distance the
    // transforms keep in 64-bit integers, on 32-bit wasm too.
    if count == 0 || count > (1 << 31) {
        return Err(Error::whole(label, format!("an image of {width_px}×{height_px} pixels cannot be used")));
    }
    Ok(count as usize)
}

impl GreyImage {
    /// An image from its rows; an error for `label` when `pixels` does not
    /// hold exactly `width_px × height_px` values or the size is empty.
    pub fn new(width_px: u32, height_px: u32, pixels: Vec<u8>, label: &str) -> Result<Self, Error> {
        let count = pixel_count(width_px, height_px, label)?;
        if pixels.len() != count {
            return Err(Error::whole(
                label,
                format!("{} grey values for a {width_px}×{height_px} image ({count} expected)", pixels.len()),
            ));
        }
        Ok(GreyImage { width_px, height_px, pixels })
    }

    /// The grey image of a decoded video frame's luma plane `luma` (rows
    /// `stride` bytes apart, the first `width_px` of each used): the grey
    /// levels `ffmpeg -pix_fmt gray` makes, so that a browser holding the
    /// decoder's own planes and `embusen track` reading ffmpeg's
    /// ([`crate::io::video`]) track the same bytes.
    /// Limited-range luma (`full_range` false: 16 black, 235 white, the
    /// video default) is stretched to full as ffmpeg's swscale does,
    /// `⌊((Y − 16) · 510 + 219) / 438⌋` clamped to 0–255 (`tests/image.rs`
    /// holds it to ffmpeg for every level); full-range luma is the grey
    /// itself. An error for `label` when the plane is too short.
    pub fn from_luma(
        width_px: u32,
        height_px: u32,
        luma: &[u8],
        stride: usize,
        full_range: bool,
        label: &str,
    ) -> Result<Self, Error> {
        let count = pixel_count(width_px, height_px, label)?;
        let (w, h) = (width_px as usize, height_px as usize);
        if stride < w || luma.len() < stride * (h - 1) + w {
            return Err(Error::whole(
                label,
                format!(
                    "a luma plane of {} bytes, rows {stride} apart, for a {width_px}×{height_px} frame",
                    luma.len()
                ),
            ));
        }
        let level = |y: u8| -> u8 {
            if full_range { y } else { ((y as i32 - 16) * 510 + 219).div_euclid(438).clamp(0, 255) as u8 }
        };
        // A table of the 256 levels: a lookup a pixel, not a division.
        let levels: [u8; 256] = std::array::from_fn(|y| level(y as u8));
        let mut pixels = Vec::with_capacity(count);
        for row in luma.chunks(stride).take(h) {
            pixels.extend(row[..w].iter().map(|&y| levels[y as usize]));
        }
        Ok(GreyImage { width_px, height_px, pixels })
    }

    /// The image shrunk by `shrink` ([`Shrink`]): each pixel the mean of
    /// the source pixels under it, weighted by the area they cover, rounded
    /// half up (integers only, the same bytes on every target; at a whole
    /// factor the mean of a block); the last columns and rows that fill no
    /// shrunk pixel are dropped, as [`crate::camera::Camera::shrunk`]
    /// drops them. [`Shrink::NONE`] is a copy.
    pub fn shrunk(&self, shrink: Shrink) -> GreyImage {
        if shrink.is_none() {
            return self.clone();
        }
        let (width_px, height_px, pixels) =
            area_resampled(&self.pixels, self.width_px, self.height_px, shrink);
        GreyImage { width_px, height_px, pixels }
    }

    /// An image of one grey level.
    pub fn filled(width_px: u32, height_px: u32, level: u8) -> Self {
        GreyImage { width_px, height_px, pixels: vec![level; width_px as usize * height_px as usize] }
    }

    /// The grey level at `(x, y)`; the caller keeps `x`, `y` inside.
    pub fn at(&self, x: u32, y: u32) -> u8 {
        self.pixels[y as usize * self.width_px as usize + x as usize]
    }

    /// Whether the image is `width_px × height_px`.
    pub fn same_size(&self, width_px: u32, height_px: u32) -> bool {
        self.width_px == width_px && self.height_px == height_px
    }

    /// FNV-1a (64-bit) of the size and the pixels: a fingerprint to compare
    /// images across builds (the wasm test holds the browser's to the CLI's).
    pub fn digest(&self) -> u64 {
        digest_of(self.width_px, self.height_px, self.pixels.iter().copied())
    }
}

impl Mask {
    /// A mask of nothing.
    pub fn empty(width_px: u32, height_px: u32) -> Self {
        Mask { width_px, height_px, on: vec![false; width_px as usize * height_px as usize] }
    }

    /// Whether `(x, y)` is on; the caller keeps `x`, `y` inside.
    pub fn at(&self, x: u32, y: u32) -> bool {
        self.on[y as usize * self.width_px as usize + x as usize]
    }

    /// How many pixels are on.
    pub fn count(&self) -> usize {
        self.on.iter().filter(|&&on| on).count()
    }

    /// The complement: on where this is off.
    pub fn inverted(&self) -> Mask {
        Mask {
            width_px: self.width_px,
            height_px: self.height_px,
            on: self.on.iter().map(|&on| !on).collect(),
        }
    }

    /// The mask as a grey image, 255 where on, 0 where off (to look at).
    pub fn to_grey(&self) -> GreyImage {
        GreyImage {
            width_px: self.width_px,
            height_px: self.height_px,
            pixels: self.on.iter().map(|&on| if on { 255 } else { 0 }).collect(),
        }
    }

    /// FNV-1a of the size and the pixels (1 on, 0 off), as [`GreyImage::digest`].
    pub fn digest(&self) -> u64 {
        digest_of(self.width_px, self.height_px, self.on.iter().map(|&on| on as u8))
    }
}

impl DistanceImage {
    /// The distance at `(x, y)`; the caller keeps `x`, `y` inside.
    pub fn at(&self, x: u32, y: u32) -> f32 {
        self.distance_px[y as usize * self.width_px as usize + x as usize]
    }

    /// The same distances, none above `max_px` (nor the infinity of an image
    /// with nothing to be near): a chamfer energy over a truncated transform
    /// is not ruled by one far outlier.
    pub fn truncated(&self, max_px: f32) -> DistanceImage {
        DistanceImage {
            width_px: self.width_px,
            height_px: self.height_px,
            distance_px: self.distance_px.iter().map(|&d| d.min(max_px)).collect(),
        }
    }

    /// FNV-1a of the size and each distance's IEEE bits (little-endian).
    pub fn digest(&self) -> u64 {
        digest_of(
            self.width_px,
            self.height_px,
            self.distance_px.iter().flat_map(|d| d.to_bits().to_le_bytes()),
        )
    }
}

/// A rectangle of pixels: columns `left..right`, rows `top..bottom`, half
/// open (`right` and `bottom` are the first column and row past it; empty
/// when `left == right` or `top == bottom`). The one box of pixels in the
/// crate: the pipeline's work areas here, the silhouettes' bounds in
/// `track::silhouette`.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, serde::Serialize)]
pub struct PixelBox {
    pub left: u32,
    pub top: u32,
    pub right: u32,
    pub bottom: u32,
}

impl PixelBox {
    pub fn width(&self) -> u32 {
        self.right.saturating_sub(self.left)
    }

    pub fn height(&self) -> u32 {
        self.bottom.saturating_sub(self.top)
    }

    pub fn is_empty(&self) -> bool {
        self.width() == 0 || self.height() == 0
    }

    /// The smallest box holding every value of the row-major `values`
    /// (`width` a row) for which `is_on` holds; `None` when there is none.
    pub fn around<T>(values: &[T], width: usize, is_on: impl Fn(&T) -> bool) -> Option<PixelBox> {
        let mut found: Option<PixelBox> = None;
        for (y, row) in (0u32..).zip(values.chunks_exact(width)) {
            let Some(first) = row.iter().position(&is_on) else { continue };
            let last = row.iter().rposition(&is_on).unwrap_or(first);
            let (left, right) = (first as u32, last as u32 + 1);
            found = Some(match found {
                None => PixelBox { left, top: y, right, bottom: y + 1 },
                Some(b) => PixelBox { left: b.left.min(left), right: b.right.max(right), bottom: y + 1, ..b },
            });
        }
        found
    }

    /// The box grown by `by` on every side, within a `width × height` image.
    pub fn grown(self, by: usize, width: usize, height: usize) -> PixelBox {
        let by = u32::try_from(by).unwrap_or(u32::MAX);
        PixelBox {
            left: self.left.saturating_sub(by),
            top: self.top.saturating_sub(by),
            right: self.right.saturating_add(by).min(width as u32),
            bottom: self.bottom.saturating_add(by).min(height as u32),
        }
    }

    /// The rows of the box, each as the range of its values in a row-major
    /// image `width` wide.
    pub fn rows(self, width: usize) -> impl Iterator<Item = std::ops::Range<usize>> {
        let (left, right) = (self.left as usize, self.right as usize);
        (self.top as usize..self.bottom as usize).map(move |y| y * width + left..y * width + right)
    }

    /// The values of the box, row-major.
    pub fn crop<T: Copy>(self, values: &[T], width: usize) -> Vec<T> {
        let mut out = Vec::with_capacity(self.width() as usize * self.height() as usize);
        for row in self.rows(width) {
            out.extend_from_slice(&values[row]);
        }
        out
    }
}

/// FNV-1a, 64-bit: small, fast enough, and the same on every target.
pub fn fnv1a(bytes: impl IntoIterator<Item = u8>) -> u64 {
    const OFFSET: u64 = 0xcbf2_9ce4_8422_2325;
    const PRIME: u64 = 0x0000_0100_0000_01b3;
    bytes.into_iter().fold(OFFSET, |hash, byte| (hash ^ byte as u64).wrapping_mul(PRIME))
}

/// [`fnv1a`] of the size (two little-endian u32) then `bytes`.
fn digest_of(width_px: u32, height_px: u32, bytes: impl Iterator<Item = u8>) -> u64 {
    fnv1a(width_px.to_le_bytes().into_iter().chain(height_px.to_le_bytes()).chain(bytes))
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_shrunk_image_is_its_blocks_means_rounded_half_up() {
        // 5×4 by 2: columns 0–3 and rows 0–3 fill blocks, column 4 is dropped.
        let pixels: Vec<u8> = (0..20u8).map(|v| v * 10).collect();
        let image = GreyImage::new(5, 4, pixels, "test").unwrap();
        let shrunk = image.shrunk(Shrink::whole(2));
        assert_eq!((shrunk.width_px, shrunk.height_px), (2, 2));
        // (0 + 10 + 50 + 60) / 4 = 30; (20 + 30 + 70 + 80) / 4 = 50; …
        assert_eq!(shrunk.pixels, [30, 50, 130, 150]);
        let halves = GreyImage::new(2, 1, vec![1, 2], "test").unwrap().shrunk(Shrink::whole(2));
        assert_eq!(halves.pixels.len(), 0);
        let odd = GreyImage::new(2, 2, vec![0, 1, 1, 0], "test").unwrap().shrunk(Shrink::whole(2));
        assert_eq!(odd.pixels, [1], "2 / 4 rounds half up");
        assert_eq!(image.shrunk(Shrink::NONE), image);
    }

    #[test]
    fn a_wrong_pixel_count_is_an_error_naming_the_image() {
        let e = GreyImage::new(4, 3, vec![0; 11], "frame 7").unwrap_err();
        assert!(e.to_string().starts_with("frame 7: 11 grey values for a 4×3 image"), "{e}");
        assert!(GreyImage::new(0, 3, vec![], "empty").is_err());
        assert_eq!(GreyImage::new(2, 2, vec![1, 2, 3, 4], "ok").unwrap().at(1, 1), 4);
    }

    #[test]
    fn the_digest_is_fnv1a_and_sees_the_size() {
        // The published FNV-1a 64 values of "" and "a".
        assert_eq!(fnv1a([]), 0xcbf2_9ce4_8422_2325);
        assert_eq!(fnv1a(*b"a"), 0xaf63_dc4c_8601_ec8c);
        let a = GreyImage::filled(2, 3, 9);
        let b = GreyImage::filled(3, 2, 9);
        assert_ne!(a.digest(), b.digest());
    }

    #[test]
    fn truncation_caps_infinity_too() {
        let d = DistanceImage { width_px: 2, height_px: 1, distance_px: vec![1.5, f32::INFINITY] };
        assert_eq!(d.truncated(1.0).distance_px, vec![1.0, 1.0]);
    }
}
