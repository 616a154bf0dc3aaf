//! `strata render`: a scene (built-in or file) to a PNG, EXR or partial
//! `.film`, after every flag is checked; run facts to stdout and `--stats`.

use std::path::{Path, PathBuf};
use std::sync::atomic::{AtomicBool, AtomicUsize, Ordering};
use std::time::Duration;

use anyhow::{Context, Result, bail};
use strata::render::{Adaptive, Tile, TileStats};

use crate::checkpoint::{self, Checkpoint, STOP};
use crate::cli::{IntegratorName, RenderArgs};
use crate::commands::output::{
    SppMap, check_output_or_film, same_path, spp_summary, write_film_or_image, write_text,
};
use crate::commands::{
    adaptive_settings, check_output_ext, check_pixels, height_for, resolve_scene, window_of,
};
use crate::film::{Film, RenderKey, is_film_path, samples_text, window_text};
use crate::image_io::{Transfer, check_writable_dir, say};
use crate::job::{Job, Outcome, Rendered, Resume, TileFilm, run_resumable};
use crate::progress::Phase;
use crate::scenes::SceneData;
use crate::scenes::built_in;

/// Runs `strata render`: the plan (every check), the render, the files,
/// the report; or, with `--resume`, the rest of a checkpointed render.
pub fn render(args: &RenderArgs) -> Result<()> {
    if let Some(path) = &args.resume {
        // A flag that changes the image would contradict the checkpoint's,
        // even one given at its default value.
        if let Some(flag) = args
            .given
            .iter()
            .find(|g| g.as_str() != "resume" && !RESUME_FLAGS.contains(&g.as_str()))
        {
            bail!(
                "--resume takes its flags from the checkpoint, not --{}: give it alone, or with \
                 what never changes the image (--threads, -o, --stats, --spp-map, --integrator, \
                 --scene for a scene file that moved)",
                flag.replace('_', "-")
            );
        }
        return resume(path, args);
    }
    let scene = resolve_scene(&args.scene)?;
    let plan = args.plan(&scene)?;
    warn_bright_lights(&scene);
    let checkpoint = match &plan.checkpoint {
        None => None,
        Some(path) => {
            if path.exists() {
                bail!(
                    "the checkpoint `{0}` exists: an earlier render was interrupted; finish it \
                     with `strata render --resume {0}`, or delete it to start again",
                    path.display()
                );
            }
            Some(Checkpoint::create(
                path,
                &args.absolute(&plan.output)?,
                &plan.job,
            )?)
        }
    };
    finish(&plan, checkpoint, Vec::new())
}

/// Says so when a light is brighter than a sample may carry: where the
/// camera sees it directly its pixels are clamped to that (the film's
/// cap), while the light it sheds on surfaces is not.
fn warn_bright_lights(scene: &SceneData) {
    let cap = strata::render::MAX_SAMPLE_VALUE;
    let brightest = scene
        .materials
        .iter()
        .filter_map(|m| match m {
            strata::render::Material::DiffuseLight { emit } => Some(emit.max_element()),
            _ => None,
        })
        .fold(0.0f32, f32::max);
    if brightest > cap {
        eprintln!(
            "warning: a light emits {brightest:e}, above the {cap} a sample may carry: where the \
             camera sees it directly its pixels are clamped to {cap} (the light it sheds is not)"
        );
    }
}

/// The flags `--resume` takes beside the checkpoint's (clap ids): none
/// changes the image (the scene file is checked against the saved
/// scene's name and content hash).
const RESUME_FLAGS: [&str; 6] = [
    "threads",
    "output",
    "stats",
    "spp_map",
    "scene",
    "integrator",
];

/// `strata render --resume FILE`: the checkpoint's flags (with those of
/// [`RESUME_FLAGS`] given now in their place) planned again, so every
/// check runs again; its tiles kept, the rest rendered.
fn resume(given_path: &Path, now: &RenderArgs) -> Result<()> {
    // The file itself, links resolved: its directory anchors the paths it
    // keeps, and it is the file appended to and removed at the end.
    let real = given_path
        .canonicalize()
        .with_context(|| format!("cannot read the checkpoint `{}`", given_path.display()))?;
    let path = real.as_path();
    let (opened, mut saved) = checkpoint::open(path)?;
    let mut args = saved.args.clone();
    let given = |id: &str| now.given.iter().any(|g| g == id);
    // The image is the same whatever the output's name, but not whether
    // it is an image or a film: an image of a window of a splatted render
    // renders the window's border too.
    if given("output")
        && let (Some(old), Some(new)) = (&args.output, &now.output)
        && is_film_path(old) != is_film_path(new)
    {
        bail!(
            "-o `{}`: the checkpoint's render writes {}; resume it to a file of that kind",
            new.display(),
            if is_film_path(old) {
                "a .film"
            } else {
                "an image (.png or .exr)"
            }
        );
    }
    if given("threads") {
        args.threads = now.threads;
    }
    if given("output") {
        args.output.clone_from(&now.output);
    }
    if given("stats") {
        args.stats.clone_from(&now.stats);
    }
    if given("spp_map") {
        args.spp_map.clone_from(&now.spp_map);
    }
    if given("scene") {
        args.scene.clone_from(&now.scene);
    }
    if given("integrator") {
        args.integrator = now.integrator;
    }
    // The checkpoint is this file, wherever it is now.
    args.checkpoint = Some(path.to_path_buf());
    args.no_checkpoint = false;
    let name = || format!("checkpoint `{}`", path.display());
    args.validate()
        .with_context(|| format!("{}: its settings", name()))?;
    // Files of a job that was moved without them: say how to go on.
    for (file, flag, id) in [
        (&args.output, "-o", "output"),
        (&args.stats, "--stats", "stats"),
        (&args.spp_map, "--spp-map", "spp_map"),
    ] {
        if let Some(dir) = file.as_deref().and_then(Path::parent)
            && !given(id)
            && !dir.as_os_str().is_empty()
            && !dir.is_dir()
        {
            bail!(
                "{}: its {flag} `{}` is in a directory that is gone (moved?): give {flag} with \
                 the file's new name",
                name(),
                file.as_deref().unwrap_or(dir).display()
            );
        }
    }
    let scene = resolve_scene(&args.scene)
        .with_context(|| format!("{}: its scene (moved? give --scene FILE)", name()))?;
    let plan = args
        .plan(&scene)
        .with_context(|| format!("{}: its settings", name()))?;
    warn_bright_lights(&scene);
    saved.check(&plan.job).with_context(name)?;
    saved.read_tiles(&opened, &plan.job).with_context(name)?;
    let checkpoint = Checkpoint::reopen(opened, &saved)?;
    if saved.dropped_bytes > 0 {
        say(&format!(
            "checkpoint `{}`: it holds {} whole; {} bytes of tile records cut off by the \
             interrupt, or damaged, are dropped, and their tiles are rendered again",
            path.display(),
            tiles_text(saved.tiles.len()),
            saved.dropped_bytes
        ));
    }
    finish(&plan, Some(checkpoint), saved.tiles)
}

/// Set once every tile is done: a first signal then lets the output be
/// written (a moment) rather than leave a temporary file; a second exits
/// at once (the checkpoint is still whole). Before, the first SIGINT or
/// SIGTERM sets [`STOP`] (no new tile starts) and a second exits at once
/// (the checkpoint's records are whole or dropped on resume).
static WRITING: AtomicBool = AtomicBool::new(false);

/// The checkpoint of the render in progress, for the message of a second
/// signal (the handler is process-wide).
static CHECKPOINT_PATH: std::sync::Mutex<Option<PathBuf>> = std::sync::Mutex::new(None);

/// Renders the tiles `done` lacks, appending each to `checkpoint`, then
/// writes the files and removes the checkpoint.
fn finish(
    plan: &RenderPlan<'_>,
    checkpoint: Option<Checkpoint>,
    done: Vec<TileFilm>,
) -> Result<()> {
    let job = &plan.job;
    if let Some(c) = &checkpoint {
        *CHECKPOINT_PATH.lock().unwrap_or_else(|e| e.into_inner()) = Some(c.path().to_path_buf());
        // Only one handler per process; a second render in one process
        // (tests) keeps the first, which sets the same flag.
        #[cfg(not(target_family = "wasm"))]
        let _ = ctrlc::set_handler(|| {
            if WRITING.load(Ordering::SeqCst) && !STOP.swap(true, Ordering::SeqCst) {
                eprintln!("\nwriting the output: a moment (again to quit at once)");
            } else if STOP.swap(true, Ordering::SeqCst) {
                // Records are whole or dropped on resume: the file is good.
                if let Ok(guard) = CHECKPOINT_PATH.try_lock()
                    && let Some(p) = guard.as_ref()
                {
                    eprintln!(
                        "quitting: the tiles finished so far are kept in `{0}`; `strata render \
                         --resume {0}` renders the rest",
                        p.display()
                    );
                }
                std::process::exit(130);
            } else {
                eprintln!("\nstopping: finishing the tiles in flight (again to quit at once)");
            }
        });
    }
    let resumed = done.len();
    let appended = AtomicUsize::new(0);
    let rendered_now = AtomicUsize::new(0);
    // A checkpoint that cannot be written (a full disk: it is 64 bytes a
    // pixel) costs only the safety it gives: the render goes on without
    // it, and the tiles it holds whole still resume.
    let failed = AtomicBool::new(false);
    let phase = Phase::start(
        &format!("render {}", job.scene.name),
        job.window.area() as u64,
    );
    let on_tile = |t: &TileFilm| -> Result<()> {
        rendered_now.fetch_add(1, Ordering::Relaxed);
        if let Some(c) = &checkpoint
            && !failed.load(Ordering::Relaxed)
        {
            match c.append(t) {
                Ok(()) => {
                    appended.fetch_add(1, Ordering::Relaxed);
                }
                Err(e) if !failed.swap(true, Ordering::SeqCst) => phase.println(&format!(
                    "warning: {e:#}; rendering on without it (an interrupted render resumes \
                     from the {} it holds whole)",
                    tiles_text(resumed + appended.load(Ordering::Relaxed))
                )),
                Err(_) => {}
            }
        }
        Ok(())
    };
    let resume = Resume {
        done,
        on_tile: &on_tile,
        stop: &STOP,
    };
    let outcome = run_resumable(job, &|n| phase.inc(n), resume);
    phase.finish();
    // Keeps the checkpoint when it holds tiles or was given (and says so),
    // else removes it: a render refused before its first tile leaves no
    // file.
    let kept = |e: anyhow::Error| -> anyhow::Error {
        match &checkpoint {
            Some(c) if resumed + appended.load(Ordering::Relaxed) > 0 || !c.is_new() => {
                c.sync().ok();
                e.context(format!(
                    "{1} finished are kept in `{0}`: once the cause is mended (room on the disk, \
                     a directory), `strata render --resume {0}` goes on",
                    c.path().display(),
                    tiles_text(resumed + appended.load(Ordering::Relaxed))
                ))
            }
            Some(c) => {
                std::fs::remove_file(c.path()).ok();
                e
            }
            None => e,
        }
    };
    let rendered = match outcome.map_err(kept)? {
        // (Also when a signal came as the last tiles finished: nothing is
        // left, so the output is written after all.)
        Outcome::Finished(r) => {
            WRITING.store(true, Ordering::SeqCst);
            r
        }
        Outcome::Stopped { total, .. } => {
            let Some(c) = &checkpoint else {
                unreachable!("only a checkpointed render installs the stop handler")
            };
            c.sync().ok();
            // What the file holds (tiles rendered after a failed append
            // are not in it).
            let kept = resumed + appended.load(Ordering::Relaxed);
            return Err(Interrupted(format!(
                "interrupted: {kept} of {total} tiles are kept in `{0}`; \
                 `strata render --resume {0}` renders the rest",
                c.path().display()
            ))
            .into());
        }
    };
    let Rendered {
        border,
        pixels,
        wall,
        stats,
        run_stats,
    } = rendered;
    let mut film = Film {
        key: RenderKey::of(job),
        window: job.window,
        samples: job.samples.clone(),
        border,
        pixels,
    };
    if let Some(window) = plan.image_window {
        // An image of part of a splatted render: its pixels' neighbours
        // within the margin were rendered too, so the window's sums are
        // complete; the image keeps the window alone.
        film = Film {
            pixels: crate::film::cut(&film.pixels, film.extent(), window),
            window,
            border: 0,
            ..film
        };
    }
    // Samples of the film's own pixels (those of a splatted image's
    // border are rendered, not kept).
    let dropped: u64 = film.window_pixels().iter().map(|p| p.dropped as u64).sum();
    plan.write(&film).map_err(kept)?;
    if let Some(path) = &plan.stats {
        write_stats(path, plan, wall, (stats, run_stats), dropped, resumed).map_err(kept)?;
    }
    if let Some(c) = &checkpoint {
        std::fs::remove_file(c.path())
            .with_context(|| format!("cannot remove the checkpoint `{}`", c.path().display()))?;
    }
    say(&plan.summary(&film));
    let now = rendered_now.load(Ordering::Relaxed);
    if resumed > 0 {
        say(&format!(
            "resumed: {resumed} of {} tiles from the checkpoint, {now} rendered now",
            resumed + now,
        ));
    }
    if now == 0 {
        say("nothing was left to render: every tile came from the checkpoint");
    } else {
        say(&speed_line(job, wall, run_stats, dropped));
    }
    Ok(())
}

/// `1 tile`, `N tiles`.
fn tiles_text(n: usize) -> String {
    match n {
        1 => "1 tile".to_string(),
        n => format!("{n} tiles"),
    }
}

/// A render stopped by a signal, its tiles checkpointed: `strata` exits
/// with status 130 and this message.
#[derive(Debug, thiserror::Error)]
#[error("{0}")]
pub struct Interrupted(pub String);

/// `strata render` with every flag checked: the job and its files.
struct RenderPlan<'a> {
    job: Job<'a>,
    /// The image or film.
    output: PathBuf,
    /// The PNG transfer curve of `output`.
    gamma: Transfer,
    /// `--spp-map`.
    spp_map: Option<PathBuf>,
    /// `--stats`.
    stats: Option<PathBuf>,
    /// The checkpoint, unless `--no-checkpoint`.
    checkpoint: Option<PathBuf>,
    /// The window an image keeps when the job renders more: a window of a
    /// splatted filter written as an image renders its border's pixels
    /// too (their samples reach it), then keeps the window.
    image_window: Option<Tile>,
}

impl RenderArgs {
    /// Checks every flag against `scene`, in the order of the messages a
    /// user meets: the size, the sample counts, the window, the filter,
    /// the files.
    fn plan<'a>(&self, scene: &'a SceneData) -> Result<RenderPlan<'a>> {
        let mut job = self.job(scene)?;
        let output = self.output_files(&scene.name)?;
        let checkpoint = self.checkpoint_file(&output)?;
        let (width, height, window) = (job.width, job.height, job.window);
        let mut image_window = None;
        let layout = job.layout();
        if layout.splats() && !is_film_path(&output) && window != Tile::whole(width, height) {
            job.window = layout.extent(window, width, height);
            image_window = Some(window);
        }
        Ok(RenderPlan {
            job,
            output,
            gamma: self.gamma,
            spp_map: self.spp_map.clone(),
            stats: self.stats.clone(),
            checkpoint,
            image_window,
        })
    }

    /// The render these settings make of `scene`, checked (the one check
    /// of [`RenderArgs::validate`], then everything that needs the
    /// scene: its default size, the window inside the image, the samples
    /// within spp, the filter), files aside: what `strata render` plans,
    /// and what the C API renders.
    pub fn job<'a>(&self, scene: &'a SceneData) -> Result<Job<'a>> {
        self.validate()?;
        let d = scene.defaults;
        let width = self.width.unwrap_or(d.width);
        let height = match self.height {
            Some(h) => h,
            None => height_for(scene, width, self.aspect)?,
        };
        check_pixels(width, height, 1).map_err(|e| {
            if self.crop.is_some() || self.pixel_bounds.is_some() {
                // The cap bounds the one image a merge of the parts holds.
                anyhow::anyhow!(
                    "{e}: the cap is on the whole frame, also for a window of it (its parts \
                     merge into one image of that size)"
                )
            } else {
                e
            }
        })?;
        let (spp, adaptive) = self.sample_counts(d.spp)?;
        let window = match (self.crop, self.pixel_bounds) {
            (Some(c), _) => crop_to_window(c, width, height)?,
            (None, Some(b)) => window_of(b, width, height)?,
            (None, None) => Tile::whole(width, height),
        };
        let filter = self.filter.filter(self.filter_radius)?;
        let samples = self.samples.clone().unwrap_or(0..spp);
        if samples.end > spp {
            bail!(
                "--samples {}..{} reaches past the {spp} samples per pixel",
                samples.start,
                samples.end
            );
        }
        Ok(Job {
            window,
            samples,
            max_depth: self.max_depth.unwrap_or(d.max_depth),
            sampler: self.sampler,
            seed: self.seed,
            threads: self.threads as usize,
            tile: self.tile,
            direct_lighting: !self.no_direct_lighting,
            bvh: self.bvh,
            filter,
            adaptive,
            texture_filter: self.texture_filter.filter(),
            integrator: IntegratorName::integrator(self.integrator),
            ..Job::new(scene, width, height, spp)
        })
    }

    /// The sampler's pattern size and the adaptive settings: `--spp` (or
    /// the scene's), or with `--adaptive` up to `--max-spp`, as the
    /// pattern then holds every sample a pixel may take.
    fn sample_counts(&self, scene_spp: u32) -> Result<(u32, Option<Adaptive>)> {
        let Some(t) = self.adaptive else {
            return Ok((self.spp.unwrap_or(scene_spp), None));
        };
        let (min, max) = (self.min_spp, self.max_spp);
        // Checked by `validate`: the settings make an adaptive render.
        let adaptive = adaptive_settings(min, max, t, "--adaptive")?;
        Ok((adaptive.max(), Some(adaptive)))
    }

    /// The image's name (`-o`, or SCENE.png), with it and `--stats` and
    /// `--spp-map` checked writable.
    fn output_files(&self, scene: &str) -> Result<PathBuf> {
        let output = self
            .output
            .clone()
            .unwrap_or_else(|| PathBuf::from(format!("{scene}.png")));
        check_output_or_film(&output)?;
        if let Some(stats) = &self.stats {
            check_output_ext(stats, "json", "--stats")?;
        }
        if let Some(map) = &self.spp_map {
            check_output_ext(map, "png", "--spp-map")?;
            if same_path(map, &output) {
                bail!("--spp-map `{}` is the image's output", map.display());
            }
        }
        Ok(output)
    }
}

impl RenderArgs {
    /// The checkpoint file (unless `--no-checkpoint`), checked: not one of
    /// the outputs, in a writable directory.
    fn checkpoint_file(&self, output: &Path) -> Result<Option<PathBuf>> {
        if self.no_checkpoint {
            return Ok(None);
        }
        let path = match &self.checkpoint {
            Some(p) => p.clone(),
            None => checkpoint::default_path(output),
        };
        let others = [Some(output), self.stats.as_deref(), self.spp_map.as_deref()];
        if others.into_iter().flatten().any(|o| same_path(o, &path)) {
            bail!(
                "--checkpoint `{}` is one of the render's outputs",
                path.display()
            );
        }
        check_writable_dir(&path).context("--checkpoint")?;
        Ok(Some(path))
    }

    /// These flags with every path absolute and the output (the plan's)
    /// named, so a checkpoint resumes the same render from any directory.
    fn absolute(&self, output: &Path) -> Result<RenderArgs> {
        let abs = |p: &Path| {
            std::path::absolute(p).with_context(|| format!("cannot resolve `{}`", p.display()))
        };
        let opt = |p: &Option<PathBuf>| p.as_deref().map(abs).transpose();
        let mut out = self.clone();
        if built_in(&self.scene).is_none() {
            out.scene = abs(Path::new(&self.scene))?
                .to_str()
                .context("the scene file's path is not UTF-8: resume needs it as text")?
                .to_string();
        }
        // The plan's output (the default is named after the scene's stem).
        out.output = Some(abs(output)?);
        out.stats = opt(&self.stats)?;
        out.spp_map = opt(&self.spp_map)?;
        out.checkpoint = opt(&self.checkpoint)?;
        Ok(out)
    }
}

impl RenderPlan<'_> {
    /// Writes the film or image and the spp map: both files or neither.
    fn write(&self, film: &Film) -> Result<()> {
        let map = self
            .spp_map
            .as_ref()
            .map(|_| SppMap::draw(film))
            .transpose()?;
        write_film_or_image(&self.output, film, self.gamma)?;
        if let (Some(path), Some(map)) = (&self.spp_map, &map)
            && let Err(e) = map.write(path)
        {
            std::fs::remove_file(&self.output).ok();
            return Err(e);
        }
        Ok(())
    }

    /// What was rendered, at what settings, to which file.
    fn summary(&self, film: &Film) -> String {
        let job = &self.job;
        let whole = film.window == Tile::whole(job.width, job.height);
        let part = if whole && job.samples == (0..job.spp) {
            String::new()
        } else {
            format!(
                " (pixels {}, samples {})",
                window_text(film.window),
                samples_text(&job.samples)
            )
        };
        let spp_text = match job.adaptive {
            None => format!("{} spp", job.spp),
            Some(a) => format!(
                "adaptive {}..{} spp at {} ({})",
                a.min(),
                a.max(),
                a.threshold(),
                spp_summary(film)
            ),
        };
        format!(
            "{}: {}x{} {spp_text} ({}, seed {}), depth {}{part}, to {}",
            job.scene.name,
            job.width,
            job.height,
            job.sampler.name(),
            job.seed,
            job.max_depth,
            self.output.display()
        )
    }
}

/// How fast the render ran, and the samples it dropped.
fn speed_line(job: &Job<'_>, wall: Duration, st: TileStats, dropped: u64) -> String {
    let secs = wall.as_secs_f64();
    format!(
        "{:.3} s on {} threads ({}): {:.2} M samples/s, {:.2} M rays/s{}",
        secs,
        job.threads,
        strata::trace::simd_level().name(),
        st.paths as f64 / secs.max(1e-9) / 1e6,
        (st.rays + st.shadow_rays) as f64 / secs.max(1e-9) / 1e6,
        if dropped > 0 {
            format!(", {dropped} NaN/inf samples dropped")
        } else {
            String::new()
        }
    )
}

/// Writes the run facts of `--stats` as JSON.
fn write_stats(
    path: &Path,
    plan: &RenderPlan<'_>,
    wall: Duration,
    (st, run): (TileStats, TileStats),
    dropped: u64,
    resumed: usize,
) -> Result<()> {
    let job = &plan.job;
    let scene = job.scene;
    let facts = serde_json::json!({
        "scene": scene.name,
        "output": plan.output.display().to_string(),
        "threads": job.threads,
        "tile": job.tile,
        "simd": strata::trace::simd_level().name(),
        "integrator": job.integrator.name(),
        "wall_seconds": wall.as_secs_f64(),
        "camera_paths": st.paths,
        "rays": st.rays,
        "shadow_rays": st.shadow_rays,
        "dropped_samples": dropped,
        "resumed_tiles": resumed,
        // What this run traced in `wall_seconds` (less than the totals
        // above after a resume).
        "run_camera_paths": run.paths,
        "run_rays": run.rays,
        "run_shadow_rays": run.shadow_rays,
        "bvh": scene.use_bvh(job.bvh),
        "version": crate::film::version(),
    });
    write_text(path, &(serde_json::to_string_pretty(&facts)? + "\n"))
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
