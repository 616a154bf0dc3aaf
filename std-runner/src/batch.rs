//! The core's per-sample calls over whole arrays, for the language
//! bindings (the C API in `bindings/c`, the Python package in
//! `bindings/python`): one implementation of each batch loop and of each
//! check of its input, so every language gets the same values and the
//! same refusals. Values are the core's, bit for bit.

use std::fmt;

use anyhow::Result;
use strata::glam::{UVec2, Vec2, Vec3};
use strata::mapping::{self, Cone};
use strata::sampler::draw_row;
use strata::trace::{BVH_MAX_SPHERES, Ray, Sphere};
use strata::{Halton, Independent, Onb, Sampler, Sobol, Stratified, UniformGrid, ZSobol};

use crate::job::SamplerKind;

/// Why a batch call refused its input.
#[derive(Clone, Debug, PartialEq, Eq)]
pub enum BatchError {
    /// An array's length does not fit the call (a short output, half a
    /// row, a size past `usize`).
    Size(String),
    /// A value is out of range (an unknown kind, a normal that is not
    /// unit length, a ray the queries refuse).
    Value(String),
}

impl fmt::Display for BatchError {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self {
            BatchError::Size(m) | BatchError::Value(m) => f.write_str(m),
        }
    }
}

impl std::error::Error for BatchError {}

/// `a · b`, or an error (sizes past `usize`).
pub fn times(a: usize, b: usize, what: &str) -> Result<usize, BatchError> {
    a.checked_mul(b)
        .ok_or_else(|| BatchError::Size(format!("{what}: size overflows")))
}

/// The rows of `width` values in `values`, or an error when it does not
/// split into them.
pub fn rows<T>(values: &[T], width: usize, what: &str) -> Result<usize, BatchError> {
    if !values.len().is_multiple_of(width) {
        return Err(BatchError::Size(format!(
            "{what} holds {} values, not a whole number of {width}-value rows",
            values.len()
        )));
    }
    Ok(values.len() / width)
}

// ------------------------------------------------------------ samplers

/// A sampler of any kind, as its concrete type: a batch runs a loop
/// compiled per kind (no call through a vtable per value).
// Its size does not matter: one lives behind each handle.
#[allow(clippy::large_enum_variant)]
#[derive(Clone, Debug)]
pub enum AnySampler {
    /// [`SamplerKind::Independent`].
    Independent(Independent),
    /// [`SamplerKind::Grid`].
    Grid(UniformGrid),
    /// [`SamplerKind::Stratified`].
    Stratified(Stratified),
    /// [`SamplerKind::Sobol`].
    Sobol(Sobol),
    /// [`SamplerKind::Halton`].
    Halton(Halton),
    /// [`SamplerKind::ZSobol`].
    ZSobol(ZSobol),
}

/// Runs `$body` with `$s` bound to the concrete sampler inside `$any`.
#[macro_export]
#[doc(hidden)]
macro_rules! with_any_sampler {
    ($any:expr, $s:ident => $body:expr) => {
        match $any {
            $crate::batch::AnySampler::Independent($s) => $body,
            $crate::batch::AnySampler::Grid($s) => $body,
            $crate::batch::AnySampler::Stratified($s) => $body,
            $crate::batch::AnySampler::Sobol($s) => $body,
            $crate::batch::AnySampler::Halton($s) => $body,
            $crate::batch::AnySampler::ZSobol($s) => $body,
        }
    };
}

impl AnySampler {
    /// The sampler of `kind` for `spp`, `seed` and an image of
    /// `resolution` pixels (only [`SamplerKind::ZSobol`] uses it); an
    /// error that says why if the kind refuses them. The one place a kind
    /// becomes a sampler ([`SamplerKind::with_sampler`] calls it).
    pub fn new(kind: SamplerKind, spp: u32, seed: u64, resolution: UVec2) -> Result<Self> {
        let refused = || {
            anyhow::anyhow!(
                "the {} sampler takes no {spp} samples per pixel",
                kind.name()
            )
        };
        Ok(match kind {
            SamplerKind::Independent => {
                AnySampler::Independent(Independent::new(spp, seed).ok_or_else(refused)?)
            }
            SamplerKind::Grid => AnySampler::Grid(UniformGrid::new(spp, seed).ok_or_else(refused)?),
            SamplerKind::Stratified => {
                AnySampler::Stratified(Stratified::new(spp, seed).ok_or_else(refused)?)
            }
            SamplerKind::Sobol => AnySampler::Sobol(Sobol::new(spp, seed).ok_or_else(refused)?),
            SamplerKind::Halton => AnySampler::Halton(Halton::new(spp, seed).ok_or_else(refused)?),
            SamplerKind::ZSobol => AnySampler::ZSobol(
                ZSobol::new(spp, seed, resolution)
                    .map_err(|e| anyhow::anyhow!("the zsobol sampler: {e}"))?,
            ),
        })
    }

    /// The sampler behind the enum, for single draws.
    pub fn as_dyn(&mut self) -> &mut dyn Sampler {
        with_any_sampler!(self, s => s)
    }

    /// Samples per pixel, as built.
    #[must_use]
    pub fn samples_per_pixel(&self) -> u32 {
        with_any_sampler!(self, s => s.samples_per_pixel())
    }

    /// Fills `out` with the first `dims` dimensions of many pixel
    /// samples, one row of `dims` values each ([`draw_row`]): sample `i` is
    /// pixel `(pixels[2i], pixels[2i + 1])`, index `indices[i]`. The
    /// sampler is left at the last sample.
    ///
    /// # Errors
    /// [`BatchError::Size`] unless `pixels` holds `2n` values for the `n`
    /// indices and `out` at least `n · dims`.
    pub fn fill<T: From<f32>>(
        &mut self,
        pixels: &[u32],
        indices: &[u32],
        dims: usize,
        out: &mut [T],
    ) -> Result<(), BatchError> {
        let n = indices.len();
        if pixels.len() != times(n, 2, "pixels")? {
            return Err(BatchError::Size(format!(
                "pixels holds {} values; {n} samples need {} (x, y per sample)",
                pixels.len(),
                2 * n
            )));
        }
        let out = room(out, times(n, dims, "out")?, "out")?;
        if dims == 0 {
            return Ok(());
        }
        let starts = pixels
            .chunks_exact(2)
            .zip(indices)
            .map(|(p, &i)| (UVec2::new(p[0], p[1]), i));
        with_any_sampler!(self, s => fill_rows(s, starts, dims, out));
        Ok(())
    }

    /// Fills `out` with `n = out.len() / dims` samples of one pixel,
    /// indices `first, first + 1, …` (rows as [`AnySampler::fill`]), by
    /// the kind's [`Sampler::fill_run`].
    ///
    /// # Errors
    /// [`BatchError::Size`] if `out` is not whole rows, or the indices
    /// would pass `u32::MAX`.
    pub fn fill_pixel(
        &mut self,
        pixel: UVec2,
        first: u32,
        dims: usize,
        out: &mut [f32],
    ) -> Result<(), BatchError> {
        if dims == 0 {
            return Ok(());
        }
        let n = rows(out, dims, "out")?;
        if u64::from(first) + n as u64 > 1 << 32 {
            return Err(BatchError::Size(format!(
                "{n} samples from index {first} pass the last index, {}",
                u32::MAX
            )));
        }
        with_any_sampler!(self, s => s.fill_run(pixel, first, dims, out));
        Ok(())
    }
}

/// Rows of `D` values: the row's length known to the compiler, so its
/// loop unrolls.
#[inline(always)]
fn rows_of<S: Sampler, T: From<f32>, const D: usize>(
    s: &mut S,
    starts: impl Iterator<Item = (UVec2, u32)>,
    out: &mut [T],
) {
    for (row, (pixel, index)) in out.chunks_exact_mut(D).zip(starts) {
        s.start_pixel_sample(pixel, index);
        draw_row(s, row);
    }
}

/// The batch fill for one sampler kind: rows of up to 16 values by a
/// loop compiled for their length, longer rows by the general loop.
fn fill_rows<S: Sampler, T: From<f32>>(
    s: &mut S,
    starts: impl Iterator<Item = (UVec2, u32)>,
    dims: usize,
    out: &mut [T],
) {
    macro_rules! by_length {
        ($($d:literal)*) => {
            match dims {
                $($d => rows_of::<S, T, $d>(s, starts, out),)*
                _ => {
                    for (row, (pixel, index)) in out.chunks_exact_mut(dims).zip(starts) {
                        s.start_pixel_sample(pixel, index);
                        draw_row(s, row);
                    }
                }
            }
        };
    }
    by_length!(1 2 3 4 5 6 7 8 9 10 11 12 13 14 15 16);
}

/// The first `need` elements of `out`, or an error naming the shortfall.
pub fn room<'a, T>(out: &'a mut [T], need: usize, what: &str) -> Result<&'a mut [T], BatchError> {
    let have = out.len();
    out.get_mut(..need).ok_or_else(|| {
        BatchError::Size(format!(
            "{what} holds {have} elements; the call writes {need}"
        ))
    })
}

// ------------------------------------------------------------ mappings

/// The mappings from the unit square (or cube) to a domain, each with a
/// pdf and an inverse.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Mapping {
    /// `[0,1)² →` the unit sphere, pdf per steradian.
    UniformSphere,
    /// `[0,1)² →` the hemisphere `z ≥ 0`, uniform.
    UniformHemisphere,
    /// `[0,1)² →` the hemisphere `z ≥ 0`, cosine-weighted.
    CosineHemisphere,
    /// `[0,1)² →` the unit disk, Shirley–Chiu concentric.
    ConcentricDisk,
    /// `[0,1)² →` the unit disk, polar.
    PolarDisk,
    /// `[0,1)³ →` the unit ball, pdf per unit volume.
    UniformBall,
    /// `[0,1)² →` the cone about `+z` given by `cos θmax`.
    UniformCone,
    /// The same cone given by `sin² θmax` (`θmax ≤ 90°`): exact for the
    /// tiniest cones, where `cos θmax` rounds to 1.
    UniformConeSin2,
}

impl Mapping {
    /// Every mapping, in the C API's numbering (`STRATA_MAPPING_*`).
    pub const ALL: [Mapping; 8] = [
        Mapping::UniformSphere,
        Mapping::UniformHemisphere,
        Mapping::CosineHemisphere,
        Mapping::ConcentricDisk,
        Mapping::PolarDisk,
        Mapping::UniformBall,
        Mapping::UniformCone,
        Mapping::UniformConeSin2,
    ];

    /// The name the bindings take (`"uniform_sphere"`, …).
    #[must_use]
    pub fn name(self) -> &'static str {
        match self {
            Mapping::UniformSphere => "uniform_sphere",
            Mapping::UniformHemisphere => "uniform_hemisphere",
            Mapping::CosineHemisphere => "cosine_hemisphere",
            Mapping::ConcentricDisk => "concentric_disk",
            Mapping::PolarDisk => "polar_disk",
            Mapping::UniformBall => "uniform_ball",
            Mapping::UniformCone => "uniform_cone",
            Mapping::UniformConeSin2 => "uniform_cone_sin2",
        }
    }

    /// The mapping named `name`.
    ///
    /// # Errors
    /// [`BatchError::Value`] listing the names, for any other.
    pub fn from_name(name: &str) -> Result<Mapping, BatchError> {
        Mapping::ALL
            .into_iter()
            .find(|m| m.name() == name)
            .ok_or_else(|| {
                let names: Vec<&str> = Mapping::ALL.iter().map(|m| m.name()).collect();
                BatchError::Value(format!(
                    "unknown mapping {name:?}: one of {}",
                    names.join(", ")
                ))
            })
    }

    /// Values per sample `u`, values per point.
    #[must_use]
    pub fn arity(self) -> (usize, usize) {
        match self {
            Mapping::ConcentricDisk | Mapping::PolarDisk => (2, 2),
            Mapping::UniformBall => (3, 3),
            _ => (2, 3),
        }
    }

    /// The cone of the two cone mappings from the call's `cone` value
    /// (`cos θmax`, or `sin² θmax` for [`Mapping::UniformConeSin2`]).
    fn cone(self, cone: f32) -> Cone {
        if self == Mapping::UniformConeSin2 {
            Cone::from_sin2(cone)
        } else {
            Cone::from_cos(cone)
        }
    }
}

/// Which operation of a mapping.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum MapOp {
    /// Sample rows in, points out.
    Sample,
    /// Points in, one density each out (per steradian, area or volume).
    Pdf,
    /// Points in, the sample rows that map to them out.
    Invert,
}

impl MapOp {
    /// The operation named `"sample"`, `"pdf"` or `"invert"`.
    ///
    /// # Errors
    /// [`BatchError::Value`] for any other name.
    pub fn from_name(name: &str) -> Result<MapOp, BatchError> {
        match name {
            "sample" => Ok(MapOp::Sample),
            "pdf" => Ok(MapOp::Pdf),
            "invert" => Ok(MapOp::Invert),
            _ => Err(BatchError::Value(format!(
                "unknown operation {name:?}: sample, pdf or invert"
            ))),
        }
    }

    /// Values per input row and per output row of `op` on `m`.
    #[must_use]
    pub fn arity(self, m: Mapping) -> (usize, usize) {
        let (u, p) = m.arity();
        match self {
            MapOp::Sample => (u, p),
            MapOp::Pdf => (p, 1),
            MapOp::Invert => (p, u),
        }
    }
}

/// One operation of mapping `m` over rows: `input` rows in, `out` rows
/// out ([`MapOp::arity`]). `cone` is the cone's parameter (other mappings
/// ignore it; the cone clamps it to its range). Returns the number of
/// rows.
///
/// # Errors
/// [`BatchError::Size`] if `input` is not whole rows or `out` is short;
/// [`BatchError::Value`] for a sample value outside `[0, 1]`, a point
/// value that is not finite, or a NaN cone.
pub fn map_rows(
    op: MapOp,
    m: Mapping,
    cone: f32,
    input: &[f32],
    out: &mut [f32],
) -> Result<usize, BatchError> {
    let (in_dims, out_dims) = op.arity(m);
    let n = rows(input, in_dims, "the input")?;
    let out = room(out, times(n, out_dims, "out")?, "out")?;
    if cone.is_nan() {
        return Err(BatchError::Value("the cone parameter is NaN".into()));
    }
    if op == MapOp::Sample {
        // Samples lie in the unit square (cube); NaN fails the test too.
        if let Some(i) = input.iter().position(|u| !(0.0..=1.0).contains(u)) {
            return Err(BatchError::Value(format!(
                "sample value {i} is {}: samples lie in [0, 1]",
                input[i]
            )));
        }
    } else {
        finite(input, "point value")?;
    }
    let cone = m.cone(cone);
    let v2 = |r: &[f32]| Vec2::new(r[0], r[1]);
    let v3 = |r: &[f32]| Vec3::new(r[0], r[1], r[2]);
    use Mapping as M;
    for (r, o) in input
        .chunks_exact(in_dims)
        .zip(out.chunks_exact_mut(out_dims))
    {
        match op {
            MapOp::Sample => match m {
                M::UniformSphere => {
                    o.copy_from_slice(&mapping::sample_uniform_sphere(v2(r)).to_array())
                }
                M::UniformHemisphere => {
                    o.copy_from_slice(&mapping::sample_uniform_hemisphere(v2(r)).to_array())
                }
                M::CosineHemisphere => {
                    o.copy_from_slice(&mapping::sample_cosine_hemisphere(v2(r)).to_array())
                }
                M::ConcentricDisk => {
                    o.copy_from_slice(&mapping::sample_concentric_disk(v2(r)).to_array())
                }
                M::PolarDisk => o.copy_from_slice(&mapping::sample_polar_disk(v2(r)).to_array()),
                M::UniformBall => {
                    o.copy_from_slice(&mapping::sample_uniform_ball(v3(r)).to_array())
                }
                M::UniformCone | M::UniformConeSin2 => {
                    o.copy_from_slice(&mapping::sample_uniform_cone(v2(r), cone).to_array())
                }
            },
            MapOp::Pdf => {
                o[0] = match m {
                    M::UniformSphere => mapping::pdf_uniform_sphere(v3(r)),
                    M::UniformHemisphere => mapping::pdf_uniform_hemisphere(v3(r)),
                    M::CosineHemisphere => mapping::pdf_cosine_hemisphere(v3(r)),
                    M::ConcentricDisk => mapping::pdf_concentric_disk(v2(r)),
                    M::PolarDisk => mapping::pdf_polar_disk(v2(r)),
                    M::UniformBall => mapping::pdf_uniform_ball(v3(r)),
                    M::UniformCone | M::UniformConeSin2 => mapping::pdf_uniform_cone(v3(r), cone),
                }
            }
            MapOp::Invert => match m {
                M::UniformSphere => {
                    o.copy_from_slice(&mapping::invert_uniform_sphere(v3(r)).to_array())
                }
                M::UniformHemisphere => {
                    o.copy_from_slice(&mapping::invert_uniform_hemisphere(v3(r)).to_array())
                }
                M::CosineHemisphere => {
                    o.copy_from_slice(&mapping::invert_cosine_hemisphere(v3(r)).to_array())
                }
                M::ConcentricDisk => {
                    o.copy_from_slice(&mapping::invert_concentric_disk(v2(r)).to_array())
                }
                M::PolarDisk => o.copy_from_slice(&mapping::invert_polar_disk(v2(r)).to_array()),
                M::UniformBall => {
                    o.copy_from_slice(&mapping::invert_uniform_ball(v3(r)).to_array())
                }
                M::UniformCone | M::UniformConeSin2 => {
                    o.copy_from_slice(&mapping::invert_uniform_cone(v3(r), cone).to_array())
                }
            },
        }
    }
    Ok(n)
}

// ------------------------------------------------------------ bases

/// The orthonormal bases about a normal.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Basis {
    /// Duff et al. 2017, right-handed (the default).
    Duff,
    /// The course's axis-switch basis (left-handed).
    AxisSwitch,
}

impl Basis {
    /// The basis named `"duff"` or `"axis_switch"`.
    ///
    /// # Errors
    /// [`BatchError::Value`] for any other name.
    pub fn from_name(name: &str) -> Result<Basis, BatchError> {
        match name {
            "duff" => Ok(Basis::Duff),
            "axis_switch" => Ok(Basis::AxisSwitch),
            _ => Err(BatchError::Value(format!(
                "unknown basis {name:?}: duff or axis_switch"
            ))),
        }
    }
}

/// Refuses a value that is not finite (`what` names one).
fn finite(values: &[f32], what: &str) -> Result<(), BatchError> {
    match values.iter().position(|v| !v.is_finite()) {
        Some(i) => Err(BatchError::Value(format!(
            "{what} {i} is {}: values must be finite",
            values[i]
        ))),
        None => Ok(()),
    }
}

/// Each direction of `dirs` (3 values a row) from the basis about the
/// matching unit normal of `normals` to world space (`to_world`), or
/// back, into `out`.
///
/// # Errors
/// [`BatchError::Size`] for arrays that do not match;
/// [`BatchError::Value`] for a normal that is not unit length (the rule
/// of the core's unit directions, `Ray::try_new`) or a direction value
/// that is not finite.
pub fn onb_rows(
    to_world: bool,
    basis: Basis,
    normals: &[f32],
    dirs: &[f32],
    out: &mut [f32],
) -> Result<(), BatchError> {
    let n = rows(normals, 3, "normals")?;
    if dirs.len() != normals.len() {
        return Err(BatchError::Size(format!(
            "dirs holds {} values; {n} normals need {}",
            dirs.len(),
            normals.len()
        )));
    }
    let out = room(out, normals.len(), "out")?;
    finite(dirs, "direction value")?;
    for (i, ((nr, d), o)) in normals
        .chunks_exact(3)
        .zip(dirs.chunks_exact(3))
        .zip(out.chunks_exact_mut(3))
        .enumerate()
    {
        let nv = Vec3::new(nr[0], nr[1], nr[2]);
        if Ray::try_new(Vec3::ZERO, nv).is_none() {
            return Err(BatchError::Value(format!(
                "normal {i} ({nv}) is not unit length (|n·n − 1| ≤ 16 ε)"
            )));
        }
        let b = match basis {
            Basis::Duff => Onb::from_normal(nv),
            Basis::AxisSwitch => Onb::from_normal_axis_switch(nv),
        };
        let dv = Vec3::new(d[0], d[1], d[2]);
        let r = if to_world {
            b.to_world(dv)
        } else {
            b.to_local(dv)
        };
        o.copy_from_slice(&r.to_array());
    }
    Ok(())
}

// ------------------------------------------------------------ spheres and rays

/// Spheres from rows of `x, y, z, radius`: a finite centre (the tree
/// checks its range) and a finite radius of at least 0.
///
/// # Errors
/// [`BatchError::Size`] for a ragged array; [`BatchError::Value`] for more
/// spheres than a tree holds, or naming the first bad sphere.
pub fn spheres_from_rows(rows_in: &[f32]) -> Result<Vec<Sphere>, BatchError> {
    let n = rows(rows_in, 4, "spheres")?;
    if n > BVH_MAX_SPHERES {
        return Err(BatchError::Value(format!(
            "{n} spheres: a tree holds at most {BVH_MAX_SPHERES}"
        )));
    }
    rows_in
        .chunks_exact(4)
        .enumerate()
        .map(|(i, r)| {
            if !r.iter().all(|v| v.is_finite()) || r[3] < 0.0 {
                return Err(BatchError::Value(format!(
                    "spheres[{i}]: ({}, {}, {}) radius {}: a finite centre and a radius of at least 0",
                    r[0], r[1], r[2], r[3]
                )));
            }
            Ok(Sphere::new(Vec3::new(r[0], r[1], r[2]), r[3]))
        })
        .collect()
}

/// A ray's parts: origin, direction, `t_min`, `t_max`.
pub type RayParts = ([f32; 3], [f32; 3], f32, f32);

/// `query` of each ray of `rays` into `out` (one result a ray), each ray
/// checked by [`checked_ray`].
///
/// # Errors
/// [`BatchError::Size`] if `out` is short; [`BatchError::Value`] for the
/// first ray the check refuses (the results are then unspecified).
pub fn query_rays<T>(
    rays: impl ExactSizeIterator<Item = RayParts>,
    out: &mut [T],
    mut query: impl FnMut(&Ray) -> T,
) -> Result<(), BatchError> {
    let out = room(out, rays.len(), "out")?;
    for (i, ((o, d, t0, t1), slot)) in rays.zip(out).enumerate() {
        let Some(ray) = checked_ray(o, d, t0, t1) else {
            return Err(ray_error(i, t0, t1));
        };
        *slot = query(&ray);
    }
    Ok(())
}

/// The core's ray `origin + t · dir`, `t ∈ (t_min, t_max)`, if the values
/// make one: `Ray::try_new`'s rule (a unit direction, which rules out
/// infinite and NaN ones; a finite origin) and no NaN bound, tested
/// without branches (a batch pays a few instructions a ray for it).
#[inline(always)]
#[must_use]
pub fn checked_ray(origin: [f32; 3], dir: [f32; 3], t_min: f32, t_max: f32) -> Option<Ray> {
    let (o, d) = (Vec3::from(origin), Vec3::from(dir));
    let unit = (d.dot(d) - 1.0).abs() <= 16.0 * f32::EPSILON;
    // 0 · x is 0 for a finite x and NaN for an infinite or NaN one.
    let finite = (o * 0.0).dot(Vec3::ONE) == 0.0;
    let bounds = !t_min.is_nan() & !t_max.is_nan();
    (unit & finite & bounds).then(|| Ray::new(o, d).with_range(t_min, t_max))
}

/// Why ray `i` (bounds `t_min`, `t_max`) was refused by [`checked_ray`].
#[cold]
#[must_use]
pub fn ray_error(i: usize, t_min: f32, t_max: f32) -> BatchError {
    let why = if t_min.is_nan() || t_max.is_nan() {
        "t_min or t_max is NaN"
    } else {
        "the origin is not finite or the direction not unit length"
    };
    BatchError::Value(format!("rays[{i}]: {why}"))
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_batch_equals_the_single_draws_for_every_kind_and_row_length() {
        let pixels = [12, 34, 0, 0, 319, 179];
        let indices = [5, 0, 15];
        for kind in SamplerKind::ALL {
            let mut s = AnySampler::new(kind, 16, 2026, UVec2::new(320, 180)).unwrap();
            for dims in [1, 2, 3, 7, 16, 17, 40] {
                let mut rows = vec![0.0f64; 3 * dims];
                s.fill(&pixels, &indices, dims, &mut rows).unwrap();
                for (i, row) in rows.chunks_exact(dims).enumerate() {
                    let one = s.as_dyn();
                    one.start_pixel_sample(
                        UVec2::new(pixels[2 * i], pixels[2 * i + 1]),
                        indices[i],
                    );
                    let p = one.pixel_2d();
                    let mut want = vec![f64::from(p.x), f64::from(p.y)];
                    while want.len() + 1 < dims {
                        let v = one.next_2d();
                        want.extend([f64::from(v.x), f64::from(v.y)]);
                    }
                    if want.len() < dims {
                        want.push(f64::from(one.next_1d()));
                    }
                    want.truncate(dims);
                    assert_eq!(row, &want[..], "{kind:?}, {dims} dims, row {i}");
                }
            }
            // One pixel's run of indices equals the same rows by pixel list.
            let mut run = vec![0.0f32; 5 * 4];
            s.fill_pixel(UVec2::new(3, 4), 7, 4, &mut run).unwrap();
            let mut listed = vec![0.0f32; 5 * 4];
            s.fill(&[3, 4].repeat(5), &[7, 8, 9, 10, 11], 4, &mut listed)
                .unwrap();
            assert_eq!(run, listed, "{kind:?}");
        }
    }

    #[test]
    fn batch_sizes_are_checked() {
        let mut s = AnySampler::new(SamplerKind::Sobol, 16, 1, UVec2::ONE).unwrap();
        let mut out = [0.0f32; 8];
        assert!(matches!(
            s.fill(&[1, 2], &[0], 9, &mut out),
            Err(BatchError::Size(_))
        ));
        assert!(matches!(
            s.fill(&[1], &[0], 2, &mut out),
            Err(BatchError::Size(_))
        ));
        assert!(s.fill::<f32>(&[], &[], 4, &mut []).is_ok());
        assert!(matches!(
            s.fill_pixel(UVec2::ZERO, u32::MAX, 2, &mut out[..4]),
            Err(BatchError::Size(_))
        ));
        assert!(
            s.fill_pixel(UVec2::ZERO, u32::MAX, 2, &mut out[..2])
                .is_ok()
        );
        assert!(matches!(
            s.fill_pixel(UVec2::ZERO, 0, 3, &mut out),
            Err(BatchError::Size(_))
        ));
        assert!(AnySampler::new(SamplerKind::Grid, 0, 1, UVec2::ONE).is_err());
        assert!(AnySampler::new(SamplerKind::ZSobol, 4, 1, UVec2::ZERO).is_err());
    }

    #[test]
    fn mappings_round_trip_and_refuse_ragged_rows() {
        let u = [0.25f32, 0.75, 0.5, 0.125, 0.875, 0.375];
        for m in Mapping::ALL {
            assert_eq!(Mapping::from_name(m.name()), Ok(m));
            let (du, dp) = m.arity();
            let n = u.len() / du;
            let input = &u[..n * du];
            let mut points = vec![0.0; n * dp];
            assert_eq!(map_rows(MapOp::Sample, m, 0.25, input, &mut points), Ok(n));
            let mut back = vec![0.0; n * du];
            map_rows(MapOp::Invert, m, 0.25, &points, &mut back).unwrap();
            for (a, b) in input.iter().zip(&back) {
                assert!((a - b).abs() < 1e-4, "{m:?}: {a} back as {b}");
            }
            let mut pdf = vec![0.0; n];
            map_rows(MapOp::Pdf, m, 0.25, &points, &mut pdf).unwrap();
            assert!(pdf.iter().all(|p| *p > 0.0), "{m:?}: {pdf:?}");
            assert!(matches!(
                map_rows(MapOp::Sample, m, 0.25, &u[..du + 1], &mut points),
                Err(BatchError::Size(_))
            ));
        }
        assert!(
            matches!(Mapping::from_name("sphere"), Err(BatchError::Value(m)) if m.contains("uniform_sphere"))
        );
    }

    #[test]
    fn bases_refuse_normals_that_are_not_unit() {
        let mut out = [0.0; 3];
        let d = [0.3, -0.2, 0.9];
        assert!(onb_rows(true, Basis::Duff, &[0.0, 0.0, 1.0], &d, &mut out).is_ok());
        assert!(matches!(
            onb_rows(true, Basis::AxisSwitch, &[0.0, 0.0, 2.0], &d, &mut out),
            Err(BatchError::Value(_))
        ));
        assert!(matches!(
            onb_rows(false, Basis::Duff, &[0.0, 0.0, 1.0], &d[..2], &mut out),
            Err(BatchError::Size(_))
        ));
    }

    #[test]
    fn bad_values_are_refused_by_every_binding_alike() {
        let mut out = [0.0; 8];
        let m = Mapping::UniformSphere;
        for bad in [f32::NAN, -0.5, 1.5, f32::INFINITY] {
            assert!(matches!(
                map_rows(MapOp::Sample, m, 0.0, &[0.5, bad], &mut out),
                Err(BatchError::Value(_))
            ));
        }
        assert!(map_rows(MapOp::Sample, m, 0.0, &[0.0, 1.0], &mut out).is_ok());
        assert!(matches!(
            map_rows(MapOp::Pdf, m, 0.0, &[0.0, f32::NAN, 1.0], &mut out),
            Err(BatchError::Value(_))
        ));
        assert!(matches!(
            map_rows(
                MapOp::Sample,
                Mapping::UniformCone,
                f32::NAN,
                &[0.5, 0.5],
                &mut out
            ),
            Err(BatchError::Value(_))
        ));
        assert!(matches!(
            onb_rows(
                true,
                Basis::Duff,
                &[0.0, 0.0, 1.0],
                &[f32::NAN, 0.0, 0.0],
                &mut out
            ),
            Err(BatchError::Value(_))
        ));
        assert_eq!(MapOp::from_name("pdf"), Ok(MapOp::Pdf));
        assert_eq!(Basis::from_name("axis_switch"), Ok(Basis::AxisSwitch));
        assert!(MapOp::from_name("sampel").is_err() && Basis::from_name("frisvad").is_err());
        assert_eq!(
            spheres_from_rows(&[0.0, 0.0, -3.0, 1.0]).map(|v| v.len()),
            Ok(1)
        );
        for bad in [
            [0.0, 0.0, 0.0, -1.0],
            [0.0, f32::NAN, 0.0, 1.0],
            [0.0, 0.0, 0.0, f32::INFINITY],
        ] {
            assert!(
                matches!(spheres_from_rows(&bad), Err(BatchError::Value(m)) if m.contains("spheres[0]"))
            );
        }
        let rays = [([0.0, 0.0, 0.0], [0.0, 0.0, -1.0], 0.0, f32::INFINITY); 2];
        let mut hits = [0.0f32; 2];
        assert!(query_rays(rays.into_iter(), &mut hits, |r| r.dir.z).is_ok());
        assert_eq!(hits, [-1.0, -1.0]);
        assert!(matches!(
            query_rays(rays.into_iter(), &mut hits[..1], |_| 0.0),
            Err(BatchError::Size(_))
        ));
    }

    #[test]
    fn rays_are_checked() {
        let o = [0.0; 3];
        let z = [0.0, 0.0, 1.0];
        assert!(checked_ray(o, z, 0.0, f32::INFINITY).is_some());
        assert!(checked_ray(o, [0.0, 0.0, 2.0], 0.0, 1.0).is_none());
        assert!(checked_ray([f32::INFINITY, 0.0, 0.0], z, 0.0, 1.0).is_none());
        assert!(checked_ray(o, z, f32::NAN, 1.0).is_none());
        assert!(ray_error(3, f32::NAN, 1.0).to_string().contains("rays[3]"));
    }
}
