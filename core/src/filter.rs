//! Pixel reconstruction filters, applied by filter importance sampling or,
//! for filters with negative lobes, by splatting.
//!
//! A pixel's value is `∫ f(x) L(p + x) dx` for a filter `f` that
//! integrates to 1. A filter that is never negative is importance-sampled:
//! each sample's offset from the pixel centre is drawn with a density
//! `pdf ∝ |f|` and the radiance weighted by `f / pdf` (pbrt-v4's
//! approach), so a pixel depends only on its own samples. A filter with
//! negative lobes ([`PixelFilter::splats`]) would give weights whose sign
//! changes at random, and a pixel of few samples whose weights sum near
//! zero; renders splat it instead
//! ([`render_tile_splat`](crate::render::render_tile_splat)), and the
//! importance sampling below serves adaptive renders and callers.
//!
//! - Box and tent are sampled exactly: the weight is 1.
//! - The others (Gaussian, Mitchell–Netravali, Lanczos, Blackman–Harris)
//!   draw from a [`PiecewiseConstant2D`] of `FILTER_TABLE_SIZE²` cells
//!   tabulating `|f|`. The weight `f / pdf` is then close to ±1 and has the
//!   sign of `f`: Mitchell's and Lanczos's negative lobes give negative
//!   weights. Every cell has a positive density (a floor of 10⁻³ of the
//!   largest), so no part of the filter is left out.
//!
//! The film divides `Σ w·L` by `Σ w` rather than by the sample count
//! ([`PixelSum::mean`](crate::render::PixelSum::mean), as pbrt-v4's film):
//! slightly biased for a finite count, consistent, exact in flat regions,
//! and far less noisy for filters with negative lobes, whose weights change
//! sign between samples (the box mean of the pixel's own samples where
//! `|Σ w| < n/2`, so few samples cannot blow it up).
//! Each `w·L / E[w]` term alone is an unbiased estimate, which is what
//! the suite's convergence test checks.
//!
//! Every filter here is separable, `f(x, y) = f₁(x) f₁(y)`. The 1-D profile
//! is normalised at construction by Simpson's rule on 2048 intervals.

use core::f32::consts::PI;

use glam::Vec2;

use crate::mapping::{PIECEWISE_2D_SIZE, PiecewiseConstant2D};
use crate::trig::sin_cos_pi;

/// Cells per axis of a tabulated filter's sampling distribution.
pub const FILTER_TABLE_SIZE: usize = PIECEWISE_2D_SIZE;
const N: usize = FILTER_TABLE_SIZE;

/// The largest filter radius accepted, in pixels.
pub const FILTER_MAX_RADIUS: f32 = 8.0;

/// The shape of a pixel filter.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum FilterKind {
    /// Constant over the square (the course's: one pixel, radius ½).
    Box,
    /// `max(0, r − |x|)` per axis.
    Tent,
    /// `exp(−x²/2σ²) − exp(−r²/2σ²)` per axis, clamped at 0.
    Gaussian {
        /// Standard deviation in pixels, `> 0`.
        sigma: f32,
    },
    /// Mitchell–Netravali cubic on `|2x/r| ≤ 2`, with parameters `B`, `C`
    /// (⅓, ⅓ recommended); negative lobes.
    Mitchell {
        /// `B`.
        b: f32,
        /// `C`.
        c: f32,
    },
    /// Lanczos: `sinc(x) sinc(x/τ)` for `|x| ≤ r`; negative lobes.
    Lanczos {
        /// Window width `τ > 0` (Lanczos-3 is `τ = r = 3`).
        tau: f32,
    },
    /// The 4-term Blackman–Harris window over `[−r, r]`.
    BlackmanHarris,
}

impl FilterKind {
    /// Every kind with its usual parameters, in the order above.
    pub const ALL: [FilterKind; 6] = [
        FilterKind::Box,
        FilterKind::Tent,
        FilterKind::Gaussian { sigma: 0.5 },
        FilterKind::Mitchell {
            b: 1.0 / 3.0,
            c: 1.0 / 3.0,
        },
        FilterKind::Lanczos { tau: 3.0 },
        FilterKind::BlackmanHarris,
    ];

    /// The kind of [`FilterKind::ALL`] called `name` ([`FilterKind::name`]),
    /// with its usual parameters.
    ///
    /// ```
    /// use strata::filter::FilterKind;
    /// assert_eq!(FilterKind::named("lanczos"), Some(FilterKind::Lanczos { tau: 3.0 }));
    /// assert_eq!(FilterKind::named("sinc"), None);
    /// ```
    #[inline]
    #[must_use]
    pub fn named(name: &str) -> Option<FilterKind> {
        FilterKind::ALL.into_iter().find(|k| k.name() == name)
    }

    /// The usual radius of this kind, in pixels.
    ///
    /// ```
    /// use strata::filter::FilterKind;
    /// assert_eq!(FilterKind::Box.default_radius(), 0.5);
    /// ```
    #[inline]
    #[must_use]
    pub const fn default_radius(self) -> f32 {
        match self {
            FilterKind::Box => 0.5,
            FilterKind::Tent => 1.0,
            FilterKind::Gaussian { .. } | FilterKind::BlackmanHarris => 1.5,
            FilterKind::Mitchell { .. } => 2.0,
            FilterKind::Lanczos { .. } => 3.0,
        }
    }

    /// The kind's name (`box`, `tent`, `gaussian`, `mitchell`, `lanczos`,
    /// `blackman-harris`).
    #[inline]
    #[must_use]
    pub const fn name(self) -> &'static str {
        match self {
            FilterKind::Box => "box",
            FilterKind::Tent => "tent",
            FilterKind::Gaussian { .. } => "gaussian",
            FilterKind::Mitchell { .. } => "mitchell",
            FilterKind::Lanczos { .. } => "lanczos",
            FilterKind::BlackmanHarris => "blackman-harris",
        }
    }

    /// The unnormalised 1-D profile at `x` (0 for `|x| > r`).
    // Inlined so that an evaluation of both axes computes what they share
    // (the Gaussian's value at the radius) once.
    #[inline(always)]
    fn profile(self, radius: f32, x: f32) -> f32 {
        let ax = x.abs();
        if ax > radius {
            return 0.0;
        }
        match self {
            FilterKind::Box => 1.0,
            FilterKind::Tent => radius - ax,
            FilterKind::Gaussian { sigma } => {
                let g = |v: f32| exp_nonpositive(-(v * v) / (2.0 * sigma * sigma));
                (g(x) - g(radius)).max(0.0)
            }
            FilterKind::Mitchell { b, c } => {
                let t = 2.0 * ax / radius;
                if t > 1.0 {
                    ((-b - 6.0 * c) * t * t * t
                        + (6.0 * b + 30.0 * c) * t * t
                        + (-12.0 * b - 48.0 * c) * t
                        + (8.0 * b + 24.0 * c))
                        / 6.0
                } else {
                    ((12.0 - 9.0 * b - 6.0 * c) * t * t * t
                        + (-18.0 + 12.0 * b + 6.0 * c) * t * t
                        + (6.0 - 2.0 * b))
                        / 6.0
                }
            }
            FilterKind::Lanczos { tau } => sinc(x) * sinc(x / tau),
            FilterKind::BlackmanHarris => {
                // cos 2πkt for k = 2, 3 from k = 1 by the Chebyshev
                // recurrence: one polynomial cosine instead of three libm
                // calls (within 6·10⁻⁷ of the exact profile, tested).
                let t = (x + radius) / (2.0 * radius);
                let c1 = crate::trig::sin_cos_turn(t).1;
                let c2 = 2.0 * c1 * c1 - 1.0;
                let c3 = c1 * (2.0 * c2 - 1.0);
                0.35875 - 0.48829 * c1 + 0.14128 * c2 - 0.01168 * c3
            }
        }
    }
}

/// `eˣ` for `x ≤ 0` in plain `f32` multiplies and adds (the same bits on
/// every CPU): `k`, the integer nearest `x·log₂e`, is taken away as `k·ln 2`
/// in two parts (Cody–Waite: the first has trailing zero bits, so its
/// product with `k` is exact), `eʳ` of the rest `|r| ≤ 0.35` is its Taylor
/// polynomial to degree 7 (truncation below 8·10⁻⁹) and `2ᵏ` is built from
/// its exponent bits; 0 below `2⁻¹²⁶`, and for NaN. Within 2·10⁻⁷ of `eˣ`,
/// relative (tested), for a fraction of a libm call: the Gaussian filter
/// evaluates it per sample.
#[inline]
fn exp_nonpositive(x: f32) -> f32 {
    // Positive x would overflow the exponent bits below.
    debug_assert!(x.is_nan() || x <= 0.0, "{x}");
    // Adding and taking away 1.5·2²³ rounds to the nearest integer.
    const ROUND: f32 = 12_582_912.0;
    const LN2_HI: f32 = 0.693_145_75; // 0x3f317200
    const LN2_LO: f32 = 1.428_606_8e-6; // 0x35bfbe8e
    let y = x * core::f32::consts::LOG2_E;
    if y.is_nan() || y < -126.0 {
        return 0.0;
    }
    let k = (y + ROUND) - ROUND;
    let r = (x - k * LN2_HI) - k * LN2_LO;
    let p = 1.0
        + r * (1.0
            + r * (0.5
                + r * (1.0 / 6.0
                    + r * (1.0 / 24.0 + r * (1.0 / 120.0 + r * (1.0 / 720.0 + r / 5040.0))))));
    // k ∈ [−126, 0]: a normal power of two.
    p * f32::from_bits(((k as i32 + 127) as u32) << 23)
}

fn sinc(x: f32) -> f32 {
    if x.abs() < 1e-5 {
        return 1.0;
    }
    libm::sinf(PI * x) / (PI * x)
}

/// Why a filter was refused.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum FilterError {
    /// The radius is not in `(0, FILTER_MAX_RADIUS]`.
    Radius,
    /// A shape parameter is not finite, or `σ`/`τ` is not positive.
    Parameter,
    /// The filter is zero everywhere on its support.
    Zero,
}

impl core::fmt::Display for FilterError {
    #[inline]
    fn fmt(&self, f: &mut core::fmt::Formatter<'_>) -> core::fmt::Result {
        match self {
            FilterError::Radius => write!(
                f,
                "the filter radius must be in (0, {FILTER_MAX_RADIUS}] pixels"
            ),
            FilterError::Parameter => {
                f.write_str("a filter parameter is not finite, or sigma/tau is not positive")
            }
            FilterError::Zero => f.write_str("the filter is zero everywhere on its support"),
        }
    }
}

impl core::error::Error for FilterError {}

/// A filter's sample: where in the image, and its weight `f / pdf`.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct FilterSample {
    /// Offset from the pixel's corner, in pixels (`[0, 1)²` for the
    /// course's box; up to the radius beyond the pixel for wider filters).
    pub offset: Vec2,
    /// The sample's weight `f / pdf`: exactly 1 for box and tent.
    pub weight: f32,
}

/// A pixel filter with its sampler. `Copy` (about 9 KB with its table);
/// `Send` and `Sync`.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct PixelFilter {
    kind: FilterKind,
    radius: f32,
    /// Whether the filter takes negative values anywhere: such filters
    /// are splatted ([`PixelFilter::splats`]).
    negative: bool,
    /// `1 / ∫ f₁`: the 1-D normalisation.
    norm: f32,
    /// What [`PixelFilter::eval_taps`] needs per tap.
    taps: Taps,
    table: Option<PiecewiseConstant2D>,
}

/// The most taps a splat has along an axis: `2m + 1` for the margin of
/// the largest radius.
pub(crate) const TAPS: usize = 2 * FILTER_MAX_RADIUS as usize + 1;

/// Per tap `d` of a splat row, offset `k = d − m` pixels (`m` the splat
/// margin): `k`, and for Lanczos `(−1)ᵏ`, `cos πk/τ` and `sin πk/τ`.
/// Taps beyond `2m` have `k` = 10⁹, so their offset is beyond any radius.
#[derive(Clone, Copy, Debug, PartialEq)]
struct Taps {
    k: [f32; TAPS],
    sign: [f32; TAPS],
    cos: [f32; TAPS],
    sin: [f32; TAPS],
}

impl Taps {
    const NONE: Taps = Taps {
        k: [1e9; TAPS],
        sign: [0.0; TAPS],
        cos: [0.0; TAPS],
        sin: [0.0; TAPS],
    };

    fn new(kind: FilterKind, margin: u32) -> Taps {
        let mut t = Taps::NONE;
        for d in 0..=2 * margin as usize {
            let k = d as i32 - margin as i32;
            t.k[d] = k as f32;
            if let FilterKind::Lanczos { tau } = kind {
                let b = PI * k as f32 / tau;
                t.sign[d] = if k % 2 == 0 { 1.0 } else { -1.0 };
                t.cos[d] = libm::cosf(b);
                t.sin[d] = libm::sinf(b);
            }
        }
        t
    }
}

impl PixelFilter {
    /// The course's filter: a box of one pixel, offsets uniform in the
    /// pixel, weight 1.
    pub const BOX: PixelFilter = PixelFilter {
        kind: FilterKind::Box,
        radius: 0.5,
        negative: false,
        norm: 1.0,
        taps: Taps {
            k: {
                let mut k = [1e9; TAPS];
                k[0] = 0.0;
                k
            },
            ..Taps::NONE
        },
        table: None,
    };

    /// A filter of `kind` and `radius` (pixels).
    ///
    /// ```
    /// use glam::Vec2;
    /// use strata::filter::{FilterKind, PixelFilter};
    /// let m = PixelFilter::new(FilterKind::ALL[3], 2.0).unwrap();
    /// assert!(m.eval(Vec2::ZERO) > 0.0);
    /// assert!(m.eval(Vec2::new(1.5, 0.0)) < 0.0); // a negative lobe
    /// assert!(PixelFilter::new(FilterKind::Box, 0.0).is_err());
    /// ```
    #[inline]
    pub fn new(kind: FilterKind, radius: f32) -> Result<Self, FilterError> {
        if !(radius > 0.0 && radius <= FILTER_MAX_RADIUS) {
            return Err(FilterError::Radius);
        }
        let ok = match kind {
            FilterKind::Box | FilterKind::Tent | FilterKind::BlackmanHarris => true,
            FilterKind::Gaussian { sigma: s } | FilterKind::Lanczos { tau: s } => {
                s > 0.0 && s.is_finite()
            }
            FilterKind::Mitchell { b, c } => b.is_finite() && c.is_finite(),
        };
        if !ok {
            return Err(FilterError::Parameter);
        }
        if kind == FilterKind::Box && radius == 0.5 {
            return Ok(Self::BOX);
        }
        let integral = simpson(|x| kind.profile(radius, x) as f64, radius as f64);
        if !(integral.abs() > 1e-12 && integral.is_finite()) {
            return Err(FilterError::Zero);
        }
        // The profile on a fine grid of [0, r], against a tolerance for
        // `f32` zeros (Lanczos's sinf(π) is −9e-8): a lobe narrower than a
        // grid step (Mitchell with C below about 3e-4) is not seen, and
        // that filter is importance-sampled as before.
        let peak = kind.profile(radius, 0.0).abs();
        let negative =
            (0..=1024).any(|i| kind.profile(radius, radius * i as f32 / 1024.0) < -1e-6 * peak);
        let mut filter = Self {
            kind,
            radius,
            negative,
            norm: (1.0 / integral) as f32,
            taps: Taps::NONE,
            table: None,
        };
        filter.taps = Taps::new(kind, filter.splat_margin());
        if !matches!(kind, FilterKind::Box | FilterKind::Tent) {
            filter.table = Some(filter.tabulate().ok_or(FilterError::Zero)?);
        }
        Ok(filter)
    }

    /// `|f₁|` averaged over 4 points of each of the `N` cells of
    /// `[−r, r]`, floored at 10⁻³ of the largest; the table is the outer
    /// product.
    fn tabulate(&self) -> Option<PiecewiseConstant2D> {
        let mut a = [0.0f32; N];
        let width = 2.0 * self.radius / N as f32;
        for (i, v) in a.iter_mut().enumerate() {
            let mut s = 0.0;
            for k in 0..4 {
                let x = -self.radius + (i as f32 + (k as f32 + 0.5) / 4.0) * width;
                s += self.kind.profile(self.radius, x).abs();
            }
            *v = s / 4.0;
        }
        let floor = a.iter().copied().fold(0.0f32, f32::max) * 1e-3;
        for v in &mut a {
            *v = v.max(floor);
        }
        let mut values = [[0.0f32; N]; N];
        for (r, row) in values.iter_mut().enumerate() {
            for (c, v) in row.iter_mut().enumerate() {
                *v = a[r] * a[c];
            }
        }
        PiecewiseConstant2D::new(&values)
    }

    /// The kind.
    #[inline]
    #[must_use]
    pub fn kind(&self) -> FilterKind {
        self.kind
    }

    /// The radius in pixels.
    #[inline]
    #[must_use]
    pub fn radius(&self) -> f32 {
        self.radius
    }

    /// The normalised filter at offset `p` from the pixel centre: it
    /// integrates to 1 over `[−r, r]²` (signed), and is 0 outside.
    #[inline]
    #[must_use]
    pub fn eval(&self, p: Vec2) -> f32 {
        let f = |x: f32| self.kind.profile(self.radius, x) * self.norm;
        f(p.x) * f(p.y)
    }

    /// The normalised 1-D profile at `x` pixels from the centre:
    /// [`PixelFilter::eval`] is `eval_axis(p.x) · eval_axis(p.y)`.
    #[inline]
    #[must_use]
    pub fn eval_axis(&self, x: f32) -> f32 {
        self.kind.profile(self.radius, x) * self.norm
    }

    /// The normalised 1-D profile at the taps `x0 − k` for `k = −m..=m`,
    /// `m` the [splat margin](PixelFilter::splat_margin), in entry `k + m`
    /// (the rest 0): a splat's weights along one axis. As
    /// [`PixelFilter::eval_axis`] at each tap except for Lanczos, whose
    /// taps cost three sines in all instead of two each: `sin π(x0 − k) =
    /// (−1)ᵏ sin πx0`, and `sin π(x0 − k)/τ` by the angle difference with
    /// the stored `cos πk/τ` and `sin πk/τ`, in a loop of fixed length
    /// that compilers vectorise; the three are polynomials (libm's
    /// where the argument is beyond ½, as `x0/τ` may be for `τ < 1`). Those are plain `f32` operations (no
    /// fused multiply–add), so the values are the same on every CPU and
    /// SIMD width; they differ from `eval_axis`'s in the last bits.
    #[inline]
    pub(crate) fn eval_taps(&self, x0: f32) -> [f32; TAPS] {
        let t = &self.taps;
        let mut out = [0.0; TAPS];
        let FilterKind::Lanczos { tau } = self.kind else {
            let n = 2 * self.splat_margin() as usize + 1;
            for (o, k) in out[..n].iter_mut().zip(t.k) {
                *o = self.eval_axis(x0 - k);
            }
            return out;
        };
        // The polynomials hold for |x| ≤ ½: x0 is there for a sample in
        // its pixel, x0/τ too for τ ≥ 1; libm's sines otherwise.
        let sin_cos = |x: f32| match x.abs() <= 0.5 {
            true => sin_cos_pi(x),
            false => libm::sincosf(PI * x),
        };
        let (s, _) = sin_cos(x0);
        let (sa, ca) = sin_cos(x0 / tau);
        let scale = tau * self.norm / (PI * PI);
        for (d, o) in out.iter_mut().enumerate() {
            let x = x0 - t.k[d];
            // sin πx / (πx) · sin(πx/τ) / (πx/τ) with both sines rotated.
            let v = scale * (s * t.sign[d] * (sa * t.cos[d] - ca * t.sin[d])) / (x * x);
            *o = if x.abs() > self.radius {
                0.0
            } else if x.abs() < 1e-5 {
                self.norm
            } else {
                v
            };
        }
        out
    }

    /// Whether renders splat this filter instead of importance-sampling
    /// it: filters with negative lobes (Mitchell–Netravali with the usual
    /// parameters, Lanczos). Importance sampling gives each sample a
    /// weight `f / pdf` whose sign changes at random, so a pixel of few
    /// samples can sum to a weight near 0 or below: speckles and dark
    /// pixels. Splatted, every sample adds `f(x − p)·L` and `f(x − p)` to
    /// every pixel `p` its filter reaches, and each pixel's sum of weights
    /// is close to its sample count. (An adaptive render samples every
    /// filter by importance all the same: whether a render splats is
    /// [`Layout::splats`](crate::render::Layout::splats).)
    ///
    /// ```
    /// use strata::filter::{FilterKind, PixelFilter};
    /// let splats = |k: FilterKind| PixelFilter::new(k, k.default_radius()).unwrap().splats();
    /// assert!(splats(FilterKind::named("lanczos").unwrap()));
    /// assert!(splats(FilterKind::named("mitchell").unwrap()));
    /// assert!(!splats(FilterKind::named("gaussian").unwrap()));
    /// assert!(!PixelFilter::BOX.splats());
    /// ```
    #[inline]
    #[must_use]
    pub fn splats(&self) -> bool {
        self.negative
    }

    /// The pixels on each side of a pixel that its samples reach when
    /// splatted: `⌈r + ½⌉ − 1` (a sample in `[p, p + 1)` reaches the
    /// centres within `r` of it). 0 for the box of radius ½.
    ///
    /// ```
    /// use strata::filter::{FilterKind, PixelFilter};
    /// let margin = |k: FilterKind, r: f32| PixelFilter::new(k, r).unwrap().splat_margin();
    /// assert_eq!(margin(FilterKind::named("mitchell").unwrap(), 2.0), 2);
    /// assert_eq!(margin(FilterKind::named("lanczos").unwrap(), 3.0), 3);
    /// assert_eq!(margin(FilterKind::Box, 0.5), 0);
    /// ```
    #[inline]
    #[must_use]
    pub fn splat_margin(&self) -> u32 {
        libm::ceilf(self.radius + 0.5) as u32 - 1
    }

    /// The density with which [`PixelFilter::sample`] draws offset `p`
    /// from the pixel centre.
    #[inline]
    #[must_use]
    pub fn pdf(&self, p: Vec2) -> f32 {
        let r = self.radius;
        if !(p.x.abs() <= r && p.y.abs() <= r) {
            return 0.0;
        }
        match &self.table {
            // Box: uniform; tent: the normalised filter itself.
            None if self.kind == FilterKind::Box => 1.0 / (4.0 * r * r),
            None => self.eval(p),
            Some(t) => t.pdf((p / r + Vec2::ONE) * 0.5) / (4.0 * r * r),
        }
    }

    /// An offset from the pixel centre drawn with [`PixelFilter::pdf`],
    /// and its weight `f / pdf` (see [`FilterSample`]; here `offset` is
    /// from the centre, not the corner).
    #[inline]
    #[must_use]
    pub fn sample(&self, u: Vec2) -> FilterSample {
        let r = self.radius;
        match &self.table {
            None if self.kind == FilterKind::Box => FilterSample {
                offset: (u * 2.0 - Vec2::ONE) * r,
                weight: 1.0,
            },
            None => FilterSample {
                offset: Vec2::new(sample_tent(u.x, r), sample_tent(u.y, r)),
                weight: 1.0,
            },
            Some(t) => {
                let (q, pdf01) = t.sample(u);
                let offset = (q * 2.0 - Vec2::ONE) * r;
                let pdf = pdf01 / (4.0 * r * r);
                FilterSample {
                    offset,
                    weight: self.eval(offset) / pdf,
                }
            }
        }
    }

    /// The `u` that [`PixelFilter::sample`] maps to offset `p`, in the
    /// samplers' domain `[0, 1)²`: an offset at or past the filter's edge
    /// (or rounding there) gives the nearest `u` inside, `0` or
    /// [`ONE_MINUS_EPSILON`](crate::rng::ONE_MINUS_EPSILON); a NaN
    /// component stays NaN.
    ///
    /// ```
    /// use glam::Vec2;
    /// use strata::filter::{FilterKind, PixelFilter};
    /// let t = PixelFilter::new(FilterKind::Tent, 1.5).unwrap();
    /// let u = Vec2::new(0.2, 0.9);
    /// assert!((t.invert(t.sample(u).offset) - u).abs().max_element() < 1e-5);
    /// // The edge itself is not u = 1, which no sampler draws.
    /// assert!(t.invert(Vec2::splat(1.5)).max_element() < 1.0);
    /// ```
    #[inline]
    #[must_use]
    pub fn invert(&self, p: Vec2) -> Vec2 {
        let r = self.radius;
        let u = match &self.table {
            None if self.kind == FilterKind::Box => (p / r + Vec2::ONE) * 0.5,
            None => Vec2::new(invert_tent(p.x, r), invert_tent(p.y, r)),
            Some(t) => t.invert((p / r + Vec2::ONE) * 0.5),
        };
        // A NaN offset gives NaN (the table's lookup would not).
        let unit = |x: f32, p: f32| {
            if p.is_nan() {
                f32::NAN
            } else {
                x.clamp(0.0, crate::rng::ONE_MINUS_EPSILON)
            }
        };
        Vec2::new(unit(u.x, p.x), unit(u.y, p.y))
    }

    /// The sample the renderer takes for pixel-sampler value `u`: the
    /// offset from the pixel's corner and the weight. For [`Self::BOX`]
    /// the offset is `u` itself, so the course's box renders the same
    /// bits as a renderer without filters.
    // Always inlined: the box's test and early return then cost a camera
    // ray no call (the other filters call `sample`).
    #[inline(always)]
    #[must_use]
    pub fn pixel_sample(&self, u: Vec2) -> FilterSample {
        if self.kind == FilterKind::Box && self.radius == 0.5 {
            return FilterSample {
                offset: u,
                weight: 1.0,
            };
        }
        let s = self.sample(u);
        FilterSample {
            offset: s.offset + Vec2::splat(0.5),
            weight: s.weight,
        }
    }
}

/// The tent `max(0, r − |x|)/r²` by inversion of its CDF.
fn sample_tent(u: f32, r: f32) -> f32 {
    if u < 0.5 {
        -r + r * crate::float::sqrtf(2.0 * u)
    } else {
        r - r * crate::float::sqrtf(2.0 * (1.0 - u))
    }
}

fn invert_tent(x: f32, r: f32) -> f32 {
    let t = (x / r).clamp(-1.0, 1.0);
    if t < 0.0 {
        (1.0 + t) * (1.0 + t) * 0.5
    } else {
        1.0 - (1.0 - t) * (1.0 - t) * 0.5
    }
}

/// `∫_{−r}^{r} g` by Simpson's rule on 2048 intervals.
fn simpson(g: impl Fn(f32) -> f64, r: f64) -> f64 {
    const K: usize = 2048;
    let h = 2.0 * r / K as f64;
    let mut s = g(-r as f32) + g(r as f32);
    for i in 1..K {
        let x = (-r + i as f64 * h) as f32;
        s += g(x) * if i % 2 == 1 { 4.0 } else { 2.0 };
    }
    s * h / 3.0
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn exp_nonpositive_is_within_2e_7_relative() {
        for i in 0..=200_000 {
            let x = -(i as f32) / 1000.0; // 0 to −200, every 1/1000
            let want = f64::from(x).exp();
            let got = f64::from(exp_nonpositive(x));
            if want < 1.2e-38 {
                assert!(got <= 1.2e-38, "{x}: {got}");
            } else {
                assert!((got / want - 1.0).abs() < 2e-7, "{x}: {got} {want}");
            }
        }
        assert_eq!(exp_nonpositive(0.0), 1.0);
        assert_eq!(exp_nonpositive(-0.0), 1.0);
        assert_eq!(exp_nonpositive(f32::NEG_INFINITY), 0.0);
        assert_eq!(exp_nonpositive(f32::NAN), 0.0);
    }

    #[test]
    fn blackman_harris_cosines_are_within_6e_7_of_the_exact_profile() {
        let r = 1.5;
        for i in -3000..=3000 {
            let x = i as f32 / 2000.0;
            let t = f64::from((x + r) / (2.0 * r));
            let c = |k: f64| (2.0 * core::f64::consts::PI * k * t).cos();
            let want = 0.35875 - 0.48829 * c(1.0) + 0.14128 * c(2.0) - 0.01168 * c(3.0);
            let got = FilterKind::BlackmanHarris.profile(r, x);
            assert!((f64::from(got) - want).abs() < 6e-7, "{x}: {got} {want}");
        }
    }

    #[test]
    fn splat_taps_are_the_profile_at_each_centre() {
        // Lanczos's rotated sines agree with the profile to f32 rounding
        // (τ below 1 takes libm's sines); the others are the profile.
        let kinds = [
            (FilterKind::Lanczos { tau: 3.0 }, 3.0),
            (FilterKind::Lanczos { tau: 0.7 }, 2.0),
            (FilterKind::Lanczos { tau: 8.0 }, 8.0),
            (
                FilterKind::Mitchell {
                    b: 1.0 / 3.0,
                    c: 1.0 / 3.0,
                },
                2.0,
            ),
            (FilterKind::Gaussian { sigma: 0.5 }, 1.5),
        ];
        for (kind, radius) in kinds {
            let f = PixelFilter::new(kind, radius).unwrap();
            let m = f.splat_margin() as usize;
            for i in 0..256 {
                let x0 = -0.5 + i as f32 / 256.0;
                let taps = f.eval_taps(x0);
                for (d, &t) in taps.iter().enumerate() {
                    let want = if d <= 2 * m {
                        f.eval_axis(x0 - (d as f32 - m as f32))
                    } else {
                        0.0
                    };
                    if matches!(kind, FilterKind::Lanczos { .. }) {
                        assert!((t - want).abs() < 2e-6, "{kind:?} at {x0}, tap {d}");
                    } else {
                        assert_eq!(t, want, "{kind:?} at {x0}, tap {d}");
                    }
                }
            }
        }
    }

    #[test]
    fn box_of_half_a_pixel_is_the_identity() {
        let u = Vec2::new(0.123, 0.987);
        assert_eq!(PixelFilter::BOX.pixel_sample(u).offset, u);
        assert_eq!(PixelFilter::new(FilterKind::Box, 0.5), Ok(PixelFilter::BOX));
    }

    #[test]
    fn bad_parameters_are_refused() {
        for r in [0.0, -1.0, f32::NAN, f32::INFINITY, 9.0] {
            assert_eq!(
                PixelFilter::new(FilterKind::Tent, r),
                Err(FilterError::Radius)
            );
        }
        let g = FilterKind::Gaussian { sigma: 0.0 };
        assert_eq!(PixelFilter::new(g, 1.0), Err(FilterError::Parameter));
        let m = FilterKind::Mitchell {
            b: f32::NAN,
            c: 0.0,
        };
        assert_eq!(PixelFilter::new(m, 1.0), Err(FilterError::Parameter));
        // A Gaussian of huge sigma is flat and clamps to 0 everywhere.
        let flat = FilterKind::Gaussian { sigma: 1e30 };
        assert_eq!(PixelFilter::new(flat, 1.0), Err(FilterError::Zero));
    }

    #[test]
    fn tabulated_pdf_matches_sample_and_weights_are_near_one() {
        for kind in FilterKind::ALL {
            let f = PixelFilter::new(kind, kind.default_radius()).unwrap();
            for i in 0..64 {
                let u = Vec2::new((i as f32 + 0.5) / 64.0, ((i * 37 % 64) as f32 + 0.5) / 64.0);
                let s = f.sample(u);
                let pdf = f.pdf(s.offset);
                assert!(pdf > 0.0, "{kind:?}");
                assert!(
                    (s.weight - f.eval(s.offset) / pdf).abs() <= 1e-4 * s.weight.abs().max(1.0)
                );
                assert!(s.weight.abs() < 3.0, "{kind:?}: weight {}", s.weight);
                let back = f.invert(s.offset);
                assert!(
                    (back - u).abs().max_element() < 2e-4,
                    "{kind:?}: {u} -> {back}"
                );
            }
        }
    }

    #[test]
    fn invert_stays_in_the_unit_square() {
        for kind in FilterKind::ALL {
            for r in [kind.default_radius(), 0.5, 1.0, 2.7] {
                let f = PixelFilter::new(kind, r).unwrap();
                // The edges, just inside and outside them, far outside,
                // and the largest samples.
                let edge = [r, -r, r * (1.0 - f32::EPSILON), r * 1.5, 1e30, -1e30, 0.0];
                for &x in &edge {
                    for &y in &edge {
                        let u = f.invert(Vec2::new(x, y));
                        assert!(
                            u.cmpge(Vec2::ZERO).all() && u.cmplt(Vec2::ONE).all(),
                            "{kind:?} r {r}: ({x}, {y}) -> {u}"
                        );
                    }
                }
                let top = f.sample(Vec2::splat(crate::rng::ONE_MINUS_EPSILON)).offset;
                assert!(f.invert(top).cmplt(Vec2::ONE).all(), "{kind:?}");
                assert!(f.invert(Vec2::new(f32::NAN, 0.0)).x.is_nan(), "{kind:?}");
            }
        }
    }
}
