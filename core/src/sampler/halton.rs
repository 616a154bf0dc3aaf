//! Owen-scrambled Halton samples: the radical inverse in a prime base per
//! dimension, digits permuted by nested affine scrambles.

use glam::{UVec2, Vec2};

use super::{PixelKey, Sampler, stratum_point};
use crate::rng::{mix64, u32_to_unit_f32};

/// The number of prime bases, the Halton dimensions.
const HALTON_BASES: usize = 64;

/// The first 64 primes: the Halton bases of dimensions 0–63.
pub(super) const PRIMES: [u32; HALTON_BASES] = [
    2, 3, 5, 7, 11, 13, 17, 19, 23, 29, 31, 37, 41, 43, 47, 53, 59, 61, 67, 71, 73, 79, 83, 89, 97,
    101, 103, 107, 109, 113, 127, 131, 137, 139, 149, 151, 157, 163, 167, 173, 179, 181, 191, 193,
    197, 199, 211, 223, 227, 229, 233, 239, 241, 251, 257, 263, 269, 271, 277, 281, 283, 293, 307,
    311,
];

/// Keys of the Halton digit scrambles, apart from other keys.
pub(super) const HALTON_SALT: u64 = 0xbe54_66cf_34e9_0c6c;

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
    use super::super::reference::{self, visits};
    use super::*;

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

    #[test]
    fn huge_indices_and_dimensions_do_not_panic() {
        let unit = |v: Vec2| v.cmplt(Vec2::ONE).all() && v.cmpge(Vec2::ZERO).all();
        let mut hal = Halton::new(7, 1).unwrap();
        hal.start_pixel_sample(UVec2::new(0, u32::MAX), u32::MAX);
        assert!(unit(hal.pixel_2d()));
        for _ in 0..100 {
            assert!(unit(hal.next_2d()) && (0.0..1.0).contains(&hal.next_1d()));
        }
    }
}
