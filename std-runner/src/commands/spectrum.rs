//! `strata spectrum`: the samplers' pixel patterns in the Fourier domain,
//! as panels, a radial plot and a CSV.

use std::path::{Path, PathBuf};

use anyhow::{Context, Result, bail};

use crate::cli::SpectrumArgs;
use crate::commands::check_output_ext;
use crate::commands::output::same_path;
use crate::image_io::{say, write_atomic};
use crate::plot;
use crate::render::SamplerKind;

/// Runs `strata spectrum`.
pub fn spectrum(args: &SpectrumArgs) -> Result<()> {
    use crate::spectrum::{self as sp, Spectrum};
    let samplers = if args.sampler.is_empty() {
        SamplerKind::ALL.to_vec()
    } else {
        let mut v = args.sampler.clone();
        let mut seen = Vec::new();
        v.retain(|s| {
            let first = !seen.contains(s);
            seen.push(*s);
            first
        });
        v
    };
    let plot_path = args
        .plot
        .clone()
        .unwrap_or_else(|| sibling(&args.output, "-radial.png"));
    let csv_path = args
        .csv
        .clone()
        .unwrap_or_else(|| sibling(&args.output, "-radial.csv"));
    check_output_ext(&args.output, "png", "--output")?;
    check_output_ext(&plot_path, "png", "--plot")?;
    check_output_ext(&csv_path, "csv", "--csv")?;
    if same_path(&args.output, &plot_path) {
        bail!("--plot `{}` is the spectrum image", plot_path.display());
    }
    let r = args.max_frequency.unwrap_or(sp::default_range(args.spp));
    let pool = rayon::ThreadPoolBuilder::new()
        .num_threads(args.threads as usize)
        .build()
        .context("cannot start the worker threads")?;
    let spectra: Vec<Spectrum> = pool.install(|| {
        samplers
            .iter()
            .map(|&s| sp::spectrum(s, args.spp, args.seed, args.pixels, r))
            .collect::<Result<_>>()
    })?;
    // Each panel about 256 pixels wide; `image`'s grey levels are the
    // file's, so the panels go in as they are.
    let cell = (256 / (2 * r as usize + 1)).max(1);
    let panels: Vec<(String, Vec<u8>)> = spectra
        .iter()
        .map(|s| {
            (
                format!("{}, {} spp", s.sampler.name(), s.spp),
                sp::image(s, cell).0,
            )
        })
        .collect();
    let n = ((2 * r as usize + 1) * cell) as u32;
    let (bytes, w, h) = plot::side_by_side(&panels, n, n)?;
    let title = format!(
        "radial power spectrum, {} spp, {} pixels",
        args.spp, args.pixels
    );
    let plot = sp::plot_radial(&spectra, &title, 800, 480)?;
    let text = sp::csv(&spectra);
    plot::write_png(&args.output, &bytes, w, h)?;
    // All three files or none.
    let rest = plot::write_png(&plot_path, &plot, 800, 480).and_then(|()| {
        write_atomic(&csv_path, |tmp| Ok(std::fs::write(tmp, &text)?))
            .with_context(|| format!("writing `{}`", csv_path.display()))
    });
    if let Err(e) = rest {
        std::fs::remove_file(&args.output).ok();
        std::fs::remove_file(&plot_path).ok();
        return Err(e);
    }
    for s in &spectra {
        let radial = s.radial();
        let low: Vec<f64> = radial
            .iter()
            .filter(|(k, _)| (*k as f64) < (s.spp as f64).sqrt())
            .map(|p| p.1)
            .collect();
        let mean = |v: &[f64]| v.iter().sum::<f64>() / v.len().max(1) as f64;
        say(&format!(
            "{:<12} mean power below √spp: {}, over all radii: {:.3}",
            s.sampler.name(),
            if low.is_empty() {
                "-".to_string()
            } else {
                format!("{:.3}", mean(&low))
            },
            mean(&radial.iter().map(|p| p.1).collect::<Vec<_>>())
        ));
    }
    say(&format!(
        "wrote {}, {} and {}",
        args.output.display(),
        plot_path.display(),
        csv_path.display()
    ));
    Ok(())
}

/// `path` with its extension replaced by `suffix` (`a.png` → `a-radial.csv`).
pub(crate) fn sibling(path: &Path, suffix: &str) -> PathBuf {
    let stem = path.file_stem().unwrap_or_default().to_string_lossy();
    path.with_file_name(format!("{stem}{suffix}"))
}
