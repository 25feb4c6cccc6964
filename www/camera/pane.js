// @ts-check
// One camera's place in the panel: its video, the overlay drawn over it
// (./overlay.js), and what the last track and calibration left to draw
// there. A take filmed by several cameras has a pane per view, side by
// side (beside the player's 3D view when there is one); the selected one
// is framed.

import { VideoOverlay } from "./overlay.js";

/** A view's video and overlay. */
export class ViewPane {
  /** Per video frame the body's outline where the last track puts it. @type {Uint32Array[]} */ outlines = [];
  /** The board's corners found in its still. @type {import("../pkg-camera/embusen.js").PixelPoint[]} */ boardCorners = [];

  /**
   * @param {HTMLElement} box the video's box (`.camera-video`), holding `canvas`
   * @param {HTMLCanvasElement} canvas the overlay
   * @param {HTMLInputElement[]} layerBoxes the layers' check boxes, which act on the selected pane alone
   * @param {() => boolean} selected whether this pane is the selected one
   * @param {(text: string, isError?: boolean) => void} say
   */
  constructor(box, canvas, layerBoxes, selected, say) {
    this.box = box;
    this.canvas = canvas;
    this.overlay = new VideoOverlay(canvas, layerBoxes, selected, say);
  }

  /**
   * A new pane's box, its overlay in it, for a view after the first.
   * @param {HTMLInputElement[]} layerBoxes
   * @param {() => boolean} selected
   * @param {(text: string, isError?: boolean) => void} say
   */
  static made(layerBoxes, selected, say) {
    const box = Object.assign(document.createElement("div"), { className: "camera-video" });
    const canvas = Object.assign(document.createElement("canvas"), { className: "camera-overlay" });
    box.append(canvas);
    return new ViewPane(box, canvas, layerBoxes, selected, say);
  }

  /** Puts `video` in the box, under the overlay. @param {HTMLVideoElement} video */
  show(video) {
    this.box.replaceChildren(video, this.canvas);
  }

  destroy() {
    this.overlay.destroy();
  }
}
