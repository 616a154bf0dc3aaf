//! What the commands write: films and images by extension, spp maps and
//! text reports (JSON, CSV); every output name checked before work starts.

use std::io::Write as _;
use std::path::Path;

use anyhow::{Context, Result};

use crate::film::{Film, is_film_path};
use crate::image_io::{
    ImageFormat, Transfer, check_output, check_writable_dir, real_path, write_atomic, write_file,
    write_png_rgb8,
};
use crate::plot::spp_map_with_legend;

/// Whether two paths name the same file, their directories' links and
/// `..` resolved ([`real_path`]; the files need not exist yet).
pub(crate) fn same_path(a: &Path, b: &Path) -> bool {
    real_path(a) == real_path(b)
}

/// Mean, least and most samples per pixel, and the share at the maximum.
pub(crate) fn spp_summary(film: &Film) -> String {
    let taken: Vec<u64> = film
        .window_pixels()
        .iter()
        .map(|p| p.taken() as u64)
        .collect();
    let n = taken.len().max(1) as f64;
    let at_max = taken
        .iter()
        .filter(|&&t| t == film.key.spp() as u64)
        .count();
    format!(
        "mean {:.1} spp, {} to {}, {:.1} % of pixels at the maximum",
        taken.iter().sum::<u64>() as f64 / n,
        taken.iter().min().unwrap_or(&0),
        taken.iter().max().unwrap_or(&0),
        100.0 * at_max as f64 / n
    )
}

/// The heat map of the samples each pixel of a film took, with its legend
/// (the colour scale and its spp values) under it, drawn and ready to
/// write: drawn before the image is written, so a drawing failure leaves
/// no image behind.
pub(crate) struct SppMap {
    rgb: Vec<u8>,
    width: u32,
    height: u32,
    meta: Vec<(String, String)>,
}

impl SppMap {
    /// Draws the spp map of `film`.
    pub(crate) fn draw(film: &Film) -> Result<Self> {
        let base = film.key.adaptive().map_or(film.key.spp(), |a| a.min());
        let (w, h) = (film.window.width, film.window.height);
        let pixels = film.window_pixels();
        let (rgb, width, height) = spp_map_with_legend(&pixels, w, h, base, film.key.spp())?;
        let mut meta = film.metadata(Transfer::Srgb);
        meta.push((
            "strata.spp_map".into(),
            format!(
                "samples per pixel of the {w}x{h} pixels at the top left, viridis on a \
                 log scale from {base} (dark) to {} (yellow); the legend below",
                film.key.spp()
            ),
        ));
        Ok(Self {
            rgb,
            width,
            height,
            meta,
        })
    }

    /// Writes the map as a PNG, atomically.
    pub(crate) fn write(&self, path: &Path) -> Result<()> {
        write_png_rgb8(
            path,
            self.width,
            self.height,
            &self.rgb,
            Transfer::Srgb,
            &self.meta,
        )
        .with_context(|| format!("writing `{}`", path.display()))
    }
}

/// `path` is a .png, .exr or .film name in a writable directory.
pub(crate) fn check_output_or_film(path: &Path) -> Result<()> {
    if is_film_path(path) {
        check_writable_dir(path)
    } else {
        match ImageFormat::of(path) {
            None => anyhow::bail!(
                "output `{}` must end in .png or .exr, or .film for a partial film",
                path.display()
            ),
            Some(_) => check_output(path),
        }
    }
}

/// Writes `film` as a .film, or its window as a PNG/EXR image.
pub(crate) fn write_film_or_image(path: &Path, film: &Film, transfer: Transfer) -> Result<()> {
    if is_film_path(path) {
        // Streamed: no second copy of a large film's pixels.
        return write_atomic(path, |tmp| {
            let file = std::fs::File::create(tmp)
                .with_context(|| format!("cannot write `{}`", tmp.display()))?;
            let mut w = std::io::BufWriter::new(file);
            film.write_to(&mut w)
                .and_then(|()| w.flush())
                .with_context(|| format!("cannot write `{}`", tmp.display()))
        })
        .with_context(|| format!("writing `{}`", path.display()));
    }
    let bytes = film.output_bytes(path, transfer)?;
    write_atomic(path, |tmp| write_file(tmp, &bytes))
        .with_context(|| format!("writing `{}`", path.display()))
}

/// Writes `text` to `path` atomically, naming the file in the error.
pub(crate) fn write_text(path: &Path, text: &str) -> Result<()> {
    write_atomic(path, |tmp| Ok(std::fs::write(tmp, text)?))
        .with_context(|| format!("writing `{}`", path.display()))
}
