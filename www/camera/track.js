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
/** @typedef {import("./inputs.js").TakeVideo} TakeVideo */

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
 * @property {number} [offsetEstimateS] the time offset estimated after the track, when asked for (the first view's)
 * @property {number} [views] the cameras the take was tracked from
 */

/**
 * Tracks the panel's take, each of its views (cameras) in its own worker,
 * then, with several, the first view's track weighed with the others' in
 * the first's worker; resolves with the result, rejects with the message
 * the page shows (the inputs are kept either way).
 * @param {CameraPanel} panel
 * @returns {Promise<TrackResult>}
 */
export async function trackTake(panel) {
  const { inputs, ui, plots } = panel;
  const recording = inputs.recording;
  // The views as they are now: one added while this runs waits for the next track.
  const views = [...inputs.tracked];
  const several = views.length > 1;
  if (!recording || views.some((v) => !v.video || !v.camera)) {
    throw new Error(several ? "open the BVH and each view's video and camera.json first" : "open a video, its BVH and a camera.json first");
  }
  const viewSaid = (/** @type {number} */ k) => (several ? `view ${k + 1} (${views[k].video?.name}): ` : "");
  for (const [k, view] of views.entries()) {
    const video = /** @type {TakeVideo} */ (view.video);
    view.background ??= await medianStill(video, (t) => panel.say(viewSaid(k) + t));
  }
  ui.exportRecording.disabled = ui.exportTrack.disabled = true;
  ui.track.disabled = true;
  ui.cancel.disabled = false;
  const progress = views.map((v) => ({ done: 0, of: v.video?.frameCount ?? 1 }));
  const runs = views.map((_, k) => new TrackerRun((opened) => {
    progress[k].of = opened.video.frame_count;
    if (opened.warnings.length > 0) panel.say(opened.warnings.map((w) => viewSaid(k) + w).join("; "));
  }, (p) => {
    progress[k].done = p.frame + 1;
    if (k === 0) plots.path.push(p);
    // The page is redrawn a few times a second, not every frame: each
    // repaint is composited in software, taken from the workers' cores.
    if (p.frame % 10 !== 0) return;
    const [done, of] = progress.reduce(([d, o], q) => [d + q.done, o + q.of], [0, 0]);
    ui.progress.value = done / of;
    void plots.paintTop();
    panel.paintPlots();
    panel.say(`tracking: frame ${done} of ${of}` + (several ? ` (${views.length} views)` : ""));
  }));
  panel.run = { cancel: (e) => runs.forEach((r) => r.cancel(e)), terminate: () => runs.forEach((r) => r.terminate()) };
  const started = performance.now();
  try {
    const method = /** @type {import("./protocol.js").TakeOptions["method"]} */ (ui.method.value);
    const truth = inputs.truth ? copyOf(inputs.truth) : null;
    const tracked = await Promise.all(runs.map(async (run, k) => {
      const view = views[k];
      const video = /** @type {TakeVideo} */ (view.video);
      const take = { recording: copyOf(recording), camera: copyOf(/** @type {FileBytes} */ (view.camera)),
        background: copyOf(/** @type {FileBytes} */ (view.background)), video: factsOf(video), method, offset_s: view.offsetS() };
      // A truth is of the first view's frames: the track is on them.
      return run.run({ type: "open", take, videoBytes: await video.file.arrayBuffer(), estimateOffset: ui.estimateOffset.checked,
        truth: k === 0 ? truth : null }, video);
    }));
    const { opened, done: first, readMs } = tracked[0];
    // The weighed track replaces the first view's alone; its timings stay.
    /** @type {Done} */
    const done = several ? { ...first, ...(await runs[0].weigh(tracked.slice(1).map((t) => t.done.view))), type: "done" } : first;
    ui.progress.value = 1;
    const result = resultOf(opened, done, readMs, (performance.now() - started) / 1000);
    await showTrack(panel, done);
    // A truth shorter than the video: its missing frames have no error.
    const errorCm = done.errors ? Array.from(done.series.recording_time_s, (_, i) => done.errors?.per_frame_cm[i] ?? NaN) : [];
    const series = { ...done.series, error_cm: errorCm, truth_name: errorCm.length > 0 ? inputs.truth?.name ?? "" : "" };
    await showInPlayer(panel, recording, /** @type {FileBytes} */ (views[0].camera), done.trackedHipsCm, series);
    const warnings = [...done.files.warnings, ...tracked.slice(1).flatMap((t, k) => t.done.files.warnings.map((/** @type {string} */ w) => viewSaid(k + 1) + w))];
    panel.say(statusOf(panel, result, tracked.map((t) => t.done), warnings));
    ui.exportRecording.disabled = ui.exportTrack.disabled = false;
    return { ...result, warnings, views: views.length };
  } finally {
    runs.forEach((r) => r.terminate());
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
 * The finished track over the videos and in the plots: the first view's
 * outlines as its track has them, each other view's where the corrected
 * recording (`done.files`, the one track of all the views) puts the body
 * as its camera sees it.
 * @param {CameraPanel} panel
 * @param {Pick<Done, "outlines" | "candidates" | "errors"> & {files: {recording_text: string}}} done
 */
async function showTrack(panel, done) {
  const { plots, inputs } = panel;
  panel.panes[0].outlines = done.outlines;
  const recording = { name: inputs.recording?.name ?? "the take", bytes: new TextEncoder().encode(done.files.recording_text) };
  for (const [k, view] of inputs.tracked.entries()) {
    if (k === 0 || !view.video || !view.camera) continue;
    panel.paneOf(k).outlines = await otherViewOutlines(recording, view);
  }
  plots.candidates = done.candidates.every((c) => c.tried.length === 0) ? [] : done.candidates;
  plots.errors = done.errors;
  plots.truthName = inputs.truth?.name ?? "the truth";
  void panel.drawOverlay();
  panel.paintPlots();
  void plots.paintTop();
}

/**
 * A view other than the first's outlines where the corrected `recording`
 * puts the body (`FinishedTakeView` with no track).
 * @param {{name: string, bytes: Uint8Array}} recording
 * @param {import("./inputs.js").ViewInputs} view
 */
async function otherViewOutlines(recording, view) {
  const m = await loadCameraModule();
  const video = /** @type {TakeVideo} */ (view.video);
  const taken = new m.FinishedTakeView({ recording, camera: copyOf(/** @type {FileBytes} */ (view.camera)), track: null,
    video: factsOf(video), offset_s: view.offsetS() });
  try {
    return taken.outlines_px();
  } finally {
    taken.free();
  }
}

/**
 * What the status line says of a finished track; an estimated offset worth
 * tracking again with is put in its view's offset (the CLI does it itself).
 * @param {CameraPanel} panel
 * @param {TrackResult} result
 * @param {Done[]} dones each view's
 * @param {string[]} warnings
 */
function statusOf(panel, result, dones, warnings) {
  const { ui, inputs } = panel;
  const several = dones.length > 1;
  const offsetSaid = dones.map((done, k) => {
    const view = inputs.views[k];
    const of = several ? `view ${k + 1}'s ` : "";
    if (!done.offset) return done.offsetProblem ? `; ${of}${done.offsetProblem}` : "";
    const estimate = done.offset.offset_s;
    let said = `; ${of}estimated offset: the BVH runs ${estimate.toFixed(3)} s ahead of the video`;
    if (view.video && Math.abs(estimate - view.offsetS()) * view.video.fps > 0.5) {
      view.offsetText = String(estimate);
      said += " (now in the offset field: track again to use it)";
    }
    return said;
  }).join("");
  ui.offset.value = inputs.view.offsetText;
  const e = result.truthErrors;
  const truthSaid = e
    ? `; against ${inputs.truth?.name}: mean ${e.meanCm.toFixed(1)} cm, p90 ${e.p90Cm.toFixed(1)}, max ${e.maxCm.toFixed(1)}`
    : dones[0].truthProblem ? `; ${dones[0].truthProblem}` : "";
  const fromVideo = inputs.views.filter((v) => v.background?.fromVideo).map((v) => `; no background still: ${v.background?.name} stands for the empty room`);
  return `${ui.method.value}: ${dones[0].frames} frames tracked${several ? ` by ${dones.length} cameras` : ""}, ` +
    `${result.framesPerSecond.toFixed(1)} frames per second` +
    truthSaid + offsetSaid + (warnings.length > 0 ? `; ${warnings.join("; ")}` : "") + fromVideo.join("");
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
 * Shows a take tracked before (its corrected BVH, its track CSV, and per
 * view its camera and its video) as a track just finished shows, with no
 * tracking: the outlines over each video, the plots, the take in the
 * player. Rejects with the message the page shows when the files are not
 * one take's.
 * @param {CameraPanel} panel
 */
export async function showFinishedTake(panel) {
  const { inputs, plots } = panel;
  const { recording, track, tracked: views } = inputs;
  const { video, camera } = views[0];
  if (!video || !recording || !camera || !track || views.some((v) => !v.video || !v.camera)) {
    throw new Error("open the tracked BVH, its track CSV, and each view's video and camera.json");
  }
  const m = await loadCameraModule();
  const view = new m.FinishedTakeView({ recording: copyOf(recording), camera: copyOf(camera), track: copyOf(track),
    video: factsOf(video), offset_s: views[0].offsetS() });
  try {
    plots.clear();
    plots.path = view.path();
    const text = new TextDecoder().decode(recording.bytes);
    await showTrack(panel, { outlines: view.outlines_px(), candidates: [], errors: null, files: { recording_text: text } });
    await showInPlayer(panel, recording, camera, view.tracked_hips_cm(), view.take_series());
  } finally {
    view.free();
  }
  const by = views.length > 1 ? ` by ${views.length} cameras` : "";
  panel.say(`${track.name}: ${video.frameCount} frames tracked${by} before, shown as they are (Track tracks the take again)`);
}
