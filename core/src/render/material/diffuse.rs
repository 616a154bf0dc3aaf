//! The Lambertian, `f = ρ / π`, and what the other smooth families take
//! from it: the `ρ kd/π` base under their lobes and the cosine-hemisphere
//! sampler, exact for the Lambertian and unbiased for the glossy lobes.

use core::f32::consts::FRAC_1_PI;

use glam::Vec3;

use super::{
    BsdfLanes, Feed, MaterialError, Shading, SurfaceLanes, check, non_negative, texture_ok,
};
use crate::lanes::{Lanes, V3};
use crate::mapping::{cosine_hemisphere, cosine_hemisphere_pdf};
use crate::onb::OnbLanes;
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

    #[inline(always)]
    pub(super) fn brdf<L: Lanes>(&self, s: &Shading<'_, L>) -> V3<L> {
        s.albedo(&self.albedo) * L::splat(FRAC_1_PI)
    }

    /// A cosine sample, whose weight `f cos θ / pdf` is the albedo itself:
    /// taken as it is, not through `ρ/π · π` (0 below the surface, as the
    /// BRDF is: only a degenerate normal, zero or NaN, gets there).
    #[inline(always)]
    pub(super) fn sample<L: Lanes>(&self, hit: &SurfaceLanes<L>, u: (L, L)) -> BsdfLanes<L> {
        sample_lambertian(&self.albedo, hit, u)
    }

    pub(super) fn content(&self, out: &mut Feed<'_>) {
        out.texture(&self.albedo);
    }
}

/// [`Lambertian::sample`] from the albedo alone.
#[inline(always)]
pub(super) fn sample_lambertian<L: Lanes>(
    albedo: &Texture<'_>,
    hit: &SurfaceLanes<L>,
    u: (L, L),
) -> BsdfLanes<L> {
    let rho = albedo.filtered_lanes(hit.uv, hit.p, hit.footprint, hit.wanted);
    sample_cosine(hit.n, u, |wi| {
        V3::select(hit.n.dot(wi).gt(L::splat(0.0)), rho, V3::splat(Vec3::ZERO))
    })
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
#[inline(always)]
pub(super) fn base<L: Lanes>(rho: V3<L>, kd: f32) -> V3<L> {
    rho * L::splat(kd * FRAC_1_PI)
}

/// Draws `L` from the cosine hemisphere around `n` and weights it by
/// `f cos θ / pdf = π f`, with `weight` giving that at the drawn
/// direction; not live on the rim, where the density is 0.
#[inline(always)]
pub(super) fn sample_cosine<L: Lanes>(
    n: V3<L>,
    u: (L, L),
    weight: impl FnOnce(V3<L>) -> V3<L>,
) -> BsdfLanes<L> {
    let local = cosine_hemisphere(u.0, u.1);
    let pdf = cosine_hemisphere_pdf(local);
    let wi = OnbLanes::from_normal(n).to_world(local);
    let weight = weight(wi);
    BsdfLanes {
        wi,
        weight,
        pdf,
        transmitted: L::mask_splat(false),
        live: L::not(pdf.le(L::splat(0.0))),
    }
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
