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

import { buildPanel } from "./camera/panel.js";
import { download, fetchOk, messageOf } from "./files.js";
import { TakeInputs, jsonKindOf, kindOf, stemOf } from "./camera/inputs.js";
import { ViewPane } from "./camera/pane.js";
import { TakePlots } from "./camera/plots.js";
import { CORNER_NAMES, calibrateFromBoard, calibrateFromCorners } from "./camera/calibration.js";
import { showFinishedTake, trackTake } from "./camera/track.js";
import { videoClock } from "./camera/clock.js";

/** @typedef {import("./camera/inputs.js").ViewInputs} ViewInputs */

export { kindOf };

/**
 * A take filmed by several cameras gives a list for each option a camera
 * has its own of (`video`, `camera`, `background`, `board`, `offsetS`), the
 * i-th for the i-th view, as `embusen track` pairs its flags; one for all
 * is one for the first.
 * @typedef {object} CameraOptions
 * @property {string | string[]} [video] the video's URL
 * @property {string} [src] the suit recording's (BVH) URL
 * @property {string | string[]} [camera] the camera.json's URL
 * @property {string | string[]} [background] the background still's URL
 * @property {string | string[]} [board] a still of the ChArUco board on the floor (its layout BOARD.json beside it)
 * @property {string} [truth] the true hips per video frame (CSV), to plot the track's error against
 * @property {string} [track] a track `embusen track` wrote (NAME.track.csv), `src` the BVH it wrote with it:
 *   the take is shown as tracked, with no tracking
 * @property {boolean} [autotrack] tracks on opening when the take's inputs are there (not with `track`)
 * @property {"fused" | "paper"} [method]
 * @property {number | number[]} [offsetS] the time offset between video and BVH (s), as `embusen track --offset-s`
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
  /** Per view its video and overlay, as `inputs.views`. @type {ViewPane[]} */ panes;
  /** The floor corners clicked so far (on the selected view), and whether clicks are taken. @type {PixelPoint[]} */ clicked = [];
  clicking = false;
  /** Resolves with each calibration from clicks (for the handle). @type {((o: object) => void) | null} */ cornersDone = null;
  destroyed = false;

  /** @param {HTMLElement} element @param {CameraOptions} options */
  constructor(element, options) {
    this.element = element;
    this.options = options;
    this.ui = buildPanel(element);
    this.panes = [new ViewPane(this.ui.videoBox, this.ui.overlay, this.ui.layerBoxes, () => this.inputs.selected === 0, (t, e) => this.say(t, e))];
    this.plots = new TakePlots({ top: this.ui.top, series: this.ui.plot, candidates: this.ui.candidates });
    this.ui.method.value = options.method ?? "fused";
    this.offsetsGiven = [options.offsetS ?? []].flat();
    this.inputs.views[0].offsetText = String(this.offsetsGiven[0] ?? 0);
    this.ui.offset.value = this.inputs.view.offsetText;
    this.ui.estimateOffset.checked = Boolean(options.estimateOffset);
  }

  /** View `k`, added (with its pane) when the take has fewer. @param {number} k */
  viewAt(k) {
    this.paneOf(k);
    for (let n = this.inputs.views.length; n <= k; n++) {
      // One offset given is every view's, as `embusen track --offset-s`.
      this.inputs.viewAt(n).offsetText = String(this.offsetsGiven[n] ?? this.offsetsGiven[0] ?? 0);
    }
    return this.inputs.views[k];
  }

  /** View `k`'s pane, made when there is none. @param {number} k */
  paneOf(k) {
    while (this.panes.length <= k) {
      const n = this.panes.length;
      const pane = ViewPane.made(this.ui.layerBoxes, () => this.inputs.selected === n, (t, e) => this.say(t, e));
      pane.box.addEventListener("click", () => this.select(n));
      pane.canvas.addEventListener("click", (e) => this.clickCorner(e));
      this.ui.videos.append(pane.box);
      this.panes.push(pane);
    }
    this.ui.videos.classList.toggle("several", this.panes.length > 1);
    this.panes.forEach((p, i) => p.box.classList.toggle("selected", i === this.inputs.selected));
    return this.panes[k];
  }

  /** Selects view `k`: the files opened next go to it, the calibration and the layers act on it. @param {number} k */
  select(k) {
    if (k === this.inputs.selected || this.clicking || k >= this.inputs.views.length) return;
    this.keepOffsetField();
    this.inputs.selected = k;
    this.clicked = []; // the corners clicked on the view left
    this.ui.offset.value = this.inputs.view.offsetText;
    this.paneOf(k);
    this.showInputs();
    if (this.inputs.views.length > 1) this.say(`view ${k + 1} selected: the files opened now are its; calibration and the layers act on it`);
  }

  /** The selected view's pane. */
  get pane() {
    return this.paneOf(this.inputs.selected);
  }

  /** The selected view's offset: 0 when empty, NaN when it is no number (a track refuses it, saying so). */
  offsetS() {
    this.keepOffsetField();
    return this.inputs.view.offsetS();
  }

  /**
   * The offset field is the selected view's: its text kept there, however
   * it was set (typed, or by a page's script), before the view is left or
   * its offset read.
   */
  keepOffsetField() {
    this.inputs.view.offsetText = this.ui.offset.value;
  }

  /** @param {string} text @param {boolean} [isError] */
  say(text, isError = false) {
    this.ui.status.textContent = text;
    this.ui.status.classList.toggle("error", isError);
  }

  /** The frame shown of view `k`'s video, the selected one's by default (frame i spans i/fps to (i+1)/fps). */
  shownFrame(k = this.inputs.selected) {
    const v = this.inputs.views[k]?.video;
    return v ? Math.min(v.frameCount - 1, Math.floor(v.element.currentTime * v.fps + 1e-6)) : 0;
  }

  /** What to draw over view `k`'s video (the selected one's by default). */
  overlayContent(k = this.inputs.selected) {
    const frame = this.shownFrame(k);
    const pane = this.paneOf(k);
    const outline = this.ui.outlineBox.checked ? pane.outlines[frame] : undefined;
    const clicked = k === this.inputs.selected ? this.clicked : [];
    return { view: this.inputs.views[k], frame, boardCorners: pane.boardCorners, outline, clicked };
  }

  /** Every view's overlay at its frame shown. */
  drawOverlay() {
    if (this.destroyed) return Promise.resolve();
    return Promise.all(this.inputs.views.map((_, k) => this.paneOf(k).overlay.draw(this.overlayContent(k)))).then(() => {});
  }

  /** The plots at the frame shown of the first view (the track is on its frames). */
  paintPlots() {
    const frameCount = this.inputs.views[0].video?.frameCount ?? this.plots.path.length;
    void this.plots.paintSeries(frameCount, this.shownFrame(0));
    void this.plots.paintCandidates(this.shownFrame(0));
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
    ui.addView.disabled = busy;
    ui.exportCamera.disabled = !inputs.camera;
    void this.drawOverlay();
    const missing = inputs.missing();
    ui.track.disabled = missing.length > 0 || busy;
    if (missing.length > 0 && !busy) this.say(`to track, open also: ${missing.join(", ")}`);
  }

  /**
   * Opens one input into `view` (the selected one by default); a video is
   * put in its pane, its overlay following the frame shown, and the player
   * (`options.player`) following the first view's video.
   * @param {Blob} blob @param {string} name @param {import("./camera/inputs.js").InputKind | null} kind
   * @param {ViewInputs} [view]
   */
  async add(blob, name, kind, view = this.inputs.view) {
    await this.inputs.add(blob, name, kind, view);
    const k = this.inputs.views.indexOf(view);
    if (kind !== "video" || !view.video) return;
    const video = view.video.element;
    const pane = this.paneOf(k);
    pane.outlines = [];
    // With a player the first view's video drives the others (one clock);
    // without, each is its own.
    video.controls = k === 0 || !this.options.player;
    const player = this.options.player;
    const follow = () => {
      void this.drawOverlay();
      this.paintPlots();
      player?.wake();
      if (!video.paused) video.requestVideoFrameCallback(follow);
    };
    for (const type of ["seeked", "play", "pause"]) video.addEventListener(type, follow);
    pane.show(video);
    this.followFirstView();
  }

  /**
   * The player (`options.player`) on the first view's clock, the views'
   * videos beside its 3D view; the other views follow the first.
   */
  followFirstView() {
    const player = this.options.player;
    const first = this.inputs.views[0];
    if (!player || !first.video) return;
    player.element.classList.add("embusen-take");
    player.element.append(this.ui.videos);
    // The clock shows a time even while a field holds no number.
    const offsetOf = (/** @type {ViewInputs} */ v) => {
      const offsetS = v === this.inputs.view ? this.offsetS() : v.offsetS();
      return Number.isFinite(offsetS) ? offsetS : 0;
    };
    const others = () => this.inputs.views.slice(1).flatMap((v) => (v.video ? [{ video: v.video, offsetS: offsetOf(v) }] : []));
    player.followClock(videoClock(first.video, () => offsetOf(first), others));
  }

  /**
   * Opens files in any order, each recognised by its name, as `embusen
   * track` pairs them: the i-th video and the i-th of each kind a camera
   * has its own of to the i-th view from the selected one. A bad one is
   * reported, the rest kept.
   * @param {FileList | File[]} files
   */
  async open(files) {
    const problems = [];
    // A camera and a board's layout are both JSON: told apart by what is in them first.
    const kinds = new Map(await Promise.all(Array.from(files, async (f) => /** @type {const} */ (
      [f, kindOf(f) === "json" ? await jsonKindOf(f) : kindOf(f)]))));
    for (const [file, view] of this.inputs.placesOf(Array.from(files), (f) => kinds.get(f) ?? null)) {
      try {
        await this.add(file, file.name, kinds.get(file) ?? null, view);
      } catch (e) {
        problems.push(messageOf(e));
      }
    }
    this.inputs.views.forEach((_, k) => this.paneOf(k));
    this.result = null;
    this.showInputs();
    if (problems.length > 0) this.say(problems.join("; "), true);
    // A track shows once the take it was tracked from is open with it.
    else if (this.inputs.track && Array.from(files).some((f) => ["track", "video", "recording", "json"].includes(kindOf(f) ?? ""))) {
      await this.showFinished();
    }
  }

  /** @param {string} url @param {import("./camera/inputs.js").InputKind} kind @param {ViewInputs} [view] */
  async openUrl(url, kind, view) {
    const response = await fetchOk(url);
    await this.add(await response.blob(), url.split("/").pop() || url, kind, view);
  }

  /**
   * Opened with a track and everything it was tracked from but the still:
   * shows it as tracked (./camera/track.js); a track that is not this
   * take's is said in the status line.
   */
  async showFinished() {
    const { recording, track, tracked } = this.inputs;
    if (!recording || !track || tracked.some((v) => !v.video || !v.camera) || this.run) return;
    this.keepOffsetField();
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
    this.keepOffsetField();
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
      const pane = this.pane; // the view calibrated, whichever is selected when the board is found
      const { outcome, found, said } = await calibrateFromBoard(this.inputs, this.shownFrame());
      pane.boardCorners = found;
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
    this.pane.canvas.style.pointerEvents = this.clicking ? "auto" : "";
    this.pane.canvas.style.cursor = this.clicking ? "crosshair" : "";
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
    const canvas = this.pane.canvas;
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
    if (player && this.inputs.views[0].video) {
      player.element.classList.remove("embusen-take");
      this.ui.videos.remove();
      player.followClock(null);
    }
    this.cancel();
    this.run?.terminate();
    this.run = null;
    for (const pane of this.panes) pane.destroy();
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
  ui.addView.addEventListener("click", () => {
    panel.viewAt(panel.inputs.views.length);
    panel.select(panel.inputs.views.length - 1);
  });
  ui.offset.addEventListener("input", () => panel.keepOffsetField());
  ui.videoBox.addEventListener("click", () => panel.select(0));
  ui.track.addEventListener("click", () => void panel.track().catch(() => {}));
  ui.cancel.addEventListener("click", () => panel.cancel());
  ui.calibrate.addEventListener("click", () => void panel.calibrate().catch(() => {}));
  ui.plot.addEventListener("click", (e) => {
    const v = panel.inputs.views[0].video;
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
  const list = (/** @type {string | string[] | undefined} */ urls) => [urls ?? []].flat();
  /** @type {Array<[string, import("./camera/inputs.js").InputKind, ViewInputs | undefined]>} */
  const given = [];
  // The i-th of each kind a camera has its own of is the i-th view's.
  for (const [urls, kind] of /** @type {const} */ ([[options.video, "video"], [options.camera, "camera"],
    [options.background, "background"], [options.board, "board"]])) {
    list(urls).forEach((url, k) => {
      given.push([url, kind, panel.viewAt(k)]);
      // A board's layout lies beside its still, as for `embusen calibrate`.
      if (kind === "board") given.push([url.replace(/\.png$/i, ".json"), "boardLayout", panel.viewAt(k)]);
    });
  }
  for (const [url, kind] of /** @type {const} */ ([[options.src, "recording"], [options.truth, "truth"], [options.track, "track"]])) {
    if (url) given.push([url, kind, undefined]);
  }
  await Promise.all(given.map(([url, kind, view]) => panel.openUrl(url, kind, view).catch((e) => panel.say(e.message, true))));
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
    /** The body's outline over video frame `i` of view `view` (the first by default) where the last track puts it (x, y pixel after pixel). */
    outlineAt: (/** @type {number} */ i, view = 0) => Array.from(panel.panes[view]?.outlines[i] ?? []),
    /** Selects view `k` (0 the first): the files opened next go to it, calibration and the layers act on it. */
    selectView: (/** @type {number} */ k) => panel.select(k),
    /** How many views (cameras) the take has. */
    get views() { return panel.inputs.views.length; },
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
      while (!panel.pane.overlay.layersReady(panel.shownFrame())) {
        if (panel.pane.overlay.reading) await new Promise((ok) => setTimeout(ok, 20));
        else await panel.pane.overlay.readLayers(panel.overlayContent());
      }
    },
    destroy: () => panel.destroy(),
  };
  /** @type {HTMLElement & {embusenCamera?: typeof handle}} */ (element).embusenCamera = handle;
  return handle;
}
