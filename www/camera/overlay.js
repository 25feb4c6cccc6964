// @ts-check
// What the panel draws over the video, as the camera sees it: the floor
// grid (every 50 cm), the board's corners found, the body's outline where
// the track puts it, the floor corners clicked, and (paused) what the
// tracker sees in the frame shown: its mask, edges, distances. Colours from
// the core's theme (the camera module's `overlay_colours`).

import { loadCameraModule } from "./modules.js";
import { textOf } from "./inputs.js";
import { frameAt } from "../video-frames.js";

/** @typedef {import("./inputs.js").ViewInputs} ViewInputs */
/** @typedef {import("./inputs.js").FileBytes} FileBytes */
/** @typedef {import("../pkg-camera/embusen.js").PixelPoint} PixelPoint */
/** @typedef {import("../pkg-camera/embusen.js").FrameLayer} FrameLayer */

/**
 * What to draw over the frame shown.
 * @typedef {object} OverlayContent
 * @property {ViewInputs} view the view whose video it is over
 * @property {number} frame the video frame shown
 * @property {PixelPoint[]} boardCorners the board's corners found
 * @property {Uint32Array | undefined} outline the body's outline in this frame (x, y pixel after pixel)
 * @property {PixelPoint[]} clicked the floor corners clicked so far
 */

/** The video overlay of one panel. */
export class VideoOverlay {
  /** The floor grid, of the camera it was made for (a camera parsed once). @type {{camera: FileBytes, lines: PixelPoint[][]} | null} */
  #grid = null;
  /**
   * The pipeline's stages of one frame as pictures (`FramePainter`), for
   * the background they were made against; `reading` while a frame is read.
   * @type {{background: FileBytes, painter: import("../pkg-camera/embusen.js").FramePainter, frame: number, images: Map<FrameLayer, ImageBitmap>, reading: boolean} | null}
   */
  #layers = null;
  #destroyed = false;

  /**
   * @param {HTMLCanvasElement} canvas
   * @param {HTMLInputElement[]} layerBoxes the layers' check boxes (`data-layer`)
   * @param {() => boolean} selected whether the boxes are this overlay's (its view is the selected one)
   * @param {(text: string, isError?: boolean) => void} say
   */
  constructor(canvas, layerBoxes, selected, say) {
    this.canvas = canvas;
    this.layerBoxes = layerBoxes;
    this.selected = selected;
    this.say = say;
  }

  /** The layers asked for. @returns {FrameLayer[]} */
  wanted() {
    if (!this.selected()) return [];
    return this.layerBoxes.filter((b) => b.checked).map((b) => /** @type {FrameLayer} */ (b.dataset.layer));
  }

  /** Whether the layers of `frame` are drawn (or none are asked for). @param {number} frame */
  layersReady(frame) {
    return this.wanted().length === 0 || (!this.#layers?.reading && this.#layers?.frame === frame);
  }

  /** Whether a frame's layers are being read. */
  get reading() {
    return Boolean(this.#layers?.reading);
  }

  /** Draws `content` (asynchronously the first time a camera is seen). @param {OverlayContent} content */
  async draw(content) {
    const video = content.view.video?.element;
    const ctx = this.#destroyed ? null : this.canvas.getContext("2d");
    if (!ctx) return;
    if (!video) {
      ctx.clearRect(0, 0, this.canvas.width, this.canvas.height);
      return;
    }
    if (this.canvas.width !== video.videoWidth || this.canvas.height !== video.videoHeight) {
      [this.canvas.width, this.canvas.height] = [video.videoWidth, video.videoHeight];
    }
    const m = await loadCameraModule();
    const colours = m.overlay_colours();
    const camera = content.view.camera;
    if (!camera) {
      ctx.clearRect(0, 0, this.canvas.width, this.canvas.height);
      drawClicked(ctx, content.clicked, colours.clicked_css);
      return;
    }
    const grid = this.#gridOf(camera, m);
    ctx.clearRect(0, 0, this.canvas.width, this.canvas.height);
    this.#drawLayers(ctx, content, video);
    ctx.strokeStyle = colours.floor_grid_css;
    ctx.lineWidth = 1;
    ctx.beginPath();
    for (const line of grid) {
      // Pixel centres to canvas coordinates.
      line.forEach(({ x_px, y_px }, i) => (i === 0 ? ctx.moveTo(x_px + 0.5, y_px + 0.5) : ctx.lineTo(x_px + 0.5, y_px + 0.5)));
    }
    ctx.stroke();
    ctx.fillStyle = colours.board_corner_css;
    for (const { x_px, y_px } of content.boardCorners) ctx.fillRect(x_px - 1.5 + 0.5, y_px - 1.5 + 0.5, 3, 3);
    const outline = content.outline;
    ctx.fillStyle = colours.outline_css;
    for (let i = 0; outline && i + 1 < outline.length; i += 2) ctx.fillRect(outline[i], outline[i + 1], 1, 1);
    drawClicked(ctx, content.clicked, colours.clicked_css);
  }

  /**
   * The floor grid of `camera`, made once per camera, not per frame drawn.
   * @param {FileBytes} camera
   * @param {typeof import("../pkg-camera/embusen.js")} m
   */
  #gridOf(camera, m) {
    if (this.#grid?.camera !== camera) {
      /** @type {PixelPoint[][]} */
      let lines = [];
      try {
        const view = new m.CameraView(camera.name, textOf(camera));
        lines = view.floor_grid_px(50, 500).map((l) => l.points);
        view.free();
      } catch (e) {
        this.say(e instanceof Error ? e.message : String(e), true);
      }
      this.#grid = { camera, lines };
    }
    return this.#grid.lines;
  }

  /**
   * The layers asked for, when the video is paused: drawn when they are of
   * the frame shown, else read (and drawn then).
   * @param {CanvasRenderingContext2D} ctx
   * @param {OverlayContent} content
   * @param {HTMLVideoElement} video
   */
  #drawLayers(ctx, content, video) {
    const wanted = this.wanted();
    if (wanted.length === 0 || !video.paused) return;
    if (this.#layers?.frame !== content.frame) {
      void this.readLayers(content);
      return;
    }
    for (const name of wanted) {
      const image = this.#layers.images.get(name);
      if (image) ctx.drawImage(image, 0, 0);
    }
  }

  /**
   * Reads the frame shown and makes its layers (the image pipeline run on
   * it here, as the tracker runs it), then draws them. One frame at a time:
   * the frame's exact read seeks the video, which asks for the overlay again.
   * @param {OverlayContent} content
   */
  async readLayers(content) {
    const { video, background } = content.view;
    if (!video || !background || this.#layers?.reading) return;
    const frame = content.frame;
    try {
      const m = await loadCameraModule();
      if (this.#layers?.background !== background) {
        this.#layers?.painter.free();
        const painter = new m.FramePainter(background.name, new Uint8Array(background.bytes));
        this.#layers = { background, painter, frame: -1, images: new Map(), reading: false };
      }
      const layers = this.#layers;
      layers.reading = true;
      const read = await frameAt(video.element, frame, video.fps);
      layers.painter.set_frame({ luma: read.luma, stride: read.stride, full_range: read.fullRange }, `${video.name} frame ${frame}`);
      const [w, h] = [video.element.videoWidth, video.element.videoHeight];
      /** @type {Map<FrameLayer, ImageBitmap>} */
      const images = new Map();
      for (const b of this.layerBoxes) {
        const name = /** @type {FrameLayer} */ (b.dataset.layer);
        // The module hands back a copy in an ArrayBuffer of its own (never shared memory).
        const rgba = /** @type {Uint8ClampedArray<ArrayBuffer>} */ (layers.painter.layer(name));
        images.set(name, await createImageBitmap(new ImageData(rgba, w, h)));
      }
      layers.images = images;
      layers.frame = frame;
    } catch (e) {
      this.say(e instanceof Error ? e.message : String(e), true);
      for (const b of this.layerBoxes) b.checked = false;
    } finally {
      if (this.#layers) this.#layers.reading = false;
    }
    void this.draw(content);
  }

  destroy() {
    this.#destroyed = true;
    this.#layers?.painter.free();
    this.#layers = null;
  }
}

/**
 * The floor corners clicked, numbered in the order asked.
 * @param {CanvasRenderingContext2D} ctx
 * @param {PixelPoint[]} clicked
 * @param {string} colour
 */
function drawClicked(ctx, clicked, colour) {
  ctx.strokeStyle = ctx.fillStyle = colour;
  ctx.lineWidth = 2;
  ctx.font = "bold 14px sans-serif";
  for (const [k, { x_px, y_px }] of clicked.entries()) {
    const [x, y] = [x_px + 0.5, y_px + 0.5]; // pixel centres to canvas coordinates
    ctx.beginPath();
    ctx.arc(x, y, 6, 0, 2 * Math.PI);
    ctx.stroke();
    ctx.fillText(String(k + 1), x + 8, y - 8);
  }
}
