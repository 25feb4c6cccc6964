// @ts-check
// The camera tracker's Web Worker: it owns one wasm CameraJob (src/web/tracking.rs)
// so the page stays responsive while frames are tracked. Messages in:
//   {type: "open", recording, camera, background: {name, bytes}, video: {name, width, height, fps, frameCount}, method, offsetS}
//   {type: "frame", luma: ArrayBuffer, stride, fullRange}     (any number, in order)
//   {type: "finish"}
// Messages out: {type: "opened", warnings}, {type: "progress", frame, x, z, confidence},
// {type: "done", recording, csv, warnings, msPerFrame}, {type: "error", message}.
// After an error the worker takes nothing more: the page starts a new one.

import init, { CameraJob } from "./pkg-camera/embusen.js";

/** @type {CameraJob | null} */
let job = null;
let failed = false;
let busyMs = 0;
/** The worker's own postMessage (the DOM types only know the window's). @param {any} m */
const post = (m) => /** @type {any} */ (self).postMessage(m);
const ready = init({ module_or_path: new URL("./pkg-camera/embusen_bg.wasm", import.meta.url) });

/** @param {unknown} e */
function fail(e) {
  failed = true;
  job?.free();
  job = null;
  post({ type: "error", message: e instanceof Error ? e.message : String(e) });
}

// Messages are handled one after another: a frame never overtakes the open.
let queue = Promise.resolve();
self.onmessage = (event) => {
  queue = queue.then(() => handle(event.data)).catch(fail);
};

/** @param {any} m */
async function handle(m) {
  if (failed) return;
  await ready;
  if (m.type === "open") {
    const v = m.video;
    job = new CameraJob(
      m.recording.name, new Uint8Array(m.recording.bytes),
      m.camera.name, new Uint8Array(m.camera.bytes),
      m.background.name, new Uint8Array(m.background.bytes),
      v.name, v.width, v.height, v.fps, v.frameCount, m.method, m.offsetS,
    );
    busyMs = 0;
    post({ type: "opened", warnings: job.warnings() });
  } else if (m.type === "frame") {
    if (!job) throw new Error("a frame before the take was opened");
    const started = performance.now();
    const frame = job.frames_done();
    const [x, z, confidence] = job.push_luma(new Uint8Array(m.luma), m.stride, m.fullRange);
    busyMs += performance.now() - started;
    post({ type: "progress", frame, x, z, confidence });
  } else if (m.type === "finish") {
    if (!job) throw new Error("nothing to finish: the take was not opened");
    const frames = job.frames_done();
    const started = performance.now();
    job.finish();
    busyMs += performance.now() - started;
    post({
      type: "done", recording: job.recording_text(), csv: job.track_csv(), warnings: job.warnings(),
      msPerFrame: busyMs / Math.max(1, frames),
    });
    job.free();
    job = null;
  }
}
