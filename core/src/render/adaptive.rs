//! Adaptive sampling: a base pass, then batches of samples while a pixel's
//! estimated relative error exceeds a threshold.
//!
//! See [`PixelError`] for the estimator.

use glam::Vec3;

/// Below this mean luminance a pixel's error is measured against the floor
/// rather than its mean (see [`PixelError`]).
pub const ERROR_FLOOR: f64 = 0.05;

/// How adaptive sampling proceeds: `base` samples every pixel, then
/// batches of `base` more while the pixel's relative error exceeds
/// `threshold`, up to `max` samples.
///
/// ```
/// use strata::render::Adaptive;
/// let a = Adaptive::new(16, 256, 0.05).unwrap();
/// assert_eq!((a.base(), a.max(), a.threshold()), (16, 256, 0.05));
/// assert!(Adaptive::new(16, 8, 0.05).is_err()); // max below the base
/// assert!(Adaptive::new(16, 256, f32::NAN).is_err());
/// ```
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Adaptive {
    base: u32,
    max: u32,
    threshold: f32,
}

/// Why an [`Adaptive`] was refused.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum AdaptiveError {
    /// The base count is 0.
    Base,
    /// The maximum is below the base count.
    Max,
    /// The threshold is not positive and finite.
    Threshold,
}

impl core::fmt::Display for AdaptiveError {
    #[inline]
    fn fmt(&self, f: &mut core::fmt::Formatter<'_>) -> core::fmt::Result {
        f.write_str(match self {
            AdaptiveError::Base => "the adaptive base sample count is 0",
            AdaptiveError::Max => "the adaptive maximum is below the base sample count",
            AdaptiveError::Threshold => "the adaptive threshold is not positive and finite",
        })
    }
}

impl core::error::Error for AdaptiveError {}

impl Adaptive {
    /// `base ≥ 1` samples first (and per batch), at most `max ≥ base`, while
    /// the relative error exceeds `threshold`, positive and finite.
    #[inline]
    pub fn new(base: u32, max: u32, threshold: f32) -> Result<Self, AdaptiveError> {
        if base == 0 {
            return Err(AdaptiveError::Base);
        }
        if max < base {
            return Err(AdaptiveError::Max);
        }
        if !(threshold > 0.0 && threshold.is_finite()) {
            return Err(AdaptiveError::Threshold);
        }
        Ok(Adaptive {
            base,
            max,
            threshold,
        })
    }

    /// Samples of the base pass, and of every batch after it.
    #[inline]
    #[must_use]
    pub fn base(&self) -> u32 {
        self.base
    }

    /// The most samples a pixel takes.
    #[inline]
    #[must_use]
    pub fn max(&self) -> u32 {
        self.max
    }

    /// The relative error at or below which a pixel stops.
    #[inline]
    #[must_use]
    pub fn threshold(&self) -> f32 {
        self.threshold
    }

    /// Whether a pixel that has taken `taken` samples (kept or dropped)
    /// with error statistics `error` takes another batch.
    ///
    /// ```
    /// use glam::Vec3;
    /// use strata::render::{Adaptive, PixelError};
    /// let a = Adaptive::new(4, 16, 0.05).unwrap();
    /// let mut flat = PixelError::ZERO;
    /// let mut noisy = PixelError::ZERO;
    /// for i in 0..4 {
    ///     flat.add(Vec3::splat(0.5), 1.0);
    ///     noisy.add(Vec3::splat((i % 2) as f32), 1.0);
    /// }
    /// assert!(!a.wants_more(4, &flat)); // no variance: stops at the base
    /// assert!(a.wants_more(4, &noisy));
    /// assert!(!a.wants_more(16, &noisy)); // at the maximum
    /// ```
    #[inline]
    #[must_use]
    pub fn wants_more(&self, taken: u32, error: &PixelError) -> bool {
        taken < self.max && error.relative_error() > self.threshold as f64
    }

    /// The sample indices of the batch after `taken` samples.
    #[inline]
    #[must_use]
    pub fn next_batch(&self, taken: u32) -> core::ops::Range<u32> {
        taken..taken.saturating_add(self.base).min(self.max)
    }
}

/// The running sums behind a pixel's error estimate.
///
/// Over the `n` finite samples a pixel has taken so far, with `wᵢ` the
/// filter weight and `yᵢ` the Rec. 709 luminance `0.2126 r + 0.7152 g +
/// 0.0722 b` of sample `i`'s radiance, computed in `f64`:
///
/// ```text
/// value  R  = Σ wᵢyᵢ / Σ wᵢ                            the film's value
/// error  e  = sqrt(n Σ (wᵢ(yᵢ − R))² / (n − 1)) / |Σ wᵢ| / max(|R|, ERROR_FLOOR)
/// ```
///
/// With weights of 1 this is `sqrt(s² / n) / max(|m|, ERROR_FLOOR)`, the
/// standard error of the mean over the mean, `s²` the unbiased sample
/// variance. Where the film falls back to the plain mean of `w·y`
/// (`|Σ w| < n/4`), the error is that mean's standard error.
///
/// `e` is the standard error of the pixel's mean relative to the mean, so
/// a threshold of 0.05 asks for a 1-σ error of 5 %. Pixels darker than
/// [`ERROR_FLOOR`] are held to the absolute error `threshold ×
/// ERROR_FLOOR` instead: a relative error of a near-black pixel is
/// unbounded and invisible once displayed. With fewer than two finite
/// samples the error is unknown and counts as infinite, so such a pixel
/// keeps sampling.
///
/// The sums run in sample-index order over the pixel's own samples and
/// nothing else, so the decision, and so the pixel, is the same for any
/// thread count, tile or pixel window. (It is not the same for any split
/// of the samples: the stopping point needs all earlier samples of the
/// pixel, which is why a run of samples `A..B` cannot be adaptive.)
///
/// Stopping on a noisy estimate is slightly biased: samples that happen
/// to be bright make a smaller relative error and stop sooner, and a pixel
/// whose first samples agree (all on one checker cell of an edge pixel)
/// stops at once. Measured in the suite: +0.4 % of the mean luminance on
/// `week09` with a base of 16, far below each pixel's noise. Use a base
/// of 16 samples or more: the bias grows as the base shrinks.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct PixelError {
    n: u32,
    /// Σ w, Σ w·y, Σ w², Σ w²·y, Σ w²·y².
    w: f64,
    wy: f64,
    w2: f64,
    w2y: f64,
    w2y2: f64,
}

impl PixelError {
    /// No samples.
    pub const ZERO: PixelError = PixelError {
        n: 0,
        w: 0.0,
        wy: 0.0,
        w2: 0.0,
        w2y: 0.0,
        w2y2: 0.0,
    };

    /// Adds a sample: radiance `l` with filter weight `w`. A sample the
    /// film drops (`w·l` or `w` not finite) is ignored here too.
    #[inline]
    pub fn add(&mut self, l: Vec3, w: f32) {
        if !((l * w).is_finite() && w.is_finite()) {
            return;
        }
        let y = 0.2126 * l.x as f64 + 0.7152 * l.y as f64 + 0.0722 * l.z as f64;
        let w = w as f64;
        self.n = self.n.saturating_add(1);
        self.w += w;
        self.wy += w * y;
        self.w2 += w * w;
        self.w2y += w * w * y;
        self.w2y2 += w * w * y * y;
    }

    /// Finite samples added.
    #[inline]
    #[must_use]
    pub fn samples(&self) -> u32 {
        self.n
    }

    /// The relative standard error of the pixel's luminance as the film
    /// computes it ([`PixelSum::mean`](super::PixelSum::mean)); infinite
    /// with fewer than two samples.
    ///
    /// With the ratio `R = Σ w·y / Σ w`, its standard error is, by the
    /// delta method, `√(n · Σ (wᵢ (yᵢ − R))² / (n − 1)) / |Σ w|`; with
    /// weights of 1 that is the familiar `√(s² / n)`. Where the film falls
    /// back to the plain mean of `w·y` (`|Σ w| < n/4`), so does this.
    ///
    /// ```
    /// use glam::Vec3;
    /// use strata::render::PixelError;
    /// let mut e = PixelError::ZERO;
    /// for v in [1.0f32, 3.0] {
    ///     e.add(Vec3::splat(v), 1.0);
    /// }
    /// // mean 2, variance 2, standard error 1: 50 %.
    /// assert!((e.relative_error() - 0.5).abs() < 1e-12);
    /// // A flat region under weights of both signs has no error.
    /// let mut flat = PixelError::ZERO;
    /// for w in [1.3f32, -0.4, 1.1, 0.9] {
    ///     flat.add(Vec3::splat(0.5), w);
    /// }
    /// assert!(flat.relative_error() < 1e-12);
    /// ```
    #[inline]
    #[must_use]
    pub fn relative_error(&self) -> f64 {
        if self.n < 2 {
            return f64::INFINITY;
        }
        let n = self.n as f64;
        let (value, se) = if libm::fabs(self.w) >= 0.25 * n {
            let r = self.wy / self.w;
            let s = (self.w2y2 - 2.0 * r * self.w2y + r * r * self.w2).max(0.0);
            (r, libm::sqrt(n * s / (n - 1.0)) / libm::fabs(self.w))
        } else {
            // The plain mean of v = w·y: Σ v = wy, Σ v² = w2y2.
            let m = self.wy / n;
            let var = ((self.w2y2 - m * self.wy) / (n - 1.0)).max(0.0);
            (m, libm::sqrt(var / n))
        };
        se / libm::fabs(value).max(ERROR_FLOOR)
    }
}
