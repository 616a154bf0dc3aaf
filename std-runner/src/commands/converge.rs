//! `strata converge`: RMSE against spp for every sampler, against a cached
//! high-spp reference, as a CSV, a log–log plot and fitted slopes.

use std::fmt::Write as _;
use std::path::{Path, PathBuf};
use std::time::Instant;

use anyhow::{Result, bail};
use strata::render::{TextureFilter, Tile};

use crate::cli::ConvergeArgs;
use crate::commands::output::{same_path, write_text};
use crate::commands::{
    check_output_ext, check_pixels, height_for, resolve_scene, samplers_or_all, window_of,
};
use crate::image_io::say;
use crate::job::SamplerKind;
use crate::limits::MAX_SPECTRUM_SIDE;
use crate::plot;
use crate::progress::Phase;
use crate::scenes::SceneData;
use crate::spectrum::{ErrorSpectrum, LOW_BAND};
use crate::study::{self, Point, View};

/// The scene the study measures unless `--scene` names another.
const DEFAULT_SCENE: &str = "week09";
/// Seeds per point unless `--seeds` says otherwise.
const DEFAULT_SEEDS: u32 = 1;

/// The plot's size in pixels.
const PLOT_SIZE: (u32, u32) = (800, 560);

/// Runs `strata converge`: the plan (every check), the reference, the
/// measured points, the files, the table.
pub fn converge(args: &ConvergeArgs) -> Result<()> {
    let scene = resolve_scene(args.study.scene_or(DEFAULT_SCENE))?;
    let plan = args.plan(&scene)?;
    let view = &plan.view;
    let started = Instant::now();
    let (reference, cached) = study::reference(view, args.reference_spp, &plan.cache_dir)?;
    let w = view.window;
    say(&format!(
        "{}: {}x{} crop at ({}, {}) of {}x{}, depth {}; reference: sobol {} spp, {}",
        scene.name,
        w.width,
        w.height,
        w.x0,
        w.y0,
        view.width,
        view.height,
        view.max_depth,
        args.reference_spp,
        if cached {
            "cached".to_string()
        } else {
            format!("rendered in {:.1} s", started.elapsed().as_secs_f64())
        }
    ));
    let total = study::converge_samples(
        view,
        plan.samplers.len(),
        &plan.spps,
        args.study.seeds_or(DEFAULT_SEEDS),
    );
    let phase = Phase::start(
        &format!(
            "measuring: {} samplers at {} spp counts, {} seed(s)",
            plan.samplers.len(),
            plan.spps.len(),
            args.study.seeds_or(DEFAULT_SEEDS)
        ),
        total,
    );
    let measured = study::converge(
        view,
        &plan.samplers,
        &plan.spps,
        args.study.seeds_or(DEFAULT_SEEDS),
        &reference,
        plan.error_spectrum.is_some(),
        &|n| phase.inc(n),
    )?;
    phase.finish();
    let points: Vec<Point> = measured.iter().map(|m| m.0).collect();
    let spectra: Option<Vec<(Point, ErrorSpectrum)>> = plan.error_spectrum.as_ref().map(|_| {
        measured
            .into_iter()
            .filter_map(|(p, s)| Some((p, s?)))
            .collect()
    });
    // Every file is drawn before any is written: all of them or none.
    let mut files = plan.convergence_files(&points)?;
    if let (Some(spectra), Some((png, csv))) = (&spectra, &plan.error_spectrum) {
        files.extend(plan.error_spectrum_files(spectra, png, csv)?);
    }
    write_all(&files)?;
    say(&study::table(&points, &plan.samplers, &plan.spps));
    if let Some(spectra) = &spectra {
        say(&plan.error_spectrum_table(spectra, args.study.seeds_or(DEFAULT_SEEDS)));
    }
    let names: Vec<String> = files.iter().map(|f| f.0.display().to_string()).collect();
    say(&format!("wrote {}", names.join(", ")));
    Ok(())
}

/// A file `strata converge` writes: a PNG (8-bit RGB and its size) or a
/// text.
enum Contents {
    Png(Vec<u8>, u32, u32),
    Text(String),
}

/// Writes every file, or none: a failure removes those this run already
/// wrote (each replaced its old file atomically, so an old file of the
/// same name is gone too).
fn write_all(files: &[(PathBuf, Contents)]) -> Result<()> {
    for (i, (path, contents)) in files.iter().enumerate() {
        let written = match contents {
            Contents::Png(rgb, w, h) => plot::write_png(path, rgb, *w, *h),
            Contents::Text(text) => write_text(path, text),
        };
        if let Err(e) = written {
            for (done, _) in &files[..i] {
                std::fs::remove_file(done).ok();
            }
            return Err(e);
        }
    }
    Ok(())
}

/// `strata converge` with every flag checked.
struct ConvergePlan<'a> {
    /// The scene, size and crop measured.
    view: View<'a>,
    /// The spp of the measured points.
    spps: Vec<u32>,
    /// The samplers measured, in order.
    samplers: Vec<SamplerKind>,
    /// The CSV written.
    csv: PathBuf,
    /// The plot written.
    plot: PathBuf,
    /// Where the reference is cached.
    cache_dir: PathBuf,
    /// The error-spectrum plot and its CSV, if asked for.
    error_spectrum: Option<(PathBuf, PathBuf)>,
}

impl ConvergeArgs {
    /// Checks every flag against `scene`: the size and crop, the spp
    /// list against the reference, the files.
    fn plan<'a>(&self, scene: &'a SceneData) -> Result<ConvergePlan<'a>> {
        let width = self.study.width.unwrap_or(scene.defaults.width);
        let height = height_for(scene, width, None)?;
        check_pixels(width, height, 1)?;
        let window = match self.pixel_bounds {
            Some(b) => window_of(b, width, height)?,
            None => Tile {
                x0: width / 4,
                y0: height / 4,
                width: (width / 2).max(1),
                height: (height / 2).max(1),
            },
        };
        let mut spps = if self.spps.is_empty() {
            vec![1u32, 4, 16, 64, 256]
        } else {
            self.spps.clone()
        };
        if self.with_1024 {
            spps.push(1024);
        }
        spps.sort_unstable();
        spps.dedup();
        let top = *spps.last().expect("spp list");
        // The reference's own error adds to every measured point: at 16
        // times the largest spp it adds at most about 3 % to the last
        // point's RMSE.
        if self.reference_spp < 16 * top {
            bail!(
                "--reference-spp {} must be at least 16 x {top} (the largest measured spp)",
                self.reference_spp
            );
        }
        let named = |flag: &Option<PathBuf>, ext: &str| {
            flag.clone()
                .unwrap_or_else(|| PathBuf::from(format!("converge-{}.{ext}", scene.name)))
        };
        let (csv, plot) = (named(&self.study.csv, "csv"), named(&self.plot, "png"));
        check_output_ext(&csv, "csv", "--csv")?;
        check_output_ext(&plot, "png", "--plot")?;
        let error_spectrum = match &self.error_spectrum {
            Some(p) => {
                check_output_ext(p, "png", "--error-spectrum")?;
                // The low band needs a frequency below LOW_BAND other than
                // 0 (the mean, removed); the periodogram is a direct
                // transform kept per point, so its window is capped.
                if window.width.max(window.height) as f64 * LOW_BAND <= 1.0 {
                    bail!(
                        "--error-spectrum needs a window wider or taller than {} pixels \
                         (its low band is below {LOW_BAND} cycles per pixel); this one is {}x{}",
                        (1.0 / LOW_BAND) as u32,
                        window.width,
                        window.height
                    );
                }
                if window.width.max(window.height) > MAX_SPECTRUM_SIDE {
                    bail!(
                        "--error-spectrum takes windows of at most {MAX_SPECTRUM_SIDE} pixels a \
                         side; this one is {}x{} (narrow it with --pixel-bounds)",
                        window.width,
                        window.height
                    );
                }
                let beside = p.with_extension("csv");
                for (other, flag) in [(&plot, "--plot"), (&csv, "--csv")] {
                    if same_path(p, other) || same_path(&beside, other) {
                        bail!("--error-spectrum `{}` would overwrite {flag}", p.display());
                    }
                }
                Some((p.clone(), beside))
            }
            None => None,
        };
        Ok(ConvergePlan {
            view: View {
                scene,
                width,
                height,
                window,
                max_depth: self.study.max_depth.unwrap_or(scene.defaults.max_depth),
                threads: self.study.threads as usize,
                texture_filter: TextureFilter::None,
                filter: strata::render::PixelFilter::BOX,
            },
            spps,
            samplers: samplers_or_all(&self.samplers),
            csv,
            plot,
            cache_dir: super::cache_dir(&self.study),
            error_spectrum,
        })
    }
}

impl ConvergePlan<'_> {
    /// The plot and the CSV of `points`.
    fn convergence_files(&self, points: &[Point]) -> Result<Vec<(PathBuf, Contents)>> {
        let w = self.view.window;
        let title = format!(
            "{}: RMSE of a {}x{} crop vs spp",
            self.view.scene.name, w.width, w.height
        );
        let (pw, ph) = PLOT_SIZE;
        let image = study::plot_convergence(points, &self.samplers, &title, pw, ph)?;
        Ok(vec![
            (self.plot.clone(), Contents::Png(image, pw, ph)),
            (self.csv.clone(), Contents::Text(study::csv(points))),
        ])
    }

    /// The error-spectrum view's plot and CSV.
    fn error_spectrum_files(
        &self,
        spectra: &[(Point, ErrorSpectrum)],
        png: &Path,
        csv: &Path,
    ) -> Result<Vec<(PathBuf, Contents)>> {
        let title = format!(
            "{}: radial power spectrum of the error (luminance)",
            self.view.scene.name
        );
        let (pw, ph) = PLOT_SIZE;
        let image = study::plot_error_spectra(spectra, &title, pw, ph)?;
        Ok(vec![
            (png.to_path_buf(), Contents::Png(image, pw, ph)),
            (csv.to_path_buf(), Contents::Text(study::error_csv(spectra))),
        ])
    }

    /// The error-spectrum table: each point's RMSE and low-band power, and
    /// their ratios to the first sampler's.
    fn error_spectrum_table(&self, spectra: &[(Point, ErrorSpectrum)], seeds: u32) -> String {
        let first = self.samplers[0];
        let find = |s: SamplerKind, spp: u32| {
            spectra
                .iter()
                .find(|(p, _)| p.sampler == s && p.spp == spp)
                .expect("every sampler at every spp")
        };
        let mut table = format!(
            "error spectrum over {seeds} seed(s); low band: below {LOW_BAND} cycles per pixel; \
             ratios to {}\n{:>6} {:<12} {:>10} {:>7} {:>11} {:>7} {:>10}",
            first.name(),
            "spp",
            "sampler",
            "RMSE",
            "ratio",
            "low power",
            "ratio",
            "low/total"
        );
        for &spp in &self.spps {
            let (p0, s0) = find(first, spp);
            for &s in &self.samplers {
                let (p, e) = find(s, spp);
                let low = e.band_power(LOW_BAND);
                write!(
                    table,
                    "\n{spp:>6} {:<12} {:>10.4e} {:>7.3} {:>11.4e} {:>7.3} {:>10.3}",
                    s.name(),
                    p.rmse,
                    p.rmse / p0.rmse,
                    low,
                    low / s0.band_power(LOW_BAND),
                    low / e.total_power()
                )
                .ok();
            }
        }
        table
    }
}
