// @ts-check
// The take's camera calibrated here, as `embusen calibrate` makes it: from
// a board (its still, or the video frame shown) with the board module, or
// from four floor corners clicked on the video with the camera module. The
// camera found becomes the take's; the one before is kept when it fails.

import { loadBoardModule, loadCameraModule } from "./modules.js";
import { frameStill } from "./stills.js";

/** @typedef {import("./inputs.js").TakeInputs} TakeInputs */
/** @typedef {import("./inputs.js").FileBytes} FileBytes */
/** @typedef {import("../pkg-camera/embusen.js").PixelPoint} PixelPoint */

/** The corners asked for, in order. */
export const CORNER_NAMES = ["the origin", "along +x", "the far corner", "along +z"];

/**
 * A camera calibrated here, as the take's camera.
 * @param {string} name
 * @param {string} json
 */
const cameraHere = (name, json) => ({ name, bytes: /** @type {ArrayBuffer} */ (new TextEncoder().encode(json).buffer), calibratedHere: true });

/**
 * Finds the board in its still (else in the video frame `shownFrame`) and
 * calibrates the camera from it, with the lens of a camera.json the user
 * opened when there is one; the camera found is the take's.
 * @param {TakeInputs} inputs
 * @param {number} shownFrame
 * @returns {Promise<{outcome: {rmsPx: number, maxPx: number, corners: number, camera: string}, found: PixelPoint[], said: string}>}
 */
export async function calibrateFromBoard(inputs, shownFrame) {
  // The view selected now: another may be selected before the board is found.
  const view = inputs.view;
  const { boardLayout, video } = view;
  const lens = view.camera?.calibratedHere ? undefined : view.camera;
  if (!boardLayout || !(view.board || video)) throw new Error("open the board's layout (BOARD.json) and a still of the board or a video showing it first");
  // Without a still, the video frame shown, read exactly.
  const still = view.board ?? (await frameStill(/** @type {NonNullable<typeof video>} */ (video), shownFrame));
  const m = await loadBoardModule();
  const fit = m.calibrate_board({ still, board: boardLayout, lens: lens ?? null });
  view.camera = cameraHere(`camera.json (from ${still.name})`, fit.camera_json);
  const maxPx = fit.max_px ?? fit.rms_px;
  return {
    outcome: { rmsPx: fit.rms_px, maxPx, corners: fit.corners.length, camera: fit.camera_json }, found: fit.corners,
    said: `calibrated from ${still.name}: ${fit.corners.length} corners, reprojection error ${fit.rms_px.toFixed(2)} px ` +
      `(rms; largest ${maxPx.toFixed(2)} px)` + (lens ? `, with the lens of ${lens.name}` : ", focal length from this view"),
  };
}

/**
 * The camera from four floor corners clicked on the video (`embusen
 * calibrate --floor-corners`); the take's camera.
 * @param {TakeInputs} inputs
 * @param {PixelPoint[]} clicked
 * @param {string} rectangle the rectangle's size, "WIDTHxDEPTH" in cm
 * @param {string} focal the focal length (px), or empty to estimate it
 */
export async function calibrateFromCorners(inputs, clicked, rectangle, focal) {
  const view = inputs.view; // the view selected now, as above
  const video = view.video;
  if (!video || clicked.length !== 4) throw new Error("click the four floor corners first");
  const size = /^\s*([\d.]+)\s*[x×]\s*([\d.]+)\s*$/.exec(rectangle);
  if (!size) throw new Error(`the rectangle "${rectangle}": give its size as WIDTHxDEPTH in cm, e.g. 200x150`);
  const focalPx = focal.trim() === "" ? null : Number(focal);
  if (focalPx !== null && !(focalPx > 0)) throw new Error(`the focal length "${focal}": a number of pixels, or empty to estimate it`);
  const m = await loadCameraModule();
  const fit = m.calibrate_floor_corners({
    width_px: video.element.videoWidth, height_px: video.element.videoHeight, corners: clicked,
    width_cm: Number(size[1]), depth_cm: Number(size[2]), focal_px: focalPx,
  });
  const outcome = {
    rmsPx: fit.rms_px, centerSigmaCmPerPx: fit.center_sigma_cm_per_px ?? NaN, focalPx: fit.focal_px, camera: fit.camera_json,
    cornersPx: clicked.flatMap((p) => [p.x_px, p.y_px]),
  };
  view.camera = cameraHere("camera.json (from 4 floor corners)", fit.camera_json);
  const said = `calibrated from 4 floor corners: reprojection error ${outcome.rmsPx.toFixed(2)} px (rms), focal length ` +
    `${outcome.focalPx.toFixed(0)} px; a pixel of click error moves the camera ${outcome.centerSigmaCmPerPx.toFixed(1)} cm: check the grid`;
  return { outcome, said };
}
