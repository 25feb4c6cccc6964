// The camera tracking in the page (www/camera.js, www/video-frames.js,
// www/track-worker.js) end to end in headless Chromium: a shared scene
// tracked in the page equals `embusen track` byte for byte, every frame of a
// clip whose pixels say its number is read as that frame, and bad input is a
// message in the page. Run by `./build.sh test` after the app is built and
// the CLI compiled (cargo test --release).
import { test, before, after } from "node:test";
import assert from "node:assert/strict";
import { execFileSync } from "node:child_process";
import { mkdtempSync, readFileSync, rmSync, writeFileSync } from "node:fs";
import { tmpdir } from "node:os";
import { join } from "node:path";
import { mkdirSync } from "node:fs";
import { startServer, launchBrowser, viewExtent, wholeInView, CLI, DATA, HAVE_DATA, SCREENSHOTS } from "./harness.mjs";

let server;
let browser;
const scratch = mkdtempSync(join(tmpdir(), "embusen-camera-"));
/** Pages the tests open: the clip is served from the scratch folder. */
const pages = {};

const skipWithoutData = (t) => {
  if (HAVE_DATA) return false;
  if (process.env.CI === "true") assert.fail(`${DATA} not found: CI must have the shared recordings`);
  t.skip(`SKIPPED: ${DATA} not found`);
  console.log(`SKIPPED: ${DATA} not found; the camera tests on the shared scenes did not run`);
  return true;
};

/** Opens the app with the camera panel's inputs given by address; waits until they are read. */
async function openTake(query) {
  const page = await browser.newPage({ viewport: { width: 1280, height: 800 } });
  const errors = [];
  page.on("pageerror", (e) => errors.push(String(e)));
  await page.goto(`${server.url}/?${query}`);
  await page.waitForFunction(() => document.querySelector("#camera-panel")?.embusenCamera, null, { timeout: 60000 });
  return { page, errors };
}

before(async () => {
  server = await startServer(pages);
  browser = await launchBrowser();
});
after(async () => {
  await browser?.close();
  await server?.close();
  rmSync(scratch, { recursive: true, force: true });
});

/**
 * `embusen track` on the shared walk scene, writing `out` (and its track
 * CSV beside it); `withBackground` gives it walk's background still.
 * Returns what it printed.
 */
function trackWalkWithCli(out, extra = [], withBackground = true) {
  const scene = (s) => join(DATA, "optical", `walk${s}`);
  return execFileSync(CLI, [
    "track", scene(".mp4"), "--bvh", scene(".suit.bvh"), "--camera", scene(".camera.json"),
    ...(withBackground ? ["--background", scene(".background.png")] : []), ...extra, "-o", out,
  ], { stdio: "pipe" }).toString();
}

/**
 * After Track on walk with its truth, the player's plots show the camera's
 * result: (d) its path beside the others, (f) per video frame the
 * uncertainty the tracker states and the error against the truth, whose
 * mean is `embusen eval-track`'s for walk; a click on (f) or on the camera's
 * path in (d) seeks the video and the 3D view together.
 */
async function thePlotsFollowTheTake(page) {
  const series = await page.evaluate(() => document.querySelector("#app").embusen.player.camera_take_series());
  assert.ok(series, "the player's plots hold no camera take");
  assert.equal(series.uncertainty_cm.length, 195);
  assert.ok(series.uncertainty_cm.every((u) => Number.isFinite(u) && u > 0), "an uncertainty stated in every frame");
  assert.equal(series.error_cm.length, 195);
  assert.equal(series.truth_name, "walk.truth.csv");
  const pageMeanCm = series.error_cm.reduce((a, b) => a + b, 0) / series.error_cm.length;
  const evalTrack = execFileSync(CLI, ["eval-track", join(DATA, "optical"), "--only", "walk", "--method", "fused"]).toString();
  const row = evalTrack.split("\n").find((l) => /^walk\s+fused\s/.test(l));
  const cliMeanCm = Number(row.split(/\s+/)[2]);
  console.log(`(f) error against walk.truth.csv: mean ${pageMeanCm.toFixed(2)} cm in the page, ${cliMeanCm} cm by eval-track`);
  assert.ok(Math.abs(pageMeanCm - cliMeanCm) <= 0.1, `${pageMeanCm} against eval-track's ${cliMeanCm}`);
  const panels = await page.evaluate(() => document.querySelector("#app").embusen.player.plot_panels());
  const shown = () => page.evaluate(() => ({
    player: document.querySelector("#app").embusen.player.frame(),
    video: Math.floor(document.querySelector(".camera-video video").currentTime * 30 + 1e-6),
  }));
  const settle = async () => {
    await page.waitForTimeout(500);
    return shown();
  };
  // (f), a quarter of the way along: frame 48 or 49 of 195.
  const f = panels[5];
  assert.ok(f.width > 50 && f.height > 10, `(f) laid out: ${JSON.stringify(f)}`);
  await page.locator("#app canvas.plots").scrollIntoViewIfNeeded();
  const plotsBox = await page.locator("#app canvas.plots").boundingBox();
  await page.mouse.click(plotsBox.x + f.x + 0.25 * f.width, plotsBox.y + f.y + 0.5 * f.height);
  const atF = await settle();
  assert.ok(Math.abs(atF.player - 0.25 * 194) <= 1, `a click on (f) seeks the player: ${JSON.stringify(atF)}`);
  assert.equal(atF.video, atF.player, `and the video with it: ${JSON.stringify(atF)}`);
  // (d): the camera's path at frame 150, where the track put the hips.
  const target = await page.evaluate(() => document.querySelector("#app").embusen.player.camera_path_px(150));
  assert.ok(target, "frame 150 of the camera's path is drawn in (d)");
  await page.mouse.click(plotsBox.x + target[0], plotsBox.y + target[1]);
  const atD = await settle();
  assert.ok(Math.abs(atD.player - 150) <= 5, `a click on the camera's path in (d) seeks there: ${JSON.stringify(atD)}`);
  assert.equal(atD.video, atD.player, `and the video with it: ${JSON.stringify(atD)}`);
}

test("a scene tracked in the page is embusen track's, byte for byte, at a measured rate", async (t) => {
  if (skipWithoutData(t)) return;
  const out = join(scratch, "walk.tracked.bvh");
  trackWalkWithCli(out);
  // The player above the panel paused (autoplay=0): its animation would
  // take a core from the tracking.
  const { page, errors } = await openTake(
    "autoplay=0&video=/data/optical/walk.mp4&src=/data/optical/walk.suit.bvh&camera=/data/optical/walk.camera.json" +
      "&background=/data/optical/walk.background.png&truth=/data/optical/walk.truth.csv",
  );
  const inputs = await page.textContent("#camera-panel .camera-inputs");
  assert.match(inputs, /640×480, 30\.000 fps, 195 frames/, inputs);
  const result = await page.evaluate(() => document.querySelector("#camera-panel").embusenCamera.track());
  console.log(
    `walk.mp4 640×480 fused in the page: ${result.framesPerSecond.toFixed(1)} frames per second in all ` +
      `(${result.decodedInWorker ? "decoded in the worker" : `read by seeking (${result.whyNotDecoded})`}: ` +
      `a frame read in ${result.readMsPerFrame.toFixed(1)} ms, tracked in ${result.trackMsPerFrame.toFixed(1)} ms, ` +
      `its path search scored in ${result.scoreMsPerFrame.toFixed(1)} ms by a second worker; ${result.workers} workers)`,
  );
  assert.ok(result.decodedInWorker, `the worker did not decode the video: ${result.whyNotDecoded}`);
  assert.equal(result.workers, 2, "the fused tracker's path search in a second worker");
  assert.equal(result.frames, 195);
  // With the truth given, the error is plotted and said: below the suit's
  // own 13.6 cm on walk.
  assert.ok(result.truthErrors && result.truthErrors.meanCm < 10, JSON.stringify(result.truthErrors));
  assert.match(await page.textContent("#camera-panel .camera-status"), /against walk\.truth\.csv: mean \d/);
  assert.ok(result.recording === readFileSync(out, "utf8"), "the page's corrected BVH is not the CLI's");
  assert.ok(result.csv === readFileSync(join(scratch, "walk.tracked.track.csv"), "utf8"), "the page's track CSV is not the CLI's");
  assert.match(await page.textContent("#camera-panel .camera-status"), /195 frames tracked/);
  // The body's outline where the track puts it, over the frame shown: on
  // the actor (the foreground of the frame against the background still).
  const outline = await page.evaluate(() => document.querySelector("#camera-panel").embusenCamera.outlineAt(100));
  assert.ok(outline.length > 200, `an outline of ${outline.length / 2} pixels over frame 100`);
  await page.evaluate(() => {
    const v = document.querySelector(".camera-video video");
    v.currentTime = 100.5 / 30;
    return new Promise((ok) => v.addEventListener("seeked", () => setTimeout(ok, 300), { once: true }));
  });
  // What the tracker sees in that frame, over the video: the foreground
  // mask lies under the body's outline where the track puts it; the edges
  // are a thin part of it; the distance to them covers the whole frame.
  const layer = (name) =>
    page.evaluate(async (name) => {
      const panel = document.querySelector("#camera-panel");
      panel.querySelector('[data-show="outline"]').checked = false;
      await panel.embusenCamera.showLayers([name]);
      const c = document.querySelector(".camera-overlay");
      const d = c.getContext("2d").getImageData(0, 0, c.width, c.height).data;
      // The layer's own pixels: the grid's lines are yellow, and thin.
      const painted = (i) => (name === "mask" ? d[i + 2] > 200 && d[i + 3] > 90 && d[i + 3] < 160
        : name === "edges" ? d[i] > 200 && d[i + 1] < 120 && d[i + 3] === 255 : d[i + 3] >= 200);
      const on = [];
      for (let i = 0; i < d.length; i += 4) on.push(painted(i));
      const outline = panel.embusenCamera.outlineAt(100);
      let under = 0;
      for (let k = 0; k < outline.length; k += 2) {
        const [x, y] = [outline[k], outline[k + 1]];
        let near = false;
        for (let dy = -2; dy <= 2 && !near; dy++) for (let dx = -2; dx <= 2 && !near; dx++) near = on[(y + dy) * c.width + x + dx];
        if (near) under++;
      }
      return { count: on.filter(Boolean).length, outline: outline.length / 2, under, total: c.width * c.height };
    }, name);
  const mask = await layer("mask");
  assert.ok(mask.count > 2000 && mask.count < 40000, `foreground mask of ${mask.count} px`);
  assert.ok(mask.under > 0.9 * mask.outline, `${mask.under} of ${mask.outline} outline pixels on the mask`);
  const edges = await layer("edges");
  assert.ok(edges.count > 200 && edges.count < mask.count, `edges of ${edges.count} px, mask ${mask.count}`);
  const distance = await layer("distance");
  assert.ok(distance.count > 0.95 * distance.total, `distance layer over ${distance.count} of ${distance.total} px`);
  await page.evaluate(async () => {
    const panel = document.querySelector("#camera-panel");
    panel.querySelector('[data-show="outline"]').checked = true;
    await panel.embusenCamera.showLayers(["mask", "edges"]);
  });
  // The player above shows the take: the suit recording opened there, the
  // body solid at the camera track, the camera, the three paths' legend.
  const player = await page.evaluate(() => {
    const app = document.querySelector("#app");
    return { name: app.embusen.player.info().name, legend: !app.querySelector(".legend").hidden,
      error: app.querySelector(".error").textContent };
  });
  assert.equal(player.name, "walk.suit.bvh", JSON.stringify(player));
  assert.ok(player.legend, `the player shows no camera take: ${player.error}`);
  await thePlotsFollowTheTake(page);
  mkdirSync(SCREENSHOTS, { recursive: true });
  await page.locator("#app").screenshot({ path: join(SCREENSHOTS, "camera-take-in-player.png") });
  // The video and the 3D view side by side above the fold at 1280×800, one
  // above the other at 390×844, each whole in the page's width. Screenshots
  // of the page with the take tracked, wide and narrow (to look at).
  const boxesOf = () => page.evaluate(() => ["#app .camera-video video", "#app canvas.view"].map((s) => {
    const r = document.querySelector(s).getBoundingClientRect();
    return { s, left: r.left, top: r.top + scrollY, right: r.right, bottom: r.bottom + scrollY, width: r.width, height: r.height };
  }));
  await page.evaluate(() => scrollTo(0, 0));
  for (const b of await boxesOf()) {
    assert.ok(b.left >= 0 && b.right <= 1280 && b.top >= 0 && b.bottom <= 800 && b.width > 400 && b.height > 200,
      `at 1280×800 ${JSON.stringify(b)} is not whole above the fold`);
  }
  await page.screenshot({ path: join(SCREENSHOTS, "take-1280x800.png") });
  const panel = page.locator("#camera");
  await panel.scrollIntoViewIfNeeded();
  await page.screenshot({ path: join(SCREENSHOTS, "camera-1280x800.png") });
  await page.setViewportSize({ width: 390, height: 844 });
  await page.waitForTimeout(300);
  const [video, view] = await boxesOf();
  for (const b of [video, view]) assert.ok(b.left >= 0 && b.right <= 390 && b.width > 300 && b.height > 150, `at 390×844 ${JSON.stringify(b)}`);
  assert.ok(video.bottom <= view.top + 1, "at 390×844 the video is above the 3D view");
  await page.evaluate(() => scrollTo(0, 0));
  await page.screenshot({ path: join(SCREENSHOTS, "take-390x844.png"), fullPage: true });
  await panel.scrollIntoViewIfNeeded();
  await page.screenshot({ path: join(SCREENSHOTS, "camera-390x844.png") });
  assert.deepEqual(errors, []);
  await page.close();
});

test("the paper's tracker in the page: the CLI's bytes, and its 25 candidates per frame", async (t) => {
  if (skipWithoutData(t)) return;
  const out = join(scratch, "walk.paper.bvh");
  trackWalkWithCli(out, ["--method", "paper"]);
  const { page, errors } = await openTake(
    "autoplay=0&video=/data/optical/walk.mp4&src=/data/optical/walk.suit.bvh&camera=/data/optical/walk.camera.json" +
      "&background=/data/optical/walk.background.png",
  );
  const result = await page.evaluate(async () => {
    const panel = document.querySelector("#camera-panel");
    panel.querySelector('[data-setting="method"]').value = "paper";
    const r = await panel.embusenCamera.track();
    const v = document.querySelector(".camera-video video");
    v.currentTime = 100.5 / 30;
    await new Promise((ok) => v.addEventListener("seeked", () => setTimeout(ok, 300), { once: true }));
    return { recording: r.recording, workers: r.workers, frame: panel.embusenCamera.candidatesAt(100),
      shown: !panel.querySelector(".camera-candidates").hidden };
  });
  assert.ok(result.recording === readFileSync(out, "utf8"), "the page's paper-tracked BVH is not the CLI's");
  assert.equal(result.workers, 1);
  const { energies, chosen } = result.frame;
  assert.equal(energies.length, 25);
  const least = Math.min(...energies.filter(Number.isFinite));
  assert.equal(chosen, energies.indexOf(least), `chose ${chosen}: ${energies}`);
  assert.ok(result.shown, "the candidates' plot is shown");
  await page.locator("#camera-panel .camera-candidates").screenshot({ path: join(SCREENSHOTS, "camera-paper-candidates.png") });
  assert.deepEqual(errors, []);
  await page.close();
});

test("the time offset is estimated in the page as embusen track --estimate-offset does", async (t) => {
  if (skipWithoutData(t)) return;
  const out = join(scratch, "walk.offset.bvh");
  // Told 0.15 s, which is wrong: the CLI estimates it, and tracks again at the estimate.
  const said = trackWalkWithCli(out, ["--offset-s", "0.15", "--estimate-offset"]);
  const cli = Number(/the BVH runs (-?[\d.]+) s ahead/.exec(said)?.[1]);
  const { page, errors } = await openTake(
    "autoplay=0&video=/data/optical/walk.mp4&src=/data/optical/walk.suit.bvh&camera=/data/optical/walk.camera.json" +
      "&background=/data/optical/walk.background.png",
  );
  const first = await page.evaluate(async () => {
    const panel = document.querySelector("#camera-panel");
    panel.querySelector('[data-setting="offset"]').value = "0.15";
    panel.querySelector('[data-setting="estimate-offset"]').checked = true;
    const r = await panel.embusenCamera.track();
    return { estimate: r.offsetEstimateS, field: panel.querySelector('[data-setting="offset"]').value,
      status: panel.querySelector(".camera-status").textContent };
  });
  assert.equal(first.estimate.toFixed(3), cli.toFixed(3), first.status);
  assert.match(first.status, /estimated offset: the BVH runs -?[\d.]+ s ahead of the video \(now in the offset field/);
  assert.equal(Number(first.field), first.estimate, "the estimate is in the offset field");
  // Tracked again at it: the CLI's bytes.
  const second = await page.evaluate(async () => {
    const panel = document.querySelector("#camera-panel");
    panel.querySelector('[data-setting="estimate-offset"]').checked = false;
    return (await panel.embusenCamera.track()).recording;
  });
  assert.ok(second === readFileSync(out, "utf8"), "tracked at the estimate, the page's BVH is not the CLI's");
  assert.deepEqual(errors, []);
  await page.close();
});

/** Where the OpenCV camera of a camera.json sees world point `p` (cm): its pixel, through the lens. */
function project(camera, p) {
  const M = camera.camera_from_world;
  const c = [0, 1, 2].map((r) => M[r][0] * p[0] + M[r][1] * p[1] + M[r][2] * p[2] + M[r][3]);
  const [x, y] = [c[0] / c[2], c[1] / c[2]];
  const { k1, k2, p1, p2, k3 } = camera.dist;
  const r2 = x * x + y * y;
  const radial = 1 + k1 * r2 + k2 * r2 * r2 + k3 * r2 * r2 * r2;
  const xd = x * radial + 2 * p1 * x * y + p2 * (r2 + 2 * x * x);
  const yd = y * radial + p1 * (r2 + 2 * y * y) + 2 * p2 * x * y;
  return [camera.K[0][0] * xd + camera.K[0][2], camera.K[1][1] * yd + camera.K[1][2]];
}

test("four floor corners clicked on the video make embusen calibrate --floor-corners's camera", async (t) => {
  if (skipWithoutData(t)) return;
  // No camera.json: the take's camera comes from the clicks.
  const { page, errors } = await openTake("autoplay=0&video=/data/optical/walk.mp4&src=/data/optical/walk.suit.bvh");
  const truth = JSON.parse(readFileSync(join(DATA, "optical/walk.camera.json"), "utf8"));
  // A 150 × 100 cm rectangle at the world's origin, seen by the true camera.
  const corners = [[0, 0, 0], [150, 0, 0], [150, 0, 100], [0, 0, 100]].map((p) => project(truth, p));
  for (const [x, y] of corners) assert.ok(x > 0 && x < 639 && y > 0 && y < 479, `corner at ${x}, ${y} is in the picture`);
  const overlay = page.locator(".camera-overlay");
  await page.fill('#camera-panel [data-setting="rectangle"]', "150x100");
  const clickAll = async () => {
    await page.click('#camera-panel [data-action="click-corners"]');
    await overlay.scrollIntoViewIfNeeded();
    const box = await overlay.boundingBox();
    const done = page.evaluate(() => Promise.race([
      document.querySelector("#camera-panel").embusenCamera.nextCornersCalibration(),
      new Promise((ok) => setTimeout(() => ok({ error: "no calibration 20 s after the clicks" }), 20000)),
    ]));
    // The picture is contained in the overlay's box, centred.
    const scale = Math.min(box.width / 640, box.height / 480);
    const [left, top] = [box.x + (box.width - 640 * scale) / 2, box.y + (box.height - 480 * scale) / 2];
    for (const [x, y] of corners) await page.mouse.click(left + (x + 0.5) * scale, top + (y + 0.5) * scale);
    return done;
  };
  // A rectangle that is no size: a message, nothing calibrated.
  await page.fill('#camera-panel [data-setting="rectangle"]', "150 by 100");
  const refused = await clickAll();
  assert.match(refused.error, /the rectangle "150 by 100": give its size as WIDTHxDEPTH/);
  assert.match(await page.textContent("#camera-panel .camera-inputs"), /camera \(camera\.json\): missing/);
  await page.fill('#camera-panel [data-setting="rectangle"]', "150x100");
  const fit = await clickAll();
  assert.ok(!fit.error, fit.error);
  const status = await page.textContent("#camera-panel .camera-status");
  assert.match(status, /calibrated from 4 floor corners: reprojection error \d/, status);
  assert.ok(fit.rmsPx < 1, `reprojection ${fit.rmsPx} px`);
  const camera = JSON.parse(fit.camera);
  const [a, b] = [camera.camera_center_world_cm, truth.camera_center_world_cm];
  const off = Math.hypot(a[0] - b[0], a[1] - b[1], a[2] - b[2]);
  console.log(`four clicked corners on walk: the camera centre ${off.toFixed(1)} cm from the true one ` +
    `(no lens model; ${fit.centerSigmaCmPerPx.toFixed(1)} cm per pixel of click error), focal ${fit.focalPx.toFixed(0)} px (true ${truth.K[0][0].toFixed(0)})`);
  assert.ok(off < 20, `the camera centre ${off.toFixed(1)} cm from the true one`);
  // The CLI, given the same clicks, writes the same camera.json.
  const out = join(scratch, "corners.camera.json");
  execFileSync(CLI, [
    "calibrate", "--floor-corners", ...fit.cornersPx.reduce((acc, v, k) => (k % 2 ? (acc[acc.length - 1] += `,${v}`, acc) : [...acc, String(v)]), []),
    "--rectangle-cm", "150x100", "--image-size", "640x480", "-o", out,
  ], { stdio: "pipe" });
  assert.ok(readFileSync(out, "utf8") === fit.camera, "the page's camera.json is not the CLI's");
  assert.match(await page.textContent("#camera-panel .camera-inputs"), /camera \(camera\.json\): camera\.json \(from 4 floor corners\)/);
  assert.deepEqual(errors, []);
  await page.close();
});

test("a take tracked before opens as it is, with no worker; autotrack=1 tracks on opening", async (t) => {
  if (skipWithoutData(t)) return;
  const out = join(scratch, "finished", "walk.tracked.bvh");
  mkdirSync(join(scratch, "finished"), { recursive: true });
  trackWalkWithCli(out);
  pages["/take/walk.tracked.bvh"] = { type: "text/plain", body: readFileSync(out) };
  pages["/take/walk.tracked.track.csv"] = { type: "text/csv", body: readFileSync(out.replace(/\.bvh$/, ".track.csv")) };
  /** Opens the page at `query`, counting the Web Workers it starts. */
  const openCounting = async (query) => {
    const page = await browser.newPage({ viewport: { width: 1280, height: 800 } });
    const errors = [];
    page.on("pageerror", (e) => errors.push(String(e)));
    await page.addInitScript(() => {
      window.workersStarted = 0;
      const Native = window.Worker;
      window.Worker = class extends Native {
        constructor(...args) {
          super(...args);
          window.workersStarted++;
        }
      };
    });
    await page.goto(`${server.url}/?autoplay=0&${query}`);
    return { page, errors };
  };
  const status = (page) => page.textContent("#camera-panel .camera-status");
  const scene = "video=/data/optical/walk.mp4&camera=/data/optical/walk.camera.json";
  const { page, errors } = await openCounting(`${scene}&src=/take/walk.tracked.bvh&track=/take/walk.tracked.track.csv`);
  await page.waitForFunction(() => /tracked before/.test(document.querySelector("#camera-panel .camera-status")?.textContent ?? ""),
    null, { timeout: 60000 });
  assert.match(await status(page), /walk\.tracked\.track\.csv: 195 frames tracked before, shown as they are/);
  // The outline over frames 0, 100 and 190 is on the actor: it surrounds
  // the true hips seen by the true camera.
  const camera = JSON.parse(readFileSync(join(DATA, "optical/walk.camera.json"), "utf8"));
  const truth = readFileSync(join(DATA, "optical/walk.truth.csv"), "utf8").trim().split("\n").slice(1)
    .map((row) => row.split(",").slice(1, 4).map(Number));
  for (const i of [0, 100, 190]) {
    const outline = await page.evaluate((i) => document.querySelector("#camera-panel").embusenCamera.outlineAt(i), i);
    const [xs, ys] = [outline.filter((_, k) => k % 2 === 0), outline.filter((_, k) => k % 2 === 1)];
    const [x, y] = project(camera, truth[i]);
    assert.ok(outline.length > 200 && Math.min(...xs) < x && x < Math.max(...xs) && Math.min(...ys) < y && y < Math.max(...ys),
      `frame ${i}: the true hips at ${x.toFixed(0)}, ${y.toFixed(0)} px, the outline over ${Math.min(...xs)}–${Math.max(...xs)}, ${Math.min(...ys)}–${Math.max(...ys)}`);
  }
  // The player shows the take: its recording, the camera track's legend.
  const player = await page.evaluate(() => {
    const app = document.querySelector("#app");
    return { name: app.embusen.player.info().name, legend: !app.querySelector(".legend").hidden };
  });
  assert.deepEqual(player, { name: "walk.tracked.bvh", legend: true });
  assert.equal(await page.evaluate(() => window.workersStarted), 0, "no worker started: nothing was tracked");
  // Its plots follow the take: (f) the uncertainty the CSV states, every frame.
  const series = await page.evaluate(() => document.querySelector("#app").embusen.player.camera_take_series());
  assert.ok(series && series.uncertainty_cm.length === 195 && series.uncertainty_cm.every((u) => u > 0), JSON.stringify(series));
  assert.deepEqual(series.error_cm, []);
  // Framed whole, wide and narrow, its body's shadow on.
  for (const [width, height] of [[1280, 800], [390, 844]]) {
    await page.setViewportSize({ width, height });
    await page.waitForTimeout(300);
    await page.evaluate(() => {
      const { player } = document.querySelector("#app").embusen;
      player.set_frame(100);
      player.draw();
    });
    const seen = await viewExtent(page);
    console.log(`the finished take at ${width}×${height}: the paths ${JSON.stringify(seen.path)}, the body ${JSON.stringify(seen.body)}`);
    await page.screenshot({ path: join(SCREENSHOTS, `finished-take-${width}x${height}.png`), fullPage: true });
    assert.ok(wholeInView(seen.path, seen) && wholeInView(seen.body, seen), `${width}×${height}: ${JSON.stringify(seen)}`);
  }
  await page.screenshot({ path: join(SCREENSHOTS, "finished-take.png") });
  assert.deepEqual(errors, []);
  await page.close();
  // The suit's own recording with that track: not one take; said, nothing shown.
  const wrong = await openCounting(`${scene}&src=/data/optical/walk.suit.bvh&track=/take/walk.tracked.track.csv`);
  await wrong.page.waitForFunction(() => document.querySelector("#camera-panel .camera-status.error"), null, { timeout: 60000 });
  assert.match(await status(wrong.page), /walk\.suit\.bvh: its hips are [\d.]+ cm from walk\.tracked\.track\.csv's at video frame \d+: it is not the recording this track corrected/);
  assert.equal(await wrong.page.evaluate(() => document.querySelector("#camera-panel").embusenCamera.outlineAt(100).length), 0);
  await wrong.page.close();
  // A take tracked at an offset opens at that offset (`offset=`), and at
  // another one says so.
  const shifted = join(scratch, "finished", "walk.shifted.bvh");
  trackWalkWithCli(shifted, ["--offset-s", "0.1"]);
  pages["/take/walk.shifted.bvh"] = { type: "text/plain", body: readFileSync(shifted) };
  pages["/take/walk.shifted.track.csv"] = { type: "text/csv", body: readFileSync(shifted.replace(/\.bvh$/, ".track.csv")) };
  const files = "src=/take/walk.shifted.bvh&track=/take/walk.shifted.track.csv";
  for (const [offset, said] of [["&offset=0.1", /195 frames tracked before/], ["", /or not at the offset it was tracked at \(0 s here\)/]]) {
    const opened = await openCounting(`${scene}&${files}${offset}`);
    await opened.page.waitForFunction(() => /tracked before|error/.test(document.querySelector("#camera-panel .camera-status")?.className +
      document.querySelector("#camera-panel .camera-status")?.textContent), null, { timeout: 60000 });
    assert.match(await status(opened.page), said);
    await opened.page.close();
  }
  // autotrack=1 with everything a track needs: tracked on opening.
  const auto = await openCounting(`${scene}&src=/data/optical/walk.suit.bvh&background=/data/optical/walk.background.png&autotrack=1`);
  await auto.page.waitForFunction(() => /195 frames tracked/.test(document.querySelector("#camera-panel .camera-status")?.textContent ?? ""),
    null, { timeout: 120000 });
  assert.ok((await auto.page.evaluate(() => window.workersStarted)) > 0);
  assert.deepEqual(auto.errors, []);
  await auto.page.close();
});

test("mount() takes a video: two players on a page, destroy() lets go of the video and the workers", async (t) => {
  if (skipWithoutData(t)) return;
  pages["/two-players.html"] = `<!doctype html><html><head><link rel="stylesheet" href="/style.css"></head><body>
    <div id="a" style="height: 300px"></div><div id="b" style="height: 300px"></div>
    <script type="module">
      import { mount } from "/embusen.js";
      const d = "/data/optical/walk";
      window.players = await Promise.all([
        mount(document.querySelector("#a"), { autoplay: true }),
        mount(document.querySelector("#b"), { src: d + ".suit.bvh", video: d + ".mp4", camera: d + ".camera.json",
          background: d + ".background.png", autoplay: false }),
      ]);
    </script></body></html>`;
  const page = await browser.newPage({ viewport: { width: 1280, height: 800 } });
  const errors = [];
  page.on("pageerror", (e) => errors.push(String(e)));
  await page.goto(`${server.url}/two-players.html`);
  await page.waitForFunction(() => window.players?.[1]?.camera, null, { timeout: 60000 });
  const before = await page.evaluate(() => ({
    panels: document.querySelectorAll(".embusen-camera").length,
    videos: [...document.querySelectorAll("video")].filter((v) => v.src).length,
    inputs: document.querySelector(".embusen-camera .camera-inputs").textContent,
  }));
  assert.equal(before.panels, 1, "only the player given a video has a camera panel");
  assert.equal(before.videos, 1);
  assert.match(before.inputs, /walk\.mp4, 640×480/);
  // Destroyed while it tracks: the track ends (cancelled), the video and its
  // panel go, the other player plays on.
  const after = await page.evaluate(async () => {
    const [a, b] = window.players;
    const tracking = b.camera.track().then(() => "tracked", (e) => e.message);
    await new Promise((ok) => setTimeout(ok, 1500));
    b.destroy();
    const said = await tracking;
    const frame = a.player.frame();
    await new Promise((ok) => setTimeout(ok, 500));
    return { said, panels: document.querySelectorAll(".embusen-camera").length,
      videos: document.querySelectorAll("video").length, played: a.player.frame() !== frame };
  });
  assert.match(after.said, /^cancelled/, after.said);
  assert.equal(after.panels, 0);
  assert.equal(after.videos, 0, "the video element is released");
  assert.ok(after.played, "the other player plays on");
  assert.deepEqual(errors, []);
  await page.close();
});

test("without a background still the page tracks against the video's median, as the CLI does", async (t) => {
  if (skipWithoutData(t)) return;
  const out = join(scratch, "walk.median.bvh");
  trackWalkWithCli(out, [], false);
  const { page, errors } = await openTake(
    "autoplay=0&video=/data/optical/walk.mp4&src=/data/optical/walk.suit.bvh&camera=/data/optical/walk.camera.json",
  );
  assert.match(await page.textContent("#camera-panel .camera-inputs"), /background still \(PNG\): none: the median/);
  const result = await page.evaluate(() => document.querySelector("#camera-panel").embusenCamera.track());
  assert.ok(result.recording === readFileSync(out, "utf8"), "against the median, the page's BVH is not the CLI's");
  assert.match(await page.textContent("#camera-panel .camera-status"), /no background still: the median of 31 frames of walk\.mp4 stands for the empty room/);
  assert.match(await page.textContent("#camera-panel .camera-inputs"), /background still \(PNG\): the median of 31 frames of walk\.mp4/);
  assert.deepEqual(errors, []);
  await page.close();
});

/**
 * Writes `name` in the scratch folder: `n` frames of 160×120 at `fps` whose
 * frame i shows i in binary as 8 bars of 20 px (white 1, black 0), encoded
 * with `codec` (ffmpeg's arguments).
 */
function countingClip(name, fps, n, codec) {
  const [w, h] = [160, 120];
  const raw = Buffer.alloc(n * w * h * 1.5);
  for (let i = 0; i < n; i++) {
    const base = i * w * h * 1.5;
    for (let y = 0; y < h; y++) {
      for (let x = 0; x < w; x++) raw[base + y * w + x] = (i >> (7 - Math.floor(x / 20))) & 1 ? 235 : 16;
    }
    raw.fill(128, base + w * h, base + w * h * 1.5);
  }
  writeFileSync(join(scratch, `${name}.yuv`), raw);
  execFileSync("ffmpeg", [
    "-v", "error", "-y", "-f", "rawvideo", "-pix_fmt", "yuv420p", "-s", `${w}x${h}`, "-r", String(fps),
    "-i", join(scratch, `${name}.yuv`), ...codec, join(scratch, name),
  ]);
}
const H264 = ["-c:v", "libx264", "-g", "30", "-pix_fmt", "yuv420p"];

test("every frame of a clip is read as itself, by its pixels, in H.264 and VP9", async () => {
  const n = 90;
  countingClip("count.mp4", 30, n, H264);
  countingClip("count.webm", 30, n, ["-c:v", "libvpx-vp9", "-g", "30", "-b:v", "1M"]);
  for (const name of ["count.mp4", "count.webm"]) {
    const bytes = readFileSync(join(scratch, name)).toString("base64");
    pages[`/${name}.html`] = `<!doctype html><body><script type="module">
      import { openVideo, measureFps, frameAt } from "/video-frames.js";
      const bytes = Uint8Array.from(atob("${bytes}"), (c) => c.charCodeAt(0));
      const video = await openVideo(new Blob([bytes], { type: "video/${name.endsWith("mp4") ? "mp4" : "webm"}" }), "${name}");
      const fps = await measureFps(video);
      const read = [];
      // Out of order too: a seek backwards must give the frame asked for.
      const order = [...Array(${n}).keys(), 45, 3, 89, 0];
      for (const i of order) {
        const f = await frameAt(video, i, fps);
        const luma = new Uint8Array(f.luma);
        let value = 0;
        for (let bit = 0; bit < 8; bit++) value = value * 2 + (luma[60 * f.stride + bit * 20 + 10] > 128 ? 1 : 0);
        read.push([i, f.index, value]);
      }
      window.done = { fps, read };
    </script></body>`;
    const page = await browser.newPage();
    await page.goto(`${server.url}/${name}.html`);
    const done = await page.waitForFunction(() => window.done, null, { timeout: 120000 }).then((h) => h.jsonValue());
    assert.ok(Math.abs(done.fps - 30) < 0.1, `${name}: ${done.fps} fps measured`);
    const wrong = done.read.filter(([asked, index, value]) => index !== asked || value !== asked);
    assert.deepEqual(wrong, [], `${name}: frames read as another (asked, by timestamp, by pixels)`);
    assert.equal(done.read.length, n + 4);
    await page.close();
  }
});

test("one clock: the player and a take's video show the same instant, whichever is moved", async () => {
  // A 60 fps clip whose frames say their number, under a 30 Hz recording
  // (the demo's, re-timed): BVH frame f is video frame 2f.
  countingClip("clock.mp4", 60, 180, H264);
  pages["/clock.mp4"] = { type: "video/mp4", body: readFileSync(join(scratch, "clock.mp4")) };
  const demo = await browser.newPage();
  await demo.goto(`${server.url}/?autoplay=0`);
  await demo.waitForFunction(() => document.querySelector("#app").embusen);
  const bvh = await demo.evaluate(async () => {
    const { player, ready } = document.querySelector("#app").embusen;
    await ready;
    return player.export_recording().text;
  });
  await demo.close();
  pages["/clock.bvh"] = { type: "text/plain", body: bvh.replace(/Frame Time:\s*\S+/, "Frame Time: 0.0333333333") };
  const { page, errors } = await openTake("video=/clock.mp4&src=/clock.bvh&autoplay=0");
  await page.waitForFunction(() => {
    const { player } = document.querySelector("#app").embusen;
    return player.frame_count() > 100 && player.fps() < 31;
  });
  const playerFrame = () => page.evaluate(() => document.querySelector("#app").embusen.player.frame());
  /** Seeks the player by its slider. */
  const slideTo = (f) => page.evaluate((f) => {
    const slider = document.querySelector("#app .slider");
    slider.value = String(f);
    slider.dispatchEvent(new Event("input", { bubbles: true }));
  }, f);
  /** Sets the offset field, gives the keys back to the page, and lets the player follow. */
  const offsetOf = async (s) => {
    const before = await playerFrame();
    await page.fill("#camera-panel [data-setting=offset]", s);
    await page.evaluate(() => document.activeElement.blur());
    await page.waitForFunction((before) => document.querySelector("#app").embusen.player.frame() !== before, before);
  };
  /** The video frame on screen, read from its pixels once it has settled. */
  const videoFrame = () => page.evaluate(async () => {
    const video = document.querySelector(".camera-video video");
    while (video.seeking || video.readyState < 2) await new Promise((ok) => setTimeout(ok, 10));
    const canvas = Object.assign(document.createElement("canvas"), { width: 160, height: 120 });
    const context = canvas.getContext("2d", { willReadFrequently: true });
    context.drawImage(video, 0, 0, 160, 120);
    const pixels = context.getImageData(0, 60, 160, 1).data;
    let value = 0;
    for (let bit = 0; bit < 8; bit++) value = value * 2 + (pixels[(bit * 20 + 10) * 4] > 128 ? 1 : 0);
    return value;
  });
  /** Waits (up to 5 s) for the video to show `expected`; gives back what it shows. */
  const videoSettlesOn = async (expected) => {
    let shown = await videoFrame();
    for (let tries = 0; shown !== expected && tries < 50; tries++) {
      await page.waitForTimeout(100);
      shown = await videoFrame();
    }
    return shown;
  };
  // The player moved (its slider, its keys): the video follows.
  for (const f of [17, 40, 0, 89]) {
    await slideTo(f);
    assert.equal(await videoSettlesOn(2 * f), 2 * f, `the player at frame ${f}`);
    assert.equal(await playerFrame(), f, "the player stays where it was put");
  }
  await page.keyboard.press("ArrowLeft");
  assert.equal(await videoSettlesOn(176), 176, "a step back in the player");
  // The offset moves the recording's instant against the video's.
  await offsetOf("0.5");
  await page.keyboard.press("Home");
  await page.keyboard.press("ArrowRight");
  assert.equal(await videoSettlesOn(0), 0, "frame 1 is before the video starts: its first frame");
  await slideTo(40);
  assert.equal(await videoSettlesOn(50), 50, "frame 40 is 1.333 s, 0.833 s into the video");
  await offsetOf("0");
  await slideTo(40);
  assert.equal(await videoSettlesOn(80), 80);
  const before = await playerFrame();
  // The player's play button plays the video, and the player follows it.
  await page.click("#app [data-action=play]");
  await page.waitForFunction(() => !document.querySelector(".camera-video video").paused);
  await page.waitForFunction(() => document.querySelector("#app [data-action=play]").textContent === "❚❚");
  await page.waitForTimeout(1000);
  const during = await playerFrame();
  assert.ok(during >= before + 15, `the player follows the video as it plays (frame ${before}, then ${during})`);
  await page.click("#app [data-action=play]");
  await page.waitForFunction(() => document.querySelector(".camera-video video").paused);
  await page.waitForTimeout(300);
  const [shown, followed] = [await videoFrame(), await playerFrame()];
  assert.ok(Math.abs(shown / 60 - followed / 30) <= 1 / 60 + 1e-9,
    `the video at frame ${shown} (${(shown / 60).toFixed(3)} s), the player at frame ${followed} (${(followed / 30).toFixed(3)} s)`);
  assert.equal(await page.textContent("#app [data-action=play]"), "▶");
  // The video seeked by itself (its own controls): the player follows.
  await page.evaluate(() => (document.querySelector(".camera-video video").currentTime = 120.5 / 60));
  await page.waitForFunction(() => document.querySelector("#app").embusen.player.frame() === 60);
  assert.equal(await videoFrame(), 120);
  assert.deepEqual(errors, []);
  await page.screenshot({ path: join(SCREENSHOTS, "one-clock.png") });
  await page.close();
});

test("bad input is a message in the page, and what was open stays open", async (t) => {
  if (skipWithoutData(t)) return;
  const { page, errors } = await openTake(
    "video=/data/optical/walk.mp4&src=/data/optical/walk.suit.bvh&camera=/data/optical/walk.camera.json" +
      "&background=/data/optical/walk.background.png",
  );
  const open = (files) =>
    page.evaluate(async (files) => {
      const panel = document.querySelector("#camera-panel");
      await panel.embusenCamera.open(files.map(([name, text]) => new File([text], name)));
      return [panel.querySelector(".camera-status").textContent, panel.querySelector(".camera-inputs").textContent];
    }, files);
  // Cancelled while it tracks: a message, the inputs kept.
  const cancelled = await page.evaluate(() => {
    const panel = document.querySelector("#camera-panel").embusenCamera;
    const tracking = panel.track().then(() => "tracked", (e) => e.message);
    setTimeout(() => panel.cancel(), 500);
    return tracking;
  });
  assert.match(cancelled, /^cancelled: the inputs are kept/, cancelled);
  // A video the browser cannot decode.
  let [said, inputs] = await open([["broken.mp4", "not a video at all"]]);
  assert.match(said, /broken\.mp4: this browser cannot decode the video/);
  assert.match(inputs, /walk\.mp4, 640×480/, "the open video stays");
  // A camera file for another image size: refused when tracking, naming both sizes.
  const camera = readFileSync(join(DATA, "optical/walk.camera.json"), "utf8").replace('"width": 640', '"width": 320');
  await open([["small.camera.json", camera]]);
  const refused = await page.evaluate(() =>
    document.querySelector("#camera-panel").embusenCamera.track().then(() => "tracked", (e) => e.message));
  assert.match(refused, /320/, refused);
  assert.match(await page.textContent("#camera-panel .camera-status"), /320/);
  assert.match(await page.textContent("#camera-panel .camera-inputs"), /walk\.mp4, 640×480/);
  // A file of no kind the panel knows.
  [said] = await open([["notes.txt", "hello"]]);
  assert.match(said, /notes\.txt: not a video, a BVH, a camera\.json, a board's layout or a PNG still/);
  // A BVH that ends before the video: its frames are tracked, the rest of
  // the video is said to have no pose, and the result still exports.
  await open([["small.camera.json", camera.replace('"width": 320', '"width": 640')]]);
  const bvh = readFileSync(join(DATA, "optical/walk.suit.bvh"), "utf8").split("\n");
  const motion = bvh.findIndex((line) => line.startsWith("Frame Time"));
  const short = [...bvh.slice(0, motion + 1).map((l) => l.replace(/^Frames: \d+/, "Frames: 90")), ...bvh.slice(motion + 1, motion + 91)];
  await open([["short.suit.bvh", short.join("\n") + "\n"]]);
  const shortTrack = await page.evaluate(() =>
    document.querySelector("#camera-panel").embusenCamera.track().then((r) => ({ frames: r.frames, recording: r.recording }), (e) => e.message));
  const status = await page.textContent("#camera-panel .camera-status");
  assert.match(status, /video frames \d+–194 have no pose in short\.suit\.bvh: not tracked/, status);
  assert.match(status, /the video lasts 6\.50 s \(195 frames at 30\.000 fps\), the BVH 3\.00 s \(90 frames/, status);
  assert.equal(shortTrack.frames, 195, JSON.stringify(shortTrack).slice(0, 200));
  assert.match(shortTrack.recording, /^Frames: 90$/m, "the corrected BVH keeps the BVH's own frames");
  assert.match(await page.textContent("#camera-panel .camera-inputs"), /short\.suit\.bvh/);
  assert.deepEqual(errors, []);
  await page.close();
});

test("a camera calibrated from board.png in the page stands where the true one does", async (t) => {
  if (skipWithoutData(t)) return;
  const page = await browser.newPage({ viewport: { width: 1280, height: 800 } });
  const fetched = [];
  page.on("request", (r) => fetched.push(new URL(r.url()).pathname));
  const errors = [];
  page.on("pageerror", (e) => errors.push(String(e)));
  // A take with its camera: the board's detector is not fetched.
  await page.goto(`${server.url}/?autoplay=0&video=/data/optical/walk.mp4&src=/data/optical/walk.suit.bvh` +
    "&camera=/data/optical/walk.camera.json");
  await page.waitForFunction(() => document.querySelector("#camera-panel")?.embusenCamera, null, { timeout: 60000 });
  await page.waitForLoadState("networkidle");
  assert.ok(!fetched.some((p) => p.includes("pkg-board")), `the detector was fetched without a board: ${fetched.join(" ")}`);
  for (const [scene, withLens] of [["walk", true], ["slash", false]]) {
    const truth = JSON.parse(readFileSync(join(DATA, `optical/${scene}.camera.json`), "utf8"));
    const found = await page.evaluate(async ([scene, withLens]) => {
      const panel = document.querySelector("#camera-panel").embusenCamera;
      const get = async (path) => new File([await (await fetch(path)).blob()], path.split("/").pop());
      const files = [await get(`/data/optical/${scene}.board.png`), await get(`/data/optical/${scene}.board.json`)];
      if (withLens) files.push(await get(`/data/optical/${scene}.camera.json`));
      await panel.open(files);
      const outcome = await panel.calibrate();
      return { ...outcome, camera: JSON.parse(outcome.camera) };
    }, [scene, withLens]);
    const centre = found.camera.camera_center_world_cm;
    const off = Math.hypot(...centre.map((c, i) => c - truth.camera_center_world_cm[i]));
    const focal = found.camera.K[0][0] / truth.K[0][0] - 1;
    console.log(`${scene}.board.png in the page (${withLens ? "the true lens" : "no lens"}): ${found.corners} corners, ` +
      `reprojection ${found.rmsPx.toFixed(2)} px rms, camera centre ${off.toFixed(2)} cm off, focal length ${(100 * focal).toFixed(2)} %`);
    if (withLens) assert.ok(off < 1, `${scene}: the camera centre is ${off.toFixed(2)} cm from the true one`);
    else assert.ok(Math.abs(focal) < 0.03, `${scene}: the focal length is ${(100 * focal).toFixed(1)} % off`);
  }
  assert.ok(fetched.some((p) => p.includes("pkg-board")), "the detector was never fetched");
  // No still: the board found in the video frame shown (a clip of the
  // board still, encoded as H.264), with the true lens.
  const clip = join(scratch, "board.mp4");
  execFileSync("ffmpeg", ["-v", "error", "-y", "-loop", "1", "-i", join(DATA, "optical/walk.board.png"), "-t", "1", "-r", "30",
    "-c:v", "libx264", "-crf", "16", "-pix_fmt", "yuv420p", clip]);
  const clipBytes = readFileSync(clip);
  // A page with no take: the files picked there bring the panel up.
  const fresh = await browser.newPage({ viewport: { width: 1280, height: 800 } });
  const freshErrors = [];
  fresh.on("pageerror", (e) => freshErrors.push(String(e)));
  await fresh.goto(`${server.url}/?autoplay=0`);
  await fresh.setInputFiles("#camera-panel input[type=file]", [
    { name: "board.mp4", mimeType: "video/mp4", buffer: clipBytes },
    ...["walk.board.json", "walk.camera.json"].map((name) =>
      ({ name, mimeType: "application/json", buffer: readFileSync(join(DATA, "optical", name)) })),
  ]);
  await fresh.waitForFunction(() => /board layout \(BOARD\.json\): walk\.board\.json/.test(
    document.querySelector("#camera-panel .camera-inputs")?.textContent ?? ""), null, { timeout: 60000 });
  const inVideo = await fresh.evaluate(async () => {
    const panel = document.querySelector("#camera-panel").embusenCamera;
    const outcome = await panel.calibrate();
    return { ...outcome, camera: JSON.parse(outcome.camera), status: document.querySelector("#camera-panel .camera-status").textContent };
  });
  const walk = JSON.parse(readFileSync(join(DATA, "optical/walk.camera.json"), "utf8"));
  const offInVideo = Math.hypot(...inVideo.camera.camera_center_world_cm.map((c, i) => c - walk.camera_center_world_cm[i]));
  console.log(`walk's board in a video frame (H.264, crf 16, the true lens): ${inVideo.corners} corners, ` +
    `reprojection ${inVideo.rmsPx.toFixed(2)} px rms, camera centre ${offInVideo.toFixed(2)} cm off`);
  assert.match(inVideo.status, /calibrated from board\.mp4 frame \d+: 24 corners/, inVideo.status);
  assert.ok(offInVideo < 2, `from the video frame the camera centre is ${offInVideo.toFixed(2)} cm from the true one`);
  assert.deepEqual(freshErrors, []);
  await fresh.close();
  // A still without a board says so, and the calibration had stays.
  const refused = await page.evaluate(async () => {
    const panel = document.querySelector("#camera-panel").embusenCamera;
    const still = new File([await (await fetch("/data/optical/walk.background.png")).blob()], "empty.board.png");
    await panel.open([still]);
    return panel.calibrate().then(() => "calibrated", (e) => e.message);
  });
  assert.match(refused, /empty\.board\.png/, refused);
  assert.match(await page.textContent("#camera-panel .camera-inputs"), /camera\.json \(from slash\.board\.png\)/);
  assert.deepEqual(errors, []);
  await page.close();
});

test("a take filmed by two cameras: tracked in the page as embusen track tracks both, both videos on one clock", async (t) => {
  if (skipWithoutData(t)) return;
  const first = (s) => join(DATA, "optical", `walk${s}`);
  const second = (s) => join(DATA, "optical", "second_view", `walk${s}`);
  const out = join(scratch, "two", "walk.tracked.bvh");
  mkdirSync(join(scratch, "two"), { recursive: true });
  execFileSync(CLI, ["track", first(".mp4"), second(".mp4"), "--bvh", first(".suit.bvh"),
    "--camera", first(".camera.json"), "--camera", second(".camera.json"),
    "--background", first(".background.png"), "--background", second(".background.png"), "-o", out], { stdio: "pipe" });
  const views = "video=/data/optical/walk.mp4&video=/data/optical/second_view/walk.mp4" +
    "&camera=/data/optical/walk.camera.json&camera=/data/optical/second_view/walk.camera.json";
  const { page, errors } = await openTake(`autoplay=0&${views}&src=/data/optical/walk.suit.bvh` +
    "&background=/data/optical/walk.background.png&background=/data/optical/second_view/walk.background.png" +
    "&truth=/data/optical/walk.truth.csv");
  const handle = () => "document.querySelector('#camera-panel').embusenCamera";
  assert.equal(await page.evaluate(`${handle()}.views`), 2);
  const inputs = await page.textContent("#camera-panel .camera-inputs");
  assert.match(inputs, /view 2/, inputs);
  const result = await page.evaluate(() => document.querySelector("#camera-panel").embusenCamera.track());
  const status = await page.textContent("#camera-panel .camera-status");
  console.log(`walk by two cameras in the page: ${status}`);
  assert.equal(result.views, 2, status);
  assert.match(status, /195 frames tracked by 2 cameras/);
  assert.ok(result.recording === readFileSync(out, "utf8"), "the page's corrected BVH is not the CLI's with two views");
  assert.ok(result.csv === readFileSync(out.replace(/\.bvh$/, ".track.csv"), "utf8"), "the page's track CSV is not the CLI's");
  assert.ok(result.truthErrors && result.truthErrors.meanCm < 3.5, JSON.stringify(result.truthErrors));
  // Each view's outline surrounds the true hips as its own camera sees them.
  const truth = readFileSync(first(".truth.csv"), "utf8").trim().split("\n").slice(1)
    .map((row) => row.split(",").slice(1, 4).map(Number));
  for (const [view, camera] of [first(".camera.json"), second(".camera.json")].entries()) {
    const cameraJson = JSON.parse(readFileSync(camera, "utf8"));
    for (const i of [20, 100, 180]) {
      const outline = await page.evaluate(([i, view]) => document.querySelector("#camera-panel").embusenCamera.outlineAt(i, view), [i, view]);
      const [xs, ys] = [outline.filter((_, k) => k % 2 === 0), outline.filter((_, k) => k % 2 === 1)];
      const [x, y] = project(cameraJson, truth[i]);
      assert.ok(outline.length > 200 && Math.min(...xs) < x && x < Math.max(...xs) && Math.min(...ys) < y && y < Math.max(...ys),
        `view ${view + 1}, frame ${i}: the true hips at ${x.toFixed(0)}, ${y.toFixed(0)} px, the outline over ` +
          `${Math.min(...xs)}–${Math.max(...xs)}, ${Math.min(...ys)}–${Math.max(...ys)}`);
    }
  }
  // One clock: the player moved to frame 120 moves both videos there.
  const shown = async () => {
    await page.waitForTimeout(600);
    return page.evaluate(() => ({
      player: document.querySelector("#app").embusen.player.frame(),
      videos: Array.from(document.querySelectorAll(".camera-video video"), (v) => Math.floor(v.currentTime * 30 + 1e-6)),
    }));
  };
  await page.evaluate(() => {
    const slider = document.querySelector("#app .slider");
    slider.value = "120";
    slider.dispatchEvent(new Event("input", { bubbles: true }));
  });
  const at = await shown();
  assert.deepEqual(at, { player: 120, videos: [120, 120] }, JSON.stringify(at));
  await page.evaluate(() => scrollTo(0, 0));
  mkdirSync(SCREENSHOTS, { recursive: true });
  await page.screenshot({ path: join(SCREENSHOTS, "two-views-1280x800.png") });
  // Both videos whole in the page, beside the 3D view at 1280×800 and above it at 390×844.
  for (const [width, height] of [[1280, 800], [390, 844]]) {
    await page.setViewportSize({ width, height });
    await page.waitForTimeout(300);
    const boxes = await page.evaluate(() => Array.from(document.querySelectorAll("#app .camera-video video"), (v) => {
      const r = v.getBoundingClientRect();
      return { left: r.left, right: r.right, width: r.width, height: r.height };
    }));
    assert.equal(boxes.length, 2);
    for (const b of boxes) assert.ok(b.left >= 0 && b.right <= width && b.width > 150 && b.height > 100, `at ${width}×${height}: ${JSON.stringify(b)}`);
    await page.screenshot({ path: join(SCREENSHOTS, `two-views-${width}x${height}.png`), fullPage: width < 800 });
  }
  assert.deepEqual(errors, []);
  await page.close();
  // The finished take opens with both videos, each with its outline.
  pages["/two/walk.tracked.bvh"] = { type: "text/plain", body: readFileSync(out) };
  pages["/two/walk.tracked.track.csv"] = { type: "text/csv", body: readFileSync(out.replace(/\.bvh$/, ".track.csv")) };
  const finished = await openTake(`autoplay=0&${views}&src=/two/walk.tracked.bvh&track=/two/walk.tracked.track.csv`);
  await finished.page.waitForFunction(() => /tracked by 2 cameras before/.test(document.querySelector("#camera-panel .camera-status")?.textContent ?? ""),
    null, { timeout: 60000 });
  for (const view of [0, 1]) {
    const outline = await finished.page.evaluate((view) => document.querySelector("#camera-panel").embusenCamera.outlineAt(100, view), view);
    assert.ok(outline.length > 200, `the finished take's view ${view + 1}: an outline of ${outline.length / 2} px over frame 100`);
  }
  assert.deepEqual(finished.errors, []);
  await finished.page.close();
  // A second view given the first's camera: its world is not the first's,
  // said with the view's name; the take stays open.
  const wrong = await openTake("autoplay=0&video=/data/optical/walk.mp4&video=/data/optical/second_view/walk.mp4" +
    "&camera=/data/optical/walk.camera.json&camera=/data/optical/walk.camera.json&src=/data/optical/walk.suit.bvh" +
    "&background=/data/optical/walk.background.png&background=/data/optical/second_view/walk.background.png");
  await wrong.page.evaluate(() => document.querySelector("#camera-panel").embusenCamera.track().catch(() => null));
  const said = await wrong.page.textContent("#camera-panel .camera-status");
  console.log(`view 2 with view 1's camera: ${said}`);
  assert.match(said, /view 2/);
  assert.equal(await wrong.page.evaluate(`${handle()}.views`), 2);
  assert.match(await wrong.page.textContent("#camera-panel .camera-inputs"), /walk\.suit\.bvh/);
  await wrong.page.close();
});

test("two cameras' files picked together go each to its view, and each view calibrates from its own board", async (t) => {
  if (skipWithoutData(t)) return;
  const page = await browser.newPage({ viewport: { width: 1280, height: 800 } });
  const errors = [];
  page.on("pageerror", (e) => errors.push(String(e)));
  await page.goto(`${server.url}/?autoplay=0`);
  const first = (name) => join(DATA, "optical", name);
  const second = (name) => join(DATA, "optical", "second_view", name);
  const file = (path, mimeType) => ({ name: path.split("/").pop(), mimeType, buffer: readFileSync(path) });
  // As `embusen track` pairs its flags: the i-th video, the i-th board
  // still, layout and camera (here its lens) are the i-th view's.
  await page.setInputFiles("#camera-panel input[type=file]", [
    file(first("walk.mp4"), "video/mp4"), file(second("walk.mp4"), "video/mp4"), file(first("walk.suit.bvh"), "text/plain"),
    file(first("walk.board.png"), "image/png"), file(second("walk.board.png"), "image/png"),
    // A layout is told from a camera by what is in it, whatever its name.
    file(first("walk.board.json"), "application/json"), { ...file(second("walk.board.json"), "application/json"), name: "layout.json" },
    file(first("walk.camera.json"), "application/json"), file(second("walk.camera.json"), "application/json"),
  ]);
  await page.waitForFunction(() => /view 2's board layout/.test(document.querySelector("#camera-panel .camera-inputs")?.textContent ?? ""),
    null, { timeout: 60000 });
  assert.equal(await page.evaluate(() => document.querySelector("#camera-panel").embusenCamera.views), 2);
  for (const [view, truthPath] of [[1, second("walk.camera.json")], [0, first("walk.camera.json")]]) {
    const truth = JSON.parse(readFileSync(truthPath, "utf8"));
    const found = await page.evaluate(async (view) => {
      const panel = document.querySelector("#camera-panel").embusenCamera;
      panel.selectView(view);
      const outcome = await panel.calibrate();
      return { ...outcome, camera: JSON.parse(outcome.camera) };
    }, view);
    const off = Math.hypot(...found.camera.camera_center_world_cm.map((c, i) => c - truth.camera_center_world_cm[i]));
    console.log(`view ${view + 1} calibrated from its board in the page: ${found.corners} corners, ` +
      `reprojection ${found.rmsPx.toFixed(2)} px rms, camera centre ${off.toFixed(2)} cm from its true one`);
    assert.ok(off < 2, `view ${view + 1}: the camera centre is ${off.toFixed(2)} cm from the true one`);
  }
  const listed = await page.textContent("#camera-panel .camera-inputs");
  for (const view of [1, 2]) {
    assert.match(listed, new RegExp(`view ${view}'s camera \\(camera\\.json\\): camera\\.json \\(from walk\\.board\\.png\\)`), listed);
  }
  assert.match(listed, /view 2's board layout \(BOARD\.json\): layout\.json/, listed);
  // A camera added and left empty does not stop a track of the two.
  const trackButton = "#camera-panel [data-action=track]";
  assert.equal(await page.isDisabled(trackButton), false);
  await page.click("#camera-panel [data-action=add-view]");
  assert.equal(await page.evaluate(() => document.querySelector("#camera-panel").embusenCamera.views), 3);
  assert.equal(await page.isDisabled(trackButton), false, await page.textContent("#camera-panel .camera-status"));
  assert.deepEqual(errors, []);
  await page.close();
});
