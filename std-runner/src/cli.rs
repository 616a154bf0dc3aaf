//! The command line: `strata [render] [flags]`, as clap types (each
//! field's doc is its `--help` text). [`crate::commands`] dispatches them
//! and checks each subcommand's flags and scene before any work starts; a
//! bad one exits non-zero with one clear line and writes nothing.

use std::path::PathBuf;

use anyhow::Result;
use clap::{Args, Parser, Subcommand, value_parser};
use strata::filter::FilterKind;
use strata::render::{PixelFilter, TextureFilter};

use crate::image_io::Transfer;
use crate::job::SamplerKind;
use crate::limits::{
    MAX_DEPTH, MAX_MIN_TIME_MS, MAX_PANEL_WIDTH, MAX_PATTERN_PIXELS, MAX_PATTERN_SPP, MAX_RANGE,
    MAX_REPETITIONS, MAX_SEEDS, MAX_SPP, MAX_STUDY_SPP, MAX_THREADS, MAX_WIDTH,
};
use crate::scenes::{BVH_THRESHOLD, BvhMode};

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

impl Cli {
    /// Parses `args` (the program name first), noting which `render`
    /// flags were given rather than defaulted
    /// ([`RenderArgs::given`]).
    pub fn parse_with_sources<I, T>(args: I) -> Result<Cli, clap::Error>
    where
        I: IntoIterator<Item = T>,
        T: Into<std::ffi::OsString> + Clone,
    {
        use clap::{CommandFactory, FromArgMatches, parser::ValueSource};
        let command = Cli::command();
        let matches = command.clone().try_get_matches_from(args)?;
        let mut cli = Cli::from_arg_matches(&matches)?;
        if let (Some(Command::Render(r)), Some(("render", sub)), Some(def)) = (
            &mut cli.command,
            matches.subcommand(),
            command.find_subcommand("render"),
        ) {
            // Arguments only (the matches also hold the flags' group).
            r.given = def
                .get_arguments()
                .map(|a| a.get_id().as_str())
                .filter(|id| sub.value_source(id) == Some(ValueSource::CommandLine))
                .map(str::to_string)
                .collect();
        }
        Ok(cli)
    }
}

/// `strata render`'s settings (clap ids) that name files or the run, not
/// the image: a library render refuses them however they are spelt (`-o
/// x`, `-ox`, `--output=x`).
const NOT_FOR_LIBRARIES: [&str; 7] = [
    "output",
    "stats",
    "spp_map",
    "checkpoint",
    "no_checkpoint",
    "resume",
    "threads",
];

/// A render for a library caller (the C API, the Python package) from the
/// flags of `strata render` (without the command's name: `["--scene",
/// "cover", "--spp", "64"]`), checked as the command line is
/// ([`RenderArgs::job`]), and its scene (built in, or a TOML file). Flags
/// about files and threads are refused: a library render writes into the
/// caller's memory on the threads it is given.
///
/// # Errors
/// The flags' first problem, in one line (clap's usage text left out).
pub fn library_render(flags: &[String]) -> anyhow::Result<(RenderArgs, crate::scenes::SceneData)> {
    let argv = ["strata", "render"]
        .into_iter()
        .map(str::to_string)
        .chain(flags.iter().cloned());
    let args = match Cli::parse_with_sources(argv) {
        Ok(Cli {
            command: Some(Command::Render(args)),
            ..
        }) => args,
        Ok(_) => anyhow::bail!("not a render"),
        Err(e) => {
            // clap's first line says what is wrong; the rest is usage.
            let text = e.to_string();
            let first = text.lines().next().unwrap_or("invalid flags");
            anyhow::bail!("{}", first.trim_start_matches("error: "));
        }
    };
    if let Some(id) = args
        .given
        .iter()
        .find(|g| NOT_FOR_LIBRARIES.contains(&g.as_str()))
    {
        anyhow::bail!(
            "--{}: a library render writes into your buffers, on the threads you give",
            id.replace('_', "-")
        );
    }
    let scene = crate::commands::resolve_scene(&args.scene)?;
    args.job(&scene)?;
    Ok((args, scene))
}

/// The subcommands.
#[derive(Debug, Subcommand)]
pub enum Command {
    /// Render a scene to a PNG or EXR image, or to a partial .film for
    /// `strata merge`; `--resume` finishes an interrupted render from its
    /// checkpoint.
    Render(RenderArgs),
    /// Measure sampling, intersection and rendering throughput (see the
    /// suite in `std-runner/src/bench/`); prints a table.
    Bench(BenchArgs),
    /// Measure how fast each sampler's error falls with spp: RMSE of a
    /// crop against a cached high-spp reference, as CSV, a log–log plot
    /// and fitted slopes.
    Converge(ConvergeArgs),
    /// Measure adaptive sampling against uniform sampling at equal cost:
    /// RMSE and relMSE against a cached reference, cost as rays and as
    /// CPU seconds, and the adaptive image's bias.
    Adaptive(AdaptiveArgs),
    /// Measure every pixel filter against the box at equal time: RMSE
    /// against each filter's own cached reference, negative pixels (noise,
    /// near 0 or ringing), fallbacks, mean luminance and wall time.
    Filters(FiltersArgs),
    /// Render one scene with several samplers at the same spp, side by
    /// side in one labelled PNG (default: the `horizon` checker plane).
    Aliasing(AliasingArgs),
    /// The power spectrum (periodogram) of each sampler's pixel-sample
    /// pattern, averaged over many pixels: an image per sampler, and the
    /// radial averages as a plot and CSV.
    Spectrum(SpectrumArgs),
    /// Merge partial films (`render --crop/--pixel-bounds/--samples -o
    /// PART.film`) into one image, bit-identical to a one-shot render, or
    /// into a staged .film that merges on with the rest.
    Merge(MergeArgs),
    /// Re-render the golden table (small renders of every scene and
    /// sampler, and of the reconstruction variants) and check this build
    /// reproduces it bit for bit.
    Verify(VerifyArgs),
}

/// Parses `x0,x1,y0,y1` (pixels, half-open: columns x0..x1, rows y0..y1),
/// like pbrt's `--pixelbounds`. Only parses: the window is checked
/// against the image where it is used ([`crate::commands`]'s
/// `window_of`).
fn pixel_bounds(s: &str) -> Result<[u32; 4], String> {
    four(s, "a pixel coordinate")
}

/// Parses four comma-separated numbers, `x0,x1,y0,y1`.
fn four<T: std::str::FromStr + Default + Copy>(s: &str, what: &str) -> Result<[T; 4], String> {
    let v: Vec<&str> = s.split(',').collect();
    let [_, _, _, _] = v[..] else {
        return Err(format!("`{s}` is not x0,x1,y0,y1"));
    };
    let mut out = [T::default(); 4];
    for (o, t) in out.iter_mut().zip(v) {
        *o = t
            .trim()
            .parse()
            .map_err(|_| format!("`{t}` is not {what}"))?;
    }
    Ok(out)
}

/// The flags every study (`converge`, `adaptive`, `filters`) takes: what
/// it renders, on how many threads, how often, and where it keeps its
/// references and rows.
#[derive(Debug, Args)]
pub struct StudyArgs {
    /// A built-in scene (week09, cover, showcase, horizon, caustics) or a
    /// TOML scene file [default: week09; caustics for `adaptive`].
    #[arg(long)]
    pub scene: Option<String>,
    /// Image width in pixels, height by the scene's aspect [default: the
    /// scene's; 320 for `filters`].
    #[arg(long, value_parser = value_parser!(u32).range(1..=MAX_WIDTH as i64))]
    pub width: Option<u32>,
    /// Ray segments per path [default: the scene's].
    #[arg(long, value_parser = value_parser!(u32).range(1..=MAX_DEPTH as i64))]
    pub max_depth: Option<u32>,
    /// Seeds per measured point or row; the RMSE is the root of the mean
    /// squared error over them [default: 1 for `converge`, 5 for
    /// `adaptive`, 4 for `filters`].
    #[arg(long, value_parser = value_parser!(u32).range(1..=MAX_SEEDS as i64))]
    pub seeds: Option<u32>,
    /// Worker threads.
    #[arg(long, default_value_t = 2, value_parser = value_parser!(u16).range(1..=MAX_THREADS as i64))]
    pub threads: u16,
    /// Where references are cached [default: $XDG_CACHE_HOME/strata or
    /// ~/.cache/strata].
    #[arg(long)]
    pub cache_dir: Option<PathBuf>,
    /// Also write the rows as CSV here [default for `converge`:
    /// converge-SCENE.csv].
    #[arg(long)]
    pub csv: Option<PathBuf>,
}

impl StudyArgs {
    /// `--scene`, or the study's default scene.
    #[must_use]
    pub fn scene_or<'a>(&'a self, default: &'a str) -> &'a str {
        self.scene.as_deref().unwrap_or(default)
    }

    /// `--seeds`, or the study's default count.
    #[must_use]
    pub fn seeds_or(&self, default: u32) -> u32 {
        self.seeds.unwrap_or(default)
    }
}

/// `strata converge` flags.
#[derive(Debug, Args)]
pub struct ConvergeArgs {
    /// The flags every study takes.
    #[command(flatten)]
    pub study: StudyArgs,
    /// The crop measured, `x0,x1,y0,y1` in pixels [default: the central
    /// half of the image in each direction].
    #[arg(long, value_parser = pixel_bounds)]
    pub pixel_bounds: Option<[u32; 4]>,
    /// Samplers to measure, comma-separated [default: all].
    #[arg(long, value_enum, value_delimiter = ',')]
    pub samplers: Vec<SamplerKind>,
    /// Also measure 1024 spp (after 1, 4, 16, 64, 256).
    #[arg(long, conflicts_with = "spps")]
    pub with_1024: bool,
    /// The spp measured, comma-separated [default: 1,4,16,64,256].
    #[arg(long, value_delimiter = ',', value_parser = value_parser!(u32).range(1..=MAX_STUDY_SPP as i64))]
    pub spps: Vec<u32>,
    /// Samples per pixel of the reference (Sobol'), at least 16 times the
    /// largest measured spp.
    #[arg(long, default_value_t = 16384, value_parser = value_parser!(u32).range(1..=MAX_STUDY_SPP as i64))]
    pub reference_spp: u32,
    /// The plot written, a PNG [default: converge-SCENE.png].
    #[arg(long)]
    pub plot: Option<PathBuf>,
    /// Also measure where the error lies in frequency: the periodogram of
    /// each point's error image (luminance, mean removed), averaged over
    /// the seeds, plotted radially to this PNG with its CSV beside it
    /// (same name, .csv); prints each sampler's power below 0.125 cycles
    /// per pixel and its RMSE as ratios to the first sampler's. The window
    /// must be wider or taller than 8 pixels (the low band's lowest
    /// frequency) and at most 512 pixels a side.
    #[arg(long)]
    pub error_spectrum: Option<PathBuf>,
}

/// [`strata::render::Adaptive::DEFAULT_THRESHOLD`] as `--adaptive`
/// shows it (a test checks they agree).
pub const DEFAULT_THRESHOLD_TEXT: &str = "0.0004";

/// `strata adaptive` flags.
#[derive(Debug, Args)]
pub struct AdaptiveArgs {
    /// The flags every study takes.
    #[command(flatten)]
    pub study: StudyArgs,
    /// The crop measured, `x0,x1,y0,y1` in pixels [default: the whole
    /// image].
    #[arg(long, value_parser = pixel_bounds)]
    pub pixel_bounds: Option<[u32; 4]>,
    /// Pixel sampler of the adaptive and the uniform renders.
    #[arg(long, value_enum, default_value_t = SamplerKind::Sobol)]
    pub sampler: SamplerKind,
    /// The adaptive threshold (`render --adaptive`'s).
    #[arg(long, value_parser = positive_f32, default_value_t = strata::render::Adaptive::DEFAULT_THRESHOLD)]
    pub threshold: f32,
    /// The fewest samples a pixel takes (a multiple of 4, at least 8).
    #[arg(long, default_value_t = strata::render::Adaptive::DEFAULT_MIN, value_parser = value_parser!(u32).range(8..=MAX_SPP as i64))]
    pub min_spp: u32,
    /// The most samples a pixel takes (rounded down to whole blocks of
    /// --min-spp/4).
    #[arg(long, default_value_t = strata::render::Adaptive::DEFAULT_MAX, value_parser = value_parser!(u32).range(8..=MAX_SPP as i64))]
    pub max_spp: u32,
}

/// `strata filters` flags.
#[derive(Debug, Args)]
pub struct FiltersArgs {
    /// The flags every study takes.
    #[command(flatten)]
    pub study: StudyArgs,
    /// Pixel sampler of every render.
    #[arg(long, value_enum, default_value_t = SamplerKind::Sobol)]
    pub sampler: SamplerKind,
    /// The filters measured, comma-separated, each at its usual radius
    /// (the box is always measured: every ratio is to it) [default: all].
    #[arg(long, value_enum, value_delimiter = ',')]
    pub filters: Vec<FilterName>,
    /// The spp measured, comma-separated.
    #[arg(long, value_delimiter = ',', default_value = "1,4,16", value_parser = value_parser!(u32).range(1..=MAX_STUDY_SPP as i64))]
    pub spps: Vec<u32>,
    /// Samples per pixel of each filter's reference (Sobol'), at least 16
    /// times the largest measured spp.
    #[arg(long, default_value_t = 1024, value_parser = value_parser!(u32).range(1..=MAX_STUDY_SPP as i64))]
    pub reference_spp: u32,
    /// Times every render is timed (the first also measures its error);
    /// each filter's time against the box's is the median over them.
    #[arg(long, default_value_t = 5, value_parser = value_parser!(u32).range(1..=MAX_SEEDS as i64))]
    pub rounds: u32,
}

/// `strata aliasing` flags.
#[derive(Debug, Args)]
pub struct AliasingArgs {
    /// A built-in scene (week09, cover, showcase, horizon, caustics) or a
    /// TOML scene file.
    #[arg(long, default_value = "horizon")]
    pub scene: String,
    /// Width of each panel in pixels, height by the scene's aspect
    /// [default: the scene's].
    #[arg(long, value_parser = value_parser!(u32).range(1..=MAX_PANEL_WIDTH as i64))]
    pub width: Option<u32>,
    /// Samples per pixel of every panel.
    #[arg(long, default_value_t = 4, value_parser = value_parser!(u32).range(1..=MAX_STUDY_SPP as i64))]
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
    #[arg(long, default_value_t = 1024, value_parser = value_parser!(u32).range(0..=MAX_STUDY_SPP as i64))]
    pub reference_spp: u32,
    /// Seed of every panel.
    #[arg(long, default_value_t = 0)]
    pub seed: u64,
    /// Worker threads.
    #[arg(long, default_value_t = 2, value_parser = value_parser!(u16).range(1..=MAX_THREADS as i64))]
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

/// `strata spectrum` flags.
#[derive(Debug, Args)]
pub struct SpectrumArgs {
    /// Samplers, comma-separated; several are shown side by side [default:
    /// all].
    #[arg(long, value_enum, value_delimiter = ',')]
    pub sampler: Vec<SamplerKind>,
    /// Samples per pixel of the pattern.
    #[arg(long, default_value_t = 64, value_parser = value_parser!(u32).range(1..=MAX_PATTERN_SPP as i64))]
    pub spp: u32,
    /// Pixels whose periodograms are averaged.
    #[arg(long, default_value_t = 1024, value_parser = value_parser!(u32).range(1..=MAX_PATTERN_PIXELS as i64))]
    pub pixels: u32,
    /// Highest frequency on each axis, in cycles per pixel [default: 4
    /// √spp, at least 16; at most 128].
    #[arg(long, value_parser = value_parser!(u32).range(1..=MAX_RANGE as i64))]
    pub max_frequency: Option<u32>,
    /// Seed of the sample streams.
    #[arg(long, default_value_t = 0)]
    pub seed: u64,
    /// Worker threads (the result does not depend on it).
    #[arg(long, default_value_t = 2, value_parser = value_parser!(u16).range(1..=MAX_THREADS as i64))]
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

/// `strata bench` flags.
#[derive(Debug, Args)]
pub struct BenchArgs {
    /// Also write the report as JSON to this file.
    #[arg(long)]
    pub json: Option<PathBuf>,
    /// Timed repetitions of every figure (after one warm-up).
    #[arg(long, default_value_t = 5, value_parser = value_parser!(u16).range(1..=MAX_REPETITIONS as i64))]
    pub repetitions: u16,
    /// Shortest duration of one timing, in milliseconds.
    #[arg(long, default_value_t = 100, value_parser = value_parser!(u64).range(1..=MAX_MIN_TIME_MS))]
    pub min_time_ms: u64,
    /// Run only this group of comparisons [default: all].
    #[arg(long, value_enum)]
    pub group: Option<crate::bench::Group>,
    /// Path tracer of the rendering figures: scalar or lockstep (the
    /// images are the same) [default: lockstep where the build has AVX,
    /// else scalar].
    #[arg(long, value_enum)]
    pub integrator: Option<IntegratorName>,
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
/// (Serde: a checkpoint keeps them, to resume the same render.)
///
/// The parsers only parse: every range and every relation between flags
/// is checked by [`RenderArgs::validate`] (`crate::settings`), the one
/// check of a render's settings however they arrive (this command line, a
/// checkpoint's header).
#[derive(Clone, Debug, PartialEq, Args, serde::Serialize, serde::Deserialize)]
pub struct RenderArgs {
    /// A built-in scene (week09, cover, showcase, horizon, caustics) or a
    /// TOML scene file.
    #[arg(long, default_value = "week09")]
    pub scene: String,
    /// Image width in pixels [default: the scene's].
    #[arg(long)]
    pub width: Option<u32>,
    /// Image height in pixels [default: width / aspect].
    #[arg(long, conflicts_with = "aspect")]
    pub height: Option<u32>,
    /// Width / height [default: the scene's, 16:9 for the built-ins].
    #[arg(long, allow_hyphen_values = true)]
    pub aspect: Option<f32>,
    /// Samples per pixel [default: the scene's].
    #[arg(long)]
    pub spp: Option<u32>,
    /// Ray segments from the camera per path (1 = camera rays only)
    /// [default: the scene's].
    #[arg(long)]
    pub max_depth: Option<u32>,
    /// Pixel sampler.
    #[arg(long, value_enum, default_value_t = SamplerKind::Independent)]
    pub sampler: SamplerKind,
    /// Seed of every sample stream.
    #[arg(long, default_value_t = 0)]
    pub seed: u64,
    /// Worker threads.
    #[arg(long, default_value_t = 2)]
    pub threads: u16,
    /// Tile side in pixels (changes speed, never the image).
    #[arg(long, default_value_t = 32)]
    pub tile: u32,
    /// PNG transfer curve: sRGB, or the course's gamma 2.
    #[arg(long, value_enum, default_value_t = Transfer::Srgb)]
    pub gamma: Transfer,
    /// Turn off direct lighting from sphere lights (BSDF sampling only).
    #[arg(long)]
    pub no_direct_lighting: bool,
    /// Trace through a BVH: auto (from [`BVH_THRESHOLD`] spheres), on or
    /// off. Changes speed, never the image.
    #[arg(long, value_enum, default_value_t = BvhMode::Auto, help = format!(
        "Trace through a BVH: auto (from {BVH_THRESHOLD} spheres), on or off. \
         Changes speed, never the image"
    ))]
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
    /// Adaptive sampling (instead of --spp): every pixel takes a pilot of
    /// --min-spp/2 samples in two halves, then a rest of at least
    /// --min-spp/2 as long as the pilot asks, up to --max-spp, and stays
    /// unbiased; a smaller THRESHOLD asks for more samples where
    /// the pilot is noisy (see the README; default 0.0004).
    #[arg(
        long,
        value_name = "THRESHOLD",
        num_args = 0..=1,
        default_missing_value = DEFAULT_THRESHOLD_TEXT,
        conflicts_with_all = ["samples", "spp"]
    )]
    pub adaptive: Option<f32>,
    /// The fewest samples a pixel takes with --adaptive (a multiple of 4,
    /// at least 8).
    #[arg(long, requires = "adaptive", default_value_t = strata::render::Adaptive::DEFAULT_MIN)]
    pub min_spp: u32,
    /// The most samples a pixel takes with --adaptive (rounded down to
    /// whole blocks of --min-spp/4).
    #[arg(long, requires = "adaptive", default_value_t = strata::render::Adaptive::DEFAULT_MAX)]
    pub max_spp: u32,
    /// With --adaptive, also write a heat map of the samples each pixel
    /// took as a PNG (viridis, log scale: dark = --min-spp, yellow =
    /// --max-spp),
    /// with a legend under it (at least 240 pixels wide).
    #[arg(long, requires = "adaptive")]
    pub spp_map: Option<PathBuf>,
    /// Pixel reconstruction filter. Box, tent, gaussian and
    /// blackman-harris are importance-sampled (each pixel depends only on
    /// its own samples); mitchell and lanczos, whose lobes are negative,
    /// are splatted into every pixel they reach (a .film of a pixel window
    /// then also holds the sums its samples add to the pixels around it;
    /// an image of a window renders those pixels' samples too), except
    /// with --adaptive.
    #[arg(long, value_enum, default_value_t = FilterName::Box)]
    pub filter: FilterName,
    /// Filter radius in pixels [default: box 0.5, tent 1, gaussian 1.5
    /// (σ 0.5), mitchell 2 (B = C = 1/3), lanczos 3 (τ 3),
    /// blackman-harris 1.5].
    #[arg(long, allow_hyphen_values = true)]
    pub filter_radius: Option<f32>,
    /// Texture filtering: none (point sampling, the course's) or box (the
    /// checker averaged in closed form over each camera ray's footprint,
    /// from ray differentials).
    #[arg(long, value_enum, default_value_t = TextureFilterName::None)]
    pub texture_filter: TextureFilterName,
    /// Path tracer: scalar (one path at a time) or lockstep (eight paths
    /// at once, shaded a material at a time); the image is the same
    /// [default: lockstep where the build has AVX, else scalar: the
    /// faster].
    #[arg(long, value_enum)]
    pub integrator: Option<IntegratorName>,
    /// Output file: .png (8-bit), .exr (linear float), or .film (exact
    /// partial sums for `strata merge`) [default: SCENE.png].
    #[arg(short, long)]
    pub output: Option<PathBuf>,
    /// Write run facts (threads, wall time, SIMD level, integrator, rays)
    /// as JSON.
    #[arg(long)]
    pub stats: Option<PathBuf>,
    /// Keep each finished tile in this file as the render goes, so an
    /// interrupted render (Ctrl-C, SIGTERM, a killed job, a failed write)
    /// can be resumed with --resume; removed once the output is written
    /// [default: OUTPUT.checkpoint, beside the output].
    #[arg(long, conflicts_with = "no_checkpoint")]
    pub checkpoint: Option<PathBuf>,
    /// Keep no checkpoint (an interrupted render is then lost).
    #[arg(long)]
    pub no_checkpoint: bool,
    /// Finish an interrupted render from its checkpoint: the flags, scene
    /// and output are the checkpoint's, but for those that never change
    /// the image (--threads, -o, --stats, --spp-map, --integrator, and
    /// --scene for a scene file that moved); tiles it holds are not rendered again, and
    /// the output is byte for byte the uninterrupted render's.
    #[arg(long, value_name = "CHECKPOINT")]
    #[serde(skip)]
    pub resume: Option<PathBuf>,
    /// The flags given on the command line (clap ids, e.g. `max_depth`),
    /// as [`Cli::parse_with_sources`] finds them: `--resume` refuses all
    /// but `threads`. Empty for arguments built in code.
    #[arg(skip)]
    #[serde(skip)]
    pub given: Vec<String>,
}

/// The texture filters `--texture-filter` offers.
#[derive(
    Clone, Copy, Debug, PartialEq, Eq, clap::ValueEnum, serde::Serialize, serde::Deserialize,
)]
pub enum TextureFilterName {
    /// Point sampling.
    None,
    /// The checker's box average over the footprint.
    Box,
}

impl TextureFilterName {
    /// The core's setting.
    #[must_use]
    pub fn filter(self) -> TextureFilter {
        match self {
            TextureFilterName::None => TextureFilter::None,
            TextureFilterName::Box => TextureFilter::Box,
        }
    }
}

/// The path tracers `--integrator` offers.
#[derive(
    Clone, Copy, Debug, PartialEq, Eq, clap::ValueEnum, serde::Serialize, serde::Deserialize,
)]
pub enum IntegratorName {
    /// One path at a time.
    Scalar,
    /// Eight paths in lockstep.
    Lockstep,
}

impl IntegratorName {
    /// The core's setting; `None` (the flag not given) is the build's
    /// faster ([`strata::render::Integrator::default`]).
    #[must_use]
    pub fn integrator(name: Option<Self>) -> strata::render::Integrator {
        match name {
            None => strata::render::Integrator::default(),
            Some(IntegratorName::Scalar) => strata::render::Integrator::Scalar,
            Some(IntegratorName::Lockstep) => strata::render::Integrator::Lockstep,
        }
    }
}

/// The filters `--filter` offers, with their usual shape parameters.
#[derive(
    Clone, Copy, Debug, PartialEq, Eq, clap::ValueEnum, serde::Serialize, serde::Deserialize,
)]
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
    /// The core's filter kind of this name, with the shape parameters the
    /// variants above document.
    #[must_use]
    pub fn kind(self) -> FilterKind {
        match self {
            FilterName::Box => FilterKind::Box,
            FilterName::Tent => FilterKind::Tent,
            FilterName::Gaussian => FilterKind::Gaussian { sigma: 0.5 },
            FilterName::Mitchell => FilterKind::Mitchell {
                b: 1.0 / 3.0,
                c: 1.0 / 3.0,
            },
            FilterName::Lanczos => FilterKind::Lanczos { tau: 3.0 },
            FilterName::BlackmanHarris => FilterKind::BlackmanHarris,
        }
    }

    /// The filter of this name and `radius` (its usual one if `None`).
    pub fn filter(self, radius: Option<f32>) -> Result<PixelFilter> {
        let kind = self.kind();
        let r = radius.unwrap_or(kind.default_radius());
        PixelFilter::new(kind, r)
            .map_err(|e| anyhow::anyhow!("--filter {} --filter-radius {r}: {e}", kind.name()))
    }
}

/// Parses `x0,x1,y0,y1` fractions (checked by the validation).
fn crop_window(s: &str) -> Result<[f32; 4], String> {
    four(s, "a number")
}

/// Parses `A..B` sample indices (checked by the validation).
fn sample_range(s: &str) -> Result<std::ops::Range<u32>, String> {
    crate::film::parse_range(s).ok_or_else(|| format!("`{s}` is not a sample range A..B"))
}

/// `strata merge` flags.
#[derive(Debug, Args)]
pub struct MergeArgs {
    /// Partial films written by `strata render -o PART.film`.
    #[arg(required = true)]
    pub parts: Vec<PathBuf>,
    /// Output: .png or .exr (the parts must make the whole render), or
    /// .film (they may make a staged part of it: one pixel window × one
    /// sample range, to merge on with the rest).
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

/// `strata verify` flags.
#[derive(Debug, Args)]
pub struct VerifyArgs {
    /// Worker threads (the hashes do not depend on it).
    #[arg(long, default_value_t = 2, value_parser = value_parser!(u16).range(1..=MAX_THREADS as i64))]
    pub threads: u16,
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn bare_adaptive_shows_the_core_default_threshold() {
        let t: f32 = DEFAULT_THRESHOLD_TEXT.parse().unwrap();
        assert_eq!(t, strata::render::Adaptive::DEFAULT_THRESHOLD);
    }

    /// Every `--filter` name is the core's kind of that name, with its
    /// usual parameters and radius.
    #[test]
    fn every_filter_name_builds_its_filter() {
        use clap::ValueEnum;
        for name in FilterName::value_variants() {
            let flag = name.to_possible_value().unwrap();
            assert_eq!(Some(name.kind()), FilterKind::named(flag.get_name()));
            let f = name.filter(None).unwrap();
            assert_eq!(f.kind(), name.kind());
            assert_eq!(f.radius(), f.kind().default_radius());
        }
    }
}
