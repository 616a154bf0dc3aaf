//! The independent sampler: a fresh PCG32 stream per pixel sample.

use glam::{UVec2, Vec2};
use rand_core::Rng;

use super::{PixelKey, Sampler};
use crate::rng::{Pcg32, STREAM, mix64, pixel_sample_rng, u32_to_unit_f32};

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

#[cfg(test)]
mod tests {
    use super::super::reference::{SPPS, visits};
    use super::*;

    /// The stream kept from the pixel's hash is the one
    /// [`pixel_sample_rng`] derives from scratch, drawn in dimension order
    /// (the pixel position first), skips included.
    #[test]
    fn independent_equals_its_definition() {
        for spp in SPPS {
            let seed = 17 + spp as u64;
            let mut s = Independent::new(spp, seed).unwrap();
            visits(spp, |pixel, index, draws| {
                let mut want = pixel_sample_rng(seed, pixel, index);
                let mut u = || u32_to_unit_f32(want.next_u32());
                s.start_pixel_sample(pixel, index);
                assert_eq!(s.pixel_2d(), Vec2::new(u(), u()));
                for (k, &two) in draws.iter().enumerate() {
                    match (two, k % 5 == 4) {
                        (false, false) => assert_eq!(s.next_1d(), u()),
                        (true, false) => assert_eq!(s.next_2d(), Vec2::new(u(), u())),
                        (false, true) => {
                            s.skip_1d();
                            u();
                        }
                        (true, true) => {
                            s.skip_2d();
                            u();
                            u();
                        }
                    }
                }
            });
        }
    }
}
