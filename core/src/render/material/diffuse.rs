//! The Lambertian, `f = ρ / π`, and what the other smooth families take
//! from it: the `ρ kd/π` base under their lobes and the cosine-hemisphere
//! sampler, exact for the Lambertian and unbiased for the glossy lobes.

use core::f32::consts::FRAC_1_PI;

use glam::{Vec2, Vec3};

use super::{
    BsdfSample, Feed, Lobe, MaterialError, Shading, SurfaceHit, check, non_negative, texture_ok,
};
use crate::mapping::{pdf_cosine_hemisphere, sample_cosine_hemisphere};
use crate::onb::Onb;
use crate::render::texture::Texture;

/// Ideal diffuse reflection.
#[derive(Clone, Copy)]
pub(super) struct Lambertian<'a> {
    pub(super) albedo: Texture<'a>,
}

impl Lambertian<'_> {
    pub(super) fn validate(&self) -> Result<(), MaterialError> {
        check(texture_ok(&self.albedo), MaterialError::Colour)
    }

    #[inline]
    pub(super) fn brdf(&self, s: &Shading<'_>) -> Vec3 {
        s.albedo(&self.albedo) * FRAC_1_PI
    }

    /// A cosine sample, whose weight `f cos θ / pdf` is the albedo itself:
    /// taken as it is, not through `ρ/π · π` (0 below the surface, as the
    /// BRDF is: only a degenerate normal, zero or NaN, gets there).
    #[inline]
    pub(super) fn sample(&self, hit: &SurfaceHit, u: Vec2) -> Option<BsdfSample> {
        sample_lambertian(&self.albedo, hit, u)
    }

    pub(super) fn content(&self, out: &mut Feed<'_>) {
        out.texture(&self.albedo);
    }
}

/// [`Lambertian::sample`] from the albedo alone.
#[inline(always)]
pub(super) fn sample_lambertian(
    albedo: &Texture<'_>,
    hit: &SurfaceHit,
    u: Vec2,
) -> Option<BsdfSample> {
    let rho = albedo.filtered(hit.uv, hit.p, hit.footprint);
    sample_cosine(
        hit.n,
        u,
        |wi| {
            if hit.n.dot(wi) > 0.0 { rho } else { Vec3::ZERO }
        },
    )
}

/// The checks of a diffuse base under a lobe: its colour, then both
/// weights `≥ 0`.
pub(super) fn validate_base(albedo: &Texture<'_>, kd: f32, ks: f32) -> Result<(), MaterialError> {
    check(texture_ok(albedo), MaterialError::Colour)?;
    check(
        non_negative(kd) && non_negative(ks),
        MaterialError::Parameter,
    )
}

/// `ρ kd/π`: the diffuse part of a lobe that adds a white specular term.
#[inline]
pub(super) fn base(rho: Vec3, kd: f32) -> Vec3 {
    rho * (kd * FRAC_1_PI)
}

/// Draws `L` from the cosine hemisphere around `n` and weights it by
/// `f cos θ / pdf = π f`, with `weight` giving that at the drawn
/// direction; `None` on the rim, where the density is 0.
#[inline]
pub(super) fn sample_cosine(
    n: Vec3,
    u: Vec2,
    weight: impl FnOnce(Vec3) -> Vec3,
) -> Option<BsdfSample> {
    let local = sample_cosine_hemisphere(u);
    let pdf = pdf_cosine_hemisphere(local);
    if pdf <= 0.0 {
        return None;
    }
    let wi = Onb::from_normal(n).to_world(local);
    let weight = weight(wi);
    Some(BsdfSample {
        wi,
        weight,
        lobe: Lobe::Smooth { pdf },
        transmitted: false,
    })
}

#[cfg(test)]
mod tests {
    use glam::Vec3;

    use crate::render::material::{Material, MaterialError};
    use crate::render::texture::Texture;

    #[test]
    fn albedo_ranges() {
        let hot = Material::Lambertian {
            albedo: Texture::Solid(Vec3::splat(1.5)),
        };
        assert_eq!(hot.validate(), Err(MaterialError::Colour));
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
}
