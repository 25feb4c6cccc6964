// Shared by the browser tests and the browser benchmark: a static server for
// dist/ (plus the shared recordings under /data/, read in place, never
// copied) and Debian's Chromium driven by playwright-core.
import { createServer } from "node:http";
import { readFile, stat } from "node:fs/promises";
import { existsSync } from "node:fs";
import { extname, join, normalize, resolve } from "node:path";
import { fileURLToPath } from "node:url";
import { gzipSync } from "node:zlib";
import { chromium } from "playwright-core";

export const ROOT = resolve(fileURLToPath(new URL("../..", import.meta.url)));
export const DIST = join(ROOT, "dist");
export const DATA = resolve(ROOT, "../shared/data");
export const HAVE_DATA = existsSync(DATA);
export const SCREENSHOTS = join(ROOT, "target", "screenshots");
/** The CLI `cargo build --release` made, in CARGO_TARGET_DIR when set. */
export const CLI = join(resolve(ROOT, process.env.CARGO_TARGET_DIR ?? "target"), "release", "embusen");

const TYPES = {
  ".html": "text/html", ".js": "text/javascript", ".mjs": "text/javascript", ".css": "text/css",
  ".wasm": "application/wasm", ".bvh": "text/plain", ".csv": "text/csv", ".png": "image/png",
};

/**
 * Serves dist/ at /, ../shared/data at /data/, and `extra` by path: an HTML
 * page as a string, any other file as `{ type, body }`.
 */
export async function startServer(extra = {}) {
  const server = createServer(async (req, res) => {
    const path = decodeURIComponent(new URL(req.url, "http://x").pathname);
    if (extra[path]) {
      const { type, body } = typeof extra[path] === "string" ? { type: "text/html", body: extra[path] } : extra[path];
      res.writeHead(200, { "content-type": type });
      res.end(body);
      return;
    }
    const [base, rest] = path.startsWith("/data/")
      ? [DATA, path.slice(6)]
      : path.startsWith("/node_modules/three/") // three.js, for the benchmark's comparison only
        ? [join(ROOT, "node_modules/three"), path.slice("/node_modules/three/".length)]
        : [DIST, path.slice(1) || "index.html"];
    const file = normalize(join(base, rest));
    try {
      if (!file.startsWith(base) || !(await stat(file)).isFile()) throw new Error("not a file");
      res.writeHead(200, { "content-type": TYPES[extname(file)] ?? "application/octet-stream" });
      res.end(await readFile(file));
    } catch {
      res.writeHead(404);
      res.end("not found");
    }
  });
  await new Promise((ok) => server.listen(0, "127.0.0.1", ok));
  const url = `http://127.0.0.1:${server.address().port}`;
  return { url, close: () => new Promise((ok) => server.close(ok)) };
}

/** Headless Chromium from Debian with software WebGL2 (never a downloaded browser). */
export function launchBrowser() {
  return chromium.launch({
    executablePath: "/usr/bin/chromium",
    args: [
      "--no-sandbox", "--use-angle=swiftshader", "--enable-unsafe-swiftshader",
      "--disable-background-networking", "--disable-component-update", "--disable-sync", "--no-first-run",
    ],
  });
}

/** Opens `path` and waits until the player in `selector` has a recording. */
export async function openApp(browser, url, path = "/", selector = "#app") {
  const page = await browser.newPage({ viewport: { width: 1280, height: 800 }, acceptDownloads: true });
  const errors = [];
  page.on("pageerror", (e) => errors.push(String(e)));
  page.on("console", (m) => m.type() === "error" && errors.push(m.text()));
  await page.goto(url + path);
  await waitReady(page, selector);
  return { page, errors };
}

export async function waitReady(page, selector = "#app") {
  await page.waitForFunction(
    (sel) => {
      const el = document.querySelector(sel);
      return el?.embusen?.player && el.dataset.state === "ready" && el.embusen.player.frame_count() > 0;
    },
    selector,
    { timeout: 30000 },
  );
}

/**
 * What opening `path` downloads until the player in `selector` plays the
 * demo and the page is idle: every response, each gzipped (level 9) as a
 * server would send it. Shared by the size gate (app.test.mjs) and the
 * benchmark, so that both measure the same thing.
 * @returns {Promise<{total: number, sizes: Array<[string, number]>}>} bytes
 */
export async function firstLoad(browser, url, path, selector) {
  const page = await browser.newPage({ viewport: { width: 1280, height: 800 } });
  try {
    const bodies = [];
    page.on("response", (r) => bodies.push(r.body().then((b) => [new URL(r.url()).pathname, gzipSync(b, { level: 9 }).length])));
    await page.goto(url + path);
    await waitReady(page, selector);
    await page.waitForLoadState("networkidle");
    const sizes = await Promise.all(bodies);
    return { total: sizes.reduce((sum, [, size]) => sum + size, 0), sizes };
  } finally {
    await page.close();
  }
}

/**
 * The first load's gate (gzipped bytes): it catches accidents, such as the
 * take's code fetched with the demo or a debug build; it does not steer design.
 */
export const FIRST_LOAD_LIMIT_BYTES = 360_000;

/** The pages whose first load is measured: the app and an embed, each with the player's selector. */
export const FIRST_LOAD_PAGES = [["/", "#app"], ["/embed.html", "#player"]];

/**
 * Where the 3D view of the player in `selector` draws the hips paths (the
 * corrected yellow, the original blue; not a camera track's magenta, which
 * its camera shares, standing metres away) and the light grey body: each
 * one's bounding box in the canvas's pixels and its count, and the
 * canvas's size.
 */
export const viewExtent = (page, selector = "#app") => page.evaluate((selector) => {
  const source = document.querySelector(`${selector} canvas.view`);
  const copy = document.createElement("canvas");
  [copy.width, copy.height] = [source.width, source.height];
  const ctx = copy.getContext("2d");
  ctx.drawImage(source, 0, 0);
  const data = ctx.getImageData(0, 0, copy.width, copy.height).data;
  const empty = () => ({ count: 0, left: Infinity, right: -Infinity, top: Infinity, bottom: -Infinity });
  const [path, body] = [empty(), empty()];
  const add = (box, x, y) => {
    box.count++;
    [box.left, box.right, box.top, box.bottom] = [Math.min(box.left, x), Math.max(box.right, x), Math.min(box.top, y), Math.max(box.bottom, y)];
  };
  const near = (r, g, b, rgb) => Math.abs(r - rgb[0]) <= 40 && Math.abs(g - rgb[1]) <= 40 && Math.abs(b - rgb[2]) <= 40;
  for (let i = 0; i < data.length; i += 4) {
    const [r, g, b] = [data[i], data[i + 1], data[i + 2]];
    const [x, y] = [(i / 4) % copy.width, Math.floor(i / 4 / copy.width)];
    if (near(r, g, b, [255, 200, 40]) || near(r, g, b, [90, 140, 255])) add(path, x, y);
    if (Math.min(r, g, b) > 110 && Math.max(r, g, b) - Math.min(r, g, b) < 30) add(body, x, y);
  }
  return { path, body, width: copy.width, height: copy.height };
}, selector);

/** Whether `box` of `viewExtent`'s drawing is there and whole: not cut by the view's edges. */
export const wholeInView = (box, seen) =>
  box.count > 50 && box.left > 0 && box.top > 0 && box.right < seen.width - 1 && box.bottom < seen.height - 1;

/**
 * Counts the pixels of a canvas that differ from its background (the colour
 * at the top-left corner), optionally only within [x, y, w, h] in canvas pixels.
 */
export function countDrawnPixels(page, canvasSelector, rect) {
  return page.evaluate(([sel, rect]) => {
    const source = document.querySelector(sel);
    const copy = document.createElement("canvas");
    copy.width = source.width;
    copy.height = source.height;
    const ctx = copy.getContext("2d");
    ctx.drawImage(source, 0, 0);
    const [x, y, w, h] = rect ?? [0, 0, copy.width, copy.height];
    const bg = ctx.getImageData(0, 0, 1, 1).data;
    const data = ctx.getImageData(Math.floor(x), Math.floor(y), Math.max(1, Math.floor(w)), Math.max(1, Math.floor(h))).data;
    let count = 0;
    for (let i = 0; i < data.length; i += 4) {
      const d = Math.abs(data[i] - bg[0]) + Math.abs(data[i + 1] - bg[1]) + Math.abs(data[i + 2] - bg[2]);
      if (d > 60) count++;
    }
    return count;
  }, [canvasSelector, rect ?? null]);
}
