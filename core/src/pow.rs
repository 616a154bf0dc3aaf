//! `xᵃ` for the Phong and Blinn lobes as a short sequence of plain `f32`
//! operations: `2^(a · log₂ x)`, with `log₂` from the exponent bits and an
//! `atanh` series of the mantissa, and `2^y` from an exact split into an
//! integer and a fraction whose power is a Taylor polynomial. The same
//! bits on every CPU (no fused multiply-add, no table, no hardware
//! approximation) for about a third of a libm `powf` call, which took 8 %
//! of a `week09` render.
//!
//! Accuracy: `log₂ x` within a few units in its last place, `2^f`
//! within 3·10⁻⁷, so `xᵃ` is within `3·10⁻⁷ + 3·10⁻⁷ · |a · log₂ x|`,
//! relative, plus half the subnormal step (tested against `f64` over lobe
//! cosines and exponents 0.08 to 10⁴): about 10⁻⁶ for a lobe that still
//! shows, far below anything an image can.

use core::f32::consts::{LN_2, LOG2_E, SQRT_2};

/// `log₂ x` for a finite `x > 0` (subnormals included).
#[inline(always)]
fn log2_positive(x: f32) -> f32 {
    // Subnormals are scaled into the normal range first.
    let tiny = x < f32::MIN_POSITIVE;
    let (x, e_tiny) = if tiny {
        (x * 16_777_216.0, -24)
    } else {
        (x, 0)
    };
    let bits = x.to_bits();
    let mut e = ((bits >> 23) as i32) - 127 + e_tiny;
    // The mantissa in [1, 2), then in [√½, √2), so that s below is small.
    let mut m = f32::from_bits((bits & 0x007f_ffff) | 0x3f80_0000);
    if m > SQRT_2 {
        m *= 0.5;
        e += 1;
    }
    // ln m = 2 atanh s, s = (m − 1)/(m + 1), |s| ≤ 0.172: the series to
    // s⁹ leaves less than 10⁻⁹. m − 1 is exact (Sterbenz).
    let s = (m - 1.0) / (m + 1.0);
    let s2 = s * s;
    let ln_m =
        2.0 * s * (1.0 + s2 * (1.0 / 3.0 + s2 * (1.0 / 5.0 + s2 * (1.0 / 7.0 + s2 * (1.0 / 9.0)))));
    e as f32 + ln_m * LOG2_E
}

/// `2^y` for `y` not NaN: `0` below −150, `+∞` from 128.
#[inline(always)]
fn exp2(y: f32) -> f32 {
    if y < -150.0 {
        return 0.0;
    }
    if y >= 128.0 {
        return f32::INFINITY;
    }
    // Adding and taking away 1.5·2²³ rounds to the nearest integer (ties
    // to even) for |y| < 2²²: exact IEEE steps; the fraction f = y − n is
    // exact too, |f| ≤ ½.
    const ROUND: f32 = 12_582_912.0;
    let n = (y + ROUND) - ROUND;
    let f = y - n;
    // 2^f = e^(f ln 2) by Taylor to degree 7 (truncation below 6·10⁻⁹).
    let p = 1.0
        + f * (LN_2
            + f * (0.240_226_5
                + f * (0.055_504_11
                    + f * (0.009_618_129
                        + f * (0.001_333_355_8 + f * (0.000_154_035_3 + f * 0.000_015_252_734))))));
    // 2ⁿ as an f32 in two exact factors where n is outside the normal
    // exponents (n = 128, or n < −126 for a subnormal result): the first
    // product is exact, the second rounds once.
    let n = n as i32;
    let (n1, second) = if n > 127 {
        (n - 1, 2.0)
    } else if n < -126 {
        (n + 64, 1.0 / 18_446_744_073_709_551_616.0)
    } else {
        (n, 1.0)
    };
    p * f32::from_bits(((n1 + 127) as u32) << 23) * second
}

/// `xᵃ` for `x ≥ 0` and a finite `a ≥ 0`: `x⁰ = 1` (`0⁰` included, as
/// `powf` has it), `0ᵃ = 0` for `a > 0`, and within the module's stated
/// accuracy elsewhere (`+∞` where it overflows, 0 below the smallest
/// subnormal). A NaN `x` gives NaN.
#[inline]
pub(crate) fn pow_nonneg(x: f32, a: f32) -> f32 {
    if a == 0.0 {
        return 1.0;
    }
    if x.is_nan() {
        return f32::NAN;
    }
    if x <= 0.0 {
        return 0.0;
    }
    if x == f32::INFINITY {
        return f32::INFINITY;
    }
    exp2(a * log2_positive(x))
}

#[cfg(test)]
mod tests {
    use super::*;

    /// The relative error against `f64` stays within the stated bound over
    /// a grid of lobe cosines (and a little above 1, where rounding puts
    /// them) and exponents from 0.08 (the course's) to 10⁴.
    #[test]
    fn pow_is_within_its_bound_of_f64() {
        let mut worst = 0.0f64;
        let exponents = [
            0.08f32, 0.5, 1.0, 2.0, 3.7, 8.0, 20.0, 32.0, 100.0, 333.3, 1000.0, 1e4,
        ];
        for &a in &exponents {
            for k in 1..=20_000u32 {
                let x = k as f32 / 19_990.0; // up to 1.0005
                let got = pow_nonneg(x, a) as f64;
                let want = libm::pow(x as f64, a as f64);
                let y = (a as f64 * libm::log2(x as f64)).abs();
                // Relative, plus the half step of subnormal results.
                let bound = want * (3e-7 + 3e-7 * y) + 0.5 * f32::from_bits(1) as f64;
                let err = (got - want).abs();
                assert!(err <= bound, "{x}^{a}: {got:e} vs {want:e}");
                worst = worst.max(err / bound);
            }
        }
        // The bound is not slack by orders of magnitude.
        assert!(worst > 0.2, "{worst}");
    }

    #[test]
    fn special_values_follow_powf() {
        assert_eq!(pow_nonneg(0.0, 0.0), 1.0);
        assert_eq!(pow_nonneg(0.7, 0.0), 1.0);
        assert_eq!(pow_nonneg(0.0, 3.0), 0.0);
        assert_eq!(pow_nonneg(-0.0, 3.0), 0.0);
        assert_eq!(pow_nonneg(1.0, 1e30), 1.0);
        assert_eq!(pow_nonneg(0.5, 1e30), 0.0);
        assert_eq!(pow_nonneg(1.0001, 1e30), f32::INFINITY);
        assert_eq!(pow_nonneg(f32::INFINITY, 2.0), f32::INFINITY);
        assert!(pow_nonneg(f32::NAN, 2.0).is_nan());
        // Powers of two are exact, subnormal results included.
        assert_eq!(pow_nonneg(0.5, 3.0), 0.125);
        assert_eq!(pow_nonneg(0.5, 140.0), f32::from_bits(1 << 9));
        assert_eq!(pow_nonneg(2.0, 127.0), 2f32.powi(127));
        // A subnormal x: √(2⁻¹⁴⁰) = 2⁻⁷⁰.
        let tiny = f32::from_bits(1 << 9);
        assert_eq!(pow_nonneg(tiny, 0.5), f32::from_bits((127 - 70) << 23));
    }
}
