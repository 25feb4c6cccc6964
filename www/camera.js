// @ts-check
// Camera tracking in the page: open a video of a suit session with its BVH, a
// camera.json and a still of the empty room; track the actor in a Web Worker
// (./track-worker.js, the wasm core's CameraJob) while the frames are read
// exactly (./video-frames.js); see the track grow, and save the corrected BVH
// and the hips CSV — the bytes `embusen track` writes for the same files.
// Nothing leaves the machine. This module mounts the panel and ties its
// parts together (./camera/: the inputs, the overlay over the video, the
// plots, the worker's client, the calibrations).
//
//   import { mountCameraTracking } from "./camera.js";
//   const handle = await mountCameraTracking(element, { video: "walk.mp4", src: "walk.suit.bvh",
//     camera: "walk.camera.json", background: "walk.background.png" });
//   const result = await handle.track();   // {recording, csv, warnings, framesPerSecond, ...}
//   handle.destroy();

import { buildPanel, download } from "./camera/panel.js";
import { TakeInputs, kindOf, stemOf } from "./camera/inputs.js";
import { VideoOverlay } from "./camera/overlay.js";
import { TakePlots } from "./camera/plots.js";
import { CORNER_NAMES, calibrateFromBoard, calibrateFromCorners } from "./camera/calibration.js";
import { showFinishedTake, trackTake } from "./camera/track.js";
import { messageOf } from "./camera/protocol.js";
import { videoClock } from "./camera/clock.js";

export { kindOf };

/**
 * @typedef {object} CameraOptions
 * @property {string} [video] the video's URL
 * @property {string} [src] the suit recording's (BVH) URL
 * @property {string} [camera] the camera.json's URL
 * @property {string} [background] the background still's URL
 * @property {string} [board] a still of the ChArUco board on the floor (its layout BOARD.json beside it)
 * @property {string} [truth] the true hips per video frame (CSV), to plot the track's error against
 * @property {string} [track] a track `embusen track` wrote (NAME.track.csv), `src` the BVH it wrote with it:
 *   the take is shown as tracked, with no tracking
 * @property {boolean} [autotrack] tracks on opening when the take's inputs are there (not with `track`)
 * @property {"fused" | "paper"} [method]
 * @property {number} [offsetS] the time offset between video and BVH (s), as `embusen track --offset-s`
 * @property {boolean} [estimateOffset] estimate the offset after tracking, as `embusen track --estimate-offset`
 * @property {import("./embusen.js").Handle} [player] a player (`mount()`'s handle) to show each track in: the
 *   suit recording opened there, the body solid at the camera track, the camera, the three floor paths
 */

/** @typedef {import("./camera/track.js").TrackResult} TrackResult */
/** @typedef {import("./pkg-camera/embusen.js").PixelPoint} PixelPoint */

/** @type {Promise<unknown> | null} */
let styled = null;
/** The panel's stylesheet (camera/camera.css), once per page; resolves when it is in. */
function loadStyle() {
  styled ??= new Promise((ok) => {
    const link = Object.assign(document.createElement("link"), { rel: "stylesheet", href: new URL("./camera/camera.css", import.meta.url).href });
    link.onload = link.onerror = ok; // without it the panel still works, unstyled
    document.head.append(link);
  });
  return styled;
}

/** One mounted panel: its inputs, what it shows, and the track under way. */
export class CameraPanel {
  inputs = new TakeInputs();
  /** @type {TrackResult | null} */ result = null;
  /** The track under way, which `cancel` ends. @type {{cancel: (e: Error) => void, terminate: () => void} | null} */ run = null;
  /** Per video frame the body's outline where the last track puts it. @type {Uint32Array[]} */ outlines = [];
  /** The board's corners found in its still. @type {PixelPoint[]} */ boardCorners = [];
  /** The floor corners clicked so far, and whether clicks are taken. @type {PixelPoint[]} */ clicked = [];
  clicking = false;
  /** Resolves with each calibration from clicks (for the handle). @type {((o: object) => void) | null} */ cornersDone = null;
  destroyed = false;

  /** @param {HTMLElement} element @param {CameraOptions} options */
  constructor(element, options) {
    this.element = element;
    this.options = options;
    this.ui = buildPanel(element);
    this.overlay = new VideoOverlay(this.ui.overlay, this.ui.layerBoxes, (t, e) => this.say(t, e));
    this.plots = new TakePlots({ top: this.ui.top, series: this.ui.plot, candidates: this.ui.candidates });
    this.ui.method.value = options.method ?? "fused";
    this.ui.offset.value = String(options.offsetS ?? 0);
    this.ui.estimateOffset.checked = Boolean(options.estimateOffset);
  }

  /** The offset field's seconds: 0 when empty, NaN when it is no number (a track refuses it, saying so). */
  offsetS() {
    const text = this.ui.offset.value.trim();
    return text === "" ? 0 : Number(text);
  }

  /** @param {string} text @param {boolean} [isError] */
  say(text, isError = false) {
    this.ui.status.textContent = text;
    this.ui.status.classList.toggle("error", isError);
  }

  /** The video frame shown (frame i spans i/fps to (i+1)/fps). */
  shownFrame() {
    const v = this.inputs.video;
    return v ? Math.min(v.frameCount - 1, Math.floor(v.element.currentTime * v.fps + 1e-6)) : 0;
  }

  overlayContent() {
    const frame = this.shownFrame();
    const outline = this.ui.outlineBox.checked ? this.outlines[frame] : undefined;
    return { inputs: this.inputs, frame, boardCorners: this.boardCorners, outline, clicked: this.clicked };
  }

  drawOverlay() {
    return this.destroyed ? Promise.resolve() : this.overlay.draw(this.overlayContent());
  }

  /** The plots at the frame shown. */
  paintPlots() {
    const frameCount = this.inputs.video?.frameCount ?? this.plots.path.length;
    void this.plots.paintSeries(frameCount, this.shownFrame());
    void this.plots.paintCandidates(this.shownFrame());
  }

  showInputs() {
    if (this.destroyed) return;
    const { inputs, ui } = this;
    const busy = this.run !== null;
    ui.inputList.innerHTML = inputs.listHtml();
    ui.calibrate.disabled = !(inputs.boardLayout && (inputs.board || inputs.video)) || busy;
    ui.calibrate.title = inputs.board || !inputs.video
      ? "find the board in its still and calibrate the camera from it"
      : "find the board in the video frame shown and calibrate the camera from it";
    ui.clickCorners.disabled = !inputs.video || busy;
    ui.exportCamera.disabled = !inputs.camera;
    void this.drawOverlay();
    const missing = inputs.missing();
    ui.track.disabled = missing.length > 0 || busy;
    if (missing.length > 0 && !busy) this.say(`to track, open also: ${missing.join(", ")}`);
  }

  /**
   * Opens one input; a video is put in the panel, its overlay following the
   * frame shown, and the player (`options.player`) following the video.
   * @param {Blob} blob @param {string} name @param {import("./camera/inputs.js").InputKind | null} kind
   */
  async add(blob, name, kind) {
    await this.inputs.add(blob, name, kind);
    if (kind !== "video" || !this.inputs.video) return;
    const video = this.inputs.video.element;
    this.outlines = [];
    video.controls = true;
    const player = this.options.player;
    const follow = () => {
      void this.drawOverlay();
      this.paintPlots();
      player?.wake();
      if (!video.paused) video.requestVideoFrameCallback(follow);
    };
    for (const type of ["seeked", "play", "pause"]) video.addEventListener(type, follow);
    this.ui.videoBox.replaceChildren(video, this.ui.overlay);
    if (!player) return;
    // Beside the 3D view, on the player's clock.
    player.element.classList.add("embusen-take");
    player.element.append(this.ui.videoBox);
    // The clock shows a time even while the field holds no number.
    player.followClock(videoClock(this.inputs.video, () => {
      const offsetS = this.offsetS();
      return Number.isFinite(offsetS) ? offsetS : 0;
    }));
  }

  /** Opens files in any order, each recognised by its name; a bad one is reported, the rest kept. @param {FileList | File[]} files */
  async open(files) {
    const problems = [];
    for (const file of Array.from(files)) {
      try {
        await this.add(file, file.name, kindOf(file));
      } catch (e) {
        problems.push(messageOf(e));
      }
    }
    this.result = null;
    this.showInputs();
    if (problems.length > 0) this.say(problems.join("; "), true);
    // A track shows once the take it was tracked from is open with it.
    else if (this.inputs.track && Array.from(files).some((f) => ["track", "video", "recording", "json"].includes(kindOf(f) ?? ""))) {
      await this.showFinished();
    }
  }

  /** @param {string} url @param {import("./camera/inputs.js").InputKind} kind */
  async openUrl(url, kind) {
    const response = await fetch(url);
    if (!response.ok) throw new Error(`${url}: ${response.status} ${response.statusText}`);
    await this.add(await response.blob(), url.split("/").pop() || url, kind);
  }

  /**
   * Opened with a track and everything it was tracked from but the still:
   * shows it as tracked (./camera/track.js); a track that is not this
   * take's is said in the status line.
   */
  async showFinished() {
    const { video, recording, camera, track } = this.inputs;
    if (!video || !recording || !camera || !track || this.run) return;
    try {
      await showFinishedTake(this);
    } catch (e) {
      this.say(messageOf(e), true);
    }
  }

  /** Reports a failure in the status line, and passes it on. @param {unknown} e @returns {never} */
  fail(e) {
    this.say(messageOf(e), true);
    throw e;
  }

  /** Tracks the open take; see ./camera/track.js. */
  async track() {
    this.plots.clear();
    this.result = null;
    void this.plots.paintCandidates(this.shownFrame());
    try {
      this.result = await trackTake(this);
      return this.result;
    } catch (e) {
      return this.fail(e);
    } finally {
      this.run = null;
      this.ui.cancel.disabled = true;
      this.showInputs();
    }
  }

  /** Finds the board and calibrates the camera from it (./camera/calibration.js). */
  async calibrate() {
    try {
      this.say("finding the board…");
      const { outcome, found, said } = await calibrateFromBoard(this.inputs, this.shownFrame());
      this.boardCorners = found;
      this.showInputs();
      this.say(said);
      return outcome;
    } catch (e) {
      return this.fail(e);
    }
  }

  /** Starts (or, asked again, stops) taking the four floor corners' clicks on the video. */
  toggleClicking() {
    this.clicking = !this.clicking && Boolean(this.inputs.video);
    this.clicked = [];
    this.ui.overlay.style.pointerEvents = this.clicking ? "auto" : "";
    this.ui.overlay.style.cursor = this.clicking ? "crosshair" : "";
    this.ui.clickCorners.textContent = this.clicking ? "Stop clicking" : "Click floor corners";
    if (this.clicking) {
      this.inputs.video?.element.pause();
      this.say(`click corner 1 of 4 on the video: ${CORNER_NAMES[0]} (the rectangle's sides run along world +x, then +z)`);
    }
    void this.drawOverlay();
  }

  /** A click on the video while corners are taken. @param {MouseEvent} e */
  clickCorner(e) {
    if (!this.clicking || !this.inputs.video) return;
    const canvas = this.ui.overlay;
    const rect = canvas.getBoundingClientRect();
    // The picture fills the canvas's box but for bars either side (it is
    // contained, as the video is); canvas coordinates to pixel centres (the
    // pixel (0, 0)'s centre is at 0.5, 0.5 of the canvas).
    const scale = Math.min(rect.width / canvas.width, rect.height / canvas.height);
    this.clicked.push({
      x_px: (e.clientX - rect.left - (rect.width - canvas.width * scale) / 2) / scale - 0.5,
      y_px: (e.clientY - rect.top - (rect.height - canvas.height * scale) / 2) / scale - 0.5,
    });
    void this.drawOverlay();
    if (this.clicked.length < 4) {
      this.say(`click corner ${this.clicked.length + 1} of 4 on the video: ${CORNER_NAMES[this.clicked.length]}`);
      return;
    }
    const corners = this.clicked;
    this.toggleClicking(); // stops taking clicks
    this.clicked = corners;
    calibrateFromCorners(this.inputs, corners, this.ui.rectangle.value, this.ui.focal.value).then(({ outcome, said }) => {
      this.showInputs();
      this.say(said);
      this.cornersDone?.(outcome);
    }, (e) => {
      this.say(messageOf(e), true);
      this.cornersDone?.({ error: messageOf(e) });
    });
  }

  destroy() {
    this.destroyed = true;
    const player = this.options.player;
    if (player && this.inputs.video) {
      player.element.classList.remove("embusen-take");
      this.ui.videoBox.remove();
      player.followClock(null);
    }
    this.cancel();
    this.run?.terminate();
    this.run = null;
    this.overlay.destroy();
    this.inputs.close();
    this.element.replaceChildren();
    this.element.classList.remove("embusen-camera");
  }

  cancel() {
    this.run?.cancel(new Error("cancelled: the inputs are kept, track again when ready"));
  }
}

/**
 * The panel's controls, wired.
 * @param {CameraPanel} panel
 */
function wire(panel) {
  const { ui, element } = panel;
  ui.fileInput.addEventListener("change", () => ui.fileInput.files && panel.open(ui.fileInput.files));
  element.addEventListener("dragover", (e) => e.preventDefault());
  element.addEventListener("drop", (e) => {
    e.preventDefault();
    if (e.dataTransfer?.files) void panel.open(e.dataTransfer.files);
  });
  for (const box of [...ui.layerBoxes, ui.outlineBox]) box.addEventListener("change", () => void panel.drawOverlay());
  ui.clickCorners.addEventListener("click", () => panel.toggleClicking());
  ui.overlay.addEventListener("click", (e) => panel.clickCorner(e));
  element.addEventListener("keydown", (e) => {
    if (panel.clicking && e.key === "Escape") (panel.toggleClicking(), panel.say("the corners were not taken: the camera is as it was"));
  });
  ui.track.addEventListener("click", () => void panel.track().catch(() => {}));
  ui.cancel.addEventListener("click", () => panel.cancel());
  ui.calibrate.addEventListener("click", () => void panel.calibrate().catch(() => {}));
  ui.plot.addEventListener("click", (e) => {
    const v = panel.inputs.video;
    if (!v) return;
    const rect = ui.plot.getBoundingClientRect();
    const at = ((e.clientX - rect.left) * (ui.plot.width / rect.width) - 40) / (ui.plot.width - 50);
    const frame = Math.round(Math.min(1, Math.max(0, at)) * (v.frameCount - 1));
    v.element.currentTime = (frame + 0.5) / v.fps;
  });
  const { inputs } = panel;
  ui.exportCamera.addEventListener("click", () => inputs.camera && download(new TextDecoder().decode(inputs.camera.bytes), "camera.json"));
  ui.exportRecording.addEventListener("click", () => panel.result && download(panel.result.recording, `${stemOf(inputs)}.tracked.bvh`));
  ui.exportTrack.addEventListener("click", () => panel.result && download(panel.result.csv, `${stemOf(inputs)}.tracked.track.csv`));
}

/**
 * The inputs given by address, fetched (a bad one said, the others kept).
 * @param {CameraPanel} panel
 * @param {CameraOptions} options
 */
async function openUrls(panel, options) {
  /** @type {Array<[string | undefined, import("./camera/inputs.js").InputKind]>} */
  const given = [[options.video, "video"], [options.src, "recording"], [options.camera, "camera"],
    [options.background, "background"], [options.board, "board"], [options.truth, "truth"], [options.track, "track"],
    // A board's layout lies beside its still, as for `embusen calibrate`.
    [options.board?.replace(/\.png$/i, ".json"), "boardLayout"]];
  await Promise.all(given.map(([url, kind]) => url && panel.openUrl(url, kind).catch((e) => panel.say(e.message, true))));
}

/**
 * Mounts the camera tracking panel in `element`.
 * @param {HTMLElement} element
 * @param {CameraOptions} [options]
 */
export async function mountCameraTracking(element, options = {}) {
  await loadStyle();
  const panel = new CameraPanel(element, options);
  wire(panel);
  await openUrls(panel, options);
  panel.showInputs();
  if (options.track) await panel.showFinished();
  else if (options.autotrack && panel.inputs.missing().length === 0) void panel.track().catch(() => {});
  const handle = {
    element,
    open: (/** @type {FileList | File[]} */ files) => panel.open(files),
    track: () => panel.track(),
    calibrate: () => panel.calibrate(),
    /** Resolves with the next calibration from clicked corners (its figures, or `{error}`). */
    nextCornersCalibration: () => new Promise((ok) => (panel.cornersDone = ok)),
    /** The paper's candidates of video frame `i` of the last track (none for `fused`). */
    candidatesAt: (/** @type {number} */ i) => panel.plots.candidatesAt(i),
    /** The body's outline over video frame `i` where the last track puts it (x, y pixel after pixel). */
    outlineAt: (/** @type {number} */ i) => Array.from(panel.outlines[i] ?? []),
    cancel: () => panel.cancel(),
    get result() { return panel.result; },
    /**
     * Shows `names` ("mask", "edges", "distance") over the video, the others
     * hidden; resolves when the frame shown has them drawn.
     * @param {string[]} names
     */
    async showLayers(names) {
      for (const b of panel.ui.layerBoxes) b.checked = names.includes(/** @type {string} */ (b.dataset.layer));
      await panel.drawOverlay();
      while (!panel.overlay.layersReady(panel.shownFrame())) {
        if (panel.overlay.reading) await new Promise((ok) => setTimeout(ok, 20));
        else await panel.overlay.readLayers(panel.overlayContent());
      }
    },
    destroy: () => panel.destroy(),
  };
  /** @type {HTMLElement & {embusenCamera?: typeof handle}} */ (element).embusenCamera = handle;
  return handle;
}
