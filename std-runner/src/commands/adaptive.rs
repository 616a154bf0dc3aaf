//! `strata adaptive`: adaptive sampling against uniform sampling at equal
//! cost (see [`crate::study::adaptive`]).

use anyhow::{Result, bail};
use strata::render::{TextureFilter, Tile};

use crate::cli::AdaptiveArgs;
use crate::commands::output::write_text;
use crate::commands::{
    adaptive_settings, check_output_ext, check_pixels, height_for, resolve_scene, window_of,
};
use crate::image_io::say;
use crate::job::SamplerKind;
use crate::study::{self, View};

/// The scene the study measures unless `--scene` names another.
const DEFAULT_SCENE: &str = "caustics";
/// Seeds per row unless `--seeds` says otherwise.
const DEFAULT_SEEDS: u32 = 5;

/// Runs `strata adaptive`: every flag checked, then the study, its table
/// and, if asked for, its CSV.
pub fn adaptive(args: &AdaptiveArgs) -> Result<()> {
    let common = &args.study;
    let scene = resolve_scene(common.scene_or(DEFAULT_SCENE))?;
    let width = common.width.unwrap_or(scene.defaults.width);
    let height = height_for(&scene, width, None)?;
    check_pixels(width, height, 1)?;
    let window = match args.pixel_bounds {
        Some(b) => window_of(b, width, height)?,
        None => Tile::whole(width, height),
    };
    if args.sampler == SamplerKind::Grid {
        bail!(
            "adaptive sampling needs a sampler whose first samples spread over the pixel; \
             the grid fills its rows in order"
        );
    }
    let adaptive = adaptive_settings(args.min_spp, args.max_spp, args.threshold, "--threshold")?;
    if let Some(csv) = &common.csv {
        check_output_ext(csv, "csv", "--csv")?;
    }
    let view = View {
        scene: &scene,
        width,
        height,
        window,
        max_depth: common.max_depth.unwrap_or(scene.defaults.max_depth),
        threads: common.threads as usize,
        texture_filter: TextureFilter::None,
        filter: strata::render::PixelFilter::BOX,
    };
    say(&format!(
        "{}: {}x{} window at ({}, {}) of {}x{}, depth {}, {}; {}",
        scene.name,
        window.width,
        window.height,
        window.x0,
        window.y0,
        width,
        height,
        view.max_depth,
        args.sampler.name(),
        adaptive
    ));
    let cache_dir = super::cache_dir(common);
    let report = study::adaptive::study(
        &view,
        args.sampler,
        adaptive,
        common.seeds_or(DEFAULT_SEEDS),
        &cache_dir,
        &say,
    )?;
    if let Some(csv) = &common.csv {
        write_text(csv, &report.csv())?;
    }
    say(&report.table());
    Ok(())
}
