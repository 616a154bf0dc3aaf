//! Images in and out: 8-bit PNG (sRGB by default, or the course's gamma 2)
//! with text metadata, linear OpenEXR, and PNG textures decoded to linear
//! RGB. Output goes to a temporary file beside the target, renamed into
//! place only when complete, so a failure leaves nothing behind.
//!
//! Transfer functions use `libm`, so the same render gives the same bytes
//! on every machine.

use std::io::Write;
use std::path::{Path, PathBuf};

use anyhow::{Context, Result, bail};
use glam::Vec3;

use crate::limits::MAX_TEXELS;

/// Rec. 709 luminance in `f64`, as the studies and spectra measure it.
#[must_use]
pub fn luminance(v: Vec3) -> f64 {
    0.2126 * v.x as f64 + 0.7152 * v.y as f64 + 0.0722 * v.z as f64
}

/// An image texture's texels, linear RGB, row 0 at the top.
#[derive(Clone, Debug, PartialEq)]
pub struct Image {
    /// Columns.
    pub width: u32,
    /// Rows.
    pub height: u32,
    /// `width × height` linear RGB values, row-major.
    pub texels: Vec<Vec3>,
}

/// How linear radiance becomes 8-bit values.
#[derive(
    Clone, Copy, Debug, PartialEq, Eq, clap::ValueEnum, serde::Serialize, serde::Deserialize,
)]
pub enum Transfer {
    /// The sRGB curve, rounded (the default; a PNG `sRGB` chunk says so).
    Srgb,
    /// The course's curve: `⌊255 · min(√v, 0.999)⌋` (its gamma-2
    /// encoding), with a `gAMA` chunk of 1/2.
    #[value(name = "2")]
    Gamma2,
}

impl Transfer {
    /// The curve's name in image metadata.
    #[must_use]
    pub fn name(self) -> &'static str {
        match self {
            Transfer::Srgb => "srgb",
            Transfer::Gamma2 => "gamma2",
        }
    }
}

/// The sRGB encoding of a linear value in `[0, 1]` (clamped).
pub fn srgb_encode(v: f32) -> f32 {
    let v = v.clamp(0.0, 1.0);
    if v <= 0.003_130_8 {
        12.92 * v
    } else {
        1.055 * libm::powf(v, 1.0 / 2.4) - 0.055
    }
}

/// The linear value of an sRGB-encoded value in `[0, 1]`.
pub fn srgb_decode(c: f32) -> f32 {
    if c <= 0.040_45 {
        c / 12.92
    } else {
        libm::powf((c + 0.055) / 1.055, 2.4)
    }
}

/// A linear value as an 8-bit code under `transfer`.
pub fn to_u8(v: f32, transfer: Transfer) -> u8 {
    match transfer {
        Transfer::Srgb => {
            // The code is the number of thresholds at or below `v`: the
            // bits of `srgb_code`, without a `powf` per channel.
            srgb_thresholds().partition_point(|&t| t <= v) as u8
        }
        Transfer::Gamma2 => (255.0 * libm::sqrtf(v.max(0.0)).min(0.999)) as u8,
    }
}

/// The 8-bit sRGB code of a linear value: `round(255 · srgb_encode(v))`,
/// NaN as 0. [`to_u8`] gives the same bits through [`srgb_thresholds`].
#[must_use]
pub fn srgb_code(v: f32) -> u8 {
    let v = if v.is_nan() { 0.0 } else { v };
    libm::roundf(srgb_encode(v) * 255.0) as u8
}

/// `t[k − 1]`, for codes `k = 1..=255`, is the least `f32` whose
/// [`srgb_code`] is at least `k`, found by bisection over the bit
/// patterns of `[0, 1]` (ordered as the values are). Since the code never
/// falls as `v` grows (`powf` is within an ulp, far finer than a code
/// step; the tests check every value near each threshold), the code of
/// `v` is the count of thresholds `≤ v`.
fn srgb_thresholds() -> &'static [f32; 255] {
    static TABLE: std::sync::OnceLock<[f32; 255]> = std::sync::OnceLock::new();
    TABLE.get_or_init(|| {
        let one = 1.0f32.to_bits();
        core::array::from_fn(|i| {
            let k = i as u8 + 1;
            // The least bits in [0, one] with code ≥ k (code(1.0) = 255).
            let (mut lo, mut hi) = (0u32, one);
            while lo < hi {
                let mid = lo + (hi - lo) / 2;
                if srgb_code(f32::from_bits(mid)) >= k {
                    hi = mid;
                } else {
                    lo = mid + 1;
                }
            }
            f32::from_bits(lo)
        })
    })
}

/// Linear RGB pixels as 8-bit RGB under `transfer`.
#[must_use]
pub fn rgb8(pixels: &[Vec3], transfer: Transfer) -> Vec<u8> {
    pixels
        .iter()
        .flat_map(|p| [p.x, p.y, p.z].map(|v| to_u8(v, transfer)))
        .collect()
}

/// Whether `path` names an output this program can write, checked before
/// any rendering: a `.png` or `.exr` name whose directory exists and
/// accepts a new file. Leaves nothing behind.
pub fn check_output(path: &Path) -> Result<()> {
    match extension(path).as_deref() {
        Some("png" | "exr") => {}
        _ => bail!("output `{}` must end in .png or .exr", path.display()),
    }
    check_writable_dir(path)
}

/// Whether a file can be created beside `path` (and `path` is not a
/// directory), by creating and removing a temporary file there; `path`
/// itself is not touched.
pub fn check_writable_dir(path: &Path) -> Result<()> {
    if path.is_dir() {
        bail!("output `{}` is a directory", path.display());
    }
    // The reason in the one line main prints (`{e:#}` shows the chain,
    // but callers that wrap this error may not).
    let (probe, _) = create_temp(path).map_err(|e| {
        let dir = path.parent().filter(|d| !d.as_os_str().is_empty());
        match dir {
            Some(d) if !d.is_dir() => anyhow::anyhow!(
                "cannot write output `{}`: its directory `{}` does not exist",
                path.display(),
                d.display()
            ),
            _ => anyhow::anyhow!("cannot write output `{}`: {e}", path.display()),
        }
    })?;
    std::fs::remove_file(&probe).ok();
    Ok(())
}

fn extension(path: &Path) -> Option<String> {
    path.extension()
        .map(|e| e.to_string_lossy().to_ascii_lowercase())
}

/// `p` with its directory's symbolic links and `..` resolved, its own
/// name kept as given (a link stays the link: a write replaces it, as the
/// rename of [`write_atomic`] does). `p` need not exist; where its
/// directory does not either, `p` made absolute.
#[must_use]
pub fn real_path(p: &Path) -> PathBuf {
    let Ok(abs) = std::path::absolute(p) else {
        return p.to_path_buf();
    };
    match (abs.parent(), abs.file_name()) {
        (Some(d), Some(name)) => d
            .canonicalize()
            .map_or_else(|_| abs.clone(), |d| d.join(name)),
        // `/` or a path ending in `..`: resolved whole.
        _ => abs.canonicalize().unwrap_or(abs),
    }
}

/// A new temporary file beside `path` ([`temp_path_n`]: the first name
/// no file has yet).
fn create_temp(path: &Path) -> std::io::Result<(PathBuf, std::fs::File)> {
    let mut n = 0;
    loop {
        let tmp = temp_path_n(path, n);
        match std::fs::File::create_new(&tmp) {
            Ok(f) => return Ok((tmp, f)),
            Err(e) if e.kind() == std::io::ErrorKind::AlreadyExists && n < 64 => n += 1,
            Err(e) => return Err(e),
        }
    }
}

/// `dir/.name.strata-tmp-PID` (`n = 0`) or `…-PID-n`: the `n`th try of a
/// name no other file has (a process of the same PID on another host or
/// in another container may write beside the same target).
fn temp_path_n(path: &Path, n: u32) -> PathBuf {
    let name = path
        .file_name()
        .map_or("out".into(), |n| n.to_string_lossy().into_owned());
    let pid = std::process::id();
    path.with_file_name(match n {
        0 => format!(".{name}.strata-tmp-{pid}"),
        n => format!(".{name}.strata-tmp-{pid}-{n}"),
    })
}

/// Writes through `write` into a temporary file and renames it to `path`;
/// on any error the temporary file is removed and `path` is untouched.
/// The temporary file is locked (`flock`) while it is written, and
/// temporary files of earlier writes of `path` that no process holds (a
/// process killed while writing) are removed first
/// ([`remove_stale_temps`]).
pub fn write_atomic(path: &Path, write: impl FnOnce(&Path) -> Result<()>) -> Result<()> {
    remove_stale_temps(path);
    // A name of our own (made new, never another writer's file), locked
    // until the rename: a live writer's file is never taken for a stale
    // one. (A file system without locks cannot have this: go on.)
    let (tmp, file) =
        create_temp(path).with_context(|| format!("cannot write `{}`", path.display()))?;
    let _held = file.try_lock().is_ok().then_some(file);
    let result = write(&tmp).and_then(|()| {
        std::fs::rename(&tmp, path)
            .with_context(|| format!("cannot move output into `{}`", path.display()))
    });
    if result.is_err() {
        std::fs::remove_file(&tmp).ok();
    }
    result
}

/// Removes the temporary files that writes of `path` left behind:
/// `.NAME.strata-tmp-PID` or `…-PID-N` beside it, regular files whose lock
/// no process holds (their writer was killed; [`write_atomic`] holds the
/// lock while it writes, on any host that shares the file system's
/// locks). A file whose lock is held, or cannot be tried, is left alone,
/// and so is anything but a regular file (a FIFO would block the open).
pub fn remove_stale_temps(path: &Path) {
    let Some(name) = path.file_name() else {
        return;
    };
    let prefix = format!(".{}.strata-tmp-", name.to_string_lossy());
    let dir = path
        .parent()
        .filter(|d| !d.as_os_str().is_empty())
        .unwrap_or(Path::new("."));
    let Ok(entries) = std::fs::read_dir(dir) else {
        return;
    };
    for entry in entries.flatten() {
        let ours = entry.file_name().to_str().is_some_and(|f| {
            f.strip_prefix(&prefix).is_some_and(|tail| {
                !tail.is_empty()
                    && tail.bytes().all(|b| b.is_ascii_digit() || b == b'-')
                    && tail.as_bytes()[0].is_ascii_digit()
            })
        });
        let regular = ours && entry.metadata().is_ok_and(|m| m.file_type().is_file());
        if !regular {
            continue;
        }
        // Removed while its lock is held here: no writer takes the name
        // meanwhile (a new one is made only once this one is gone).
        if let Ok(f) = std::fs::File::open(entry.path())
            && f.try_lock().is_ok()
        {
            std::fs::remove_file(entry.path()).ok();
        }
    }
}

/// An image file format the renderer writes.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum ImageFormat {
    /// 8-bit RGB PNG under a [`Transfer`] curve.
    Png,
    /// Linear 32-bit float RGB OpenEXR.
    Exr,
}

impl ImageFormat {
    /// The format a file name asks for by its extension (any case).
    #[must_use]
    pub fn of(path: &Path) -> Option<ImageFormat> {
        match extension(path).as_deref() {
            Some("png") => Some(ImageFormat::Png),
            Some("exr") => Some(ImageFormat::Exr),
            _ => None,
        }
    }
}

/// The bytes of an image file of `pixels` (linear RGB, row-major), with
/// `metadata` as PNG text chunks or EXR comments. The same pixels and
/// metadata give the same bytes on every machine.
pub fn image_bytes(
    format: ImageFormat,
    width: u32,
    height: u32,
    pixels: &[Vec3],
    transfer: Transfer,
    metadata: &[(String, String)],
) -> Result<Vec<u8>> {
    assert_eq!(pixels.len(), (width * height) as usize);
    match format {
        ImageFormat::Png => {
            png_rgb8_bytes(width, height, &rgb8(pixels, transfer), transfer, metadata)
        }
        ImageFormat::Exr => exr_bytes(width, height, pixels, metadata),
    }
}

/// Writes `bytes` to `path`, naming the file in the error.
pub fn write_file(path: &Path, bytes: &[u8]) -> Result<()> {
    std::fs::write(path, bytes).with_context(|| format!("cannot write `{}`", path.display()))
}

/// Writes 8-bit RGB `bytes` (already encoded with `transfer`, row-major)
/// as a PNG at `path`, atomically, with `metadata` as text chunks.
pub fn write_png_rgb8(
    path: &Path,
    width: u32,
    height: u32,
    bytes: &[u8],
    transfer: Transfer,
    metadata: &[(String, String)],
) -> Result<()> {
    let png = png_rgb8_bytes(width, height, bytes, transfer, metadata)?;
    write_atomic(path, |tmp| write_file(tmp, &png))
}

/// The PNG file of 8-bit RGB `bytes` (already encoded with `transfer`,
/// row-major), with `metadata` as text chunks.
pub fn png_rgb8_bytes(
    width: u32,
    height: u32,
    bytes: &[u8],
    transfer: Transfer,
    metadata: &[(String, String)],
) -> Result<Vec<u8>> {
    assert_eq!(bytes.len(), width as usize * height as usize * 3);
    let mut out = Vec::new();
    let mut enc = png::Encoder::new(&mut out, width, height);
    enc.set_color(png::ColorType::Rgb);
    enc.set_depth(png::BitDepth::Eight);
    // fdeflate's PNG-tuned mode: on renders about 15 times fewer
    // instructions than zlib's default level, for files 5-35 % larger
    // (noisier images compress worse); a render is rarely the final file.
    enc.set_compression(png::Compression::Fast);
    match transfer {
        Transfer::Srgb => enc.set_source_srgb(png::SrgbRenderingIntent::Perceptual),
        Transfer::Gamma2 => enc.set_source_gamma(png::ScaledFloat::new(0.5)),
    }
    for (k, v) in metadata {
        enc.add_text_chunk(k.clone(), v.clone())?;
    }
    let mut writer = enc.write_header()?;
    writer.write_image_data(bytes)?;
    writer.finish()?;
    Ok(out)
}

fn exr_bytes(
    width: u32,
    height: u32,
    pixels: &[Vec3],
    metadata: &[(String, String)],
) -> Result<Vec<u8>> {
    use exr::prelude::*;
    let w = width as usize;
    let channels = SpecificChannels::rgb(|pos: Vec2<usize>| {
        let p = pixels[pos.y() * w + pos.x()];
        (p.x, p.y, p.z)
    });
    // One text attribute holds all metadata: exr keeps custom attributes in
    // a hash map whose order would vary between runs. EXR is linear, so the
    // PNG transfer curve does not belong in it.
    let comments: String = metadata
        .iter()
        .filter(|(k, _)| k != "strata.transfer")
        .map(|(k, v)| format!("{k}={v}\n"))
        .collect();
    let mut attributes = LayerAttributes::named("rgb");
    attributes.comments = Some(Text::from(comments.as_str()));
    attributes.software_name = Some(Text::from(
        format!("strata {}", env!("CARGO_PKG_VERSION")).as_str(),
    ));
    let layer = Layer::new(
        (w, height as usize),
        attributes,
        Encoding::SMALL_LOSSLESS,
        channels,
    );
    let mut out = std::io::Cursor::new(Vec::new());
    exr::image::Image::from_layer(layer)
        .write()
        .non_parallel()
        .to_buffered(&mut out)
        .context("cannot encode the EXR image")?;
    Ok(out.into_inner())
}

/// Reads a PNG (8- or 16-bit, grey, grey-alpha, RGB or RGBA; alpha is
/// ignored) and decodes its sRGB values to linear RGB. A header that
/// claims more than [`MAX_TEXELS`] texels is refused before anything is
/// allocated.
pub fn read_png_linear(path: &Path) -> Result<Image> {
    let file = std::fs::File::open(path).context("cannot open")?;
    let limits = png::Limits {
        bytes: (MAX_TEXELS * 4) as usize,
    };
    let mut dec = png::Decoder::new_with_limits(std::io::BufReader::new(file), limits);
    dec.set_transformations(png::Transformations::EXPAND | png::Transformations::STRIP_16);
    let mut reader = dec.read_info().context("not a readable PNG")?;
    let (w, h) = (reader.info().width as u64, reader.info().height as u64);
    if w * h > MAX_TEXELS {
        bail!("{w} x {h} texels is over the limit of {MAX_TEXELS}");
    }
    let size = reader.output_buffer_size().context("image too large")?;
    let mut buf = vec![0; size];
    let info = reader.next_frame(&mut buf).context("corrupt PNG")?;
    let (width, height) = (info.width, info.height);
    let step = match info.color_type {
        png::ColorType::Grayscale => 1,
        png::ColorType::GrayscaleAlpha => 2,
        png::ColorType::Rgb => 3,
        png::ColorType::Rgba => 4,
        png::ColorType::Indexed => bail!("indexed PNG was not expanded"),
    };
    let decode: Vec<f32> = (0..=255u8).map(|c| srgb_decode(c as f32 / 255.0)).collect();
    let mut texels = Vec::with_capacity((width * height) as usize);
    for row in buf[..info.buffer_size()].chunks(info.line_size) {
        for px in row.chunks(step).take(width as usize) {
            let (r, g, b) = if step < 3 {
                (px[0], px[0], px[0])
            } else {
                (px[0], px[1], px[2])
            };
            texels.push(Vec3::new(
                decode[r as usize],
                decode[g as usize],
                decode[b as usize],
            ));
        }
    }
    Ok(Image {
        width,
        height,
        texels,
    })
}

/// Writes a line to stdout, ignoring a closed pipe or a full disk: the
/// image is already written, and a report nobody reads is no error.
pub fn say(line: &str) {
    let mut out = std::io::stdout().lock();
    writeln!(out, "{line}").ok();
    out.flush().ok();
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn transfer_curves() {
        assert_eq!(to_u8(0.0, Transfer::Srgb), 0);
        assert_eq!(to_u8(1.0, Transfer::Srgb), 255);
        assert_eq!(to_u8(0.215_860_5, Transfer::Srgb), 128); // sRGB code 128
        assert_eq!(to_u8(5.0, Transfer::Srgb), 255);
        assert_eq!(to_u8(f32::NAN, Transfer::Srgb), 0);
        // The course's: sqrt, clamp to 0.999, truncate: 1.0 gives 254.
        assert_eq!(to_u8(1.0, Transfer::Gamma2), 254);
        assert_eq!(to_u8(0.25, Transfer::Gamma2), 127);
        for c in 0..=255u8 {
            let v = srgb_decode(c as f32 / 255.0);
            assert_eq!(to_u8(v, Transfer::Srgb), c, "round trip of {c}");
        }
    }

    /// The threshold table gives `srgb_code`'s bits: at every value
    /// within 2¹² ulps of each threshold (where a rounding wobble in
    /// `powf` could make the code fall back), at special values, and at
    /// values spread over the whole `f32` range.
    #[test]
    fn the_srgb_table_gives_the_codes_of_powf() {
        let check = |v: f32| {
            assert_eq!(
                to_u8(v, Transfer::Srgb),
                srgb_code(v),
                "{v:e} ({:#x})",
                v.to_bits()
            );
        };
        for &t in srgb_thresholds() {
            let b = t.to_bits();
            for bits in b.saturating_sub(1 << 12)..=b + (1 << 12) {
                check(f32::from_bits(bits));
            }
        }
        for v in [
            0.0,
            -0.0,
            1.0,
            -1.0,
            f32::MIN_POSITIVE,
            1e-45,
            f32::INFINITY,
            f32::NEG_INFINITY,
            f32::NAN,
            f32::MAX,
            0.003_130_8,
        ] {
            check(v);
        }
        // Every 4099th bit pattern: both signs, subnormals to infinities.
        for bits in (0..=u32::MAX).step_by(4099) {
            check(f32::from_bits(bits));
        }
        // Must-fail control: a threshold one ulp off changes a code.
        let t = srgb_thresholds()[127];
        let below = f32::from_bits(t.to_bits() - 1);
        assert_eq!(srgb_code(t), 128);
        assert_eq!(srgb_code(below), 127);
    }
}
