//! `strata render`: a scene (built-in or file) to a PNG, EXR or partial
//! `.film`, after every flag is checked; run facts to stdout and `--stats`.

use std::io::IsTerminal;
use std::path::PathBuf;

use anyhow::{Context, Result, bail};
use indicatif::{ProgressBar, ProgressStyle};
use strata::render::Tile;

use crate::cli::RenderArgs;
use crate::commands::output::{
    check_json, check_output_or_film, same_path, spp_summary, write_film_or_image, write_spp_map,
};
use crate::commands::{check_output_ext, resolve_scene, window_of};
use crate::film::{Film, RenderKey, samples_text, window_text};
use crate::image_io::{say, write_atomic};
use crate::limits::{MAX_PIXELS, MAX_WIDTH};
use crate::render::{Job, SamplerKind, run};

/// Runs `strata render`.
pub fn render(args: &RenderArgs) -> Result<()> {
    let scene = resolve_scene(&args.scene)?;
    let d = scene.defaults;
    let width = args.width.unwrap_or(d.width);
    let height = match args.height {
        Some(h) => h,
        None => {
            let aspect = args.aspect.unwrap_or(d.aspect);
            // Rounded: an f32 aspect such as 16/9 is inexact, and flooring
            // 320 / 1.7777778 would give 179 rather than the course's 180.
            let h = (width as f64 / aspect as f64).round();
            if !(1.0..=MAX_WIDTH as f64).contains(&h) {
                bail!(
                    "--aspect {aspect} with width {width} gives a height of {h} pixels (1..={MAX_WIDTH})"
                );
            }
            h as u32
        }
    };
    if width as u64 * height as u64 > MAX_PIXELS {
        bail!("{width} x {height} is over {MAX_PIXELS} pixels");
    }
    let base_spp = args.spp.unwrap_or(d.spp);
    let adaptive = match (args.adaptive, args.max_spp) {
        (Some(t), Some(max)) => Some(strata::render::Adaptive::new(base_spp, max, t).map_err(
            |_| {
                anyhow::anyhow!(
                    "--max-spp {max} is below the base count {base_spp} (--spp or the scene's)"
                )
            },
        )?),
        _ => None,
    };
    if adaptive.is_some() && args.sampler == SamplerKind::Grid {
        bail!(
            "--adaptive needs a sampler whose first samples spread over the pixel \
             (independent, stratified, sobol, halton, zsobol): the grid fills its rows in order"
        );
    }
    // The sampler's pattern holds every sample a pixel may take.
    let spp = adaptive.map_or(base_spp, |a| a.max());
    let max_depth = args.max_depth.unwrap_or(d.max_depth);
    if args.sampler != SamplerKind::Independent && spp > strata::sampler::MAX_STRATA_SPP {
        bail!(
            "--sampler {} takes at most {} spp",
            args.sampler.name(),
            strata::sampler::MAX_STRATA_SPP
        );
    }
    let window = match (args.crop, args.pixel_bounds) {
        (Some(c), _) => crop_to_window(c, width, height)?,
        (None, Some(b)) => window_of(b, width, height)?,
        (None, None) => Tile::whole(width, height),
    };
    let filter = args.filter.filter(args.filter_radius)?;
    let samples = args.samples.clone().unwrap_or(0..spp);
    if samples.end > spp {
        bail!(
            "--samples {}..{} reaches past the {spp} samples per pixel",
            samples.start,
            samples.end
        );
    }
    let output = args
        .output
        .clone()
        .unwrap_or_else(|| PathBuf::from(format!("{}.png", scene.name)));
    check_output_or_film(&output)?;
    if let Some(stats) = &args.stats {
        check_json(stats, "--stats")?;
    }
    if let Some(map) = &args.spp_map {
        check_output_ext(map, "png", "--spp-map")?;
        if same_path(map, &output) {
            bail!("--spp-map `{}` is the image's output", map.display());
        }
    }

    let job = Job {
        scene: &scene,
        width,
        height,
        window,
        spp,
        samples: samples.clone(),
        max_depth,
        sampler: args.sampler,
        seed: args.seed,
        threads: args.threads as usize,
        tile: args.tile,
        direct_lighting: !args.no_direct_lighting,
        bvh: args.bvh,
        filter,
        adaptive,
        texture_filter: args.texture_filter.filter(),
    };
    let bar = if std::io::stderr().is_terminal() {
        let bar = ProgressBar::new(window.area() as u64);
        bar.set_style(
            ProgressStyle::with_template(
                "{spinner} [{elapsed_precise}] {wide_bar} {percent}% ETA {eta}",
            )
            .expect("a valid template"),
        );
        bar
    } else {
        ProgressBar::hidden()
    };
    let rendered = run(&job, &|n| bar.inc(n))?;
    bar.finish_and_clear();

    let dropped: u64 = rendered.pixels.iter().map(|p| p.dropped as u64).sum();
    let film = Film {
        key: RenderKey::of(&job),
        window,
        samples: samples.clone(),
        pixels: rendered.pixels,
    };
    write_film_or_image(&output, &film, args.gamma)?;
    if let Some(map) = &args.spp_map {
        // Both files or neither.
        if let Err(e) = write_spp_map(map, &film) {
            std::fs::remove_file(&output).ok();
            return Err(e);
        }
    }

    let secs = rendered.wall.as_secs_f64();
    let st = rendered.stats;
    let part = if window == Tile::whole(width, height) && samples == (0..spp) {
        String::new()
    } else {
        format!(
            " (pixels {}, samples {})",
            window_text(window),
            samples_text(&samples)
        )
    };
    let spp_text = match adaptive {
        None => format!("{spp} spp"),
        Some(a) => format!(
            "adaptive {}..{} spp at {} ({})",
            a.base(),
            a.max(),
            a.threshold(),
            spp_summary(&film)
        ),
    };
    say(&format!(
        "{}: {}x{} {spp_text} ({}, seed {}), depth {}{part}, to {}",
        scene.name,
        width,
        height,
        args.sampler.name(),
        args.seed,
        max_depth,
        output.display()
    ));
    say(&format!(
        "{:.3} s on {} threads ({}): {:.2} M samples/s, {:.2} M rays/s{}",
        secs,
        args.threads,
        strata::trace::simd_level().name(),
        st.paths as f64 / secs.max(1e-9) / 1e6,
        (st.rays + st.shadow_rays) as f64 / secs.max(1e-9) / 1e6,
        if dropped > 0 {
            format!(", {dropped} NaN/inf samples dropped")
        } else {
            String::new()
        }
    ));
    if let Some(path) = &args.stats {
        let facts = serde_json::json!({
            "scene": scene.name,
            "output": output.display().to_string(),
            "threads": args.threads,
            "tile": args.tile,
            "simd": strata::trace::simd_level().name(),
            "wall_seconds": secs,
            "camera_paths": st.paths,
            "rays": st.rays,
            "shadow_rays": st.shadow_rays,
            "dropped_samples": dropped,
            "bvh": scene.use_bvh(args.bvh),
            "version": crate::film::version(),
        });
        let text = serde_json::to_string_pretty(&facts)? + "\n";
        write_atomic(path, |tmp| Ok(std::fs::write(tmp, &text)?))
            .with_context(|| format!("writing `{}`", path.display()))?;
    }
    Ok(())
}

/// The pixel window of a `--crop` in a `width × height` image: pbrt's
/// rule, `ceil(fraction × size)` at both ends.
pub(crate) fn crop_to_window(c: [f32; 4], width: u32, height: u32) -> Result<Tile> {
    // The product in f32, as pbrt computes it: 0.2 × 10 rounds to 2.
    let at = |f: f32, n: u32| (f * n as f32).ceil() as u32;
    let (x0, x1, y0, y1) = (
        at(c[0], width),
        at(c[1], width),
        at(c[2], height),
        at(c[3], height),
    );
    if x0 >= x1 || y0 >= y1 {
        bail!(
            "--crop {},{},{},{} holds no pixel of the {width}x{height} image",
            c[0],
            c[1],
            c[2],
            c[3]
        );
    }
    Ok(Tile {
        x0,
        y0,
        width: x1 - x0,
        height: y1 - y0,
    })
}
