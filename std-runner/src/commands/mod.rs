//! One file per `strata` subcommand, each read top to bottom: a plan (the
//! parsed flags of `crate::cli` and the scene, checked), then the run,
//! then the report. Here: [`run`], the dispatch `main` calls, and what
//! several commands share: naming a scene, the image height and size it
//! implies, pixel windows, output names, sampler lists, progress bars.

pub mod adaptive;
pub mod aliasing;
pub mod bench;
pub mod converge;
pub mod filters;
pub mod merge;
pub mod output;
pub mod render;
pub use render::Interrupted;
pub mod spectrum;
pub mod verify;

use std::path::Path;

use anyhow::{Result, bail};
use clap::Parser;
use indicatif::{ProgressBar, ProgressStyle};
use strata::render::Tile;

use crate::cli::{Cli, Command};
use crate::image_io::{check_writable_dir, say};
use crate::job::SamplerKind;
use crate::limits::{MAX_PIXELS, MAX_WIDTH};
use crate::scenes::{BUILT_IN, SceneData, built_in, file};
pub(crate) use crate::settings::adaptive_settings;

/// Runs a parsed command line; what `main` calls.
pub fn run(cli: Cli) -> Result<()> {
    if cli.version {
        say(&crate::version_line());
        return Ok(());
    }
    match cli.command {
        Some(Command::Render(args)) => render::render(&args),
        Some(Command::Bench(args)) => bench::bench(&args),
        Some(Command::Converge(args)) => converge::converge(&args),
        Some(Command::Adaptive(args)) => adaptive::adaptive(&args),
        Some(Command::Filters(args)) => filters::filters(&args),
        Some(Command::Aliasing(args)) => aliasing::aliasing(&args),
        Some(Command::Spectrum(args)) => spectrum::spectrum(&args),
        Some(Command::Merge(args)) => merge::merge(&args),
        Some(Command::Verify(args)) => verify::verify(&args),
        // No subcommand: `strata render` with every default.
        None => match Cli::try_parse_from(["strata", "render"])?.command {
            Some(Command::Render(args)) => render::render(&args),
            _ => unreachable!("`render` parses as the render subcommand"),
        },
    }
}

/// Where a study caches its references: `--cache-dir`, or the user's
/// cache directory.
pub(crate) fn cache_dir(study: &crate::cli::StudyArgs) -> std::path::PathBuf {
    study
        .cache_dir
        .clone()
        .unwrap_or_else(crate::study::default_cache_dir)
}

/// Loads `--scene`: a built-in name, or a path to a TOML file.
pub fn resolve_scene(arg: &str) -> Result<SceneData> {
    if let Some(s) = built_in(arg) {
        return Ok(s);
    }
    let path = Path::new(arg);
    if arg.ends_with(".toml") || path.exists() {
        return Ok(file::load(path)?);
    }
    bail!(
        "unknown scene `{arg}`: use one of {} or a .toml file",
        BUILT_IN.join(", ")
    )
}

/// The height of a `width`-wide image at `aspect` (`--aspect`, named in
/// the error), or at the scene's if `None`.
pub(crate) fn height_for(scene: &SceneData, width: u32, aspect: Option<f32>) -> Result<u32> {
    let a = aspect.unwrap_or(scene.defaults.aspect);
    // Rounded: an f32 aspect such as 16/9 is inexact, and flooring
    // 320 / 1.7777778 would give 179 rather than the course's 180.
    let h = (width as f64 / a as f64).round();
    if !(1.0..=MAX_WIDTH as f64).contains(&h) {
        match aspect {
            Some(_) => bail!(
                "--aspect {a} with width {width} gives a height of {h} pixels (1..={MAX_WIDTH})"
            ),
            None => {
                bail!(
                    "width {width} at the scene's aspect {a} (its [render] aspect) gives a height \
                     of {h} pixels (1..={MAX_WIDTH}): give --height or --aspect"
                )
            }
        }
    }
    Ok(h as u32)
}

/// Refuses `panels` images of `width × height` side by side (1: one
/// image) over [`MAX_PIXELS`] in all.
pub(crate) fn check_pixels(width: u32, height: u32, panels: usize) -> Result<()> {
    if width as u64 * height as u64 * panels as u64 > MAX_PIXELS {
        if panels == 1 {
            bail!("{width} x {height} is over {MAX_PIXELS} pixels");
        }
        bail!("{panels} panels of {width} x {height} are over {MAX_PIXELS} pixels");
    }
    Ok(())
}

/// The window of `bounds` in a `width × height` image, or an error naming
/// the flag.
pub(crate) fn window_of(bounds: [u32; 4], width: u32, height: u32) -> Result<Tile> {
    let [x0, x1, y0, y1] = bounds;
    if x0 >= x1 || y0 >= y1 {
        bail!("--pixel-bounds {x0},{x1},{y0},{y1} is empty: need x0 < x1 and y0 < y1");
    }
    if x1 > width || y1 > height {
        bail!("--pixel-bounds {x0},{x1},{y0},{y1} reaches outside the {width}x{height} image");
    }
    Ok(Tile {
        x0,
        y0,
        width: x1 - x0,
        height: y1 - y0,
    })
}

/// Checks that `path` ends in `.ext` (in any case) and can be written.
pub(crate) fn check_output_ext(path: &Path, ext: &str, flag: &str) -> Result<()> {
    if path
        .extension()
        .is_none_or(|e| !e.eq_ignore_ascii_case(ext))
    {
        bail!("{flag} `{}` must end in .{ext}", path.display());
    }
    check_writable_dir(path)
}

/// The samplers a study measures: those listed, in the order given, each
/// once; all of them if none is.
pub(crate) fn samplers_or_all(listed: &[SamplerKind]) -> Vec<SamplerKind> {
    if listed.is_empty() {
        return SamplerKind::ALL.to_vec();
    }
    let mut out = Vec::new();
    for &s in listed {
        if !out.contains(&s) {
            out.push(s);
        }
    }
    out
}

/// A progress bar of `len` steps on stderr drawn by `template`, hidden
/// unless stderr is a terminal (a log or a pipe would fill with redraws)
/// or `STRATA_PROGRESS` hides it ([`crate::progress::Mode`]).
pub(crate) fn progress_bar(len: u64, template: &str) -> ProgressBar {
    if crate::progress::Mode::from_env() != crate::progress::Mode::Bar {
        return ProgressBar::hidden();
    }
    let bar = ProgressBar::new(len);
    bar.set_style(ProgressStyle::with_template(template).expect("a valid template"));
    bar
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn outputs_need_their_extension_in_any_case() {
        let tmp = tempfile::tempdir().unwrap();
        let dir = tmp.path();
        for ok in ["r.json", "R.JSON", "r.Json"] {
            check_output_ext(&dir.join(ok), "json", "--json").unwrap();
        }
        assert_eq!(
            std::fs::read_dir(dir).unwrap().count(),
            0,
            "the probe leaves nothing"
        );
        for bad in ["r.txt", "r", "json"] {
            let e = check_output_ext(&dir.join(bad), "json", "--stats").unwrap_err();
            assert!(e.to_string().contains("--stats"), "{e}");
        }
    }

    #[test]
    fn sampler_lists_keep_the_first_of_each_in_order() {
        use SamplerKind::{Grid, Halton, Sobol};
        assert_eq!(samplers_or_all(&[]), SamplerKind::ALL);
        assert_eq!(
            samplers_or_all(&[Sobol, Grid, Sobol, Halton, Grid]),
            [Sobol, Grid, Halton]
        );
    }
}
