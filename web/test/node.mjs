// The page's module under Node: the very files web/build.sh writes for
// the browser (wasm-bindgen's `web` target, given the bytes instead of a
// URL). Every golden row is computed in WebAssembly and compared with the
// table, which the module carries: the bits match a native build's.
// Run by web/test.sh; exits non-zero on any mismatch.
import { readFile } from "node:fs/promises";
import { exit } from "node:process";
import init, { goldenRows, goldenValue, samplePoints, outputVersion } from "../dist/strata_web.js";

const bytes = await readFile(new URL("../dist/strata_web_bg.wasm", import.meta.url));
await init({ module_or_path: bytes });

let failed = 0;
const check = (ok, what) => {
  if (!ok) {
    failed += 1;
    console.log(`FAILED: ${what}`);
  }
};

const rows = goldenRows().trim().split("\n").map((l) => l.split(" "));
check(rows.length > 50, `${rows.length} golden rows`);
const started = Date.now();
for (const [scene, key, want] of rows) {
  const got = goldenValue(scene, key);
  check(got === want, `${scene} ${key}: ${got}, table ${want}`);
}
console.log(`${rows.length} golden rows computed in WebAssembly in ${(Date.now() - started) / 1000} s`);

// The page's sample patterns: the renderer's rows, one per stratum.
const p = samplePoints("stratified", 16, 7n, 2);
check(p.length === 32, `16 two-dimensional samples: ${p.length} values`);
const cells = new Set();
for (let i = 0; i < 16; i++) cells.add(Math.floor(p[2 * i] * 4) + 4 * Math.floor(p[2 * i + 1] * 4));
check(cells.size === 16, `stratified 16 fills ${cells.size} of 16 strata`);
const other = samplePoints("sobol", 16, 7n, 2);
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
  refused(() => samplePoints(kind, n, 1n, dims), reason, `samplePoints(${kind}, ${n}, ${dims})`);
}
refused(() => goldenValue("no such scene", "sobol"), /not a row/, "an unknown scene");
refused(() => goldenValue("examples/scenes/materials.toml", "file.png"), /not a row/, "a pair outside the table");
check(/^\d+\.\d+\.\d+\+r\d+$/.test(outputVersion()), `output version ${outputVersion()}`);

console.log(failed === 0 ? "web: all checks passed" : `web: ${failed} checks failed`);
exit(failed === 0 ? 0 : 1);
