//! The golden table: a hash of the exact film sums of a small render of
//! every built-in scene and every example scene file, under every sampler,
//! and of a few renders with the reconstruction settings ([`VARIANTS`]:
//! pixel filters, the prefiltered checker, adaptive sampling).
//!
//! Every build of Strata, on any x86-64 CPU (SSE2 to AVX-512), at any
//! thread count, must reproduce these values: `strata verify` re-renders
//! the table, and the value-stability test checks it under a portable and
//! a native build. A change that alters any pixel must update the table
//! and add a line under "Output changes" in CHANGELOG.md.

use anyhow::{Result, anyhow};
use strata::render::PixelSum;

use crate::render::{Job, SamplerKind, run, whole};
use crate::scenes::{BUILT_IN, BvhMode, SceneData, built_in};

/// Image size of a golden render.
pub const SIZE: (u32, u32) = (32, 18);
/// Samples per pixel of a golden render.
pub const SPP: u32 = 4;
/// Seed of a golden render.
pub const SEED: u64 = 5;
/// Ray segments per path of a golden render.
pub const MAX_DEPTH: u32 = 8;

/// Scene files rendered by the table, embedded so `strata verify` needs
/// no files: (path in the repository, text).
pub const EXAMPLE_SCENES: [(&str, &str); 1] = [(
    "examples/scenes/materials.toml",
    include_str!("../../examples/scenes/materials.toml"),
)];

/// (scene, sampler, FNV-1a 64 of the film). Keyed by name, so a new
/// scene or sampler adds rows without moving any.
pub const GOLDEN: &[(&str, &str, u64)] = &[
    ("week09", "independent", 0xa3b1b2bcd3e21f77),
    ("week09", "grid", 0xce8d68df935a9439),
    ("week09", "stratified", 0x4f28f547359e6b5b),
    ("week09", "sobol", 0xeb1beeb21e8f4a66),
    ("week09", "halton", 0x78ff2021113a1e1d),
    ("cover", "independent", 0x8d79f6b18daa403c),
    ("cover", "grid", 0xcdca85e9a21a9c62),
    ("cover", "stratified", 0x332191608714f4cf),
    ("cover", "sobol", 0x5bd1dac69d25b954),
    ("cover", "halton", 0x7a4a9d46768b32a1),
    ("showcase", "independent", 0xef9e80853e86fd92),
    ("showcase", "grid", 0x7fa9bbbe2ce4aea2),
    ("showcase", "stratified", 0x39144b2cc4deda66),
    ("showcase", "sobol", 0xf66c2daf48bd9a39),
    ("showcase", "halton", 0x764c2363dd055970),
    ("horizon", "independent", 0xce069952a9473211),
    ("horizon", "grid", 0x6cfe20ba8230211f),
    ("horizon", "stratified", 0x8404b5754b2be31a),
    ("horizon", "sobol", 0xed74181e1e966aa1),
    ("horizon", "halton", 0x52a8e6640794f150),
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
        0x0c15bb3fa4e73c04,
    ),
    ("showcase", "sobol+mitchell", 0x03df8e7fdc635746),
    ("showcase", "stratified+lanczos", 0xcc1e2c3ebebefc9c),
    ("week09", "halton+gaussian", 0xb95b672928246bff),
    ("horizon", "stratified+texture-box", 0x590209255971fe33),
    ("week09", "sobol+adaptive", 0xbc65cf2a907b80b3),
    ("cover", "independent+adaptive", 0x47bba7a9e811a346),
];

/// A reconstruction setting rendered on top of the base settings.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum Variant {
    /// A pixel filter at its usual radius.
    Filter(strata::filter::FilterKind),
    /// The box-filtered checker (`--texture-filter box`).
    TextureBox,
    /// Adaptive sampling: base [`SPP`], at most 4 × [`SPP`], threshold 0.05.
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
    Ok(crate::scene_file::parse(std::path::Path::new(path), text)?)
}

/// FNV-1a 64 of a film: each pixel's sums (low, high 32-bit halves), its
/// sample count and dropped count, little-endian, row-major; then its
/// weight sum (halves likewise) if that is not `2²⁴ × samples`, the value
/// weights of 1 give (so films of box and tent hash as before weights
/// were kept).
#[must_use]
pub fn film_hash(pixels: &[PixelSum]) -> u64 {
    let mut h = 0xcbf2_9ce4_8422_2325u64;
    for p in pixels {
        let [r, g, b] = p.sum;
        let words = [
            r as u32,
            (r >> 32) as u32,
            g as u32,
            (g >> 32) as u32,
            b as u32,
            (b >> 32) as u32,
            p.samples,
            p.dropped,
        ];
        let weight = (p.weight != (p.samples as i64) << 24)
            .then_some([p.weight as u32, (p.weight >> 32) as u32]);
        for w in words.into_iter().chain(weight.into_iter().flatten()) {
            for byte in w.to_le_bytes() {
                h = (h ^ byte as u64).wrapping_mul(0x0100_0000_01b3);
            }
        }
    }
    h
}

/// Renders the golden film of `scene` with `sampler` and hashes it. The
/// BVH is on where the renderer would use it, so the hash covers that
/// path too.
pub fn render_hash(scene: &SceneData, sampler: SamplerKind, threads: usize) -> Result<u64> {
    render_variant_hash(scene, sampler, None, threads)
}

/// The hash of a golden render with a reconstruction setting (`None`: the
/// base settings).
pub fn render_variant_hash(
    scene: &SceneData,
    sampler: SamplerKind,
    variant: Option<Variant>,
    threads: usize,
) -> Result<u64> {
    let (width, height) = SIZE;
    let mut job = Job {
        scene,
        width,
        height,
        window: whole(width, height),
        spp: SPP,
        samples: 0..SPP,
        max_depth: MAX_DEPTH,
        sampler,
        seed: SEED,
        threads,
        tile: 8,
        direct_lighting: true,
        bvh: BvhMode::Auto,
        filter: strata::render::PixelFilter::BOX,
        texture_filter: strata::render::TextureFilter::None,
        adaptive: None,
    };
    match variant {
        None => {}
        Some(Variant::Filter(kind)) => {
            job.filter = strata::render::PixelFilter::new(kind, kind.default_radius())
                .map_err(|e| anyhow!("filter {}: {e:?}", kind.name()))?;
        }
        Some(Variant::TextureBox) => job.texture_filter = strata::render::TextureFilter::Box,
        Some(Variant::Adaptive) => {
            job.adaptive = Some(
                strata::render::Adaptive::new(SPP, 4 * SPP, 0.05)
                    .map_err(|e| anyhow!("adaptive: {e:?}"))?,
            );
            job.spp = 4 * SPP;
            job.samples = 0..4 * SPP;
        }
    }
    Ok(film_hash(&run(&job, &|_| {})?.pixels))
}

/// One entry of the table, re-rendered.
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct Outcome {
    /// Scene name.
    pub scene: String,
    /// Sampler name, or for a variant row its key (`sobol+mitchell`).
    pub sampler: &'static str,
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

/// Re-renders every (scene, sampler) of the table and every variant,
/// calling `each` as each finishes.
pub fn verify(threads: usize, each: &mut dyn FnMut(&Outcome)) -> Result<Vec<Outcome>> {
    let mut out = Vec::new();
    for name in scene_names() {
        let data = scene(name)?;
        for sampler in SamplerKind::ALL {
            let got = render_hash(&data, sampler, threads)?;
            let expected = GOLDEN
                .iter()
                .find(|(s, k, _)| *s == name && *k == sampler.name())
                .map(|e| e.2);
            let o = Outcome {
                scene: name.to_string(),
                sampler: sampler.name(),
                expected,
                got,
            };
            each(&o);
            out.push(o);
        }
    }
    for (name, key, sampler, variant) in VARIANTS {
        let got = render_variant_hash(&scene(name)?, sampler, Some(variant), threads)?;
        let o = Outcome {
            scene: name.to_string(),
            sampler: key,
            expected: GOLDEN
                .iter()
                .find(|(s, k, _)| *s == name && *k == key)
                .map(|e| e.2),
            got,
        };
        each(&o);
        out.push(o);
    }
    Ok(out)
}

/// The table as Rust source rows, for updating [`GOLDEN`].
#[must_use]
pub fn table_source(outcomes: &[Outcome]) -> String {
    outcomes
        .iter()
        .map(|o| {
            format!(
                "    (\"{}\", \"{}\", {:#018x}),\n",
                o.scene, o.sampler, o.got
            )
        })
        .collect()
}
