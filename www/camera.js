// @ts-check
// Camera tracking in the page: open a video of a suit session with its BVH, a
// camera.json and a still of the empty room; track the actor in a Web Worker
// (./track-worker.js, the wasm core's CameraJob) while the frames are read
// exactly (./video-frames.js); see the track grow, and save the corrected BVH
// and the hips CSV — the bytes `embusen track` writes for the same files.
// Nothing leaves the machine.
//
//   import { mountCameraTracking } from "./camera.js";
//   const handle = await mountCameraTracking(element, { video: "walk.mp4", src: "walk.suit.bvh",
//     camera: "walk.camera.json", background: "walk.background.png" });
//   const result = await handle.track();   // {recording, csv, warnings, framesPerSecond, ...}
//   handle.destroy();

import { closeVideo, frameAt, measureFps, openVideo } from "./video-frames.js";

/**
 * @typedef {object} CameraOptions
 * @property {string} [video] the video's URL
 * @property {string} [src] the suit recording's (BVH) URL
 * @property {string} [camera] the camera.json's URL
 * @property {string} [background] the background still's URL
 * @property {string} [board] a still of the ChArUco board on the floor (its layout BOARD.json beside it)
 * @property {string} [truth] the true hips per video frame (CSV), to plot the track's error against
 * @property {"fused" | "paper"} [method]
 * @property {number} [offsetS] the time offset between video and BVH (s), as `embusen track --offset-s`
 * @property {boolean} [estimateOffset] estimate the offset after tracking, as `embusen track --estimate-offset`
 * @property {import("./embusen.js").Handle} [player] a player (`mount()`'s handle) to show each track in: the
 *   suit recording opened there, the body solid at the camera track, the camera, the three floor paths
 */

/**
 * @typedef {object} TrackResult
 * @property {string} recording the corrected recording's text
 * @property {string} csv the hips per video frame
 * @property {string[]} warnings
 * @property {number} frames
 * @property {number} framesPerSecond tracked frames per second of wall time, frame reading included
 * @property {number} readMsPerFrame reading a frame: decoding and copying its luma plane in the worker, or a seek here
 * @property {number} trackMsPerFrame the worker's tracking per frame
 * @property {number} scoreMsPerFrame the second worker's scoring of the path search per frame (0 with one)
 * @property {number} workers the workers that tracked: 2 for `fused` (the path search's energies in the second), 1 for `paper`
 * @property {boolean} decodedInWorker whether the worker decoded the frames itself (WebCodecs)
 * @property {string | null} whyNotDecoded why not, when it did not
 * @property {{meanCm: number, p90Cm: number, maxCm: number} | null} truthErrors against the truth, when given
 * @property {number} [offsetEstimateS] the time offset estimated after the track, when asked for
 */

/** @typedef {{name: string, bytes: ArrayBuffer}} NamedFile */

/** What kind of input a file is, by its name (then its type). @param {File} file */
export function kindOf(file) {
  const name = file.name.toLowerCase();
  if (name.endsWith(".bvh")) return "recording";
  if (name.endsWith(".csv")) return "truth";
  if (name.endsWith(".json")) return "json";
  if (name.endsWith(".png")) return name.includes("board") ? "board" : "background";
  if (/\.(mp4|m4v|webm|mov|mkv|ogv)$/.test(name) || file.type.startsWith("video/")) return "video";
  return null;
}

/**
 * A wasm module of the app (`pkg-camera/`, `pkg-board/`), fetched and
 * instantiated on this thread once, the first time it is asked for.
 * @template T
 * @param {() => Promise<T & {default: (options: {module_or_path: URL}) => Promise<unknown>}>} load
 * @param {string} dir
 * @returns {() => Promise<T>}
 */
function lazyModule(load, dir) {
  /** @type {Promise<T> | null} */
  let loaded = null;
  return () =>
    (loaded ??= load().then(async (m) => {
      await m.default({ module_or_path: new URL(`./${dir}/embusen_bg.wasm`, import.meta.url) });
      return m;
    }));
}
/** The camera module (the floor grid), when a take has a camera. */
const loadCameraModule = lazyModule(() => import("./pkg-camera/embusen.js"), "pkg-camera");
/** The board module (the ChArUco detector), only when a board is used. */
const loadBoardModule = lazyModule(() => import("./pkg-board/embusen.js"), "pkg-board");

const PANEL = `
  <div class="camera-controls">
    <label class="file">Open video + BVH + camera.json + background… <input type="file" multiple accept="video/*,.bvh,.json,.png"></label>
    <label>method <select data-setting="method"><option value="fused">fused</option><option value="paper">paper</option></select></label>
    <label title="added to a video frame's time to read the BVH (embusen track --offset-s): positive when the BVH started first">offset
      <input data-setting="offset" type="number" step="0.01" value="0" style="width: 5em"> s</label>
    <label title="after tracking, find the offset at which the suit's pose fits the video best (within 0.25 s; embusen track --estimate-offset)">
      <input type="checkbox" data-setting="estimate-offset"> estimate it</label>
    <button data-action="track">Track</button>
    <button data-action="cancel" disabled>Cancel</button>
    <progress value="0" max="1"></progress>
    <button data-action="export-recording" disabled title="download the corrected BVH">⬇ corrected BVH</button>
    <button data-action="export-track" disabled title="download the hips track with the camera's confidence">⬇ track CSV</button>
    <button data-action="calibrate" disabled>Calibrate from board</button>
    <button data-action="export-camera" disabled title="download the camera as camera.json">⬇ camera.json</button>
    <span class="camera-corners" title="no board? click on the video the corners of a rectangle of known size on the floor">
      <button data-action="click-corners" disabled>Click floor corners</button>
      <label>rectangle <input data-setting="rectangle" value="200x150" size="7"> cm</label>
      <label>focal <input data-setting="focal" placeholder="estimate" size="6"> px</label>
    </span>
  </div>
  <fieldset class="camera-layers" title="what the tracker sees in the frame shown (while paused)">
    <legend>over the video</legend>
    <label><input type="checkbox" data-layer="distance"> distance to edges</label>
    <label><input type="checkbox" data-layer="mask"> foreground mask</label>
    <label><input type="checkbox" data-layer="edges"> edges</label>
    <label><input type="checkbox" data-show="outline" checked> body outline</label>
  </fieldset>
  <ul class="camera-inputs"></ul>
  <p class="camera-status" role="status"></p>
  <div class="camera-views"><div class="camera-video"><canvas class="camera-overlay"></canvas></div><canvas class="camera-top" width="320" height="240"></canvas>
    <canvas class="camera-candidates" width="240" height="240" hidden
      title="the paper's 25 positions tried in the frame shown, by energy (green low, red high); ringed: the one it chose"></canvas></div>
  <canvas class="camera-plot" width="960" height="180" title="click to see that frame"></canvas>`;

/**
 * Mounts the camera tracking panel in `element`.
 * @param {HTMLElement} element
 * @param {CameraOptions} [options]
 */
export async function mountCameraTracking(element, options = {}) {
  element.classList.add("embusen-camera");
  element.innerHTML = PANEL;
  const $ = (/** @type {string} */ sel) => /** @type {HTMLElement} */ (element.querySelector(sel));
  const status = $(".camera-status");
  const progress = /** @type {HTMLProgressElement} */ ($("progress"));
  const trackButton = /** @type {HTMLButtonElement} */ ($('[data-action="track"]'));
  const cancelButton = /** @type {HTMLButtonElement} */ ($('[data-action="cancel"]'));
  const exportRecording = /** @type {HTMLButtonElement} */ ($('[data-action="export-recording"]'));
  const exportTrack = /** @type {HTMLButtonElement} */ ($('[data-action="export-track"]'));
  const methodSelect = /** @type {HTMLSelectElement} */ ($('[data-setting="method"]'));
  const offsetInput = /** @type {HTMLInputElement} */ ($('[data-setting="offset"]'));
  const estimateOffset = /** @type {HTMLInputElement} */ ($('[data-setting="estimate-offset"]'));
  const top = /** @type {HTMLCanvasElement} */ ($(".camera-top"));
  const plot = /** @type {HTMLCanvasElement} */ ($(".camera-plot"));
  /** The track's error against the truth per frame (cm), when a truth was given. @type {Float64Array | null} */
  let errors = null;
  methodSelect.value = options.method ?? "fused";
  offsetInput.value = String(options.offsetS ?? 0);
  estimateOffset.checked = Boolean(options.estimateOffset);

  const calibrateButton = /** @type {HTMLButtonElement} */ ($('[data-action="calibrate"]'));
  const exportCamera = /** @type {HTMLButtonElement} */ ($('[data-action="export-camera"]'));
  const overlay = /** @type {HTMLCanvasElement} */ ($(".camera-overlay"));
  const cornersButton = /** @type {HTMLButtonElement} */ ($('[data-action="click-corners"]'));
  const rectangleInput = /** @type {HTMLInputElement} */ ($('[data-setting="rectangle"]'));
  const focalInput = /** @type {HTMLInputElement} */ ($('[data-setting="focal"]'));
  /** The floor corners clicked so far (x, y video pixels), and whether clicks are taken. */
  let clicked = /** @type {number[]} */ ([]);
  let clicking = false;
  const CORNER_NAMES = ["the origin", "along +x", "the far corner", "along +z"];
  /** (`camera.calibratedHere`: calibrated here, from a board or clicks, so not a lens to calibrate a board with.) */
  /** @type {{truth?: NamedFile, recording?: NamedFile, camera?: NamedFile & {calibratedHere?: boolean}, background?: NamedFile & {fromVideo?: boolean}, board?: NamedFile, boardLayout?: NamedFile, video?: {file: Blob, name: string, element: HTMLVideoElement, fps: number, frameCount: number}}} */
  const inputs = {};
  /** The board's corners found in its still (pixels), drawn over the picture. @type {number[]} */
  let corners = [];
  /** Per video frame, the body's outline where the track puts it (x, y pixel after pixel). @type {Uint32Array[]} */
  let outlines = [];
  /** The floor grid over the video (x, y pixel after pixel, NaN between lines), of the camera it was made for. @type {{camera: NamedFile, px: number[]} | null} */
  let floorGrid = null;
  /**
   * The pipeline's stages of one frame as pictures (`FramePainter`), for the
   * background they were made against; `reading` while a frame is read.
   * @type {{background: NamedFile, painter: any, frame: number, images: Map<string, ImageBitmap>, reading: boolean} | null}
   */
  let layers = null;
  const layerBoxes = /** @type {HTMLInputElement[]} */ (Array.from(element.querySelectorAll("[data-layer]")));
  const outlineBox = /** @type {HTMLInputElement} */ ($('[data-show="outline"]'));
  /** @type {TrackResult | null} */
  let result = null;
  /** @type {Worker | null} */
  let worker = null;
  /** Ends the tracking under way with its message (set while one runs). @type {((e: Error) => void) | null} */
  let abort = null;
  /** Set by `destroy()`: what is still under way ends without touching the page. */
  let destroyed = false;
  const cancel = () => {
    abort?.(new Error("cancelled: the inputs are kept, track again when ready"));
  };
  /** @type {Array<[number, number, number]>} */
  let path = [];
  /** The paper's candidates per frame of the last track: each tried [x, z (cm), energy (px)], the chosen one's index. @type {Array<{tried: number[][], chosen: number}>} */
  let candidates = [];
  const candidatesCanvas = /** @type {HTMLCanvasElement} */ ($(".camera-candidates"));

  const say = (/** @type {string} */ text, /** @type {boolean} */ isError = false) => {
    status.textContent = text;
    status.classList.toggle("error", isError);
  };

  function showInputs() {
    if (destroyed) return;
    const line = (/** @type {string} */ what, /** @type {string | undefined} */ have) =>
      `<li class="${have ? "have" : "missing"}">${what}: ${have ?? "missing"}</li>`;
    const v = inputs.video;
    $(".camera-inputs").innerHTML = [
      line("video", v && `${v.name}, ${v.element.videoWidth}×${v.element.videoHeight}, ${v.fps.toFixed(3)} fps, ${v.frameCount} frames`),
      line("suit recording (BVH)", inputs.recording?.name),
      line("camera (camera.json)", inputs.camera?.name),
      line("background still (PNG)", inputs.background?.name ?? (v ? "none: the median of the video's frames will stand in" : undefined)),
      ...(inputs.truth ? [line("true hips (CSV)", inputs.truth.name)] : []),
      ...(inputs.board || inputs.boardLayout
        ? [line("board still", inputs.board?.name), line("board layout (BOARD.json)", inputs.boardLayout?.name)]
        : []),
    ].join("");
    calibrateButton.disabled = !(inputs.boardLayout && (inputs.board || inputs.video)) || worker !== null;
    calibrateButton.title = inputs.board || !inputs.video
      ? "find the board in its still and calibrate the camera from it"
      : "find the board in the video frame shown and calibrate the camera from it";
    cornersButton.disabled = !inputs.video || worker !== null;
    exportCamera.disabled = !inputs.camera;
    void drawOverlay();
    const missing = ["video", "recording", "camera"].filter((k) => !(/** @type {any} */ (inputs))[k]);
    trackButton.disabled = missing.length > 0 || worker !== null;
    if (missing.length > 0 && !worker) say(`to track, open also: ${missing.join(", ")}`);
  }

  /** Opens one input (a file the user gave, or one fetched); the others stay. */
  async function add(/** @type {Blob} */ blob, /** @type {string} */ name, /** @type {string | null} */ kind) {
    if (kind === "video") {
      const video = await openVideo(blob, name);
      try {
        const fps = (await loadCameraModule()).nominal_fps(await measureFps(video));
        const frameCount = Math.round(video.duration * fps);
        if (inputs.video) closeVideo(inputs.video.element);
        inputs.video = { file: blob, name, element: video, fps, frameCount };
        outlines = [];
        video.controls = true;
        // The overlay follows the frame shown, played or sought.
        const follow = () => {
          void drawOverlay();
          drawPlot();
          drawCandidates();
          if (!video.paused) video.requestVideoFrameCallback(follow);
        };
        video.addEventListener("seeked", follow);
        video.addEventListener("play", follow);
        $(".camera-video").replaceChildren(video, overlay);
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
      if (parsed && typeof parsed === "object" && "squares_x" in parsed) inputs.boardLayout = { name, bytes };
      else inputs.camera = { name, bytes };
    } else if (kind === "recording" || kind === "camera" || kind === "background" || kind === "board" || kind === "boardLayout" || kind === "truth") {
      inputs[kind] = { name, bytes: await blob.arrayBuffer() };
    } else {
      throw new Error(`${name}: not a video, a BVH, a camera.json, a board's layout or a PNG still`);
    }
  }

  /** Opens files in any order, each recognised by its name; a bad one is reported, the rest kept. */
  async function open(/** @type {FileList | File[]} */ files) {
    const problems = [];
    for (const file of Array.from(files)) {
      try {
        await add(file, file.name, kindOf(file));
      } catch (e) {
        problems.push(e instanceof Error ? e.message : String(e));
      }
    }
    result = null;
    showInputs();
    if (problems.length > 0) say(problems.join("; "), true);
  }

  async function openUrl(/** @type {string} */ url, /** @type {string} */ kind) {
    const response = await fetch(url);
    if (!response.ok) throw new Error(`${url}: ${response.status} ${response.statusText}`);
    await add(await response.blob(), url.split("/").pop() || url, kind);
  }

  /** The floor grid (every 50 cm) and the board's corners over the video, as the camera sees them. */
  async function drawOverlay() {
    const video = inputs.video?.element;
    const ctx = destroyed ? null : overlay.getContext("2d");
    if (!ctx) return;
    if (!video) {
      ctx.clearRect(0, 0, overlay.width, overlay.height);
      return;
    }
    if (!inputs.camera) {
      if (overlay.width !== video.videoWidth || overlay.height !== video.videoHeight) {
        [overlay.width, overlay.height] = [video.videoWidth, video.videoHeight];
      }
      ctx.clearRect(0, 0, overlay.width, overlay.height);
      drawClicked(ctx);
      return;
    }
    if (overlay.width !== video.videoWidth || overlay.height !== video.videoHeight) {
      [overlay.width, overlay.height] = [video.videoWidth, video.videoHeight];
    }
    // The grid is the camera's: made once per camera, not per frame drawn.
    const camera = inputs.camera;
    if (floorGrid?.camera !== camera) {
      /** @type {number[]} */
      let px = [];
      try {
        const m = await loadCameraModule();
        px = Array.from(m.floor_grid(camera.name, new TextDecoder().decode(camera.bytes), 50, 500));
      } catch (e) {
        say(e instanceof Error ? e.message : String(e), true);
      }
      floorGrid = { camera, px };
    }
    const grid = floorGrid.px;
    ctx.clearRect(0, 0, overlay.width, overlay.height);
    const wanted = layerBoxes.filter((b) => b.checked).map((b) => /** @type {string} */ (b.dataset.layer));
    if (wanted.length > 0 && video.paused) {
      if (layers?.frame === shownFrame()) for (const name of wanted) {
        const image = layers.images.get(name);
        if (image) ctx.drawImage(image, 0, 0);
      }
      else void readLayers();
    }
    ctx.strokeStyle = "rgba(255, 200, 40, 0.55)";
    ctx.lineWidth = 1;
    ctx.beginPath();
    let pen = false;
    for (let i = 0; i + 1 < grid.length; i += 2) {
      const [x, y] = [grid[i] + 0.5, grid[i + 1] + 0.5]; // pixel centres to canvas coordinates
      if (Number.isNaN(x)) pen = false;
      else if (pen) ctx.lineTo(x, y);
      else (ctx.moveTo(x, y), (pen = true));
    }
    ctx.stroke();
    ctx.fillStyle = "#4ade80";
    for (let i = 0; i + 1 < corners.length; i += 2) ctx.fillRect(corners[i] - 1.5 + 0.5, corners[i + 1] - 1.5 + 0.5, 3, 3);
    const outline = outlineBox.checked ? outlines[shownFrame()] : undefined;
    ctx.fillStyle = "#38bdf8";
    for (let i = 0; outline && i + 1 < outline.length; i += 2) ctx.fillRect(outline[i], outline[i + 1], 1, 1);
    drawClicked(ctx);
  }

  /** The floor corners clicked, numbered in the order asked. @param {CanvasRenderingContext2D} ctx */
  function drawClicked(ctx) {
    ctx.strokeStyle = ctx.fillStyle = "#f472b6";
    ctx.lineWidth = 2;
    ctx.font = "bold 14px sans-serif";
    for (let k = 0; k + 1 < clicked.length; k += 2) {
      const [x, y] = [clicked[k] + 0.5, clicked[k + 1] + 0.5]; // pixel centres to canvas coordinates
      ctx.beginPath();
      ctx.arc(x, y, 6, 0, 2 * Math.PI);
      ctx.stroke();
      ctx.fillText(String(k / 2 + 1), x + 8, y - 8);
    }
  }

  /** Starts (or, asked again, stops) taking the four floor corners' clicks on the video. */
  function clickCorners() {
    clicking = !clicking && Boolean(inputs.video);
    clicked = [];
    overlay.style.pointerEvents = clicking ? "auto" : "";
    overlay.style.cursor = clicking ? "crosshair" : "";
    cornersButton.textContent = clicking ? "Stop clicking" : "Click floor corners";
    if (clicking) {
      inputs.video?.element.pause();
      say(`click corner 1 of 4 on the video: ${CORNER_NAMES[0]} (the rectangle's sides run along world +x, then +z)`);
    }
    void drawOverlay();
  }

  /**
   * The camera from the four corners clicked (`embusen calibrate
   * --floor-corners`); the take's camera when it works, the one before
   * kept when not. Resolves with the figures said.
   */
  async function calibrateFromCorners() {
    const video = inputs.video;
    if (!video || clicked.length !== 8) throw new Error("click the four floor corners first");
    try {
      const size = /^\s*([\d.]+)\s*[x×]\s*([\d.]+)\s*$/.exec(rectangleInput.value);
      if (!size) throw new Error(`the rectangle "${rectangleInput.value}": give its size as WIDTHxDEPTH in cm, e.g. 200x150`);
      const focal = focalInput.value.trim() === "" ? undefined : Number(focalInput.value);
      if (focal !== undefined && !(focal > 0)) throw new Error(`the focal length "${focalInput.value}": a number of pixels, or empty to estimate it`);
      const m = await loadCameraModule();
      const fit = m.calibrate_floor_corners(video.element.videoWidth, video.element.videoHeight, new Float64Array(clicked),
        Number(size[1]), Number(size[2]), focal);
      const outcome = { rmsPx: fit.rms_px(), centerSigmaCmPerPx: fit.center_sigma_cm_per_px(), focalPx: fit.focal_px(), camera: fit.camera_json(), cornersPx: [...clicked] };
      fit.free();
      inputs.camera = { name: "camera.json (from 4 floor corners)", bytes: new TextEncoder().encode(outcome.camera).buffer, calibratedHere: true };
      showInputs();
      say(`calibrated from 4 floor corners: reprojection error ${outcome.rmsPx.toFixed(2)} px (rms), focal length ` +
        `${outcome.focalPx.toFixed(0)} px; a pixel of click error moves the camera ${outcome.centerSigmaCmPerPx.toFixed(1)} cm: check the grid`);
      return outcome;
    } catch (e) {
      say(e instanceof Error ? e.message : String(e), true);
      throw e;
    }
  }

  /**
   * Reads the frame shown and makes its layers (the image pipeline run on
   * it here, as the tracker runs it), then draws them. One frame at a time:
   * the frame's exact read seeks the video, which asks for the overlay again.
   */
  async function readLayers() {
    const { video, background } = inputs;
    if (!video || !background || layers?.reading) return;
    const frame = shownFrame();
    try {
      const m = await loadCameraModule();
      if (layers?.background !== background) {
        layers?.painter.free();
        layers = { background, painter: new m.FramePainter(background.name, new Uint8Array(background.bytes)), frame: -1, images: new Map(), reading: false };
      }
      layers.reading = true;
      const read = await frameAt(video.element, frame, video.fps);
      layers.painter.set_frame(new Uint8Array(read.luma), read.stride, read.fullRange, `${video.name} frame ${frame}`);
      const [w, h] = [video.element.videoWidth, video.element.videoHeight];
      const images = new Map();
      for (const b of layerBoxes) {
        const name = /** @type {string} */ (b.dataset.layer);
        images.set(name, await createImageBitmap(new ImageData(layers.painter.layer(name), w, h)));
      }
      layers.images = images;
      layers.frame = frame;
    } catch (e) {
      say(e instanceof Error ? e.message : String(e), true);
      for (const b of layerBoxes) b.checked = false;
    } finally {
      if (layers) layers.reading = false;
    }
    void drawOverlay();
  }

  /** The video frame the panel's video shows (frame i spans i/fps to (i+1)/fps). */
  function shownFrame() {
    const v = inputs.video;
    return v ? Math.min(v.frameCount - 1, Math.floor(v.element.currentTime * v.fps + 1e-6)) : 0;
  }

  /**
   * Finds the board in its still and calibrates the camera from it (with the
   * lens of a camera.json the user opened, when there is one, else the focal
   * length too); the result is the take's camera. Resolves with the reprojection error.
   * @returns {Promise<{rmsPx: number, maxPx: number, corners: number, camera: string}>}
   */
  async function calibrate() {
    const { boardLayout, video } = inputs;
    const camera = inputs.camera?.calibratedHere ? undefined : inputs.camera;
    if (!boardLayout || !(inputs.board || video)) throw new Error("open the board's layout (BOARD.json) and a still of the board or a video showing it first");
    try {
      say("finding the board…");
      // Without a still, the video frame shown, read exactly.
      const board = inputs.board ?? (await videoFrameStill(/** @type {NonNullable<typeof video>} */ (video)));
      const m = await loadBoardModule();
      const text = (/** @type {NamedFile} */ f) => new TextDecoder().decode(f.bytes);
      const found = m.calibrate_board(
        board.name, new Uint8Array(board.bytes), boardLayout.name, text(boardLayout),
        camera?.name ?? "", camera ? text(camera) : undefined,
      );
      const cameraJson = found.camera_json();
      corners = Array.from(found.corners_px());
      const outcome = { rmsPx: found.rms_px(), maxPx: found.max_px(), corners: corners.length / 2, camera: cameraJson };
      found.free();
      inputs.camera = {
        name: `camera.json (from ${board.name})`, bytes: new TextEncoder().encode(cameraJson).buffer, calibratedHere: true,
      };
      showInputs();
      say(`calibrated from ${board.name}: ${outcome.corners} corners, reprojection error ${outcome.rmsPx.toFixed(2)} px ` +
        `(rms; largest ${outcome.maxPx.toFixed(2)} px)` + (camera ? `, with the lens of ${camera.name}` : ", focal length from this view"));
      return outcome;
    } catch (e) {
      say(e instanceof Error ? e.message : String(e), true);
      throw e;
    }
  }

  function drawTop() {
    const ctx = top.getContext("2d");
    if (!ctx) return;
    ctx.fillStyle = "#1e2126";
    ctx.fillRect(0, 0, top.width, top.height);
    if (path.length === 0) return;
    const xs = path.map((p) => p[0]), zs = path.map((p) => p[1]);
    const [x0, x1, z0, z1] = [Math.min(...xs), Math.max(...xs), Math.min(...zs), Math.max(...zs)];
    // The floor seen from above, x right and z down, one scale for both,
    // the path's box in the middle.
    const scale = Math.min((top.width - 20) / Math.max(x1 - x0, 50), (top.height - 30) / Math.max(z1 - z0, 50));
    const [cx, cz] = [(x0 + x1) / 2, (z0 + z1) / 2];
    const at = (/** @type {number[]} */ p) => [top.width / 2 + (p[0] - cx) * scale, (top.height - 10) / 2 + (p[1] - cz) * scale];
    ctx.strokeStyle = "#ffc828";
    ctx.lineWidth = 2;
    ctx.beginPath();
    path.forEach((p, i) => (i === 0 ? ctx.moveTo(at(p)[0], at(p)[1]) : ctx.lineTo(at(p)[0], at(p)[1])));
    ctx.stroke();
    ctx.fillStyle = "#9aa0aa";
    const [sx, sz] = at(path[0]);
    ctx.fillRect(sx - 3, sz - 3, 6, 6);
    // A metre, for scale.
    ctx.fillRect(top.width - 10 - 100 * scale, top.height - 12, 100 * scale, 2);
    ctx.fillText("1 m", top.width - 30, top.height - 16);
    ctx.fillText("the hips from above (■ start)", 10, top.height - 6);
  }

  /**
   * The plots under the views: the camera's confidence per frame (0 to 1)
   * and, with a truth, the track's error (cm); a cursor at the frame shown.
   */
  function drawPlot() {
    const ctx = plot.getContext("2d");
    if (!ctx) return;
    const [w, h] = [plot.width, plot.height];
    ctx.fillStyle = "#1e2126";
    ctx.fillRect(0, 0, w, h);
    const n = inputs.video?.frameCount ?? path.length;
    if (n === 0 || path.length === 0) return;
    const rows = errors ? 2 : 1;
    const rowH = (h - 10) / rows;
    const x = (/** @type {number} */ i) => 40 + (i / Math.max(1, n - 1)) * (w - 50);
    /** @param {ArrayLike<number>} values @param {number} row @param {number} top @param {string} colour @param {string} label */
    const series = (values, row, top, colour, label) => {
      const y0 = 5 + row * rowH;
      const y = (/** @type {number} */ v) => y0 + rowH - 14 - (Math.min(v, top) / top) * (rowH - 20);
      ctx.strokeStyle = "#3a3f47";
      ctx.strokeRect(40, y0 + 4, w - 50, rowH - 16);
      ctx.strokeStyle = colour;
      ctx.beginPath();
      for (let i = 0; i < values.length; i++) (i === 0 ? ctx.moveTo(x(i), y(values[i])) : ctx.lineTo(x(i), y(values[i])));
      ctx.stroke();
      ctx.fillStyle = "#9aa0aa";
      ctx.fillText(label, 44, y0 + 16);
      ctx.fillText(String(top), 4, y0 + 12);
      ctx.fillText("0", 4, y0 + rowH - 12);
    };
    series(path.map((p) => p[2]), 0, 1, "#4ade80", "the camera's confidence per frame");
    if (errors) {
      const top = Math.max(20, Math.ceil(Math.max(...errors) / 10) * 10);
      series(errors, 1, top, "#f87171", `error against ${inputs.truth?.name ?? "the truth"} (cm)`);
    }
    ctx.strokeStyle = "#ffc828";
    const cx = x(shownFrame());
    ctx.beginPath();
    ctx.moveTo(cx, 5);
    ctx.lineTo(cx, h - 5);
    ctx.stroke();
  }

  /**
   * The video frame shown as a still (PNG), to find the board in.
   * @param {{name: string, element: HTMLVideoElement, fps: number}} video
   * @returns {Promise<NamedFile>}
   */
  async function videoFrameStill(video) {
    const m = await loadCameraModule();
    const i = shownFrame();
    const frame = await frameAt(video.element, i, video.fps);
    const name = `${video.name} frame ${i}`;
    const png = m.frame_png(name, video.element.videoWidth, video.element.videoHeight, new Uint8Array(frame.luma), frame.stride, frame.fullRange);
    return { name, bytes: /** @type {ArrayBuffer} */ (png.buffer) };
  }

  /**
   * Without a background still, the empty room as `embusen track` makes it:
   * the per-pixel median of 31 frames spread over the video, each read
   * exactly; kept as the take's background (and said so).
   * @param {{name: string, element: HTMLVideoElement, fps: number, frameCount: number}} video
   * @returns {Promise<NamedFile>}
   */
  async function medianBackground(video) {
    const m = await loadCameraModule();
    const indices = Array.from(m.median_background_frames(video.frameCount));
    const lumas = [];
    let stride = 0;
    let fullRange = false;
    for (const [k, i] of indices.entries()) {
      say(`no background still: reading frame ${k + 1} of the ${indices.length} whose median stands for the empty room…`);
      const frame = await frameAt(video.element, i, video.fps);
      if (k > 0 && frame.stride !== stride) throw new Error(`${video.name}: frames of different strides`);
      [stride, fullRange] = [frame.stride, frame.fullRange];
      lumas.push(new Uint8Array(frame.luma));
    }
    const png = m.median_background_png(video.name, video.element.videoWidth, video.element.videoHeight, lumas, stride, fullRange);
    const background = { name: `the median of ${indices.length} frames of ${video.name}`, bytes: /** @type {ArrayBuffer} */ (png.buffer), fromVideo: true };
    inputs.background = background;
    return background;
  }

  /**
   * The paper's 25 candidates of the frame shown, where they lie on the
   * floor around the last position (seen from above, x right, z down, as
   * the top view), coloured by energy, the chosen one ringed.
   */
  function drawCandidates() {
    const frame = candidates[shownFrame()];
    candidatesCanvas.hidden = candidates.length === 0;
    const ctx = candidatesCanvas.getContext("2d");
    if (!ctx || candidatesCanvas.hidden) return;
    const [w, h] = [candidatesCanvas.width, candidatesCanvas.height];
    ctx.fillStyle = "#1e2126";
    ctx.fillRect(0, 0, w, h);
    ctx.fillStyle = "#9aa0aa";
    if (!frame || frame.tried.length === 0) {
      ctx.fillText("no candidates in this frame (no pose)", 10, h / 2);
      return;
    }
    const finite = frame.tried.map((c) => c[2]).filter(Number.isFinite);
    const [low, high] = [Math.min(...finite), Math.max(...finite)];
    const [x0, z0] = frame.tried[0]; // the first is the last position
    const reach = Math.max(1, ...frame.tried.map(([x, z]) => Math.max(Math.abs(x - x0), Math.abs(z - z0))));
    const scale = (Math.min(w, h - 40) / 2 - 14) / reach;
    const [cx, cy] = [w / 2, (h - 40) / 2 + 8];
    for (const [k, [xCm, zCm, e]] of frame.tried.entries()) {
      const [x, y] = [cx + (xCm - x0) * scale, cy + (zCm - z0) * scale];
      const t = Number.isFinite(e) && high > low ? (e - low) / (high - low) : Number.isFinite(e) ? 0 : 1;
      ctx.fillStyle = Number.isFinite(e) ? `rgb(${Math.round(74 + 174 * t)}, ${Math.round(222 - 109 * t)}, ${Math.round(128 - 15 * t)})` : "#555";
      ctx.beginPath();
      ctx.arc(x, y, 6, 0, 2 * Math.PI);
      ctx.fill();
      if (k === frame.chosen) {
        ctx.strokeStyle = "#ffc828";
        ctx.lineWidth = 2;
        ctx.beginPath();
        ctx.arc(x, y, 10, 0, 2 * Math.PI);
        ctx.stroke();
      }
    }
    ctx.fillStyle = "#9aa0aa";
    ctx.fillText(`the paper's ${frame.tried.length} candidates, frame ${shownFrame()}`, 8, h - 24);
    ctx.fillText(`energy ${low.toFixed(2)}–${high.toFixed(2)} px; ${scale > 0 ? (10 * scale).toFixed(0) : 0} px = 10 cm`, 8, h - 10);
  }

  /**
   * Tracks the open take; resolves with the result, rejects with the message
   * the page shows (the inputs are kept either way).
   * @returns {Promise<TrackResult>}
   */
  async function track() {
    const { video, recording, camera } = inputs;
    if (!video || !recording || !camera) throw new Error("open a video, its BVH and a camera.json first");
    const background = inputs.background ?? (await medianBackground(video).catch((e) => {
      say(e instanceof Error ? e.message : String(e), true);
      throw e;
    }));
    path = [];
    errors = null;
    result = null;
    candidates = [];
    drawCandidates();
    exportRecording.disabled = exportTrack.disabled = true;
    trackButton.disabled = true;
    cancelButton.disabled = false;
    const w = new Worker(new URL("./track-worker.js", import.meta.url), { type: "module" });
    worker = w;
    /** @type {Map<string, (m: any) => void>} */
    const waiting = new Map();
    let inFlight = 0;
    let frameCount = video.frameCount;
    /** @type {(() => void) | null} */
    let slot = null;
    const failed = new Promise((_, reject) => {
      abort = reject;
      w.onmessage = (event) => {
        const m = event.data;
        if (m.type === "error") {
          reject(new Error(m.message));
        } else if (m.type === "progress") {
          inFlight = Math.max(0, inFlight - 1);
          slot?.();
          path.push([m.x, m.z, m.confidence]);
          // The page is redrawn a few times a second, not every frame: each
          // repaint is composited in software, taken from the worker's core.
          if (m.frame % 10 === 0) {
            progress.value = (m.frame + 1) / frameCount;
            drawTop();
            drawPlot();
            say(`tracking: frame ${m.frame + 1} of ${frameCount}`);
          }
        } else waiting.get(m.type)?.(m);
      };
      w.onerror = (e) => reject(new Error(`the tracker's worker failed: ${e.message}`));
    });
    failed.catch(() => {});
    const reply = (/** @type {string} */ type) =>
      Promise.race([new Promise((ok) => waiting.set(type, ok)), failed]);
    const started = performance.now();
    let readMs = 0;
    try {
      const copy = (/** @type {NamedFile} */ f) => ({ name: f.name, bytes: f.bytes.slice(0) });
      const offsetS = offsetInput.value.trim() === "" ? 0 : Number(offsetInput.value);
      const videoBytes = await video.file.arrayBuffer();
      w.postMessage({
        type: "open", recording: copy(recording), camera: copy(camera), background: copy(background),
        video: {
          name: video.name, width: video.element.videoWidth, height: video.element.videoHeight, fps: video.fps,
          frameCount: video.frameCount, bytes: videoBytes,
        },
        method: methodSelect.value, offsetS, estimateOffset: estimateOffset.checked,
        truth: inputs.truth ? copy(inputs.truth) : undefined,
      }, [videoBytes]);
      const opened = /** @type {any} */ (await reply("opened"));
      frameCount = opened.frameCount;
      if (opened.warnings.length > 0) say(opened.warnings.join("; "));
      // The worker decodes the frames itself (WebCodecs, each frame once, in
      // order) where it can read the container; else they are read here, a
      // seek each.
      if (!opened.decodes) {
        for (let i = 0; i < frameCount; i++) {
          const t = performance.now();
          const frame = /** @type {import("./video-frames.js").LumaFrame} */ (await Promise.race([frameAt(video.element, i, video.fps), failed]));
          readMs += performance.now() - t;
          // At most a few frames wait in the worker: memory stays bounded.
          while (inFlight >= 3) await Promise.race([new Promise((ok) => (slot = () => ok(null))), failed]);
          inFlight++;
          w.postMessage({ type: "frame", luma: frame.luma, stride: frame.stride, fullRange: frame.fullRange }, [frame.luma]);
        }
        w.postMessage({ type: "finish" });
      }
      const done = /** @type {any} */ (await reply("done"));
      progress.value = 1;
      const seconds = (performance.now() - started) / 1000;
      outlines = [];
      for (let at = 0; at < done.outlines.length; ) {
        const n = done.outlines[at];
        outlines.push(done.outlines.subarray(at + 1, at + 1 + 2 * n));
        at += 1 + 2 * n;
      }
      candidates = [];
      for (let at = 0; at < done.candidates.length; ) {
        const [n, chosen] = [done.candidates[at], done.candidates[at + 1]];
        const tried = Array.from({ length: n }, (_, k) => Array.from(done.candidates.subarray(at + 2 + 3 * k, at + 5 + 3 * k)));
        candidates.push({ tried, chosen });
        at += 2 + 3 * n;
      }
      if (candidates.every((c) => c.tried.length === 0)) candidates = [];
      drawCandidates();
      void drawOverlay();
      errors = done.errors ? done.errors.subarray(3) : null;
      drawPlot();
      result = {
        recording: done.recording, csv: done.csv, warnings: done.warnings, frames: done.frames,
        framesPerSecond: done.frames / seconds, readMsPerFrame: opened.decodes ? done.decodeMsPerFrame : readMs / done.frames,
        trackMsPerFrame: done.msPerFrame, scoreMsPerFrame: done.scoreMsPerFrame, workers: opened.workers,
        decodedInWorker: opened.decodes, whyNotDecoded: opened.why ?? null,
        truthErrors: done.errors ? { meanCm: done.errors[0], p90Cm: done.errors[1], maxCm: done.errors[2] } : null,
      };
      drawTop();
      await showInPlayer(recording, camera, done);
      /** @type {string} */
      let offsetSaid = done.offsetProblem ? `; ${done.offsetProblem}` : "";
      if (done.offset) {
        const estimate = done.offset[0];
        result.offsetEstimateS = estimate;
        offsetSaid = `; estimated offset: the BVH runs ${estimate.toFixed(3)} s ahead of the video`;
        // Another frame's pose: worth tracking again (the CLI does it itself).
        if (Math.abs(estimate - offsetS) * video.fps > 0.5) {
          offsetInput.value = String(estimate);
          offsetSaid += " (now in the offset field: track again to use it)";
        }
      }
      const truthSaid = result.truthErrors
        ? `; against ${inputs.truth?.name}: mean ${result.truthErrors.meanCm.toFixed(1)} cm, p90 ${result.truthErrors.p90Cm.toFixed(1)}, max ${result.truthErrors.maxCm.toFixed(1)}`
        : done.truthProblem ? `; ${done.truthProblem}` : "";
      say(`${methodSelect.value}: ${done.frames} frames tracked, ${result.framesPerSecond.toFixed(1)} frames per second` +
        truthSaid + offsetSaid + (done.warnings.length > 0 ? `; ${done.warnings.join("; ")}` : "") +
        (/** @type {any} */ (background).fromVideo ? `; no background still: ${background.name} stands for the empty room` : ""));
      exportRecording.disabled = exportTrack.disabled = false;
      return result;
    } catch (e) {
      say(e instanceof Error ? e.message : String(e), true);
      throw e;
    } finally {
      abort = null;
      w.terminate();
      worker = null;
      cancelButton.disabled = true;
      showInputs();
    }
  }

  /**
   * Shows the take just tracked in the player given (`options.player`): its
   * suit recording opened there (unless it is already), then the body at
   * the camera track, the camera and the paths in its 3D view.
   * @param {NamedFile} recording
   * @param {NamedFile} camera
   * @param {any} done the worker's last message
   */
  async function showInPlayer(recording, camera, done) {
    const player = options.player;
    if (!player) return;
    try {
      if (player.player.info().name !== recording.name) {
        await player.open([new File([recording.bytes], recording.name)]);
      }
      const m = await loadCameraModule();
      // The frustum reaches a metre ahead: the camera's size in the room's scale.
      const frustumCm = m.camera_frustum(camera.name, new TextDecoder().decode(camera.bytes), 100);
      player.showCameraTake({ bodyShapeJson: done.bodyShapeJson, cameraHipsCm: done.trackedHipsCm, frustumCm });
    } catch {
      // The player says what went wrong in its own error box; the track stands.
    }
  }

  function download(/** @type {string} */ text, /** @type {string} */ name) {
    const a = document.createElement("a");
    a.href = URL.createObjectURL(new Blob([text], { type: "text/plain" }));
    a.download = name;
    a.click();
    setTimeout(() => URL.revokeObjectURL(a.href), 1000);
  }
  const stem = () => (inputs.recording?.name ?? "take").replace(/(\.suit)?\.bvh$/i, "");

  const input = /** @type {HTMLInputElement} */ ($('input[type="file"]'));
  input.addEventListener("change", () => input.files && open(input.files));
  element.addEventListener("dragover", (e) => e.preventDefault());
  element.addEventListener("drop", (e) => {
    e.preventDefault();
    if (e.dataTransfer?.files) void open(e.dataTransfer.files);
  });
  for (const box of [...layerBoxes, outlineBox]) box.addEventListener("change", () => void drawOverlay());
  /** Resolves with each calibration from clicks (for the handle). @type {((o: any) => void) | null} */
  let cornersDone = null;
  cornersButton.addEventListener("click", clickCorners);
  overlay.addEventListener("click", (e) => {
    if (!clicking || !inputs.video) return;
    const rect = overlay.getBoundingClientRect();
    // Canvas coordinates to pixel centres (the pixel (0, 0)'s centre is at 0.5, 0.5 of the canvas).
    clicked.push((e.clientX - rect.left) * (overlay.width / rect.width) - 0.5, (e.clientY - rect.top) * (overlay.height / rect.height) - 0.5);
    void drawOverlay();
    if (clicked.length < 8) {
      say(`click corner ${clicked.length / 2 + 1} of 4 on the video: ${CORNER_NAMES[clicked.length / 2]}`);
      return;
    }
    const corners = clicked;
    clickCorners(); // stops taking clicks
    clicked = corners;
    calibrateFromCorners().then((o) => cornersDone?.(o), (e) => cornersDone?.({ error: e.message }));
  });
  element.addEventListener("keydown", (e) => {
    if (clicking && e.key === "Escape") (clickCorners(), say("the corners were not taken: the camera is as it was"));
  });
  trackButton.addEventListener("click", () => void track().catch(() => {}));
  cancelButton.addEventListener("click", cancel);
  calibrateButton.addEventListener("click", () => void calibrate().catch(() => {}));
  plot.addEventListener("click", (e) => {
    const v = inputs.video;
    if (!v) return;
    const rect = plot.getBoundingClientRect();
    const at = ((e.clientX - rect.left) * (plot.width / rect.width) - 40) / (plot.width - 50);
    const frame = Math.round(Math.min(1, Math.max(0, at)) * (v.frameCount - 1));
    v.element.currentTime = (frame + 0.5) / v.fps;
  });
  exportCamera.addEventListener("click", () => inputs.camera && download(new TextDecoder().decode(inputs.camera.bytes), "camera.json"));
  exportRecording.addEventListener("click", () => result && download(result.recording, `${stem()}.tracked.bvh`));
  exportTrack.addEventListener("click", () => result && download(result.csv, `${stem()}.tracked.track.csv`));

  const loads = [];
  for (const [key, kind] of [["video", "video"], ["src", "recording"], ["camera", "camera"], ["background", "background"], ["board", "board"], ["truth", "truth"]]) {
    const url = /** @type {any} */ (options)[key];
    if (url) loads.push(openUrl(url, kind).catch((e) => say(e.message, true)));
  }
  // A board's layout lies beside its still, as for `embusen calibrate`.
  if (options.board) loads.push(openUrl(options.board.replace(/\.png$/i, ".json"), "boardLayout").catch((e) => say(e.message, true)));
  await Promise.all(loads);
  showInputs();

  const handle = {
    element,
    open,
    track,
    calibrate,
    /** Resolves with the next calibration from clicked corners (its figures, or `{error}`). */
    nextCornersCalibration: () => new Promise((ok) => (cornersDone = ok)),
    /** The paper's candidates of video frame `i` of the last track (none for `fused`). */
    candidatesAt: (/** @type {number} */ i) =>
      candidates[i] ? { energies: candidates[i].tried.map((c) => c[2]), chosen: candidates[i].chosen } : null,
    /** The body's outline over video frame `i` where the last track puts it (x, y pixel after pixel). */
    outlineAt: (/** @type {number} */ i) => Array.from(outlines[i] ?? []),
    cancel,
    get result() { return result; },
    /**
     * Shows `names` ("mask", "edges", "distance") over the video, the others
     * hidden; resolves when the frame shown has them drawn.
     * @param {string[]} names
     */
    async showLayers(names) {
      for (const b of layerBoxes) b.checked = names.includes(/** @type {string} */ (b.dataset.layer));
      await drawOverlay();
      while (names.length > 0 && (layers?.reading || layers?.frame !== shownFrame())) {
        if (layers?.reading) await new Promise((ok) => setTimeout(ok, 20));
        else await readLayers();
      }
    },
    destroy() {
      destroyed = true;
      cancel();
      worker?.terminate();
      worker = null;
      layers?.painter.free();
      layers = null;
      if (inputs.video) closeVideo(inputs.video.element);
      element.replaceChildren();
      element.classList.remove("embusen-camera");
    },
  };
  /** @type {any} */ (element).embusenCamera = handle;
  return handle;
}
