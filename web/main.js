// The page: loads Strata's WebAssembly module once, hands it to four
// workers (patterns and the golden check; aliasing; the live passes; the
// live panel's reference) and draws what they return. All numbers come
// from the module; this file only draws them.

// A tiny module using SIMD instructions (i8x16.splat, i8x16.popcnt):
// valid only where the browser has WebAssembly SIMD.
const SIMD_PROBE = new Uint8Array([
  0, 97, 115, 109, 1, 0, 0, 0, 1, 5, 1, 96, 0, 1, 123, 3, 2, 1, 0, 10, 10, 1, 8, 0, 65, 0, 253, 15, 253, 98, 11,
]);
// `?simd=0` asks for the plain module where the browser has SIMD too.
const SIMD = new URLSearchParams(location.search).get("simd") !== "0" && WebAssembly.validate(SIMD_PROBE);

const KINDS = ["independent", "grid", "stratified", "sobol", "halton", "zsobol"];
const FILTERS = ["box", "tent", "gaussian", "mitchell", "lanczos"];
const $ = (id) => document.getElementById(id);

// Viridis at nine stops: index colours and plot lines.
const VIRIDIS = ["#440154", "#472d7b", "#3b528b", "#2c728e", "#21918c", "#28ae80", "#5ec962", "#addc30", "#fde725"]
  .map((h) => [1, 3, 5].map((i) => parseInt(h.slice(i, i + 2), 16)));
function viridis(t) {
  const x = Math.min(Math.max(t, 0), 1) * (VIRIDIS.length - 1);
  const i = Math.min(Math.floor(x), VIRIDIS.length - 2);
  const f = x - i;
  const c = VIRIDIS[i].map((v, k) => Math.round(v + f * (VIRIDIS[i + 1][k] - v)));
  return `rgb(${c[0]},${c[1]},${c[2]})`;
}

function fail(what, e) {
  const m = $("module");
  m.dataset.state = "failed";
  m.textContent = `${what}: ${e.message || e}`;
  console.error(what, e);
}

// The module: fetched once, gzip-compressed (the download the page's
// budget counts), compiled once, shared with every worker.
async function loadModule() {
  const file = SIMD ? "strata_web_simd128.wasm.gz" : "strata_web.wasm.gz";
  const res = await fetch(file);
  if (!res.ok) throw new Error(`${file}: HTTP ${res.status}`);
  const got = new Uint8Array(await res.arrayBuffer());
  let bytes = got;
  // A server that sends .gz files with Content-Encoding: gzip has the
  // browser inflate them already: then the bytes are the module itself.
  if (got[0] === 0x1f && got[1] === 0x8b) {
    if (typeof DecompressionStream === "undefined") {
      throw new Error("this browser lacks DecompressionStream (Chrome 80, Firefox 113, Safari 16.4 have it)");
    }
    const inflated = new Blob([got]).stream().pipeThrough(new DecompressionStream("gzip"));
    bytes = new Uint8Array(await new Response(inflated).arrayBuffer());
  } else if (!(got[0] === 0 && got[1] === 0x61 && got[2] === 0x73 && got[3] === 0x6d)) {
    throw new Error(`${file} is neither gzip nor WebAssembly`);
  }
  const packed = Number(res.headers.get("content-length")) || got.byteLength;
  return { module: await WebAssembly.compile(bytes), file, packed, size: bytes.byteLength };
}

// A request a restart dropped: its caller has moved on.
class Cancelled extends Error {}

// A worker and its pending requests; `call` resolves to {result, ms}.
// `restart()` drops what it is doing (a new instance of the module in a
// new worker; the compiled module is shared); so does a worker that
// failed or trapped, for the requests after it.
function startWorker(module) {
  let w = null;
  let pending = new Map();
  let next = 0;
  let ready = null;
  let restarts = 0;
  const dropAll = (error) => {
    for (const p of pending.values()) p.reject(error);
    pending = new Map();
  };
  const spawn = () => {
    w = new Worker("worker.js", { type: "module" });
    ready = new Promise((resolve, reject) => {
      w.onmessage = (e) => {
        const m = e.data;
        if (m.type === "ready") return resolve(m);
        if (m.type === "failed") return reject(new Error(m.error));
        const p = pending.get(m.id);
        if (!p) return;
        pending.delete(m.id);
        if (m.ok) p.resolve(m);
        else p.reject(new Error(m.error));
        // A trap may leave the instance broken: the requests behind it
        // fail (they are not cancelled: their callers say so), the next
        // ones get a fresh instance.
        if (m.trap) restart(new Error(`the module trapped before this request: ${m.error}`));
      };
      // A worker that died answers nothing more: fail what waits, start
      // another for what follows.
      const broken = (what) => (e) => {
        const error = new Error(`${what}: ${e.message || "the worker failed"}`);
        reject(error);
        restart(error);
      };
      w.onerror = broken("worker error");
      w.onmessageerror = broken("worker message error");
    });
    ready.catch(() => {});
    w.postMessage({ type: "init", module });
  };
  // Drops what the worker does: its requests fail with `why` (by default
  // as cancelled, which callers ignore).
  const restart = (why = new Cancelled("cancelled")) => {
    restarts += 1;
    w.terminate();
    dropAll(why);
    spawn();
  };
  spawn();
  return {
    get ready() {
      return ready;
    },
    get busy() {
      return pending.size > 0;
    },
    get restarts() {
      return restarts;
    },
    restart,
    call(op, ...args) {
      return new Promise((resolve, reject) => {
        const id = next++;
        pending.set(id, { resolve, reject });
        w.postMessage({ id, op, args });
      });
    },
  };
}

function fillSelect(select, names, chosen) {
  for (const n of names) {
    const o = document.createElement("option");
    o.textContent = n;
    o.selected = n === chosen;
    select.append(o);
  }
}

function putImage(canvas, width, height, rgba) {
  canvas.width = width;
  canvas.height = height;
  canvas.getContext("2d").putImageData(new ImageData(new Uint8ClampedArray(rgba.buffer), width, height), 0, 0);
}

// ---- 1. Sample patterns ------------------------------------------------

const SPECTRUM_R = 40;
let patternGen = 0;

async function updatePatterns(quick) {
  const gen = ++patternGen;
  const kind = $("p-sampler").value;
  const n = 2 ** Number($("p-count").value);
  const dx = Number($("p-dx").value);
  const dy = Number($("p-dy").value);
  // A whole number the input box allows (u64 in the module; kept small).
  const seed = Math.min(1e6, Math.max(0, Math.floor(Number($("p-seed").value) || 0)));
  $("p-count-out").textContent = n;
  $("p-n").textContent = n;
  if (dx === dy) {
    $("p-pixels").textContent = "–";
    for (const id of ["points", "spectrum", "radial"]) {
      const c = $(id);
      const g = c.getContext("2d");
      g.fillStyle = "#fff";
      g.fillRect(0, 0, c.width, c.height);
    }
    const g = $("points").getContext("2d");
    g.fillStyle = "#333";
    g.font = "14px system-ui, sans-serif";
    g.fillText("Pick two different dimensions.", 20, 30);
    $("patterns").dataset.drawn = `none ${dx} ${dy}`;
    return;
  }
  // About 16k samples in all: a steady average at any count.
  const pixels = Math.min(1024, Math.max(8, Math.round(16384 / n)));
  $("p-pixels").textContent = pixels;
  const [pts, spec] = await Promise.all([
    quick.call("points", kind, n, seed, Math.max(dx, dy) + 1),
    quick.call("periodogram", kind, n, seed, dx, dy, pixels, SPECTRUM_R),
  ]);
  if (gen !== patternGen) return;
  drawSpectrum(spec.result);
  drawRadial(spec.result, n);
  await drawPoints(pts.result, Math.max(dx, dy) + 1, dx, dy, gen);
  if (gen === patternGen) $("patterns").dataset.drawn = `${kind} ${n} ${dx} ${dy} ${seed}`;
}

// Draws the points in order over about half a second, so the order shows.
function drawPoints(p, dims, dx, dy, gen) {
  const c = $("points");
  const g = c.getContext("2d");
  const s = c.width;
  g.fillStyle = "#fff";
  g.fillRect(0, 0, s, s);
  g.strokeStyle = "#ddd";
  g.strokeRect(0.5, 0.5, s - 1, s - 1);
  const n = p.length / dims;
  const radius = n > 256 ? 2 : 3.5;
  const per = Math.max(1, Math.ceil(n / 30));
  let i = 0;
  return new Promise((done) => {
    const step = () => {
      if (gen !== patternGen) return done();
      for (const end = Math.min(n, i + per); i < end; i++) {
        g.fillStyle = viridis(n > 1 ? i / (n - 1) : 0.5);
        g.beginPath();
        // y up, as in the lecture's plots.
        g.arc(p[i * dims + dx] * s, (1 - p[i * dims + dy]) * s, radius, 0, 2 * Math.PI);
        g.fill();
      }
      if (i < n) requestAnimationFrame(step);
      else done();
    };
    step();
  });
}

function drawSpectrum(spec) {
  const side = 2 * spec.r + 1;
  const img = new Uint8ClampedArray(side * side * 4);
  for (let k = 0; k < side * side; k++) {
    // The runner's scale: P / 2, so white noise is mid-grey. Rows top to
    // bottom are ω_y from r down to −r (y up).
    const row = side - 1 - Math.floor(k / side);
    const v = Math.round(Math.min(1, spec.power[row * side + (k % side)] / 2) * 255);
    img.set([v, v, v, 255], k * 4);
  }
  const c = $("spectrum");
  const g = c.getContext("2d");
  const tmp = new OffscreenCanvas(side, side);
  tmp.getContext("2d").putImageData(new ImageData(img, side, side), 0, 0);
  g.imageSmoothingEnabled = false;
  g.drawImage(tmp, 0, 0, c.width, c.height);
}

// A plot frame: maps data to the canvas and draws axes with labels.
function axes(c, x0, x1, y0, y1, { logX = false, logY = false, xLabel, yLabel }) {
  const g = c.getContext("2d");
  const L = 52, R = 12, T = 12, B = 38;
  const w = c.width - L - R, h = c.height - T - B;
  const fx = (x) => L + (logX ? Math.log(x / x0) / Math.log(x1 / x0) : (x - x0) / (x1 - x0)) * w;
  const fy = (y) => T + h - (logY ? Math.log(y / y0) / Math.log(y1 / y0) : (y - y0) / (y1 - y0)) * h;
  g.fillStyle = "#fff";
  g.fillRect(0, 0, c.width, c.height);
  g.strokeStyle = "#888";
  g.strokeRect(L, T, w, h);
  g.fillStyle = "#333";
  g.font = "11px system-ui, sans-serif";
  const ticks = (a, b, log) => {
    if (!log) {
      const step = 10 ** Math.floor(Math.log10((b - a) / 4));
      const k = [1, 2, 5, 10].find((m) => (b - a) / (m * step) <= 6) * step;
      const out = [];
      for (let t = Math.ceil(a / k) * k; t <= b + 1e-9; t += k) out.push(+t.toPrecision(6));
      return out;
    }
    const out = [];
    for (let e = Math.floor(Math.log10(a)); e <= Math.ceil(Math.log10(b)); e++) {
      for (const m of [1, 2, 5]) {
        const t = m * 10 ** e;
        if (t >= a * 0.999 && t <= b * 1.001) out.push(t);
      }
    }
    return out;
  };
  g.textAlign = "center";
  for (const t of ticks(x0, x1, logX)) g.fillText(String(t), fx(t), T + h + 14);
  g.textAlign = "right";
  for (const t of ticks(y0, y1, logY)) g.fillText(logY ? t.toExponential(0) : String(t), L - 4, fy(t) + 4);
  g.textAlign = "center";
  g.fillText(xLabel, L + w / 2, c.height - 6);
  g.save();
  g.translate(12, T + h / 2);
  g.rotate(-Math.PI / 2);
  g.fillText(yLabel, 0, 0);
  g.restore();
  return { g, fx, fy, L, T, w, h };
}

function drawRadial(spec, n) {
  const r = spec.radial;
  const top = Math.max(2, ...r) * 1.05;
  const { g, fx, fy } = axes($("radial"), 0, spec.r, 0, top, { xLabel: "frequency |ω|", yLabel: "power" });
  g.setLineDash([5, 4]);
  g.strokeStyle = "#999";
  g.beginPath();
  g.moveTo(fx(0), fy(1));
  g.lineTo(fx(spec.r), fy(1));
  g.stroke();
  if (Math.sqrt(n) <= spec.r) {
    g.setLineDash([1, 3]);
    g.beginPath();
    g.moveTo(fx(Math.sqrt(n)), fy(0));
    g.lineTo(fx(Math.sqrt(n)), fy(top));
    g.stroke();
  }
  g.setLineDash([]);
  g.strokeStyle = viridis(0.25);
  g.lineWidth = 1.5;
  g.beginPath();
  r.forEach((v, i) => (i ? g.lineTo(fx(i + 1), fy(v)) : g.moveTo(fx(i + 1), fy(v))));
  g.stroke();
  g.lineWidth = 1;
}

// ---- 2. Aliasing against noise ------------------------------------------

let aliasGen = 0;

async function updateAliasing(render) {
  const gen = ++aliasGen;
  const spp = Number($("a-spp").value);
  for (const [id, sampler, textureBox] of [
    ["a-grid", "grid", false],
    ["a-jitter", "stratified", false],
    ["a-prefilter", "grid", true],
  ]) {
    const f = await render.call("render", {
      scene: "horizon", sampler, filter: "box", adaptive: false, textureBox, width: 256, height: 144, spp, seed: 1,
    });
    if (gen !== aliasGen) return;
    putImage($(id), f.result.width, f.result.height, f.result.rgba);
  }
  $("aliasing").dataset.drawn = String(spp);
}

// ---- 3. Live render -----------------------------------------------------

const LIVE = { width: 160, height: 90, seed: 1 };
// The reference: rendered in its own worker, while the passes render.
const REFERENCE = { sampler: "sobol", spp: 1024, seed: 1000003 };
// Finished references by scene; the one in flight, if any.
const references = new Map();
let referenceInFlight = null;
let liveGen = 0;

// The reference of `scene`: the finished one, the one in flight, or a new
// one (a reference of another scene in flight is dropped first).
function reference(refWorker, scene) {
  if (references.has(scene)) return Promise.resolve(references.get(scene));
  if (referenceInFlight?.scene === scene) return referenceInFlight.promise;
  if (refWorker.busy) refWorker.restart();
  const promise = refWorker.call("render", {
    scene, sampler: REFERENCE.sampler, filter: "box", adaptive: false, textureBox: false,
    width: LIVE.width, height: LIVE.height, spp: REFERENCE.spp, seed: REFERENCE.seed,
  }).then((m) => {
    const r = { linear: m.result.linear, ms: m.ms };
    references.set(scene, r);
    return r;
  }).finally(() => {
    if (referenceInFlight?.promise === promise) referenceInFlight = null;
  });
  referenceInFlight = { scene, promise };
  return promise;
}

function sideSettings(id) {
  const el = $(id);
  return {
    el,
    sampler: el.querySelector(".l-sampler").value,
    filter: el.querySelector(".l-filter").value,
    adaptive: el.querySelector(".l-adaptive").checked,
  };
}

function clear(canvas) {
  const g = canvas.getContext("2d");
  g.fillStyle = "#f4f4f4";
  g.fillRect(0, 0, canvas.width, canvas.height);
}

async function updateLive(render, quick, refWorker, gen) {
  const scene = $("l-scene").value;
  const max = Number($("l-max").value);
  const sides = [sideSettings("side-a"), sideSettings("side-b")];
  const curves = [[], []];
  const pixels = LIVE.width * LIVE.height;
  const run = `${scene} ${max} ${sides.map((s) => `${s.sampler} ${s.filter} ${s.adaptive}`).join(" ")}`;
  $("live").dataset.passes = "0";
  $("live").dataset.run = "";
  for (const s of sides) {
    for (const c of s.el.querySelectorAll("canvas")) clear(c);
    s.el.querySelector(".l-status").textContent = "rendering…";
  }
  let ref = null;
  const caption = (state) => {
    $("error-caption").textContent = `RMSE (linear RGB) against a reference of ${scene}: ${REFERENCE.sampler}, ` +
      `${REFERENCE.spp} samples per pixel, box filter, ${LIVE.width}×${LIVE.height}, seed ${REFERENCE.seed}, ` +
      `rendered in this page's worker (not downloaded) — ${state}. Its own noise sets a floor under both ` +
      "curves; a side with another filter levels off at that filter's blur too. The dashed line falls as " +
      "1/√N, Monte Carlo's rate.";
  };
  caption("rendering");
  const plot = async () => {
    if (!ref || gen !== liveGen) return;
    for (const c of curves) {
      for (const p of c) if (p.rmse === undefined) p.rmse = (await quick.call("rmse", p.linear, ref.linear)).result;
    }
    if (gen === liveGen) drawError(curves, sides, max);
  };
  reference(refWorker, scene).then((r) => {
    if (gen !== liveGen) return;
    ref = r;
    caption(`${(r.ms / 1000).toFixed(1)} s`);
    return plot();
  }).catch((e) => {
    if (!(e instanceof Cancelled) && gen === liveGen) fail("reference", e);
  });
  drawError(curves, sides, max);
  let passes = 0;
  for (let spp = 1; spp <= max; spp *= 2) {
    for (const [k, s] of sides.entries()) {
      // A newer run owns the panel (it restarted the worker only if a
      // pass was in flight).
      if (gen !== liveGen) return;
      const status = s.el.querySelector(".l-status");
      // Adaptive sampling needs a pilot of at least 8 samples.
      if (s.adaptive && spp < 8) {
        status.textContent = "adaptive: passes from 8 samples per pixel";
        continue;
      }
      const f = await render.call("render", {
        scene, sampler: s.sampler, filter: s.filter, adaptive: s.adaptive, textureBox: false,
        width: LIVE.width, height: LIVE.height, spp, seed: LIVE.seed,
      });
      if (gen !== liveGen) return;
      const r = f.result;
      putImage(s.el.querySelector(".l-image"), r.width, r.height, r.rgba);
      putImage(s.el.querySelector(".l-heat"), r.width, r.height, r.heat);
      const taken = r.samples / pixels;
      status.textContent = `${s.adaptive ? `up to ${spp}` : spp} samples per pixel, ${taken.toFixed(1)} taken on ` +
        `average; ${(f.ms / 1000).toFixed(2)} s, ${(r.samples / f.ms / 1000).toFixed(2)} M samples/s`;
      curves[k].push({ spp: taken, linear: r.linear });
      passes += 1;
      await plot();
    }
  }
  if (gen === liveGen) {
    $("live").dataset.passes = String(passes);
    $("live").dataset.run = run;
  }
}

function drawError(curves, sides, max) {
  const pts = curves.flat().filter((p) => p.rmse > 0);
  const lo = pts.length ? Math.min(...pts.map((p) => p.rmse)) / 1.5 : 1e-3;
  const hi = pts.length ? Math.max(...pts.map((p) => p.rmse)) * 1.5 : 1;
  const { g, fx, fy } = axes($("error"), 1, max, lo, hi,
    { logX: true, logY: true, xLabel: "samples per pixel (taken)", yLabel: "RMSE" });
  $("live").dataset.plotted = String(pts.length);
  if (pts.length) {
    // N^−½ through the first point.
    const p0 = pts[0];
    g.setLineDash([5, 4]);
    g.strokeStyle = "#999";
    g.beginPath();
    g.moveTo(fx(1), fy(p0.rmse * Math.sqrt(p0.spp)));
    g.lineTo(fx(max), fy(p0.rmse * Math.sqrt(p0.spp / max)));
    g.stroke();
    g.setLineDash([]);
  }
  ["#1f5fbf", "#d9730d"].forEach((colour, k) => {
    const c = curves[k].filter((p) => p.rmse > 0);
    g.strokeStyle = g.fillStyle = colour;
    g.lineWidth = 1.5;
    g.beginPath();
    c.forEach((p, i) => (i ? g.lineTo(fx(p.spp), fy(p.rmse)) : g.moveTo(fx(p.spp), fy(p.rmse))));
    g.stroke();
    for (const p of c) g.fillRect(fx(p.spp) - 2, fy(p.rmse) - 2, 4, 4);
    const s = sides[k];
    g.fillText(`${"AB"[k]}: ${s.sampler}, ${s.filter}${s.adaptive ? ", adaptive" : ""}`, 130, 26 + 14 * k);
  });
  g.lineWidth = 1;
}

// ---- 4. Same bits -------------------------------------------------------

async function runGolden(quick, rows) {
  const [scene, key] = $("g-row").value.split(" ");
  const want = rows.get(`${scene} ${key}`);
  $("g-got").textContent = "rendering…";
  $("g-want").textContent = want;
  $("g-match").dataset.state = "pending";
  const m = await quick.call("golden", scene, key);
  if (`${scene} ${key}` !== $("g-row").value) return;
  $("g-got").textContent = m.result;
  const same = m.result === want;
  $("g-match").dataset.state = same ? "same" : "different";
  $("g-match").textContent = same ? `yes, bit for bit (${m.ms.toFixed(0)} ms)` : "NO: this browser differs from the table";
}

// ---- start --------------------------------------------------------------

async function main() {
  const { module, file, packed, size } = await loadModule();
  // Patterns and the golden check; aliasing; the live passes; the
  // reference: each panel waits only for its own work.
  const [quick, alias, render, refWorker] = [0, 1, 2, 3].map(() => startWorker(module));
  const info = await quick.ready;
  await Promise.all([alias.ready, render.ready, refWorker.ready]);
  // The workers, for the browser test's speed report and the console:
  // `await strata.render.call("render", {...})`.
  window.strata = { quick, alias, render, reference: refWorker };
  const m = $("module");
  m.dataset.state = "ready";
  m.dataset.simd = String(SIMD);
  m.textContent = `Module: ${SIMD ? "WebAssembly SIMD (simd128)" : "plain WebAssembly (no SIMD)"}, ${file} ` +
    `(${(packed / 1e6).toFixed(2)} MB compressed, ${(size / 1e6).toFixed(2)} MB), output ${info.version}.`;
  const ignoreCancelled = (what) => (e) => e instanceof Cancelled || fail(what, e);

  fillSelect($("p-sampler"), KINDS, "stratified");
  const dims = Array.from({ length: 16 }, (_, i) => String(i));
  fillSelect($("p-dx"), dims, "0");
  fillSelect($("p-dy"), dims, "1");
  const patterns = () => updatePatterns(quick).catch(ignoreCancelled("sample patterns"));
  for (const id of ["p-sampler", "p-count", "p-dx", "p-dy", "p-seed"]) $(id).addEventListener("input", patterns);

  const aliasing = () => updateAliasing(alias).catch(ignoreCancelled("aliasing"));
  $("a-spp").addEventListener("input", aliasing);

  for (const [id, sampler] of [["side-a", "independent"], ["side-b", "zsobol"]]) {
    const el = $(id);
    fillSelect(el.querySelector(".l-sampler"), KINDS, sampler);
    fillSelect(el.querySelector(".l-filter"), FILTERS, "box");
    el.querySelector(".l-adaptive").checked = false;
  }
  // A change stops the running live run at once (its worker restarts)
  // and starts the new one.
  const live = () => {
    const gen = ++liveGen;
    if (render.busy) render.restart();
    updateLive(render, quick, refWorker, gen).catch((e) => {
      if (!(e instanceof Cancelled) && gen === liveGen) fail("live render", e);
    });
  };
  for (const el of document.querySelectorAll("#live select, #live input")) el.addEventListener("input", live);

  const rows = new Map((await quick.call("rows")).result.trim().split("\n").map((l) => {
    const [scene, key, hash] = l.split(" ");
    return [`${scene} ${key}`, hash];
  }));
  fillSelect($("g-row"), [...rows.keys()], "week09 sobol");
  const golden = () => runGolden(quick, rows).catch(ignoreCancelled("golden check"));
  $("g-run").addEventListener("click", golden);
  $("g-row").addEventListener("input", golden);

  golden();
  patterns();
  aliasing();
  live();
}

// Side B: a copy of side A's controls and canvases, before anything draws.
const sideB = $("side-a").cloneNode(true);
sideB.id = "side-b";
sideB.querySelector("h3").textContent = "B";
$("side-a").after(sideB);

main().catch((e) => fail("loading Strata's module", e));
