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

/**
 * A JSON file's kind by what is in it: a board's layout has `squares_x`,
 * anything else is taken for a camera (and said so if it is not one);
 * "json" when it does not parse (`add` says why).
 * @param {Blob} file
 * @returns {Promise<InputKind>}
 */
export async function jsonKindOf(file) {
  try {
    return isBoardLayout(JSON.parse(await file.text())) ? "boardLayout" : "camera";
  } catch {
    return "json";
  }
}

/** Whether parsed JSON is a board's layout (it has `squares_x`) rather than a camera. @param {unknown} parsed */
const isBoardLayout = (parsed) => Boolean(parsed) && typeof parsed === "object" && "squares_x" in /** @type {object} */ (parsed);

/** A file's bytes as text, as the camera module reads a camera.json. @param {FileBytes} f */
export const textOf = (f) => new TextDecoder().decode(f.bytes);

/** The kinds of input each camera of a take has its own of. */
const PER_VIEW = /** @type {const} */ (["video", "camera", "background", "board", "boardLayout"]);

/** What one camera of the take gives: its video, its camera, its empty room, its board. */
export class ViewInputs {
  /** @type {TakeVideo | undefined} */ video;
  /** The camera (`calibratedHere`: from a board or clicks here, so no lens to calibrate a board with). @type {(FileBytes & {calibratedHere?: boolean}) | undefined} */
  camera;
  /** (`fromVideo`: the median of the video's frames.) @type {(FileBytes & {fromVideo?: boolean}) | undefined} */
  background;
  /** @type {FileBytes | undefined} */ board;
  /** @type {FileBytes | undefined} */ boardLayout;
  /** The offset field's text for this view: added to a video frame's time to read the BVH (s). */
  offsetText = "0";

  /** The offset's seconds: 0 when empty, NaN when it is no number (a track refuses it, saying so). */
  offsetS() {
    const text = this.offsetText.trim();
    return text === "" ? 0 : Number(text);
  }

  /** Releases the video. */
  close() {
    if (this.video) closeVideo(this.video.element);
  }
}

/**
 * The take's inputs, as opened so far: the suit's recording, a truth and a
 * track for the whole take, and per camera (view) its own files, as
 * `embusen track` takes several videos. One view is selected: what the
 * calibration and the overlay's layers act on, and where files go.
 */
export class TakeInputs {
  /** @type {FileBytes | undefined} */ recording;
  /** @type {FileBytes | undefined} */ truth;
  /** A track `embusen track` (or the page) wrote for this take: shown as it is. @type {FileBytes | undefined} */ track;
  /** The take's cameras, the first the one whose frames the track is on. @type {ViewInputs[]} */
  views = [new ViewInputs()];
  /** The index of the selected view. */
  selected = 0;

  /** The selected view. */
  get view() {
    return this.views[this.selected];
  }

  get video() { return this.view.video; }
  get camera() { return this.view.camera; }
  set camera(c) { this.view.camera = c; }
  get background() { return this.view.background; }
  set background(b) { this.view.background = b; }
  get board() { return this.view.board; }
  get boardLayout() { return this.view.boardLayout; }

  /** View `k`, added (after empty ones, as needed) when the take has fewer. @param {number} k */
  viewAt(k) {
    while (this.views.length <= k) this.views.push(new ViewInputs());
    return this.views[k];
  }

  /**
   * Opens one input into `view` (a take-wide one, the recording, a truth or
   * a track, into the take); the others stay. A video replaces the view's
   * one before (closed).
   * @param {Blob} blob
   * @param {string} name
   * @param {InputKind | null} kind
   * @param {ViewInputs} [view] the selected one when not given
   */
  async add(blob, name, kind, view = this.view) {
    if (kind === "video") {
      const video = await openVideo(blob, name);
      try {
        const fps = (await loadCameraModule()).nominal_fps(await measureFps(video));
        const frameCount = Math.round(video.duration * fps);
        view.close();
        view.video = { file: blob, name, element: video, fps, frameCount };
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
      if (isBoardLayout(parsed)) view.boardLayout = { name, bytes };
      else view.camera = { name, bytes };
    } else if (kind === "recording" || kind === "truth" || kind === "track") {
      this[kind] = { name, bytes: await blob.arrayBuffer() };
    } else if (kind !== null) {
      view[kind] = { name, bytes: await blob.arrayBuffer() };
    } else {
      throw new Error(`${name}: not a video, a BVH, a camera.json, a board's layout or a PNG still`);
    }
  }

  /**
   * Where each of `files` goes, as `embusen track` pairs its flags with its
   * videos: the i-th video, and the i-th of each kind a camera has its own
   * of, to the i-th view from the selected one (views added as needed);
   * the recording, a truth and a track to the take.
   * @template {{name: string}} F
   * @param {F[]} files
   * @param {(f: F) => InputKind | null} kindOfFile
   * @returns {Array<[F, ViewInputs]>}
   */
  placesOf(files, kindOfFile) {
    /** @type {Map<string, number>} */
    const seen = new Map();
    return files.map((f) => {
      const kind = kindOfFile(f);
      // A JSON not yet told apart (see `jsonKindOf`) counts as a camera.
      const counted = kind === "json" ? "camera" : kind;
      if (counted === null || !(/** @type {readonly string[]} */ (PER_VIEW).includes(counted))) {
        return [f, this.view];
      }
      const k = seen.get(counted) ?? 0;
      seen.set(counted, k + 1);
      return [f, this.viewAt(this.selected + k)];
    });
  }

  /**
   * The views a track takes: all but those added last and left empty (a
   * `+ camera` given nothing does not stop a track).
   */
  get tracked() {
    const isEmpty = (/** @type {ViewInputs} */ v) => !v.video && !v.camera && !v.background && !v.board && !v.boardLayout;
    let n = this.views.length;
    while (n > 1 && isEmpty(this.views[n - 1])) n--;
    return this.views.slice(0, n);
  }

  /** What a track still needs, each view's named when there are several. */
  missing() {
    if (this.tracked.length === 1) {
      const view = this.views[0];
      return [view.video ? [] : ["video"], this.recording ? [] : ["recording"], view.camera ? [] : ["camera"]].flat();
    }
    const views = this.tracked.flatMap((v, k) => [v.video ? [] : [`view ${k + 1}'s video`], v.camera ? [] : [`view ${k + 1}'s camera`]].flat());
    return [...(this.recording ? [] : ["recording"]), ...views];
  }

  /** The list of inputs, as HTML: each there or missing. */
  listHtml() {
    const line = (/** @type {string} */ what, /** @type {string | undefined} */ have) =>
      `<li class="${have ? "have" : "missing"}">${what}: ${have ?? "missing"}</li>`;
    const several = this.views.length > 1;
    const viewLines = (/** @type {ViewInputs} */ view, /** @type {number} */ k) => {
      const v = view.video;
      const of = several ? `view ${k + 1}'s ` : "";
      return [
        line(`${of}video`, v && `${v.name}, ${v.element.videoWidth}×${v.element.videoHeight}, ${v.fps.toFixed(3)} fps, ${v.frameCount} frames`),
        line(`${of}camera (camera.json)`, view.camera?.name),
        line(`${of}background still (PNG)`, view.background?.name ?? (v ? "none: the median of the video's frames will stand in" : undefined)),
        ...(view.board || view.boardLayout
          ? [line(`${of}board still`, view.board?.name), line(`${of}board layout (BOARD.json)`, view.boardLayout?.name)]
          : []),
      ];
    };
    return [
      ...viewLines(this.views[0], 0),
      line("suit recording (BVH)", this.recording?.name),
      ...(this.truth ? [line("true hips (CSV)", this.truth.name)] : []),
      ...(this.track ? [line("track (CSV)", this.track.name)] : []),
      ...this.views.slice(1).flatMap((v, k) => viewLines(v, k + 1)),
    ].join("");
  }

  /** Releases the videos. */
  close() {
    for (const v of this.views) v.close();
  }
}

/** The stem of the take's files, for the names of its exports. @param {TakeInputs} inputs */
export const stemOf = (inputs) => (inputs.recording?.name ?? "take").replace(/(\.suit)?\.bvh$/i, "");

/** A copy of a file's bytes to send to a worker (which takes it). @param {FileBytes} f @returns {NamedFile} */
export const copyOf = (f) => ({ name: f.name, bytes: f.bytes.slice(0) });
