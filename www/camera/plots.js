// @ts-check
// The camera panel's plots: the hips' track from above, the camera's
// confidence per frame (and the error against a truth) with a cursor at the
// frame shown, and the paper's candidates of the frame shown. Laid out in
// the core (app::plot::camera) and painted by the camera module; this keeps
// the track's figures and says which frame is shown.

import { loadCameraModule } from "./modules.js";

/** @typedef {import("./protocol.js").FrameProgress} FrameProgress */
/** @typedef {import("./protocol.js").TruthErrors} TruthErrors */
/** @typedef {import("./protocol.js").FrameCandidates} FrameCandidates */

/** The plots of one panel and the track they show. */
export class TakePlots {
  /** Where each frame tracked so far put the actor. @type {FrameProgress[]} */
  path = [];
  /** The track's error against the truth, when a truth was given. @type {TruthErrors | null} */
  errors = null;
  /** The name of that truth. */
  truthName = "the truth";
  /** The paper's candidates per video frame of the last track (none for fused). @type {FrameCandidates[]} */
  candidates = [];

  /**
   * @param {{top: HTMLCanvasElement, series: HTMLCanvasElement, candidates: HTMLCanvasElement}} canvases
   */
  constructor(canvases) {
    this.canvases = canvases;
  }

  /** Forgets the last track. */
  clear() {
    this.path = [];
    this.errors = null;
    this.candidates = [];
  }

  async paintTop() {
    (await loadCameraModule()).paint_top_view(this.canvases.top, this.path.map((p) => p.floor));
  }

  /** @param {number} frameCount the video's frames @param {number} shownFrame */
  async paintSeries(frameCount, shownFrame) {
    const m = await loadCameraModule();
    const confidence = Float64Array.from(this.path, (p) => p.confidence);
    m.paint_frame_series(this.canvases.series, confidence, this.errors ?? undefined, this.truthName, frameCount, shownFrame);
  }

  /** The paper's candidates of the frame shown (hidden without any). @param {number} shownFrame */
  async paintCandidates(shownFrame) {
    const canvas = this.canvases.candidates;
    canvas.hidden = this.candidates.length === 0;
    if (canvas.hidden) return;
    (await loadCameraModule()).paint_candidates(canvas, this.candidates[shownFrame], shownFrame);
  }

  /** The candidates of video frame `i`, as the panel's handle gives them. @param {number} i */
  candidatesAt(i) {
    const frame = this.candidates[i];
    return frame ? { energies: frame.tried.map((c) => c.energy_px), chosen: frame.chosen ?? -1 } : null;
  }
}
