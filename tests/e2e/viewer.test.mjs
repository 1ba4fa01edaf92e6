// End-to-end tests of the `carom view` page in Debian's headless Chromium (playwright-core, no
// browser download). CAROM_EXE names the carom binary.
import { test, before, after } from "node:test";
import assert from "node:assert/strict";
import { execFileSync } from "node:child_process";
import { mkdtempSync, rmSync, statSync } from "node:fs";
import { tmpdir } from "node:os";
import { join } from "node:path";
import { chromium } from "playwright-core";

const carom = process.env.CAROM_EXE;
const folder = mkdtempSync(join(tmpdir(), "carom-view-"));
let browser, page;
const errors = [];

before(async () => {
  const start = join(folder, "gas.txt"), movie = join(folder, "movie.xyz");
  execFileSync(carom, ["init", "--n", "2000", "--phi", "0.5", "--boundary", "periodic", "-o", start]);
  execFileSync(carom, ["run", start, "3", "--rule", "elastic", "--boundary", "periodic",
                       "--dump", movie, "--every", "0.1", "--format", "csv", "-o", join(folder, "end.csv")]);
  execFileSync(carom, ["view", movie, "-o", join(folder, "movie.html")]);
  // Playwright gives the browser a fresh temporary profile (user data dir) of its own.
  browser = await chromium.launch({
    executablePath: "/usr/bin/chromium",
    args: ["--headless", "--no-sandbox", "--disable-gpu", "--disable-background-networking",
           "--disable-component-update", "--no-first-run", "--disable-sync"],
  });
  page = await browser.newPage({ viewport: { width: 1200, height: 800 } });
  page.on("pageerror", (e) => errors.push(String(e)));
  page.on("requestfailed", (r) => errors.push(`request ${r.url()}`));
  await page.goto("file://" + join(folder, "movie.html"));
});

after(async () => {
  await browser?.close();
  rmSync(folder, { recursive: true, force: true });
});

const text = (selector) => page.textContent(selector);

test("the page loads from disk with every frame and no errors", async () => {
  assert.equal(await text("#frames"), "30");  // frames t = 0, 0.1, ..., 3
  assert.equal(await text("#frame"), "0");
  assert.match(await text("#info"), /2000 disks/);
  assert.deepEqual(errors, []);
});

test("playing advances the frame counter, pausing stops it", async () => {
  await page.click("#play");
  // Waits for the animation to move rather than for a fixed time: a loaded machine may deliver
  // the first animation frames late.
  await page.waitForFunction(() => Number(document.querySelector("#frame").textContent) > 0,
                             null, { timeout: 20000 });
  await page.click("#play");
  const paused = Number(await text("#frame"));
  assert.ok(paused > 0, `frame ${paused} after playing`);
  await page.waitForTimeout(300);
  assert.equal(Number(await text("#frame")), paused);
});

test("the slider moves to a frame", async () => {
  await page.$eval("#slider", (slider) => {
    slider.value = "20";
    slider.dispatchEvent(new Event("input"));
  });
  assert.equal(await text("#frame"), "20");
  assert.equal(await text("#time"), "2.00000");
});

test("the disks and the histogram are drawn, in both colourings", async () => {
  for (const colour of ["speed", "collisions"]) {
    await page.selectOption("#colour", colour);
    const painted = await page.$eval("#box", (canvas) => {
      const pixels = canvas.getContext("2d").getImageData(0, 0, canvas.width, canvas.height).data;
      let count = 0;
      for (let i = 3; i < pixels.length; i += 4) if (pixels[i] > 0) ++count;
      return count / (pixels.length / 4);
    });
    assert.ok(painted > 0.3, `${colour}: only ${painted} of the box is painted`);  // eta = 0.5
  }
  const bars = await page.$eval("#histogram", (canvas) => {
    const pixels = canvas.getContext("2d").getImageData(0, 0, canvas.width, canvas.height).data;
    let count = 0;
    for (let i = 3; i < pixels.length; i += 4) if (pixels[i] > 0) ++count;
    return count;
  });
  assert.ok(bars > 1000, `histogram has ${bars} painted pixels`);
  const shot = join(folder, "shot.png");
  await page.screenshot({ path: shot });
  assert.ok(statSync(shot).size > 20000, "the screenshot is blank");
  assert.deepEqual(errors, []);
});
