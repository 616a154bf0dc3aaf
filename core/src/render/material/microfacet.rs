//! Cook–Torrance with the GGX distribution, Smith's separable shadowing
//! and Schlick's Fresnel on `V·H`, over a diffuse base.

use core::f32::consts::PI;

use super::{Feed, MaterialError, Shading, check, diffuse, max0, r0_of, schlick};
use crate::lanes::{Lanes, V3};
use crate::render::texture::Texture;

/// The GGX normal distribution `D` at `n·H = cos_h`.
#[inline(always)]
fn ggx<L: Lanes>(cos_h: L, alpha: f32) -> L {
    let a2 = alpha * alpha;
    let t = cos_h * cos_h * L::splat(a2 - 1.0) + L::splat(1.0);
    L::splat(a2) / (L::splat(PI) * t * t)
}

/// Smith's G₁ for GGX: `2 / (1 + √(1 + α² tan² θ))`, 0 below the surface.
#[inline(always)]
fn smith_g1<L: Lanes>(cos: L, alpha: f32) -> L {
    let (k1, z) = (L::splat(1.0), L::splat(0.0));
    let c2 = cos * cos;
    let tan2 = max0(k1 - c2) / c2;
    let g = L::splat(2.0) / (k1 + (k1 + L::splat(alpha * alpha) * tan2).sqrt());
    L::select(cos.le(z), z, g)
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
    #[inline(always)]
    pub(super) fn brdf<L: Lanes>(&self, s: &Shading<'_, L>) -> V3<L> {
        let (alpha, z) = (self.alpha, L::splat(0.0));
        let n = s.n();
        let cos_v = n.dot(s.v);
        let h = s.half();
        let cos_h = n.dot(h);
        let g = smith_g1(cos_v, alpha) * smith_g1(s.cos_l, alpha);
        let f = schlick(s.v.dot(h), L::splat(r0_of(self.ior)));
        let spec =
            L::splat(self.ks) * ggx(cos_h, alpha) * g * f / (L::splat(4.0) * cos_v * s.cos_l);
        let spec = L::select(L::and(cos_v.gt(z), cos_h.gt(z)), spec, z);
        diffuse::base(s.albedo(&self.albedo), self.kd) + V3::new(spec, spec, spec)
    }

    pub(super) fn content(&self, out: &mut Feed<'_>) {
        out.texture(&self.albedo);
        for p in [self.kd, self.ks, self.alpha, self.ior] {
            out.f32(p);
        }
    }
}
