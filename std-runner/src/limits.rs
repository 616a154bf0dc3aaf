//! The sizes of what the runner holds in memory (images, samples, paths,
//! textures, spectra), in one place: the command line, scene files, film
//! files, textures and the studies check against these, so a request too
//! large is refused before any work starts (and before any memory is
//! allocated for it). Flags whose range is their own (threads, tile size,
//! seeds) state it where they are declared.

/// The widest (or tallest) image, in pixels; scene files may set defaults
/// up to it too.
pub const MAX_WIDTH: u32 = 16_384;

/// The largest image, in pixels: 2²⁵ (e.g. 8192 × 4096), whose films and
/// output buffers need about 2.5 GiB at the peak.
pub const MAX_PIXELS: u64 = 1 << 25;

/// The most samples per pixel.
pub const MAX_SPP: u32 = 1 << 20;

/// The longest path, in ray segments (`--max-depth`).
pub const MAX_DEPTH: u32 = 10_000;

/// The largest texture, in texels (64 Mi: 768 MiB of linear RGB).
pub const MAX_TEXELS: u64 = 1 << 26;

/// The largest frequency range of `strata spectrum` (a 257 × 257 grid).
pub const MAX_RANGE: u32 = 128;
