//! Adaptive sampling: smooth pixels stop at the minimum and noisy ones
//! take more, and the image is unbiased: its mean agrees with uniform
//! sampling's within noise, on a smooth scene and on one with rare bright
//! paths. (Its exactness for any split is in `determinism`.)

use strata::render::{Adaptive, PixelFilter, PixelSum, Tile};
use strata_runner::job::{Job, SamplerKind, run};
use strata_runner::scenes::{SceneData, built_in};

pub(crate) fn job(scene: &SceneData, width: u32, height: u32, spp: u32, seed: u64) -> Job<'_> {
    Job {
        max_depth: 5,
        seed,
        threads: 1,
        tile: 8,
        ..Job::new(scene, width, height, spp)
    }
}

pub(crate) fn adaptive(mut j: Job<'_>, min: u32, max: u32, threshold: f32) -> Job<'_> {
    j.adaptive = Some(Adaptive::new(min, max, threshold).unwrap());
    j.spp = max;
    j.samples = 0..max;
    j
}

pub(crate) fn taken(p: &PixelSum) -> u32 {
    p.taken()
}

#[test]
fn adaptive_jobs_refuse_sample_runs_and_the_grid() {
    let scene = built_in("week09").unwrap();
    let base = adaptive(job(&scene, 8, 4, 8, 0), 8, 16, 0.05);
    let run_err = |j: &Job<'_>| format!("{:#}", run(j, &|_| {}).unwrap_err());
    let part = Job {
        samples: 0..8,
        ..base.clone()
    };
    assert!(
        run_err(&part).contains("not 0..8 of 16"),
        "{}",
        run_err(&part)
    );
    let grid = Job {
        sampler: SamplerKind::Grid,
        ..base.clone()
    };
    assert!(run_err(&grid).contains("the grid fills its rows in order"));
    // The core refuses a sampler pattern smaller than the maximum.
    let data = built_in("week09").unwrap();
    let camera = strata::render::Camera::new(&data.camera, 8, 4).unwrap();
    let settings = strata::render::RenderSettings {
        max_depth: 2,
        direct_lighting: true,
        filter: PixelFilter::BOX,
        texture_filter: strata::render::TextureFilter::None,
        integrator: strata::render::Integrator::Scalar,
    };
    let mut film = vec![PixelSum::ZERO; 32];
    let e = data
        .with_scene(|s| {
            strata::render::render_tile_adaptive(
                s,
                &camera,
                &strata::Independent::new(8, 0).unwrap(),
                &settings,
                Tile::whole(8, 4),
                Adaptive::new(8, 16, 0.05).unwrap(),
                &mut film,
            )
        })
        .unwrap();
    assert_eq!(
        e,
        Err(strata::render::RenderError::SamplerTooSmall { spp: 8, max: 16 })
    );
    assert!(film.iter().all(|p| *p == PixelSum::ZERO), "nothing traced");
}

/// A diffuse sphere on a diffuse ground under the course's sky (or, with
/// `background` replaced, a flat one).
const SKY_AND_SPHERE: &str = r#"
background = "sky"

[camera]
look_from = [0.0, 0.3, 4.0]
look_at = [0.0, 0.0, 0.0]
vfov = 40.0

[render]
width = 48
spp = 4
max_depth = 6

[materials.grey]
kind = "lambertian"
albedo = [0.5, 0.5, 0.5]

[[spheres]]
center = [0.0, -100.5, 0.0]
radius = 100.0
material = "grey"

[[spheres]]
center = [0.0, 0.0, 0.0]
radius = 0.5
material = "grey"
"#;

#[test]
fn smooth_pixels_stop_at_the_minimum_and_noisy_ones_take_more() {
    let parse = |text: &str| {
        strata_runner::scenes::file::parse(std::path::Path::new("sky.toml"), text).unwrap()
    };
    let scene = parse(SKY_AND_SPHERE);
    let flat = parse(&SKY_AND_SPHERE.replace("\"sky\"", "[1.0, 1.0, 1.0]"));
    let (w, h) = (48, 27);
    let (base, max) = (8, 256);
    // The flat sky at depth 1 shows 1 or black: a pixel whose mean over
    // every sample index is exactly 1 saw only sky, exactly 0 only
    // surfaces, at the same sample positions as the adaptive render.
    let mut probe = job(&flat, w, h, max, 7);
    probe.max_depth = 1;
    let seen = run(&probe, &|_| {}).unwrap().pixels;
    let got = run(
        &adaptive(job(&scene, w, h, base, 7), base, max, 0.0005),
        &|_| {},
    )
    .unwrap()
    .pixels;
    let (mut sky, mut surface, mut surface_samples, mut more) = (0, 0, 0u64, 0u32);
    for (s, a) in seen.iter().zip(&got) {
        let m = s.mean();
        if m == glam::Vec3::ONE {
            sky += 1;
            assert_eq!(taken(a), base, "a sky pixel took more than the minimum");
        } else if m == glam::Vec3::ZERO {
            surface += 1;
            surface_samples += taken(a) as u64;
            more += (taken(a) > base) as u32;
        }
    }
    assert!(
        sky > 100 && surface > 100,
        "{sky} sky, {surface} surface pixels"
    );
    // Diffuse pixels integrate the sky's gradient: noisy, nearly all of
    // them take more, and several times the minimum on average.
    assert!(more as f64 > 0.95 * surface as f64, "{more} of {surface}");
    let mean = surface_samples as f64 / surface as f64;
    assert!(
        mean > 4.0 * base as f64,
        "diffuse pixels took {mean:.1} on average"
    );
}

/// Welch's t of two samples given as (mean, variance of one value, count).
fn welch(a: (f64, f64, f64), b: (f64, f64, f64)) -> f64 {
    let se = (a.1 / a.2 + b.1 / b.2).sqrt();
    if se == 0.0 {
        return if a.0 == b.0 { 0.0 } else { f64::INFINITY };
    }
    (a.0 - b.0) / se
}

/// Mean and unbiased variance.
fn moments(v: &[f64]) -> (f64, f64, f64) {
    let n = v.len() as f64;
    let m = v.iter().sum::<f64>() / n;
    let var = v.iter().map(|x| (x - m) * (x - m)).sum::<f64>() / (n - 1.0);
    (m, var, n)
}

/// K adaptive renders of `window` and K uniform ones at their mean spp
/// (other seeds) with `sampler`, as per-pixel luminance samples:
/// `(adaptive, uniform, mean spp)`.
fn adaptive_and_uniform(
    scene: &strata_runner::scenes::SceneData,
    (w, h): (u32, u32),
    window: Tile,
    (min, max, threshold): (u32, u32, f32),
    (k, sampler): (u64, SamplerKind),
) -> (Vec<Vec<f64>>, Vec<Vec<f64>>, u32) {
    let lum = |p: &PixelSum| strata_runner::study::luminance(p.mean());
    let mut a = vec![Vec::new(); window.area()];
    let mut u = vec![Vec::new(); window.area()];
    let mut spent = 0u64;
    for seed in 0..k {
        let mut j = adaptive(job(scene, w, h, min, seed), min, max, threshold);
        (j.window, j.threads, j.max_depth) = (window, 2, scene.defaults.max_depth);
        j.sampler = sampler;
        for (i, p) in run(&j, &|_| {}).unwrap().pixels.iter().enumerate() {
            a[i].push(lum(p));
            spent += taken(p) as u64;
        }
    }
    let uniform_spp = (spent / (k * window.area() as u64)) as u32;
    for seed in 0..k {
        let mut j = job(scene, w, h, uniform_spp, 1000 + seed);
        (j.window, j.threads, j.max_depth) = (window, 2, scene.defaults.max_depth);
        j.sampler = sampler;
        for (i, p) in run(&j, &|_| {}).unwrap().pixels.iter().enumerate() {
            u[i].push(lum(p));
        }
    }
    (a, u, uniform_spp)
}

/// The difference of the two images' mean luminance and its standard
/// error, from per-pixel samples (pixels are independent).
fn mean_difference(a: &[Vec<f64>], u: &[Vec<f64>]) -> (f64, f64, f64) {
    let (mut diff, mut var, mut level) = (0.0, 0.0, 0.0);
    for (pa, pu) in a.iter().zip(u) {
        let (ma, mu) = (moments(pa), moments(pu));
        diff += ma.0 - mu.0;
        var += ma.1 / ma.2 + mu.1 / mu.2;
        level += mu.0;
    }
    let n = a.len() as f64;
    (diff / n, var.sqrt() / n, level / n)
}

#[test]
fn adaptive_pixel_means_agree_with_uniform_sampling() {
    // 16 seeds of an adaptive render and of a uniform one at the same
    // mean spp; per pixel, Welch's t of the two means. Without bias each t
    // is roughly Student-t with at least 15 degrees of freedom, so
    // P(|t| > 4.5) < 4·10⁻⁴: over 32 × 18 pixels about 0.2 are expected
    // and 4 or more have probability < 10⁻³. With independent samples the
    // adaptive image is unbiased by construction, so the mean difference
    // over all pixels is held within 4 standard errors (false alarm
    // 6·10⁻⁵); stopping on a pixel's own estimate made it +0.4 % here,
    // 7 standard errors.
    const K: u64 = 16;
    let scene = built_in("week09").unwrap();
    let window = Tile {
        x0: 96,
        y0: 54,
        width: 32,
        height: 18,
    };
    let (a, u, uniform_spp) = adaptive_and_uniform(
        &scene,
        (320, 180),
        window,
        (16, 256, 0.002),
        (K, SamplerKind::Independent),
    );
    assert!(
        uniform_spp > 20,
        "adaptive took {uniform_spp} spp on average"
    );
    let mut outliers = Vec::new();
    for i in 0..a.len() {
        let t = welch(moments(&a[i]), moments(&u[i]));
        if t.abs() > 4.5 {
            outliers.push((i % 32, i / 32, t));
        }
    }
    assert!(
        outliers.len() < 4,
        "pixels whose means differ: {outliers:?}"
    );
    let (d, se, level) = mean_difference(&a, &u);
    assert!(
        d.abs() < 4.0 * se,
        "mean difference {d:.2e} (standard error {se:.2e}), mean luminance {level:.3}"
    );
}

#[test]
fn rare_bright_paths_are_not_lost_to_adaptive_sampling() {
    // Under the glass sphere of `caustics` and in the metal sphere's
    // highlight, bright paths are rare: a pixel whose first samples
    // missed them looks smooth. Weighting every sample alike once the
    // pilot has chosen the count (the plain mean) made this window's mean
    // 14 % too dark, 10 standard errors; here the mean difference to
    // uniform sampling is held within 4 standard errors, for independent
    // samples (unbiased by construction) and for Sobol' (whose parts are
    // slightly dependent). The 4 assumes the window's mean, over 10,800
    // pixels and 16 seeds, is near normal; its pixels are heavy-tailed,
    // which 16 seeds estimate less badly than 12.
    const K: u64 = 16;
    let scene = built_in("caustics").unwrap();
    let window = Tile {
        x0: 100,
        y0: 40,
        width: 120,
        height: 90,
    };
    for sampler in [SamplerKind::Independent, SamplerKind::Sobol] {
        let (a, u, uniform_spp) =
            adaptive_and_uniform(&scene, (320, 180), window, (16, 512, 0.002), (K, sampler));
        assert!(
            uniform_spp > 20,
            "{sampler:?}: adaptive took {uniform_spp} spp on average"
        );
        let (d, se, level) = mean_difference(&a, &u);
        assert!(
            d.abs() < 4.0 * se,
            "{sampler:?}: mean difference {d:.2e} (standard error {se:.2e}), mean luminance \
             {level:.3}"
        );
    }
}

#[test]
fn flat_regions_stop_at_the_minimum_whatever_the_filter() {
    // Under a flat white sky a pixel that sees only sky is exactly 1 for
    // every filter (the film's Σ w·L / Σ w, or where a pilot half's
    // weights nearly cancel, |Σ w| < n/2, its samples' box mean), so its
    // pilot has no variance and it stops at the minimum, even under
    // Mitchell and Lanczos, whose weights change sign. Sky pixels
    // are found by a probe at depth 1: a uniform render, which splats
    // these filters, is exactly 1 where every sample within the filter's
    // reach saw sky, which covers the adaptive render's offsets too.
    let flat = strata_runner::scenes::file::parse(
        std::path::Path::new("sky.toml"),
        &SKY_AND_SPHERE.replace("\"sky\"", "[1.0, 1.0, 1.0]"),
    )
    .unwrap();
    let (w, h) = (48, 27);
    for (filter, most_going_on) in [
        (PixelFilter::BOX, 0.0),
        (
            PixelFilter::new(strata::filter::FilterKind::named("mitchell").unwrap(), 2.0).unwrap(),
            0.0,
        ),
        (
            PixelFilter::new(strata::filter::FilterKind::named("lanczos").unwrap(), 3.0).unwrap(),
            0.0,
        ),
    ] {
        let mut probe = job(&flat, w, h, 256, 5);
        (probe.max_depth, probe.filter) = (1, filter);
        let seen = run(&probe, &|_| {}).unwrap().pixels;
        let mut j = adaptive(job(&flat, w, h, 16, 5), 16, 256, 0.002);
        j.filter = filter;
        let got = run(&j, &|_| {}).unwrap().pixels;
        let sky: Vec<&PixelSum> = got
            .iter()
            .zip(&seen)
            .filter(|(_, s)| s.mean() == glam::Vec3::ONE)
            .map(|(p, _)| p)
            .collect();
        assert!(
            sky.len() > 300,
            "{:?}: {} sky pixels",
            filter.kind(),
            sky.len()
        );
        let going_on = sky.iter().filter(|p| p.taken() > 16).count();
        assert!(
            going_on as f64 <= most_going_on * sky.len() as f64,
            "{:?}: {going_on} of {} sky pixels went on past the minimum",
            filter.kind(),
            sky.len()
        );
        // Whatever they took, sky pixels are exactly 1 (halves that fall
        // back take their own samples' box mean, which is 1 too).
        assert!(sky.iter().all(|p| p.mean() == glam::Vec3::ONE));
    }
}

#[test]
fn an_adaptive_pixel_is_its_pilot_and_rest_blended_as_documented() {
    // Each pixel recomputed from single samples: the pilot's halves and
    // their statistics, the rest the whole pilot asks for, each half
    // weighted by the other's rest. A swapped weight would be biased, and
    // only this exact check sees it at once.
    use glam::UVec2;
    use strata::render::{
        Camera, PilotStats, RenderSettings, TextureFilter, pixel_sample, render_tile,
        render_tile_adaptive,
    };
    let data = built_in("caustics").unwrap();
    let camera = Camera::new(&data.camera, 32, 18).unwrap();
    // The box's instance adds with the unit add, every other filter with
    // the weighted one: both are checked.
    let gaussian =
        PixelFilter::new(strata::filter::FilterKind::named("gaussian").unwrap(), 1.5).unwrap();
    for filter in [PixelFilter::BOX, gaussian] {
        let settings = RenderSettings {
            max_depth: 8,
            direct_lighting: true,
            filter,
            texture_filter: TextureFilter::None,
            integrator: strata::render::Integrator::Scalar,
        };
        let a = Adaptive::new(8, 64, 0.002).unwrap();
        let sampler = strata::Independent::new(64, 9).unwrap();
        let tile = Tile {
            x0: 10,
            y0: 8,
            width: 8,
            height: 3,
        };
        let adapted = data
            .with_scene(|scene| {
                let mut film = vec![PixelSum::ZERO; tile.area()];
                render_tile_adaptive(scene, &camera, &sampler, &settings, tile, a, &mut film)
                    .unwrap();
                let mut adapted = 0;
                for (i, got) in film.iter().enumerate() {
                    let i = i as u32;
                    let pixel = UVec2::new(tile.x0 + i % tile.width, tile.y0 + i / tile.width);
                    // A sample's value and weight, and the rays it traced.
                    let sample = |index: u32| {
                        let mut s = sampler.clone();
                        let (v, w) = pixel_sample(scene, &camera, &mut s, &settings, pixel, index);
                        let one = Tile {
                            x0: pixel.x,
                            y0: pixel.y,
                            width: 1,
                            height: 1,
                        };
                        let mut f = [PixelSum::ZERO];
                        let st = render_tile(
                            scene,
                            &camera,
                            &sampler,
                            &settings,
                            one,
                            index..index + 1,
                            &mut f,
                        )
                        .unwrap();
                        (v, w, (st.rays + st.shadow_rays) as u32)
                    };
                    let b = a.block();
                    let (mut parts, mut pilots) = ([PixelSum::ZERO; 3], [PilotStats::ZERO; 2]);
                    for index in 0..2 * b {
                        let (v, w, rays) = sample(index);
                        let h = (index / b) as usize;
                        parts[h].add_weighted(v, w);
                        pilots[h].add(v, w, rays);
                    }
                    let mut both = pilots[0];
                    both.merge(&pilots[1]);
                    let rest = a.rest_for(&both);
                    for index in 2 * b..2 * b + rest {
                        let (v, w, _) = sample(index);
                        parts[2].add_weighted(v, w);
                    }
                    let [ca, cb] = a.pilot_weights(a.rest_for(&pilots[0]), a.rest_for(&pilots[1]));
                    let want = PixelSum::blend(&[
                        (parts[0], ca),
                        (parts[1], cb),
                        (parts[2], 1.0 - ca - cb),
                    ]);
                    assert_eq!(*got, want, "pixel {pixel}");
                    adapted += (rest > 2 * b) as usize;
                }
                adapted
            })
            .unwrap();
        assert!(
            adapted > 0 && adapted < tile.area(),
            "{adapted} pixels adapted"
        );
    }
}
