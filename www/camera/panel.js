// @ts-check
// The camera panel's elements: its HTML, and each control found once, typed.

const PANEL = `
  <div class="camera-controls">
    <label class="file">Open video + BVH + camera.json + background… <input type="file" multiple accept="video/*,.bvh,.json,.png"></label>
    <label>method <select data-setting="method"><option value="fused">fused</option><option value="paper">paper</option></select></label>
    <label title="added to a video frame's time to read the BVH (embusen track --offset-s): positive when the BVH started first">offset
      <input data-setting="offset" type="number" step="0.01" value="0" style="width: 5em"> s</label>
    <label title="after tracking, find the offset at which the suit's pose fits the video best (within 0.25 s; embusen track --estimate-offset)">
      <input type="checkbox" data-setting="estimate-offset"> estimate it</label>
    <button data-action="add-view" title="another camera of the same take: the files opened next are its, the i-th video and the i-th camera.json (…) to the i-th view, as embusen track pairs them">+ camera</button>
    <button data-action="track">Track</button>
    <button data-action="cancel" disabled>Cancel</button>
    <progress value="0" max="1"></progress>
    <button data-action="export-recording" disabled title="download the BVH with its hips on the camera's track (what embusen track writes), not the player's method's">⬇ BVH on the camera track</button>
    <button data-action="export-track" disabled title="download the camera's hips track with its confidence per video frame">⬇ camera track CSV</button>
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
  <div class="camera-views"><div class="camera-videos"><div class="camera-video"><canvas class="camera-overlay"></canvas></div></div><canvas class="camera-top" width="320" height="240"></canvas>
    <canvas class="camera-candidates" width="240" height="240" hidden
      title="the paper's 25 positions tried in the frame shown, by energy (green low, red high); ringed: the one it chose"></canvas></div>
  <canvas class="camera-plot" width="960" height="180" title="click to see that frame"></canvas>`;

/**
 * Fills `element` with the panel and finds its controls.
 * @param {HTMLElement} element
 */
export function buildPanel(element) {
  element.classList.add("embusen-camera");
  element.innerHTML = PANEL;
  /**
   * The element at `selector`, which must be a `type`.
   * @template {Element} T
   * @param {string} selector
   * @param {new (...args: any[]) => T} type (any: a constructor's arguments are whatever the DOM's are)
   * @returns {T}
   */
  const get = (selector, type) => {
    const found = element.querySelector(selector);
    if (!(found instanceof type)) throw new Error(`embusen: no ${type.name} at ${selector}`);
    return found;
  };
  const button = (/** @type {string} */ action) => get(`[data-action="${action}"]`, HTMLButtonElement);
  const setting = (/** @type {string} */ name) => get(`[data-setting="${name}"]`, HTMLInputElement);
  return {
    status: get(".camera-status", HTMLElement),
    inputList: get(".camera-inputs", HTMLElement),
    videoBox: get(".camera-video", HTMLElement),
    /** The views' video boxes, moved beside the player's 3D view with a take. */
    videos: get(".camera-videos", HTMLElement),
    progress: get("progress", HTMLProgressElement),
    fileInput: get('input[type="file"]', HTMLInputElement),
    addView: button("add-view"),
    track: button("track"),
    cancel: button("cancel"),
    exportRecording: button("export-recording"),
    exportTrack: button("export-track"),
    calibrate: button("calibrate"),
    exportCamera: button("export-camera"),
    clickCorners: button("click-corners"),
    method: get('[data-setting="method"]', HTMLSelectElement),
    offset: setting("offset"),
    estimateOffset: setting("estimate-offset"),
    rectangle: setting("rectangle"),
    focal: setting("focal"),
    layerBoxes: Array.from(element.querySelectorAll("[data-layer]")).filter((b) => b instanceof HTMLInputElement),
    outlineBox: get('[data-show="outline"]', HTMLInputElement),
    overlay: get(".camera-overlay", HTMLCanvasElement),
    top: get(".camera-top", HTMLCanvasElement),
    candidates: get(".camera-candidates", HTMLCanvasElement),
    plot: get(".camera-plot", HTMLCanvasElement),
  };
}

/** @typedef {ReturnType<typeof buildPanel>} PanelElements */

