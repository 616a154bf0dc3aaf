//! Measured studies: the convergence study (`strata converge`: RMSE
//! against a cached high-spp reference, by sampler and spp, as CSV, a
//! log–log plot and fitted slopes), the aliasing demo (`strata aliasing`:
//! one scene under several samplers side by side), adaptive against
//! uniform sampling (`strata adaptive`, [`adaptive`]) and every pixel
//! filter against the box (`strata filters`, [`filters`]).

use std::fmt::Write as _;
use std::io::{Read, Write};
use std::path::{Path, PathBuf};

use anyhow::{Result, bail};
use glam::Vec3;
use plotters::prelude::*;
use strata::render::Tile;

pub use crate::image_io::luminance;
use crate::image_io::write_atomic;
use crate::job::{Job, SamplerKind, run};
use crate::plot;
use crate::progress::Phase;
use crate::scenes::SceneData;
use crate::spectrum::{ErrorSpectrum, LOW_BAND};

pub mod adaptive;
pub mod filters;

/// Root mean square error over pixels and RGB channels, in f64.
///
/// # Panics
/// If the slices differ in length or are empty.
#[must_use]
pub fn rmse(image: &[Vec3], reference: &[Vec3]) -> f64 {
    assert_eq!(image.len(), reference.len());
    assert!(!image.is_empty());
    let sum: f64 = image
        .iter()
        .zip(reference)
        .map(|(a, b)| {
            let d = (*a - *b).as_dvec3();
            d.dot(d)
        })
        .sum();
    (sum / (3 * image.len()) as f64).sqrt()
}

/// The least-squares slope of `ln y` against `ln x`: the exponent `k` of
/// the best fit `y ≈ c·x^k`. `None` with fewer than two distinct `x` or a
/// non-positive value.
#[must_use]
pub fn log_log_slope(points: &[(f64, f64)]) -> Option<f64> {
    if points.iter().any(|&(x, y)| !(x > 0.0 && y > 0.0)) {
        return None;
    }
    let n = points.len() as f64;
    let (sx, sy) = points
        .iter()
        .fold((0.0, 0.0), |(a, b), &(x, y)| (a + x.ln(), b + y.ln()));
    let (mx, my) = (sx / n, sy / n);
    let (mut sxx, mut sxy) = (0.0, 0.0);
    for &(x, y) in points {
        let dx = x.ln() - mx;
        sxx += dx * dx;
        sxy += dx * (y.ln() - my);
    }
    (sxx > 0.0).then(|| sxy / sxx)
}

/// What a study renders: a scene, its image size, the pixel window and
/// the path depth.
#[derive(Clone, Debug)]
pub struct View<'a> {
    /// The scene.
    pub scene: &'a SceneData,
    /// Image width.
    pub width: u32,
    /// Image height.
    pub height: u32,
    /// The pixels rendered.
    pub window: Tile,
    /// Ray segments per path.
    pub max_depth: u32,
    /// Worker threads.
    pub threads: usize,
    /// Texture filtering (references are always point-sampled).
    pub texture_filter: strata::render::TextureFilter,
    /// The pixel filter of the view's renders and of its reference (the
    /// box everywhere but `strata filters`).
    pub filter: strata::render::PixelFilter,
}

impl View<'_> {
    /// Renders the window with `sampler` at `spp` and `seed`, returning the
    /// pixel means (row-major within the window); `progress` is called with
    /// each finished tile's pixel count.
    pub fn render(
        &self,
        sampler: SamplerKind,
        spp: u32,
        seed: u64,
        progress: &(dyn Fn(u64) + Sync),
    ) -> Result<Vec<Vec3>> {
        let job = Job {
            window: self.window,
            max_depth: self.max_depth,
            sampler,
            seed,
            threads: self.threads,
            texture_filter: self.texture_filter,
            filter: self.filter,
            ..Job::new(self.scene, self.width, self.height, spp)
        };
        Ok(run(&job, progress)?
            .pixels
            .iter()
            .map(|p| p.mean())
            .collect())
    }

    /// Everything the reference depends on, as one line: two views with
    /// the same key render the same reference.
    fn reference_key(&self, spp: u32) -> String {
        let w = self.window;
        // The box's key is the one every earlier cache file was made with.
        let filter = match self.filter == strata::render::PixelFilter::BOX {
            true => String::new(),
            false => format!(" filter {}", crate::film::filter_text(&self.filter)),
        };
        format!(
            "strata {} output revision {} scene {:016x} size {}x{} window {},{} {}x{} depth {} \
             direct lighting on, reference sobol {} spp seed {}{}",
            env!("CARGO_PKG_VERSION"),
            strata::render::OUTPUT_REVISION,
            self.scene.content_hash(),
            self.width,
            self.height,
            w.x0,
            w.y0,
            w.width,
            w.height,
            self.max_depth,
            spp,
            REFERENCE_SEED,
            filter
        )
    }
}

/// The seed of every reference render: apart from the seeds the studies
/// measure (0, 1, 2, …), so reference and estimate are independent.
pub const REFERENCE_SEED: u64 = u64::MAX;

const CACHE_MAGIC: &[u8] = b"strata reference v1\n";

/// Where references are cached when no directory is given:
/// `$XDG_CACHE_HOME/strata`, else `$HOME/.cache/strata`, else
/// `.strata-cache` in the current directory.
#[must_use]
pub fn default_cache_dir() -> PathBuf {
    if let Some(d) = std::env::var_os("XDG_CACHE_HOME").filter(|d| !d.is_empty()) {
        return PathBuf::from(d).join("strata");
    }
    if let Some(h) = std::env::var_os("HOME").filter(|h| !h.is_empty()) {
        return PathBuf::from(h).join(".cache").join("strata");
    }
    PathBuf::from(".strata-cache")
}

/// A high-spp reference of `view`: Sobol' at `spp` with
/// [`REFERENCE_SEED`], read from `cache_dir` when a file there was made
/// for exactly this view (the file stores its key and is checked against
/// it), else rendered and stored. Returns the pixels and whether they came
/// from the cache. A cache that cannot be read or written is ignored with
/// a warning: it only saves time. A render shows its progress as the
/// phase `reference: sobol N spp`, which ends once the reference is
/// stored: a study interrupted after it keeps its reference.
pub fn reference(view: &View<'_>, spp: u32, cache_dir: &Path) -> Result<(Vec<Vec3>, bool)> {
    let key = view.reference_key(spp);
    let n = view.window.area();
    let path = cache_dir.join(format!(
        "{}-{:016x}.ref",
        view.scene.name,
        crate::hash::fnv1a(key.as_bytes())
    ));
    if let Some(pixels) = read_reference(&path, &key, n) {
        return Ok((pixels, true));
    }
    // References are point-sampled whatever the view measures.
    let point = View {
        texture_filter: strata::render::TextureFilter::None,
        ..view.clone()
    };
    let w = view.window;
    let filter = match view.filter == strata::render::PixelFilter::BOX {
        true => String::new(),
        false => format!(", {}", crate::film::filter_text(&view.filter)),
    };
    let phase = Phase::start(
        &format!(
            "reference: sobol {spp} spp, {}x{} pixels{filter}",
            w.width, w.height
        ),
        n as u64,
    );
    let pixels = point.render(SamplerKind::Sobol, spp, REFERENCE_SEED, &|k| phase.inc(k))?;
    let stored = std::fs::create_dir_all(cache_dir)
        .map_err(anyhow::Error::from)
        .and_then(|()| write_atomic(&path, |tmp| write_reference(tmp, &key, &pixels)));
    if let Err(e) = stored {
        eprintln!(
            "warning: reference not cached at `{}`: {e:#}",
            path.display()
        );
    }
    phase.finish();
    Ok((pixels, false))
}

/// The cached pixels, or `None` if the file is missing, was made for
/// another key, or is truncated.
fn read_reference(path: &Path, key: &str, n: usize) -> Option<Vec<Vec3>> {
    let mut bytes = Vec::new();
    std::fs::File::open(path)
        .ok()?
        .take((CACHE_MAGIC.len() + key.len() + 1 + n * 12 + 1) as u64)
        .read_to_end(&mut bytes)
        .ok()?;
    let rest = bytes.strip_prefix(CACHE_MAGIC)?;
    let rest = rest.strip_prefix(key.as_bytes())?.strip_prefix(b"\n")?;
    if rest.len() != n * 12 {
        return None;
    }
    let f = |b: &[u8]| f32::from_le_bytes([b[0], b[1], b[2], b[3]]);
    Some(
        rest.chunks_exact(12)
            .map(|c| Vec3::new(f(&c[0..4]), f(&c[4..8]), f(&c[8..12])))
            .collect(),
    )
}

fn write_reference(path: &Path, key: &str, pixels: &[Vec3]) -> Result<()> {
    let mut out = std::io::BufWriter::new(std::fs::File::create(path)?);
    out.write_all(CACHE_MAGIC)?;
    out.write_all(key.as_bytes())?;
    out.write_all(b"\n")?;
    for p in pixels {
        for c in p.to_array() {
            out.write_all(&c.to_le_bytes())?;
        }
    }
    out.into_inner().map_err(|e| e.into_error())?.sync_all()?;
    Ok(())
}

/// One measured point of the convergence study.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Point {
    /// The sampler.
    pub sampler: SamplerKind,
    /// Samples per pixel.
    pub spp: u32,
    /// RMSE against the reference, root of the mean over seeds of the MSE.
    pub rmse: f64,
}

/// Renders `view` with every sampler at every spp for seeds `0..seeds`
/// and measures RMSE against `reference`; with `spectra`, also the
/// periodogram of each point's error images (luminance, mean removed)
/// averaged over the seeds: where in frequency each sampler puts its
/// error. `progress` is called with the pixel samples of each finished
/// tile (pixels × spp): the study's total is
/// [`converge_samples`].
pub fn converge(
    view: &View<'_>,
    samplers: &[SamplerKind],
    spps: &[u32],
    seeds: u32,
    reference: &[Vec3],
    spectra: bool,
    progress: &(dyn Fn(u64) + Sync),
) -> Result<Vec<(Point, Option<ErrorSpectrum>)>> {
    let (w, h) = (view.window.width as usize, view.window.height as usize);
    let mut out = Vec::new();
    for &sampler in samplers {
        for &spp in spps {
            let mut mse = 0.0;
            let mut spectrum = spectra.then(|| ErrorSpectrum::new(w, h));
            for seed in 0..seeds {
                let image =
                    view.render(sampler, spp, seed as u64, &|n| progress(n * spp as u64))?;
                let e = rmse(&image, reference);
                mse += e * e;
                if let Some(s) = &mut spectrum {
                    s.add(&image, reference);
                }
            }
            let point = Point {
                sampler,
                spp,
                rmse: (mse / seeds as f64).sqrt(),
            };
            out.push((point, spectrum));
        }
    }
    Ok(out)
}

/// The pixel samples [`converge`] renders: every sampler at every spp for
/// every seed, over the view's window.
#[must_use]
pub fn converge_samples(view: &View<'_>, samplers: usize, spps: &[u32], seeds: u32) -> u64 {
    let per_sampler: u64 = spps.iter().map(|&s| s as u64).sum();
    per_sampler * samplers as u64 * seeds as u64 * view.window.area() as u64
}

/// The rings of the error-spectrum plot and CSV, up to 0.5 cycles per
/// pixel.
pub const ERROR_RINGS: usize = 32;

/// The radial error spectra as CSV: `frequency,SAMPLER@SPP…`, frequency in
/// cycles per pixel (ring centres), power per pixel of error luminance.
#[must_use]
pub fn error_csv(points: &[(Point, ErrorSpectrum)]) -> String {
    let mut s = String::from("frequency");
    for (p, _) in points {
        write!(s, ",{}@{}", p.sampler.name(), p.spp).expect("a String");
    }
    s.push('\n');
    let radial: Vec<Vec<(f64, f64)>> = points.iter().map(|(_, e)| e.radial(ERROR_RINGS)).collect();
    let rows = radial.iter().map(Vec::len).max().unwrap_or(0);
    for i in 0..rows {
        let f = radial.iter().find_map(|r| r.get(i)).map_or(0.0, |p| p.0);
        write!(s, "{f:.6}").expect("a String");
        for r in &radial {
            match r.get(i) {
                Some((_, p)) => write!(s, ",{p:.6e}"),
                None => write!(s, ","),
            }
            .expect("a String");
        }
        s.push('\n');
    }
    s
}

/// Draws the radial error spectra (log power against frequency, one line
/// per sampler and spp, lighter for fewer samples; the low band's edge
/// dashed) into an 8-bit RGB buffer of `width × height`.
pub fn plot_error_spectra(
    points: &[(Point, ErrorSpectrum)],
    title: &str,
    width: u32,
    height: u32,
) -> Result<Vec<u8>> {
    let radial: Vec<Vec<(f64, f64)>> = points
        .iter()
        .map(|(_, e)| {
            e.radial(ERROR_RINGS)
                .into_iter()
                .filter(|&(_, p)| p > 0.0)
                .collect()
        })
        .collect();
    let (y0, y1) = radial
        .iter()
        .flatten()
        .fold((f64::MAX, f64::MIN), |(a, b), &(_, p)| (a.min(p), b.max(p)));
    if y0 > y1 {
        bail!("nothing to plot: no error power above zero");
    }
    let spps: Vec<u32> = {
        let mut v: Vec<u32> = points.iter().map(|(p, _)| p.spp).collect();
        v.sort_unstable();
        v.dedup();
        v
    };
    plot::chart(width, height, |root| {
        let mut chart = plot::titled(root, title, 70)
            .build_cartesian_2d(0.0..0.5, (y0 / 1.5..y1 * 1.5).log_scale())?;
        chart
            .configure_mesh()
            .x_desc("frequency |f| (cycles per pixel)")
            .y_desc("error power per pixel")
            .label_style(("sans-serif", 15))
            .max_light_lines(0)
            .y_label_formatter(&|y| format!("{y:.0e}"))
            .draw()?;
        let edge = [(LOW_BAND, y0 / 1.5), (LOW_BAND, y1 * 1.5)];
        chart
            .draw_series(DashedLineSeries::new(edge, 6, 4, BLACK.stroke_width(1)))?
            .label(format!("{LOW_BAND} cycles per pixel"))
            .legend(plot::legend_line(BLACK));
        for ((p, _), line) in points.iter().zip(&radial) {
            // Fewer samples, lighter line: mix towards white.
            let rank = spps.iter().position(|&s| s == p.spp).unwrap_or(0);
            let t = 0.6 * (spps.len() - 1 - rank) as f64 / spps.len().max(1) as f64;
            let RGBColor(r, g, b) = plot::colour(p.sampler);
            let mix = |c: u8| (c as f64 + (255.0 - c as f64) * t).round() as u8;
            let c = RGBColor(mix(r), mix(g), mix(b));
            chart
                .draw_series(LineSeries::new(line.clone(), c.stroke_width(2)))?
                .label(format!("{}, {} spp", p.sampler.name(), p.spp))
                .legend(plot::legend_line(c.stroke_width(2)));
        }
        plot::legend(&mut chart, SeriesLabelPosition::LowerRight)
    })
}

/// The study's CSV: `sampler,spp,rmse`, one row per point.
#[must_use]
pub fn csv(points: &[Point]) -> String {
    let mut s = String::from("sampler,spp,rmse\n");
    for p in points {
        writeln!(s, "{},{},{:.9e}", p.sampler.name(), p.spp, p.rmse).expect("a String");
    }
    s
}

/// The points of one sampler as `(spp, rmse)`.
#[must_use]
pub fn series(points: &[Point], sampler: SamplerKind) -> Vec<(f64, f64)> {
    points
        .iter()
        .filter(|p| p.sampler == sampler)
        .map(|p| (p.spp as f64, p.rmse))
        .collect()
}

/// The study's results as a table for the terminal: a row per sampler,
/// its RMSE at each of `spps`, and the fitted log–log slope over all of
/// them and over 16 spp and up (where the asymptotic rate shows).
#[must_use]
pub fn table(points: &[Point], samplers: &[SamplerKind], spps: &[u32]) -> String {
    let mut table = format!("{:<12}", "sampler");
    for spp in spps {
        write!(table, " {:>9}", format!("{spp} spp")).expect("a String");
    }
    table.push_str("  slope  slope>=16");
    let slope = |line: &[(f64, f64)]| log_log_slope(line).map_or("-".into(), |k| format!("{k:.2}"));
    for &s in samplers {
        let line = series(points, s);
        write!(table, "\n{:<12}", s.name()).expect("a String");
        for &(_, e) in &line {
            write!(table, " {e:>9.2e}").expect("a String");
        }
        let tail: Vec<_> = line.iter().copied().filter(|&(x, _)| x >= 16.0).collect();
        write!(table, "  {:>5} {:>10}", slope(&line), slope(&tail)).expect("a String");
    }
    table
}

/// Draws the log–log convergence plot of `points` (one line per sampler,
/// labelled with its fitted slope, and a dashed `spp^-1/2` guide) into an
/// 8-bit RGB buffer of `width × height`.
pub fn plot_convergence(
    points: &[Point],
    samplers: &[SamplerKind],
    title: &str,
    width: u32,
    height: u32,
) -> Result<Vec<u8>> {
    let xs = points.iter().map(|p| p.spp as f64);
    let ys = points.iter().map(|p| p.rmse).filter(|&y| y > 0.0);
    let (x0, x1) = xs.fold((f64::MAX, f64::MIN), |(a, b), x| (a.min(x), b.max(x)));
    let (y0, y1) = ys.fold((f64::MAX, f64::MIN), |(a, b), y| (a.min(y), b.max(y)));
    if !(x0 <= x1 && y0 <= y1) {
        bail!("nothing to plot: no point has a positive RMSE");
    }
    plot::chart(width, height, |root| {
        let mut chart = plot::titled(root, title, 70).build_cartesian_2d(
            (x0 / 1.5..x1 * 1.5).log_scale(),
            (y0 / 1.5..y1 * 1.5).log_scale(),
        )?;
        chart
            .configure_mesh()
            .x_desc("samples per pixel")
            .y_desc("RMSE")
            .label_style(("sans-serif", 15))
            .x_labels(12)
            .y_labels(12)
            .max_light_lines(0)
            .x_label_formatter(&|x| format!("{x:.0}"))
            .y_label_formatter(&|y| format!("{y:.0e}"))
            .draw()?;
        for &s in samplers {
            let line = series(points, s);
            let Some(&(gx, gy)) = line.first() else {
                continue;
            };
            let c = plot::colour(s);
            let label = match log_log_slope(&line) {
                Some(k) => format!("{} (slope {k:.2})", s.name()),
                None => s.name().to_string(),
            };
            chart
                .draw_series(LineSeries::new(line.clone(), c.stroke_width(2)))?
                .label(label)
                .legend(plot::legend_line(c.stroke_width(2)));
            chart.draw_series(line.iter().map(|&p| Circle::new(p, 4, c.filled())))?;
            if s == SamplerKind::Independent {
                // The Monte Carlo rate through the first independent point.
                let guide = [(gx, gy), (x1, gy * (x1 / gx).powf(-0.5))];
                chart
                    .draw_series(DashedLineSeries::new(guide, 6, 4, BLACK.stroke_width(1)))?
                    .label("spp^-1/2")
                    .legend(plot::legend_line(BLACK));
            }
        }
        plot::legend(&mut chart, SeriesLabelPosition::LowerLeft)
    })
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn slope_of_a_power_law() {
        let pts: Vec<_> = [1.0, 4.0, 16.0, 64.0]
            .iter()
            .map(|&x: &f64| (x, 3.0 * x.powf(-0.75)))
            .collect();
        assert!((log_log_slope(&pts).unwrap() + 0.75).abs() < 1e-12);
        assert_eq!(log_log_slope(&[(1.0, 1.0)]), None);
        assert_eq!(log_log_slope(&[(1.0, 1.0), (2.0, 0.0)]), None);
        assert_eq!(log_log_slope(&[(2.0, 1.0), (2.0, 3.0)]), None);
    }

    #[test]
    fn rmse_counts_every_channel() {
        let a = [Vec3::ZERO, Vec3::ZERO];
        let b = [Vec3::new(3.0, 0.0, 0.0), Vec3::ZERO];
        // One squared error of 9 over 6 values.
        assert!((rmse(&a, &b) - 1.5f64.sqrt()).abs() < 1e-12);
        assert_eq!(rmse(&b, &b), 0.0);
    }

    #[test]
    fn reference_cache_round_trips_and_checks_its_key() {
        let dir = tempfile::tempdir().unwrap();
        let path = dir.path().join("r.ref");
        let pixels = vec![Vec3::new(0.1, -2.0, f32::MAX), Vec3::splat(1e-30)];
        write_reference(&path, "key a", &pixels).unwrap();
        assert_eq!(read_reference(&path, "key a", 2), Some(pixels));
        assert_eq!(read_reference(&path, "key b", 2), None);
        assert_eq!(read_reference(&path, "key a", 3), None);
        // Truncated by one byte.
        let bytes = std::fs::read(&path).unwrap();
        std::fs::write(&path, &bytes[..bytes.len() - 1]).unwrap();
        assert_eq!(read_reference(&path, "key a", 2), None);
    }
}
