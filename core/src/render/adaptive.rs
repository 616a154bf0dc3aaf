//! Adaptive sampling that stays unbiased: a pilot decides how many
//! samples a pixel takes, and no part of the pixel's estimate is weighted
//! by a decision its own samples made.
//!
//! Stopping a pixel when its own samples look converged is biased: a
//! pixel whose first samples happen to miss a rare bright path (a
//! caustic, a light seen through glass) looks converged and stops low,
//! while one that saw such a path keeps sampling and dilutes it. On the
//! `caustics` scene that made images 5–10 % too dark.
//!
//! Here a pixel's samples come in blocks of `b = min / 4` consecutive
//! indices. Block 0 is pilot half A, block 1 pilot half B, and the rest
//! `R` (samples `2b..2b + r`, `r ≥ 2b`) is as long as the whole pilot
//! asks for. The pixel is
//!
//! ```text
//! value = c_A · mean(A) + c_B · mean(B) + (1 − c_A − c_B) · mean(R)
//! c_A   = b / (2b + r_B),   c_B = b / (2b + r_A)
//! ```
//!
//! where `r_A` is the rest half A's statistics alone would ask for (and
//! `r_B` B's). Each part's weight and length depend only on samples
//! outside it, so each term is unbiased and so is the pixel: exactly for
//! independent samples under filter weights of 1 (box, tent). Two things
//! bend it (the first is measured in the README and tested on
//! `caustics`):
//! - samplers that stratify a pixel's samples jointly (stratified, the
//!   Sobol' family, Halton) make the parts slightly dependent;
//! - under a filter whose weights vary, each part's mean is the film's
//!   ratio `Σ w·L / Σ w` over that part alone, biased by `O(1/b)` where a
//!   plain mean is `O(1/n)`, and a part of few samples falls back to its
//!   box mean (`|Σ w| < n/2`) more often than a whole pixel would.
//!
//! Where both halves agree (`r_A = r_B = r`) every sample weighs the
//! same, as in a plain mean; where only half A saw a rare bright path,
//! the rest grows and dilutes B's share, but A's own weight is set by B,
//! which saw a smooth pixel: that is the price of unbiasedness, paid only
//! by such pixels. (Likewise, where each half looks smooth but the two
//! disagree, so the whole pilot asks for a long rest, the pilot keeps the
//! weight of a short one.) A pilot half whose samples were all dropped
//! (not finite) gives its weight to the rest, which keeps the weights
//! free of the samples they weigh; a rest whose samples were all dropped
//! leaves the pilot's halves to share its weight.
//!
//! How many samples a pixel takes follows the allocation that minimises
//! the image's squared error for a given number of rays: samples in
//! proportion to `σ / √c`, the per-sample standard deviation over the
//! square root of the rays one sample costs. `σ` is measured on the
//! luminance `Y` and divided by `√Y`, so it is the error a gamma-2
//! display shows (one threshold serves dim and bright scenes); see
//! [`PilotStats::samples_wanted`].

use glam::Vec3;

use super::RenderSettings;
use super::camera::Camera;
use super::film::PixelSum;
use super::integrator::TileStats;
use super::scene::Scene;
use super::tile::{RenderError, Tile, check_tile, for_each_group, unit_weights};
use crate::sampler::Sampler;

/// The smallest normalising value of the error: pixels darker than
/// `ERROR_FLOOR²` in luminance are measured as if they had that
/// luminance (see [`PilotStats::samples_wanted`]).
pub const ERROR_FLOOR: f64 = 0.05;

/// How adaptive sampling proceeds (see the [module](self)): blocks of
/// `min / 4` samples, the pilot's two blocks, then a rest of at least two
/// blocks as the pilot asks, for `min..=max` samples a pixel;
/// `threshold` sets how many (a pixel asks for `σ / (N · threshold ·
/// √c)` samples, see [`PilotStats::samples_wanted`]).
///
/// ```
/// use strata::render::Adaptive;
/// let a = Adaptive::new(32, 1024, 0.02).unwrap();
/// assert_eq!((a.min(), a.max(), a.threshold()), (32, 1024, 0.02));
/// assert_eq!(a.block(), 8);
/// assert_eq!(a.rest_range(), 16..=1008);
/// assert!(Adaptive::new(30, 1024, 0.02).is_err()); // four blocks need a multiple of 4
/// assert!(Adaptive::new(4, 1024, 0.02).is_err()); // a half needs two samples
/// assert!(Adaptive::new(32, 16, 0.02).is_err()); // max below the minimum
/// assert!(Adaptive::new(32, 1024, f32::NAN).is_err());
/// ```
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Adaptive {
    min: u32,
    max: u32,
    threshold: f32,
}

/// Why an [`Adaptive`] was refused.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum AdaptiveError {
    /// The minimum is below 8 or not a multiple of 4 (it is four blocks
    /// of at least two samples: a half's deviation needs two).
    Min,
    /// The maximum is below the minimum.
    Max,
    /// The threshold is not positive and finite.
    Threshold,
}

impl core::fmt::Display for AdaptiveError {
    #[inline]
    fn fmt(&self, f: &mut core::fmt::Formatter<'_>) -> core::fmt::Result {
        f.write_str(match self {
            AdaptiveError::Min => {
                "the adaptive minimum must be a multiple of 4 of at least 8 (four blocks of min/4 samples, at least 2)"
            }
            AdaptiveError::Max => "the adaptive maximum is below the minimum",
            AdaptiveError::Threshold => "the adaptive threshold is not positive and finite",
        })
    }
}

impl core::error::Error for AdaptiveError {}

// The threshold is never NaN (`new` refuses it), so equality is total.
impl Eq for Adaptive {}

impl core::fmt::Display for Adaptive {
    #[inline]
    fn fmt(&self, f: &mut core::fmt::Formatter<'_>) -> core::fmt::Result {
        write!(
            f,
            "adaptive threshold {} min {} max {}",
            self.threshold, self.min, self.max
        )
    }
}

impl Adaptive {
    /// The default threshold (`strata render --adaptive`), chosen with
    /// [`DEFAULT_MIN`](Adaptive::DEFAULT_MIN) and
    /// [`DEFAULT_MAX`](Adaptive::DEFAULT_MAX) by `strata adaptive` on
    /// `caustics`, `week09` and `cover` (the README's adaptive sampling
    /// table): one setting whose RMSE is below uniform sampling's at equal
    /// rays and CPU seconds on all three (relMSE, which weighs dark pixels
    /// up, is not, on `caustics`).
    pub const DEFAULT_THRESHOLD: f32 = 0.0004;
    /// The default minimum: four blocks of 64, each a (0, 6, 2)-net of
    /// the Sobol' family's first two dimensions. A pixel whose bright
    /// paths are rarer than about one in `min / 2` samples looks smooth
    /// to the pilot; a smaller minimum misses more of them (measured on
    /// `caustics` at equal rays and threshold 0.001: a minimum of 128 gave
    /// 0.80 of uniform sampling's RMSE, 256 gives 0.62 and 512 0.52; 256
    /// keeps an adaptive render's least cost at half of 512's).
    pub const DEFAULT_MIN: u32 = 256;
    /// The default maximum: 16 times the minimum, room for the few pixels
    /// whose pilot caught a rare bright path (`caustics` at threshold
    /// 0.0005: 0.61 of uniform sampling's RMSE with a maximum of 2048, 0.58
    /// with 4096).
    pub const DEFAULT_MAX: u32 = 4096;

    /// At least `min` samples (a multiple of 4 of at least 8: four blocks
    /// of `min / 4 ≥ 2`), at most `max ≥ min` (rounded down to whole
    /// blocks), `threshold` positive and finite.
    #[inline]
    pub fn new(min: u32, max: u32, threshold: f32) -> Result<Self, AdaptiveError> {
        if min < 8 || !min.is_multiple_of(4) {
            return Err(AdaptiveError::Min);
        }
        if max < min {
            return Err(AdaptiveError::Max);
        }
        if !(threshold > 0.0 && threshold.is_finite()) {
            return Err(AdaptiveError::Threshold);
        }
        Ok(Adaptive {
            min,
            max,
            threshold,
        })
    }

    /// The fewest samples a pixel takes.
    #[inline]
    #[must_use]
    pub fn min(&self) -> u32 {
        self.min
    }

    /// The most samples a pixel takes.
    #[inline]
    #[must_use]
    pub fn max(&self) -> u32 {
        self.max
    }

    /// What sets how many samples a pixel takes.
    #[inline]
    #[must_use]
    pub fn threshold(&self) -> f32 {
        self.threshold
    }

    /// Samples per block: `min / 4`. Block 0 is pilot half A (indices
    /// `0..b`), block 1 half B (`b..2b`); the rest starts at `2b`.
    #[inline]
    #[must_use]
    pub fn block(&self) -> u32 {
        self.min / 4
    }

    /// The lengths the rest can take: whole blocks from two to as many
    /// as fit in `max` after the pilot.
    #[inline]
    #[must_use]
    pub fn rest_range(&self) -> core::ops::RangeInclusive<u32> {
        let b = self.block();
        2 * b..=(self.max - 2 * b) / b * b
    }

    /// The rest the statistics `stats` ask for: `samples_wanted` less
    /// the pilot's `2b`, rounded up to whole blocks, within
    /// [`rest_range`](Adaptive::rest_range).
    ///
    /// ```
    /// use glam::Vec3;
    /// use strata::render::{Adaptive, PilotStats};
    /// let a = Adaptive::new(16, 256, 0.005).unwrap();
    /// let (mut flat, mut noisy) = (PilotStats::ZERO, PilotStats::ZERO);
    /// for i in 0..4 {
    ///     flat.add(Vec3::splat(0.5), 1.0, 2);
    ///     noisy.add(Vec3::splat((i % 2) as f32), 1.0, 2);
    /// }
    /// assert_eq!(a.rest_for(&flat), 8); // no variance: the shortest rest
    /// assert!(a.rest_for(&noisy) > 8);
    /// assert!(a.rest_for(&noisy) <= 248);
    /// ```
    #[inline]
    #[must_use]
    pub fn rest_for(&self, stats: &PilotStats) -> u32 {
        let (b, range) = (self.block() as f64, self.rest_range());
        let (lo, hi) = (*range.start(), *range.end());
        let want = (stats.samples_wanted(self.threshold) - 2.0 * b) / b;
        // ∞ (fewer than two samples), huge values and, defensively, NaN
        // take the most.
        if want.is_nan() || want >= (hi / self.block()) as f64 {
            hi
        } else {
            (libm::ceil(want.max(0.0)) as u32 * self.block()).clamp(lo, hi)
        }
    }

    /// The weights of pilot halves A and B, from the rests `rest_a` and
    /// `rest_b` that each half's statistics ask for: `b / (2b + rest_b)`
    /// and `b / (2b + rest_a)` (each set by the *other* half).
    #[inline]
    #[must_use]
    pub fn pilot_weights(&self, rest_a: u32, rest_b: u32) -> [f64; 2] {
        let b = self.block() as f64;
        [b / (2.0 * b + rest_b as f64), b / (2.0 * b + rest_a as f64)]
    }

    /// Whether a pixel can hold `taken` samples after an adaptive render:
    /// the pilot's `2b` and a rest in [`rest_range`](Adaptive::rest_range).
    #[inline]
    #[must_use]
    pub fn can_take(&self, taken: u32) -> bool {
        let b = self.block();
        taken
            .checked_sub(2 * b)
            .is_some_and(|r| r.is_multiple_of(b) && self.rest_range().contains(&r))
    }
}

/// The running sums of a pilot (or one half of it): what
/// [`Adaptive::rest_for`] decides the rest from.
///
/// Over the `n` finite samples added, with `wᵢ` the filter weight, `yᵢ`
/// the Rec. 709 luminance `0.2126 r + 0.7152 g + 0.0722 b` of the
/// radiance (in `f64`) and `cᵢ` the rays the sample traced:
///
/// ```text
/// value  R = Σ wᵢyᵢ / Σ wᵢ                                   the film's value
/// σ      = n · sqrt(Σ (wᵢ(yᵢ − R))² / (n − 1)) / |Σ wᵢ|       one sample's deviation
/// c      = Σ cᵢ / n                                         rays per sample
/// ```
///
/// With weights of 1, `σ` is the sample standard deviation. Where the
/// film falls back to the box mean of `y` (`|Σ w| < n/2`), `R` and `σ` are
/// that mean and the sample standard deviation.
///
/// The sums are exact, like the film's: each sample's terms are taken in
/// `f64` and truncated to fixed point (units of `2⁻⁴⁰`) in `i128`, so the
/// statistics, and the decisions made from them, never depend on the
/// order in which samples arrive or how partial sums are merged. Radiance
/// channels and the weight are each clamped to `±MAX_SAMPLE_VALUE` first
/// (the film clamps `w·l` and `w`); then a signed term is at most `2⁸⁸`
/// units, and the signed sums, added modulo `2¹²⁸`, are exact for fewer
/// than `2³⁹` samples of the largest values (far more of ordinary radiance);
/// the non-negative ones (`Σ w²`, `Σ w²y²`, `Σ y²`) saturate, which no
/// order changes either. Each term is truncated towards zero to its unit
/// (a bias below `10⁻¹²` a sample).
///
/// ```
/// use glam::Vec3;
/// use strata::render::PilotStats;
/// let samples = [(0.1f32, 0.25f32), (3.0, 1.0), (1e-7, -0.5), (7.0, 1.25)];
/// let (mut forward, mut backward) = (PilotStats::ZERO, PilotStats::ZERO);
/// for &(v, w) in &samples {
///     forward.add(Vec3::splat(v), w, 2);
/// }
/// for &(v, w) in samples.iter().rev() {
///     backward.add(Vec3::splat(v), w, 2);
/// }
/// assert_eq!(forward, backward);
/// ```
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub struct PilotStats {
    n: u32,
    rays: u64,
    /// Σ w, Σ w·y, Σ w², Σ w²·y, Σ w²·y², and Σ y, Σ y² for the box mean,
    /// in units of `2⁻⁴⁰`.
    w: i128,
    wy: i128,
    w2: i128,
    w2y: i128,
    w2y2: i128,
    y: i128,
    y2: i128,
}

/// Fixed-point scale of [`PilotStats`]' sums.
const PILOT_SCALE: f64 = 1_099_511_627_776.0; // 2⁴⁰

/// `t` in units of `2⁻⁴⁰`, truncated towards zero (saturating; `t` is
/// never NaN). Most terms fit an `i64`, whose conversion is one
/// instruction; the result is the same either way.
#[inline]
fn pilot_fixed(t: f64) -> i128 {
    let v = t * PILOT_SCALE;
    if libm::fabs(v) < 9.0e18 {
        v as i64 as i128
    } else {
        v as i128
    }
}

/// A sum back in `f64` (rounded to nearest).
#[inline]
fn pilot_float(s: i128) -> f64 {
    s as f64 / PILOT_SCALE
}

impl PilotStats {
    /// No samples.
    pub const ZERO: PilotStats = PilotStats {
        n: 0,
        rays: 0,
        w: 0,
        wy: 0,
        w2: 0,
        w2y: 0,
        w2y2: 0,
        y: 0,
        y2: 0,
    };

    /// Adds a sample: radiance `l` with filter weight `w`, which traced
    /// `rays` rays. A sample the film drops (`w·l` or `w` not finite) is
    /// ignored here too, its rays included.
    #[inline]
    pub fn add(&mut self, l: Vec3, w: f32, rays: u32) {
        if !((l * w).is_finite() && w.is_finite()) {
            return;
        }
        let max = super::film::MAX_SAMPLE_VALUE;
        let l = l.clamp(Vec3::splat(-max), Vec3::splat(max));
        let y = 0.2126 * l.x as f64 + 0.7152 * l.y as f64 + 0.0722 * l.z as f64;
        let w = w.clamp(-max, max) as f64;
        self.n = self.n.saturating_add(1);
        self.rays = self.rays.saturating_add(rays as u64);
        // Signed sums wrap (exact in any order, see the type); the others
        // saturate.
        self.w = self.w.wrapping_add(pilot_fixed(w));
        self.wy = self.wy.wrapping_add(pilot_fixed(w * y));
        self.w2 = self.w2.saturating_add(pilot_fixed(w * w));
        self.w2y = self.w2y.wrapping_add(pilot_fixed(w * w * y));
        self.w2y2 = self.w2y2.saturating_add(pilot_fixed(w * w * y * y));
        self.y = self.y.wrapping_add(pilot_fixed(y));
        self.y2 = self.y2.saturating_add(pilot_fixed(y * y));
    }

    /// Adds another's sums: the statistics of both sets of samples, the
    /// same whatever the order or grouping of the merges.
    #[inline]
    pub fn merge(&mut self, o: &PilotStats) {
        self.n = self.n.saturating_add(o.n);
        self.rays = self.rays.saturating_add(o.rays);
        self.w = self.w.wrapping_add(o.w);
        self.wy = self.wy.wrapping_add(o.wy);
        self.w2 = self.w2.saturating_add(o.w2);
        self.w2y = self.w2y.wrapping_add(o.w2y);
        self.w2y2 = self.w2y2.saturating_add(o.w2y2);
        self.y = self.y.wrapping_add(o.y);
        self.y2 = self.y2.saturating_add(o.y2);
    }

    /// Finite samples added.
    #[inline]
    #[must_use]
    pub fn samples(&self) -> u32 {
        self.n
    }

    /// The value `R` and one sample's standard deviation `σ` (see the
    /// type); `None` with fewer than two samples.
    #[inline]
    #[must_use]
    pub fn value_and_deviation(&self) -> Option<(f64, f64)> {
        if self.n < 2 {
            return None;
        }
        let n = self.n as f64;
        let w = pilot_float(self.w);
        Some(if libm::fabs(w) >= super::film::FALLBACK_SHARE * n {
            let r = pilot_float(self.wy) / w;
            let (w2, w2y, w2y2) = (
                pilot_float(self.w2),
                pilot_float(self.w2y),
                pilot_float(self.w2y2),
            );
            let s = (w2y2 - 2.0 * r * w2y + r * r * w2).max(0.0);
            (r, n * crate::float::sqrt(s / (n - 1.0)) / libm::fabs(w))
        } else {
            // The box mean of y, as the film's fallback.
            let (y, y2) = (pilot_float(self.y), pilot_float(self.y2));
            let m = y / n;
            let var = ((y2 - m * y) / (n - 1.0)).max(0.0);
            (m, crate::float::sqrt(var))
        })
    }

    /// The samples a pixel with these statistics asks for at `threshold`:
    /// `σ / (N · threshold · √c)`, with `N = max(√|R|, ERROR_FLOOR)`.
    /// Infinite with fewer than two samples; 0 without variance.
    ///
    /// Why this form: for a budget of rays, the squared error summed over
    /// pixels is least when pixel `i` takes samples in proportion to
    /// `σᵢ / √cᵢ` (minimise `Σ σᵢ²/nᵢ` subject to `Σ cᵢ nᵢ = C`);
    /// `threshold` sets the proportion. Dividing by `√R` measures the
    /// error as a gamma-2 display shows it (`d√Y = dY / 2√Y`), so one
    /// threshold serves dim and bright scenes; Cycles' convergence test
    /// normalises the same way below 1. (Measured: Cycles' switch to `R`
    /// above 1, and no normalisation, did no better on `caustics`.)
    ///
    /// ```
    /// use glam::Vec3;
    /// use strata::render::PilotStats;
    /// let mut h = PilotStats::ZERO;
    /// for v in [0.0f32, 2.0] {
    ///     h.add(Vec3::splat(v), 1.0, 4); // mean 1, σ √2, 4 rays a sample
    /// }
    /// let want = 2f64.sqrt() / (0.5 * 2.0);
    /// assert!((h.samples_wanted(0.5) - want).abs() < 1e-12);
    /// ```
    #[inline]
    #[must_use]
    pub fn samples_wanted(&self, threshold: f32) -> f64 {
        let Some((r, sigma)) = self.value_and_deviation() else {
            return f64::INFINITY;
        };
        let r = libm::fabs(r);
        let norm = crate::float::sqrt(r).max(ERROR_FLOOR);
        let c = (self.rays as f64 / self.n as f64).max(1.0);
        sigma / (norm * threshold as f64 * crate::float::sqrt(c))
    }
}

/// Renders every pixel of `tile` adaptively and writes it to `film`
/// (row-major over the tile; what was there is replaced): each pixel holds
/// its blended value (its `weight` is `2²⁴` times its kept samples, not a
/// filter-weight sum) and its sample count as `samples + dropped`, as
/// [`Adaptive`] describes: the pilot's two blocks, then the rest the
/// pilot asks for, joined by [`PixelSum::blend`] with weights that never
/// depend on the samples they weigh. A pixel depends on its own samples
/// alone, so tiles, threads and windows do not change it.
///
/// `sampler` is the prototype; its pattern must hold every index a pixel
/// may take (`samples_per_pixel() ≥ adaptive.max()`, else
/// [`RenderError::SamplerTooSmall`]), and each block should spread over
/// the pixel: [`UniformGrid`](crate::UniformGrid) fills its grid in
/// raster order, so its blocks cover a few rows each and adaptive renders
/// with it are biased.
///
/// ```
/// use glam::{UVec2, Vec3};
/// use strata::render::*;
/// use strata::trace::{Sphere, SphereChunk8};
/// use strata::Independent;
/// // A diffuse sphere on a diffuse ground under a flat white sky.
/// let spheres = [
///     Sphere::new(Vec3::new(-1.0, 0.0, 0.0), 1.0),
///     Sphere::new(Vec3::new(0.0, -101.0, 0.0), 100.0),
/// ];
/// let materials = [Material::Lambertian { albedo: Texture::Solid(Vec3::splat(0.5)) }];
/// const SIZE: SceneStorageSize = SceneStorageSize::for_spheres(2, false);
/// let (mut chunks, mut lights) = ([SphereChunk8::EMPTY; SIZE.chunks], [0u32; SIZE.lights]);
/// let storage = SceneStorage {
///     chunks: &mut chunks, lights: &mut lights,
///     bvh_nodes: &mut [], bvh_lanes: &mut [], bvh_ids: &mut [],
/// };
/// let sky = Background::Flat(Vec3::ONE);
/// let scene = Scene::build(&spheres, &materials, &[0, 0], sky, storage).unwrap();
/// let desc = CameraDesc {
///     look_from: Vec3::new(0.0, 0.0, 5.0), look_at: Vec3::ZERO, up: Vec3::Y,
///     vfov_deg: 40.0, defocus_angle_deg: 0.0, focus_dist: 5.0,
/// };
/// let camera = Camera::new(&desc, 8, 4).unwrap();
/// let settings = RenderSettings { max_depth: 8, direct_lighting: true, filter: PixelFilter::BOX,
///     texture_filter: TextureFilter::None, integrator: Integrator::Scalar };
/// let adaptive = Adaptive::new(8, 64, 0.002).unwrap();
/// let tile = Tile { x0: 0, y0: 0, width: 8, height: 4 };
/// let mut film = [PixelSum::ZERO; 32];
/// let sampler = Independent::new(64, 1).unwrap();
/// render_tile_adaptive(&scene, &camera, &sampler, &settings, tile, adaptive, &mut film).unwrap();
/// let taken = |x: usize, y: usize| film[y * 8 + x].samples;
/// assert!(taken(2, 2) > 8); // on the sphere, lit by the sky and the ground
/// assert_eq!(taken(7, 0), 8); // the flat sky: no variance, the pilot only
/// ```
#[inline]
pub fn render_tile_adaptive<S: Sampler + Clone>(
    scene: &Scene<'_>,
    camera: &Camera,
    sampler: &S,
    settings: &RenderSettings,
    tile: Tile,
    adaptive: Adaptive,
    film: &mut [PixelSum],
) -> Result<TileStats, RenderError> {
    check_tile(camera, settings, tile, film.len())?;
    if sampler.samples_per_pixel() < adaptive.max() {
        return Err(RenderError::SamplerTooSmall {
            spp: sampler.samples_per_pixel(),
            max: adaptive.max(),
        });
    }
    Ok(if unit_weights(settings) {
        render_tile_adaptive_adding::<S, true>(
            scene, camera, sampler, settings, tile, adaptive, film,
        )
    } else {
        render_tile_adaptive_adding::<S, false>(
            scene, camera, sampler, settings, tile, adaptive, film,
        )
    })
}

/// [`render_tile_adaptive`] after its checks; `UNIT`: every weight is 1.
#[inline]
fn render_tile_adaptive_adding<S: Sampler + Clone, const UNIT: bool>(
    scene: &Scene<'_>,
    camera: &Camera,
    sampler: &S,
    settings: &RenderSettings,
    tile: Tile,
    adaptive: Adaptive,
    film: &mut [PixelSum],
) -> TileStats {
    let b = adaptive.block();
    let add = |sum: &mut PixelSum, v: Vec3, w: f32| {
        if UNIT {
            sum.add_unit(v, w);
        } else {
            sum.add_weighted(v, w);
        }
    };
    for_each_group(scene, camera, sampler, settings, tile, |group, at, n| {
        let film = &mut film[at..at + n];
        // Each lane's pilot halves and rest, and the halves' statistics.
        let mut parts = [[PixelSum::ZERO; 3]; 8];
        let mut pilots = [[PilotStats::ZERO; 2]; 8];
        let mut rests = [0u32; 8];
        let mut weights = [[0.0f64; 3]; 8];
        // One trace site for the pilot and the rest (two would inline the
        // path tracer twice, at a measured ~6 % per sample): the pilot's
        // two blocks, then the rest in index order, where the lanes still
        // sampling trace each index together so their camera rays stay one
        // packet.
        let mut ids = [0usize, 1, 2, 3, 4, 5, 6, 7];
        let mut m = n;
        let mut end = 2 * b;
        let mut index = 0;
        while index < end {
            let h = if index < 2 * b {
                (index / b) as usize
            } else {
                let mut kept = 0;
                for k in 0..m {
                    if index - 2 * b < rests[ids[k]] {
                        ids[kept] = ids[k];
                        kept += 1;
                    }
                }
                m = kept;
                2
            };
            group.trace(&ids[..m], index, |l, v, w, rays, _| {
                add(&mut parts[l][h], v, w);
                if h < 2 {
                    // A literal 1 lets the box's instance fold the weight
                    // products (the same values: w = 1 exactly).
                    pilots[l][h].add(v, if UNIT { 1.0 } else { w }, rays);
                }
            });
            index += 1;
            if index == 2 * b {
                for l in 0..n {
                    let [a, bh] = pilots[l];
                    let mut both = a;
                    both.merge(&bh);
                    rests[l] = adaptive.rest_for(&both);
                    let [ca, cb] =
                        adaptive.pilot_weights(adaptive.rest_for(&a), adaptive.rest_for(&bh));
                    // A pilot half with no kept sample gives its weight to
                    // the rest, whose weight then still depends on the
                    // pilot only.
                    let ca = if parts[l][0].samples == 0 { 0.0 } else { ca };
                    let cb = if parts[l][1].samples == 0 { 0.0 } else { cb };
                    weights[l] = [ca, cb, 1.0 - ca - cb];
                }
                end += rests[..n].iter().max().copied().unwrap_or(0);
            }
        }
        for l in 0..n {
            let blended = PixelSum::blend(&[
                (parts[l][0], weights[l][0]),
                (parts[l][1], weights[l][1]),
                (parts[l][2], weights[l][2]),
            ]);
            // Written, not added: a blend's `weight` is 2²⁴·n, not a
            // filter-weight sum, so it does not merge with one.
            film[l] = blended;
        }
    })
}

#[cfg(test)]
mod tests {
    use super::*;

    fn stats(values: &[f32], rays: u32) -> PilotStats {
        let mut s = PilotStats::ZERO;
        for &v in values {
            s.add(Vec3::splat(v), 1.0, rays);
        }
        s
    }

    /// Any order and any grouping of merges give the same statistics; the
    /// samples are chosen so that plain `f64` sums do depend on the order
    /// (the control), so the test would catch a return to them.
    #[test]
    fn pilot_sums_do_not_depend_on_order() {
        use rand_core::Rng;
        let mut rng = crate::rng::Pcg32::new(7, crate::rng::STREAM);
        let mut f = move || crate::rng::next_f32(&mut rng);
        let samples: std::vec::Vec<(Vec3, f32, u32)> = (0..257)
            .map(|k| {
                let scale = [1e-6f32, 1.0, 300.0, 7e4][k % 4];
                let l = Vec3::new(f(), f(), f()) * scale;
                let w = f() * 1.4 - 0.2;
                (l, w, 1 + k as u32 % 5)
            })
            .collect();
        let add_all = |order: &[usize]| {
            let mut s = PilotStats::ZERO;
            for &i in order {
                let (l, w, r) = samples[i];
                s.add(l, w, r);
            }
            s
        };
        let forward: std::vec::Vec<usize> = (0..samples.len()).collect();
        let want = add_all(&forward);
        let mut differs = false;
        for round in 0..20u64 {
            let mut order = forward.clone();
            let mut r = crate::rng::Pcg32::new(round, crate::rng::STREAM);
            for i in (1..order.len()).rev() {
                order.swap(i, (r.next_u32() as usize) % (i + 1));
            }
            assert_eq!(add_all(&order), want);
            // Merged from three parts, last first.
            let (a, b) = (order.len() / 3, 2 * order.len() / 3);
            let mut merged = add_all(&order[b..]);
            merged.merge(&add_all(&order[..a]));
            merged.merge(&add_all(&order[a..b]));
            assert_eq!(merged, want);
            // The control: f64 sums of w²y² in these orders.
            let plain = |o: &[usize]| {
                o.iter().fold(0.0f64, |acc, &i| {
                    let (l, w, _) = samples[i];
                    let y = 0.2126 * l.x as f64 + 0.7152 * l.y as f64 + 0.0722 * l.z as f64;
                    acc + (w as f64 * w as f64 * y * y)
                })
            };
            differs |= plain(&order) != plain(&forward);
        }
        assert!(differs, "the samples do not exercise rounding order");
        assert_eq!(want.samples(), 257);
    }

    #[test]
    fn settings_are_checked() {
        for min in [0, 4, 6, 10] {
            assert_eq!(Adaptive::new(min, 64, 0.1), Err(AdaptiveError::Min));
        }
        assert_eq!(Adaptive::new(8, 4, 0.1), Err(AdaptiveError::Max));
        for t in [0.0, -1.0, f32::INFINITY, f32::NAN] {
            assert_eq!(Adaptive::new(8, 8, t), Err(AdaptiveError::Threshold));
        }
        let d = Adaptive::new(
            Adaptive::DEFAULT_MIN,
            Adaptive::DEFAULT_MAX,
            Adaptive::DEFAULT_THRESHOLD,
        )
        .unwrap();
        assert_eq!(d.block(), 64);
    }

    #[test]
    fn rests_stay_in_range_and_every_count_they_give_is_possible() {
        for (min, max) in [(8, 8), (8, 9), (8, 24), (16, 1000), (128, 1024)] {
            let a = Adaptive::new(min, max, 0.01).unwrap();
            let range = a.rest_range();
            assert!(2 * a.block() + range.end() <= max, "{min} {max}");
            assert!(range.end().is_multiple_of(a.block()));
            let cases = [
                PilotStats::ZERO,                  // no samples: ∞
                stats(&[0.5], 1),                  // one sample: ∞
                stats(&[0.5, 0.5, 0.5], 3),        // no variance: 0
                stats(&[0.0, 1.0, 0.0, 1.0], 2),   // noisy
                stats(&[0.0, 3e38, 0.0, 3e38], 2), // the largest values
                stats(&[1e-30, 2e-30], 9),         // below the floor
            ];
            for c in &cases {
                let r = a.rest_for(c);
                assert!(range.contains(&r), "{min} {max}: {r} for {c:?}");
                assert!(a.can_take(2 * a.block() + r));
            }
            assert_eq!(a.rest_for(&PilotStats::ZERO), *range.end());
            assert_eq!(a.rest_for(&cases[2]), *range.start());
            assert_eq!(a.rest_for(&cases[4]), *range.end());
            assert!(!a.can_take(min - 1) && !a.can_take(max + 1));
            assert!(!a.can_take(min + 1), "{min}: not a whole block");
        }
    }

    #[test]
    fn a_smaller_threshold_asks_for_more_and_costlier_samples_for_fewer() {
        let noisy = stats(&[0.1, 0.9, 0.3, 0.6, 0.0, 1.0], 2);
        let costly = stats(&[0.1, 0.9, 0.3, 0.6, 0.0, 1.0], 8);
        let (a, b) = (noisy.samples_wanted(0.01), noisy.samples_wanted(0.001));
        assert!((b / a - 10.0).abs() < 1e-5, "{a} {b}"); // f32 thresholds
        // Four times the rays: half the samples (σ/√c).
        assert!((costly.samples_wanted(0.01) * 2.0 - a).abs() < 1e-9);
        let (lo, hi) = (
            Adaptive::new(16, 4096, 0.01).unwrap(),
            Adaptive::new(16, 4096, 0.001).unwrap(),
        );
        assert!(hi.rest_for(&noisy) > lo.rest_for(&noisy));
    }

    #[test]
    fn pilot_weights_are_the_fair_share_where_the_halves_agree() {
        let a = Adaptive::new(16, 1024, 0.01).unwrap();
        for rest in [8, 40, 1008] {
            let [ca, cb] = a.pilot_weights(rest, rest);
            let share = 4.0 / (8.0 + rest as f64);
            assert!((ca - share).abs() < 1e-15 && (cb - share).abs() < 1e-15);
        }
        // Each half's weight comes from the other half's rest.
        let [ca, cb] = a.pilot_weights(1008, 8);
        assert_eq!((ca, cb), (4.0 / 16.0, 4.0 / 1016.0));
        assert!(ca + cb < 1.0);
    }
}
