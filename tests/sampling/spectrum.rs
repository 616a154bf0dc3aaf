//! The Fourier view of the samplers: independent samples have a flat
//! spectrum, jittered ones little power at low frequencies, the uniform
//! grid spikes at multiples of √spp and nothing between.

use strata_runner::job::SamplerKind;
use strata_runner::spectrum::spectrum;

const SPP: u32 = 64;
const PIXELS: u32 = 1024;
const R: u32 = 24;

#[test]
fn independent_samples_have_a_flat_spectrum() {
    // For independent uniform points E[P(ω)] = 1 at every integer ω ≠ 0,
    // and P(ω) is close to exponentially distributed (standard deviation
    // 1). P(ω) = P(−ω), so a radial bin holding m frequencies averages
    // m/2 independent values per pixel: its standard error is at most
    // 1/√(1024 · m/2) ≤ 1/√(1024 · 2) = 0.022 (m ≥ 4 for every radius).
    // Each bin is held to 5 standard errors of its own size.
    let s = spectrum(SamplerKind::Independent, SPP, 3, PIXELS, R).unwrap();
    let r = R as i32;
    for (k, p) in s.radial() {
        let m = (-r..=r)
            .flat_map(|y| (-r..=r).map(move |x| (x, y)))
            .filter(|&(x, y)| ((x * x + y * y) as f64).sqrt().round() as u32 == k)
            .count() as f64;
        let se = 1.0 / (PIXELS as f64 * m / 2.0).sqrt();
        assert!(
            (p - 1.0).abs() < 5.0 * se,
            "radius {k}: {p:.4} (5 SE = {:.4})",
            5.0 * se
        );
    }
    // The zero frequency is the sample count.
    assert!((s.at(0, 0) - SPP as f64).abs() < 1e-9);
}

#[test]
fn jittered_and_low_discrepancy_samples_have_little_low_frequency_power() {
    // Below the strata frequency √spp = 8 cycles per pixel.
    let low = |sampler| {
        let s = spectrum(sampler, SPP, 3, PIXELS, R).unwrap();
        let v: Vec<f64> = s
            .radial()
            .into_iter()
            .filter(|&(k, _)| k < 8)
            .map(|p| p.1)
            .collect();
        v.iter().sum::<f64>() / v.len() as f64
    };
    let independent = low(SamplerKind::Independent);
    assert!(independent > 0.9, "{independent}");
    for sampler in [
        SamplerKind::Stratified,
        SamplerKind::Sobol,
        SamplerKind::Halton,
    ] {
        let l = low(sampler);
        assert!(
            l < 0.6 * independent,
            "{}: {l:.3} vs {independent:.3}",
            sampler.name()
        );
    }
    // Lowest radii: jittering removes nearly all power there.
    let s = spectrum(SamplerKind::Stratified, SPP, 3, PIXELS, R).unwrap();
    assert!(s.radial()[0].1 < 0.15, "{:?}", s.radial()[0]);
}

#[test]
fn the_uniform_grid_spikes_at_multiples_of_its_spacing() {
    // Strata centres on an 8 × 8 grid: P = spp at ω ∈ 8ℤ², 0 elsewhere.
    let s = spectrum(SamplerKind::Grid, SPP, 3, 16, R).unwrap();
    let r = R as i32;
    for wy in -r..=r {
        for wx in -r..=r {
            let p = s.at(wx, wy);
            if wx % 8 == 0 && wy % 8 == 0 {
                assert!((p - SPP as f64).abs() < 1e-6, "({wx}, {wy}): {p}");
            } else {
                assert!(p < 1e-9, "({wx}, {wy}): {p}");
            }
        }
    }
}
