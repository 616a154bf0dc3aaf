//! Sines and cosines of the sampling mappings and of Lanczos's filter
//! taps, as short sequences of
//! plain `f32` multiplies and adds: the same bits on every CPU (no fused
//! multiply-add, no table, no hardware approximation), for a fraction of a
//! libm call. Every mapping angle is a fraction of a turn or of `π`, so
//! the range reduction is exact.

/// `(sin πx, cos πx)` for `|x| ≤ ¼` by their Taylor polynomials to degree
/// 9 and 10 (truncation below 2·10⁻⁹; within 1.2·10⁻⁷ of the true values
/// with rounding, tested).
#[inline(always)]
pub(crate) fn sin_cos_pi_quarter(x: f32) -> (f32, f32) {
    let x2 = x * x;
    let sin = x
        * (core::f32::consts::PI
            + x2 * (-5.167_712_8 + x2 * (2.550_164 + x2 * (-0.599_264_5 + x2 * 0.082_145_89))));
    let cos = 1.0
        + x2 * (-4.934_802
            + x2 * (4.058_712 + x2 * (-1.335_262_8 + x2 * (0.235_330_63 + x2 * -0.025_806_89))));
    (sin, cos)
}

/// `(sin 2πu, cos 2πu)`: `4u` is split exactly into the nearest quarter
/// turn `q` and a rest `r ∈ [−½, ½]`, whose sine and cosine
/// ([`sin_cos_pi_quarter`] of `r / 2`) are rotated by `q` quarter turns.
/// Exact reduction, and the stated accuracy, for `|u| < 2²⁰`; a sampler's
/// `u ∈ [0, 1)` always is.
#[inline(always)]
pub(crate) fn sin_cos_turn(u: f32) -> (f32, f32) {
    // Adding and taking away 1.5·2²³ rounds to the nearest integer (ties
    // to even) for |v| < 2²² (|u| < 2²⁰): exact IEEE steps, no rounding
    // mode needed.
    const ROUND: f32 = 12_582_912.0;
    let v = 4.0 * u;
    let q = (v + ROUND) - ROUND;
    let (s, c) = sin_cos_pi_quarter((v - q) * 0.5);
    match (q as i32) & 3 {
        0 => (s, c),
        1 => (c, -s),
        2 => (-s, -c),
        _ => (-c, s),
    }
}

/// `(sin πx, cos πx)` for `|x| ≤ ½` by their Taylor polynomials to
/// degree 11 and 12 (truncation below 6·10⁻⁸), in plain `f32`
/// multiplies and adds: the same bits on every CPU, for a fraction of a
/// libm call. (Lanczos's taps; the mappings take
/// [`sin_cos_pi_quarter`], shorter on its narrower range.)
#[inline]
pub(crate) fn sin_cos_pi(x: f32) -> (f32, f32) {
    debug_assert!(x.abs() <= 0.5);
    let x2 = x * x;
    let sin = x
        * (core::f32::consts::PI
            + x2 * (-5.167_712_8
                + x2 * (2.550_164
                    + x2 * (-0.599_264_5 + x2 * (0.082_145_89 + x2 * -0.007_370_431)))));
    let cos = 1.0
        + x2 * (-4.934_802
            + x2 * (4.058_712
                + x2 * (-1.335_262_8
                    + x2 * (0.235_330_63 + x2 * (-0.025_806_89 + x2 * 0.001_929_574_3)))));
    (sin, cos)
}

#[cfg(test)]
mod tests {
    use super::*;

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
