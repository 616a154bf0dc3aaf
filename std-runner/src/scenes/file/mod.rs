//! Scene files in TOML. Every error names the file, the line and the
//! field, and every value is checked before any work starts.
//!
//! ```toml
//! background = "sky"          # or an RGB radiance: [0.1, 0.1, 0.1]; top-level
//!                             # keys come before the first [table]
//! [camera]
//! look_from = [-2.0, 2.0, 1.0]
//! look_at = [0.0, 0.0, -1.0]
//! up = [0.0, 1.0, 0.0]        # optional, default +y
//! vfov = 60.0                 # degrees, in (0, 180)
//! defocus_angle = 0.0         # optional, degrees; 0 is a pinhole
//! focus_dist = 5.0            # optional, default |look_from - look_at|
//!
//! [render]                    # optional defaults for the command line
//! width = 320
//! aspect = 1.7777778
//! spp = 30
//! max_depth = 5
//!
//! [textures.checker]
//! kind = "checker"            # or "image" with path = "file.png"
//! scale = 0.32
//! even = [0.2, 0.2, 0.2]
//! odd = [0.9, 0.9, 0.9]
//!
//! [materials.ground]
//! kind = "lambertian"         # lambertian, mirror, metal, dielectric, phong,
//! texture = "checker"         # blinn, phong_normalized, blinn_normalized,
//!                             # cook_torrance, light
//! [materials.centre]
//! kind = "blinn"
//! albedo = [0.4, 0.5, 0.4]
//! kd = 0.5
//! ks = 0.6
//! exponent = 8.0
//!
//! [[spheres]]
//! center = [0.0, -100.5, -1.0]
//! radius = 100.0
//! material = "ground"
//! ```
//!
//! Material parameters: `albedo` (RGB in [0, 1]) or `texture` (a texture
//! name) for lambertian, phong, blinn, the normalised lobes and
//! cook_torrance; `kd`, `ks`, `exponent` for the lobes; `alpha` (0, 1] and
//! `ior` for cook_torrance; `albedo` and `roughness` [0, 1] for metal;
//! `albedo` for mirror; `ior` for dielectric; `emit` for light.
//!
//! One file per section: `camera.rs` (`[camera]`, `[render]`),
//! `textures.rs`, `materials.rs` and `spheres.rs` (`[[spheres]]` and the
//! background); each checks its section and names what is wrong.

mod camera;
mod materials;
mod spheres;
mod textures;

use std::collections::BTreeMap;
use std::ops::Range;
use std::path::{Path, PathBuf};

use glam::Vec3;
use serde::Deserialize;
use toml::Spanned;

use crate::limits::MAX_SCENE_BYTES;
use crate::scenes::SceneData;

/// A scene file that could not be used: where and why. Shown as
/// `file:line: field: message`, or `file: message` for the file as a
/// whole (line 0: it cannot be read).
#[derive(Debug, PartialEq)]
pub struct SceneFileError {
    /// The file.
    pub file: PathBuf,
    /// 1-based line of the offending value (or its table); 0 for the
    /// file as a whole.
    pub line: usize,
    /// The field, as a TOML path (`spheres[2].radius`).
    pub field: String,
    /// What is wrong.
    pub message: String,
}

impl std::fmt::Display for SceneFileError {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        match self.line {
            0 => write!(f, "{}: {}", self.file.display(), self.message),
            n => write!(
                f,
                "{}:{n}: {}: {}",
                self.file.display(),
                self.field,
                self.message
            ),
        }
    }
}

impl std::error::Error for SceneFileError {}

/// The whole file as deserialized, each section's types next to the code
/// that checks them.
#[derive(Deserialize)]
#[serde(deny_unknown_fields)]
struct File {
    camera: Spanned<camera::FileCamera>,
    render: Option<Spanned<camera::FileRender>>,
    background: Option<Spanned<spheres::FileBackground>>,
    #[serde(default)]
    textures: BTreeMap<String, Spanned<textures::FileTexture>>,
    materials: BTreeMap<String, Spanned<materials::FileMaterial>>,
    spheres: Vec<Spanned<spheres::FileSphere>>,
}

/// Reads and checks a scene file.
pub fn load(path: &Path) -> Result<SceneData, SceneFileError> {
    use std::io::Read;
    let whole = |message: String| SceneFileError {
        file: path.to_path_buf(),
        line: 0,
        field: "(file)".into(),
        message,
    };
    // A regular file, of which at most one byte past the limit is read: a
    // device, a FIFO or a huge file is refused, not waited on or loaded.
    let meta =
        std::fs::metadata(path).map_err(|e| whole(format!("cannot read the scene file: {e}")))?;
    if !meta.is_file() {
        return Err(whole(
            "not a regular file: a scene file is TOML text".into(),
        ));
    }
    let too_large = || {
        whole(format!(
            "larger than {} MiB: not a scene file strata reads",
            MAX_SCENE_BYTES >> 20
        ))
    };
    if meta.len() > MAX_SCENE_BYTES {
        return Err(too_large());
    }
    let mut bytes = Vec::new();
    std::fs::File::open(path)
        .and_then(|f| f.take(MAX_SCENE_BYTES + 1).read_to_end(&mut bytes))
        .map_err(|e| whole(format!("cannot read the scene file: {e}")))?;
    if bytes.len() as u64 > MAX_SCENE_BYTES {
        return Err(too_large());
    }
    let text = String::from_utf8(bytes).map_err(|e| {
        // The line of the first byte that is not UTF-8.
        let at = e.utf8_error().valid_up_to();
        SceneFileError {
            file: path.to_path_buf(),
            line: e.as_bytes()[..at].iter().filter(|&&b| b == b'\n').count() + 1,
            field: "(file)".into(),
            message: format!("not UTF-8 text (byte {at} is not): a scene file is TOML, in UTF-8"),
        }
    })?;
    parse(path, &text)
}

/// Parses and checks scene-file text; `path` names it in errors and
/// anchors relative image paths. The sections are checked one after
/// another, and the first error found is the one reported.
pub fn parse(path: &Path, text: &str) -> Result<SceneData, SceneFileError> {
    let src = Source { path, text };
    let file = src.deserialize()?;
    let camera = camera::camera(&src, &file.camera)?;
    let defaults = camera::defaults(&src, file.render.as_ref())?;
    let background = spheres::background(&src, file.background.as_ref())?;
    let textures = textures::textures(&src, &file.textures)?;
    let materials = materials::materials(&src, &file.materials, &textures.named)?;
    let (spheres, sphere_material) =
        spheres::spheres(&src, &file.spheres, &materials.index, camera.look_from)?;
    Ok(SceneData {
        name: path
            .file_stem()
            .map_or("scene".into(), |s| s.to_string_lossy().into_owned()),
        spheres,
        sphere_material,
        materials: materials.list,
        image_albedo: materials.image_albedo,
        images: textures.images,
        camera,
        background,
        defaults,
    })
}

/// A point or direction as written: exactly three numbers. (serde reads
/// a `[f32; 3]` from the first three of a longer array and drops the
/// rest without a word, so a fourth component must be refused here.)
#[derive(Clone, Copy, Debug, PartialEq)]
pub(super) struct Triple(pub [f32; 3]);

impl<'de> Deserialize<'de> for Triple {
    fn deserialize<D: serde::Deserializer<'de>>(d: D) -> Result<Self, D::Error> {
        let v = Vec::<f32>::deserialize(d)?;
        <[f32; 3]>::try_from(v.as_slice()).map(Triple).map_err(|_| {
            serde::de::Error::custom(format!(
                "{} numbers where a point or direction takes three, [x, y, z]",
                v.len()
            ))
        })
    }
}

/// The file being parsed: its name and text, which every error points
/// into.
struct Source<'a> {
    path: &'a Path,
    text: &'a str,
}

impl Source<'_> {
    /// An error at the line holding byte `span.start`.
    fn error(&self, span: Range<usize>, field: &str, message: String) -> SceneFileError {
        SceneFileError {
            file: self.path.to_path_buf(),
            line: self.text[..span.start.min(self.text.len())]
                .matches('\n')
                .count()
                + 1,
            field: field.to_string(),
            // One line: a value quoted from the file may hold newlines.
            message: message.replace('\r', "").replace('\n', "\\n"),
        }
    }

    /// The text as a [`File`], or the TOML error placed in its table.
    fn deserialize(&self) -> Result<File, SceneFileError> {
        toml::from_str(self.text).map_err(|e| {
            let span = e.span().unwrap_or(0..0);
            let message = e.message();
            // serde's message for an untagged enum names only the type.
            if message.contains("FileBackground") {
                return self.error(
                    span,
                    "background",
                    "must be \"sky\" or an RGB radiance [r, g, b]".into(),
                );
            }
            // A span over the whole file is about the file itself (a
            // missing top-level table), not its first table.
            let whole =
                span.start == 0 && (span.end == 0 || span.end >= self.text.trim_end().len());
            let field = match whole {
                true => "(top level)".to_string(),
                false => enclosing_key(self.text, span.start),
            };
            // A material's keys are not spanned (a tagged enum): find the
            // one at fault and its line.
            if let Some(name) = field.strip_prefix("materials.")
                && !name.contains('.')
                && let Some(key) = materials::material_key_at_fault(self.text, name, message)
            {
                let at = materials::key_in_table(self.text, span.clone(), &key).unwrap_or(span);
                return self.error(at, &format!("{field}.{key}"), message.to_string());
            }
            self.error(span, &field, message.to_string())
        })
    }

    /// A finite point or direction.
    fn vec3(&self, s: &Spanned<Triple>, field: &str) -> Result<Vec3, SceneFileError> {
        let v = Vec3::from(s.get_ref().0);
        if v.is_finite() {
            Ok(v)
        } else {
            Err(self.error(s.span(), field, format!("must be finite, got {v}")))
        }
    }

    /// A colour with every component in `[0, max]`.
    fn colour(
        &self,
        c: [f32; 3],
        max: f32,
        span: Range<usize>,
        field: &str,
    ) -> Result<Vec3, SceneFileError> {
        let v = Vec3::from(c);
        if v.is_finite() && v.cmpge(Vec3::ZERO).all() && v.cmple(Vec3::splat(max)).all() {
            Ok(v)
        } else {
            Err(self.error(
                span,
                field,
                format!(
                    "each component must be in [0, {max}], got {v}{}",
                    if max == strata::render::MAX_SAMPLE_VALUE && v.max_element() > max {
                        // Brighter would be clamped without a word.
                        " (the film clamps every sample to 65536)"
                    } else {
                        ""
                    }
                ),
            ))
        }
    }
}

/// The table holding `offset` and, when `offset` is in a `key = value`
/// line's value, the key: `camera.vfov`, `spheres[2].radius`.
fn enclosing_key(text: &str, offset: usize) -> String {
    let table = enclosing_table(text, offset);
    let start = text[..offset.min(text.len())]
        .rfind('\n')
        .map_or(0, |i| i + 1);
    let before = &text[start..offset.min(text.len())];
    match before.split_once('=') {
        Some((key, _)) if is_bare_key(key.trim()) => match table.as_str() {
            "(top level)" => key.trim().to_string(),
            t => format!("{t}.{}", key.trim()),
        },
        _ => table,
    }
}

/// A TOML bare key (not quoted or dotted).
fn is_bare_key(k: &str) -> bool {
    !k.is_empty()
        && k.chars()
            .all(|c| c.is_ascii_alphanumeric() || c == '_' || c == '-')
}

/// The TOML table that holds byte `offset`: `materials.glass` for a
/// `[materials.glass]` header, `spheres[3]` for the fourth `[[spheres]]`,
/// `(top level)` before any header.
fn enclosing_table(text: &str, offset: usize) -> String {
    let mut current = "(top level)".to_string();
    let mut arrays: BTreeMap<String, usize> = BTreeMap::new();
    let mut pos = 0;
    for line in text.split_inclusive('\n') {
        if pos > offset {
            break;
        }
        let t = line.trim();
        if let Some(name) = t.strip_prefix("[[").and_then(|r| r.split("]]").next()) {
            let k = arrays.entry(name.trim().to_string()).or_insert(0);
            current = format!("{}[{}]", name.trim(), k);
            *k += 1;
        } else if let Some(name) = t.strip_prefix('[').and_then(|r| r.split(']').next()) {
            current = name.trim().to_string();
        }
        pos += line.len();
    }
    current
}
