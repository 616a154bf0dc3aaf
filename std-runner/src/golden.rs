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
//! text, so a release re-pins them. The pin test in
//! `std-runner/tests/output_locks.rs` enforces all of it.

use anyhow::{Result, anyhow};
use strata::render::PixelSum;

use crate::film::{Film, RenderKey};
use crate::hash::Fnv;
use crate::image_io::Transfer;
use crate::render::{Job, SamplerKind, run};
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
    ("week09", "independent", 0xa3b1b2bcd3e21f77),
    ("week09", "grid", 0xce8d68df935a9439),
    ("week09", "stratified", 0x4f28f547359e6b5b),
    ("week09", "sobol", 0xeb1beeb21e8f4a66),
    ("week09", "halton", 0x3d5dba40fd8bad4c),
    ("cover", "independent", 0x8d79f6b18daa403c),
    ("cover", "grid", 0xcdca85e9a21a9c62),
    ("cover", "stratified", 0x332191608714f4cf),
    ("cover", "sobol", 0x5bd1dac69d25b954),
    ("cover", "halton", 0x521ae0030e5a2d52),
    ("showcase", "independent", 0xef9e80853e86fd92),
    ("showcase", "grid", 0x7fa9bbbe2ce4aea2),
    ("showcase", "stratified", 0x39144b2cc4deda66),
    ("showcase", "sobol", 0xf66c2daf48bd9a39),
    ("showcase", "halton", 0x084d223c41d30e9a),
    ("horizon", "independent", 0xce069952a9473211),
    ("horizon", "grid", 0x6cfe20ba8230211f),
    ("horizon", "stratified", 0x8404b5754b2be31a),
    ("horizon", "sobol", 0xed74181e1e966aa1),
    ("horizon", "halton", 0x5ee56c30afd79f99),
    (
        "examples/scenes/materials.toml",
        "independent",
        0x4e9a76299dd713d9,
    ),
    ("examples/scenes/materials.toml", "grid", 0xb7bdfa88cc204b5c),
    (
        "examples/scenes/materials.toml",
        "stratified",
        0x68704f5d5dbb597f,
    ),
    (
        "examples/scenes/materials.toml",
        "sobol",
        0x8432a9c9ccf7dc66,
    ),
    (
        "examples/scenes/materials.toml",
        "halton",
        0xf4b122cae7b12919,
    ),
    ("showcase", "sobol+mitchell", 0xaabd93efd85d7fad),
    ("showcase", "stratified+lanczos", 0x549455ec1f013ba7),
    ("week09", "halton+gaussian", 0xb9e7b0ef8cb82649),
    ("horizon", "stratified+texture-box", 0x590209255971fe33),
    ("week09", "sobol+adaptive", 0x217c7066ab1b418a),
    ("cover", "independent+adaptive", 0xd7e1f2566e68f300),
    ("week09", "scene", 0x7ee690f76348c390),
    ("cover", "scene", 0xdec2984dedc5ee3f),
    ("showcase", "scene", 0x0fd2d63ec0dc14d1),
    ("horizon", "scene", 0x70895a9d06f68ddd),
    (
        "examples/scenes/materials.toml",
        "scene",
        0x5d436e3c9fec95bc,
    ),
    ("week09", "file.png", 0x485d6848b62d50cd),
    ("week09", "file.exr", 0x63d3eea8f8d29b3c),
    ("week09", "file.film", 0x34fb8fda69f27ecf),
    ("cover", "file.png", 0xaf2e5a8ac76f4f54),
    ("cover", "file.exr", 0x682d95853f15ca33),
    ("cover", "file.film", 0x0abf53aa2e25c122),
    ("showcase", "file.png", 0x107fd7d945d8c86c),
    ("showcase", "file.exr", 0x2c1861eba21948f0),
    ("showcase", "file.film", 0x53a263b7908591d2),
    ("horizon", "file.png", 0x5f786cbb2999ac31),
    ("horizon", "file.exr", 0xd0fd83b1f0b8eb52),
    ("horizon", "file.film", 0x5c99498959a1fd48),
    ("week09", "zsobol", 0xc51a6e4b93c45b74),
    ("cover", "zsobol", 0xce56cb08457f5d8f),
    ("showcase", "zsobol", 0x8489a2810577e7db),
    ("horizon", "zsobol", 0x9fad9dcef5b0c84d),
    (
        "examples/scenes/materials.toml",
        "zsobol",
        0xd86847d06851a30b,
    ),
    ("caustics", "independent", 0x827cbdf31a4ded27),
    ("caustics", "grid", 0x315a6e922b49b218),
    ("caustics", "stratified", 0x2c0299a084199167),
    ("caustics", "sobol", 0xdf9d8dc9bdd7b677),
    ("caustics", "halton", 0xb61a2518ad22d907),
    ("caustics", "zsobol", 0xa0cc35579024951c),
    ("caustics", "scene", 0x03a5d427e40e1807),
    ("caustics", "file.png", 0x6c92bfb7d82bb4d0),
    ("caustics", "file.exr", 0x1f82defd297d12fd),
    ("caustics", "file.film", 0xc02e3a4936a5125b),
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
/// were kept).
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
    if key == "scene" {
        return Ok(scene_data.content_hash());
    }
    if let Some(ext) = key.strip_prefix("file.") {
        let k = FILE_FORMATS
            .iter()
            .position(|f| *f == ext)
            .ok_or_else(|| anyhow!("golden key `{key}`: no such file format"))?;
        return Ok(file_hashes(scene_data, threads)?[k]);
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
