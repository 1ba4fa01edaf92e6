// End-to-end tests of the `carom analyze --html` report in Debian's headless Chromium
// (playwright-core, no browser download). The first part fills src/analysis/report/report.html with
// fixture analyses, as carom does, to cover missing sections and edge cases; the second runs
// carom (CAROM_EXE) on real disks and spheres.
import { test, describe, before, after } from "node:test";
import assert from "node:assert/strict";
import { execFileSync } from "node:child_process";
import { mkdtempSync, readFileSync, rmSync, writeFileSync } from "node:fs";
import { tmpdir } from "node:os";
import { dirname, join } from "node:path";
import { fileURLToPath } from "node:url";
import { chromium } from "playwright-core";

const carom = process.env.CAROM_EXE;
const template = readFileSync(join(dirname(fileURLToPath(import.meta.url)), "../../src/analysis/report/report.html"), "utf8");
const slot = "/*CAROM_DATA*/";
const folder = mkdtempSync(join(tmpdir(), "carom-report-"));
let browser;

before(async () => {
  // Playwright gives the browser a fresh temporary profile (user data dir) of its own.
  browser = await chromium.launch({
    executablePath: "/usr/bin/chromium",
    args: ["--headless", "--no-sandbox", "--disable-gpu", "--disable-background-networking",
           "--disable-component-update", "--no-first-run", "--disable-sync"],
  });
});

after(async () => {
  await browser?.close();
  rmSync(folder, { recursive: true, force: true });
});

// A page of the browser that records its errors (uncaught, console.error, failed requests) and
// any request that leaves the file: the report must be self-contained.
async function open(html, errors, viewport = { width: 1200, height: 800 }) {
  const page = await browser.newPage({ viewport });
  page.on("pageerror", (e) => errors.push(String(e)));
  page.on("console", (m) => { if (m.type() === "error") errors.push(`console ${m.text()}`); });
  page.on("requestfailed", (r) => errors.push(`request failed ${r.url()}`));
  page.on("request", (r) => { if (!/^(file|data|blob):/.test(r.url())) errors.push(`request ${r.url()}`); });
  await page.goto("file://" + html);
  return page;
}

// The page as carom writes it: the first slot replaced by the JSON (a function, so that `$` in the
// JSON is not a replacement pattern).
async function openWith(name, analysis, errors, viewport) {
  const html = join(folder, `${name}.html`);
  writeFileSync(html, template.replace(slot, () => JSON.stringify(analysis)));
  return open(html, errors, viewport);
}

// The drawn points of a plot's series, in data coordinates, read back through the svg's scales.
const seriesPoints = (page, section, name) => page.$eval(`#${section} svg`, (svg, name) => {
  const path = svg.querySelector(`path.series[data-name="${name}"]`);
  if (!path) return null;
  const back = (scale, pixel) => {
    const { lo, hi, log, from, to } = JSON.parse(scale);
    const f = (pixel - from) / (to - from);
    return log ? lo * (hi / lo) ** f : lo + f * (hi - lo);
  };
  return [...path.getAttribute("d").matchAll(/[ML](-?[\d.]+) (-?[\d.]+)/g)]
    .map((m) => [back(svg.dataset.x, Number(m[1])), back(svg.dataset.y, Number(m[2]))]);
}, name);

// Where g(r) first peaks, in units of d: the first local maximum above g = 1.5.
async function firstPeak(page) {
  const points = await seriesPoints(page, "rdf", "g");
  let k = points.findIndex(([, g]) => g > 1.5);
  assert.ok(k >= 0, "g(r) never exceeds 1.5");
  while (k + 1 < points.length && points[k + 1][1] >= points[k][1]) ++k;
  return points[k][0];
}

// The fraction of the snapshot canvas painted (alpha > 0), and how many of 12 hue sectors hold at
// least 1% of its coloured (saturated) pixels.
const canvasStats = (page) => page.$eval("#snapshot-canvas", (canvas) => {
  const p = canvas.getContext("2d").getImageData(0, 0, canvas.width, canvas.height).data;
  const sectors = new Array(12).fill(0);
  let painted = 0, coloured = 0;
  for (let i = 0; i < p.length; i += 4) {
    if (p[i + 3] === 0) continue;
    ++painted;
    const r = p[i], g = p[i + 1], b = p[i + 2], max = Math.max(r, g, b), range = max - Math.min(r, g, b);
    if (p[i + 3] < 250 || max === 0 || range / max < 0.25) continue;
    const h = max === r ? ((g - b) / range + 6) % 6 : max === g ? (b - r) / range + 2 : (r - g) / range + 4;
    ++sectors[Math.floor(h * 2) % 12];
    ++coloured;
  }
  return { painted: painted / (p.length / 4), hues: sectors.filter((s) => s > 0.01 * coloured).length };
});

// The number of drawn points of every series in a section's plot.
const pointCounts = (page, section) => page.$$eval(`#${section} svg path.series`,
  (paths) => Object.fromEntries(paths.map((p) => [p.dataset.name, Number(p.dataset.points)])));
const note = (page, section) => page.textContent(`#${section} .unavailable`);
const fact = (page, key) => page.textContent(`#summary dd[data-key="${key}"]`);

// ---- Fixtures: analyses as carom writes them, made up but shaped like real ones. ------------------
const range = (n, f) => Array.from({ length: n }, (_, i) => f(i));
function random(seed) {  // a small deterministic generator (LCG), for jitter
  let s = seed >>> 0;
  return () => ((s = (Math.imul(s, 1664525) + 1013904223) >>> 0) / 2 ** 32);
}
const rdf = (contact) => ({
  r: range(250, (i) => 0.01 + 0.02 * i), bin_width: 0.02, r_max: 5, contact,
  g: range(250, (i) => { const r = 0.01 + 0.02 * i; return r < 1 ? 0 : 1 + 2 * Math.exp(-1.5 * (r - 1)) * Math.cos((2 * Math.PI * (r - 1)) / 1.05); }),
});
const logColumns = ["time", "events", "pair_collisions", "virial", "wall_momentum", "temperature", "pressure", "Z",
                    "collision_rate", "pressure_mean", "pressure_error", "Z_mean", "Z_error"];

function disks() {
  // 400 disks on a jittered triangular lattice in a periodic box; psi6 phase winds once around
  // the centre, so that every hue appears.
  const next = random(7), a = 1.25, Lx = 20 * a, Ly = 20 * a * Math.sqrt(3) / 2, position = [], phase = [], modulus = [];
  for (let row = 0; row < 20; ++row) for (let col = 0; col < 20; ++col) {
    const x = (((col + (row % 2) / 2) * a + 0.06 * (next() - 0.5)) % Lx + Lx) % Lx, y = (row + 0.5) * a * Math.sqrt(3) / 2;
    position.push(x, y);
    phase.push(Math.atan2(y - Ly / 2, x - Lx / 2));
    modulus.push(0.3 + 0.7 * next());
  }
  const t = range(41, (i) => 0.5 * i);
  return {
    carom_version: "1.3.0", trajectory: "fixture.gsd", dimension: 2, particles: 400, box: [Lx, Ly], periodic: true,
    packing_fraction: (400 * Math.PI * 0.25) / (Lx * Ly), diameter: 1, monodisperse: true,
    frames: { count: 41, first_time: 0, last_time: 20 }, time: t,
    rdf: rdf({ r: 1, g: 3, Z: 1 + 2 * 0.58 * 3 }),
    msd: { t, msd: t.map((s) => 0.4 * (s - 0.2 * (1 - Math.exp(-s / 0.2)))) },
    psi6: { t, global: t.map((s) => 0.03 + 0.9 * Math.exp(-s / 2)), local_mean: t.map((s) => 0.4 + 0.5 * Math.exp(-s)), bonds: "6 nearest neighbours" },
    // A fluid's S(k): low at small k, its main peak at k d = 7, then oscillating about 1.
    structure_factor: { k: range(60, (i) => 0.25 * (i + 1)), k_peak: 7,
      s: range(60, (i) => { const k = 0.25 * (i + 1); return 1 - 0.9 * Math.exp(-k / 1.5) + 1.6 * Math.exp(-((k - 7) ** 2) / 0.8); }) },
    self_scattering: { k: 7, t, fs: t.map((s) => Math.exp(-s / 2)), alpha2: t.map((s, i) => (i ? 0.3 * s / (1 + s * s) : null)), tau_alpha: 2 },
    snapshot: { time: 20, position, radius: range(400, () => 0.5), psi6_modulus: modulus, psi6_phase: phase },
    // Rows before the measurement window (t < 2) have no running means; the first has no Z.
    log: { file: "run.csv", columns: logColumns, rows: t.map((s, i) => [s, 1000 * i, 1000 * i, 2 * i, 0, 1,
      i ? 2.6 : null, i ? 4 + 0.1 * Math.sin(i) : null, i ? 7 : null, i ? 2.6 : null, s >= 2 ? 0.02 : null,
      s >= 2 ? 4.02 : null, s > 2 ? 0.2 / Math.sqrt(i) : null]) },
    warnings: ["the first frames are a <b>lattice</b> $& not yet melted"],
  };
}

function spheres() {
  const next = random(3), L = 8, position = [];
  for (let i = 0; i < 300; ++i) position.push(L * next(), L * next(), L * next());
  return {
    carom_version: "1.3.0", trajectory: "balls.gsd", dimension: 3, particles: 300, box: [L, L, L], periodic: true,
    packing_fraction: (300 * Math.PI / 6) / L ** 3, diameter: 1, monodisperse: true,
    frames: { count: 21, first_time: 0, last_time: 5 }, time: range(21, (i) => 0.25 * i),
    rdf: rdf(null), msd: null, psi6: null,
    snapshot: { time: 5, position, radius: range(300, () => 0.5), psi6_modulus: null, psi6_phase: null },
    log: null, warnings: [],
  };
}

function oneFrame() {  // a single frame in a 2:1 box with walls: little to plot
  const next = random(5), position = [];
  for (let i = 0; i < 50; ++i) position.push(1 + 18 * next(), 1 + 8 * next());
  return {
    carom_version: "1.3.0", trajectory: "one.gsd", dimension: 2, particles: 50, box: [20, 10], periodic: false,
    packing_fraction: (50 * Math.PI / 4) / 200, diameter: 1, monodisperse: false,
    frames: { count: 1, first_time: 3, last_time: 3 }, time: [3], rdf: rdf(null), msd: null,
    psi6: { t: [3], global: [0.2], local_mean: [0.5], bonds: "6 nearest neighbours" },
    snapshot: { time: 3, position, radius: range(50, (i) => 0.4 + 0.2 * (i % 2)), psi6_modulus: null, psi6_phase: null },
    log: { file: "short.csv", columns: logColumns, rows: [[0, 0, 0, 0, 0, 1, null, null, null, null, null, null, null]] },
    warnings: [], unavailable: { msd: "one frame: no displacements" },
  };
}

function mixture() {  // the disks as a 50:50 mixture of A and B: its partial g_ab(r)
  const analysis = disks(), r = analysis.rdf.r;
  const peaked = (at, height) => r.map((x) => (x < at ? 0 : 1 + height * Math.exp(-3 * (x - at))));
  analysis.monodisperse = false;
  analysis.rdf.partial = { "A-A": peaked(1, 2), "A-B": peaked(1.2, 1.5), "B-B": peaked(1.4, 1) };
  analysis.rdf.partial_weights = { "A-A": 0.2494, "A-B": 0.5013, "B-B": 0.2494 };
  return analysis;
}

describe("the page filled with fixtures", () => {
  test("the template has one data slot, in the data block, and fits carom's raw string", () => {
    assert.ok(!template.includes(')carom_html"'), "the page would end carom's raw string literal");
    const block = '<script id="data" type="application/json">';
    assert.equal(template.indexOf(slot), template.indexOf(block) + block.length);
    assert.equal(template.indexOf(slot, template.indexOf(slot) + 1), -1, "a second slot");
  });

  describe("disks", () => {
    const errors = [], analysis = disks();
    let page;
    before(async () => { page = await openWith("disks", analysis, errors); });
    after(() => page?.close());

    test("every section is drawn, without errors", async () => {
      // All but the bond order, which is for spheres, as psi6 is for disks.
      assert.deepEqual(await page.$$eval(".unavailable", (e) => e.map((u) => u.closest("section").id)), ["steinhardt"]);
      assert.equal(await page.$$eval("#partial_rdf", (e) => e.length), 0);  // one type: no partials
      assert.match(await note(page, "steinhardt"), /defined for spheres \(3D\)/);
      assert.deepEqual(await pointCounts(page, "rdf"), { g: 250 });
      assert.deepEqual(await pointCounts(page, "msd"), { "MSD/d²": 40 });  // lag 0 left out
      assert.deepEqual(await pointCounts(page, "psi6"), { global: 41, local: 41 });
      assert.deepEqual(await pointCounts(page, "structure_factor"), { S: 60 });
      assert.deepEqual(await pointCounts(page, "self_scattering"), { F_s: 40, "α₂": 40 });  // lag 0 left out
      assert.equal(await page.$$eval("#structure_factor .mark", (e) => e.length), 1);  // the main peak
      assert.deepEqual(await pointCounts(page, "log"), { Z: 40, "Z mean": 37 });
      assert.equal(await page.$$eval("#log svg path[fill-opacity]", (e) => e.length), 1);  // the error band
      assert.deepEqual(errors, []);
    });

    test("the summary shows the facts and the warning as text", async () => {
      assert.match(await fact(page, "particles"), /^400 disks/);
      assert.equal(Number(await fact(page, "packing_fraction")), Number(analysis.packing_fraction.toPrecision(4)));
      assert.match(await fact(page, "box"), /periodic/);
      assert.match(await fact(page, "frames"), /41, t = 0 … 20/);
      assert.match(await fact(page, "z_contact"), /^4\.48 \(g\(d⁺\) = 3\)$/);
      assert.match(await fact(page, "z_log"), /^4\.02 ± /);
      assert.match(await fact(page, "tau_alpha"), /^2 \(F_s = 1\/e at k d = 7\)$/);
      assert.match(await page.textContent("#summary .warnings"), /a <b>lattice<\/b> \$& not/);
    });

    test("g(r) peaks at contact, marked, on axes in units of d", async () => {
      assert.ok(Math.abs(await firstPeak(page) - 1) < 0.05);
      assert.equal(await page.$$eval("#rdf .mark", (e) => e.length), 1);
      assert.match(await page.textContent("#rdf svg"), /r \/ d/);
      // MSD on log-log axes; psi6 on [0, 1].
      const scale = (section, axis) => page.$eval(`#${section} svg`, (svg, axis) => JSON.parse(svg.dataset[axis]), axis);
      assert.equal((await scale("msd", "x")).log, true);
      assert.equal((await scale("self_scattering", "x")).log, true);
      assert.equal((await scale("msd", "y")).log, true);
      const psi = await scale("psi6", "y");
      assert.deepEqual([psi.lo, psi.hi], [0, 1]);
    });

    test("hovering a plot reads out the nearest point", async () => {
      await page.locator("#rdf svg").scrollIntoViewIfNeeded();  // the summary may push it below the fold
      const box = await page.locator("#rdf svg").boundingBox();
      const [x, y] = await page.$eval("#rdf path.series", (p) => p.getAttribute("d").split("L")[125].split(" ").map(Number));
      await page.mouse.move(box.x + x, box.y + y + 3);  // just below the 126th point
      assert.match(await page.textContent("#rdf .readout"), /^r\/d = 2\.51, {2}g = [\d.]+$/);  // the 126th bin
      await page.mouse.move(box.x - 5, box.y - 5);
      assert.equal(await page.textContent("#rdf .readout"), "");
    });

    test("the snapshot is painted in many hues, with a colour wheel", async () => {
      assert.equal(await page.getAttribute("#snapshot-canvas", "data-colouring"), "psi6");
      const { painted, hues } = await canvasStats(page);
      assert.ok(painted > 0.5 && painted < 0.7, `${painted} of the box painted`);  // phi = 0.58
      assert.ok(hues >= 10, `only ${hues} of 12 hue sectors`);
      assert.equal(await page.$$eval("#snapshot .key canvas", (e) => e.length), 1);
    });

    test("a narrow window gets narrower plots and no sideways scrolling", async () => {
      await page.setViewportSize({ width: 420, height: 800 });
      await page.waitForFunction(() => document.querySelector("#rdf svg").getAttribute("width") < 400, null, { timeout: 10000 });
      assert.ok(await page.evaluate(() => document.documentElement.scrollWidth <= 420));
      assert.ok(Math.abs(await firstPeak(page) - 1) < 0.05);
      assert.deepEqual(errors, []);
    });
  });

  test("a mixture's partial g_ab(r) are drawn over g(r), with each pair's share", async () => {
    const errors = [], page = await openWith("mixture", mixture(), errors);
    assert.deepEqual(await pointCounts(page, "partial_rdf"), { g: 250, "g A-A": 250, "g A-B": 250, "g B-B": 250 });
    assert.match(await page.textContent("#partial_rdf .legend"), /g A-A.*g A-B.*g B-B.*all pairs/);
    assert.match(await page.textContent("#partial_rdf .caption"), /A-A 0\.249, A-B 0\.501, B-B 0\.249\.$/);
    // Where each partial is drawn: A-B rises from 0 to 2.5 at r = 1.2 d.
    const ab = await seriesPoints(page, "partial_rdf", "g A-B");
    const first = ab.findIndex(([, g]) => g > 0.1);
    assert.ok(Math.abs(ab[first][0] - 1.21) < 0.02 && Math.abs(ab[first][1] - 2.5) < 0.05, `A-B starts at ${ab[first]}`);
    assert.deepEqual(errors, []);
    await page.close();
  });

  test("spheres: no psi6, MSD or log; a depth-coloured projection", async () => {
    const errors = [], page = await openWith("spheres", spheres(), errors);
    assert.match(await note(page, "psi6"), /defined for disks \(2D\)/);
    assert.match(await note(page, "msd"), /image flags/);
    assert.match(await note(page, "self_scattering"), /image flags/);
    assert.match(await note(page, "log"), /No log file given/);
    for (const section of ["psi6", "msd", "log"]) {
      assert.ok(await page.isVisible(`#${section} .unavailable`));
      assert.equal(await page.$$eval(`#${section} svg`, (e) => e.length), 0);
    }
    assert.match(await fact(page, "particles"), /^300 spheres/);
    assert.equal(await page.getAttribute("body", "data-dimension"), "3");
    assert.equal(await page.getAttribute("#snapshot-canvas", "data-colouring"), "z");
    assert.match(await page.textContent("#snapshot .caption"), /xy plane/);
    assert.ok((await canvasStats(page)).painted > 0.5);
    // No contact value: the contact line at r = d stays, without a mark.
    assert.equal(await page.$$eval("#rdf .mark", (e) => e.length), 0);
    assert.ok(Math.abs(await firstPeak(page) - 1) < 0.05);
    assert.deepEqual(errors, []);
    await page.close();
  });

  test("one frame in a box with walls: carom's own reasons and sparse plots", async () => {
    const errors = [], page = await openWith("one", oneFrame(), errors);
    assert.equal(await note(page, "msd"), "one frame: no displacements");
    assert.match(await note(page, "log"), /short\.csv has no Z values yet/);
    assert.match(await note(page, "structure_factor"), /hard walls/);
    assert.deepEqual(await pointCounts(page, "psi6"), { global: 1, local: 1 });
    assert.equal(await page.$$eval("#psi6 svg circle[r='2.5']", (e) => e.length), 2);  // single points as dots
    assert.match(await fact(page, "box"), /^20 × 10, hard walls$/);
    assert.match(await fact(page, "diameter"), /polydisperse/);
    assert.equal(await page.$$eval("#summary dd[data-key=psi6]", (e) => e.length), 1);
    const shape = await page.$eval("#snapshot-canvas", (c) => c.width / c.height);
    assert.ok(Math.abs(shape - 2) < 0.02, `the canvas is ${shape}:1`);
    assert.equal(await page.getAttribute("#snapshot-canvas", "data-colouring"), "plain");
    assert.deepEqual(errors, []);
    await page.close();
  });
});

// ---- carom analyze on real trajectories ---------------------------------------------------------
describe("carom analyze", { skip: !carom && "CAROM_EXE is not set" }, () => {
  const run = (...args) => execFileSync(carom, args, { cwd: folder, stdio: ["ignore", "pipe", "pipe"] });
  const embedded = (page) => page.$eval("#data", (e) => JSON.parse(e.textContent));

  // Every section with data has a plot with many points; every one without says why.
  async function sectionsDrawn(page, analysis) {
    for (const section of ["rdf", "msd", "psi6", "structure_factor", "self_scattering", "steinhardt",
                           "log"]) {
      if (analysis[section] === null) {
        assert.ok(await page.isVisible(`#${section} .unavailable`), `${section}: no note`);
        continue;
      }
      const counts = Object.values(await pointCounts(page, section));
      assert.ok(Math.max(...counts) >= 15, `${section}: only ${counts} points drawn`);
    }
  }

  describe("disks", () => {
    const errors = [];
    let page, analysis, output;
    before(async () => {
      run("init", "--n", "1000", "--phi", "0.5", "--boundary", "periodic", "-o", "gas.txt");
      run("run", "gas.txt", "20", "--rule", "elastic", "--boundary", "periodic", "--dump", "run.gsd", "--every", "0.5",
          "--log", "run.csv", "--log-every", "0.5", "-o", "end.txt");
      run("analyze", "run.gsd", "--log", "run.csv", "--html", "report.html", "-o", "analysis.json");
      output = JSON.parse(readFileSync(join(folder, "analysis.json"), "utf8"));
      page = await open(join(folder, "report.html"), errors);
      analysis = await embedded(page);
    });
    after(() => page?.close());

    test("the page loads without errors and summarises the run", async () => {
      assert.equal(output.particles, 1000);
      assert.ok(Math.abs(output.packing_fraction - 0.5) < 1e-6);
      assert.match(await fact(page, "particles"), /^1000 disks/);
      const phi = Number(await fact(page, "packing_fraction"));
      assert.ok(Math.abs(phi - output.packing_fraction) < 5e-4, `phi ${phi}`);
      assert.match(await page.textContent("#title"), /run\.gsd/);
      assert.deepEqual(errors, []);
    });

    test("g(r), MSD, psi6 and the log's Z are plotted", async () => {
      for (const section of ["rdf", "psi6", "log"]) assert.notEqual(analysis[section], null, `${section} is null`);
      await sectionsDrawn(page, analysis);
      const peak = await firstPeak(page);
      assert.ok(Math.abs(peak - 1) < 0.1, `g(r) first peaks at r = ${peak} d`);
      assert.ok((await pointCounts(page, "log")).Z >= 30);
      assert.ok(await page.isVisible("#summary dd[data-key=psi6]"));
      assert.match(await note(page, "steinhardt"), /defined for spheres \(3D\)/);
      assert.deepEqual(errors, []);
    });

    test("the snapshot shows the disks in the hues of their psi6 phase", async () => {
      assert.equal(await page.getAttribute("#snapshot-canvas", "data-colouring"), "psi6");
      const { painted, hues } = await canvasStats(page);
      assert.ok(painted > 0.35 && painted < 0.7, `${painted} of the box painted`);  // phi = 0.5
      assert.ok(hues >= 8, `only ${hues} of 12 hue sectors`);
      await page.screenshot({ path: join(folder, "disks.png"), fullPage: true });
      assert.deepEqual(errors, []);
    });
  });

  test("--only: psi6 alone is plotted, and every section left out says that it was", async () => {
    run("analyze", "run.gsd", "--only", "psi6", "--html", "only.html");
    const errors = [], page = await open(join(folder, "only.html"), errors);
    const analysis = await embedded(page);
    assert.deepEqual(analysis.only, ["psi6"]);
    assert.ok((await pointCounts(page, "psi6")).global >= 15);
    for (const section of ["rdf", "msd", "structure_factor", "self_scattering", "steinhardt"]) {
      assert.equal(await note(page, section), `Not computed: carom analyze --only psi6 left ${section} out.`);
    }
    assert.deepEqual(errors, []);
    await page.close();
  });

  test("a binary mixture's partial g_ab(r) are plotted, one type's run has none", async () => {
    run("init", "--n", "400", "--phi", "0.4", "--species", "A:0.5:1.0,B:0.5:1.4", "--boundary", "periodic", "-o", "mix.txt");
    run("run", "mix.txt", "2", "--rule", "elastic", "--dump", "mix.gsd", "--every", "0.5", "-o", "mix_end.txt");
    run("analyze", "mix.gsd", "--html", "mix.html");
    const errors = [], page = await open(join(folder, "mix.html"), errors);
    const analysis = await embedded(page);
    assert.deepEqual(Object.keys(analysis.rdf.partial), ["A-A", "A-B", "B-B"]);
    const counts = await pointCounts(page, "partial_rdf");
    assert.deepEqual(Object.keys(counts), ["g", "g A-A", "g A-B", "g B-B"]);
    assert.ok(Math.min(...Object.values(counts)) >= 100, `points drawn: ${JSON.stringify(counts)}`);
    // An A and a B touch at (1.0 + 1.4) / 2: the plot's r / d times d.
    const ab = await seriesPoints(page, "partial_rdf", "g A-B");
    const contact = ab.find(([, g]) => g > 0.5)[0] * analysis.diameter;
    assert.ok(Math.abs(contact - 1.2) < 0.05, `A-B pairs start at r = ${contact}`);
    await page.close();
    const disks = await open(join(folder, "report.html"), errors);
    assert.equal(await disks.$$eval("#partial_rdf", (e) => e.length), 0);
    await disks.close();
    assert.deepEqual(errors, []);
  });

  describe("spheres", () => {
    const errors = [];
    let page, analysis;
    before(async () => {
      run("init", "--n", "500", "--phi", "0.3", "--dim", "3", "--boundary", "periodic", "-o", "balls.txt");
      run("run", "balls.txt", "5", "--rule", "elastic", "--boundary", "periodic", "--dump", "balls.gsd", "--every", "0.25",
          "-o", "balls_end.txt");
      run("analyze", "balls.gsd", "--html", "balls.html");
      page = await open(join(folder, "balls.html"), errors);
      analysis = await embedded(page);
    });
    after(() => page?.close());

    test("psi6 and the log are not available, the rest is drawn", async () => {
      assert.equal(analysis.psi6, null);
      assert.notEqual(analysis.steinhardt, null);
      assert.deepEqual(await pointCounts(page, "steinhardt"), { "q₆": 21, "q̄₆": 21, "cluster/N": 21 });
      assert.match(await fact(page, "steinhardt"), /solid-like, largest cluster \d+$/);
      assert.equal(analysis.log, null);
      assert.match(await note(page, "psi6"), /disks \(2D\)/);
      assert.match(await note(page, "log"), /log/);
      await sectionsDrawn(page, analysis);
      const peak = await firstPeak(page);
      assert.ok(Math.abs(peak - 1) < 0.1, `g(r) first peaks at r = ${peak} d`);
      assert.match(await fact(page, "particles"), /^500 spheres/);
      assert.ok(Math.abs(Number(await fact(page, "packing_fraction")) - analysis.packing_fraction) < 5e-4);
      assert.deepEqual(errors, []);
    });

    test("the snapshot is the xy projection coloured by z", async () => {
      assert.equal(await page.getAttribute("#snapshot-canvas", "data-colouring"), "z");
      const { painted } = await canvasStats(page);
      assert.ok(painted > 0.5, `only ${painted} of the box painted`);
      assert.deepEqual(errors, []);
    });
  });
});
