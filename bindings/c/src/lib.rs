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
use std::ffi::{CString, c_char};
use std::panic::{AssertUnwindSafe, catch_unwind};

use strata_core::glam::{UVec2, Vec2, Vec3};
use strata_core::mapping::{self, Cone};
use strata_core::trace::{Ray, SimdLevel, simd_level};
use strata_core::{Halton, Independent, Onb, Sampler, Sobol, Stratified, UniformGrid, ZSobol};

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
    let have = out.len();
    out.get_mut(..need).ok_or_else(|| {
        failure(
            StrataStatus::ShortBuffer,
            format!("{what} holds {have} elements; the call writes {need}"),
        )
    })
}

/// `a · b`, or a failure (sizes past `usize`).
fn times(a: usize, b: usize, what: &str) -> Result<usize, Failure> {
    a.checked_mul(b)
        .ok_or_else(|| failure(StrataStatus::ShortBuffer, format!("{what}: size overflows")))
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
    inner: Box<dyn Sampler + Send>,
}

fn make_sampler(
    kind: u32,
    spp: u32,
    seed: u64,
    width: u32,
    height: u32,
) -> Result<StrataSampler, Failure> {
    fn boxed<S: Sampler + Send + 'static>(s: Option<S>) -> Option<Box<dyn Sampler + Send>> {
        s.map(|s| Box::new(s) as Box<dyn Sampler + Send>)
    }
    let (name, made) = match kind {
        0 => ("independent", boxed(Independent::new(spp, seed))),
        1 => ("grid", boxed(UniformGrid::new(spp, seed))),
        2 => ("stratified", boxed(Stratified::new(spp, seed))),
        3 => ("sobol", boxed(Sobol::new(spp, seed))),
        4 => ("halton", boxed(Halton::new(spp, seed))),
        5 => {
            let z = ZSobol::new(spp, seed, UVec2::new(width, height)).map_err(|e| {
                failure(
                    StrataStatus::InvalidArgument,
                    format!("zsobol sampler: {e}"),
                )
            })?;
            ("zsobol", boxed(Some(z)))
        }
        k => {
            return Err(failure(
                StrataStatus::InvalidArgument,
                format!("sampler kind {k} is unknown (0 to 5: STRATA_SAMPLER_KIND_*)"),
            ));
        }
    };
    let inner = made.ok_or_else(|| {
        failure(
            StrataStatus::InvalidArgument,
            format!("the {name} sampler takes no {spp} samples per pixel"),
        )
    })?;
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
unsafe fn sampler<'a>(s: *mut StrataSampler) -> Result<&'a mut StrataSampler, Failure> {
    // SAFETY: a live handle, used by this thread only, per the contract.
    unsafe { s.as_mut() }.ok_or_else(|| null("sampler"))
}

/// Writes the first `dims` dimensions of the current pixel sample to
/// `out`: values 0 and 1 are the position in the pixel (`pixel_2d`), then
/// pairs from `next_2d`, and the last from `next_1d` when `dims` is odd
/// (one dimension: the position's x).
fn draw(s: &mut dyn Sampler, out: &mut [f32]) {
    let dims = out.len();
    if dims == 0 {
        return;
    }
    let p = s.pixel_2d();
    out[0] = p.x;
    if dims == 1 {
        return;
    }
    out[1] = p.y;
    let mut k = 2;
    while k + 1 < dims {
        let v = s.next_2d();
        out[k] = v.x;
        out[k + 1] = v.y;
        k += 2;
    }
    if k < dims {
        out[k] = s.next_1d();
    }
}

/// Begins sample `index` of pixel `(px, py)`: the dimension goes back to
/// 2 and every value is a function of (kind, spp, seed, pixel, index).
///
/// # Safety
/// `sampler` must be null (refused) or a live sampler no other thread
/// uses during the call.
#[unsafe(no_mangle)]
pub unsafe extern "C" fn strata_sampler_start(
    sampler_: *mut StrataSampler,
    px: u32,
    py: u32,
    index: u32,
) -> StrataStatus {
    guard(|| {
        // SAFETY: per this function's contract.
        let s = unsafe { sampler(sampler_) }?;
        s.inner.start_pixel_sample(UVec2::new(px, py), index);
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
    sampler_: *mut StrataSampler,
    out: *mut f32,
    out_len: usize,
) -> StrataStatus {
    guard(|| {
        // SAFETY: per this function's contract.
        let (s, out) = unsafe { (sampler(sampler_)?, output(out, out_len, "out")?) };
        let out = room(out, 2, "out")?;
        let p = s.inner.pixel_2d();
        out.copy_from_slice(&[p.x, p.y]);
        Ok(())
    })
}

/// The next dimension, in `[0, 1)`, into `out[0]`.
///
/// # Safety
/// As [`strata_sampler_pixel_2d`].
#[unsafe(no_mangle)]
pub unsafe extern "C" fn strata_sampler_next_1d(
    sampler_: *mut StrataSampler,
    out: *mut f32,
    out_len: usize,
) -> StrataStatus {
    guard(|| {
        // SAFETY: per this function's contract.
        let (s, out) = unsafe { (sampler(sampler_)?, output(out, out_len, "out")?) };
        let out = room(out, 1, "out")?;
        out[0] = s.inner.next_1d();
        Ok(())
    })
}

/// The next two dimensions, in `[0, 1)²`, into `out[0..2]`.
///
/// # Safety
/// As [`strata_sampler_pixel_2d`].
#[unsafe(no_mangle)]
pub unsafe extern "C" fn strata_sampler_next_2d(
    sampler_: *mut StrataSampler,
    out: *mut f32,
    out_len: usize,
) -> StrataStatus {
    guard(|| {
        // SAFETY: per this function's contract.
        let (s, out) = unsafe { (sampler(sampler_)?, output(out, out_len, "out")?) };
        let out = room(out, 2, "out")?;
        let v = s.inner.next_2d();
        out.copy_from_slice(&[v.x, v.y]);
        Ok(())
    })
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
    sampler_: *mut StrataSampler,
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
                sampler(sampler_)?,
                input(pixels, pixels_len, "pixels")?,
                input(indices, indices_len, "indices")?,
                output(out, out_len, "out")?,
            )
        };
        let n = indices.len();
        if pixels.len() != times(n, 2, "pixels")? {
            return Err(failure(
                StrataStatus::ShortBuffer,
                format!(
                    "pixels holds {} values; {n} samples need {} (x, y per sample)",
                    pixels.len(),
                    2 * n
                ),
            ));
        }
        let dims = dims as usize;
        let out = room(out, times(n, dims, "out")?, "out")?;
        if dims == 0 {
            return Ok(());
        }
        for ((row, pixel), &index) in out
            .chunks_exact_mut(dims)
            .zip(pixels.chunks_exact(2))
            .zip(indices)
        {
            s.inner
                .start_pixel_sample(UVec2::new(pixel[0], pixel[1]), index);
            draw(s.inner.as_mut(), row);
        }
        Ok(())
    })
}

/// The sampler's samples per pixel into `*out`.
///
/// # Safety
/// `sampler` as in [`strata_sampler_start`]; `out` null (refused) or
/// valid for one `uint32_t`.
#[unsafe(no_mangle)]
pub unsafe extern "C" fn strata_sampler_spp(
    sampler_: *mut StrataSampler,
    out: *mut u32,
) -> StrataStatus {
    guard(|| {
        // SAFETY: per this function's contract.
        let (s, out) = unsafe { (sampler(sampler_)?, output(out, 1, "out")?) };
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

/// A mapping's arities: floats per sample `u`, floats per point.
fn arity(kind: u32) -> Result<(usize, usize), Failure> {
    Ok(match kind {
        0..=2 | 6 | 7 => (2, 3),
        3 | 4 => (2, 2),
        5 => (3, 3),
        k => {
            return Err(failure(
                StrataStatus::InvalidArgument,
                format!("mapping kind {k} is unknown (0 to 7: STRATA_MAPPING_*)"),
            ));
        }
    })
}

/// Rows of `width` floats in `values`, or a failure when it does not
/// split into them.
fn rows(values: &[f32], width: usize, what: &str) -> Result<usize, Failure> {
    if !values.len().is_multiple_of(width) {
        return Err(failure(
            StrataStatus::ShortBuffer,
            format!(
                "{what} holds {} floats, not a whole number of {width}-float rows",
                values.len()
            ),
        ));
    }
    Ok(values.len() / width)
}

/// Which operation of a mapping.
#[derive(Clone, Copy)]
enum Op {
    Sample,
    Pdf,
    Invert,
}

/// One operation over arrays: `input` rows in, `out` rows out.
///
/// # Safety
/// The arrays as the public calls document.
unsafe fn map_arrays(
    op: Op,
    kind: u32,
    cone: f32,
    values: *const f32,
    values_len: usize,
    out: *mut f32,
    out_len: usize,
) -> StrataStatus {
    guard(|| {
        let (u_dims, p_dims) = arity(kind)?;
        let (in_dims, out_dims) = match op {
            Op::Sample => (u_dims, p_dims),
            Op::Pdf => (p_dims, 1),
            Op::Invert => (p_dims, u_dims),
        };
        // SAFETY: per the calling function's contract.
        let (values, out) = unsafe {
            (
                input(values, values_len, "values")?,
                output(out, out_len, "out")?,
            )
        };
        let n = rows(values, in_dims, "values")?;
        let out = room(out, times(n, out_dims, "out")?, "out")?;
        let cone = if kind == 7 {
            Cone::from_sin2(cone)
        } else {
            Cone::from_cos(cone)
        };
        let v2 = |r: &[f32]| Vec2::new(r[0], r[1]);
        let v3 = |r: &[f32]| Vec3::new(r[0], r[1], r[2]);
        for (r, o) in values
            .chunks_exact(in_dims)
            .zip(out.chunks_exact_mut(out_dims))
        {
            match (op, kind) {
                (Op::Sample, 0) => {
                    o.copy_from_slice(&mapping::sample_uniform_sphere(v2(r)).to_array())
                }
                (Op::Sample, 1) => {
                    o.copy_from_slice(&mapping::sample_uniform_hemisphere(v2(r)).to_array())
                }
                (Op::Sample, 2) => {
                    o.copy_from_slice(&mapping::sample_cosine_hemisphere(v2(r)).to_array())
                }
                (Op::Sample, 3) => {
                    o.copy_from_slice(&mapping::sample_concentric_disk(v2(r)).to_array())
                }
                (Op::Sample, 4) => o.copy_from_slice(&mapping::sample_polar_disk(v2(r)).to_array()),
                (Op::Sample, 5) => {
                    o.copy_from_slice(&mapping::sample_uniform_ball(v3(r)).to_array())
                }
                (Op::Sample, _) => {
                    o.copy_from_slice(&mapping::sample_uniform_cone(v2(r), cone).to_array())
                }
                (Op::Pdf, 0) => o[0] = mapping::pdf_uniform_sphere(v3(r)),
                (Op::Pdf, 1) => o[0] = mapping::pdf_uniform_hemisphere(v3(r)),
                (Op::Pdf, 2) => o[0] = mapping::pdf_cosine_hemisphere(v3(r)),
                (Op::Pdf, 3) => o[0] = mapping::pdf_concentric_disk(v2(r)),
                (Op::Pdf, 4) => o[0] = mapping::pdf_polar_disk(v2(r)),
                (Op::Pdf, 5) => o[0] = mapping::pdf_uniform_ball(v3(r)),
                (Op::Pdf, _) => o[0] = mapping::pdf_uniform_cone(v3(r), cone),
                (Op::Invert, 0) => {
                    o.copy_from_slice(&mapping::invert_uniform_sphere(v3(r)).to_array())
                }
                (Op::Invert, 1) => {
                    o.copy_from_slice(&mapping::invert_uniform_hemisphere(v3(r)).to_array())
                }
                (Op::Invert, 2) => {
                    o.copy_from_slice(&mapping::invert_cosine_hemisphere(v3(r)).to_array())
                }
                (Op::Invert, 3) => {
                    o.copy_from_slice(&mapping::invert_concentric_disk(v2(r)).to_array())
                }
                (Op::Invert, 4) => o.copy_from_slice(&mapping::invert_polar_disk(v2(r)).to_array()),
                (Op::Invert, 5) => {
                    o.copy_from_slice(&mapping::invert_uniform_ball(v3(r)).to_array())
                }
                (Op::Invert, _) => {
                    o.copy_from_slice(&mapping::invert_uniform_cone(v3(r), cone).to_array())
                }
            }
        }
        Ok(())
    })
}

/// Maps each sample row of `u` (2 floats, 3 for the ball) to its point
/// (3 floats, 2 for the disks) in `out`. `cone` is the cone's
/// `cos θmax`, or `sin² θmax` for `STRATA_MAPPING_UNIFORM_CONE_SIN2`
/// (other kinds ignore it). `u_len` must be a whole number of
/// rows; `out_len` at least the points' floats.
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
    unsafe { map_arrays(Op::Sample, kind, cone, u, u_len, out, out_len) }
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
    unsafe { map_arrays(Op::Pdf, kind, cone, points, points_len, out, out_len) }
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
    unsafe { map_arrays(Op::Invert, kind, cone, points, points_len, out, out_len) }
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
        let n = rows(normals, 3, "normals")?;
        if dirs.len() != normals.len() {
            return Err(failure(
                StrataStatus::ShortBuffer,
                format!(
                    "dirs holds {} floats; {n} normals need {}",
                    dirs.len(),
                    normals.len()
                ),
            ));
        }
        let out = room(out, normals.len(), "out")?;
        for (i, ((nr, d), o)) in normals
            .chunks_exact(3)
            .zip(dirs.chunks_exact(3))
            .zip(out.chunks_exact_mut(3))
            .enumerate()
        {
            let nv = Vec3::new(nr[0], nr[1], nr[2]);
            // The rule of the core's unit directions (`Ray::try_new`).
            if Ray::try_new(Vec3::ZERO, nv).is_none() {
                return Err(failure(
                    StrataStatus::InvalidArgument,
                    format!("normal {i} ({nv}) is not unit length (|n·n − 1| ≤ 16 ε)"),
                ));
            }
            let basis = if kind == 1 {
                Onb::from_normal_axis_switch(nv)
            } else {
                Onb::from_normal(nv)
            };
            let dv = Vec3::new(d[0], d[1], d[2]);
            let r = if to_world {
                basis.to_world(dv)
            } else {
                basis.to_local(dv)
            };
            o.copy_from_slice(&r.to_array());
        }
        Ok(())
    })
}

/// Takes each direction of `dirs` (3 floats a row) from the basis about
/// the matching unit normal of `normals` (`z` along the normal) to world
/// space, into `out`. A normal that is not unit length is refused.
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
