//! `[[spheres]]` and `background`: what rays hit, and what they see when
//! they hit nothing.

use std::collections::BTreeMap;

use serde::Deserialize;
use strata::render::Background;
use strata::trace::Sphere;
use toml::Spanned;

use super::{SceneFileError, Source};

/// `background` as written. The name is part of serde's message when
/// neither form matches, which `Source::deserialize` looks for.
#[derive(Deserialize)]
#[serde(untagged)]
pub(super) enum FileBackground {
    Named(String),
    Colour([f32; 3]),
}

/// `[[spheres]]` as written.
#[derive(Deserialize)]
#[serde(deny_unknown_fields)]
pub(super) struct FileSphere {
    center: Spanned<[f32; 3]>,
    radius: Spanned<f32>,
    material: Spanned<String>,
}

/// The background: the sky unless the file gives a flat radiance.
pub(super) fn background(
    src: &Source<'_>,
    value: Option<&Spanned<FileBackground>>,
) -> Result<Background, SceneFileError> {
    let Some(b) = value else {
        return Ok(Background::Sky);
    };
    match b.get_ref() {
        FileBackground::Named(n) if n == "sky" => Ok(Background::Sky),
        FileBackground::Named(n) => Err(src.error(
            b.span(),
            "background",
            format!("unknown background `{n}` (use \"sky\" or [r, g, b])"),
        )),
        FileBackground::Colour(c) => Ok(Background::Flat(src.colour(
            *c,
            f32::MAX,
            b.span(),
            "background",
        )?)),
    }
}

/// The spheres and each one's material index, looked up by name in
/// `materials`; a scene needs at least one.
pub(super) fn spheres(
    src: &Source<'_>,
    section: &[Spanned<FileSphere>],
    materials: &BTreeMap<&str, u32>,
) -> Result<(Vec<Sphere>, Vec<u32>), SceneFileError> {
    if section.is_empty() {
        return Err(src.error(0..0, "spheres", "a scene needs at least one sphere".into()));
    }
    let mut spheres = Vec::with_capacity(section.len());
    let mut sphere_material = Vec::with_capacity(section.len());
    for (i, s) in section.iter().enumerate() {
        let s = s.get_ref();
        let center = src.vec3(&s.center, &format!("spheres[{i}].center"))?;
        let r = *s.radius.get_ref();
        if !(r > 0.0 && r.is_finite()) {
            return Err(src.error(
                s.radius.span(),
                &format!("spheres[{i}].radius"),
                format!("must be positive and finite, got {r}"),
            ));
        }
        let name = s.material.get_ref();
        let Some(&m) = materials.get(name.as_str()) else {
            return Err(src.error(
                s.material.span(),
                &format!("spheres[{i}].material"),
                format!("unknown material `{name}`"),
            ));
        };
        spheres.push(Sphere::new(center, r));
        sphere_material.push(m);
    }
    Ok((spheres, sphere_material))
}
