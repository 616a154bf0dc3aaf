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

use std::collections::BTreeMap;
use std::path::{Path, PathBuf};

use glam::Vec3;
use serde::Deserialize;
use strata::render::{Background, Camera, CameraDesc, Material, Texture};
use strata::trace::Sphere;
use toml::Spanned;

use crate::image_io::read_png_linear;
use crate::limits::{MAX_DEPTH, MAX_SPP, MAX_WIDTH};
use crate::scenes::{Defaults, Image, SceneData};

/// A scene file that could not be used: where and why.
#[derive(Debug, thiserror::Error, PartialEq)]
#[error("{file}:{line}: {field}: {message}")]
pub struct SceneFileError {
    /// The file.
    pub file: PathBuf,
    /// 1-based line of the offending value (or its table).
    pub line: usize,
    /// The field, as a TOML path (`spheres[2].radius`).
    pub field: String,
    /// What is wrong.
    pub message: String,
}

#[derive(Deserialize)]
#[serde(deny_unknown_fields)]
struct File {
    camera: Spanned<FileCamera>,
    render: Option<Spanned<FileRender>>,
    background: Option<Spanned<FileBackground>>,
    #[serde(default)]
    textures: BTreeMap<String, Spanned<FileTexture>>,
    materials: BTreeMap<String, Spanned<FileMaterial>>,
    spheres: Vec<Spanned<FileSphere>>,
}

#[derive(Deserialize)]
#[serde(deny_unknown_fields)]
struct FileCamera {
    look_from: Spanned<[f32; 3]>,
    look_at: Spanned<[f32; 3]>,
    up: Option<Spanned<[f32; 3]>>,
    vfov: Spanned<f32>,
    defocus_angle: Option<Spanned<f32>>,
    focus_dist: Option<Spanned<f32>>,
}

#[derive(Deserialize)]
#[serde(deny_unknown_fields)]
struct FileRender {
    width: Option<Spanned<u32>>,
    aspect: Option<Spanned<f32>>,
    spp: Option<Spanned<u32>>,
    max_depth: Option<Spanned<u32>>,
}

#[derive(Deserialize)]
#[serde(untagged)]
enum FileBackground {
    Named(String),
    Colour([f32; 3]),
}

#[derive(Deserialize)]
#[serde(tag = "kind", rename_all = "snake_case", deny_unknown_fields)]
enum FileTexture {
    Checker {
        scale: f32,
        even: [f32; 3],
        odd: [f32; 3],
    },
    Image {
        path: String,
    },
}

#[derive(Deserialize)]
#[serde(tag = "kind", rename_all = "snake_case", deny_unknown_fields)]
enum FileMaterial {
    Lambertian {
        albedo: Option<[f32; 3]>,
        texture: Option<String>,
    },
    Mirror {
        albedo: [f32; 3],
    },
    Metal {
        albedo: [f32; 3],
        roughness: f32,
    },
    Dielectric {
        ior: f32,
    },
    Phong {
        albedo: Option<[f32; 3]>,
        texture: Option<String>,
        kd: f32,
        ks: f32,
        exponent: f32,
    },
    Blinn {
        albedo: Option<[f32; 3]>,
        texture: Option<String>,
        kd: f32,
        ks: f32,
        exponent: f32,
    },
    PhongNormalized {
        albedo: Option<[f32; 3]>,
        texture: Option<String>,
        kd: f32,
        ks: f32,
        exponent: f32,
    },
    BlinnNormalized {
        albedo: Option<[f32; 3]>,
        texture: Option<String>,
        kd: f32,
        ks: f32,
        exponent: f32,
    },
    CookTorrance {
        albedo: Option<[f32; 3]>,
        texture: Option<String>,
        kd: f32,
        ks: f32,
        alpha: f32,
        ior: f32,
    },
    Light {
        emit: [f32; 3],
    },
}

#[derive(Deserialize)]
#[serde(deny_unknown_fields)]
struct FileSphere {
    center: Spanned<[f32; 3]>,
    radius: Spanned<f32>,
    material: Spanned<String>,
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

/// Reads and checks a scene file.
pub fn load(path: &Path) -> Result<SceneData, SceneFileError> {
    let text = std::fs::read_to_string(path).map_err(|e| SceneFileError {
        file: path.to_path_buf(),
        line: 0,
        field: "(file)".into(),
        message: format!("cannot read: {e}"),
    })?;
    parse(path, &text)
}

/// Parses and checks scene-file text; `path` names it in errors and
/// anchors relative image paths.
pub fn parse(path: &Path, text: &str) -> Result<SceneData, SceneFileError> {
    let at = |span: std::ops::Range<usize>, field: &str, message: String| SceneFileError {
        file: path.to_path_buf(),
        line: text[..span.start.min(text.len())].matches('\n').count() + 1,
        field: field.to_string(),
        message,
    };
    let file: File = toml::from_str(text).map_err(|e| {
        let span = e.span().unwrap_or(0..0);
        let field = enclosing_table(text, span.start);
        let message = e.message();
        if message.contains("FileBackground") {
            return at(
                span,
                "background",
                "must be \"sky\" or an RGB radiance [r, g, b]".into(),
            );
        }
        at(span, &field, message.to_string())
    })?;
    let v3 = |s: &Spanned<[f32; 3]>, field: &str| -> Result<Vec3, SceneFileError> {
        let v = Vec3::from(*s.get_ref());
        if v.is_finite() {
            Ok(v)
        } else {
            Err(at(s.span(), field, format!("must be finite, got {v}")))
        }
    };
    let colour = |c: [f32; 3], max: f32, span, field: &str| -> Result<Vec3, SceneFileError> {
        let v = Vec3::from(c);
        if v.is_finite() && v.cmpge(Vec3::ZERO).all() && v.cmple(Vec3::splat(max)).all() {
            Ok(v)
        } else {
            Err(at(
                span,
                field,
                format!("each component must be in [0, {max}], got {v}"),
            ))
        }
    };

    // Camera.
    let cam = file.camera.get_ref();
    let look_from = v3(&cam.look_from, "camera.look_from")?;
    let look_at = v3(&cam.look_at, "camera.look_at")?;
    let up = match &cam.up {
        Some(u) => v3(u, "camera.up")?,
        None => Vec3::Y,
    };
    let focus_dist = match &cam.focus_dist {
        Some(f) => *f.get_ref(),
        None => (look_from - look_at).length(),
    };
    let camera = CameraDesc {
        look_from,
        look_at,
        up,
        vfov_deg: *cam.vfov.get_ref(),
        defocus_angle_deg: cam.defocus_angle.as_ref().map_or(0.0, |d| *d.get_ref()),
        focus_dist,
    };
    if let Err(e) = Camera::new(&camera, 1, 1) {
        use strata::render::CameraError::*;
        let (span, field, message) = match e {
            FieldOfView => (
                cam.vfov.span(),
                "camera.vfov",
                "must be in (0, 180) degrees",
            ),
            Lens => match (&cam.focus_dist, &cam.defocus_angle) {
                (Some(f), _) if !(*f.get_ref() > 0.0 && f.get_ref().is_finite()) => {
                    (f.span(), "camera.focus_dist", "must be positive and finite")
                }
                (_, Some(d)) => (
                    d.span(),
                    "camera.defocus_angle",
                    "must be in [0, 180) degrees",
                ),
                _ => (
                    file.camera.span(),
                    "camera",
                    "look_from and look_at coincide",
                ),
            },
            DegenerateView | EmptyImage => (
                file.camera.span(),
                "camera",
                "look_from equals look_at, or up is parallel to the view",
            ),
        };
        return Err(at(span, field, message.into()));
    }

    // Render defaults.
    let mut defaults = Defaults {
        width: 320,
        aspect: 16.0 / 9.0,
        spp: 16,
        max_depth: 8,
    };
    if let Some(r) = &file.render {
        let r = r.get_ref();
        let ranged = |v: &Option<Spanned<u32>>,
                      field: &str,
                      max: u32|
         -> Result<Option<u32>, SceneFileError> {
            match v {
                Some(s) if !(1..=max).contains(s.get_ref()) => Err(at(
                    s.span(),
                    field,
                    format!("must be in 1..={max}, got {}", s.get_ref()),
                )),
                Some(s) => Ok(Some(*s.get_ref())),
                None => Ok(None),
            }
        };
        if let Some(w) = ranged(&r.width, "render.width", MAX_WIDTH)? {
            defaults.width = w;
        }
        if let Some(s) = ranged(&r.spp, "render.spp", MAX_SPP)? {
            defaults.spp = s;
        }
        if let Some(d) = ranged(&r.max_depth, "render.max_depth", MAX_DEPTH)? {
            defaults.max_depth = d;
        }
        if let Some(a) = &r.aspect {
            let v = *a.get_ref();
            if !(v > 0.0 && v.is_finite()) {
                return Err(at(
                    a.span(),
                    "render.aspect",
                    format!("must be positive, got {v}"),
                ));
            }
            defaults.aspect = v;
        }
    }

    let background = match &file.background {
        None => Background::Sky,
        Some(b) => match b.get_ref() {
            FileBackground::Named(n) if n == "sky" => Background::Sky,
            FileBackground::Named(n) => {
                return Err(at(
                    b.span(),
                    "background",
                    format!("unknown background `{n}` (use \"sky\" or [r, g, b])"),
                ));
            }
            FileBackground::Colour(c) => {
                Background::Flat(colour(*c, f32::MAX, b.span(), "background")?)
            }
        },
    };

    // Textures.
    let mut images: Vec<Image> = Vec::new();
    let mut textures: BTreeMap<&str, (Texture<'static>, Option<usize>)> = BTreeMap::new();
    for (name, t) in &file.textures {
        let field = format!("textures.{name}");
        let tex = match t.get_ref() {
            FileTexture::Checker { scale, even, odd } => {
                if !(*scale > 0.0 && scale.is_finite()) {
                    return Err(at(
                        t.span(),
                        &field,
                        format!("scale must be positive, got {scale}"),
                    ));
                }
                let even = colour(*even, 1.0, t.span(), &format!("{field}.even"))?;
                let odd = colour(*odd, 1.0, t.span(), &format!("{field}.odd"))?;
                (
                    Texture::Checker {
                        scale: *scale,
                        even,
                        odd,
                    },
                    None,
                )
            }
            FileTexture::Image { path: p } => {
                let full = path.parent().unwrap_or(Path::new(".")).join(p);
                let img = read_png_linear(&full).map_err(|e| {
                    at(
                        t.span(),
                        &format!("{field}.path"),
                        format!("{}: {e}", full.display()),
                    )
                })?;
                images.push(img);
                (Texture::Solid(Vec3::splat(0.5)), Some(images.len() - 1))
            }
        };
        textures.insert(name, tex);
    }

    // Materials.
    let mut materials: Vec<Material<'static>> = Vec::new();
    let mut image_albedo = Vec::new();
    let mut index: BTreeMap<&str, u32> = BTreeMap::new();
    for (name, m) in &file.materials {
        let field = format!("materials.{name}");
        let span = m.span();
        let err = |message: String| at(span.clone(), &field, message);
        let albedo_of =
            |albedo: &Option<[f32; 3]>, texture: &Option<String>| match (albedo, texture) {
                (Some(_), Some(_)) => Err(err("give `albedo` or `texture`, not both".into())),
                (None, None) => Err(err("needs `albedo` or `texture`".into())),
                (Some(c), None) => Ok((
                    Texture::Solid(colour(*c, 1.0, span.clone(), &format!("{field}.albedo"))?),
                    None,
                )),
                (None, Some(t)) => textures
                    .get(t.as_str())
                    .copied()
                    .ok_or_else(|| err(format!("unknown texture `{t}`"))),
            };
        let (material, image) = match m.get_ref() {
            FileMaterial::Lambertian { albedo, texture } => {
                let (albedo, img) = albedo_of(albedo, texture)?;
                (Material::Lambertian { albedo }, img)
            }
            FileMaterial::Mirror { albedo } => (
                Material::Mirror {
                    albedo: colour(*albedo, 1.0, span.clone(), &format!("{field}.albedo"))?,
                },
                None,
            ),
            FileMaterial::Metal { albedo, roughness } => (
                Material::Metal {
                    albedo: colour(*albedo, 1.0, span.clone(), &format!("{field}.albedo"))?,
                    roughness: *roughness,
                },
                None,
            ),
            FileMaterial::Dielectric { ior } => (Material::Dielectric { ior: *ior }, None),
            FileMaterial::Phong {
                albedo,
                texture,
                kd,
                ks,
                exponent,
            } => {
                let (albedo, img) = albedo_of(albedo, texture)?;
                (
                    Material::Phong {
                        albedo,
                        kd: *kd,
                        ks: *ks,
                        exponent: *exponent,
                    },
                    img,
                )
            }
            FileMaterial::Blinn {
                albedo,
                texture,
                kd,
                ks,
                exponent,
            } => {
                let (albedo, img) = albedo_of(albedo, texture)?;
                (
                    Material::Blinn {
                        albedo,
                        kd: *kd,
                        ks: *ks,
                        exponent: *exponent,
                    },
                    img,
                )
            }
            FileMaterial::PhongNormalized {
                albedo,
                texture,
                kd,
                ks,
                exponent,
            } => {
                let (albedo, img) = albedo_of(albedo, texture)?;
                (
                    Material::PhongNormalized {
                        albedo,
                        kd: *kd,
                        ks: *ks,
                        exponent: *exponent,
                    },
                    img,
                )
            }
            FileMaterial::BlinnNormalized {
                albedo,
                texture,
                kd,
                ks,
                exponent,
            } => {
                let (albedo, img) = albedo_of(albedo, texture)?;
                (
                    Material::BlinnNormalized {
                        albedo,
                        kd: *kd,
                        ks: *ks,
                        exponent: *exponent,
                    },
                    img,
                )
            }
            FileMaterial::CookTorrance {
                albedo,
                texture,
                kd,
                ks,
                alpha,
                ior,
            } => {
                let (albedo, img) = albedo_of(albedo, texture)?;
                (
                    Material::CookTorrance {
                        albedo,
                        kd: *kd,
                        ks: *ks,
                        alpha: *alpha,
                        ior: *ior,
                    },
                    img,
                )
            }
            FileMaterial::Light { emit } => (
                Material::DiffuseLight {
                    emit: colour(*emit, f32::MAX, span.clone(), &format!("{field}.emit"))?,
                },
                None,
            ),
        };
        // Each parameter by name, so the message names the field.
        let param = |ok: bool, name: &str, rule: &str, value: f32| {
            if ok {
                Ok(())
            } else {
                Err(at(
                    span.clone(),
                    &format!("{field}.{name}"),
                    format!("{rule}, got {value}"),
                ))
            }
        };
        let weight = |name: &str, v: f32| {
            param(
                v >= 0.0 && v.is_finite(),
                name,
                "must be finite and at least 0",
                v,
            )
        };
        match &material {
            Material::Phong {
                kd, ks, exponent, ..
            }
            | Material::Blinn {
                kd, ks, exponent, ..
            }
            | Material::PhongNormalized {
                kd, ks, exponent, ..
            }
            | Material::BlinnNormalized {
                kd, ks, exponent, ..
            } => {
                weight("kd", *kd)?;
                weight("ks", *ks)?;
                weight("exponent", *exponent)?;
                if matches!(
                    material,
                    Material::PhongNormalized { .. } | Material::BlinnNormalized { .. }
                ) {
                    param(
                        kd + ks <= 1.0,
                        "ks",
                        "kd + ks must be at most 1 for a normalised lobe",
                        *ks,
                    )?;
                }
            }
            Material::Metal { roughness, .. } => {
                param(
                    (0.0..=1.0).contains(roughness),
                    "roughness",
                    "must be in [0, 1]",
                    *roughness,
                )?;
            }
            Material::Dielectric { ior } => param(
                *ior > 0.0 && ior.is_finite(),
                "ior",
                "must be positive",
                *ior,
            )?,
            Material::CookTorrance {
                kd, ks, alpha, ior, ..
            } => {
                weight("kd", *kd)?;
                weight("ks", *ks)?;
                param(
                    *alpha > 0.0 && *alpha <= 1.0,
                    "alpha",
                    "must be in (0, 1]",
                    *alpha,
                )?;
                param(
                    *ior > 0.0 && ior.is_finite(),
                    "ior",
                    "must be positive",
                    *ior,
                )?;
            }
            // Colours only: validate() below names what is wrong.
            Material::Lambertian { .. }
            | Material::Mirror { .. }
            | Material::DiffuseLight { .. } => {}
        }
        if let Err(e) = material.validate() {
            use strata::render::MaterialError::*;
            let why = match e {
                Colour => "a colour is out of range",
                Parameter => {
                    "a parameter is out of range (kd, ks, exponent ≥ 0; roughness in [0, 1]; alpha in (0, 1]; ior > 0)"
                }
                Energy => "kd + ks must be at most 1 for a normalised lobe",
            };
            return Err(err(why.into()));
        }
        debug_assert!(image.is_none() || material.is_smooth());
        if let Some(img) = image {
            image_albedo.push((materials.len(), img));
        }
        index.insert(name, materials.len() as u32);
        materials.push(material);
    }

    // Spheres.
    if file.spheres.is_empty() {
        return Err(at(
            0..0,
            "spheres",
            "a scene needs at least one sphere".into(),
        ));
    }
    let mut spheres = Vec::with_capacity(file.spheres.len());
    let mut sphere_material = Vec::with_capacity(file.spheres.len());
    for (i, s) in file.spheres.iter().enumerate() {
        let s = s.get_ref();
        let center = v3(&s.center, &format!("spheres[{i}].center"))?;
        let r = *s.radius.get_ref();
        if !(r > 0.0 && r.is_finite()) {
            return Err(at(
                s.radius.span(),
                &format!("spheres[{i}].radius"),
                format!("must be positive and finite, got {r}"),
            ));
        }
        let name = s.material.get_ref();
        let Some(&m) = index.get(name.as_str()) else {
            return Err(at(
                s.material.span(),
                &format!("spheres[{i}].material"),
                format!("unknown material `{name}`"),
            ));
        };
        spheres.push(Sphere::new(center, r));
        sphere_material.push(m);
    }

    Ok(SceneData {
        name: path
            .file_stem()
            .map_or("scene".into(), |s| s.to_string_lossy().into_owned()),
        spheres,
        sphere_material,
        materials,
        image_albedo,
        images,
        camera,
        background,
        defaults,
    })
}
