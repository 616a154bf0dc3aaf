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
use crate::plot;
use crate::render::SamplerKind;
use crate::scenes::SceneData;
use crate::spectrum::{ErrorSpectrum, LOW_BAND};
use crate::study::{self, Point, View};

/// The plot's size in pixels.
const PLOT_SIZE: (u32, u32) = (800, 560);

/// Runs `strata converge`: the plan (every check), the reference, the
/// measured points, the files, the table.
pub fn converge(args: &ConvergeArgs) -> Result<()> {
    let scene = resolve_scene(&args.scene)?;
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
    let measured = study::converge(
        view,
        &plan.samplers,
        &plan.spps,
        args.seeds,
        &reference,
        plan.error_spectrum.is_some(),
        &|_| {},
    )?;
    let points: Vec<Point> = measured.iter().map(|m| m.0).collect();
    plan.write(&points)?;
    say(&study::table(&points, &plan.samplers, &plan.spps));
    say(&format!(
        "wrote {} and {}",
        plan.csv.display(),
        plan.plot.display()
    ));
    if let Some((png, csv)) = &plan.error_spectrum {
        let spectra: Vec<(Point, ErrorSpectrum)> = measured
            .into_iter()
            .filter_map(|(p, s)| Some((p, s?)))
            .collect();
        plan.write_error_spectra(&spectra, args.seeds, png, csv)?;
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
        let width = self.width.unwrap_or(scene.defaults.width);
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
        let (csv, plot) = (named(&self.csv, "csv"), named(&self.plot, "png"));
        check_output_ext(&csv, "csv", "--csv")?;
        check_output_ext(&plot, "png", "--plot")?;
        let error_spectrum = match &self.error_spectrum {
            Some(p) => {
                check_output_ext(p, "png", "--error-spectrum")?;
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
                max_depth: self.max_depth.unwrap_or(scene.defaults.max_depth),
                threads: self.threads as usize,
                texture_filter: TextureFilter::None,
            },
            spps,
            samplers: samplers_or_all(&self.samplers),
            csv,
            plot,
            cache_dir: self
                .cache_dir
                .clone()
                .unwrap_or_else(study::default_cache_dir),
            error_spectrum,
        })
    }
}

impl ConvergePlan<'_> {
    /// Writes the plot and the CSV of `points`: both files or neither.
    fn write(&self, points: &[Point]) -> Result<()> {
        let w = self.view.window;
        let title = format!(
            "{}: RMSE of a {}x{} crop vs spp",
            self.view.scene.name, w.width, w.height
        );
        let (pw, ph) = PLOT_SIZE;
        let image = study::plot_convergence(points, &self.samplers, &title, pw, ph)?;
        let text = study::csv(points);
        plot::write_png(&self.plot, &image, pw, ph)?;
        if let Err(e) = write_text(&self.csv, &text) {
            std::fs::remove_file(&self.plot).ok();
            return Err(e);
        }
        Ok(())
    }

    /// The error-spectrum view: its table, plot and CSV (both files or
    /// neither).
    fn write_error_spectra(
        &self,
        spectra: &[(Point, ErrorSpectrum)],
        seeds: u32,
        png: &Path,
        csv: &Path,
    ) -> Result<()> {
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
        say(&table);
        let title = format!(
            "{}: radial power spectrum of the error (luminance)",
            self.view.scene.name
        );
        let (pw, ph) = PLOT_SIZE;
        let image = study::plot_error_spectra(spectra, &title, pw, ph)?;
        let text = study::error_csv(spectra);
        plot::write_png(png, &image, pw, ph)?;
        if let Err(e) = write_text(csv, &text) {
            std::fs::remove_file(png).ok();
            return Err(e);
        }
        say(&format!("wrote {} and {}", png.display(), csv.display()));
        Ok(())
    }
}
