#!/usr/bin/env -S node --no-warnings
// Runs a wasm32-wasip1 program (a test binary built by cargo) under Node's
// WASI: `node .ci/wasi-run.mjs prog.wasm [args...]`. Used as cargo's runner
// for that target, so `cargo test --target wasm32-wasip1` runs the tests.
// A panic aborts the module (an `unreachable` trap): Node then exits
// non-zero, which is the failure cargo sees.
import { readFile } from "node:fs/promises";
import { argv, env, exit } from "node:process";
import { WASI } from "node:wasi";

const [program, ...args] = argv.slice(2);
const wasi = new WASI({
  version: "preview1",
  args: [program, ...args],
  env,
  returnOnExit: true,
});
const module = await WebAssembly.compile(await readFile(program));
// getImportObject() is Node 19.8+/18.17+; wasiImport is the older spelling.
const imports = wasi.getImportObject?.() ?? { wasi_snapshot_preview1: wasi.wasiImport };
const instance = await WebAssembly.instantiate(module, imports);
exit(wasi.start(instance));
