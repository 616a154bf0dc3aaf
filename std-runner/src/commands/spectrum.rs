//! `strata spectrum`: the samplers' pixel patterns in the Fourier domain,
//! as panels, a radial plot and a CSV.

use std::path::{Path, PathBuf};

use anyhow::{Context, Result, bail};

use crate::cli::SpectrumArgs;
use crate::commands::output::{same_path, write_text};
use crate::commands::{check_output_ext, samplers_or_all};
use crate::image_io::say;
use crate::plot;
use crate::progress::Phase;
use crate::spectrum::{self as sp, Spectrum};

/// The radial plot's size in pixels.
const PLOT_SIZE: (u32, u32) = (800, 480);

/// Runs `strata spectrum`: the checks, the spectra, the files, a line per
/// sampler.
pub fn spectrum(args: &SpectrumArgs) -> Result<()> {
    let samplers = samplers_or_all(&args.sampler);
    let (plot_path, csv_path) = args.output_files()?;
    let r = args.max_frequency.unwrap_or(sp::default_range(args.spp));
    let pool = rayon::ThreadPoolBuilder::new()
        .num_threads(args.threads as usize)
        .build()
        .context("cannot start the worker threads")?;
    let phase = Phase::start(
        &format!(
            "periodograms: {} samplers over {} pixels",
            samplers.len(),
            args.pixels
        ),
        samplers.len() as u64 * args.pixels as u64,
    );
    let spectra: Vec<Spectrum> = pool.install(|| {
        samplers
            .iter()
            .map(|&s| {
                sp::spectrum_counted(s, args.spp, args.seed, args.pixels, r, &|n| phase.inc(n))
            })
            .collect::<Result<_>>()
    })?;
    phase.finish();
    write_files(args, &spectra, r, &plot_path, &csv_path)?;
    for s in &spectra {
        say(&sp::summary(s));
    }
    say(&format!(
        "wrote {}, {} and {}",
        args.output.display(),
        plot_path.display(),
        csv_path.display()
    ));
    Ok(())
}

impl SpectrumArgs {
    /// The radial plot's and the CSV's names, with every output checked
    /// writable.
    fn output_files(&self) -> Result<(PathBuf, PathBuf)> {
        let plot_path = self
            .plot
            .clone()
            .unwrap_or_else(|| sibling(&self.output, "-radial.png"));
        let csv_path = self
            .csv
            .clone()
            .unwrap_or_else(|| sibling(&self.output, "-radial.csv"));
        check_output_ext(&self.output, "png", "--output")?;
        check_output_ext(&plot_path, "png", "--plot")?;
        check_output_ext(&csv_path, "csv", "--csv")?;
        if same_path(&self.output, &plot_path) {
            bail!("--plot `{}` is the spectrum image", plot_path.display());
        }
        Ok((plot_path, csv_path))
    }
}

/// Writes the panels of `spectra` (frequencies up to `r`), the radial
/// plot and the CSV: all three files or none.
fn write_files(
    args: &SpectrumArgs,
    spectra: &[Spectrum],
    r: u32,
    plot_path: &Path,
    csv_path: &Path,
) -> Result<()> {
    // Each panel about 256 pixels wide; `image`'s grey levels are the
    // file's, so the panels go in as they are.
    let cell = (256 / (2 * r as usize + 1)).max(1);
    let panels: Vec<(String, Vec<u8>)> = spectra
        .iter()
        .map(|s| {
            let label = format!("{}, {} spp", s.sampler.name(), s.spp);
            (label, sp::image(s, cell))
        })
        .collect();
    let n = ((2 * r as usize + 1) * cell) as u32;
    let (bytes, w, h) = plot::side_by_side(&panels, n, n)?;
    let title = format!(
        "radial power spectrum, {} spp, {} pixels",
        args.spp, args.pixels
    );
    let (pw, ph) = PLOT_SIZE;
    let radial = sp::plot_radial(spectra, &title, pw, ph)?;
    let text = sp::csv(spectra);
    plot::write_png(&args.output, &bytes, w, h)?;
    let rest =
        plot::write_png(plot_path, &radial, pw, ph).and_then(|()| write_text(csv_path, &text));
    if let Err(e) = rest {
        std::fs::remove_file(&args.output).ok();
        std::fs::remove_file(plot_path).ok();
        return Err(e);
    }
    Ok(())
}

/// `path` with its extension replaced by `suffix` (`a.png` → `a-radial.csv`).
pub(crate) fn sibling(path: &Path, suffix: &str) -> PathBuf {
    let stem = path.file_stem().unwrap_or_default().to_string_lossy();
    path.with_file_name(format!("{stem}{suffix}"))
}
