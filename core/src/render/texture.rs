//! Textures: a solid colour, the course's 3-D checker, and an image read
//! from a borrowed slice of linear RGB texels.

use glam::{Vec2, Vec3};

use crate::lanes::{Lanes, V3, set_lanes};
use crate::trig;

/// An image texture over borrowed texels: `width × height` linear RGB
/// values, row 0 at the top. Lookups are nearest-texel, with `(u, v)`
/// clamped to `[0, 1]` and `v` flipped as in *Ray Tracing in One Weekend*
/// (`v = 1` is the top row), so `u = 1` reads the last column rather than
/// past it (COURSE.md D16). The caller decodes 8-bit sRGB files to linear.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct ImageTexture<'a> {
    width: u32,
    height: u32,
    texels: &'a [Vec3],
}

impl<'a> ImageTexture<'a> {
    /// A texture over `texels` (`width × height` of them, row-major);
    /// `None` if a side is 0 or the slice has another length.
    ///
    /// ```
    /// use glam::{Vec2, Vec3};
    /// use strata::render::{ImageTexture, Texture};
    /// // 2 × 1: red on the left, blue on the right.
    /// let texels = [Vec3::X, Vec3::Z];
    /// let t = Texture::Image(ImageTexture::new(2, 1, &texels).unwrap());
    /// assert_eq!(t.value(Vec2::new(0.1, 0.5), Vec3::ZERO), Vec3::X);
    /// assert_eq!(t.value(Vec2::new(1.0, 0.5), Vec3::ZERO), Vec3::Z);
    /// assert_eq!(t.value(Vec2::NAN, Vec3::ZERO), Vec3::X);
    /// ```
    #[inline]
    #[must_use]
    pub fn new(width: u32, height: u32, texels: &'a [Vec3]) -> Option<Self> {
        let n = (width as usize).checked_mul(height as usize)?;
        (width > 0 && height > 0 && texels.len() == n).then_some(Self {
            width,
            height,
            texels,
        })
    }

    /// The texel nearest to `uv` (see the type docs).
    #[inline]
    #[must_use]
    pub fn lookup(&self, uv: Vec2) -> Vec3 {
        // A NaN stays NaN through clamp and casts to index 0: a NaN uv
        // reads the top-left texel.
        let u = uv.x.clamp(0.0, 1.0);
        let v = 1.0 - uv.y.clamp(0.0, 1.0);
        let i = ((u * self.width as f32) as u32).min(self.width - 1);
        let j = ((v * self.height as f32) as u32).min(self.height - 1);
        self.texels[(j * self.width + i) as usize]
    }
}

/// How textures are filtered over a camera ray's footprint.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub enum TextureFilter {
    /// Point sampling: the texture at the hit point (the course's).
    #[default]
    None,
    /// The checker's closed-form average over a box with the footprint's
    /// extent (see [`Texture::filtered`]); other textures point-sampled.
    Box,
}

/// `Q(t) = ∫₀ᵗ (−1)^⌊u⌋ du`: a triangle wave between 0 and 1.
#[inline]
fn square_wave_integral(t: f64) -> f64 {
    let k = libm::floor(t);
    let f = t - k;
    if libm::floor(k * 0.5) * 2.0 == k {
        f
    } else {
        1.0 - f
    }
}

/// The average of `(−1)^⌊u⌋` over `[t − h, t + h]`, in cells; `None` when
/// `h` is too small to average over (the caller point-samples).
#[inline]
fn square_wave_average(t: f64, h: f64) -> Option<f64> {
    if h < 1e-6 || h < 1e-9 * t.abs() {
        None
    } else if h < 1e9 && t.is_finite() {
        let avg = (square_wave_integral(t + h) - square_wave_integral(t - h)) / (2.0 * h);
        Some(avg.clamp(-1.0, 1.0))
    } else {
        // So wide (or undefined) that the cells cancel.
        Some(0.0)
    }
}

/// The lanes where `⌊x/s⌋ + ⌊y/s⌋ + ⌊z/s⌋` is odd, as [`Texture::value`]
/// finds it with `floor_i64` (saturating, NaN as 0), without 64-bit lanes:
/// the parity of `⌊q⌋` is that of `trunc(q)` flipped where truncation
/// rounded up; every `f32` with `|q| ≥ 2²⁴` is an even integer, except that
/// `q ≥ 2⁶³` saturates to `i64::MAX`, which is odd.
#[inline(always)]
fn checker_odd_lanes<L: Lanes>(p: V3<L>, scale: f32) -> L::Mask {
    let s = L::splat(scale);
    let odd = |x: L| {
        let q = x / s;
        let t = q.to_int();
        let up = L::select_int(L::from_int(t).gt(q), L::splat_int(1), L::splat_int(0));
        let small = L::int_eq((t ^ up) & L::splat_int(1), L::splat_int(1));
        let exact = L::and(q.abs().lt(L::splat(16_777_216.0)), small);
        L::or(exact, q.ge(L::splat(9_223_372_036_854_775_808.0)))
    };
    let xor = |a: L::Mask, b: L::Mask| L::or(L::and(a, L::not(b)), L::and(L::not(a), b));
    xor(xor(odd(p.x), odd(p.y)), odd(p.z))
}

/// A colour as a function of the surface point.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum Texture<'a> {
    /// One colour everywhere.
    Solid(Vec3),
    /// The course's solid 3-D checker: the parity of `⌊x/s⌋ + ⌊y/s⌋ +
    /// ⌊z/s⌋` at the world-space point picks `even` or `odd`. On a curved
    /// surface the `y` term makes the course's rings and seams; keep it 3-D
    /// to match the course.
    Checker {
        /// Cell size `s`, `> 0`.
        scale: f32,
        /// Colour where the sum is even.
        even: Vec3,
        /// Colour where the sum is odd.
        odd: Vec3,
    },
    /// An image mapped by the sphere's `(u, v)`.
    Image(ImageTexture<'a>),
}

impl Texture<'_> {
    /// The colour at surface coordinates `uv` and world point `p`.
    ///
    /// ```
    /// use glam::{Vec2, Vec3};
    /// use strata::render::Texture;
    /// let c = Texture::Checker { scale: 1.0, even: Vec3::ZERO, odd: Vec3::ONE };
    /// // Negative cells alternate too (floor, not truncation).
    /// assert_eq!(c.value(Vec2::ZERO, Vec3::new(0.5, 0.5, 0.5)), Vec3::ZERO);
    /// assert_eq!(c.value(Vec2::ZERO, Vec3::new(-0.5, 0.5, 0.5)), Vec3::ONE);
    /// assert_eq!(c.value(Vec2::ZERO, Vec3::new(-1.5, 0.5, 0.5)), Vec3::ZERO);
    /// ```
    #[inline]
    #[must_use]
    pub fn value(&self, uv: Vec2, p: Vec3) -> Vec3 {
        match self {
            Texture::Solid(c) => *c,
            Texture::Checker { scale, even, odd } => {
                let cell = |x: f32| crate::float::floor_i64(x / scale);
                // Saturating casts keep huge or NaN points from panicking.
                let sum = cell(p.x).wrapping_add(cell(p.y)).wrapping_add(cell(p.z));
                if sum & 1 == 0 { *even } else { *odd }
            }
            Texture::Image(img) => img.lookup(uv),
        }
    }

    /// The texture averaged over the axis-aligned box of half-widths
    /// `half_width` (world units) around `p`: in closed form for the
    /// checker, the value at the point for the others.
    ///
    /// A point-sampled checker aliases: far away, a pixel covers many
    /// cells and one sample picks one of them. The checker is `even·(1 +
    /// P)/2 + odd·(1 − P)/2` with `P = q(x/s)·q(y/s)·q(z/s)` and `q(t) =
    /// (−1)^⌊t⌋`, a square wave; over a box the product averages axis by
    /// axis, and the average of `q` over `[t − h, t + h]` is `(Q(t + h) −
    /// Q(t − h)) / 2h` with `Q(t) = ∫₀ᵗ q`, a triangle wave (`Q = f` in even
    /// cells, `1 − f` in odd ones, `f` the fraction of `t`), clamped to
    /// `[−1, 1]` against rounding. The integrator supplies the box from the
    /// camera's ray differentials ([`TextureFilter::Box`]).
    ///
    /// An axis narrower than 10⁻⁶ cells, or than 10⁻⁹ of the point's cell
    /// coordinate (where `t ± h` would round), is point-sampled, so a
    /// zero box gives [`Texture::value`] exactly; an infinite or NaN
    /// width averages the cells away, giving `(even + odd) / 2`.
    ///
    /// ```
    /// use glam::{Vec2, Vec3};
    /// use strata::render::Texture;
    /// let c = Texture::Checker { scale: 1.0, even: Vec3::ZERO, odd: Vec3::ONE };
    /// let p = Vec3::new(0.5, 0.5, 0.5);
    /// assert_eq!(c.filtered(Vec2::ZERO, p, Vec3::ZERO), c.value(Vec2::ZERO, p));
    /// // Half a cell either side of a boundary in x: half even, half odd.
    /// let edge = c.filtered(Vec2::ZERO, Vec3::new(1.0, 0.5, 0.5), Vec3::new(0.5, 0.0, 0.0));
    /// assert!((edge - Vec3::splat(0.5)).abs().max_element() < 1e-6);
    /// // A box of whole cells averages to the mean colour.
    /// let far = c.filtered(Vec2::ZERO, p, Vec3::new(2.0, 0.0, 3.0));
    /// assert!((far - Vec3::splat(0.5)).abs().max_element() < 1e-6);
    /// ```
    #[inline(always)]
    #[must_use]
    pub fn filtered(&self, uv: Vec2, p: Vec3, half_width: Vec3) -> Vec3 {
        self.filtered_lanes((uv.x, uv.y), V3::from(p), V3::from(half_width), 1)
            .into()
    }

    /// [`Texture::filtered`] over lanes, for the lanes in `wanted` (bit
    /// `k`: lane `k`; ignored for one lane, which always computes): a
    /// solid colour (the common case, without a call) in every lane; a
    /// checker point-sampled in every lane at once, and averaged over its
    /// box (in `f64`) lane by lane in the wanted lanes whose box is not
    /// zero; an image's texels fetched lane by lane in the wanted lanes,
    /// the others 0.
    #[inline(always)]
    pub(crate) fn filtered_lanes<L: Lanes>(
        &self,
        uv: (L, L),
        p: V3<L>,
        half_width: V3<L>,
        wanted: u8,
    ) -> V3<L> {
        if let Texture::Solid(c) = self {
            return V3::splat(*c);
        }
        let at = |k: usize| {
            let uv = Vec2::new(uv.0.lane(k), uv.1.lane(k));
            self.filtered_varying(uv, p.lane(k), half_width.lane(k))
        };
        if L::WIDTH == 1 {
            return V3::from_fn(at);
        }
        if let Texture::Checker { scale, even, odd } = self {
            // Point-sampled in every lane at once; a lane with a box to
            // average over is filtered alone (only at camera hits, and
            // only with `TextureFilter::Box`).
            let point = checker_odd_lanes(p, *scale);
            let mut out = V3::select(point, V3::splat(*odd), V3::splat(*even));
            let mut boxed = set_lanes(u32::from(wanted))
                .filter(|&k| half_width.lane(k) != Vec3::ZERO)
                .peekable();
            if boxed.peek().is_some() {
                let mut lanes: [Vec3; 8] = core::array::from_fn(|k| out.lane(k));
                for k in boxed {
                    lanes[k] = at(k);
                }
                out = V3::from_fn(|k| lanes[k]);
            }
            return out;
        }
        let mut out = [Vec3::ZERO; 8];
        for k in set_lanes(u32::from(wanted)) {
            out[k] = at(k);
        }
        V3::from_fn(|k| out[k])
    }

    /// [`Texture::filtered`] for the textures that vary.
    #[inline(never)]
    fn filtered_varying(&self, uv: Vec2, p: Vec3, half_width: Vec3) -> Vec3 {
        let Texture::Checker { scale, even, odd } = self else {
            return self.value(uv, p);
        };
        if half_width == Vec3::ZERO {
            return self.value(uv, p);
        }
        let s = *scale as f64;
        let axis = |x: f32, h: f32| {
            square_wave_average(x as f64 / s, h as f64 / s).unwrap_or_else(|| {
                // The point value, by the same cell rule as `value`.
                let k = crate::float::floor_i64(x / scale);
                if k & 1 == 0 { 1.0 } else { -1.0 }
            })
        };
        let parity = axis(p.x, half_width.x) * axis(p.y, half_width.y) * axis(p.z, half_width.z);
        let a = ((1.0 + parity) * 0.5) as f32;
        *even * a + *odd * (1.0 - a)
    }

    /// Whether [`Texture::value`] reads `uv` (only image textures do), so
    /// a renderer can skip computing it.
    ///
    /// ```
    /// use glam::Vec3;
    /// use strata::render::Texture;
    /// assert!(!Texture::Solid(Vec3::ONE).uses_uv());
    /// ```
    #[inline]
    #[must_use]
    pub fn uses_uv(&self) -> bool {
        matches!(self, Texture::Image(_))
    }
}

/// The course's sphere `(u, v)` of an outward unit normal `n`: `θ =
/// acos(−n_y)`, `φ = atan2(−n_z, n_x) + π`, `u = φ / 2π`, `v = θ / π`, with
/// `n_y` clamped to `[−1, 1]` so a pole never takes `acos` out of its
/// domain (COURSE.md D14).
///
/// ```
/// use glam::{Vec2, Vec3};
/// use strata::render::sphere_uv;
/// assert_eq!(sphere_uv(Vec3::new(0.0, -1.0, 0.0)).y, 0.0);
/// // A pole whose n_y rounded past 1 still maps (acos would give NaN).
/// assert!((sphere_uv(Vec3::new(0.0, 1.0000001, 0.0)).y - 1.0).abs() < 1e-6);
/// assert!((sphere_uv(Vec3::X) - Vec2::new(0.5, 0.5)).length() < 1e-6);
/// // u runs from −x through +z (u = 1/4), +x (1/2), −z (3/4).
/// assert!((sphere_uv(Vec3::Z).x - 0.25).abs() < 1e-6);
/// assert!((sphere_uv(-Vec3::Z).x - 0.75).abs() < 1e-6);
/// ```
#[inline]
#[must_use]
pub fn sphere_uv(n: Vec3) -> Vec2 {
    let (u, v) = sphere_uv_lanes(V3::<f32>::splat(n));
    Vec2::new(u, v)
}

/// [`sphere_uv`] over lanes, with the portable `acos` and `atan2` of
/// `crate::trig` (the same bits for one lane and for eight).
#[inline]
pub(crate) fn sphere_uv_lanes<L: Lanes>(n: V3<L>) -> (L, L) {
    use core::f32::consts::{FRAC_1_PI, PI};
    let theta = trig::acos((-n.y).clamp_to(-1.0, 1.0));
    let phi = trig::atan2(-n.z, n.x) + L::splat(PI);
    (phi * L::splat(0.5 * FRAC_1_PI), theta * L::splat(FRAC_1_PI))
}

#[cfg(test)]
mod tests {
    use glam::{Vec2, Vec3};

    use super::{ImageTexture, Texture};
    use crate::lanes::{Lanes, V3, f32x8};

    /// Over lanes, a varying texture filters exactly the wanted lanes (as
    /// one lane would); the others are 0 for an image and the point value
    /// for a checker (point-sampled in every lane at once, a box averaged
    /// in the wanted lanes only); a solid one fills all.
    #[test]
    fn a_texture_over_lanes_filters_the_wanted_lanes_only() {
        let checker = Texture::Checker {
            scale: 0.3,
            even: Vec3::new(0.9, 0.8, 0.7),
            odd: Vec3::new(0.1, 0.2, 0.3),
        };
        let texels: [Vec3; 6] =
            core::array::from_fn(|i| Vec3::new(i as f32, 0.5, 1.0 / (i + 1) as f32));
        let image = Texture::Image(ImageTexture::new(3, 2, &texels).unwrap());
        let p = |k: usize| Vec3::new(k as f32 * 0.37 - 1.1, 0.2 * k as f32, 0.5 - 0.13 * k as f32);
        let h = |k: usize| {
            Vec3::splat(if k.is_multiple_of(3) {
                0.0
            } else {
                0.05 * k as f32
            })
        };
        let uv = |k: usize| Vec2::new(0.1 * k as f32, 0.9 - 0.1 * k as f32);
        let lanes = |t: &Texture<'_>, wanted: u8| {
            t.filtered_lanes(
                (f32x8::from_fn(|k| uv(k).x), f32x8::from_fn(|k| uv(k).y)),
                V3::from_fn(p),
                V3::from_fn(h),
                wanted,
            )
        };
        for wanted in [0u8, 1, 0b1000_0000, 0b0101_1010, u8::MAX] {
            for (t, others) in [(&checker, "point"), (&image, "zero")] {
                let got = lanes(t, wanted);
                for k in 0..8 {
                    let want = if wanted >> k & 1 == 1 {
                        t.filtered(uv(k), p(k), h(k))
                    } else if others == "point" {
                        t.value(uv(k), p(k))
                    } else {
                        Vec3::ZERO
                    };
                    assert_eq!(got.lane(k), want, "{t:?}, wanted {wanted:#010b}, lane {k}");
                }
            }
        }
        // The box does change some wanted lanes (else the test above
        // could not tell filtering from point sampling).
        assert!((0..8).any(|k| checker.filtered(uv(k), p(k), h(k)) != checker.value(uv(k), p(k))));
        let solid = Texture::Solid(Vec3::new(0.25, 0.5, 0.75));
        let got = lanes(&solid, 0);
        assert!((0..8).all(|k| got.lane(k) == Vec3::new(0.25, 0.5, 0.75)));
    }

    /// The point-sampled checker over lanes picks the colour `value` picks
    /// at every edge of `floor_i64`: fractions, whole numbers, ±2²³, ±2²⁴,
    /// ±2³¹, ±2⁶³ (where `i64` saturates, to an odd `MAX` above and an even
    /// `MIN` below), infinities, NaN, −0 and subnormals, each with its
    /// neighbouring floats, on every axis and with scales that round.
    #[test]
    fn the_checker_over_lanes_picks_the_colours_of_value() {
        let mut qs = std::vec![
            0.0f32,
            -0.0,
            1e-45,
            -1e-45,
            f32::MIN_POSITIVE,
            f32::NAN,
            f32::INFINITY,
            f32::NEG_INFINITY,
            f32::MAX,
            f32::MIN
        ];
        for m in [
            0.5f32,
            1.0,
            1.5,
            2.0,
            3.0,
            8_388_607.5,
            8_388_608.0,
            16_777_216.0,
            2_147_483_648.0,
            9_223_372_036_854_775_808.0,
        ] {
            for x in [m, -m] {
                let b = x.to_bits();
                qs.extend([
                    x,
                    f32::from_bits(b + 1),
                    f32::from_bits(b - 1),
                    f32::from_bits(b + 2),
                ]);
            }
        }
        let zero = V3::splat(Vec3::ZERO);
        let mut cases = 0;
        for scale in [1.0f32, 0.3, 7.0] {
            let c = Texture::Checker {
                scale,
                even: Vec3::ONE,
                odd: Vec3::ZERO,
            };
            for (i, axis) in [0usize, 1, 2].into_iter().enumerate() {
                for chunk in qs.chunks(8) {
                    // The other axes at 0.5 scale: even cells.
                    let at = |k: usize| {
                        let mut v = Vec3::splat(0.5 * scale);
                        v[axis] = chunk[k % chunk.len()] * scale;
                        v
                    };
                    let got = c.filtered_lanes(
                        (f32x8::splat(0.0), f32x8::splat(0.0)),
                        V3::from_fn(at),
                        zero,
                        u8::MAX,
                    );
                    for k in 0..8 {
                        assert_eq!(
                            got.lane(k),
                            c.value(Vec2::ZERO, at(k)),
                            "scale {scale}, axis {i}, {:e}",
                            at(k)[axis]
                        );
                        cases += 1;
                    }
                }
            }
        }
        // Both colours come up, including from saturation at 2⁶³.
        let c = Texture::Checker {
            scale: 1.0,
            even: Vec3::ONE,
            odd: Vec3::ZERO,
        };
        assert_eq!(
            c.value(Vec2::ZERO, Vec3::new(f32::INFINITY, 0.5, 0.5)),
            Vec3::ZERO
        );
        assert_eq!(
            c.value(Vec2::ZERO, Vec3::new(f32::NEG_INFINITY, 0.5, 0.5)),
            Vec3::ONE
        );
        assert!(cases > 800);
    }
}
