//! Materials: the course's models with its maths fixed (COURSE.md §4–5).
//!
//! Conventions: `d` is the incoming ray's unit direction, `n` the unit
//! shading normal turned to face it (`n · d < 0`), `V = −d`, `L = wi` the
//! unit outgoing direction. Every direction is unit length (the course's
//! D6 used raw camera directions of length ≈ 5).
//!
//! Smooth materials (everything diffuse-like or glossy) sample `L` from the
//! cosine-weighted hemisphere around `n` in an [`Onb`](crate::onb::Onb) — the course's
//! assignment — and weight it by `f(V, L) cos θ / pdf`, which is `π f`
//! (the course left out the `1/pdf`, D2, and the `1/π` of the diffuse
//! BRDF, D10). So each estimate is unbiased; glossy lobes are noisy at
//! high exponents but right on average.
//!
//! Mirror, metal and glass are *specular*: they scatter into one
//! direction (metal: a fuzzed one) with weight equal to their colour, no
//! cosine and no BRDF evaluation (the course applied both, D5), and take no
//! direct lighting.
//!
//! The course's `Phong` and `Blinn` keep its unnormalised lobes: their
//! albedo depends on the exponent and can exceed 1 (COURSE.md D11: 1.51 for
//! the centre sphere at normal incidence). `PhongNormalized` and
//! `BlinnNormalized` are the energy-conserving forms, with `kd + ks ≤ 1`
//! (`tests/rendering/render.rs` checks their albedo stays at or below 1).
//!
//! ## Layout
//!
//! One file per family, cut where the maths is shared:
//!
//! - `diffuse`: the Lambertian, plus the cosine-hemisphere sampler and the
//!   `ρ kd/π` base that every smooth family reuses;
//! - `specular`: mirror, metal and glass, the delta (or fuzzed-delta)
//!   lobes, which share the reflection and are never evaluated;
//! - `phong`: the four Phong and Blinn lobes, which differ only in the
//!   lobe's cosine (`R·V` or `n·H`) and its normalisation;
//! - `microfacet`: Cook–Torrance with GGX and Smith's shadowing;
//! - `emissive`: the light, which only emits.
//!
//! Each family file holds a type for its variants with their checks,
//! evaluation, sampling and content bytes. Schlick's Fresnel, which glass
//! and Cook–Torrance share, and the range checks stay here. One exhaustive
//! match turns a [`Material`] into its family (and one more gives its tag
//! in the content bytes); every method is then a short exhaustive match
//! over the five families, so a new variant fails to compile until a
//! family takes it.

mod diffuse;
mod emissive;
mod microfacet;
mod phong;
mod specular;

use core::f32::consts::{FRAC_1_PI, PI};

use glam::{Vec2, Vec3};

use super::texture::Texture;
use crate::lanes::{Lanes, V3};
use diffuse::Lambertian;
use emissive::DiffuseLight;
use microfacet::CookTorrance;
use phong::{Kind, Phong};
use specular::Specular;

/// The surface point a material shades, as [`Material::sample`],
/// [`Material::eval`] and [`Material::brdf`] take it (the path tracer keeps
/// the same record in its one-lane form).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct SurfaceHit {
    /// The hit point.
    pub p: Vec3,
    /// Unit shading normal facing the incoming ray.
    pub n: Vec3,
    /// Whether the ray arrived from outside the sphere.
    pub front_face: bool,
    /// The sphere's `(u, v)` at the point ([`sphere_uv`](super::sphere_uv));
    /// the path tracer leaves it zero when the material does not read it
    /// ([`Material::uses_uv`]).
    pub uv: Vec2,
    /// Half-widths, per world axis, of the box textures are averaged over
    /// ([`Texture::filtered`]); zero for point sampling.
    pub footprint: Vec3,
}

impl SurfaceHit {
    /// The sphere's outward unit normal at the point (`n` turned back for
    /// a hit from inside).
    ///
    /// ```
    /// use glam::{Vec2, Vec3};
    /// use strata::render::SurfaceHit;
    /// let inside = SurfaceHit { p: Vec3::Y, n: -Vec3::Y, front_face: false,
    ///     uv: Vec2::ZERO, footprint: Vec3::ZERO };
    /// assert_eq!(inside.outward(), Vec3::Y);
    /// ```
    #[inline]
    #[must_use]
    pub fn outward(&self) -> Vec3 {
        outward(V3::from(self.n), self.front_face).into()
    }
}

/// [`SurfaceHit`] over lanes: what a lane form of shading reads.
#[derive(Clone, Copy, Debug)]
pub(crate) struct SurfaceLanes<L: Lanes> {
    pub(crate) p: V3<L>,
    pub(crate) n: V3<L>,
    pub(crate) front_face: L::Mask,
    pub(crate) uv: (L, L),
    pub(crate) footprint: V3<L>,
    /// The lanes whose results are read (bit `k`: lane `k`): code that
    /// falls back to one lane at a time (a varying texture) skips the
    /// others. All of them unless the caller narrows it; ignored for one
    /// lane.
    pub(crate) wanted: u8,
}

impl<L: Lanes> SurfaceLanes<L> {
    /// [`SurfaceHit::outward`] per lane.
    #[inline(always)]
    pub(crate) fn outward(&self) -> V3<L> {
        outward(self.n, self.front_face)
    }
}

/// The sphere's outward normal from the shading normal `n` and the side
/// the ray came from.
#[inline(always)]
fn outward<L: Lanes>(n: V3<L>, front_face: L::Mask) -> V3<L> {
    V3::select(front_face, n, -n)
}

impl From<&SurfaceHit> for SurfaceLanes<f32> {
    #[inline(always)]
    fn from(h: &SurfaceHit) -> Self {
        Self {
            p: h.p.into(),
            n: h.n.into(),
            front_face: h.front_face,
            uv: (h.uv.x, h.uv.y),
            footprint: h.footprint.into(),
            wanted: 1,
        }
    }
}

/// A sampled direction over lanes ([`BsdfSample`] per lane).
#[derive(Clone, Copy, Debug)]
pub(crate) struct BsdfLanes<L: Lanes> {
    /// Unit outgoing direction.
    pub(crate) wi: V3<L>,
    /// `f cos θ / pdf` (smooth) or the colour (specular).
    pub(crate) weight: V3<L>,
    /// The smooth lobe's density (the material decides, for all lanes,
    /// whether its lobe is smooth: [`Material::is_smooth`]).
    pub(crate) pdf: L,
    /// The lanes whose direction crosses the surface.
    pub(crate) transmitted: L::Mask,
    /// The lanes not absorbed (where `sample` gives `Some`).
    pub(crate) live: L::Mask,
}

/// `max(x, 0)` per lane, NaN to 0 (as `f32::max` has it).
#[inline(always)]
pub(crate) fn max0<L: Lanes>(x: L) -> L {
    L::select(x.gt(L::splat(0.0)), x, L::splat(0.0))
}

/// How a sampled direction was chosen.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum Lobe {
    /// From the cosine hemisphere, with this solid-angle density.
    Smooth {
        /// Density of the sampled direction, per steradian, `> 0`.
        pdf: f32,
    },
    /// A delta or fuzzed mirror direction: no density, no direct lighting.
    Specular,
}

/// One sampled scattering direction.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct BsdfSample {
    /// Unit outgoing direction.
    pub wi: Vec3,
    /// `f cos θ / pdf` (smooth) or the colour (specular).
    pub weight: Vec3,
    /// How `wi` was chosen.
    pub lobe: Lobe,
    /// Whether `wi` crosses the surface (refraction).
    pub transmitted: bool,
}

/// A surface material. Textures are borrowed, so a material is `Copy`.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum Material<'a> {
    /// Ideal diffuse, `f = ρ / π`; the course's `Lambertian` and
    /// `TextureColor`.
    Lambertian {
        /// Reflectance `ρ`, components in `[0, 1]`.
        albedo: Texture<'a>,
    },
    /// A perfect mirror with colour `ρ`.
    Mirror {
        /// Reflectance, components in `[0, 1]`.
        albedo: Vec3,
    },
    /// The course's (and RTIOW's) fuzzy metal: the mirror direction plus
    /// `roughness` times a uniform unit vector, renormalised; absorbed when
    /// that points below the surface.
    Metal {
        /// Reflectance, components in `[0, 1]`.
        albedo: Vec3,
        /// Fuzz, in `[0, 1]`.
        roughness: f32,
    },
    /// Glass: reflects with Schlick's probability (always under total
    /// internal reflection), else refracts; colourless. Schlick takes the
    /// cosine on the outside (air) side of the interface.
    Dielectric {
        /// Index of refraction relative to the outside, `> 0`.
        ior: f32,
    },
    /// The course's Phong: `ρ kd/π + ρ ks max(0, R·V)^α`, `R` the mirror
    /// of `L` about `n`. Unnormalised (see the module docs).
    Phong {
        /// Colour `ρ`.
        albedo: Texture<'a>,
        /// Diffuse weight, `≥ 0`.
        kd: f32,
        /// Specular weight, `≥ 0`.
        ks: f32,
        /// Exponent `α ≥ 0`.
        exponent: f32,
    },
    /// The course's Blinn–Phong: `ρ kd/π + ρ ks max(0, n·H)^α`, `H =
    /// unit(V + L)`. Unnormalised; `week09`'s spheres.
    Blinn {
        /// Colour `ρ`.
        albedo: Texture<'a>,
        /// Diffuse weight, `≥ 0`.
        kd: f32,
        /// Specular weight, `≥ 0`.
        ks: f32,
        /// Exponent `α ≥ 0`.
        exponent: f32,
    },
    /// Energy-conserving Phong: `ρ kd/π + ks (α+2)/(2π) max(0, R·V)^α`,
    /// white specular, `kd + ks ≤ 1`.
    PhongNormalized {
        /// Diffuse colour `ρ`.
        albedo: Texture<'a>,
        /// Diffuse weight.
        kd: f32,
        /// Specular weight; `kd + ks ≤ 1`.
        ks: f32,
        /// Exponent `α ≥ 0`.
        exponent: f32,
    },
    /// Energy-conserving Blinn–Phong: `ρ kd/π + ks N(α) max(0, n·H)^α`
    /// with the exact normalisation `N(α) = (α+2)(α+4) / (8π (2^(−α/2) +
    /// α))` (directional albedo 1 at normal incidence, less elsewhere),
    /// white specular, `kd + ks ≤ 1`.
    BlinnNormalized {
        /// Diffuse colour `ρ`.
        albedo: Texture<'a>,
        /// Diffuse weight.
        kd: f32,
        /// Specular weight; `kd + ks ≤ 1`.
        ks: f32,
        /// Exponent `α ≥ 0`.
        exponent: f32,
    },
    /// Cook–Torrance with the GGX distribution, Smith's separable
    /// shadowing and Schlick's Fresnel on `V·H`:
    /// `ρ kd/π + ks D G₁(V) G₁(L) F / (4 (n·V)(n·L))`. The course's version
    /// (D12) took Fresnel on `L·N`, the Smith tangent from `v·H`, and had
    /// no colour: fixed here.
    CookTorrance {
        /// Diffuse colour `ρ`.
        albedo: Texture<'a>,
        /// Diffuse weight.
        kd: f32,
        /// Specular weight.
        ks: f32,
        /// GGX roughness `α`, in `(0, 1]`.
        alpha: f32,
        /// Index of refraction for Fresnel, `> 0`.
        ior: f32,
    },
    /// An emitter: radiance `emit` on both sides, no scattering (the
    /// course's `Diffuse_light`).
    DiffuseLight {
        /// Emitted radiance, components `≥ 0`.
        emit: Vec3,
    },
}

/// Why a material's parameters were refused.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum MaterialError {
    /// A colour component is negative, above 1 (for a reflectance) or not
    /// finite.
    Colour,
    /// A weight, exponent, roughness or index is out of its range.
    Parameter,
    /// A normalised lobe has `kd + ks > 1`.
    Energy,
}

impl core::fmt::Display for MaterialError {
    #[inline]
    fn fmt(&self, f: &mut core::fmt::Formatter<'_>) -> core::fmt::Result {
        f.write_str(match self {
            MaterialError::Colour => {
                "a colour component is negative, above 1 for a reflectance, or not finite"
            }
            MaterialError::Parameter => "a weight, exponent, roughness or index is out of range",
            MaterialError::Energy => "a normalised lobe has kd + ks > 1",
        })
    }
}

impl core::error::Error for MaterialError {}

/// `r₀ + (1 − r₀)(1 − c)⁵`.
#[inline(always)]
fn schlick<L: Lanes>(cosine: L, r0: L) -> L {
    let k1 = L::splat(1.0);
    let m = (k1 - cosine).clamp_to(0.0, 1.0);
    let m2 = m * m;
    r0 + (k1 - r0) * (m2 * m2 * m)
}

/// `((1 − η)/(1 + η))²`.
#[inline(always)]
fn r0_of<L: Lanes>(eta: L) -> L {
    let k1 = L::splat(1.0);
    let r = (k1 - eta) / (k1 + eta);
    r * r
}

/// `Ok` when `ok`, else `e`: the checks read as a list of ranges.
fn check(ok: bool, e: MaterialError) -> Result<(), MaterialError> {
    if ok { Ok(()) } else { Err(e) }
}

fn colour_ok(c: Vec3, max: f32) -> bool {
    c.is_finite() && c.cmpge(Vec3::ZERO).all() && c.cmple(Vec3::splat(max)).all()
}

fn texture_ok(t: &Texture<'_>) -> bool {
    match t {
        Texture::Solid(c) => colour_ok(*c, 1.0),
        Texture::Checker { scale, even, odd } => {
            *scale > 0.0 && scale.is_finite() && colour_ok(*even, 1.0) && colour_ok(*odd, 1.0)
        }
        // The texels were validated when the image was decoded.
        Texture::Image(_) => true,
    }
}

fn non_negative(x: f32) -> bool {
    x >= 0.0 && x.is_finite()
}

/// What a smooth BRDF reads at the hit, per lane: `V = −d` and `L = wi`,
/// with `cos_l = n·L` (where it is not positive the BRDF is 0, and the
/// caller replaces what the lane computes).
struct Shading<'h, L: Lanes> {
    hit: &'h SurfaceLanes<L>,
    v: V3<L>,
    wi: V3<L>,
    cos_l: L,
}

impl<L: Lanes> Shading<'_, L> {
    /// The unit shading normal.
    #[inline(always)]
    fn n(&self) -> V3<L> {
        self.hit.n
    }

    /// The albedo `ρ` at the hit, averaged over its footprint.
    #[inline(always)]
    fn albedo(&self, t: &Texture<'_>) -> V3<L> {
        t.filtered_lanes(self.hit.uv, self.hit.p, self.hit.footprint, self.hit.wanted)
    }

    /// The half vector `unit(V + L)` of Blinn and Cook–Torrance.
    #[inline(always)]
    fn half(&self) -> V3<L> {
        (self.v + self.wi).normalize_or_zero()
    }
}

/// The sink of [`Material::content_bytes`]: every value as little-endian
/// bytes, floats as their bits, so the stream is the same on every machine.
struct Feed<'o>(&'o mut dyn FnMut(&[u8]));

impl Feed<'_> {
    fn u32(&mut self, x: u32) {
        (self.0)(&x.to_le_bytes());
    }

    fn f32(&mut self, x: f32) {
        self.u32(x.to_bits());
    }

    fn v3(&mut self, v: Vec3) {
        self.f32(v.x);
        self.f32(v.y);
        self.f32(v.z);
    }

    /// A tag for the kind of texture, then its parameters.
    fn texture(&mut self, t: &Texture<'_>) {
        match t {
            Texture::Solid(c) => {
                self.u32(1);
                self.v3(*c);
            }
            Texture::Checker { scale, even, odd } => {
                self.u32(2);
                self.f32(*scale);
                self.v3(*even);
                self.v3(*odd);
            }
            // The texels are borrowed: the caller hashes the images it owns.
            Texture::Image(_) => self.u32(3),
        }
    }
}

/// A material as its family's code takes it. [`Material::family`] is the
/// one place the variants are taken apart: a new variant fails to compile
/// there until a family takes it, and every method follows from that.
enum Family<'a> {
    Diffuse(Lambertian<'a>),
    Specular(Specular),
    Phong(Phong<'a>),
    Microfacet(CookTorrance<'a>),
    Emissive(DiffuseLight),
}

impl<'a> Material<'a> {
    /// The material's family, with its parameters.
    #[inline]
    fn family(&self) -> Family<'a> {
        match *self {
            Material::Lambertian { albedo } => Family::Diffuse(Lambertian { albedo }),
            Material::Mirror { albedo } => Family::Specular(Specular::Mirror { albedo }),
            Material::Metal { albedo, roughness } => {
                Family::Specular(Specular::Metal { albedo, roughness })
            }
            Material::Dielectric { ior } => Family::Specular(Specular::Dielectric { ior }),
            Material::Phong {
                albedo,
                kd,
                ks,
                exponent,
            } => Family::Phong(Phong::new(Kind::Phong, albedo, kd, ks, exponent)),
            Material::Blinn {
                albedo,
                kd,
                ks,
                exponent,
            } => Family::Phong(Phong::new(Kind::Blinn, albedo, kd, ks, exponent)),
            Material::PhongNormalized {
                albedo,
                kd,
                ks,
                exponent,
            } => Family::Phong(Phong::new(Kind::PhongNormalized, albedo, kd, ks, exponent)),
            Material::BlinnNormalized {
                albedo,
                kd,
                ks,
                exponent,
            } => Family::Phong(Phong::new(Kind::BlinnNormalized, albedo, kd, ks, exponent)),
            Material::CookTorrance {
                albedo,
                kd,
                ks,
                alpha,
                ior,
            } => Family::Microfacet(CookTorrance::new(albedo, kd, ks, alpha, ior)),
            Material::DiffuseLight { emit } => Family::Emissive(DiffuseLight { emit }),
        }
    }

    /// The first word of [`Material::content_bytes`]: never renumber one
    /// (every scene hash would change); a new variant takes the next.
    fn kind_tag(&self) -> u32 {
        match self {
            Material::Lambertian { .. } => 1,
            Material::Mirror { .. } => 2,
            Material::Metal { .. } => 3,
            Material::Dielectric { .. } => 4,
            Material::Phong { .. } => 5,
            Material::Blinn { .. } => 6,
            Material::PhongNormalized { .. } => 7,
            Material::BlinnNormalized { .. } => 8,
            Material::CookTorrance { .. } => 9,
            Material::DiffuseLight { .. } => 10,
        }
    }

    /// Checks every parameter against its documented range.
    ///
    /// ```
    /// use glam::Vec3;
    /// use strata::render::{Material, MaterialError, Texture};
    /// let ok = Material::Lambertian { albedo: Texture::Solid(Vec3::splat(0.5)) };
    /// assert_eq!(ok.validate(), Ok(()));
    /// let bad = Material::Dielectric { ior: -1.5 };
    /// assert_eq!(bad.validate(), Err(MaterialError::Parameter));
    /// ```
    #[inline]
    pub fn validate(&self) -> Result<(), MaterialError> {
        match self.family() {
            Family::Diffuse(m) => m.validate(),
            Family::Specular(m) => m.validate(),
            Family::Phong(m) => m.validate(),
            Family::Microfacet(m) => m.validate(),
            Family::Emissive(m) => m.validate(),
        }
    }

    /// Radiance emitted towards any direction (both sides).
    #[inline]
    #[must_use]
    pub fn emitted(&self) -> Vec3 {
        match self.family() {
            Family::Emissive(m) => m.emit,
            Family::Diffuse(_) | Family::Specular(_) | Family::Phong(_) | Family::Microfacet(_) => {
                Vec3::ZERO
            }
        }
    }

    /// Whether shading reads [`SurfaceHit::uv`] (an image-textured
    /// albedo), so the integrator computes it only then.
    ///
    /// ```
    /// use glam::Vec3;
    /// use strata::render::{Material, Texture};
    /// let m = Material::Lambertian { albedo: Texture::Solid(Vec3::ONE) };
    /// assert!(!m.uses_uv());
    /// ```
    #[inline]
    #[must_use]
    pub fn uses_uv(&self) -> bool {
        match self.family() {
            Family::Diffuse(m) => m.albedo.uses_uv(),
            Family::Phong(m) => m.albedo.uses_uv(),
            Family::Microfacet(m) => m.albedo.uses_uv(),
            Family::Specular(_) | Family::Emissive(_) => false,
        }
    }

    /// Whether this is an emitter.
    #[inline]
    #[must_use]
    pub fn is_light(&self) -> bool {
        match self.family() {
            Family::Emissive(_) => true,
            Family::Diffuse(_) | Family::Specular(_) | Family::Phong(_) | Family::Microfacet(_) => {
                false
            }
        }
    }

    /// Which of [`Material::sample`]'s random inputs it reads: `(u,
    /// u_lobe)`. The integrator skips the dimensions of the others (they
    /// keep their indices), so a value it would not read is never made.
    #[inline]
    pub(crate) fn reads(&self) -> (bool, bool) {
        match self.family() {
            Family::Specular(Specular::Mirror { .. }) => (false, false),
            Family::Specular(Specular::Metal { roughness, .. }) => (roughness != 0.0, false),
            Family::Specular(Specular::Dielectric { .. }) => (false, true),
            Family::Diffuse(_) | Family::Phong(_) | Family::Microfacet(_) => (true, false),
            Family::Emissive(_) => (false, false),
        }
    }

    /// Whether the material has a smooth lobe that [`Material::eval`] can
    /// evaluate (and so takes direct lighting).
    #[inline]
    #[must_use]
    pub fn is_smooth(&self) -> bool {
        match self.family() {
            Family::Diffuse(_) | Family::Phong(_) | Family::Microfacet(_) => true,
            Family::Specular(_) | Family::Emissive(_) => false,
        }
    }

    /// The BRDF `f(V, L)` of a smooth material (0 for the others), for
    /// unit `V = −d` and `L` on the side of `n`.
    #[inline]
    #[must_use]
    pub fn brdf(&self, d: Vec3, hit: &SurfaceHit, wi: Vec3) -> Vec3 {
        self.brdf_lanes(V3::from(d), &hit.into(), V3::from(wi))
            .into()
    }

    /// [`Material::brdf`] over lanes.
    #[inline(always)]
    pub(crate) fn brdf_lanes<L: Lanes>(&self, d: V3<L>, hit: &SurfaceLanes<L>, wi: V3<L>) -> V3<L> {
        let zero = V3::splat(Vec3::ZERO);
        let cos_l = hit.n.dot(wi);
        // Not `cos_l > 0`: a NaN lane goes on to a NaN, which the film drops.
        let above = L::not(cos_l.le(L::splat(0.0)));
        if !L::any(above) {
            return zero;
        }
        let s = Shading {
            hit,
            v: -d,
            wi,
            cos_l,
        };
        let f = match self.family() {
            Family::Diffuse(m) => m.brdf(&s),
            Family::Phong(m) => m.brdf(&s),
            Family::Microfacet(m) => m.brdf(&s),
            // Delta lobes and emitters have no density to evaluate.
            Family::Specular(_) | Family::Emissive(_) => zero,
        };
        V3::select(above, f, zero)
    }

    /// `f(V, L) cos θ` and the density with which [`Material::sample`]
    /// would pick `L` (per steradian): what direct lighting and MIS need.
    /// Both are 0 for specular materials and below the surface.
    #[inline]
    #[must_use]
    pub fn eval(&self, d: Vec3, hit: &SurfaceHit, wi: Vec3) -> (Vec3, f32) {
        let (f, pdf) = self.eval_lanes(V3::from(d), &hit.into(), V3::from(wi));
        (f.into(), pdf)
    }

    /// [`Material::eval`] over lanes.
    #[inline(always)]
    pub(crate) fn eval_lanes<L: Lanes>(
        &self,
        d: V3<L>,
        hit: &SurfaceLanes<L>,
        wi: V3<L>,
    ) -> (V3<L>, L) {
        let (zero, z) = (V3::splat(Vec3::ZERO), L::splat(0.0));
        if !self.is_smooth() {
            return (zero, z);
        }
        let cos = hit.n.dot(wi);
        let above = L::not(cos.le(z));
        if !L::any(above) {
            return (zero, z);
        }
        // Every smooth family samples the cosine hemisphere: pdf = cos θ / π.
        let f = self.brdf_lanes(d, hit, wi) * cos;
        let pdf = cos * L::splat(FRAC_1_PI);
        (V3::select(above, f, zero), L::select(above, pdf, z))
    }

    /// Samples an outgoing direction for a ray of direction `d` at `hit`,
    /// from `u` (2D) and `u_lobe` (1D, the Fresnel choice of glass).
    /// `None` when the ray is absorbed: a light, a fuzzed metal direction
    /// below the surface, or a cosine sample exactly on the rim (pdf 0).
    ///
    /// ```
    /// use glam::{Vec2, Vec3};
    /// use strata::render::{Lobe, Material, SurfaceHit, Texture};
    /// let hit = SurfaceHit {
    ///     p: Vec3::ZERO, n: Vec3::Y, front_face: true, uv: Vec2::ZERO, footprint: Vec3::ZERO,
    /// };
    /// let m = Material::Lambertian { albedo: Texture::Solid(Vec3::splat(0.5)) };
    /// let s = m.sample(-Vec3::Y, &hit, Vec2::new(0.3, 0.6), 0.5).unwrap();
    /// // Cosine sampling a Lambertian: the weight is exactly its albedo.
    /// assert_eq!(s.weight, Vec3::splat(0.5));
    /// assert!(matches!(s.lobe, Lobe::Smooth { .. }) && s.wi.y > 0.0);
    /// ```
    #[inline]
    #[must_use]
    pub fn sample(&self, d: Vec3, hit: &SurfaceHit, u: Vec2, u_lobe: f32) -> Option<BsdfSample> {
        let s = self.sample_lanes(V3::from(d), &hit.into(), (u.x, u.y), u_lobe);
        s.live.then(|| BsdfSample {
            wi: s.wi.into(),
            weight: s.weight.into(),
            lobe: if self.is_smooth() {
                Lobe::Smooth { pdf: s.pdf }
            } else {
                Lobe::Specular
            },
            transmitted: s.transmitted,
        })
    }

    /// [`Material::sample`] over lanes.
    #[inline(always)]
    pub(crate) fn sample_lanes<L: Lanes>(
        &self,
        d: V3<L>,
        hit: &SurfaceLanes<L>,
        u: (L, L),
        u_lobe: L,
    ) -> BsdfLanes<L> {
        // The Lambertian, the commonest material, without the family
        // conversion.
        if let Material::Lambertian { albedo } = self {
            return diffuse::sample_lambertian(albedo, hit, u);
        }
        match self.family() {
            Family::Specular(m) => m.sample(d, hit, u, u_lobe),
            Family::Diffuse(m) => m.sample(hit, u),
            // Every smooth lobe is sampled by the cosine: its BRDF is
            // evaluated at the drawn direction; f cos θ / pdf = π f.
            Family::Phong(_) | Family::Microfacet(_) => {
                diffuse::sample_cosine(hit.n, u, |wi| self.brdf_lanes(d, hit, wi) * L::splat(PI))
            }
            Family::Emissive(_) => BsdfLanes {
                wi: V3::splat(Vec3::ZERO),
                weight: V3::splat(Vec3::ZERO),
                pdf: L::splat(0.0),
                transmitted: L::mask_splat(false),
                live: L::mask_splat(false),
            },
        }
    }

    /// Feeds `out` the material's kind and the exact bits of its
    /// parameters, as little-endian bytes, for content hashes (the runner's
    /// scene hash is built on it, so the stream is stable: it changes only
    /// when a variant is added). An image albedo contributes only its kind:
    /// its texels are borrowed, so the caller hashes the images it owns.
    ///
    /// ```
    /// use strata::render::Material;
    /// let mut bytes = Vec::new();
    /// Material::Dielectric { ior: 1.5 }.content_bytes(|b| bytes.extend_from_slice(b));
    /// assert_eq!(bytes, [4u32.to_le_bytes(), 1.5f32.to_le_bytes()].concat());
    /// ```
    #[inline]
    pub fn content_bytes(&self, mut out: impl FnMut(&[u8])) {
        let out = &mut Feed(&mut out);
        out.u32(self.kind_tag());
        match self.family() {
            Family::Diffuse(m) => m.content(out),
            Family::Specular(m) => m.content(out),
            Family::Phong(m) => m.content(out),
            Family::Microfacet(m) => m.content(out),
            Family::Emissive(m) => m.content(out),
        }
    }
}

/// A hit facing up at the origin, for the family tests.
#[cfg(test)]
const HIT: SurfaceHit = SurfaceHit {
    p: Vec3::ZERO,
    n: Vec3::Y,
    front_face: true,
    uv: Vec2::ZERO,
    footprint: Vec3::ZERO,
};

#[cfg(test)]
mod tests {
    use super::*;

    /// [`Material::reads`] is honest: what `sample` does not read cannot
    /// change its result, for every variant, from many directions.
    #[test]
    fn sample_ignores_the_inputs_it_does_not_read() {
        let t = Texture::Solid(Vec3::new(0.8, 0.5, 0.3));
        let materials = [
            Material::Lambertian { albedo: t },
            Material::Mirror { albedo: Vec3::ONE },
            Material::Metal {
                albedo: Vec3::ONE,
                roughness: 0.3,
            },
            Material::Metal {
                albedo: Vec3::ONE,
                roughness: 0.0,
            },
            Material::Dielectric { ior: 1.5 },
            Material::Phong {
                albedo: t,
                kd: 0.5,
                ks: 0.5,
                exponent: 20.0,
            },
            Material::Blinn {
                albedo: t,
                kd: 0.5,
                ks: 0.5,
                exponent: 20.0,
            },
            Material::PhongNormalized {
                albedo: t,
                kd: 0.5,
                ks: 0.5,
                exponent: 20.0,
            },
            Material::BlinnNormalized {
                albedo: t,
                kd: 0.5,
                ks: 0.5,
                exponent: 20.0,
            },
            Material::CookTorrance {
                albedo: t,
                kd: 0.5,
                ks: 0.5,
                alpha: 0.3,
                ior: 1.5,
            },
            Material::DiffuseLight { emit: Vec3::ONE },
        ];
        let bits = |s: Option<BsdfSample>| {
            s.map(|s| {
                (
                    s.wi.to_array().map(f32::to_bits),
                    s.weight.to_array().map(f32::to_bits),
                )
            })
        };
        let mut read = [false; 2];
        for m in &materials {
            m.validate().unwrap();
            let (reads_u, reads_lobe) = m.reads();
            read[0] |= reads_u;
            read[1] |= reads_lobe;
            for k in 0..64 {
                let a = k as f32 / 64.0;
                let d = Vec3::new(a - 0.5, -1.0, 0.3 * a).normalize();
                let (u, lobe) = (Vec2::new(a, 1.0 - a * a), (k * 37 % 64) as f32 / 64.0);
                let base = bits(m.sample(d, &HIT, u, lobe));
                let other_u = Vec2::new(0.9 - 0.8 * a, a * 0.7);
                let other_lobe = 1.0 - lobe - 1.0 / 128.0;
                let changed_u = base != bits(m.sample(d, &HIT, other_u, lobe));
                let changed_lobe = base != bits(m.sample(d, &HIT, u, other_lobe));
                assert!(reads_u || !changed_u, "{m:?} reads u");
                assert!(reads_lobe || !changed_lobe, "{m:?} reads u_lobe");
            }
        }
        assert_eq!(read, [true, true]);
    }
}
