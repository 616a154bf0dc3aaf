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
//!
//! The second view is of a rendered image's error ([`ErrorSpectrum`],
//! `strata converge --error-spectrum`): the periodogram of the luminance
//! of `image − reference`, mean removed, over the image's own frequency
//! grid (`kₓ / W`, `k_y / H` cycles per pixel). White noise (pixels with
//! independent errors) is flat; blue noise (neighbours' errors cancel)
//! has little power at low frequencies, where the eye sees noise most.

use std::fmt::Write as _;

use anyhow::{Result, bail};
use glam::{UVec2, Vec3};
use plotters::prelude::*;
use rayon::prelude::*;
use strata::Sampler;

use crate::job::{SamplerKind, WithSampler};
use crate::limits::MAX_RANGE;
use crate::plot;

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
    spectrum_counted(sampler, spp, seed, pixels, r, &|_| {})
}

/// [`spectrum`], calling `progress` with the pixel count of each
/// finished chunk of pixels.
pub fn spectrum_counted(
    sampler: SamplerKind,
    spp: u32,
    seed: u64,
    pixels: u32,
    r: u32,
    progress: &(dyn Fn(u64) + Sync),
) -> Result<Spectrum> {
    spectrum_of_dims(sampler, spp, seed, pixels, r, [0, 1], progress)
}

/// The most dimensions [`spectrum_of_dims`] draws per sample.
pub const MAX_DIMS: u32 = 64;

/// [`spectrum_counted`] of the 2-D projection of the samples onto the
/// dimensions `dims` (x then y) of each sample's row, as the renderer
/// draws it: `[0, 1]` is the position in the pixel, higher pairs what a
/// path's bounces draw.
///
/// # Errors
/// [`spectrum`]'s, and `dims` equal or past [`MAX_DIMS`].
pub fn spectrum_of_dims(
    sampler: SamplerKind,
    spp: u32,
    seed: u64,
    pixels: u32,
    r: u32,
    dims: [u32; 2],
    progress: &(dyn Fn(u64) + Sync),
) -> Result<Spectrum> {
    if spp == 0 || pixels == 0 || r == 0 || r > MAX_RANGE {
        bail!("spectrum of {spp} spp over {pixels} pixels up to frequency {r}: out of range");
    }
    if dims[0] == dims[1] || dims.iter().any(|&d| d >= MAX_DIMS) {
        bail!(
            "spectrum of dimensions {} and {}: two different dimensions below {MAX_DIMS}",
            dims[0],
            dims[1]
        );
    }
    // The pixels are a row-major run of a 64-pixel-wide image.
    let resolution = UVec2::new(64, pixels.div_ceil(64));
    let work = Average {
        spp,
        pixels,
        r,
        dims,
        progress,
    };
    let power = sampler.with_sampler(spp, seed, resolution, work)?;
    Ok(Spectrum {
        sampler,
        spp,
        pixels,
        r,
        power,
    })
}

/// The averaged periodogram, for one sampler kind.
struct Average<'p> {
    spp: u32,
    pixels: u32,
    r: u32,
    dims: [u32; 2],
    progress: &'p (dyn Fn(u64) + Sync),
}

impl WithSampler for Average<'_> {
    type Output = Vec<f64>;
    fn run<S: Sampler + Clone + Send + Sync>(self, sampler: S) -> Vec<f64> {
        average(sampler, &self)
    }
}

fn average<S: Sampler + Clone + Send + Sync>(sampler: S, work: &Average<'_>) -> Vec<f64> {
    let &Average {
        spp,
        pixels,
        r,
        dims,
        progress,
    } = work;
    let row_len = dims[0].max(dims[1]) as usize + 1;
    let side = 2 * r as usize + 1;
    let one = |i: u32| {
        let mut s = sampler.clone();
        let pixel = UVec2::new(i % 64, i / 64);
        // Per axis, e^{−2πi ω t} for ω in −r..=r, as (re, im).
        let mut ex = vec![(0.0f64, 0.0f64); side];
        let mut ey = vec![(0.0f64, 0.0f64); side];
        let mut f = vec![(0.0f64, 0.0f64); side * side];
        let mut row = vec![0.0f32; row_len];
        for k in 0..spp {
            let (x, y) = if dims == [0, 1] {
                s.start_pixel_sample(pixel, k);
                let p = s.pixel_2d();
                (p.x, p.y)
            } else {
                s.fill_run(pixel, k, row_len, &mut row);
                (row[dims[0] as usize], row[dims[1] as usize])
            };
            powers(x as f64, r, &mut ex);
            powers(y as f64, r, &mut ey);
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
        let run = c * 16..(c * 16 + 16).min(pixels);
        let n = run.len() as u64;
        let sum = run.map(one).reduce(add).expect("a chunk holds a pixel");
        progress(n);
        sum
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

/// The low band of the error spectra: frequencies below 0.125 cycles per
/// pixel (wavelengths above 8 pixels).
pub const LOW_BAND: f64 = 0.125;

/// The periodogram of a rendered image's error, averaged over seeds.
#[derive(Clone, Debug)]
pub struct ErrorSpectrum {
    /// Image width of the error images, in pixels.
    pub width: usize,
    /// Image height.
    pub height: usize,
    /// Error images averaged.
    pub images: u32,
    /// `P(kₓ, k_y) = |Σ e(x, y) e^{−2πi (kₓ x / W + k_y y / H)}|² / (W H)`
    /// summed over the images, row-major over `k_y` then `kₓ`, each in
    /// DFT order `0..n` (a `k > n/2` is the frequency `k − n`).
    sum: Vec<f64>,
}

impl ErrorSpectrum {
    /// An empty average for `width × height` error images.
    #[must_use]
    pub fn new(width: usize, height: usize) -> Self {
        ErrorSpectrum {
            width,
            height,
            images: 0,
            sum: vec![0.0; width * height],
        }
    }

    /// Adds the periodogram of the luminance error of `image` against
    /// `reference` (linear RGB, row-major, `width × height`), its mean
    /// removed first.
    ///
    /// # Panics
    /// If either slice is not `width × height` long.
    pub fn add(&mut self, image: &[Vec3], reference: &[Vec3]) {
        let n = self.width * self.height;
        assert!(image.len() == n && reference.len() == n, "image size");
        let lum = crate::image_io::luminance;
        let mut e: Vec<f64> = image
            .iter()
            .zip(reference)
            .map(|(&a, &b)| lum(a) - lum(b))
            .collect();
        let mean = e.iter().sum::<f64>() / n as f64;
        e.iter_mut().for_each(|v| *v -= mean);
        let power = periodogram(&e, self.width, self.height);
        self.sum.iter_mut().zip(power).for_each(|(s, p)| *s += p);
        self.images += 1;
    }

    /// The frequency of DFT bin `k` of `n`, in cycles per pixel.
    fn frequency(k: usize, n: usize) -> f64 {
        let k = if 2 * k > n {
            k as f64 - n as f64
        } else {
            k as f64
        };
        k / n as f64
    }

    /// Every bin as (|frequency| in cycles per pixel, mean power), the zero
    /// frequency left out.
    fn bins(&self) -> impl Iterator<Item = (f64, f64)> + '_ {
        let div = self.images.max(1) as f64;
        (0..self.height).flat_map(move |ky| {
            let fy = Self::frequency(ky, self.height);
            (0..self.width).filter_map(move |kx| {
                let fx = Self::frequency(kx, self.width);
                let f = (fx * fx + fy * fy).sqrt();
                (f > 0.0).then(|| (f, self.sum[ky * self.width + kx] / div))
            })
        })
    }

    /// The mean power over the frequencies with `0 < |f| < below` cycles
    /// per pixel (0 if there are none).
    #[must_use]
    pub fn band_power(&self, below: f64) -> f64 {
        let (sum, count) = self
            .bins()
            .filter(|&(f, _)| f < below)
            .fold((0.0, 0u32), |(s, c), (_, p)| (s + p, c + 1));
        if count == 0 { 0.0 } else { sum / count as f64 }
    }

    /// The mean power over every frequency but zero, for normalising: by
    /// Parseval, `n / (n − 1)` times the error's variance over the `n`
    /// pixels (the mean is removed, so the zero frequency holds nothing).
    #[must_use]
    pub fn total_power(&self) -> f64 {
        self.band_power(f64::INFINITY)
    }

    /// The radial average in `bins` rings of equal width up to 0.5 cycles
    /// per pixel, as (ring centre, mean power); empty rings are left out.
    #[must_use]
    pub fn radial(&self, bins: usize) -> Vec<(f64, f64)> {
        let width = 0.5 / bins as f64;
        let mut sum = vec![0.0; bins];
        let mut count = vec![0u32; bins];
        for (f, p) in self.bins() {
            let b = (f / width) as usize;
            if b < bins {
                sum[b] += p;
                count[b] += 1;
            }
        }
        (0..bins)
            .filter(|&b| count[b] > 0)
            .map(|b| ((b as f64 + 0.5) * width, sum[b] / count[b] as f64))
            .collect()
    }
}

/// `|DFT(e)|² / (W H)` of a `width × height` row-major image, by separable
/// direct transforms (`W H (W + H)` complex multiply-adds).
fn periodogram(e: &[f64], width: usize, height: usize) -> Vec<f64> {
    let twiddles = |n: usize| -> Vec<(f64, f64)> {
        (0..n)
            .map(|k| {
                let a = -2.0 * std::f64::consts::PI * k as f64 / n as f64;
                (a.cos(), a.sin())
            })
            .collect()
    };
    let (tx, ty) = (twiddles(width), twiddles(height));
    // Rows: F(kx, y).
    let mut rows = vec![(0.0f64, 0.0f64); width * height];
    for y in 0..height {
        let src = &e[y * width..][..width];
        for kx in 0..width {
            let (mut re, mut im) = (0.0, 0.0);
            for (x, &v) in src.iter().enumerate() {
                let (c, s) = tx[(kx * x) % width];
                re += v * c;
                im += v * s;
            }
            rows[y * width + kx] = (re, im);
        }
    }
    // Columns: F(kx, ky).
    let mut out = vec![0.0; width * height];
    let norm = (width * height) as f64;
    for kx in 0..width {
        for ky in 0..height {
            let (mut re, mut im) = (0.0, 0.0);
            for y in 0..height {
                let (a, b) = rows[y * width + kx];
                let (c, s) = ty[(ky * y) % height];
                re += a * c - b * s;
                im += a * s + b * c;
            }
            out[ky * width + kx] = (re * re + im * im) / norm;
        }
    }
    out
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

    /// A projection's spectrum is of the dimensions asked for, in the
    /// order asked for: (1, 0) is (0, 1) transposed, and both come from
    /// the drawn rows, as the renderer draws them.
    #[test]
    fn projections_take_the_dimensions_asked_for() {
        let of = |kind, dims| spectrum_of_dims(kind, 16, 3, 40, 6, dims, &|_| {}).unwrap();
        for kind in SamplerKind::ALL {
            let xy = of(kind, [0, 1]);
            assert_eq!(xy.power, spectrum(kind, 16, 3, 40, 6).unwrap().power);
            let yx = of(kind, [1, 0]);
            for wy in -6..=6 {
                for wx in -6..=6 {
                    let (a, b) = (xy.at(wx, wy), yx.at(wy, wx));
                    assert!(
                        (a - b).abs() <= 1e-9 * a.abs().max(1.0),
                        "{kind:?} ({wx}, {wy})"
                    );
                }
            }
            // A bounce's pair is another pattern.
            assert_ne!(of(kind, [2, 3]).power, xy.power, "{kind:?}");
        }
        // A 4 × 4 grid puts all its power at multiples of 4.
        let grid = of(SamplerKind::Grid, [0, 1]);
        assert!((grid.at(4, 0) - 16.0).abs() < 1e-6 && grid.at(1, 0) < 1e-6);
        for bad in [[0, 0], [3, 3], [0, MAX_DIMS], [MAX_DIMS, 1]] {
            assert!(spectrum_of_dims(SamplerKind::Sobol, 16, 3, 4, 6, bad, &|_| {}).is_err());
        }
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
    fn error_periodogram_finds_a_wave_and_keeps_parseval() {
        // A cosine of 2 cycles across a 16-pixel width: all its power at
        // kx = ±2, none at DC or elsewhere; the mean power over the
        // non-zero frequencies is the variance (Parseval).
        let (w, h) = (16, 8);
        let image: Vec<Vec3> = (0..w * h)
            .map(|i| {
                let x = (i % w) as f64;
                Vec3::splat((3.0 + (2.0 * std::f64::consts::TAU * x / w as f64).cos()) as f32)
            })
            .collect();
        let reference = vec![Vec3::ZERO; w * h];
        let mut s = ErrorSpectrum::new(w, h);
        s.add(&image, &reference);
        let p = |kx: usize, ky: usize| s.sum[ky * w + kx];
        let n = (w * h) as f64;
        // |Σ cos|² / n = (n/2)² / n at each of ±2 (luminance weights sum to 1).
        assert!((p(2, 0) - n / 4.0).abs() < 1e-3 && (p(w - 2, 0) - n / 4.0).abs() < 1e-3);
        assert!(p(0, 0).abs() < 1e-9 && p(1, 0).abs() < 1e-9 && p(2, 1).abs() < 1e-9);
        let variance = 0.5; // of a unit cosine
        assert!((s.total_power() * (n - 1.0) / n - variance).abs() < 1e-3);
        // 2/16 = 0.125 cycles per pixel: not below the low band's edge.
        assert!(s.band_power(LOW_BAND) < 1e-9);
        assert!(s.band_power(0.13) > 0.0);
        let radial = s.radial(4);
        assert!(radial.iter().all(|&(f, _)| f > 0.0 && f < 0.5));
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
