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

use crate::lanes::Lanes;

/// `log₂ x` for a finite `x > 0` (subnormals included).
#[inline(always)]
fn log2_positive<L: Lanes>(x: L) -> L {
    let (k, int) = (L::splat, L::splat_int);
    // Subnormals are scaled into the normal range first (behind a test
    // of all lanes: they are rare, and one lane skips the work).
    let tiny = x.lt(k(f32::MIN_POSITIVE));
    let (x, e_tiny) = if L::any(tiny) {
        (
            L::select(tiny, x * k(16_777_216.0), x),
            L::select_int(tiny, int(-24), int(0)),
        )
    } else {
        (x, int(0))
    };
    let bits = x.to_bits();
    let e = (bits >> 23) - int(127) + e_tiny;
    // The mantissa in [1, 2), then in [√½, √2), so that s below is small.
    let m = L::from_bits((bits & int(0x007f_ffff)) | int(0x3f80_0000));
    let big = m.gt(k(SQRT_2));
    let m = L::select(big, m * k(0.5), m);
    let e = e + L::select_int(big, int(1), int(0));
    // ln m = 2 atanh s, s = (m − 1)/(m + 1), |s| ≤ 0.172: the series to
    // s⁹ leaves less than 10⁻⁹. m − 1 is exact (Sterbenz).
    let s = (m - k(1.0)) / (m + k(1.0));
    let s2 = s * s;
    let series = k(1.0)
        + s2 * (k(1.0 / 3.0) + s2 * (k(1.0 / 5.0) + s2 * (k(1.0 / 7.0) + s2 * k(1.0 / 9.0))));
    let ln_m = k(2.0) * s * series;
    L::from_int(e) + ln_m * k(LOG2_E)
}

/// `2^y`: `0` below −150, `+∞` from 128, NaN for NaN; within 3·10⁻⁷,
/// relative, elsewhere (plus half the subnormal step), tested.
#[inline(always)]
pub(crate) fn exp2<L: Lanes>(y: L) -> L {
    let (k, int) = (L::splat, L::splat_int);
    // Clamped so the exponent arithmetic below stays in range. The ends
    // give the right limits by themselves: 2⁻¹⁵¹ rounds to 0 (as does all
    // of 2^[−151, −150)), and 2¹²⁸ overflows to +∞.
    let yc = y.clamp_to(-151.0, 128.0);
    // Adding and taking away 1.5·2²³ rounds to the nearest integer (ties
    // to even) for |y| < 2²²: exact IEEE steps; the fraction f = y − n is
    // exact too, |f| ≤ ½.
    const ROUND: f32 = 12_582_912.0;
    let n = (yc + k(ROUND)) - k(ROUND);
    let f = yc - n;
    // 2^f = e^(f ln 2) by Taylor to degree 7 (truncation below 6·10⁻⁹).
    let p = k(1.0)
        + f * (k(LN_2)
            + f * (k(0.240_226_5)
                + f * (k(0.055_504_11)
                    + f * (k(0.009_618_129)
                        + f * (k(0.001_333_355_8)
                            + f * (k(0.000_154_035_3) + f * k(0.000_015_252_734)))))));
    // 2ⁿ as an f32 in two exact factors where n is outside the normal
    // exponents (n = 128, or n < −126 for a subnormal result): the first
    // product is exact, the second rounds once. (A NaN n converts to 0.)
    let n = n.to_int();
    let high = L::int_lt(int(127), n);
    let low = L::int_lt(n, int(-126));
    if !L::any(L::or(high, low)) {
        return p * L::from_bits((n + int(127)) << 23);
    }
    let n1 = L::select_int(high, n - int(1), L::select_int(low, n + int(64), n));
    let tiny = k(1.0 / 18_446_744_073_709_551_616.0);
    let second = L::select(high, k(2.0), L::select(low, tiny, k(1.0)));
    p * L::from_bits((n1 + int(127)) << 23) * second
}

/// `xᵃ` for `x ≥ 0` and a finite `a ≥ 0`: `x⁰ = 1` (`0⁰` included, as
/// `powf` has it), `0ᵃ = 0` for `a > 0`, and within the module's stated
/// accuracy elsewhere (`+∞` where it overflows, 0 below the smallest
/// subnormal). A NaN `x` gives NaN.
#[inline]
pub(crate) fn pow_nonneg<L: Lanes>(x: L, a: L) -> L {
    let k = L::splat;
    // Lanes outside (0, ∞) take 1 so the logarithm sees a finite positive
    // number; they are replaced below.
    let inside = L::and(x.gt(k(0.0)), x.lt(k(f32::INFINITY)));
    let r = exp2(a * log2_positive(L::select(inside, x, k(1.0))));
    let zero_a = a.eq(k(0.0));
    if !L::any(L::or(L::not(inside), zero_a)) {
        return r;
    }
    let r = L::select(x.eq(k(f32::INFINITY)), k(f32::INFINITY), r);
    let r = L::select(x.le(k(0.0)), k(0.0), r);
    let r = L::select(x.eq(x), r, k(f32::NAN));
    L::select(zero_a, k(1.0), r)
}

#[cfg(test)]
mod tests {
    use super::*;

    use crate::lanes::{classes, f32x8};

    #[test]
    fn lane_forms_give_the_scalar_bits() {
        classes::same_bits_1("exp2", exp2::<f32>, exp2::<f32x8>);
        classes::same_bits_1("log2", log2_positive::<f32>, log2_positive::<f32x8>);
        classes::same_bits_2("pow", pow_nonneg::<f32>, pow_nonneg::<f32x8>);
    }

    #[test]
    fn exp2_is_within_its_bound_of_f64() {
        let mut worst = 0.0f64;
        for i in -160_000..=130_000 {
            let y = i as f32 / 1000.0 + 0.000_3;
            let want = libm::exp2(f64::from(y));
            let got = f64::from(exp2(y));
            if want >= f64::from(f32::MAX) {
                assert_eq!(got, f64::INFINITY, "2^{y}");
                continue;
            }
            let bound = want * 3e-7 + 0.5 * f64::from(f32::from_bits(1));
            let err = (got - want).abs();
            assert!(err <= bound, "2^{y}: {got:e} vs {want:e}");
            worst = worst.max(err / bound);
        }
        assert!(worst > 0.05, "{worst}");
        assert_eq!(exp2(0.0f32), 1.0);
        assert_eq!(exp2(-3.0f32), 0.125);
        assert_eq!(exp2(-149.0f32), f32::from_bits(1));
        assert_eq!(exp2(-151.0f32), 0.0);
        assert_eq!(exp2(128.0f32), f32::INFINITY);
        assert!(exp2(f32::NAN).is_nan());
    }

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
