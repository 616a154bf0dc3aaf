//! `[textures.NAME]`: checkers, and PNG images read relative to the scene
//! file.

use std::collections::BTreeMap;
use std::path::Path;

use glam::Vec3;
use serde::Deserialize;
use strata::render::Texture;
use toml::Spanned;

use super::{SceneFileError, Source};
use crate::image_io::{Image, read_png_linear};

/// `[textures.NAME]` as written.
#[derive(Deserialize)]
#[serde(tag = "kind", rename_all = "snake_case", deny_unknown_fields)]
pub(super) enum FileTexture {
    Checker {
        scale: f32,
        even: [f32; 3],
        odd: [f32; 3],
    },
    Image {
        path: String,
    },
}

/// A texture as a material takes it: the texture and, for an image, the
/// index of the image its albedo becomes (the texture is then only a
/// placeholder, as [`crate::scenes::SceneData`] attaches images later).
pub(super) type Named = (Texture<'static>, Option<usize>);

/// The checked textures: each by name, and the images they read.
pub(super) struct Textures<'a> {
    /// Textures by name.
    pub named: BTreeMap<&'a str, Named>,
    /// The images, in the order their textures were read.
    pub images: Vec<Image>,
}

/// Checks every texture and reads every image.
pub(super) fn textures<'a>(
    src: &Source<'_>,
    section: &'a BTreeMap<String, Spanned<FileTexture>>,
) -> Result<Textures<'a>, SceneFileError> {
    let mut out = Textures {
        named: BTreeMap::new(),
        images: Vec::new(),
    };
    for (name, t) in section {
        let tex = texture(src, &format!("textures.{name}"), t, &mut out.images)?;
        out.named.insert(name, tex);
    }
    Ok(out)
}

/// One texture, named `field` in errors; an image is read and added to
/// `images`.
fn texture(
    src: &Source<'_>,
    field: &str,
    t: &Spanned<FileTexture>,
    images: &mut Vec<Image>,
) -> Result<Named, SceneFileError> {
    match t.get_ref() {
        FileTexture::Checker { scale, even, odd } => {
            if !(*scale > 0.0 && scale.is_finite()) {
                return Err(src.error(
                    t.span(),
                    field,
                    format!("scale must be positive, got {scale}"),
                ));
            }
            let even = src.colour(*even, 1.0, t.span(), &format!("{field}.even"))?;
            let odd = src.colour(*odd, 1.0, t.span(), &format!("{field}.odd"))?;
            let checker = Texture::Checker {
                scale: *scale,
                even,
                odd,
            };
            Ok((checker, None))
        }
        FileTexture::Image { path } => {
            let full = src.path.parent().unwrap_or(Path::new(".")).join(path);
            let img = read_png_linear(&full).map_err(|e| {
                src.error(
                    t.span(),
                    &format!("{field}.path"),
                    format!("{}: {e}", full.display()),
                )
            })?;
            images.push(img);
            Ok((Texture::Solid(Vec3::splat(0.5)), Some(images.len() - 1)))
        }
    }
}
