//! Square roots and the vector operations built on them, in the vector
//! unit's encoding.
//!
//! `libm::sqrtf` on x86 is an `asm!` block holding the legacy-SSE
//! `sqrtss`, and glam's `length`/`normalize` call it (glam has no `std`
//! here). In a build with AVX, that one legacy instruction next to
//! 256-bit code stalls: sampled with `perf` on an AMD EPYC (Zen 3), a
//! camera ray's `normalize` took 47 % of a stratified render's tile loop.
//! These go through `wide` instead, whose `sqrt` is the compiler's
//! (`(v)sqrtps`/`(v)sqrtss` on x86, `fsqrt` on aarch64). A square root is
//! correctly rounded by IEEE 754 on every one of those paths, so for every
//! non-NaN input the bits are those of `libm` (a NaN stays a NaN; its sign
//! is unspecified, and the film drops NaN samples).
//!
//! The `cfg` must name exactly the targets where `wide` takes a hardware
//! branch (SSE, SSE2, aarch64 NEON): elsewhere `wide` falls back to a
//! software routine, so those targets (WebAssembly, embedded cores,
//! soft-float x86) keep `libm`.

use glam::Vec3;

/// `√x`, correctly rounded (NaN for `x < 0`), as `libm::sqrtf`.
#[inline(always)]
pub(crate) fn sqrtf(x: f32) -> f32 {
    if cfg!(any(
        target_feature = "sse",
        all(target_arch = "aarch64", target_feature = "neon")
    )) {
        wide::f32x4::splat(x).sqrt().to_array()[0]
    } else {
        libm::sqrtf(x)
    }
}

/// `√x` in `f64`, correctly rounded, as `libm::sqrt`.
#[inline(always)]
pub(crate) fn sqrt(x: f64) -> f64 {
    if cfg!(any(
        target_feature = "sse2",
        all(target_arch = "aarch64", target_feature = "neon")
    )) {
        wide::f64x2::splat(x).sqrt().to_array()[0]
    } else {
        libm::sqrt(x)
    }
}

/// `⌊q⌋` as an `i64`, as `libm::floorf(q) as i64` gives it for every `q`
/// (NaN is 0, beyond the range saturates): the integer part toward zero,
/// one less where that is above `q`. No libm call (a software routine: 4 %
/// of a `week09` render's instructions went to the checker's three calls a
/// hit).
#[inline(always)]
pub(crate) fn floor_i64(q: f32) -> i64 {
    let t = q as i64;
    // `t as f32` is exact wherever `q` has a fraction (|q| < 2²³), and
    // `q` is whole beyond; past ±2⁶³ `t` saturates, and `t as f32` (±2⁶³)
    // is above `q` only at −∞-ward saturation, which saturates again.
    t.saturating_sub(i64::from((t as f32) > q))
}

/// `|v|`, with the bits of glam's `Vec3::length`.
#[inline(always)]
pub(crate) fn length(v: Vec3) -> f32 {
    crate::lanes::V3::<f32>::from(v).length()
}

/// `v / |v|`, with the bits of glam's `Vec3::normalize` (non-finite for a
/// zero or non-finite `v`).
#[inline(always)]
pub(crate) fn normalize(v: Vec3) -> Vec3 {
    crate::lanes::V3::<f32>::from(v).normalize().into()
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn floor_i64_is_libm_floor_cast() {
        let check = |q: f32| assert_eq!(floor_i64(q), libm::floorf(q) as i64, "{q:e}");
        for q in [
            0.0,
            -0.0,
            0.5,
            -0.5,
            1.0,
            -1.0,
            -1.5,
            8_388_607.5,
            -8_388_607.5,
            8_388_608.0,
            -8_388_609.0,
            9.223_372e18,
            -9.223_372e18,
            f32::from_bits(0x5eff_ffff), // the largest float below 2⁶³
            -f32::from_bits(0x5eff_ffff),
            -f32::from_bits(1), // a negative subnormal
            1e30,
            -1e30,
            f32::MIN_POSITIVE,
            -f32::MIN_POSITIVE,
            f32::MAX,
            f32::MIN,
            f32::INFINITY,
            f32::NEG_INFINITY,
            f32::NAN,
        ] {
            check(q);
        }
        // Every 4099th bit pattern: all exponents and signs, NaNs too.
        for bits in (0..=u32::MAX).step_by(4099) {
            check(f32::from_bits(bits));
        }
    }

    fn bits(v: Vec3) -> [u32; 3] {
        v.to_array().map(f32::to_bits)
    }

    #[test]
    fn equal_libm_and_glam_bit_for_bit() {
        let mut x = 0x9e37_79b9u32;
        let mut next = || {
            x ^= x << 13;
            x ^= x >> 17;
            x ^= x << 5;
            f32::from_bits(x)
        };
        for s in [
            0.0f32,
            -0.0,
            1.0,
            2.0,
            f32::MIN_POSITIVE,
            1e-45,
            f32::MAX,
            f32::INFINITY,
        ] {
            assert_eq!(sqrtf(s).to_bits(), libm::sqrtf(s).to_bits(), "{s:e}");
        }
        assert!(sqrtf(-1.0).is_nan() && sqrtf(f32::NAN).is_nan());
        assert!(sqrt(-1.0).is_nan() && sqrt(f64::NAN).is_nan());
        for s in [
            0.0f64,
            -0.0,
            2.0,
            f64::MIN_POSITIVE,
            5e-324,
            f64::MAX,
            f64::INFINITY,
        ] {
            assert_eq!(sqrt(s).to_bits(), libm::sqrt(s).to_bits(), "{s:e}");
        }
        // Zero, tiny (1/|v| infinite), huge (|v|² overflows: 1/|v| = 0),
        // negative zeros, non-finite, and ordinary vectors.
        let fixed = [
            Vec3::new(1.0, 2.0, 3.0),
            Vec3::ZERO,
            Vec3::new(-0.0, 0.0, -0.0),
            Vec3::new(1e-30, 0.0, 0.0),
            Vec3::new(1e-45, -1e-45, 0.0),
            Vec3::splat(1e30),
            Vec3::new(-3e38, 1.0, 0.0),
            Vec3::new(f32::INFINITY, 0.0, 1.0),
            Vec3::new(f32::NAN, 1.0, 1.0),
        ];
        for k in 0..200_000 + fixed.len() {
            let v = fixed.get(k).copied().unwrap_or_else(|| {
                let v = Vec3::new(next(), next(), next());
                // Finite values over the whole range, most of them ordinary.
                if k % 4 == 0 {
                    v
                } else {
                    v.clamp(Vec3::splat(-1e18), Vec3::splat(1e18))
                }
            });
            let s = next().abs();
            assert_eq!(sqrtf(s).to_bits(), libm::sqrtf(s).to_bits(), "{s:e}");
            let d = f64::from_bits((s.to_bits() as u64) << 32 | next().to_bits() as u64);
            assert_eq!(sqrt(d).to_bits(), libm::sqrt(d).to_bits(), "{d:e}");
            assert_eq!(length(v).to_bits(), v.length().to_bits(), "{v}");
            let (a, b) = (normalize(v), v.normalize());
            for (x, y) in a.to_array().into_iter().zip(b.to_array()) {
                assert!(
                    x.to_bits() == y.to_bits() || x.is_nan() && y.is_nan(),
                    "{v}"
                );
            }
            // The lane forms, one lane and eight, against glam.
            let one = Vec3::from(crate::lanes::V3::<f32>::from(v).normalize_or_zero());
            assert_eq!(bits(one), bits(v.normalize_or_zero()), "{v}");
            let eight = crate::lanes::V3::<crate::lanes::f32x8>::splat(v).normalize_or_zero();
            assert_eq!(bits(eight.lane(k % 8)), bits(one), "{v}");
            let n8 = crate::lanes::V3::<crate::lanes::f32x8>::splat(v).normalize();
            let n1 = normalize(v);
            assert_eq!(bits(n8.lane(3)), bits(n1), "{v}");
        }
    }
}
