//! A shared camera scene read whole (`../shared/data/optical/NAME.*`): the
//! true camera, the suit's recording, the empty room and every frame of the
//! mp4 in grey, for the tracker tests and the tracker bench.

use std::path::Path;

use embusen::camera::Camera;
use embusen::image::GreyImage;
use embusen::io::image_file::open_png_grey;
use embusen::io::recording::Recording;
use embusen::io::video::Ffmpeg;

pub struct OpticalScene {
    pub camera: Camera,
    pub recording: Recording,
    pub background: GreyImage,
    pub frames: Vec<GreyImage>,
    pub fps: f64,
}

/// Scene `name` of the folder `dir`.
pub fn open_scene(dir: &Path, name: &str) -> OpticalScene {
    let path = |s: &str| dir.join(format!("{name}{s}"));
    let camera = Camera::from_json(&std::fs::read_to_string(path(".camera.json")).unwrap(), name).unwrap();
    let recording = Recording::parse(&std::fs::read(path(".suit.bvh")).unwrap(), name, None).unwrap();
    let background = open_png_grey(&path(".background.png")).unwrap();
    let mut video = Ffmpeg::default().open(&path(".mp4")).unwrap();
    let fps = video.info.fps;
    let mut frames = Vec::new();
    while let Some(frame) = video.next_frame() {
        frames.push(frame.unwrap());
    }
    OpticalScene { camera, recording, background, frames, fps }
}
