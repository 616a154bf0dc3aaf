//! Strata's C API: `libstrata.a`, `libstrata.so` and the header
//! `include/strata.h` (generated from this file by cbindgen).
//!
//! The style of the C libraries renderers already link (Embree, Open
//! Image Denoise): opaque handles, every call returns a [`StrataStatus`]
//! and, when it is not `STRATA_STATUS_OK`, [`strata_last_error`] says
//! why. Every pointer is checked for null and alignment, every array
//! comes with its length in elements and is checked against what the
//! call needs, and no panic crosses into C: one is caught and returned as
//! `STRATA_STATUS_PANIC`. Calls work on whole arrays, so one call does
//! real work.
//!
//! Values are the Rust core's, bit for bit: the C tests reproduce the
//! core's value locks (`core/tests/data/locks.json`).
//!
//! Thread safety: the functions without a handle may be called from any
//! thread at once. A [`StrataSampler`] is used by one thread at a time
//! (it holds the state of the pixel sample being drawn); give each thread
//! its own (creating one is cheap), or move it between threads.
//!
//! This is the one crate besides tests where `unsafe` appears: the C
//! boundary itself. Each block says why it is sound.

#![deny(unsafe_op_in_unsafe_fn)]

use std::cell::RefCell;
use std::ffi::{CString, c_char, c_void};
use std::panic::{AssertUnwindSafe, catch_unwind};

use strata_core::Sampler;
use strata_core::glam::{UVec2, Vec2};
use strata_core::mapping::PiecewiseConstant2D;
use strata_core::render::PixelSum;
use strata_core::trace::{
    Aabb, BVH_MAX_SPHERES, Bvh, BvhNode8, BvhStack, BvhStorage, PrimitiveBvh, Primitives, Ray,
    SimdLevel, bvh_storage_for, primitive_bvh_storage_for, simd_level,
};
use strata_runner::batch::{
    self, AnySampler, Basis, BatchError, MapOp, Mapping, map_rows, onb_rows, query_rays,
    spheres_from_rows,
};
use strata_runner::cli::{RenderArgs, library_render};
use strata_runner::golden;
use strata_runner::job::SamplerKind;
use strata_runner::job::{Job, job_tile, render_tile_here, run, tile_count};
use strata_runner::scenes::SceneData;

/// What a call did. Anything but `STRATA_STATUS_OK` comes with a message
/// from [`strata_last_error`].
#[repr(C)]
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum StrataStatus {
    /// Done.
    Ok = 0,
    /// A pointer the call needs was null (or misaligned for its type).
    NullPointer = 1,
    /// An output array is shorter than the call needs, or an input's
    /// length does not fit the call.
    ShortBuffer = 2,
    /// An argument is out of range: an unknown kind, a sample count the
    /// sampler refuses, a normal that is not unit length.
    InvalidArgument = 3,
    /// A bug in Strata: a panic was caught at the boundary.
    Panic = 4,
}

/// A failed call: its status and message.
struct Failure {
    status: StrataStatus,
    message: String,
}

fn failure(status: StrataStatus, message: impl Into<String>) -> Failure {
    Failure {
        status,
        message: message.into(),
    }
}

thread_local! {
    /// The message of this thread's last failed call.
    static LAST_ERROR: RefCell<CString> = RefCell::new(CString::default());
}

fn set_error(message: &str) {
    // A message never holds NUL; should one, it is cut there.
    let bytes: Vec<u8> = message.bytes().take_while(|&b| b != 0).collect();
    let text = CString::new(bytes).unwrap_or_default();
    LAST_ERROR.with(|e| *e.borrow_mut() = text);
}

/// Runs `body`, turning its failure or panic into a status and message.
fn guard(body: impl FnOnce() -> Result<(), Failure>) -> StrataStatus {
    match catch_unwind(AssertUnwindSafe(body)) {
        Ok(Ok(())) => StrataStatus::Ok,
        Ok(Err(f)) => {
            set_error(&f.message);
            f.status
        }
        Err(panic) => {
            let what = panic
                .downcast_ref::<&str>()
                .map(|s| s.to_string())
                .or_else(|| panic.downcast_ref::<String>().cloned())
                .unwrap_or_else(|| "a panic".to_string());
            set_error(&format!("internal error (please report): {what}"));
            StrataStatus::Panic
        }
    }
}

/// `len` elements at `ptr`, for reading; `what` names the argument.
///
/// # Safety
/// If `ptr` is not null and is aligned, it must be valid for reads of
/// `len` elements of `T` for `'a`, as the C caller promises.
unsafe fn input<'a, T>(ptr: *const T, len: usize, what: &str) -> Result<&'a [T], Failure> {
    if len == 0 {
        return Ok(&[]);
    }
    if ptr.is_null() || !ptr.is_aligned() {
        return Err(failure(
            StrataStatus::NullPointer,
            format!("{what} is null or misaligned with {len} elements given"),
        ));
    }
    // SAFETY: non-null and aligned, checked above; the caller promises
    // `len` readable elements (the documented contract of every call).
    Ok(unsafe { std::slice::from_raw_parts(ptr, len) })
}

/// `len` elements at `ptr`, for writing.
///
/// # Safety
/// As [`input`], for writes, and nothing else may access them for `'a`.
unsafe fn output<'a, T>(ptr: *mut T, len: usize, what: &str) -> Result<&'a mut [T], Failure> {
    if len == 0 {
        return Ok(&mut []);
    }
    if ptr.is_null() || !ptr.is_aligned() {
        return Err(failure(
            StrataStatus::NullPointer,
            format!("{what} is null or misaligned with {len} elements given"),
        ));
    }
    // SAFETY: non-null and aligned, checked above; the caller promises
    // `len` writable elements that nothing else uses during the call.
    Ok(unsafe { std::slice::from_raw_parts_mut(ptr, len) })
}

/// The first `need` elements of `out`, or a failure naming the shortfall.
fn room<'a, T>(out: &'a mut [T], need: usize, what: &str) -> Result<&'a mut [T], Failure> {
    batch::room(out, need, what).map_err(batch_failure)
}

/// `a · b`, or a failure (sizes past `usize`).
fn times(a: usize, b: usize, what: &str) -> Result<usize, Failure> {
    batch::times(a, b, what).map_err(batch_failure)
}

/// Rows of `width` floats in `values`, or a failure when it does not
/// split into them.
fn rows(values: &[f32], width: usize, what: &str) -> Result<usize, Failure> {
    batch::rows(values, width, what).map_err(batch_failure)
}

/// A shared batch check's refusal, as a status and message.
fn batch_failure(e: BatchError) -> Failure {
    match e {
        BatchError::Size(m) => failure(StrataStatus::ShortBuffer, m),
        BatchError::Value(m) => failure(StrataStatus::InvalidArgument, m),
    }
}

fn null(what: &str) -> Failure {
    failure(StrataStatus::NullPointer, format!("{what} is null"))
}

// ------------------------------------------------------------ versions

/// The library's version, `"MAJOR.MINOR.PATCH"` (static storage).
#[unsafe(no_mangle)]
pub extern "C" fn strata_version() -> *const c_char {
    concat!(env!("CARGO_PKG_VERSION"), "\0").as_ptr().cast()
}

/// The output revision: it changes whenever a seeded render's pixels
/// change (the core's `render::OUTPUT_REVISION`).
#[unsafe(no_mangle)]
pub extern "C" fn strata_output_revision() -> u32 {
    strata_core::render::OUTPUT_REVISION
}

/// The SIMD level the library was compiled for (static storage):
/// `"sse2"` for the portable x86-64 build, `"avx2"`, `"avx512"`,
/// `"neon"`, ... It is fixed when the library is built, not chosen at
/// run time; every level returns the same bits.
#[unsafe(no_mangle)]
pub extern "C" fn strata_simd_level() -> *const c_char {
    let name: &'static std::ffi::CStr = match simd_level() {
        SimdLevel::Scalar => c"scalar",
        SimdLevel::Sse2 => c"sse2",
        SimdLevel::Sse41 => c"sse4.1",
        SimdLevel::Avx => c"avx",
        SimdLevel::Avx2 => c"avx2",
        SimdLevel::Avx512 => c"avx512",
        SimdLevel::Neon => c"neon",
        SimdLevel::Simd128 => c"simd128",
        _ => c"unknown",
    };
    name.as_ptr()
}

/// The message of the calling thread's last failed call (empty if none
/// failed). It stays valid until the next failed call on this thread.
#[unsafe(no_mangle)]
pub extern "C" fn strata_last_error() -> *const c_char {
    LAST_ERROR.with(|e| e.borrow().as_ptr())
}

// ------------------------------------------------------------ samplers

/// The pixel samplers (the `kind` of [`strata_sampler_new`]).
#[repr(C)]
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum StrataSamplerKind {
    /// Uniform random values.
    Independent = 0,
    /// Unjittered strata centres.
    Grid = 1,
    /// Jittered strata, any spp.
    Stratified = 2,
    /// Owen-scrambled Sobol'.
    Sobol = 3,
    /// Owen-scrambled Halton.
    Halton = 4,
    /// Sobol' along a hashed Morton curve over the image (blue-noise
    /// error); needs the image's resolution.
    Zsobol = 5,
}

/// A pixel sampler (opaque). One thread at a time.
pub struct StrataSampler {
    inner: AnySampler,
}

fn make_sampler(
    kind: u32,
    spp: u32,
    seed: u64,
    width: u32,
    height: u32,
) -> Result<StrataSampler, Failure> {
    let kind = *SamplerKind::ALL.get(kind as usize).ok_or_else(|| {
        failure(
            StrataStatus::InvalidArgument,
            format!("sampler kind {kind} is unknown (0 to 5: STRATA_SAMPLER_KIND_*)"),
        )
    })?;
    let inner = AnySampler::new(kind, spp, seed, UVec2::new(width, height))
        .map_err(|e| failure(StrataStatus::InvalidArgument, format!("{e:#}")))?;
    Ok(StrataSampler { inner })
}

/// Creates a sampler of `kind` (a `StrataSamplerKind`) for `spp` samples
/// per pixel and `seed`; `width` and `height` are the image's resolution,
/// which only `STRATA_SAMPLER_KIND_ZSOBOL` uses (others ignore them). On
/// success `*out` holds a sampler to free with [`strata_sampler_free`].
///
/// # Safety
/// `out` must be null (refused) or point to writable storage for one
/// pointer.
#[unsafe(no_mangle)]
pub unsafe extern "C" fn strata_sampler_new(
    kind: u32,
    spp: u32,
    seed: u64,
    width: u32,
    height: u32,
    out: *mut *mut StrataSampler,
) -> StrataStatus {
    guard(|| {
        // SAFETY: `out` is checked and, per the contract, writable.
        let out = unsafe { output(out, 1, "out") }?;
        out[0] = std::ptr::null_mut(); // what a failure leaves
        let sampler = make_sampler(kind, spp, seed, width, height)?;
        out[0] = Box::into_raw(Box::new(sampler));
        Ok(())
    })
}

/// Frees a sampler from [`strata_sampler_new`]; null is ignored.
///
/// # Safety
/// `sampler` must be null or a pointer from [`strata_sampler_new`] not
/// freed before, and not used after.
#[unsafe(no_mangle)]
pub unsafe extern "C" fn strata_sampler_free(sampler: *mut StrataSampler) {
    if !sampler.is_null() {
        // SAFETY: the pointer came from `Box::into_raw` in
        // `strata_sampler_new` and is freed once, per the contract.
        drop(unsafe { Box::from_raw(sampler) });
    }
}

/// The sampler behind a handle.
///
/// # Safety
/// `s` must be null (refused) or a live sampler that no other thread
/// uses during the call.
unsafe fn sampler_of<'a>(s: *mut StrataSampler) -> Result<&'a mut StrataSampler, Failure> {
    // SAFETY: a live handle, used by this thread only, per the contract.
    unsafe { s.as_mut() }.ok_or_else(|| null("sampler"))
}

/// Begins sample `index` of pixel `(px, py)`: the dimension goes back to
/// 2 and every value is a function of (kind, spp, seed, pixel, index).
///
/// # Safety
/// `sampler` must be null (refused) or a live sampler no other thread
/// uses during the call.
#[unsafe(no_mangle)]
pub unsafe extern "C" fn strata_sampler_start(
    sampler: *mut StrataSampler,
    px: u32,
    py: u32,
    index: u32,
) -> StrataStatus {
    guard(|| {
        // SAFETY: per this function's contract.
        let s = unsafe { sampler_of(sampler) }?;
        s.inner
            .as_dyn()
            .start_pixel_sample(UVec2::new(px, py), index);
        Ok(())
    })
}

/// One draw of `K` values from the sampler behind `sampler` into `out`.
///
/// # Safety
/// As the public draws document.
unsafe fn draw_into<const K: usize>(
    sampler: *mut StrataSampler,
    out: *mut f32,
    out_len: usize,
    draw: impl FnOnce(&mut dyn Sampler) -> [f32; K],
) -> StrataStatus {
    guard(|| {
        // SAFETY: per the calling function's contract.
        let (s, out) = unsafe { (sampler_of(sampler)?, output(out, out_len, "out")?) };
        room(out, K, "out")?.copy_from_slice(&draw(s.inner.as_dyn()));
        Ok(())
    })
}

/// The position in the pixel (dimensions 0 and 1), in `[0, 1)²`, into
/// `out[0..2]`; it does not advance the dimension.
///
/// # Safety
/// `sampler` as in [`strata_sampler_start`]; `out` null (refused) or
/// valid for `out_len` floats.
#[unsafe(no_mangle)]
pub unsafe extern "C" fn strata_sampler_pixel_2d(
    sampler: *mut StrataSampler,
    out: *mut f32,
    out_len: usize,
) -> StrataStatus {
    // SAFETY: the contract is this function's.
    unsafe {
        draw_into(sampler, out, out_len, |s| {
            let p = s.pixel_2d();
            [p.x, p.y]
        })
    }
}

/// The next dimension, in `[0, 1)`, into `out[0]`.
///
/// # Safety
/// As [`strata_sampler_pixel_2d`].
#[unsafe(no_mangle)]
pub unsafe extern "C" fn strata_sampler_next_1d(
    sampler: *mut StrataSampler,
    out: *mut f32,
    out_len: usize,
) -> StrataStatus {
    // SAFETY: the contract is this function's.
    unsafe { draw_into(sampler, out, out_len, |s| [s.next_1d()]) }
}

/// The next two dimensions, in `[0, 1)²`, into `out[0..2]`.
///
/// # Safety
/// As [`strata_sampler_pixel_2d`].
#[unsafe(no_mangle)]
pub unsafe extern "C" fn strata_sampler_next_2d(
    sampler: *mut StrataSampler,
    out: *mut f32,
    out_len: usize,
) -> StrataStatus {
    // SAFETY: the contract is this function's.
    unsafe {
        draw_into(sampler, out, out_len, |s| {
            let v = s.next_2d();
            [v.x, v.y]
        })
    }
}

/// Fills `out` with the first `dims` dimensions of many pixel samples,
/// one row of `dims` floats per sample: sample `i` is pixel
/// `(pixels[2i], pixels[2i + 1])`, index `indices[i]`. A row holds the
/// position in the pixel, then `next_2d` pairs, then a `next_1d` when
/// `dims` is odd, exactly as the single calls give them. `n` is
/// `indices_len`; `pixels_len` must be `2n` and `out_len` at least
/// `n · dims`. The sampler is left at the last sample.
///
/// # Safety
/// `sampler` as in [`strata_sampler_start`]; each array null (refused
/// unless its length is 0) or valid for its length.
#[unsafe(no_mangle)]
pub unsafe extern "C" fn strata_sampler_fill(
    sampler: *mut StrataSampler,
    pixels: *const u32,
    pixels_len: usize,
    indices: *const u32,
    indices_len: usize,
    dims: u32,
    out: *mut f32,
    out_len: usize,
) -> StrataStatus {
    guard(|| {
        // SAFETY: per this function's contract.
        let (s, pixels, indices, out) = unsafe {
            (
                sampler_of(sampler)?,
                input(pixels, pixels_len, "pixels")?,
                input(indices, indices_len, "indices")?,
                output(out, out_len, "out")?,
            )
        };
        s.inner
            .fill(pixels, indices, dims as usize, out)
            .map_err(batch_failure)
    })
}

/// The sampler's samples per pixel into `*out`.
///
/// # Safety
/// `sampler` as in [`strata_sampler_start`]; `out` null (refused) or
/// valid for one `uint32_t`.
#[unsafe(no_mangle)]
pub unsafe extern "C" fn strata_sampler_spp(
    sampler: *const StrataSampler,
    out: *mut u32,
) -> StrataStatus {
    guard(|| {
        // SAFETY: per this function's contract.
        let (s, out) = unsafe { (handle(sampler, "sampler")?, output(out, 1, "out")?) };
        out[0] = s.inner.samples_per_pixel();
        Ok(())
    })
}

// ------------------------------------------------------------ mappings

/// The mappings from the unit square (or cube) to a domain, each with
/// its pdf and inverse (the `kind` of the `strata_mapping_*` calls).
#[repr(C)]
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum StrataMapping {
    /// `[0,1)² →` the unit sphere (3 floats), pdf per steradian.
    UniformSphere = 0,
    /// `[0,1)² →` the hemisphere `z ≥ 0`, uniform.
    UniformHemisphere = 1,
    /// `[0,1)² →` the hemisphere `z ≥ 0`, cosine-weighted.
    CosineHemisphere = 2,
    /// `[0,1)² →` the unit disk (2 floats), Shirley–Chiu concentric.
    ConcentricDisk = 3,
    /// `[0,1)² →` the unit disk, polar.
    PolarDisk = 4,
    /// `[0,1)³ →` the unit ball (3 floats), pdf per unit volume.
    UniformBall = 5,
    /// `[0,1)² →` the cone about `+z` with `cos θmax` = the call's
    /// `cone` (clamped to `[−1, 1]`).
    UniformCone = 6,
    /// The same cone given by `sin² θmax` = the call's `cone` (clamped to
    /// `[0, 1]`, `θmax ≤ 90°`): exact for the tiniest cones (small lights
    /// far away), where `cos θmax` rounds to 1.
    UniformConeSin2 = 7,
}

/// One operation over arrays: `input` rows in, `out` rows out.
///
/// # Safety
/// The arrays as the public calls document.
unsafe fn map_arrays(
    op: MapOp,
    kind: u32,
    cone: f32,
    values: *const f32,
    values_len: usize,
    out: *mut f32,
    out_len: usize,
) -> StrataStatus {
    guard(|| {
        let m = *Mapping::ALL.get(kind as usize).ok_or_else(|| {
            failure(
                StrataStatus::InvalidArgument,
                format!("mapping kind {kind} is unknown (0 to 7: STRATA_MAPPING_*)"),
            )
        })?;
        // SAFETY: per the calling function's contract.
        let (values, out) = unsafe {
            (
                input(values, values_len, "values")?,
                output(out, out_len, "out")?,
            )
        };
        map_rows(op, m, cone, values, out).map_err(batch_failure)?;
        Ok(())
    })
}

/// Maps each sample row of `u` (2 floats, 3 for the ball) to its point
/// (3 floats, 2 for the disks) in `out`. `cone` is the cone's
/// `cos θmax`, or `sin² θmax` for `STRATA_MAPPING_UNIFORM_CONE_SIN2`
/// (other kinds ignore it). `u_len` must be a whole number of
/// rows; `out_len` at least the points' floats. A sample value outside
/// `[0, 1]` (or NaN) and a NaN `cone` are refused
/// (`STRATA_STATUS_INVALID_ARGUMENT`); the pdf and the inverse refuse
/// points that are not finite.
///
/// # Safety
/// Each array null (refused unless its length is 0) or valid for its
/// length; `out` not overlapping `u`.
#[unsafe(no_mangle)]
pub unsafe extern "C" fn strata_mapping_sample(
    kind: u32,
    cone: f32,
    u: *const f32,
    u_len: usize,
    out: *mut f32,
    out_len: usize,
) -> StrataStatus {
    // SAFETY: the contract is this function's.
    unsafe { map_arrays(MapOp::Sample, kind, cone, u, u_len, out, out_len) }
}

/// The density of each point row of `points` (with respect to solid
/// angle, area or volume, as the mapping's domain) into `out`, one float
/// per point.
///
/// # Safety
/// As [`strata_mapping_sample`].
#[unsafe(no_mangle)]
pub unsafe extern "C" fn strata_mapping_pdf(
    kind: u32,
    cone: f32,
    points: *const f32,
    points_len: usize,
    out: *mut f32,
    out_len: usize,
) -> StrataStatus {
    // SAFETY: the contract is this function's.
    unsafe { map_arrays(MapOp::Pdf, kind, cone, points, points_len, out, out_len) }
}

/// The sample row that maps to each point row of `points`, into `out`.
///
/// # Safety
/// As [`strata_mapping_sample`].
#[unsafe(no_mangle)]
pub unsafe extern "C" fn strata_mapping_invert(
    kind: u32,
    cone: f32,
    points: *const f32,
    points_len: usize,
    out: *mut f32,
    out_len: usize,
) -> StrataStatus {
    // SAFETY: the contract is this function's.
    unsafe { map_arrays(MapOp::Invert, kind, cone, points, points_len, out, out_len) }
}

// ------------------------------------------------------------ bases

/// The orthonormal bases (the `kind` of [`strata_onb_to_world`]).
#[repr(C)]
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum StrataOnb {
    /// Duff et al. 2017, right-handed (the default).
    Duff = 0,
    /// The course's axis-switch basis (left-handed).
    AxisSwitch = 1,
}

/// # Safety
/// As [`strata_onb_to_world`].
#[allow(clippy::too_many_arguments)]
unsafe fn onb_arrays(
    to_world: bool,
    kind: u32,
    normals: *const f32,
    normals_len: usize,
    dirs: *const f32,
    dirs_len: usize,
    out: *mut f32,
    out_len: usize,
) -> StrataStatus {
    guard(|| {
        if kind > 1 {
            return Err(failure(
                StrataStatus::InvalidArgument,
                format!("basis kind {kind} is unknown (0 or 1: STRATA_ONB_*)"),
            ));
        }
        // SAFETY: per the calling function's contract.
        let (normals, dirs, out) = unsafe {
            (
                input(normals, normals_len, "normals")?,
                input(dirs, dirs_len, "dirs")?,
                output(out, out_len, "out")?,
            )
        };
        let basis = if kind == 1 {
            Basis::AxisSwitch
        } else {
            Basis::Duff
        };
        onb_rows(to_world, basis, normals, dirs, out).map_err(batch_failure)
    })
}

/// Takes each direction of `dirs` (3 floats a row) from the basis about
/// the matching unit normal of `normals` (`z` along the normal) to world
/// space, into `out`. A normal that is not unit length, or a direction
/// value that is not finite, is refused.
///
/// # Safety
/// Each array null (refused unless its length is 0) or valid for its
/// length; `out` not overlapping the inputs.
#[unsafe(no_mangle)]
pub unsafe extern "C" fn strata_onb_to_world(
    kind: u32,
    normals: *const f32,
    normals_len: usize,
    dirs: *const f32,
    dirs_len: usize,
    out: *mut f32,
    out_len: usize,
) -> StrataStatus {
    // SAFETY: the contract is this function's.
    unsafe {
        onb_arrays(
            true,
            kind,
            normals,
            normals_len,
            dirs,
            dirs_len,
            out,
            out_len,
        )
    }
}

/// The inverse of [`strata_onb_to_world`]: world directions into each
/// normal's basis.
///
/// # Safety
/// As [`strata_onb_to_world`].
#[unsafe(no_mangle)]
pub unsafe extern "C" fn strata_onb_to_local(
    kind: u32,
    normals: *const f32,
    normals_len: usize,
    dirs: *const f32,
    dirs_len: usize,
    out: *mut f32,
    out_len: usize,
) -> StrataStatus {
    // SAFETY: the contract is this function's.
    unsafe {
        onb_arrays(
            false,
            kind,
            normals,
            normals_len,
            dirs,
            dirs_len,
            out,
            out_len,
        )
    }
}

// ------------------------------------------------------------ rays and the BVH

/// A ray: `origin + t · dir` for `t` in `(t_min, t_max)`. `dir` must be
/// unit length (`|d·d − 1| ≤ 16 ε`, which a normalised vector meets),
/// `origin` finite, and neither bound NaN; calls refuse other rays.
#[repr(C)]
#[derive(Clone, Copy, Debug)]
pub struct StrataRay {
    /// The origin.
    pub origin: [f32; 3],
    /// The unit direction.
    pub dir: [f32; 3],
    /// The interval's lower end (0 for a camera ray).
    pub t_min: f32,
    /// The interval's upper end (`INFINITY` for none).
    pub t_max: f32,
}

/// A closest hit: `id` is the sphere's or primitive's index,
/// `UINT32_MAX` for a miss (then `t` is `INFINITY`).
#[repr(C)]
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct StrataHit {
    /// The ray parameter of the hit.
    pub t: f32,
    /// What was hit, or `UINT32_MAX`.
    pub id: u32,
}

const MISS: StrataHit = StrataHit {
    t: f32::INFINITY,
    id: u32::MAX,
};

/// The alignment, in bytes, of the storage every BVH call takes.
const STORAGE_ALIGN: usize = 64;
const _: () = assert!(std::mem::align_of::<BvhNode8>() <= STORAGE_ALIGN);

/// Where a tree's three arrays sit in one block of caller storage.
struct Layout {
    need: BvhStorage,
    lanes_at: usize,
    ids_at: usize,
    bytes: usize,
}

fn layout(need: BvhStorage) -> Result<Layout, Failure> {
    let over = || {
        failure(
            StrataStatus::InvalidArgument,
            "the tree's storage overflows",
        )
    };
    let nodes = need
        .nodes
        .checked_mul(std::mem::size_of::<BvhNode8>())
        .ok_or_else(over)?;
    let lanes = need.lanes.checked_mul(4).ok_or_else(over)?;
    let ids = need.ids.checked_mul(4).ok_or_else(over)?;
    let ids_at = nodes.checked_add(lanes).ok_or_else(over)?;
    Ok(Layout {
        need,
        lanes_at: nodes,
        ids_at,
        bytes: ids_at.checked_add(ids).ok_or_else(over)?,
    })
}

fn too_many(n: usize) -> Result<(), Failure> {
    if n > BVH_MAX_SPHERES {
        return Err(failure(
            StrataStatus::InvalidArgument,
            format!("{n} items: a tree holds at most {BVH_MAX_SPHERES}"),
        ));
    }
    Ok(())
}

/// A tree's nodes, sphere lanes and ids.
type TreeArrays<'a> = (&'a mut [BvhNode8], &'a mut [f32], &'a mut [u32]);

/// The three arrays of a tree in the caller's block, zeroed (nodes
/// empty) so that no reference ever sees uninitialised memory.
///
/// # Safety
/// `storage` (checked non-null and aligned here) must be valid for
/// writes of `bytes` bytes, used by nothing else, for as long as `'a`.
unsafe fn carve<'a>(
    storage: *mut c_void,
    bytes: usize,
    at: &Layout,
) -> Result<TreeArrays<'a>, Failure> {
    if storage.is_null() || !(storage as usize).is_multiple_of(STORAGE_ALIGN) {
        return Err(failure(
            StrataStatus::NullPointer,
            format!("storage is null or not aligned to {STORAGE_ALIGN} bytes"),
        ));
    }
    if bytes < at.bytes {
        return Err(failure(
            StrataStatus::ShortBuffer,
            format!("storage holds {bytes} bytes; the tree needs {}", at.bytes),
        ));
    }
    let base = storage.cast::<u8>();
    // SAFETY: the block is valid for `at.bytes ≤ bytes` writes (the
    // caller's contract, the length checked above); the three arrays are
    // disjoint ranges of it, each aligned for its type (the block to 64,
    // nodes a multiple of 32 bytes long, floats and ids 4), and each is
    // written before a reference to it is made.
    unsafe {
        let nodes = base.cast::<BvhNode8>();
        for k in 0..at.need.nodes {
            nodes.add(k).write(BvhNode8::EMPTY);
        }
        let lanes = base.add(at.lanes_at).cast::<f32>();
        lanes.write_bytes(0, at.need.lanes);
        let ids = base.add(at.ids_at).cast::<u32>();
        ids.write_bytes(0, at.need.ids);
        Ok((
            std::slice::from_raw_parts_mut(nodes, at.need.nodes),
            std::slice::from_raw_parts_mut(lanes, at.need.lanes),
            std::slice::from_raw_parts_mut(ids, at.need.ids),
        ))
    }
}

/// The bytes of caller storage a BVH over `n` spheres needs, into
/// `*bytes`; the storage must be aligned to 64 bytes (C11
/// `aligned_alloc(64, bytes rounded up to 64)`, or `posix_memalign`).
///
/// # Safety
/// `bytes` null (refused) or valid for one `size_t`.
#[unsafe(no_mangle)]
pub unsafe extern "C" fn strata_bvh_storage_size(n: usize, bytes: *mut usize) -> StrataStatus {
    guard(|| {
        too_many(n)?;
        // SAFETY: per this function's contract.
        let out = unsafe { output(bytes, 1, "bytes") }?;
        out[0] = layout(bvh_storage_for(n))?.bytes;
        Ok(())
    })
}

/// A BVH over spheres, built into caller storage (opaque). Queries from
/// many threads at once are safe; the storage must outlive it unchanged.
pub struct StrataBvh {
    bvh: Bvh<'static>,
}

/// Builds a BVH over the spheres of `spheres` (rows of `x, y, z,
/// radius`) into `storage` (of `storage_bytes`, at least
/// [`strata_bvh_storage_size`], aligned to 64), and returns its handle
/// in `*out`. The spheres are copied into the storage: the array may go
/// once this returns; the storage may not until [`strata_bvh_free`].
/// Closest hits are the brute-force loop's over the spheres, bit for bit,
/// ties to the lowest index. A sphere with a value that is not finite or
/// a negative radius is refused.
///
/// # Safety
/// `spheres` null (refused unless its length is 0) or valid for
/// `spheres_len` floats; `storage` valid for `storage_bytes` bytes and
/// untouched by the caller until the handle is freed; `out` null
/// (refused) or valid for one pointer.
#[unsafe(no_mangle)]
pub unsafe extern "C" fn strata_bvh_build(
    spheres: *const f32,
    spheres_len: usize,
    storage: *mut c_void,
    storage_bytes: usize,
    out: *mut *mut StrataBvh,
) -> StrataStatus {
    guard(|| {
        // SAFETY: per this function's contract.
        let out = unsafe { output(out, 1, "out") }?;
        out[0] = std::ptr::null_mut(); // what a failure leaves
        // SAFETY: per this function's contract.
        let spheres = unsafe { input(spheres, spheres_len, "spheres") }?;
        let list = spheres_from_rows(spheres).map_err(batch_failure)?;
        let at = layout(bvh_storage_for(list.len()))?;
        // SAFETY: the caller keeps the storage alive and untouched until
        // `strata_bvh_free`, which drops the view first: `'static` stands
        // for that span.
        let (nodes, lanes, ids): TreeArrays<'static> =
            unsafe { carve(storage, storage_bytes, &at) }?;
        let bvh = Bvh::build(&list, nodes, lanes, ids)
            .map_err(|e| failure(StrataStatus::InvalidArgument, format!("spheres: {e}")))?;
        out[0] = Box::into_raw(Box::new(StrataBvh { bvh }));
        Ok(())
    })
}

/// Frees a BVH handle (not its storage, which is the caller's); null is
/// ignored.
///
/// # Safety
/// `bvh` null or a handle from [`strata_bvh_build`] not freed before.
#[unsafe(no_mangle)]
pub unsafe extern "C" fn strata_bvh_free(bvh: *mut StrataBvh) {
    if !bvh.is_null() {
        // SAFETY: from `Box::into_raw` in `strata_bvh_build`, freed once.
        drop(unsafe { Box::from_raw(bvh) });
    }
}

/// # Safety
/// `p` null (refused) or a live handle.
unsafe fn handle<'a, T>(p: *const T, what: &str) -> Result<&'a T, Failure> {
    // SAFETY: a live handle per the caller's contract.
    unsafe { p.as_ref() }.ok_or_else(|| null(what))
}

/// Runs `query` over `rays` into `out` (one result per ray).
///
/// # Safety
/// Arrays as the public calls document.
unsafe fn over_rays<T>(
    rays: *const StrataRay,
    n: usize,
    out: *mut T,
    out_len: usize,
    mut query: impl FnMut(&Ray) -> T,
) -> Result<(), Failure> {
    // SAFETY: per the calling function's contract.
    let (rays, out) = unsafe { (input(rays, n, "rays")?, output(out, out_len, "out")?) };
    let parts = rays.iter().map(|r| (r.origin, r.dir, r.t_min, r.t_max));
    query_rays(parts, out, &mut query).map_err(batch_failure)
}

/// One query per ray of a tree behind `tree`, its results into `out`.
///
/// # Safety
/// As the public queries document.
unsafe fn query<H, T>(
    tree: *const H,
    rays: *const StrataRay,
    n: usize,
    out: *mut T,
    out_len: usize,
    mut q: impl FnMut(&H, &Ray, &mut BvhStack) -> T,
) -> StrataStatus {
    guard(|| {
        // SAFETY: per the calling function's contract.
        let tree = unsafe { handle(tree, "bvh") }?;
        let mut stack = BvhStack::new();
        // SAFETY: per the calling function's contract.
        unsafe { over_rays(rays, n, out, out_len, |ray| q(tree, ray, &mut stack)) }
    })
}

/// The closest hit of each of the `n` rays into `hits[i]`.
/// Rays are checked (see [`StrataRay`]); on an error the hits are
/// unspecified.
///
/// # Safety
/// `bvh` a live handle; `rays` valid for `n` rays, `hits` for
/// `hits_len` hits (null refused unless the length is 0).
#[unsafe(no_mangle)]
pub unsafe extern "C" fn strata_bvh_closest_hit(
    bvh: *const StrataBvh,
    rays: *const StrataRay,
    n: usize,
    hits: *mut StrataHit,
    hits_len: usize,
) -> StrataStatus {
    // SAFETY: the contract is this function's.
    unsafe {
        query(bvh, rays, n, hits, hits_len, |t, ray, stack| {
            t.bvh
                .closest_hit_with(ray, stack)
                .map_or(MISS, |h| StrataHit {
                    t: h.t,
                    id: h.sphere,
                })
        })
    }
}

/// Whether each of the `n` rays hits anything (`1`) or not (`0`), into
/// `occluded[i]`.
///
/// # Safety
/// As [`strata_bvh_closest_hit`].
#[unsafe(no_mangle)]
pub unsafe extern "C" fn strata_bvh_any_hit(
    bvh: *const StrataBvh,
    rays: *const StrataRay,
    n: usize,
    occluded: *mut u8,
    occluded_len: usize,
) -> StrataStatus {
    // SAFETY: the contract is this function's.
    unsafe {
        query(bvh, rays, n, occluded, occluded_len, |t, ray, stack| {
            u8::from(t.bvh.any_hit_with(ray, stack))
        })
    }
}

// ------------------------------------------------------------ the caller's primitives

/// A box: `min` to `max`; empty (`min > max` on an axis) for a primitive
/// that can never be hit.
#[repr(C)]
#[derive(Clone, Copy, Debug)]
pub struct StrataAabb {
    /// The least corner.
    pub min: [f32; 3],
    /// The greatest corner.
    pub max: [f32; 3],
}

/// The caller's intersection routine: nonzero if `ray` hits primitive
/// `index` in `(t_min, t_max)`, with its `t` in `*t`; 0 if not. `user` is
/// the pointer given to the build. It must be a pure function of its
/// arguments while the tree is used; it runs on the thread that queries
/// the tree, so when several threads query one tree at once it runs on
/// all of them at once. It must not throw a C++ exception or `longjmp`
/// out (an exception that reaches Strata aborts the process).
pub type StrataIntersectFn = Option<
    unsafe extern "C-unwind" fn(
        user: *mut c_void,
        index: u32,
        ray: *const StrataRay,
        t: *mut f32,
    ) -> std::ffi::c_int,
>;

/// The caller's primitives as the core sees them.
struct CPrimitives {
    bounds: &'static [StrataAabb],
    intersect: unsafe extern "C-unwind" fn(
        *mut c_void,
        u32,
        *const StrataRay,
        *mut f32,
    ) -> std::ffi::c_int,
    user: *mut c_void,
}

fn aabb(b: &StrataAabb) -> Aabb {
    Aabb::new(b.min, b.max)
}

impl Primitives for CPrimitives {
    type Data = ();
    fn len(&self) -> usize {
        self.bounds.len()
    }
    fn bounds(&self, index: usize) -> Aabb {
        aabb(&self.bounds[index])
    }
    fn intersect(&self, index: usize, ray: &Ray) -> Option<(f32, ())> {
        let r = StrataRay {
            origin: ray.origin.to_array(),
            dir: ray.dir.to_array(),
            t_min: ray.t_min,
            t_max: ray.t_max,
        };
        let mut t = f32::NAN;
        // SAFETY: the routine and `user` are the caller's, with the
        // contract of `StrataIntersectFn`; `index` < len fits a u32
        // (at most BVH_MAX_SPHERES items); both pointers are to locals.
        let hit = unsafe { (self.intersect)(self.user, index as u32, &r, &mut t) } != 0;
        // The tree's one requirement, kept here: a hit outside its box is
        // dropped (as the brute-force reference drops it too).
        (hit && t > ray.t_min && t < ray.t_max && self.bounds(index).holds_hit(ray, t))
            .then_some((t, ()))
    }
}

/// A BVH over the caller's primitives (opaque). Queries from several
/// threads at once are safe when the intersection routine is.
pub struct StrataPrimitiveBvh {
    /// The view borrows `prims`: dropped by hand, before them.
    bvh: std::mem::ManuallyDrop<PrimitiveBvh<'static, CPrimitives>>,
    prims: *mut CPrimitives,
}

impl Drop for StrataPrimitiveBvh {
    fn drop(&mut self) {
        // SAFETY: the view is dropped once, here, and never used after;
        // then `prims`, from `Box::into_raw` in the build, is freed once,
        // with nothing left borrowing it.
        unsafe {
            std::mem::ManuallyDrop::drop(&mut self.bvh);
            drop(Box::from_raw(self.prims));
        }
    }
}

/// The bytes of caller storage a BVH over `n` primitives needs (aligned
/// to 64, as for spheres).
///
/// # Safety
/// `bytes` null (refused) or valid for one `size_t`.
#[unsafe(no_mangle)]
pub unsafe extern "C" fn strata_primitive_bvh_storage_size(
    n: usize,
    bytes: *mut usize,
) -> StrataStatus {
    guard(|| {
        too_many(n)?;
        // SAFETY: per this function's contract.
        let out = unsafe { output(bytes, 1, "bytes") }?;
        out[0] = layout(primitive_bvh_storage_for(n))?.bytes;
        Ok(())
    })
}

/// Builds a BVH over `n` primitives with boxes `bounds[0..n]` whose hits
/// `intersect` reports, into `storage` (at least
/// [`strata_primitive_bvh_storage_size`], aligned to 64). The boxes are
/// not copied: `bounds`, `user`'s data and the storage must outlive the
/// handle unchanged. A hit the routine reports outside its primitive's
/// box (beyond rounding: the core's `Aabb::holds_hit`) is dropped, so
/// queries return exactly what a loop over the routine (dropping the
/// same hits) returns, ties to the lowest index.
///
/// # Safety
/// `bounds` valid for `n` boxes; `intersect` a routine with the contract
/// of [`StrataIntersectFn`]; `storage` valid for `storage_bytes` bytes;
/// `out` valid for one pointer (nulls refused).
#[unsafe(no_mangle)]
pub unsafe extern "C" fn strata_primitive_bvh_build(
    bounds: *const StrataAabb,
    n: usize,
    intersect: StrataIntersectFn,
    user: *mut c_void,
    storage: *mut c_void,
    storage_bytes: usize,
    out: *mut *mut StrataPrimitiveBvh,
) -> StrataStatus {
    guard(|| {
        // SAFETY: per this function's contract.
        let out = unsafe { output(out, 1, "out") }?;
        out[0] = std::ptr::null_mut(); // what a failure leaves
        too_many(n)?;
        let intersect = intersect.ok_or_else(|| null("intersect"))?;
        // SAFETY: per this function's contract; `'static` stands for the
        // handle's life, which the caller keeps `bounds` alive for.
        let bounds: &'static [StrataAabb] = unsafe { input(bounds, n, "bounds") }?;
        let at = layout(primitive_bvh_storage_for(n))?;
        // SAFETY: as in `strata_bvh_build`.
        let (nodes, _, ids): TreeArrays<'static> = unsafe { carve(storage, storage_bytes, &at) }?;
        let prims = Box::into_raw(Box::new(CPrimitives {
            bounds,
            intersect,
            user,
        }));
        // SAFETY: `prims` lives until the handle's drop frees it, after
        // the last use of this reference.
        let view: &'static CPrimitives = unsafe { &*prims };
        match PrimitiveBvh::build(view, nodes, ids) {
            Ok(bvh) => {
                out[0] = Box::into_raw(Box::new(StrataPrimitiveBvh {
                    bvh: std::mem::ManuallyDrop::new(bvh),
                    prims,
                }));
                Ok(())
            }
            Err(e) => {
                // SAFETY: from `Box::into_raw` above; nothing borrows it.
                drop(unsafe { Box::from_raw(prims) });
                Err(failure(
                    StrataStatus::InvalidArgument,
                    format!("bounds: {e}"),
                ))
            }
        }
    })
}

/// Frees a primitive BVH handle (not the storage, the boxes or `user`);
/// null is ignored.
///
/// # Safety
/// `bvh` null or a handle from [`strata_primitive_bvh_build`] not freed
/// before.
#[unsafe(no_mangle)]
pub unsafe extern "C" fn strata_primitive_bvh_free(bvh: *mut StrataPrimitiveBvh) {
    if !bvh.is_null() {
        // SAFETY: from `Box::into_raw` in the build, freed once.
        drop(unsafe { Box::from_raw(bvh) });
    }
}

/// The closest hit of each of the `n` rays among the primitives, into
/// `hits[i]` (`id` the primitive's index).
///
/// # Safety
/// As [`strata_bvh_closest_hit`].
#[unsafe(no_mangle)]
pub unsafe extern "C" fn strata_primitive_bvh_closest_hit(
    bvh: *const StrataPrimitiveBvh,
    rays: *const StrataRay,
    n: usize,
    hits: *mut StrataHit,
    hits_len: usize,
) -> StrataStatus {
    // SAFETY: the contract is this function's.
    unsafe {
        query(bvh, rays, n, hits, hits_len, |t, ray, stack| {
            t.bvh
                .closest_hit_with(ray, stack)
                .map_or(MISS, |h| StrataHit {
                    t: h.t,
                    id: h.primitive,
                })
        })
    }
}

/// Whether each of the `n` rays hits any primitive, into `occluded[i]`.
///
/// # Safety
/// As [`strata_bvh_closest_hit`].
#[unsafe(no_mangle)]
pub unsafe extern "C" fn strata_primitive_bvh_any_hit(
    bvh: *const StrataPrimitiveBvh,
    rays: *const StrataRay,
    n: usize,
    occluded: *mut u8,
    occluded_len: usize,
) -> StrataStatus {
    // SAFETY: the contract is this function's.
    unsafe {
        query(bvh, rays, n, occluded, occluded_len, |t, ray, stack| {
            u8::from(t.bvh.any_hit_with(ray, stack))
        })
    }
}

// ------------------------------------------------------------ the renderer

/// A pixel's exact film sums (the core's `render::PixelSum`): weighted
/// RGB and weight sums in units of `2⁻²⁴`, the own-sample sums' offset,
/// and the sample counts. Films add exactly, in any order; the golden
/// table hashes these ([`strata_film_hash`]), not RGB.
#[repr(C)]
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub struct StrataPixelSum {
    /// `Σ w·L` per channel, in units of `2⁻²⁴`.
    pub sum: [i64; 3],
    /// `Σ w`, in units of `2⁻²⁴`.
    pub weight: i64,
    /// `Σ L − Σ w·L` per channel (wrapping): 0 for weights of 1.
    pub own_minus_sum: [i64; 3],
    /// Samples summed.
    pub samples: u32,
    /// Samples dropped for a NaN or infinite channel.
    pub dropped: u32,
}

const _: () = assert!(std::mem::size_of::<StrataPixelSum>() == 64);

fn to_c(p: &PixelSum) -> StrataPixelSum {
    StrataPixelSum {
        sum: p.sum,
        weight: p.weight,
        own_minus_sum: p.own_minus_sum,
        samples: p.samples,
        dropped: p.dropped,
    }
}

fn from_c(p: &StrataPixelSum) -> PixelSum {
    PixelSum {
        sum: p.sum,
        weight: p.weight,
        own_minus_sum: p.own_minus_sum,
        samples: p.samples,
        dropped: p.dropped,
    }
}

/// A render, planned and checked (opaque): a scene and the settings of
/// `strata render`. Calls on it may run on many threads at once.
pub struct StrataRender {
    args: RenderArgs,
    scene: SceneData,
}

impl StrataRender {
    fn job(&self) -> Result<Job<'_>, Failure> {
        // Checked at creation; planned again per call (cheap).
        self.args.job(&self.scene).map_err(invalid)
    }
}

/// A runner error as a failure, with its whole chain of causes.
fn invalid(e: anyhow::Error) -> Failure {
    failure(StrataStatus::InvalidArgument, format!("{e:#}"))
}

/// Plans a render from the flags of `strata render` (`flags[0..n]`, for
/// example `{"--scene", "cover", "--spp", "64", "--width", "400"}`: a
/// built-in scene or a TOML file, the size, samples, sampler, seed,
/// filter, depth, window...). Every setting passes the one check the
/// command line and its checkpoints use; its message comes back from
/// [`strata_last_error`]. Flags about files and threads are refused (the
/// calls take buffers and a thread count).
///
/// # Safety
/// `flags` null (refused unless `n` is 0) or valid for `n` pointers, each
/// null (refused) or a NUL-terminated string; `out` valid for one
/// pointer.
#[unsafe(no_mangle)]
pub unsafe extern "C" fn strata_render_new(
    flags: *const *const c_char,
    n: usize,
    out: *mut *mut StrataRender,
) -> StrataStatus {
    guard(|| {
        // SAFETY: per this function's contract.
        let out = unsafe { output(out, 1, "out") }?;
        out[0] = std::ptr::null_mut(); // what a failure leaves
        // SAFETY: per this function's contract.
        let flags = unsafe { input(flags, n, "flags") }?;
        let mut argv = Vec::with_capacity(flags.len());
        for (i, &f) in flags.iter().enumerate() {
            if f.is_null() {
                return Err(null(&format!("flags[{i}]")));
            }
            // SAFETY: non-null, NUL-terminated per the contract.
            let text = unsafe { std::ffi::CStr::from_ptr(f) }
                .to_str()
                .map_err(|_| {
                    failure(
                        StrataStatus::InvalidArgument,
                        format!("flags[{i}] is not UTF-8"),
                    )
                })?;
            argv.push(text.to_string());
        }
        let (args, scene) = library_render(&argv).map_err(invalid)?;
        let render = StrataRender { args, scene };
        out[0] = Box::into_raw(Box::new(render));
        Ok(())
    })
}

/// Frees a render; null is ignored.
///
/// # Safety
/// `render` null or from [`strata_render_new`], not freed before.
#[unsafe(no_mangle)]
pub unsafe extern "C" fn strata_render_free(render: *mut StrataRender) {
    if !render.is_null() {
        // SAFETY: from `Box::into_raw` in `strata_render_new`, freed once.
        drop(unsafe { Box::from_raw(render) });
    }
}

/// What a render makes.
#[repr(C)]
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub struct StrataRenderInfo {
    /// The image's size.
    pub width: u32,
    /// The image's size.
    pub height: u32,
    /// The window rendered (all of the image unless `--crop` or
    /// `--pixel-bounds`): its corner and size.
    pub x0: u32,
    /// See `x0`.
    pub y0: u32,
    /// See `x0`.
    pub window_width: u32,
    /// See `x0`.
    pub window_height: u32,
    /// Pixels of the film [`strata_render_film`] fills: the window, and
    /// for a splatted filter (negative lobes) its border a side.
    pub film_width: u32,
    /// See `film_width`.
    pub film_height: u32,
    /// Samples per pixel (the most, for an adaptive render).
    pub spp: u32,
    /// The number of tiles, each rendered by one [`strata_render_tile`]
    /// call (calls for different tiles may run on different threads at
    /// once).
    pub tiles: u32,
}

/// The sizes of a render into `*info`.
///
/// # Safety
/// `render` a live render; `info` valid for one `StrataRenderInfo`
/// (nulls refused).
#[unsafe(no_mangle)]
pub unsafe extern "C" fn strata_render_info(
    render: *const StrataRender,
    info: *mut StrataRenderInfo,
) -> StrataStatus {
    guard(|| {
        // SAFETY: per this function's contract.
        let (render, info) = unsafe { (handle(render, "render")?, output(info, 1, "info")?) };
        let job = render.job()?;
        let w = job.window;
        let film = job.layout().extent(w, job.width, job.height);
        let tiles = u32::try_from(tile_count(&job))
            .map_err(|_| failure(StrataStatus::InvalidArgument, "too many tiles"))?;
        info[0] = StrataRenderInfo {
            width: job.width,
            height: job.height,
            x0: w.x0,
            y0: w.y0,
            window_width: w.width,
            window_height: w.height,
            film_width: film.width,
            film_height: film.height,
            spp: job.spp,
            tiles,
        };
        Ok(())
    })
}

/// Renders the whole window on `threads` threads (with 1, the calling
/// thread, on its stack; with more, a pool that lives for this call
/// only) into `film` (`film_width × film_height` pixels,
/// row-major, of [`strata_render_info`]). The sums are the same for any
/// thread count.
///
/// # Safety
/// `render` a live render; `film` valid for `film_len` pixels (nulls
/// refused).
#[unsafe(no_mangle)]
pub unsafe extern "C" fn strata_render_film(
    render: *const StrataRender,
    threads: u32,
    film: *mut StrataPixelSum,
    film_len: usize,
) -> StrataStatus {
    guard(|| {
        // SAFETY: per this function's contract.
        let (render, film) =
            unsafe { (handle(render, "render")?, output(film, film_len, "film")?) };
        let mut args = render.args.clone();
        // Past u16 is past the check's limit anyway: saturate into it.
        args.threads = u16::try_from(threads).unwrap_or(u16::MAX);
        // The thread count passes the same check as the command line's.
        let job = args.job(&render.scene).map_err(invalid)?;
        let need = job
            .layout()
            .extent(job.window, job.width, job.height)
            .area();
        let film = room(film, need, "film")?;
        let done = run(&job, &|_| {}).map_err(invalid)?;
        for (o, p) in film.iter_mut().zip(&done.pixels) {
            *o = to_c(p);
        }
        Ok(())
    })
}

/// Renders tile `index` (of [`StrataRenderInfo`]'s `tiles`) on the
/// calling thread, no pool: for a host renderer that owns its threads
/// (different tiles may render on different threads at once). The film
/// of the tile goes to `film`, its corner and size to `tile[0..4]`
/// (`x0, y0, width, height` in the image) and its film's size to
/// `film_size[0..2]` (the tile, or for a splatted filter the tile and
/// its margin a side, which adds into its neighbours). Placed (or
/// added) into the window's film, the tiles give
/// [`strata_render_film`]'s sums exactly.
///
/// # Safety
/// `render` a live render; each array valid for its length (nulls
/// refused).
#[unsafe(no_mangle)]
pub unsafe extern "C" fn strata_render_tile(
    render: *const StrataRender,
    index: u32,
    film: *mut StrataPixelSum,
    film_len: usize,
    tile: *mut u32,
    tile_len: usize,
    film_size: *mut u32,
    film_size_len: usize,
) -> StrataStatus {
    guard(|| {
        // SAFETY: per this function's contract.
        let (render, film, tile_out, size_out) = unsafe {
            (
                handle(render, "render")?,
                output(film, film_len, "film")?,
                output(tile, tile_len, "tile")?,
                output(film_size, film_size_len, "film_size")?,
            )
        };
        let job = render.job()?;
        let t = job_tile(&job, index as usize).ok_or_else(|| {
            failure(
                StrataStatus::InvalidArgument,
                format!("tile {index}: the render has {} tiles", tile_count(&job)),
            )
        })?;
        let (fw, fh) = job.layout().film_size(t).ok_or_else(|| {
            failure(
                StrataStatus::InvalidArgument,
                "the tile's film is too large",
            )
        })?;
        let film = room(film, fw as usize * fh as usize, "film")?;
        let tile_out = room(tile_out, 4, "tile")?;
        let size_out = room(size_out, 2, "film_size")?;
        let (_, sums, _) = render_tile_here(&job, index as usize).map_err(invalid)?;
        for (o, p) in film.iter_mut().zip(&sums) {
            *o = to_c(p);
        }
        tile_out.copy_from_slice(&[t.x0, t.y0, t.width, t.height]);
        size_out.copy_from_slice(&[fw, fh]);
        Ok(())
    })
}

/// Each pixel's value from its sums (the filter's weighted mean, as the
/// runner's images take it), 3 floats a pixel, into `rgb`.
///
/// # Safety
/// Each array valid for its length (nulls refused unless it is 0).
#[unsafe(no_mangle)]
pub unsafe extern "C" fn strata_film_rgb(
    film: *const StrataPixelSum,
    n: usize,
    rgb: *mut f32,
    rgb_len: usize,
) -> StrataStatus {
    guard(|| {
        // SAFETY: per this function's contract.
        let (film, rgb) = unsafe { (input(film, n, "film")?, output(rgb, rgb_len, "rgb")?) };
        let rgb = room(rgb, times(n, 3, "rgb")?, "rgb")?;
        for (p, o) in film.iter().zip(rgb.chunks_exact_mut(3)) {
            o.copy_from_slice(&from_c(p).mean().to_array());
        }
        Ok(())
    })
}

/// The golden table's FNV-1a 64 of a film's sums (row-major), into
/// `*hash`: what `strata verify` and the golden rows compare.
///
/// # Safety
/// `film` valid for `n` pixels; `hash` for one `uint64_t` (nulls
/// refused).
#[unsafe(no_mangle)]
pub unsafe extern "C" fn strata_film_hash(
    film: *const StrataPixelSum,
    n: usize,
    hash: *mut u64,
) -> StrataStatus {
    guard(|| {
        // SAFETY: per this function's contract.
        let (film, hash) = unsafe { (input(film, n, "film")?, output(hash, 1, "hash")?) };
        let sums: Vec<PixelSum> = film.iter().map(from_c).collect();
        hash[0] = golden::film_hash(&sums);
        Ok(())
    })
}

// ------------------------------------------------------------ the tabulated mapping

/// Cells per axis of a [`StrataPiecewise2d`]: its table holds this
/// squared values.
pub const STRATA_PIECEWISE_2D_SIZE: usize = 32;
const _: () = assert!(STRATA_PIECEWISE_2D_SIZE == strata_core::mapping::PIECEWISE_2D_SIZE);

/// A piecewise-constant density on `[0, 1)²` tabulated from your values
/// (opaque; the core's `PiecewiseConstant2D`): sample, pdf and inverse
/// like every mapping. Use from many threads at once is safe.
pub struct StrataPiecewise2d {
    table: PiecewiseConstant2D,
}

/// Tabulates the density proportional to `values`
/// (`STRATA_PIECEWISE_2D_SIZE²` floats, row-major, row = y), every value
/// finite and `≥ 0` and not all 0; the handle in `*out` (NULL on a
/// failure).
///
/// # Safety
/// `values` valid for `values_len` floats; `out` for one pointer (nulls
/// refused).
#[unsafe(no_mangle)]
pub unsafe extern "C" fn strata_piecewise2d_new(
    values: *const f32,
    values_len: usize,
    out: *mut *mut StrataPiecewise2d,
) -> StrataStatus {
    guard(|| {
        // SAFETY: per this function's contract.
        let out = unsafe { output(out, 1, "out") }?;
        out[0] = std::ptr::null_mut(); // what a failure leaves
        // SAFETY: per this function's contract.
        let values = unsafe { input(values, values_len, "values") }?;
        const N: usize = STRATA_PIECEWISE_2D_SIZE;
        if values.len() != N * N {
            return Err(failure(
                StrataStatus::ShortBuffer,
                format!(
                    "values holds {} floats; the table takes {}",
                    values.len(),
                    N * N
                ),
            ));
        }
        let mut grid = [[0.0f32; N]; N];
        for (row, src) in grid.iter_mut().zip(values.chunks_exact(N)) {
            row.copy_from_slice(src);
        }
        let table = PiecewiseConstant2D::new(&grid).ok_or_else(|| {
            failure(
                StrataStatus::InvalidArgument,
                "values: each must be finite and ≥ 0, and not all 0",
            )
        })?;
        out[0] = Box::into_raw(Box::new(StrataPiecewise2d { table }));
        Ok(())
    })
}

/// Frees a table; null is ignored.
///
/// # Safety
/// `table` null or from [`strata_piecewise2d_new`], not freed before.
#[unsafe(no_mangle)]
pub unsafe extern "C" fn strata_piecewise2d_free(table: *mut StrataPiecewise2d) {
    if !table.is_null() {
        // SAFETY: from `Box::into_raw` in `strata_piecewise2d_new`, once.
        drop(unsafe { Box::from_raw(table) });
    }
}

/// Maps each sample row of `u` (2 floats) to a point of `[0, 1)²` in
/// `points` (2 floats a row) and its density in `pdfs`.
///
/// # Safety
/// `table` a live table; each array valid for its length (nulls refused
/// unless it is 0); outputs not overlapping inputs.
#[unsafe(no_mangle)]
pub unsafe extern "C" fn strata_piecewise2d_sample(
    table: *const StrataPiecewise2d,
    u: *const f32,
    u_len: usize,
    points: *mut f32,
    points_len: usize,
    pdfs: *mut f32,
    pdfs_len: usize,
) -> StrataStatus {
    guard(|| {
        // SAFETY: per this function's contract.
        let (t, u, points, pdfs) = unsafe {
            (
                &handle(table, "table")?.table,
                input(u, u_len, "u")?,
                output(points, points_len, "points")?,
                output(pdfs, pdfs_len, "pdfs")?,
            )
        };
        let n = rows(u, 2, "u")?;
        let points = room(points, u.len(), "points")?;
        let pdfs = room(pdfs, n, "pdfs")?;
        for ((r, p), pdf) in u.chunks_exact(2).zip(points.chunks_exact_mut(2)).zip(pdfs) {
            let (q, d) = t.sample(Vec2::new(r[0], r[1]));
            p.copy_from_slice(&q.to_array());
            *pdf = d;
        }
        Ok(())
    })
}

/// The density at each point row of `points` (2 floats) into `out`.
///
/// # Safety
/// As [`strata_piecewise2d_sample`].
#[unsafe(no_mangle)]
pub unsafe extern "C" fn strata_piecewise2d_pdf(
    table: *const StrataPiecewise2d,
    points: *const f32,
    points_len: usize,
    out: *mut f32,
    out_len: usize,
) -> StrataStatus {
    guard(|| {
        // SAFETY: per this function's contract.
        let (t, points, out) = unsafe {
            (
                &handle(table, "table")?.table,
                input(points, points_len, "points")?,
                output(out, out_len, "out")?,
            )
        };
        let n = rows(points, 2, "points")?;
        let out = room(out, n, "out")?;
        for (p, o) in points.chunks_exact(2).zip(out) {
            *o = t.pdf(Vec2::new(p[0], p[1]));
        }
        Ok(())
    })
}

/// The sample row that maps to each point row of `points`, into `out`
/// (2 floats a row).
///
/// # Safety
/// As [`strata_piecewise2d_sample`].
#[unsafe(no_mangle)]
pub unsafe extern "C" fn strata_piecewise2d_invert(
    table: *const StrataPiecewise2d,
    points: *const f32,
    points_len: usize,
    out: *mut f32,
    out_len: usize,
) -> StrataStatus {
    guard(|| {
        // SAFETY: per this function's contract.
        let (t, points, out) = unsafe {
            (
                &handle(table, "table")?.table,
                input(points, points_len, "points")?,
                output(out, out_len, "out")?,
            )
        };
        rows(points, 2, "points")?;
        let out = room(out, points.len(), "out")?;
        for (p, o) in points.chunks_exact(2).zip(out.chunks_exact_mut(2)) {
            o.copy_from_slice(&t.invert(Vec2::new(p[0], p[1])).to_array());
        }
        Ok(())
    })
}

// The thread-safety each handle's docs promise.
const _: () = {
    const fn send<T: Send>() {}
    const fn sync<T: Sync>() {}
    send::<StrataSampler>();
    sync::<StrataBvh>();
    send::<StrataBvh>();
    sync::<StrataRender>();
    send::<StrataRender>();
    sync::<StrataPiecewise2d>();
    send::<StrataPiecewise2d>();
};

#[cfg(test)]
mod tests {
    use super::*;

    /// A panic inside a call comes back as `STRATA_STATUS_PANIC` with its
    /// message; an error as its status and message.
    #[test]
    fn panics_and_failures_become_statuses() {
        let last = || {
            // SAFETY: a NUL-terminated string this thread owns.
            unsafe { std::ffi::CStr::from_ptr(strata_last_error()) }
                .to_string_lossy()
                .into_owned()
        };
        assert_eq!(guard(|| panic!("deliberate")), StrataStatus::Panic);
        assert!(last().contains("deliberate"), "{}", last());
        let status = guard(|| Err(failure(StrataStatus::ShortBuffer, "short")));
        assert_eq!(status, StrataStatus::ShortBuffer);
        assert_eq!(last(), "short");
        assert_eq!(guard(|| Ok(())), StrataStatus::Ok);
    }
}
