//! ZSobol': one Owen-scrambled Sobol' sequence shared by every pixel of
//! the image, visited along a Morton (Z) curve with hashed base-4 digit
//! permutations, so that neighbouring pixels receive complementary points
//! and the image's error becomes blue noise (Ahmed and Wonka 2020,
//! *Screen-Space Blue-Noise Diffusion of Monte Carlo Sampling Error via
//! Hierarchical Ordering of Pixels*, SIGGRAPH Asia; pbrt-v4's
//! `ZSobolSampler`).
//!
//! The construction, its guarantees and its limits are documented on
//! [`ZSobol`].

use glam::{UVec2, Vec2};

use super::Sampler;
use super::sobol;
use crate::rng::{mix64, u32_to_unit_f32};

/// Keys of the image-wide hashes, apart from every other key in the crate
/// (further hexadecimal digits of π, after those the other samplers use).
const ZSOBOL_SEED_SALT: u64 = 0x4528_21e6_38d0_1377;

const ZSOBOL_DIM_SALT: u64 = 0xc0ac_29b7_c97c_50dd;

/// The 24 permutations of `{0, 1, 2, 3}` in lexicographic order, each
/// packed into a byte: digit `t` goes to `(p >> 2t) & 3`.
const PERMUTATIONS: [u8; 24] = permutations();

const fn permutations() -> [u8; 24] {
    let mut out = [0u8; 24];
    let mut n = 0;
    let mut a = 0;
    while a < 4 {
        let mut b = 0;
        while b < 4 {
            let mut c = 0;
            while c < 4 {
                let d = 6 - a - b - c;
                if a != b && a != c && b != c {
                    out[n] = (a | b << 2 | c << 4 | d << 6) as u8;
                    n += 1;
                }
                c += 1;
            }
            b += 1;
        }
        a += 1;
    }
    out
}

/// Spreads the 32 bits of `v` to the even bit positions of a `u64`.
#[inline]
const fn spread_bits(v: u32) -> u64 {
    let mut x = v as u64;
    x = (x | x << 16) & 0x0000_ffff_0000_ffff;
    x = (x | x << 8) & 0x00ff_00ff_00ff_00ff;
    x = (x | x << 4) & 0x0f0f_0f0f_0f0f_0f0f;
    x = (x | x << 2) & 0x3333_3333_3333_3333;
    (x | x << 1) & 0x5555_5555_5555_5555
}

/// The Morton code of `(x, y)`: `x`'s bits at even positions, `y`'s at odd.
#[inline]
const fn morton2(x: u32, y: u32) -> u64 {
    spread_bits(x) | spread_bits(y) << 1
}

/// `⌈log₂ n⌉` for `n ≥ 1`.
#[inline]
const fn ceil_log2(n: u32) -> u32 {
    if n <= 1 {
        0
    } else {
        32 - (n - 1).leading_zeros()
    }
}

/// Why a [`ZSobol`] was refused.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum ZSobolError {
    /// The sample count is 0.
    NoSamples,
    /// The resolution has no pixels (a side is 0).
    NoPixels,
    /// The Morton index `2r + k` would need more than 64 bits (see the
    /// module docs).
    IndexTooWide {
        /// The sample count asked for.
        spp: u32,
        /// The resolution asked for.
        resolution: UVec2,
        /// The bits the index would need.
        bits: u32,
    },
}

impl core::fmt::Display for ZSobolError {
    #[inline]
    fn fmt(&self, f: &mut core::fmt::Formatter<'_>) -> core::fmt::Result {
        match *self {
            ZSobolError::NoSamples => f.write_str("zsobol needs at least one sample per pixel"),
            ZSobolError::NoPixels => f.write_str("zsobol needs a resolution of at least 1 x 1"),
            ZSobolError::IndexTooWide {
                spp,
                resolution,
                bits,
            } => write!(
                f,
                "zsobol at {spp} samples per pixel over {} x {} pixels needs a {bits}-bit \
                 sample index; 64 bits is the most",
                resolution.x, resolution.y
            ),
        }
    }
}

impl core::error::Error for ZSobolError {}

/// Sobol' points of one image-wide sequence, handed to pixels along a
/// hashed Morton curve so that neighbouring pixels get complementary
/// points: the same per-pixel nets as [`Sobol`](super::Sobol), but an error
/// image of blue noise. Built for an image resolution; a pure function of
/// `(seed, pixel, sample index, dimension)` for a given spp and resolution,
/// like every sampler.
///
/// # Construction
///
/// With `spp` samples per pixel, let `k = ⌈log₂ spp⌉` (the pixel's *block*
/// holds `2^k` sequence points) and `r = ⌈log₂ max(width, height)⌉`. Sample
/// index `i` of pixel `(x, y)` is slot `s = i mod spp` of pass `i / spp`,
/// and its *Morton index* is the 64-bit number
///
/// ```text
/// m = morton(x mod 2^r, y mod 2^r) · 2^k + s        (2r + k bits)
/// ```
///
/// where `morton` interleaves the bits of `x` (even positions) and `y`
/// (odd positions). For each draw, at dimension `d`, `m` is shuffled one
/// base-4 digit at a time: digit `j` goes through one of the 24
/// permutations of `{0, 1, 2, 3}`, chosen by a hash of `m`'s digits above
/// `j` and a key of `(seed, d)`. (With `k` odd the lowest bit is its own
/// digit, flipped by such a hash, so that the pixel digits stay aligned.)
/// The shuffled index selects a point of the Sobol' (0, 2)-sequence
/// (dimensions 0 and 1 for a 2D draw, dimension 0 for a 1D one), which is
/// then Owen-scrambled by a key of `(seed, d)` (Burley 2020, see
/// [`Sobol`](super::Sobol)). The keys depend on the dimension, not on the
/// pixel: every pixel draws from the same scrambled sequence, which is
/// what lets neighbours complement each other.
///
/// # What it guarantees
///
/// Because each digit's permutation depends only on the digits above it,
/// every aligned run of Morton indices maps onto an aligned run of
/// sequence points. So, with `spp = 2^k`, in the pixel position and in
/// every 2D draw:
///
/// - a pixel's `2^k` samples form a `(0, k, 2)`-net (one point in every
///   elementary interval of area `2^-k`); every 1D draw puts one sample in
///   each of `2^k` equal strata; the first `2^j` samples alone form a
///   `(0, j, 2)`-net when `j` ends a digit (`j` and `k` both even or both
///   odd: the first 4 of 16, the first 2 or 8 of 32);
/// - the `4^a · 2^k` samples of an aligned `2^a × 2^a` block of pixels
///   together form a `(0, 2a + k, 2)`-net: neighbours fill each other's
///   gaps, so the errors of neighbouring pixels are negatively correlated
///   and the error image has little low-frequency power;
/// - each value alone is uniform on `[0, 1)` (the output scramble), so
///   every pixel's estimate is unbiased.
///
/// # Limits and choices
///
/// - **spp that is not a power of two.** A pixel takes the first `spp`
///   slots of its block of `2^k`: still unbiased, and its first `2^j`
///   samples are still nets as above, but the block is not filled, so
///   neighbours complement each other only in part. (pbrt-v4 instead
///   renders the power of two below, with a warning; here the count asked
///   for is the count rendered.) Powers of two are what the method is for.
/// - **Sample indices `i ≥ spp`** start pass `i / spp`, which keys every
///   hash: each pass is a fresh, independently scrambled ZSobol' pattern
///   over the image (for adaptive sampling and split renders).
/// - **The 64-bit index.** `2r + k` must fit 64 bits, or
///   [`ZSobol::new`] refuses ([`ZSobolError::IndexTooWide`]); a
///   `4096 × 4096` image at 256 spp needs 32 bits, one of `2^32 × 2^32`
///   pixels at 1 spp 64. Every bit counts: the second Sobol' dimension's
///   generator matrix has a one in the top row of every column (the top
///   bit of `y` is the parity of the index), so it takes 64 columns.
/// - **Pixels outside the resolution** (a filter's reach, a caller's
///   choice) are valid. Up to `2^r` (the power of two at or above the
///   larger side) they belong to the image's pattern: the Morton curve
///   covers the `2^r × 2^r` square. Beyond it, coordinates are taken
///   modulo `2^r` and the quotient keys every hash like a pass, so those
///   pixels get an independent pattern rather than one interleaved with
///   the image's.
/// - **One scramble per image.** Every pixel shares the scrambled
///   sequence of a dimension, so how well one seed stratifies (the
///   scramble's few top-level choices) shows in the whole image: an
///   image's error varies more from seed to seed than with
///   [`Sobol`](super::Sobol), whose pixels average over independent
///   scrambles. The mean over seeds is the same.
/// - **Dimensions.** [`Sampler::next_2d`] takes two dimensions and does not
///   align them (each draw has its own permutation and scramble); the
///   first value of a 2D draw at `d` equals a 1D draw at `d`. At the
///   dimension counter's wrap-around, 2³² draws into a sample, it would
///   reuse dimension 0.
///
/// # Cost
///
/// A draw hashes once per permuted digit, `r + ⌈k/2⌉` digits (at most
/// 32; 11 for a `320 × 180` image at 16 spp). For the first 64
/// dimensions, what does not depend on the sample's slot (the dimension's
/// key, its `r` permuted pixel digits and the permutation of its top slot
/// digit) is remembered from one sample of a pixel to the next, so while a
/// pixel's samples are drawn in a row (as a tile renders them), a draw
/// hashes only the slot digits below the top one: none at 1 and 4 spp,
/// one at 2, 8 and 16. The memo never changes a value: any order gives the
/// same bits.
///
/// ```
/// use glam::UVec2;
/// use strata::sampler::{Sampler, ZSobol};
/// // One sample per pixel: the four pixels of an aligned 2 × 2 block put
/// // their pixel positions in the four quarters of the pixel square.
/// let mut s = ZSobol::new(1, 7, UVec2::new(64, 64)).unwrap();
/// let mut quarters = [0; 4];
/// for (x, y) in [(10, 20), (11, 20), (10, 21), (11, 21)] {
///     s.start_pixel_sample(UVec2::new(x, y), 0);
///     let p = s.pixel_2d();
///     quarters[(p.y * 2.0) as usize * 2 + (p.x * 2.0) as usize] += 1;
/// }
/// assert_eq!(quarters, [1; 4]);
/// ```
#[derive(Clone, Debug)]
pub struct ZSobol {
    spp: u32,
    /// `k`: the pixel's block holds `2^k` points.
    block_bits: u32,
    /// `r`: pixel coordinates are taken modulo `2^r`.
    resolution_bits: u32,
    seed_key: u64,
    /// The key of pass 0 inside the resolution, computed once.
    base_key: u64,
    /// The current sample: its Morton index and its (seed, tile, pass) key.
    morton: u64,
    key: u64,
    dimension: u32,
    pixel: Vec2,
    /// A memo, never a source of values: what dimensions
    /// `0..CACHED_DIMENSIONS` need that does not depend on the sample's
    /// slot (bit `d` of `cached` says whether entry `d` is filled), for
    /// the pixel and key of `cache_tag`. So the samples of one pixel hash
    /// only their lower slot digits (a tile renders a pixel's samples in a
    /// row).
    cache: [DimensionMemo; CACHED_DIMENSIONS],
    cached: u64,
    cache_tag: (u64, u64),
}

/// How many dimensions' pixel digits a [`ZSobol`] remembers.
const CACHED_DIMENSIONS: usize = 64;

/// What a dimension's draws share across the samples of one pixel: its
/// key, its permuted pixel digits, and the permutation of its top slot
/// digit (whose digits above are the pixel's).
#[derive(Clone, Copy, Debug, Default)]
struct DimensionMemo {
    dkey: u64,
    pixel_digits: u64,
    top_permutation: u8,
}

impl ZSobol {
    /// A ZSobol' sampler of `spp` samples per pixel for an image of
    /// `resolution` pixels. Refuses 0 samples, an empty resolution and
    /// an index wider than 64 bits.
    ///
    /// ```
    /// use glam::UVec2;
    /// use strata::sampler::{ZSobol, ZSobolError};
    /// let s = ZSobol::new(16, 1, UVec2::new(320, 180)).unwrap();
    /// assert_eq!(s.index_bits(), 2 * 9 + 4); // 512² pixels, 16 slots
    /// assert_eq!(ZSobol::new(0, 1, UVec2::ONE).unwrap_err(), ZSobolError::NoSamples);
    /// assert!(ZSobol::new(2, 1, UVec2::splat(u32::MAX)).is_err()); // 65 bits
    /// ```
    #[inline]
    pub fn new(spp: u32, seed: u64, resolution: UVec2) -> Result<Self, ZSobolError> {
        if spp == 0 {
            return Err(ZSobolError::NoSamples);
        }
        if resolution.x == 0 || resolution.y == 0 {
            return Err(ZSobolError::NoPixels);
        }
        let block_bits = ceil_log2(spp);
        let resolution_bits = ceil_log2(resolution.x.max(resolution.y));
        let bits = 2 * resolution_bits + block_bits;
        if bits > 64 {
            return Err(ZSobolError::IndexTooWide {
                spp,
                resolution,
                bits,
            });
        }
        let seed_key = mix64(seed ^ ZSOBOL_SEED_SALT);
        let mut s = Self {
            spp,
            block_bits,
            resolution_bits,
            seed_key,
            base_key: pass_key(seed_key, 0, 0),
            morton: 0,
            key: 0,
            dimension: 2,
            pixel: Vec2::ZERO,
            cache: [DimensionMemo::default(); CACHED_DIMENSIONS],
            cached: 0,
            cache_tag: (u64::MAX, 0),
        };
        s.start_pixel_sample(UVec2::ZERO, 0);
        Ok(s)
    }

    /// The bits of the Morton index, `2r + k` (see the module docs): at
    /// most 64.
    #[inline]
    #[must_use]
    pub fn index_bits(&self) -> u32 {
        2 * self.resolution_bits + self.block_bits
    }

    /// The digits of the current sample's Morton index from bit `lo` to
    /// bit `hi`, each through the permutation that dimension key `dkey` and
    /// the digits above it choose (the bits outside are left 0). `lo` is 0
    /// or `k`: the slot digits or the pixel digits.
    #[inline]
    fn permute_digits(&self, dkey: u64, lo: u32, hi: u32) -> u64 {
        let m = self.morton;
        let mut out = 0u64;
        let mut shift = lo;
        if shift == 0 && self.block_bits & 1 == 1 {
            // The lone lowest bit: flipped by a hash of everything above,
            // marked by a set bit 0 so no other digit's word equals it.
            let word = m | 1;
            out |= (m & 1) ^ (mix64(word ^ dkey) >> 63);
            shift = 1;
        }
        while shift < hi {
            let p = self.digit_permutation(dkey, shift);
            out |= permute_digit(p, m, shift);
            shift += 2;
        }
        out
    }

    /// The permutation of the base-4 digit at bit `shift` of the current
    /// sample's Morton index, chosen by a hash of `dkey` and the digits
    /// above it.
    #[inline]
    fn digit_permutation(&self, dkey: u64, shift: u32) -> u8 {
        // The digits above this one, with a marker bit at the top of this
        // digit's place: distinct for every (level, prefix). (At shift 62
        // nothing is above: the mask wraps to all ones.)
        let below = (4u64 << shift).wrapping_sub(1);
        let word = (self.morton & !below) | 2u64 << shift;
        let h = mix64(word ^ dkey);
        PERMUTATIONS[(((h >> 32) * 24) >> 32) as usize]
    }

    /// What dimension `d` of the current pixel shares between its samples.
    #[inline]
    fn dimension_memo(&self, d: u32) -> DimensionMemo {
        let dkey = self.dimension_key(d);
        let k = self.block_bits;
        DimensionMemo {
            dkey,
            pixel_digits: self.permute_digits(dkey, k, self.index_bits()),
            top_permutation: if k >= 2 {
                self.digit_permutation(dkey, k - 2)
            } else {
                0
            },
        }
    }

    /// Dimension `d`'s key and the current sample's Morton index after
    /// its digit permutations: the index of its Sobol' point.
    #[inline]
    fn key_and_index(&mut self, d: u32) -> (u64, u64) {
        let memo = if (d as usize) < CACHED_DIMENSIONS {
            if self.cached >> d & 1 == 0 {
                self.cache[d as usize] = self.dimension_memo(d);
                self.cached |= 1 << d;
            }
            self.cache[d as usize]
        } else {
            self.dimension_memo(d)
        };
        let k = self.block_bits;
        let slot_digits = if k >= 2 {
            self.permute_digits(memo.dkey, 0, k - 2)
                | permute_digit(memo.top_permutation, self.morton, k - 2)
        } else {
            self.permute_digits(memo.dkey, 0, k)
        };
        (memo.dkey, memo.pixel_digits | slot_digits)
    }

    /// The key of dimension `d` of the current sample: its low half
    /// scrambles the first Sobol' dimension, its high half the second.
    #[inline]
    fn dimension_key(&self, d: u32) -> u64 {
        mix64(self.key ^ ZSOBOL_DIM_SALT ^ d as u64)
    }

    /// Dimension `d` as a 1D draw: the first Sobol' dimension (whose
    /// matrix is the identity, so the index's low 32 bits are all of it).
    #[inline]
    fn value_1d(&mut self, d: u32) -> f32 {
        let (dkey, i) = self.key_and_index(d);
        // Owen scrambling works on reversed digits: no reversal in between.
        let x = sobol::laine_karras(sobol::sobol_rev(i, 0), dkey as u32);
        u32_to_unit_f32(x.reverse_bits())
    }

    /// Dimensions `d` and `d + 1` as a 2D draw: the first two Sobol'
    /// dimensions of one index.
    #[inline]
    fn value_2d(&mut self, d: u32) -> Vec2 {
        let (dkey, i) = self.key_and_index(d);
        let x = sobol::laine_karras(sobol::sobol_rev(i, 0), dkey as u32);
        let y = sobol::laine_karras(sobol::sobol_rev(i, 1), (dkey >> 32) as u32);
        Vec2::new(
            u32_to_unit_f32(x.reverse_bits()),
            u32_to_unit_f32(y.reverse_bits()),
        )
    }
}

/// The base-4 digit of `m` at bit `shift` through permutation `p`, in
/// place.
#[inline]
fn permute_digit(p: u8, m: u64, shift: u32) -> u64 {
    let digit = (m >> shift) & 3;
    ((p as u64 >> (2 * digit)) & 3) << shift
}

/// The key of pass `pass` of the pixels whose coordinates divided by
/// `2^r` are `tile`.
#[inline]
const fn pass_key(seed_key: u64, tile: u64, pass: u32) -> u64 {
    mix64(mix64(seed_key ^ tile) ^ pass as u64)
}

impl Sampler for ZSobol {
    #[inline]
    fn samples_per_pixel(&self) -> u32 {
        self.spp
    }

    #[inline]
    fn start_pixel_sample(&mut self, pixel: UVec2, index: u32) {
        let pass = index / self.spp;
        let slot = index - pass * self.spp;
        let r = self.resolution_bits;
        // r ≤ 32: shift in 64 bits.
        let (x, y) = (pixel.x as u64, pixel.y as u64);
        let tile = (x >> r) | (y >> r) << 32;
        let low = (1u64 << r) - 1;
        self.key = if tile == 0 && pass == 0 {
            self.base_key
        } else {
            pass_key(self.seed_key, tile, pass)
        };
        // 2r + k ≤ 64, checked at construction.
        let pixel_index = morton2((x & low) as u32, (y & low) as u32);
        if (pixel_index, self.key) != self.cache_tag {
            self.cache_tag = (pixel_index, self.key);
            self.cached = 0;
        }
        self.morton = pixel_index << self.block_bits | slot as u64;
        self.dimension = 2;
        self.pixel = self.value_2d(0);
    }

    #[inline]
    fn pixel_2d(&mut self) -> Vec2 {
        self.pixel
    }

    #[inline]
    fn next_1d(&mut self) -> f32 {
        let d = self.dimension;
        self.dimension = d.wrapping_add(1);
        self.value_1d(d)
    }

    #[inline]
    fn next_2d(&mut self) -> Vec2 {
        let d = self.dimension;
        self.dimension = d.wrapping_add(2);
        self.value_2d(d)
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
    fn permutations_are_the_24_distinct_ones() {
        let mut seen = [false; 256];
        for p in PERMUTATIONS {
            let images: [u8; 4] = core::array::from_fn(|t| (p >> (2 * t)) & 3);
            let mut hit = [false; 4];
            for v in images {
                hit[v as usize] = true;
            }
            assert!(hit.iter().all(|&h| h), "{p:08b} is not a permutation");
            assert!(!seen[p as usize], "{p:08b} twice");
            seen[p as usize] = true;
        }
        assert_eq!(PERMUTATIONS[0], 0b11_10_01_00); // the identity first
    }

    #[test]
    fn morton_interleaves_x_low() {
        assert_eq!(morton2(1, 0), 1);
        assert_eq!(morton2(0, 1), 2);
        assert_eq!(morton2(3, 3), 15);
        assert_eq!(morton2(u32::MAX, 0), 0x5555_5555_5555_5555);
        assert_eq!(morton2(u32::MAX, u32::MAX), u64::MAX);
        // Bit by bit against a plain loop.
        let mut x = 0x9e37_79b9u32;
        for _ in 0..1000 {
            x = x.wrapping_mul(747_796_405).wrapping_add(2_891_336_453);
            let y = x.rotate_left(13);
            let mut want = 0u64;
            for b in 0..32 {
                want |= ((x >> b) as u64 & 1) << (2 * b) | ((y >> b) as u64 & 1) << (2 * b + 1);
            }
            assert_eq!(morton2(x, y), want);
        }
    }

    #[test]
    fn ceil_log2_rounds_up() {
        let want = [(1, 0), (2, 1), (3, 2), (4, 2), (5, 3), (16, 4), (17, 5)];
        for (n, k) in want {
            assert_eq!(ceil_log2(n), k, "{n}");
        }
        assert_eq!(ceil_log2(u32::MAX), 32);
        assert_eq!(ceil_log2(1 << 31), 31);
    }

    /// The digit shuffle of one (pixel, dimension) is a bijection of the
    /// pixel's block: every slot gets its own sequence point, and the
    /// points stay inside the block the pixel's digits select.
    #[test]
    fn sequence_indices_permute_each_block() {
        for spp in [1u32, 2, 4, 8, 32, 64] {
            let mut s = ZSobol::new(spp, 3, UVec2::new(16, 16)).unwrap();
            let k = s.block_bits;
            for pixel in [UVec2::new(0, 0), UVec2::new(5, 9), UVec2::new(15, 15)] {
                let mut seen = [false; 64];
                let mut block = None;
                for i in 0..spp {
                    s.start_pixel_sample(pixel, i);
                    let j = s.key_and_index(7).1 as u32;
                    let b = *block.get_or_insert(j >> k);
                    assert_eq!(j >> k, b, "spp {spp} {pixel}: slot {i} left its block");
                    assert!(!seen[(j & (spp - 1)) as usize]);
                    seen[(j & (spp - 1)) as usize] = true;
                }
            }
        }
    }

    /// The values equal a direct computation: every digit of the 64-bit
    /// index shuffled, then a bit-by-bit Sobol' product whose second
    /// dimension is built from its definition (column `j` has a one in row
    /// `i` iff `C(j, i)` is odd, i.e. `i & j == i`, Lucas). This checks the
    /// 64-bit superset sums of the second dimension and the memo's split of
    /// the digits (pixel, top slot digit, lower slot digits).
    #[test]
    fn values_equal_the_direct_64_bit_computation() {
        fn full_shuffle(m: u64, dkey: u64, k: u32, bits: u32) -> u64 {
            let mut out = 0;
            let mut shift = 0;
            if k & 1 == 1 {
                out |= (m & 1) ^ (mix64((m | 1) ^ dkey) >> 63);
                shift = 1;
            }
            while shift < bits {
                let word = (m & !(4u64 << shift).wrapping_sub(1)) | 2u64 << shift;
                let p = PERMUTATIONS[(((mix64(word ^ dkey) >> 32) * 24) >> 32) as usize];
                out |= ((p as u64 >> (2 * ((m >> shift) & 3))) & 3) << shift;
                shift += 2;
            }
            out
        }
        fn sobol64(i: u64, dim: usize) -> u32 {
            let column = |j: u64| -> u32 {
                if dim == 0 {
                    if j < 32 { 1 << (31 - j) } else { 0 }
                } else {
                    (0..32u64)
                        .filter(|&r| r & j == r)
                        .fold(0, |c, r| c | 1 << (31 - r))
                }
            };
            (0..64)
                .filter(|j| i >> j & 1 == 1)
                .fold(0, |x, j| x ^ column(j))
        }
        for j in 0..32 {
            assert_eq!(sobol64(1 << j, 1), sobol::sobol(1 << j, 1), "column {j}");
        }
        let cases = [
            (256u32, UVec2::splat(1 << 20)),
            (2, UVec2::splat(1 << 31)), // 63 bits, odd k
            (4, UVec2::splat(1 << 31)), // 64 bits
            (1, UVec2::splat(u32::MAX)),
            (2, UVec2::new(320, 180)),
            // Every split of the slot digits the memo makes: k = 2 (the
            // top digit only), 3 (top and lone bit), 4, 5, 6 and more.
            (3, UVec2::new(40, 30)),
            (8, UVec2::new(320, 180)),
            (5, UVec2::new(320, 180)),
            (16, UVec2::new(320, 180)),
            (12, UVec2::new(7, 3)),
            (32, UVec2::new(64, 64)),
            (64, UVec2::new(1000, 10)),
        ];
        for (spp, res) in cases {
            let mut s = ZSobol::new(spp, 5, res).unwrap();
            let mut x = 0x1234_5678u32;
            for _ in 0..2000 {
                x = x.wrapping_mul(747_796_405).wrapping_add(2_891_336_453);
                let pixel = UVec2::new(x % res.x, x.rotate_left(16) % res.y);
                s.start_pixel_sample(pixel, x % spp);
                let d = x >> 28;
                let dkey = s.dimension_key(d);
                let i = full_shuffle(s.morton, dkey, s.block_bits, s.index_bits());
                let want = [(0, dkey as u32), (1, (dkey >> 32) as u32)].map(|(dim, key)| {
                    u32_to_unit_f32(sobol::nested_uniform_scramble(sobol64(i, dim), key))
                });
                s.dimension = d;
                assert_eq!(s.next_2d().to_array(), want, "{pixel} dimension {d}");
                s.dimension = d;
                assert_eq!(s.next_1d(), want[0], "{pixel} dimension {d}, 1D");
            }
        }
    }

    /// The pixel-digit memo never changes a value: a sampler that has just
    /// drawn other samples of the pixel (of this pass or another, and past
    /// the memo's 64 dimensions) gives the bits of a fresh one.
    #[test]
    fn the_memo_never_changes_a_value() {
        let proto = ZSobol::new(8, 3, UVec2::new(40, 30)).unwrap();
        let mut warm = proto.clone();
        let visits = [
            (3, 4, 0),
            (3, 4, 5),
            (3, 4, 9),
            (3, 4, 1),
            (4, 4, 1),
            (3, 4, 2),
        ];
        for (x, y, i) in visits {
            let pixel = UVec2::new(x, y);
            warm.start_pixel_sample(pixel, i);
            let mut fresh = proto.clone();
            fresh.start_pixel_sample(pixel, i);
            assert_eq!(warm.pixel_2d(), fresh.pixel_2d());
            for d in 0..50 {
                assert_eq!(warm.next_2d(), fresh.next_2d(), "{pixel} #{i} draw {d}");
                assert_eq!(warm.next_1d(), fresh.next_1d(), "{pixel} #{i} draw {d}");
            }
        }
    }

    #[test]
    fn the_index_width_limit_is_exact() {
        // 2r + k = 64 is accepted, 65 refused.
        let big = UVec2::splat(1 << 31); // r = 31
        assert_eq!(ZSobol::new(4, 0, big).unwrap().index_bits(), 64);
        let err = ZSobol::new(5, 0, big).unwrap_err();
        assert_eq!(
            err,
            ZSobolError::IndexTooWide {
                spp: 5,
                resolution: big,
                bits: 65
            }
        );
        assert_eq!(
            ZSobol::new(1, 0, UVec2::splat(u32::MAX))
                .unwrap()
                .index_bits(),
            64
        );
        assert_eq!(
            ZSobol::new(u32::MAX, 0, UVec2::ONE).unwrap().index_bits(),
            32
        );
        assert_eq!(
            ZSobol::new(1, 0, UVec2::new(0, 5)).unwrap_err(),
            ZSobolError::NoPixels
        );
    }

    #[test]
    fn extreme_pixels_indices_and_dimensions_stay_in_range() {
        let unit = |v: Vec2| v.cmplt(Vec2::ONE).all() && v.cmpge(Vec2::ZERO).all();
        for (spp, res) in [
            (1u32, UVec2::splat(u32::MAX)),
            (4, UVec2::splat(1 << 31)),
            (u32::MAX, UVec2::ONE),
            (3, UVec2::new(320, 180)),
        ] {
            let mut s = ZSobol::new(spp, 9, res).unwrap();
            for pixel in [UVec2::ZERO, UVec2::splat(u32::MAX), UVec2::new(u32::MAX, 0)] {
                for index in [0, spp - 1, spp.wrapping_add(1), u32::MAX] {
                    s.start_pixel_sample(pixel, index);
                    assert!(unit(s.pixel_2d()));
                    s.dimension = u32::MAX - 1;
                    assert!(unit(s.next_2d()) && (0.0..1.0).contains(&s.next_1d()));
                }
            }
        }
    }

    #[test]
    fn sampler_is_send_and_sync() {
        fn assert_send_sync<T: Send + Sync + Clone + core::fmt::Debug>() {}
        assert_send_sync::<ZSobol>();
    }
}
