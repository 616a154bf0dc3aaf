//! Partial films on disk, and merging them.
//!
//! A render of part of a frame (a pixel window, a range of sample indices,
//! or both) is saved as a `.film`: the exact per-pixel sums of
//! [`PixelSum`] (integers, so adding parts is associative), the sample
//! counts, and the [`RenderKey`] that defines the pixels. [`merge`] adds any
//! set of parts that partitions `image × samples` exactly, so the merged
//! image is bit-identical to the one-shot render; it refuses overlaps, gaps
//! and parts of another render.
//!
//! The format (version 3) is a text header and a binary body:
//!
//! ```text
//! strata-film 3
//! version=0.1.0+r1
//! scene=cover
//! ...                      the RenderKey fields, then:
//! window=x0,x1,y0,y1       pixels covered, half-open
//! samples=A..B             sample indices covered, half-open
//! checksum=<16 hex digits> FNV-1a 64 of the body
//!                          (an empty line ends the header)
//! body: one record per window pixel, row-major, 40 bytes each,
//!       little-endian: weighted sums r, g, b and the filter-weight sum as
//!       i64 (units of 2^-24), samples u32, dropped u32.
//! ```
//!
//! An adaptive render (`adaptive=threshold=T base=B max=M`, with `spp` =
//! M) covers samples `0..M` of its window: each pixel holds the `B..=M`
//! samples its error asked for. Adaptive parts split the pixels only,
//! never the samples.

use std::fmt::Write as _;
use std::ops::Range;
use std::path::{Path, PathBuf};

use anyhow::{Context, Result, bail};
use strata::render::{PixelSum, Tile};

use crate::limits::{MAX_PIXELS, MAX_SPP, MAX_WIDTH};
use crate::render::Job;

/// The first line of every film file.
pub const MAGIC: &str = "strata-film 3";

/// Bytes per pixel in a film's body.
pub const BYTES_PER_PIXEL: usize = 40;

/// What defines a render's pixels: two parts merge only if every field
/// agrees. Values are kept as the strings written to files, so comparing
/// and reporting a difference need no parsing.
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct RenderKey {
    fields: Vec<(&'static str, String)>,
    width: u32,
    height: u32,
    spp: u32,
    /// The base sample count of an adaptive render.
    adaptive_base: Option<u32>,
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
            format!(
                "from {:?} at {:?} up {:?} vfov {:?} defocus {:?} focus {:?}",
                c.look_from.to_array(),
                c.look_at.to_array(),
                c.up.to_array(),
                c.vfov_deg,
                c.defocus_angle_deg,
                c.focus_dist
            ),
            format!("{}x{}", job.width, job.height),
            job.spp.to_string(),
            job.sampler.name().to_string(),
            job.seed.to_string(),
            job.max_depth.to_string(),
            job.direct_lighting.to_string(),
            // The BVH is not in the key: it never changes a pixel.
            filter_text(&job.filter),
            adaptive_text(job.adaptive),
            match job.texture_filter {
                strata::render::TextureFilter::None => "none",
                strata::render::TextureFilter::Box => "box",
            }
            .to_string(),
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
            adaptive_base: job.adaptive.map(|a| a.base()),
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

    /// The base sample count if the render is adaptive: each pixel then
    /// holds between it and [`RenderKey::spp`] samples.
    #[must_use]
    pub fn adaptive_base(&self) -> Option<u32> {
        self.adaptive_base
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

/// Adaptive sampling as text: `off`, or `threshold=T base=B max=M`.
#[must_use]
pub fn adaptive_text(a: Option<strata::render::Adaptive>) -> String {
    match a {
        None => "off".to_string(),
        Some(a) => format!(
            "threshold={:?} base={} max={}",
            a.threshold(),
            a.base(),
            a.max()
        ),
    }
}

/// Parses [`adaptive_text`].
fn parse_adaptive(s: &str) -> Option<Option<strata::render::Adaptive>> {
    if s == "off" {
        return Some(None);
    }
    let v: Vec<&str> = s.split(' ').collect();
    let [t, b, m] = v[..] else { return None };
    let t: f32 = t.strip_prefix("threshold=")?.parse().ok()?;
    let b: u32 = b.strip_prefix("base=")?.parse().ok()?;
    let m: u32 = m.strip_prefix("max=")?.parse().ok()?;
    strata::render::Adaptive::new(b, m, t).ok().map(Some)
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

/// `x0,x1,y0,y1` of a window.
#[must_use]
pub fn window_text(w: Tile) -> String {
    format!("{},{},{},{}", w.x0, w.x0 + w.width, w.y0, w.y0 + w.height)
}

/// A part of a render: the pixels of `window`, samples `samples` of each.
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct Film {
    /// What render this is part of.
    pub key: RenderKey,
    /// The pixels covered.
    pub window: Tile,
    /// The sample indices covered.
    pub samples: Range<u32>,
    /// One accumulator per window pixel, row-major.
    pub pixels: Vec<PixelSum>,
}

impl Film {
    /// The image metadata of this film (PNG text chunks, EXR attributes):
    /// what defines it, nothing that varies between runs.
    #[must_use]
    pub fn metadata(&self, transfer: &str) -> Vec<(String, String)> {
        let mut out = vec![(
            "Software".to_string(),
            format!("strata {}", env!("CARGO_PKG_VERSION")),
        )];
        for (k, v) in self.key.fields() {
            out.push((format!("strata.{k}"), v.clone()));
        }
        out.push(("strata.window".into(), window_text(self.window)));
        out.push((
            "strata.samples".into(),
            format!("{}..{}", self.samples.start, self.samples.end),
        ));
        out.push(("strata.transfer".into(), transfer.into()));
        out
    }

    /// The file bytes: header and body.
    #[must_use]
    pub fn to_bytes(&self) -> Vec<u8> {
        let mut body = Vec::with_capacity(self.pixels.len() * BYTES_PER_PIXEL);
        for p in &self.pixels {
            for s in p.sum.into_iter().chain([p.weight]) {
                body.extend_from_slice(&s.to_le_bytes());
            }
            body.extend_from_slice(&p.samples.to_le_bytes());
            body.extend_from_slice(&p.dropped.to_le_bytes());
        }
        let mut head = String::new();
        writeln!(head, "{MAGIC}").unwrap();
        for (k, v) in self.key.fields() {
            writeln!(head, "{k}={v}").unwrap();
        }
        writeln!(head, "window={}", window_text(self.window)).unwrap();
        writeln!(head, "samples={}..{}", self.samples.start, self.samples.end).unwrap();
        writeln!(head, "checksum={:016x}", crate::hash::fnv1a(&body)).unwrap();
        writeln!(head).unwrap();
        let mut out = head.into_bytes();
        out.extend_from_slice(&body);
        out
    }

    /// Parses a film file's bytes; errors say what is wrong, not where
    /// (the caller adds the file name).
    pub fn from_bytes(bytes: &[u8]) -> Result<Film> {
        let not_film = || anyhow::anyhow!("not a Strata film (no `{MAGIC}` line)");
        let first = bytes
            .iter()
            .position(|&b| b == b'\n')
            .ok_or_else(not_film)?;
        if &bytes[..first] != MAGIC.as_bytes() {
            if bytes.starts_with(b"strata-film ") {
                bail!(
                    "a film of another format version (`{}`; this build reads `{MAGIC}`)",
                    String::from_utf8_lossy(&bytes[..first])
                );
            }
            return Err(not_film());
        }
        // The header's end is searched from the magic line's newline on, so
        // an empty header is found as such, not before the magic line ends.
        let end =
            first + find(&bytes[first..], b"\n\n").context("truncated: the header does not end")?;
        let head = std::str::from_utf8(&bytes[first + 1..end.max(first + 1)])
            .context("header is not UTF-8")?;
        let body = &bytes[end + 2..];
        let mut map: Vec<(&str, &str)> = Vec::new();
        for line in head.lines() {
            let (k, v) = line
                .split_once('=')
                .with_context(|| format!("header line `{line}` is not key=value"))?;
            if map.iter().any(|(seen, _)| *seen == k) {
                bail!("header repeats `{k}`");
            }
            map.push((k, v));
        }
        let get = |name: &str| -> Result<&str> {
            map.iter()
                .find(|(k, _)| *k == name)
                .map(|(_, v)| *v)
                .with_context(|| format!("header has no `{name}`"))
        };
        let fields: Vec<(&'static str, String)> = KEY_FIELDS
            .iter()
            .map(|&k| get(k).map(|v| (k, v.to_string())))
            .collect::<Result<_>>()?;
        let (width, height) = get("size")?
            .split_once('x')
            .and_then(|(w, h)| Some((w.parse::<u32>().ok()?, h.parse::<u32>().ok()?)))
            .context("bad `size`")?;
        let spp: u32 = get("spp")?.parse().context("bad `spp`")?;
        let window = parse_window(get("window")?).context("bad `window`")?;
        let samples = parse_samples(get("samples")?).context("bad `samples`")?;
        if width == 0 || height == 0 || spp == 0 {
            bail!("empty image or zero spp");
        }
        // The limits `strata render` accepts, so a hostile header cannot
        // ask a merge for a huge allocation.
        if width > MAX_WIDTH
            || height > MAX_WIDTH
            || width as u64 * height as u64 > MAX_PIXELS
            || spp > MAX_SPP
        {
            bail!("size {width}x{height} or spp {spp} is beyond what strata renders");
        }
        if window.x0 + window.width > width || window.y0 + window.height > height {
            bail!(
                "window {} is outside the {width}x{height} image",
                window_text(window)
            );
        }
        if samples.end > spp {
            bail!(
                "samples {}..{} exceed spp {spp}",
                samples.start,
                samples.end
            );
        }
        let adaptive = parse_adaptive(get("adaptive")?).context("bad `adaptive`")?;
        if let Some(a) = adaptive
            && (a.max() != spp || samples != (0..spp))
        {
            bail!(
                "an adaptive film must cover samples 0..{spp} with max={spp}, not samples {}..{} \
                 with max={}",
                samples.start,
                samples.end,
                a.max()
            );
        }
        let need = window.area() * BYTES_PER_PIXEL;
        if body.len() != need {
            bail!(
                "truncated or padded: {} bytes of pixels where the window needs {need}",
                body.len()
            );
        }
        let sum = u64::from_str_radix(get("checksum")?, 16).context("bad `checksum`")?;
        if sum != crate::hash::fnv1a(body) {
            bail!("corrupt: the pixel checksum does not match");
        }
        let pixels = body
            .chunks_exact(BYTES_PER_PIXEL)
            .map(|r| {
                let i = |k: usize| i64::from_le_bytes(r[8 * k..8 * k + 8].try_into().unwrap());
                let u = |o: usize| u32::from_le_bytes(r[o..o + 4].try_into().unwrap());
                PixelSum {
                    sum: [i(0), i(1), i(2)],
                    weight: i(3),
                    samples: u(32),
                    dropped: u(36),
                }
            })
            .collect::<Vec<PixelSum>>();
        let key = RenderKey {
            fields,
            width,
            height,
            spp,
            adaptive_base: adaptive.map(|a| a.base()),
        };
        check_counts(&key, &samples, &pixels)?;
        Ok(Film {
            key,
            window,
            samples,
            pixels,
        })
    }

    /// Reads a film file; errors name it.
    pub fn read(path: &Path) -> Result<Film> {
        let bytes =
            std::fs::read(path).with_context(|| format!("cannot read `{}`", path.display()))?;
        Film::from_bytes(&bytes).with_context(|| format!("`{}`", path.display()))
    }
}

/// Every pixel took every sample of the range, kept or dropped; an
/// adaptive pixel (whose range is all of `0..spp`) took a whole number of
/// base-sized batches, or the maximum.
fn check_counts(key: &RenderKey, samples: &Range<u32>, pixels: &[PixelSum]) -> Result<()> {
    let n = samples.end - samples.start;
    if key.adaptive_base.is_some() && *samples != (0..key.spp) {
        bail!(
            "an adaptive film must cover samples 0..{}, not {}..{}",
            key.spp,
            samples.start,
            samples.end
        );
    }
    let possible = |t: u32| match key.adaptive_base {
        None => t == n,
        Some(base) => t == n || (t >= base && t < n && t.is_multiple_of(base)),
    };
    if let Some(at) = pixels.iter().position(|p| !possible(p.taken())) {
        let want = match key.adaptive_base {
            None => n.to_string(),
            Some(base) => format!("a multiple of {base} up to {n}"),
        };
        bail!(
            "pixel {at} of the window holds {} samples where the range {}..{} has {want}",
            pixels[at].taken(),
            samples.start,
            samples.end
        );
    }
    Ok(())
}

fn find(hay: &[u8], needle: &[u8]) -> Option<usize> {
    hay.windows(needle.len()).position(|w| w == needle)
}

/// Parses `x0,x1,y0,y1` into a non-empty window.
fn parse_window(s: &str) -> Option<Tile> {
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

/// Parses `A..B` with `A < B`.
pub fn parse_samples(s: &str) -> Option<Range<u32>> {
    let (a, b) = s.split_once("..")?;
    let (a, b): (u32, u32) = (a.trim().parse().ok()?, b.trim().parse().ok()?);
    (a < b).then_some(a..b)
}

fn overlap(a: &Range<u32>, b: &Range<u32>) -> Option<Range<u32>> {
    let r = a.start.max(b.start)..a.end.min(b.end);
    (r.start < r.end).then_some(r)
}

/// Merges parts that partition the whole image and every sample index
/// exactly once into one whole film. `names` label the parts in errors
/// (one per part). Refuses parts of different renders, overlaps and gaps.
pub fn merge(parts: &[Film], names: &[PathBuf]) -> Result<Film> {
    assert_eq!(parts.len(), names.len());
    let Some(first) = parts.first() else {
        bail!("nothing to merge");
    };
    let name = |i: usize| names[i].display().to_string();
    for (i, p) in parts.iter().enumerate().skip(1) {
        if let Some((field, ours, theirs)) = first.key.first_difference(&p.key) {
            bail!(
                "`{}` is from another render than `{}`: {field} is `{theirs}`, not `{ours}`",
                name(i),
                name(0)
            );
        }
    }
    let (w, h, spp) = (first.key.width(), first.key.height(), first.key.spp());
    // Films built in code rather than read: the same checks as `from_bytes`.
    for (i, p) in parts.iter().enumerate() {
        let t = &p.window;
        let inside = t.x0.checked_add(t.width).is_some_and(|x| x <= w)
            && t.y0.checked_add(t.height).is_some_and(|y| y <= h);
        if !inside
            || p.pixels.len() != t.area()
            || p.samples.start >= p.samples.end
            || p.samples.end > spp
        {
            bail!(
                "`{}` is inconsistent: its window, pixels or samples do not fit the render",
                name(i)
            );
        }
        check_counts(&p.key, &p.samples, &p.pixels)
            .with_context(|| format!("`{}` is inconsistent", name(i)))?;
    }
    let cols = |t: &Tile| t.x0..t.x0 + t.width;
    let rows = |t: &Tile| t.y0..t.y0 + t.height;
    // Pairwise overlap: the windows and the sample ranges both meet.
    for i in 0..parts.len() {
        for j in i + 1..parts.len() {
            let (a, b) = (&parts[i], &parts[j]);
            if let (Some(x), Some(y), Some(s)) = (
                overlap(&cols(&a.window), &cols(&b.window)),
                overlap(&rows(&a.window), &rows(&b.window)),
                overlap(&a.samples, &b.samples),
            ) {
                bail!(
                    "`{}` and `{}` overlap: both hold pixels x {}..{}, y {}..{}, samples {}..{}",
                    name(i),
                    name(j),
                    x.start,
                    x.end,
                    y.start,
                    y.end,
                    s.start,
                    s.end
                );
            }
        }
    }
    // With no overlap, a pixel is complete exactly when the sample ranges
    // covering it add up to spp.
    let mut pixels = vec![PixelSum::ZERO; (w as usize) * (h as usize)];
    let mut covered = vec![0u64; pixels.len()];
    for p in parts {
        let n = (p.samples.end - p.samples.start) as u64;
        for (r, y) in rows(&p.window).enumerate() {
            for (c, x) in cols(&p.window).enumerate() {
                let at = y as usize * w as usize + x as usize;
                covered[at] += n;
                pixels[at].merge(&p.pixels[r * p.window.width as usize + c]);
            }
        }
    }
    if let Some(at) = covered.iter().position(|&c| c != spp as u64) {
        let (x, y) = (at % w as usize, at / w as usize);
        bail!(
            "the parts leave a gap: pixel ({x}, {y}) has {} of its {spp} samples",
            covered[at]
        );
    }
    Ok(Film {
        key: first.key.clone(),
        window: Tile::whole(w, h),
        samples: 0..spp,
        pixels,
    })
}

#[cfg(test)]
mod tests {
    use super::*;

    fn film(width: u32, height: u32, window: Tile, samples: Range<u32>) -> Film {
        let job_key = |k: &str| match k {
            "size" => format!("{width}x{height}"),
            "spp" => "8".to_string(),
            "adaptive" => "off".to_string(),
            _ => format!("{k}-value"),
        };
        let n = samples.end - samples.start;
        Film {
            key: RenderKey {
                fields: KEY_FIELDS.iter().map(|&k| (k, job_key(k))).collect(),
                width,
                height,
                spp: 8,
                adaptive_base: None,
            },
            window,
            pixels: (0..window.area())
                .map(|i| PixelSum {
                    sum: [i as i64, -(i as i64), 1 << 40],
                    weight: (n as i64 - 1) << 24,
                    samples: n - 1,
                    dropped: 1,
                })
                .collect(),
            samples,
        }
    }

    fn tile(x0: u32, y0: u32, width: u32, height: u32) -> Tile {
        Tile {
            x0,
            y0,
            width,
            height,
        }
    }

    #[test]
    fn films_round_trip_through_bytes() {
        let f = film(7, 5, tile(2, 1, 3, 4), 2..5);
        assert_eq!(Film::from_bytes(&f.to_bytes()).unwrap(), f);
    }

    fn refused(bytes: &[u8]) -> String {
        format!("{:#}", Film::from_bytes(bytes).unwrap_err())
    }

    #[test]
    fn damaged_or_hostile_films_are_refused() {
        let good = film(7, 5, tile(2, 1, 3, 4), 2..5).to_bytes();
        let text = |b: &[u8]| String::from_utf8_lossy(b).into_owned();
        let edit = |from: &str, to: &str| {
            let t = text(&good);
            let (head, _) = t.split_once("\n\n").unwrap();
            let body = &good[head.len() + 2..];
            let mut out = head.replacen(from, to, 1).into_bytes();
            out.extend_from_slice(b"\n\n");
            out.extend_from_slice(body);
            out
        };
        // A huge size would make a merge allocate it.
        let e = refused(&edit("size=7x5", "size=4000000000x4000000000"));
        assert!(e.contains("beyond what strata renders"), "{e}");
        let e = refused(&edit("size=7x5", "size=4x5"));
        assert!(e.contains("outside the 4x5 image"), "{e}");
        let e = refused(&edit("samples=2..5", "samples=2..9"));
        assert!(e.contains("exceed spp 8"), "{e}");
        let e = refused(&edit("samples=2..5", "samples=1..5"));
        assert!(
            e.contains("holds 3 samples where the range 1..5 has 4"),
            "{e}"
        );
        let e = refused(&edit("window=2,5,1,5", "window=5,2,1,5"));
        assert!(e.contains("bad `window`"), "{e}");
        let e = refused(&edit("seed=seed-value\n", ""));
        assert!(e.contains("no `seed`"), "{e}");
        let e = refused(&good[..good.len() - 1]);
        assert!(e.contains("truncated"), "{e}");
        let e = refused(&good[..40]);
        assert!(e.contains("truncated"), "{e}");
        let e = refused(b"strata-film 3\n\nxyz");
        assert!(e.contains("no `version`"), "{e}");
        let e = refused(&edit("seed=seed-value", "seed=seed-value\nseed=9"));
        assert!(e.contains("repeats `seed`"), "{e}");
        for old in [&b"strata-film 1\n"[..], b"strata-film 2\n"] {
            let e = refused(old);
            assert!(e.contains("another format version"), "{e}");
        }
        let e = refused(b"");
        assert!(e.contains("not a Strata film"), "{e}");
    }

    #[test]
    fn adaptive_films_hold_counts_from_the_base_to_the_maximum() {
        let mut f = film(7, 5, tile(2, 1, 3, 4), 0..8);
        f.key.fields[11].1 = "threshold=0.05 base=2 max=8".into();
        f.key.adaptive_base = Some(2);
        for (i, p) in f.pixels.iter_mut().enumerate() {
            p.samples = 1 + 2 * (i as u32 % 4); // 2, 4, 6, 8 with the dropped one
        }
        assert_eq!(Film::from_bytes(&f.to_bytes()).unwrap(), f);
        for bad in [0, 2] {
            let mut odd = f.clone();
            odd.pixels[3].samples = bad; // 1 or 3 taken: no batch ends there
            let e = refused(&odd.to_bytes());
            let want = format!(
                "holds {} samples where the range 0..8 has a multiple of 2",
                bad + 1
            );
            assert!(e.contains(&want), "{e}");
            // Built in code, the merge checks the same.
            let names = [PathBuf::from("odd")];
            let e = format!("{:#}", merge(&[odd], &names).unwrap_err());
            assert!(e.contains(&want), "{e}");
        }
        let mut part = f.clone();
        part.samples = 0..4;
        let e = refused(&part.to_bytes());
        assert!(e.contains("must cover samples 0..8 with max=8"), "{e}");
        let mut other = f.clone();
        other.key.fields[11].1 = "threshold=0.05 base=2 max=6".into();
        let e = refused(&other.to_bytes());
        assert!(e.contains("with max=6"), "{e}");
        other.key.fields[11].1 = "threshold=-1 base=2 max=8".into();
        let e = refused(&other.to_bytes());
        assert!(e.contains("bad `adaptive`"), "{e}");
    }

    #[test]
    fn merge_names_the_first_differing_field() {
        let a = film(4, 2, tile(0, 0, 2, 2), 0..8);
        let mut b = film(4, 2, tile(2, 0, 2, 2), 0..8);
        b.key.fields[3].1 = "another camera".into();
        let names = [PathBuf::from("a"), PathBuf::from("b")];
        let e = merge(&[a.clone(), b], &names).unwrap_err().to_string();
        assert!(
            e.contains("`b` is from another render than `a`: camera"),
            "{e}"
        );
        let ok = merge(&[a.clone(), film(4, 2, tile(2, 0, 2, 2), 0..8)], &names).unwrap();
        assert_eq!(ok.pixels[0], a.pixels[0]);
        assert_eq!(ok.window, tile(0, 0, 4, 2));
    }
}
