//! Owen-scrambled Sobol' samples by hashing (Burley 2020, *Practical
//! Hash-based Owen Scrambling*, JCGT 9(4)), padded in pairs of dimensions
//! (as pbrt's `PaddedSobolSampler`).
//!
//! Sample dimension `d` of a pixel belongs to pair `g = d / 2` and uses
//! Sobol' dimension `d % 2`. Within a pair the sample index is shuffled by
//! a nested uniform scramble keyed by `(seed, pixel, g)`, and every output
//! value is Owen-scrambled by a key of `(seed, pixel, d)`. So:
//!
//! - the first `2^k` samples of a pixel, in every pair, form a
//!   `(0, k, 2)`-net: every elementary interval of area `2^-k` holds
//!   exactly one point (the pixel position and every 2D draw are pairs);
//! - every single dimension is a `(0, 1)`-sequence: `2^k` samples fill
//!   `2^k` equal strata exactly once;
//! - pairs are decorrelated from each other and pixels from each other.
//!
//! # Building blocks
//!
//! A sampler that draws the same scrambled sequence in its own index order
//! (a 64-bit one, say) uses these; a `_rev` suffix means the bits of a
//! fraction are reversed (bit `a` is the digit of weight `2^-(a+1)`), the
//! domain in which both Sobol' matrices and Owen scrambling are cheap:
//!
//! - [`sobol_rev`] and [`sobol`]: Sobol' dimensions 0 and 1 of a 64-bit
//!   index as 32-bit fractions;
//! - [`laine_karras`]: the hash that scrambles a `_rev` value;
//! - [`nested_uniform_scramble`]: the Owen scramble of a fraction, or the
//!   shuffle of an index that keeps aligned blocks of `2^k` together.
//!
//! # Evaluation
//!
//! Dimension 0 is van der Corput's (the index reversed), so its `_rev` form
//! is the index itself. Dimension 1 is Pascal's triangle mod 2 (Joe and
//! Kuo's first row: `s = 1`, `a = 0`, `m₁ = 1`): by Lucas's theorem digit
//! `a` of its value is the XOR of the index bits `j ⊇ a` (bitwise), a
//! superset sum that five shift-and-mask steps compute (six for a 64-bit
//! index). So a value needs no table: with `i'` the scrambled index,
//! `value = reverse(laine_karras(sobol_rev(i', d % 2), key))`. The sampler
//! evaluates sixteen dimensions at a time as independent lanes, which a
//! compiler turns into SIMD; integer lanes give the same bits at any
//! width. The tests check both matrices against the direction numbers.
//!
//! Direction numbers: dimension 0 is van der Corput; dimension 1 is the
//! row for dimension 2 of Joe and Kuo's `new-joe-kuo-6.21201` (2008),
//! whose licence is in `core/data/LICENSE-JOE-KUO.txt`.

use glam::{UVec2, Vec2};

use super::{PixelKey, Sampler};
use crate::rng::mix64;

/// Dimensions a [`Sobol`] block evaluates at once: eight
/// pairs.
pub(crate) const BLOCK: usize = 16;

/// Sobol' point `index` in dimension `dim` (0 or 1; taken mod 2) as a
/// bit-reversed 32-bit fraction: bit `a` is the digit of weight
/// `2^-(a+1)`. Every bit of a 64-bit index counts (dimension 0 ignores the
/// high 32, whose digits lie below `2^-32`).
#[inline]
#[must_use]
pub(crate) const fn sobol_rev(index: u64, dim: usize) -> u32 {
    if dim & 1 == 0 {
        return index as u32;
    }
    // Superset sums over the six bits of a position: after the step for
    // bit b, position i (bit b clear) also holds position i + 2^b.
    let mut x = index;
    x ^= (x >> 1) & 0x5555_5555_5555_5555;
    x ^= (x >> 2) & 0x3333_3333_3333_3333;
    x ^= (x >> 4) & 0x0f0f_0f0f_0f0f_0f0f;
    x ^= (x >> 8) & 0x00ff_00ff_00ff_00ff;
    x ^= (x >> 16) & 0x0000_ffff_0000_ffff;
    x ^= x >> 32;
    x as u32
}

/// [`sobol_rev`] of a 32-bit index in dimension 1: the superset sums of
/// its five position bits.
#[inline]
const fn pascal_rev(mut x: u32) -> u32 {
    x ^= (x >> 1) & 0x5555_5555;
    x ^= (x >> 2) & 0x3333_3333;
    x ^= (x >> 4) & 0x0f0f_0f0f;
    x ^= (x >> 8) & 0x00ff_00ff;
    x ^ (x >> 16)
}

/// Sobol' point `index` in dimension `dim` (0 or 1) as a 32-bit fraction,
/// most significant digit first: `sobol_rev(index, dim).reverse_bits()`.
#[cfg_attr(
    not(test),
    expect(
        dead_code,
        reason = "the definitions tests compare the fast paths with"
    )
)]
#[inline]
#[must_use]
pub(crate) const fn sobol(index: u64, dim: usize) -> u32 {
    sobol_rev(index, dim).reverse_bits()
}

/// The Laine–Karras permutation as Burley improves it: output bit `j`
/// depends only on input bits `0..=j` and the seed.
#[inline]
#[must_use]
pub(crate) const fn laine_karras(mut x: u32, seed: u32) -> u32 {
    x = x.wrapping_add(seed);
    x ^= x.wrapping_mul(0x6c50_b47c);
    x ^= x.wrapping_mul(0xb82f_1e52);
    x ^= x.wrapping_mul(0xc7af_e638);
    x ^= x.wrapping_mul(0x8d22_f6e6);
    x
}

/// A nested uniform (Owen) scramble of `x` keyed by `seed`: bit `j` is
/// flipped by a hash of the bits above it. As a shuffle of indices it
/// keeps every aligned block of `2^k` indices together.
#[cfg_attr(
    not(test),
    expect(
        dead_code,
        reason = "the definitions tests compare the fast paths with"
    )
)]
#[inline]
#[must_use]
pub(crate) const fn nested_uniform_scramble(x: u32, seed: u32) -> u32 {
    laine_karras(x.reverse_bits(), seed).reverse_bits()
}

/// Dimensions `16b .. 16b + 16` of one sample, as the 24-bit integers
/// `u32_to_unit_f32` scales: `index_rev` is the sample index reversed,
/// `pair_keys[g]` the index shuffle of pair `g` (lanes `2g` and `2g + 1`),
/// `dim_keys[l]` lane `l`'s output scramble. Lanes are independent
/// (SIMD-friendly).
///
/// Two evaluation orders give the same bits (integer lanes): with 16-lane
/// vectors (AVX-512) every lane shuffles its pair's index itself, one
/// vector wide; narrower vectors shuffle each pair's index once, take
/// Pascal's matrix of the 8 shuffled indices, and interleave them, which
/// saves a third of the work where 16 lanes are two or more vectors.
#[inline]
pub(crate) fn padded_block(
    index_rev: u32,
    pair_keys: &[u32; BLOCK / 2],
    dim_keys: &[u32; BLOCK],
) -> [u32; BLOCK] {
    if cfg!(target_feature = "avx512f") {
        padded_block_by_lane(index_rev, pair_keys, dim_keys)
    } else {
        padded_block_by_pair(index_rev, pair_keys, dim_keys)
    }
}

/// [`padded_block`] with every lane shuffling its own index.
#[inline(always)]
fn padded_block_by_lane(
    index_rev: u32,
    pair_keys: &[u32; BLOCK / 2],
    dim_keys: &[u32; BLOCK],
) -> [u32; BLOCK] {
    let mut out = [0u32; BLOCK];
    for l in 0..BLOCK {
        // The scrambled index i' = nested_uniform_scramble(index, pair key).
        let index = laine_karras(index_rev, pair_keys[l / 2]).reverse_bits();
        // Odd lanes are Sobol' dimension 1 (a select, not a branch).
        let odd = 0u32.wrapping_sub(l as u32 & 1);
        let rev = index ^ ((pascal_rev(index) ^ index) & odd);
        out[l] = laine_karras(rev, dim_keys[l]).reverse_bits() >> 8;
    }
    out
}

/// [`padded_block`] with each pair's index shuffled once.
#[inline(always)]
fn padded_block_by_pair(
    index_rev: u32,
    pair_keys: &[u32; BLOCK / 2],
    dim_keys: &[u32; BLOCK],
) -> [u32; BLOCK] {
    // The scrambled index i' = nested_uniform_scramble(index, pair key) is
    // Sobol' dimension 0 reversed; dimension 1 is Pascal's matrix times it.
    // (Plain loops: `array::map` is not always inlined.)
    let mut rev = [0u32; BLOCK];
    for g in 0..BLOCK / 2 {
        let index = laine_karras(index_rev, pair_keys[g]).reverse_bits();
        rev[2 * g] = index;
        rev[2 * g + 1] = pascal_rev(index);
    }
    let mut out = [0u32; BLOCK];
    for l in 0..BLOCK {
        out[l] = laine_karras(rev[l], dim_keys[l]).reverse_bits() >> 8;
    }
    out
}

/// One 2-D pair for eight samples (`irev`: their indices reversed): the
/// pair's shuffled index and its two output scrambles, as the 24-bit
/// integers of [`padded_block`] (the same operations per lane).
#[inline(always)]
fn run_pair(irev: &[u32; 8], pair_key: u32, key0: u32, key1: u32) -> ([u32; 8], [u32; 8]) {
    let (mut v0, mut v1) = ([0u32; 8], [0u32; 8]);
    for l in 0..8 {
        let index = reverse(laine_karras(irev[l], pair_key));
        v0[l] = reverse(laine_karras(index, key0)) >> 8;
        v1[l] = reverse(laine_karras(pascal_rev(index), key1)) >> 8;
    }
    (v0, v1)
}

/// `x.reverse_bits()`, by shifts and masks below SSSE3: x86-64 has no
/// bit-reverse instruction, and without SSSE3's byte shuffle LLVM takes
/// the vector form lane by lane; the shifts vectorise on every level.
#[inline(always)]
const fn reverse(x: u32) -> u32 {
    if cfg!(target_feature = "ssse3") {
        return x.reverse_bits();
    }
    let x = x.rotate_left(16);
    let x = ((x >> 8) & 0x00ff_00ff) | ((x & 0x00ff_00ff) << 8);
    let x = ((x >> 4) & 0x0f0f_0f0f) | ((x & 0x0f0f_0f0f) << 4);
    let x = ((x >> 2) & 0x3333_3333) | ((x & 0x3333_3333) << 2);
    ((x >> 1) & 0x5555_5555) | ((x & 0x5555_5555) << 1)
}

/// Keys of the Sobol' index shuffles and output scrambles, apart from
/// each other and from stream states.
pub(super) const SOBOL_GROUP_SALT: u64 = 0x1319_8a2e_0370_7344;
pub(super) const SOBOL_DIM_SALT: u64 = 0xa409_3822_299f_31d0;

/// Blocks of [`BLOCK`] dimensions whose keys a Sobol' sampler keeps
/// for its current pixel (a path of 5 segments draws 28 dimensions).
const SOBOL_KEYED_BLOCKS: usize = 2;

/// The keys of Sobol' block `block` (dimensions `16·block ..`) of the pixel
/// hashed to `pixel_key`: each pair's key (index shuffle) and each lane's
/// dimension key (output scramble).
#[inline]
fn sobol_keys(pixel_key: u64, block: u32) -> SobolKeys {
    let first = block.wrapping_mul(BLOCK as u32);
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
    pairs: [u32; BLOCK / 2],
    /// Each dimension's output scramble key.
    dims: [u32; BLOCK],
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
    values: [f32; BLOCK],
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
            values: [0.0; BLOCK],
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
        let ints = padded_block(self.index_rev, &keys.pairs, &keys.dims);
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
        let block = d / BLOCK as u32;
        if block != self.block {
            self.refill(block);
        }
        self.values[d as usize % BLOCK]
    }

    #[inline]
    fn next_2d(&mut self) -> Vec2 {
        // A pair starts on an even dimension, so it never straddles blocks.
        let d = self.dimension.wrapping_add(self.dimension & 1);
        self.dimension = d.wrapping_add(2);
        let block = d / BLOCK as u32;
        if block != self.block {
            self.refill(block);
        }
        let k = d as usize % BLOCK;
        Vec2::new(self.values[k], self.values[k | 1])
    }

    /// Eight consecutive samples at once: each 2-D pair's keys are made
    /// once per block of dimensions, and the lanes of a pair are eight
    /// sample indices (the integer maths of `padded_block`, lane for
    /// lane, so the bits are the per-sample draws').
    #[inline]
    fn fill_run(&mut self, pixel: UVec2, first: u32, dims: usize, out: &mut [f32]) {
        if dims == 0 {
            return;
        }
        let rows = out.len() / dims;
        self.start_pixel_sample(pixel, first);
        let key = self.pixel.key;
        // Batches of 64 rows: each pair's keys are made once per batch, and
        // the batch's rows stay in cache while every pair is written.
        let mut keys = sobol_keys(key, 0);
        let mut keyed_block = 0;
        for (b64, batch) in out[..rows * dims].chunks_mut(64 * dims).enumerate() {
            for d in (0..dims).step_by(2) {
                let block = (d / BLOCK) as u32;
                if block != keyed_block {
                    keys = sobol_keys(key, block);
                    keyed_block = block;
                }
                let lane = d % BLOCK;
                let (pair_key, key0, key1) =
                    (keys.pairs[lane / 2], keys.dims[lane], keys.dims[lane + 1]);
                for (g8, group) in batch.chunks_mut(8 * dims).enumerate() {
                    let base = first.wrapping_add((64 * b64 + 8 * g8) as u32);
                    let irev: [u32; 8] =
                        core::array::from_fn(|l| base.wrapping_add(l as u32).reverse_bits());
                    let (v0, v1) = run_pair(&irev, pair_key, key0, key1);
                    // Below 2^24: the signed conversion is exact (and one
                    // instruction a vector, where the unsigned one is not).
                    let f0 = v0.map(|v| v as i32 as f32 * (1.0 / 16_777_216.0));
                    let f1 = v1.map(|v| v as i32 as f32 * (1.0 / 16_777_216.0));
                    if dims == 2
                        && let Ok(pairs) = <&mut [f32; 16]>::try_from(&mut *group)
                    {
                        // Eight whole rows of one pair: interleaved in
                        // registers, stored as one block.
                        for l in 0..8 {
                            pairs[2 * l] = f0[l];
                            pairs[2 * l + 1] = f1[l];
                        }
                        continue;
                    }
                    for (l, row) in group.chunks_exact_mut(dims).enumerate() {
                        row[d] = f0[l];
                        if d + 1 < dims {
                            row[d + 1] = f1[l];
                        }
                    }
                }
            }
        }
        let last = first.wrapping_add(rows.saturating_sub(1) as u32);
        self.start_pixel_sample(pixel, last);
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

#[cfg(test)]
mod tests {
    use super::*;
    use crate::sampler::draw_row;

    #[test]
    fn reverse_is_reverse_bits() {
        for x in [0, 1, 0x8000_0000, 0xdead_beef, u32::MAX, 0x1234_5678] {
            assert_eq!(reverse(x), x.reverse_bits());
        }
        let mut x = 0x9e37_79b9u32;
        for _ in 0..10_000 {
            x = x.wrapping_mul(0x2c1b_3c6d).wrapping_add(0x297a_2d39);
            assert_eq!(reverse(x), x.reverse_bits());
        }
    }

    #[test]
    fn a_run_equals_the_per_sample_draws() {
        // Row lengths across blocks (16, 32) and odd ones; runs shorter
        // than, equal to and past the 8-sample groups and 64-row batches;
        // indices that wrap past u32::MAX.
        let mut s = Sobol::new(1 << 10, 99).unwrap();
        let mut one = Sobol::new(1 << 10, 99).unwrap();
        for dims in [1, 2, 3, 7, 16, 17, 31, 32, 33, 50] {
            for (first, n) in [
                (0u32, 1usize),
                (5, 8),
                (3, 63),
                (64, 130),
                (u32::MAX - 4, 9),
            ] {
                let pixel = UVec2::new(dims as u32, n as u32);
                let mut run = [0.0f32; 130 * 50];
                let run = &mut run[..n * dims];
                s.fill_run(pixel, first, dims, run);
                for (k, row) in run.chunks_exact(dims).enumerate() {
                    let mut want = [0.0f32; 50];
                    one.start_pixel_sample(pixel, first.wrapping_add(k as u32));
                    draw_row(&mut one, &mut want[..dims]);
                    assert_eq!(row, &want[..dims], "{dims} dims, from {first}, row {k}");
                }
                // Left at the last sample.
                one.start_pixel_sample(pixel, first.wrapping_add(n as u32 - 1));
                assert_eq!(s.next_2d(), one.next_2d());
            }
        }
    }

    /// `(s, a, m₁..m_s)` of Sobol' dimension 1 (Joe and Kuo, row 2).
    const JOE_KUO: (u32, u32, [u32; 1]) = (1, 0, [1]);

    /// The 64 direction vectors of Sobol' dimension `dim` (0 or 1),
    /// MSB-aligned: bit `j` of an index contributes `v[j]`. Digits below
    /// `2^-32` are dropped, which the recurrence allows: it only shifts
    /// right, so no dropped digit ever moves up.
    fn directions(dim: usize) -> [u32; 64] {
        let mut v = [0u32; 64];
        if dim == 0 {
            for (j, v) in v.iter_mut().enumerate().take(32) {
                *v = 1 << (31 - j);
            }
            return v;
        }
        let (s, a, m) = JOE_KUO;
        let s = s as usize;
        for j in 0..64 {
            v[j] = if j < s {
                m[j] << (31 - j)
            } else {
                let mut x = v[j - s] ^ (v[j - s] >> s);
                for k in 1..s {
                    if (a >> (s - 1 - k)) & 1 == 1 {
                        x ^= v[j - k];
                    }
                }
                x
            };
        }
        v
    }

    /// The matrix product by the bit loop.
    fn sobol_bits(mut index: u64, dim: usize) -> u32 {
        let v = directions(dim);
        let (mut x, mut j) = (0, 0);
        while index != 0 {
            if index & 1 == 1 {
                x ^= v[j];
            }
            index >>= 1;
            j += 1;
        }
        x
    }

    #[test]
    fn first_points_are_the_textbook_ones() {
        // Dimension 0: 0, 1/2, 1/4, 3/4; dimension 1: 0, 1/2, 3/4, 1/4.
        let f = |i, d| sobol(i, d) as f64 / 4_294_967_296.0;
        assert_eq!([f(0, 0), f(1, 0), f(2, 0), f(3, 0)], [0.0, 0.5, 0.25, 0.75]);
        assert_eq!([f(0, 1), f(1, 1), f(2, 1), f(3, 1)], [0.0, 0.5, 0.75, 0.25]);
    }

    #[test]
    fn superset_sums_equal_the_direction_numbers() {
        let mut x = 0x1234_5678_9abc_def0u64;
        for _ in 0..100_000 {
            x = x
                .wrapping_mul(6_364_136_223_846_793_005)
                .wrapping_add(1_442_695_040_888_963_407);
            for i in [x, x >> 32, x & 0xffff] {
                for d in 0..2 {
                    assert_eq!(sobol(i, d), sobol_bits(i, d), "index {i} dim {d}");
                }
                assert_eq!(pascal_rev(i as u32), sobol_rev(i as u32 as u64, 1));
            }
        }
        for i in [0, 1, u32::MAX as u64, 1 << 31, 1 << 32, u64::MAX] {
            assert_eq!(sobol(i, 0), (i as u32).reverse_bits()); // van der Corput
            assert_eq!(sobol(i, 1), sobol_bits(i, 1));
        }
    }

    #[test]
    fn block_equals_the_scalar_definition() {
        // Each lane: scramble the index, take the Sobol' point, scramble it.
        let pair: [u32; BLOCK / 2] =
            core::array::from_fn(|g| (g as u32).wrapping_mul(0x9e37_79b9) ^ 0xdead_beef);
        let mut dim: [u32; BLOCK] = core::array::from_fn(|l| l as u32 * 7 + 1);
        dim[3] = u32::MAX;
        let mut x = 0x2545_f491u32;
        let random = core::iter::from_fn(|| {
            x ^= x << 13;
            x ^= x >> 17;
            x ^= x << 5;
            Some(x)
        });
        for index in [0u32, 1, 5, 1000, u32::MAX]
            .into_iter()
            .chain(random.take(500))
        {
            let block = padded_block(index.reverse_bits(), &pair, &dim);
            // Both evaluation orders, whichever this build uses.
            let by_lane = padded_block_by_lane(index.reverse_bits(), &pair, &dim);
            let by_pair = padded_block_by_pair(index.reverse_bits(), &pair, &dim);
            assert_eq!((by_lane, by_pair), (block, block), "index {index}");
            for l in 0..BLOCK {
                let i = nested_uniform_scramble(index, pair[l / 2]);
                let v = nested_uniform_scramble(sobol(i as u64, l % 2), dim[l]);
                assert_eq!(block[l], v >> 8, "index {index} lane {l}");
            }
        }
    }

    #[test]
    fn scramble_is_a_bijection_that_keeps_blocks() {
        for seed in [0u32, 1, 0xdead_beef] {
            let mut seen = [false; 256];
            for i in 0..256u32 {
                let j = nested_uniform_scramble(i, seed);
                // The first 2^8 indices stay in one aligned block of 2^8.
                assert_eq!(j >> 8, nested_uniform_scramble(0, seed) >> 8);
                assert!(!seen[(j & 255) as usize]);
                seen[(j & 255) as usize] = true;
            }
        }
    }

    #[test]
    fn sobol_equals_its_definition() {
        for spp in super::super::reference::SPPS {
            let seed = 5 + spp as u64;
            let mut s = Sobol::new(spp, seed).unwrap();
            super::super::reference::visits(spp, |pixel, index, draws| {
                let want = |d| super::super::reference::sobol_value(seed, pixel, index, d);
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
                super::super::reference::sobol_value(9, UVec2::new(3, 4), 2, d),
                "dim {d}"
            );
        }
    }

    #[test]
    fn huge_indices_and_dimensions_do_not_panic() {
        use super::super::Sampler;
        let unit =
            |v: glam::Vec2| v.cmplt(glam::Vec2::ONE).all() && v.cmpge(glam::Vec2::ZERO).all();
        let mut sob = Sobol::new(7, 1).unwrap();
        sob.start_pixel_sample(glam::UVec2::new(u32::MAX, 0), u32::MAX);
        sob.dimension = u32::MAX - 2;
        assert!(unit(sob.next_2d()) && (0.0..1.0).contains(&sob.next_1d()));
    }
}
