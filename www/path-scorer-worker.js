// @ts-check
// The path scorer's Web Worker, started by the tracker's (./track-worker.js)
// for the fused tracker: a second CameraJob of the same take that scores the
// path search's energies of each frame the tracker hands over, from the
// features the tracker made of it — the same bytes as the tracker scoring
// them itself. Its
// messages are typed in ./camera/protocol.js (`ToScorer`, `FromScorer`); any
// other is an error, after which it takes nothing more.

import init, { CameraJob } from "./pkg-camera/embusen.js";
import { unexpected } from "./camera/protocol.js";
import { messageOf } from "./files.js";

/** @typedef {import("./camera/protocol.js").ToScorer} ToScorer */
/** @typedef {import("./camera/protocol.js").FromScorer} FromScorer */

/** The worker's own postMessage (the DOM types only know the window's). @param {FromScorer} m */
const post = (m) => /** @type {{postMessage: (m: FromScorer) => void}} */ (/** @type {unknown} */ (self)).postMessage(m);
const ready = init({ module_or_path: new URL("./pkg-camera/embusen_bg.wasm", import.meta.url) });

/** @type {CameraJob | null} */
let job = null;
let failed = false;

/** @param {ToScorer} m */
async function handle(m) {
  if (failed) return;
  await ready;
  switch (m.type) {
    case "open":
      job = new CameraJob(m.take);
      return;
    case "score": {
      if (!job) throw new Error("a path to score before the take was opened");
      const started = performance.now();
      const energies = job.score_path(m.work, new Uint8Array(m.features));
      post({ type: "energies", frame: m.work.frame, energies, ms: performance.now() - started });
      return;
    }
    default:
      throw unexpected("the path scorer", m);
  }
}

// Messages are handled one after another: a frame never overtakes the open.
let queue = Promise.resolve();
self.onmessage = (event) => {
  queue = queue.then(() => handle(/** @type {ToScorer} */ (event.data))).catch((e) => {
    failed = true;
    job?.free();
    job = null;
    post({ type: "error", message: messageOf(e) });
  });
};
