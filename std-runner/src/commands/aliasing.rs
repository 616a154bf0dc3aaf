//! `strata aliasing`: the aliasing demo, grid against independent against
//! stratified samples beside a reference, as one PNG.

use std::fmt::Write as _;

use anyhow::{Result, bail};
use strata::render::Tile;

use crate::cli::{AliasingArgs, TextureFilterName};
use crate::commands::{check_output_ext, height_for, resolve_scene};
use crate::image_io::{Transfer, rgb8, say};
use crate::limits::MAX_PIXELS;
use crate::plot;
use crate::render::SamplerKind;

/// Runs `strata aliasing`.
pub fn aliasing(args: &AliasingArgs) -> Result<()> {
    use crate::study::{self, View};
    let scene = resolve_scene(&args.scene)?;
    let width = args.width.unwrap_or(scene.defaults.width);
    let height = height_for(&scene, width)?;
    if args.samplers.is_empty() {
        bail!("--samplers needs at least one sampler");
    }
    if args.samplers.len() > 8 {
        bail!("--samplers takes at most 8 panels");
    }
    if args.spp > strata::sampler::MAX_STRATA_SPP {
        bail!("--spp is at most {}", strata::sampler::MAX_STRATA_SPP);
    }
    check_output_ext(&args.output, "png", "--output")?;
    if width as u64 * height as u64 * args.samplers.len() as u64 > MAX_PIXELS {
        bail!(
            "{} panels of {width} x {height} are over {MAX_PIXELS} pixels",
            args.samplers.len()
        );
    }
    let view = View {
        scene: &scene,
        width,
        height,
        window: Tile::whole(width, height),
        max_depth: args.max_depth.unwrap_or(scene.defaults.max_depth),
        threads: args.threads as usize,
        texture_filter: args.texture_filter.filter(),
    };
    let prefiltered = match args.texture_filter {
        TextureFilterName::None => "",
        TextureFilterName::Box => ", prefiltered",
    };
    let mut panels = Vec::new();
    for &s in &args.samplers {
        panels.push((
            format!("{}, {} spp{prefiltered}", s.name(), args.spp),
            view.render(s, args.spp, args.seed)?,
        ));
    }
    if args.reference_spp > 0 {
        let point = View {
            texture_filter: strata::render::TextureFilter::None,
            ..view.clone()
        };
        let reference = point.render(
            SamplerKind::Sobol,
            args.reference_spp,
            // A seed apart from the panels' (never equal to it).
            args.seed ^ study::REFERENCE_SEED,
        )?;
        for (label, pixels) in &mut panels {
            let e = study::rmse(pixels, &reference);
            say(&format!("{label}: RMSE {e:.4}"));
            write!(label, " (RMSE {e:.3})").ok();
        }
        panels.push((
            format!("reference: sobol, {} spp", args.reference_spp),
            reference,
        ));
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
