// @ts-check
// The take's video decoded in the tracker's worker (WebCodecs), each frame
// once and in order: the k-th frame out is the CLI's frame k.

import { demux_video } from "../pkg-camera/embusen.js";
import { lumaOf } from "../video-frames.js";
import { messageOf } from "../files.js";

/** @typedef {import("../pkg-camera/embusen.js").VideoFacts} VideoFacts */
/** @typedef {import("../pkg-camera/embusen.js").EncodedFrame} EncodedFrame */
/** @typedef {{bytes: Uint8Array, name: string, facts: VideoFacts, frames: EncodedFrame[], config: VideoDecoderConfig}} Decodable */

/**
 * The video's frames as a decoder wants them, or why they cannot be had.
 * @param {string} name
 * @param {ArrayBuffer | undefined} bytes
 * @returns {Promise<{decoder?: Decodable, why?: string}>}
 */
export async function decodable(name, bytes) {
  if (typeof VideoDecoder === "undefined") return { why: "this browser has no WebCodecs decoder" };
  if (!bytes) return { why: "the page sent no file" };
  let demuxed;
  try {
    demuxed = demux_video(new Uint8Array(bytes), name);
  } catch (e) {
    return { why: messageOf(e) };
  }
  try {
    const description = demuxed.description();
    /** @type {VideoDecoderConfig} */
    const config = {
      codec: demuxed.codec(), codedWidth: demuxed.facts(name).width_px, codedHeight: demuxed.facts(name).height_px,
      ...(description ? { description } : {}),
    };
    const support = await VideoDecoder.isConfigSupported(config).catch(() => ({ supported: false }));
    if (!support.supported) return { why: `${name}: this browser cannot decode ${config.codec} in a worker` };
    return { decoder: { bytes: new Uint8Array(bytes), name, facts: demuxed.facts(name), frames: demuxed.frames(), config } };
  } finally {
    demuxed.free();
  }
}

/**
 * Decodes every frame and hands each to `track` as it comes out, in
 * presentation order. A few frames are decoded ahead while one is tracked;
 * each is closed as soon as its luma is copied, so the decoder never runs
 * out of frames.
 * @param {Decodable} video
 * @param {(luma: Uint8Array, stride: number, fullRange: boolean, decodeMs: number) => Promise<void>} track
 */
export async function decodeFrames(video, track) {
  const { bytes, name, frames } = video;
  const n = frames.length;
  const queue = new DecodedQueue(video.config);
  let fed = 0;
  let tracked = 0;
  let lastTimestamp = -Infinity;
  try {
    while (tracked < n) {
      while (fed < n && queue.wantsMore()) {
        const f = frames[fed];
        queue.decode(new EncodedVideoChunk({ type: f.keyframe ? "key" : "delta", timestamp: f.timestamp_us, data: bytes.subarray(f.offset, f.offset + f.size) }));
        fed++;
        if (fed === n) queue.flush();
      }
      if (queue.error) throw new Error(`${name}: the decoder failed after ${tracked} frames: ${queue.error.message}`);
      const frame = queue.out.shift();
      if (!frame) {
        if (queue.flushed) break;
        await queue.woken();
        continue;
      }
      const started = performance.now();
      let luma;
      try {
        if (frame.timestamp <= lastTimestamp) throw new Error(`${name}: the decoder gave frame ${tracked} out of order`);
        lastTimestamp = frame.timestamp;
        luma = await lumaOf(frame);
      } finally {
        frame.close();
      }
      await track(new Uint8Array(luma.luma), luma.stride, luma.fullRange, performance.now() - started);
      tracked++;
    }
  } finally {
    queue.close();
  }
  if (tracked !== n) throw new Error(`${name}: ${n} frames in the file, the decoder gave ${tracked}`);
}

/** A VideoDecoder and the frames it has given and not yet taken. */
class DecodedQueue {
  /** @type {VideoFrame[]} */ out = [];
  /** @type {DOMException | Error | null} */ error = null;
  flushed = false;
  /** @type {(() => void) | null} */ #wake = null;

  /** @param {VideoDecoderConfig} config */
  constructor(config) {
    const poke = () => this.#wake?.();
    this.decoder = new VideoDecoder({ output: (f) => (this.out.push(f), poke()), error: (e) => ((this.error = e), poke()) });
    this.decoder.addEventListener("dequeue", poke);
    this.decoder.configure(config);
  }

  wantsMore() {
    return this.decoder.decodeQueueSize < 4 && this.out.length < 4;
  }

  /** @param {EncodedVideoChunk} chunk */
  decode(chunk) {
    this.decoder.decode(chunk);
  }

  flush() {
    this.decoder.flush().then(() => ((this.flushed = true), this.#wake?.()), (e) => ((this.error = e), this.#wake?.()));
  }

  /** Resolves when woken by an output, a dequeue, the flush or an error; or after a moment. */
  async woken() {
    await new Promise((ok) => {
      this.#wake = () => ok(null);
      setTimeout(this.#wake, 20);
    });
    this.#wake = null;
  }

  close() {
    for (const f of this.out) f.close();
    if (this.decoder.state !== "closed") this.decoder.close();
  }
}
