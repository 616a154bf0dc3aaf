// The page in a real browser: Debian's Chromium, headless, driven by
// puppeteer-core (no browser download). Serves web/dist from a local
// server that counts the bytes it sends, then checks that the page
//   - loads with no console error, failed request or uncaught exception,
//   - computes the golden configuration's film hash equal to the row the
//     Rust tests export (std-runner/tests/data/golden.json, not the
//     page's own table), with the simd128 module and again with the plain
//     one (`?simd=0`),
//   - redraws the sample pattern and its spectrum when the sampler changes,
//   - draws the aliasing panel, the live passes and the error plot; when
//     settings change mid-run, ends with the new run's passes, error plot
//     and (B adaptive) a sampling map of more than one colour,
//   - downloads less than 2 MB in all, with either module.
// Screenshots go to target/web/. Reports (never judges) the first
// contentful paint and the live panel's status lines.
// Run by web/test.sh (after web/build.sh); CHROMIUM names the browser.
import { readFile, mkdir } from "node:fs/promises";
import { join } from "node:path";
import { exit, getuid } from "node:process";
import puppeteer from "puppeteer-core";
import { serve } from "./serve.mjs";

const root = new URL("../..", import.meta.url).pathname;
const dist = join(root, "web/dist");
const shots = join(root, "target/web");
await mkdir(shots, { recursive: true });
const BUDGET = 2_000_000;
const GOLDEN = ["week09", "sobol"];

// The table's value, as the Rust tests export it for the bindings.
const exported = JSON.parse(await readFile(join(root, "std-runner/tests/data/golden.json"), "utf8"));
const film = exported.films[GOLDEN.join("/")];
if (!/^0x[0-9a-f]{16}$/.test(film ?? "")) throw new Error(`no golden row ${GOLDEN.join("/")} in golden.json`);
const want = film.slice(2);

const server = await serve(dist);
const base = server.base;

// Whatever hangs, the test ends: 5 minutes in all (it takes about 20 s).
setTimeout(() => {
  console.log("FAILED: the browser test did not finish within 5 minutes");
  if (problems.length) console.log(`  ${problems.join("\n  ")}`);
  exit(1);
}, 300_000).unref();

let failed = 0;
const check = (ok, what) => {
  console.log(`${ok ? "ok" : "FAILED"}: ${what}`);
  if (!ok) failed += 1;
};

const browser = await puppeteer.launch({
  executablePath: process.env.CHROMIUM || "/usr/bin/chromium",
  headless: true,
  // Chromium's sandbox refuses to run as root; a container's small
  // /dev/shm can crash it on a full-page screenshot.
  args: [...(getuid?.() === 0 ? ["--no-sandbox"] : []), "--disable-dev-shm-usage"],
});
const problems = [];
async function open(query) {
  const page = await browser.newPage();
  await page.setViewport({ width: 1280, height: 900 });
  page.on("console", (m) => m.type() === "error" && problems.push(`console: ${m.text()}`));
  page.on("pageerror", (e) => problems.push(`exception: ${e.message}`));
  page.on("requestfailed", (r) => problems.push(`request failed: ${r.url()} (${r.failure()?.errorText})`));
  page.on("response", (r) => r.status() >= 400 && problems.push(`HTTP ${r.status()}: ${r.url()}`));
  server.reset();
  await page.goto(base + query, { waitUntil: "load" });
  await page.waitForFunction(() => document.getElementById("module").dataset.state !== "loading",
    { timeout: 60_000 });
  return page;
}
const text = (page, sel) => page.$eval(sel, (e) => e.textContent);
const canvas = (page, id) => page.$eval(`#${id}`, (c) => c.toDataURL());

async function golden(page, label) {
  await page.waitForFunction(() => document.getElementById("g-match").dataset.state !== "pending",
    { timeout: 60_000 });
  const got = await text(page, "#g-got");
  check(got === want, `${label}: the page's ${GOLDEN.join(" ")} film hash ${got} is the table's ${want}`);
  check(await page.$eval("#g-match", (e) => e.dataset.state) === "same", `${label}: the page says the bits match`);
}

try {
  // simd128 (Chromium has WebAssembly SIMD).
  const page = await open("");
  check(await page.$eval("#module", (e) => e.dataset.state) === "ready", `module: ${await text(page, "#module")}`);
  check(await page.$eval("#module", (e) => e.dataset.simd) === "true", "the simd128 module was chosen");
  await golden(page, "simd128");

  // Sample patterns: another sampler, another pattern and spectrum.
  const drawn = (prefix) => page.waitForFunction((p) => (document.getElementById("patterns").dataset.drawn || "")
    .startsWith(p), { timeout: 60_000 }, prefix);
  await drawn("stratified 64 0 1");
  const before = [await canvas(page, "points"), await canvas(page, "spectrum"), await canvas(page, "radial")];
  await page.screenshot({ path: join(shots, "patterns-stratified.png") });
  await page.select("#p-sampler", "grid");
  await drawn("grid 64 0 1");
  const after = [await canvas(page, "points"), await canvas(page, "spectrum"), await canvas(page, "radial")];
  ["points", "spectrum", "radial average"].forEach((what, i) => check(before[i] !== after[i],
    `changing the sampler redraws the ${what}`));
  await page.screenshot({ path: join(shots, "patterns-grid.png") });

  // Aliasing, then the live panel's passes and its error plot.
  await page.waitForFunction(() => document.getElementById("aliasing").dataset.drawn, { timeout: 60_000 });
  const aliasing = [await canvas(page, "a-grid"), await canvas(page, "a-jitter"), await canvas(page, "a-prefilter")];
  check(new Set(aliasing).size === 3, "the three aliasing panels differ");
  await page.waitForFunction(() => document.getElementById("live").dataset.passes === "14" &&
    document.getElementById("live").dataset.plotted === "14", { timeout: 180_000 });
  check(true, `live: ${(await page.$$eval(".l-status", (e) => e.map((x) => x.textContent))).join(" | ")}`);
  // Changes mid-run: B turns adaptive, then (before that run ends) the
  // scene and the most samples change. The last settings' run ends: its
  // passes (A: 1 to 16 spp; B adaptive: 8 and 16), its error plot
  // against cover's reference, and a sampling map that is not one colour.
  await page.click("#side-b .l-adaptive");
  await page.select("#l-scene", "cover");
  await page.select("#l-max", "16");
  const last = "cover 16 independent box false zsobol box true";
  await page.waitForFunction((run) => {
    const live = document.getElementById("live").dataset;
    return live.run === run && live.passes === "7" && live.plotted === "7";
  }, { timeout: 180_000 }, last);
  check(true, `the last settings' run ended: ${last}`);
  const restarts = await page.evaluate(() => window.strata.render.restarts);
  check(restarts >= 1, `a change during a pass restarted the render worker (${restarts} restarts)`);
  const heat = await page.$eval("#side-b .l-heat", (c) => {
    const d = c.getContext("2d").getImageData(0, 0, c.width, c.height).data;
    const colours = new Set();
    for (let i = 0; i < d.length; i += 4) colours.add(`${d[i]},${d[i + 1]},${d[i + 2]}`);
    return colours.size;
  });
  check(heat > 1, `the adaptive map shows where samples went (${heat} colours)`);
  const fcp = await page.evaluate(() => performance.getEntriesByName("first-contentful-paint")[0]?.startTime);
  console.log(`first contentful paint: ${fcp?.toFixed(0)} ms (local server, cold cache)`);
  await page.screenshot({ path: join(shots, "page-simd128.png"), fullPage: true });
  check(server.served() < BUDGET, `the page downloaded ${server.served()} bytes (budget ${BUDGET})`);
  await page.close();

  // The plain module (browsers without WebAssembly SIMD).
  const plain = await open("?simd=0");
  check(await plain.$eval("#module", (e) => e.dataset.simd) === "false", `plain: ${await text(plain, "#module")}`);
  await golden(plain, "plain");
  await plain.waitForFunction(() => document.getElementById("patterns").dataset.drawn, { timeout: 60_000 });
  check(server.served() < BUDGET, `the plain page downloaded ${server.served()} bytes (budget ${BUDGET})`);
  await plain.screenshot({ path: join(shots, "page-plain.png") });
  await plain.close();
} catch (e) {
  check(false, `the browser test ran to its end: ${e.message}`);
}
check(problems.length === 0, `no console errors, exceptions or failed requests${problems.length ? `:\n  ${problems.join("\n  ")}` : ""}`);
await browser.close();
server.close();
console.log(failed === 0 ? "browser: all checks passed" : `browser: ${failed} checks failed`);
exit(failed === 0 ? 0 : 1);
