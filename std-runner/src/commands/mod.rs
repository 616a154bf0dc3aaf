//! One file per `strata` subcommand, each read top to bottom: check the
//! parsed flags (`crate::cli`), then do the work. Shared here: naming a
//! scene, the image height it implies, pixel windows and output names.

pub mod aliasing;
pub mod bench;
pub mod converge;
pub mod merge;
pub mod output;
pub mod render;
pub mod spectrum;
pub mod verify;

use std::path::Path;

use anyhow::{Result, bail};
use strata::render::Tile;

use crate::image_io::check_writable_dir;
use crate::limits::MAX_WIDTH;
use crate::scenes::{BUILT_IN, SceneData, built_in, file};

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

/// The height of a `width`-wide image of `scene` at its aspect.
pub(crate) fn height_for(scene: &SceneData, width: u32) -> Result<u32> {
    let aspect = scene.defaults.aspect;
    let h = (width as f64 / aspect as f64).round();
    if !(1.0..=MAX_WIDTH as f64).contains(&h) {
        bail!("width {width} at aspect {aspect} gives a height of {h} pixels (1..={MAX_WIDTH})");
    }
    Ok(h as u32)
}

/// The window of `bounds` in a `width × height` image, or an error naming
/// the flag.
pub(crate) fn window_of(bounds: [u32; 4], width: u32, height: u32) -> Result<Tile> {
    let [x0, x1, y0, y1] = bounds;
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

/// Checks that `path` ends in `.ext` and can be written.
pub(crate) fn check_output_ext(path: &Path, ext: &str, flag: &str) -> Result<()> {
    if path
        .extension()
        .is_none_or(|e| !e.eq_ignore_ascii_case(ext))
    {
        bail!("{flag} `{}` must end in .{ext}", path.display());
    }
    check_writable_dir(path)
}
