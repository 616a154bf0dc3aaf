//! `strata converge`: RMSE against spp for every sampler, against a cached
//! high-spp reference, as a CSV, a log–log plot and fitted slopes.

use std::fmt::Write as _;
use std::path::{Path, PathBuf};

use anyhow::{Result, bail};
use strata::render::Tile;

use crate::cli::ConvergeArgs;
use crate::commands::output::same_path;
use crate::commands::{check_output_ext, height_for, resolve_scene, window_of};
use crate::image_io::{say, write_atomic};
use crate::limits::MAX_PIXELS;
use crate::plot;
use crate::render::SamplerKind;
use crate::spectrum::{ErrorSpectrum, LOW_BAND};
use crate::study;

/// Runs `strata converge`.
pub fn converge(args: &ConvergeArgs) -> Result<()> {
    use crate::study::View;
    let scene = resolve_scene(&args.scene)?;
    let width = args.width.unwrap_or(scene.defaults.width);
    let height = height_for(&scene, width)?;
    if width as u64 * height as u64 > MAX_PIXELS {
        bail!("{width} x {height} is over {MAX_PIXELS} pixels");
    }
    let window = match args.pixel_bounds {
        Some(b) => window_of(b, width, height)?,
        None => Tile {
            x0: width / 4,
            y0: height / 4,
            width: (width / 2).max(1),
            height: (height / 2).max(1),
        },
    };
    let mut spps = if args.spps.is_empty() {
        vec![1u32, 4, 16, 64, 256]
    } else {
        args.spps.clone()
    };
    if args.with_1024 {
        spps.push(1024);
    }
    spps.sort_unstable();
    spps.dedup();
    let top = *spps.last().expect("spp list");
    // The reference's own error adds to every measured point: at 16 times
    // the largest spp it adds at most about 3 % to the last point's RMSE.
    if args.reference_spp < 16 * top {
        bail!(
            "--reference-spp {} must be at least 16 x {top} (the largest measured spp)",
            args.reference_spp
        );
    }
    let samplers = if args.samplers.is_empty() {
        SamplerKind::ALL.to_vec()
    } else {
        // In the order given, each once.
        let mut v = args.samplers.clone();
        let mut seen = Vec::new();
        v.retain(|s| {
            let first = !seen.contains(s);
            seen.push(*s);
            first
        });
        v
    };
    let csv_path = args
        .csv
        .clone()
        .unwrap_or_else(|| PathBuf::from(format!("converge-{}.csv", scene.name)));
    let plot_path = args
        .plot
        .clone()
        .unwrap_or_else(|| PathBuf::from(format!("converge-{}.png", scene.name)));
    check_output_ext(&csv_path, "csv", "--csv")?;
    check_output_ext(&plot_path, "png", "--plot")?;
    let spectrum_paths = match &args.error_spectrum {
        Some(p) => {
            check_output_ext(p, "png", "--error-spectrum")?;
            let csv = p.with_extension("csv");
            for (other, flag) in [(&plot_path, "--plot"), (&csv_path, "--csv")] {
                if same_path(p, other) || same_path(&csv, other) {
                    bail!("--error-spectrum `{}` would overwrite {flag}", p.display());
                }
            }
            Some((p.clone(), csv))
        }
        None => None,
    };
    let cache_dir = args
        .cache_dir
        .clone()
        .unwrap_or_else(study::default_cache_dir);

    let view = View {
        scene: &scene,
        width,
        height,
        window,
        max_depth: args.max_depth.unwrap_or(scene.defaults.max_depth),
        threads: args.threads as usize,
        texture_filter: strata::render::TextureFilter::None,
    };
    let started = std::time::Instant::now();
    let (reference, cached) = study::reference(&view, args.reference_spp, &cache_dir)?;
    say(&format!(
        "{}: {}x{} crop at ({}, {}) of {}x{}, depth {}; reference: sobol {} spp, {}",
        scene.name,
        window.width,
        window.height,
        window.x0,
        window.y0,
        width,
        height,
        view.max_depth,
        args.reference_spp,
        if cached {
            "cached".to_string()
        } else {
            format!("rendered in {:.1} s", started.elapsed().as_secs_f64())
        }
    ));
    let measured = study::converge(
        &view,
        &samplers,
        &spps,
        args.seeds,
        &reference,
        spectrum_paths.is_some(),
        &|_| {},
    )?;
    let points: Vec<study::Point> = measured.iter().map(|m| m.0).collect();

    let title = format!(
        "{}: RMSE of a {}x{} crop vs spp",
        scene.name, window.width, window.height
    );
    let plot = study::plot_convergence(&points, &samplers, &title, 800, 560)?;
    let text = study::csv(&points);
    plot::write_png(&plot_path, &plot, 800, 560)?;
    // Both files or neither.
    if let Err(e) = write_atomic(&csv_path, |tmp| Ok(std::fs::write(tmp, &text)?)) {
        std::fs::remove_file(&plot_path).ok();
        return Err(e.context(format!("writing `{}`", csv_path.display())));
    }

    let mut table = format!("{:<12}", "sampler");
    for spp in &spps {
        write!(table, " {:>9}", format!("{spp} spp")).ok();
    }
    table.push_str("  slope  slope>=16");
    for &s in &samplers {
        let line = study::series(&points, s);
        write!(
            table,
            "
{:<12}",
            s.name()
        )
        .ok();
        for &(_, e) in &line {
            write!(table, " {e:>9.2e}").ok();
        }
        let tail: Vec<_> = line.iter().copied().filter(|&(x, _)| x >= 16.0).collect();
        let fmt = |k: Option<f64>| k.map_or("-".into(), |k| format!("{k:.2}"));
        write!(
            table,
            "  {:>5} {:>10}",
            fmt(study::log_log_slope(&line)),
            fmt(study::log_log_slope(&tail))
        )
        .ok();
    }
    say(&table);
    say(&format!(
        "wrote {} and {}",
        csv_path.display(),
        plot_path.display()
    ));
    if let Some((png, csv)) = spectrum_paths {
        let spectra: Vec<(study::Point, ErrorSpectrum)> = measured
            .into_iter()
            .filter_map(|(p, s)| Some((p, s?)))
            .collect();
        write_error_spectra(
            &spectra,
            &samplers,
            &spps,
            args.seeds,
            &scene.name,
            &png,
            &csv,
        )?;
    }
    Ok(())
}

/// The error-spectrum view: its table, plot and CSV.
fn write_error_spectra(
    spectra: &[(study::Point, ErrorSpectrum)],
    samplers: &[SamplerKind],
    spps: &[u32],
    seeds: u32,
    scene: &str,
    png: &Path,
    csv: &Path,
) -> Result<()> {
    let first = samplers[0];
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
    for &spp in spps {
        let (p0, s0) = find(first, spp);
        for &s in samplers {
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
    let title = format!("{scene}: radial power spectrum of the error (luminance)");
    let plot = study::plot_error_spectra(spectra, &title, 800, 560)?;
    let text = study::error_csv(spectra);
    plot::write_png(png, &plot, 800, 560)?;
    if let Err(e) = write_atomic(csv, |tmp| Ok(std::fs::write(tmp, &text)?)) {
        std::fs::remove_file(png).ok();
        return Err(e.context(format!("writing `{}`", csv.display())));
    }
    say(&format!("wrote {} and {}", png.display(), csv.display()));
    Ok(())
}
