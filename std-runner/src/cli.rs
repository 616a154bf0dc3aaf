//! The command line: `strata [render] [flags]`. Every flag and the scene
//! are checked before any work starts; a bad one exits non-zero with one
//! clear line and writes nothing.

use std::io::{IsTerminal, Write};
use std::path::{Path, PathBuf};

use anyhow::{Context, Result, bail};
use clap::{Args, Parser, Subcommand, value_parser};
use indicatif::{ProgressBar, ProgressStyle};

use crate::image_io::{Transfer, check_output, check_writable_dir, say, write_atomic, write_image};
use crate::render::{Job, SamplerKind, run};
use crate::scene_file::{self, MAX_DEPTH, MAX_SPP, MAX_WIDTH};
use crate::scenes::{BUILT_IN, SceneData, built_in};

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
        if path
            .extension()
            .is_none_or(|e| !e.eq_ignore_ascii_case("json"))
        {
            bail!("--json `{}` must end in .json", path.display());
        }
        // Probe the directory with a file of our own: an existing report is
        // left alone until the new one replaces it.
        check_writable_dir(path)?;
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
    /// Output file, .png (8-bit) or .exr (linear float) [default: SCENE.png].
    #[arg(short, long)]
    pub output: Option<PathBuf>,
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

/// The largest image accepted, in pixels: 2²⁵ (e.g. 8192 × 4096), whose
/// films and output buffers need about 2.5 GiB at the peak.
pub const MAX_PIXELS: u64 = 1 << 25;

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
    let spp = args.spp.unwrap_or(d.spp);
    let max_depth = args.max_depth.unwrap_or(d.max_depth);
    if args.sampler != SamplerKind::Independent && spp > strata::sampler::MAX_STRATA_SPP {
        bail!(
            "--sampler {} takes at most {} spp",
            args.sampler.name(),
            strata::sampler::MAX_STRATA_SPP
        );
    }
    let output = args
        .output
        .clone()
        .unwrap_or_else(|| PathBuf::from(format!("{}.png", scene.name)));
    check_output(&output)?;

    let job = Job {
        scene: &scene,
        width,
        height,
        spp,
        samples: 0..spp,
        max_depth,
        sampler: args.sampler,
        seed: args.seed,
        threads: args.threads as usize,
        tile: args.tile,
        direct_lighting: !args.no_direct_lighting,
    };
    let bar = if std::io::stderr().is_terminal() {
        let bar = ProgressBar::new(width as u64 * height as u64);
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

    let pixels: Vec<glam::Vec3> = rendered.pixels.iter().map(|p| p.mean()).collect();
    let dropped: u64 = rendered.pixels.iter().map(|p| p.dropped as u64).sum();
    write_image(
        &output,
        width,
        height,
        &pixels,
        args.gamma,
        &metadata(&job, args.gamma),
    )
    .with_context(|| format!("writing `{}`", output.display()))?;

    let secs = rendered.wall.as_secs_f64();
    say(&format!(
        "{}: {}x{} {} spp ({}, seed {}), depth {}, to {}",
        scene.name,
        width,
        height,
        spp,
        args.sampler.name(),
        args.seed,
        max_depth,
        output.display()
    ));
    let st = rendered.stats;
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
    Ok(())
}

/// What defines a render, and nothing that varies from run to run, so the
/// same render is the same file on any machine.
pub fn metadata(job: &Job<'_>, transfer: Transfer) -> Vec<(String, String)> {
    let v = |k: &str, v: String| (format!("strata.{k}"), v);
    vec![
        (
            "Software".into(),
            format!("strata {}", env!("CARGO_PKG_VERSION")),
        ),
        v("scene", job.scene.name.clone()),
        v("scene_hash", format!("{:016x}", job.scene.content_hash())),
        v("size", format!("{}x{}", job.width, job.height)),
        v("spp", job.spp.to_string()),
        v(
            "samples",
            format!("{}..{}", job.samples.start, job.samples.end),
        ),
        v("sampler", job.sampler.name().into()),
        v("seed", job.seed.to_string()),
        v("max_depth", job.max_depth.to_string()),
        v("direct_lighting", job.direct_lighting.to_string()),
        v("filter", "box".into()),
        v(
            "transfer",
            match transfer {
                Transfer::Srgb => "srgb".into(),
                Transfer::Gamma2 => "gamma2".into(),
            },
        ),
    ]
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
        // No subcommand: `strata render` with every default.
        None => match Cli::try_parse_from(["strata", "render"])?.command {
            Some(Command::Render(args)) => render(&args),
            _ => unreachable!("`render` parses as the render subcommand"),
        },
    }
}
