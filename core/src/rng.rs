//! Deterministic random streams: one fresh PCG32 per pixel sample.
//!
//! # The stream contract
//!
//! The independent sampler's random numbers come from a [`Pcg32`] (PCG
//! XSH-RR 64/32, O'Neill 2014) created for that sample alone; the other
//! samplers hash the same per-sample `state` (the stratified jitter), the
//! pixel hash `h2` or the seed (their permutation and scrambling keys)
//! instead of drawing from it:
//!
//! ```text
//! h1    = mix64(seed ^ 0x9e37_79b9_7f4a_7c15)
//! h2    = mix64(h1 ^ (px | py << 32))
//! state = mix64(h2 ^ index)
//! rng   = Pcg32::new(state, STREAM)
//! ```
//!
//! where [`mix64`] is the SplitMix64 finaliser (Stafford's "Mix13"), a
//! bijection on `u64`, and [`STREAM`] is PCG's default stream. Nothing is
//! ever advanced from a shared generator, so a value depends only on
//! `(seed, pixel, sample index, dimension)` and never on the order in which
//! pixels or samples are evaluated, on tiles, or on threads.
//!
//! **This scheme is a stability promise.** Changing any constant or step
//! changes every render, and is a breaking change recorded in the
//! CHANGELOG; `core/tests/locks.rs` locks it.
//!
//! # Floats
//!
//! [`u32_to_unit_f32`] keeps the 24 high bits of a `u32`: the result is
//! `k · 2⁻²⁴` for an integer `k`, so it lies in `[0, 1)` and is never `1.0`.

use glam::UVec2;
use rand_core::Rng;

pub use rand_pcg::Pcg32;

/// The PCG stream (increment selector) every pixel-sample generator uses:
/// PCG's default, `1442695040888963407 >> 1`.
pub const STREAM: u64 = 0x0a02_bdbf_7bb3_c0a7;

/// Added to the seed before hashing so that seed 0 does not start from the
/// fixed point `mix64(0) = 0`: the 64-bit golden ratio.
const SEED_SALT: u64 = 0x9e37_79b9_7f4a_7c15;

/// The largest `f32` below 1: `1 - 2⁻²⁴`.
pub const ONE_MINUS_EPSILON: f32 = 1.0 - f32::EPSILON / 2.0;

/// SplitMix64's finaliser (Stafford's variant 13): a bijective 64-bit mix
/// in which every input bit affects every output bit.
///
/// ```
/// use strata::rng::mix64;
/// assert_eq!(mix64(0), 0); // the one fixed point, hence the seed salt
/// assert_ne!(mix64(1), mix64(2));
/// ```
#[inline]
#[must_use]
pub const fn mix64(mut z: u64) -> u64 {
    z = (z ^ (z >> 30)).wrapping_mul(0xbf58_476d_1ce4_e5b9);
    z = (z ^ (z >> 27)).wrapping_mul(0x94d0_49bb_1331_11eb);
    z ^ (z >> 31)
}

/// Packs a pixel into one word: `px` in the low 32 bits, `py` in the high.
#[inline]
const fn pixel_word(pixel: UVec2) -> u64 {
    pixel.x as u64 | (pixel.y as u64) << 32
}

/// The hash of `(seed, pixel)` that every per-pixel value starts from:
/// `mix64(mix64(seed ^ SALT) ^ (px | py << 32))`.
///
/// ```
/// use glam::UVec2;
/// use strata::rng::pixel_hash;
/// assert_ne!(pixel_hash(1, UVec2::new(1, 0)), pixel_hash(1, UVec2::new(0, 1)));
/// ```
#[inline]
#[must_use]
pub const fn pixel_hash(seed: u64, pixel: UVec2) -> u64 {
    mix64(mix64(seed ^ SEED_SALT) ^ pixel_word(pixel))
}

/// The 64-bit PCG state of the stream for one pixel sample (see the module
/// docs for the formula). Distinct sample indices of one pixel always give
/// distinct states, because [`mix64`] is a bijection.
///
/// ```
/// use glam::UVec2;
/// use strata::rng::stream_state;
/// let a = stream_state(7, UVec2::new(3, 4), 0);
/// assert_eq!(a, stream_state(7, UVec2::new(3, 4), 0));
/// assert_ne!(a, stream_state(7, UVec2::new(3, 4), 1));
/// assert_ne!(a, stream_state(7, UVec2::new(4, 3), 0));
/// ```
#[inline]
#[must_use]
pub const fn stream_state(seed: u64, pixel: UVec2, index: u32) -> u64 {
    mix64(pixel_hash(seed, pixel) ^ index as u64)
}

/// The fresh generator of one pixel sample: `Pcg32::new(stream_state(..),
/// STREAM)`.
///
/// ```
/// use glam::UVec2;
/// use rand_core::Rng;
/// use strata::rng::pixel_sample_rng;
/// let mut a = pixel_sample_rng(1, UVec2::new(10, 20), 5);
/// let mut b = pixel_sample_rng(1, UVec2::new(10, 20), 5);
/// assert_eq!(a.next_u32(), b.next_u32()); // a pure function of its inputs
/// ```
#[inline]
#[must_use]
pub fn pixel_sample_rng(seed: u64, pixel: UVec2, index: u32) -> Pcg32 {
    Pcg32::new(stream_state(seed, pixel, index), STREAM)
}

/// Turns a `u32` into a float in `[0, 1)` from its 24 high bits:
/// `(x >> 8) · 2⁻²⁴`. Exact (no rounding), and never `1.0`.
///
/// ```
/// use strata::rng::{u32_to_unit_f32, ONE_MINUS_EPSILON};
/// assert_eq!(u32_to_unit_f32(0), 0.0);
/// assert_eq!(u32_to_unit_f32(u32::MAX), ONE_MINUS_EPSILON);
/// assert!(u32_to_unit_f32(u32::MAX) < 1.0);
/// ```
#[inline]
#[must_use]
pub fn u32_to_unit_f32(x: u32) -> f32 {
    (x >> 8) as f32 * (1.0 / 16_777_216.0)
}

/// The next uniform float in `[0, 1)` from any `rand_core` generator, by
/// [`u32_to_unit_f32`].
///
/// ```
/// use strata::rng::{next_f32, Pcg32};
/// let mut rng = Pcg32::new(42, 54);
/// // The reference stream's first output is 0xa15c02b7.
/// assert_eq!(next_f32(&mut rng), (0xa15c02b7u32 >> 8) as f32 / 16_777_216.0);
/// ```
#[inline]
pub fn next_f32<R: Rng + ?Sized>(rng: &mut R) -> f32 {
    u32_to_unit_f32(rng.next_u32())
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn unit_f32_bounds() {
        assert_eq!(u32_to_unit_f32(0), 0.0);
        assert_eq!(u32_to_unit_f32(255), 0.0);
        assert_eq!(u32_to_unit_f32(256), 1.0 / 16_777_216.0);
        assert_eq!(u32_to_unit_f32(u32::MAX), ONE_MINUS_EPSILON);
        const { assert!(ONE_MINUS_EPSILON < 1.0) };
        assert_eq!(ONE_MINUS_EPSILON.to_bits(), 0x3f7f_ffff);
    }

    #[test]
    fn stream_state_is_injective_in_index() {
        let p = UVec2::new(5, 9);
        let mut seen = [0u64; 256];
        for (i, s) in seen.iter_mut().enumerate() {
            *s = stream_state(3, p, i as u32);
        }
        seen.sort_unstable();
        assert!(seen.windows(2).all(|w| w[0] != w[1]));
    }

    #[test]
    fn seed_zero_is_not_degenerate() {
        assert_ne!(stream_state(0, UVec2::ZERO, 0), 0);
        assert_ne!(pixel_hash(0, UVec2::ZERO), pixel_hash(1, UVec2::ZERO));
        // px and py are not interchangeable.
        assert_ne!(
            pixel_hash(0, UVec2::new(1, 0)),
            pixel_hash(0, UVec2::new(0, 1))
        );
    }
}
