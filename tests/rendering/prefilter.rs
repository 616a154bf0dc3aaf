//! The prefiltered checker: the closed form against quadrature, the
//! footprint from ray differentials against the pixel it should cover,
//! and less error than point sampling on the aliasing demo's plane.

use glam::{Vec2, Vec3};
use strata::render::{Texture, TextureFilter};
use strata::rng::{Pcg32, STREAM, next_f32};
use strata_runner::job::{Job, SamplerKind, run};
use strata_runner::scenes::{SceneData, built_in};
use strata_runner::study::rmse;

#[test]
fn the_closed_form_is_the_box_average_of_the_checker() {
    // 300 random boxes, from a fraction of a cell to several cells wide,
    // some flat in one axis; the 3-D average by the midpoint rule on a
    // 48³ grid, whose error for a box of width w cells is at most about
    // (number of boundary planes crossed) / 48.
    let even = Vec3::new(0.1, 0.2, 0.3);
    let odd = Vec3::new(0.9, 0.6, 0.4);
    let scale = 0.37;
    let c = Texture::Checker { scale, even, odd };
    let mut rng = Pcg32::new(11, STREAM);
    let mut u = || next_f32(&mut rng);
    const N: usize = 48;
    for case in 0..300 {
        let p = Vec3::new(u() * 6.0 - 3.0, u() * 6.0 - 3.0, u() * 6.0 - 3.0);
        let mut h = Vec3::new(u(), u(), u()) * 3.0 * scale;
        if case % 3 == 0 {
            h.y = 0.0;
        }
        let got = c.filtered(Vec2::ZERO, p, h);
        let mut sum = Vec3::ZERO;
        for i in 0..N {
            for j in 0..N {
                for k in 0..N {
                    let at = |n: usize, c: f32, w: f32| {
                        c + w * (2.0 * (n as f32 + 0.5) / N as f32 - 1.0)
                    };
                    let q = Vec3::new(at(i, p.x, h.x), at(j, p.y, h.y), at(k, p.z, h.z));
                    sum += c.value(Vec2::ZERO, q);
                }
            }
        }
        let want = sum / (N * N * N) as f32;
        // Cell boundaries crossed: each costs up to 1/N of the contrast.
        let planes = (h * 2.0 / scale).ceil() + Vec3::ONE;
        let tol = (planes.x + planes.y + planes.z) / N as f32 * (odd - even).abs().max_element();
        assert!(
            (got - want).abs().max_element() <= tol,
            "case {case}: p {p}, h {h}: {got} vs {want} (tolerance {tol})"
        );
    }
    // Zero widths are the point value; infinite or NaN ones the mean.
    let p = Vec3::new(0.3, -1.2, 2.9);
    assert_eq!(
        c.filtered(Vec2::ZERO, p, Vec3::ZERO),
        c.value(Vec2::ZERO, p)
    );
    for h in [Vec3::INFINITY, Vec3::NAN, Vec3::new(1e30, 0.0, 0.0)] {
        let m = c.filtered(Vec2::ZERO, p, h);
        assert!(
            (m - (even + odd) * 0.5).abs().max_element() < 1e-6,
            "{h}: {m}"
        );
    }
    // Solid and image textures ignore the box.
    let s = Texture::Solid(even);
    assert_eq!(s.filtered(Vec2::ZERO, p, Vec3::ONE), even);
}

fn job(scene: &SceneData, w: u32, h: u32, sampler: SamplerKind, spp: u32, seed: u64) -> Job<'_> {
    Job {
        max_depth: 2,
        sampler,
        seed,
        ..Job::new(scene, w, h, spp)
    }
}

fn means(j: &Job<'_>) -> Vec<Vec3> {
    run(j, &|_| {})
        .unwrap()
        .pixels
        .iter()
        .map(|p| p.mean())
        .collect()
}

/// A checker wall facing the camera (the near side of a huge sphere),
/// cells 0.8 pixels wide, lit by a flat white sky: each pixel's value is
/// the albedo it sees.
const WALL: &str = r#"
background = [1.0, 1.0, 1.0]

[camera]
look_from = [0.0, 0.0, 0.0]
look_at = [0.0, 0.0, -1.0]
vfov = 40.0

[render]
width = 64
spp = 1
max_depth = 2

[textures.fine]
kind = "checker"
scale = 0.0462
even = [0.05, 0.05, 0.05]
odd = [0.95, 0.95, 0.95]

[materials.wall]
kind = "lambertian"
texture = "fine"

[[spheres]]
center = [0.0, 0.0, -10005.0]
radius = 10000.0
material = "wall"
"#;

#[test]
fn the_footprint_of_a_pixel_centre_covers_its_pixel() {
    // A camera ray through a pixel's centre (the 1-spp grid) on a wall
    // facing the camera: the footprint box is the pixel's square on the
    // wall, so the prefiltered value is the pixel's area average, which a
    // 4096-spp point-sampled render estimates to within about 0.45/64.
    // The wall is at z = −5; 5 / 0.0462 = 108.2 cells, mid-cell in z.
    let scene =
        strata_runner::scenes::file::parse(std::path::Path::new("wall.toml"), WALL).unwrap();
    let (w, h) = (64, 36);
    // Pixel size at the wall: 2·5·tan(20°) / 36 = 0.1011; cells 0.0462
    // wide, so a pixel spans about 2.2 cells and point samples alias.
    let reference = means(&job(&scene, w, h, SamplerKind::Independent, 4096, 1));
    let mut centre = job(&scene, w, h, SamplerKind::Grid, 1, 0);
    let point = means(&centre);
    centre.texture_filter = TextureFilter::Box;
    let boxed = means(&centre);
    let worst = |img: &[Vec3]| {
        img.iter()
            .zip(&reference)
            .map(|(a, b)| (*a - *b).abs().max_element())
            .fold(0.0f32, f32::max)
    };
    // Some pixels' box average is off by perspective (the wall's points
    // are not all at the centre's depth) and by the reference's noise.
    assert!(worst(&boxed) < 0.05, "prefiltered: worst {}", worst(&boxed));
    assert!(
        worst(&point) > 0.3,
        "point-sampled: worst {}",
        worst(&point)
    );
    assert!(
        rmse(&boxed, &reference) < 0.01,
        "{}",
        rmse(&boxed, &reference)
    );
}

#[test]
fn prefiltering_lowers_the_error_on_the_horizon_at_1_spp() {
    // The aliasing demo's plane at 160 × 90: RMSE against a 1024-spp
    // point-sampled Sobol' reference (the pixel's box average), mean
    // squared error over 4 seeds of 1 spp.
    let scene = built_in("horizon").unwrap();
    let (w, h) = (160, 90);
    let reference = means(&job(&scene, w, h, SamplerKind::Sobol, 1024, 99));
    let err = |filter: TextureFilter| {
        let mut sq = 0.0;
        for seed in 0..4 {
            let mut j = job(&scene, w, h, SamplerKind::Independent, 1, seed);
            j.texture_filter = filter;
            sq += rmse(&means(&j), &reference).powi(2);
        }
        (sq / 4.0).sqrt()
    };
    let (none, boxed) = (err(TextureFilter::None), err(TextureFilter::Box));
    assert!(boxed < 0.7 * none, "box {boxed:.4} vs none {none:.4}");
}
