//! A film's bytes: the header and body written by [`Film::to_bytes`] and
//! read back, checked, by [`Film::from_bytes`].

use std::fmt::Write as _;
use std::path::Path;

use anyhow::{Context, Result, bail};
use strata::render::PixelSum;

use super::Film;
use super::key::{
    KEY_FIELDS, RenderKey, parse_adaptive, parse_samples, parse_window, samples_text, window_text,
};
use crate::limits::{MAX_PIXELS, MAX_SPP, MAX_WIDTH};

/// The first line of every film file.
pub const MAGIC: &str = "strata-film 4";

/// Bytes per pixel in a film's body.
pub const BYTES_PER_PIXEL: usize = 64;

impl Film {
    /// The file bytes: header and body.
    #[must_use]
    pub fn to_bytes(&self) -> Vec<u8> {
        let mut body = Vec::with_capacity(self.pixels.len() * BYTES_PER_PIXEL);
        encode_pixels(&self.pixels, &mut body);
        let mut head = String::new();
        writeln!(head, "{MAGIC}").unwrap();
        for (k, v) in self.key.fields() {
            writeln!(head, "{k}={v}").unwrap();
        }
        writeln!(head, "window={}", window_text(self.window)).unwrap();
        writeln!(head, "samples={}", samples_text(&self.samples)).unwrap();
        if self.border > 0 {
            writeln!(head, "border={}", self.border).unwrap();
        }
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
        let border = match map.iter().find(|(k, _)| *k == "border") {
            None => 0,
            Some((_, v)) => v
                .parse::<u32>()
                .ok()
                .filter(|&b| b > 0)
                .with_context(|| format!("bad `border`: `{v}`"))?,
        };
        let key = RenderKey {
            fields,
            width,
            height,
            spp,
            adaptive,
        };
        check_border(&key, border)?;
        let extent = super::extent(window, border, width, height);
        let need = extent.area() * BYTES_PER_PIXEL;
        if body.len() != need {
            bail!(
                "truncated or padded: {} bytes of pixels where the window and its border need \
                 {need}",
                body.len()
            );
        }
        let sum = u64::from_str_radix(get("checksum")?, 16).context("bad `checksum`")?;
        if sum != crate::hash::fnv1a(body) {
            bail!("corrupt: the pixel checksum does not match");
        }
        let pixels = decode_pixels(body);
        let film = Film {
            key,
            window,
            samples,
            border,
            pixels,
        };
        check_counts(&film)?;
        Ok(film)
    }

    /// Reads a film file; errors name it.
    pub fn read(path: &Path) -> Result<Film> {
        let bytes =
            std::fs::read(path).with_context(|| format!("cannot read `{}`", path.display()))?;
        Film::from_bytes(&bytes).with_context(|| format!("`{}`", path.display()))
    }
}

/// Appends the body records of `pixels` to `out` (64 bytes each, the
/// layout in the module docs).
pub(crate) fn encode_pixels(pixels: &[PixelSum], out: &mut Vec<u8>) {
    let at = out.len();
    out.resize(at + pixels.len() * BYTES_PER_PIXEL, 0);
    for (p, rec) in pixels
        .iter()
        .zip(out[at..].chunks_exact_mut(BYTES_PER_PIXEL))
    {
        // Fixed offsets into a fixed-size record: no length checks and
        // regrowth per field (extending field by field cost about 350
        // instructions a pixel, 1.7 % of a cover render).
        let words = [p.sum[0], p.sum[1], p.sum[2], p.weight];
        for (o, s) in rec[..32].chunks_exact_mut(8).zip(words) {
            o.copy_from_slice(&s.to_le_bytes());
        }
        rec[32..36].copy_from_slice(&p.samples.to_le_bytes());
        rec[36..40].copy_from_slice(&p.dropped.to_le_bytes());
        for (o, s) in rec[40..].chunks_exact_mut(8).zip(p.own_minus_sum) {
            o.copy_from_slice(&s.to_le_bytes());
        }
    }
}

/// The pixels of body records (`bytes` a whole number of records).
pub(crate) fn decode_pixels(bytes: &[u8]) -> Vec<PixelSum> {
    bytes
        .chunks_exact(BYTES_PER_PIXEL)
        .map(|r| {
            let i = |k: usize| i64::from_le_bytes(r[8 * k..8 * k + 8].try_into().unwrap());
            let u = |o: usize| u32::from_le_bytes(r[o..o + 4].try_into().unwrap());
            PixelSum {
                sum: [i(0), i(1), i(2)],
                weight: i(3),
                own_minus_sum: [i(5), i(6), i(7)],
                samples: u(32),
                dropped: u(36),
            }
        })
        .collect()
}

/// The film's border is the one its render's filter reaches (checked
/// before the body's size is trusted, by the caller for a file).
pub(super) fn check_border(key: &RenderKey, border: u32) -> Result<()> {
    let want = key
        .border()
        .with_context(|| format!("bad `filter`: `{}`", key.get("filter").unwrap_or_default()))?;
    if border != want {
        bail!(
            "a border of {border} pixels where the render's filter (`{}`{}) reaches {want}",
            key.get("filter").unwrap_or_default(),
            if key.adaptive.is_some() {
                ", adaptive"
            } else {
                ""
            }
        );
    }
    Ok(())
}

/// Every window pixel took every sample of the range, kept or dropped,
/// and every border pixel none; an adaptive pixel (whose range is all of
/// `0..spp`) took a count its settings allow
/// ([`Adaptive::can_take`](strata::render::Adaptive::can_take)). A merge
/// checks the same of films built in code.
pub(super) fn check_counts(film: &Film) -> Result<()> {
    let (key, samples) = (&film.key, &film.samples);
    let n = samples.end - samples.start;
    if key.adaptive.is_some() && *samples != (0..key.spp) {
        bail!(
            "an adaptive film must cover samples 0..{}, not {}..{}",
            key.spp,
            samples.start,
            samples.end
        );
    }
    let possible = |t: u32| match key.adaptive {
        None => t == n,
        Some(a) => a.can_take(t),
    };
    let extent = film.extent();
    if film.pixels.len() != extent.area() {
        bail!(
            "{} pixels where the window and its border have {}",
            film.pixels.len(),
            extent.area()
        );
    }
    let w = film.window;
    for (i, p) in film.pixels.iter().enumerate() {
        let (x, y) = (
            extent.x0 + (i % extent.width as usize) as u32,
            extent.y0 + (i / extent.width as usize) as u32,
        );
        let owned = (w.x0..w.x0 + w.width).contains(&x) && (w.y0..w.y0 + w.height).contains(&y);
        if owned && !possible(p.taken()) {
            let want = match key.adaptive {
                None => n.to_string(),
                Some(a) => format!(
                    "a multiple of {} from {} to {}",
                    a.block(),
                    a.min(),
                    2 * a.block() + a.rest_range().end()
                ),
            };
            bail!(
                "pixel ({x}, {y}) holds {} samples where the range {}..{} has {want}",
                p.taken(),
                samples.start,
                samples.end
            );
        }
        if !owned && p.taken() != 0 {
            bail!(
                "pixel ({x}, {y}) of the border holds {} samples; a border holds only sums",
                p.taken()
            );
        }
    }
    Ok(())
}

fn find(hay: &[u8], needle: &[u8]) -> Option<usize> {
    hay.windows(needle.len()).position(|w| w == needle)
}
