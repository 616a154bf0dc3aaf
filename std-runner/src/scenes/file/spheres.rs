//! `[[spheres]]` and `background`: what rays hit, and what they see when
//! they hit nothing.

use std::collections::BTreeMap;

use serde::Deserialize;
use strata::render::{Background, MAX_SAMPLE_VALUE};
use strata::trace::{BVH_MAX_COORDINATE, SPHERE_MIN_RADIUS_RATIO, Sphere};
use toml::Spanned;

use super::{SceneFileError, Source, Triple};

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
    center: Spanned<Triple>,
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
            MAX_SAMPLE_VALUE,
            b.span(),
            "background",
        )?)),
    }
}

/// The spheres and each one's material index, looked up by name in
/// `materials`; a scene needs at least one, each within the kernel's range
/// and resolved from the camera at `look_from`
/// (`Sphere::is_resolved_within`).
pub(super) fn spheres(
    src: &Source<'_>,
    section: &[Spanned<FileSphere>],
    materials: &BTreeMap<&str, u32>,
    look_from: glam::Vec3,
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
        let big = |x: f32| x.abs() > BVH_MAX_COORDINATE;
        if center.to_array().into_iter().any(big) {
            return Err(src.error(
                s.center.span(),
                &format!("spheres[{i}].center"),
                format!(
                    "{center} is beyond ±{BVH_MAX_COORDINATE:e}: the intersection squares \
                     distances, which overflow f32 there, and the sphere would never be drawn"
                ),
            ));
        }
        if big(r) {
            return Err(src.error(
                s.radius.span(),
                &format!("spheres[{i}].radius"),
                format!(
                    "{r:e} is beyond {BVH_MAX_COORDINATE:e}: the intersection squares it, which \
                     overflows f32, and the sphere would never be drawn"
                ),
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
    // Checked for camera rays, which draw every silhouette the image shows
    // directly; rays from spheres farther out blur small spheres by up to
    // 2^-24 of that distance, as documented on `Sphere`.
    let reach = look_from.length();
    if let Some(i) = spheres.iter().position(|s| !s.is_resolved_within(reach)) {
        let s = &spheres[i];
        return Err(src.error(
            section[i].get_ref().radius.span(),
            &format!("spheres[{i}].radius"),
            format!(
                "{:e} is below what f32 resolves from the camera: the radius must be at least \
                 2^-20 × (|look_from| + |center|) = {:e} (the sphere is {:e} from the camera, \
                 whose rays round to 2^-24 of such distances), or the scene must be scaled or \
                 moved nearer the origin",
                s.radius,
                SPHERE_MIN_RADIUS_RATIO * (reach + s.center.length()),
                (s.center - look_from).length(),
            ),
        ));
    }
    Ok((spheres, sphere_material))
}
