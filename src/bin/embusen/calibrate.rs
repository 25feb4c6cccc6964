//! `embusen calibrate`: the camera from stills of a ChArUco board, written
//! as `camera.json`. One still goes the app's way
//! (`app::calibration`: the board found, then the camera fitted, a lens
//! checked against the still's size); several stills are Zhang's method
//! (`camera::calibrate::calibrate_views`), which the app does not offer; four
//! clicked floor corners are `camera::floor_rectangle`'s, as the app's.

use std::path::{Path, PathBuf};
use std::process::ExitCode;

use embusen::Error;
use embusen::app::calibration::{
    BoardInStill, calibrate_from_board_in_still, calibrate_from_still, find_board_in_still,
};
use embusen::app::tracking::NamedBytes;
use embusen::camera::board::Board;
use embusen::camera::calibrate::{BoardView, Calibration, LensFit, calibrate_views};
use embusen::camera::floor_rectangle::SOURCE;
use embusen::camera::rotation::rodrigues_from_rotation;
use embusen::camera::{Camera, FloorRectangle, FocalLength, ImageSize};
use embusen::io::image_file::png_to_grey;
use glam::DVec2;

#[derive(clap::Args)]
pub struct CalibrateArgs {
    /// Stills of the board (PNG). With --intrinsics, one; without, one (the
    /// principal point assumed at the image centre) or several views of the
    /// board (Zhang's method; the camera written is posed at the first).
    #[arg(required_unless_present = "floor_corners")]
    stills: Vec<PathBuf>,
    /// By hand instead of a board: the pixels of the four corners of a
    /// known rectangle on the floor, in the order origin, along world +X,
    /// the far corner, along world +Z (`X,Y X,Y X,Y X,Y`).
    #[arg(long, num_args = 4, value_name = "X,Y", value_parser = parse_pixel, requires = "rectangle_cm")]
    floor_corners: Vec<(f64, f64)>,
    /// The floor rectangle's size: along +X × along +Z (cm), e.g. 210x150.
    #[arg(long, value_name = "WxD", value_parser = parse_size_cm)]
    rectangle_cm: Option<(f64, f64)>,
    /// With --floor-corners and no still to read it from: the image's size (px).
    #[arg(long, value_name = "WxH", value_parser = parse_squares)]
    image_size: Option<(u32, u32)>,
    /// With --floor-corners: the focal length (px); without it or
    /// --hfov-deg, it is estimated from the four corners.
    #[arg(long)]
    focal_px: Option<f64>,
    /// With --floor-corners: the horizontal field of view (degrees).
    #[arg(long, conflicts_with = "focal_px")]
    hfov_deg: Option<f64>,
    /// The camera's lens, from a camera.json: only the pose is fitted.
    #[arg(long, value_name = "CAMERA.json")]
    intrinsics: Option<PathBuf>,
    /// Where to write the camera.json.
    #[arg(short, long, value_name = "CAMERA.json")]
    output: PathBuf,
    /// The board's layout, when there is no BOARD.json beside a still
    /// (`walk.board.png` → `walk.board.json`): its OpenCV dictionary.
    #[arg(long, default_value = "DICT_4X4_50")]
    dictionary: String,
    /// Squares across × down, as OpenCV's CharucoBoard((x, y), …): e.g. 7x5.
    #[arg(long, value_name = "XxY", value_parser = parse_squares)]
    squares: Option<(u32, u32)>,
    /// The side of a square (cm).
    #[arg(long)]
    square_cm: Option<f64>,
    /// The side of a marker (cm).
    #[arg(long)]
    marker_cm: Option<f64>,
    /// One still without --intrinsics: fit the radial k1 as well.
    #[arg(long)]
    fit_k1: bool,
}

fn parse_squares(text: &str) -> Result<(u32, u32), String> {
    let (x, y) =
        text.split_once(['x', 'X', '×']).ok_or_else(|| format!("expected XxY such as 7x5, not {text:?}"))?;
    let number =
        |s: &str| s.trim().parse::<u32>().map_err(|_| format!("expected XxY such as 7x5, not {text:?}"));
    Ok((number(x)?, number(y)?))
}

fn parse_pixel(text: &str) -> Result<(f64, f64), String> {
    let bad = || format!("expected a pixel X,Y such as 120.5,380, not {text:?}");
    let (x, y) = text.split_once(',').ok_or_else(bad)?;
    let number = |s: &str| s.trim().parse::<f64>().ok().filter(|v| v.is_finite()).ok_or_else(bad);
    Ok((number(x)?, number(y)?))
}

fn parse_size_cm(text: &str) -> Result<(f64, f64), String> {
    let bad = || format!("expected WxD in cm such as 210x150, not {text:?}");
    let (w, d) = text.split_once(['x', 'X', '×']).ok_or_else(bad)?;
    let number = |s: &str| s.trim().parse::<f64>().ok().filter(|v| v.is_finite()).ok_or_else(bad);
    Ok((number(w)?, number(d)?))
}

/// The camera from four clicked floor corners (`camera::floor_rectangle`).
fn calibrate_by_hand(args: &CalibrateArgs) -> Result<(), Error> {
    let size = match (args.image_size, args.stills.first()) {
        (Some((width_px, height_px)), _) => ImageSize { width_px, height_px },
        (None, Some(still)) => {
            let name = shown_path(still);
            let grey = png_to_grey(&read_still(still, &name)?, &name)?;
            ImageSize { width_px: grey.width_px, height_px: grey.height_px }
        }
        (None, None) => {
            return Err(Error::whole(SOURCE, "give --image-size (or a still to read it from)"));
        }
    };
    let (width_cm, depth_cm) = args.rectangle_cm.unwrap_or((0.0, 0.0));
    let corners: Vec<DVec2> = args.floor_corners.iter().map(|&(x, y)| DVec2::new(x, y)).collect();
    let corners: [DVec2; 4] =
        corners.try_into().map_err(|_| Error::whole(SOURCE, "give exactly four --floor-corners"))?;
    let focal = match (args.focal_px, args.hfov_deg) {
        (Some(px), _) => FocalLength::Px(px),
        (None, Some(deg)) => FocalLength::HorizontalFovDeg(deg),
        (None, None) => FocalLength::Unknown,
    };
    let fit = FloorRectangle { width_cm, depth_cm }.calibrate(size, corners, focal)?;
    let c = fit.camera.center_in_world();
    println!(
        "floor rectangle: reprojection error {:.3} px rms; camera centre (world, cm): {:.2} {:.2} {:.2}; focal {:.1} px",
        fit.reprojection_rms_px, c.x, c.y, c.z, fit.camera.intrinsics.fx_px
    );
    println!("  one pixel of click error moves the camera centre by {:.1} cm", fit.center_sigma_cm_per_px);
    let out = shown_path(&args.output);
    std::fs::write(&args.output, fit.camera.to_json())
        .map_err(|e| Error::whole(&out, format!("cannot write: {e}")))?;
    println!("wrote {out}");
    Ok(())
}

pub fn run(args: &CalibrateArgs) -> ExitCode {
    if !args.floor_corners.is_empty() {
        return match calibrate_by_hand(args) {
            Ok(()) => ExitCode::SUCCESS,
            Err(e) => {
                eprintln!("error: {e}");
                ExitCode::FAILURE
            }
        };
    }
    let flags = [args.squares.is_some(), args.square_cm.is_some(), args.marker_cm.is_some()];
    if flags.iter().any(|f| *f) && !flags.iter().all(|f| *f) {
        eprintln!("error: a board from flags needs --squares, --square-cm and --marker-cm together");
        return ExitCode::from(2);
    }
    if args.intrinsics.is_some() && args.stills.len() > 1 {
        eprintln!("error: with --intrinsics give one still: the camera written is posed at it");
        return ExitCode::from(2);
    }
    match calibrate(args) {
        Ok(()) => ExitCode::SUCCESS,
        Err(e) => {
            eprintln!("error: {e}");
            ExitCode::FAILURE
        }
    }
}

/// A still, its board and the corners found in it.
struct Seen {
    name: String,
    board: Board,
    found: BoardInStill,
}

fn calibrate(args: &CalibrateArgs) -> Result<(), Error> {
    let lens = match &args.intrinsics {
        Some(path) => {
            let name = shown_path(path);
            let text = std::fs::read_to_string(path)
                .map_err(|e| Error::whole(&name, format!("cannot read: {e}")))?;
            Some(Camera::from_json(&text, &name)?)
        }
        None => None,
    };
    let mut seen = Vec::new();
    for still in &args.stills {
        let name = shown_path(still);
        let board = board_for(still, args)?;
        let bytes = read_still(still, &name)?;
        let found = find_board_in_still(NamedBytes { name: &name, bytes: &bytes }, &board)?;
        let (detection, size) = (&found.detection, found.size);
        println!(
            "{name}: {} of {} corners found ({} markers decoded)",
            detection.corners.len(),
            board.corner_count(),
            detection.markers
        );
        if let Some(first) = seen.first().map(|s: &Seen| s.found.size)
            && first != size
        {
            return Err(Error::whole(
                &name,
                format!(
                    "{}×{} px, but the first still is {}×{}",
                    size.width_px, size.height_px, first.width_px, first.height_px
                ),
            ));
        }
        seen.push(Seen { name, board, found });
    }
    let fits = match &seen[..] {
        [one] => {
            let lens_fit = LensFit { k1: args.fit_k1 };
            vec![calibrate_from_board_in_still(&one.name, &one.board, &one.found, lens.as_ref(), lens_fit)?]
        }
        [first, ..] => {
            let views: Vec<BoardView> = seen
                .iter()
                .map(|s| BoardView { file: &s.name, board: &s.board, corners: &s.found.detection.corners })
                .collect();
            calibrate_views(&views, first.found.size)?
        }
        [] => return Err(Error::whole("<calibrate>", "no board still to calibrate from")),
    };
    for (still, fit) in seen.iter().zip(&fits) {
        report(&still.name, fit, lens.is_none());
    }
    let camera = &fits[0].camera;
    let out = shown_path(&args.output);
    std::fs::write(&args.output, camera.to_json())
        .map_err(|e| Error::whole(&out, format!("cannot write: {e}")))?;
    println!("wrote {out}");
    Ok(())
}

fn report(name: &str, fit: &Calibration, lens_fitted: bool) {
    let c = fit.camera.center_in_world();
    let r = rodrigues_from_rotation(fit.camera.camera_from_world.matrix3);
    println!(
        "{name}: reprojection error {:.3} px rms, {:.3} px max over {} corners",
        fit.rms_px, fit.max_px, fit.corners
    );
    println!(
        "  camera centre (world, cm): {:.2} {:.2} {:.2}; rvec {:.5} {:.5} {:.5}",
        c.x, c.y, c.z, r.x, r.y, r.z
    );
    if lens_fitted {
        let k = fit.camera.intrinsics;
        let d = fit.camera.distortion;
        println!(
            "  lens: fx {:.2} fy {:.2} cx {:.2} cy {:.2} px; k1 {:.4} k2 {:.4}",
            k.fx_px, k.fy_px, k.cx_px, k.cy_px, d.k1, d.k2
        );
    }
}

/// The camera from one still of a board whose layout is in `BOARD.json`
/// beside it: posed with `lens`, or with the focal length estimated (the
/// principal point at the image's centre) without one.
/// As the app's [`calibrate_from_still`], so a lens of another image size is
/// refused.
pub fn camera_from_still(still: &Path, lens: Option<&Camera>) -> Result<Camera, Error> {
    let name = shown_path(still);
    let board = board_beside(still)?;
    let bytes = read_still(still, &name)?;
    Ok(calibrate_from_still(NamedBytes { name: &name, bytes: &bytes }, &board, lens)?.calibration.camera)
}

/// The still's board: from the flags when given, else `BOARD.json` beside
/// it (`walk.board.png` → `walk.board.json`).
fn board_for(still: &Path, args: &CalibrateArgs) -> Result<Board, Error> {
    if let (Some((x, y)), Some(square_cm), Some(marker_cm)) = (args.squares, args.square_cm, args.marker_cm) {
        return Board::on_floor(&args.dictionary, x, y, square_cm, marker_cm, "board flags");
    }
    board_beside(still)
}

/// The board of `BOARD.json` beside a still.
fn board_beside(still: &Path) -> Result<Board, Error> {
    let json = board_json_path(still);
    let name = shown_path(&json);
    let text = std::fs::read_to_string(&json).map_err(|e| {
        Error::whole(
            &name,
            format!("cannot read the board's layout ({e}); give --squares, --square-cm, --marker-cm (and --dictionary)"),
        )
    })?;
    Board::from_json(&text, &name)
}

fn board_json_path(still: &Path) -> PathBuf {
    let mut stem = still.as_os_str().to_owned();
    if still.extension().is_some_and(|e| e.eq_ignore_ascii_case("png")) {
        stem = still.with_extension("").into_os_string();
    }
    stem.push(".json");
    PathBuf::from(stem)
}

/// A path as the messages show it: whole, as the user gave it.
fn shown_path(path: &Path) -> String {
    path.display().to_string()
}

/// The bytes of the still at `path` (`name` in errors).
fn read_still(path: &Path, name: &str) -> Result<Vec<u8>, Error> {
    std::fs::read(path).map_err(|e| Error::whole(name, format!("cannot read: {e}")))
}
