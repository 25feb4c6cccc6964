// @ts-check
// Stills made from the take's video, read exactly, as `embusen` makes them:
// the frame shown (to find a board in) and, without a background still,
// the per-pixel median of frames spread over the video (the empty room).

import { loadCameraModule } from "./modules.js";
import { frameAt } from "../video-frames.js";

/** @typedef {import("./inputs.js").TakeVideo} TakeVideo */
/** @typedef {import("./inputs.js").FileBytes} FileBytes */

/** The camera module's description of the take's video. @param {TakeVideo} video */
export const factsOf = (video) => ({
  name: video.name, width_px: video.element.videoWidth, height_px: video.element.videoHeight,
  fps: video.fps, frame_count: video.frameCount,
});

/**
 * Video frame `i` as a still (PNG).
 * @param {TakeVideo} video
 * @param {number} i
 * @returns {Promise<FileBytes>}
 */
export async function frameStill(video, i) {
  const m = await loadCameraModule();
  const frame = await frameAt(video.element, i, video.fps);
  const name = `${video.name} frame ${i}`;
  const png = m.frame_png(factsOf(video), { luma: frame.luma, stride: frame.stride, full_range: frame.fullRange }, name);
  return { name, bytes: /** @type {ArrayBuffer} */ (png.buffer) };
}

/**
 * Without a background still, the empty room as `embusen track` makes it:
 * the per-pixel median of 31 frames spread over the video, each read
 * exactly.
 * @param {TakeVideo} video
 * @param {(text: string) => void} say
 * @returns {Promise<FileBytes & {fromVideo: boolean}>}
 */
export async function medianStill(video, say) {
  const m = await loadCameraModule();
  const indices = Array.from(m.median_background_frames(video.frameCount));
  /** @type {import("../pkg-camera/embusen.js").LumaPlane[]} */
  const planes = [];
  for (const [k, i] of indices.entries()) {
    say(`no background still: reading frame ${k + 1} of the ${indices.length} whose median stands for the empty room…`);
    const frame = await frameAt(video.element, i, video.fps);
    if (k > 0 && frame.stride !== planes[0].stride) throw new Error(`${video.name}: frames of different strides`);
    planes.push({ luma: frame.luma, stride: frame.stride, full_range: frame.fullRange });
  }
  const png = m.median_background_png(factsOf(video), planes);
  return { name: `the median of ${indices.length} frames of ${video.name}`, bytes: /** @type {ArrayBuffer} */ (png.buffer), fromVideo: true };
}
