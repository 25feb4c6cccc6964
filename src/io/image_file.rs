//! PNG stills (a background, a board, a frame of an image sequence) read
//! into grey images, and image sequences: a folder of PNGs, one per frame.
//!
//! Colour becomes grey the way ffmpeg makes the grey frames of a video (the
//! luma of BT.601, limited range stretched to full, see [`luma_of_rgb`]), so
//! a background still and the frames of a video of the same empty room have
//! the same grey levels and their difference is the noise, not a bias.

use crate::error::Error;
use crate::image::GreyImage;

/// The most bytes a PNG may decode into (1 GiB: an 8K RGBA16 still fits);
/// beyond it the file is refused before anything is allocated.
const DECODE_LIMIT_BYTES: usize = 1 << 30;

/// Decodes a PNG of any colour type and bit depth into grey: palettes and
/// low bit depths expanded, 16-bit samples cut to their high byte, colour
/// through [`luma_of_rgb`], alpha ignored (a still is opaque). An error
/// naming `file` when the bytes are not a whole PNG.
pub fn png_to_grey(bytes: &[u8], file: &str) -> Result<GreyImage, Error> {
    let mut decoder =
        png::Decoder::new_with_limits(std::io::Cursor::new(bytes), png::Limits { bytes: DECODE_LIMIT_BYTES });
    decoder.set_transformations(png::Transformations::EXPAND | png::Transformations::STRIP_16);
    let mut reader = decoder.read_info().map_err(|e| png_error(file, e))?;
    let size = reader.output_buffer_size().ok_or_else(|| Error::whole(file, "a PNG too large to decode"))?;
    let mut buffer = vec![0; size];
    let frame = reader.next_frame(&mut buffer).map_err(|e| png_error(file, e))?;
    let (width_px, height_px) = (frame.width, frame.height);
    let samples = &buffer[..frame.buffer_size()];
    let channels = match frame.color_type {
        png::ColorType::Grayscale => 1,
        png::ColorType::GrayscaleAlpha => 2,
        png::ColorType::Rgb => 3,
        png::ColorType::Rgba => 4,
        // EXPAND turns a palette into RGB(A); a decoder that did not is a bug
        // of the decoder, still not a reason to panic.
        png::ColorType::Indexed => {
            return Err(Error::whole(file, "a palette PNG the decoder did not expand"));
        }
    };
    let line_bytes = frame.line_size;
    let mut pixels = Vec::with_capacity(width_px as usize * height_px as usize);
    for row in samples.chunks_exact(line_bytes) {
        let row = &row[..width_px as usize * channels];
        match channels {
            1 | 2 => pixels.extend(row.chunks_exact(channels).map(|p| p[0])),
            _ => pixels.extend(row.chunks_exact(channels).map(|p| luma_of_rgb(p[0], p[1], p[2]))),
        }
    }
    GreyImage::new(width_px, height_px, pixels, file)
}

/// `image` as an 8-bit greyscale PNG (what [`png_to_grey`] reads back as
/// the same pixels): a background the app made, saved as a still.
pub fn grey_to_png(image: &GreyImage, file: &str) -> Result<Vec<u8>, Error> {
    let mut bytes = Vec::new();
    let mut encoder = png::Encoder::new(&mut bytes, image.width_px, image.height_px);
    encoder.set_color(png::ColorType::Grayscale);
    encoder.set_depth(png::BitDepth::Eight);
    let failed = |e: png::EncodingError| Error::whole(file, format!("cannot write the PNG: {e}"));
    let mut writer = encoder.write_header().map_err(failed)?;
    writer.write_image_data(&image.pixels).map_err(failed)?;
    writer.finish().map_err(failed)?;
    Ok(bytes)
}

fn png_error(file: &str, e: png::DecodingError) -> Error {
    let what = match e {
        png::DecodingError::IoError(e) if e.kind() == std::io::ErrorKind::UnexpectedEof => {
            "the PNG ends early (a truncated file?)".to_string()
        }
        png::DecodingError::LimitsExceeded => {
            format!("a PNG larger than {} MiB decoded", DECODE_LIMIT_BYTES >> 20)
        }
        e => format!("not a readable PNG: {e}"),
    };
    Error::whole(file, what)
}

/// The grey level ffmpeg gives an sRGB pixel when it encodes it as BT.601
/// limited-range YUV and decodes the luma to `-pix_fmt gray`:
/// `Y = 16 + 219/255 · (0.299 R + 0.587 G + 0.114 B)`, then `(Y − 16) · 255/219`
/// back to full range, which is the full-range luma itself. Integer weights
/// (sum 2¹⁵) rounded once, so every target computes the same byte.
pub fn luma_of_rgb(r: u8, g: u8, b: u8) -> u8 {
    // 0.299, 0.587, 0.114 × 32768, adjusted to sum to exactly 32768 so that
    // white stays 255.
    let y = 9798 * r as u32 + 19235 * g as u32 + 3735 * b as u32;
    ((y + (1 << 14)) >> 15) as u8
}

/// Reads and decodes the PNG at `path` into grey; the error names the file.
#[cfg(not(target_arch = "wasm32"))]
pub fn open_png_grey(path: &std::path::Path) -> Result<GreyImage, Error> {
    let name = path.display().to_string();
    let bytes = std::fs::read(path).map_err(|e| Error::whole(&name, format!("cannot read: {e}")))?;
    png_to_grey(&bytes, &name)
}

/// A folder of PNG frames, in the order of their file names, at a frame rate
/// the user gives (a folder has none of its own).
#[cfg(not(target_arch = "wasm32"))]
#[derive(Clone, Debug, PartialEq)]
pub struct ImageSequence {
    pub frames: Vec<std::path::PathBuf>,
    pub fps: f64,
}

#[cfg(not(target_arch = "wasm32"))]
impl ImageSequence {
    /// The `.png` files (any case) of `folder`, sorted by name; an error when
    /// the folder cannot be read, holds no PNG, or `fps` is not positive.
    /// The frames themselves are read one at a time by [`ImageSequence::frame`].
    pub fn open(folder: &std::path::Path, fps: f64) -> Result<Self, Error> {
        let name = folder.display().to_string();
        if !(fps.is_finite() && fps > 0.0) {
            return Err(Error::whole(&name, format!("a frame rate of {fps} fps: it must be positive")));
        }
        let entries =
            std::fs::read_dir(folder).map_err(|e| Error::whole(&name, format!("cannot read: {e}")))?;
        let mut frames = Vec::new();
        for entry in entries {
            let path = entry.map_err(|e| Error::whole(&name, format!("cannot read: {e}")))?.path();
            if path.is_file() && path.extension().is_some_and(|e| e.eq_ignore_ascii_case("png")) {
                frames.push(path);
            }
        }
        if frames.is_empty() {
            return Err(Error::whole(&name, "no .png frames in this folder"));
        }
        frames.sort();
        Ok(ImageSequence { frames, fps })
    }

    pub fn frame_count(&self) -> usize {
        self.frames.len()
    }

    /// Frame `index` in grey; an error naming its file when it cannot be
    /// read, or when its size differs from the first frame's.
    pub fn frame(&self, index: usize) -> Result<GreyImage, Error> {
        let Some(path) = self.frames.get(index) else {
            return Err(Error::whole(
                &self.frames.first().map(|p| p.display().to_string()).unwrap_or_default(),
                format!("no frame {index}: the sequence has {}", self.frames.len()),
            ));
        };
        let image = open_png_grey(path)?;
        if index > 0 {
            let first = open_png_size(&self.frames[0])?;
            if !image.same_size(first.0, first.1) {
                return Err(Error::whole(
                    &path.display().to_string(),
                    format!(
                        "{}×{} pixels, where the sequence's first frame has {}×{}",
                        image.width_px, image.height_px, first.0, first.1
                    ),
                ));
            }
        }
        Ok(image)
    }
}

/// The size of the PNG at `path`, from its header alone.
#[cfg(not(target_arch = "wasm32"))]
fn open_png_size(path: &std::path::Path) -> Result<(u32, u32), Error> {
    let name = path.display().to_string();
    let file = std::fs::File::open(path).map_err(|e| Error::whole(&name, format!("cannot read: {e}")))?;
    let reader =
        png::Decoder::new(std::io::BufReader::new(file)).read_info().map_err(|e| png_error(&name, e))?;
    Ok(reader.info().size())
}

#[cfg(test)]
mod tests {
    use super::*;

    fn encode(width: u32, height: u32, color: png::ColorType, depth: png::BitDepth, data: &[u8]) -> Vec<u8> {
        let mut bytes = Vec::new();
        let mut encoder = png::Encoder::new(&mut bytes, width, height);
        encoder.set_color(color);
        encoder.set_depth(depth);
        let mut writer = encoder.write_header().unwrap();
        writer.write_image_data(data).unwrap();
        writer.finish().unwrap();
        bytes
    }

    #[test]
    fn grey_rgb_and_16_bit_pngs_read_as_grey() {
        let grey = encode(2, 1, png::ColorType::Grayscale, png::BitDepth::Eight, &[7, 200]);
        assert_eq!(png_to_grey(&grey, "g.png").unwrap().pixels, vec![7, 200]);
        let rgb = encode(2, 1, png::ColorType::Rgb, png::BitDepth::Eight, &[255, 255, 255, 255, 0, 0]);
        assert_eq!(png_to_grey(&rgb, "c.png").unwrap().pixels, vec![255, 76]);
        let deep = encode(1, 1, png::ColorType::Grayscale, png::BitDepth::Sixteen, &[0x12, 0x34]);
        assert_eq!(png_to_grey(&deep, "d.png").unwrap().pixels, vec![0x12]);
        let low = encode(8, 1, png::ColorType::Grayscale, png::BitDepth::One, &[0b1010_0000]);
        assert_eq!(png_to_grey(&low, "l.png").unwrap().pixels, vec![255, 0, 255, 0, 0, 0, 0, 0]);
    }

    #[test]
    fn luma_keeps_black_and_white_and_weights_green_most() {
        assert_eq!((luma_of_rgb(0, 0, 0), luma_of_rgb(255, 255, 255)), (0, 255));
        assert_eq!((luma_of_rgb(255, 0, 0), luma_of_rgb(0, 255, 0), luma_of_rgb(0, 0, 255)), (76, 150, 29));
    }

    #[test]
    fn a_cut_png_is_an_error_naming_the_file() {
        let rgb = encode(16, 16, png::ColorType::Rgb, png::BitDepth::Eight, &[90; 16 * 16 * 3]);
        for cut in [0, 8, 30, rgb.len() / 2, rgb.len() - 13] {
            let e = png_to_grey(&rgb[..cut], "room.png").unwrap_err();
            assert!(e.to_string().starts_with("room.png: "), "{e}");
        }
        assert!(png_to_grey(b"GIF89a", "x.png").is_err());
    }
}
