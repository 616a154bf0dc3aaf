//! Splatting: a sample of a filter with negative lobes (Mitchell,
//! Lanczos) adds `f·L` and `f` to every pixel its filter reaches, in
//! fixed point ([`Splat`]), so sums stay exact integers that tiles,
//! threads and sample runs add in any order. A tile's film holds the tile
//! and a margin of [`PixelFilter::splat_margin`] pixels a side
//! ([`super::Layout`]).

use super::RenderSettings;
use super::camera::Camera;
use super::film::{MAX_SAMPLE_VALUE, PixelSum};
use super::integrator::TileStats;
use super::scene::Scene;
use super::tile::{RenderError, Tile, check_tile, for_each_group, padded};
use crate::filter::PixelFilter;
use crate::sampler::Sampler;
use core::ops::Range;
use glam::{Vec2, Vec3};

/// The most pixels a splat reaches along an axis: `2m + 1` for the
/// largest margin, that of [`FILTER_MAX_RADIUS`](crate::filter::FILTER_MAX_RADIUS).
pub const SPLAT_SIDE: usize = crate::filter::TAPS;
// The margin of the largest radius is ⌈r + ½⌉ − 1 = r for an integer r.
const _: () = assert!(crate::filter::FILTER_MAX_RADIUS == 8.0);

/// Fixed-point scale of a splat's filter values: `2⁻¹²` per axis, so
/// their product is in the film's units of `2⁻²⁴`.
const SPLAT_FILTER_SCALE: f32 = 4096.0;
/// Fixed-point scale of a splatted radiance: `2⁻¹⁸`.
const SPLAT_RADIANCE_SCALE: f32 = 262_144.0;

/// One splatted sample in fixed point: its radiance (clamped to
/// `±MAX_SAMPLE_VALUE`, in units of `2⁻¹⁸`) and the filter per axis at
/// the centres around its pixel (units of `2⁻¹²`). A target pixel `(dx,
/// dy)` of the `(2m + 1)²` around it (its own at `(m, m)`) gets the
/// weight `Fx·Fy` (units `2⁻²⁴`, the film's) and the sums `Fx·Fy·L`
/// rounded to the film's units, all in integers: each target costs a few
/// integer multiplies instead of four float roundings, and the bits are
/// the same on every CPU and in any order of addition.
///
/// ```
/// use glam::{Vec2, Vec3};
/// use strata::filter::{FilterKind, PixelFilter};
/// use strata::render::{PixelSum, Splat};
/// let mitchell = PixelFilter::new(FilterKind::named("mitchell").unwrap(), 2.0).unwrap();
/// let s = Splat::new(&mitchell, Vec2::splat(0.5), Vec3::splat(0.25)).unwrap();
/// let mut own = PixelSum::ZERO;
/// s.add_to(&mut own, 2, 2, true); // the centre of the 5 × 5 it reaches
/// assert_eq!(own.samples, 1);
/// // f·L is rounded to the film's 2⁻²⁴: within a unit of the radiance.
/// assert!((own.mean() - Vec3::splat(0.25)).abs().max_element() < 1e-6);
/// assert!(Splat::new(&mitchell, Vec2::ZERO, Vec3::NAN).is_none());
/// ```
#[derive(Clone, Copy, Debug)]
pub struct Splat {
    l: [i64; 3],
    /// The radiance in the film's units, for its own pixel's box sum.
    own: [i64; 3],
    /// Every filter value within `±2¹⁴` units (`±4`): no product
    /// overflows, so [`Splat::add_square`] needs no saturating multiplies.
    small: bool,
    fx: [i64; SPLAT_SIDE],
    fy: [i64; SPLAT_SIDE],
}

impl Splat {
    /// The splat of radiance `l` at offset `u` (from the pixel's corner,
    /// in `[0, 1)²`) under `filter`; `None` if `l` is not finite.
    #[inline]
    #[must_use]
    pub fn new(filter: &crate::filter::PixelFilter, u: Vec2, l: Vec3) -> Option<Splat> {
        if !l.is_finite() {
            return None;
        }
        let lc = l.clamp(
            Vec3::splat(-MAX_SAMPLE_VALUE),
            Vec3::splat(MAX_SAMPLE_VALUE),
        );
        // The centre `k` pixels from the sample's own is `u − ½ − k` away.
        let (tx, ty) = (filter.eval_taps(u.x - 0.5), filter.eval_taps(u.y - 0.5));
        let (fx, fy) = (
            fixed_taps(&tx, SPLAT_FILTER_SCALE)
                .unwrap_or_else(|| tx.map(|t| fixed(t, SPLAT_FILTER_SCALE))),
            fixed_taps(&ty, SPLAT_FILTER_SCALE)
                .unwrap_or_else(|| ty.map(|t| fixed(t, SPLAT_FILTER_SCALE))),
        );
        let small = |f: &[i64; SPLAT_SIDE]| f.iter().all(|v| v.unsigned_abs() <= 1 << 14);
        Some(Splat {
            l: lc.to_array().map(|c| fixed(c, SPLAT_RADIANCE_SCALE)),
            own: lc.to_array().map(super::film::to_fixed),
            small: small(&fx) && small(&fy),
            fx,
            fy,
        })
    }

    /// The weight the target `(dx, dy)` gets, in the film's units.
    #[inline]
    #[must_use]
    pub fn weight(&self, dx: usize, dy: usize) -> i64 {
        self.fx[dx].saturating_mul(self.fy[dy])
    }

    /// Adds the splat to target `(dx, dy)`'s accumulator, counting it as
    /// one of that pixel's samples (and its radiance in the pixel's own
    /// sum, [`PixelSum::own`]) if `own`.
    #[inline]
    pub fn add_to(&self, pixel: &mut PixelSum, dx: usize, dy: usize, own: bool) {
        // The own sum does not move with the sums (as saturated).
        pixel.begin_splats();
        self.add_sums(pixel, dx, dy);
        if own {
            pixel.add_splatted_own(self.own);
        }
        pixel.end_splats();
    }

    /// `f·L` and `f` to target `(dx, dy)`'s sums, leaving `own_minus_sum`.
    #[inline]
    fn add_sums(&self, pixel: &mut PixelSum, dx: usize, dy: usize) {
        let f = self.weight(dx, dy);
        if f != 0 {
            for (s, l) in pixel.sum.iter_mut().zip(self.l) {
                // f·L in units of 2⁻⁴², rounded (half up) to 2⁻²⁴. With
                // |L| ≤ 2¹⁶ (2³⁴ units) it fits an i64 while |f| < 32
                // (2²⁹ units), true of every usual filter; beyond, it
                // saturates.
                let v = f.saturating_mul(l).saturating_add(1 << 17) >> 18;
                *s = s.saturating_add(v);
            }
            pixel.weight = pixel.weight.saturating_add(f);
        }
    }

    /// Adds the splat to its `side × side` targets, target `(dx, dy)` at
    /// `film[first + dy·stride + dx]` (none counted as a sample):
    /// [`Splat::add_to`] on each between the film's
    /// [`PixelSum::begin_splats`] and [`PixelSum::end_splats`], which the
    /// caller makes once around all its splats. Where the values are small enough for
    /// no product to overflow (`|Fx·L| ≤ 2⁴⁸`, `|Fx·Fy·L| ≤ 2⁶²`) the
    /// products `Fx·L` are formed once per column and the weight rides
    /// along as a fourth channel of radiance `2¹⁸` (`(Fx·Fy·2¹⁸ + 2¹⁷) >>
    /// 18 = Fx·Fy`): the same sums, four lanes of one multiply, add and
    /// shift per target. `SATURATE = false` adds with plain (wrapping)
    /// adds: the caller's promise that no sum reaches `i64`'s end (see
    /// [`Splat::reach`]), where they give the saturating adds' sums.
    #[inline]
    fn add_square<const SATURATE: bool>(
        &self,
        film: &mut [PixelSum],
        first: usize,
        stride: usize,
        side: usize,
    ) {
        if !self.small {
            for dy in 0..side {
                let row = first + dy * stride;
                for (dx, p) in film[row..row + side].iter_mut().enumerate() {
                    self.add_sums(p, dx, dy);
                }
            }
            return;
        }
        // Columns of zero weight (a radius below the margin's reach, as
        // Lanczos-3's outer column on the far side) are skipped.
        let fx = &self.fx[..side];
        let lo = fx.iter().position(|&f| f != 0).unwrap_or(side);
        let hi = fx.iter().rposition(|&f| f != 0).map_or(lo, |i| i + 1);
        let mut columns = [[0i64; 4]; SPLAT_SIDE];
        for (g, &fx) in columns.iter_mut().zip(&fx[lo..hi]) {
            *g = [fx * self.l[0], fx * self.l[1], fx * self.l[2], fx << 18];
        }
        for (dy, &fy) in self.fy[..side].iter().enumerate() {
            if fy == 0 {
                continue;
            }
            let row = first + dy * stride;
            for (p, g) in film[row + lo..row + hi].iter_mut().zip(&columns) {
                let v: [i64; 4] = core::array::from_fn(|c| (fy * g[c] + (1 << 17)) >> 18);
                let add = |s: i64, v: i64| {
                    if SATURATE {
                        s.saturating_add(v)
                    } else {
                        s.wrapping_add(v)
                    }
                };
                for (s, v) in p.sum.iter_mut().zip(v) {
                    *s = add(*s, v);
                }
                p.weight = add(p.weight, v[3]);
            }
        }
    }

    /// The most this splat changes any one sum of any target, when
    /// `small`: `|(f·L + 2¹⁷) >> 18| ≤ (|f|·|L| >> 18) + 1`, with the
    /// weight's lane as radiance 2¹⁸ (`None` when not `small`).
    #[inline]
    fn reach(&self) -> Option<i64> {
        let most = |f: &[i64; SPLAT_SIDE]| f.iter().fold(0, |m, v| m.max(v.abs()));
        let l = self.l.iter().fold(1 << 18, |m: i64, v| m.max(v.abs()));
        // |f| ≤ 2²⁸ and |L| ≤ 2³⁴ (clamped): the product fits.
        self.small
            .then(|| ((most(&self.fx) * most(&self.fy) * l) >> 18) + 1)
    }
}

/// `x·scale` rounded half away from zero, exactly, as the film's
/// `to_fixed` (saturating beyond `i64`).
#[inline]
fn fixed(x: f32, scale: f32) -> i64 {
    let y = x * scale;
    let t = y as i64;
    let frac = y - t as f32;
    t + (frac >= 0.5) as i64 - (frac <= -0.5) as i64
}

/// `x·scale` rounded half away from zero, as [`fixed`],
/// for every tap at once, or `None` if some `|x·scale|` is not below
/// 2²²: the rounding by the float's own (to even, in `[2²³, 2²⁴)`, where
/// the integer is the bits' low part) corrected at ties, in a loop of
/// plain lane operations that compilers vectorise, where the saturating
/// `as i64` is a branchy scalar conversion per tap.
#[inline]
fn fixed_taps(x: &[f32; SPLAT_SIDE], scale: f32) -> Option<[i64; SPLAT_SIDE]> {
    const BIG: f32 = 8_388_608.0; // 2²³
    let mut out = [0i64; SPLAT_SIDE];
    let mut small = true;
    for (o, &x) in out.iter_mut().zip(x) {
        let y = x * scale;
        let a = y.abs();
        small &= a < 4_194_304.0; // 2²², false for NaN
        let shifted = a + BIG;
        let t = shifted.to_bits() as i32 - BIG.to_bits() as i32;
        // To even gave `t` below a tie `a = t + ½`; away from zero wants
        // one more.
        let t = t + (a - (shifted - BIG) == 0.5) as i32;
        *o = i64::from(if y < 0.0 { -t } else { t });
    }
    small.then_some(out)
}

/// The film a splatted render of `tile` fills: the tile and a margin of
/// [`PixelFilter::splat_margin`](crate::filter::PixelFilter::splat_margin)
/// pixels on every side, `(width + 2m) × (height + 2m)` entries row-major
/// from pixel `(x0 − m, y0 − m)` (which may lie outside the image: such
/// entries are the caller's to drop). `None` if that overflows.
///
/// ```
/// use strata::filter::{FilterKind, PixelFilter};
/// use strata::render::{Tile, splat_film_size};
/// let mitchell = PixelFilter::new(FilterKind::named("mitchell").unwrap(), 2.0).unwrap();
/// let t = Tile { x0: 8, y0: 0, width: 16, height: 4 };
/// assert_eq!(splat_film_size(&mitchell, t), Some((20, 8)));
/// ```
#[inline]
#[must_use]
pub fn splat_film_size(filter: &PixelFilter, tile: Tile) -> Option<(u32, u32)> {
    // For any filter this renderer is given; a render that chooses its
    // renderer by `Layout` splats only filters that splat, and there it
    // is `Layout::film_size`.
    padded(tile, filter.splat_margin())
}

/// Renders samples `samples` of every pixel of `tile` and splats each into
/// the pixels its filter (`settings.filter`) reaches, adding to `film`,
/// the tile and its margin ([`splat_film_size`]): a sample at `x`, with
/// radiance `L`, adds `f(x − c)·L` and `f(x − c)` to every pixel of
/// centre `c` within the filter's radius, in fixed point ([`Splat`]), and
/// counts as a sample of its own pixel only (a sample that is not finite
/// counts as dropped there and adds nothing). Positions are uniform in the
/// pixel (the box's), and the tracing is the box render's. A pixel's value
/// `Σ f·L / Σ f` gathers every sample near it, and where radiance is
/// constant it is that constant whatever the weights' signs, to the
/// fixed point's rounding of each product (exactly for radiance 1, as
/// `horizon`'s sky: each product is then an integer).
///
/// Sums are exact integers, so films of tiles, threads and sample runs
/// add to the same bits in any order; a pixel near a tile's edge gets its
/// value once the neighbouring tiles' margins are added.
#[inline]
pub fn render_tile_splat<S: Sampler + Clone>(
    scene: &Scene<'_>,
    camera: &Camera,
    sampler: &S,
    settings: &RenderSettings,
    tile: Tile,
    samples: Range<u32>,
    film: &mut [PixelSum],
) -> Result<TileStats, RenderError> {
    let filter = settings.filter;
    let (pw, ph) = splat_film_size(&filter, tile).ok_or(RenderError::Tile)?;
    let needed = pw as usize * ph as usize;
    check_tile(camera, settings, tile, tile.area())?;
    if film.len() != needed {
        return Err(RenderError::FilmSize {
            needed,
            provided: film.len(),
        });
    }
    let (m, pw) = (filter.splat_margin() as usize, pw as usize);
    let side = 2 * m + 1;
    debug_assert!(side <= SPLAT_SIDE);
    // Positions come from the box, so the tracing is the box render's.
    let boxed = RenderSettings {
        filter: PixelFilter::BOX,
        ..*settings
    };
    const ALL: [usize; 8] = [0, 1, 2, 3, 4, 5, 6, 7];
    let width = tile.width as usize;
    // Saturating adds are needed only near `i64`'s end: while the film's
    // largest sum plus every splat's largest change (`Splat::reach`)
    // stays within 2⁶², plain adds give the same sums, cheaper.
    let largest = film
        .iter()
        .flat_map(|p| p.sum.iter().chain([&p.weight]))
        .fold(0u64, |m, v| m.max(v.unsigned_abs()));
    let mut headroom = (1i64 << 62) - largest.min(1 << 62) as i64;
    // The splats below move the sums alone.
    for p in film.iter_mut() {
        p.begin_splats();
    }
    let stats = for_each_group(scene, camera, sampler, &boxed, tile, |group, at, n| {
        // The group's first pixel's top-left splat target in the
        // padded film (its own pixel is m further right and down).
        let (gx, gy) = (at % width, at / width);
        for index in samples.clone() {
            group.trace(&ALL[..n], index, |l, v, _, _, u| {
                let own = (gy + m) * pw + gx + l + m;
                let Some(splat) = Splat::new(&filter, u, v) else {
                    // Counted as dropped by its own pixel only.
                    film[own].dropped = film[own].dropped.saturating_add(1);
                    return;
                };
                let first = gy * pw + gx + l;
                match splat.reach() {
                    Some(r) if r <= headroom => {
                        headroom -= r;
                        splat.add_square::<false>(film, first, pw, side);
                    }
                    _ => {
                        // Uncharged, this splat may bring a sum near
                        // i64's end: every later one saturates too.
                        headroom = 0;
                        splat.add_square::<true>(film, first, pw, side);
                    }
                }
                film[own].add_splatted_own(splat.own);
            });
        }
    });
    for p in film.iter_mut() {
        p.end_splats();
    }
    Ok(stats)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn fixed_taps_round_as_fixed_does() {
        // Ties (x·scale = k + ½) both ways, values near the 2²² bound, a
        // NaN and the bound itself (which send every tap the slow way).
        let mut values = [0.0f32; SPLAT_SIDE];
        let mut seen = 0;
        for i in -3000i32..3000 {
            let base = i as f32 * 0.33;
            let ties = [(i as f32 + 0.5) / 4096.0, (i as f32 - 0.5) / 4096.0];
            for (j, x) in [base, -base, ties[0], ties[1], base * 1e-3]
                .into_iter()
                .enumerate()
            {
                values[(i.unsigned_abs() as usize + j) % SPLAT_SIDE] = x;
            }
            let got = fixed_taps(&values, SPLAT_FILTER_SCALE).unwrap();
            assert_eq!(got, values.map(|x| fixed(x, SPLAT_FILTER_SCALE)));
            seen += 1;
        }
        assert_eq!(seen, 6000);
        let edge = 4_194_303.5 / SPLAT_FILTER_SCALE;
        values[3] = edge;
        assert_eq!(
            fixed_taps(&values, SPLAT_FILTER_SCALE).unwrap()[3],
            fixed(edge, SPLAT_FILTER_SCALE)
        );
        values[3] = 4_194_304.0 / SPLAT_FILTER_SCALE;
        assert!(fixed_taps(&values, SPLAT_FILTER_SCALE).is_none());
        values[3] = f32::NAN;
        assert!(fixed_taps(&values, SPLAT_FILTER_SCALE).is_none());
    }

    #[test]
    fn plain_and_saturating_squares_add_the_same_sums_unless_they_overflow() {
        use crate::filter::{FilterKind, PixelFilter};
        let f = PixelFilter::new(FilterKind::Lanczos { tau: 3.0 }, 3.0).unwrap();
        let side = 2 * f.splat_margin() as usize + 1;
        let splat = Splat::new(&f, Vec2::new(0.3, 0.8), Vec3::new(0.5, 2.0, 900.0)).unwrap();
        let reach = splat.reach().unwrap();
        assert_eq!(side, 7);
        let start: [PixelSum; 49] = core::array::from_fn(|i| PixelSum {
            sum: [i as i64 * 1_000_003, -(i as i64), 7],
            weight: 1 << 30,
            ..PixelSum::ZERO
        });
        let (mut plain, mut saturating, mut one_by_one) = (start, start, start);
        // add_square leaves own − sum to its caller, which takes the sums'
        // change off it once.
        let settle = |after: &mut [PixelSum; 49], before: &[PixelSum; 49]| {
            for (a, b) in after.iter_mut().zip(before) {
                for c in 0..3 {
                    let moved = a.sum[c].wrapping_sub(b.sum[c]);
                    a.own_minus_sum[c] = a.own_minus_sum[c].wrapping_sub(moved);
                }
            }
        };
        splat.add_square::<false>(&mut plain, 0, side, side);
        splat.add_square::<true>(&mut saturating, 0, side, side);
        settle(&mut plain, &start);
        settle(&mut saturating, &start);
        for dy in 0..side {
            for dx in 0..side {
                splat.add_to(&mut one_by_one[dy * side + dx], dx, dy, false);
            }
        }
        assert_eq!(plain, saturating);
        assert_eq!(plain, one_by_one);
        // The reach bounds every change.
        for (a, b) in plain.iter().zip(&start) {
            for (x, y) in a
                .sum
                .iter()
                .chain([&a.weight])
                .zip(b.sum.iter().chain([&b.weight]))
            {
                assert!((x - y).abs() <= reach);
            }
        }
        // Near i64's end only the saturating adds are right.
        let full = [PixelSum {
            sum: [i64::MAX; 3],
            weight: i64::MAX,
            ..PixelSum::ZERO
        }; 49];
        let mut saturated = full;
        splat.add_square::<true>(&mut saturated, 0, side, side);
        settle(&mut saturated, &full);
        let mut want = full;
        for dy in 0..side {
            for dx in 0..side {
                splat.add_to(&mut want[dy * side + dx], dx, dy, false);
            }
        }
        assert_eq!(saturated, want);
        assert!(saturated.iter().any(|p| p.sum[2] == i64::MAX));
    }
}
