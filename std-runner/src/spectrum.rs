//! The Fourier view of pixel-sample patterns: the periodogram of each
//! pixel's `spp` positions, averaged over many pixels, and its radial
//! average.
//!
//! For a pixel's positions `x₁ … x_N` in `[0, 1)²` and an integer
//! frequency `ω`, the periodogram is `P(ω) = |Σₖ e^{−2πi ω·xₖ}|² / N`.
//! Independent uniform points give `E[P(ω)] = 1` at every `ω ≠ 0` (a flat,
//! "white" spectrum); a grid of `√N × √N` centres gives `N` at multiples
//! of `√N` and 0 elsewhere; jittered and low-discrepancy points give
//! little power below `√N` (blue noise). `P(0) = N` always and is left
//! out of the radial average.
//!
//! The sums are separable: `e^{−2πi ω·x} = e^{−2πi ωₓ x} e^{−2πi ω_y y}`,
//! and each factor's powers come from one complex exponential by
//! repeated multiplication, so a pixel costs `N (2R + 1)²` complex
//! multiply-adds for frequencies up to `R`.

use std::fmt::Write as _;

use anyhow::{Result, bail};
use glam::UVec2;
use plotters::prelude::*;
use rayon::prelude::*;
use strata::Sampler;

use crate::limits::MAX_RANGE;
use crate::plot;
use crate::render::{SamplerKind, WithSampler};

/// The averaged periodogram of one sampler.
#[derive(Clone, Debug)]
pub struct Spectrum {
    /// The sampler.
    pub sampler: SamplerKind,
    /// Samples per pixel.
    pub spp: u32,
    /// Pixels averaged.
    pub pixels: u32,
    /// Frequencies run over `−r..=r` on each axis.
    pub r: u32,
    /// `P(ω)` averaged over the pixels, row-major over `ω_y` then `ω_x`,
    /// each from `−r` to `r` (so `ω = 0` is at the centre).
    pub power: Vec<f64>,
}

impl Spectrum {
    /// The side of the frequency grid, `2r + 1`.
    #[must_use]
    pub fn side(&self) -> usize {
        2 * self.r as usize + 1
    }

    /// `P` at frequency `(wx, wy)`, each in `−r..=r`.
    ///
    /// # Panics
    /// If either is outside `−r..=r`.
    #[must_use]
    pub fn at(&self, wx: i32, wy: i32) -> f64 {
        let r = self.r as i32;
        assert!(
            (-r..=r).contains(&wx) && (-r..=r).contains(&wy),
            "frequency ({wx}, {wy}) outside ±{r}"
        );
        self.power[((wy + r) as usize) * self.side() + (wx + r) as usize]
    }

    /// The radial average: for each integer radius `k` in `1..=r`, the mean
    /// of `P(ω)` over the frequencies with `k − ½ ≤ |ω| < k + ½`.
    #[must_use]
    pub fn radial(&self) -> Vec<(u32, f64)> {
        let r = self.r as i32;
        let mut sum = vec![0.0; self.r as usize + 1];
        let mut count = vec![0u32; self.r as usize + 1];
        for wy in -r..=r {
            for wx in -r..=r {
                let k = ((wx * wx + wy * wy) as f64).sqrt().round() as usize;
                if (1..=self.r as usize).contains(&k) {
                    sum[k] += self.at(wx, wy);
                    count[k] += 1;
                }
            }
        }
        (1..=self.r)
            .map(|k| (k, sum[k as usize] / count[k as usize] as f64))
            .collect()
    }
}

/// The default frequency range for `spp` samples: four times the strata
/// frequency `√spp`, at least 16 and at most [`MAX_RANGE`].
#[must_use]
pub fn default_range(spp: u32) -> u32 {
    (4.0 * (spp as f64).sqrt())
        .ceil()
        .clamp(16.0, MAX_RANGE as f64) as u32
}

/// The periodogram of `sampler` at `spp`, averaged over `pixels` pixels
/// (a row-major run of a 64-pixel-wide image), for frequencies up to `r`.
pub fn spectrum(
    sampler: SamplerKind,
    spp: u32,
    seed: u64,
    pixels: u32,
    r: u32,
) -> Result<Spectrum> {
    if spp == 0 || pixels == 0 || r == 0 || r > MAX_RANGE {
        bail!("spectrum of {spp} spp over {pixels} pixels up to frequency {r}: out of range");
    }
    let made = sampler.with_sampler(spp, seed, Average { spp, pixels, r });
    let Some(power) = made else {
        bail!("{} takes no {spp} samples per pixel", sampler.name());
    };
    Ok(Spectrum {
        sampler,
        spp,
        pixels,
        r,
        power,
    })
}

/// The averaged periodogram, for one sampler kind.
struct Average {
    spp: u32,
    pixels: u32,
    r: u32,
}

impl WithSampler for Average {
    type Output = Vec<f64>;
    fn run<S: Sampler + Clone + Send + Sync>(self, sampler: S) -> Vec<f64> {
        average(sampler, self.spp, self.pixels, self.r)
    }
}

fn average<S: Sampler + Clone + Send + Sync>(
    sampler: S,
    spp: u32,
    pixels: u32,
    r: u32,
) -> Vec<f64> {
    let side = 2 * r as usize + 1;
    let one = |i: u32| {
        let mut s = sampler.clone();
        let pixel = UVec2::new(i % 64, i / 64);
        // Per axis, e^{−2πi ω t} for ω in −r..=r, as (re, im).
        let mut ex = vec![(0.0f64, 0.0f64); side];
        let mut ey = vec![(0.0f64, 0.0f64); side];
        let mut f = vec![(0.0f64, 0.0f64); side * side];
        for k in 0..spp {
            s.start_pixel_sample(pixel, k);
            let p = s.pixel_2d();
            powers(p.x as f64, r, &mut ex);
            powers(p.y as f64, r, &mut ey);
            for (row, &(yr, yi)) in f.chunks_exact_mut(side).zip(&ey) {
                for (acc, &(xr, xi)) in row.iter_mut().zip(&ex) {
                    acc.0 += xr * yr - xi * yi;
                    acc.1 += xr * yi + xi * yr;
                }
            }
        }
        f.iter()
            .map(|&(re, im)| (re * re + im * im) / spp as f64)
            .collect::<Vec<f64>>()
    };
    // Chunks of 16 pixels, 64 chunks at a time in parallel, added to the
    // total in order: the same bits for any thread count, and memory
    // bounded by 64 partial sums whatever the pixel count.
    let add = |mut a: Vec<f64>, b: Vec<f64>| {
        a.iter_mut().zip(b).for_each(|(x, y)| *x += y);
        a
    };
    let chunk = |c: u32| {
        (c * 16..(c * 16 + 16).min(pixels))
            .map(one)
            .reduce(add)
            .expect("a chunk holds a pixel")
    };
    let chunks = pixels.div_ceil(16);
    let mut total = vec![0.0; side * side];
    for wave in (0..chunks).step_by(64) {
        let sums: Vec<Vec<f64>> = (wave..(wave + 64).min(chunks))
            .into_par_iter()
            .map(chunk)
            .collect();
        total = sums.into_iter().fold(total, add);
    }
    total.into_iter().map(|p| p / pixels as f64).collect()
}

/// `out[ω + r] = e^{−2πi ω t}` for `ω` in `−r..=r`.
fn powers(t: f64, r: u32, out: &mut [(f64, f64)]) {
    let a = -2.0 * std::f64::consts::PI * t;
    let step = (a.cos(), a.sin());
    let mul = |(a, b): (f64, f64), (c, d): (f64, f64)| (a * c - b * d, a * d + b * c);
    let r = r as usize;
    out[r] = (1.0, 0.0);
    for w in 1..=r {
        out[r + w] = mul(out[r + w - 1], step);
        // The conjugate: e^{+2πi w t}.
        out[r - w] = (out[r + w].0, -out[r + w].1);
    }
}

/// The spectrum as an 8-bit grey image (RGB), [`Spectrum::side`]` ×
/// cell` pixels on a side, each frequency a `cell × cell` square: grey `P / 2` (a flat
/// spectrum is mid-grey, `P ≥ 2` white), `ω = 0` at the centre.
#[must_use]
pub fn image(s: &Spectrum, cell: usize) -> Vec<u8> {
    let side = s.side();
    let n = side * cell;
    let mut buf = vec![0u8; n * n * 3];
    for y in 0..n {
        for x in 0..n {
            let p = s.power[(y / cell) * side + x / cell];
            let v = (p / 2.0).clamp(0.0, 1.0);
            let g = (v * 255.0).round() as u8;
            buf[(y * n + x) * 3..][..3].copy_from_slice(&[g, g, g]);
        }
    }
    buf
}

/// One line on the spectrum of a sampler: its mean power below the
/// strata frequency `√spp` (where stratification removes power; `-` if
/// no radius is that low) and over all radii.
#[must_use]
pub fn summary(s: &Spectrum) -> String {
    let radial = s.radial();
    let low: Vec<f64> = radial
        .iter()
        .filter(|(k, _)| (*k as f64) < (s.spp as f64).sqrt())
        .map(|p| p.1)
        .collect();
    let mean = |v: &[f64]| v.iter().sum::<f64>() / v.len().max(1) as f64;
    format!(
        "{:<12} mean power below √spp: {}, over all radii: {:.3}",
        s.sampler.name(),
        if low.is_empty() {
            "-".to_string()
        } else {
            format!("{:.3}", mean(&low))
        },
        mean(&radial.iter().map(|p| p.1).collect::<Vec<_>>())
    )
}

/// The radial averages as CSV: `frequency,SAMPLER…`, frequency in cycles
/// per pixel.
#[must_use]
pub fn csv(spectra: &[Spectrum]) -> String {
    let mut out = String::from("frequency");
    for s in spectra {
        write!(out, ",{}", s.sampler.name()).ok();
    }
    out.push('\n');
    let radial: Vec<_> = spectra.iter().map(Spectrum::radial).collect();
    let rows = radial.iter().map(Vec::len).max().unwrap_or(0);
    for i in 0..rows {
        let k = radial.iter().find_map(|r| r.get(i)).map_or(0, |p| p.0);
        write!(out, "{k}").ok();
        for r in &radial {
            match r.get(i) {
                Some((_, p)) => write!(out, ",{p:.6}").ok(),
                None => write!(out, ",").ok(),
            };
        }
        out.push('\n');
    }
    out
}

/// The radial averages as one plot, a line per sampler, into an 8-bit RGB
/// buffer of `width × height`.
pub fn plot_radial(spectra: &[Spectrum], title: &str, width: u32, height: u32) -> Result<Vec<u8>> {
    let radial: Vec<_> = spectra.iter().map(Spectrum::radial).collect();
    let x1 = spectra.iter().map(|s| s.r).max().unwrap_or(1) as f64;
    let y1 = radial
        .iter()
        .flatten()
        .map(|p| p.1)
        .fold(2.0f64, f64::max)
        .min(4.0);
    plot::chart(width, height, |root| {
        let mut chart =
            plot::titled(root, title, 56).build_cartesian_2d(0.0..x1, 0.0..y1 * 1.05)?;
        chart
            .configure_mesh()
            .x_desc("frequency |ω| (cycles per pixel)")
            .y_desc("radial mean power")
            .label_style(("sans-serif", 15))
            .max_light_lines(0)
            .draw()?;
        for (s, line) in spectra.iter().zip(&radial) {
            let c = plot::colour(s.sampler);
            let pts: Vec<(f64, f64)> = line.iter().map(|&(k, p)| (k as f64, p.min(y1))).collect();
            chart
                .draw_series(LineSeries::new(pts, c.stroke_width(2)))?
                .label(s.sampler.name())
                .legend(plot::legend_line(c.stroke_width(2)));
        }
        plot::legend(&mut chart, SeriesLabelPosition::UpperLeft)
    })
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn one_point_has_a_flat_periodogram_and_powers_are_exact() {
        let mut out = vec![(0.0, 0.0); 9];
        powers(0.25, 4, &mut out);
        // e^{−2πi ω / 4}: ω = 1 → −i, ω = 2 → −1, ω = −1 → i.
        let close = |a: (f64, f64), b: (f64, f64)| (a.0 - b.0).abs() + (a.1 - b.1).abs() < 1e-12;
        assert!(close(out[5], (0.0, -1.0)));
        assert!(close(out[6], (-1.0, 0.0)));
        assert!(close(out[3], (0.0, 1.0)));
        // One sample: |e^{…}|² / 1 = 1 everywhere.
        let s = spectrum(SamplerKind::Independent, 1, 0, 3, 5).unwrap();
        assert!(s.power.iter().all(|&p| (p - 1.0).abs() < 1e-9));
    }

    #[test]
    fn the_default_range_stays_within_the_limit() {
        assert_eq!(default_range(1), 16);
        assert_eq!(default_range(64), 32);
        assert_eq!(default_range(crate::limits::MAX_PATTERN_SPP), MAX_RANGE);
        assert!(spectrum(SamplerKind::Independent, 1089, 0, 1, default_range(1089)).is_ok());
    }

    #[test]
    fn spectra_do_not_depend_on_the_thread_count() {
        let run = |threads| {
            rayon::ThreadPoolBuilder::new()
                .num_threads(threads)
                .build()
                .unwrap()
                .install(|| spectrum(SamplerKind::Sobol, 16, 1, 100, 8).unwrap().power)
        };
        assert_eq!(run(1), run(2));
    }

    #[test]
    fn csv_has_a_column_per_sampler_and_a_row_per_radius() {
        let a = spectrum(SamplerKind::Independent, 4, 0, 8, 3).unwrap();
        let b = spectrum(SamplerKind::Grid, 4, 0, 8, 3).unwrap();
        let text = csv(&[a, b]);
        let lines: Vec<&str> = text.lines().collect();
        assert_eq!(lines[0], "frequency,independent,grid");
        assert_eq!(lines.len(), 4);
        assert!(lines[1].starts_with("1,") && lines[3].starts_with("3,"));
    }
}
