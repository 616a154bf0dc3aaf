//! `strata._strata`: the native module of the `strata` Python package.
//!
//! Every call takes and returns whole numpy arrays and releases the GIL
//! while it works. The Python layer (`python/strata/`) turns the caller's
//! arrays into the exact dtypes and shapes these functions take; this
//! module checks what it is given again (sizes, finite values, names)
//! through the runner's shared batch checks
//! ([`strata_runner::batch`]), whose messages become `ValueError`s.
//! Values are the Rust core's, bit for bit.

use std::ops::Range;
use std::sync::atomic::{AtomicBool, AtomicU64, Ordering};
use std::time::{Duration, Instant};

use numpy::{
    PyArray1, PyArray2, PyArray3, PyArrayMethods, PyReadonlyArray1, PyReadonlyArray2,
    PyReadwriteArray2, PyUntypedArrayMethods,
};
use pyo3::exceptions::{PyMemoryError, PyRuntimeError, PyValueError};
use pyo3::prelude::*;
use strata::Sampler as _;
use strata::glam::UVec2;
use strata::render::PixelSum;
use strata::sampler::draw_row;
use strata::trace::{BvhStack, OwnedBvh, simd_level};
use strata_runner::batch::{
    AnySampler, Basis, BatchError, MapOp, Mapping, RayParts, map_rows, onb_rows, query_rays,
    spheres_from_rows,
};
use strata_runner::cli::library_render;
use strata_runner::golden;
use strata_runner::job::{Job, Outcome, Rendered, Resume, SamplerKind, run_resumable, tile_side};

/// A refusal of the shared checks as a `ValueError`.
fn value_error(e: impl std::fmt::Display) -> PyErr {
    PyValueError::new_err(e.to_string())
}

/// A vector of `n` zeros, or a `MemoryError` (not an abort) when the
/// allocation fails.
fn zeros<T: Clone + Default>(n: usize, what: &str) -> PyResult<Vec<T>> {
    let mut v = Vec::new();
    v.try_reserve_exact(n)
        .map_err(|_| PyMemoryError::new_err(format!("{what}: cannot allocate {n} values")))?;
    v.resize(n, T::default());
    Ok(v)
}

/// `a · b`, or a `ValueError` for sizes past `usize`.
fn times(a: usize, b: usize, what: &str) -> PyResult<usize> {
    strata_runner::batch::times(a, b, what).map_err(value_error)
}

/// The contiguous values of an array (the Python layer makes them so).
fn slice<'a, T: numpy::Element, D: numpy::ndarray::Dimension>(
    a: &'a numpy::PyReadonlyArray<'_, T, D>,
    what: &str,
) -> PyResult<&'a [T]> {
    a.as_slice()
        .map_err(|_| value_error(format!("{what} is not a contiguous array")))
}

/// A `(rows, cols)` array from a vector of `rows · cols` values.
fn matrix<'py, T: numpy::Element>(
    py: Python<'py>,
    v: Vec<T>,
    rows: usize,
    cols: usize,
) -> PyResult<Bound<'py, PyArray2<T>>> {
    PyArray1::from_vec(py, v).reshape([rows, cols])
}

// ------------------------------------------------------------ build facts

/// The SIMD level the module was compiled for: `"sse2"` for the portable
/// x86-64 build the package makes; every level gives the same values.
#[pyfunction]
fn simd() -> &'static str {
    simd_level().name()
}

/// The output revision: it changes whenever a seeded render's pixels do.
#[pyfunction]
fn output_revision() -> u32 {
    strata::render::OUTPUT_REVISION
}

/// The sampler kinds' names, in the C API's numbering.
#[pyfunction]
fn sampler_kinds() -> Vec<&'static str> {
    SamplerKind::ALL.iter().map(|k| k.name()).collect()
}

/// The mappings' names, in the C API's numbering.
#[pyfunction]
fn mapping_names() -> Vec<&'static str> {
    Mapping::ALL.iter().map(|m| m.name()).collect()
}

/// The sampler kind named `name`.
fn sampler_kind(name: &str) -> PyResult<SamplerKind> {
    SamplerKind::from_name(name).map_err(value_error)
}

/// `(values per sample, values per point)` of the mapping `name`.
#[pyfunction]
fn mapping_arity(name: &str) -> PyResult<(usize, usize)> {
    Ok(Mapping::from_name(name).map_err(value_error)?.arity())
}

// ------------------------------------------------------------ samplers

/// A pixel sampler of one kind, spp and seed (and, for `zsobol`, image
/// resolution).
#[pyclass(module = "strata._strata")]
struct Sampler {
    inner: AnySampler,
}

#[pymethods]
impl Sampler {
    #[new]
    fn new(kind: &str, spp: u32, seed: u64, width: u32, height: u32) -> PyResult<Self> {
        let kind = sampler_kind(kind)?;
        let inner =
            AnySampler::new(kind, spp, seed, UVec2::new(width, height)).map_err(value_error)?;
        Ok(Sampler { inner })
    }

    /// Samples per pixel, as built.
    #[getter]
    fn spp(&self) -> u32 {
        self.inner.samples_per_pixel()
    }

    /// The first `dims` dimensions of pixel samples `(pixels[i], indices[i])`
    /// into the rows of `out`, a C-contiguous `(n, dims)` float32 array.
    fn fill_into(
        &mut self,
        py: Python<'_>,
        pixels: PyReadonlyArray2<'_, u32>,
        indices: PyReadonlyArray1<'_, u32>,
        mut out: PyReadwriteArray2<'_, f32>,
    ) -> PyResult<()> {
        let (p, i) = (slice(&pixels, "pixels")?, slice(&indices, "indices")?);
        let [n, dims] = [out.shape()[0], out.shape()[1]];
        if i.len() != n || p.len() != times(n, 2, "pixels")? {
            return Err(value_error(format!(
                "{} pixel values and {} indices for {n} rows (x, y and an index each)",
                p.len(),
                i.len()
            )));
        }
        let out = out
            .as_slice_mut()
            .map_err(|_| value_error("out is not a C-contiguous array"))?;
        let inner = &mut self.inner;
        py.detach(|| {
            by_chunks(out, dims, |row, rows, chunk| {
                inner.fill(
                    &p[2 * row..2 * (row + rows)],
                    &i[row..row + rows],
                    dims,
                    chunk,
                )
            })
        })
    }

    /// Samples `first, first + 1, …` of pixel `(x, y)` into the rows of
    /// `out`, a C-contiguous `(n, dims)` float64 array the caller made
    /// (numpy's own allocation: large arrays get huge pages, so the
    /// first write costs less); the values are float32's, exactly.
    fn run_into(
        &mut self,
        py: Python<'_>,
        x: u32,
        y: u32,
        first: u32,
        mut out: PyReadwriteArray2<'_, f64>,
    ) -> PyResult<()> {
        let [n, dims] = [out.shape()[0], out.shape()[1]];
        if u64::from(first) + n as u64 > 1 << 32 {
            return Err(value_error(format!(
                "{n} samples from index {first} pass the last index, {}",
                u32::MAX
            )));
        }
        let out = out
            .as_slice_mut()
            .map_err(|_| value_error("out is not a C-contiguous array"))?;
        let inner = &mut self.inner;
        py.detach(|| {
            by_chunks(out, dims, |row, _, chunk| {
                // Within u32: the run's end is checked above.
                inner.fill_pixel(UVec2::new(x, y), first + row as u32, dims, chunk)
            })
        })
    }
}

/// Rows the size of the L1 cache's share: values are made into a small
/// scratch block and appended, so the output is written once (not
/// zeroed first) and every value arrives as `T`.
const CHUNK_VALUES: usize = 4096;

/// Fills `out` (whole rows of `dims` values) a chunk of rows at a time
/// by `make(first row, rows, scratch)`, each chunk converted to `T` as it
/// is copied in.
fn by_chunks<T: From<f32>>(
    out: &mut [T],
    dims: usize,
    mut make: impl FnMut(usize, usize, &mut [f32]) -> Result<(), BatchError>,
) -> PyResult<()> {
    if dims == 0 {
        return Ok(());
    }
    // Whole groups of 8 rows (Sobol' makes eight samples at once).
    let per = (CHUNK_VALUES / dims).max(1).next_multiple_of(8);
    let mut scratch = vec![0.0f32; per * dims];
    for (k, rows_out) in out.chunks_mut(per * dims).enumerate() {
        let rows = rows_out.len() / dims;
        let chunk = &mut scratch[..rows * dims];
        make(k * per, rows, chunk).map_err(value_error)?;
        for (o, &v) in rows_out.iter_mut().zip(chunk.iter()) {
            *o = T::from(v);
        }
    }
    Ok(())
}

/// The same values as [`Sampler::run_into`] drawn through the core's public
/// per-sample API into a vector (`start_pixel_sample`, `pixel_2d`,
/// `next_2d` pairs, `next_1d` for an odd last), timed in Rust: the
/// benchmark's reference. Returns the seconds and the values' checksum
/// (the sum of their bits, which the batch's must equal).
#[pyfunction]
fn per_sample_reference(
    py: Python<'_>,
    kind: &str,
    spp: u32,
    seed: u64,
    n: u32,
    dims: usize,
) -> PyResult<(f64, u64)> {
    let kind = sampler_kind(kind)?;
    let mut s = AnySampler::new(kind, spp, seed, UVec2::ONE).map_err(value_error)?;
    let total = times(n as usize, dims, "the samples")?;
    py.detach(|| {
        let start = Instant::now();
        // Into a new vector, as a caller's own loop would (the batch call
        // also makes its output).
        let mut out: Vec<f64> = Vec::new();
        if out.try_reserve_exact(total).is_err() {
            return Err(PyMemoryError::new_err(format!(
                "cannot allocate {total} values"
            )));
        }
        strata_runner::with_any_sampler!(&mut s, s => {
            let mut row = vec![0.0f64; dims];
            for i in 0..n {
                s.start_pixel_sample(UVec2::ZERO, i);
                // pixel_2d, next_2d pairs, a last next_1d: the core's order.
                draw_row(s, &mut row);
                out.extend_from_slice(&row);
            }
        });
        let seconds = start.elapsed().as_secs_f64();
        let sum = out.iter().fold(0u64, |a, v| a.wrapping_add(v.to_bits()));
        Ok((seconds, sum))
    })
}

// ------------------------------------------------------------ mappings and bases

/// One operation (`"sample"`, `"pdf"`, `"invert"`) of the mapping `name`
/// over the rows of `values`.
#[pyfunction]
fn map<'py>(
    py: Python<'py>,
    op: &str,
    name: &str,
    cone: f32,
    values: PyReadonlyArray2<'py, f32>,
) -> PyResult<Bound<'py, PyArray2<f32>>> {
    let op = MapOp::from_name(op).map_err(value_error)?;
    let m = Mapping::from_name(name).map_err(value_error)?;
    let v = slice(&values, "the input")?;
    let (in_dims, out_dims) = op.arity(m);
    if values.shape()[1] != in_dims {
        return Err(value_error(format!(
            "{name} {op:?}: rows of {in_dims} values, not {}",
            values.shape()[1]
        )));
    }
    let n = values.shape()[0];
    let mut out = zeros::<f32>(times(n, out_dims, "the output")?, "the output")?;
    py.detach(|| map_rows(op, m, cone, v, &mut out))
        .map_err(value_error)?;
    matrix(py, out, n, out_dims)
}

/// Directions into (`to_world`) or out of the bases about unit normals.
#[pyfunction]
fn onb<'py>(
    py: Python<'py>,
    to_world: bool,
    basis: &str,
    normals: PyReadonlyArray2<'py, f32>,
    dirs: PyReadonlyArray2<'py, f32>,
) -> PyResult<Bound<'py, PyArray2<f32>>> {
    let basis = Basis::from_name(basis).map_err(value_error)?;
    let (nv, dv) = (slice(&normals, "normals")?, slice(&dirs, "dirs")?);
    if normals.shape()[1] != 3 || dirs.shape() != normals.shape() {
        return Err(value_error(format!(
            "normals and dirs: two (n, 3) arrays, not {:?} and {:?}",
            normals.shape(),
            dirs.shape()
        )));
    }
    let n = normals.shape()[0];
    let mut out = zeros::<f32>(nv.len(), "the output")?;
    py.detach(|| onb_rows(to_world, basis, nv, dv, &mut out))
        .map_err(value_error)?;
    matrix(py, out, n, 3)
}

// ------------------------------------------------------------ tracing

/// Spheres in a BVH (hits equal the brute-force loop's, bit for bit).
#[pyclass(module = "strata._strata", frozen)]
struct Spheres {
    bvh: OwnedBvh,
    count: usize,
}

#[pymethods]
impl Spheres {
    #[new]
    fn new(py: Python<'_>, spheres: PyReadonlyArray2<'_, f32>) -> PyResult<Self> {
        if spheres.shape()[1] != 4 {
            return Err(value_error(format!(
                "spheres: rows of x, y, z, radius, not {} values",
                spheres.shape()[1]
            )));
        }
        let list = spheres_from_rows(slice(&spheres, "spheres")?).map_err(value_error)?;
        let bvh = py
            .detach(|| OwnedBvh::build(&list))
            .map_err(|e| value_error(format!("spheres: {e}")))?;
        Ok(Spheres {
            bvh,
            count: list.len(),
        })
    }

    fn __len__(&self) -> usize {
        self.count
    }

    /// The closest hit of each ray: `(t, id)` arrays, `id` −1 and `t`
    /// infinite for a miss.
    fn closest_hit<'py>(
        &self,
        py: Python<'py>,
        rays: PyReadonlyArray2<'py, f32>,
    ) -> PyResult<Hits<'py>> {
        let r = ray_rows(&rays)?;
        let mut hits = zeros::<(f32, i64)>(r.len() / 8, "hits")?;
        let view = self.bvh.view();
        py.detach(|| {
            let mut stack = BvhStack::new();
            query_rays(ray_parts(r), &mut hits, |ray| {
                view.closest_hit_with(ray, &mut stack)
                    .map_or((f32::INFINITY, -1), |h| (h.t, i64::from(h.sphere)))
            })
        })
        .map_err(value_error)?;
        let (t, id): (Vec<f32>, Vec<i64>) = hits.into_iter().unzip();
        Ok((PyArray1::from_vec(py, t), PyArray1::from_vec(py, id)))
    }

    /// Whether each ray hits anything.
    fn any_hit<'py>(
        &self,
        py: Python<'py>,
        rays: PyReadonlyArray2<'py, f32>,
    ) -> PyResult<Bound<'py, PyArray1<bool>>> {
        let r = ray_rows(&rays)?;
        let mut hit = zeros::<bool>(r.len() / 8, "hits")?;
        let view = self.bvh.view();
        py.detach(|| {
            let mut stack = BvhStack::new();
            query_rays(ray_parts(r), &mut hit, |ray| {
                view.any_hit_with(ray, &mut stack)
            })
        })
        .map_err(value_error)?;
        Ok(PyArray1::from_vec(py, hit))
    }
}

/// Closest hits: each ray's `t` and sphere index (−1 for none).
type Hits<'py> = (Bound<'py, PyArray1<f32>>, Bound<'py, PyArray1<i64>>);

/// Rays as rows of `ox, oy, oz, dx, dy, dz, t_min, t_max`.
fn ray_rows<'a>(rays: &'a PyReadonlyArray2<'_, f32>) -> PyResult<&'a [f32]> {
    if rays.shape()[1] != 8 {
        return Err(value_error(format!(
            "rays: rows of 8 values (origin, direction, t_min, t_max), not {}",
            rays.shape()[1]
        )));
    }
    slice(rays, "rays")
}

/// Each row's ray parts, for the shared query loop.
fn ray_parts(r: &[f32]) -> impl ExactSizeIterator<Item = RayParts> + '_ {
    r.chunks_exact(8)
        .map(|r| ([r[0], r[1], r[2]], [r[3], r[4], r[5]], r[6], r[7]))
}

// ------------------------------------------------------------ rendering

/// A finished render's exact film: the sums the golden table hashes.
#[pyclass(module = "strata._strata", frozen)]
struct Film {
    pixels: Vec<PixelSum>,
    width: usize,
    height: usize,
    /// Where the rendered window (the image unless cropped) sits in the
    /// film, which for a splatted filter may also hold a margin around
    /// it: `x, y, width, height`.
    window: [usize; 4],
}

#[pymethods]
impl Film {
    /// `(height, width)` of the film (the window and any splat margin).
    #[getter]
    fn shape(&self) -> (usize, usize) {
        (self.height, self.width)
    }

    /// Where the rendered window sits in the film: `(x, y, width,
    /// height)`; the whole film unless a splatted filter's margin around
    /// a cropped window is kept.
    #[getter]
    fn window(&self) -> (usize, usize, usize, usize) {
        let [x, y, w, h] = self.window;
        (x, y, w, h)
    }

    /// The golden table's FNV-1a 64 of the sums.
    fn hash(&self) -> u64 {
        golden::film_hash(&self.pixels)
    }

    /// The window's pixels (the filter's weighted mean of each),
    /// `(h, w, 3)` float32 linear RGB.
    fn rgb<'py>(&self, py: Python<'py>) -> PyResult<Bound<'py, PyArray3<f32>>> {
        let [x, y, w, h] = self.window;
        let mut v = zeros::<f32>(times(w * h, 3, "rgb")?, "rgb")?;
        for (row, out) in v.chunks_exact_mut(3 * w).enumerate() {
            let film = &self.pixels[(y + row) * self.width + x..][..w];
            for (o, p) in out.chunks_exact_mut(3).zip(film) {
                o.copy_from_slice(&p.mean().to_array());
            }
        }
        PyArray1::from_vec(py, v).reshape([h, w, 3])
    }

    /// The weighted sums `Σ w·L` (r, g, b) and `Σ w`, in units of `2⁻²⁴`,
    /// `(h, w, 4)` int64.
    fn sums<'py>(&self, py: Python<'py>) -> PyResult<Bound<'py, PyArray3<i64>>> {
        let mut v = zeros::<i64>(times(self.pixels.len(), 4, "sums")?, "sums")?;
        for (o, p) in v.chunks_exact_mut(4).zip(&self.pixels) {
            o[..3].copy_from_slice(&p.sum);
            o[3] = p.weight;
        }
        PyArray1::from_vec(py, v).reshape([self.height, self.width, 4])
    }

    /// Samples taken per pixel, `(h, w)` uint32.
    fn samples<'py>(&self, py: Python<'py>) -> PyResult<Bound<'py, PyArray2<u32>>> {
        let v: Vec<u32> = self.pixels.iter().map(|p| p.samples).collect();
        matrix(py, v, self.height, self.width)
    }

    /// Samples dropped per pixel for a NaN or infinite value, `(h, w)`.
    fn dropped<'py>(&self, py: Python<'py>) -> PyResult<Bound<'py, PyArray2<u32>>> {
        let v: Vec<u32> = self.pixels.iter().map(|p| p.dropped).collect();
        matrix(py, v, self.height, self.width)
    }
}

/// How often a waiting render looks at Ctrl-C and calls `progress`.
const POLL: Duration = Duration::from_millis(20);

/// Paths a tile renders per pass at most: a render goes in passes of
/// sample indices (their exact films add up to the one-shot film, bit
/// for bit), so a stop waits for one pass of the tiles in flight, not
/// for whole tiles of every sample.
const PASS_PATHS: u64 = 1 << 18;

/// The passes of `job`: ranges of its sample indices. An adaptive render
/// decides per pixel from all its samples: one pass.
fn passes(job: &Job<'_>) -> Vec<Range<u32>> {
    let r = job.samples.clone();
    if job.adaptive.is_some() || r.is_empty() {
        return vec![r];
    }
    // The largest tile's real area: a tile larger than the window is the
    // window.
    let side = tile_side(job).max(1);
    let area = u64::from(side.min(job.window.width)) * u64::from(side.min(job.window.height));
    let per = u32::try_from((PASS_PATHS / area.max(1)).max(1)).unwrap_or(u32::MAX);
    (r.start..r.end)
        .step_by(per as usize)
        .map(|a| a..a.saturating_add(per).min(r.end))
        .collect()
}

/// Set when the render thread ends, however it ends (a panic too), and
/// wakes the waiting caller.
struct Ended<'a> {
    flag: &'a AtomicBool,
    caller: std::thread::Thread,
}

impl Drop for Ended<'_> {
    fn drop(&mut self) {
        self.flag.store(true, Ordering::Release);
        self.caller.unpark();
    }
}

/// Renders with the flags of `strata render` on `threads` threads,
/// returning the film. Ctrl-C (any pending Python signal) or an exception
/// from `progress(done, total)` (pixel samples rendered, of those
/// planned) stops it within one pass of the tiles in flight.
#[pyfunction]
#[pyo3(signature = (flags, threads, progress=None))]
fn render(
    py: Python<'_>,
    flags: Vec<String>,
    threads: u32,
    progress: Option<Bound<'_, PyAny>>,
) -> PyResult<Film> {
    let (mut args, scene) = library_render(&flags).map_err(|e| value_error(format!("{e:#}")))?;
    // Past u16 is past the check's limit anyway: saturate into it.
    args.threads = u16::try_from(threads).unwrap_or(u16::MAX);
    let job = args
        .job(&scene)
        .map_err(|e| value_error(format!("{e:#}")))?;
    let per_pixel = u64::from(job.samples.end - job.samples.start);
    let total = u64::from(job.window.width) * u64::from(job.window.height) * per_pixel;
    let (stop, over, done) = (
        AtomicBool::new(false),
        AtomicBool::new(false),
        AtomicU64::new(0),
    );
    let caller = std::thread::current();
    let outcome = std::thread::scope(|s| -> PyResult<_> {
        let worker = s.spawn(|| -> anyhow::Result<Option<Rendered>> {
            let _ended = Ended {
                flag: &over,
                caller,
            };
            let mut whole: Option<Rendered> = None;
            for samples in passes(&job) {
                let n = u64::from(samples.end - samples.start);
                let pass = Job {
                    samples,
                    ..job.clone()
                };
                let resume = Resume {
                    done: Vec::new(),
                    on_tile: &|_| Ok(()),
                    stop: &stop,
                };
                let count = |pixels: u64| {
                    done.fetch_add(pixels * n, Ordering::Relaxed);
                };
                match run_resumable(&pass, &count, resume)? {
                    Outcome::Stopped { .. } => return Ok(None),
                    Outcome::Finished(r) => match &mut whole {
                        None => whole = Some(r),
                        Some(w) => {
                            for (a, b) in w.pixels.iter_mut().zip(&r.pixels) {
                                a.merge(b);
                            }
                        }
                    },
                }
            }
            Ok(whole)
        });
        let wait = || {
            if !over.load(Ordering::Acquire) {
                std::thread::park_timeout(POLL);
            }
        };
        let mut reported = u64::MAX;
        loop {
            py.detach(wait);
            // `over` before `done`: once it is seen, the count is final
            // and this round reports it.
            let ended = over.load(Ordering::Acquire);
            let mut failed = py.check_signals().err();
            let now = done.load(Ordering::Relaxed);
            if failed.is_none()
                && now != reported
                && let Some(cb) = &progress
            {
                reported = now;
                failed = cb.call1((now, total)).err();
            }
            if let Some(e) = failed {
                stop.store(true, Ordering::Relaxed);
                // The passes of tiles in flight finish; nothing else starts.
                let _ = py.detach(|| worker.join());
                return Err(e);
            }
            if ended {
                break;
            }
        }
        py.detach(|| worker.join())
            .map_err(|_| PyRuntimeError::new_err("the render thread panicked"))
    })?;
    let rendered = outcome
        .map_err(|e| value_error(format!("{e:#}")))?
        .ok_or_else(|| PyRuntimeError::new_err("the render stopped early"))?;
    let (w, ext) = (
        job.window,
        job.layout().extent(job.window, job.width, job.height),
    );
    Ok(Film {
        pixels: rendered.pixels,
        width: ext.width as usize,
        height: ext.height as usize,
        window: [
            (w.x0 - ext.x0) as usize,
            (w.y0 - ext.y0) as usize,
            w.width as usize,
            w.height as usize,
        ],
    })
}

/// Whether this CPU runs x86-64-v3 code (AVX, AVX2, BMI1, BMI2, F16C,
/// FMA, LZCNT, MOVBE and the v2 set): the package then imports its v3
/// module. Always false off x86-64.
#[pyfunction]
fn cpu_supports_v3() -> bool {
    #[cfg(target_arch = "x86_64")]
    {
        use std::arch::is_x86_feature_detected as has;
        has!("avx")
            && has!("avx2")
            && has!("bmi1")
            && has!("bmi2")
            && has!("f16c")
            && has!("fma")
            && has!("lzcnt")
            && has!("movbe")
            && has!("sse4.2")
            && has!("popcnt")
            && has!("cmpxchg16b")
    }
    #[cfg(not(target_arch = "x86_64"))]
    false
}

/// The module: `strata._strata` (portable), or `strata._strata_v3`
/// built with the `v3` feature for x86-64-v3.
#[pymodule]
#[cfg_attr(feature = "v3", pyo3(name = "_strata_v3"))]
fn _strata(m: &Bound<'_, PyModule>) -> PyResult<()> {
    m.add("__version__", env!("CARGO_PKG_VERSION"))?;
    m.add_function(wrap_pyfunction!(simd, m)?)?;
    m.add_function(wrap_pyfunction!(cpu_supports_v3, m)?)?;
    m.add_function(wrap_pyfunction!(output_revision, m)?)?;
    m.add_function(wrap_pyfunction!(sampler_kinds, m)?)?;
    m.add_function(wrap_pyfunction!(mapping_names, m)?)?;
    m.add_function(wrap_pyfunction!(mapping_arity, m)?)?;
    m.add_function(wrap_pyfunction!(per_sample_reference, m)?)?;
    m.add_function(wrap_pyfunction!(map, m)?)?;
    m.add_function(wrap_pyfunction!(onb, m)?)?;
    m.add_function(wrap_pyfunction!(render, m)?)?;
    m.add_class::<Sampler>()?;
    m.add_class::<Spheres>()?;
    m.add_class::<Film>()?;
    Ok(())
}
