// @ts-check
// The camera tracker's Web Worker: it owns one wasm CameraJob (src/web/tracking.rs)
// so the page stays responsive while frames are tracked. Where it can read the
// video's container (io::container: MP4/MOV, WebM/Matroska) and the browser
// has a WebCodecs decoder for its codec, it decodes the frames itself, each
// once and in order (./camera/decode.js); else the page sends them, read a
// seek each. Its messages are typed in ./camera/protocol.js (`ToTracker`,
// `FromTracker`); any other is an error. After an error it takes nothing
// more: the page starts a new one.
//
// A finished take stays open until the worker is let go: a take filmed by
// several cameras is weighed in the first view's worker (`weigh`), each
// other view's track sent there from its own.
//
// For the fused tracker it starts a second worker (./path-scorer-worker.js)
// with the same take: half the tracker's work (the path search's energies,
// CameraJob.defer_path_energies) is done there, from the frame's features
// this one made, while this one reads the next — two cores for one take,
// the same bytes.

import init, { CameraJob } from "./pkg-camera/embusen.js";
import { decodable, decodeFrames } from "./camera/decode.js";
import { unexpected } from "./camera/protocol.js";
import { messageOf } from "./files.js";

/** @typedef {import("./camera/protocol.js").ToTracker} ToTracker */
/** @typedef {import("./camera/protocol.js").FromTracker} FromTracker */
/** @typedef {import("./camera/protocol.js").ToScorer} ToScorer */
/** @typedef {import("./camera/protocol.js").FromScorer} FromScorer */
/** @typedef {Extract<ToTracker, {type: "open"}>} Open */

/** The worker's own postMessage (the DOM types only know the window's). @param {FromTracker} m @param {Transferable[]} [transfer] */
const post = (m, transfer = []) => /** @type {{postMessage: (m: FromTracker, transfer: Transferable[]) => void}} */ (/** @type {unknown} */ (self)).postMessage(m, transfer);
const ready = init({ module_or_path: new URL("./pkg-camera/embusen_bg.wasm", import.meta.url) });

/** The path scorer: a worker, and the answers it owes. */
class Scorer {
  /** How many of its answers are awaited. */
  owed = 0;
  /** The path scorer's time, summed over the frames it scored (ms). */
  ms = 0;
  /** Wakes whoever waits for its answers. @type {(() => void) | null} */
  #answered = null;

  /**
   * @param {Open["take"]} take
   * @param {CameraJob} job the tracker's job, which takes the energies
   * @param {(e: unknown) => void} fail
   */
  constructor(take, job, fail) {
    this.worker = new Worker(new URL("./path-scorer-worker.js", import.meta.url), { type: "module" });
    this.worker.onmessage = (event) => {
      const a = /** @type {FromScorer} */ (event.data);
      try {
        if (a.type === "error") throw new Error(a.message);
        if (a.type !== "energies") throw unexpected("the path scorer", a);
        job.set_path_energies(a.frame, a.energies);
        this.ms += a.ms;
        this.owed--;
        this.#answered?.();
      } catch (e) {
        fail(e);
      }
    };
    this.worker.onerror = (e) => fail(new Error(`the path scorer's worker failed: ${e.message}`));
    /** @type {ToScorer} */
    const open = { type: "open", take };
    this.worker.postMessage(open);
  }

  /** @param {ToScorer} m @param {Transferable[]} transfer */
  send(m, transfer) {
    this.owed++;
    this.worker.postMessage(m, transfer);
  }

  /** Resolves when at most `most` answers are owed; `failed` says whether to give up. @param {number} most @param {() => boolean} failed */
  async settled(most, failed) {
    while (this.owed > most && !failed()) await new Promise((ok) => (this.#answered = () => ok(null)));
    this.#answered = null;
  }

  /** Stops it, and wakes whoever waits. */
  stop() {
    this.worker.terminate();
    this.#answered?.();
  }
}

/** One take being tracked. */
class Tracking {
  busyMs = 0;
  decodeMs = 0;
  /** @type {Scorer | null} */ scorer = null;

  /**
   * @param {Open} m
   * @param {Open["take"]} take the take as opened (the video as the demuxer has it, where it decodes)
   * @param {CameraJob} job
   * @param {(e: unknown) => void} fail
   * @param {() => boolean} failed
   */
  constructor(m, take, job, fail, failed) {
    this.job = job;
    this.failed = failed;
    this.estimating = m.estimateOffset;
    this.truth = m.truth;
    if (this.estimating) job.keep_offset_samples();
    // The fused tracker's path search in a second worker, where a worker can start one.
    if (take.method === "fused" && typeof Worker !== "undefined") {
      this.scorer = new Scorer(take, job, fail);
      job.defer_path_energies();
    }
  }

  /**
   * Tracks one frame, hands its path search to the scorer with the frame's
   * features, and says where it put the actor. A few frames' paths may
   * wait to be scored (memory stays bounded: the features of a few).
   * @param {Uint8Array} luma the frame's luma plane
   * @param {number} stride
   * @param {boolean} fullRange
   */
  async track(luma, stride, fullRange) {
    await this.scorer?.settled(4, this.failed);
    if (this.failed()) throw new Error("the tracking failed");
    const started = performance.now();
    const progress = this.job.push_luma(luma, stride, fullRange);
    const work = this.scorer ? this.job.path_work() : undefined;
    if (this.scorer && work) {
      const features = /** @type {ArrayBuffer} */ (this.job.path_features().buffer);
      this.scorer.send({ type: "score", work, features }, [features]);
    }
    this.busyMs += performance.now() - started;
    post({ type: "progress", progress });
  }

  /** Smooths the track, writes it, and sends it all to the page. */
  async finish() {
    await this.scorer?.settled(0, this.failed);
    if (this.failed()) throw new Error("the tracking failed");
    this.scorer?.stop();
    const job = this.job;
    const frames = job.frames_done();
    const started = performance.now();
    const files = job.finish();
    this.busyMs += performance.now() - started;
    const outlines = job.outlines_px();
    const { offset, offsetProblem } = this.#offset();
    const { errors, truthProblem } = this.#errors();
    const per = (/** @type {number} */ ms) => ms / Math.max(1, frames);
    post({
      type: "done", files, frames, msPerFrame: per(this.busyMs), decodeMsPerFrame: per(this.decodeMs),
      scoreMsPerFrame: per(this.scorer?.ms ?? 0), outlines, candidates: job.riecicky_candidates(),
      trackedHipsCm: job.tracked_hips_cm(), series: job.take_series(), errors, truthProblem, offset, offsetProblem,
      view: job.finished_view(),
    }, outlines.map((o) => o.buffer));
  }

  /**
   * The finished track (the first view's) weighed with the other views',
   * written as `embusen track` writes it for all the videos, and sent.
   * @param {import("./camera/protocol.js").FinishedViewFrames[]} views
   */
  weigh(views) {
    const files = this.job.weigh(views);
    const outlines = this.job.outlines_px();
    const { errors, truthProblem } = this.#errors();
    post({
      type: "weighed", files, outlines, trackedHipsCm: this.job.tracked_hips_cm(), series: this.job.take_series(),
      errors, truthProblem,
    }, outlines.map((o) => o.buffer));
  }

  /** The offset estimated, when asked for, or why there is none. */
  #offset() {
    if (!this.estimating) return { offset: null, offsetProblem: null };
    try {
      const offset = this.job.estimate_offset() ?? null;
      return { offset, offsetProblem: offset ? null : "the offset could not be estimated: no sampled frame had a pose to fit" };
    } catch (e) {
      return { offset: null, offsetProblem: messageOf(e) };
    }
  }

  /** The track against the truth, when one was given, or why not. */
  #errors() {
    if (!this.truth) return { errors: null, truthProblem: null };
    try {
      return { errors: this.job.against_truth(this.truth), truthProblem: null };
    } catch (e) {
      return { errors: null, truthProblem: messageOf(e) };
    }
  }

  free() {
    this.scorer?.stop();
    this.scorer = null;
    this.job.free();
  }
}

/** @type {Tracking | null} */
let tracking = null;
let failed = false;

/** @param {unknown} e */
function fail(e) {
  if (failed) return;
  failed = true;
  tracking?.free();
  tracking = null;
  post({ type: "error", message: messageOf(e) });
}

/** Opens the take and, where it can, decodes and tracks every frame. @param {Open} m */
async function open(m) {
  const { decoder, why } = await decodable(m.take.video.name, m.videoBytes);
  // Where it decodes, the video's rate and frame count are the demuxer's.
  const video = decoder ? { ...m.take.video, fps: decoder.facts.fps, frame_count: decoder.facts.frame_count } : m.take.video;
  const take = { ...m.take, video };
  tracking?.free(); // a take finished before
  tracking = null;
  const job = new CameraJob(take);
  tracking = new Tracking(m, take, job, fail, () => failed);
  post({ type: "opened", decodes: Boolean(decoder), why: why ?? null, video, warnings: job.warnings(), workers: tracking.scorer ? 2 : 1 });
  if (!decoder) return;
  const t = tracking;
  await decodeFrames(decoder, async (luma, stride, fullRange, decodeMs) => {
    t.decodeMs += decodeMs;
    await t.track(luma, stride, fullRange);
  });
  await t.finish();
}

/** @param {ToTracker} m */
async function handle(m) {
  if (failed) return;
  await ready;
  switch (m.type) {
    case "open":
      return open(m);
    case "frame":
      if (!tracking) throw new Error("a frame before the take was opened");
      return tracking.track(new Uint8Array(m.luma), m.stride, m.fullRange);
    case "finish":
      if (!tracking) throw new Error("nothing to finish: the take was not opened");
      return tracking.finish();
    case "weigh":
      // The finished take stays open for this: a first view's track
      // weighed with the other views'.
      if (!tracking) throw new Error("nothing to weigh: the take was not opened");
      return tracking.weigh(m.views);
    default:
      throw unexpected("the tracker's worker", m);
  }
}

// Messages are handled one after another: a frame never overtakes the open.
let queue = Promise.resolve();
self.onmessage = (event) => {
  queue = queue.then(() => handle(/** @type {ToTracker} */ (event.data))).catch(fail);
};
