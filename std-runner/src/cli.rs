//! The command line: `strata [render] [flags]`. Every flag and the scene
//! are checked before any work starts; a bad one exits non-zero with one
//! clear line and writes nothing.

use std::fmt::Write as _;
use std::io::{IsTerminal, Write};
use std::path::{Path, PathBuf};

use anyhow::{Context, Result, bail};
use clap::{Args, Parser, Subcommand, value_parser};
use glam::Vec3;
use indicatif::{ProgressBar, ProgressStyle};
use strata::render::Tile;

use crate::film_file::{Film, RenderKey, window_text};
use crate::image_io::{Transfer, check_output, check_writable_dir, say, write_atomic};
use crate::limits::{MAX_DEPTH, MAX_PIXELS, MAX_RANGE, MAX_SPP, MAX_WIDTH};
use crate::render::{Job, SamplerKind, run};
use crate::scene_file;
use crate::scenes::{BUILT_IN, BvhMode, SceneData, built_in};

/// Deterministic sampling and ray tracing of sphere scenes.
#[derive(Debug, Parser)]
#[command(
    name = "strata",
    about,
    disable_version_flag = true,
    after_help = "Examples:\n  strata                                   render week09 to week09.png\n  \
                  strata render --scene cover --spp 64 -o cover.exr\n  \
                  strata render --scene my.toml --sampler stratified --threads 2"
)]
pub struct Cli {
    /// Print the version and the SIMD level of this build.
    #[arg(short = 'V', long)]
    pub version: bool,
    /// What to do (default: render).
    #[command(subcommand)]
    pub command: Option<Command>,
}

/// The subcommands.
#[derive(Debug, Subcommand)]
pub enum Command {
    /// Render a scene to a PNG or EXR image.
    Render(RenderArgs),
    /// Measure sampling, intersection and rendering throughput (see the
    /// suite in `std-runner/src/bench.rs`); prints a table.
    Bench(BenchArgs),
    /// Measure how fast each sampler's error falls with spp: RMSE of a
    /// crop against a cached high-spp reference, as CSV, a log–log plot
    /// and fitted slopes.
    Converge(ConvergeArgs),
    /// Render one scene with several samplers at the same spp, side by
    /// side in one labelled PNG (default: the `horizon` checker plane).
    Aliasing(AliasingArgs),
    /// The power spectrum (periodogram) of each sampler's pixel-sample
    /// pattern, averaged over many pixels: an image per sampler, and the
    /// radial averages as a plot and CSV.
    Spectrum(SpectrumArgs),
    /// Merge partial films (`render --crop/--pixel-bounds/--samples -o
    /// PART.film`) into one image, bit-identical to a one-shot render.
    Merge(MergeArgs),
    /// Re-render the golden table (small renders of every scene and
    /// sampler, and of the reconstruction variants) and check this build
    /// reproduces it bit for bit.
    Verify(VerifyArgs),
}

/// Parses `x0,x1,y0,y1` (pixels, half-open: columns x0..x1, rows y0..y1),
/// like pbrt's `--pixelbounds`.
fn pixel_bounds(s: &str) -> Result<[u32; 4], String> {
    let v: Vec<&str> = s.split(',').collect();
    let [x0, x1, y0, y1] = v[..] else {
        return Err(format!("`{s}` is not x0,x1,y0,y1"));
    };
    let mut out = [0u32; 4];
    for (o, t) in out.iter_mut().zip([x0, x1, y0, y1]) {
        *o = t
            .trim()
            .parse()
            .map_err(|_| format!("`{t}` is not a pixel coordinate"))?;
    }
    if out[0] >= out[1] || out[2] >= out[3] {
        return Err(format!("`{s}` is empty: need x0 < x1 and y0 < y1"));
    }
    Ok(out)
}

/// The window of `bounds` in a `width × height` image, or an error naming
/// the flag.
fn window_of(bounds: [u32; 4], width: u32, height: u32) -> Result<Tile> {
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

/// `strata converge` flags.
#[derive(Debug, Args)]
pub struct ConvergeArgs {
    /// A built-in scene or a TOML scene file.
    #[arg(long, default_value = "week09")]
    pub scene: String,
    /// Image width in pixels, height by the scene's aspect [default: the
    /// scene's].
    #[arg(long, value_parser = value_parser!(u32).range(1..=MAX_WIDTH as i64))]
    pub width: Option<u32>,
    /// The crop measured, `x0,x1,y0,y1` in pixels [default: the central
    /// half of the image in each direction].
    #[arg(long, value_parser = pixel_bounds)]
    pub pixel_bounds: Option<[u32; 4]>,
    /// Ray segments per path [default: the scene's].
    #[arg(long, value_parser = value_parser!(u32).range(1..=MAX_DEPTH as i64))]
    pub max_depth: Option<u32>,
    /// Samplers to measure, comma-separated [default: all].
    #[arg(long, value_enum, value_delimiter = ',')]
    pub samplers: Vec<SamplerKind>,
    /// Also measure 1024 spp (after 1, 4, 16, 64, 256).
    #[arg(long)]
    pub with_1024: bool,
    /// Samples per pixel of the reference (Sobol'), at least 4 times the
    /// largest measured spp.
    #[arg(long, default_value_t = 16384, value_parser = value_parser!(u32).range(1..=1 << 24))]
    pub reference_spp: u32,
    /// Seeds per point; the RMSE is the root of the mean squared error
    /// over them.
    #[arg(long, default_value_t = 1, value_parser = value_parser!(u32).range(1..=64))]
    pub seeds: u32,
    /// Worker threads.
    #[arg(long, default_value_t = 2, value_parser = value_parser!(u16).range(1..=512))]
    pub threads: u16,
    /// Where references are cached [default: $XDG_CACHE_HOME/strata or
    /// ~/.cache/strata].
    #[arg(long)]
    pub cache_dir: Option<PathBuf>,
    /// The CSV written [default: converge-SCENE.csv].
    #[arg(long)]
    pub csv: Option<PathBuf>,
    /// The plot written, a PNG [default: converge-SCENE.png].
    #[arg(long)]
    pub plot: Option<PathBuf>,
}

/// `strata aliasing` flags.
#[derive(Debug, Args)]
pub struct AliasingArgs {
    /// A built-in scene or a TOML scene file.
    #[arg(long, default_value = "horizon")]
    pub scene: String,
    /// Width of each panel in pixels, height by the scene's aspect
    /// [default: the scene's].
    #[arg(long, value_parser = value_parser!(u32).range(1..=4096))]
    pub width: Option<u32>,
    /// Samples per pixel of every panel.
    #[arg(long, default_value_t = 4, value_parser = value_parser!(u32).range(1..=1 << 24))]
    pub spp: u32,
    /// Ray segments per path [default: the scene's].
    #[arg(long, value_parser = value_parser!(u32).range(1..=MAX_DEPTH as i64))]
    pub max_depth: Option<u32>,
    /// The samplers, one panel each, comma-separated.
    #[arg(
        long,
        value_enum,
        value_delimiter = ',',
        default_value = "grid,independent,stratified"
    )]
    pub samplers: Vec<SamplerKind>,
    /// Samples per pixel of a last, reference panel (Sobol'); 0 for none.
    /// Each panel's label gives its RMSE against it.
    #[arg(long, default_value_t = 1024, value_parser = value_parser!(u32).range(0..=1 << 24))]
    pub reference_spp: u32,
    /// Seed of every panel.
    #[arg(long, default_value_t = 0)]
    pub seed: u64,
    /// Worker threads.
    #[arg(long, default_value_t = 2, value_parser = value_parser!(u16).range(1..=512))]
    pub threads: u16,
    /// Texture filtering of the sampler panels (the reference is
    /// point-sampled): none, or box (the checker averaged over each
    /// camera ray's footprint).
    #[arg(long, value_enum, default_value_t = TextureFilterName::None)]
    pub texture_filter: TextureFilterName,
    /// Output PNG.
    #[arg(short, long, default_value = "aliasing.png")]
    pub output: PathBuf,
}

/// The height of a `width`-wide image of `scene` at its aspect.
fn height_for(scene: &SceneData, width: u32) -> Result<u32> {
    let aspect = scene.defaults.aspect;
    let h = (width as f64 / aspect as f64).round();
    if !(1.0..=MAX_WIDTH as f64).contains(&h) {
        bail!("width {width} at aspect {aspect} gives a height of {h} pixels (1..={MAX_WIDTH})");
    }
    Ok(h as u32)
}

/// Checks that `path` ends in `.ext` and can be written.
fn check_output_ext(path: &Path, ext: &str, flag: &str) -> Result<()> {
    if path
        .extension()
        .is_none_or(|e| !e.eq_ignore_ascii_case(ext))
    {
        bail!("{flag} `{}` must end in .{ext}", path.display());
    }
    check_writable_dir(path)
}

/// Runs `strata converge`.
pub fn converge(args: &ConvergeArgs) -> Result<()> {
    use crate::study::{self, View};
    let scene = resolve_scene(&args.scene)?;
    let width = args.width.unwrap_or(scene.defaults.width);
    let height = height_for(&scene, width)?;
    if width as u64 * height as u64 > MAX_PIXELS {
        bail!("{width} x {height} is over {MAX_PIXELS} pixels");
    }
    let window = match args.pixel_bounds {
        Some(b) => window_of(b, width, height)?,
        None => Tile {
            x0: width / 4,
            y0: height / 4,
            width: (width / 2).max(1),
            height: (height / 2).max(1),
        },
    };
    let mut spps = vec![1u32, 4, 16, 64, 256];
    if args.with_1024 {
        spps.push(1024);
    }
    let top = *spps.last().expect("spp list");
    // The reference's own error adds to every measured point: at 16 times
    // the largest spp it adds at most about 3 % to the last point's RMSE.
    if args.reference_spp < 16 * top {
        bail!(
            "--reference-spp {} must be at least 16 x {top} (the largest measured spp)",
            args.reference_spp
        );
    }
    let samplers = if args.samplers.is_empty() {
        SamplerKind::ALL.to_vec()
    } else {
        // In the order given, each once.
        let mut v = args.samplers.clone();
        let mut seen = Vec::new();
        v.retain(|s| {
            let first = !seen.contains(s);
            seen.push(*s);
            first
        });
        v
    };
    let csv_path = args
        .csv
        .clone()
        .unwrap_or_else(|| PathBuf::from(format!("converge-{}.csv", scene.name)));
    let plot_path = args
        .plot
        .clone()
        .unwrap_or_else(|| PathBuf::from(format!("converge-{}.png", scene.name)));
    check_output_ext(&csv_path, "csv", "--csv")?;
    check_output_ext(&plot_path, "png", "--plot")?;
    let cache_dir = args
        .cache_dir
        .clone()
        .unwrap_or_else(study::default_cache_dir);

    let view = View {
        scene: &scene,
        width,
        height,
        window,
        max_depth: args.max_depth.unwrap_or(scene.defaults.max_depth),
        threads: args.threads as usize,
        texture_filter: strata::render::TextureFilter::None,
    };
    let started = std::time::Instant::now();
    let (reference, cached) = study::reference(&view, args.reference_spp, &cache_dir)?;
    say(&format!(
        "{}: {}x{} crop at ({}, {}) of {}x{}, depth {}; reference: sobol {} spp, {}",
        scene.name,
        window.width,
        window.height,
        window.x0,
        window.y0,
        width,
        height,
        view.max_depth,
        args.reference_spp,
        if cached {
            "cached".to_string()
        } else {
            format!("rendered in {:.1} s", started.elapsed().as_secs_f64())
        }
    ));
    let points = study::converge(&view, &samplers, &spps, args.seeds, &reference, &|_| {})?;

    let title = format!(
        "{}: RMSE of a {}x{} crop vs spp",
        scene.name, window.width, window.height
    );
    let plot = study::plot_convergence(&points, &samplers, &title, 800, 560)?;
    let text = study::csv(&points);
    study::write_png(&plot_path, &plot, 800, 560)?;
    // Both files or neither.
    if let Err(e) = write_atomic(&csv_path, |tmp| Ok(std::fs::write(tmp, &text)?)) {
        std::fs::remove_file(&plot_path).ok();
        return Err(e.context(format!("writing `{}`", csv_path.display())));
    }

    let mut table = format!("{:<12}", "sampler");
    for spp in &spps {
        write!(table, " {:>9}", format!("{spp} spp")).ok();
    }
    table.push_str("  slope  slope>=16");
    for &s in &samplers {
        let line = study::series(&points, s);
        write!(
            table,
            "
{:<12}",
            s.name()
        )
        .ok();
        for &(_, e) in &line {
            write!(table, " {e:>9.2e}").ok();
        }
        let tail: Vec<_> = line.iter().copied().filter(|&(x, _)| x >= 16.0).collect();
        let fmt = |k: Option<f64>| k.map_or("-".into(), |k| format!("{k:.2}"));
        write!(
            table,
            "  {:>5} {:>10}",
            fmt(study::log_log_slope(&line)),
            fmt(study::log_log_slope(&tail))
        )
        .ok();
    }
    say(&table);
    say(&format!(
        "wrote {} and {}",
        csv_path.display(),
        plot_path.display()
    ));
    Ok(())
}

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
    let refs: Vec<(&str, &[Vec3])> = panels
        .iter()
        .map(|(l, p)| (l.as_str(), p.as_slice()))
        .collect();
    let (bytes, w, h) = study::side_by_side(&refs, width, height)?;
    study::write_png(&args.output, &bytes, w, h)?;
    say(&format!(
        "{}: {} panels of {}x{}, to {}",
        scene.name,
        panels.len(),
        width,
        height,
        args.output.display()
    ));
    Ok(())
}

/// `strata spectrum` flags.
#[derive(Debug, Args)]
pub struct SpectrumArgs {
    /// Samplers, comma-separated; several are shown side by side [default:
    /// all].
    #[arg(long, value_enum, value_delimiter = ',')]
    pub sampler: Vec<SamplerKind>,
    /// Samples per pixel of the pattern.
    #[arg(long, default_value_t = 64, value_parser = value_parser!(u32).range(1..=4096))]
    pub spp: u32,
    /// Pixels whose periodograms are averaged.
    #[arg(long, default_value_t = 1024, value_parser = value_parser!(u32).range(1..=1 << 20))]
    pub pixels: u32,
    /// Highest frequency on each axis, in cycles per pixel [default: 4
    /// √spp, at least 16; at most 128].
    #[arg(long, value_parser = value_parser!(u32).range(1..=MAX_RANGE as i64))]
    pub max_frequency: Option<u32>,
    /// Seed of the sample streams.
    #[arg(long, default_value_t = 0)]
    pub seed: u64,
    /// Worker threads (the result does not depend on it).
    #[arg(long, default_value_t = 2, value_parser = value_parser!(u16).range(1..=512))]
    pub threads: u16,
    /// The spectrum image, a PNG (grey = power / 2: a flat spectrum is
    /// mid-grey; zero frequency at the centre).
    #[arg(short, long, default_value = "spectrum.png")]
    pub output: PathBuf,
    /// The radial-average plot [default: OUTPUT with `-radial.png`].
    #[arg(long)]
    pub plot: Option<PathBuf>,
    /// The radial averages as CSV [default: OUTPUT with `-radial.csv`].
    #[arg(long)]
    pub csv: Option<PathBuf>,
}

/// `path` with its extension replaced by `suffix` (`a.png` → `a-radial.csv`).
fn sibling(path: &Path, suffix: &str) -> PathBuf {
    let stem = path.file_stem().unwrap_or_default().to_string_lossy();
    path.with_file_name(format!("{stem}{suffix}"))
}

/// Runs `strata spectrum`.
pub fn spectrum(args: &SpectrumArgs) -> Result<()> {
    use crate::spectrum::{self as sp, Spectrum};
    let samplers = if args.sampler.is_empty() {
        SamplerKind::ALL.to_vec()
    } else {
        let mut v = args.sampler.clone();
        let mut seen = Vec::new();
        v.retain(|s| {
            let first = !seen.contains(s);
            seen.push(*s);
            first
        });
        v
    };
    let plot_path = args
        .plot
        .clone()
        .unwrap_or_else(|| sibling(&args.output, "-radial.png"));
    let csv_path = args
        .csv
        .clone()
        .unwrap_or_else(|| sibling(&args.output, "-radial.csv"));
    check_output_ext(&args.output, "png", "--output")?;
    check_output_ext(&plot_path, "png", "--plot")?;
    check_output_ext(&csv_path, "csv", "--csv")?;
    if same_path(&args.output, &plot_path) {
        bail!("--plot `{}` is the spectrum image", plot_path.display());
    }
    let r = args.max_frequency.unwrap_or(sp::default_range(args.spp));
    let pool = rayon::ThreadPoolBuilder::new()
        .num_threads(args.threads as usize)
        .build()
        .context("cannot start the worker threads")?;
    let spectra: Vec<Spectrum> = pool.install(|| {
        samplers
            .iter()
            .map(|&s| sp::spectrum(s, args.spp, args.seed, args.pixels, r))
            .collect::<Result<_>>()
    })?;
    // Each panel about 256 pixels wide.
    let cell = (256 / (2 * r as usize + 1)).max(1);
    let panels: Vec<(String, Vec<Vec3>)> = spectra
        .iter()
        .map(|s| {
            let (bytes, _) = sp::image(s, cell);
            // The panels are drawn with the sRGB curve; undo it so the
            // grey levels are the ones `image` chose.
            let lin = bytes
                .chunks_exact(3)
                .map(|c| Vec3::splat(crate::image_io::srgb_decode(c[0] as f32 / 255.0)))
                .collect();
            (format!("{}, {} spp", s.sampler.name(), s.spp), lin)
        })
        .collect();
    let n = ((2 * r as usize + 1) * cell) as u32;
    let refs: Vec<(&str, &[Vec3])> = panels
        .iter()
        .map(|(l, p)| (l.as_str(), p.as_slice()))
        .collect();
    let (bytes, w, h) = crate::study::side_by_side(&refs, n, n)?;
    let title = format!(
        "radial power spectrum, {} spp, {} pixels",
        args.spp, args.pixels
    );
    let plot = sp::plot_radial(&spectra, &title, 800, 480)?;
    let text = sp::csv(&spectra);
    crate::study::write_png(&args.output, &bytes, w, h)?;
    // All three files or none.
    let rest = crate::study::write_png(&plot_path, &plot, 800, 480).and_then(|()| {
        write_atomic(&csv_path, |tmp| Ok(std::fs::write(tmp, &text)?))
            .with_context(|| format!("writing `{}`", csv_path.display()))
    });
    if let Err(e) = rest {
        std::fs::remove_file(&args.output).ok();
        std::fs::remove_file(&plot_path).ok();
        return Err(e);
    }
    for s in &spectra {
        let radial = s.radial();
        let low: Vec<f64> = radial
            .iter()
            .filter(|(k, _)| (*k as f64) < (s.spp as f64).sqrt())
            .map(|p| p.1)
            .collect();
        let mean = |v: &[f64]| v.iter().sum::<f64>() / v.len().max(1) as f64;
        say(&format!(
            "{:<12} mean power below √spp: {}, over all radii: {:.3}",
            s.sampler.name(),
            if low.is_empty() {
                "-".to_string()
            } else {
                format!("{:.3}", mean(&low))
            },
            mean(&radial.iter().map(|p| p.1).collect::<Vec<_>>())
        ));
    }
    say(&format!(
        "wrote {}, {} and {}",
        args.output.display(),
        plot_path.display(),
        csv_path.display()
    ));
    Ok(())
}

/// `strata bench` flags.
#[derive(Debug, Args)]
pub struct BenchArgs {
    /// Also write the report as JSON to this file.
    #[arg(long)]
    pub json: Option<PathBuf>,
    /// Timed repetitions of every figure (after one warm-up).
    #[arg(long, default_value_t = 5, value_parser = value_parser!(u16).range(1..=100))]
    pub repetitions: u16,
    /// Shortest duration of one timing, in milliseconds.
    #[arg(long, default_value_t = 100, value_parser = value_parser!(u64).range(1..=60_000))]
    pub min_time_ms: u64,
}

/// Runs `strata bench`.
pub fn bench(args: &BenchArgs) -> Result<()> {
    if let Some(path) = &args.json {
        // Probes the directory with a file of our own: an existing report
        // is left alone until the new one replaces it.
        check_json(path, "--json")?;
    }
    let options = crate::bench::Options {
        repetitions: args.repetitions as usize,
        min_time: std::time::Duration::from_millis(args.min_time_ms),
    };
    let bar = if std::io::stderr().is_terminal() {
        let bar = ProgressBar::new(crate::bench::COMPARISONS);
        bar.set_style(
            ProgressStyle::with_template("{spinner} {pos}/{len} {wide_msg}")
                .expect("a valid template"),
        );
        bar
    } else {
        ProgressBar::hidden()
    };
    let report = crate::bench::run_suite(options, &|name| {
        bar.set_message(name.to_string());
        bar.inc(1);
    })?;
    bar.finish_and_clear();
    if let Some(path) = &args.json {
        let text = serde_json::to_string_pretty(&report)?;
        write_atomic(path, |tmp| Ok(std::fs::write(tmp, &text)?))
            .with_context(|| format!("writing `{}`", path.display()))?;
    }
    // The table is the result here: a full disk is an error, a reader
    // that went away (a closed pipe) is not.
    let mut out = std::io::stdout().lock();
    match writeln!(out, "{}", crate::bench::table(&report).trim_end()).and_then(|()| out.flush()) {
        Err(e) if e.kind() != std::io::ErrorKind::BrokenPipe => Err(e).context("writing the table"),
        _ => Ok(()),
    }
}

fn positive_f32(s: &str) -> Result<f32, String> {
    let v: f32 = s.parse().map_err(|_| format!("`{s}` is not a number"))?;
    if v > 0.0 && v.is_finite() {
        Ok(v)
    } else {
        Err(format!("must be positive and finite, got {s}"))
    }
}

/// `strata render` flags. Unset values come from the scene's defaults.
#[derive(Debug, Args)]
pub struct RenderArgs {
    /// A built-in scene (week09, cover, showcase) or a TOML scene file.
    #[arg(long, default_value = "week09")]
    pub scene: String,
    /// Image width in pixels [default: the scene's].
    #[arg(long, value_parser = value_parser!(u32).range(1..=MAX_WIDTH as i64))]
    pub width: Option<u32>,
    /// Image height in pixels [default: width / aspect].
    #[arg(long, conflicts_with = "aspect", value_parser = value_parser!(u32).range(1..=MAX_WIDTH as i64))]
    pub height: Option<u32>,
    /// Width / height [default: the scene's, 16:9 for the built-ins].
    #[arg(long, allow_hyphen_values = true, value_parser = positive_f32)]
    pub aspect: Option<f32>,
    /// Samples per pixel [default: the scene's].
    #[arg(long, value_parser = value_parser!(u32).range(1..=MAX_SPP as i64))]
    pub spp: Option<u32>,
    /// Ray segments from the camera per path (1 = camera rays only)
    /// [default: the scene's].
    #[arg(long, value_parser = value_parser!(u32).range(1..=MAX_DEPTH as i64))]
    pub max_depth: Option<u32>,
    /// Pixel sampler.
    #[arg(long, value_enum, default_value_t = SamplerKind::Independent)]
    pub sampler: SamplerKind,
    /// Seed of every sample stream.
    #[arg(long, default_value_t = 0)]
    pub seed: u64,
    /// Worker threads.
    #[arg(long, default_value_t = 2, value_parser = value_parser!(u16).range(1..=512))]
    pub threads: u16,
    /// Tile side in pixels (changes speed, never the image).
    #[arg(long, default_value_t = 32, value_parser = value_parser!(u32).range(1..=4096))]
    pub tile: u32,
    /// PNG transfer curve: sRGB, or the course's gamma 2.
    #[arg(long, value_enum, default_value_t = Transfer::Srgb)]
    pub gamma: Transfer,
    /// Turn off direct lighting from sphere lights (BSDF sampling only).
    #[arg(long)]
    pub no_direct_lighting: bool,
    /// Trace through a BVH: auto (from 16 spheres), on or off. Changes
    /// speed, never the image.
    #[arg(long, value_enum, default_value_t = BvhMode::Auto)]
    pub bvh: BvhMode,
    /// Render only part of the frame: x0,x1,y0,y1 as fractions of the
    /// image in [0, 1] (pbrt's --cropwindow); pixel bounds are
    /// ceil(fraction × size).
    #[arg(long, value_parser = crop_window, conflicts_with = "pixel_bounds")]
    pub crop: Option<[f32; 4]>,
    /// Render only pixels x0..x1, y0..y1 (half-open; pbrt's --pixelbounds).
    #[arg(long, value_parser = pixel_bounds)]
    pub pixel_bounds: Option<[u32; 4]>,
    /// Render only sample indices A..B-1 of every pixel (within 0..spp).
    #[arg(long, value_parser = sample_range)]
    pub samples: Option<std::ops::Range<u32>>,
    /// Adaptive sampling: after --spp samples, each pixel takes batches of
    /// --spp more while its relative error exceeds THRESHOLD, up to
    /// --max-spp. The error is the standard error of the pixel's mean
    /// luminance over that mean (over 0.05 for darker pixels).
    #[arg(
        long,
        value_name = "THRESHOLD",
        value_parser = positive_f32,
        requires = "max_spp",
        conflicts_with = "samples"
    )]
    pub adaptive: Option<f32>,
    /// The most samples a pixel takes with --adaptive.
    #[arg(long, requires = "adaptive", value_parser = value_parser!(u32).range(1..=MAX_SPP as i64))]
    pub max_spp: Option<u32>,
    /// With --adaptive, also write a heat map of the samples each pixel
    /// took as a PNG (viridis, log scale: dark = --spp, yellow = --max-spp).
    #[arg(long, requires = "adaptive")]
    pub spp_map: Option<PathBuf>,
    /// Pixel reconstruction filter, applied by importance sampling (each
    /// pixel depends only on its own samples).
    #[arg(long, value_enum, default_value_t = FilterName::Box)]
    pub filter: FilterName,
    /// Filter radius in pixels [default: box 0.5, tent 1, gaussian 1.5
    /// (σ 0.5), mitchell 2 (B = C = 1/3), lanczos 3 (τ 3),
    /// blackman-harris 1.5].
    #[arg(long, value_parser = positive_f32)]
    pub filter_radius: Option<f32>,
    /// Texture filtering: none (point sampling, the course's) or box (the
    /// checker averaged in closed form over each camera ray's footprint,
    /// from ray differentials).
    #[arg(long, value_enum, default_value_t = TextureFilterName::None)]
    pub texture_filter: TextureFilterName,
    /// Output file: .png (8-bit), .exr (linear float), or .film (exact
    /// partial sums for `strata merge`) [default: SCENE.png].
    #[arg(short, long)]
    pub output: Option<PathBuf>,
    /// Write run facts (threads, wall time, SIMD level, rays) as JSON.
    #[arg(long)]
    pub stats: Option<PathBuf>,
}

/// The texture filters `--texture-filter` offers.
#[derive(Clone, Copy, Debug, PartialEq, Eq, clap::ValueEnum)]
pub enum TextureFilterName {
    /// Point sampling.
    None,
    /// The checker's box average over the footprint.
    Box,
}

impl TextureFilterName {
    /// The core's setting.
    #[must_use]
    pub fn filter(self) -> strata::render::TextureFilter {
        match self {
            TextureFilterName::None => strata::render::TextureFilter::None,
            TextureFilterName::Box => strata::render::TextureFilter::Box,
        }
    }
}

/// The filters `--filter` offers, with their usual shape parameters.
#[derive(Clone, Copy, Debug, PartialEq, Eq, clap::ValueEnum)]
pub enum FilterName {
    /// The course's: uniform over the pixel.
    Box,
    /// Triangle.
    Tent,
    /// Gaussian, σ = 0.5 pixel.
    Gaussian,
    /// Mitchell–Netravali, B = C = 1/3.
    Mitchell,
    /// Windowed sinc, τ = 3.
    Lanczos,
    /// 4-term Blackman–Harris window.
    BlackmanHarris,
}

impl FilterName {
    /// The filter of this name and `radius` (its usual one if `None`).
    pub fn filter(self, radius: Option<f32>) -> Result<strata::render::PixelFilter> {
        use strata::filter::FilterKind;
        let name = clap::ValueEnum::to_possible_value(&self)
            .map(|v| v.get_name().to_string())
            .unwrap_or_default();
        let kind = FilterKind::named(&name)
            .ok_or_else(|| anyhow::anyhow!("--filter {name}: no such filter in this build"))?;
        let r = radius.unwrap_or(kind.default_radius());
        strata::render::PixelFilter::new(kind, r)
            .map_err(|e| anyhow::anyhow!("--filter {} --filter-radius {r}: {e}", kind.name()))
    }
}

/// Parses `x0,x1,y0,y1` fractions in [0, 1] with x0 < x1, y0 < y1.
fn crop_window(s: &str) -> Result<[f32; 4], String> {
    let v: Vec<&str> = s.split(',').collect();
    let [_, _, _, _] = v[..] else {
        return Err(format!("`{s}` is not x0,x1,y0,y1"));
    };
    let mut out = [0f32; 4];
    for (o, t) in out.iter_mut().zip(v) {
        *o = t
            .trim()
            .parse()
            .ok()
            .filter(|x: &f32| (0.0..=1.0).contains(x))
            .ok_or_else(|| format!("`{t}` is not a fraction in [0, 1]"))?;
    }
    if out[0] >= out[1] || out[2] >= out[3] {
        return Err(format!("`{s}` is empty: need x0 < x1 and y0 < y1"));
    }
    Ok(out)
}

/// Parses `A..B` sample indices, `A < B`.
fn sample_range(s: &str) -> Result<std::ops::Range<u32>, String> {
    crate::film_file::parse_samples(s)
        .ok_or_else(|| format!("`{s}` is not a sample range A..B with A < B"))
}

/// The pixel window of a `--crop` in a `width × height` image: pbrt's
/// rule, `ceil(fraction × size)` at both ends.
fn crop_to_window(c: [f32; 4], width: u32, height: u32) -> Result<Tile> {
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

/// Loads `--scene`: a built-in name, or a path to a TOML file.
pub fn resolve_scene(arg: &str) -> Result<SceneData> {
    if let Some(s) = built_in(arg) {
        return Ok(s);
    }
    let path = Path::new(arg);
    if arg.ends_with(".toml") || path.exists() {
        return Ok(scene_file::load(path)?);
    }
    bail!(
        "unknown scene `{arg}`: use one of {} or a .toml file",
        BUILT_IN.join(", ")
    )
}

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
             (independent, stratified, sobol, halton): the grid fills its rows in order"
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
            " (pixels {}, samples {}..{})",
            window_text(window),
            samples.start,
            samples.end
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
            "version": crate::film_file::version(),
        });
        let text = serde_json::to_string_pretty(&facts)? + "\n";
        write_atomic(path, |tmp| Ok(std::fs::write(tmp, &text)?))
            .with_context(|| format!("writing `{}`", path.display()))?;
    }
    Ok(())
}

/// Whether two paths name the same file, by their absolute forms (the
/// files need not exist yet).
fn same_path(a: &Path, b: &Path) -> bool {
    match (std::path::absolute(a), std::path::absolute(b)) {
        (Ok(a), Ok(b)) => a == b,
        _ => a == b,
    }
}

/// Mean, least and most samples per pixel, and the share at the maximum.
fn spp_summary(film: &Film) -> String {
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
fn write_spp_map(path: &Path, film: &Film) -> Result<()> {
    let base = film.key.adaptive_base().unwrap_or(film.key.spp());
    let bytes = crate::study::spp_heat_map(&film.pixels, base, film.key.spp());
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
fn transfer_name(t: Transfer) -> &'static str {
    match t {
        Transfer::Srgb => "srgb",
        Transfer::Gamma2 => "gamma2",
    }
}

/// `path` is a .png, .exr or .film name in a writable directory.
fn check_output_or_film(path: &Path) -> Result<()> {
    if is_film(path) {
        check_writable_dir(path)
    } else {
        check_output(path).map_err(|e| anyhow::anyhow!("{e}, or .film for a partial film"))
    }
}

fn is_film(path: &Path) -> bool {
    path.extension()
        .is_some_and(|e| e.eq_ignore_ascii_case("film"))
}

/// `path` ends in .json and can be written.
fn check_json(path: &Path, flag: &str) -> Result<()> {
    if path
        .extension()
        .is_none_or(|e| !e.eq_ignore_ascii_case("json"))
    {
        bail!("{flag} `{}` must end in .json", path.display());
    }
    check_writable_dir(path)
}

/// Writes `film` as a .film, or its window as a PNG/EXR image.
fn write_film_or_image(path: &Path, film: &Film, transfer: Transfer) -> Result<()> {
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

/// `strata merge` flags.
#[derive(Debug, Args)]
pub struct MergeArgs {
    /// Partial films written by `strata render -o PART.film`.
    #[arg(required = true)]
    pub parts: Vec<PathBuf>,
    /// Output: .png, .exr or .film.
    #[arg(short, long)]
    pub output: PathBuf,
    /// PNG transfer curve: sRGB, or the course's gamma 2.
    #[arg(long, value_enum, default_value_t = Transfer::Srgb)]
    pub gamma: Transfer,
    /// Also write a heat map of the samples each pixel took (PNG; see
    /// `render --spp-map`).
    #[arg(long)]
    pub spp_map: Option<PathBuf>,
}

/// Runs `strata merge`: every part is read and checked before the output
/// is written; a refused merge writes nothing.
pub fn merge(args: &MergeArgs) -> Result<()> {
    check_output_or_film(&args.output)?;
    if let Ok(out) = args.output.canonicalize()
        && let Some(p) = args
            .parts
            .iter()
            .find(|p| p.canonicalize().is_ok_and(|p| p == out))
    {
        bail!("the output `{}` is one of the parts", p.display());
    }
    let parts: Vec<Film> = args
        .parts
        .iter()
        .map(|p| Film::read(p))
        .collect::<Result<_>>()?;
    if let Some(map) = &args.spp_map {
        check_output_ext(map, "png", "--spp-map")?;
        if same_path(map, &args.output) || args.parts.iter().any(|p| same_path(map, p)) {
            bail!(
                "--spp-map `{}` is the output or one of the parts",
                map.display()
            );
        }
    }
    let film = crate::film_file::merge(&parts, &args.parts)?;
    write_film_or_image(&args.output, &film, args.gamma)?;
    if let Some(map) = &args.spp_map
        && let Err(e) = write_spp_map(map, &film)
    {
        std::fs::remove_file(&args.output).ok();
        return Err(e);
    }
    say(&format!(
        "merged {} part{}: {} {}x{}, {} spp, to {}",
        parts.len(),
        if parts.len() == 1 { "" } else { "s" },
        film.key.get("scene").unwrap_or("?"),
        film.key.width(),
        film.key.height(),
        film.key.spp(),
        args.output.display()
    ));
    Ok(())
}

/// `strata verify` flags.
#[derive(Debug, Args)]
pub struct VerifyArgs {
    /// Worker threads (the hashes do not depend on it).
    #[arg(long, default_value_t = 2, value_parser = value_parser!(u16).range(1..=512))]
    pub threads: u16,
}

/// Runs `strata verify`: one line per row of the golden table (renders,
/// scene hashes, file bytes), and an error if any differs.
pub fn verify(args: &VerifyArgs) -> Result<()> {
    use crate::golden;
    say(&format!(
        "{}: golden renders {}x{}, {} spp, seed {}, depth {}",
        crate::version_line(),
        golden::SIZE.0,
        golden::SIZE.1,
        golden::SPP,
        golden::SEED,
        golden::DEPTH
    ));
    let outcomes = golden::verify(args.threads as usize, &mut |o| {
        let (status, why) = match o.expected {
            Some(e) if e == o.got => ("pass", String::new()),
            Some(e) => ("FAIL", format!("  (expected {e:016x})")),
            None => ("FAIL", "  (not in the table)".to_string()),
        };
        say(&format!(
            "{status}  {:<32} {:<22} {:016x}{why}",
            o.scene, o.key, o.got
        ));
    })?;
    let failed = outcomes.iter().filter(|o| !o.pass()).count();
    if failed > 0 {
        bail!(
            "{failed} of {} golden rows differ: this build or machine does not reproduce \
             Strata {}'s output",
            outcomes.len(),
            crate::film_file::version()
        );
    }
    say(&format!("all {} golden rows match", outcomes.len()));
    Ok(())
}

/// Parses and runs a command line; what `main` calls.
pub fn main_with(cli: Cli) -> Result<()> {
    if cli.version {
        say(&crate::version_line());
        return Ok(());
    }
    match cli.command {
        Some(Command::Render(args)) => render(&args),
        Some(Command::Bench(args)) => bench(&args),
        Some(Command::Converge(args)) => converge(&args),
        Some(Command::Aliasing(args)) => aliasing(&args),
        Some(Command::Spectrum(args)) => spectrum(&args),
        Some(Command::Merge(args)) => merge(&args),
        Some(Command::Verify(args)) => verify(&args),
        // No subcommand: `strata render` with every default.
        None => match Cli::try_parse_from(["strata", "render"])?.command {
            Some(Command::Render(args)) => render(&args),
            _ => unreachable!("`render` parses as the render subcommand"),
        },
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Every `--filter` name is a core filter kind (names are matched at
    /// run time, so this is where a mismatch would show).
    #[test]
    fn every_filter_name_builds_its_filter() {
        use clap::ValueEnum;
        for name in FilterName::value_variants() {
            let f = name.filter(None).unwrap();
            let flag = name.to_possible_value().unwrap();
            assert_eq!(f.kind().name(), flag.get_name());
            assert_eq!(f.radius(), f.kind().default_radius());
        }
    }

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
