//! The text of a film header: the [`RenderKey`] fields that define a
//! render's pixels, and the window and sample range a part covers. The
//! same texts go into image metadata.

use std::ops::Range;

use anyhow::{Context, Result, bail};
use strata::render::Tile;

use crate::job::Job;

/// What defines a render's pixels: two parts merge only if every field
/// agrees. Values are kept as the strings written to files, so comparing
/// and reporting a difference need no parsing.
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct RenderKey {
    // Visible to the film module, which builds keys from parsed headers.
    pub(super) fields: Vec<(&'static str, String)>,
    pub(super) width: u32,
    pub(super) height: u32,
    pub(super) spp: u32,
    /// The adaptive settings of an adaptive render.
    pub(super) adaptive: Option<strata::render::Adaptive>,
}

/// The field names of a [`RenderKey`], in file order.
pub const KEY_FIELDS: [&str; 13] = [
    "version",
    "scene",
    "scene_hash",
    "camera",
    "size",
    "spp",
    "sampler",
    "seed",
    "max_depth",
    "direct_lighting",
    "filter",
    "adaptive",
    "texture_filter",
];

impl RenderKey {
    /// The key of `job`.
    #[must_use]
    pub fn of(job: &Job<'_>) -> Self {
        let c = &job.scene.camera;
        let values = [
            version(),
            job.scene.name.clone(),
            format!("{:016x}", job.scene.content_hash()),
            camera_text(&CameraNumbers {
                look_from: c.look_from.to_array(),
                look_at: c.look_at.to_array(),
                up: c.up.to_array(),
                vfov: c.vfov_deg,
                defocus: c.defocus_angle_deg,
                focus: c.focus_dist,
            }),
            format!("{}x{}", job.width, job.height),
            job.spp.to_string(),
            job.sampler.name().to_string(),
            job.seed.to_string(),
            job.max_depth.to_string(),
            job.direct_lighting.to_string(),
            // The BVH is not in the key: it never changes a pixel.
            filter_text(&job.filter),
            adaptive_text(job.adaptive),
            texture_filter_text(job.texture_filter).to_string(),
        ];
        RenderKey {
            // A value is one header line: control characters (a scene file
            // named with a newline) become U+FFFD.
            fields: KEY_FIELDS
                .into_iter()
                .zip(values.map(|v| v.replace(char::is_control, "\u{fffd}")))
                .collect(),
            width: job.width,
            height: job.height,
            spp: job.spp,
            adaptive: job.adaptive,
        }
    }

    /// Image width.
    #[must_use]
    pub fn width(&self) -> u32 {
        self.width
    }

    /// Image height.
    #[must_use]
    pub fn height(&self) -> u32 {
        self.height
    }

    /// Samples per pixel of the whole render.
    #[must_use]
    pub fn spp(&self) -> u32 {
        self.spp
    }

    /// The adaptive settings if the render is adaptive: each pixel then
    /// holds between their minimum and [`RenderKey::spp`] samples.
    #[must_use]
    pub fn adaptive(&self) -> Option<strata::render::Adaptive> {
        self.adaptive
    }

    /// The fields as (name, value), in file order.
    #[must_use]
    pub fn fields(&self) -> &[(&'static str, String)] {
        &self.fields
    }

    /// The value of field `name`.
    #[must_use]
    pub fn get(&self, name: &str) -> Option<&str> {
        self.fields
            .iter()
            .find(|(k, _)| *k == name)
            .map(|(_, v)| v.as_str())
    }

    /// The border a film of this render holds around its window: the
    /// filter's splat margin if the filter splats (and the render is not
    /// adaptive), else 0; `None` if the filter text does not parse.
    #[must_use]
    pub fn border(&self) -> Option<u32> {
        let filter = parse_filter(self.get("filter")?)?;
        Some(strata::render::Layout::of(&filter, self.adaptive.is_some()).margin())
    }

    /// The key of a film header's fields (`get(name)` gives each field's
    /// text), every one parsed as its type and written back the same
    /// (so `seed=05`, `seed=hello` or `texture_filter=banana` are
    /// refused), and made by this build (`version` is [`version()`]).
    /// The error names the field.
    pub(super) fn parse<'v>(get: impl Fn(&str) -> Result<&'v str>) -> Result<RenderKey> {
        let mut fields = Vec::with_capacity(KEY_FIELDS.len());
        for name in KEY_FIELDS {
            let v = get(name)?;
            if canonical(name, v) != Some(true) {
                bail!("bad `{name}`: `{}`", clip(v));
            }
            fields.push((name, v.to_string()));
        }
        let text = |name: &str| {
            fields
                .iter()
                .find(|(k, _)| *k == name)
                .map(|(_, v)| v.as_str())
        };
        let ours = version();
        if text("version") != Some(ours.as_str()) {
            bail!(
                "made by strata {}, and this is strata {ours}: parts merge only with the build \
                 that made them (their pixels may differ)",
                clip(text("version").unwrap_or_default())
            );
        }
        let (width, height) = text("size").and_then(parse_size).context("bad `size`")?;
        let spp: u32 = text("spp")
            .and_then(|v| v.parse().ok())
            .context("bad `spp`")?;
        let adaptive = text("adaptive")
            .and_then(parse_adaptive)
            .context("bad `adaptive`")?;
        Ok(RenderKey {
            fields,
            width,
            height,
            spp,
            adaptive,
        })
    }

    /// The first field where `other` differs: (name, ours, theirs).
    #[must_use]
    pub fn first_difference<'a>(
        &'a self,
        other: &'a RenderKey,
    ) -> Option<(&'a str, &'a str, &'a str)> {
        self.fields
            .iter()
            .zip(&other.fields)
            .find(|(a, b)| a.1 != b.1)
            .map(|(a, b)| (a.0, a.1.as_str(), b.1.as_str()))
    }
}

/// Whether `v` is a value field `name` of a [`RenderKey`] can hold, written
/// as the key writes it; `None` for a name that is not a field.
fn canonical(name: &str, v: &str) -> Option<bool> {
    let same = |t: Option<String>| t.as_deref() == Some(v);
    Some(match name {
        // Its own field: checked against this build by the caller.
        "version" => !v.is_empty() && !v.contains(char::is_control),
        // A scene's name (a file's stem), control characters replaced.
        "scene" => !v.is_empty() && !v.contains(char::is_control),
        "scene_hash" => {
            v.len() == 16
                && v.bytes()
                    .all(|b| b.is_ascii_digit() || (b'a'..=b'f').contains(&b))
        }
        "camera" => parse_camera(v).is_some_and(|c| c.is_camera() && camera_text(&c) == v),
        "size" => same(parse_size(v).map(|(w, h)| format!("{w}x{h}"))),
        "spp" => same(v.parse::<u32>().ok().map(|n| n.to_string())),
        "max_depth" => same(
            v.parse::<u32>()
                .ok()
                .filter(|d| (1..=crate::limits::MAX_DEPTH).contains(d))
                .map(|n| n.to_string()),
        ),
        "seed" => same(v.parse::<u64>().ok().map(|n| n.to_string())),
        "sampler" => crate::job::SamplerKind::ALL.iter().any(|s| s.name() == v),
        "direct_lighting" => v == "true" || v == "false",
        "filter" => same(parse_filter(v).map(|f| filter_text(&f))),
        "adaptive" => same(parse_adaptive(v).map(adaptive_text)),
        "texture_filter" => [
            strata::render::TextureFilter::None,
            strata::render::TextureFilter::Box,
        ]
        .into_iter()
        .any(|t| texture_filter_text(t) == v),
        _ => return None,
    })
}

/// `WxH`.
fn parse_size(v: &str) -> Option<(u32, u32)> {
    let (w, h) = v.split_once('x')?;
    Some((w.parse().ok()?, h.parse().ok()?))
}

/// The numbers of a camera as the key writes them.
struct CameraNumbers {
    look_from: [f32; 3],
    look_at: [f32; 3],
    up: [f32; 3],
    vfov: f32,
    defocus: f32,
    focus: f32,
}

impl CameraNumbers {
    /// Whether a render could have had this camera: finite numbers that
    /// make one.
    fn is_camera(&self) -> bool {
        let desc = strata::render::CameraDesc {
            look_from: self.look_from.into(),
            look_at: self.look_at.into(),
            up: self.up.into(),
            vfov_deg: self.vfov,
            defocus_angle_deg: self.defocus,
            focus_dist: self.focus,
        };
        strata::render::Camera::new(&desc, 1, 1).is_ok()
    }
}

/// `from [x, y, z] at [x, y, z] up [x, y, z] vfov V defocus D focus F`,
/// each number as Rust writes an `f32` (shortest text that reads back
/// the same bits).
fn camera_text(c: &CameraNumbers) -> String {
    format!(
        "from {:?} at {:?} up {:?} vfov {:?} defocus {:?} focus {:?}",
        c.look_from, c.look_at, c.up, c.vfov, c.defocus, c.focus
    )
}

/// Parses [`camera_text`].
fn parse_camera(v: &str) -> Option<CameraNumbers> {
    let triple = |s: &str| -> Option<[f32; 3]> {
        let inner = s.strip_prefix('[')?.strip_suffix(']')?;
        let n: Vec<f32> = inner
            .split(", ")
            .map(|t| t.parse().ok())
            .collect::<Option<_>>()?;
        n.try_into().ok()
    };
    let rest = v.strip_prefix("from ")?;
    let (from, rest) = rest.split_once(" at ")?;
    let (at, rest) = rest.split_once(" up ")?;
    let (up, rest) = rest.split_once(" vfov ")?;
    let (vfov, rest) = rest.split_once(" defocus ")?;
    let (defocus, focus) = rest.split_once(" focus ")?;
    Some(CameraNumbers {
        look_from: triple(from)?,
        look_at: triple(at)?,
        up: triple(up)?,
        vfov: vfov.parse().ok()?,
        defocus: defocus.parse().ok()?,
        focus: focus.parse().ok()?,
    })
}

/// A texture filter as the key writes it.
fn texture_filter_text(t: strata::render::TextureFilter) -> &'static str {
    match t {
        strata::render::TextureFilter::None => "none",
        strata::render::TextureFilter::Box => "box",
    }
}

/// The crate version and the output revision: a change of either may
/// change pixels, so parts of different builds do not merge.
#[must_use]
pub fn version() -> String {
    format!(
        "{}+r{}",
        env!("CARGO_PKG_VERSION"),
        strata::render::OUTPUT_REVISION
    )
}

/// A filter as text: its name, radius and shape parameters.
#[must_use]
pub fn filter_text(f: &strata::render::PixelFilter) -> String {
    use strata::filter::FilterKind;
    let r = f.radius();
    match f.kind() {
        FilterKind::Gaussian { sigma } => format!("gaussian r={r:?} sigma={sigma:?}"),
        FilterKind::Mitchell { b, c } => format!("mitchell r={r:?} b={b:?} c={c:?}"),
        FilterKind::Lanczos { tau } => format!("lanczos r={r:?} tau={tau:?}"),
        k => format!("{} r={r:?}", k.name()),
    }
}

/// Parses [`filter_text`] back into the filter.
pub(super) fn parse_filter(s: &str) -> Option<strata::render::PixelFilter> {
    use strata::filter::FilterKind;
    let mut words = s.split(' ');
    let kind = FilterKind::named(words.next()?)?;
    let r: f32 = words.next()?.strip_prefix("r=")?.parse().ok()?;
    let mut value = |name: &str| -> Option<f32> {
        words
            .next()?
            .strip_prefix(name)?
            .strip_prefix('=')?
            .parse()
            .ok()
    };
    let kind = match kind {
        FilterKind::Gaussian { .. } => FilterKind::Gaussian {
            sigma: value("sigma")?,
        },
        FilterKind::Mitchell { .. } => FilterKind::Mitchell {
            b: value("b")?,
            c: value("c")?,
        },
        FilterKind::Lanczos { .. } => FilterKind::Lanczos { tau: value("tau")? },
        k => k,
    };
    if words.next().is_some() {
        return None;
    }
    strata::render::PixelFilter::new(kind, r).ok()
}

/// Adaptive sampling as text: `off`, or `threshold=T min=N max=M`.
#[must_use]
pub fn adaptive_text(a: Option<strata::render::Adaptive>) -> String {
    match a {
        None => "off".to_string(),
        Some(a) => format!(
            "threshold={:?} min={} max={}",
            a.threshold(),
            a.min(),
            a.max()
        ),
    }
}

/// Parses [`adaptive_text`].
pub(super) fn parse_adaptive(s: &str) -> Option<Option<strata::render::Adaptive>> {
    if s == "off" {
        return Some(None);
    }
    let v: Vec<&str> = s.split(' ').collect();
    let [t, b, m] = v[..] else { return None };
    let t: f32 = t.strip_prefix("threshold=")?.parse().ok()?;
    let b: u32 = b.strip_prefix("min=")?.parse().ok()?;
    let m: u32 = m.strip_prefix("max=")?.parse().ok()?;
    strata::render::Adaptive::new(b, m, t).ok().map(Some)
}

/// `x0,x1,y0,y1` of a window.
#[must_use]
pub fn window_text(w: Tile) -> String {
    format!("{},{},{},{}", w.x0, w.x0 + w.width, w.y0, w.y0 + w.height)
}

/// Parses [`window_text`] into a non-empty window.
pub(super) fn parse_window(s: &str) -> Option<Tile> {
    let v: Vec<u32> = s
        .split(',')
        .map(|t| t.parse().ok())
        .collect::<Option<_>>()?;
    let [x0, x1, y0, y1] = v[..] else { return None };
    // `then`, not `then_some`: the widths must not be computed when empty.
    (x0 < x1 && y0 < y1).then(|| Tile {
        x0,
        y0,
        width: x1 - x0,
        height: y1 - y0,
    })
}

/// `A..B` of a range of sample indices.
#[must_use]
pub fn samples_text(s: &Range<u32>) -> String {
    format!("{}..{}", s.start, s.end)
}

/// Parses `A..B` with `A < B`.
pub fn parse_samples(s: &str) -> Option<Range<u32>> {
    parse_range(s).filter(|r| r.start < r.end)
}

/// Parses `A..B`, empty or not.
pub fn parse_range(s: &str) -> Option<Range<u32>> {
    let (a, b) = s.split_once("..")?;
    Some(a.trim().parse().ok()?..b.trim().parse().ok()?)
}

/// A header value as errors quote it: at most 80 characters.
pub(super) fn clip(v: &str) -> String {
    match v.char_indices().nth(80) {
        Some((at, _)) => format!("{}… ({} bytes)", &v[..at], v.len()),
        None => v.to_string(),
    }
}
