//! `[camera]` and `[render]`: where the picture is taken from, and the
//! settings the command line falls back on.

use std::ops::Range;

use glam::Vec3;
use serde::Deserialize;
use strata::render::{Camera, CameraDesc, CameraError};
use toml::Spanned;

use super::{SceneFileError, Source, Triple};
use crate::limits::{MAX_DEPTH, MAX_SPP, MAX_WIDTH};
use crate::scenes::Defaults;

/// `[camera]` as written.
#[derive(Deserialize)]
#[serde(deny_unknown_fields)]
pub(super) struct FileCamera {
    look_from: Spanned<Triple>,
    look_at: Spanned<Triple>,
    up: Option<Spanned<Triple>>,
    vfov: Spanned<f32>,
    defocus_angle: Option<Spanned<f32>>,
    focus_dist: Option<Spanned<f32>>,
}

/// `[render]` as written.
#[derive(Deserialize)]
#[serde(deny_unknown_fields)]
pub(super) struct FileRender {
    width: Option<Spanned<u32>>,
    aspect: Option<Spanned<f32>>,
    spp: Option<Spanned<u32>>,
    max_depth: Option<Spanned<u32>>,
}

/// What a scene file without `[render]` (or a key of it) renders at.
const DEFAULTS: Defaults = Defaults {
    width: 320,
    aspect: 16.0 / 9.0,
    spp: 16,
    max_depth: 8,
};

/// The camera, checked by building it as the renderer will.
pub(super) fn camera(
    src: &Source<'_>,
    section: &Spanned<FileCamera>,
) -> Result<CameraDesc, SceneFileError> {
    let cam = section.get_ref();
    let look_from = src.vec3(&cam.look_from, "camera.look_from")?;
    let look_at = src.vec3(&cam.look_at, "camera.look_at")?;
    let up = match &cam.up {
        Some(u) => src.vec3(u, "camera.up")?,
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
    match Camera::new(&camera, 1, 1) {
        Ok(_) => Ok(camera),
        Err(e) => {
            let (span, field, message) = blame(section, e, &camera);
            Err(src.error(span, field, message))
        }
    }
}

/// The key (its span and name) a camera error is about, and why.
fn blame(
    section: &Spanned<FileCamera>,
    e: CameraError,
    desc: &CameraDesc,
) -> (Range<usize>, &'static str, String) {
    let cam = section.get_ref();
    match e {
        CameraError::FieldOfView => (
            cam.vfov.span(),
            "camera.vfov",
            "must be in (0, 180) degrees".into(),
        ),
        CameraError::Lens => match (&cam.focus_dist, &cam.defocus_angle) {
            (Some(f), _) if !(*f.get_ref() > 0.0 && f.get_ref().is_finite()) => (
                f.span(),
                "camera.focus_dist",
                "must be positive and finite".into(),
            ),
            (_, Some(d)) if !(*d.get_ref() >= 0.0 && *d.get_ref() < 180.0) => (
                d.span(),
                "camera.defocus_angle",
                "must be in [0, 180) degrees".into(),
            ),
            _ if desc.focus_dist == 0.0 => (
                section.span(),
                "camera",
                "look_from and look_at coincide".into(),
            ),
            // Valid values whose product is not representable: a pixel's
            // step on the focus plane underflows (a tiny field of view) or
            // the plane's corner overflows (a huge distance).
            _ if Camera::new(
                &CameraDesc {
                    vfov_deg: 60.0,
                    ..*desc
                },
                1,
                1,
            )
            .is_ok() =>
            {
                (
                    cam.vfov.span(),
                    "camera.vfov",
                    format!(
                        "{:e}° is too narrow for f32: a pixel on the focus plane, {:e} away, \
                         would be below its resolution",
                        desc.vfov_deg, desc.focus_dist
                    ),
                )
            }
            _ => {
                // The key that puts the plane so far: focus_dist if given,
                // else the farther of look_from and look_at.
                let (span, field) = match &cam.focus_dist {
                    Some(f) => (f.span(), "camera.focus_dist"),
                    None if desc.look_from.as_dvec3().length()
                        >= desc.look_at.as_dvec3().length() =>
                    {
                        (cam.look_from.span(), "camera.look_from")
                    }
                    None => (cam.look_at.span(), "camera.look_at"),
                };
                (
                    span,
                    field,
                    format!(
                        "the focus plane is {:e} away (from look_from at {:e} from the origin): \
                         too far for f32 to place a pixel on it; move the scene nearer the origin",
                        // In f64: the f32 distance may overflow.
                        match cam.focus_dist {
                            Some(_) => desc.focus_dist as f64,
                            None => (desc.look_at - desc.look_from).as_dvec3().length(),
                        },
                        desc.look_from.as_dvec3().length()
                    ),
                )
            }
        },
        CameraError::DegenerateView | CameraError::EmptyImage => (
            section.span(),
            "camera",
            "look_from equals look_at, or up is parallel to the view".into(),
        ),
    }
}

/// The render defaults: [`DEFAULTS`] with what `[render]` sets, each in
/// the range the command line accepts.
pub(super) fn defaults(
    src: &Source<'_>,
    section: Option<&Spanned<FileRender>>,
) -> Result<Defaults, SceneFileError> {
    let mut defaults = DEFAULTS;
    let Some(section) = section else {
        return Ok(defaults);
    };
    let r = section.get_ref();
    let ranged =
        |v: &Option<Spanned<u32>>, field: &str, max: u32| -> Result<Option<u32>, SceneFileError> {
            match v {
                Some(s) if !(1..=max).contains(s.get_ref()) => Err(src.error(
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
            return Err(src.error(
                a.span(),
                "render.aspect",
                format!("must be positive, got {v}"),
            ));
        }
        defaults.aspect = v;
    }
    Ok(defaults)
}
