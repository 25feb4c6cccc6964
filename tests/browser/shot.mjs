// Development aid: `node tests/browser/shot.mjs URL OUT.png [wait_ms]` saves a
// screenshot of a page in the same headless Chromium the tests use, and
// prints the page's errors.
import { launchBrowser } from "./harness.mjs";

const [url, out, wait = "1500"] = process.argv.slice(2);
const browser = await launchBrowser();
const page = await browser.newPage({ viewport: { width: 1280, height: 800 } });
page.on("pageerror", (e) => console.log("page error:", String(e)));
page.on("console", (m) => console.log(`console.${m.type()}:`, m.text()));
await page.goto(url);
await page.waitForTimeout(+wait);
await page.screenshot({ path: out });
await browser.close();
