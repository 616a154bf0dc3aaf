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
use rand_core::Rng;

use crate::rng::{Pcg32, STREAM, mix64, pixel_hash, pixel_sample_rng, u32_to_unit_f32};

mod sobol;
mod zsobol;

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

/// Kensler's hashed permutation: the image of `i` under a pseudo-random
/// bijection of `[0, len)` chosen by `key`. For `len ≤ 1` it returns 0;
/// an `i ≥ len` is taken modulo `len`.
///
/// ```
/// use strata::sampler::permute;
/// let mut hit = [false; 10];
/// for i in 0..10 {
///     hit[permute(i, 10, 0xdead_beef) as usize] = true;
/// }
/// assert!(hit.iter().all(|&h| h)); // a bijection of 0..10
/// ```
#[inline]
#[must_use]
pub const fn permute(i: u32, len: u32, key: u32) -> u32 {
    if len <= 1 {
        return 0;
    }
    // Outside [0, len) the cycle walk need not come back: fold first.
    let i = if i >= len { i % len } else { i };
    permute_in(i, len, permute_mask(len), key, key % len)
}

/// The smallest `2^k − 1 ≥ len − 1`: the domain of one permutation round.
#[inline]
const fn permute_mask(len: u32) -> u32 {
    let mut w = len.saturating_sub(1);
    w |= w >> 1;
    w |= w >> 2;
    w |= w >> 4;
    w |= w >> 8;
    w | w >> 16
}

/// [`permute`] of an `i < len` (`len ≥ 1`), with `w = permute_mask(len)`
/// and `key_mod = key % len` given, so callers that hold `len` or `key`
/// fixed compute them once. For `len = 1` it returns 0 like `permute`.
#[inline]
const fn permute_in(mut i: u32, len: u32, w: u32, key: u32, key_mod: u32) -> u32 {
    // Each step is a bijection of [0, w]; cycle walking restricts it to
    // [0, len), and len > w / 2 bounds the expected walk by two rounds.
    loop {
        i = permute_round(i, w, key);
        if i < len {
            break;
        }
    }
    // (i + key) mod len without overflow: both terms are below len, so
    // one subtraction.
    let r = i.wrapping_add(key_mod);
    if r >= len || r < i {
        r.wrapping_sub(len)
    } else {
        r
    }
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

/// One stratified axis of `n` strata: where stratum `s` puts jitter
/// bits `x` (a jitter word, whose 24 high bits are the jitter, as
/// [`u32_to_unit_f32`] reads them). [`Axis::point`] is [`stratum_point`]'s
/// value; with `n` a power of two it comes from integers alone: `s·2²⁴ + J`
/// is exact in an `i64`, its conversion to `f32` rounds as the `f64` path
/// does, and the scale `2^-(24+k)` is exact, so the bits are the same.
/// [`Axis::fixed_point`] is the jittered sampler's placement on a
/// power-of-two axis.
#[derive(Clone, Copy, Debug)]
struct Axis {
    n: u32,
    /// `1 / n` for the general path.
    inv: f64,
    /// `log2 n` if `n` is a power of two, else [`Axis::GENERAL`].
    shift: u32,
    /// `2^-(24 + log2 n)` if `n` is a power of two.
    scale: f32,
}

impl Axis {
    /// The `shift` of an `n` that is not a power of two.
    const GENERAL: u32 = u32::MAX;

    fn new(n: u32) -> Self {
        let pow2 = n.is_power_of_two();
        let shift = if pow2 {
            n.trailing_zeros()
        } else {
            Self::GENERAL
        };
        Self {
            n,
            inv: 1.0 / n as f64,
            shift,
            // n ≤ 2²⁴, so the scale is at least 2⁻⁴⁸, a normal f32.
            scale: if pow2 {
                f32::from_bits((127 - 24 - shift) << 23)
            } else {
                0.0
            },
        }
    }

    /// `s / n` and `s % n`.
    #[inline(always)]
    fn div_rem(self, s: u32) -> (u32, u32) {
        if self.shift == Self::GENERAL {
            (s / self.n, s % self.n)
        } else {
            self.div_rem_pow2(s)
        }
    }

    /// The point of stratum `s < n` at jitter bits `x`.
    #[inline(always)]
    fn point(self, s: u32, x: u32) -> f32 {
        if self.shift == Self::GENERAL {
            return stratum_point(s, u32_to_unit_f32(x), self.n, self.inv);
        }
        self.point_pow2(s, x)
    }

    /// [`Axis::div_rem`], or [`Axis::div_rem_pow2`] where the caller knows
    /// `n` is a power of two (`POW2`).
    #[inline(always)]
    fn div_rem_as<const POW2: bool>(self, s: u32) -> (u32, u32) {
        if POW2 {
            self.div_rem_pow2(s)
        } else {
            self.div_rem(s)
        }
    }

    /// [`Axis::point`], or [`Axis::point_pow2`] where the caller knows `n`
    /// is a power of two (`POW2`).
    #[inline(always)]
    fn point_as<const POW2: bool>(self, s: u32, x: u32) -> f32 {
        if POW2 {
            self.point_pow2(s, x)
        } else {
            self.point(s, x)
        }
    }

    /// The point of stratum `s < n = 2^k` at jitter word `x`, on the
    /// `2⁻²⁴` grid of [`u32_to_unit_f32`]: the stratum's `k` bits above
    /// the jitter word's high bits, of which `24 − k` survive (none at
    /// `k = 24`: the stratum's left end). Exact, no rounding, and inside
    /// the stratum by construction.
    #[inline(always)]
    fn fixed_point(self, s: u32, x: u32) -> f32 {
        debug_assert!(self.shift <= 24 && s < self.n);
        u32_to_unit_f32((((s as u64) << 32 | x as u64) >> self.shift) as u32)
    }

    /// `s / n` and `s % n` of an axis whose `n` is a power of two.
    #[inline(always)]
    fn div_rem_pow2(self, s: u32) -> (u32, u32) {
        debug_assert!(self.shift != Self::GENERAL);
        (s >> self.shift, s & (self.n - 1))
    }

    /// [`Axis::point`] of an axis whose `n` is a power of two.
    #[inline(always)]
    fn point_pow2(self, s: u32, x: u32) -> f32 {
        debug_assert!(self.shift != Self::GENERAL);
        // s + 1 ≤ 2²⁴, so both integers are below 2⁴⁹ and `top` is exact.
        let num = ((s as u64) << 24 | (x >> 8) as u64) as i64 as f32;
        // Rounding may reach the next stratum's start, never beyond: cap
        // at the float below it, as stratum_point's check does.
        let top = (((s as u64) + 1) << 24) as i64 as f32;
        let below_top = f32::from_bits(top.to_bits() - 1);
        let v = if num < below_top { num } else { below_top };
        v * self.scale
    }
}

/// Uniform random samples: the course's `get_ray`, with a reproducible
/// stream per pixel sample. Any spp and index: each `(pixel, index)` has a
/// stream of its own, so an index `≥ spp` is just another sample.
///
/// ```
/// use glam::UVec2;
/// use strata::sampler::{Independent, Sampler};
/// let mut s = Independent::new(4, 1).unwrap();
/// s.start_pixel_sample(UVec2::new(0, 0), 0);
/// let u = s.next_1d();
/// assert!((0.0..1.0).contains(&u));
/// ```
#[derive(Clone, Debug)]
pub struct Independent {
    spp: u32,
    /// The current pixel's hash, kept across its samples.
    key: PixelKey,
    rng: Pcg32,
    pixel: Vec2,
}

impl Independent {
    /// An independent sampler; `None` if `spp` is 0.
    #[inline]
    #[must_use]
    pub fn new(spp: u32, seed: u64) -> Option<Self> {
        if spp == 0 {
            return None;
        }
        let mut s = Self {
            spp,
            key: PixelKey::new(seed),
            rng: pixel_sample_rng(seed, UVec2::ZERO, 0),
            pixel: Vec2::ZERO,
        };
        s.start_pixel_sample(UVec2::ZERO, 0);
        Some(s)
    }
}

impl Sampler for Independent {
    #[inline]
    fn samples_per_pixel(&self) -> u32 {
        self.spp
    }

    #[inline]
    fn start_pixel_sample(&mut self, pixel: UVec2, index: u32) {
        // pixel_sample_rng(seed, pixel, index), from the kept pixel hash.
        self.key.set(pixel);
        self.rng = Pcg32::new(mix64(self.key.key ^ index as u64), STREAM);
        self.pixel = self.next_2d();
    }

    #[inline]
    fn pixel_2d(&mut self) -> Vec2 {
        self.pixel
    }

    #[inline]
    fn next_1d(&mut self) -> f32 {
        u32_to_unit_f32(self.rng.next_u32())
    }

    #[inline]
    fn next_2d(&mut self) -> Vec2 {
        let x = u32_to_unit_f32(self.rng.next_u32());
        let y = u32_to_unit_f32(self.rng.next_u32());
        Vec2::new(x, y)
    }

    // One LCG step per dimension, without the output permutation.
    #[inline]
    fn skip_1d(&mut self) {
        self.rng.advance(1);
    }

    #[inline]
    fn skip_2d(&mut self) {
        self.rng.advance(2);
    }
}

/// Keeps permutation keys apart from stream states: `π − 3` in 64 bits.
const PERMUTATION_SALT: u64 = 0x243f_6a88_85a3_08d3;

/// The largest spp the strata samplers accept: beyond `2²⁴` a stratum of a
/// 1D dimension is narrower than the `f32` spacing near 1, and "one sample
/// per stratum" could no longer hold.
pub const MAX_STRATA_SPP: u32 = 1 << 24;

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

/// Dimensions whose strata a strata sampler evaluates at once.
const STRATA_BLOCK: usize = 16;

/// Blocks of [`STRATA_BLOCK`] dimensions whose permutation keys a strata
/// sampler keeps for its current pixel and pass (a path of 5 segments
/// draws 28 dimensions).
const STRATA_KEYED_BLOCKS: usize = 2;

/// One round of Kensler's permutation of `[0, w]` keyed by `p` (see
/// [`permute_in`]).
#[inline(always)]
const fn permute_round(i: u32, w: u32, p: u32) -> u32 {
    permute_round_keyed::<false>(i, w, RoundKey::new(p))
}

/// What one round of Kensler's permutation takes from its key `p`,
/// derived once per key: the shifted key words, and the two multipliers
/// the round applies back to back folded into one (products mod 2³² do not
/// depend on grouping, so the bits are the same).
#[derive(Clone, Copy, Debug)]
struct RoundKey {
    p: u32,
    p16: u32,
    p8: u32,
    p23: u32,
    m: u32,
}

impl RoundKey {
    /// The derived words of key `p`.
    #[inline(always)]
    const fn new(p: u32) -> Self {
        Self {
            p,
            p16: p >> 16,
            p8: p >> 8,
            p23: p >> 23,
            m: (1 | p >> 27).wrapping_mul(0x6935_fa69),
        }
    }
}

/// [`permute_round`] from a derived key. With `SMALL` (only for `w < 16`)
/// the steps `(i & w) >> 4`, `(i & w) >> 11` and the final `i >> 5` are
/// left out: they see at most `w ≤ 15` and xor zero, so the bits are the
/// same.
#[inline(always)]
const fn permute_round_keyed<const SMALL: bool>(mut i: u32, w: u32, k: RoundKey) -> u32 {
    debug_assert!(!SMALL || w < 16);
    i ^= k.p;
    i = i.wrapping_mul(0xe170_893d);
    i ^= k.p16;
    if !SMALL {
        i ^= (i & w) >> 4;
    }
    i ^= k.p8;
    i = i.wrapping_mul(0x0929_eb3f);
    i ^= k.p23;
    i ^= (i & w) >> 1;
    i = i.wrapping_mul(k.m);
    if !SMALL {
        i ^= (i & w) >> 11;
    }
    i = i.wrapping_mul(0x74dc_b303);
    i ^= (i & w) >> 2;
    i = i.wrapping_mul(0x9e50_1cc3);
    i ^= (i & w) >> 2;
    i = i.wrapping_mul(0xc860_a3df);
    i &= w;
    if SMALL { i } else { i ^ i >> 5 }
}

/// The permutation keys of one block of [`STRATA_BLOCK`] dimensions, lane
/// by lane (structure of arrays, for SIMD): each round key's words and the
/// key's residue mod the stratum count.
#[derive(Clone, Copy, Debug)]
struct BlockKeys {
    p: [u32; STRATA_BLOCK],
    p16: [u32; STRATA_BLOCK],
    p8: [u32; STRATA_BLOCK],
    p23: [u32; STRATA_BLOCK],
    m: [u32; STRATA_BLOCK],
    key_mod: [u32; STRATA_BLOCK],
}

impl BlockKeys {
    /// All keys 0 (a placeholder until a block's keys are written).
    const ZERO: Self = Self {
        p: [0; STRATA_BLOCK],
        p16: [0; STRATA_BLOCK],
        p8: [0; STRATA_BLOCK],
        p23: [0; STRATA_BLOCK],
        m: [0; STRATA_BLOCK],
        key_mod: [0; STRATA_BLOCK],
    };

    /// Lane `l`'s round key.
    #[inline(always)]
    fn lane(&self, l: usize) -> RoundKey {
        RoundKey {
            p: self.p[l],
            p16: self.p16[l],
            p8: self.p8[l],
            p23: self.p23[l],
            m: self.m[l],
        }
    }
}

/// [`permute_in`] of one `i < len` under `STRATA_BLOCK` keys at once, into
/// `out`: lanes are independent and branch-free (a lane that has reached
/// `[0, len)` keeps its value while the others walk on), so a compiler
/// turns them into SIMD.
#[inline]
fn permute_block(i: u32, len: u32, w: u32, keys: &BlockKeys, out: &mut [u32; STRATA_BLOCK]) {
    if w < 16 {
        permute_block_in::<true>(i, len, w, keys, out);
    } else {
        permute_block_in::<false>(i, len, w, keys, out);
    }
}

/// [`permute_block`] with rounds of one kind (see [`permute_round_keyed`]).
#[inline(always)]
fn permute_block_in<const SMALL: bool>(
    i: u32,
    len: u32,
    w: u32,
    keys: &BlockKeys,
    out: &mut [u32; STRATA_BLOCK],
) {
    if w.wrapping_add(1) == len {
        // A power of two: one round stays in [0, len), nothing walks, and
        // (x + key) mod len is a mask.
        for (l, o) in out.iter_mut().enumerate() {
            *o = permute_round_keyed::<SMALL>(i, w, keys.lane(l)).wrapping_add(keys.key_mod[l]) & w;
        }
        return;
    }
    let mut x = [i; STRATA_BLOCK];
    // All ones while a lane still walks.
    let mut walking = [u32::MAX; STRATA_BLOCK];
    loop {
        let mut any = 0;
        for l in 0..STRATA_BLOCK {
            let y = permute_round_keyed::<SMALL>(x[l], w, keys.lane(l));
            x[l] = (y & walking[l]) | (x[l] & !walking[l]);
            walking[l] &= 0u32.wrapping_sub((y >= len) as u32);
            any |= walking[l];
        }
        if any == 0 {
            break;
        }
    }
    for l in 0..STRATA_BLOCK {
        // (x + key) mod len without overflow, as permute_in.
        let r = x[l].wrapping_add(keys.key_mod[l]);
        let wrap = (r >= len) | (r < x[l]);
        out[l] = r.wrapping_sub(len & 0u32.wrapping_sub(wrap as u32));
    }
}

/// Writes into `keys` the permutation keys of block `block` (dimensions
/// `16·block ..`) of pass `pass` of the pixel hashed to `pixel_key`, and
/// their residues mod the stratum count of `axis`.
#[inline]
fn block_keys(keys: &mut BlockKeys, pixel_key: u64, pass: u32, axis: Axis, block: u32) {
    let first = block.wrapping_mul(STRATA_BLOCK as u32);
    for l in 0..STRATA_BLOCK {
        let d = first.wrapping_add(l as u32);
        // Salted so that a key never equals a stream state
        // (`mix64(pixel_key ^ index)`) of the same pixel.
        let word = d as u64 | (pass as u64) << 32;
        let p = (mix64(pixel_key ^ PERMUTATION_SALT ^ word) >> 32) as u32;
        let k = RoundKey::new(p);
        keys.p[l] = k.p;
        keys.p16[l] = k.p16;
        keys.p8[l] = k.p8;
        keys.p23[l] = k.p23;
        keys.m[l] = k.m;
        keys.key_mod[l] = axis.div_rem(p).1;
    }
}

/// Salt of the jitter words' input.
const JITTER_SALT: u32 = 0x3707_3449;

/// The jitter word of dimension `d` of the pixel sample hashed to `key`
/// ([`crate::rng::stream_state`]): Wellons' `lowbias32` of the key's low
/// word, the dimension and a salt, xored with the key's high word. 32-bit
/// integer steps only, so a block of them is one SIMD loop.
#[inline(always)]
const fn jitter_word(key: u64, d: u32) -> u32 {
    let mut x = (key as u32) ^ d.wrapping_mul(0x9e37_79b9) ^ JITTER_SALT;
    x ^= x >> 16;
    x = x.wrapping_mul(0x7feb_352d);
    x ^= x >> 15;
    x = x.wrapping_mul(0x846c_a68b);
    x ^= x >> 16;
    x ^ (key >> 32) as u32
}

/// The jitter words of block `block`'s dimensions and of the first one
/// after it.
#[inline]
fn jitter_block(out: &mut [u32; STRATA_BLOCK + 1], key: u64, block: u32) {
    let first = block.wrapping_mul(STRATA_BLOCK as u32);
    for (l, o) in out.iter_mut().enumerate() {
        *o = jitter_word(key, first.wrapping_add(l as u32));
    }
}

/// The state the two strata samplers share; `JITTER` is the only
/// difference between them, as in pbrt's `StratifiedSampler`. Without
/// jitter every point is a stratum centre and no jitter word is hashed.
#[derive(Clone, Debug)]
struct Strata<const JITTER: bool> {
    spp: u32,
    /// The strata of a 1D draw (`spp`) and of a 2D draw's two axes.
    axes: [Axis; 3],
    /// `permute_mask(spp)`.
    mask: u32,
    pixel: PixelKey,
    /// Stratum slot `index % spp` and pass `index / spp`.
    slot: u32,
    pass: u32,
    dimension: u32,
    /// The pass whose keys `keys` holds, and which blocks of it are
    /// filled (bit `b`).
    keyed_pass: u32,
    keyed: u32,
    /// Each dimension's permutation key (its round's derived words) and
    /// its residue mod spp, by block.
    keys: [BlockKeys; STRATA_KEYED_BLOCKS],
    /// The block whose shuffled strata `strata` holds.
    block: u32,
    strata: [u32; STRATA_BLOCK],
    /// The hash of the current pixel sample that its jitter words come
    /// from, and the words of `block`'s dimensions and the one after it
    /// (a 2D draw at a block's last dimension reads it).
    sample_key: u64,
    jitter: [u32; STRATA_BLOCK + 1],
    pixel_2d: Vec2,
}

impl<const JITTER: bool> Strata<JITTER> {
    fn new(spp: u32, seed: u64, shuffle_pixel: bool) -> Option<Self> {
        if spp == 0 || spp > MAX_STRATA_SPP {
            return None;
        }
        let (nx, ny) = grid_dims(spp);
        let mut s = Self {
            spp,
            axes: [Axis::new(spp), Axis::new(nx), Axis::new(ny)],
            mask: permute_mask(spp),
            pixel: PixelKey::new(seed),
            slot: 0,
            pass: 0,
            dimension: 2,
            keyed_pass: 0,
            keyed: 0,
            keys: [BlockKeys::ZERO; STRATA_KEYED_BLOCKS],
            block: 0,
            strata: [0; STRATA_BLOCK],
            sample_key: 0,
            jitter: [0; STRATA_BLOCK + 1],
            pixel_2d: Vec2::ZERO,
        };
        s.start(UVec2::ZERO, 0, shuffle_pixel);
        Some(s)
    }

    /// Shuffles the strata of block `block` of the current sample into
    /// `strata`.
    #[inline(always)]
    fn fill(&mut self, block: u32) {
        let far;
        let keys = if (block as usize) < STRATA_KEYED_BLOCKS {
            let b = block as usize;
            if self.keyed & 1 << b == 0 {
                block_keys(
                    &mut self.keys[b],
                    self.pixel.key,
                    self.pass,
                    self.axes[0],
                    block,
                );
                self.keyed |= 1 << b;
            }
            &self.keys[b]
        } else {
            // Past the kept blocks (long paths only): computed each time.
            let mut k = BlockKeys::ZERO;
            block_keys(&mut k, self.pixel.key, self.pass, self.axes[0], block);
            far = k;
            &far
        };
        permute_block(self.slot, self.spp, self.mask, keys, &mut self.strata);
        if JITTER {
            jitter_block(&mut self.jitter, self.sample_key, block);
        }
        self.block = block;
    }

    /// [`Strata::fill`] for a draw past the current block: out of line, so
    /// the draws stay small enough to inline.
    #[cold]
    #[inline(never)]
    fn refill(&mut self, block: u32) {
        self.fill(block);
    }

    /// The lane of `dimension` in its block, filling the block first if
    /// it is not the current one.
    #[inline]
    fn lane(&mut self, dimension: u32) -> usize {
        let block = dimension / STRATA_BLOCK as u32;
        if block != self.block {
            self.refill(block);
        }
        dimension as usize % STRATA_BLOCK
    }

    /// The jitter word of lane `l` of the current block (`l` may be
    /// [`STRATA_BLOCK`]: the next block's first dimension); the centre
    /// (jitter 0.5) without jitter.
    #[inline(always)]
    fn jitter(&self, l: usize) -> u32 {
        if JITTER { self.jitter[l] } else { 1 << 31 }
    }

    /// Whether spp, and so both axes of a 2D draw, is a power of two.
    #[inline(always)]
    fn pow2(&self) -> bool {
        self.axes[0].shift != Axis::GENERAL
    }

    /// The point of 2D stratum `stratum`, from the jitter words of lanes
    /// `l` and `l + 1`.
    /// A power-of-two spp (one test for the three axis operations) stays
    /// small enough to inline; other counts take the general path out of
    /// line.
    #[inline(always)]
    fn point_2d(&self, l: usize, stratum: u32) -> Vec2 {
        if self.pow2() {
            self.point_2d_in::<true>(l, stratum)
        } else {
            self.point_2d_general(l, stratum)
        }
    }

    #[inline(never)]
    fn point_2d_general(&self, l: usize, stratum: u32) -> Vec2 {
        self.point_2d_in::<false>(l, stratum)
    }

    /// [`Strata::point_2d`], `POW2` saying whether the axes are powers of
    /// two.
    #[inline(always)]
    fn point_2d_in<const POW2: bool>(&self, l: usize, stratum: u32) -> Vec2 {
        let jx = self.jitter(l);
        let jy = self.jitter(l + 1);
        let [_, x, y] = self.axes;
        let (row, column) = x.div_rem_as::<POW2>(stratum);
        Vec2::new(
            Self::place::<POW2>(x, column, jx),
            Self::place::<POW2>(y, row, jy),
        )
    }

    /// The point of stratum `s` of `axis` at jitter word `x`: on the
    /// `2⁻²⁴` grid ([`Axis::fixed_point`]) for jittered strata of a
    /// power-of-two axis, else [`Axis::point`] (a centre without jitter).
    /// `POW2`: the caller knows the axis is a power of two.
    #[inline(always)]
    fn place<const POW2: bool>(axis: Axis, s: u32, x: u32) -> f32 {
        if JITTER && (POW2 || axis.shift != Axis::GENERAL) {
            axis.fixed_point(s, x)
        } else {
            axis.point_as::<POW2>(s, x)
        }
    }

    /// The point of 1D stratum `stratum`, from lane `l`'s jitter word (as
    /// [`Strata::point_2d`]).
    #[inline(always)]
    fn point_1d(&self, l: usize, stratum: u32) -> f32 {
        if self.pow2() {
            self.point_1d_in::<true>(l, stratum)
        } else {
            self.point_1d_general(l, stratum)
        }
    }

    #[inline(never)]
    fn point_1d_general(&self, l: usize, stratum: u32) -> f32 {
        self.point_1d_in::<false>(l, stratum)
    }

    /// [`Strata::point_1d`], `POW2` as for [`Strata::point_2d_in`].
    #[inline(always)]
    fn point_1d_in<const POW2: bool>(&self, l: usize, stratum: u32) -> f32 {
        Self::place::<POW2>(self.axes[0], stratum, self.jitter(l))
    }

    #[inline]
    fn start(&mut self, pixel: UVec2, index: u32, shuffle_pixel: bool) {
        let (pass, slot) = self.axes[0].div_rem(index);
        if self.pixel.set(pixel) || pass != self.keyed_pass {
            self.keyed = 0;
            self.keyed_pass = pass;
        }
        self.slot = slot;
        self.pass = pass;
        if JITTER {
            // stream_state(seed, pixel, index), from the kept pixel hash.
            self.sample_key = mix64(self.pixel.key ^ index as u64);
        }
        // Block 0 holds the pixel's stratum and the first draws'.
        self.fill(0);
        let stratum = if shuffle_pixel {
            self.strata[0]
        } else {
            self.slot
        };
        self.pixel_2d = self.point_2d(0, stratum);
        self.dimension = 2;
    }

    #[inline]
    fn next_1d(&mut self) -> f32 {
        let l = self.lane(self.dimension);
        self.dimension = self.dimension.wrapping_add(1);
        self.point_1d(l, self.strata[l])
    }

    #[inline]
    fn next_2d(&mut self) -> Vec2 {
        let l = self.lane(self.dimension);
        self.dimension = self.dimension.wrapping_add(2);
        self.point_2d(l, self.strata[l])
    }

    /// Skips `n` coordinates: every value is a function of its dimension,
    /// so only the dimension moves.
    #[inline]
    fn skip(&mut self, n: u32) {
        self.dimension = self.dimension.wrapping_add(n);
    }

    #[inline]
    fn skip_1d(&mut self) {
        self.skip(1);
    }

    #[inline]
    fn skip_2d(&mut self) {
        self.skip(2);
    }
}

/// The lecture's unjittered stratified pattern: every sample at the centre
/// of its stratum. The pixel positions form an `nx × ny` grid visited in
/// raster order (sample `i` at column `i % nx`, row `i / nx`); the other
/// dimensions use stratum centres shuffled per dimension. Its regularity
/// aliases, which is what it is here to show.
///
/// ```
/// use glam::{UVec2, Vec2};
/// use strata::sampler::{Sampler, UniformGrid};
/// let mut s = UniformGrid::new(4, 0).unwrap(); // 2 × 2
/// s.start_pixel_sample(UVec2::new(9, 9), 3);
/// assert_eq!(s.pixel_2d(), Vec2::new(0.75, 0.75));
/// ```
#[derive(Clone, Debug)]
pub struct UniformGrid(Strata<false>);

impl UniformGrid {
    /// A grid sampler; `None` if `spp` is 0 or above [`MAX_STRATA_SPP`].
    #[inline]
    #[must_use]
    pub fn new(spp: u32, seed: u64) -> Option<Self> {
        Strata::new(spp, seed, false).map(Self)
    }

    /// The `(nx, ny)` pixel grid.
    #[inline]
    #[must_use]
    pub fn grid(&self) -> (u32, u32) {
        (self.0.axes[1].n, self.0.axes[2].n)
    }
}

impl Sampler for UniformGrid {
    #[inline]
    fn samples_per_pixel(&self) -> u32 {
        self.0.spp
    }
    #[inline]
    fn start_pixel_sample(&mut self, pixel: UVec2, index: u32) {
        self.0.start(pixel, index, false);
    }
    #[inline]
    fn pixel_2d(&mut self) -> Vec2 {
        self.0.pixel_2d
    }
    #[inline]
    fn next_1d(&mut self) -> f32 {
        self.0.next_1d()
    }
    #[inline]
    fn next_2d(&mut self) -> Vec2 {
        self.0.next_2d()
    }
    #[inline]
    fn skip_1d(&mut self) {
        self.0.skip_1d();
    }
    #[inline]
    fn skip_2d(&mut self) {
        self.0.skip_2d();
    }
}

/// Jittered stratified samples for any spp (the course's `render_jittered`,
/// with its offset bug D3 fixed): each sample takes a uniform point inside
/// its own stratum, and the strata of every dimension are shuffled
/// independently.
///
/// The jitter of dimension `d` is a hash of the pixel sample and `d`
/// (32-bit integer steps, a block of dimensions at a time). With `spp` a
/// power of two, `2^k` strata on an axis, a point is the stratum's `k`
/// bits above the jitter's `24 − k` high bits, on the `2⁻²⁴` grid that
/// [`Independent`] draws from; other spp place the jitter in the stratum
/// in `f64` and round into it.
///
/// ```
/// use glam::UVec2;
/// use strata::sampler::{Sampler, Stratified};
/// // 9 samples of one pixel: exactly one in each third of every dimension.
/// let mut s = Stratified::new(9, 7).unwrap();
/// let mut thirds = [0; 3];
/// for i in 0..9 {
///     s.start_pixel_sample(UVec2::new(1, 2), i);
///     thirds[(s.next_1d() * 3.0) as usize] += 1;
/// }
/// assert_eq!(thirds, [3, 3, 3]);
/// ```
#[derive(Clone, Debug)]
pub struct Stratified(Strata<true>);

impl Stratified {
    /// A jittered stratified sampler; `None` if `spp` is 0 or above
    /// [`MAX_STRATA_SPP`].
    #[inline]
    #[must_use]
    pub fn new(spp: u32, seed: u64) -> Option<Self> {
        Strata::new(spp, seed, true).map(Self)
    }

    /// The `(nx, ny)` strata of the 2D dimensions.
    #[inline]
    #[must_use]
    pub fn grid(&self) -> (u32, u32) {
        (self.0.axes[1].n, self.0.axes[2].n)
    }
}

impl Sampler for Stratified {
    #[inline]
    fn samples_per_pixel(&self) -> u32 {
        self.0.spp
    }
    #[inline]
    fn start_pixel_sample(&mut self, pixel: UVec2, index: u32) {
        self.0.start(pixel, index, true);
    }
    #[inline]
    fn pixel_2d(&mut self) -> Vec2 {
        self.0.pixel_2d
    }
    #[inline]
    fn next_1d(&mut self) -> f32 {
        self.0.next_1d()
    }
    #[inline]
    fn next_2d(&mut self) -> Vec2 {
        self.0.next_2d()
    }
    #[inline]
    fn skip_1d(&mut self) {
        self.0.skip_1d();
    }
    #[inline]
    fn skip_2d(&mut self) {
        self.0.skip_2d();
    }
}

/// Keys of the Sobol' index shuffles and output scrambles, apart from
/// each other and from stream states.
const SOBOL_GROUP_SALT: u64 = 0x1319_8a2e_0370_7344;
const SOBOL_DIM_SALT: u64 = 0xa409_3822_299f_31d0;

/// Blocks of [`sobol::BLOCK`] dimensions whose keys a Sobol' sampler keeps
/// for its current pixel (a path of 5 segments draws 28 dimensions).
const SOBOL_KEYED_BLOCKS: usize = 2;

/// The keys of Sobol' block `block` (dimensions `16·block ..`) of the pixel
/// hashed to `pixel_key`: each pair's key (index shuffle) and each lane's
/// dimension key (output scramble).
#[inline]
fn sobol_keys(pixel_key: u64, block: u32) -> SobolKeys {
    let first = block.wrapping_mul(sobol::BLOCK as u32);
    SobolKeys {
        pairs: core::array::from_fn(|g| {
            let pair = first / 2 + g as u32;
            (mix64(pixel_key ^ SOBOL_GROUP_SALT ^ pair as u64) >> 32) as u32
        }),
        dims: core::array::from_fn(|l| {
            let d = first.wrapping_add(l as u32);
            (mix64(pixel_key ^ SOBOL_DIM_SALT ^ d as u64) >> 32) as u32
        }),
    }
}

/// The keys of one Sobol' block (see [`sobol_keys`]).
#[derive(Clone, Copy, Debug, Default)]
struct SobolKeys {
    /// Each pair's index shuffle key.
    pairs: [u32; sobol::BLOCK / 2],
    /// Each dimension's output scramble key.
    dims: [u32; sobol::BLOCK],
}

/// Owen-scrambled Sobol' samples (Burley 2020), padded in pairs of
/// dimensions (as pbrt's `PaddedSobolSampler`); see the `sobol` module for
/// the construction. Best with a power-of-two spp: the first `2^k` samples
/// of a pixel are a `(0, k, 2)`-net in the pixel position and in every 2D
/// draw, and stratify every dimension into `2^k` equal strata (up to
/// `k = 24`: values are `f32`s, multiples of `2⁻²⁴`). Any spp works; an
/// index `≥ spp` continues the sequence, so every aligned block of `2^k`
/// indices is such a net too.
///
/// `next_2d` starts on an even dimension (skipping one if needed), so a 2D
/// draw is always one pair and keeps its joint stratification. Dimensions
/// are evaluated sixteen at a time, when a draw first reaches them; the
/// values are those of each dimension alone.
///
/// ```
/// use glam::UVec2;
/// use strata::sampler::{Sampler, Sobol};
/// // 16 samples: one in each of 4 × 4 cells of the pixel, and one in
/// // each 16th of every other dimension.
/// let mut s = Sobol::new(16, 3).unwrap();
/// let (mut cells, mut strata) = ([0; 16], [0; 16]);
/// for i in 0..16 {
///     s.start_pixel_sample(UVec2::new(5, 9), i);
///     let p = s.pixel_2d();
///     cells[(p.y * 4.0) as usize * 4 + (p.x * 4.0) as usize] += 1;
///     strata[(s.next_1d() * 16.0) as usize] += 1;
/// }
/// assert_eq!((cells, strata), ([1; 16], [1; 16]));
/// ```
#[derive(Clone, Debug)]
pub struct Sobol {
    spp: u32,
    pixel: PixelKey,
    /// Bit `b`: `keys[b]` holds block `b`'s keys for the current pixel.
    keyed: u32,
    keys: [SobolKeys; SOBOL_KEYED_BLOCKS],
    /// The sample index, bit-reversed.
    index_rev: u32,
    dimension: u32,
    /// The block whose values `values` holds.
    block: u32,
    values: [f32; sobol::BLOCK],
    pixel_2d: Vec2,
}

impl Sobol {
    /// A Sobol' sampler; `None` if `spp` is 0.
    #[inline]
    #[must_use]
    pub fn new(spp: u32, seed: u64) -> Option<Self> {
        if spp == 0 {
            return None;
        }
        let mut s = Self {
            spp,
            pixel: PixelKey::new(seed),
            keyed: 0,
            keys: [SobolKeys::default(); SOBOL_KEYED_BLOCKS],
            index_rev: 0,
            dimension: 2,
            block: 0,
            values: [0.0; sobol::BLOCK],
            pixel_2d: Vec2::ZERO,
        };
        s.start_pixel_sample(UVec2::ZERO, 0);
        Some(s)
    }

    /// Evaluates block `block` of the current sample into `values`.
    #[inline(always)]
    fn fill(&mut self, block: u32) {
        let far;
        let keys = if (block as usize) < SOBOL_KEYED_BLOCKS {
            let b = block as usize;
            if self.keyed & 1 << b == 0 {
                self.keys[b] = sobol_keys(self.pixel.key, block);
                self.keyed |= 1 << b;
            }
            &self.keys[b]
        } else {
            far = sobol_keys(self.pixel.key, block);
            &far
        };
        let ints = sobol::padded_block(self.index_rev, &keys.pairs, &keys.dims);
        // u32_to_unit_f32 of the 32-bit values, whose 24 high bits these are.
        self.values = ints.map(|x| x as f32 * (1.0 / 16_777_216.0));
        self.block = block;
    }

    /// [`Sobol::fill`] for a draw past the current block: out of line, so
    /// the draws stay small enough to inline.
    #[cold]
    #[inline(never)]
    fn refill(&mut self, block: u32) {
        self.fill(block);
    }
}

impl Sampler for Sobol {
    #[inline]
    fn samples_per_pixel(&self) -> u32 {
        self.spp
    }

    #[inline]
    fn start_pixel_sample(&mut self, pixel: UVec2, index: u32) {
        if self.pixel.set(pixel) {
            self.keyed = 0;
        }
        self.index_rev = index.reverse_bits();
        self.dimension = 2;
        self.fill(0);
        self.pixel_2d = Vec2::new(self.values[0], self.values[1]);
    }

    #[inline]
    fn pixel_2d(&mut self) -> Vec2 {
        self.pixel_2d
    }

    #[inline]
    fn next_1d(&mut self) -> f32 {
        let d = self.dimension;
        self.dimension = d.wrapping_add(1);
        let block = d / sobol::BLOCK as u32;
        if block != self.block {
            self.refill(block);
        }
        self.values[d as usize % sobol::BLOCK]
    }

    #[inline]
    fn next_2d(&mut self) -> Vec2 {
        // A pair starts on an even dimension, so it never straddles blocks.
        let d = self.dimension.wrapping_add(self.dimension & 1);
        self.dimension = d.wrapping_add(2);
        let block = d / sobol::BLOCK as u32;
        if block != self.block {
            self.refill(block);
        }
        let k = d as usize % sobol::BLOCK;
        Vec2::new(self.values[k], self.values[k | 1])
    }

    // Only the dimension moves: a block is filled when a value is read.
    #[inline]
    fn skip_1d(&mut self) {
        self.dimension = self.dimension.wrapping_add(1);
    }

    #[inline]
    fn skip_2d(&mut self) {
        let d = self.dimension.wrapping_add(self.dimension & 1);
        self.dimension = d.wrapping_add(2);
    }
}

/// The number of prime bases, the Halton dimensions.
const HALTON_BASES: usize = 64;

/// The first 64 primes: the Halton bases of dimensions 0–63.
const PRIMES: [u32; HALTON_BASES] = [
    2, 3, 5, 7, 11, 13, 17, 19, 23, 29, 31, 37, 41, 43, 47, 53, 59, 61, 67, 71, 73, 79, 83, 89, 97,
    101, 103, 107, 109, 113, 127, 131, 137, 139, 149, 151, 157, 163, 167, 173, 179, 181, 191, 193,
    197, 199, 211, 223, 227, 229, 233, 239, 241, 251, 257, 263, 269, 271, 277, 281, 283, 293, 307,
    311,
];

/// Keys of the Halton digit scrambles, apart from other keys.
const HALTON_SALT: u64 = 0xbe54_66cf_34e9_0c6c;

/// What the digit loop of one Halton base needs, computed at compile time.
#[derive(Clone, Copy, Debug)]
struct HaltonBase {
    base: u32,
    /// Digits that fit an `f32`: `base^levels ≤ 2²⁴ < base^(levels+1)`.
    levels: u32,
    /// `⌈2⁶⁴ / base⌉`: divides and reduces a `u32` exactly by multiplying
    /// (Lemire, Kaser and Kurz 2019).
    magic: u64,
}

impl HaltonBase {
    const fn new(base: u32) -> Self {
        let (mut levels, mut cells) = (0u32, 1u64);
        while cells * base as u64 <= 1 << 24 {
            cells *= base as u64;
            levels += 1;
        }
        Self {
            base,
            levels,
            magic: u64::MAX / base as u64 + 1,
        }
    }

    /// `(x / base, x % base)`.
    #[inline]
    const fn div_rem(&self, x: u32) -> (u32, u32) {
        let q = ((self.magic as u128 * x as u128) >> 64) as u32;
        (q, x - q * self.base)
    }

    /// `x % base`.
    #[inline]
    const fn rem(&self, x: u32) -> u32 {
        let low = self.magic.wrapping_mul(x as u64);
        ((low as u128 * self.base as u128) >> 64) as u32
    }

    /// The random affine permutation `x ↦ (a·x + c) mod base` of a digit,
    /// with `a ∈ [1, base)` and `c ∈ [0, base)` drawn from `key` (the high
    /// and low 32 bits, scaled by multiplying). In base 2 it is a keyed
    /// bit flip.
    #[inline]
    const fn permute(&self, digit: u32, key: u64) -> u32 {
        if self.base == 2 {
            return digit ^ (key >> 63) as u32;
        }
        let a = 1 + (((key >> 32) * (self.base as u64 - 1)) >> 32) as u32;
        let c = (((key & 0xffff_ffff) * self.base as u64) >> 32) as u32;
        self.rem(a * digit + c)
    }

    /// The digits a sampler of `spp` scrambles: the fewest `k` with
    /// `base^k ≥ spp`, at most `levels`; and `base^k`.
    const fn digits_for(&self, spp: u32) -> (u32, u32) {
        let (mut k, mut cells) = (0u32, 1u32);
        while cells < spp && k < self.levels {
            cells *= self.base;
            k += 1;
        }
        (k, cells)
    }
}

/// [`HaltonBase`] of every prime base.
static HALTON: [HaltonBase; HALTON_BASES] = {
    let mut t = [HaltonBase::new(2); HALTON_BASES];
    let mut d = 1;
    while d < HALTON_BASES {
        t[d] = HaltonBase::new(PRIMES[d]);
        d += 1;
    }
    t
};

/// Owen-scrambled Halton samples: dimension `d` is the radical inverse of
/// the sample index in the `d`-th prime base (2, 3, 5, 7, … for the first
/// 64 dimensions, enough for 10 bounces; beyond that the values are
/// independent uniforms), each digit passed through a random permutation
/// that depends on the digits before it (a nested, Owen scramble) and on
/// `(seed, pixel, d)`. The permutations are affine, `x ↦ (a·x + c) mod b`
/// with `a ≠ 0` (a bit flip in base 2): each digit is uniform, and two
/// different digits go to a uniform pair of different digits, the
/// pairwise law on which the variance of Owen's scramble rests.
///
/// Only the digits that tell the pixel's samples apart are scrambled: the
/// first `k` in base `b`, the fewest with `b^k ≥ spp` (at most the `f32`
/// resolution, `b^k ≤ 2²⁴`). Below them the value is uniform in its cell
/// of width `b^-k`, hashed from the digits' node, which is what scrambling
/// the zero digits further down would give (independent uniform digits),
/// at the price of `k` permutations instead of one per digit of an `f32`.
///
/// So the first `b^k` samples of a pixel fill the `b^k` strata of base `b`
/// once each in every dimension, and with `2^a · 3^b` samples the pixel
/// positions fill a `2^a × 3^b` grid exactly once. Indices come in blocks
/// of `b^k`: index `i` uses the digits of `i mod b^k`, and each block
/// (`i / b^k`) has its own scramble, so every block is a fresh stratified
/// set. Works for any spp; best with products of small primes.
///
/// ```
/// use glam::UVec2;
/// use strata::sampler::{Halton, Sampler};
/// // 6 samples: one in each cell of a 2 × 3 grid of the pixel.
/// let mut s = Halton::new(6, 1).unwrap();
/// let mut cells = [0; 6];
/// for i in 0..6 {
///     s.start_pixel_sample(UVec2::new(4, 2), i);
///     let p = s.pixel_2d();
///     cells[(p.y * 3.0) as usize * 2 + (p.x * 2.0) as usize] += 1;
/// }
/// assert_eq!(cells, [1; 6]);
/// ```
#[derive(Clone, Debug)]
pub struct Halton {
    spp: u32,
    pixel: PixelKey,
    index: u32,
    dimension: u32,
    /// Per base: the digits scrambled for this spp, and `base^digits`.
    digits: [u8; HALTON_BASES],
    cells: [u32; HALTON_BASES],
    pixel_2d: Vec2,
}

impl Halton {
    /// A Halton sampler; `None` if `spp` is 0.
    #[inline]
    #[must_use]
    pub fn new(spp: u32, seed: u64) -> Option<Self> {
        if spp == 0 {
            return None;
        }
        let (mut digits, mut cells) = ([0; HALTON_BASES], [0; HALTON_BASES]);
        for (d, b) in HALTON.iter().enumerate() {
            let (k, c) = b.digits_for(spp);
            (digits[d], cells[d]) = (k as u8, c);
        }
        let mut s = Self {
            spp,
            pixel: PixelKey::new(seed),
            index: 0,
            dimension: 2,
            digits,
            cells,
            pixel_2d: Vec2::ZERO,
        };
        s.start_pixel_sample(UVec2::ZERO, 0);
        Some(s)
    }

    /// Dimension `d` of the current sample.
    #[inline]
    fn value(&self, d: u32) -> f32 {
        if d >= HALTON_BASES as u32 {
            // Beyond the 64 bases: independent uniform values (a repeated
            // base would be driven by the same index digits and correlate).
            let h = mix64(self.pixel.key ^ HALTON_SALT ^ ((d as u64) << 32 | self.index as u64));
            return u32_to_unit_f32((h >> 32) as u32);
        }
        let b = &HALTON[d as usize];
        let cells = self.cells[d as usize];
        let mut key = mix64(self.pixel.key ^ HALTON_SALT ^ d as u64);
        let mut i = self.index;
        if i >= cells {
            // A later block of b^k indices: a scramble of its own.
            key = mix64(key ^ (i / cells) as u64);
            i %= cells;
        }
        // The scrambled digits, most significant first, as an integer.
        let mut stratum = 0u32;
        for _ in 0..self.digits[d as usize] {
            let (rest, digit) = if b.base == 2 {
                (i >> 1, i & 1)
            } else {
                b.div_rem(i)
            };
            i = rest;
            let permuted = b.permute(digit, key);
            stratum = stratum * b.base + permuted;
            // The next digit's permutation depends on this one (nested): a
            // multiply-xorshift step, cheaper than a full mix per digit.
            key = (key ^ (digit as u64 + 1)).wrapping_mul(0x9e37_79b9_7f4a_7c15);
            key ^= key >> 29;
        }
        // The digits below: uniform in the stratum, from the node's key.
        let j = u32_to_unit_f32((mix64(key) >> 32) as u32);
        stratum_point(stratum, j, cells, 1.0 / cells as f64)
    }
}

impl Sampler for Halton {
    #[inline]
    fn samples_per_pixel(&self) -> u32 {
        self.spp
    }

    #[inline]
    fn start_pixel_sample(&mut self, pixel: UVec2, index: u32) {
        self.pixel.set(pixel);
        self.index = index;
        self.dimension = 2;
        self.pixel_2d = Vec2::new(self.value(0), self.value(1));
    }

    #[inline]
    fn pixel_2d(&mut self) -> Vec2 {
        self.pixel_2d
    }

    #[inline]
    fn next_1d(&mut self) -> f32 {
        let d = self.dimension;
        self.dimension = d.wrapping_add(1);
        self.value(d)
    }

    #[inline]
    fn next_2d(&mut self) -> Vec2 {
        let d = self.dimension;
        self.dimension = d.wrapping_add(2);
        Vec2::new(self.value(d), self.value(d.wrapping_add(1)))
    }

    #[inline]
    fn skip_1d(&mut self) {
        self.dimension = self.dimension.wrapping_add(1);
    }

    #[inline]
    fn skip_2d(&mut self) {
        self.dimension = self.dimension.wrapping_add(2);
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
    fn permute_is_a_bijection() {
        for len in [1u32, 2, 3, 5, 16, 17, 31, 100, 1000] {
            for key in [0u32, 1, 0xdead_beef, u32::MAX] {
                let mut seen = [false; 1000];
                for i in 0..len {
                    let j = permute(i, len, key);
                    assert!(j < len);
                    assert!(!seen[j as usize], "len {len} key {key}: {j} twice");
                    seen[j as usize] = true;
                }
            }
        }
        assert_eq!(permute(0, 0, 5), 0);
        // Out-of-range inputs fold instead of walking forever.
        assert_eq!(permute(3, 3, 0), permute(0, 3, 0));
        assert!(permute(u32::MAX, 1000, 7) < 1000);
    }

    /// One round of Kensler's permutation as published (Kensler 2013,
    /// *Correlated Multi-Jittered Sampling*), for the derived forms.
    fn kensler_round(mut i: u32, w: u32, p: u32) -> u32 {
        i ^= p;
        i = i.wrapping_mul(0xe170_893d);
        i ^= p >> 16;
        i ^= (i & w) >> 4;
        i ^= p >> 8;
        i = i.wrapping_mul(0x0929_eb3f);
        i ^= p >> 23;
        i ^= (i & w) >> 1;
        i = i.wrapping_mul(1 | p >> 27);
        i = i.wrapping_mul(0x6935_fa69);
        i ^= (i & w) >> 11;
        i = i.wrapping_mul(0x74dc_b303);
        i ^= (i & w) >> 2;
        i = i.wrapping_mul(0x9e50_1cc3);
        i ^= (i & w) >> 2;
        i = i.wrapping_mul(0xc860_a3df);
        i &= w;
        i ^ i >> 5
    }

    #[test]
    fn derived_rounds_equal_the_published_one() {
        // The folded multiplier, and the steps left out below 16, give the
        // bits of the round as published.
        let mut rng = Pcg32::new(3, 5);
        for _ in 0..20_000 {
            let p = rng.next_u32();
            let small = (1u32 << (rng.next_u32() % 5)) - 1;
            let i = rng.next_u32() & small;
            let want = kensler_round(i, small, p);
            assert_eq!(
                permute_round_keyed::<true>(i, small, RoundKey::new(p)),
                want
            );
            assert_eq!(permute_round(i, small, p), want);
            let w = u32::MAX >> (rng.next_u32() % 32);
            let j = rng.next_u32() & w;
            assert_eq!(permute_round(j, w, p), kensler_round(j, w, p), "w {w:#x}");
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

    /// The integer path of a power-of-two axis gives `stratum_point`'s
    /// bits: every `n = 2^k` up to `2²⁴`, strata at both ends and inside,
    /// jitter words at both ends, at the rounding ties and at random.
    #[test]
    fn axis_points_match_stratum_point() {
        let mut rng = Pcg32::new(7, STREAM);
        for k in 0..=24 {
            let n = 1u32 << k;
            let axis = Axis::new(n);
            assert_ne!(axis.shift, Axis::GENERAL);
            let mut strata = [0, 1, n / 3, n / 2, n.saturating_sub(2), n - 1];
            let mut words = [0, 0xff, 0x100, 1 << 31, u32::MAX - 0xff, u32::MAX, 0, 0];
            for _ in 0..200 {
                strata[2] = rng.next_u32() % n;
                words[6] = rng.next_u32();
                // A jitter whose low k bits are exactly half: a tie.
                words[7] = (rng.next_u32() & !((1 << 8 << k.min(23)) - 1)) | 1 << 7 << k.min(23);
                for &s in &strata {
                    for &x in &words {
                        let want =
                            stratum_point(s.min(n - 1), u32_to_unit_f32(x), n, 1.0 / n as f64);
                        let got = axis.point(s.min(n - 1), x);
                        assert_eq!(got.to_bits(), want.to_bits(), "n {n} s {s} x {x:#x}");
                    }
                }
            }
        }
        // Other n take the general path.
        let axis = Axis::new(12);
        assert_eq!(axis.shift, Axis::GENERAL);
        assert_eq!(axis.div_rem(29), (2, 5));
        assert_eq!(Axis::new(16).div_rem(37), (2, 5));
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

    #[test]
    fn huge_indices_and_dimensions_do_not_panic() {
        let unit = |v: Vec2| v.cmplt(Vec2::ONE).all() && v.cmpge(Vec2::ZERO).all();
        let mut s = Stratified::new(7, 1).unwrap();
        s.start_pixel_sample(UVec2::new(u32::MAX, u32::MAX), u32::MAX);
        s.0.dimension = u32::MAX - 1;
        assert!(unit(s.next_2d()));
        assert!((0.0..1.0).contains(&s.next_1d()));
        let mut sob = Sobol::new(7, 1).unwrap();
        sob.start_pixel_sample(UVec2::new(u32::MAX, 0), u32::MAX);
        sob.dimension = u32::MAX - 2;
        assert!(unit(sob.next_2d()) && (0.0..1.0).contains(&sob.next_1d()));
        let mut hal = Halton::new(7, 1).unwrap();
        hal.start_pixel_sample(UVec2::new(0, u32::MAX), u32::MAX);
        assert!(unit(hal.pixel_2d()));
        for _ in 0..100 {
            assert!(unit(hal.next_2d()) && (0.0..1.0).contains(&hal.next_1d()));
        }
    }

    #[test]
    fn grid_pixel_positions_are_centres_in_raster_order() {
        let mut s = UniformGrid::new(6, 0).unwrap(); // 3 × 2
        assert_eq!(s.grid(), (3, 2));
        for i in 0..6 {
            s.start_pixel_sample(UVec2::new(4, 4), i);
            let p = s.pixel_2d();
            let want = Vec2::new(((i % 3) as f32 + 0.5) / 3.0, ((i / 3) as f32 + 0.5) / 2.0);
            assert_eq!(p, want);
        }
    }

    #[test]
    fn pixel_2d_does_not_advance() {
        let mut a = Stratified::new(8, 3).unwrap();
        let mut b = a.clone();
        a.start_pixel_sample(UVec2::new(1, 1), 2);
        b.start_pixel_sample(UVec2::new(1, 1), 2);
        let _ = a.pixel_2d();
        let _ = a.pixel_2d();
        assert_eq!(a.next_2d(), b.next_2d());
    }

    #[test]
    fn stratified_jitter_is_a_function_of_the_dimension() {
        // With spp = 1 there is one stratum and a value is its jitter
        // alone: dimension d reads the same word whether a 1D draw or
        // either half of a 2D draw reaches it, across the block edge too.
        let pixel = UVec2::new(2, 3);
        for i in 0..4 {
            let mut ones = Stratified::new(1, 9).unwrap();
            let mut twos = ones.clone();
            let mut odd = ones.clone();
            ones.start_pixel_sample(pixel, i);
            twos.start_pixel_sample(pixel, i);
            odd.start_pixel_sample(pixel, i);
            let by_one: [f32; 20] = core::array::from_fn(|_| ones.next_1d());
            let first = odd.next_1d();
            assert_eq!(first, by_one[0]);
            for k in 0..9 {
                let v = twos.next_2d();
                assert_eq!((v.x, v.y), (by_one[2 * k], by_one[2 * k + 1]));
                let w = odd.next_2d();
                assert_eq!((w.x, w.y), (by_one[2 * k + 1], by_one[2 * k + 2]));
            }
            // Distinct dimensions are not one word repeated.
            assert_ne!(by_one[0], by_one[1]);
        }
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
/// caches and blocks of the fast paths, which must give the same bits.
#[cfg(test)]
mod reference {
    use super::*;
    use crate::rng::stream_state;

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
}

#[cfg(test)]
mod fast_paths {
    use super::*;

    /// Pseudo-random visits: pixels from a small set (so the per-pixel
    /// caches hit and miss), indices within and beyond spp, and a mixed
    /// sequence of 1D and 2D draws after each start.
    fn visits(spp: u32, mut f: impl FnMut(UVec2, u32, &[bool])) {
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
    const SPPS: [u32; 12] = [1, 2, 3, 6, 7, 12, 16, 24, 30, 64, 100, 256];

    fn check_strata<const JITTER: bool>(spp: u32) {
        // The grid keeps its pixel strata in raster order.
        let shuffle = JITTER;
        let seed = 11 + spp as u64;
        let mut fast = Strata::<JITTER>::new(spp, seed, shuffle).unwrap();
        let mut slow = reference::Strata {
            spp,
            seed,
            jitter: JITTER,
            shuffle_pixel: shuffle,
            pixel: UVec2::ZERO,
            index: 0,
            dimension: 2,
        };
        visits(spp, |pixel, index, draws| {
            fast.start(pixel, index, shuffle);
            assert_eq!(fast.pixel_2d, slow.start(pixel, index), "spp {spp}");
            for &two in draws {
                if two {
                    assert_eq!(fast.next_2d(), slow.next_2d(), "spp {spp}");
                } else {
                    assert_eq!(fast.next_1d(), slow.next_1d(), "spp {spp}");
                }
            }
        });
    }

    #[test]
    fn strata_equal_their_definition() {
        // Beyond SPPS: the round's `>> 11` step at work, and the cap.
        for spp in SPPS.into_iter().chain([4096, MAX_STRATA_SPP]) {
            check_strata::<true>(spp);
            check_strata::<false>(spp);
        }
    }

    #[test]
    fn sobol_equals_its_definition() {
        for spp in SPPS {
            let seed = 5 + spp as u64;
            let mut s = Sobol::new(spp, seed).unwrap();
            visits(spp, |pixel, index, draws| {
                let want = |d| reference::sobol_value(seed, pixel, index, d);
                s.start_pixel_sample(pixel, index);
                assert_eq!(s.pixel_2d(), Vec2::new(want(0), want(1)));
                let mut d = 2u32;
                for &two in draws {
                    if two {
                        d += d & 1;
                        assert_eq!(s.next_2d(), Vec2::new(want(d), want(d + 1)), "dim {d}");
                        d += 2;
                    } else {
                        assert_eq!(s.next_1d(), want(d), "dim {d}");
                        d += 1;
                    }
                }
            });
        }
        // Dimensions far out, where keys are not kept, and at the wrap.
        let mut s = Sobol::new(4, 9).unwrap();
        for d in [31, 32, 33, 1000, u32::MAX - 9, u32::MAX - 1] {
            s.start_pixel_sample(UVec2::new(3, 4), 2);
            s.dimension = d;
            let v = s.next_1d();
            assert_eq!(
                v,
                reference::sobol_value(9, UVec2::new(3, 4), 2, d),
                "dim {d}"
            );
        }
    }

    #[test]
    fn halton_equals_its_definition() {
        for spp in [1, 6, 16, 100] {
            let seed = 3 + spp as u64;
            let mut s = Halton::new(spp, seed).unwrap();
            visits(spp, |pixel, index, draws| {
                let want = |d| reference::halton_value(seed, spp, pixel, index, d);
                s.start_pixel_sample(pixel, index);
                assert_eq!(s.pixel_2d(), Vec2::new(want(0), want(1)));
                let mut d = 2u32;
                for &two in draws {
                    if two {
                        assert_eq!(s.next_2d(), Vec2::new(want(d), want(d + 1)), "dim {d}");
                        d += 2;
                    } else {
                        assert_eq!(s.next_1d(), want(d), "dim {d}");
                        d += 1;
                    }
                }
            });
        }
    }

    #[test]
    fn halton_bases_match_their_loop() {
        for (d, b) in HALTON.iter().enumerate() {
            assert_eq!(b.base, PRIMES[d]);
            for x in [0, 1, b.base - 1, b.base, 12345, u32::MAX - 1, u32::MAX] {
                assert_eq!(b.div_rem(x), (x / b.base, x % b.base), "base {}", b.base);
                assert_eq!(b.rem(x), x % b.base);
            }
            let cells = (b.base as u64).pow(b.levels);
            assert!(cells <= 1 << 24 && cells * b.base as u64 > 1 << 24);
        }
        let digits = |d: usize, spp| HALTON[d].digits_for(spp);
        assert_eq!(
            [digits(0, 1), digits(0, 16), digits(0, 17)],
            [(0, 1), (4, 16), (5, 32)]
        );
        assert_eq!([digits(1, 16), digits(63, 16)], [(3, 27), (1, 311)]);
        assert_eq!(digits(0, u32::MAX), (24, 1 << 24));
    }
}
