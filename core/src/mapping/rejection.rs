//! The course's rejection methods, kept as a documented comparison with the
//! analytic warps of [`crate::mapping`].
//!
//! Each draws from a generator of its own (any `rand_core::Rng`, e.g. a
//! [`crate::rng::Pcg32`]), never from a pixel's [`crate::sampler`]: the
//! number of values a rejection loop consumes is random, which would make
//! every later dimension depend on the path taken. They are for benchmarks
//! and teaching; the renderer uses the analytic warps.
//!
//! Acceptance rates: the disk accepts `π/4 ≈ 78.5 %` of candidate points,
//! the ball `π/6 ≈ 52.4 %`, so on average a disk point costs 2.55 uniform
//! draws and a ball point 5.73. The loops terminate with probability 1; a
//! generator that returned the same rejected value forever would loop
//! forever, which no PCG stream does.

use glam::{Vec2, Vec3};
use rand_core::Rng;

use crate::rng::next_f32;

/// Below this squared length a ball point has no usable direction.
const MIN_LEN2: f32 = 1e-30;

/// A point uniform in the open unit disk: draw `(2u − 1, 2v − 1)` until it
/// falls inside (the course's `random_vec3_in_unit_disk`). Its density is
/// `1 / π` per unit area, like [`crate::mapping::pdf_concentric_disk`].
///
/// ```
/// use strata::{mapping::rejection::rejection_unit_disk, rng::Pcg32};
/// let mut rng = Pcg32::new(42, 54);
/// assert!(rejection_unit_disk(&mut rng).length() < 1.0);
/// ```
#[inline]
pub fn rejection_unit_disk<R: Rng + ?Sized>(rng: &mut R) -> Vec2 {
    loop {
        let p = Vec2::new(2.0 * next_f32(rng) - 1.0, 2.0 * next_f32(rng) - 1.0);
        if p.length_squared() < 1.0 {
            return p;
        }
    }
}

/// A point uniform in the open unit ball: draw from the cube `[-1, 1)³`
/// until it falls inside (the course's `random_vec3_in_unit_sphere`).
/// Density `3 / (4π)` per unit volume.
///
/// ```
/// use strata::{mapping::rejection::rejection_unit_ball, rng::Pcg32};
/// let mut rng = Pcg32::new(42, 54);
/// assert!(rejection_unit_ball(&mut rng).length() < 1.0);
/// ```
#[inline]
pub fn rejection_unit_ball<R: Rng + ?Sized>(rng: &mut R) -> Vec3 {
    loop {
        let p = Vec3::new(
            2.0 * next_f32(rng) - 1.0,
            2.0 * next_f32(rng) - 1.0,
            2.0 * next_f32(rng) - 1.0,
        );
        if p.length_squared() < 1.0 {
            return p;
        }
    }
}

/// A direction uniform on the unit sphere: a [ball point](rejection_unit_ball)
/// normalised (RTIOW's `random_unit_vector`). Points too close to the
/// centre to normalise are rejected too. Density `1 / (4π)` per steradian,
/// like [`crate::mapping::pdf_uniform_sphere`].
///
/// ```
/// use strata::{mapping::rejection::rejection_unit_sphere, rng::Pcg32};
/// let mut rng = Pcg32::new(42, 54);
/// assert!((rejection_unit_sphere(&mut rng).length() - 1.0).abs() < 1e-6);
/// ```
#[inline]
pub fn rejection_unit_sphere<R: Rng + ?Sized>(rng: &mut R) -> Vec3 {
    loop {
        let p = rejection_unit_ball(rng);
        let len2 = p.length_squared();
        if len2 > MIN_LEN2 {
            return p / crate::float::sqrtf(len2);
        }
    }
}

/// A direction uniform on the hemisphere `z ≥ 0` by flipping (the course's
/// `random_on_hemisphere`): a [sphere direction](rejection_unit_sphere),
/// negated when it points below. Density `1 / (2π)` per steradian, like
/// [`crate::mapping::pdf_uniform_hemisphere`].
///
/// ```
/// use strata::{mapping::rejection::rejection_uniform_hemisphere, rng::Pcg32};
/// let mut rng = Pcg32::new(42, 54);
/// assert!(rejection_uniform_hemisphere(&mut rng).z >= 0.0);
/// ```
#[inline]
pub fn rejection_uniform_hemisphere<R: Rng + ?Sized>(rng: &mut R) -> Vec3 {
    let w = rejection_unit_sphere(rng);
    if w.z < 0.0 { -w } else { w }
}

/// A cosine-weighted direction on the hemisphere `z ≥ 0` by RTIOW's
/// Lambertian trick: the normal `+z` plus a uniform unit vector,
/// normalised (the course's pre-`a20431a` Phong/Blinn sampler, COURSE.md
/// D18). A sum too short to normalise is drawn again. Density `cos θ / π`,
/// like [`crate::mapping::pdf_cosine_hemisphere`].
///
/// ```
/// use strata::{mapping::rejection::rejection_cosine_hemisphere, rng::Pcg32};
/// let mut rng = Pcg32::new(42, 54);
/// let w = rejection_cosine_hemisphere(&mut rng);
/// assert!(w.z >= 0.0 && (w.length() - 1.0).abs() < 1e-6);
/// ```
#[inline]
pub fn rejection_cosine_hemisphere<R: Rng + ?Sized>(rng: &mut R) -> Vec3 {
    loop {
        let s = Vec3::Z + rejection_unit_sphere(rng);
        let len2 = s.length_squared();
        if len2 > MIN_LEN2 {
            let w = s / crate::float::sqrtf(len2);
            // Rounding can leave z a hair below 0 at the rim.
            return Vec3::new(w.x, w.y, w.z.max(0.0));
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::rng::Pcg32;

    #[test]
    fn outputs_lie_on_their_domains() {
        let mut rng = Pcg32::new(1, 2);
        for _ in 0..10_000 {
            assert!(rejection_unit_disk(&mut rng).length_squared() < 1.0);
            assert!(rejection_unit_ball(&mut rng).length_squared() < 1.0);
            let s = rejection_unit_sphere(&mut rng);
            assert!((s.length() - 1.0).abs() < 1e-6);
            let h = rejection_uniform_hemisphere(&mut rng);
            assert!(h.z >= 0.0 && (h.length() - 1.0).abs() < 1e-6);
            let c = rejection_cosine_hemisphere(&mut rng);
            assert!(c.z >= 0.0 && (c.length() - 1.0).abs() < 1e-6);
        }
    }

    #[test]
    fn disk_acceptance_rate_is_pi_over_4() {
        // Count the u32 draws a disk point costs: 2 per candidate.
        struct Counting(Pcg32, u64);
        impl rand_core::TryRng for Counting {
            type Error = core::convert::Infallible;
            fn try_next_u32(&mut self) -> Result<u32, Self::Error> {
                self.1 += 1;
                Ok(self.0.next_u32())
            }
            fn try_next_u64(&mut self) -> Result<u64, Self::Error> {
                self.1 += 2;
                Ok(self.0.next_u64())
            }
            fn try_fill_bytes(&mut self, dst: &mut [u8]) -> Result<(), Self::Error> {
                self.0.fill_bytes(dst);
                Ok(())
            }
        }
        let mut rng = Counting(Pcg32::new(3, 4), 0);
        let n = 100_000;
        for _ in 0..n {
            let _ = rejection_unit_disk(&mut rng);
        }
        let rate = (2 * n) as f64 / rng.1 as f64;
        // Binomial standard deviation of the rate is about 0.0013; 5 sigma.
        assert!(
            (rate - core::f64::consts::FRAC_PI_4).abs() < 0.0065,
            "{rate}"
        );
    }
}
