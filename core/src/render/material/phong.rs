//! Phong's and Blinn's lobes over a diffuse base, each in the course's
//! unnormalised form and an energy-conserving one. The four differ only in
//! the lobe's cosine (`R·V` or `n·H`) and its normalisation, so they share
//! one evaluation.

use core::f32::consts::{FRAC_1_PI, PI};

use super::{Feed, MaterialError, Shading, check, diffuse, max0, non_negative};
use crate::lanes::{Lanes, V3};
use crate::render::texture::Texture;

/// Which of the four lobes.
#[derive(Clone, Copy)]
pub(super) enum Kind {
    Phong,
    Blinn,
    PhongNormalized,
    BlinnNormalized,
}

impl Kind {
    /// The cosine the lobe raises to the exponent: `R·V` with `R` the
    /// mirror of `L` about `n`, or `n·H`.
    #[inline(always)]
    fn cosine<L: Lanes>(self, s: &Shading<'_, L>) -> L {
        match self {
            Kind::Phong | Kind::PhongNormalized => {
                (s.n() * (L::splat(2.0) * s.cos_l) - s.wi).dot(s.v)
            }
            Kind::Blinn | Kind::BlinnNormalized => s.n().dot(s.half()),
        }
    }

    /// The factor that makes the lobe conserve energy; `None` for the
    /// course's unnormalised lobes.
    #[inline]
    fn normalisation(self, exponent: f32) -> Option<f32> {
        match self {
            Kind::Phong | Kind::Blinn => None,
            Kind::PhongNormalized => Some((exponent + 2.0) * (0.5 * FRAC_1_PI)),
            // Exact for normal incidence (the common (α+8)/(8π) is an
            // approximation that exceeds albedo 1 at low exponents).
            Kind::BlinnNormalized => {
                let a = exponent;
                Some((a + 2.0) * (a + 4.0) / (8.0 * PI * (crate::pow::exp2(-0.5 * a) + a)))
            }
        }
    }
}

/// `max(0, x)^α` (`0^0` is 1, as `powf` has it), by the plain-`f32`
/// power of `crate::pow` (within about 10⁻⁶ of `powf`).
#[inline(always)]
fn lobe<L: Lanes>(x: L, alpha: f32) -> L {
    crate::pow::pow_nonneg(max0(x), L::splat(alpha))
}

/// One of the four lobes with its parameters.
#[derive(Clone, Copy)]
pub(super) struct Phong<'a> {
    kind: Kind,
    pub(super) albedo: Texture<'a>,
    kd: f32,
    ks: f32,
    exponent: f32,
}

impl<'a> Phong<'a> {
    pub(super) fn new(kind: Kind, albedo: Texture<'a>, kd: f32, ks: f32, exponent: f32) -> Self {
        Phong {
            kind,
            albedo,
            kd,
            ks,
            exponent,
        }
    }

    pub(super) fn validate(&self) -> Result<(), MaterialError> {
        diffuse::validate_base(&self.albedo, self.kd, self.ks)?;
        check(non_negative(self.exponent), MaterialError::Parameter)?;
        match self.kind {
            // The course's lobes may reflect more than they receive.
            Kind::Phong | Kind::Blinn => Ok(()),
            Kind::PhongNormalized | Kind::BlinnNormalized => {
                check(self.kd + self.ks <= 1.0, MaterialError::Energy)
            }
        }
    }

    /// The course's lobes tint the specular term with `ρ`; the normalised
    /// ones keep it white.
    #[inline(always)]
    pub(super) fn brdf<L: Lanes>(&self, s: &Shading<'_, L>) -> V3<L> {
        let (kd, ks, exponent) = (self.kd, self.ks, self.exponent);
        let rho = s.albedo(&self.albedo);
        let x = self.kind.cosine(s);
        match self.kind.normalisation(exponent) {
            None => rho * (L::splat(kd * FRAC_1_PI) + L::splat(ks) * lobe(x, exponent)),
            Some(norm) => {
                let spec = L::splat(ks * norm) * lobe(x, exponent);
                diffuse::base(rho, kd) + V3::new(spec, spec, spec)
            }
        }
    }

    pub(super) fn content(&self, out: &mut Feed<'_>) {
        out.texture(&self.albedo);
        for p in [self.kd, self.ks, self.exponent] {
            out.f32(p);
        }
    }
}

#[cfg(test)]
mod tests {
    use glam::Vec3;

    use crate::render::material::{Material, MaterialError};
    use crate::render::texture::Texture;

    #[test]
    fn weight_and_energy_ranges() {
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
    }
}
