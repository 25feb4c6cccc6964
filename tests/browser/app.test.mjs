// End-to-end tests of the web app in headless Chromium (playwright-core).
// Run by `./build.sh test` after the app is built into dist/.
import { test, before, after } from "node:test";
import assert from "node:assert/strict";
import { execFileSync } from "node:child_process";
import { mkdirSync, readFileSync, writeFileSync, mkdtempSync } from "node:fs";
import { tmpdir } from "node:os";
import { join } from "node:path";
import {
  startServer, launchBrowser, openApp, waitReady, countDrawnPixels, DATA, HAVE_DATA, ROOT, SCREENSHOTS,
} from "./harness.mjs";

let server;
let browser;
const TWO_PLAYERS = `<!doctype html><html><head><link rel="stylesheet" href="/style.css"></head><body>
  <div id="a" style="height:380px"></div><div id="b" style="height:380px"></div>
  <script type="module">
    import { mount } from "/embusen.js";
    mount(document.querySelector("#a"), { autoplay: true });
    mount(document.querySelector("#b"), { src: "/data/karate/mae_geri_left.bvh", autoplay: true });
  </script></body></html>`;
const IFRAME = `<!doctype html><html><body>
  <iframe id="f" src="/embed.html" width="640" height="480" style="border:0"></iframe></body></html>`;

const skipWithoutData = (t) => {
  if (HAVE_DATA) return false;
  t.skip(`SKIPPED: ${DATA} not found`);
  console.log(`SKIPPED: ${DATA} not found; tests on the real recordings did not run`);
  return true;
};

before(async () => {
  server = await startServer({ "/test/two.html": TWO_PLAYERS, "/test/iframe.html": IFRAME });
  browser = await launchBrowser();
  mkdirSync(SCREENSHOTS, { recursive: true });
});
after(async () => {
  await browser?.close();
  await server?.close();
});

const frameOf = (page, sel = "#app") => page.evaluate((s) => document.querySelector(s).embusen.player.frame(), sel);

test("the demo opens, plays, and draws a skeleton and every plot", async () => {
  const requests = [];
  const page = await browser.newPage({ viewport: { width: 1280, height: 800 } });
  page.on("request", (r) => requests.push(r.url()));
  const errors = [];
  page.on("pageerror", (e) => errors.push(String(e)));
  await page.goto(server.url + "/");
  await waitReady(page);
  const first = await frameOf(page);
  await page.waitForTimeout(600);
  const later = await frameOf(page);
  assert.ok(later > first, `playing: frame ${first} → ${later}`);
  const skeleton = await countDrawnPixels(page, "#app canvas.view");
  assert.ok(skeleton > 500, `3D view draws (${skeleton} pixels off the background)`);
  const panels = await page.evaluate(() => [...document.querySelector("#app").embusen.player.plot_panels()]);
  assert.equal(panels.length, 20, "five plot panels");
  for (let i = 0; i < 5; i++) {
    const rect = panels.slice(4 * i, 4 * i + 4);
    const drawn = await countDrawnPixels(page, "#app canvas.plots", rect);
    assert.ok(drawn > 200, `plot ${"abcde"[i]} is drawn (${drawn} pixels in ${rect.map(Math.round)})`);
  }
  await page.screenshot({ path: join(SCREENSHOTS, "demo.png") });
  // Only the app's own files were requested.
  const foreign = requests.filter((u) => !u.startsWith(server.url + "/"));
  assert.deepEqual(foreign, []);
  assert.deepEqual(errors, []);
  await page.close();
});

test("keyboard: space pauses, arrows step, Home/End jump", async () => {
  const { page } = await openApp(browser, server.url);
  await page.keyboard.press(" ");
  const paused = await frameOf(page);
  await page.waitForTimeout(200);
  assert.equal(await frameOf(page), paused, "space paused");
  await page.keyboard.press("ArrowRight");
  await page.keyboard.press("ArrowRight");
  assert.equal(await frameOf(page), paused + 2);
  await page.keyboard.press("ArrowLeft");
  assert.equal(await frameOf(page), paused + 1);
  await page.keyboard.press("End");
  const count = await page.evaluate(() => document.querySelector("#app").embusen.player.frame_count());
  assert.equal(await frameOf(page), count - 1);
  await page.keyboard.press("Home");
  assert.equal(await frameOf(page), 0);
  await page.close();
});

test("clicking a plot seeks", async () => {
  const { page } = await openApp(browser, server.url, "/?autoplay=0");
  const panels = await page.evaluate(() => [...document.querySelector("#app").embusen.player.plot_panels()]);
  const box = await page.locator("#app canvas.plots").boundingBox();
  const dpr = await page.evaluate(() => window.devicePixelRatio);
  // The middle of panel (b), in CSS pixels.
  const [x, y, w, h] = panels.slice(4, 8).map((v) => v / dpr);
  await page.mouse.click(box.x + x + w * 0.5, box.y + y + h * 0.5);
  const frame = await frameOf(page);
  const count = await page.evaluate(() => document.querySelector("#app").embusen.player.frame_count());
  assert.ok(Math.abs(frame - count / 2) < count * 0.1, `seeked to frame ${frame} of ${count}`);
  await page.close();
});

test("heian_nidan.bvh opens through the file input and exports what the CLI writes", async (t) => {
  if (skipWithoutData(t)) return;
  const { page, errors } = await openApp(browser, server.url, "/?autoplay=0");
  const file = join(DATA, "karate/heian_nidan.bvh");
  const started = Date.now();
  await page.setInputFiles("#app input[type=file]", file);
  await page.waitForFunction(() => document.querySelector("#app").embusen.player.name() === "heian_nidan.bvh");
  await waitReady(page);
  console.log(`heian_nidan.bvh: input → ready in ${Date.now() - started} ms (including the page's file read)`);
  assert.equal(await page.evaluate(() => document.querySelector("#app").embusen.player.frame_count()), 2689);
  const info = await page.textContent("#app .info");
  assert.match(info, /2689/);
  assert.match(info, /kinematics/);
  assert.match(info, /sole \d cm below the lowest foot joint \(estimated\)/);
  await page.evaluate(() => document.querySelector("#app").embusen.player.draw());
  assert.ok((await countDrawnPixels(page, "#app canvas.view")) > 500);
  // Export with non-default settings, and compare with the CLI's output for the same.
  const dir = mkdtempSync(join(tmpdir(), "embusen-"));
  const exportMatchesCli = async (name, cliArgs) => {
    const [download] = await Promise.all([page.waitForEvent("download"), page.click("#app [data-action=export-recording]")]);
    assert.equal(download.suggestedFilename(), "heian_nidan.embusen.bvh");
    const exported = readFileSync(await download.path(), "utf8");
    const cliOut = join(dir, `${name}.bvh`);
    execFileSync(join(ROOT, "target/release/embusen"), ["translate", file, ...cliArgs, "-o", cliOut]);
    if (exported !== readFileSync(cliOut, "utf8")) writeFileSync(join(SCREENSHOTS, `exported-${name}.bvh`), exported);
    assert.ok(exported === readFileSync(cliOut, "utf8"), `the exported BVH equals \`embusen translate ${cliArgs.join(" ")}\`'s (diff ${cliOut} ${SCREENSHOTS}/exported-${name}.bvh)`);
  };
  await page.selectOption("#app [data-setting=sole]", "2");
  assert.match(await page.textContent("#app .info"), /sole 2 cm below the lowest foot joint(?! \(estimated)/);
  await exportMatchesCli("contact", ["--sole-depth-cm", "2"]);
  await page.selectOption("#app [data-setting=method]", "paper");
  await page.selectOption("#app [data-setting=smoothing]", "clean");
  await page.fill("#app [data-setting=dyeps]", "4");
  await page.dispatchEvent("#app [data-setting=dyeps]", "change");
  assert.doesNotMatch(await page.textContent("#app .info"), /sole/);
  await exportMatchesCli("paper", ["--method", "paper", "--smoothing", "clean", "--dy-eps", "4"]);
  const [hips] = await Promise.all([page.waitForEvent("download"), page.click("#app [data-action=export-hips]")]);
  assert.equal(hips.suggestedFilename(), "heian_nidan.hips.csv");
  await page.screenshot({ path: join(SCREENSHOTS, "heian_nidan.png") });
  assert.deepEqual(errors, []);
  await page.close();
});

test("a corrupted file shows its error and the open recording stays", async () => {
  const { page } = await openApp(browser, server.url, "/?autoplay=0");
  const dir = mkdtempSync(join(tmpdir(), "embusen-"));
  const bad = join(dir, "broken.bvh");
  writeFileSync(bad, "HIERARCHY\nROOT Hips\n{\n  OFFSET 0 0 0\n  CHANNELS 3 Xposition Yposition Zposition\n}\nMOTION\nFrames: 1\nFrame Time: 0.01\n1 2 x\n");
  await page.keyboard.press("End");
  const before = await frameOf(page);
  await page.setInputFiles("#app input[type=file]", bad);
  await page.waitForSelector("#app .error:not([hidden])");
  const message = await page.textContent("#app .error");
  assert.match(message, /broken\.bvh:10:5: expected a number, found `x`/);
  assert.equal(await page.evaluate(() => document.querySelector("#app").embusen.player.name()), "demo (synthetic kata)");
  assert.equal(await frameOf(page), before);
  await page.screenshot({ path: join(SCREENSHOTS, "error.png") });
  await page.close();
});

test("?src loads by address, with an accelerometer file", async (t) => {
  if (skipWithoutData(t)) return;
  const requests = [];
  const page = await browser.newPage({ viewport: { width: 1400, height: 900 } });
  page.on("request", (r) => requests.push(new URL(r.url()).pathname));
  await page.goto(server.url + "/?autoplay=0&src=/data/karate/heian_shodan.bvh&accel=/data/karate/heian_shodan.accel.csv");
  await waitReady(page);
  await page.waitForFunction(() => document.querySelector("#app").embusen.player.name() === "heian_shodan.bvh");
  assert.match(await page.textContent("#app .info"), /accelerometers LeftFoot\/RightFoot/);
  await page.evaluate(() => { const p = document.querySelector("#app").embusen.player; p.set_frame(1200); p.draw(); });
  await page.screenshot({ path: join(SCREENSHOTS, "heian_shodan.png") });
  const ours = requests.filter((p) => p.startsWith("/data/"));
  assert.deepEqual(ours.sort(), ["/data/karate/heian_shodan.accel.csv", "/data/karate/heian_shodan.bvh"]);
  await page.goto(server.url + "/?autoplay=0&src=/data/groundtruth/bandai1_walk_active_001.bvh");
  await waitReady(page);
  await page.waitForFunction(() => document.querySelector("#app").embusen.player.name() === "bandai1_walk_active_001.bvh");
  await page.evaluate(() => { const p = document.querySelector("#app").embusen.player; p.set_frame(100); p.draw(); });
  await page.screenshot({ path: join(SCREENSHOTS, "bandai_walk.png") });
  await page.close();
});

test("embed.html works in an iframe and two players run on one page", async (t) => {
  const page = await browser.newPage({ viewport: { width: 900, height: 800 } });
  await page.goto(server.url + "/test/iframe.html");
  const frame = page.frameLocator("#f");
  await frame.locator("#player canvas.view").waitFor();
  const inner = page.frames().find((f) => f.url().endsWith("/embed.html"));
  await waitReady(inner, "#player");
  assert.ok((await countDrawnPixels(inner, "#player canvas.view")) > 300, "the embedded player draws");
  await page.screenshot({ path: join(SCREENSHOTS, "iframe.png") });
  if (HAVE_DATA) {
    await page.goto(server.url + "/test/two.html");
    await waitReady(page, "#a");
    await waitReady(page, "#b");
    const names = await page.evaluate(() => ["#a", "#b"].map((s) => document.querySelector(s).embusen.player.name()));
    assert.deepEqual(names, ["demo (synthetic kata)", "mae_geri_left.bvh"]);
    for (const sel of ["#a", "#b"]) {
      assert.ok((await countDrawnPixels(page, `${sel} canvas.view`)) > 300, `${sel} draws`);
      // Playing: the frame moves on by itself (within 5 s, however slow the software GPU).
      const start = await frameOf(page, sel);
      await page.waitForFunction(([s, f]) => document.querySelector(s).embusen.player.frame() !== f, [sel, start], { timeout: 5000 });
    }
    await page.screenshot({ path: join(SCREENSHOTS, "two_players.png") });
  } else {
    skipWithoutData(t);
  }
  await page.close();
});
