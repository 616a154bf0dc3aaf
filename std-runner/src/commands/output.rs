//! What the commands write: films and images by extension, JSON reports,
//! spp maps; every output name checked before work starts.

use std::path::Path;

use anyhow::{Context, Result, bail};

use crate::film::Film;
use crate::image_io::{Transfer, check_output, check_writable_dir, write_atomic};

/// Whether two paths name the same file, by their absolute forms (the
/// files need not exist yet).
pub(crate) fn same_path(a: &Path, b: &Path) -> bool {
    match (std::path::absolute(a), std::path::absolute(b)) {
        (Ok(a), Ok(b)) => a == b,
        _ => a == b,
    }
}

/// Mean, least and most samples per pixel, and the share at the maximum.
pub(crate) fn spp_summary(film: &Film) -> String {
    let taken: Vec<u64> = film.pixels.iter().map(|p| p.taken() as u64).collect();
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

/// Writes the heat map of the samples each pixel of `film` took.
pub(crate) fn write_spp_map(path: &Path, film: &Film) -> Result<()> {
    let base = film.key.adaptive_base().unwrap_or(film.key.spp());
    let bytes = crate::plot::spp_heat_map(&film.pixels, base, film.key.spp());
    let mut meta = film.metadata("srgb");
    meta.push((
        "strata.spp_map".into(),
        format!(
            "samples per pixel, viridis on a log scale from {base} (dark) to {} (yellow)",
            film.key.spp()
        ),
    ));
    crate::image_io::write_png_rgb8(
        path,
        film.window.width,
        film.window.height,
        &bytes,
        Transfer::Srgb,
        &meta,
    )
    .with_context(|| format!("writing `{}`", path.display()))
}

/// The transfer curve's name in metadata.
pub(crate) fn transfer_name(t: Transfer) -> &'static str {
    match t {
        Transfer::Srgb => "srgb",
        Transfer::Gamma2 => "gamma2",
    }
}

/// `path` is a .png, .exr or .film name in a writable directory.
pub(crate) fn check_output_or_film(path: &Path) -> Result<()> {
    if is_film(path) {
        check_writable_dir(path)
    } else {
        check_output(path).map_err(|e| anyhow::anyhow!("{e}, or .film for a partial film"))
    }
}

pub(crate) fn is_film(path: &Path) -> bool {
    path.extension()
        .is_some_and(|e| e.eq_ignore_ascii_case("film"))
}

/// `path` ends in .json and can be written.
pub(crate) fn check_json(path: &Path, flag: &str) -> Result<()> {
    if path
        .extension()
        .is_none_or(|e| !e.eq_ignore_ascii_case("json"))
    {
        bail!("{flag} `{}` must end in .json", path.display());
    }
    check_writable_dir(path)
}

/// Writes `film` as a .film, or its window as a PNG/EXR image.
pub(crate) fn write_film_or_image(path: &Path, film: &Film, transfer: Transfer) -> Result<()> {
    let bytes = film_output_bytes(path, film, transfer)?;
    write_atomic(path, |tmp| crate::image_io::write_file(tmp, &bytes))
        .with_context(|| format!("writing `{}`", path.display()))
}

/// The bytes `strata render -o path` writes for `film`: the .film file, or
/// its window as a PNG or EXR image with the film's metadata.
pub fn film_output_bytes(path: &Path, film: &Film, transfer: Transfer) -> Result<Vec<u8>> {
    if is_film(path) {
        return Ok(film.to_bytes());
    }
    let format = crate::image_io::ImageFormat::of(path).ok_or_else(|| {
        anyhow::anyhow!(
            "output `{}` must end in .png, .exr or .film",
            path.display()
        )
    })?;
    let pixels: Vec<glam::Vec3> = film.pixels.iter().map(|p| p.mean()).collect();
    crate::image_io::image_bytes(
        format,
        film.window.width,
        film.window.height,
        &pixels,
        transfer,
        &film.metadata(transfer_name(transfer)),
    )
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn json_outputs_need_a_json_name_in_any_case() {
        let tmp = tempfile::tempdir().unwrap();
        let dir = tmp.path();
        for ok in ["r.json", "R.JSON", "r.Json"] {
            check_json(&dir.join(ok), "--json").unwrap();
        }
        assert_eq!(
            std::fs::read_dir(dir).unwrap().count(),
            0,
            "the probe leaves nothing"
        );
        for bad in ["r.txt", "r", "json"] {
            let e = check_json(&dir.join(bad), "--stats").unwrap_err();
            assert!(e.to_string().contains("--stats"), "{e}");
        }
    }
}
