//! The golden table: every output Strata writes, locked by hash.
//!
//! - Renders: the exact film sums of a small render of every built-in
//!   scene and every example scene file, under every sampler, and of a few
//!   renders with the reconstruction settings ([`VARIANTS`]: pixel
//!   filters, the prefiltered checker, adaptive sampling).
//! - Scenes: the content hash of every scene of the table (`scene` rows),
//!   which film keys, image metadata and study caches carry.
//! - Files: the exact bytes of the PNG, EXR and `.film` file of one
//!   golden render of each built-in scene (`file.png`, `file.exr`,
//!   `file.film` rows), so encoders and headers are locked too.
//!
//! Every build of Strata, on any CPU (x86-64 from SSE2 to AVX-512,
//! aarch64), at any thread count, must reproduce these values: `strata
//! verify` checks the table, and CI checks it on a native, a portable
//! SSE2 and an aarch64 build.
//!
//! Versioning: a change that alters an existing row is an output change:
//! raise `strata::render::OUTPUT_REVISION`, update the rows and add a line
//! under "Output changes" in CHANGELOG.md. New rows (a new sampler, scene
//! or file) are appended and do not change the revision, so users'
//! partial films keep merging. The file rows also hold the crate version's
//! text, so a release re-pins them, and the PNG rows the bytes of the
//! `png` crate's fast deflate (fdeflate) at the versions `Cargo.lock`
//! pins: an update that changes its output is an output change. The pin test in
//! `std-runner/tests/output_locks.rs` enforces all of it.

use anyhow::{Result, anyhow};
use strata::render::PixelSum;

use crate::film::{Film, RenderKey};
use crate::hash::Fnv;
use crate::image_io::Transfer;
use crate::job::{Job, SamplerKind, run};
use crate::scenes::{BUILT_IN, SceneData, built_in, file};

/// Image size of a golden render.
pub const SIZE: (u32, u32) = (32, 18);
/// Samples per pixel of a golden render.
pub const SPP: u32 = 4;
/// Seed of a golden render.
pub const SEED: u64 = 5;
/// Ray segments per path of a golden render.
pub const DEPTH: u32 = 8;

/// Scene files rendered by the table, embedded so `strata verify` needs
/// no files: (path in the repository, text).
pub const EXAMPLE_SCENES: [(&str, &str); 1] = [(
    "examples/scenes/materials.toml",
    include_str!("../../examples/scenes/materials.toml"),
)];

/// (scene, key, FNV-1a 64). The key is a sampler (the film sums of that
/// render), a variant key (`sobol+mitchell`), `scene` (the scene's content
/// hash) or `file.EXT` (the bytes of [`FILE_FORMATS`]' files). Keyed by
/// name; new rows are appended.
pub const GOLDEN: &[(&str, &str, u64)] = &[
    ("week09", "independent", 0xef90137be0baabed),
    ("week09", "grid", 0xce5e83ae653f5c3b),
    ("week09", "stratified", 0xcfc40dd5903b6621),
    ("week09", "sobol", 0x0ce399d2f3d237ec),
    ("week09", "halton", 0x10b617f9a6e09f14),
    ("cover", "independent", 0x7c4f21e8847c08a5),
    ("cover", "grid", 0x0f9b6ac2091a6162),
    ("cover", "stratified", 0x31b329bd52f7c93f),
    ("cover", "sobol", 0x2d982d151fd9377d),
    ("cover", "halton", 0x0425d495fee4d47f),
    ("showcase", "independent", 0xb7be970b8294f39e),
    ("showcase", "grid", 0x2fe8c5a4b53f8831),
    ("showcase", "stratified", 0x6ec1316d39ba1b19),
    ("showcase", "sobol", 0x63fc9e8883742a82),
    ("showcase", "halton", 0x4ca9093b2eac4edd),
    ("horizon", "independent", 0xc868a8be5b898e42),
    ("horizon", "grid", 0xe8883ca54db29ca3),
    ("horizon", "stratified", 0x07bb3d9113943dea),
    ("horizon", "sobol", 0xba7d5ce98ada1b6a),
    ("horizon", "halton", 0x55211b31a56ba780),
    (
        "examples/scenes/materials.toml",
        "independent",
        0x051a95e245f740fb,
    ),
    ("examples/scenes/materials.toml", "grid", 0xc4d28080ffdf57c3),
    (
        "examples/scenes/materials.toml",
        "stratified",
        0x297197030d402c4f,
    ),
    (
        "examples/scenes/materials.toml",
        "sobol",
        0xce19734d8eb44e36,
    ),
    (
        "examples/scenes/materials.toml",
        "halton",
        0xcea86264b0378216,
    ),
    ("showcase", "sobol+mitchell", 0xf22ff17388606ef7),
    ("showcase", "stratified+lanczos", 0x923d46048966546d),
    ("week09", "halton+gaussian", 0x654bbe6f5ff71871),
    ("horizon", "stratified+texture-box", 0xc57dfd9d5e59c2b0),
    ("week09", "sobol+adaptive", 0xe94489c1fa500cee),
    ("cover", "independent+adaptive", 0xbc01e39da46954d9),
    ("week09", "scene", 0x7ee690f76348c390),
    ("cover", "scene", 0xdec2984dedc5ee3f),
    ("showcase", "scene", 0x0fd2d63ec0dc14d1),
    ("horizon", "scene", 0x70895a9d06f68ddd),
    (
        "examples/scenes/materials.toml",
        "scene",
        0x5d436e3c9fec95bc,
    ),
    ("week09", "file.png", 0x9e9373741d1c627e),
    ("week09", "file.exr", 0xcffe4d65a09b578d),
    ("week09", "file.film", 0x6f1d421365b42379),
    ("cover", "file.png", 0xd37a564d3675897d),
    ("cover", "file.exr", 0xd848043d1227e0b6),
    ("cover", "file.film", 0xb57f19e4afe3eb35),
    ("showcase", "file.png", 0x522fd699e6c457ee),
    ("showcase", "file.exr", 0x9168035cbaf4b621),
    ("showcase", "file.film", 0x00c83e968873ab70),
    ("horizon", "file.png", 0xfaef62a69f3b83fb),
    ("horizon", "file.exr", 0xc2396d98bbcad29d),
    ("horizon", "file.film", 0xb034292ed2b18c82),
    ("week09", "zsobol", 0xb0c5ca522d792239),
    ("cover", "zsobol", 0x171f443435315b18),
    ("showcase", "zsobol", 0xb55d2e6b853e234a),
    ("horizon", "zsobol", 0xf708af671b27b1d7),
    (
        "examples/scenes/materials.toml",
        "zsobol",
        0x82f1ea945317ac0f,
    ),
    ("caustics", "independent", 0xeb4e7d1feaff04a4),
    ("caustics", "grid", 0x0259081fd17d31c8),
    ("caustics", "stratified", 0x39bd820dd7d2356f),
    ("caustics", "sobol", 0x1bc77160a90e23f4),
    ("caustics", "halton", 0xb3a3711b160aff30),
    ("caustics", "zsobol", 0xcc9b09bf6251b89e),
    ("caustics", "scene", 0x03a5d427e40e1807),
    ("caustics", "file.png", 0xec8fb59ca2eaa021),
    ("caustics", "file.exr", 0xa906fd09dfa11470),
    ("caustics", "file.film", 0x905cf894c1f34f02),
];

/// The files locked byte for byte for each built-in scene: the golden
/// render with [`FILE_SAMPLER`], written as `strata render -o x.EXT` would.
pub const FILE_FORMATS: [&str; 3] = ["png", "exr", "film"];

/// The sampler of the file rows.
pub const FILE_SAMPLER: SamplerKind = SamplerKind::Independent;

/// A reconstruction setting rendered on top of the base settings.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum Variant {
    /// A pixel filter at its usual radius.
    Filter(strata::filter::FilterKind),
    /// The box-filtered checker (`--texture-filter box`).
    TextureBox,
    /// Adaptive sampling: at least 2 × [`SPP`], at most 4 × [`SPP`], threshold 0.002.
    Adaptive,
}

/// The variant rows: (scene, row key, sampler, setting). The row key names
/// the sampler and the setting, and is the table's second column.
pub const VARIANTS: [(&str, &str, SamplerKind, Variant); 6] = [
    (
        "showcase",
        "sobol+mitchell",
        SamplerKind::Sobol,
        Variant::Filter(strata::filter::FilterKind::Mitchell {
            b: 1.0 / 3.0,
            c: 1.0 / 3.0,
        }),
    ),
    (
        "showcase",
        "stratified+lanczos",
        SamplerKind::Stratified,
        Variant::Filter(strata::filter::FilterKind::Lanczos { tau: 3.0 }),
    ),
    (
        "week09",
        "halton+gaussian",
        SamplerKind::Halton,
        Variant::Filter(strata::filter::FilterKind::Gaussian { sigma: 0.5 }),
    ),
    (
        "horizon",
        "stratified+texture-box",
        SamplerKind::Stratified,
        Variant::TextureBox,
    ),
    (
        "week09",
        "sobol+adaptive",
        SamplerKind::Sobol,
        Variant::Adaptive,
    ),
    (
        "cover",
        "independent+adaptive",
        SamplerKind::Independent,
        Variant::Adaptive,
    ),
];

/// The scenes of the table: the built-ins, then the example files.
#[must_use]
pub fn scene_names() -> Vec<&'static str> {
    BUILT_IN
        .iter()
        .copied()
        .chain(EXAMPLE_SCENES.iter().map(|(p, _)| *p))
        .collect()
}

/// Loads a scene of the table by name.
pub fn scene(name: &str) -> Result<SceneData> {
    if let Some(s) = built_in(name) {
        return Ok(s);
    }
    let (path, text) = EXAMPLE_SCENES
        .iter()
        .find(|(p, _)| *p == name)
        .ok_or_else(|| anyhow!("`{name}` is not a scene of the golden table"))?;
    Ok(file::parse(std::path::Path::new(path), text)?)
}

/// FNV-1a 64 of a film: each pixel's sums (low, high 32-bit halves), its
/// sample count and dropped count, little-endian, row-major; then its
/// weight sum (halves likewise) if that is not `2²⁴ × samples`, the value
/// weights of 1 give (so films of box and tent hash as before weights
/// were kept); then its `own_minus_sum` if that is not 0 (likewise).
#[must_use]
pub fn film_hash(pixels: &[PixelSum]) -> u64 {
    let mut h = Fnv::default();
    for p in pixels {
        let [r, g, b] = p.sum;
        for s in [r, g, b] {
            h.u32(s as u32);
            h.u32((s >> 32) as u32);
        }
        h.u32(p.samples);
        h.u32(p.dropped);
        if p.weight != (p.samples as i64) << 24 {
            h.u32(p.weight as u32);
            h.u32((p.weight >> 32) as u32);
        }
        // Hashed where the own sums are not the sums (weights other than
        // 1), so box films keep their hashes.
        if p.own_minus_sum != [0; 3] {
            for s in p.own_minus_sum {
                h.u32(s as u32);
                h.u32((s >> 32) as u32);
            }
        }
    }
    h.finish()
}

/// Renders the golden film of `scene` with `sampler` and hashes it. The
/// BVH is on where the renderer would use it, so the hash covers that
/// path too.
pub fn render_hash(scene: &SceneData, sampler: SamplerKind, threads: usize) -> Result<u64> {
    render_variant_hash(scene, sampler, None, threads)
}

/// The golden job for `scene` and `sampler`: [`SIZE`], [`SPP`], [`SEED`],
/// [`DEPTH`], the box filter, on `threads` threads in tiles of 8.
#[must_use]
pub fn job(scene: &SceneData, sampler: SamplerKind, threads: usize) -> Job<'_> {
    let (width, height) = SIZE;
    Job {
        max_depth: DEPTH,
        sampler,
        seed: SEED,
        threads,
        tile: 8,
        ..Job::new(scene, width, height, SPP)
    }
}

/// The hash of a golden render with a reconstruction setting (`None`: the
/// base settings).
pub fn render_variant_hash(
    scene: &SceneData,
    sampler: SamplerKind,
    variant: Option<Variant>,
    threads: usize,
) -> Result<u64> {
    let mut job = job(scene, sampler, threads);
    match variant {
        None => {}
        Some(Variant::Filter(kind)) => {
            job.filter = strata::render::PixelFilter::new(kind, kind.default_radius())
                .map_err(|e| anyhow!("filter {}: {e}", kind.name()))?;
        }
        Some(Variant::TextureBox) => job.texture_filter = strata::render::TextureFilter::Box,
        Some(Variant::Adaptive) => {
            job.adaptive = Some(
                strata::render::Adaptive::new(2 * SPP, 4 * SPP, 0.002)
                    .map_err(|e| anyhow!("adaptive: {e}"))?,
            );
            job.spp = 4 * SPP;
            job.samples = 0..4 * SPP;
        }
    }
    Ok(film_hash(&run(&job, &|_| {})?.pixels))
}

/// The FNV-1a 64 of the bytes of each of [`FILE_FORMATS`]' files of the
/// golden render of `scene` with [`FILE_SAMPLER`] (sRGB PNG), encoded in
/// memory exactly as `strata render -o golden.EXT` writes them.
pub fn file_hashes(scene: &SceneData, threads: usize) -> Result<[u64; 3]> {
    let job = job(scene, FILE_SAMPLER, threads);
    let done = run(&job, &|_| {})?;
    let film = Film {
        key: RenderKey::of(&job),
        window: job.window,
        samples: job.samples.clone(),
        border: done.border,
        pixels: done.pixels,
    };
    let mut out = [0; 3];
    for (h, ext) in out.iter_mut().zip(FILE_FORMATS) {
        let name = std::path::PathBuf::from(format!("golden.{ext}"));
        let bytes = film.output_bytes(&name, Transfer::Srgb)?;
        *h = crate::hash::fnv1a(&bytes);
    }
    Ok(out)
}

/// One entry of the table, re-rendered.
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct Outcome {
    /// Scene name.
    pub scene: String,
    /// The row's key: a sampler name, a variant key (`sobol+mitchell`),
    /// `scene` or `file.EXT`.
    pub key: String,
    /// The table's value, if the table has the entry.
    pub expected: Option<u64>,
    /// What this build renders.
    pub got: u64,
}

impl Outcome {
    /// Whether this build reproduces the table.
    #[must_use]
    pub fn pass(&self) -> bool {
        self.expected == Some(self.got)
    }
}

/// Every row this build can produce, as (scene, key): every scene under
/// every sampler, the variants, every scene's hash, the built-in scenes'
/// files. [`verify`] checks the table's rows in the table's order, then
/// any of these the table lacks.
#[must_use]
pub fn rows() -> Vec<(&'static str, String)> {
    let mut out = Vec::new();
    for name in scene_names() {
        for sampler in SamplerKind::ALL {
            out.push((name, sampler.name().to_string()));
        }
    }
    for (name, key, _, _) in VARIANTS {
        out.push((name, key.to_string()));
    }
    for name in scene_names() {
        out.push((name, "scene".to_string()));
    }
    for name in BUILT_IN {
        for ext in FILE_FORMATS {
            out.push((name, format!("file.{ext}")));
        }
    }
    out
}

/// This build's value of the row (`name`, `key`) of the table, where
/// `scene_data` is the scene `name` loads.
pub fn compute(name: &str, scene_data: &SceneData, key: &str, threads: usize) -> Result<u64> {
    if let Some(ext) = key.strip_prefix("file.") {
        let k = FILE_FORMATS
            .iter()
            .position(|f| *f == ext)
            .ok_or_else(|| anyhow!("golden key `{key}`: no such file format"))?;
        return Ok(file_hashes(scene_data, threads)?[k]);
    }
    compute_film(name, scene_data, key, threads)
}

/// [`compute`] for every row but the file rows: film and scene hashes,
/// which need no image encoder (so a program that calls only this, such
/// as the browser page, links none).
///
/// # Errors
/// A file row, an unknown key, or a render's error.
pub fn compute_film(name: &str, scene_data: &SceneData, key: &str, threads: usize) -> Result<u64> {
    if key == "scene" {
        return Ok(scene_data.content_hash());
    }
    if key.starts_with("file.") {
        return Err(anyhow!("golden key `{key}` is a file row"));
    }
    if let Some((_, _, sampler, variant)) = VARIANTS.iter().find(|v| v.0 == name && v.1 == key) {
        return render_variant_hash(scene_data, *sampler, Some(*variant), threads);
    }
    let sampler = SamplerKind::ALL
        .into_iter()
        .find(|s| s.name() == key)
        .ok_or_else(|| {
            anyhow!("golden key `{key}` of `{name}` is not a sampler, variant, scene or file")
        })?;
    render_hash(scene_data, sampler, threads)
}

/// Checks every row of the table in the table's order, then computes the
/// rows this build can produce that the table lacks (they fail, with no
/// expected value), calling `each` as each finishes.
pub fn verify(threads: usize, each: &mut dyn FnMut(&Outcome)) -> Result<Vec<Outcome>> {
    let scenes = scene_names()
        .into_iter()
        .map(|name| Ok((name, scene(name)?)))
        .collect::<Result<Vec<_>>>()?;
    let mut keys: Vec<(String, String)> = GOLDEN
        .iter()
        .map(|(s, k, _)| (s.to_string(), k.to_string()))
        .collect();
    for (s, k) in rows() {
        if expected(s, &k).is_none() {
            keys.push((s.to_string(), k));
        }
    }
    let mut out = Vec::with_capacity(keys.len());
    let mut files: Option<(String, [u64; 3])> = None;
    for (name, key) in keys {
        let data = &scenes
            .iter()
            .find(|(n, _)| *n == name)
            .ok_or_else(|| anyhow!("golden row `{name}` names no scene of this build"))?
            .1;
        // One render serves a scene's three file rows.
        let file = FILE_FORMATS
            .iter()
            .position(|ext| key.strip_prefix("file.") == Some(ext));
        let got = match file {
            Some(k) => {
                if files.as_ref().is_none_or(|(n, _)| *n != name) {
                    files = Some((name.clone(), file_hashes(data, threads)?));
                }
                files.as_ref().expect("just filled").1[k]
            }
            None => compute(&name, data, &key, threads)?,
        };
        let o = Outcome {
            expected: expected(&name, &key),
            got,
            scene: name,
            key,
        };
        each(&o);
        out.push(o);
    }
    Ok(out)
}

/// The table's value for (scene, key), if it has the row.
#[must_use]
pub fn expected(scene: &str, key: &str) -> Option<u64> {
    GOLDEN
        .iter()
        .find(|(s, k, _)| *s == scene && *k == key)
        .map(|e| e.2)
}

/// The table as Rust source rows, for updating [`GOLDEN`].
#[must_use]
pub fn table_source(outcomes: &[Outcome]) -> String {
    outcomes
        .iter()
        .map(|o| format!("    (\"{}\", \"{}\", {:#018x}),\n", o.scene, o.key, o.got))
        .collect()
}
