//! Materials: the course's models with its maths fixed (COURSE.md §4–5).
//!
//! Conventions: `d` is the incoming ray's unit direction, `n` the unit
//! shading normal turned to face it (`n · d < 0`), `V = −d`, `L = wi` the
//! unit outgoing direction. Every direction is unit length (the course's
//! D6 used raw camera directions of length ≈ 5).
//!
//! Smooth materials (everything diffuse-like or glossy) sample `L` from the
//! cosine-weighted hemisphere around `n` in an [`Onb`] — the course's
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

use core::f32::consts::{FRAC_1_PI, PI};

use glam::{Vec2, Vec3};

use super::texture::Texture;
use crate::mapping::{pdf_cosine_hemisphere, sample_cosine_hemisphere, sample_uniform_sphere};
use crate::onb::Onb;

/// What the integrator knows about the surface point it shades.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct SurfaceHit {
    /// The hit point.
    pub p: Vec3,
    /// Unit shading normal facing the incoming ray.
    pub n: Vec3,
    /// Whether the ray arrived from outside the sphere.
    pub front_face: bool,
    /// The sphere's `(u, v)` at the point; the integrator leaves it zero
    /// when the material does not read it ([`Material::uses_uv`]).
    pub uv: Vec2,
    /// Half-widths, per world axis, of the box textures are averaged over
    /// ([`Texture::filtered`]); zero for point sampling.
    pub footprint: Vec3,
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
#[inline]
fn schlick(cosine: f32, r0: f32) -> f32 {
    let m = (1.0 - cosine).clamp(0.0, 1.0);
    let m2 = m * m;
    r0 + (1.0 - r0) * (m2 * m2 * m)
}

/// `((1 − η)/(1 + η))²`.
#[inline]
fn r0_of(eta: f32) -> f32 {
    let r = (1.0 - eta) / (1.0 + eta);
    r * r
}

/// The mirror of `d` about `n`.
#[inline]
fn reflect(d: Vec3, n: Vec3) -> Vec3 {
    d - n * (2.0 * d.dot(n))
}

/// `max(0, x)^α` (`0^0` is 1, as `powf` has it).
#[inline]
fn lobe(x: f32, alpha: f32) -> f32 {
    libm::powf(x.max(0.0), alpha)
}

/// Smith's G₁ for GGX: `2 / (1 + √(1 + α² tan² θ))`, 0 below the surface.
#[inline]
fn smith_g1(cos: f32, alpha: f32) -> f32 {
    if cos <= 0.0 {
        return 0.0;
    }
    let c2 = cos * cos;
    let tan2 = (1.0 - c2).max(0.0) / c2;
    2.0 / (1.0 + libm::sqrtf(1.0 + alpha * alpha * tan2))
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

impl Material<'_> {
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
        use MaterialError::*;
        let check = |ok: bool, e| if ok { Ok(()) } else { Err(e) };
        match self {
            Material::Lambertian { albedo } => check(texture_ok(albedo), Colour),
            Material::Mirror { albedo } => check(colour_ok(*albedo, 1.0), Colour),
            Material::Metal { albedo, roughness } => {
                check(colour_ok(*albedo, 1.0), Colour)?;
                check((0.0..=1.0).contains(roughness), Parameter)
            }
            Material::Dielectric { ior } => check(*ior > 0.0 && ior.is_finite(), Parameter),
            Material::Phong {
                albedo,
                kd,
                ks,
                exponent,
            }
            | Material::Blinn {
                albedo,
                kd,
                ks,
                exponent,
            } => {
                check(texture_ok(albedo), Colour)?;
                check(
                    non_negative(*kd) && non_negative(*ks) && non_negative(*exponent),
                    Parameter,
                )
            }
            Material::PhongNormalized {
                albedo,
                kd,
                ks,
                exponent,
            }
            | Material::BlinnNormalized {
                albedo,
                kd,
                ks,
                exponent,
            } => {
                check(texture_ok(albedo), Colour)?;
                check(
                    non_negative(*kd) && non_negative(*ks) && non_negative(*exponent),
                    Parameter,
                )?;
                check(kd + ks <= 1.0, Energy)
            }
            Material::CookTorrance {
                albedo,
                kd,
                ks,
                alpha,
                ior,
            } => {
                check(texture_ok(albedo), Colour)?;
                let ok = non_negative(*kd)
                    && non_negative(*ks)
                    && *alpha > 0.0
                    && *alpha <= 1.0
                    && *ior > 0.0
                    && ior.is_finite();
                check(ok, Parameter)
            }
            Material::DiffuseLight { emit } => check(colour_ok(*emit, f32::MAX), Colour),
        }
    }

    /// Radiance emitted towards any direction (both sides).
    #[inline]
    #[must_use]
    pub fn emitted(&self) -> Vec3 {
        match self {
            Material::DiffuseLight { emit } => *emit,
            Material::Lambertian { .. }
            | Material::Mirror { .. }
            | Material::Metal { .. }
            | Material::Dielectric { .. }
            | Material::Phong { .. }
            | Material::Blinn { .. }
            | Material::PhongNormalized { .. }
            | Material::BlinnNormalized { .. }
            | Material::CookTorrance { .. } => Vec3::ZERO,
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
        match self {
            Material::Lambertian { albedo }
            | Material::Phong { albedo, .. }
            | Material::Blinn { albedo, .. }
            | Material::PhongNormalized { albedo, .. }
            | Material::BlinnNormalized { albedo, .. }
            | Material::CookTorrance { albedo, .. } => albedo.uses_uv(),
            Material::Mirror { .. }
            | Material::Metal { .. }
            | Material::Dielectric { .. }
            | Material::DiffuseLight { .. } => false,
        }
    }

    /// Whether this is an emitter.
    #[inline]
    #[must_use]
    pub fn is_light(&self) -> bool {
        matches!(self, Material::DiffuseLight { .. })
    }

    /// Whether the material has a smooth lobe that [`Material::eval`] can
    /// evaluate (and so takes direct lighting).
    #[inline]
    #[must_use]
    pub fn is_smooth(&self) -> bool {
        match self {
            Material::Lambertian { .. }
            | Material::Phong { .. }
            | Material::Blinn { .. }
            | Material::PhongNormalized { .. }
            | Material::BlinnNormalized { .. }
            | Material::CookTorrance { .. } => true,
            Material::Mirror { .. }
            | Material::Metal { .. }
            | Material::Dielectric { .. }
            | Material::DiffuseLight { .. } => false,
        }
    }

    /// The BRDF `f(V, L)` of a smooth material (0 for the others), for
    /// unit `V = −d` and `L` on the side of `n`.
    #[inline]
    #[must_use]
    pub fn brdf(&self, d: Vec3, hit: &SurfaceHit, wi: Vec3) -> Vec3 {
        let n = hit.n;
        let v = -d;
        let rho = |t: &Texture<'_>| t.filtered(hit.uv, hit.p, hit.footprint);
        let cos_l = n.dot(wi);
        if cos_l <= 0.0 {
            return Vec3::ZERO;
        }
        let half = || (v + wi).normalize_or_zero();
        let mirror_of_l = || n * (2.0 * cos_l) - wi;
        match self {
            Material::Lambertian { albedo } => rho(albedo) * FRAC_1_PI,
            Material::Phong {
                albedo,
                kd,
                ks,
                exponent,
            } => rho(albedo) * (kd * FRAC_1_PI + ks * lobe(mirror_of_l().dot(v), *exponent)),
            Material::Blinn {
                albedo,
                kd,
                ks,
                exponent,
            } => rho(albedo) * (kd * FRAC_1_PI + ks * lobe(n.dot(half()), *exponent)),
            Material::PhongNormalized {
                albedo,
                kd,
                ks,
                exponent,
            } => {
                let norm = (exponent + 2.0) * (0.5 * FRAC_1_PI);
                rho(albedo) * (kd * FRAC_1_PI)
                    + Vec3::splat(ks * norm * lobe(mirror_of_l().dot(v), *exponent))
            }
            Material::BlinnNormalized {
                albedo,
                kd,
                ks,
                exponent,
            } => {
                // Exact for normal incidence (the common (α+8)/(8π) is an
                // approximation that exceeds albedo 1 at low exponents).
                let a = *exponent;
                let norm = (a + 2.0) * (a + 4.0) / (8.0 * PI * (libm::exp2f(-0.5 * a) + a));
                rho(albedo) * (kd * FRAC_1_PI)
                    + Vec3::splat(ks * norm * lobe(n.dot(half()), *exponent))
            }
            Material::CookTorrance {
                albedo,
                kd,
                ks,
                alpha,
                ior,
            } => {
                let cos_v = n.dot(v);
                let h = half();
                let cos_h = n.dot(h);
                let mut spec = 0.0;
                if cos_v > 0.0 && cos_h > 0.0 {
                    let a2 = alpha * alpha;
                    let t = cos_h * cos_h * (a2 - 1.0) + 1.0;
                    let dist = a2 / (PI * t * t);
                    let g = smith_g1(cos_v, *alpha) * smith_g1(cos_l, *alpha);
                    let f = schlick(v.dot(h), r0_of(*ior));
                    spec = ks * dist * g * f / (4.0 * cos_v * cos_l);
                }
                rho(albedo) * (kd * FRAC_1_PI) + Vec3::splat(spec)
            }
            // Delta lobes and emitters have no density to evaluate.
            Material::Mirror { .. }
            | Material::Metal { .. }
            | Material::Dielectric { .. }
            | Material::DiffuseLight { .. } => Vec3::ZERO,
        }
    }

    /// `f(V, L) cos θ` and the density with which [`Material::sample`]
    /// would pick `L` (per steradian): what direct lighting and MIS need.
    /// Both are 0 for specular materials and below the surface.
    #[inline]
    #[must_use]
    pub fn eval(&self, d: Vec3, hit: &SurfaceHit, wi: Vec3) -> (Vec3, f32) {
        if !self.is_smooth() {
            return (Vec3::ZERO, 0.0);
        }
        let cos = hit.n.dot(wi);
        if cos <= 0.0 {
            return (Vec3::ZERO, 0.0);
        }
        (self.brdf(d, hit, wi) * cos, cos * FRAC_1_PI)
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
    /// assert!((s.weight - Vec3::splat(0.5)).abs().max_element() < 1e-6);
    /// assert!(matches!(s.lobe, Lobe::Smooth { .. }) && s.wi.y > 0.0);
    /// ```
    #[inline]
    #[must_use]
    pub fn sample(&self, d: Vec3, hit: &SurfaceHit, u: Vec2, u_lobe: f32) -> Option<BsdfSample> {
        let n = hit.n;
        match self {
            Material::DiffuseLight { .. } => None,
            Material::Mirror { albedo } => Some(BsdfSample {
                wi: reflect(d, n),
                weight: *albedo,
                lobe: Lobe::Specular,
                transmitted: false,
            }),
            Material::Metal { albedo, roughness } => {
                let fuzzed = reflect(d, n) + sample_uniform_sphere(u) * *roughness;
                let wi = fuzzed.normalize_or_zero();
                (wi.dot(n) > 0.0).then_some(BsdfSample {
                    wi,
                    weight: *albedo,
                    lobe: Lobe::Specular,
                    transmitted: false,
                })
            }
            Material::Dielectric { ior } => {
                let eta = if hit.front_face { 1.0 / ior } else { *ior };
                let cos_i = (-d.dot(n)).min(1.0);
                let sin2_t = eta * eta * (1.0 - cos_i * cos_i);
                let cos_t = libm::sqrtf((1.0 - sin2_t).max(0.0));
                // Schlick's approximation takes the cosine on the side of the
                // thinner medium: the incident one entering, the
                // transmitted one leaving (else it is far too low inside).
                let cos_outside = if eta <= 1.0 { cos_i } else { cos_t };
                let reflects = sin2_t > 1.0 || u_lobe < schlick(cos_outside, r0_of(eta));
                let wi = if reflects {
                    reflect(d, n)
                } else {
                    (d * eta + n * (eta * cos_i - cos_t)).normalize()
                };
                Some(BsdfSample {
                    wi,
                    weight: Vec3::ONE,
                    lobe: Lobe::Specular,
                    transmitted: !reflects,
                })
            }
            // Every smooth lobe is sampled by the cosine: its BRDF is
            // evaluated at the drawn direction.
            Material::Lambertian { .. }
            | Material::Phong { .. }
            | Material::Blinn { .. }
            | Material::PhongNormalized { .. }
            | Material::BlinnNormalized { .. }
            | Material::CookTorrance { .. } => {
                let local = sample_cosine_hemisphere(u);
                let pdf = pdf_cosine_hemisphere(local);
                if pdf <= 0.0 {
                    return None;
                }
                let wi = Onb::from_normal(n).to_world(local);
                // f cos θ / pdf with pdf = cos θ / π.
                let weight = self.brdf(d, hit, wi) * PI;
                Some(BsdfSample {
                    wi,
                    weight,
                    lobe: Lobe::Smooth { pdf },
                    transmitted: false,
                })
            }
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    const HIT: SurfaceHit = SurfaceHit {
        p: Vec3::ZERO,
        n: Vec3::Y,
        front_face: true,
        uv: Vec2::ZERO,
        footprint: Vec3::ZERO,
    };

    #[test]
    fn metal_directions_are_unit() {
        let m = Material::Metal {
            albedo: Vec3::ONE,
            roughness: 1.0,
        };
        let d = Vec3::new(0.6, -0.8, 0.0);
        for k in 0..100 {
            let u = Vec2::new(k as f32 / 100.0, (k * 37 % 100) as f32 / 100.0);
            if let Some(s) = m.sample(d, &HIT, u, 0.0) {
                assert!((s.wi.length() - 1.0).abs() < 1e-6 && s.wi.y > 0.0);
            }
        }
    }

    /// Glass reflects with Schlick's probability on the air-side cosine,
    /// entering and leaving alike.
    #[test]
    fn glass_reflects_with_schlick_probability() {
        let g = Material::Dielectric { ior: 1.5 };
        let r0 = (0.5f32 / 2.5).powi(2);
        let schlick = |c: f32| r0 + (1.0 - r0) * (1.0 - c).powi(5);
        // Entering at 60°: the air-side cosine is the incident one.
        let d = Vec3::new(0.866_025_4, -0.5, 0.0);
        let want = schlick(0.5);
        let frac = |d: Vec3, hit: &SurfaceHit| {
            let n = 10_000;
            (0..n)
                .filter(|&k| {
                    !g.sample(d, hit, Vec2::ZERO, (k as f32 + 0.5) / n as f32)
                        .unwrap()
                        .transmitted
                })
                .count() as f32
                / n as f32
        };
        assert!(
            (frac(d, &HIT) - want).abs() < 2e-4,
            "{} vs {want}",
            frac(d, &HIT)
        );
        // Leaving at 30° inside: the ray refracts to 48.6° in air.
        let inside = SurfaceHit {
            front_face: false,
            ..HIT
        };
        let d = Vec3::new(0.5, -0.866_025_4, 0.0);
        let cos_t = (1.0f32 - (1.5f32 * 0.5).powi(2)).sqrt();
        let want = schlick(cos_t);
        assert!(
            (frac(d, &inside) - want).abs() < 2e-4,
            "{} vs {want}",
            frac(d, &inside)
        );
    }

    #[test]
    fn mirror_reflects() {
        let m = Material::Mirror {
            albedo: Vec3::splat(0.9),
        };
        let d = Vec3::new(1.0, -1.0, 0.0).normalize();
        let s = m.sample(d, &HIT, Vec2::ZERO, 0.0).unwrap();
        assert!((s.wi - Vec3::new(1.0, 1.0, 0.0).normalize()).length() < 1e-6);
        assert_eq!(s.weight, Vec3::splat(0.9));
        assert_eq!(m.eval(d, &HIT, s.wi), (Vec3::ZERO, 0.0));
    }

    #[test]
    fn glass_refracts_by_snell_and_reflects_totally() {
        let g = Material::Dielectric { ior: 1.5 };
        let d = Vec3::new(0.6, -0.8, 0.0);
        // u_lobe near 1: refract (Schlick's reflectance is small here).
        let s = g.sample(d, &HIT, Vec2::ZERO, 0.99).unwrap();
        assert!(s.transmitted && s.wi.y < 0.0);
        let sin_t = s.wi.x;
        assert!((sin_t - 0.6 / 1.5).abs() < 1e-6, "{sin_t}");
        // From inside at a grazing angle: total internal reflection.
        let inside = SurfaceHit {
            front_face: false,
            ..HIT
        };
        let s = g
            .sample(Vec3::new(0.9, -0.435_889_9, 0.0), &inside, Vec2::ZERO, 0.99)
            .unwrap();
        assert!(!s.transmitted && s.wi.y > 0.0);
    }

    #[test]
    fn validation_ranges() {
        let t = Texture::Solid(Vec3::splat(0.5));
        let blinn = |kd, ks, exponent| Material::BlinnNormalized {
            albedo: t,
            kd,
            ks,
            exponent,
        };
        assert_eq!(blinn(0.5, 0.5, 10.0).validate(), Ok(()));
        assert_eq!(blinn(0.6, 0.5, 10.0).validate(), Err(MaterialError::Energy));
        assert_eq!(
            blinn(0.5, 0.2, f32::NAN).validate(),
            Err(MaterialError::Parameter)
        );
        // The course's unnormalised lobe is allowed kd + ks > 1.
        let course = Material::Blinn {
            albedo: t,
            kd: 0.5,
            ks: 0.6,
            exponent: 8.0,
        };
        assert_eq!(course.validate(), Ok(()));
        let hot = Material::Lambertian {
            albedo: Texture::Solid(Vec3::splat(1.5)),
        };
        assert_eq!(hot.validate(), Err(MaterialError::Colour));
        let light = Material::DiffuseLight {
            emit: Vec3::splat(40.0),
        };
        assert_eq!(light.validate(), Ok(()));
        let bad_light = Material::DiffuseLight {
            emit: Vec3::new(1.0, f32::NAN, 1.0),
        };
        assert_eq!(bad_light.validate(), Err(MaterialError::Colour));
        assert_eq!(
            Material::Metal {
                albedo: Vec3::ONE,
                roughness: 1.5
            }
            .validate(),
            Err(MaterialError::Parameter)
        );
        let checker = Texture::Checker {
            scale: 0.0,
            even: Vec3::ZERO,
            odd: Vec3::ONE,
        };
        assert_eq!(
            Material::Lambertian { albedo: checker }.validate(),
            Err(MaterialError::Colour)
        );
    }

    #[test]
    fn lights_do_not_scatter() {
        let l = Material::DiffuseLight { emit: Vec3::ONE };
        assert!(l.sample(-Vec3::Y, &HIT, Vec2::splat(0.5), 0.5).is_none());
        assert_eq!(l.emitted(), Vec3::ONE);
        assert!(l.is_light() && !l.is_smooth());
    }
}
