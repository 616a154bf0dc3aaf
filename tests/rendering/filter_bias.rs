//! Every filter's film is an unbiased estimate of the filter's true
//! output: averaged over many seeds, each pixel matches the convolution
//! of a converged point-sampled image with the filter, within the seeds'
//! standard error.
//!
//! The reference is a box render at 16× the resolution on each axis, 64
//! samples per sub-pixel (16,384 per pixel), and a pixel's true output is
//! `Σ w_s·I_s / Σ w_s` over the sub-pixels `s`, with `w_s` the filter's
//! integral over the sub-pixel (separable: the product of two 1-D
//! integrals, 8-point midpoint rule each) and `I_s` the sub-pixel's
//! luminance. Only pixels whose filter support lies inside the image are
//! compared: the importance-sampled filters draw rays beyond the frame's
//! edge, the splatted ones renormalise by the weights inside it, and the
//! reference's convolution would have to follow each.

use strata::filter::{FilterKind, PixelFilter};
use strata_runner::job::{Job, SamplerKind, run};
use strata_runner::scenes::built_in;
use strata_runner::study::luminance;

/// Sub-pixels per pixel along each axis in the reference.
const SUPER: u32 = 16;
/// Samples per sub-pixel in the reference.
const REFERENCE_SPP: u32 = 64;
/// Samples a pixel summed over the seeds: 32 seeds at 16 spp, 128 at 4,
/// 512 at 1. As many seeds as that at low spp keeps the mean close to
/// normal where a pixel's radiance has a long tail (a glass sphere's rare
/// bright paths), and its standard error well estimated.
const SAMPLES: u64 = 512;
/// Path length: enough for every material's look, short enough to keep
/// the reference cheap.
const DEPTH: u32 = 6;

/// The reference image's luminance, `SUPER` × the size on each axis.
fn reference(scene: &str, w: u32, h: u32) -> Vec<f64> {
    let data = built_in(scene).unwrap();
    let job = Job {
        sampler: SamplerKind::Sobol,
        seed: 1_000_003,
        max_depth: DEPTH,
        ..Job::new(&data, w * SUPER, h * SUPER, REFERENCE_SPP)
    };
    run(&job, &|_| {})
        .unwrap()
        .pixels
        .iter()
        .map(|p| luminance(p.mean()))
        .collect()
}

/// For pixel `p` on an axis: the filter's integral over each sub-pixel
/// of its support, as `(sub-pixel index, weight)`.
fn axis_weights(f: &PixelFilter, p: u32) -> Vec<(usize, f64)> {
    let centre = p as f64 + 0.5;
    let r = f.radius() as f64;
    let first = ((centre - r) * SUPER as f64).floor() as i64;
    let last = ((centre + r) * SUPER as f64).ceil() as i64;
    let h = 1.0 / SUPER as f64;
    (first..last)
        .map(|s| {
            let w: f64 = (0..8)
                .map(|k| {
                    let x = (s as f64 + (k as f64 + 0.5) / 8.0) * h - centre;
                    f.eval_axis(x as f32) as f64
                })
                .sum::<f64>()
                * h
                / 8.0;
            (s as usize, w)
        })
        .collect()
}

/// Pixels compared, pixels beyond 3 standard errors, and the same count
/// for the mean 2 % too bright (a bias the test must see).
struct Counts {
    compared: usize,
    outside: usize,
    outside_if_biased: usize,
}

/// Checks `filter` on `scene` against `reference`.
fn check(
    scene: &str,
    (w, h): (u32, u32),
    reference: &[f64],
    filter: PixelFilter,
    spp: u32,
) -> Counts {
    let data = built_in(scene).unwrap();
    let n = (w * h) as usize;
    let seeds = SAMPLES / u64::from(spp);
    let (mut sum, mut sum2) = (vec![0.0f64; n], vec![0.0f64; n]);
    for seed in 0..seeds {
        let job = Job {
            sampler: SamplerKind::Sobol,
            seed,
            max_depth: DEPTH,
            filter,
            ..Job::new(&data, w, h, spp)
        };
        for (i, p) in run(&job, &|_| {}).unwrap().pixels.iter().enumerate() {
            let y = luminance(p.mean());
            sum[i] += y;
            sum2[i] += y * y;
        }
    }
    let margin = filter.radius().ceil() as u32;
    let wide = (w * SUPER) as usize;
    let mut counts = Counts {
        compared: 0,
        outside: 0,
        outside_if_biased: 0,
    };
    for y in margin..h - margin {
        let wy = axis_weights(&filter, y);
        for x in margin..w - margin {
            let wx = axis_weights(&filter, x);
            let (mut num, mut den) = (0.0, 0.0);
            for &(sy, fy) in &wy {
                for &(sx, fx) in &wx {
                    num += fx * fy * reference[sy * wide + sx];
                    den += fx * fy;
                }
            }
            let truth = num / den;
            // The spread of the sub-pixels under the filter's footprint:
            // what one independent sample's variance would be, at least.
            let (mut spread, mut mass) = (0.0, 0.0);
            for &(sy, fy) in &wy {
                for &(sx, fx) in &wx {
                    let d = reference[sy * wide + sx] - truth;
                    spread += (fx * fy).abs() * d * d;
                    mass += (fx * fy).abs();
                }
            }
            let i = (y * w + x) as usize;
            let mean = sum[i] / seeds as f64;
            let var = (sum2[i] - sum[i] * mean) / (seeds - 1) as f64;
            // The reference's own noise: its 16,384 samples a pixel
            // against the test's 512.
            let ratio = SAMPLES as f64 / (SUPER * SUPER * REFERENCE_SPP) as f64;
            // A small bright feature that no seed's samples hit leaves the
            // seeds agreeing on a wrong value with a tiny spread; the
            // standard error is floored at independent sampling's, from
            // the reference's spread (which a bias of the estimator does
            // not change).
            let independent = spread / mass / SAMPLES as f64;
            let se = ((var.max(0.0) / seeds as f64).max(independent) * (1.0 + ratio)).sqrt();
            // Fixed-point weights (2⁻¹² per axis) round each splat.
            let tolerance = 3.0 * se + 1e-4 * truth.abs();
            counts.compared += 1;
            counts.outside += usize::from((mean - truth).abs() > tolerance);
            counts.outside_if_biased += usize::from((1.02 * mean - truth).abs() > tolerance);
        }
    }
    counts
}

#[test]
fn every_filter_averages_to_its_convolution_of_the_image() {
    // The standard error is itself estimated: Student's t with 31 degrees
    // of freedom (16 spp) exceeds 3 in 0.53 % of pixels by chance, a
    // normal variable in 0.27 %.
    for (scene, w, h) in [("week09", 48, 27), ("cover", 48, 27)] {
        let reference = reference(scene, w, h);
        for kind in FilterKind::ALL {
            let filter = PixelFilter::new(kind, kind.default_radius()).unwrap();
            let name = kind.name();
            for spp in [1, 4, 16] {
                let c = check(scene, (w, h), &reference, filter, spp);
                eprintln!(
                    "{scene} {name} {spp} spp: {} of {} beyond 3 s.e. ({} if 2 % too bright)",
                    c.outside, c.compared, c.outside_if_biased
                );
                assert!(c.compared > 500, "{scene} {name}: {} pixels", c.compared);
                assert!(
                    c.outside as f64 <= 0.01 * c.compared as f64,
                    "{scene} {name} {spp} spp: {} of {} pixels beyond 3 standard errors",
                    c.outside,
                    c.compared
                );
                // The test's power: at 16 spp a bias of 2 % would fail it
                // (importance-sampled Lanczos was 16 % dark at 4 spp).
                assert!(
                    spp < 16 || c.outside_if_biased as f64 > 0.01 * c.compared as f64,
                    "{scene} {name}: a 2 % bias leaves only {} of {} pixels beyond",
                    c.outside_if_biased,
                    c.compared
                );
            }
        }
    }
}
