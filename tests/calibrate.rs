//! `embusen calibrate` as a user runs it: on each shared board still, with
//! the true lens (the pose must come back within the issue's 1.5 cm and
//! 0.3°) and without (the focal length within 3 %); and its refusals.

// A test may panic on what it does not expect: that is how it fails.
#![allow(clippy::unwrap_used, clippy::expect_used)]
#![cfg(feature = "board")]

mod common;

use common::Scratch;

use std::path::Path;
use std::process::{Command, Output};

use embusen::camera::Camera;
use embusen::camera::board::Board;
use embusen::camera::rotation::angle_between;
use glam::DVec3;
use serde_json::Value;

/// The shared scenes; the by-hand test keeps to the first four, the ones
/// its tolerance was set on (its four-point model has no lens distortion).
const SCENES: [&str; 7] = ["walk", "walk_turns", "run", "slash", "walk_toward", "shadow", "second_person"];

fn embusen(args: &[&str]) -> Output {
    Command::new(env!("CARGO_BIN_EXE_embusen")).args(args).output().expect("runs embusen")
}

fn text(bytes: &[u8]) -> String {
    String::from_utf8_lossy(bytes).into_owned()
}

/// Runs `embusen calibrate` and reads the camera it wrote.
fn calibrated(still: &Path, extra: &[&str], out: &Path) -> (Camera, String) {
    let mut args = vec!["calibrate", still.to_str().unwrap(), "-o", out.to_str().unwrap()];
    args.extend_from_slice(extra);
    let run = embusen(&args);
    let stdout = text(&run.stdout);
    assert!(run.status.success(), "{args:?}: {}{stdout}", text(&run.stderr));
    let written = std::fs::read_to_string(out).unwrap();
    (Camera::from_json(&written, &out.display().to_string()).unwrap(), stdout)
}

/// The count in "N of M corners found".
fn corners_found(stdout: &str) -> usize {
    let line = stdout.lines().find(|l| l.contains("corners found")).unwrap();
    line.split(": ").nth(1).unwrap().split(' ').next().unwrap().parse().unwrap()
}

#[test]
fn each_shared_board_gives_the_true_camera() {
    let Some(dir) = common::data_dir() else { return };
    let dir = dir.join("optical");
    let out = Scratch::new("pose");
    eprintln!("scene       corners  centre off (cm)  rotation off (°)  focal, one still (%)");
    for scene in SCENES {
        let still = dir.join(format!("{scene}.board.png"));
        let true_file = dir.join(format!("{scene}.camera.json"));
        let true_text = std::fs::read_to_string(&true_file).unwrap();
        let truth = Camera::from_json(&true_text, scene).unwrap();
        let recorded: Value = serde_json::from_str(&true_text).unwrap();
        let c: Vec<f64> = recorded["camera_center_world_cm"]
            .as_array()
            .unwrap()
            .iter()
            .map(|v| v.as_f64().unwrap())
            .collect();
        let true_centre = DVec3::new(c[0], c[1], c[2]);

        let (posed, stdout) = calibrated(
            &still,
            &["--intrinsics", true_file.to_str().unwrap()],
            &out.join(format!("{scene}.json")),
        );
        let corners = corners_found(&stdout);
        let centre_cm = (posed.center_in_world() - true_centre).length();
        let rotation_deg =
            angle_between(posed.camera_from_world.matrix3, truth.camera_from_world.matrix3).to_degrees();
        assert_eq!(posed.intrinsics, truth.intrinsics, "{scene}: the given lens is kept");

        let (lens, _) = calibrated(&still, &[], &out.join(format!("{scene}.lens.json")));
        let focal_pct = [truth.intrinsics.fx_px, truth.intrinsics.fy_px]
            .map(|f| 100.0 * (lens.intrinsics.fx_px / f - 1.0))
            .into_iter()
            .max_by(|a, b| a.abs().total_cmp(&b.abs()))
            .unwrap();
        eprintln!(
            "{scene:<11} {corners:>2}/24    {centre_cm:>10.3}      {rotation_deg:>10.4}      {focal_pct:>+10.2}"
        );
        // OpenCV's detector finds 10–24 corners here.
        assert!(corners >= 10, "{scene}: {corners} corners");
        // Measured: 0.01–0.07 cm, 0.002–0.013°, focal −0.2 to +0.9 %.
        assert!(centre_cm < 1.5, "{scene}: centre {centre_cm} cm off");
        assert!(rotation_deg < 0.3, "{scene}: rotation {rotation_deg}° off");
        assert!(focal_pct.abs() < 3.0, "{scene}: focal {focal_pct} % off");
    }
}

#[test]
fn each_shared_board_file_reads() {
    let Some(dir) = common::data_dir() else { return };
    for scene in SCENES {
        let path = dir.join(format!("optical/{scene}.board.json"));
        let board = Board::from_json(&std::fs::read_to_string(&path).unwrap(), scene).unwrap();
        assert_eq!((board.dictionary, board.squares_x, board.squares_y), ("DICT_4X4_50", 7, 5), "{scene}");
        assert_eq!(board.corner_in_world(23), Some(DVec3::new(180.0, 0.0, 120.0)), "{scene}");
    }
}

/// A plain grey PNG of `width × height`.
fn blank_png(path: &Path, width: u32, height: u32) {
    let file = std::fs::File::create(path).unwrap();
    let mut encoder = png::Encoder::new(std::io::BufWriter::new(file), width, height);
    encoder.set_color(png::ColorType::Grayscale);
    let pixels = vec![128u8; (width * height) as usize];
    encoder.write_header().unwrap().write_image_data(&pixels).unwrap();
}

const BOARD_JSON: &str = r#"{"dictionary": "DICT_4X4_50", "squares_x": 7, "squares_y": 5,
 "square_cm": 30.0, "marker_cm": 23.0, "legacy_pattern": false}"#;

#[test]
fn bad_input_is_a_clear_message() {
    let dir = Scratch::new("bad");
    let out = dir.join("camera.json");
    let fails = |args: &[&str]| {
        let run = embusen(args);
        assert!(!run.status.success(), "{args:?} succeeded");
        assert!(!out.exists(), "{args:?} wrote a camera");
        text(&run.stderr)
    };
    let o = out.to_str().unwrap();

    // A board that is not there: says how far the search got.
    let blank = dir.join("blank.board.png");
    blank_png(&blank, 160, 120);
    std::fs::write(dir.join("blank.board.json"), BOARD_JSON).unwrap();
    let e = fails(&["calibrate", blank.to_str().unwrap(), "-o", o]);
    assert!(e.contains("blank.board.png") && e.contains("0 markers"), "{e}");

    // Not a PNG.
    let junk = dir.join("junk.board.png");
    std::fs::write(&junk, b"not a picture").unwrap();
    std::fs::write(dir.join("junk.board.json"), BOARD_JSON).unwrap();
    let e = fails(&["calibrate", junk.to_str().unwrap(), "-o", o]);
    assert!(e.contains("junk.board.png") && e.contains("PNG"), "{e}");

    // A board file without a field, or none at all and no flags.
    let lacking = dir.join("lacking.board.png");
    blank_png(&lacking, 160, 120);
    std::fs::write(dir.join("lacking.board.json"), BOARD_JSON.replace(r#""marker_cm": 23.0, "#, "")).unwrap();
    let e = fails(&["calibrate", lacking.to_str().unwrap(), "-o", o]);
    assert!(e.contains("lacking.board.json:2:") && e.contains("marker_cm"), "{e}");
    let alone = dir.join("alone.png");
    blank_png(&alone, 160, 120);
    let e = fails(&["calibrate", alone.to_str().unwrap(), "-o", o]);
    assert!(e.contains("alone.json") && e.contains("--squares"), "{e}");
    let e = fails(&["calibrate", alone.to_str().unwrap(), "--squares", "7x5", "-o", o]);
    assert!(e.contains("--square-cm"), "{e}");
    let e = fails(&[
        "calibrate",
        alone.to_str().unwrap(),
        "--squares",
        "7x5",
        "--square-cm",
        "30",
        "--marker-cm",
        "40",
        "-o",
        o,
    ]);
    assert!(e.contains("marker_cm"), "{e}");
}

/// `embusen calibrate --floor-corners`, by hand: the board's outline (210 ×
/// 150 cm at the origin) projected with each true camera and given as four
/// clicks, with the true focal length and without. The four-point model has
/// no lens distortion nor principal-point offset, which these cameras have:
/// the centre comes back within a few centimetres, not to the board's mm.
#[test]
fn four_floor_corners_give_the_camera_by_hand() {
    let Some(data) = common::data_dir() else { return };
    let dir = Scratch::new("by-hand");
    for scene in &SCENES[..4] {
        let path = data.join("optical").join(format!("{scene}.camera.json"));
        let truth = Camera::from_json(&std::fs::read_to_string(&path).unwrap(), scene).unwrap();
        let clicks: Vec<String> = [(0.0, 0.0), (210.0, 0.0), (210.0, 150.0), (0.0, 150.0)]
            .map(|(x, z)| truth.point_in_image(DVec3::new(x, 0.0, z)).unwrap())
            .iter()
            .map(|p| format!("{},{}", p.x, p.y))
            .collect();
        let out = dir.join(format!("{scene}.camera.json"));
        let size = format!("{}x{}", truth.image_size.width_px, truth.image_size.height_px);
        let focal = truth.intrinsics.fx_px.to_string();
        let mut args = vec!["calibrate", "--floor-corners"];
        args.extend(clicks.iter().map(String::as_str));
        args.extend(["--rectangle-cm", "210x150", "--image-size", &size, "-o", out.to_str().unwrap()]);
        for extra in [vec!["--focal-px", focal.as_str()], vec![]] {
            let mut args = args.clone();
            args.extend(extra.iter().copied());
            let run = embusen(&args);
            assert!(run.status.success(), "{args:?}: {}", text(&run.stderr));
            let camera = Camera::from_json(&std::fs::read_to_string(&out).unwrap(), scene).unwrap();
            let off = (camera.center_in_world() - truth.center_in_world()).length();
            eprintln!("{scene} by hand {extra:?}: centre {off:.2} cm off");
            assert!(off < 10.0, "{scene} {extra:?}: centre {off:.2} cm off");
        }
    }
    // Three corners in a line are refused with a message.
    let run = embusen(&[
        "calibrate",
        "--floor-corners",
        "10,10",
        "20,20",
        "30,30",
        "10,40",
        "--rectangle-cm",
        "210x150",
        "--image-size",
        "640x480",
        "-o",
        dir.join("bad.json").to_str().unwrap(),
    ]);
    let said = text(&run.stderr);
    assert!(!run.status.success() && said.starts_with("error: floor rectangle"), "{said}");
}

/// A lens for another image size is refused, by `calibrate --intrinsics`
/// and by `track --board --intrinsics` alike (both go through
/// `app::calibration`, as the page does): an error naming the still,
/// never a camera posed with the wrong pixels.
#[test]
fn a_lens_of_another_size_is_refused_by_calibrate_and_track() {
    let Some(data) = common::data_dir() else { return };
    let optical = data.join("optical");
    let dir = Scratch::new("other-size");
    let mut lens: Value =
        serde_json::from_str(&std::fs::read_to_string(optical.join("walk.camera.json")).unwrap()).unwrap();
    lens["image_size"]["width"] = 320.into();
    let lens_path = dir.join("half.camera.json");
    std::fs::write(&lens_path, serde_json::to_string(&lens).unwrap()).unwrap();
    let (still, lens_arg) = (optical.join("walk.board.png"), lens_path.to_str().unwrap());
    let still = still.to_str().unwrap();
    let expected = format!("error: {still}: the still is 640×480 px, the intrinsics are for 320×480\n");

    let out = dir.join("camera.json");
    let run = embusen(&["calibrate", still, "--intrinsics", lens_arg, "-o", out.to_str().unwrap()]);
    assert!(!run.status.success() && !out.exists());
    assert_eq!(text(&run.stderr), expected);

    let (video, bvh) = (optical.join("walk.mp4"), optical.join("walk.suit.bvh"));
    let tracked = dir.join("tracked.bvh");
    let run = embusen(&[
        "track",
        video.to_str().unwrap(),
        "--bvh",
        bvh.to_str().unwrap(),
        "--board",
        still,
        "--intrinsics",
        lens_arg,
        "-o",
        tracked.to_str().unwrap(),
    ]);
    assert!(!run.status.success() && !tracked.exists());
    assert_eq!(text(&run.stderr), expected);
}
