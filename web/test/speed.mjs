// Reports (never judges) the page's render speed against a native build:
// one scene, size and spp, rendered in turns by the native `strata`
// binary on one thread and by the page's render worker in headless
// Chromium with the simd128 module and with the plain one.
//
//   node web/test/speed.mjs NATIVE_STRATA [ROUNDS] [SCENE] [WIDTH] [HEIGHT] [SPP]
//
// NATIVE_STRATA is, for the comparison the README reports, a portable
// build: RUSTFLAGS="-C target-cpu=x86-64" cargo build --release -p
// strata-runner --target x86_64-unknown-linux-gnu. Needs web/dist (bash
// web/build.sh) and web/test's packages (npm ci in web/test).
import { readFile, mkdtemp } from "node:fs/promises";
import { execFileSync } from "node:child_process";
import { join } from "node:path";
import { tmpdir } from "node:os";
import { argv, getuid } from "node:process";
import puppeteer from "puppeteer-core";
import { serve } from "./serve.mjs";

const [native, rounds = "5", scene = "cover", width = "320", height = "180", spp = "16"] = argv.slice(2);
if (!native) throw new Error("usage: node web/test/speed.mjs NATIVE_STRATA [ROUNDS] [SCENE] [WIDTH] [HEIGHT] [SPP]");
const dist = new URL("../dist", import.meta.url).pathname;
const server = await serve(dist);
const base = server.base;
const browser = await puppeteer.launch({
  executablePath: process.env.CHROMIUM || "/usr/bin/chromium",
  headless: true,
  args: getuid?.() === 0 ? ["--no-sandbox"] : [],
});
const pages = {};
for (const [name, query] of [["simd128", ""], ["plain", "?simd=0"]]) {
  pages[name] = await browser.newPage();
  await pages[name].goto(base + query);
  // Once the page is idle: its live panel and reference are done.
  await pages[name].waitForFunction(() => window.strata && document.getElementById("live").dataset.plotted === "14",
    { timeout: 300_000 });
}
const settings = { scene, sampler: "independent", filter: "box", adaptive: false, textureBox: false,
  width: Number(width), height: Number(height), spp: Number(spp), seed: 0 };
const paths = settings.width * settings.height * settings.spp;
const dir = await mkdtemp(join(tmpdir(), "strata-speed-"));
const times = { native: [], simd128: [], plain: [] };
for (let r = 0; r < Number(rounds); r++) {
  execFileSync(native, ["render", "--scene", scene, "--width", width, "--height", height, "--spp", spp,
    "--threads", "1", "--no-checkpoint", "--stats", join(dir, "s.json"), "-o", join(dir, "x.png")]);
  const stats = JSON.parse(await readFile(join(dir, "s.json"), "utf8"));
  times.native.push(stats.wall_seconds);
  for (const name of ["simd128", "plain"]) {
    const ms = await pages[name].evaluate((s) => window.strata.render.call("render", s).then((m) => m.ms), settings);
    times[name].push(ms / 1000);
  }
}
const median = (v) => [...v].sort((a, b) => a - b)[Math.floor(v.length / 2)];
console.log(`${scene} ${width}x${height} ${spp} spp, one thread, ${rounds} rounds in turns (median seconds, M paths/s):`);
for (const [name, v] of Object.entries(times)) {
  console.log(`  ${name.padEnd(8)} ${median(v).toFixed(3)} s  ${(paths / median(v) / 1e6).toFixed(2)} M/s  ` +
    `${(median(times.native) / median(v)).toFixed(3)}x native  [${v.map((t) => t.toFixed(3)).join(" ")}]`);
}
await browser.close();
server.close();
