// @ts-check
// The messages between the page, the tracker's worker (../track-worker.js)
// and its path scorer (../path-scorer-worker.js): types only, checked by tsc
// on both sides. A message of another type is an error (`unexpected`), never
// ignored. After an error a worker takes nothing more: its sender starts a
// new one.

/** @typedef {import("../pkg-camera/embusen.js").TakeOptions} TakeOptions */
/** @typedef {import("../pkg-camera/embusen.js").NamedFile} NamedFile */
/** @typedef {import("../pkg-camera/embusen.js").VideoFacts} VideoFacts */
/** @typedef {import("../pkg-camera/embusen.js").FrameProgress} FrameProgress */
/** @typedef {import("../pkg-camera/embusen.js").PathWork} PathWork */
/** @typedef {import("../pkg-camera/embusen.js").TakeFiles} TakeFiles */
/** @typedef {import("../pkg-camera/embusen.js").FrameCandidates} FrameCandidates */
/** @typedef {import("../pkg-camera/embusen.js").TruthErrors} TruthErrors */
/** @typedef {import("../pkg-camera/embusen.js").OffsetFound} OffsetFound */
/** @typedef {import("../pkg-camera/embusen.js").TakeSeries} TakeSeries */
/** @typedef {import("../pkg-camera/embusen.js").FinishedViewFrames} FinishedViewFrames */

/**
 * The page to the tracker's worker: open a take (with the video's bytes the
 * worker decodes the frames itself where it can), then, only when it does
 * not decode, each frame's luma plane and the finish. After its `done`, a
 * first view's worker weighs the other views' finished tracks in (`weigh`).
 * @typedef {{type: "open", take: TakeOptions, videoBytes: ArrayBuffer, estimateOffset: boolean, truth: NamedFile | null}
 *   | {type: "frame", luma: ArrayBuffer, stride: number, fullRange: boolean}
 *   | {type: "finish"}
 *   | {type: "weigh", views: FinishedViewFrames[]}} ToTracker
 */

/**
 * What the tracker does and why, once open.
 * @typedef {object} Opened
 * @property {"opened"} type
 * @property {boolean} decodes whether it decodes the frames itself (WebCodecs)
 * @property {string | null} why why not, when it does not
 * @property {VideoFacts} video the video as tracked (the demuxer's rate and count where it decodes)
 * @property {string[]} warnings
 * @property {number} workers 2 with a path scorer (fused), else 1
 */

/**
 * A finished take.
 * @typedef {object} Done
 * @property {"done"} type
 * @property {TakeFiles} files the bytes `embusen track` writes
 * @property {number} frames
 * @property {number} msPerFrame the tracker's own time per frame
 * @property {number} decodeMsPerFrame decoding and copying a frame, where the worker decodes
 * @property {number} scoreMsPerFrame the path scorer's time per frame (0 without one)
 * @property {Uint32Array[]} outlines per video frame the body's outline where the track puts it: x, y pixel after pixel
 * @property {FrameCandidates[]} candidates the paper's per video frame (none for fused)
 * @property {Float64Array} trackedHipsCm per frame of the recording x, y, z (cm): for the player's 3D view
 * @property {TakeSeries} series per video frame its instant on the recording's clock and the uncertainty: for the player's plots
 * @property {TruthErrors | null} errors against the truth, when one was given
 * @property {string | null} truthProblem why there are none, when a truth was given
 * @property {OffsetFound | null} offset the time offset estimated, when asked for and found
 * @property {string | null} offsetProblem why not, when asked for
 * @property {FinishedViewFrames} view the track as another view's worker weighs it in
 */

/**
 * The first view's track weighed with the others': what `embusen track`
 * writes for all the videos, and the weighed track as `Done` has it.
 * @typedef {{type: "weighed"} & Pick<Done, "files" | "outlines" | "trackedHipsCm" | "series" | "errors" | "truthProblem">} Weighed
 */

/**
 * The tracker's worker to the page.
 * @typedef {Opened | {type: "progress", progress: FrameProgress} | Done | Weighed | {type: "error", message: string}} FromTracker
 */

/**
 * The tracker's worker to its path scorer: the same take (without the
 * video), then a frame's work with the frame's features as the tracker
 * made them (CameraJob.path_features: the frame is read once).
 * @typedef {{type: "open", take: TakeOptions}
 *   | {type: "score", work: PathWork, features: ArrayBuffer}} ToScorer
 */

/**
 * The path scorer's answers.
 * @typedef {{type: "energies", frame: number, energies: Float64Array, ms: number}
 *   | {type: "error", message: string}} FromScorer
 */

/**
 * The error for a message no side expects.
 * @param {string} who
 * @param {{type: string}} message
 */
export function unexpected(who, message) {
  return new Error(`${who}: an unexpected message of type ${JSON.stringify(message?.type)}`);
}
