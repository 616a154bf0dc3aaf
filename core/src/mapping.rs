//! Warps from the unit square to spheres, hemispheres, disks and cones
//! (and from the unit cube to the ball), each as a triad: `sample_X`,
//! `pdf_X`, `invert_X`, in that order.
//!
//! # Conventions
//!
//! - `u` is a uniform sample in `[0, 1)²`; inputs outside it are mapped by
//!   the same formula (no clamping), so they land off the nominal domain.
//! - Directions are unit vectors in a local frame whose `+z` is the pole or
//!   normal; use [`crate::onb::Onb`] to take them to the world.
//! - A pdf takes the sampled value, so `pdf_x(sample_x(u))` always
//!   type-checks. Direction pdfs are per steradian, disk pdfs per unit
//!   area, the ball's per unit volume.
//!   A pdf is `0` outside the support, and `0` for a NaN argument (the χ²
//!   tests rely on this to catch samples landing where the pdf says none
//!   can).
//! - An inverse takes a point of the domain and returns the `u` that maps to
//!   it, in `[0, 1)²`; it is the exact inverse up to rounding.
//! - NaN in `u` gives NaN out of `sample_*`; nothing panics.
//! - Sines and cosines are polynomials in plain `f32` operations after an
//!   exact range reduction (the crate's `trig`), the other transcendental
//!   functions come from `libm`, and no multiply-add is fused, so results
//!   are the same bits on every CPU.
//!
//! # Sources
//!
//! Shirley and Chiu 1997, *A Low Distortion Map Between Disk and Square*
//! (concentric disk); Malley's method (cosine hemisphere by lifting a disk
//! point); Pharr, Jakob and Humphreys, *Physically Based Rendering* 4th ed.,
//! A.5 (sphere, hemisphere, cone, inverses). The course's rejection methods
//! are in [`rejection`], for comparison. [`PiecewiseConstant2D`] is the
//! tabulated density for shapes without a closed form.

use core::f32::consts::{FRAC_1_PI, FRAC_PI_2, FRAC_PI_4, PI, TAU};

use glam::{Vec2, Vec3};

use crate::lanes::{Lanes, V3};
use crate::rng::ONE_MINUS_EPSILON;
use crate::trig::{sin_cos_pi_quarter, sin_cos_turn};

mod piecewise;
pub mod rejection;

pub use piecewise::{PIECEWISE_2D_SIZE, PiecewiseConstant2D};

/// `1 / (4π)`.
const INV_4PI: f32 = FRAC_1_PI / 4.0;
/// `1 / (2π)`.
const INV_2PI: f32 = FRAC_1_PI / 2.0;
/// `|p|²` of the rim of the unit disk and ball, with the rounding of the
/// maps.
const RIM2: f32 = 1.0 + 4.0 * f32::EPSILON;

/// `sqrt(max(x, 0))`: rounding can push `1 - z²` a hair below zero. Unlike
/// `f32::max`, it keeps a NaN a NaN.
#[inline(always)]
fn safe_sqrt<L: Lanes>(x: L) -> L {
    L::select(x.lt(L::splat(0.0)), L::splat(0.0), x).sqrt()
}

/// The azimuth of `(x, y)` as a fraction of a turn, in `[0, 1)`.
#[inline]
fn azimuth_fraction(x: f32, y: f32) -> f32 {
    let mut phi = libm::atan2f(y, x);
    if phi < 0.0 {
        phi += TAU;
    }
    (phi * INV_2PI).clamp(0.0, ONE_MINUS_EPSILON)
}

/// A point at azimuth `2π · u` and height `z` on the unit sphere.
#[inline(always)]
fn spherical<L: Lanes>(z: L, u_phi: L) -> V3<L> {
    let r = safe_sqrt(L::splat(1.0) - z * z);
    let (sin, cos) = sin_cos_turn(u_phi);
    V3::new(r * cos, r * sin, z)
}

// ---------------------------------------------------------------- sphere

/// A direction uniform on the unit sphere: `z = 1 - 2u₀`, azimuth `2π u₁`.
///
/// See also [`pdf_uniform_sphere`], [`invert_uniform_sphere`].
///
/// ```
/// use glam::Vec2;
/// use strata::mapping::*;
/// let w = sample_uniform_sphere(Vec2::new(0.3, 0.8));
/// assert!((w.length() - 1.0).abs() < 1e-6);
/// assert!((invert_uniform_sphere(w) - Vec2::new(0.3, 0.8)).abs().max_element() < 1e-5);
/// ```
#[doc(alias = "square_to_uniform_sphere")]
#[inline]
#[must_use]
pub fn sample_uniform_sphere(u: Vec2) -> Vec3 {
    uniform_sphere(u.x, u.y).into()
}

/// [`sample_uniform_sphere`] over lanes.
#[inline(always)]
pub(crate) fn uniform_sphere<L: Lanes>(u0: L, u1: L) -> V3<L> {
    spherical(L::splat(1.0) - L::splat(2.0) * u0, u1)
}

/// The density of [`sample_uniform_sphere`]: `1 / (4π)` per steradian
/// (`0` for a NaN direction).
#[doc(alias = "square_to_uniform_sphere_pdf")]
#[inline]
#[must_use]
pub fn pdf_uniform_sphere(w: Vec3) -> f32 {
    if w.is_nan() { 0.0 } else { INV_4PI }
}

/// The inverse of [`sample_uniform_sphere`].
#[doc(alias = "uniform_sphere_to_square")]
#[inline]
#[must_use]
pub fn invert_uniform_sphere(w: Vec3) -> Vec2 {
    let u0 = ((1.0 - w.z) * 0.5).clamp(0.0, ONE_MINUS_EPSILON);
    Vec2::new(u0, azimuth_fraction(w.x, w.y))
}

// ------------------------------------------------------------------ ball

/// A point uniform in the unit ball (as *Ray Tracing in One Weekend*'s
/// fuzzy metal draws): the direction [`sample_uniform_sphere`] makes of
/// `(u₀, u₁)`, at radius `∛u₂` (so the volume inside radius `r`, `r³`, is
/// uniform). One 3D sample, no rejection loop.
///
/// See also [`pdf_uniform_ball`], [`invert_uniform_ball`], and the
/// course's rejection method [`rejection::rejection_unit_ball`].
///
/// ```
/// use glam::Vec3;
/// use strata::mapping::*;
/// let u = Vec3::new(0.3, 0.8, 0.125);
/// let p = sample_uniform_ball(u);
/// assert!((p.length() - 0.5).abs() < 1e-6); // ∛0.125
/// assert!((invert_uniform_ball(p) - u).abs().max_element() < 1e-5);
/// assert!((pdf_uniform_ball(p) - 0.75 / core::f32::consts::PI).abs() < 1e-7); // 3/(4π)
/// ```
#[doc(alias = "square_to_uniform_ball")]
#[inline]
#[must_use]
pub fn sample_uniform_ball(u: Vec3) -> Vec3 {
    sample_uniform_sphere(Vec2::new(u.x, u.y)) * libm::cbrtf(u.z)
}

/// The density of [`sample_uniform_ball`]: `3 / (4π)` per unit volume
/// inside the ball (`|p| ≤ 1`, up to the rounding of its samples at the
/// rim), `0` outside it and for a NaN point.
#[doc(alias = "square_to_uniform_ball_pdf")]
#[inline]
#[must_use]
pub fn pdf_uniform_ball(p: Vec3) -> f32 {
    // The rim's samples reach a few ulps past 1.
    if p.length_squared() <= RIM2 {
        3.0 * INV_4PI
    } else {
        0.0
    }
}

/// The inverse of [`sample_uniform_ball`]: the direction's `(u₀, u₁)` and
/// `u₂ = |p|³`, in `[0, 1)³`. The centre, which has no direction, maps to
/// the pole's `(0, 0)` (any `(u₀, u₁)` samples it at `u₂ = 0`).
#[doc(alias = "uniform_ball_to_square")]
#[inline]
#[must_use]
pub fn invert_uniform_ball(p: Vec3) -> Vec3 {
    let r = crate::float::length(p);
    let w = if r > 0.0 { p / r } else { Vec3::Z };
    let r3 = (r * r * r).clamp(0.0, ONE_MINUS_EPSILON);
    invert_uniform_sphere(w).extend(r3)
}

// ------------------------------------------------------------ hemisphere

/// A direction uniform on the hemisphere `z ≥ 0`: `z = u₀`, azimuth `2π u₁`.
///
/// See also [`pdf_uniform_hemisphere`], [`invert_uniform_hemisphere`].
///
/// ```
/// use glam::Vec2;
/// use strata::mapping::*;
/// let w = sample_uniform_hemisphere(Vec2::new(0.25, 0.5));
/// assert!(w.z >= 0.0 && (w.length() - 1.0).abs() < 1e-6);
/// assert_eq!(pdf_uniform_hemisphere(w), 0.5 / core::f32::consts::PI);
/// ```
#[doc(alias = "square_to_uniform_hemisphere")]
#[inline]
#[must_use]
pub fn sample_uniform_hemisphere(u: Vec2) -> Vec3 {
    spherical(u.x, u.y).into()
}

/// The density of [`sample_uniform_hemisphere`]: `1 / (2π)` per steradian
/// where `w.z ≥ 0`, else `0` (and `0` for NaN).
#[doc(alias = "square_to_uniform_hemisphere_pdf")]
#[inline]
#[must_use]
pub fn pdf_uniform_hemisphere(w: Vec3) -> f32 {
    if w.z >= 0.0 && !w.is_nan() {
        INV_2PI
    } else {
        0.0
    }
}

/// The inverse of [`sample_uniform_hemisphere`].
#[doc(alias = "uniform_hemisphere_to_square")]
#[inline]
#[must_use]
pub fn invert_uniform_hemisphere(w: Vec3) -> Vec2 {
    Vec2::new(
        w.z.clamp(0.0, ONE_MINUS_EPSILON),
        azimuth_fraction(w.x, w.y),
    )
}

// ----------------------------------------------------- cosine hemisphere

/// A cosine-weighted direction on the hemisphere `z ≥ 0` (Malley's method:
/// a [concentric-disk](sample_concentric_disk) point lifted to the
/// hemisphere). The square's centre maps to the pole.
///
/// See also [`pdf_cosine_hemisphere`], [`invert_cosine_hemisphere`].
///
/// ```
/// use glam::{Vec2, Vec3};
/// use strata::mapping::*;
/// assert_eq!(sample_cosine_hemisphere(Vec2::splat(0.5)), Vec3::Z);
/// let u = Vec2::new(0.1, 0.7);
/// let w = sample_cosine_hemisphere(u);
/// assert!(w.z >= 0.0 && (w.length() - 1.0).abs() < 1e-6);
/// assert!((invert_cosine_hemisphere(w) - u).abs().max_element() < 1e-5);
/// ```
#[doc(alias = "square_to_cosine_hemisphere")]
#[inline]
#[must_use]
pub fn sample_cosine_hemisphere(u: Vec2) -> Vec3 {
    cosine_hemisphere(u.x, u.y).into()
}

/// [`sample_cosine_hemisphere`] over lanes.
#[inline(always)]
pub(crate) fn cosine_hemisphere<L: Lanes>(u0: L, u1: L) -> V3<L> {
    let k1 = L::splat(1.0);
    let (_, x, y) = concentric(u0, u1);
    // z = √((1 − r)(1 + r)) with 1 − r taken exactly from u, not from the
    // rounded point or radius: the radius is |2uₖ − 1| for the wider
    // coordinate k, and 1 − |2uₖ − 1| = 2 min(uₖ, 1 − uₖ), exact (1 − uₖ
    // by Sterbenz where it is the smaller), while 2uₖ − 1 itself rounds
    // for uₖ < ¼, which is the rim, where z is all in 1 − r.
    let two = L::splat(2.0);
    let wide = (two * u0 - k1).abs().gt((two * u1 - k1).abs());
    let k = L::select(wide, u0, u1);
    let one_minus_r = two * L::select(k.lt(k1 - k), k, k1 - k);
    let z = safe_sqrt(one_minus_r * (two - one_minus_r));
    V3::new(x, y, z)
}

/// [`pdf_cosine_hemisphere`] over lanes.
#[inline(always)]
pub(crate) fn cosine_hemisphere_pdf<L: Lanes>(w: V3<L>) -> L {
    let ok = L::and(w.z.ge(L::splat(0.0)), not_nan(w));
    L::select(ok, w.z * L::splat(FRAC_1_PI), L::splat(0.0))
}

/// The lanes where no component of `w` is NaN.
#[inline(always)]
fn not_nan<L: Lanes>(w: V3<L>) -> L::Mask {
    L::and(L::and(w.x.eq(w.x), w.y.eq(w.y)), w.z.eq(w.z))
}

/// The density of [`sample_cosine_hemisphere`]: `cos θ / π = w.z / π` per
/// steradian where `w.z ≥ 0`, else `0` (and `0` for NaN).
///
/// A sample exactly on the rim (`w.z = 0`, from a coordinate of `u` of
/// exactly 0: 1 in 2²³ of the samplers' values) has density 0 and
/// contributes nothing: an estimator must skip samples whose pdf is 0
/// rather than divide by it.
#[doc(alias = "square_to_cosine_hemisphere_pdf")]
#[inline]
#[must_use]
pub fn pdf_cosine_hemisphere(w: Vec3) -> f32 {
    cosine_hemisphere_pdf(V3::from(w))
}

/// The inverse of [`sample_cosine_hemisphere`]: the concentric-disk inverse
/// of `(w.x, w.y)`, with the disk radius's distance from the rim taken
/// from `w.z` (which keeps it where the radius rounds to 1). For a unit
/// `w` of the upper hemisphere.
#[doc(alias = "cosine_hemisphere_to_square")]
#[inline]
#[must_use]
pub fn invert_cosine_hemisphere(w: Vec3) -> Vec2 {
    let p = Vec2::new(w.x, w.y);
    let r = crate::float::sqrtf(p.x * p.x + p.y * p.y);
    // Near the rim 1 − r is all of z's information and r has rounded it
    // away: 1 − r = z² / (1 + r) instead.
    let one_minus_r = if r > 0.5 {
        w.z * w.z / (1.0 + r)
    } else {
        1.0 - r
    };
    invert_concentric(p, r, one_minus_r)
}

// ------------------------------------------------------- concentric disk

/// A point uniform on the unit disk by Shirley and Chiu's concentric map,
/// which takes squares around the centre to rings and keeps strata compact.
/// The square's centre maps to the origin.
///
/// See also [`pdf_concentric_disk`], [`invert_concentric_disk`].
///
/// ```
/// use glam::Vec2;
/// use strata::mapping::*;
/// assert_eq!(sample_concentric_disk(Vec2::splat(0.5)), Vec2::ZERO);
/// let p = sample_concentric_disk(Vec2::new(1.0, 0.5)); // right edge
/// assert!((p - Vec2::X).length() < 1e-6);
/// ```
#[doc(alias = "square_to_uniform_disk_concentric")]
#[inline]
#[must_use]
pub fn sample_concentric_disk(u: Vec2) -> Vec2 {
    let (_, x, y) = concentric(u.x, u.y);
    Vec2::new(x, y)
}

/// The concentric map of `(u0, u1)`: its radius `|r|` (taken as it is,
/// not from the rounded point) and the point `(x, y)`.
#[inline(always)]
pub(crate) fn concentric<L: Lanes>(u0: L, u1: L) -> (L, L, L) {
    let (k1, k2, zero) = (L::splat(1.0), L::splat(2.0), L::splat(0.0));
    let a = k2 * u0 - k1;
    let b = k2 * u1 - k1;
    // Which of the four triangles of the square holds (a, b) decides
    // whether a or b is the radius: θ = π/4 · b/a, or π/2 − π/4 · a/b,
    // whose sine and cosine are the cosine and sine of π/4 · a/b. Both
    // cases run the same operations on swapped inputs, chosen by selects:
    // a branch on a coin flip is mispredicted half the time.
    let wide = a.abs().gt(b.abs());
    let (r, q) = (L::select(wide, a, b), L::select(wide, b, a));
    // |q| ≤ |r|, so r is 0 only at the centre, 0/0; there q/1 = 0 maps it
    // to itself (r = +0, sin 0 = 0, cos 0 = 1).
    let ratio = q / L::select(r.eq(zero), k1, r);
    let (sin, cos) = sin_cos_pi_quarter(L::splat(0.25) * ratio);
    let (x, y) = (L::select(wide, cos, sin), L::select(wide, sin, cos));
    (r.abs(), r * x, r * y)
}

/// The density of [`sample_concentric_disk`]: `1 / π` per unit area inside
/// the closed unit disk, else `0` (and `0` for NaN). The disk is taken as
/// `|p|² ≤ 1 + 4ε` (ε = `f32::EPSILON`): `r cos θ, r sin θ` can round an
/// ulp past the rim, and such a sample must not get density 0.
#[doc(alias = "square_to_uniform_disk_concentric_pdf")]
#[inline]
#[must_use]
pub fn pdf_concentric_disk(p: Vec2) -> f32 {
    if p.length_squared() <= RIM2 {
        FRAC_1_PI
    } else {
        0.0
    }
}

/// The inverse of [`sample_concentric_disk`].
#[doc(alias = "uniform_disk_to_square_concentric")]
#[inline]
#[must_use]
pub fn invert_concentric_disk(p: Vec2) -> Vec2 {
    let r = crate::float::sqrtf(p.x * p.x + p.y * p.y);
    invert_concentric(p, r, 1.0 - r)
}

/// The concentric inverse of `p`, of radius `r`, given `1 − r` (which a
/// caller may know better than `1 − r` rounds it: the cosine hemisphere
/// knows it from `z`). A radius coordinate `−r` maps to `(1 − r) / 2`.
#[inline]
fn invert_concentric(p: Vec2, r: f32, one_minus_r: f32) -> Vec2 {
    let mut theta = libm::atan2f(p.y, p.x);
    // Put theta in [-π/4, 7π/4) so each wedge is one interval.
    if theta < -FRAC_PI_4 {
        theta += TAU;
    }
    let (a, b) = if theta < FRAC_PI_4 {
        // Right wedge: radius a, theta = π/4 · b/a.
        (r, theta * r / FRAC_PI_4)
    } else if theta < 3.0 * FRAC_PI_4 {
        // Top wedge: radius b, theta = π/2 − π/4 · a/b.
        (-(theta - FRAC_PI_2) * r / FRAC_PI_4, r)
    } else if theta < 5.0 * FRAC_PI_4 {
        // Left wedge: radius −a, theta = π + π/4 · b/a.
        (-r, (theta - PI) * -r / FRAC_PI_4)
    } else {
        // Bottom wedge: radius −b, theta = 3π/2 − π/4 · a/b.
        (-(theta - 3.0 * FRAC_PI_2) * -r / FRAC_PI_4, -r)
    };
    // The radius coordinate ±r maps to (1 − r) / 2 or 1 − (1 − r) / 2,
    // from the caller's 1 − r: near the rim that is all the information
    // (u is as fine as f32 allows near 0, and a grid of 2⁻²⁴ near 1).
    let to_unit = |c: f32| {
        let u = if c == -r {
            one_minus_r * 0.5
        } else if c == r {
            1.0 - one_minus_r * 0.5
        } else {
            (c + 1.0) * 0.5
        };
        u.clamp(0.0, ONE_MINUS_EPSILON)
    };
    Vec2::new(to_unit(a), to_unit(b))
}

// ------------------------------------------------------------ polar disk

/// A point uniform on the unit disk in polar form: `r = sqrt(u₀)`, angle
/// `2π u₁`. Simple, but it stretches strata near the centre; see
/// [`sample_concentric_disk`].
///
/// See also [`pdf_polar_disk`], [`invert_polar_disk`].
///
/// ```
/// use glam::Vec2;
/// use strata::mapping::*;
/// let u = Vec2::new(0.49, 0.3);
/// let p = sample_polar_disk(u);
/// assert!((p.length() - 0.7).abs() < 1e-6);
/// assert!((invert_polar_disk(p) - u).abs().max_element() < 1e-5);
/// ```
#[doc(alias = "square_to_uniform_disk")]
#[inline]
#[must_use]
pub fn sample_polar_disk(u: Vec2) -> Vec2 {
    let r = safe_sqrt(u.x);
    let (sin, cos) = sin_cos_turn(u.y);
    Vec2::new(r * cos, r * sin)
}

/// The density of [`sample_polar_disk`]: `1 / π` per unit area inside the
/// closed unit disk, else `0` (and `0` for NaN).
#[doc(alias = "square_to_uniform_disk_pdf")]
#[inline]
#[must_use]
pub fn pdf_polar_disk(p: Vec2) -> f32 {
    pdf_concentric_disk(p)
}

/// The inverse of [`sample_polar_disk`].
#[doc(alias = "uniform_disk_to_square")]
#[inline]
#[must_use]
pub fn invert_polar_disk(p: Vec2) -> Vec2 {
    Vec2::new(
        (p.x * p.x + p.y * p.y).clamp(0.0, ONE_MINUS_EPSILON),
        azimuth_fraction(p.x, p.y),
    )
}

// ---------------------------------------------------------- uniform cone

/// A cone of directions around `+z` with half-angle `θmax`, stored as
/// `cos θmax` and `1 − cos θmax`, the second computed without
/// cancellation, so that even a cone of a microradian (a small light far
/// away) has an exact solid angle and pdf. Built from whichever quantity
/// the caller knows accurately.
///
/// ```
/// use strata::mapping::Cone;
/// // A sphere of radius 1 seen from 10⁴ away: θmax = 10⁻⁴.
/// let cone = Cone::subtended_by_sphere(1e4, 1.0).unwrap();
/// let exact = 2.0 * core::f64::consts::PI * (1.0 - (1.0f64 - 1e-8).sqrt());
/// assert!((cone.solid_angle() as f64 / exact - 1.0).abs() < 1e-6);
/// // From cos θmax, that cone is lost: cos(10⁻⁴) rounds to 1 in f32.
/// assert_eq!(Cone::from_cos(1e-4f32.cos()).solid_angle(), 0.0);
/// ```
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Cone {
    cos_theta_max: f32,
    one_minus_cos: f32,
}

impl Cone {
    /// The cone with `cos θmax = cos_theta_max`, clamped to `[−1, 1]` (−1
    /// is the whole sphere, 1 a zero-width cone). `1 − c` is exact for
    /// `c ≥ 0.5`, so this loses nothing the `f32` cosine still holds. A NaN
    /// gives a cone whose samples are NaN and whose pdf is 0.
    #[inline]
    #[must_use]
    pub fn from_cos(cos_theta_max: f32) -> Self {
        let c = cos_theta_max.clamp(-1.0, 1.0);
        Self {
            cos_theta_max: c,
            one_minus_cos: 1.0 - c,
        }
    }

    /// The cone with `sin² θmax = sin2_theta_max` and `θmax ≤ 90°`
    /// (clamped to `[0, 1]`): `1 − cos θmax = sin² / (1 + cos)`, accurate
    /// for the tiniest cones.
    #[inline]
    #[must_use]
    pub fn from_sin2(sin2_theta_max: f32) -> Self {
        let c = ConeLanes::from_sin2(sin2_theta_max);
        Self {
            cos_theta_max: c.cos_theta_max,
            one_minus_cos: c.one_minus_cos,
        }
    }

    /// The cone a sphere of `radius` subtends from `distance` to its
    /// centre: `sin² θmax = (r / d)²`. `None` when the point is inside or on
    /// the sphere (`distance ≤ radius`), where no cone exists, or for
    /// non-finite or negative input.
    #[inline]
    #[must_use]
    pub fn subtended_by_sphere(distance: f32, radius: f32) -> Option<Self> {
        let (c, ok) = ConeLanes::subtended_by_sphere(distance, radius);
        ok.then_some(Self {
            cos_theta_max: c.cos_theta_max,
            one_minus_cos: c.one_minus_cos,
        })
    }

    /// `cos θmax`.
    #[inline]
    #[must_use]
    pub fn cos_theta_max(&self) -> f32 {
        self.cos_theta_max
    }

    /// `1 − cos θmax`, without cancellation.
    #[inline]
    #[must_use]
    pub fn one_minus_cos_theta_max(&self) -> f32 {
        self.one_minus_cos
    }

    /// The solid angle `2π (1 − cos θmax)`, in steradians.
    #[inline]
    #[must_use]
    pub fn solid_angle(&self) -> f32 {
        TAU * self.one_minus_cos
    }

    /// The cone as one lane.
    #[inline(always)]
    pub(crate) fn lanes(self) -> ConeLanes<f32> {
        ConeLanes {
            cos_theta_max: self.cos_theta_max,
            one_minus_cos: self.one_minus_cos,
        }
    }
}

/// [`Cone`] over lanes: one cone per lane.
#[derive(Clone, Copy, Debug)]
pub(crate) struct ConeLanes<L> {
    pub(crate) cos_theta_max: L,
    pub(crate) one_minus_cos: L,
}

impl<L: Lanes> ConeLanes<L> {
    /// [`Cone::from_sin2`] per lane.
    #[inline(always)]
    pub(crate) fn from_sin2(sin2_theta_max: L) -> Self {
        let s2 = sin2_theta_max.clamp_to(0.0, 1.0);
        let c = safe_sqrt(L::splat(1.0) - s2);
        Self {
            cos_theta_max: c,
            one_minus_cos: s2 / (L::splat(1.0) + c),
        }
    }

    /// [`Cone::subtended_by_sphere`] per lane: the cone, meaningful where
    /// the mask is set (`radius ≥ 0`, `distance > radius`, finite
    /// `distance`).
    #[inline(always)]
    pub(crate) fn subtended_by_sphere(distance: L, radius: L) -> (Self, L::Mask) {
        let ok = L::and(
            L::and(radius.ge(L::splat(0.0)), distance.gt(radius)),
            distance.lt(L::splat(f32::INFINITY)),
        );
        let ratio = radius / distance;
        (Self::from_sin2(ratio * ratio), ok)
    }
}

/// [`sample_uniform_cone`] over lanes.
#[inline(always)]
pub(crate) fn uniform_cone<L: Lanes>(u0: L, u1: L, cone: &ConeLanes<L>) -> V3<L> {
    let omz = u0 * cone.one_minus_cos;
    let sin_theta = safe_sqrt(omz * (L::splat(2.0) - omz));
    let (sin, cos) = sin_cos_turn(u1);
    V3::new(sin_theta * cos, sin_theta * sin, L::splat(1.0) - omz)
}

/// `1 − z` of a unit direction without cancellation near the pole:
/// `(x² + y²) / (1 + z)` where `z > 0`.
#[inline(always)]
fn one_minus_z<L: Lanes>(w: V3<L>) -> L {
    let k1 = L::splat(1.0);
    L::select(
        w.z.gt(L::splat(0.0)),
        (w.x * w.x + w.y * w.y) / (k1 + w.z),
        k1 - w.z,
    )
}

/// [`pdf_uniform_cone`] over lanes.
#[inline(always)]
pub(crate) fn uniform_cone_pdf<L: Lanes>(w: V3<L>, cone: &ConeLanes<L>) -> L {
    const SLACK: f32 = 1.0 + 1.0 / 1_048_576.0;
    let inside = L::and(
        one_minus_z(w).le(cone.one_minus_cos * L::splat(SLACK)),
        not_nan(w),
    );
    L::select(
        inside,
        L::splat(INV_2PI) / cone.one_minus_cos,
        L::splat(0.0),
    )
}

/// A direction uniform in a [`Cone`] around `+z`: `1 − cos θ = u₀ (1 −
/// cos θmax)`, azimuth `2π u₁`; `sin θ` comes from `1 − cos θ`, so tiny
/// cones keep their spread. This is how a spherical light is sampled by
/// the solid angle it subtends.
///
/// See also [`pdf_uniform_cone`], [`invert_uniform_cone`].
///
/// ```
/// use glam::Vec2;
/// use strata::mapping::*;
/// let cone = Cone::from_cos(0.9);
/// let w = sample_uniform_cone(Vec2::new(0.999, 0.2), cone);
/// assert!(w.z >= 0.9 && (w.length() - 1.0).abs() < 1e-6);
/// assert!((pdf_uniform_cone(w, cone) * cone.solid_angle() - 1.0).abs() < 1e-6);
/// assert!((invert_uniform_cone(w, cone) - Vec2::new(0.999, 0.2)).abs().max_element() < 1e-5);
/// ```
#[doc(alias = "square_to_uniform_cone")]
#[inline]
#[must_use]
pub fn sample_uniform_cone(u: Vec2, cone: Cone) -> Vec3 {
    uniform_cone(u.x, u.y, &cone.lanes()).into()
}

/// The density of [`sample_uniform_cone`]: `1 / (2π (1 − cos θmax))` per
/// steradian inside the cone, else `0` (and `0` for NaN). "Inside" is
/// `1 − w.z ≤ (1 − cos θmax)(1 + 2⁻²⁰)`, with `1 − w.z` computed without
/// cancellation: the slack absorbs the rounding of a sample at the rim.
/// For a zero-width cone the pdf is `+∞` on the axis: a delta.
#[doc(alias = "square_to_uniform_cone_pdf")]
#[inline]
#[must_use]
pub fn pdf_uniform_cone(w: Vec3, cone: Cone) -> f32 {
    uniform_cone_pdf(V3::from(w), &cone.lanes())
}

/// The inverse of [`sample_uniform_cone`]; for a zero-width cone every
/// direction inverts to `u₀ = 0`.
#[doc(alias = "uniform_cone_to_square")]
#[inline]
#[must_use]
pub fn invert_uniform_cone(w: Vec3, cone: Cone) -> Vec2 {
    let u0 = if cone.one_minus_cos > 0.0 {
        one_minus_z(V3::from(w)) / cone.one_minus_cos
    } else {
        0.0
    };
    Vec2::new(u0.clamp(0.0, ONE_MINUS_EPSILON), azimuth_fraction(w.x, w.y))
}

#[cfg(test)]
mod tests {
    use super::*;

    /// A grid over [0, 1)² kept `margin` away from the borders, where an
    /// inverse is ambiguous (azimuth 0 vs 1, the disk's centre).
    fn grid(n: u32, margin: f32) -> impl Iterator<Item = Vec2> {
        (0..n).flat_map(move |i| {
            (0..n).map(move |j| {
                let t = |k: u32| margin + (1.0 - 2.0 * margin) * k as f32 / (n - 1) as f32;
                Vec2::new(t(i), t(j))
            })
        })
    }

    fn assert_round_trip(name: &str, f: impl Fn(Vec2) -> Vec2, tol: f32) {
        for u in grid(41, 1e-3) {
            let back = f(u);
            assert!(
                (back - u).abs().max_element() < tol,
                "{name}: {u} -> {back} (|Δ| {})",
                (back - u).abs().max_element()
            );
        }
    }

    /// Every sample of the ball has a positive density, at the rim too
    /// (`∛u₂` rounds to 1 there and the direction's length to a few ulps
    /// past it), and points clearly outside have none.
    #[test]
    fn uniform_ball_samples_have_density_at_the_rim() {
        let mut worst = 0.0f32;
        for z in [1.0 - f32::EPSILON / 2.0, 1.0 - f32::EPSILON, 0.999_999, 0.5] {
            for u in grid(1024, 0.0) {
                let p = sample_uniform_ball(u.extend(z));
                worst = worst.max(p.length_squared());
                assert!(
                    pdf_uniform_ball(p) > 0.0,
                    "u {u} z {z}: |p|² {}",
                    p.length_squared()
                );
            }
        }
        assert!(worst > 1.0, "the grid reaches past the rim: {worst}");
        std::eprintln!(
            "largest |p|² {worst}, 1 + {} ε",
            (worst - 1.0) / f32::EPSILON
        );
        assert_eq!(pdf_uniform_ball(Vec3::new(0.0, 0.0, 1.0 + 1e-5)), 0.0);
        assert_eq!(pdf_uniform_ball(Vec3::NAN), 0.0);
    }

    #[test]
    fn uniform_sphere_round_trip() {
        assert_round_trip(
            "uniform sphere",
            |u| invert_uniform_sphere(sample_uniform_sphere(u)),
            1e-5,
        );
    }

    #[test]
    fn uniform_hemisphere_round_trip() {
        assert_round_trip(
            "uniform hemisphere",
            |u| invert_uniform_hemisphere(sample_uniform_hemisphere(u)),
            1e-5,
        );
    }

    #[test]
    fn cosine_hemisphere_round_trip() {
        assert_round_trip(
            "cosine hemisphere",
            |u| invert_cosine_hemisphere(sample_cosine_hemisphere(u)),
            1e-5,
        );
    }

    #[test]
    fn concentric_disk_round_trip() {
        assert_round_trip(
            "concentric disk",
            |u| invert_concentric_disk(sample_concentric_disk(u)),
            1e-5,
        );
    }

    #[test]
    fn polar_disk_round_trip() {
        assert_round_trip(
            "polar disk",
            |u| invert_polar_disk(sample_polar_disk(u)),
            1e-5,
        );
    }

    #[test]
    fn uniform_cone_round_trip() {
        for c in [-0.5f32, 0.0, 0.5, 0.99] {
            let cone = Cone::from_cos(c);
            assert_round_trip(
                "uniform cone",
                |u| invert_uniform_cone(sample_uniform_cone(u, cone), cone),
                2e-5,
            );
        }
        // A tiny cone round-trips as well as a wide one.
        let tiny = Cone::from_sin2(1e-10);
        assert_round_trip(
            "tiny cone",
            |u| invert_uniform_cone(sample_uniform_cone(u, tiny), tiny),
            2e-5,
        );
    }

    #[test]
    fn outputs_lie_on_their_domains() {
        for u in grid(64, 0.0) {
            let s = sample_uniform_sphere(u);
            assert!((s.length() - 1.0).abs() < 1e-6, "{u}");
            let h = sample_uniform_hemisphere(u);
            assert!(h.z >= 0.0 && (h.length() - 1.0).abs() < 1e-6, "{u}");
            let c = sample_cosine_hemisphere(u);
            assert!(c.z >= 0.0 && (c.length() - 1.0).abs() < 1e-6, "{u}");
            assert!(sample_concentric_disk(u).length() <= 1.0 + 1e-6, "{u}");
            assert!(sample_polar_disk(u).length() <= 1.0 + 1e-6, "{u}");
            let cone = Cone::from_cos(0.7);
            let k = sample_uniform_cone(u, cone);
            assert!(k.z >= 0.7 && (k.length() - 1.0).abs() < 1e-6, "{u}");
            assert!(pdf_cosine_hemisphere(c) >= 0.0);
            assert!(pdf_uniform_cone(k, cone) > 0.0);
        }
    }

    #[test]
    fn pinned_points() {
        // Square centre to pole / origin; corners to the rim.
        assert_eq!(sample_cosine_hemisphere(Vec2::splat(0.5)), Vec3::Z);
        assert_eq!(sample_uniform_sphere(Vec2::new(0.0, 0.0)), Vec3::Z);
        assert_eq!(sample_uniform_sphere(Vec2::new(1.0, 0.0)), -Vec3::Z);
        assert_eq!(sample_uniform_hemisphere(Vec2::new(1.0, 0.0)), Vec3::Z);
        assert_eq!(
            sample_uniform_cone(Vec2::new(0.0, 0.3), Cone::from_cos(0.5)),
            Vec3::Z
        );
        assert_eq!(
            sample_uniform_cone(Vec2::new(1.0, 0.0), Cone::from_cos(0.5)).z,
            0.5
        );
        for corner in [Vec2::ZERO, Vec2::X, Vec2::Y, Vec2::ONE] {
            let p = sample_concentric_disk(corner);
            assert!((p.length() - 1.0).abs() < 1e-6, "{corner} -> {p}");
            assert!(sample_cosine_hemisphere(corner).z.abs() < 1e-3);
        }
        assert_eq!(invert_concentric_disk(Vec2::ZERO), Vec2::splat(0.5));
    }

    #[test]
    fn pdfs_are_zero_off_support_and_for_nan() {
        let below = Vec3::new(0.0, 0.6, -0.8);
        assert_eq!(pdf_uniform_hemisphere(below), 0.0);
        assert_eq!(pdf_cosine_hemisphere(below), 0.0);
        assert_eq!(
            pdf_uniform_cone(Vec3::new(0.6, 0.0, 0.8), Cone::from_cos(0.9)),
            0.0
        );
        assert_eq!(pdf_concentric_disk(Vec2::new(0.8, 0.8)), 0.0);
        assert_eq!(pdf_polar_disk(Vec2::new(1.0, 0.1)), 0.0);
        let nan3 = Vec3::new(f32::NAN, 0.0, 1.0);
        let nan2 = Vec2::new(0.0, f32::NAN);
        assert_eq!(pdf_uniform_sphere(nan3), 0.0);
        assert_eq!(pdf_uniform_hemisphere(nan3), 0.0);
        assert_eq!(pdf_cosine_hemisphere(nan3), 0.0);
        assert_eq!(pdf_uniform_cone(nan3, Cone::from_cos(0.5)), 0.0);
        assert_eq!(pdf_uniform_cone(Vec3::Z, Cone::from_cos(f32::NAN)), 0.0);
        assert_eq!(pdf_concentric_disk(nan2), 0.0);
        assert_eq!(pdf_polar_disk(nan2), 0.0);
    }

    #[test]
    fn nan_sample_gives_nan_not_panic() {
        let u = Vec2::new(f32::NAN, 0.5);
        assert!(sample_uniform_sphere(u).is_nan());
        assert!(sample_uniform_hemisphere(u).is_nan());
        assert!(sample_cosine_hemisphere(u).is_nan());
        assert!(sample_concentric_disk(u).is_nan());
        assert!(sample_polar_disk(u).is_nan());
        assert!(sample_uniform_cone(u, Cone::from_cos(0.5)).is_nan());
        assert!(sample_uniform_cone(Vec2::splat(0.5), Cone::from_cos(f32::NAN)).is_nan());
    }

    #[test]
    fn degenerate_cone() {
        // A zero-width cone: a delta on +z with an infinite density.
        for cone in [
            Cone::from_cos(1.0),
            Cone::from_sin2(0.0),
            Cone::from_cos(2.0),
        ] {
            let w = sample_uniform_cone(Vec2::new(0.7, 0.3), cone);
            assert_eq!(w, Vec3::Z);
            assert_eq!(pdf_uniform_cone(w, cone), f32::INFINITY);
            assert_eq!(invert_uniform_cone(w, cone).x, 0.0);
        }
        // Out-of-range cosines are clamped: −2 is the whole sphere.
        assert_eq!(pdf_uniform_cone(-Vec3::Z, Cone::from_cos(-2.0)), INV_4PI);
        assert!(Cone::subtended_by_sphere(1.0, 1.0).is_none());
        assert!(Cone::subtended_by_sphere(0.5, 1.0).is_none());
        assert!(Cone::subtended_by_sphere(f32::INFINITY, 1.0).is_none());
        assert!(Cone::subtended_by_sphere(f32::NAN, 1.0).is_none());
        assert!(Cone::subtended_by_sphere(2.0, -1.0).is_none());
        let c = Cone::subtended_by_sphere(2.0, 1.0).unwrap(); // θmax = 30°
        assert!((c.cos_theta_max() - 0.75f32.sqrt()).abs() < 1e-7);
    }

    #[test]
    fn tiny_cones_keep_their_solid_angle() {
        for theta in [1e-6f64, 1e-5, 1e-4, 1e-3, 0.01, 0.1, 0.5, 1.0, 1.5] {
            let cone = Cone::from_sin2(theta.sin().powi(2) as f32);
            // 1 − cos θ = 2 sin²(θ/2): no cancellation in the reference either.
            let exact = core::f64::consts::TAU * 2.0 * (theta / 2.0).sin().powi(2);
            let rel = (cone.solid_angle() as f64 / exact - 1.0).abs();
            assert!(rel < 1e-6, "θ {theta}: relative error {rel}");
            // Its samples spread over the whole cone and stay inside it.
            let w = sample_uniform_cone(Vec2::new(ONE_MINUS_EPSILON, 0.1), cone);
            let angle = libm::atan2((w.x as f64).hypot(w.y as f64), w.z as f64);
            assert!(
                (angle / theta - 1.0).abs() < 1e-5,
                "θ {theta}: rim at {angle}"
            );
            assert!(pdf_uniform_cone(w, cone) > 0.0);
        }
    }

    #[test]
    fn inverses_stay_in_unit_square() {
        for w in [Vec3::Z, -Vec3::Z, Vec3::X, Vec3::new(1.0, -1e-9, 0.0)] {
            for u in [
                invert_uniform_sphere(w),
                invert_uniform_hemisphere(w),
                invert_cosine_hemisphere(w),
                invert_uniform_cone(w, Cone::from_cos(0.0)),
            ] {
                assert!(
                    u.cmpge(Vec2::ZERO).all() && u.cmplt(Vec2::ONE).all(),
                    "{w} -> {u}"
                );
            }
        }
    }
}
