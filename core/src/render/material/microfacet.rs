//! Cook–Torrance with the GGX distribution, Smith's separable shadowing
//! and Schlick's Fresnel on `V·H`, over a diffuse base.

use core::f32::consts::PI;

use glam::Vec3;

use super::{Feed, MaterialError, Shading, check, diffuse, r0_of, schlick};
use crate::render::texture::Texture;

/// The GGX normal distribution `D` at `n·H = cos_h`.
#[inline]
fn ggx(cos_h: f32, alpha: f32) -> f32 {
    let a2 = alpha * alpha;
    let t = cos_h * cos_h * (a2 - 1.0) + 1.0;
    a2 / (PI * t * t)
}

/// Smith's G₁ for GGX: `2 / (1 + √(1 + α² tan² θ))`, 0 below the surface.
#[inline]
fn smith_g1(cos: f32, alpha: f32) -> f32 {
    if cos <= 0.0 {
        return 0.0;
    }
    let c2 = cos * cos;
    let tan2 = (1.0 - c2).max(0.0) / c2;
    2.0 / (1.0 + crate::float::sqrtf(1.0 + alpha * alpha * tan2))
}

/// Cook–Torrance's parameters.
#[derive(Clone, Copy)]
pub(super) struct CookTorrance<'a> {
    pub(super) albedo: Texture<'a>,
    kd: f32,
    ks: f32,
    alpha: f32,
    ior: f32,
}

impl<'a> CookTorrance<'a> {
    pub(super) fn new(albedo: Texture<'a>, kd: f32, ks: f32, alpha: f32, ior: f32) -> Self {
        CookTorrance {
            albedo,
            kd,
            ks,
            alpha,
            ior,
        }
    }

    pub(super) fn validate(&self) -> Result<(), MaterialError> {
        let (alpha, ior) = (self.alpha, self.ior);
        diffuse::validate_base(&self.albedo, self.kd, self.ks)?;
        let ok = alpha > 0.0 && alpha <= 1.0 && ior > 0.0 && ior.is_finite();
        check(ok, MaterialError::Parameter)
    }

    /// `ρ kd/π + ks D G₁(V) G₁(L) F / (4 (n·V)(n·L))`, the specular term 0
    /// when `V` or `H` is below the surface.
    #[inline]
    pub(super) fn brdf(&self, s: &Shading<'_>) -> Vec3 {
        let alpha = self.alpha;
        let n = s.n();
        let cos_v = n.dot(s.v);
        let h = s.half();
        let cos_h = n.dot(h);
        let mut spec = 0.0;
        if cos_v > 0.0 && cos_h > 0.0 {
            let g = smith_g1(cos_v, alpha) * smith_g1(s.cos_l, alpha);
            let f = schlick(s.v.dot(h), r0_of(self.ior));
            spec = self.ks * ggx(cos_h, alpha) * g * f / (4.0 * cos_v * s.cos_l);
        }
        diffuse::base(s.albedo(&self.albedo), self.kd) + Vec3::splat(spec)
    }

    pub(super) fn content(&self, out: &mut Feed<'_>) {
        out.texture(&self.albedo);
        for p in [self.kd, self.ks, self.alpha, self.ior] {
            out.f32(p);
        }
    }
}
