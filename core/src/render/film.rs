//! The film: exact per-pixel sums, so a pixel's value never depends on
//! how its samples were split, ordered or distributed over threads.
//!
//! Floating-point addition is not associative; integer addition is. Each
//! sample's RGB is clamped to `±MAX_SAMPLE_VALUE`, scaled by `2^24` and
//! rounded to an `i64`, and the sums are integers. Merging
//! two partial films is integer addition, so one run of samples `[0, b)`
//! gives the same bits as runs `[0, a)` and `[a, b)` merged, in any order.
//!
//! Range and resolution: a sample value is kept to `2⁻²⁴ ≈ 6·10⁻⁸` (far
//! below what an 8-bit or half-float image resolves) and clamped at
//! `2^16 = 65536`; a pixel holds up to `2²³` samples of that maximum, and
//! far more of ordinary radiance, before its sum saturates (it saturates
//! rather than wrapping; the own sums' difference from it, below, wraps
//! and stays exact). A sample with a NaN or infinite channel is
//! counted in `dropped` and not summed; the mean is over the samples kept.
//!
//! Each sample also adds its pixel-filter weight `w = f/pdf` to `weight`,
//! and the pixel's value is `Σ w·L / Σ w` (pbrt-v4's film): for the box
//! and tent, whose weights are exactly 1, that is the plain mean; for
//! filters with negative lobes it keeps the weights' noise out of flat
//! regions; where the weights nearly cancel it is the box mean of the
//! pixel's own samples, whose unweighted sum the film keeps too (as its
//! difference from the weighted one, 0 with weights of 1). Every sum is
//! exact, so merges stay exact. A splatted pixel
//! ([`Splat`](super::Splat)) gathers `f·L` and `f` from every sample
//! within the filter's reach, up to `(2m + 1)²` per sample of its own, so
//! it saturates that much sooner; once a sum saturates, the order of
//! additions can matter (so far above any radiance a scene shows that
//! no test reaches it).

use glam::Vec3;

/// A pixel whose weights sum below this share of its sample count (in
/// magnitude) takes its own samples' box mean ([`PixelSum::falls_back`]);
/// the adaptive pilot's statistics follow the same rule.
pub(crate) const FALLBACK_SHARE: f64 = 0.5;

/// Fixed-point scale: one unit is `2⁻²⁴`.
pub const FILM_SCALE: f32 = 16_777_216.0;

/// Sample values are clamped to `[−MAX_SAMPLE_VALUE, MAX_SAMPLE_VALUE]`
/// before summing (negative values come from filters with negative lobes).
pub const MAX_SAMPLE_VALUE: f32 = 65_536.0;

/// `x` in film units: `round(clamp(x) · 2²⁴)`, halves away from zero (as
/// `roundf`), exact and the same on every CPU: the scaling is by a power
/// of two, and `y ± ½` taken in `f64` is exact wherever it decides the
/// result, so the truncating cast rounds (see the body). (Every sample of
/// the film goes through it; `libm::roundf` is a software routine.) NaN
/// is never passed (the film drops it first).
#[inline]
#[must_use]
pub(crate) fn to_fixed(x: f32) -> i64 {
    let y = x.clamp(-MAX_SAMPLE_VALUE, MAX_SAMPLE_VALUE) * FILM_SCALE;
    // Half away from zero, as `roundf`, in five instructions: `y ± ½` in
    // f64 is exact for 2⁻²⁹ ≤ |y| ≤ 2⁴⁰ (y has 24 significant bits; the
    // sum needs at most 25, or 24 − e for y's exponent e below −1), so the
    // truncating cast rounds it; for smaller |y| the sum, however it
    // rounds, stays within 2⁻²⁹ of ½ and truncates to 0, as it should.
    let d = y as f64;
    (d + 0.5f64.copysign(d)) as i64
}

/// One pixel's exact accumulator: fixed-point sums of the weighted RGB,
/// of the filter weights and of its own samples' unweighted RGB, and
/// sample counts. 64 bytes; `Copy`, `Send`, `Sync`.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Hash)]
pub struct PixelSum {
    /// Sum of the kept samples' weighted RGB `w·L` in units of `2⁻²⁴`.
    pub sum: [i64; 3],
    /// Sum of the kept samples' filter weights `w` in units of `2⁻²⁴`.
    pub weight: i64,
    /// The sum of the pixel's own kept samples' RGB `L`, unweighted,
    /// minus `sum`, in units of `2⁻²⁴` (wrapping): [`PixelSum::own`] is
    /// the box mean's numerator the value falls back to where the weights
    /// nearly cancel ([`PixelSum::mean`]). Kept as a difference so that
    /// with weights of 1 (the box filter, a [`PixelSum::blend`]) it stays
    /// 0 and costs nothing (past saturation the own sums then saturate
    /// with the sums; such a pixel never falls back to them).
    pub own_minus_sum: [i64; 3],
    /// Samples summed.
    pub samples: u32,
    /// Samples dropped for a NaN or infinite channel.
    pub dropped: u32,
}

const _: () = assert!(core::mem::size_of::<PixelSum>() == 64);

impl PixelSum {
    /// No samples.
    pub const ZERO: PixelSum = PixelSum {
        sum: [0; 3],
        weight: 0,
        own_minus_sum: [0; 3],
        samples: 0,
        dropped: 0,
    };

    /// Adds one sample of weight 1 (or counts it as dropped if not
    /// finite).
    ///
    /// ```
    /// use glam::Vec3;
    /// use strata::render::PixelSum;
    /// let mut a = PixelSum::ZERO;
    /// a.add_sample(Vec3::new(0.1, 0.2, 0.3));
    /// a.add_sample(Vec3::new(f32::NAN, 0.0, 0.0));
    /// assert_eq!((a.samples, a.dropped), (1, 1));
    /// assert!((a.mean() - Vec3::new(0.1, 0.2, 0.3)).abs().max_element() < 1e-7);
    /// ```
    #[inline]
    pub fn add_sample(&mut self, v: Vec3) {
        if !v.is_finite() {
            self.dropped = self.dropped.saturating_add(1);
            return;
        }
        self.add_unit(v, 1.0);
    }

    /// Adds `l` with weight `w`, which must be 1 (the box's, given at run
    /// time: the weight's film units are then a constant), leaving
    /// `own_minus_sum`: the own sums move with the sums.
    #[inline]
    pub(crate) fn add_unit(&mut self, l: Vec3, w: f32) {
        debug_assert!(w == 1.0);
        let v = l * w;
        if !v.is_finite() {
            self.dropped = self.dropped.saturating_add(1);
            return;
        }
        // The own sums move with the sums, past saturation too: a pixel of
        // weights 1 never falls back to them.
        for (s, x) in self.sum.iter_mut().zip(v.to_array()) {
            *s = s.saturating_add(to_fixed(x));
        }
        // to_fixed(1.0), known here.
        self.weight = self.weight.saturating_add(FILM_SCALE as i64);
        self.samples = self.samples.saturating_add(1);
    }

    /// Adds radiance `l` with filter weight `w`: `w·l` to the sum, `w` to
    /// the weight and `l` to the own sum ([`PixelSum::own`]) (or counts the
    /// sample as dropped if `w·l` or `w` is not finite).
    ///
    /// ```
    /// use glam::Vec3;
    /// use strata::render::PixelSum;
    /// // A flat region under a filter with a negative lobe: the weights
    /// // vary, the value does not.
    /// let mut a = PixelSum::ZERO;
    /// for w in [1.25f32, -0.5, 0.75] {
    ///     a.add_weighted(Vec3::splat(0.5), w);
    /// }
    /// assert!((a.mean() - Vec3::splat(0.5)).abs().max_element() < 1e-7);
    /// ```
    #[inline]
    pub fn add_weighted(&mut self, l: Vec3, w: f32) {
        self.add_weighted_inline(l, w);
    }

    /// [`PixelSum::add_weighted`], always inlined: the tile renderers'
    /// per-sample add (a call there cost about 150 instructions a sample).
    #[inline(always)]
    pub(crate) fn add_weighted_inline(&mut self, l: Vec3, w: f32) {
        if w == 1.0 {
            // `w·l` is `l`: the own sums move with the sums.
            return self.add_sample(l);
        }
        let v = l * w;
        if !(v.is_finite() && w.is_finite()) {
            self.dropped = self.dropped.saturating_add(1);
            return;
        }
        for ((s, o), (x, y)) in self
            .sum
            .iter_mut()
            .zip(&mut self.own_minus_sum)
            .zip(v.to_array().into_iter().zip(l.to_array()))
        {
            let before = *s;
            *s = s.saturating_add(to_fixed(x));
            // As saturated: own − sum stays exact.
            *o = o
                .wrapping_add(to_fixed(y))
                .wrapping_sub(s.wrapping_sub(before));
        }
        self.weight = self.weight.saturating_add(to_fixed(w));
        self.samples = self.samples.saturating_add(1);
    }

    /// The sum of the pixel's own kept samples' RGB, unweighted, in units
    /// of `2⁻²⁴`: `sum + own_minus_sum`.
    ///
    /// ```
    /// use glam::Vec3;
    /// use strata::render::PixelSum;
    /// let mut a = PixelSum::ZERO;
    /// a.add_weighted(Vec3::splat(0.5), 1.5);
    /// a.add_weighted(Vec3::splat(0.25), -0.5);
    /// assert_eq!(a.own(), [(0.75 * 16_777_216.0) as i64; 3]);
    /// ```
    #[inline]
    #[must_use]
    pub fn own(&self) -> [i64; 3] {
        core::array::from_fn(|c| self.sum[c].wrapping_add(self.own_minus_sum[c]))
    }

    /// Adds another accumulator of the same pixel: exact, commutative and
    /// associative.
    ///
    /// ```
    /// use glam::Vec3;
    /// use strata::render::PixelSum;
    /// let (mut a, mut b, mut all) = (PixelSum::ZERO, PixelSum::ZERO, PixelSum::ZERO);
    /// for (i, v) in [0.1f32, 0.7, 1e-3, 5.0].into_iter().enumerate() {
    ///     let s = Vec3::splat(v);
    ///     all.add_sample(s);
    ///     if i % 2 == 0 { a.add_sample(s) } else { b.add_sample(s) }
    /// }
    /// b.merge(&a);
    /// assert_eq!(b, all); // the same bits, whatever the split
    /// ```
    #[inline]
    pub fn merge(&mut self, other: &PixelSum) {
        for c in 0..3 {
            let before = self.sum[c];
            self.sum[c] = before.saturating_add(other.sum[c]);
            // own − sum of the two, less what saturation kept off the sum.
            let lost = other.sum[c].wrapping_sub(self.sum[c].wrapping_sub(before));
            self.own_minus_sum[c] = self.own_minus_sum[c]
                .wrapping_add(other.own_minus_sum[c])
                .wrapping_add(lost);
        }
        self.weight = self.weight.saturating_add(other.weight);
        self.samples = self.samples.saturating_add(other.samples);
        self.dropped = self.dropped.saturating_add(other.dropped);
    }

    /// Starts splatting into the pixel: while splats move its sums
    /// directly ([`Splat`](super::Splat)), `own_minus_sum` holds the own
    /// sums themselves (own − sum + sum, wrapping: exact), so that they do
    /// not move with the splats' sums. [`PixelSum::end_splats`] restores
    /// the invariant; between the two the pixel is not a valid sum.
    #[inline]
    pub(crate) fn begin_splats(&mut self) {
        for (o, s) in self.own_minus_sum.iter_mut().zip(self.sum) {
            *o = o.wrapping_add(s);
        }
    }

    /// Ends [`PixelSum::begin_splats`]: `own_minus_sum` is own − sum
    /// again, of the sums the splats left.
    #[inline]
    pub(crate) fn end_splats(&mut self) {
        for (o, s) in self.own_minus_sum.iter_mut().zip(self.sum) {
            *o = o.wrapping_sub(s);
        }
    }

    /// Counts one of the pixel's own samples splatted into it, of
    /// radiance `own` in the film's units, between
    /// [`PixelSum::begin_splats`] and [`PixelSum::end_splats`]: its
    /// radiance to the own sums, and the sample count (its weighted sums
    /// came with the splat).
    #[inline]
    pub(crate) fn add_splatted_own(&mut self, own: [i64; 3]) {
        for (o, l) in self.own_minus_sum.iter_mut().zip(own) {
            *o = o.wrapping_add(l);
        }
        self.samples = self.samples.saturating_add(1);
    }

    /// Whether [`PixelSum::mean`] is the box mean of the own samples
    /// (`own / n`) rather than the weighted mean (`sum / Σ w`): where
    /// `|Σ w| < n/2`, and with no samples. Never with weights of 1.
    #[inline]
    #[must_use]
    pub fn falls_back(&self) -> bool {
        let n = FILM_SCALE as f64 * self.samples as f64;
        !(self.samples > 0 && libm::fabs(self.weight as f64) >= FALLBACK_SHARE * n)
    }

    /// The sums [`PixelSum::mean`] divides and what it divides them by,
    /// in film units (with no samples, the own sums over `2²⁴·0`).
    #[inline]
    fn ratio(&self) -> ([i64; 3], f64) {
        if self.falls_back() {
            (self.own(), FILM_SCALE as f64 * self.samples as f64)
        } else {
            (self.sum, self.weight as f64)
        }
    }

    /// Samples taken, kept or dropped (saturating).
    ///
    /// ```
    /// use glam::Vec3;
    /// use strata::render::PixelSum;
    /// let mut a = PixelSum::ZERO;
    /// a.add_sample(Vec3::ONE);
    /// a.add_sample(Vec3::splat(f32::INFINITY));
    /// assert_eq!(a.taken(), 2);
    /// ```
    #[inline]
    #[must_use]
    pub fn taken(&self) -> u32 {
        self.samples.saturating_add(self.dropped)
    }

    /// One accumulator whose [`mean`](PixelSum::mean) is `Σ cₖ ·
    /// mean(partₖ)` over the parts with samples (the weights `cₖ`
    /// renormalised over those), and which counts every part's samples:
    /// how an adaptive pixel ([`Adaptive`](super::Adaptive)) joins its
    /// pilot and its rest. Its weight is `2²⁴·n` for the `n` kept samples,
    /// its sums the blend's times that, rounded; a pure function of the
    /// parts in `f64`, so the same on every CPU. With no kept sample it
    /// is [`PixelSum::ZERO`] with the dropped count.
    ///
    /// ```
    /// use glam::Vec3;
    /// use strata::render::PixelSum;
    /// let (mut a, mut b) = (PixelSum::ZERO, PixelSum::ZERO);
    /// a.add_sample(Vec3::splat(1.0));
    /// for _ in 0..3 {
    ///     b.add_sample(Vec3::splat(3.0));
    /// }
    /// let j = PixelSum::blend(&[(a, 0.25), (b, 0.75)]);
    /// assert_eq!((j.samples, j.taken()), (4, 4));
    /// assert!((j.mean() - Vec3::splat(2.5)).abs().max_element() < 1e-6);
    /// ```
    #[inline]
    #[must_use]
    pub fn blend(parts: &[(PixelSum, f64)]) -> PixelSum {
        let mut out = PixelSum::ZERO;
        let mut total = 0.0;
        for (p, c) in parts {
            out.samples = out.samples.saturating_add(p.samples);
            out.dropped = out.dropped.saturating_add(p.dropped);
            if p.samples > 0 {
                total += c;
            }
        }
        if out.samples == 0 || total <= 0.0 {
            out.samples = 0;
            out.dropped = parts
                .iter()
                .fold(0u32, |d, (p, _)| d.saturating_add(p.taken()));
            return out;
        }
        let weight = FILM_SCALE as f64 * out.samples as f64;
        for ch in 0..3 {
            let mut m = 0.0;
            for (p, c) in parts.iter().filter(|(p, _)| p.samples > 0) {
                let (num, den) = p.ratio();
                m += c / total * (num[ch] as f64 / den);
            }
            // `as` saturates, like every sum of the film.
            out.sum[ch] = libm::round(m * weight) as i64;
        }
        out.weight = weight as i64;
        // Its weights are 1: its own sums are its sums.
        out
    }

    /// The pixel's value as linear RGB: the weighted mean `Σ w·L / Σ w` of
    /// the `n` kept samples (black with none). With weights of 1 it is the
    /// plain mean; in a flat region it is exact whatever the weights.
    ///
    /// The weights average 1, so `Σ w` estimates `n`; over few samples a
    /// filter with large negative lobes (Lanczos) can bring it near 0 and
    /// the ratio would blow up. Where `|Σ w| < n/2`
    /// ([`PixelSum::falls_back`]) the value is therefore the box mean of
    /// the pixel's own samples, `own / n`: never far from the pixel's
    /// radiance, exact where it is flat, and never negative where the
    /// radiance is not. (The earlier fallback, `Σ w·L / n` where
    /// `|Σ w| < n/4`, is unbiased on its own but scaled down by the small
    /// `Σ w` that chose it: splatted Lanczos at 1 spp was 4 % dark. With
    /// the box mean below a quarter, 2 % of `week09`'s pixels were still
    /// beyond 3 standard errors of the filter's true output; below a
    /// half, none beyond chance: `tests/rendering/filter_bias.rs`.) Box
    /// and tent weights are 1 and never fall back; Gaussian and
    /// Blackman–Harris weights are positive but small near the edge of
    /// their support, so a pixel of one or two samples there can.
    ///
    /// ```
    /// use glam::Vec3;
    /// use strata::render::PixelSum;
    /// let mut a = PixelSum::ZERO;
    /// a.add_weighted(Vec3::ONE, 1.0);
    /// a.add_weighted(Vec3::ZERO, -0.4); // Σ w = 0.6 < 2/2: the box mean
    /// assert!(a.falls_back());
    /// assert!((a.mean() - Vec3::splat(0.5)).abs().max_element() < 1e-6);
    /// a.add_weighted(Vec3::ONE, 1.0); // Σ w = 1.6 ≥ 3/2: the ratio
    /// assert!(!a.falls_back());
    /// assert!((a.mean() - Vec3::splat(2.0 / 1.6)).abs().max_element() < 1e-6);
    /// ```
    #[inline]
    #[must_use]
    pub fn mean(&self) -> Vec3 {
        if self.samples == 0 {
            return Vec3::ZERO;
        }
        let (num, den) = self.ratio();
        let k = 1.0 / den;
        Vec3::from_array(num.map(|x| (x as f64 * k) as f32))
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Between `begin_splats` and `end_splats` the sums move alone and the
    /// own sums stay: the pixel ends as if its own samples had been added
    /// and the splats' sums merged, in any order.
    #[test]
    fn splats_leave_the_own_sums_alone() {
        let mut p = PixelSum::ZERO;
        p.add_weighted(Vec3::new(0.5, 1.0, 2.0), 0.25);
        let own_before = p.own();
        p.begin_splats();
        for (c, s) in p.sum.iter_mut().enumerate() {
            *s = s.wrapping_add(1000 * (c as i64 + 1));
        }
        let own = [to_fixed(0.75), to_fixed(-0.5), to_fixed(3.0)];
        p.add_splatted_own(own);
        p.end_splats();
        let got = p.own();
        for c in 0..3 {
            assert_eq!(got[c], own_before[c].wrapping_add(own[c]), "channel {c}");
        }
        assert_eq!(p.samples, 2);
    }

    #[test]
    fn to_fixed_rounds_as_roundf_does() {
        let check = |x: f32| {
            let want =
                libm::roundf(x.clamp(-MAX_SAMPLE_VALUE, MAX_SAMPLE_VALUE) * FILM_SCALE) as i64;
            assert_eq!(to_fixed(x), want, "{x:e}");
        };
        // The clamp's boundaries and beyond, zeros, tiny values.
        for x in [
            0.0,
            -0.0,
            f32::MIN_POSITIVE,
            1e-30,
            0.5,
            -0.5,
            1.0,
            MAX_SAMPLE_VALUE,
            -MAX_SAMPLE_VALUE,
            MAX_SAMPLE_VALUE * 2.0,
            f32::INFINITY,
            f32::NEG_INFINITY,
            f32::MAX,
        ] {
            check(x);
        }
        // Every tie k + ½ film units below 2¹⁴ and its neighbours.
        for k in 0..1 << 14 {
            let half = (k as f32 + 0.5) / FILM_SCALE;
            for v in [half, -half] {
                check(v);
                check(f32::from_bits(v.to_bits() + 1));
                check(f32::from_bits(v.to_bits() - 1));
            }
        }
        // A sweep of bit patterns.
        let mut state = 0x9e37_79b9_u32;
        for _ in 0..1_000_000 {
            state ^= state << 13;
            state ^= state >> 17;
            state ^= state << 5;
            let x = f32::from_bits(state);
            if !x.is_nan() {
                check(x);
            }
        }
    }

    #[test]
    fn to_fixed_scales_clamps_and_rounds() {
        assert_eq!(to_fixed(1.0), FILM_SCALE as i64);
        assert_eq!(to_fixed(-0.5), -(FILM_SCALE as i64) / 2);
        assert_eq!(to_fixed(1e30), to_fixed(MAX_SAMPLE_VALUE));
        assert_eq!(to_fixed(-1e30), -to_fixed(MAX_SAMPLE_VALUE));
        // Half a film unit rounds away from zero.
        assert_eq!(to_fixed(0.5 / FILM_SCALE), 1);
    }

    #[test]
    fn own_sums_stay_exact_where_sums_saturate() {
        // own − sum wraps while the sum saturates: the own sum is still
        // the own samples' sum (mod 2⁶⁴).
        let near = i64::MAX - 10;
        let a = PixelSum {
            sum: [near; 3],
            own_minus_sum: [5i64.wrapping_sub(near); 3],
            samples: 1,
            ..PixelSum::ZERO
        };
        let b = PixelSum {
            sum: [100; 3],
            own_minus_sum: [1 - 100; 3],
            samples: 1,
            ..PixelSum::ZERO
        };
        let mut m = a;
        m.merge(&b);
        assert_eq!((m.sum, m.own()), ([i64::MAX; 3], [6; 3]));
        // A unit-weight add saturates the own sums with the sums (such a
        // pixel never falls back to them).
        let mut u = a;
        u.add_sample(Vec3::ONE);
        assert_eq!(u.sum, [i64::MAX; 3]);
        assert_eq!(u.own_minus_sum, a.own_minus_sum);
        // A weighted one keeps them exact.
        let mut w = a;
        w.add_weighted(Vec3::ONE, 2.0);
        assert_eq!(w.own(), [5 + (1 << 24); 3]);
    }

    #[test]
    fn blend_renormalises_over_parts_with_samples() {
        let mut a = PixelSum::ZERO;
        a.add_sample(Vec3::splat(2.0));
        let mut dropped = PixelSum::ZERO;
        dropped.add_sample(Vec3::splat(f32::NAN));
        // A part with no kept sample gives its weight to the others.
        let j = PixelSum::blend(&[(a, 0.2), (dropped, 0.8)]);
        assert_eq!((j.samples, j.dropped), (1, 1));
        assert_eq!(j.mean(), Vec3::splat(2.0));
        // None kept: zero, with every sample counted as dropped.
        let none = PixelSum::blend(&[(dropped, 0.5), (dropped, 0.5)]);
        assert_eq!(
            (none.samples, none.dropped, none.mean()),
            (0, 2, Vec3::ZERO)
        );
        assert_eq!(PixelSum::blend(&[]), PixelSum::ZERO);
        // Weighted parts keep their own means: a filter's Σ w·L / Σ w.
        let mut w = PixelSum::ZERO;
        w.add_weighted(Vec3::splat(1.0), 0.5);
        w.add_weighted(Vec3::splat(3.0), 1.5);
        let j = PixelSum::blend(&[(w, 0.5), (a, 0.5)]);
        assert!((j.mean() - Vec3::splat(2.25)).abs().max_element() < 1e-6);
    }
}
