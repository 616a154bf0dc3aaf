//! χ² goodness-of-fit of every mapping against its own pdf: 10⁶ samples
//! from a fixed-seed PCG32, α = 1 % across the whole file with a Šidák
//! correction (see `support/chi2.rs`). Each test also checks that the pdf
//! integrates to 1 over its domain.

use crate::support::chi2::{Chi2, Domain, chi2_sf, gamma_q};
use glam::{UVec2, Vec2, Vec3};
use strata::filter::{FilterKind, PixelFilter};
use strata::mapping::{self, Cone, rejection};
use strata::rng::{Pcg32, STREAM, next_f32};
use strata::{Onb, Sampler, Stratified};

fn v3(w: Vec3) -> [f64; 3] {
    [w.x as f64, w.y as f64, w.z as f64]
}
fn v2(p: Vec2) -> [f64; 3] {
    [p.x as f64, p.y as f64, 0.0]
}
fn w3(p: [f64; 3]) -> Vec3 {
    Vec3::new(p[0] as f32, p[1] as f32, p[2] as f32)
}
fn w2(p: [f64; 3]) -> Vec2 {
    Vec2::new(p[0] as f32, p[1] as f32)
}
fn uniform(rng: &mut Pcg32) -> Vec2 {
    Vec2::new(next_f32(rng), next_f32(rng))
}

fn uniform3(rng: &mut Pcg32) -> Vec3 {
    Vec3::new(next_f32(rng), next_f32(rng), next_f32(rng))
}

/// A ball point as `(|p|³, (z/|p| + 1)/2)` and as `(|p|³, φ / 2π)`: for a
/// uniform ball, each pair is uniform on the unit square.
fn ball_params(p: Vec3) -> ([f64; 3], [f64; 3]) {
    let q = v3(p);
    let r = (q[0] * q[0] + q[1] * q[1] + q[2] * q[2]).sqrt();
    let z = if r > 0.0 { q[2] / r } else { 0.0 };
    let phi = q[1].atan2(q[0]).rem_euclid(std::f64::consts::TAU);
    (
        [r * r * r, (z + 1.0) / 2.0, 0.0],
        [r * r * r, phi / std::f64::consts::TAU, 0.0],
    )
}

/// The density of `ball_params`' squares that `pdf_uniform_ball` claims:
/// its value at a point of that radius, times the ball's volume.
fn ball_density(p: [f64; 3]) -> f64 {
    let r = p[0].max(0.0).cbrt() as f32;
    mapping::pdf_uniform_ball(Vec3::new(0.0, 0.0, r)) as f64 * 4.0 / 3.0 * std::f64::consts::PI
}

const SPHERE_RES: (usize, usize) = (51, 101);
const DISK_RES: (usize, usize) = (51, 101);
const CONE_COS: f32 = 0.6;
const WIDE_CONE_COS: f32 = -0.3;
/// sin²(10⁻³).
const TINY_CONE_SIN2: f32 = 1e-6;
/// A normal away from every axis, for the ONB tests.
fn tilted() -> Vec3 {
    Vec3::new(0.3, -0.5, 0.8).normalize()
}

/// Declares one `#[test]` per case and counts them for the Šidák
/// correction. Each case: name, domain, resolution, a sampler taking the
/// test's PCG32, and the claimed pdf.
macro_rules! chi2_tests {
    ($($name:ident: $domain:expr, $res:expr, |$rng:ident| $sample:expr, |$p:ident| $pdf:expr;)*) => {
        const TEST_COUNT: usize = [$(stringify!($name)),*].len();
        $(
            #[test]
            fn $name() {
                let seed = crate::support::seed_for(stringify!($name));
                let mut $rng = Pcg32::new(seed, STREAM);
                let test = Chi2::new(stringify!($name), $domain, $res, TEST_COUNT);
                let outcome = test.run(|| $sample, |$p: [f64; 3]| $pdf);
                eprintln!("{outcome:?}");
                outcome.assert_passed();
                assert!(
                    (outcome.integral - 1.0).abs() < 2e-3,
                    "{}: pdf integrates to {}", stringify!($name), outcome.integral
                );
            }
        )*
    };
}

/// The filter called `name` at its usual radius (built once: the pdf is
/// called for every histogram cell).
fn filter(name: &str) -> &'static PixelFilter {
    static FILTERS: std::sync::OnceLock<Vec<PixelFilter>> = std::sync::OnceLock::new();
    FILTERS
        .get_or_init(|| {
            FilterKind::ALL
                .iter()
                .map(|&kind| PixelFilter::new(kind, kind.default_radius()).unwrap())
                .collect()
        })
        .iter()
        .find(|f| f.kind().name() == name)
        .unwrap_or_else(|| panic!("no filter `{name}`"))
}

/// The square `[−r, r]²` the filter called `name` covers.
fn filter_domain(name: &str) -> Domain {
    let r = filter(name).radius() as f64;
    Domain::Rect {
        x0: -r,
        x1: r,
        y0: -r,
        y1: r,
    }
}

/// Cells of the filter tests: each table cell (32 per axis) split 2 × 2,
/// so the expected counts are exact and the test sees both the choice of
/// cell and the uniformity within it.
const FILTER_RES: (usize, usize) = (64, 64);

chi2_tests! {
    box_filter_chi2: filter_domain("box"), FILTER_RES,
        |rng| v2(filter("box").sample(uniform(&mut rng)).offset),
        |p| filter("box").pdf(w2(p)) as f64;
    tent_filter_chi2: filter_domain("tent"), FILTER_RES,
        |rng| v2(filter("tent").sample(uniform(&mut rng)).offset),
        |p| filter("tent").pdf(w2(p)) as f64;
    gaussian_filter_chi2: filter_domain("gaussian"), FILTER_RES,
        |rng| v2(filter("gaussian").sample(uniform(&mut rng)).offset),
        |p| filter("gaussian").pdf(w2(p)) as f64;
    mitchell_filter_chi2: filter_domain("mitchell"), FILTER_RES,
        |rng| v2(filter("mitchell").sample(uniform(&mut rng)).offset),
        |p| filter("mitchell").pdf(w2(p)) as f64;
    lanczos_filter_chi2: filter_domain("lanczos"), FILTER_RES,
        |rng| v2(filter("lanczos").sample(uniform(&mut rng)).offset),
        |p| filter("lanczos").pdf(w2(p)) as f64;
    blackman_harris_filter_chi2: filter_domain("blackman-harris"), FILTER_RES,
        |rng| v2(filter("blackman-harris").sample(uniform(&mut rng)).offset),
        |p| filter("blackman-harris").pdf(w2(p)) as f64;
    uniform_sphere_chi2: Domain::SPHERE, SPHERE_RES,
        |rng| v3(mapping::sample_uniform_sphere(uniform(&mut rng))),
        |p| mapping::pdf_uniform_sphere(w3(p)) as f64;
    uniform_hemisphere_chi2: Domain::HEMISPHERE, SPHERE_RES,
        |rng| v3(mapping::sample_uniform_hemisphere(uniform(&mut rng))),
        |p| mapping::pdf_uniform_hemisphere(w3(p)) as f64;
    cosine_hemisphere_chi2: Domain::HEMISPHERE, SPHERE_RES,
        |rng| v3(mapping::sample_cosine_hemisphere(uniform(&mut rng))),
        |p| mapping::pdf_cosine_hemisphere(w3(p)) as f64;
    concentric_disk_chi2: Domain::Disk, DISK_RES,
        |rng| v2(mapping::sample_concentric_disk(uniform(&mut rng))),
        |p| mapping::pdf_concentric_disk(w2(p)) as f64;
    polar_disk_chi2: Domain::Disk, DISK_RES,
        |rng| v2(mapping::sample_polar_disk(uniform(&mut rng))),
        |p| mapping::pdf_polar_disk(w2(p)) as f64;
    uniform_cone_chi2: Domain::Sphere { z_min: CONE_COS as f64, z_max: 1.0 }, SPHERE_RES,
        |rng| v3(mapping::sample_uniform_cone(uniform(&mut rng), Cone::from_cos(CONE_COS))),
        |p| mapping::pdf_uniform_cone(w3(p), Cone::from_cos(CONE_COS)) as f64;
    uniform_cone_wide_chi2: Domain::Sphere { z_min: WIDE_CONE_COS as f64, z_max: 1.0 }, SPHERE_RES,
        |rng| v3(mapping::sample_uniform_cone(uniform(&mut rng), Cone::from_cos(WIDE_CONE_COS))),
        |p| mapping::pdf_uniform_cone(w3(p), Cone::from_cos(WIDE_CONE_COS)) as f64;
    // A cone of 10⁻³ rad (a small light far away), which an f32 cosine
    // cannot resolve: (1 − cos θ) / (1 − cos θmax), computed without
    // cancellation, is uniform on [0, 1), and the azimuth on [0, 1).
    tiny_cone_chi2: Domain::UNIT_SQUARE, (101, 51),
        |rng| {
            let cone = Cone::from_sin2(TINY_CONE_SIN2);
            let w = mapping::sample_uniform_cone(uniform(&mut rng), cone);
            let omz = (w.x as f64 * w.x as f64 + w.y as f64 * w.y as f64) / (1.0 + w.z as f64);
            let phi = (w.y as f64).atan2(w.x as f64).rem_euclid(std::f64::consts::TAU);
            [omz / cone.one_minus_cos_theta_max() as f64, phi / std::f64::consts::TAU, 0.0]
        },
        |p| if (0.0..=1.0).contains(&p[0]) { 1.0 } else { 0.0 };
    // The ONB carries the cosine lobe to a tilted normal intact.
    cosine_hemisphere_onb_chi2: Domain::SPHERE, SPHERE_RES,
        |rng| v3(Onb::from_normal(tilted()).to_world(
            mapping::sample_cosine_hemisphere(uniform(&mut rng)))),
        |p| (w3(p).dot(tilted()).max(0.0) / core::f32::consts::PI) as f64;
    cosine_hemisphere_course_onb_chi2: Domain::SPHERE, SPHERE_RES,
        |rng| v3(Onb::from_normal_axis_switch(tilted()).to_world(
            mapping::sample_cosine_hemisphere(uniform(&mut rng)))),
        |p| (w3(p).dot(tilted()).max(0.0) / core::f32::consts::PI) as f64;
    // Samples of a stratified sampler, across pixels, are uniform overall.
    stratified_cosine_hemisphere_chi2: Domain::HEMISPHERE, SPHERE_RES,
        |rng| {
            let k = rng.next_u32();
            let mut s = Stratified::new(16, 11).unwrap();
            s.start_pixel_sample(UVec2::new(k >> 20, (k >> 8) & 0xfff), k & 15);
            let _ = s.next_1d();
            v3(mapping::sample_cosine_hemisphere(s.next_2d()))
        },
        |p| mapping::pdf_cosine_hemisphere(w3(p)) as f64;
    rejection_unit_disk_chi2: Domain::Disk, DISK_RES,
        |rng| v2(rejection::rejection_unit_disk(&mut rng)),
        |p| mapping::pdf_concentric_disk(w2(p)) as f64;
    rejection_unit_sphere_chi2: Domain::SPHERE, SPHERE_RES,
        |rng| v3(rejection::rejection_unit_sphere(&mut rng)),
        |p| mapping::pdf_uniform_sphere(w3(p)) as f64;
    // Uniform in the ball: (|p|³, the direction's z) and (|p|³, its
    // azimuth) are uniform on the square, the density being the ball's
    // 3 / (4π) times its volume 4π / 3 wherever |p| ≤ 1.
    uniform_ball_radius_z_chi2: Domain::UNIT_SQUARE, (51, 51),
        |rng| ball_params(mapping::sample_uniform_ball(uniform3(&mut rng))).0,
        |p| ball_density(p);
    uniform_ball_radius_phi_chi2: Domain::UNIT_SQUARE, (51, 51),
        |rng| ball_params(mapping::sample_uniform_ball(uniform3(&mut rng))).1,
        |p| ball_density(p);
    // Uniform in the ball: |p|³ is uniform on [0, 1).
    rejection_unit_ball_radius_chi2: Domain::Line { x0: 0.0, x1: 1.0 }, (200, 1),
        |rng| [(rejection::rejection_unit_ball(&mut rng).length() as f64).powi(3), 0.0, 0.0],
        |p| if (0.0..=1.0).contains(&p[0]) { 1.0 } else { 0.0 };
    rejection_uniform_hemisphere_chi2: Domain::HEMISPHERE, SPHERE_RES,
        |rng| v3(rejection::rejection_uniform_hemisphere(&mut rng)),
        |p| mapping::pdf_uniform_hemisphere(w3(p)) as f64;
    rejection_cosine_hemisphere_chi2: Domain::HEMISPHERE, SPHERE_RES,
        |rng| v3(rejection::rejection_cosine_hemisphere(&mut rng)),
        |p| mapping::pdf_cosine_hemisphere(w3(p)) as f64;
}

use rand_core::Rng;

/// A wrong mapping must be rejected: uniform hemisphere samples claimed to
/// be cosine-weighted. This is the harness's power check.
#[test]
fn uniform_claimed_as_cosine_is_rejected() {
    let mut rng = Pcg32::new(1, STREAM);
    let test = Chi2::new(
        "negative_uniform_as_cosine",
        Domain::HEMISPHERE,
        SPHERE_RES,
        TEST_COUNT,
    );
    let outcome = test.run(
        || v3(mapping::sample_uniform_hemisphere(uniform(&mut rng))),
        |p| mapping::pdf_cosine_hemisphere(w3(p)) as f64,
    );
    assert_eq!(outcome.impossible, 0);
    eprintln!("{outcome:?}");
    assert!(!outcome.passed(), "a wrong pdf passed: {outcome:?}");
}

/// The classic disk mistake, `r = u` instead of `sqrt(u)`, must be rejected.
#[test]
fn linear_radius_disk_is_rejected() {
    let mut rng = Pcg32::new(2, STREAM);
    let test = Chi2::new("negative_linear_radius", Domain::Disk, DISK_RES, TEST_COUNT);
    let outcome = test.run(
        || {
            let u = uniform(&mut rng);
            let p = mapping::sample_polar_disk(Vec2::new(u.x * u.x, u.y));
            v2(p)
        },
        |p| mapping::pdf_polar_disk(w2(p)) as f64,
    );
    eprintln!("{outcome:?}");
    assert!(!outcome.passed(), "a wrong disk passed: {outcome:?}");
}

/// The ball's classic mistake, radius `u` instead of `∛u`, must be
/// rejected.
#[test]
fn linear_radius_ball_is_rejected() {
    let mut rng = Pcg32::new(4, STREAM);
    let test = Chi2::new(
        "negative_linear_radius_ball",
        Domain::UNIT_SQUARE,
        (51, 51),
        TEST_COUNT,
    );
    let outcome = test.run(
        || {
            let u = uniform3(&mut rng);
            let p = mapping::sample_uniform_sphere(Vec2::new(u.x, u.y)) * u.z;
            ball_params(p).0
        },
        ball_density,
    );
    eprintln!("{outcome:?}");
    assert!(!outcome.passed(), "a wrong ball passed: {outcome:?}");
}

/// A mapping that puts samples where its pdf is zero fails outright.
#[test]
fn samples_outside_support_are_rejected() {
    let mut rng = Pcg32::new(3, STREAM);
    let mut test = Chi2::new("negative_outside", Domain::SPHERE, SPHERE_RES, TEST_COUNT);
    test.samples = 10_000;
    let outcome = test.run(
        || v3(mapping::sample_uniform_sphere(uniform(&mut rng))),
        |p| mapping::pdf_uniform_hemisphere(w3(p)) as f64,
    );
    assert!(outcome.zero_density > 4000, "{outcome:?}");
    assert!(!outcome.passed());
}

/// The p-value function against published χ² critical values at 1 %.
#[test]
fn chi2_survival_matches_tables() {
    for (x, dof) in [
        (6.634_897, 1.0),
        (23.209_251, 10.0),
        (135.806_723, 100.0),
        (1106.969, 1000.0),
    ] {
        let p = chi2_sf(x, dof);
        assert!((p - 0.01).abs() < 1e-4, "dof {dof}: p = {p}");
    }
    // Q(1, x) = e^-x exactly.
    for x in [0.1, 1.0, 5.0, 30.0] {
        assert!((gamma_q(1.0, x) - (-x).exp()).abs() < 1e-12);
    }
    assert_eq!(gamma_q(3.0, 0.0), 1.0);
}
