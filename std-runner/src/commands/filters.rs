//! `strata filters`: every pixel filter against the box at equal time
//! (see [`crate::study::filters`]).

use anyhow::{Result, bail};
use clap::ValueEnum;
use strata::render::{TextureFilter, Tile};

use crate::cli::{FilterName, FiltersArgs};
use crate::commands::output::write_text;
use crate::commands::{check_output_ext, check_pixels, height_for, resolve_scene};
use crate::image_io::say;
use crate::study::{self, View};

/// How many times the largest measured spp the references must take, so
/// that their own error stays a small part of the RMSE measured.
const REFERENCE_FACTOR: u32 = 16;

/// The scene the study measures unless `--scene` names another.
const DEFAULT_SCENE: &str = "week09";
/// Seeds per row unless `--seeds` says otherwise.
const DEFAULT_SEEDS: u32 = 4;
/// The image width unless `--width` says otherwise (whatever the scene).
const DEFAULT_WIDTH: u32 = 320;

/// Runs `strata filters`: every flag checked, then the study, its table
/// and, if asked for, its CSV.
pub fn filters(args: &FiltersArgs) -> Result<()> {
    let common = &args.study;
    let scene = resolve_scene(common.scene_or(DEFAULT_SCENE))?;
    let width = common.width.unwrap_or(DEFAULT_WIDTH);
    let height = height_for(&scene, width, None)?;
    check_pixels(width, height, 1)?;
    // Each spp and filter once, the spps ascending (the box's rate is
    // measured between neighbours).
    let mut spps = args.spps.clone();
    spps.sort_unstable();
    spps.dedup();
    let largest = spps.last().copied().unwrap_or(1);
    if args.reference_spp / REFERENCE_FACTOR < largest {
        bail!(
            "--reference-spp {} must be at least {REFERENCE_FACTOR} times the largest of --spps \
             ({largest})",
            args.reference_spp
        );
    }
    if let Some(csv) = &common.csv {
        check_output_ext(csv, "csv", "--csv")?;
    }
    let mut names: Vec<FilterName> = match args.filters.is_empty() {
        true => FilterName::value_variants().to_vec(),
        false => args.filters.clone(),
    };
    let mut seen = Vec::new();
    names.retain(|n| {
        let new = !seen.contains(n);
        seen.push(*n);
        new
    });
    let filters = names
        .iter()
        .map(|n| n.filter(None))
        .collect::<Result<Vec<_>>>()?;
    let view = View {
        scene: &scene,
        width,
        height,
        window: Tile::whole(width, height),
        max_depth: common.max_depth.unwrap_or(scene.defaults.max_depth),
        threads: common.threads as usize,
        texture_filter: TextureFilter::None,
        filter: strata::render::PixelFilter::BOX,
    };
    say(&format!(
        "{}: {}x{}, depth {}, {}, spp {:?}, {} seed(s), timed {} time(s)",
        scene.name,
        width,
        height,
        view.max_depth,
        args.sampler.name(),
        spps,
        common.seeds_or(DEFAULT_SEEDS),
        args.rounds
    ));
    let cache_dir = super::cache_dir(common);
    let report = study::filters::study(
        &view,
        args.sampler,
        &filters,
        &study::filters::Settings {
            spps,
            seeds: common.seeds_or(DEFAULT_SEEDS),
            rounds: args.rounds,
            reference_spp: args.reference_spp,
        },
        &cache_dir,
        &say,
    )?;
    if let Some(csv) = &common.csv {
        write_text(csv, &report.csv())?;
    }
    say(&report.table());
    Ok(())
}
