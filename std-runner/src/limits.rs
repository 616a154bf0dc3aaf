//! Every limit the runner checks, in one place. First the sizes of what it
//! holds in memory (images, samples, paths, textures, spectra): the
//! command line, scene files, film files, textures and the studies check
//! against these, so a request too large is refused before any work
//! starts (and before any memory is allocated for it). Then the ranges of
//! the flags only the command line has.

/// The widest (or tallest) image, in pixels; scene files may set defaults
/// up to it too.
pub const MAX_WIDTH: u32 = 16_384;

/// The largest image, in pixels: 2²⁵ (e.g. 8192 × 4096), whose films (64
/// bytes a pixel: 2 GiB a copy) and output buffers need about 4 GiB at
/// the peak.
pub const MAX_PIXELS: u64 = 1 << 25;

/// The most samples per pixel.
pub const MAX_SPP: u32 = 1 << 20;

// Every sampler takes any spp a render may ask for (`--spp`, `--max-spp`,
// a scene file's), so `strata render` needs no check of its own.
const _: () = assert!(MAX_SPP <= strata::sampler::MAX_STRATA_SPP);

/// The longest path, in ray segments (`--max-depth`).
pub const MAX_DEPTH: u32 = 10_000;

/// The largest scene file, in bytes (256 MiB: some three million spheres
/// of about 80 bytes of TOML each).
pub const MAX_SCENE_BYTES: u64 = 256 << 20;

/// The largest texture, in texels (64 Mi: 768 MiB of linear RGB).
pub const MAX_TEXELS: u64 = 1 << 26;

/// The largest frequency range of `strata spectrum` (a 257 × 257 grid).
pub const MAX_RANGE: u32 = 128;

/// The most worker threads (`--threads` of every command).
pub const MAX_THREADS: u16 = 512;

/// The largest tile side, in pixels (`render --tile`).
pub const MAX_TILE: u32 = 4096;

/// The most samples per pixel of a study's panels and references
/// (`converge --reference-spp`, `aliasing --spp` and `--reference-spp`):
/// the stratified sampler's limit, 2²⁴.
pub const MAX_STUDY_SPP: u32 = strata::sampler::MAX_STRATA_SPP;

/// The most seeds a `converge` point averages over (`--seeds`).
pub const MAX_SEEDS: u32 = 64;

/// The widest `aliasing` panel, in pixels (`--width`).
pub const MAX_PANEL_WIDTH: u32 = 4096;

/// The most samples per pixel of a `spectrum` pattern (`--spp`).
pub const MAX_PATTERN_SPP: u32 = 4096;

/// The most pixels whose periodograms `spectrum` averages (`--pixels`).
pub const MAX_PATTERN_PIXELS: u32 = 1 << 20;

/// The most timed repetitions of each `bench` figure (`--repetitions`).
pub const MAX_REPETITIONS: u16 = 100;

/// The longest minimum duration of one `bench` timing, in milliseconds
/// (`--min-time-ms`): a minute.
pub const MAX_MIN_TIME_MS: u64 = 60_000;

/// The longest side of a window `converge --error-spectrum` transforms:
/// its periodogram is a direct transform, `W·H·(W + H)` operations (at
/// most `2²⁸` per image at 512 × 512), and each measured point keeps its
/// `W·H` spectrum until the end.
pub const MAX_SPECTRUM_SIDE: u32 = 512;
