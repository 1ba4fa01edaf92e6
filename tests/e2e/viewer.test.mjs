// End-to-end tests of the `carom view` page in Debian's headless Chromium (playwright-core, no
// browser download), for disks and for spheres. CAROM_EXE names the carom binary.
import { test, describe, before, after } from "node:test";
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
  page = await open(join(folder, "movie.html"), errors);
});

// A page of the browser that records its errors (uncaught, console.error, failed requests).
async function open(html, errors) {
  const opened = await browser.newPage({ viewport: { width: 1200, height: 800 } });
  opened.on("pageerror", (e) => errors.push(String(e)));
  opened.on("console", (m) => { if (m.type() === "error") errors.push(`console ${m.text()}`); });
  opened.on("requestfailed", (r) => errors.push(`request ${r.url()}`));
  await opened.goto("file://" + html);
  return opened;
}

// The fraction of a canvas's pixels painted (alpha > 0).
const painted = (on, selector) => on.$eval(selector, (canvas) => {
  const pixels = canvas.getContext("2d").getImageData(0, 0, canvas.width, canvas.height).data;
  let count = 0;
  for (let i = 3; i < pixels.length; i += 4) if (pixels[i] > 0) ++count;
  return count / (pixels.length / 4);
});

// Where the histogram's Maxwell-Boltzmann line peaks, as a fraction of the histogram's width:
// the mean column of the highest row holding the line's yellow. The speed axis ends at
// 4 sqrt(kT), so the 2D curve (peak at sqrt(kT)) peaks at 0.25, the 3D one (sqrt(2 kT)) at 0.354.
const curvePeak = (on) => on.$eval("#histogram", (canvas) => {
  const pixels = canvas.getContext("2d").getImageData(0, 0, canvas.width, canvas.height).data;
  for (let y = 0; y < canvas.height; ++y) {
    let sum = 0, count = 0;
    for (let x = 0; x < canvas.width; ++x) {
      const k = 4 * (y * canvas.width + x);
      if (pixels[k] > 180 && pixels[k + 1] > 140 && pixels[k + 2] < 130 && pixels[k + 3] > 200) {
        sum += x;
        ++count;
      }
    }
    if (count > 0) return (sum / count + 0.5) / canvas.width;
  }
  return null;
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
  // Box sides to 7 significant digits, not the 17 of a double (or the noise of a float32).
  assert.match(await text("#info"), /^2000 disks, box \d{2}\.\d{1,5} x \d{2}\.\d{1,5} \(periodic\)$/);
  assert.equal(await page.getAttribute("body", "data-dimension"), "2");
  assert.deepEqual(errors, []);
});

test("playing advances the frame counter, pausing stops it", async () => {
  await page.click("#play");
  // Waits for the animation to move rather than for a fixed time: a loaded machine may deliver
  // the first animation frames late.
  await page.waitForFunction(() => Number(document.querySelector("#frame").textContent) > 0,
                             null, { timeout: 20000 });
  await page.click("#play");
  // No check that the paused frame is above 0: playback wraps after the last frame, and on a
  // loaded machine it may have wrapped to frame 0 by the time the click lands.
  const paused = Number(await text("#frame"));
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

test("the disks and the histogram are drawn, in every colouring", async () => {
  for (const colour of ["speed", "collisions", "psi6"]) {
    await page.selectOption("#colour", colour);
    const box = await painted(page, "#box");
    assert.ok(box > 0.3, `${colour}: only ${box} of the box is painted`);  // eta = 0.5
    // The legend says what the colours run up to in this frame.
    assert.match(await text("#legend-high"),
                 colour === "speed" ? /^\d\.\d\d \(speed\)$/
                 : colour === "psi6" ? /the phase of psi6/ : /^\d+ collisions$/);
    assert.ok((await page.getAttribute("#legend-bar", "style")).includes("linear-gradient"));
  }
  // The page's psi6 is carom analyze's: the global |psi6| of the frame shown, and of frame 0
  // (the lattice the start was, before it melted).
  const analysis = JSON.parse(execFileSync(carom, ["analyze", join(folder, "movie.xyz"), "-o", "-"]));
  const global = async () => Number((await text("#legend-high")).match(/global \|psi6\| = ([\d.]+)/)[1]);
  for (const at of [Number(await text("#frame")), 0]) {
    await page.evaluate((f) => {
      slider.value = String(f);
      slider.dispatchEvent(new Event("input"));
    }, at);
    const expected = analysis.psi6.global[at], shown = await global();
    assert.ok(Math.abs(shown - expected) < 2e-3, `frame ${at}: ${shown} vs ${expected}`);
  }
  const bars = await painted(page, "#histogram");
  assert.ok(bars > 0.02, `only ${bars} of the histogram is painted`);
  const shot = join(folder, "shot.png");
  await page.screenshot({ path: shot });
  assert.ok(statSync(shot).size > 20000, "the screenshot is blank");
  assert.deepEqual(errors, []);
});

test("the histogram's curve is the 2D Maxwell-Boltzmann distribution", async () => {
  assert.match(await text("#curve"), /2D Maxwell-Boltzmann/);
  const peak = await curvePeak(page);
  assert.ok(Math.abs(peak - 0.25) < 0.03, `the curve peaks at ${peak} of the width, not 0.25`);
});

describe("spheres", () => {
  let spheres;
  const sphereErrors = [];
  const at = (selector) => spheres.textContent(selector);
  const rotation = async () => ({ yaw: Number(await spheres.getAttribute("body", "data-yaw")),
                                  pitch: Number(await spheres.getAttribute("body", "data-pitch")) });
  const checksum = () => spheres.$eval("#box", (canvas) => {
    const pixels = canvas.getContext("2d").getImageData(0, 0, canvas.width, canvas.height).data;
    let sum = 0;
    for (let i = 0; i < pixels.length; ++i) sum = (sum * 31 + pixels[i]) % 1000000007;
    return sum;
  });

  before(async () => {
    const start = join(folder, "spheres.txt"), movie = join(folder, "spheres.xyz");
    execFileSync(carom, ["init", "--dim", "3", "--n", "500", "--phi", "0.3", "--boundary", "walls", "-o", start]);
    execFileSync(carom, ["run", start, "3", "--rule", "elastic", "--dump", movie, "--every", "0.1",
                         "--format", "csv", "-o", join(folder, "spheres-end.csv")]);
    execFileSync(carom, ["view", movie, "-o", join(folder, "spheres.html")]);
    spheres = await open(join(folder, "spheres.html"), sphereErrors);
  });

  after(() => spheres?.close());

  test("the page knows the trajectory holds spheres", async () => {
    assert.equal(await spheres.getAttribute("body", "data-dimension"), "3");
    assert.equal(await at("#frames"), "30");
    assert.match(await at("#info"), /^500 spheres, box [\d.]+ x [\d.]+ x [\d.]+ \(walls\)/);
    assert.deepEqual(sphereErrors, []);
  });

  test("the spheres, the box and the histogram are drawn, in both colourings", async () => {
    assert.equal(await spheres.locator('#colour option[value="psi6"]').count(), 0);
    for (const colour of ["speed", "collisions"]) {
      await spheres.selectOption("#colour", colour);
      const box = await painted(spheres, "#box");
      assert.ok(box > 0.15, `${colour}: only ${box} of the canvas is painted`);
    }
    const bars = await painted(spheres, "#histogram");
    assert.ok(bars > 0.02, `only ${bars} of the histogram is painted`);
    await spheres.$eval("#slider", (slider) => {
      slider.value = "20";
      slider.dispatchEvent(new Event("input"));
    });
    assert.equal(await at("#frame"), "20");
    assert.equal(await at("#time"), "2.00000");
    assert.deepEqual(sphereErrors, []);
  });

  test("the histogram's curve is the 3D Maxwell-Boltzmann distribution", async () => {
    assert.match(await at("#curve"), /3D Maxwell-Boltzmann/);
    const peak = await curvePeak(spheres);
    assert.ok(Math.abs(peak - Math.SQRT2 / 4) < 0.03,
              `the curve peaks at ${peak} of the width, not sqrt(2) / 4`);
  });

  test("dragging rotates the view, a double click restores it", async () => {
    const home = await rotation(), unturned = await checksum();
    const box = await spheres.locator("#box").boundingBox();
    const x = box.x + box.width / 2, y = box.y + box.height / 2;
    await spheres.mouse.move(x, y);
    await spheres.mouse.down();
    await spheres.mouse.move(x + 120, y + 40, { steps: 6 });  // 0.01 radian a pixel
    await spheres.mouse.up();
    // The page redraws on its next animation frame: wait for it rather than for a fixed time.
    const shown = (yaw, pitch) => spheres.waitForFunction(
        ([yaw, pitch]) => Math.abs(Number(document.body.dataset.yaw) - yaw) < 1e-3 &&
                          Math.abs(Number(document.body.dataset.pitch) - pitch) < 1e-3,
        [yaw, pitch], { timeout: 20000 });
    await shown(home.yaw + 1.2, home.pitch + 0.4);
    assert.notEqual(await checksum(), unturned, "the canvas did not change");
    await spheres.dblclick("#box");
    await shown(home.yaw, home.pitch);
    assert.equal(await checksum(), unturned);
    const shot = join(folder, "spheres.png");
    await spheres.screenshot({ path: shot });
    assert.ok(statSync(shot).size > 20000, "the screenshot is blank");
    assert.deepEqual(sphereErrors, []);
  });
});
