// @ts-check
// The take's inputs: the files the user gives (or the page fetches), each
// recognised by its name, kept until replaced; and the list that says which
// are there.

import { loadCameraModule } from "./modules.js";
import { closeVideo, measureFps, openVideo } from "../video-frames.js";

/** @typedef {import("./protocol.js").NamedFile} NamedFile */
/** @typedef {{name: string, bytes: ArrayBuffer}} FileBytes a file read here */
/**
 * The take's video: its file, its element, its rate as the camera recorded it.
 * @typedef {{file: Blob, name: string, element: HTMLVideoElement, fps: number, frameCount: number}} TakeVideo
 */
/** @typedef {"video" | "recording" | "camera" | "background" | "board" | "boardLayout" | "truth" | "track" | "json"} InputKind */

/** What kind of input a file is, by its name (then its type). @param {File} file @returns {InputKind | null} */
export function kindOf(file) {
  const name = file.name.toLowerCase();
  if (name.endsWith(".bvh")) return "recording";
  // `embusen track` names its CSV NAME.track.csv (beside NAME.bvh).
  if (name.endsWith(".track.csv")) return "track";
  if (name.endsWith(".csv")) return "truth";
  if (name.endsWith(".json")) return "json";
  if (name.endsWith(".png")) return name.includes("board") ? "board" : "background";
  if (/\.(mp4|m4v|webm|mov|mkv|ogv)$/.test(name) || file.type.startsWith("video/")) return "video";
  return null;
}

/** A file's bytes as text, as the camera module reads a camera.json. @param {FileBytes} f */
export const textOf = (f) => new TextDecoder().decode(f.bytes);

/** The take's inputs, as opened so far. */
export class TakeInputs {
  /** @type {TakeVideo | undefined} */ video;
  /** @type {FileBytes | undefined} */ recording;
  /** The camera (`calibratedHere`: from a board or clicks here, so no lens to calibrate a board with). @type {(FileBytes & {calibratedHere?: boolean}) | undefined} */
  camera;
  /** (`fromVideo`: the median of the video's frames.) @type {(FileBytes & {fromVideo?: boolean}) | undefined} */
  background;
  /** @type {FileBytes | undefined} */ board;
  /** @type {FileBytes | undefined} */ boardLayout;
  /** @type {FileBytes | undefined} */ truth;
  /** A track `embusen track` (or the page) wrote for this take: shown as it is. @type {FileBytes | undefined} */ track;

  /**
   * Opens one input; the others stay. A video replaces the one before (closed).
   * @param {Blob} blob
   * @param {string} name
   * @param {InputKind | null} kind
   */
  async add(blob, name, kind) {
    if (kind === "video") {
      const video = await openVideo(blob, name);
      try {
        const fps = (await loadCameraModule()).nominal_fps(await measureFps(video));
        const frameCount = Math.round(video.duration * fps);
        if (this.video) closeVideo(this.video.element);
        this.video = { file: blob, name, element: video, fps, frameCount };
      } catch (e) {
        closeVideo(video);
        throw e;
      }
    } else if (kind === "json") {
      // A camera or a board's layout, told apart by what is in it.
      const bytes = await blob.arrayBuffer();
      let parsed;
      try {
        parsed = JSON.parse(new TextDecoder().decode(bytes));
      } catch (e) {
        throw new Error(`${name}: not JSON (${e instanceof Error ? e.message : e})`);
      }
      if (parsed && typeof parsed === "object" && "squares_x" in parsed) this.boardLayout = { name, bytes };
      else this.camera = { name, bytes };
    } else if (kind !== null) {
      this[kind] = { name, bytes: await blob.arrayBuffer() };
    } else {
      throw new Error(`${name}: not a video, a BVH, a camera.json, a board's layout or a PNG still`);
    }
  }

  /** What a track still needs. */
  missing() {
    return /** @type {const} */ (["video", "recording", "camera"]).filter((k) => !this[k]);
  }

  /** The list of inputs, as HTML: each there or missing. */
  listHtml() {
    const line = (/** @type {string} */ what, /** @type {string | undefined} */ have) =>
      `<li class="${have ? "have" : "missing"}">${what}: ${have ?? "missing"}</li>`;
    const v = this.video;
    return [
      line("video", v && `${v.name}, ${v.element.videoWidth}×${v.element.videoHeight}, ${v.fps.toFixed(3)} fps, ${v.frameCount} frames`),
      line("suit recording (BVH)", this.recording?.name),
      line("camera (camera.json)", this.camera?.name),
      line("background still (PNG)", this.background?.name ?? (v ? "none: the median of the video's frames will stand in" : undefined)),
      ...(this.truth ? [line("true hips (CSV)", this.truth.name)] : []),
      ...(this.track ? [line("track (CSV)", this.track.name)] : []),
      ...(this.board || this.boardLayout
        ? [line("board still", this.board?.name), line("board layout (BOARD.json)", this.boardLayout?.name)]
        : []),
    ].join("");
  }

  /** Releases the video. */
  close() {
    if (this.video) closeVideo(this.video.element);
  }
}

/** The stem of the take's files, for the names of its exports. @param {TakeInputs} inputs */
export const stemOf = (inputs) => (inputs.recording?.name ?? "take").replace(/(\.suit)?\.bvh$/i, "");

/** A copy of a file's bytes to send to a worker (which takes it). @param {FileBytes} f @returns {NamedFile} */
export const copyOf = (f) => ({ name: f.name, bytes: f.bytes.slice(0) });
