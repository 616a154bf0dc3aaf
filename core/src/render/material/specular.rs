//! Mirror, metal and glass: each scatters into one direction (metal: a
//! fuzzed one) built on the mirror reflection, weighted by its colour with
//! no cosine and no BRDF, so they are never evaluated and take no direct
//! lighting.

use glam::Vec3;

use super::{BsdfLanes, Feed, MaterialError, SurfaceLanes, check, colour_ok, max0, r0_of, schlick};
use crate::lanes::{Lanes, V3};
use crate::mapping::uniform_sphere;

/// The mirror of `d` about `n`.
#[inline(always)]
fn reflect<L: Lanes>(d: V3<L>, n: V3<L>) -> V3<L> {
    d - n * (L::splat(2.0) * d.dot(n))
}

/// A reflected direction carrying `weight`, live where `live`.
#[inline(always)]
fn reflected<L: Lanes>(wi: V3<L>, weight: Vec3, live: L::Mask) -> BsdfLanes<L> {
    BsdfLanes {
        wi,
        weight: V3::splat(weight),
        pdf: L::splat(0.0),
        transmitted: L::mask_splat(false),
        live,
    }
}

/// The delta (and fuzzed-delta) lobes.
#[derive(Clone, Copy)]
pub(super) enum Specular {
    Mirror { albedo: Vec3 },
    Metal { albedo: Vec3, roughness: f32 },
    Dielectric { ior: f32 },
}

impl Specular {
    pub(super) fn validate(&self) -> Result<(), MaterialError> {
        use MaterialError::{Colour, Parameter};
        match *self {
            Specular::Mirror { albedo } => check(colour_ok(albedo, 1.0), Colour),
            Specular::Metal { albedo, roughness } => {
                check(colour_ok(albedo, 1.0), Colour)?;
                check((0.0..=1.0).contains(&roughness), Parameter)
            }
            Specular::Dielectric { ior } => check(ior > 0.0 && ior.is_finite(), Parameter),
        }
    }

    /// Metal adds `roughness` times a uniform unit vector to the mirror
    /// direction and is absorbed when that points below the surface.
    #[inline(always)]
    pub(super) fn sample<L: Lanes>(
        &self,
        d: V3<L>,
        hit: &SurfaceLanes<L>,
        u: (L, L),
        u_lobe: L,
    ) -> BsdfLanes<L> {
        let n = hit.n;
        let above = |wi: V3<L>| wi.dot(n).gt(L::splat(0.0));
        match *self {
            Specular::Mirror { albedo } => reflected(reflect(d, n), albedo, L::mask_splat(true)),
            // An unfuzzed metal is a coloured mirror: no sphere sample, the
            // same absorption below the surface.
            Specular::Metal {
                albedo,
                roughness: 0.0,
            } => {
                let wi = reflect(d, n).normalize_or_zero();
                reflected(wi, albedo, above(wi))
            }
            Specular::Metal { albedo, roughness } => {
                let fuzzed = reflect(d, n) + uniform_sphere(u.0, u.1) * L::splat(roughness);
                let wi = fuzzed.normalize_or_zero();
                reflected(wi, albedo, above(wi))
            }
            Specular::Dielectric { ior } => refract_or_reflect(d, hit, ior, u_lobe),
        }
    }

    pub(super) fn content(&self, out: &mut Feed<'_>) {
        match *self {
            Specular::Mirror { albedo } => out.v3(albedo),
            Specular::Metal { albedo, roughness } => {
                out.v3(albedo);
                out.f32(roughness);
            }
            Specular::Dielectric { ior } => out.f32(ior),
        }
    }
}

/// Glass: reflects when `u_lobe` falls under Schlick's reflectance (always
/// under total internal reflection), else refracts by Snell's law.
#[inline(always)]
fn refract_or_reflect<L: Lanes>(
    d: V3<L>,
    hit: &SurfaceLanes<L>,
    ior: f32,
    u_lobe: L,
) -> BsdfLanes<L> {
    let (k1, n) = (L::splat(1.0), hit.n);
    let eta = L::select(hit.front_face, L::splat(1.0 / ior), L::splat(ior));
    let cos_i = (-d.dot(n)).clamp_to(f32::NEG_INFINITY, 1.0);
    // (`min(x, 1)` takes a NaN to 1.)
    let cos_i = L::select(cos_i.eq(cos_i), cos_i, k1);
    let sin2_t = eta * eta * (k1 - cos_i * cos_i);
    let cos_t = max0(k1 - sin2_t).sqrt();
    // Schlick's approximation takes the cosine on the side of the
    // thinner medium: the incident one entering, the
    // transmitted one leaving (else it is far too low inside).
    let cos_outside = L::select(eta.le(k1), cos_i, cos_t);
    let reflects = L::or(sin2_t.gt(k1), u_lobe.lt(schlick(cos_outside, r0_of(eta))));
    let refracted = (d * eta + n * (eta * cos_i - cos_t)).normalize();
    BsdfLanes {
        wi: V3::select(reflects, reflect(d, n), refracted),
        weight: V3::splat(Vec3::ONE),
        pdf: L::splat(0.0),
        transmitted: L::not(reflects),
        live: L::mask_splat(true),
    }
}

#[cfg(test)]
mod tests {
    use glam::{Vec2, Vec3};

    use crate::render::material::{HIT, Material, MaterialError, SurfaceHit};

    /// An unfuzzed metal takes its own path (no sphere sample) but scatters
    /// and absorbs as the fuzzed formula does at roughness 0, grazing and
    /// tangent rays included (equal up to the signs of zeros).
    #[test]
    fn unfuzzed_metal_is_the_fuzzed_formula_at_roughness_0() {
        let albedo = Vec3::new(0.9, 0.5, 0.2);
        let m = Material::Metal {
            albedo,
            roughness: 0.0,
        };
        let n = HIT.n;
        let mut absorbed = 0;
        for k in 0..=200 {
            // From straight down to tangent and just past it.
            let a = k as f32 / 200.0 * 1.6;
            let d = Vec3::new(libm::sinf(a), -libm::cosf(a), 0.1 * libm::sinf(a)).normalize();
            for d in [
                d,
                Vec3::new(1.0, 0.0, 0.0),
                Vec3::new(1.0, 1e-8, 0.0).normalize(),
            ] {
                let u = Vec2::new(0.3, 0.8);
                let r = d - n * (2.0 * d.dot(n));
                let wi = (r + crate::mapping::sample_uniform_sphere(u) * 0.0).normalize_or_zero();
                let want = (wi.dot(n) > 0.0).then_some(wi);
                let got = m.sample(d, &HIT, u, 0.0);
                assert_eq!(got.map(|s| s.wi), want, "d = {d}");
                if let Some(s) = got {
                    assert_eq!(s.weight, albedo);
                } else {
                    absorbed += 1;
                }
            }
        }
        assert!(absorbed > 0, "no ray reached the absorbing case");
    }

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
    fn metal_roughness_range() {
        assert_eq!(
            Material::Metal {
                albedo: Vec3::ONE,
                roughness: 1.5
            }
            .validate(),
            Err(MaterialError::Parameter)
        );
    }
}
