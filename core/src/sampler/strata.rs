//! The strata engine of the grid and the stratified sampler: `spp`
//! strata per dimension (an `nx × ny` grid for a 2D draw), shuffled per
//! dimension with Kensler's permutation ([`permute`](fn@super::permute)), sixteen
//! dimensions at a time; with jitter ([`Stratified`]) each point is
//! uniform in its stratum, without ([`UniformGrid`]) it is the stratum's
//! centre. One engine, `Strata<JITTER>`, serves both.

use glam::{UVec2, Vec2};

use super::permute::{BlockKeys, RoundKey, STRATA_BLOCK, permute_block, permute_mask};
use super::{PixelKey, Sampler, grid_dims, stratum_point};
use crate::rng::{mix64, u32_to_unit_f32};

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
/// Keeps permutation keys apart from stream states: `π − 3` in 64 bits.
pub(super) const PERMUTATION_SALT: u64 = 0x243f_6a88_85a3_08d3;
/// The largest spp the strata samplers accept: beyond `2²⁴` a stratum of a
/// 1D dimension is narrower than the `f32` spacing near 1, and "one sample
/// per stratum" could no longer hold.
pub const MAX_STRATA_SPP: u32 = 1 << 24;
/// Dimensions whose strata a strata sampler evaluates at once.
/// Blocks of [`STRATA_BLOCK`] dimensions whose permutation keys a strata
/// sampler keeps for its current pixel and pass (a path of 5 segments
/// draws 28 dimensions).
const STRATA_KEYED_BLOCKS: usize = 2;
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

/// The strata samplers: [`UniformGrid`] (`JITTER = false`) and
/// [`Stratified`] (`JITTER = true`). `JITTER` is the only difference
/// between them, as in pbrt's `StratifiedSampler`: without jitter every
/// point is a stratum centre, no jitter word is hashed, and the pixel
/// positions keep their grid's raster order instead of being shuffled.
#[derive(Clone)]
pub struct Strata<const JITTER: bool> {
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

/// Named as the kind it is (`UniformGrid` or `Stratified`), with its
/// settings and position; the caches are left out.
impl<const JITTER: bool> core::fmt::Debug for Strata<JITTER> {
    #[inline]
    fn fmt(&self, f: &mut core::fmt::Formatter<'_>) -> core::fmt::Result {
        f.debug_struct(if JITTER { "Stratified" } else { "UniformGrid" })
            .field("spp", &self.spp)
            .field("seed", &self.pixel.seed)
            .field("pixel", &self.pixel.pixel)
            .field(
                "index",
                &(self.pass as u64 * self.spp as u64 + self.slot as u64),
            )
            .field("dimension", &self.dimension)
            .finish_non_exhaustive()
    }
}

impl<const JITTER: bool> Strata<JITTER> {
    /// A strata sampler; `None` if `spp` is 0 or above [`MAX_STRATA_SPP`].
    fn build(spp: u32, seed: u64) -> Option<Self> {
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
        s.start(UVec2::ZERO, 0);
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

    /// The `(nx, ny)` strata of the 2D dimensions (the pixel grid).
    #[inline]
    #[must_use]
    pub fn grid(&self) -> (u32, u32) {
        (self.axes[1].n, self.axes[2].n)
    }

    #[inline]
    fn start(&mut self, pixel: UVec2, index: u32) {
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
        // The grid keeps its pixel strata in raster order.
        let stratum = if JITTER { self.strata[0] } else { self.slot };
        self.pixel_2d = self.point_2d(0, stratum);
        self.dimension = 2;
    }
}

impl<const JITTER: bool> Sampler for Strata<JITTER> {
    #[inline]
    fn samples_per_pixel(&self) -> u32 {
        self.spp
    }

    #[inline]
    fn start_pixel_sample(&mut self, pixel: UVec2, index: u32) {
        self.start(pixel, index);
    }

    #[inline]
    fn pixel_2d(&mut self) -> Vec2 {
        self.pixel_2d
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

    // Every value is a function of its dimension: only the dimension moves.
    #[inline]
    fn skip_1d(&mut self) {
        self.dimension = self.dimension.wrapping_add(1);
    }

    #[inline]
    fn skip_2d(&mut self) {
        self.dimension = self.dimension.wrapping_add(2);
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
pub type UniformGrid = Strata<false>;

impl Strata<false> {
    /// A grid sampler; `None` if `spp` is 0 or above [`MAX_STRATA_SPP`].
    #[inline]
    #[must_use]
    pub fn new(spp: u32, seed: u64) -> Option<Self> {
        Self::build(spp, seed)
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
/// [`Independent`](super::Independent) draws from; other spp place the jitter in the stratum
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
pub type Stratified = Strata<true>;

impl Strata<true> {
    /// A jittered stratified sampler; `None` if `spp` is 0 or above
    /// [`MAX_STRATA_SPP`].
    #[inline]
    #[must_use]
    pub fn new(spp: u32, seed: u64) -> Option<Self> {
        Self::build(spp, seed)
    }
}

#[cfg(test)]
mod tests {
    use super::super::reference::{self, SPPS, visits};
    use super::*;
    use crate::rng::{Pcg32, STREAM};
    use rand_core::Rng;

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

    fn check_strata<const JITTER: bool>(spp: u32) {
        // The grid keeps its pixel strata in raster order.
        let shuffle = JITTER;
        let seed = 11 + spp as u64;
        let mut fast = Strata::<JITTER>::build(spp, seed).unwrap();
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
            fast.start(pixel, index);
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

    /// The two instances of the engine name themselves as their kinds.
    #[test]
    fn debug_names_the_kind() {
        use core::fmt::Write;
        // No allocator here: the text into a fixed buffer.
        struct Buf([u8; 256], usize);
        impl Write for Buf {
            fn write_str(&mut self, s: &str) -> core::fmt::Result {
                let end = (self.1 + s.len()).min(self.0.len());
                self.0[self.1..end].copy_from_slice(&s.as_bytes()[..end - self.1]);
                self.1 = end;
                Ok(())
            }
        }
        let (mut grid, mut jittered) = (Buf([0; 256], 0), Buf([0; 256], 0));
        write!(grid, "{:?}", UniformGrid::new(4, 1).unwrap()).unwrap();
        write!(jittered, "{:?}", Stratified::new(4, 1).unwrap()).unwrap();
        let grid = core::str::from_utf8(&grid.0[..grid.1]).unwrap();
        let jittered = core::str::from_utf8(&jittered.0[..jittered.1]).unwrap();
        assert!(grid.starts_with("UniformGrid {") && grid.contains("spp: 4"));
        assert!(jittered.starts_with("Stratified {"));
    }

    #[test]
    fn huge_indices_and_dimensions_do_not_panic() {
        let unit = |v: Vec2| v.cmplt(Vec2::ONE).all() && v.cmpge(Vec2::ZERO).all();
        let mut s = Stratified::new(7, 1).unwrap();
        s.start_pixel_sample(UVec2::new(u32::MAX, u32::MAX), u32::MAX);
        s.dimension = u32::MAX - 1;
        assert!(unit(s.next_2d()));
        assert!((0.0..1.0).contains(&s.next_1d()));
    }
}
