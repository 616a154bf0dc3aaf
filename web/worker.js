// The page's worker: instantiates the WebAssembly module the page
// compiled (first message: {type: "init", module}) and answers the page's
// requests one at a time, so renders never block the page.
//
// Request: {id, op, args}. Reply: {id, ok: true, result, ms} or
// {id, ok: false, trap, error}. After init: {type: "ready", version} or
// {type: "failed", error}.

let wasm = null;
let loaded = null;

// Each op returns [result, transferable buffers].
const ops = {
  rows: () => [wasm.goldenRows(), []],
  golden: (scene, key) => [wasm.goldenValue(scene, key), []],
  points: (kind, n, seed, dims) => {
    const p = wasm.samplePoints(kind, n, seed, dims);
    return [p, [p.buffer]];
  },
  periodogram: (kind, n, seed, dimX, dimY, pixels, r) => {
    const s = wasm.periodogram(kind, n, seed, dimX, dimY, pixels, r);
    const out = { r: s.r, power: s.power(), radial: s.radial() };
    s.free();
    return [out, [out.power.buffer, out.radial.buffer]];
  },
  render: (s) => {
    const f = wasm.render(s.scene, s.sampler, s.filter, s.adaptive, s.textureBox, s.width, s.height, s.spp, s.seed);
    const out = {
      width: f.width, height: f.height, samples: f.samples,
      rgba: f.rgba(), heat: f.heat(), linear: f.linear(),
    };
    f.free();
    return [out, [out.rgba.buffer, out.heat.buffer, out.linear.buffer]];
  },
  rmse: (a, b) => [wasm.rmse(a, b), []],
};

self.onmessage = async (e) => {
  if (e.data.type === "init") {
    // The page's compiled module (it chose simd128 or plain); the glue is
    // the same for both builds.
    loaded = import("./strata_web.js").then(async (m) => {
      await m.default({ module_or_path: e.data.module });
      wasm = m;
      self.postMessage({ type: "ready", version: m.outputVersion() });
    });
    loaded.catch((err) => self.postMessage({ type: "failed", error: String(err && err.message ? err.message : err) }));
    return;
  }
  const { id, op, args } = e.data;
  try {
    await loaded;
    if (!(op in ops)) throw new Error(`no operation ${op}`);
    const t0 = performance.now();
    const [result, transfer] = ops[op](...args);
    self.postMessage({ id, ok: true, result, ms: performance.now() - t0 }, transfer);
  } catch (err) {
    // A trap (a Rust panic) or a stack overflow (V8: a RangeError) may
    // leave the instance broken: the page then starts a new worker. The
    // module's own refusals are plain Errors.
    const trap = err instanceof WebAssembly.RuntimeError || err instanceof RangeError;
    self.postMessage({ id, ok: false, trap, error: String(err && err.message ? err.message : err) });
  }
};
