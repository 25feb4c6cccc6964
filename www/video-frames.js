// @ts-check
// A video's frames, exactly: frame i is read at its own timestamp. Seeking to
// (i + 0.5) / fps and drawing on `seeked` can give the previous frame, and
// playback skips frames, so each frame is taken in a requestVideoFrameCallback
// after the seek, and checked against the frame's own timestamp. The pixels
// are the decoder's luma plane (WebCodecs VideoFrame.copyTo), which the core
// makes grey exactly as `embusen track` does through ffmpeg
// (GreyImage::from_luma), so the page and the CLI track the same bytes.

/**
 * @typedef {object} LumaFrame
 * @property {number} index the frame's index, from its timestamp
 * @property {ArrayBuffer} luma the luma plane, rows `stride` bytes apart
 * @property {number} stride
 * @property {boolean} fullRange whether black is 0 (else 16: limited range)
 * @property {number} mediaTimeS the frame's presentation time (s)
 */

/**
 * A `<video>` element holding `blob` (a File or a fetched Blob), its metadata
 * loaded; rejects with a message when the browser cannot decode it.
 * @param {Blob} blob
 * @param {string} name
 * @returns {Promise<HTMLVideoElement>}
 */
export function openVideo(blob, name) {
  const video = document.createElement("video");
  video.muted = true;
  video.playsInline = true;
  video.preload = "auto";
  video.src = URL.createObjectURL(blob);
  return new Promise((resolve, reject) => {
    video.onloadeddata = () => resolve(video);
    video.onerror = () => {
      URL.revokeObjectURL(video.src);
      reject(new Error(`${name}: this browser cannot decode the video (${video.error?.message || "no decoder for it"})`));
    };
  });
}

/** Releases what `openVideo` holds. @param {HTMLVideoElement} video */
export function closeVideo(video) {
  video.pause();
  URL.revokeObjectURL(video.src);
  video.removeAttribute("src");
  video.load();
}

/**
 * The video's frame rate as measured: the frames presented while it plays a
 * moment are counted (each step between their timestamps a whole number of
 * the shortest) over the time their timestamps span. (The core's
 * `nominal_fps` turns it into the rate the camera recorded at.)
 * @param {HTMLVideoElement} video
 * @returns {Promise<number>}
 */
export async function measureFps(video) {
  /** @type {number[]} */
  const times = [];
  await new Promise((resolve) => {
    const take = (/** @type {number} */ _now, /** @type {VideoFrameCallbackMetadata} */ meta) => {
      times.push(meta.mediaTime);
      if (times.length >= 16 || video.ended) resolve(null);
      else video.requestVideoFrameCallback(take);
    };
    video.requestVideoFrameCallback(take);
    video.currentTime = 0;
    void video.play().catch(() => resolve(null));
    setTimeout(() => resolve(null), 3000);
  });
  video.pause();
  const steps = times.slice(1).map((t, i) => t - times[i]).filter((d) => d > 1e-4);
  if (steps.length === 0) throw new Error("the video's frame rate could not be measured: it presented no two frames");
  const span = times[times.length - 1] - times[0];
  const frames = steps.reduce((sum, d) => sum + Math.round(d / Math.min(...steps)), 0);
  return frames / span;
}

/**
 * Frame `index` of `video` at `fps`: seeks to the middle of the frame, takes
 * it when it is presented, and checks its timestamp.
 * @param {HTMLVideoElement} video
 * @param {number} index
 * @param {number} fps
 * @returns {Promise<LumaFrame>}
 */
export async function frameAt(video, index, fps) {
  const target = (index + 0.5) / fps;
  // Asking for the frame already shown presents nothing new: step off it first.
  if (Math.abs(video.currentTime - target) < 0.5 / fps) await presentedAt(video, (index === 0 ? 1.5 : index - 0.5) / fps);
  const meta = await presentedAt(video, target);
  const frame = new VideoFrame(video);
  try {
    const found = Math.round(frame.timestamp / 1e6 * fps);
    if (found !== index) throw new Error(`frame ${index} was asked for, the video presented frame ${found}`);
    return { index: found, ...(await lumaOf(frame)), mediaTimeS: meta.mediaTime };
  } finally {
    frame.close();
  }
}

/**
 * Seeks to `time_s` and resolves with the presented frame's metadata.
 * @param {HTMLVideoElement} video
 * @param {number} timeS
 * @returns {Promise<VideoFrameCallbackMetadata>}
 */
function presentedAt(video, timeS) {
  return new Promise((resolve, reject) => {
    const timer = setTimeout(() => reject(new Error(`the video presented no frame at ${timeS.toFixed(3)} s`)), 5000);
    video.requestVideoFrameCallback((_now, meta) => {
      clearTimeout(timer);
      resolve(meta);
    });
    video.currentTime = timeS;
  });
}

/**
 * The luma plane of a decoded frame: plane 0 of the YUV formats; from RGB
 * (a decoder that gives no planes) the BT.601 luma in full range, which
 * tracks the same but not to the CLI's last bit.
 * @param {VideoFrame} frame
 * @returns {Promise<{luma: ArrayBuffer, stride: number, fullRange: boolean}>}
 */
export async function lumaOf(frame) {
  const rect = frame.visibleRect;
  if (!rect) throw new Error("the decoder gives no picture size");
  const [w, h] = [rect.width, rect.height];
  const format = frame.format ?? "";
  if (format.startsWith("I4") || format.startsWith("NV12")) {
    if (format.includes("P1")) throw new Error(`frames of ${format} (more than 8 bits) are not read yet`);
    const buffer = new Uint8Array(frame.allocationSize());
    const layout = await frame.copyTo(buffer);
    const { offset, stride } = layout[0];
    return {
      luma: buffer.slice(offset, offset + stride * (h - 1) + w).buffer,
      stride,
      fullRange: frame.colorSpace?.fullRange === true,
    };
  }
  const canvas = new OffscreenCanvas(w, h);
  const ctx = canvas.getContext("2d");
  if (!ctx) throw new Error("no 2D canvas to read the frame through");
  ctx.drawImage(frame, 0, 0);
  const rgba = ctx.getImageData(0, 0, w, h).data;
  const luma = new Uint8Array(w * h);
  for (let i = 0; i < w * h; i++) {
    luma[i] = (9798 * rgba[4 * i] + 19235 * rgba[4 * i + 1] + 3735 * rgba[4 * i + 2] + 16384) >> 15;
  }
  return { luma: luma.buffer, stride: w, fullRange: true };
}
