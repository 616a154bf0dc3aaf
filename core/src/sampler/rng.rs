//! A sampler as a random number generator, for renderers that thread an
//! RNG through their camera, materials and lights.

use core::convert::Infallible;

use glam::UVec2;
use rand_core::TryRng;
use rand_core::utils::{fill_bytes_via_next_word, next_u64_via_u32};

use super::Sampler;

/// A [`Sampler`] as rand_core 0.10's infallible generator
/// (`TryRng<Error = Infallible>`, so `rand_core::Rng`; the deprecated
/// `RngCore` is not implemented): the on-ramp for a renderer that passes
/// `&mut impl Rng` to its camera, materials and lights. rand 0.10 builds
/// on rand_core 0.10 and takes it as is (`rng.random::<f32>()`, ranges,
/// distributions); rand 0.9 and older use rand_core 0.9's `RngCore` and
/// cannot.
///
/// Each `u32` is the sampler's next 1D value `v` (one dimension): its 24
/// high bits are `⌊v · 2²⁴⌋`, as `u32 → f32` conversions read them, so
/// rand's `f32` from a `u32` returns `v` exactly where `v` lies on the
/// `2⁻²⁴` grid (the independent, Sobol' and ZSobol samplers, and the
/// strata ones at a power-of-two spp) and `v` rounded down to it
/// otherwise; its low 8 bits repeat the top 8. A `u64` takes two
/// dimensions, bytes one per four.
///
/// What this is, and is not: the dimensions are handed out in call order,
/// so where a path takes a different number of draws (a material that
/// draws twice, a light skipped), every later dimension shifts; each
/// pixel sample still starts at dimension 2 (after the pixel position,
/// [`SamplerRng::start_pixel_sample`]). For [`Independent`] that changes
/// nothing: every dimension is an independent uniform, so this is simply
/// a reproducible per-sample RNG. For the stratified and low-discrepancy
/// kinds it keeps determinism but loses part of their gain once paths
/// diverge; the right port draws a fixed set of dimensions per bounce
/// (as Strata's integrator does: [`crate::render::VERTEX_DIMENSIONS`]).
///
/// [`Independent`]: super::Independent
///
/// ```
/// use glam::UVec2;
/// use rand_core::Rng;
/// use strata::sampler::{Independent, Sampler, SamplerRng};
/// let mut rng = SamplerRng::new(Independent::new(16, 7).unwrap());
/// let mut plain = Independent::new(16, 7).unwrap();
/// rng.start_pixel_sample(UVec2::new(3, 4), 5);
/// plain.start_pixel_sample(UVec2::new(3, 4), 5);
/// // The same values as the sampler's own draws, dimension by dimension.
/// let x = rng.next_u32();
/// assert_eq!((x >> 8) as f32 / 16_777_216.0, plain.next_1d());
/// assert_eq!(rng.pixel_2d(), plain.pixel_2d());
/// ```
#[derive(Clone, Debug)]
pub struct SamplerRng<S> {
    sampler: S,
}

impl<S: Sampler> SamplerRng<S> {
    /// The generator over `sampler`.
    #[inline]
    #[must_use]
    pub fn new(sampler: S) -> Self {
        Self { sampler }
    }

    /// Starts sample `index` of `pixel` ([`Sampler::start_pixel_sample`]):
    /// the next draw is dimension 2.
    #[inline]
    pub fn start_pixel_sample(&mut self, pixel: UVec2, index: u32) {
        self.sampler.start_pixel_sample(pixel, index);
    }

    /// The sample's position in its pixel ([`Sampler::pixel_2d`]).
    #[inline]
    pub fn pixel_2d(&mut self) -> glam::Vec2 {
        self.sampler.pixel_2d()
    }

    /// The sampler, to draw from it directly.
    #[inline]
    pub fn sampler_mut(&mut self) -> &mut S {
        &mut self.sampler
    }

    /// The sampler back.
    #[inline]
    #[must_use]
    pub fn into_inner(self) -> S {
        self.sampler
    }
}

impl<S: Sampler> TryRng for SamplerRng<S> {
    type Error = Infallible;

    #[inline]
    fn try_next_u32(&mut self) -> Result<u32, Infallible> {
        // ⌊v · 2²⁴⌋ < 2²⁴ for v in [0, 1).
        let high = (self.sampler.next_1d() * 16_777_216.0) as u32;
        Ok(high << 8 | high >> 16)
    }

    #[inline]
    fn try_next_u64(&mut self) -> Result<u64, Infallible> {
        next_u64_via_u32(self)
    }

    #[inline]
    fn try_fill_bytes(&mut self, dst: &mut [u8]) -> Result<(), Infallible> {
        fill_bytes_via_next_word(dst, || self.try_next_u32())
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::sampler::{Halton, Independent, Sobol};
    use rand_core::Rng;

    /// `v` on the 2⁻²⁴ grid (what rand makes of the word's high bits).
    fn grid(v: f32) -> f32 {
        (v * 16_777_216.0) as u32 as f32 / 16_777_216.0
    }

    fn check<S: Sampler + Clone>(prototype: S) {
        let mut rng = SamplerRng::new(prototype.clone());
        let mut plain = prototype;
        for index in 0..8 {
            rng.start_pixel_sample(UVec2::new(2, 9), index);
            plain.start_pixel_sample(UVec2::new(2, 9), index);
            for _ in 0..20 {
                let x = rng.next_u32();
                let v = plain.next_1d();
                assert_eq!((x >> 8) as f32 / 16_777_216.0, grid(v));
                assert_eq!(x & 0xff, x >> 24);
            }
            // A u64 is two dimensions, low word first.
            let w = rng.next_u64();
            assert_eq!(
                ((w as u32) >> 8) as f32 / 16_777_216.0,
                grid(plain.next_1d())
            );
            assert_eq!(
                ((w >> 40) as u32) as f32 / 16_777_216.0,
                grid(plain.next_1d())
            );
            let mut bytes = [0u8; 6];
            rng.fill_bytes(&mut bytes);
            let a = u32::from_le_bytes(bytes[..4].try_into().unwrap());
            assert_eq!((a >> 8) as f32 / 16_777_216.0, grid(plain.next_1d()));
            // The last word's first two bytes (little-endian).
            let h = (plain.next_1d() * 16_777_216.0) as u32;
            assert_eq!(bytes[4..], (h << 8 | h >> 16).to_le_bytes()[..2]);
        }
    }

    #[test]
    fn draws_are_the_samplers_dimensions() {
        // On the grid: the values themselves.
        let mut s = Independent::new(4, 1).unwrap();
        s.start_pixel_sample(UVec2::ZERO, 0);
        for _ in 0..100 {
            let v = s.next_1d();
            assert_eq!(grid(v), v);
        }
        check(Independent::new(4, 1).unwrap());
        check(Sobol::new(16, 2).unwrap());
        check(Halton::new(6, 3).unwrap());
    }
}
