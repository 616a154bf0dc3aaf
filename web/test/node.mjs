// The page's modules under Node: the very files web/build.sh writes for
// the browser (wasm-bindgen's `web` glue, given the inflated module
// instead of a URL), the plain one and the simd128 one. Every golden row
// the page computes is computed in WebAssembly by both and compared with
// the table the module carries and with the film rows the Rust tests
// export (std-runner/tests/data/golden.json): the bits match a native
// build's.
// Run by web/test.sh; exits non-zero on any mismatch.
import { readFile } from "node:fs/promises";
import { gunzipSync } from "node:zlib";
import { exit } from "node:process";

const exported = JSON.parse(await readFile(new URL("../../std-runner/tests/data/golden.json", import.meta.url), "utf8"));
const modules = {};
for (const name of ["strata_web.wasm.gz", "strata_web_simd128.wasm.gz"]) {
  modules[name] = gunzipSync(await readFile(new URL(`../dist/${name}`, import.meta.url)));
}

let failed = 0;
const check = (ok, what) => {
  if (!ok) {
    failed += 1;
    console.log(`FAILED: ${what}`);
  }
};

check(Buffer.compare(modules["strata_web.wasm.gz"], modules["strata_web_simd128.wasm.gz"]) !== 0,
  "the simd128 module differs from the plain one");
let rows = [];
let glue = null;
// The plain module last: the checks below run on it. The glue holds one
// instance, so each module gets its own copy of it (another URL).
for (const name of ["strata_web_simd128.wasm.gz", "strata_web.wasm.gz"]) {
  glue = await import(`../dist/strata_web.js?${name}`);
  await glue.default({ module_or_path: modules[name] });
  const { goldenRows, goldenValue } = glue;
  rows = goldenRows().trim().split("\n").map((l) => l.split(" "));
  // Every built-in scene's rows but the file rows: 5 scenes x 6 samplers,
  // 6 variants, 5 scene hashes.
  check(rows.length === 41, `${rows.length} golden rows, not 41`);
  const started = Date.now();
  let fromFile = 0;
  for (const [scene, key, want] of rows) {
    const got = goldenValue(scene, key);
    check(got === want, `${name}: ${scene} ${key}: ${got}, table ${want}`);
    const film = exported.films[`${scene}/${key}`];
    if (film !== undefined) {
      fromFile += 1;
      check(`0x${got}` === film, `${name}: ${scene} ${key}: ${got}, golden.json ${film}`);
    }
  }
  // Every built-in scene under every sampler.
  check(fromFile === 30 && fromFile === Object.keys(exported.films).length, `${fromFile} rows of golden.json checked`);
  console.log(`${name}: ${rows.length} golden rows computed in WebAssembly in ${(Date.now() - started) / 1000} s`);
}

const { goldenValue, samplePoints, outputVersion, render, periodogram, rmse } = glue;

// The page's sample patterns: the renderer's rows, one per stratum.
const p = samplePoints("stratified", 16, 7, 2);
check(p.length === 32, `16 two-dimensional samples: ${p.length} values`);
const cells = new Set();
for (let i = 0; i < 16; i++) cells.add(Math.floor(p[2 * i] * 4) + 4 * Math.floor(p[2 * i + 1] * 4));
check(cells.size === 16, `stratified 16 fills ${cells.size} of 16 strata`);
const other = samplePoints("sobol", 16, 7, 2);
check(other.some((v, i) => v !== p[i]), "sobol's pattern differs from stratified's");

// Bad input is an Error that gives the reason, never a trap (a panic
// would be a WebAssembly.RuntimeError).
const refused = (call, reason, what) => {
  try {
    call();
    check(false, `${what} was refused`);
  } catch (e) {
    check(!(e instanceof WebAssembly.RuntimeError) && e instanceof Error && reason.test(e.message),
      `${what}: ${e}`);
  }
};
for (const [kind, n, dims, reason] of [
  ["nope", 4, 2, /unknown sampler/],
  ["sobol", 0, 2, /1 to 4096/],
  ["sobol", 5000, 2, /1 to 4096/],
  ["sobol", 4, 0, /1 to 64/],
  ["sobol", 2 ** 32 + 16, 2, /whole number/],
  ["sobol", 4.5, 2, /whole number/],
  ["sobol", -1, 2, /whole number/],
]) {
  refused(() => samplePoints(kind, n, 1, dims), reason, `samplePoints(${kind}, ${n}, ${dims})`);
}
refused(() => goldenValue("no such scene", "sobol"), /not a golden row/, "an unknown scene");
refused(() => goldenValue("examples/scenes/materials.toml", "file.png"), /not a golden row/,
  "a pair outside the table");
refused(() => goldenValue("week09", "file.png"), /not a golden row/, "a file row");

// A render: sizes, codes, the adaptive map; bad settings refused.
const frame = render("week09", "sobol", "box", false, false, 16, 9, 4, 1);
check(frame.width === 16 && frame.height === 9 && frame.samples === 16 * 9 * 4, "a 16x9 frame of 4 spp");
check(frame.rgba().length === 16 * 9 * 4 && frame.linear().length === 16 * 9 * 3, "frame buffers");
check(frame.rgba().filter((_, i) => i % 4 === 3).every((a) => a === 255), "opaque pixels");
check(rmse(frame.linear(), frame.linear()) === 0, "an image's RMSE against itself");
const another = render("week09", "independent", "box", false, false, 16, 9, 4, 1);
check(rmse(frame.linear(), another.linear()) > 0, "two samplers' images differ");
const adaptive = render("caustics", "sobol", "box", true, false, 16, 9, 64, 1);
check(adaptive.samples >= 16 * 16 * 9 && adaptive.samples < 64 * 16 * 9, `adaptive samples ${adaptive.samples}`);
for (const [args, reason] of [
  [["nope", "sobol", "box", false, false, 16, 9, 4, 1], /unknown scene/],
  [["week09", "nope", "box", false, false, 16, 9, 4, 1], /invalid value 'nope' for '--sampler/],
  [["week09", "sobol", "nope", false, false, 16, 9, 4, 1], /invalid value 'nope' for '--filter/],
  [["week09", "sobol", "box", false, false, 0, 9, 4, 1], /--width 0/],
  [["week09", "sobol", "box", false, false, 2048, 512, 64, 1], /at most 33554432 samples/],
  [["week09", "sobol", "box", false, false, 1024, 1024, 1024, 1], /at most 33554432 samples/],
  [["week09", "sobol", "box", false, false, 8192, 4096, 1, 1], /at most 1048576 pixels/],
  [["week09", "grid", "box", true, false, 16, 9, 64, 1], /--adaptive needs a sampler/],
  [["week09", "sobol", "box", false, false, 16.5, 9, 4, 1], /whole number/],
  [["week09", "sobol", "box", false, false, 16, 9, 4, -1], /seed must be a whole number/],
  [["week09", "sobol", "box", false, false, 16, 9, 4, 2 ** 60], /seed must be a whole number/],
]) {
  refused(() => render(...args), reason, `render(${args.slice(0, 8).join(", ")})`);
}
refused(() => rmse(new Float32Array(3), new Float32Array(6)), /equal/, "rmse of different sizes");

// The periodogram: a 4 x 4 grid has its power at multiples of 4.
const grid = periodogram("grid", 16, 1, 0, 1, 4, 8);
const at = (wx, wy) => grid.power()[(wy + 8) * 17 + wx + 8];
check(Math.abs(at(4, 0) - 16) < 1e-3 && at(1, 0) < 1e-3 && grid.radial().length === 8, "the grid's periodogram");
refused(() => periodogram("sobol", 16, 1, 2, 2, 4, 8), /different dimensions/, "a periodogram of one dimension");
refused(() => periodogram("sobol", 16, 1, 0, 1, 4, 129), /out of range/, "a periodogram past frequency 128");
refused(() => periodogram("sobol", 4096, 1, 0, 1, 4096, 128), /the page sums at most/,
  "a periodogram of too many terms");
check(/^\d+\.\d+\.\d+\+r\d+$/.test(outputVersion()), `output version ${outputVersion()}`);

console.log(failed === 0 ? "web: all checks passed" : `web: ${failed} checks failed`);
exit(failed === 0 ? 0 : 1);
