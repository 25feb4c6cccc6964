// @ts-check
// Tracking the panel's take: the background (a still, or the median of the
// video's frames), the run in the tracker's worker with the track drawn as
// it grows, then what it found: the outlines, the candidates, the error
// against a truth, the offset estimated, the take in the player, and the
// status line that says it all.

import { loadCameraModule } from "./modules.js";
import { copyOf, textOf } from "./inputs.js";
import { medianStill, factsOf } from "./stills.js";
import { TrackerRun } from "./tracker-client.js";

/** @typedef {import("../camera.js").CameraPanel} CameraPanel */
/** @typedef {import("./protocol.js").Done} Done */
/** @typedef {import("./protocol.js").Opened} Opened */
/** @typedef {import("./inputs.js").FileBytes} FileBytes */

/**
 * @typedef {object} TrackResult
 * @property {string} recording the corrected recording's text
 * @property {string} csv the hips per video frame
 * @property {string[]} warnings
 * @property {number} frames
 * @property {number} framesPerSecond tracked frames per second of wall time, frame reading included
 * @property {number} readMsPerFrame reading a frame: decoding and copying its luma plane in the worker, or a seek here
 * @property {number} trackMsPerFrame the worker's tracking per frame
 * @property {number} scoreMsPerFrame the second worker's scoring of the path search per frame (0 with one)
 * @property {number} workers the workers that tracked: 2 for `fused` (the path search's energies in the second), 1 for `paper`
 * @property {boolean} decodedInWorker whether the worker decoded the frames itself (WebCodecs)
 * @property {string | null} whyNotDecoded why not, when it did not
 * @property {{meanCm: number, p90Cm: number, maxCm: number} | null} truthErrors against the truth, when given
 * @property {number} [offsetEstimateS] the time offset estimated after the track, when asked for
 */

/**
 * Tracks the panel's take; resolves with the result, rejects with the
 * message the page shows (the inputs are kept either way).
 * @param {CameraPanel} panel
 * @returns {Promise<TrackResult>}
 */
export async function trackTake(panel) {
  const { inputs, ui, plots } = panel;
  const { video, recording, camera } = inputs;
  if (!video || !recording || !camera) throw new Error("open a video, its BVH and a camera.json first");
  const background = inputs.background ?? (inputs.background = await medianStill(video, (t) => panel.say(t)));
  ui.exportRecording.disabled = ui.exportTrack.disabled = true;
  ui.track.disabled = true;
  ui.cancel.disabled = false;
  let frameCount = video.frameCount;
  const run = new TrackerRun((opened) => {
    frameCount = opened.video.frame_count;
    if (opened.warnings.length > 0) panel.say(opened.warnings.join("; "));
  }, (progress) => {
    plots.path.push(progress);
    // The page is redrawn a few times a second, not every frame: each
    // repaint is composited in software, taken from the worker's core.
    if (progress.frame % 10 === 0) {
      ui.progress.value = (progress.frame + 1) / frameCount;
      void plots.paintTop();
      panel.paintPlots();
      panel.say(`tracking: frame ${progress.frame + 1} of ${frameCount}`);
    }
  });
  panel.run = run;
  const started = performance.now();
  try {
    const offsetS = panel.offsetS();
    const method = /** @type {import("./protocol.js").TakeOptions["method"]} */ (ui.method.value);
    const take = { recording: copyOf(recording), camera: copyOf(camera), background: copyOf(background), video: factsOf(video), method, offset_s: offsetS };
    const videoBytes = await video.file.arrayBuffer();
    const truth = inputs.truth ? copyOf(inputs.truth) : null;
    const { opened, done, readMs } = await run.run({ type: "open", take, videoBytes, estimateOffset: ui.estimateOffset.checked, truth }, video);
    ui.progress.value = 1;
    const result = resultOf(opened, done, readMs, (performance.now() - started) / 1000);
    showTrack(panel, done);
    // A truth shorter than the video: its missing frames have no error.
    const errorCm = done.errors ? Array.from(done.series.recording_time_s, (_, i) => done.errors?.per_frame_cm[i] ?? NaN) : [];
    const series = { ...done.series, error_cm: errorCm, truth_name: errorCm.length > 0 ? inputs.truth?.name ?? "" : "" };
    await showInPlayer(panel, recording, camera, done.trackedHipsCm, series);
    panel.say(statusOf(panel, result, done, offsetS, background));
    ui.exportRecording.disabled = ui.exportTrack.disabled = false;
    return result;
  } finally {
    run.terminate();
  }
}

/**
 * The result the handle gives.
 * @param {Opened} opened
 * @param {Done} done
 * @param {number} readMs the time spent reading frames here
 * @param {number} seconds the whole run's
 * @returns {TrackResult}
 */
function resultOf(opened, done, readMs, seconds) {
  const e = done.errors;
  return {
    recording: done.files.recording_text, csv: done.files.track_csv, warnings: done.files.warnings, frames: done.frames,
    framesPerSecond: done.frames / seconds, readMsPerFrame: opened.decodes ? done.decodeMsPerFrame : readMs / done.frames,
    trackMsPerFrame: done.msPerFrame, scoreMsPerFrame: done.scoreMsPerFrame, workers: opened.workers,
    decodedInWorker: opened.decodes, whyNotDecoded: opened.why ?? null,
    truthErrors: e ? { meanCm: e.mean_cm, p90Cm: e.p90_cm, maxCm: e.max_cm } : null,
    ...(done.offset ? { offsetEstimateS: done.offset.offset_s } : {}),
  };
}

/**
 * The finished track over the video and in the plots.
 * @param {CameraPanel} panel
 * @param {Pick<Done, "outlines" | "candidates" | "errors">} done
 */
function showTrack(panel, done) {
  const { plots } = panel;
  panel.outlines = done.outlines;
  plots.candidates = done.candidates.every((c) => c.tried.length === 0) ? [] : done.candidates;
  plots.errors = done.errors;
  plots.truthName = panel.inputs.truth?.name ?? "the truth";
  void panel.drawOverlay();
  panel.paintPlots();
  void plots.paintTop();
}

/**
 * What the status line says of a finished track; an estimated offset worth
 * tracking again with is put in the offset field (the CLI does it itself).
 * @param {CameraPanel} panel
 * @param {TrackResult} result
 * @param {Done} done
 * @param {number} offsetS the offset tracked with
 * @param {FileBytes & {fromVideo?: boolean}} background
 */
function statusOf(panel, result, done, offsetS, background) {
  const { ui, inputs } = panel;
  let offsetSaid = done.offsetProblem ? `; ${done.offsetProblem}` : "";
  if (done.offset) {
    const estimate = done.offset.offset_s;
    offsetSaid = `; estimated offset: the BVH runs ${estimate.toFixed(3)} s ahead of the video`;
    if (inputs.video && Math.abs(estimate - offsetS) * inputs.video.fps > 0.5) {
      ui.offset.value = String(estimate);
      offsetSaid += " (now in the offset field: track again to use it)";
    }
  }
  const e = result.truthErrors;
  const truthSaid = e
    ? `; against ${inputs.truth?.name}: mean ${e.meanCm.toFixed(1)} cm, p90 ${e.p90Cm.toFixed(1)}, max ${e.maxCm.toFixed(1)}`
    : done.truthProblem ? `; ${done.truthProblem}` : "";
  const warnings = done.files.warnings;
  return `${ui.method.value}: ${done.frames} frames tracked, ${result.framesPerSecond.toFixed(1)} frames per second` +
    truthSaid + offsetSaid + (warnings.length > 0 ? `; ${warnings.join("; ")}` : "") +
    (background.fromVideo ? `; no background still: ${background.name} stands for the empty room` : "");
}

/**
 * Shows a tracked take in the panel's player (`options.player`): its
 * recording opened there (unless it is already), then the body at the
 * camera track, the camera and the paths in its 3D view.
 * @param {CameraPanel} panel
 * @param {FileBytes} recording
 * @param {FileBytes} camera
 * @param {ArrayLike<number>} trackedHipsCm per recording frame x, y, z (cm)
 * @param {import("./protocol.js").TakeSeries} series per video frame, for the player's plots
 */
async function showInPlayer(panel, recording, camera, trackedHipsCm, series) {
  const player = panel.options.player;
  if (!player) return;
  try {
    if (player.player.info().name !== recording.name) {
      await player.open([new File([recording.bytes], recording.name)]);
    }
    const m = await loadCameraModule();
    const view = new m.CameraView(camera.name, textOf(camera));
    // The frustum reaches a metre ahead: the camera's size in the room's scale.
    const frustumCm = view.frustum_cm(100);
    view.free();
    player.showCameraTake({ cameraHipsCm: trackedHipsCm, frustumCm, series });
  } catch {
    // The player says what went wrong in its own error box; the track stands.
  }
}

/**
 * Shows a take tracked before (its corrected BVH, its track CSV, its camera
 * and its video) as a track just finished shows, with no tracking: the
 * outlines over the video, the plots, the take in the player. Rejects with
 * the message the page shows when the files are not one take's.
 * @param {CameraPanel} panel
 */
export async function showFinishedTake(panel) {
  const { inputs, plots } = panel;
  const { video, recording, camera, track } = inputs;
  if (!video || !recording || !camera || !track) throw new Error("open a video, its tracked BVH, its track CSV and a camera.json");
  const m = await loadCameraModule();
  const offsetS = panel.offsetS();
  const view = new m.FinishedTakeView({ recording: copyOf(recording), camera: copyOf(camera), track: copyOf(track), video: factsOf(video), offset_s: offsetS });
  try {
    plots.clear();
    plots.path = view.path();
    showTrack(panel, { outlines: view.outlines_px(), candidates: [], errors: null });
    await showInPlayer(panel, recording, camera, view.tracked_hips_cm(), view.take_series());
  } finally {
    view.free();
  }
  panel.say(`${track.name}: ${video.frameCount} frames tracked before, shown as they are (Track tracks the take again)`);
}
