//! `[materials.NAME]`: each kind's keys, checked one by one so an error
//! names the key, then by the core's own [`Material::validate`].

use std::collections::BTreeMap;
use std::ops::Range;

use glam::Vec3;
use serde::Deserialize;
use strata::render::{Material, MaterialError, Texture};
use toml::Spanned;

use super::textures::Named;
use super::{SceneFileError, Source};

/// `[materials.NAME]` as written.
#[derive(Deserialize)]
#[serde(tag = "kind", rename_all = "snake_case", deny_unknown_fields)]
pub(super) enum FileMaterial {
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
    Phong(FileLobe),
    Blinn(FileLobe),
    PhongNormalized(FileLobe),
    BlinnNormalized(FileLobe),
    CookTorrance(FileCookTorrance),
    Light {
        emit: [f32; 3],
    },
}

/// The keys of the Phong and Blinn kinds, plain and normalised.
#[derive(Deserialize)]
#[serde(deny_unknown_fields)]
pub(super) struct FileLobe {
    albedo: Option<[f32; 3]>,
    texture: Option<String>,
    kd: f32,
    ks: f32,
    exponent: f32,
}

/// The keys of the Cook–Torrance kind.
#[derive(Deserialize)]
#[serde(deny_unknown_fields)]
pub(super) struct FileCookTorrance {
    albedo: Option<[f32; 3]>,
    texture: Option<String>,
    kd: f32,
    ks: f32,
    alpha: f32,
    ior: f32,
}

/// The checked materials, in name order.
pub(super) struct Materials<'a> {
    /// The materials.
    pub list: Vec<Material<'static>>,
    /// `(material, image)`: the material's albedo is that image.
    pub image_albedo: Vec<(usize, usize)>,
    /// Each name's index in `list`.
    pub index: BTreeMap<&'a str, u32>,
}

/// Checks every material; `textures` are the ones a material may name.
pub(super) fn materials<'a>(
    src: &Source<'_>,
    section: &'a BTreeMap<String, Spanned<FileMaterial>>,
    textures: &BTreeMap<&str, Named>,
) -> Result<Materials<'a>, SceneFileError> {
    let mut out = Materials {
        list: Vec::new(),
        image_albedo: Vec::new(),
        index: BTreeMap::new(),
    };
    for (name, m) in section {
        let table = Table {
            src,
            span: m.span(),
            field: format!("materials.{name}"),
        };
        let (material, image) = table.material(m.get_ref(), textures)?;
        table.validate(&material)?;
        debug_assert!(image.is_none() || material.is_smooth());
        if let Some(img) = image {
            out.image_albedo.push((out.list.len(), img));
        }
        out.index.insert(name, out.list.len() as u32);
        out.list.push(material);
    }
    Ok(out)
}

/// The constructor of lobe `$variant` from its albedo, kd, ks and
/// exponent, for [`Table::lobe`]: the four lobe kinds differ only in the
/// variant they build.
macro_rules! lobe {
    ($variant:ident) => {
        |albedo, kd, ks, exponent| Material::$variant {
            albedo,
            kd,
            ks,
            exponent,
        }
    };
}

/// Where `key = ` is written in the table at `span` (a header and its
/// lines up to the next header, or an inline table), outside comments.
pub(super) fn key_in_table(text: &str, span: Range<usize>, key: &str) -> Option<Range<usize>> {
    let start = span.start.min(text.len());
    let first = text[start..].find('\n').map_or(text.len(), |i| start + i);
    let end = text[first..]
        .find("\n[")
        .map_or(text.len(), |i| first + i)
        .max(span.end.min(text.len()));
    let body = &text[start..end];
    let is_key_char = |c: char| c.is_ascii_alphanumeric() || c == '_' || c == '-';
    body.match_indices(key)
        .find(|&(at, _)| {
            // Not in a comment.
            let line = &body[body[..at].rfind('\n').map_or(0, |i| i + 1)..at];
            if line.contains('#') {
                return false;
            }
            let before = body[..at].chars().next_back();
            let after = body[at + key.len()..].trim_start_matches([' ', '\t']);
            before.is_none_or(|c| !is_key_char(c) && c != '"') && after.starts_with('=')
        })
        .map(|(at, _)| start + at..start + at + key.len())
}

/// The key of material `name` that serde's `message` is about: named in
/// it (an unknown field), or found by leaving each key out in turn until
/// the message changes (a value of the wrong type or length, which serde's
/// tagged enums report against the whole table); `None` for a missing
/// key, which is the table's fault.
pub(super) fn material_key_at_fault(text: &str, name: &str, message: &str) -> Option<String> {
    if let Some(k) = message
        .strip_prefix("unknown field `")
        .and_then(|r| r.split('`').next())
    {
        return Some(k.to_string());
    }
    if message.starts_with("missing field") {
        // The table's, which lacks it.
        return None;
    }
    let doc: toml::Table = toml::from_str(text).ok()?;
    let table = doc.get("materials")?.get(name)?.as_table()?;
    table
        .keys()
        .filter(|k| *k != "kind")
        .find(|k| {
            let mut without = table.clone();
            without.remove(k.as_str());
            // Without the bad key the value error goes (serde reads values
            // before it checks for missing keys), so the message changes.
            FileMaterial::deserialize(toml::Value::Table(without))
                .map_or_else(|e| e.message() != message, |_| true)
        })
        .cloned()
}

/// A material and, if its albedo is an image, the image's index.
type Built = (Material<'static>, Option<usize>);

/// The table of one material: every error about it names it, or the key
/// in it and that key's line.
struct Table<'a> {
    src: &'a Source<'a>,
    span: Range<usize>,
    field: String,
}

impl Table<'_> {
    /// Where `key = ` is written in the table (its keys are not spanned:
    /// serde's internally tagged enums cannot carry spans), else the
    /// table: an error about a key then points at its line.
    fn key_span(&self, key: &str) -> Range<usize> {
        key_in_table(self.src.text, self.span.clone(), key).unwrap_or(self.span.clone())
    }

    /// An error about the material as a whole.
    fn error(&self, message: String) -> SceneFileError {
        self.src.error(self.span.clone(), &self.field, message)
    }

    /// An error naming `key` unless `ok`.
    fn param(&self, ok: bool, key: &str, rule: &str, value: f32) -> Result<(), SceneFileError> {
        if ok {
            Ok(())
        } else {
            Err(self.src.error(
                self.key_span(key),
                &format!("{}.{key}", self.field),
                format!("{rule}, got {value}"),
            ))
        }
    }

    /// A lobe weight or exponent.
    fn weight(&self, key: &str, v: f32) -> Result<(), SceneFileError> {
        self.param(
            v >= 0.0 && v.is_finite(),
            key,
            "must be finite and at least 0",
            v,
        )
    }

    /// An index of refraction.
    fn ior(&self, ior: f32) -> Result<(), SceneFileError> {
        self.param(ior > 0.0 && ior.is_finite(), "ior", "must be positive", ior)
    }

    /// The colour at `key`, each component in `[0, max]`.
    fn colour(&self, c: [f32; 3], max: f32, key: &str) -> Result<Vec3, SceneFileError> {
        self.src
            .colour(c, max, self.key_span(key), &format!("{}.{key}", self.field))
    }

    /// The albedo of a textured kind: a colour or a texture's name, not
    /// both.
    fn albedo(
        &self,
        albedo: &Option<[f32; 3]>,
        texture: &Option<String>,
        textures: &BTreeMap<&str, Named>,
    ) -> Result<Named, SceneFileError> {
        match (albedo, texture) {
            (Some(_), Some(_)) => Err(self.error("give `albedo` or `texture`, not both".into())),
            (None, None) => Err(self.error("needs `albedo` or `texture`".into())),
            (Some(c), None) => Ok((Texture::Solid(self.colour(*c, 1.0, "albedo")?), None)),
            (None, Some(t)) => textures
                .get(t.as_str())
                .copied()
                .ok_or_else(|| self.error(format!("unknown texture `{t}`"))),
        }
    }

    /// The material, each key checked in the order it is written here.
    fn material(
        &self,
        m: &FileMaterial,
        textures: &BTreeMap<&str, Named>,
    ) -> Result<Built, SceneFileError> {
        Ok(match m {
            FileMaterial::Lambertian { albedo, texture } => {
                let (albedo, image) = self.albedo(albedo, texture, textures)?;
                (Material::Lambertian { albedo }, image)
            }
            FileMaterial::Mirror { albedo } => {
                let albedo = self.colour(*albedo, 1.0, "albedo")?;
                (Material::Mirror { albedo }, None)
            }
            FileMaterial::Metal { albedo, roughness } => {
                let albedo = self.colour(*albedo, 1.0, "albedo")?;
                let roughness = *roughness;
                let ok = (0.0..=1.0).contains(&roughness);
                self.param(ok, "roughness", "must be in [0, 1]", roughness)?;
                (Material::Metal { albedo, roughness }, None)
            }
            FileMaterial::Dielectric { ior } => {
                self.ior(*ior)?;
                (Material::Dielectric { ior: *ior }, None)
            }
            FileMaterial::Phong(l) => self.lobe(l, textures, lobe!(Phong))?,
            FileMaterial::Blinn(l) => self.lobe(l, textures, lobe!(Blinn))?,
            FileMaterial::PhongNormalized(l) => self.lobe(l, textures, lobe!(PhongNormalized))?,
            FileMaterial::BlinnNormalized(l) => self.lobe(l, textures, lobe!(BlinnNormalized))?,
            FileMaterial::CookTorrance(c) => self.cook_torrance(c, textures)?,
            FileMaterial::Light { emit } => {
                // Not capped at the film's sample cap: a small bright light
                // lights surfaces correctly; `strata render` warns that
                // where it is seen directly its pixels clamp.
                let emit = self.colour(*emit, f32::MAX, "emit")?;
                (Material::DiffuseLight { emit }, None)
            }
        })
    }

    /// A Phong or Blinn lobe, made by `make` from its albedo, kd, ks and
    /// exponent.
    fn lobe(
        &self,
        l: &FileLobe,
        textures: &BTreeMap<&str, Named>,
        make: fn(Texture<'static>, f32, f32, f32) -> Material<'static>,
    ) -> Result<Built, SceneFileError> {
        let (albedo, image) = self.albedo(&l.albedo, &l.texture, textures)?;
        self.weight("kd", l.kd)?;
        self.weight("ks", l.ks)?;
        self.weight("exponent", l.exponent)?;
        let material = make(albedo, l.kd, l.ks, l.exponent);
        // Only the normalised lobes promise to conserve energy.
        if matches!(
            material,
            Material::PhongNormalized { .. } | Material::BlinnNormalized { .. }
        ) {
            let rule = "kd + ks must be at most 1 for a normalised lobe";
            self.param(l.kd + l.ks <= 1.0, "ks", rule, l.ks)?;
        }
        Ok((material, image))
    }

    /// A Cook–Torrance material.
    fn cook_torrance(
        &self,
        c: &FileCookTorrance,
        textures: &BTreeMap<&str, Named>,
    ) -> Result<Built, SceneFileError> {
        let (albedo, image) = self.albedo(&c.albedo, &c.texture, textures)?;
        self.weight("kd", c.kd)?;
        self.weight("ks", c.ks)?;
        let alpha_ok = c.alpha > 0.0 && c.alpha <= 1.0;
        self.param(alpha_ok, "alpha", "must be in (0, 1]", c.alpha)?;
        self.ior(c.ior)?;
        let material = Material::CookTorrance {
            albedo,
            kd: c.kd,
            ks: c.ks,
            alpha: c.alpha,
            ior: c.ior,
        };
        Ok((material, image))
    }

    /// The core's own check, behind the checks of each key: it names no
    /// key, so it speaks only of what they let through.
    fn validate(&self, material: &Material<'_>) -> Result<(), SceneFileError> {
        let Err(e) = material.validate() else {
            return Ok(());
        };
        let why = match e {
            MaterialError::Colour => "a colour is out of range",
            MaterialError::Parameter => {
                "a parameter is out of range (kd, ks, exponent ≥ 0; roughness in [0, 1]; alpha in (0, 1]; ior > 0)"
            }
            MaterialError::Energy => "kd + ks must be at most 1 for a normalised lobe",
        };
        Err(self.error(why.into()))
    }
}

#[cfg(test)]
mod tests {
    use std::path::Path;

    /// The error for a scene whose one material, on line 6, is `body`.
    fn error(body: &str) -> String {
        let text = format!(
            "[camera]\nlook_from = [0.0, 0.0, 1.0]\nlook_at = [0.0, 0.0, 0.0]\nvfov = 40.0\n\n\
             [materials.m]\n{body}\n\n\
             [[spheres]]\ncenter = [0.0, 0.0, 0.0]\nradius = 1.0\nmaterial = \"m\"\n"
        );
        let e = super::super::parse(Path::new("s.toml"), &text).unwrap_err();
        e.to_string()
    }

    /// The lobe kinds share one set of keys, yet their errors name the
    /// material's table and keys as every other kind's do, at the bad
    /// key's line (the table's for serde's own errors).
    #[test]
    fn lobe_errors_name_the_table_and_the_key() {
        let lobe = |kind: &str, keys: &str| {
            error(&format!(
                "kind = \"{kind}\"\nalbedo = [0.5, 0.5, 0.5]\n{keys}"
            ))
        };
        assert_eq!(
            lobe("phong", "kd = 0.5\nks = 0.5\nexponent = 2.0\nshine = 1.0"),
            "s.toml:12: materials.m.shine: unknown field `shine`, expected one of \
             `albedo`, `texture`, `kd`, `ks`, `exponent`"
        );
        assert_eq!(
            lobe("blinn", "kd = 0.5\nexponent = 2.0"),
            "s.toml:6: materials.m: missing field `ks`"
        );
        assert_eq!(
            lobe("blinn_normalized", "kd = 0.5\nks = 0.6\nexponent = 2.0"),
            "s.toml:10: materials.m.ks: kd + ks must be at most 1 for a normalised lobe, got 0.6"
        );
        assert_eq!(
            lobe(
                "cook_torrance",
                "kd = 0.5\nks = 0.5\nalpha = 0.0\nior = 1.5"
            ),
            "s.toml:11: materials.m.alpha: must be in (0, 1], got 0"
        );
    }
}
