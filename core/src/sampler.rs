//! Pixel samplers: where each sample of a pixel puts its pixel position and
//! its random numbers.
//!
//! # Dimensions
//!
//! A pixel sample is a point in `[0, 1)^d`. Dimensions 0 and 1 are the
//! position in the pixel, returned by [`Sampler::pixel_2d`] whenever it is
//! called. [`Sampler::next_1d`] and [`Sampler::next_2d`] then hand out
//! dimensions 2, 3, … in call order (a 2D draw takes two). Every kind draws
//! the same count of stream values per call, so dimension `k` of a sample
//! has the same value whichever kind-independent path led to it.
//!
//! # Determinism
//!
//! Every value is a pure function of `(seed, pixel, sample index,
//! dimension)`: [`Sampler::start_pixel_sample`] rebuilds all state from
//! those numbers (see [`crate::rng`]), so samples may be drawn in any order,
//! on any thread, in any tile, and revisiting a sample gives the same bits.
//!
//! # Kinds
//!
//! | kind | pixel dimensions | other dimensions |
//! |---|---|---|
//! | [`Independent`] | uniform random | uniform random |
//! | [`UniformGrid`] | centres of an `nx × ny` grid, raster order | centres of `spp` strata, shuffled |
//! | [`Stratified`] | jittered `nx × ny` strata, shuffled | jittered strata, shuffled |
//! | [`Sobol`] | Owen-scrambled Sobol' `(0, 2)`-sequence | padded Owen-scrambled Sobol', groups of 4 |
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
//! [`ZSobol`] alone is built for an image resolution and correlates
//! neighbouring pixels on purpose (their samples complement each other,
//! so the error is blue noise); the others treat every pixel
//! independently.
//!
//! Samplers are `Clone + Debug`, never `Copy` (a silent copy would repeat a
//! stream), and have no `Default` that would hide a seed. They are `Send +
//! Sync`; each thread owns its own.

use glam::{UVec2, Vec2};
use rand_core::Rng;

use crate::rng::{Pcg32, mix64, pixel_hash, pixel_sample_rng, u32_to_unit_f32};

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
pub const fn permute(mut i: u32, len: u32, key: u32) -> u32 {
    if len <= 1 {
        return 0;
    }
    // Outside [0, len) the cycle walk need not come back: fold first.
    if i >= len {
        i %= len;
    }
    let p = key;
    let mut w = len - 1;
    w |= w >> 1;
    w |= w >> 2;
    w |= w >> 4;
    w |= w >> 8;
    w |= w >> 16;
    // Each step is a bijection of [0, w]; cycle walking restricts it to
    // [0, len), and len > w / 2 bounds the expected walk by two rounds.
    loop {
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
        i ^= i >> 5;
        if i < len {
            break;
        }
    }
    // (i + p) mod len without overflow: i < len, so one subtraction.
    let r = i.wrapping_add(p % len);
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
    let nf = n as f64;
    let mut v = ((s as f64 + j as f64) * inv_n) as f32;
    // An f32 (24-bit significand) times an integer below 2^29 fits the 53
    // bits of an f64 exactly; n ≤ MAX_STRATA_SPP = 2^24.
    if v as f64 * nf >= (s + 1) as f64 {
        v = f32::from_bits(v.to_bits() - 1);
    } else if (v as f64 * nf) < s as f64 {
        v = f32::from_bits(v.to_bits() + 1);
    }
    v
}

/// Uniform random samples: the course's `get_ray`, with a reproducible
/// stream per pixel sample.
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
    seed: u64,
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
            seed,
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
        self.rng = pixel_sample_rng(self.seed, pixel, index);
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
}

/// Keeps permutation keys apart from stream states: `π − 3` in 64 bits.
const PERMUTATION_SALT: u64 = 0x243f_6a88_85a3_08d3;

/// The largest spp the strata samplers accept: beyond `2²⁴` a stratum of a
/// 1D dimension is narrower than the `f32` spacing near 1, and "one sample
/// per stratum" could no longer hold.
pub const MAX_STRATA_SPP: u32 = 1 << 24;

/// The state the two strata samplers share; `jitter` is the only
/// difference between them, as in pbrt's `StratifiedSampler`.
#[derive(Clone, Debug)]
struct Strata {
    spp: u32,
    nx: u32,
    ny: u32,
    /// `1 / spp`, `1 / nx`, `1 / ny`: reciprocals instead of divisions.
    inv: [f64; 3],
    seed: u64,
    jitter: bool,
    /// Hash of (seed, pixel), the start of every permutation key.
    pixel_key: u64,
    /// Stratum slot `index % spp` and pass `index / spp`.
    slot: u32,
    pass: u32,
    dimension: u32,
    rng: Pcg32,
    pixel: Vec2,
}

impl Strata {
    fn new(spp: u32, seed: u64, jitter: bool, shuffle_pixel: bool) -> Option<Self> {
        if spp == 0 || spp > MAX_STRATA_SPP {
            return None;
        }
        let (nx, ny) = grid_dims(spp);
        let mut s = Self {
            spp,
            nx,
            ny,
            inv: [1.0 / spp as f64, 1.0 / nx as f64, 1.0 / ny as f64],
            seed,
            jitter,
            pixel_key: 0,
            slot: 0,
            pass: 0,
            dimension: 2,
            rng: pixel_sample_rng(seed, UVec2::ZERO, 0),
            pixel: Vec2::ZERO,
        };
        s.start(UVec2::ZERO, 0, shuffle_pixel);
        Some(s)
    }

    /// The shuffled stratum of the current sample in `dimension`.
    #[inline]
    fn stratum(&self, dimension: u32) -> u32 {
        // Salted so that a key never equals a stream state
        // (`mix64(pixel_key ^ index)`) of the same pixel.
        let word = dimension as u64 | (self.pass as u64) << 32;
        let key = mix64(self.pixel_key ^ PERMUTATION_SALT ^ word);
        permute(self.slot, self.spp, (key >> 32) as u32)
    }

    /// One jitter value per stratified coordinate; drawn even when unused
    /// so the stream position depends only on the dimension.
    #[inline]
    fn jitter(&mut self) -> f32 {
        let u = u32_to_unit_f32(self.rng.next_u32());
        if self.jitter { u } else { 0.5 }
    }

    #[inline]
    fn point_2d(&mut self, stratum: u32) -> Vec2 {
        let jx = self.jitter();
        let jy = self.jitter();
        Vec2::new(
            stratum_point(stratum % self.nx, jx, self.nx, self.inv[1]),
            stratum_point(stratum / self.nx, jy, self.ny, self.inv[2]),
        )
    }

    fn start(&mut self, pixel: UVec2, index: u32, shuffle_pixel: bool) {
        self.pixel_key = pixel_hash(self.seed, pixel);
        self.slot = index % self.spp;
        self.pass = index / self.spp;
        self.rng = pixel_sample_rng(self.seed, pixel, index);
        let stratum = if shuffle_pixel {
            self.stratum(0)
        } else {
            self.slot
        };
        self.pixel = self.point_2d(stratum);
        self.dimension = 2;
    }

    #[inline]
    fn next_1d(&mut self) -> f32 {
        let stratum = self.stratum(self.dimension);
        self.dimension = self.dimension.wrapping_add(1);
        let j = self.jitter();
        stratum_point(stratum, j, self.spp, self.inv[0])
    }

    #[inline]
    fn next_2d(&mut self) -> Vec2 {
        let stratum = self.stratum(self.dimension);
        self.dimension = self.dimension.wrapping_add(2);
        self.point_2d(stratum)
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
pub struct UniformGrid(Strata);

impl UniformGrid {
    /// A grid sampler; `None` if `spp` is 0 or above [`MAX_STRATA_SPP`].
    #[inline]
    #[must_use]
    pub fn new(spp: u32, seed: u64) -> Option<Self> {
        Strata::new(spp, seed, false, false).map(Self)
    }

    /// The `(nx, ny)` pixel grid.
    #[inline]
    #[must_use]
    pub fn grid(&self) -> (u32, u32) {
        (self.0.nx, self.0.ny)
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
        self.0.pixel
    }
    #[inline]
    fn next_1d(&mut self) -> f32 {
        self.0.next_1d()
    }
    #[inline]
    fn next_2d(&mut self) -> Vec2 {
        self.0.next_2d()
    }
}

/// Jittered stratified samples for any spp (the course's `render_jittered`,
/// with its offset bug D3 fixed): each sample takes a uniform point inside
/// its own stratum, and the strata of every dimension are shuffled
/// independently.
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
pub struct Stratified(Strata);

impl Stratified {
    /// A jittered stratified sampler; `None` if `spp` is 0 or above
    /// [`MAX_STRATA_SPP`].
    #[inline]
    #[must_use]
    pub fn new(spp: u32, seed: u64) -> Option<Self> {
        Strata::new(spp, seed, true, true).map(Self)
    }

    /// The `(nx, ny)` strata of the 2D dimensions.
    #[inline]
    #[must_use]
    pub fn grid(&self) -> (u32, u32) {
        (self.0.nx, self.0.ny)
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
        self.0.pixel
    }
    #[inline]
    fn next_1d(&mut self) -> f32 {
        self.0.next_1d()
    }
    #[inline]
    fn next_2d(&mut self) -> Vec2 {
        self.0.next_2d()
    }
}

/// The `Sampler` impl shared by the hashed low-discrepancy samplers: all
/// state is `(pixel key, index, dimension)`, and each dimension's value
/// comes from the type's `value(d)`. `align_2d` starts 2D draws on an even
/// dimension (Sobol' pairs must not straddle groups of four).
macro_rules! hashed_sampler {
    ($name:ident, $align:ident) => {
        impl Sampler for $name {
            #[inline]
            fn samples_per_pixel(&self) -> u32 {
                self.spp
            }

            #[inline]
            fn start_pixel_sample(&mut self, pixel: UVec2, index: u32) {
                self.pixel_key = pixel_hash(self.seed, pixel);
                self.index = index;
                self.dimension = 2;
                self.pixel = Vec2::new(self.value(0), self.value(1));
            }

            #[inline]
            fn pixel_2d(&mut self) -> Vec2 {
                self.pixel
            }

            #[inline]
            fn next_1d(&mut self) -> f32 {
                let d = self.dimension;
                self.dimension = d.wrapping_add(1);
                self.value(d)
            }

            #[inline]
            fn next_2d(&mut self) -> Vec2 {
                let d = hashed_sampler!(@start $align, self.dimension);
                self.dimension = d.wrapping_add(2);
                Vec2::new(self.value(d), self.value(d.wrapping_add(1)))
            }
        }
    };
    (@start align_2d, $d:expr) => {
        $d.wrapping_add($d & 1)
    };
    (@start no_align, $d:expr) => {
        $d
    };
}

/// Keys of the Sobol' index shuffles and output scrambles, apart from
/// each other and from stream states.
const SOBOL_GROUP_SALT: u64 = 0x1319_8a2e_0370_7344;
const SOBOL_DIM_SALT: u64 = 0xa409_3822_299f_31d0;

/// Owen-scrambled Sobol' samples (Burley 2020), padded in pairs of
/// dimensions (as pbrt's `PaddedSobolSampler`); see the `sobol` module for
/// the construction. Best with a power-of-two spp: the first `2^k` samples
/// of a pixel are a `(0, k, 2)`-net in the pixel position and in every 2D
/// draw, and stratify every dimension into `2^k` equal strata.
///
/// `next_2d` starts on an even dimension (skipping one if needed), so a 2D
/// draw is always one pair and keeps its joint stratification. (At the
/// dimension counter's wrap-around, 2³² draws into a sample, it would
/// reuse dimension 0.)
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
    seed: u64,
    pixel_key: u64,
    index: u32,
    dimension: u32,
    pixel: Vec2,
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
            seed,
            pixel_key: 0,
            index: 0,
            dimension: 2,
            pixel: Vec2::ZERO,
        };
        s.start_pixel_sample(UVec2::ZERO, 0);
        Some(s)
    }

    /// Dimension `d` of the current sample.
    #[inline]
    fn value(&self, d: u32) -> f32 {
        let group = (mix64(self.pixel_key ^ SOBOL_GROUP_SALT ^ (d / 2) as u64) >> 32) as u32;
        let index = sobol::nested_uniform_scramble(self.index, group);
        let key = (mix64(self.pixel_key ^ SOBOL_DIM_SALT ^ d as u64) >> 32) as u32;
        u32_to_unit_f32(sobol::nested_uniform_scramble(
            sobol::sobol(index, (d % 2) as usize),
            key,
        ))
    }
}

hashed_sampler!(Sobol, align_2d);

/// The first 64 primes: the Halton bases of dimensions 0–63.
const PRIMES: [u32; 64] = [
    2, 3, 5, 7, 11, 13, 17, 19, 23, 29, 31, 37, 41, 43, 47, 53, 59, 61, 67, 71, 73, 79, 83, 89, 97,
    101, 103, 107, 109, 113, 127, 131, 137, 139, 149, 151, 157, 163, 167, 173, 179, 181, 191, 193,
    197, 199, 211, 223, 227, 229, 233, 239, 241, 251, 257, 263, 269, 271, 277, 281, 283, 293, 307,
    311,
];

/// Keys of the Halton digit scrambles, apart from other keys.
const HALTON_SALT: u64 = 0xbe54_66cf_34e9_0c6c;

/// Owen-scrambled Halton samples: dimension `d` is the radical inverse of
/// the sample index in the `d`-th prime base (2, 3, 5, 7, … for the first
/// 64 dimensions, enough for 10 bounces; beyond that the values are
/// independent uniforms), each digit passed through a random permutation that
/// depends on the digits before it (a nested, Owen scramble) and on
/// `(seed, pixel, d)`. Digits are scrambled down to `2⁻²⁵`, so the value
/// uses the full precision of an `f32`.
///
/// With `2^a · 3^b` samples the pixel positions fill a `2^a × 3^b` grid
/// exactly once; every dimension alone is stratified in its base. Works
/// for any spp; best with products of small primes.
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
    seed: u64,
    pixel_key: u64,
    index: u32,
    dimension: u32,
    pixel: Vec2,
}

impl Halton {
    /// A Halton sampler; `None` if `spp` is 0.
    #[inline]
    #[must_use]
    pub fn new(spp: u32, seed: u64) -> Option<Self> {
        if spp == 0 {
            return None;
        }
        let mut s = Self {
            spp,
            seed,
            pixel_key: 0,
            index: 0,
            dimension: 2,
            pixel: Vec2::ZERO,
        };
        s.start_pixel_sample(UVec2::ZERO, 0);
        Some(s)
    }

    /// Dimension `d` of the current sample: the Owen-scrambled radical
    /// inverse of the index in base `PRIMES[d % 64]`.
    fn value(&self, d: u32) -> f32 {
        if d >= 64 {
            // Beyond the 64 bases: independent uniform values (a repeated
            // base would be driven by the same index digits and correlate).
            let h = mix64(self.pixel_key ^ HALTON_SALT ^ ((d as u64) << 32 | self.index as u64));
            return u32_to_unit_f32((h >> 32) as u32);
        }
        let base = PRIMES[d as usize];
        let inv = 1.0 / base as f64;
        let mut key = mix64(self.pixel_key ^ HALTON_SALT ^ d as u64);
        let (mut i, mut scale, mut v) = (self.index, inv, 0.0f64);
        // The integer formed by the first `levels` scrambled digits, where
        // base^levels ≤ 2^24: the f32 result must stay in that interval.
        let (mut levels, mut cells) = (0u32, 1u64);
        while cells * base as u64 <= 1 << 24 {
            cells *= base as u64;
            levels += 1;
        }
        let (mut prefix, mut k) = (0u64, 0u32);
        // Digits of the index, then scrambled zeros, down to 2^-25.
        while scale > 1.0 / 33_554_432.0 {
            let digit = i % base;
            i /= base;
            // In base 2 a random permutation of {0, 1} is a keyed bit flip.
            let permuted = if base == 2 {
                digit ^ (key >> 63) as u32
            } else {
                permute(digit, base, (key >> 32) as u32)
            };
            v += permuted as f64 * scale;
            if k < levels {
                prefix = prefix * base as u64 + permuted as u64;
            }
            k += 1;
            // The next digit's permutation depends on this one (nested): a
            // multiply-xorshift step, cheaper than a full mix per digit.
            key = (key ^ (digit as u64 + 1)).wrapping_mul(0x9e37_79b9_7f4a_7c15);
            key ^= key >> 29;
            scale *= inv;
        }
        // Rounding to f32 may cross a cell boundary by an ulp: step back in.
        // f · cells is exact in f64 (24 + 24 bits).
        let mut f = (v as f32).min(crate::rng::ONE_MINUS_EPSILON);
        for _ in 0..4 {
            let cell = (f as f64 * cells as f64) as u64; // ≥ 0: truncation floors
            if cell > prefix {
                f = f32::from_bits(f.to_bits() - 1);
            } else if cell < prefix {
                f = f32::from_bits(f.to_bits() + 1);
            } else {
                break;
            }
        }
        f
    }
}

hashed_sampler!(Halton, no_align);

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
    fn kinds_consume_the_stream_alike() {
        // Jitter of a stratified sample and the independent value of the
        // same dimension come from the same stream word, so a sample with
        // spp = 1 (one stratum) reproduces the independent sampler exactly.
        let mut ind = Independent::new(1, 9).unwrap();
        let mut st = Stratified::new(1, 9).unwrap();
        for i in 0..4 {
            ind.start_pixel_sample(UVec2::new(2, 3), i);
            st.start_pixel_sample(UVec2::new(2, 3), i);
            assert_eq!(ind.pixel_2d(), st.pixel_2d());
            assert_eq!(ind.next_1d(), st.next_1d());
            assert_eq!(ind.next_2d(), st.next_2d());
        }
    }
}
