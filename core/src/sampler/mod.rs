//! Pixel samplers: where each sample of a pixel puts its pixel position and
//! its random numbers.
//!
//! # Dimensions
//!
//! A pixel sample is a point in `[0, 1)^d`. Dimensions 0 and 1 are the
//! position in the pixel, returned by [`Sampler::pixel_2d`] whenever it is
//! called. [`Sampler::next_1d`] and [`Sampler::next_2d`] then hand out
//! dimensions 2, 3, … in call order: a 1D draw takes one, a 2D draw two.
//! Every kind but [`Sobol`] starts a draw at the dimension after the
//! previous draw's; Sobol' aligns a 2D draw to an even dimension.
//!
//! # Determinism
//!
//! Every value is a pure function of `(seed, pixel, sample index,
//! dimension)` and of what the sampler was built with (its spp; for
//! [`ZSobol`] also the image resolution): [`Sampler::start_pixel_sample`]
//! rebuilds all state from those numbers (see [`crate::rng`]), so samples may be drawn in any order,
//! on any thread, in any tile, and revisiting a sample gives the same bits.
//!
//! # Kinds
//!
//! | kind | pixel dimensions | other dimensions |
//! |---|---|---|
//! | [`Independent`] | uniform random | uniform random |
//! | [`UniformGrid`] | centres of an `nx × ny` grid, raster order | centres of `spp` strata, shuffled |
//! | [`Stratified`] | jittered `nx × ny` strata, shuffled | jittered strata, shuffled |
//! | [`Sobol`] | Owen-scrambled Sobol' `(0, 2)`-sequence | padded Owen-scrambled Sobol', in pairs |
//! | [`Halton`] | Owen-scrambled Halton, bases 2 and 3 | Owen-scrambled Halton, the next prime bases |
//! | [`ZSobol`] | one Owen-scrambled Sobol' sequence over the image, along a hashed Morton curve | the same, keyed per dimension |
//!
//! `nx × ny = spp` is the factorisation closest to square with `nx ≥ ny`
//! ([`grid_dims`]): 16 → 4 × 4, 30 → 6 × 5, 12 → 4 × 3, 7 → 7 × 1. A prime
//! spp therefore gets strips; every stratum still gets exactly one sample.
//! A 1D dimension has `spp` strata; a 2D one uses the `nx × ny` grid.
//!
//! Strata are shuffled per dimension (pbrt's `StratifiedSampler`) with
//! Kensler's hashed permutation (*Correlated Multi-Jittered Sampling*,
//! Pixar 2013), keyed by `(seed, pixel, dimension, pass)`, so a bounce
//! direction is as evenly spread as the pixel position yet not correlated
//! with it. A sample index `i ≥ spp` belongs to pass `i / spp` and stratum
//! slot `i % spp`: every run of `spp` consecutive indices starting at a
//! multiple of `spp` is a fresh stratified set.
//!
//! # Limits
//!
//! What each kind does at every edge a caller can reach (the tests in
//! `tests/sampling/limits.rs` check each):
//!
//! | kind | spp | stratifies | dimensions | index `i ≥ spp` |
//! |---|---|---|---|---|
//! | [`Independent`] | 1 to `u32::MAX` | nothing | unbounded | a stream of its own |
//! | [`UniformGrid`], [`Stratified`] | 1 to [`MAX_STRATA_SPP`] `= 2²⁴`; `new` returns `None` beyond | `spp` strata per dimension | unbounded | pass `i / spp`: a fresh stratified set |
//! | [`Sobol`] | 1 to `u32::MAX` | `2^k` strata with `2^k` samples up to `k = 24`, the `f32` resolution; with `2^k > 2²⁴` samples each of the `2²⁴` values of a dimension comes `2^(k−24)` times | unbounded | the sequence goes on: every aligned block of `2^k` indices is a net |
//! | [`Halton`] | 1 to `u32::MAX` | `b^k` strata in base `b`, `b^k` the least power `≥ spp`, at most `2²⁴` | 0–63: the prime bases 2–311; from 64 on: independent uniforms hashed from `(seed, pixel, index, d)` | blocks of `b^k` indices, each a fresh stratified set |
//! | [`ZSobol`] | 1 to `u32::MAX`, as long as `2r + k ≤ 64` bits (`2^r ≥` the larger side, `2^k ≥ spp`); [`ZSobol::new`] refuses beyond | with `spp = 2^k`: `2^k` strata per pixel, `4^a · 2^k` per aligned `2^a × 2^a` pixel block, up to the `f32` resolution of `2²⁴` strata as for [`Sobol`]; other spp take the first `spp` slots of `2^k` | unbounded | pass `i / spp`: a fresh, independently scrambled pattern |
//!
//! Apart from [`ZSobol`] (whose 64-bit index is the point), no kind forms a
//! global index from the pixel and the sample index: the
//! index is the pixel's own `u32`, and the pixel is hashed with `px` and
//! `py` in separate halves of a 64-bit word. So nothing overflows however
//! large the image or spp: every pixel in `u32 × u32` and every index up
//! to `u32::MAX` is valid and gets values like any other. (For the strata
//! samplers the last pass, `u32::MAX / spp`, ends at `u32::MAX` and is
//! short unless spp divides `2³²`.) The dimension counter is a `u32` as
//! well: after `2³²` draws in one sample it wraps to dimension 0.
//!
//! [`ZSobol`] alone is built for an image resolution and correlates
//! neighbouring pixels on purpose (their samples complement each other,
//! so the error is blue noise); the others treat every pixel
//! independently.
//!
//! Samplers are `Clone + Debug`, never `Copy` (a silent copy would repeat its
//! samples), and have no `Default` that would hide a seed. They are `Send +
//! Sync`; each thread owns its own.

use glam::{UVec2, Vec2};

use crate::rng::pixel_hash;

mod halton;
mod independent;
mod permute;
mod rng;
mod sobol;
mod strata;
mod zsobol;

pub use halton::Halton;
pub use independent::Independent;
pub use permute::permute;
pub use rng::SamplerRng;
pub use sobol::Sobol;
pub use strata::{MAX_STRATA_SPP, Strata, Stratified, UniformGrid};
pub use zsobol::{ZSobol, ZSobolError};

/// The interface every sampler kind implements; generic code calls it with
/// static dispatch.
///
/// ```
/// use glam::UVec2;
/// use strata::sampler::{Sampler, Stratified};
/// let mut s = Stratified::new(16, 42).unwrap();
/// s.start_pixel_sample(UVec2::new(3, 7), 5);
/// let p = s.pixel_2d();
/// let d = s.next_2d();
/// assert!(p.cmpge(Vec2::ZERO).all() && p.cmplt(Vec2::ONE).all());
/// // Revisiting the sample gives the same values.
/// s.start_pixel_sample(UVec2::new(3, 7), 5);
/// assert_eq!((s.pixel_2d(), s.next_2d()), (p, d));
/// # use glam::Vec2;
/// ```
pub trait Sampler {
    /// Samples per pixel, fixed at construction (at least 1).
    fn samples_per_pixel(&self) -> u32;

    /// Begins sample `index` of `pixel`: resets the dimension to 2 and
    /// rebuilds all state from `(seed, pixel, index)`.
    fn start_pixel_sample(&mut self, pixel: UVec2, index: u32);

    /// The position in the pixel (dimensions 0 and 1), in `[0, 1)²`, with
    /// `(0, 0)` the pixel's top-left corner. Does not advance the dimension.
    fn pixel_2d(&mut self) -> Vec2;

    /// The next dimension, in `[0, 1)`.
    fn next_1d(&mut self) -> f32;

    /// The next two dimensions, in `[0, 1)²`.
    fn next_2d(&mut self) -> Vec2;

    /// Skips the next dimension: the sampler is left where
    /// [`Sampler::next_1d`] would leave it, so every later dimension keeps
    /// its value, but the value is not made (a path vertex that does not
    /// use a dimension skips it; samplers that can jump do so for less).
    ///
    /// ```
    /// use glam::UVec2;
    /// use strata::sampler::{Independent, Sampler};
    /// let (mut a, mut b) = (Independent::new(4, 9).unwrap(), Independent::new(4, 9).unwrap());
    /// a.start_pixel_sample(UVec2::new(1, 2), 3);
    /// b.start_pixel_sample(UVec2::new(1, 2), 3);
    /// a.next_1d();
    /// a.next_2d();
    /// b.skip_1d();
    /// b.skip_2d();
    /// assert_eq!(a.next_2d(), b.next_2d());
    /// ```
    #[inline]
    fn skip_1d(&mut self) {
        self.next_1d();
    }

    /// Skips the next two dimensions as [`Sampler::next_2d`] takes them
    /// (see [`Sampler::skip_1d`]).
    #[inline]
    fn skip_2d(&mut self) {
        self.next_2d();
    }

    /// Fills `out` with rows of `dims` values for samples `first, first +
    /// 1, …` of `pixel`, `out.len() / dims` rows ([`draw_row`]'s order:
    /// the position, then `next_2d` pairs, then a `next_1d` for an odd
    /// last): the same bits as those calls, made faster where a kind can
    /// share work between consecutive samples (Sobol' does eight at
    /// once). Indices wrap past `u32::MAX`; the sampler is left at the
    /// last sample. Nothing is written for `dims = 0`.
    ///
    /// ```
    /// use glam::UVec2;
    /// use strata::sampler::{Sampler, Sobol, draw_row};
    /// let mut s = Sobol::new(64, 7).unwrap();
    /// let mut run = [0.0; 5 * 3];
    /// s.fill_run(UVec2::new(4, 2), 10, 5, &mut run);
    /// let mut row = [0.0; 5];
    /// s.start_pixel_sample(UVec2::new(4, 2), 12);
    /// draw_row(&mut s, &mut row);
    /// assert_eq!(row, run[10..15]);
    /// ```
    #[inline]
    fn fill_run(&mut self, pixel: UVec2, first: u32, dims: usize, out: &mut [f32]) {
        if dims == 0 {
            return;
        }
        for (k, row) in out.chunks_exact_mut(dims).enumerate() {
            self.start_pixel_sample(pixel, first.wrapping_add(k as u32));
            draw_row(self, row);
        }
    }
}

/// The first `out.len()` dimensions of the current pixel sample, in the
/// renderer's order: values 0 and 1 are the position in the pixel
/// ([`Sampler::pixel_2d`]), then pairs from [`Sampler::next_2d`], and the
/// last from [`Sampler::next_1d`] when the length is odd (one value: the
/// position's x). A camera ray takes the position, then each bounce its
/// pairs; the language bindings' batch calls give these rows.
///
/// ```
/// use glam::UVec2;
/// use strata::sampler::{Halton, Sampler, draw_row};
/// let mut s = Halton::new(16, 3).unwrap();
/// s.start_pixel_sample(UVec2::new(1, 1), 2);
/// let mut row = [0.0; 5];
/// draw_row(&mut s, &mut row);
/// s.start_pixel_sample(UVec2::new(1, 1), 2);
/// let (p, a) = (s.pixel_2d(), s.next_2d());
/// assert_eq!(row, [p.x, p.y, a.x, a.y, s.next_1d()]);
/// ```
#[inline(always)]
pub fn draw_row<S: Sampler + ?Sized, T: From<f32>>(s: &mut S, out: &mut [T]) {
    let Some((first, rest)) = out.split_first_mut() else {
        return;
    };
    let p = s.pixel_2d();
    *first = p.x.into();
    let Some((second, rest)) = rest.split_first_mut() else {
        return;
    };
    *second = p.y.into();
    let mut pairs = rest.chunks_exact_mut(2);
    for pair in &mut pairs {
        let v = s.next_2d();
        pair[0] = v.x.into();
        pair[1] = v.y.into();
    }
    if let [last] = pairs.into_remainder() {
        *last = s.next_1d().into();
    }
}
/// The `(nx, ny)` grid of `spp` strata closest to square, `nx ≥ ny`,
/// `nx · ny = spp`; `(0, 0)` for `spp = 0`.
///
/// ```
/// use strata::sampler::grid_dims;
/// assert_eq!(grid_dims(16), (4, 4));
/// assert_eq!(grid_dims(30), (6, 5));
/// assert_eq!(grid_dims(7), (7, 1));
/// ```
#[inline]
#[must_use]
pub const fn grid_dims(spp: u32) -> (u32, u32) {
    if spp == 0 {
        return (0, 0);
    }
    let mut ny = isqrt(spp);
    while !spp.is_multiple_of(ny) {
        ny -= 1;
    }
    (spp / ny, ny)
}

/// `floor(sqrt(n))`, exactly, by integer Newton iteration.
const fn isqrt(n: u32) -> u32 {
    if n < 2 {
        return n;
    }
    let n = n as u64;
    let mut x = n;
    let mut y = x.div_ceil(2);
    while y < x {
        x = y;
        y = (x + n / x) / 2;
    }
    x as u32
}
/// The point of stratum `s` of `n` at jitter `j ∈ [0, 1)`: `(s + j) / n`,
/// rounded to an `f32` that is guaranteed to lie in `[s/n, (s+1)/n)`, so
/// `floor(v · n) = s` holds exactly (it is checked exactly in `f64`).
/// `inv_n` is `1 / n` in `f64`; multiplying by it instead of dividing may be
/// off by an ulp, which the check repairs.
#[inline]
fn stratum_point(s: u32, j: f32, n: u32, inv_n: f64) -> f32 {
    let (sf, nf) = (s as f64, n as f64);
    let mut v = ((sf + j as f64) * inv_n) as f32;
    // An f32 (24-bit significand) times an integer below 2^29 fits the 53
    // bits of an f64 exactly; n ≤ MAX_STRATA_SPP = 2^24 (so is s + 1).
    if v as f64 * nf >= sf + 1.0 {
        v = f32::from_bits(v.to_bits() - 1);
    } else if (v as f64 * nf) < sf {
        v = f32::from_bits(v.to_bits() + 1);
    }
    v
}
/// The pixel a sampler is on and its [`pixel_hash`], kept while the
/// sampler stays on that pixel: a renderer takes all the samples of a
/// pixel in a row, so the two mixes are paid once per pixel, not per
/// sample. Only a cache: every value is the same without it.
#[derive(Clone, Debug)]
struct PixelKey {
    seed: u64,
    pixel: UVec2,
    key: u64,
}

impl PixelKey {
    fn new(seed: u64) -> Self {
        Self {
            seed,
            pixel: UVec2::ZERO,
            key: pixel_hash(seed, UVec2::ZERO),
        }
    }

    /// Moves to `pixel`; `true` if it is another pixel than before.
    #[inline]
    fn set(&mut self, pixel: UVec2) -> bool {
        if pixel == self.pixel {
            return false;
        }
        self.pixel = pixel;
        self.key = pixel_hash(self.seed, pixel);
        true
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn grid_dims_factorise_closest_to_square() {
        for spp in 1..=2000u32 {
            let (nx, ny) = grid_dims(spp);
            assert_eq!(nx * ny, spp);
            assert!(nx >= ny);
            // No divisor lies strictly between ny and sqrt(spp).
            for d in ny + 1..=isqrt(spp) {
                assert_ne!(spp % d, 0, "spp {spp}: {d} is closer to square");
            }
        }
        assert_eq!(grid_dims(0), (0, 0));
        assert_eq!(grid_dims(u32::MAX), (65537, 65535));
    }

    #[test]
    fn isqrt_exact() {
        for n in (0..100_000u32).chain([u32::MAX, u32::MAX - 1, 65535 * 65535, 65535 * 65535 - 1]) {
            let r = isqrt(n) as u64;
            assert!(r * r <= n as u64 && (r + 1) * (r + 1) > n as u64, "{n}");
        }
    }

    #[test]
    fn stratum_point_stays_in_its_stratum() {
        let hi = crate::rng::ONE_MINUS_EPSILON;
        for n in [1u32, 2, 3, 7, 10, 49, 100, 1000, 4095, 65535] {
            for s in [0, n / 3, n / 2, n - 1] {
                for j in [0.0, 0.5, hi] {
                    let v = stratum_point(s, j, n, 1.0 / n as f64);
                    assert_eq!((v as f64 * n as f64).floor() as u32, s, "n {n} s {s} j {j}");
                    assert!(v < 1.0);
                }
            }
        }
    }

    #[test]
    fn zero_and_huge_spp_are_refused() {
        assert!(Independent::new(0, 1).is_none());
        assert!(UniformGrid::new(0, 1).is_none());
        assert!(Stratified::new(0, 1).is_none());
        assert!(Stratified::new(MAX_STRATA_SPP + 1, 1).is_none());
        assert!(Stratified::new(MAX_STRATA_SPP, 1).is_some());
        assert!(Independent::new(u32::MAX, 1).is_some());
    }

    #[test]
    fn samplers_are_send_and_sync() {
        fn assert_send_sync<T: Send + Sync + Clone + core::fmt::Debug>() {}
        assert_send_sync::<Independent>();
        assert_send_sync::<UniformGrid>();
        assert_send_sync::<Stratified>();
        assert_send_sync::<Sobol>();
        assert_send_sync::<Halton>();
        assert_send_sync::<ZSobol>();
    }

    /// Skipping a dimension leaves every sampler where drawing it would:
    /// random runs of draws and skips (1D and 2D, odd and even starts,
    /// across the samplers' blocks) against the same runs drawn.
    fn check_skips<S: Sampler + Clone>(prototype: S) {
        let mut state = 0x2545_f491_u32;
        let mut next = || {
            state ^= state << 13;
            state ^= state >> 17;
            state ^= state << 5;
            state
        };
        for sample in 0..64u32 {
            let pixel = UVec2::new(next() % 7, next() % 5);
            let (mut drawn, mut skipped) = (prototype.clone(), prototype.clone());
            drawn.start_pixel_sample(pixel, sample);
            skipped.start_pixel_sample(pixel, sample);
            for _ in 0..40 {
                let (two, skip) = (next() % 2 == 0, next() % 3 != 0);
                match (two, skip) {
                    (false, false) => assert_eq!(drawn.next_1d(), skipped.next_1d()),
                    (true, false) => assert_eq!(drawn.next_2d(), skipped.next_2d()),
                    (false, true) => {
                        drawn.next_1d();
                        skipped.skip_1d();
                    }
                    (true, true) => {
                        drawn.next_2d();
                        skipped.skip_2d();
                    }
                }
            }
            assert_eq!(drawn.next_2d(), skipped.next_2d());
        }
    }

    #[test]
    fn skipped_dimensions_leave_every_sampler_where_drawing_would() {
        for spp in [1, 4, 7, 16] {
            check_skips(Independent::new(spp, 3).unwrap());
            check_skips(UniformGrid::new(spp, 3).unwrap());
            check_skips(Stratified::new(spp, 3).unwrap());
            check_skips(Sobol::new(spp, 3).unwrap());
            check_skips(Halton::new(spp, 3).unwrap());
            check_skips(ZSobol::new(spp, 3, UVec2::new(7, 5)).unwrap());
        }
    }
}

/// The samplers' definitions written one value at a time, without the
/// caches and blocks of the fast paths, which must give the same bits;
/// and the visits each kind's test of its fast paths makes.
#[cfg(test)]
mod reference {
    use glam::{UVec2, Vec2};

    use super::halton::{HALTON_SALT, PRIMES};
    use super::sobol::{self, SOBOL_DIM_SALT, SOBOL_GROUP_SALT};
    use super::strata::PERMUTATION_SALT;
    use super::{grid_dims, permute, stratum_point};
    use crate::rng::{Pcg32, STREAM, mix64, pixel_hash, stream_state, u32_to_unit_f32};
    use rand_core::Rng;

    /// Sobol' dimension `d` of sample `index` of `pixel`.
    pub fn sobol_value(seed: u64, pixel: UVec2, index: u32, d: u32) -> f32 {
        let pixel_key = pixel_hash(seed, pixel);
        let group = (mix64(pixel_key ^ SOBOL_GROUP_SALT ^ (d / 2) as u64) >> 32) as u32;
        let index = sobol::nested_uniform_scramble(index, group);
        let key = (mix64(pixel_key ^ SOBOL_DIM_SALT ^ d as u64) >> 32) as u32;
        u32_to_unit_f32(sobol::nested_uniform_scramble(
            sobol::sobol(index as u64, (d % 2) as usize),
            key,
        ))
    }

    /// Halton dimension `d` of sample `index` of `pixel` for `spp`.
    pub fn halton_value(seed: u64, spp: u32, pixel: UVec2, index: u32, d: u32) -> f32 {
        let pixel_key = pixel_hash(seed, pixel);
        if d >= 64 {
            let h = mix64(pixel_key ^ HALTON_SALT ^ ((d as u64) << 32 | index as u64));
            return u32_to_unit_f32((h >> 32) as u32);
        }
        let base = PRIMES[d as usize];
        // The fewest digits k with base^k >= spp, within the f32 cells.
        let (mut k, mut cells) = (0, 1u64);
        while cells < spp as u64 && cells * base as u64 <= 1 << 24 {
            cells *= base as u64;
            k += 1;
        }
        let cells = cells as u32;
        let mut key = mix64(pixel_key ^ HALTON_SALT ^ d as u64);
        if index / cells > 0 {
            key = mix64(key ^ (index / cells) as u64);
        }
        let mut i = index % cells;
        let mut stratum = 0;
        for _ in 0..k {
            let digit = i % base;
            i /= base;
            let permuted = if base == 2 {
                digit ^ (key >> 63) as u32
            } else {
                let a = 1 + (((key >> 32) * (base as u64 - 1)) >> 32) as u32;
                let c = (((key & 0xffff_ffff) * base as u64) >> 32) as u32;
                (a * digit + c) % base
            };
            stratum = stratum * base + permuted;
            key = (key ^ (digit as u64 + 1)).wrapping_mul(0x9e37_79b9_7f4a_7c15);
            key ^= key >> 29;
        }
        let j = u32_to_unit_f32((mix64(key) >> 32) as u32);
        stratum_point(stratum, j, cells, 1.0 / cells as f64)
    }

    /// Wellons' `lowbias32`, as published.
    fn lowbias32(mut x: u32) -> u32 {
        x ^= x >> 16;
        x = x.wrapping_mul(0x7feb_352d);
        x ^= x >> 15;
        x = x.wrapping_mul(0x846c_a68b);
        x ^ x >> 16
    }

    /// A strata sampler that hashes every key and every jitter word.
    pub struct Strata {
        pub spp: u32,
        pub seed: u64,
        pub jitter: bool,
        pub shuffle_pixel: bool,
        pub pixel: UVec2,
        pub index: u32,
        pub dimension: u32,
    }

    impl Strata {
        fn stratum(&self, d: u32) -> u32 {
            let word = d as u64 | ((self.index / self.spp) as u64) << 32;
            let key = mix64(pixel_hash(self.seed, self.pixel) ^ PERMUTATION_SALT ^ word);
            permute(self.index % self.spp, self.spp, (key >> 32) as u32)
        }

        /// The point of stratum `s` of `n` at the jitter word of
        /// dimension `d`: on the 2⁻²⁴ grid for a jittered power of two,
        /// else `stratum_point` (a centre without jitter).
        fn point(&self, s: u32, n: u32, d: u32) -> f32 {
            if !self.jitter {
                return stratum_point(s, 0.5, n, 1.0 / n as f64);
            }
            let key = stream_state(self.seed, self.pixel, self.index);
            let x = lowbias32(key as u32 ^ d.wrapping_mul(0x9e37_79b9) ^ 0x3707_3449);
            let word = x ^ (key >> 32) as u32;
            if n.is_power_of_two() {
                let k = n.trailing_zeros();
                let cells = 1u64 << (24 - k);
                let v = (s as u64 * cells + (word as u64 >> (8 + k))) as f64;
                (v / 16_777_216.0) as f32
            } else {
                stratum_point(s, u32_to_unit_f32(word), n, 1.0 / n as f64)
            }
        }

        fn point_2d(&mut self, stratum: u32, d: u32) -> Vec2 {
            let (nx, ny) = grid_dims(self.spp);
            Vec2::new(
                self.point(stratum % nx, nx, d),
                self.point(stratum / nx, ny, d.wrapping_add(1)),
            )
        }

        pub fn start(&mut self, pixel: UVec2, index: u32) -> Vec2 {
            (self.pixel, self.index, self.dimension) = (pixel, index, 2);
            let s = if self.shuffle_pixel {
                self.stratum(0)
            } else {
                index % self.spp
            };
            self.point_2d(s, 0)
        }

        pub fn next_1d(&mut self) -> f32 {
            let d = self.dimension;
            self.dimension = d.wrapping_add(1);
            self.point(self.stratum(d), self.spp, d)
        }

        pub fn next_2d(&mut self) -> Vec2 {
            let d = self.dimension;
            self.dimension = d.wrapping_add(2);
            self.point_2d(self.stratum(d), d)
        }
    }

    /// Pseudo-random visits: pixels from a small set (so the per-pixel
    /// caches hit and miss), indices within and beyond spp, and a mixed
    /// sequence of 1D and 2D draws after each start.
    pub fn visits(spp: u32, mut f: impl FnMut(UVec2, u32, &[bool])) {
        let mut rng = Pcg32::new(spp as u64, STREAM);
        let pixels = [
            UVec2::new(0, 0),
            UVec2::new(1, 0),
            UVec2::new(17, 3),
            UVec2::new(u32::MAX, u32::MAX),
        ];
        let mut draws = [false; 48];
        for _ in 0..300 {
            let pixel = pixels[(rng.next_u32() % 4) as usize];
            let index = match rng.next_u32() % 8 {
                0 => u32::MAX - rng.next_u32() % 64,
                _ => rng.next_u32() % (3 * spp.min(1000)),
            };
            let n = (rng.next_u32() % 48) as usize;
            for d in &mut draws[..n] {
                *d = rng.next_u32().is_multiple_of(3); // true: a 2D draw
            }
            // The samples of one pixel in a row, as a renderer takes them.
            for k in 0..1 + rng.next_u32() % 3 {
                f(pixel, index.wrapping_add(k), &draws[..n]);
            }
        }
    }

    // 6, 12 and 24: a power-of-two axis in a spp that is not one.
    pub const SPPS: [u32; 12] = [1, 2, 3, 6, 7, 12, 16, 24, 30, 64, 100, 256];
}
