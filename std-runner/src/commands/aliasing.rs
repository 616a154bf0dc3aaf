//! `strata aliasing`: the aliasing demo, grid against independent against
//! stratified samples beside a reference, as one PNG.

use std::fmt::Write as _;

use anyhow::{Result, bail};
use glam::Vec3;
use strata::render::{TextureFilter, Tile};

use crate::cli::{AliasingArgs, TextureFilterName};
use crate::commands::{check_output_ext, check_pixels, height_for, resolve_scene};
use crate::image_io::{Transfer, rgb8, say};
use crate::job::SamplerKind;
use crate::plot;
use crate::progress::Phase;
use crate::study::{self, View};

/// Runs `strata aliasing`: the checks, a panel per sampler, the reference
/// panel and each panel's RMSE against it, the PNG.
pub fn aliasing(args: &AliasingArgs) -> Result<()> {
    let scene = resolve_scene(&args.scene)?;
    let width = args.width.unwrap_or(scene.defaults.width);
    let height = height_for(&scene, width, None)?;
    if args.samplers.is_empty() {
        bail!("--samplers needs at least one sampler");
    }
    if args.samplers.len() > 8 {
        bail!("--samplers takes at most 8 panels");
    }
    check_output_ext(&args.output, "png", "--output")?;
    check_pixels(width, height, args.samplers.len())?;
    let view = View {
        scene: &scene,
        width,
        height,
        window: Tile::whole(width, height),
        max_depth: args.max_depth.unwrap_or(scene.defaults.max_depth),
        threads: args.threads as usize,
        texture_filter: args.texture_filter.filter(),
        filter: strata::render::PixelFilter::BOX,
    };
    let mut panels = sampler_panels(args, &view)?;
    if args.reference_spp > 0 {
        add_reference(args, &view, &mut panels)?;
    }
    let encoded: Vec<(String, Vec<u8>)> = panels
        .into_iter()
        .map(|(l, p)| (l, rgb8(&p, Transfer::Srgb)))
        .collect();
    let (bytes, w, h) = plot::side_by_side(&encoded, width, height)?;
    plot::write_png(&args.output, &bytes, w, h)?;
    say(&format!(
        "{}: {} panels of {}x{}, to {}",
        scene.name,
        encoded.len(),
        width,
        height,
        args.output.display()
    ));
    Ok(())
}

/// A labelled panel: its caption and linear pixels.
type Panel = (String, Vec<Vec3>);

/// One panel per `--samplers` entry, at `--spp` and `--seed`.
fn sampler_panels(args: &AliasingArgs, view: &View<'_>) -> Result<Vec<Panel>> {
    let prefiltered = match args.texture_filter {
        TextureFilterName::None => "",
        TextureFilterName::Box => ", prefiltered",
    };
    let phase = Phase::start(
        &format!(
            "panels: {} samplers at {} spp",
            args.samplers.len(),
            args.spp
        ),
        (args.samplers.len() * view.window.area()) as u64,
    );
    let panels = args
        .samplers
        .iter()
        .map(|&s| {
            let label = format!("{}, {} spp{prefiltered}", s.name(), args.spp);
            Ok((
                label,
                view.render(s, args.spp, args.seed, &|n| phase.inc(n))?,
            ))
        })
        .collect();
    phase.finish();
    panels
}

/// Renders the point-sampled Sobol' reference, labels each panel with its
/// RMSE against it (and prints it), and adds it as the last panel.
fn add_reference(args: &AliasingArgs, view: &View<'_>, panels: &mut Vec<Panel>) -> Result<()> {
    let point = View {
        texture_filter: TextureFilter::None,
        ..view.clone()
    };
    let phase = Phase::start(
        &format!("reference: sobol {} spp", args.reference_spp),
        view.window.area() as u64,
    );
    let reference = point.render(
        SamplerKind::Sobol,
        args.reference_spp,
        // A seed apart from the panels' (never equal to it).
        args.seed ^ study::REFERENCE_SEED,
        &|n| phase.inc(n),
    )?;
    phase.finish();
    for (label, pixels) in panels.iter_mut() {
        let e = study::rmse(pixels, &reference);
        say(&format!("{label}: RMSE {e:.4}"));
        write!(label, " (RMSE {e:.3})").expect("a String");
    }
    panels.push((
        format!("reference: sobol, {} spp", args.reference_spp),
        reference,
    ));
    Ok(())
}
