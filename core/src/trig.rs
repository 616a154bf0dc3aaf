//! Sines and cosines of the sampling mappings and of Lanczos's filter
//! taps, and the arc cosine and arc tangent of sphere texture
//! coordinates, as short sequences of plain IEEE operations over
//! [`Lanes`] (one `f32` or eight): the same bits on every CPU and in both
//! forms (no fused multiply-add, no table, no hardware approximation), for
//! a fraction of a libm call. Every mapping angle is a fraction of a turn
//! or of `π`, so the range reduction is exact.

use crate::lanes::Lanes;

/// `(sin πx, cos πx)` for `|x| ≤ ¼` by their Taylor polynomials to degree
/// 9 and 10 (truncation below 2·10⁻⁹; within 1.2·10⁻⁷ of the true values
/// with rounding, tested).
#[inline(always)]
pub(crate) fn sin_cos_pi_quarter<L: Lanes>(x: L) -> (L, L) {
    let k = L::splat;
    let x2 = x * x;
    let sin = x
        * (k(core::f32::consts::PI)
            + x2 * (k(-5.167_712_8)
                + x2 * (k(2.550_164) + x2 * (k(-0.599_264_5) + x2 * k(0.082_145_89)))));
    let cos = k(1.0)
        + x2 * (k(-4.934_802)
            + x2 * (k(4.058_712)
                + x2 * (k(-1.335_262_8) + x2 * (k(0.235_330_63) + x2 * k(-0.025_806_89)))));
    (sin, cos)
}

/// `(sin 2πu, cos 2πu)`: `4u` is split exactly into the nearest quarter
/// turn `q` and a rest `r ∈ [−½, ½]`, whose sine and cosine
/// ([`sin_cos_pi_quarter`] of `r / 2`) are rotated by `q` quarter turns.
/// Exact reduction, and the stated accuracy, for `|u| < 2²⁰`; a sampler's
/// `u ∈ [0, 1)` always is. Beyond that (and for NaN) the result is a
/// number of no meaning, the same in both lane forms.
#[inline(always)]
pub(crate) fn sin_cos_turn<L: Lanes>(u: L) -> (L, L) {
    // Adding and taking away 1.5·2²³ rounds to the nearest integer (ties
    // to even) for |v| < 2²² (|u| < 2²⁰): exact IEEE steps, no rounding
    // mode needed.
    const ROUND: f32 = 12_582_912.0;
    let v = L::splat(4.0) * u;
    let t = v + L::splat(ROUND);
    let q = t - L::splat(ROUND);
    let (s, c) = sin_cos_pi_quarter((v - q) * L::splat(0.5));
    // Quarter turn q mod 4 rotates (s, c) to (s, c), (c, −s), (−s, −c),
    // (−c, s): odd q swaps them; bit 1 negates the sine, bit 0 xor bit 1
    // the cosine (sign flips by xor: the same bits as negation). q + 1.5·2²³
    // is an integer in t's mantissa, and 1.5·2²³ ≡ 0 (mod 4), so q's low
    // bits are t's: no conversion to an integer.
    let q = t.to_bits();
    let one = L::splat_int(1);
    let swap = L::int_eq(q & one, one);
    let (a, b) = (L::select(swap, c, s), L::select(swap, s, c));
    let neg_sin = L::int_eq(q & L::splat_int(2), L::splat_int(2));
    let neg_cos = L::int_eq((q ^ (q >> 1)) & one, one);
    let sin = L::select(neg_sin, -a, a);
    let cos = L::select(neg_cos, -b, b);
    (sin, cos)
}

/// `(sin πx, cos πx)` for `|x| ≤ ½` by their Taylor polynomials to
/// degree 11 and 12 (truncation below 6·10⁻⁸), in plain `f32`
/// multiplies and adds: the same bits on every CPU, for a fraction of a
/// libm call. (Lanczos's taps; the mappings take
/// [`sin_cos_pi_quarter`], shorter on its narrower range.)
#[inline]
pub(crate) fn sin_cos_pi<L: Lanes>(x: L) -> (L, L) {
    debug_assert!((0..L::WIDTH).all(|k| x.lane(k).abs() <= 0.5));
    let k = L::splat;
    let x2 = x * x;
    let sin = x
        * (k(core::f32::consts::PI)
            + x2 * (k(-5.167_712_8)
                + x2 * (k(2.550_164)
                    + x2 * (k(-0.599_264_5) + x2 * (k(0.082_145_89) + x2 * k(-0.007_370_431))))));
    let cos = k(1.0)
        + x2 * (k(-4.934_802)
            + x2 * (k(4.058_712)
                + x2 * (k(-1.335_262_8)
                    + x2 * (k(0.235_330_63) + x2 * (k(-0.025_806_89) + x2 * k(0.001_929_574_3))))));
    (sin, cos)
}

/// `asin x` for `|x| ≤ ½` (Cephes' odd polynomial in `x²`, within an
/// ulp or two).
#[inline(always)]
fn asin_small<L: Lanes>(x: L) -> L {
    let k = L::splat;
    let z = x * x;
    let p = (((k(4.216_32e-2) * z + k(2.418_131e-2)) * z + k(4.547_002_6e-2)) * z
        + k(7.495_300_3e-2))
        * z
        + k(1.666_675_2e-1);
    x + x * z * p
}

/// `acos x` for `x ∈ [−1, 1]` (NaN outside, and for NaN): the arcsine
/// polynomial on `|x| ≤ ½`, and `2 asin √((1 − |x|)/2)` beyond, where
/// `1 − |x|` is exact, so the result stays accurate next to ±1. Within
/// 3·10⁻⁷ of the true value, tested against `f64`.
#[inline]
pub(crate) fn acos<L: Lanes>(x: L) -> L {
    use core::f32::consts::{FRAC_PI_2, PI};
    let k = L::splat;
    let a = x.abs();
    let near = a.le(k(0.5));
    // The square root of a negative (|x| > 1) gives the NaN.
    let s = ((k(1.0) - a) * k(0.5)).sqrt();
    let far = k(2.0) * asin_small(L::select(near, k(0.0), s));
    let far = L::select(x.sign_bit(), k(PI) - far, far);
    L::select(
        near,
        k(FRAC_PI_2) - asin_small(L::select(near, x, k(0.0))),
        far,
    )
}

/// `atan2(y, x)`, the angle of `(x, y)` in `[−π, π]` with C's signs of
/// zero (`atan2(±0, −0) = ±π`, `atan2(±0, +0) = ±0`) and infinities
/// (`atan2(∞, ∞) = π/4`); NaN if either is. The ratio of the smaller to
/// the larger magnitude is reduced below `tan(π/8)` and takes Cephes'
/// arctangent polynomial. Within 3·10⁻⁷ of the true value, tested against
/// `f64`.
#[inline]
pub(crate) fn atan2<L: Lanes>(y: L, x: L) -> L {
    use core::f32::consts::{FRAC_PI_2, FRAC_PI_4, PI};
    let k = L::splat;
    let (ax, ay) = (x.abs(), y.abs());
    let steep = ay.gt(ax);
    let (lo, hi) = (L::select(steep, ax, ay), L::select(steep, ay, ax));
    let t = lo / hi;
    let t = L::select(lo.eq(hi), k(1.0), t); // ∞/∞
    let t = L::select(hi.eq(k(0.0)), k(0.0), t); // 0/0
    // atan t = π/4 + atan((t − 1)/(t + 1)) above tan(π/8).
    let reduce = t.gt(k(0.414_213_57));
    let t = L::select(reduce, (t - k(1.0)) / (t + k(1.0)), t);
    let z = t * t;
    let p =
        ((k(8.053_744_5e-2) * z - k(1.387_768_6e-1)) * z + k(1.997_771_1e-1)) * z - k(3.333_295e-1);
    let r = t + t * z * p;
    let r = L::select(reduce, k(FRAC_PI_4) + r, r);
    let r = L::select(steep, k(FRAC_PI_2) - r, r);
    let r = L::select(x.sign_bit(), k(PI) - r, r);
    r.copysign(y)
}

#[cfg(test)]
mod tests {
    use super::*;

    use crate::lanes::{classes, f32x8};

    #[test]
    fn lane_forms_give_the_scalar_bits() {
        let sin = |x: f32| sin_cos_turn(x).0;
        classes::same_bits_1("sin_turn", sin, |x: f32x8| sin_cos_turn(x).0);
        let cos = |x: f32| sin_cos_turn(x).1;
        classes::same_bits_1("cos_turn", cos, |x: f32x8| sin_cos_turn(x).1);
        let q0 = |x: f32| sin_cos_pi_quarter(x).0;
        classes::same_bits_1("sin_pi_quarter", q0, |x: f32x8| sin_cos_pi_quarter(x).0);
        let q1 = |x: f32| sin_cos_pi_quarter(x).1;
        classes::same_bits_1("cos_pi_quarter", q1, |x: f32x8| sin_cos_pi_quarter(x).1);
        // sin_cos_pi's domain is |x| ≤ ½ (debug builds check it).
        let half = |x: f32| if x.abs() <= 0.5 { x } else { 0.25 };
        let half8 = |x: f32x8| f32x8::from_fn(|k| half(x.lane(k)));
        let p0 = |x: f32| sin_cos_pi(half(x)).0;
        classes::same_bits_1("sin_pi", p0, |x: f32x8| sin_cos_pi(half8(x)).0);
        let p1 = |x: f32| sin_cos_pi(half(x)).1;
        classes::same_bits_1("cos_pi", p1, |x: f32x8| sin_cos_pi(half8(x)).1);
        classes::same_bits_1("acos", acos::<f32>, acos::<f32x8>);
        classes::same_bits_2("atan2", atan2::<f32>, atan2::<f32x8>);
    }

    #[test]
    fn acos_is_within_3e_7_of_f64() {
        let mut xs: std::vec::Vec<f32> = (-65_536..=65_536).map(|i| i as f32 / 65_536.0).collect();
        for b in [1.0f32, 0.5] {
            for k in 1..64 {
                xs.push(f32::from_bits(b.to_bits() - k));
                xs.push(-f32::from_bits(b.to_bits() - k));
                xs.push(f32::from_bits(b.to_bits() + k).min(1.0));
            }
        }
        let mut worst = 0.0f64;
        for x in xs {
            let err = (f64::from(acos(x)) - f64::from(x).acos()).abs();
            assert!(
                err <= 3e-7,
                "acos({x:e}): {} vs {}",
                acos(x),
                f64::from(x).acos()
            );
            worst = worst.max(err);
        }
        assert!(worst > 5e-8, "{worst}");
        assert_eq!(acos(1.0f32), 0.0);
        assert_eq!(acos(-1.0f32), core::f32::consts::PI);
        for bad in [1.000_001f32, -1.5, f32::INFINITY, f32::NAN] {
            assert!(acos(bad).is_nan(), "{bad}");
        }
    }

    #[test]
    fn atan2_is_within_3e_7_of_f64() {
        let mut worst = 0.0f64;
        for i in 0..=20_000 {
            let a = (i as f64 / 20_000.0 - 0.5) * core::f64::consts::TAU;
            for r in [1e-30f64, 1e-3, 1.0, 7.5, 1e20] {
                let (y, x) = ((a.sin() * r) as f32, (a.cos() * r) as f32);
                let want = f64::from(y).atan2(f64::from(x));
                let err = (f64::from(atan2(y, x)) - want).abs();
                assert!(
                    err <= 3e-7,
                    "atan2({y:e}, {x:e}) = {} vs {want}",
                    atan2(y, x)
                );
                worst = worst.max(err);
            }
        }
        assert!(worst > 5e-8, "{worst}");
        // C's special cases, signs of zero included.
        let inf = f32::INFINITY;
        let cases = [
            (0.0f32, 0.0f32, 0.0f64),
            (-0.0, 0.0, -0.0),
            (0.0, -0.0, core::f64::consts::PI),
            (-0.0, -0.0, -core::f64::consts::PI),
            (1.0, 0.0, core::f64::consts::FRAC_PI_2),
            (-1.0, -0.0, -core::f64::consts::FRAC_PI_2),
            (inf, inf, core::f64::consts::FRAC_PI_4),
            (-inf, -inf, -3.0 * core::f64::consts::FRAC_PI_4),
            (1.0, -inf, core::f64::consts::PI),
            (-1.0, inf, -0.0),
        ];
        for (y, x, want) in cases {
            let got = atan2(y, x);
            assert_eq!(got, want as f32, "atan2({y}, {x})");
            assert_eq!(
                got.is_sign_negative(),
                want.is_sign_negative(),
                "atan2({y}, {x})"
            );
        }
        assert!(atan2(f32::NAN, 1.0).is_nan() && atan2(1.0, f32::NAN).is_nan());
    }

    #[test]
    fn sin_cos_pi_is_within_2e_7_of_the_true_values() {
        for i in -4096..=4096 {
            let x = i as f32 / 8192.0;
            let (s, c) = sin_cos_pi(x);
            let t = core::f64::consts::PI * f64::from(x);
            assert!((f64::from(s) - t.sin()).abs() < 1.8e-7, "sin at {x}");
            assert!((f64::from(c) - t.cos()).abs() < 1.8e-7, "cos at {x}");
        }
    }

    #[test]
    fn quarter_sines_are_within_1_2e_7_of_the_true_values() {
        for i in -8192..=8192 {
            let x = i as f32 / 32768.0;
            let (s, c) = sin_cos_pi_quarter(x);
            let t = core::f64::consts::PI * f64::from(x);
            assert!((f64::from(s) - t.sin()).abs() < 1.2e-7, "sin at {x}");
            assert!((f64::from(c) - t.cos()).abs() < 1.2e-7, "cos at {x}");
        }
    }

    #[test]
    fn turns_are_within_1_2e_7_of_the_true_values() {
        // Every multiple of 2⁻¹⁶ in [0, 1), the quadrant ties among them,
        // the float just below 1, and a few negative and large turns.
        let mut us: [f32; 65_536 + 6] = [0.0; 65_536 + 6];
        for (i, u) in us.iter_mut().enumerate().take(65_536) {
            *u = i as f32 / 65_536.0;
        }
        us[65_536..].copy_from_slice(&[
            crate::rng::ONE_MINUS_EPSILON,
            -0.3,
            -0.125,
            7.625,
            1000.1,
            0.875,
        ]);
        for u in us {
            let (s, c) = sin_cos_turn(u);
            let t = core::f64::consts::TAU * f64::from(u);
            assert!((f64::from(s) - t.sin()).abs() < 1.2e-7, "sin at {u}");
            assert!((f64::from(c) - t.cos()).abs() < 1.2e-7, "cos at {u}");
        }
        // Exact at the quarter turns, signs of zero included.
        let bits = |(s, c): (f32, f32)| (s.to_bits(), c.to_bits());
        assert_eq!(bits(sin_cos_turn(0.0)), bits((0.0, 1.0)));
        assert_eq!(bits(sin_cos_turn(0.25)), bits((1.0, -0.0)));
        assert_eq!(bits(sin_cos_turn(0.5)), bits((-0.0, -1.0)));
        assert_eq!(bits(sin_cos_turn(0.75)), bits((-1.0, 0.0)));
    }

    /// The documented range holds to its ends: every quarter and eighth
    /// turn just inside ±2²⁰ (where 4u is an integer plus ½ and
    /// ties decide the quadrant).
    #[test]
    fn turns_hold_up_to_the_range_end() {
        let top = (1u32 << 20) as f32;
        for k in 1..=64u32 {
            for u in [top - k as f32 / 8.0, -(top - k as f32 / 8.0)] {
                let (s, c) = sin_cos_turn(u);
                let t = core::f64::consts::TAU * (f64::from(u) % 1.0);
                assert!((f64::from(s) - t.sin()).abs() < 1.2e-7, "sin at {u}");
                assert!((f64::from(c) - t.cos()).abs() < 1.2e-7, "cos at {u}");
            }
        }
    }
}
