// @ts-check
// The page's side of the tracker's worker (../track-worker.js): one run of
// one take. It opens the take there, sends the frames (read here, a seek
// each) when the worker cannot decode them itself, passes on its progress,
// and resolves with what it finished. The messages are typed in
// ./protocol.js; any other is an error.

import { unexpected } from "./protocol.js";
import { frameAt } from "../video-frames.js";

/** @typedef {import("./protocol.js").ToTracker} ToTracker */
/** @typedef {import("./protocol.js").FromTracker} FromTracker */
/** @typedef {import("./protocol.js").Opened} Opened */
/** @typedef {import("./protocol.js").Done} Done */
/** @typedef {import("./protocol.js").Weighed} Weighed */
/** @typedef {import("./protocol.js").FinishedViewFrames} FinishedViewFrames */
/** @typedef {import("./protocol.js").FrameProgress} FrameProgress */
/** @typedef {import("./inputs.js").TakeVideo} TakeVideo */

/** One take tracked in a worker; `cancel` ends it with a message. */
export class TrackerRun {
  /** Ends the run with its message. @type {(e: Error) => void} */
  cancel = () => {};
  /** The worker's reply awaited, by type. @type {{opened?: (m: Opened) => void, done?: (m: Done) => void, weighed?: (m: Weighed) => void}} */
  #waiting = {};
  /** Frames sent and not yet tracked, and who waits for one to be. */
  #inFlight = 0;
  /** @type {(() => void) | null} */
  #slot = null;
  /** Rejects when the worker fails or the run is cancelled. @type {Promise<never>} */
  #failed;

  /**
   * @param {(opened: Opened) => void} onOpened when the worker has opened the take
   * @param {(progress: FrameProgress) => void} onProgress each frame tracked
   */
  constructor(onOpened, onProgress) {
    this.onOpened = onOpened;
    this.onProgress = onProgress;
    this.worker = new Worker(new URL("../track-worker.js", import.meta.url), { type: "module" });
    this.#failed = new Promise((_, reject) => {
      this.cancel = reject;
      this.worker.onmessage = (event) => {
        try {
          this.#receive(/** @type {FromTracker} */ (event.data));
        } catch (e) {
          reject(e);
        }
      };
      this.worker.onerror = (e) => reject(new Error(`the tracker's worker failed: ${e.message}`));
    });
    this.#failed.catch(() => {});
  }

  /** @param {FromTracker} m */
  #receive(m) {
    switch (m.type) {
      case "error":
        throw new Error(m.message);
      case "progress":
        this.#inFlight = Math.max(0, this.#inFlight - 1);
        this.#slot?.();
        this.onProgress(m.progress);
        return;
      case "opened":
        return this.#waiting.opened?.(m);
      case "done":
        return this.#waiting.done?.(m);
      case "weighed":
        return this.#waiting.weighed?.(m);
      default:
        throw unexpected("the tracker's worker", m);
    }
  }

  /**
   * The worker's reply of `type`, or the run's failure.
   * @template {"opened" | "done" | "weighed"} K
   * @param {K} type
   * @returns {Promise<K extends "opened" ? Opened : K extends "done" ? Done : Weighed>}
   */
  #reply(type) {
    return Promise.race([new Promise((ok) => (this.#waiting[type] = ok)), this.#failed]);
  }

  /**
   * Tracks the take: opens it (`open`, which takes the video's bytes), then
   * reads and sends the frames unless the worker decodes them.
   * @param {Extract<ToTracker, {type: "open"}>} open
   * @param {TakeVideo} video
   * @returns {Promise<{opened: Opened, done: Done, readMs: number}>}
   */
  async run(open, video) {
    this.#send(open, [open.videoBytes]);
    const opened = await this.#reply("opened");
    this.onOpened(opened);
    let readMs = 0;
    // The worker decodes the frames itself (WebCodecs, each frame once, in
    // order) where it can read the container; else they are read here, a
    // seek each.
    if (!opened.decodes) readMs = await this.#sendFrames(video, opened.video.frame_count);
    return { opened, done: await this.#reply("done"), readMs };
  }

  /**
   * After `run`, this (the first) view's track weighed with the other
   * views' tracks (`Done.view` of their runs).
   * @param {FinishedViewFrames[]} views
   * @returns {Promise<Weighed>}
   */
  weigh(views) {
    this.#send({ type: "weigh", views });
    return this.#reply("weighed");
  }

  /**
   * Reads each frame exactly and sends it; the time spent reading (ms).
   * @param {TakeVideo} video
   * @param {number} frameCount
   */
  async #sendFrames(video, frameCount) {
    let readMs = 0;
    for (let i = 0; i < frameCount; i++) {
      const t = performance.now();
      const frame = await Promise.race([frameAt(video.element, i, video.fps), this.#failed]);
      readMs += performance.now() - t;
      // At most a few frames wait in the worker: memory stays bounded.
      while (this.#inFlight >= 3) await Promise.race([new Promise((ok) => (this.#slot = () => ok(null))), this.#failed]);
      this.#inFlight++;
      this.#send({ type: "frame", luma: frame.luma, stride: frame.stride, fullRange: frame.fullRange }, [frame.luma]);
    }
    this.#send({ type: "finish" });
    return readMs;
  }

  /** @param {ToTracker} m @param {Transferable[]} [transfer] */
  #send(m, transfer = []) {
    this.worker.postMessage(m, transfer);
  }

  /** Ends the worker; the run's reads and replies still awaited fail (one view's failure ends the others'). */
  terminate() {
    this.cancel(new Error("the tracking ended"));
    this.worker.terminate();
  }
}
