// @ts-check
// The camera tracker's Web Worker: it owns one wasm CameraJob (src/web/tracking.rs)
// so the page stays responsive while frames are tracked. Where it can read the
// video's container (io::container: MP4/MOV, WebM/Matroska) and the browser
// has a WebCodecs decoder for its codec, it decodes the frames itself, each
// once and in order; else the page sends them, read a seek each.
// Messages in:
//   {type: "open", recording, camera, background: {name, bytes},
//    video: {name, width, height, fps, frameCount, bytes}, method, offsetS, estimateOffset, truth?: {name, bytes}}
//   {type: "frame", luma: ArrayBuffer, stride, fullRange}     (only when it does not decode)
//   {type: "finish"}                                          (likewise)
// Messages out: {type: "opened", decodes, why, fps, frameCount, warnings, workers (1 or 2)},
// {type: "progress", frame, x, z, confidence},
// {type: "done", recording, csv, warnings, frames, msPerFrame, decodeMsPerFrame, scoreMsPerFrame,
//  outlines: Uint32Array (per frame n, then n pixels x, y: the body where the track puts it),
//  candidates: Float64Array (paper: per frame n, chosen, then n times x, z, energy; see CameraJob.paper_candidates),
//  bodyShapeJson, trackedHipsCm: Float64Array (per BVH frame x, y, z: for the player's 3D view),
//  errors: Float64Array | null (with a truth: mean, p90, max, then per frame, cm), truthProblem,
//  offset: Float64Array | undefined (estimateOffset: CameraJob.estimate_offset), offsetProblem},
// {type: "error", message}.
// After an error the worker takes nothing more: the page starts a new one.
//
// For the fused tracker it starts a second worker of its own, this file again
// named "path-scorer", with the same take: half the tracker's work (the path
// search's energies, CameraJob.defer_path_energies) is done there, from the
// same frame, while this one reads the next — two cores for one take, the
// same bytes. It takes {type: "open", ...as above without the video's bytes}
// and {type: "score", request, luma, stride, fullRange}, and answers
// {type: "energies", frame, energies} or {type: "error", message}.

import init, { CameraJob, demux_video } from "./pkg-camera/embusen.js";
import { lumaOf } from "./video-frames.js";

/** @type {CameraJob | null} */
let job = null;
/** The path scorer (a worker) and how many of its answers are awaited. @type {Worker | null} */
let scorer = null;
let scoring = 0;
/** Wakes whoever waits for the scorer's answers. @type {(() => void) | null} */
let answered = null;
let failed = false;
let busyMs = 0;
let decodeMs = 0;
/** The path scorer's time, summed over the frames it scored. */
let scoreMs = 0;
/** Whether the take's time offset is to be estimated after the track. */
let estimating = false;
/** The true hips per video frame (a CSV), when the page has them. @type {{name: string, bytes: ArrayBuffer} | null} */
let truth = null;
/** The worker's own postMessage (the DOM types only know the window's). @param {any} m */
const post = (m) => /** @type {any} */ (self).postMessage(m);
const ready = init({ module_or_path: new URL("./pkg-camera/embusen_bg.wasm", import.meta.url) });

/** @param {unknown} e */
function fail(e) {
  if (failed) return;
  failed = true;
  job?.free();
  job = null;
  scorer?.terminate();
  scorer = null;
  answered?.();
  post({ type: "error", message: e instanceof Error ? e.message : String(e) });
}

/** The take's job, as the page described it (the scorer's is the same). @param {any} m */
const openJob = (m, /** @type {number} */ fps, /** @type {number} */ frameCount) => new CameraJob(
  m.recording.name, new Uint8Array(m.recording.bytes),
  m.camera.name, new Uint8Array(m.camera.bytes),
  m.background.name, new Uint8Array(m.background.bytes),
  m.video.name, m.video.width, m.video.height, fps, frameCount, m.method, m.offsetS,
);

// Messages are handled one after another: a frame never overtakes the open.
let queue = Promise.resolve();
self.onmessage = (event) => {
  queue = queue.then(() => (self.name === "path-scorer" ? score(event.data) : handle(event.data))).catch(fail);
};

/** The path scorer's side. @param {any} m */
async function score(m) {
  if (failed) return;
  await ready;
  if (m.type === "open") {
    job = openJob(m, m.video.fps, m.video.frameCount);
  } else if (m.type === "score") {
    if (!job) throw new Error("a path to score before the take was opened");
    const started = performance.now();
    const energies = job.score_path(m.request, new Uint8Array(m.luma), m.stride, m.fullRange);
    post({ type: "energies", frame: m.request[0], energies, ms: performance.now() - started });
  }
}

/**
 * Starts the path scorer for the take `m` opened at `fps` (the fused
 * tracker only; where a worker cannot start one, this one scores itself).
 * @param {any} m
 * @param {number} fps
 * @param {number} frameCount
 */
function startScorer(m, fps, frameCount) {
  if (m.method !== "fused" || typeof Worker === "undefined" || !job) return;
  const s = new Worker(new URL(import.meta.url), { type: "module", name: "path-scorer" });
  s.onmessage = (event) => {
    const a = event.data;
    try {
      if (a.type === "error") throw new Error(a.message);
      job?.set_path_energies(a.frame, a.energies);
      scoreMs += a.ms;
      scoring--;
      answered?.();
    } catch (e) {
      fail(e);
    }
  };
  s.onerror = (e) => fail(new Error(`the path scorer's worker failed: ${e.message}`));
  const { bytes: _, ...video } = m.video;
  s.postMessage({ ...m, video: { ...video, fps, frameCount } });
  job.defer_path_energies();
  scorer = s;
}

/** Resolves when at most `most` of the scorer's answers are awaited. */
async function scored(/** @type {number} */ most) {
  while (scoring > most && !failed) await new Promise((ok) => (answered = () => ok(null)));
  answered = null;
  if (failed) throw new Error("the tracking failed");
}

/**
 * The video's frames as a decoder wants them, or why they cannot be had.
 * @param {{name: string, bytes?: ArrayBuffer}} video
 */
async function decodable(video) {
  if (typeof VideoDecoder === "undefined") return { why: "this browser has no WebCodecs decoder" };
  if (!video.bytes) return { why: "the page sent no file" };
  let demuxed;
  try {
    demuxed = demux_video(new Uint8Array(video.bytes), video.name);
  } catch (e) {
    return { why: e instanceof Error ? e.message : String(e) };
  }
  const description = demuxed.description();
  /** @type {VideoDecoderConfig} */
  const config = {
    codec: demuxed.codec(), codedWidth: demuxed.width_px(), codedHeight: demuxed.height_px(),
    ...(description ? { description } : {}),
  };
  const support = await VideoDecoder.isConfigSupported(config).catch(() => ({ supported: false }));
  if (!support.supported) {
    demuxed.free();
    return { why: `${video.name}: this browser cannot decode ${config.codec} in a worker` };
  }
  return { demuxed, config };
}

/** @param {any} m */
async function handle(m) {
  if (failed) return;
  await ready;
  if (m.type === "open") {
    const v = m.video;
    const { demuxed, config, why } = await decodable(v);
    const fps = demuxed ? demuxed.fps() : v.fps;
    const frameCount = demuxed ? demuxed.frame_count() : v.frameCount;
    job = openJob(m, fps, frameCount);
    estimating = Boolean(m.estimateOffset);
    if (estimating) job.keep_offset_samples();
    truth = m.truth ?? null;
    busyMs = decodeMs = scoreMs = 0;
    startScorer(m, fps, frameCount);
    post({
      type: "opened", decodes: Boolean(demuxed), why: why ?? null, fps, frameCount, warnings: job.warnings(),
      workers: scorer ? 2 : 1,
    });
    if (demuxed && config) {
      const frames = demuxed.frames();
      demuxed.free();
      await decodeAndTrack(new Uint8Array(v.bytes), v.name, frames, config);
      await finish();
    }
  } else if (m.type === "frame") {
    if (!job) throw new Error("a frame before the take was opened");
    await track(new Uint8Array(m.luma), m.stride, m.fullRange);
  } else if (m.type === "finish") {
    await finish();
  }
}

/**
 * Tracks one frame, hands its path search to the scorer, and says where it
 * put the actor. A few frames' paths may wait to be scored (memory stays
 * bounded: a luma plane each).
 * @param {Uint8Array} luma the frame's luma plane (given away to the scorer)
 * @param {number} stride
 * @param {boolean} fullRange
 */
async function track(luma, stride, fullRange) {
  if (!job) throw new Error("no take is open");
  await scored(4);
  if (!job) throw new Error("no take is open");
  const started = performance.now();
  const frame = job.frames_done();
  const [x, z, confidence] = job.push_luma(luma, stride, fullRange);
  const request = scorer ? job.path_request() : undefined;
  if (scorer && request) {
    scoring++;
    scorer.postMessage({ type: "score", request, luma: luma.buffer, stride, fullRange }, [luma.buffer]);
  }
  busyMs += performance.now() - started;
  post({ type: "progress", frame, x, z, confidence });
}

async function finish() {
  await scored(0);
  scorer?.terminate();
  scorer = null;
  if (!job) throw new Error("nothing to finish: the take was not opened");
  const frames = job.frames_done();
  const started = performance.now();
  job.finish();
  busyMs += performance.now() - started;
  const outlines = job.outlines_px();
  /** @type {Float64Array | undefined} */
  let offset;
  /** @type {string | null} */
  let offsetProblem = null;
  if (estimating) {
    try {
      offset = job.estimate_offset() ?? undefined;
      if (!offset) offsetProblem = "the offset could not be estimated: no sampled frame had a pose to fit";
    } catch (e) {
      offsetProblem = e instanceof Error ? e.message : String(e);
    }
  }
  /** @type {Float64Array | null} */
  let errors = null;
  /** @type {string | null} */
  let truthProblem = null;
  if (truth) {
    try {
      errors = job.against_truth(truth.name, new Uint8Array(truth.bytes));
    } catch (e) {
      truthProblem = e instanceof Error ? e.message : String(e);
    }
  }
  /** @type {any} */ (self).postMessage({
    type: "done", recording: job.recording_text(), csv: job.track_csv(), warnings: job.warnings(), frames,
    msPerFrame: busyMs / Math.max(1, frames), decodeMsPerFrame: decodeMs / Math.max(1, frames),
    scoreMsPerFrame: scoreMs / Math.max(1, frames), outlines, candidates: job.paper_candidates(),
    bodyShapeJson: job.body_shape_json(), trackedHipsCm: job.tracked_hips_cm(),
    errors, truthProblem, offset, offsetProblem,
  }, [outlines.buffer]);
  job.free();
  job = null;
}

/**
 * Decodes every frame (`table`: per frame in decoding order its offset,
 * size, time in µs and keyframe flag) and tracks each as it comes out, in
 * presentation order: the k-th frame out is the CLI's frame k. A few frames
 * are decoded ahead while one is tracked; each is closed as soon as its luma
 * is copied, so the decoder never runs out of frames.
 * @param {Uint8Array} bytes
 * @param {string} name
 * @param {Float64Array | number[]} table
 * @param {VideoDecoderConfig} config
 */
async function decodeAndTrack(bytes, name, table, config) {
  const n = table.length / 4;
  /** @type {VideoFrame[]} */
  const out = [];
  /** @type {DOMException | null} */
  let error = null;
  /** @type {(() => void) | null} */
  let wake = null;
  const poke = () => wake?.();
  const decoder = new VideoDecoder({ output: (f) => (out.push(f), poke()), error: (e) => ((error = e), poke()) });
  decoder.addEventListener("dequeue", poke);
  decoder.configure(config);
  let fed = 0;
  let tracked = 0;
  let flushed = false;
  let lastTimestamp = -Infinity;
  try {
    while (tracked < n) {
      while (fed < n && decoder.decodeQueueSize < 4 && out.length < 4) {
        const [offset, size, timestamp, key] = [table[4 * fed], table[4 * fed + 1], table[4 * fed + 2], table[4 * fed + 3]];
        decoder.decode(new EncodedVideoChunk({ type: key ? "key" : "delta", timestamp, data: bytes.subarray(offset, offset + size) }));
        fed++;
        if (fed === n) decoder.flush().then(() => ((flushed = true), poke()), (e) => ((error = e), poke()));
      }
      if (error) throw new Error(`${name}: the decoder failed after ${tracked} frames: ${/** @type {any} */ (error).message}`);
      const frame = out.shift();
      if (!frame) {
        if (flushed) break;
        // Woken by an output, a dequeue, the flush or an error; a timer too.
        await new Promise((ok) => {
          wake = () => ok(null);
          setTimeout(wake, 20);
        });
        wake = null;
        continue;
      }
      let luma;
      const started = performance.now();
      try {
        if (frame.timestamp <= lastTimestamp) throw new Error(`${name}: the decoder gave frame ${tracked} out of order`);
        lastTimestamp = frame.timestamp;
        luma = await lumaOf(frame);
      } finally {
        frame.close();
      }
      decodeMs += performance.now() - started;
      await track(new Uint8Array(luma.luma), luma.stride, luma.fullRange);
      tracked++;
    }
  } finally {
    for (const f of out) f.close();
    if (decoder.state !== "closed") decoder.close();
  }
  if (tracked !== n) throw new Error(`${name}: ${n} frames in the file, the decoder gave ${tracked}`);
}
