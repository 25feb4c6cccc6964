//! The pinhole camera with OpenCV's lens distortion (conventions in the
//! folder's documentation).

use glam::{DAffine3, DMat3, DVec2, DVec3};

use crate::image::Shrink;

/// The size of the camera's images.
#[derive(Clone, Copy, Debug, PartialEq, Eq, serde::Serialize, serde::Deserialize)]
pub struct ImageSize {
    pub width_px: u32,
    pub height_px: u32,
}

/// Focal lengths and principal point, in pixels (the matrix `K`).
#[derive(Clone, Copy, Debug, PartialEq, serde::Serialize, serde::Deserialize)]
pub struct Intrinsics {
    pub fx_px: f64,
    pub fy_px: f64,
    pub cx_px: f64,
    pub cy_px: f64,
}

/// OpenCV's distortion coefficients `(k1, k2, p1, p2, k3)`; all zero is a
/// perfect pinhole.
#[derive(Clone, Copy, Debug, Default, PartialEq, serde::Serialize, serde::Deserialize)]
pub struct Distortion {
    pub k1: f64,
    pub k2: f64,
    pub p1: f64,
    pub p2: f64,
    pub k3: f64,
}

/// A calibrated camera: what it sees of the world, pixel by pixel.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Camera {
    pub image_size: ImageSize,
    pub intrinsics: Intrinsics,
    pub distortion: Distortion,
    /// World cm → camera cm; its matrix is a rotation.
    pub camera_from_world: DAffine3,
}

/// Points closer to the camera's plane than this (cm) are not projected:
/// they are behind it or in the lens.
const NEAREST_DEPTH_CM: f64 = 1.0;

impl Intrinsics {
    /// The matrix `K`.
    pub fn matrix(&self) -> DMat3 {
        DMat3::from_cols(
            DVec3::new(self.fx_px, 0.0, 0.0),
            DVec3::new(0.0, self.fy_px, 0.0),
            DVec3::new(self.cx_px, self.cy_px, 1.0),
        )
    }

    /// The pixel of a normalised (distorted) image point `x/z, y/z`.
    pub fn pixel(&self, normalised: DVec2) -> DVec2 {
        DVec2::new(self.fx_px * normalised.x + self.cx_px, self.fy_px * normalised.y + self.cy_px)
    }

    /// The normalised (distorted) image point of `pixel`.
    pub fn normalised(&self, pixel: DVec2) -> DVec2 {
        DVec2::new((pixel.x - self.cx_px) / self.fx_px, (pixel.y - self.cy_px) / self.fy_px)
    }
}

impl Distortion {
    /// Where the lens puts the ideal normalised point `p` (OpenCV's model).
    pub fn distort(&self, p: DVec2) -> DVec2 {
        let r2 = p.length_squared();
        let radial = 1.0 + r2 * (self.k1 + r2 * (self.k2 + r2 * self.k3));
        let xy = p.x * p.y;
        DVec2::new(
            p.x * radial + 2.0 * self.p1 * xy + self.p2 * (r2 + 2.0 * p.x * p.x),
            p.y * radial + self.p1 * (r2 + 2.0 * p.y * p.y) + 2.0 * self.p2 * xy,
        )
    }

    /// The ideal normalised point that the lens puts at `distorted`: the
    /// fixed-point iteration of OpenCV's `undistortPoints`, run until it
    /// moves less than 1e-12 (at most 50 rounds; for lenses within their
    /// calibrated field it converges in a few).
    pub fn undistort(&self, distorted: DVec2) -> DVec2 {
        let mut p = distorted;
        for _ in 0..50 {
            let r2 = p.length_squared();
            let radial = 1.0 + r2 * (self.k1 + r2 * (self.k2 + r2 * self.k3));
            let xy = p.x * p.y;
            let tangential = DVec2::new(
                2.0 * self.p1 * xy + self.p2 * (r2 + 2.0 * p.x * p.x),
                self.p1 * (r2 + 2.0 * p.y * p.y) + 2.0 * self.p2 * xy,
            );
            let next = (distorted - tangential) / radial;
            let moved = (next - p).length();
            p = next;
            if moved.is_nan() || moved <= 1e-12 {
                break;
            }
        }
        p
    }
}

impl Camera {
    /// For tests: a `width_px` × `height_px` camera of focal length `f_px`
    /// centred on the image, without distortion, at the world's origin
    /// looking along its +z.
    #[cfg(test)]
    pub fn at_origin(width_px: u32, height_px: u32, f_px: f64) -> Camera {
        Camera {
            image_size: ImageSize { width_px, height_px },
            intrinsics: Intrinsics {
                fx_px: f_px,
                fy_px: f_px,
                cx_px: width_px as f64 / 2.0,
                cy_px: height_px as f64 / 2.0,
            },
            distortion: Distortion::default(),
            camera_from_world: DAffine3::IDENTITY,
        }
    }

    /// The camera's pose in the world: camera cm → world cm.
    pub fn world_from_camera(&self) -> DAffine3 {
        self.camera_from_world.inverse()
    }

    /// The camera's centre in the world (cm).
    pub fn center_in_world(&self) -> DVec3 {
        self.world_from_camera().translation
    }

    /// The direction on the floor (x, z, unit) of the camera's line of
    /// sight through the floor point `floor_cm` (x, z): from below the
    /// camera's centre towards it; zero right below the centre.
    pub fn line_of_sight_on_floor(&self, floor_cm: DVec2) -> DVec2 {
        let centre = self.center_in_world();
        (floor_cm - DVec2::new(centre.x, centre.z)).normalize_or_zero()
    }

    pub fn point_in_camera(&self, point_in_world: DVec3) -> DVec3 {
        self.camera_from_world.transform_point3(point_in_world)
    }

    /// The pixel where `point_in_world` appears, through the lens; `None`
    /// for a point less than 1 cm in front of the camera. The pixel may lie
    /// outside the image.
    pub fn point_in_image(&self, point_in_world: DVec3) -> Option<DVec2> {
        self.pixel_of_camera_point(self.point_in_camera(point_in_world))
    }

    /// The pixel of a point in camera coordinates (cm), as
    /// [`Camera::point_in_image`].
    pub fn pixel_of_camera_point(&self, point_in_camera: DVec3) -> Option<DVec2> {
        if point_in_camera.z.is_nan() || point_in_camera.z < NEAREST_DEPTH_CM {
            return None;
        }
        let ideal = DVec2::new(point_in_camera.x, point_in_camera.y) / point_in_camera.z;
        Some(self.intrinsics.pixel(self.distortion.distort(ideal)))
    }

    /// The direction (unit, in camera coordinates) of the ray through
    /// `pixel`, the lens undone.
    pub fn ray_in_camera(&self, pixel: DVec2) -> DVec3 {
        let ideal = self.distortion.undistort(self.intrinsics.normalised(pixel));
        ideal.extend(1.0).normalize()
    }

    /// Where the ray through `pixel` meets the floor (world y = 0); `None`
    /// when it runs parallel to the floor or meets it behind the camera.
    pub fn floor_point(&self, pixel: DVec2) -> Option<DVec3> {
        let world_from_camera = self.world_from_camera();
        let origin = world_from_camera.translation;
        let direction = world_from_camera.transform_vector3(self.ray_in_camera(pixel));
        if direction.y.is_nan() || direction.y.abs() <= 1e-12 {
            return None;
        }
        let distance = -origin.y / direction.y;
        (distance > 0.0).then(|| origin + direction * distance)
    }

    /// An error for `label` (an image's name) unless it is `width_px ×
    /// height_px`, the size of this camera's images.
    pub fn check_image_size(
        &self,
        width_px: u32,
        height_px: u32,
        label: &str,
    ) -> Result<(), crate::error::Error> {
        let size = self.image_size;
        if (width_px, height_px) == (size.width_px, size.height_px) {
            return Ok(());
        }
        Err(crate::error::Error::whole(
            label,
            format!(
                "is {width_px}×{height_px} px but the camera was calibrated for {}×{}",
                size.width_px, size.height_px
            ),
        ))
    }

    /// The camera whose images are this one's shrunk by `shrink`
    /// ([`crate::image::GreyImage::shrunk`]): a pixel of it spans `f × f`
    /// of this one's (`f` = [`Shrink::factor`]), its centre at
    /// `(x + ½) · f − ½` here, so the focal lengths divide by `f` and the
    /// principal point moves to `(c + ½) / f − ½`; the lens, in the ideal
    /// image, is the same. Columns and rows that fill no shrunk pixel are
    /// dropped. [`Shrink::NONE`] is this camera.
    pub fn shrunk(&self, shrink: Shrink) -> Camera {
        if shrink.is_none() {
            // Not through the arithmetic: (c + ½) / 1 − ½ may differ from c
            // in its last bit.
            return *self;
        }
        let k = self.intrinsics;
        let f = shrink.factor();
        Camera {
            image_size: ImageSize {
                width_px: shrink.length_px(self.image_size.width_px),
                height_px: shrink.length_px(self.image_size.height_px),
            },
            intrinsics: Intrinsics {
                fx_px: k.fx_px / f,
                fy_px: k.fy_px / f,
                cx_px: shrink.coordinate_px(k.cx_px),
                cy_px: shrink.coordinate_px(k.cy_px),
            },
            ..*self
        }
    }

    /// Whether `pixel` lies on the image (pixel centres at whole numbers).
    pub fn sees_pixel(&self, pixel: DVec2) -> bool {
        let (w, h) = (self.image_size.width_px as f64, self.image_size.height_px as f64);
        pixel.x >= -0.5 && pixel.y >= -0.5 && pixel.x < w - 0.5 && pixel.y < h - 0.5
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Looking along world −Z from 5 m back and 1.5 m up, tilted down a
    /// little, with a mild barrel lens.
    fn camera() -> Camera {
        let tilt = DMat3::from_rotation_x(-0.3);
        // Camera axes in world terms: x right (+X), y down (−Y), z forward (−Z).
        let axes = DMat3::from_cols(DVec3::X, DVec3::NEG_Y, DVec3::NEG_Z);
        let world_from_camera = DAffine3::from_mat3_translation(tilt * axes, DVec3::new(20.0, 150.0, 500.0));
        Camera {
            image_size: ImageSize { width_px: 640, height_px: 480 },
            intrinsics: Intrinsics { fx_px: 500.0, fy_px: 502.0, cx_px: 319.5, cy_px: 239.5 },
            distortion: Distortion { k1: -0.05, k2: 0.02, p1: -0.0003, p2: -0.0002, k3: 0.001 },
            camera_from_world: world_from_camera.inverse(),
        }
    }

    #[test]
    fn a_shrunk_camera_sees_a_point_in_the_block_it_fell_in() {
        let camera = camera();
        for quarters in [4, 8, 9, 12] {
            let shrunk = camera.shrunk(Shrink::from_quarters(quarters).unwrap());
            let factor = quarters as f64 / 4.0;
            assert_eq!(shrunk.image_size.width_px, 640 * 4 / quarters);
            for point in [DVec3::new(0.0, 0.0, 0.0), DVec3::new(80.0, 170.0, -120.0)] {
                let full = camera.point_in_image(point).unwrap();
                let small = shrunk.point_in_image(point).unwrap();
                let expected = (full + 0.5) / factor - 0.5;
                assert!((small - expected).length() < 1e-9, "{factor}: {small} ≠ {expected}");
            }
        }
    }

    #[test]
    fn a_floor_point_projects_back_to_its_pixel() {
        let camera = camera();
        for pixel in [DVec2::new(10.0, 470.0), DVec2::new(319.5, 400.0), DVec2::new(630.0, 300.0)] {
            let floor = camera.floor_point(pixel).unwrap();
            assert!(floor.y.abs() < 1e-9);
            let back = camera.point_in_image(floor).unwrap();
            assert!((back - pixel).length() < 1e-6, "{pixel} → {floor} → {back}");
        }
        // Above the horizon the ray never meets the floor ahead.
        assert_eq!(camera.floor_point(DVec2::new(319.5, -400.0)), None);
    }

    #[test]
    fn the_centre_is_where_the_camera_stands_and_behind_is_not_seen() {
        let camera = camera();
        assert!((camera.center_in_world() - DVec3::new(20.0, 150.0, 500.0)).length() < 1e-9);
        assert_eq!(camera.point_in_image(DVec3::new(20.0, 150.0, 600.0)), None);
        // The principal point is the image of the optical axis.
        let ahead = camera.world_from_camera().transform_point3(DVec3::new(0.0, 0.0, 300.0));
        let pixel = camera.point_in_image(ahead).unwrap();
        assert!((pixel - DVec2::new(319.5, 239.5)).length() < 1e-9);
    }

    #[test]
    fn undistort_inverts_distort() {
        let lens = camera().distortion;
        for p in [DVec2::new(0.0, 0.0), DVec2::new(0.6, -0.4), DVec2::new(-0.3, 0.45)] {
            assert!((lens.undistort(lens.distort(p)) - p).length() < 1e-10, "{p}");
        }
    }
}
