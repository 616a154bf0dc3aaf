//! Rendering a whole image: the scene's core structures built once, tiles
//! spread over a rayon pool of exactly the requested number of threads
//! (one thread: the calling one, tile after tile, with its stack).
//! Pixels do not depend on the thread count, the tile size or the order
//! in which tiles finish: each tile renders into its own film and the
//! films are placed (or, splatted, added in exact integers, whose sums
//! do not depend on the order).

use std::ops::Range;
use std::sync::atomic::{AtomicBool, Ordering};
use std::time::Duration;

use anyhow::{Context, Result, anyhow};
use glam::UVec2;
use rayon::prelude::*;
use strata::Sampler;
use strata::render::{
    Adaptive, Camera, Layout, PixelSum, RenderSettings, Scene, Tile, TileRenderer, TileStats,
    render_tile, render_tile_adaptive, render_tile_splat,
};

use crate::scenes::{BvhMode, SceneData};

/// The pixel samplers the command line offers.
#[derive(
    Clone, Copy, Debug, PartialEq, Eq, clap::ValueEnum, serde::Serialize, serde::Deserialize,
)]
pub enum SamplerKind {
    /// Uniform random positions (the course's `render()`).
    Independent,
    /// Unjittered strata centres (aliases on purpose).
    Grid,
    /// Jittered strata for any spp (the course's `render_jittered`, fixed).
    Stratified,
    /// Owen-scrambled Sobol' (best with a power-of-two spp).
    Sobol,
    /// Owen-scrambled Halton (best with spp = 2^a 3^b).
    Halton,
    /// Sobol' shared by the whole image along a hashed Morton curve:
    /// neighbouring pixels complement each other, so the error is blue
    /// noise (best with a power-of-two spp).
    #[value(name = "zsobol")]
    ZSobol,
}

impl SamplerKind {
    /// Every sampler, in the order above.
    pub const ALL: [SamplerKind; 6] = [
        SamplerKind::Independent,
        SamplerKind::Grid,
        SamplerKind::Stratified,
        SamplerKind::Sobol,
        SamplerKind::Halton,
        SamplerKind::ZSobol,
    ];

    /// The kind named `name` (its [`SamplerKind::name`]).
    ///
    /// # Errors
    /// The names of every kind, for any other.
    pub fn from_name(name: &str) -> Result<SamplerKind> {
        SamplerKind::ALL
            .into_iter()
            .find(|k| k.name() == name)
            .ok_or_else(|| {
                let names: Vec<&str> = SamplerKind::ALL.iter().map(|k| k.name()).collect();
                anyhow!("unknown sampler {name:?}: one of {}", names.join(", "))
            })
    }

    /// The name used on the command line and in metadata.
    pub fn name(self) -> &'static str {
        match self {
            SamplerKind::Independent => "independent",
            SamplerKind::Grid => "grid",
            SamplerKind::Stratified => "stratified",
            SamplerKind::Sobol => "sobol",
            SamplerKind::Halton => "halton",
            SamplerKind::ZSobol => "zsobol",
        }
    }

    /// Runs `work` with the sampler of this kind for `spp`, `seed` and an
    /// image of `resolution` pixels (only [`SamplerKind::ZSobol`] uses it),
    /// as its concrete type (static dispatch: the hot loop is compiled per
    /// kind); an error that says why if the kind refuses them
    /// ([`AnySampler::new`](crate::batch::AnySampler::new), the one place a
    /// kind becomes a sampler).
    pub fn with_sampler<W: WithSampler>(
        self,
        spp: u32,
        seed: u64,
        resolution: UVec2,
        work: W,
    ) -> Result<W::Output> {
        Ok(
            match crate::batch::AnySampler::new(self, spp, seed, resolution)? {
                crate::batch::AnySampler::Independent(s) => work.run(s),
                crate::batch::AnySampler::Grid(s) => work.run(s),
                crate::batch::AnySampler::Stratified(s) => work.run(s),
                crate::batch::AnySampler::Sobol(s) => work.run(s),
                crate::batch::AnySampler::Halton(s) => work.run(s),
                crate::batch::AnySampler::ZSobol(s) => work.run(s),
            },
        )
    }
}

/// Work generic over the sampler, for [`SamplerKind::with_sampler`] (a
/// closure cannot be generic).
pub trait WithSampler {
    /// What the work returns.
    type Output;
    /// Does the work with `sampler`.
    fn run<S: Sampler + Clone + Send + Sync>(self, sampler: S) -> Self::Output;
}

/// One render: what, at what size, how.
#[derive(Clone, Debug)]
pub struct Job<'a> {
    /// The scene.
    pub scene: &'a SceneData,
    /// Image width.
    pub width: u32,
    /// Image height.
    pub height: u32,
    /// The pixels to render, inside `width × height` ([`Tile::whole`] for
    /// all of them). Pixels outside are not traced. A pixel's samples do
    /// not depend on the window; with a splatted filter a pixel near the
    /// window's edge also gathers samples of pixels outside it, so it is
    /// complete only once the parts around it are merged.
    pub window: Tile,
    /// Samples per pixel (the sampler's pattern size).
    pub spp: u32,
    /// Sample indices to render, within `0..spp` for a whole render.
    pub samples: Range<u32>,
    /// Ray segments per path.
    pub max_depth: u32,
    /// Pixel sampler.
    pub sampler: SamplerKind,
    /// Seed of every sample stream.
    pub seed: u64,
    /// Worker threads (1: the calling thread renders, on its own stack;
    /// more: a pool of that many, which lives for the render).
    pub threads: usize,
    /// Tile side in pixels.
    pub tile: u32,
    /// Next-event estimation from sphere lights.
    pub direct_lighting: bool,
    /// Whether to trace through a BVH.
    pub bvh: BvhMode,
    /// The pixel filter (`PixelFilter::BOX` is the course's).
    pub filter: strata::render::PixelFilter,
    /// Adaptive sampling: `spp` is then its maximum and `samples` must be
    /// `0..spp`; each pixel takes what its error asks for.
    pub adaptive: Option<Adaptive>,
    /// Texture filtering at camera rays' first hits.
    pub texture_filter: strata::render::TextureFilter,
    /// The path tracer (the film is the same with either).
    pub integrator: strata::render::Integrator,
}

impl<'a> Job<'a> {
    /// A whole `width × height` render of `scene` at `spp`, with the
    /// defaults of `strata render` but one: the scene's depth, the
    /// independent sampler, seed 0, 2 threads, direct lighting, the BVH
    /// where it pays, the box filter, no texture filter, no adaptive
    /// sampling, the build's faster integrator; tiles of 16 pixels where
    /// `--tile` defaults to 32 (the side changes speed only, and the
    /// benchmark figures are timed at 16).
    /// Change what differs with struct update syntax.
    #[must_use]
    pub fn new(scene: &'a SceneData, width: u32, height: u32, spp: u32) -> Self {
        Job {
            scene,
            width,
            height,
            window: Tile::whole(width, height),
            spp,
            samples: 0..spp,
            max_depth: scene.defaults.max_depth,
            sampler: SamplerKind::Independent,
            seed: 0,
            threads: 2,
            tile: 16,
            direct_lighting: true,
            bvh: BvhMode::Auto,
            filter: strata::render::PixelFilter::BOX,
            adaptive: None,
            texture_filter: strata::render::TextureFilter::None,
            integrator: strata::render::Integrator::default(),
        }
    }
}

impl Job<'_> {
    /// How the job's films are laid out (the core's one answer): which
    /// tile renderer runs, and the margin its films hold.
    #[must_use]
    pub fn layout(&self) -> Layout {
        Layout::of(&self.filter, self.adaptive.is_some())
    }
}

/// A finished render.
#[derive(Debug)]
pub struct Rendered {
    /// Pixels beyond the window on each side whose sums `pixels` also
    /// holds (with counts of 0): a splatted filter's margin, else 0.
    pub border: u32,
    /// One accumulator per pixel of the job's window grown by `border`
    /// and clipped to the image ([`Layout::extent`]), row-major: the
    /// window's alone unless the filter splats and the window is not the
    /// whole image.
    pub pixels: Vec<PixelSum>,
    /// Wall-clock time of the render: the BVH's build and the tracing
    /// (not the merge of splatted tiles' borders, which follows); 0 in a
    /// browser (wasm32-unknown-unknown has no clock).
    pub wall: Duration,
    /// What was traced: camera paths, closest-hit rays, shadow rays (of
    /// every tile, those [`Resume::done`] brought included).
    pub stats: TileStats,
    /// What this run traced (without the tiles [`Resume::done`] brought).
    pub run_stats: TileStats,
}

/// A finished tile: its index in [`job_tiles`], its film (the tile, or the
/// tile and its splat margin) and what it traced.
pub type TileFilm = (u32, Vec<PixelSum>, TileStats);

/// What a resumable render ([`run_resumable`]) is told and tells.
pub struct Resume<'h> {
    /// Tiles already rendered (from a checkpoint): not rendered again.
    pub done: Vec<TileFilm>,
    /// Called with each tile this run finishes, before it counts as done;
    /// an error stops the render.
    pub on_tile: &'h (dyn Fn(&TileFilm) -> Result<()> + Sync),
    /// Once set, no further tile starts (those in flight finish and are
    /// passed to `on_tile`); the render then ends as [`Outcome::Stopped`].
    pub stop: &'h AtomicBool,
}

/// How a resumable render ended.
#[derive(Debug)]
pub enum Outcome {
    /// Every tile is done.
    Finished(Rendered),
    /// Stopped with `done` of `total` tiles finished (those `on_tile` took,
    /// and the ones given).
    Stopped {
        /// Tiles finished.
        done: usize,
        /// Tiles of the job.
        total: usize,
    },
}

/// The side of the job's tiles: `--tile`, or for a splatted filter at
/// least four times its margin, so a tile's film (the tile and the margin
/// a side) stays within 2.25 times the tile (the side changes speed, never
/// the image).
#[must_use]
pub fn tile_side(job: &Job<'_>) -> u32 {
    job.tile.max(4 * job.layout().margin())
}

/// The job's tiles, in the order [`run`] indexes them.
#[must_use]
pub fn job_tiles(job: &Job<'_>) -> Vec<Tile> {
    tiles(job.window, tile_side(job))
}

/// The number of the job's tiles, without listing them.
#[must_use]
pub fn tile_count(job: &Job<'_>) -> usize {
    let side = tile_side(job) as usize;
    let w = job.window;
    (w.width as usize).div_ceil(side) * (w.height as usize).div_ceil(side)
}

/// Tile `index` of [`job_tiles`], computed without listing them (a
/// single-tile call costs the same for any number of tiles).
#[must_use]
pub fn job_tile(job: &Job<'_>, index: usize) -> Option<Tile> {
    let side = tile_side(job);
    let w = job.window;
    let across = w.width.div_ceil(side) as usize;
    if index >= tile_count(job) {
        return None;
    }
    let (dx, dy) = (
        (index % across) as u32 * side,
        (index / across) as u32 * side,
    );
    Some(Tile {
        x0: w.x0 + dx,
        y0: w.y0 + dy,
        width: side.min(w.width - dx),
        height: side.min(w.height - dy),
    })
}

/// The length of a tile's film in `job`: the tile, or for a splatted
/// filter the tile and its margin a side.
pub fn tile_film_len(job: &Job<'_>, tile: Tile) -> Result<usize> {
    job.layout()
        .film_len(tile)
        .ok_or_else(|| anyhow!("tile {}: too large", bounds_text(tile)))
}

/// The tiles of `window`, row-major, `side × side` except at its right
/// and bottom edges.
pub fn tiles(window: Tile, side: u32) -> Vec<Tile> {
    let mut out = Vec::new();
    for dy in (0..window.height).step_by(side as usize) {
        for dx in (0..window.width).step_by(side as usize) {
            out.push(Tile {
                x0: window.x0 + dx,
                y0: window.y0 + dy,
                width: side.min(window.width - dx),
                height: side.min(window.height - dy),
            });
        }
    }
    out
}

/// Renders `job`, calling `progress` with each finished tile's pixel count.
pub fn run(job: &Job<'_>, progress: &(dyn Fn(u64) + Sync)) -> Result<Rendered> {
    let stop = AtomicBool::new(false);
    let resume = Resume {
        done: Vec::new(),
        on_tile: &|_| Ok(()),
        stop: &stop,
    };
    match run_resumable(job, progress, resume)? {
        Outcome::Finished(r) => Ok(r),
        Outcome::Stopped { .. } => unreachable!("nothing sets the stop flag"),
    }
}

/// [`run`], skipping the tiles `resume.done` holds, handing each tile it
/// finishes to `resume.on_tile`, and stopping early when `resume.stop`
/// is set. The pixels do not depend on which tiles were done before: the
/// tiles are placed (or added) in index order either way.
pub fn run_resumable(
    job: &Job<'_>,
    progress: &(dyn Fn(u64) + Sync),
    resume: Resume<'_>,
) -> Result<Outcome> {
    let resolution = UVec2::new(job.width, job.height);
    resumable(job, progress, resume, |work| {
        job.sampler
            .with_sampler(job.spp, job.seed, resolution, work)?
    })
}

/// [`run`] with `sampler` in place of the one `job.sampler` names (whose
/// name still keys the render): for benchmarks that time an instrumented
/// or deliberately slowed sampler in a real render.
pub fn run_with_sampler<S: Sampler + Clone + Send + Sync>(
    job: &Job<'_>,
    sampler: S,
) -> Result<Rendered> {
    let stop = AtomicBool::new(false);
    let resume = Resume {
        done: Vec::new(),
        on_tile: &|_| Ok(()),
        stop: &stop,
    };
    match resumable(job, &|_| {}, resume, |work| work.run(sampler))? {
        Outcome::Finished(r) => Ok(r),
        Outcome::Stopped { .. } => unreachable!("nothing sets the stop flag"),
    }
}

/// [`run_resumable`], the tiles rendered by `render_tiles` (the work with
/// a sampler).
fn resumable(
    job: &Job<'_>,
    progress: &(dyn Fn(u64) + Sync),
    resume: Resume<'_>,
    render_tiles: impl FnOnce(RenderAll<'_, '_>) -> Result<Vec<TileFilm>> + Send,
) -> Result<Outcome> {
    let data = job.scene;
    let w = job.window;
    let (camera, settings) = prepare(job)?;
    let layout = job.layout();
    let all = job_tiles(job);
    let mut skip = vec![false; all.len()];
    for (i, _, _) in &resume.done {
        match skip.get_mut(*i as usize) {
            Some(s) if !*s => *s = true,
            _ => return Err(anyhow!("done tile {i} is not a tile of the job, or twice")),
        }
    }
    let start = Clock::now();
    // (A macro: a closure could not take the scene's borrow.)
    macro_rules! all_of {
        ($scene:expr, $sequential:expr) => {
            RenderAll {
                job,
                scene: $scene,
                camera: &camera,
                settings: &settings,
                progress,
                tiles: &all,
                skip: &skip,
                on_tile: resume.on_tile,
                stop: resume.stop,
                sequential: $sequential,
            }
        };
    }
    let new = if job.threads == 1 {
        // One thread: this one, tile after tile (in a browser there is no
        // other).
        data.with_scene_bvh(job.bvh, |scene| render_tiles(all_of!(scene, true)))??
    } else {
        // A scoped pool: its threads have ended when the render returns (a
        // library caller may unload the code right after).
        rayon::ThreadPoolBuilder::new()
            .num_threads(job.threads)
            .build_scoped(
                |thread| thread.run(),
                |pool| {
                    data.with_scene_bvh(job.bvh, |scene| {
                        pool.install(|| render_tiles(all_of!(scene, false)))
                    })
                },
            )
            .context("cannot start the worker threads")???
    };
    let wall = start.elapsed();
    let mut run_stats = TileStats::default();
    for (_, _, s) in &new {
        run_stats.add(s);
    }
    let mut films = resume.done;
    films.extend(new);
    if films.len() < all.len() {
        return Ok(Outcome::Stopped {
            done: films.len(),
            total: all.len(),
        });
    }
    // Index order, whichever run rendered a tile: the splatted sums are
    // added in one order always.
    films.sort_unstable_by_key(|f| f.0);
    let border = layout.margin();
    let out = layout.extent(w, job.width, job.height);
    let mut pixels = vec![PixelSum::ZERO; out.area()];
    let mut stats = TileStats::default();
    for (i, film, tile_stats) in films {
        let tile = all[i as usize];
        stats.add(&tile_stats);
        if layout.splats() {
            add_splatted(&mut pixels, out, tile, layout, &film);
            continue;
        }
        for row in 0..tile.height {
            let src = &film[(row * tile.width) as usize..][..tile.width as usize];
            let at = ((tile.y0 - w.y0 + row) * w.width + tile.x0 - w.x0) as usize;
            pixels[at..at + tile.width as usize].copy_from_slice(src);
        }
    }
    Ok(Outcome::Finished(Rendered {
        border,
        pixels,
        wall,
        stats,
        run_stats,
    }))
}

/// Checks what the plan cannot (the window inside the image, adaptive
/// settings that fit the job) and makes the camera and the settings of
/// the core's tile renderers.
fn prepare(job: &Job<'_>) -> Result<(Camera, RenderSettings)> {
    let w = job.window;
    if w.width == 0
        || w.height == 0
        || w.x0.checked_add(w.width).is_none_or(|x1| x1 > job.width)
        || w.y0.checked_add(w.height).is_none_or(|y1| y1 > job.height)
    {
        return Err(anyhow!(
            "pixel window {} is empty or outside the {}x{} image",
            bounds_text(w),
            job.width,
            job.height
        ));
    }
    if job.adaptive.is_some() && job.sampler == SamplerKind::Grid {
        return Err(anyhow!(
            "adaptive sampling needs a sampler whose first samples spread over the pixel; \
             the grid fills its rows in order"
        ));
    }
    if let Some(a) = job.adaptive
        && (a.max() != job.spp || job.samples != (0..job.spp))
    {
        return Err(anyhow!(
            "adaptive sampling renders samples 0..{} of every pixel, not {}..{} of {}",
            a.max(),
            job.samples.start,
            job.samples.end,
            job.spp
        ));
    }
    let camera = Camera::new(&job.scene.camera, job.width, job.height)
        .map_err(|e| anyhow!("camera of `{}`: {e}", job.scene.name))?;
    let settings = RenderSettings {
        max_depth: job.max_depth,
        direct_lighting: job.direct_lighting,
        filter: job.filter,
        texture_filter: job.texture_filter,
        integrator: job.integrator,
    };
    Ok((camera, settings))
}

/// Adds a splatted tile's film (the tile and its margin, as `layout`
/// lays it out) into `pixels`, those of `w` (the window and its border,
/// clipped to the image); entries outside it (outside the image) are
/// dropped.
fn add_splatted(pixels: &mut [PixelSum], w: Tile, tile: Tile, layout: Layout, film: &[PixelSum]) {
    let margin = layout.margin();
    // (The film was sized by the same layout, so its size is known.)
    let pw = layout.film_size(tile).map_or(0, |s| s.0) as usize;
    for (i, p) in film.iter().enumerate() {
        let x = (tile.x0 as i64) - margin as i64 + (i % pw) as i64 - w.x0 as i64;
        let y = (tile.y0 as i64) - margin as i64 + (i / pw) as i64 - w.y0 as i64;
        if (0..w.width as i64).contains(&x) && (0..w.height as i64).contains(&y) {
            pixels[(y * w.width as i64 + x) as usize].merge(p);
        }
    }
}

/// A render's wall clock: none in a browser (wasm32-unknown-unknown),
/// whose `std` has no clock, where every duration reads 0.
struct Clock(#[cfg(not(all(target_family = "wasm", target_os = "unknown")))] std::time::Instant);

impl Clock {
    fn now() -> Self {
        Clock(
            #[cfg(not(all(target_family = "wasm", target_os = "unknown")))]
            std::time::Instant::now(),
        )
    }

    fn elapsed(&self) -> Duration {
        #[cfg(not(all(target_family = "wasm", target_os = "unknown")))]
        return self.0.elapsed();
        #[cfg(all(target_family = "wasm", target_os = "unknown"))]
        Duration::ZERO
    }
}

/// Every tile of a job, in parallel (or one after another), with one
/// sampler kind.
struct RenderAll<'a, 's> {
    job: &'a Job<'a>,
    scene: &'a Scene<'s>,
    camera: &'a Camera,
    settings: &'a RenderSettings,
    progress: &'a (dyn Fn(u64) + Sync),
    /// The job's tiles ([`job_tiles`]), and those not to render (done
    /// before).
    tiles: &'a [Tile],
    skip: &'a [bool],
    on_tile: &'a (dyn Fn(&TileFilm) -> Result<()> + Sync),
    stop: &'a AtomicBool,
    /// Tile after tile on the calling thread, not on rayon's pool.
    sequential: bool,
}

impl WithSampler for RenderAll<'_, '_> {
    type Output = Result<Vec<TileFilm>>;
    fn run<S: Sampler + Clone + Send + Sync>(self, sampler: S) -> Self::Output {
        render_all(&self, sampler)
    }
}

/// The tiles of the job `all` does not skip, in parallel (tile after tile
/// if `all.sequential`), until the stop
/// flag is set.
fn render_all<S: Sampler + Clone + Send + Sync>(
    all: &RenderAll<'_, '_>,
    sampler: S,
) -> Result<Vec<TileFilm>> {
    let RenderAll {
        job,
        scene,
        camera,
        settings,
        progress,
        ..
    } = *all;
    let done: u64 = all
        .tiles
        .iter()
        .zip(all.skip)
        .filter(|(_, s)| **s)
        .map(|(t, _)| t.area() as u64)
        .sum();
    progress(done);
    let one = |(i, tile): (usize, Tile)| -> Result<Option<TileFilm>> {
        if all.skip[i] || all.stop.load(Ordering::Relaxed) {
            return Ok(None);
        }
        let (film, stats) = tile_film(job, scene, camera, &sampler, settings, tile)?;
        let out = (i as u32, film, stats);
        (all.on_tile)(&out)?;
        progress(tile.area() as u64);
        Ok(Some(out))
    };
    let found: Result<Vec<Option<TileFilm>>> = if all.sequential {
        all.tiles.iter().copied().enumerate().map(one).collect()
    } else {
        all.tiles.par_iter().copied().enumerate().map(one).collect()
    };
    Ok(found?.into_iter().flatten().collect())
}

/// One tile's film and statistics, by the core renderer the job's
/// layout picks.
fn tile_film<S: Sampler + Clone>(
    job: &Job<'_>,
    scene: &Scene<'_>,
    camera: &Camera,
    sampler: &S,
    settings: &RenderSettings,
    tile: Tile,
) -> Result<(Vec<PixelSum>, TileStats)> {
    let mut film = vec![PixelSum::ZERO; tile_film_len(job, tile)?];
    let samples = job.samples.clone();
    let stats = match job.layout().renderer() {
        TileRenderer::Adaptive => {
            let a = job
                .adaptive
                .ok_or_else(|| anyhow!("an adaptive layout without adaptive settings"))?;
            render_tile_adaptive(scene, camera, sampler, settings, tile, a, &mut film)
        }
        TileRenderer::Splat => {
            render_tile_splat(scene, camera, sampler, settings, tile, samples, &mut film)
        }
        TileRenderer::Uniform => {
            render_tile(scene, camera, sampler, settings, tile, samples, &mut film)
        }
    }
    .map_err(|e| anyhow!("tile {}: {e}", bounds_text(tile)))?;
    Ok((film, stats))
}

/// Renders tile `index` of `job` ([`job_tiles`]' order) on the calling
/// thread, with no pool: for a host that owns its threads (the C API's
/// tile calls). Its film is the one [`run`] places (or adds, splatted)
/// at that tile, so a host that renders every tile and places them so
/// has [`run`]'s pixels. The scene's structures are built for the call
/// (for the cover's 485 spheres, well under a millisecond).
pub fn render_tile_here(job: &Job<'_>, index: usize) -> Result<TileFilm> {
    let tile = job_tile(job, index)
        .ok_or_else(|| anyhow!("tile {index}: the render has {} tiles", tile_count(job)))?;
    let (camera, settings) = prepare(job)?;
    struct One<'a, 's> {
        job: &'a Job<'a>,
        scene: &'a Scene<'s>,
        camera: &'a Camera,
        settings: &'a RenderSettings,
        tile: Tile,
    }
    impl WithSampler for One<'_, '_> {
        type Output = Result<(Vec<PixelSum>, TileStats)>;
        fn run<S: Sampler + Clone + Send + Sync>(self, sampler: S) -> Self::Output {
            tile_film(
                self.job,
                self.scene,
                self.camera,
                &sampler,
                self.settings,
                self.tile,
            )
        }
    }
    let resolution = UVec2::new(job.width, job.height);
    let (film, stats) = job.scene.with_scene_bvh(job.bvh, |scene| {
        let one = One {
            job,
            scene,
            camera: &camera,
            settings: &settings,
            tile,
        };
        job.sampler.with_sampler(job.spp, job.seed, resolution, one)
    })???;
    Ok((index as u32, film, stats))
}

/// `x0,x1,y0,y1` of a tile, as `--pixel-bounds` takes it, for messages;
/// in `u64`, as a refused window may end past `u32::MAX`.
fn bounds_text(t: Tile) -> String {
    let end = |start: u32, len: u32| start as u64 + len as u64;
    format!(
        "{},{},{},{}",
        t.x0,
        end(t.x0, t.width),
        t.y0,
        end(t.y0, t.height)
    )
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn tiles_cover_the_image_once() {
        for (w, h, s) in [(320, 180, 32), (7, 5, 3), (1, 1, 64), (100, 3, 7)] {
            // The whole image, and a window inside a larger one.
            for window in [
                Tile::whole(w, h),
                Tile {
                    x0: 5,
                    y0: 2,
                    width: w,
                    height: h,
                },
            ] {
                let (iw, ih) = (window.x0 + w + 3, window.y0 + h + 1);
                let mut hit = vec![0u8; (iw * ih) as usize];
                for t in tiles(window, s) {
                    for y in t.y0..t.y0 + t.height {
                        for x in t.x0..t.x0 + t.width {
                            hit[(y * iw + x) as usize] += 1;
                        }
                    }
                }
                for y in 0..ih {
                    for x in 0..iw {
                        let inside = (window.x0..window.x0 + w).contains(&x)
                            && (window.y0..window.y0 + h).contains(&y);
                        assert_eq!(hit[(y * iw + x) as usize], inside as u8, "{w}x{h}/{s}");
                    }
                }
            }
        }
    }
}
