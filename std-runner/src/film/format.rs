//! A film's bytes: the header and body written by [`Film::to_bytes`] and
//! read back, checked, by [`Film::from_bytes`].

use std::fmt::Write as _;
use std::fs::File;
use std::io::{Read, Seek, SeekFrom};
use std::path::Path;

use anyhow::{Context, Result, bail};
use strata::render::PixelSum;

use super::Film;
use super::key::{
    KEY_FIELDS, RenderKey, clip, parse_samples, parse_window, samples_text, window_text,
};
use crate::limits::{MAX_PIXELS, MAX_SPP, MAX_WIDTH};

/// The first line of every film file.
pub const MAGIC: &str = "strata-film 5";

/// Bytes per pixel in a film's body.
pub const BYTES_PER_PIXEL: usize = 64;

/// Longest film header read: the key's values are short (a scene file's
/// name is the longest), so a longer one is not a film.
pub const MAX_HEADER_BYTES: usize = 64 * 1024;

/// The header's last line: FNV-1a 64 of every header byte before it.
const HEAD_CHECKSUM: &str = "head_checksum=";

/// Pixels read at once while a film body is streamed (1 MiB).
const CHUNK_PIXELS: usize = 16 * 1024;

/// A film's header: what [`Film`] holds but its pixels, and the body's
/// checksum. Every header check is made when it is parsed.
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct FilmHead {
    /// What render this is part of.
    pub key: RenderKey,
    /// The pixels covered.
    pub window: strata::render::Tile,
    /// The sample indices covered.
    pub samples: std::ops::Range<u32>,
    /// Pixels beyond the window on each side whose sums the film holds.
    pub border: u32,
    /// FNV-1a 64 of the body.
    pub checksum: u64,
}

impl FilmHead {
    /// The pixels the body covers: the window and its border, clipped to
    /// the image.
    #[must_use]
    pub fn extent(&self) -> strata::render::Tile {
        self.window
            .grown(self.border, self.key.width(), self.key.height())
    }

    /// The header's text, the empty line that ends it included.
    fn text(&self) -> String {
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
        writeln!(head, "checksum={:016x}", self.checksum).unwrap();
        let own = crate::hash::fnv1a(head.as_bytes());
        writeln!(head, "{HEAD_CHECKSUM}{own:016x}").unwrap();
        writeln!(head).unwrap();
        head
    }
}

impl Film {
    /// The header of this film (its checksum computed).
    #[must_use]
    pub fn head(&self) -> FilmHead {
        let mut sum = crate::hash::Fnv::default();
        let mut buf = Vec::with_capacity(CHUNK_PIXELS * BYTES_PER_PIXEL);
        for chunk in self.pixels.chunks(CHUNK_PIXELS) {
            buf.clear();
            encode_pixels(chunk, &mut buf);
            sum.bytes(&buf);
        }
        FilmHead {
            key: self.key.clone(),
            window: self.window,
            samples: self.samples.clone(),
            border: self.border,
            checksum: sum.finish(),
        }
    }

    /// The header without its checksum (0): for checks of a film built in
    /// code, which has no file to check the checksum against.
    pub(super) fn head_unchecked(&self) -> FilmHead {
        FilmHead {
            key: self.key.clone(),
            window: self.window,
            samples: self.samples.clone(),
            border: self.border,
            checksum: 0,
        }
    }

    /// The file bytes: header and body.
    #[must_use]
    pub fn to_bytes(&self) -> Vec<u8> {
        let mut out = Vec::with_capacity(self.pixels.len() * BYTES_PER_PIXEL + 1024);
        self.write_to(&mut out)
            .expect("writing to a Vec does not fail");
        out
    }

    /// Writes the file (header and body) to `w` a chunk at a time: no
    /// second copy of the pixels.
    pub fn write_to(&self, w: &mut impl std::io::Write) -> std::io::Result<()> {
        w.write_all(self.head().text().as_bytes())?;
        let mut buf = Vec::with_capacity(CHUNK_PIXELS * BYTES_PER_PIXEL);
        for chunk in self.pixels.chunks(CHUNK_PIXELS) {
            buf.clear();
            encode_pixels(chunk, &mut buf);
            w.write_all(&buf)?;
        }
        Ok(())
    }

    /// Parses a film file's bytes; errors say what is wrong, not where
    /// (the caller adds the file name).
    pub fn from_bytes(bytes: &[u8]) -> Result<Film> {
        let end = header_end(bytes)?;
        let head = parse_head(&bytes[..end])?;
        let body = &bytes[end..];
        check_body_len(&head, body.len() as u64)?;
        if head.checksum != crate::hash::fnv1a(body) {
            bail!("corrupt: the pixel checksum does not match");
        }
        let film = Film {
            key: head.key,
            window: head.window,
            samples: head.samples,
            border: head.border,
            pixels: decode_pixels(body),
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

/// A film file opened for a merge: its header read and checked, its body
/// not yet read.
pub struct FilmFile {
    /// The file.
    pub path: std::path::PathBuf,
    /// Its header.
    pub head: FilmHead,
    /// Where the body starts.
    body_at: u64,
}

impl FilmFile {
    /// Reads and checks a film's header and its body's length (not the
    /// body). Errors name the file.
    pub fn open(path: &Path) -> Result<FilmFile> {
        let name = || format!("`{}`", path.display());
        let file = File::open(path).with_context(|| format!("cannot read `{}`", path.display()))?;
        let len = file.metadata().map(|m| m.len()).with_context(name)?;
        let mut start = Vec::new();
        file.take(MAX_HEADER_BYTES as u64 + 2)
            .read_to_end(&mut start)
            .with_context(name)?;
        let end = header_end(&start).with_context(name)?;
        let head = parse_head(&start[..end]).with_context(name)?;
        // (A file cut shorter since its length was read has no body.)
        check_body_len(&head, len.saturating_sub(end as u64)).with_context(name)?;
        Ok(FilmFile {
            path: path.to_path_buf(),
            head,
            body_at: end as u64,
        })
    }

    /// Streams the body a chunk of pixels at a time to `each` (with the
    /// index of the chunk's first pixel in the extent), then checks the
    /// checksum: a corrupt body is refused after it was read, so a caller
    /// must not keep what it added. Errors name the file.
    pub fn for_each_chunk(
        &self,
        mut each: impl FnMut(usize, &[PixelSum]) -> Result<()>,
    ) -> Result<()> {
        let name = || format!("`{}`", self.path.display());
        let mut file = File::open(&self.path).with_context(name)?;
        file.seek(SeekFrom::Start(self.body_at))
            .with_context(name)?;
        let mut sum = crate::hash::Fnv::default();
        let mut buf = vec![0u8; CHUNK_PIXELS * BYTES_PER_PIXEL];
        let total = self.head.extent().area();
        let mut at = 0;
        while at < total {
            let n = (total - at).min(CHUNK_PIXELS);
            let bytes = &mut buf[..n * BYTES_PER_PIXEL];
            file.read_exact(bytes)
                .with_context(|| format!("{}: the body ends early", name()))?;
            sum.bytes(bytes);
            each(at, &decode_pixels(bytes)).with_context(name)?;
            at += n;
        }
        if sum.finish() != self.head.checksum {
            bail!("{}: corrupt: the pixel checksum does not match", name());
        }
        Ok(())
    }
}

/// Where the header of a film's bytes ends (just past its empty line),
/// after checking the magic line.
fn header_end(bytes: &[u8]) -> Result<usize> {
    let not_film = || anyhow::anyhow!("not a Strata film (no `{MAGIC}` line)");
    let first = bytes
        .iter()
        .position(|&b| b == b'\n')
        .ok_or_else(not_film)?;
    if &bytes[..first] != MAGIC.as_bytes() {
        if bytes.starts_with(b"strata-film ") {
            bail!(
                "a film of another format version (`{}`; this build reads `{MAGIC}`)",
                clip(&String::from_utf8_lossy(&bytes[..first]))
            );
        }
        return Err(not_film());
    }
    // The header's end is searched from the magic line's newline on, so
    // an empty header is found as such, not before the magic line ends.
    match find(&bytes[first..], b"\n\n") {
        Some(at) if first + at + 2 <= MAX_HEADER_BYTES + 2 => Ok(first + at + 2),
        _ if bytes.len() > MAX_HEADER_BYTES => {
            bail!(
                "the header is longer than {} KB: not a film",
                MAX_HEADER_BYTES / 1024
            )
        }
        _ => bail!("truncated: the header does not end"),
    }
}

/// The body holds exactly the extent's pixels.
fn check_body_len(head: &FilmHead, len: u64) -> Result<()> {
    let need = head.extent().area() as u64 * BYTES_PER_PIXEL as u64;
    if len != need {
        bail!(
            "truncated or padded: {len} bytes of pixels where the window and its border need \
             {need}"
        );
    }
    Ok(())
}

/// Parses and checks a header (the bytes up to and with its empty line):
/// its checksum first, so no damaged byte is used; then every field as
/// its type ([`RenderKey::parse`]), and the window, samples and border
/// against the render.
fn parse_head(bytes: &[u8]) -> Result<FilmHead> {
    // The magic line and its newline, then lines, then the empty line
    // (whose newline is the last byte; the last line's is the one before).
    let first = (MAGIC.len() + 1).min(bytes.len() - 1);
    // The last line (before the empty one) starts after the newline
    // before it.
    let end = bytes.len().saturating_sub(2);
    let last = bytes[..end]
        .iter()
        .rposition(|&b| b == b'\n')
        .map_or(0, |i| i + 1)
        .max(first);
    let sealed = bytes
        .get(last..end)
        .and_then(|l| std::str::from_utf8(l).ok())
        .and_then(|l| l.strip_prefix(HEAD_CHECKSUM))
        .and_then(|h| u64::from_str_radix(h, 16).ok())
        .is_some_and(|sum| sum == crate::hash::fnv1a(&bytes[..last]));
    if !sealed {
        bail!("corrupt: the header's checksum does not match (its header is damaged)");
    }
    let head = std::str::from_utf8(&bytes[first..last]).context("header is not UTF-8")?;
    let mut map: Vec<(&str, &str)> = Vec::new();
    for line in head.lines() {
        let (k, v) = line
            .split_once('=')
            .with_context(|| format!("header line `{}` is not key=value", clip(line)))?;
        if map.iter().any(|(seen, _)| *seen == k) {
            bail!("header repeats `{}`", clip(k));
        }
        map.push((k, v));
    }
    let get = |name: &str| -> Result<&str> {
        map.iter()
            .find(|(k, _)| *k == name)
            .map(|(_, v)| *v)
            .with_context(|| format!("header has no `{name}`"))
    };
    let bad = |name: &str| {
        let v = get(name).unwrap_or_default();
        format!("bad `{name}`: `{}`", clip(v))
    };
    let known = |k: &str| {
        KEY_FIELDS.contains(&k) || ["window", "samples", "border", "checksum"].contains(&k)
    };
    if let Some((k, _)) = map.iter().find(|(k, _)| !known(k)) {
        bail!(
            "header has a field this build does not write: `{}`",
            clip(k)
        );
    }
    let key = RenderKey::parse(get)?;
    let (width, height, spp) = (key.width(), key.height(), key.spp());
    let window = parse_window(get("window")?).with_context(|| bad("window"))?;
    let samples = parse_samples(get("samples")?).with_context(|| bad("samples"))?;
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
    if window.x0 as u64 + window.width as u64 > width as u64
        || window.y0 as u64 + window.height as u64 > height as u64
    {
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
    let adaptive = key.adaptive();
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
            .with_context(|| bad("border"))?,
    };
    check_border(&key, border)?;
    let checksum = u64::from_str_radix(get("checksum")?, 16).with_context(|| bad("checksum"))?;
    Ok(FilmHead {
        key,
        window,
        samples,
        border,
        checksum,
    })
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
    let head = film.head_unchecked();
    let check = CountCheck::new(&head)?;
    if film.pixels.len() != check.extent.area() {
        bail!(
            "{} pixels where the window and its border have {}",
            film.pixels.len(),
            check.extent.area()
        );
    }
    film.pixels
        .iter()
        .enumerate()
        .try_for_each(|(i, p)| check.pixel(i, p))
}

/// [`check_counts`] a pixel at a time, for a body read in chunks.
pub(super) struct CountCheck<'h> {
    head: &'h FilmHead,
    /// The body's pixels.
    pub extent: strata::render::Tile,
}

impl<'h> CountCheck<'h> {
    pub fn new(head: &'h FilmHead) -> Result<Self> {
        let (key, samples) = (&head.key, &head.samples);
        if key.adaptive.is_some() && *samples != (0..key.spp) {
            bail!(
                "an adaptive film must cover samples 0..{}, not {}..{}",
                key.spp,
                samples.start,
                samples.end
            );
        }
        Ok(CountCheck {
            head,
            extent: head.extent(),
        })
    }

    /// Checks pixel `i` of the extent (row-major).
    pub fn pixel(&self, i: usize, p: &PixelSum) -> Result<()> {
        let (key, w) = (&self.head.key, self.head.window);
        let extent = self.extent;
        let (x, y) = (
            extent.x0 + (i % extent.width as usize) as u32,
            extent.y0 + (i / extent.width as usize) as u32,
        );
        let owned = (w.x0..w.x0 + w.width).contains(&x) && (w.y0..w.y0 + w.height).contains(&y);
        match count_problem(p, owned, &self.head.samples, key.adaptive) {
            Some(why) => bail!("pixel ({x}, {y}) {why}"),
            None => Ok(()),
        }
    }
}

/// What is wrong with a pixel's sample count, if anything: a pixel a part
/// owns took every sample of its range (an adaptive one, a count its
/// settings allow: [`Adaptive::can_take`](strata::render::Adaptive::can_take)),
/// and a pixel of its border none (it holds only sums). The films' check
/// and the checkpoints' records' check.
pub(crate) fn count_problem(
    p: &PixelSum,
    owned: bool,
    samples: &std::ops::Range<u32>,
    adaptive: Option<strata::render::Adaptive>,
) -> Option<String> {
    let n = samples.end.saturating_sub(samples.start);
    if !owned {
        return (p.taken() != 0).then(|| {
            format!(
                "of the border holds {} samples; a border holds only sums",
                p.taken()
            )
        });
    }
    let (possible, want) = match adaptive {
        None => (p.taken() == n, n.to_string()),
        Some(a) => (
            a.can_take(p.taken()),
            format!(
                "a multiple of {} from {} to {}",
                a.block(),
                a.min(),
                2 * a.block() + a.rest_range().end()
            ),
        ),
    };
    (!possible).then(|| {
        format!(
            "holds {} samples where the range {}..{} has {want}",
            p.taken(),
            samples.start,
            samples.end
        )
    })
}

fn find(hay: &[u8], needle: &[u8]) -> Option<usize> {
    hay.windows(needle.len()).position(|w| w == needle)
}
