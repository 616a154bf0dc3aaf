//! Partial films on disk, and merging them.
//!
//! A render of part of a frame (a pixel window, a range of sample indices,
//! or both) is saved as a `.film`: the exact per-pixel sums of
//! [`PixelSum`] (integers, so adding parts is associative), the sample
//! counts, and the [`RenderKey`] that defines the pixels. [`merge()`] adds
//! parts that cover disjoint `window × samples` cells, so the merged image
//! is bit-identical to the one-shot render; it refuses overlaps, parts of
//! another render, and a set whose cells do not join into one window ×
//! one sample range (the whole image and every sample, or a staged part
//! of it).
//!
//! **Coverage.** A film *owns* the samples `samples` of the pixels of
//! `window`: those pixels' counts are its. A splatted filter's samples
//! also reach `border` pixels beyond the window (the filter's
//! [`splat_margin`](strata::filter::PixelFilter::splat_margin)), so the
//! film also holds the sums it adds to the pixels of that border (clipped
//! to the image), with counts of 0: the body covers the *extent*, the
//! window grown by the border. Overlap and gap checks apply to owned
//! pixels; sums are added wherever they fall, so a pixel near a part's
//! edge is complete once its neighbours' parts are merged. Films of
//! filters that do not splat have no border.
//!
//! The format (version 5) is a text header and a binary body:
//!
//! ```text
//! strata-film 5
//! version=0.1.0+r14        the build's: a merge takes parts of its own
//! scene=cover              build only
//! ...                      the RenderKey fields, each parsed as its type
//!                          when read, then:
//! window=x0,x1,y0,y1       pixels covered, half-open
//! samples=A..B             sample indices covered, half-open
//! border=N                 only for N > 0: the extent's border
//! checksum=<16 hex digits> FNV-1a 64 of the body
//! head_checksum=<16 hex>   FNV-1a 64 of every header byte before this
//!                          line (checked before any of them is used)
//!                          (an empty line ends the header)
//! body: one record per extent pixel, row-major, 64 bytes each,
//!       little-endian: weighted sums r, g, b and the filter-weight sum as
//!       i64 (units of 2^-24), samples u32, dropped u32, then the own
//!       samples' unweighted sums r, g, b minus the weighted ones as i64
//!       (units of 2^-24, wrapping; 0 with weights of 1).
//! ```
//!
//! An adaptive render (`adaptive=threshold=T min=N max=M`, with `spp` =
//! M) covers samples `0..M` of its window: each pixel holds the `N..=M`
//! samples its pilot asked for (whole blocks of N/4), and its record's
//! weight is 2^24 times its kept samples (its value is a blend of the
//! pilot's halves and the rest, see `strata::render::Adaptive`).
//! Adaptive parts split the pixels only, never the samples.

//!
//! Here: [`Film`] and the file it becomes (a `.film`, or its window as an
//! image). In `key`: the [`RenderKey`] and the header's texts. In
//! `format`: the bytes. In `merge`: [`merge()`] and its checks.

mod format;
mod key;
mod merge;
#[cfg(test)]
mod tests;

use std::ops::Range;
use std::path::Path;

use anyhow::Result;
use strata::render::{PixelSum, Tile};

use crate::image_io::{ImageFormat, Transfer, image_bytes};

pub use format::{BYTES_PER_PIXEL, MAGIC};
pub use format::{FilmFile, FilmHead};
pub(crate) use format::{count_problem, decode_pixels, encode_pixels};
pub use key::{
    KEY_FIELDS, RenderKey, adaptive_text, filter_text, parse_range, parse_samples, samples_text,
    version, window_text,
};
pub use merge::{merge, merge_files, merge_whole};

/// A part of a render: the pixels of `window`, samples `samples` of each.
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct Film {
    /// What render this is part of.
    pub key: RenderKey,
    /// The pixels covered.
    pub window: Tile,
    /// The sample indices covered.
    pub samples: Range<u32>,
    /// Pixels beyond the window on each side (clipped to the image) whose
    /// sums the film holds: a splatted filter's margin, else 0.
    pub border: u32,
    /// One accumulator per pixel of the [extent](Film::extent), row-major.
    pub pixels: Vec<PixelSum>,
}

/// The pixels of `inner` (inside `outer`) out of `pixels`, `outer`'s,
/// row-major.
#[must_use]
pub fn cut(pixels: &[PixelSum], outer: Tile, inner: Tile) -> Vec<PixelSum> {
    let mut out = Vec::with_capacity(inner.area());
    for y in inner.y0..inner.y0 + inner.height {
        let row = (y - outer.y0) as usize * outer.width as usize;
        let at = row + (inner.x0 - outer.x0) as usize;
        out.extend_from_slice(&pixels[at..at + inner.width as usize]);
    }
    out
}

impl Film {
    /// The pixels the body covers: the window and its border, clipped to
    /// the image.
    #[must_use]
    pub fn extent(&self) -> Tile {
        self.window
            .grown(self.border, self.key.width(), self.key.height())
    }

    /// The accumulators of the window's pixels (the owned ones), row-major.
    #[must_use]
    pub fn window_pixels(&self) -> Vec<PixelSum> {
        cut(&self.pixels, self.extent(), self.window)
    }

    /// Whether the window's pixels hold every sample that reaches them:
    /// true without a border, or when the window is the whole image.
    #[must_use]
    pub fn window_complete(&self) -> bool {
        self.border == 0 || self.window == Tile::whole(self.key.width(), self.key.height())
    }

    /// The image metadata of this film encoded with `transfer` (PNG text
    /// chunks, EXR attributes): what defines it, nothing that varies
    /// between runs.
    #[must_use]
    pub fn metadata(&self, transfer: Transfer) -> Vec<(String, String)> {
        let mut out = vec![(
            "Software".to_string(),
            format!("strata {}", env!("CARGO_PKG_VERSION")),
        )];
        for (k, v) in self.key.fields() {
            out.push((format!("strata.{k}"), v.clone()));
        }
        out.push(("strata.window".into(), window_text(self.window)));
        out.push(("strata.samples".into(), samples_text(&self.samples)));
        out.push(("strata.transfer".into(), transfer.name().into()));
        out
    }

    /// The bytes `strata render -o path` writes for this film: the .film
    /// file, or its window as a PNG or EXR image with the film's metadata.
    pub fn output_bytes(&self, path: &Path, transfer: Transfer) -> Result<Vec<u8>> {
        if is_film_path(path) {
            return Ok(self.to_bytes());
        }
        let format = ImageFormat::of(path).ok_or_else(|| {
            anyhow::anyhow!(
                "output `{}` must end in .png, .exr or .film",
                path.display()
            )
        })?;
        if !self.window_complete() {
            anyhow::bail!(
                "this film's window {} is part of a splatted render: its edge pixels miss the \
                 samples of pixels up to {} beyond it, so it is no image yet; merge it with the \
                 parts around it, or write .film",
                window_text(self.window),
                self.border
            );
        }
        // Means straight from the extent's rows: no copy of the sums.
        let (e, w) = (self.extent(), self.window);
        let pixels: Vec<glam::Vec3> = (w.y0..w.y0 + w.height)
            .flat_map(|y| {
                let at = (y - e.y0) as usize * e.width as usize + (w.x0 - e.x0) as usize;
                self.pixels[at..at + w.width as usize]
                    .iter()
                    .map(|p| p.mean())
            })
            .collect();
        image_bytes(
            format,
            self.window.width,
            self.window.height,
            &pixels,
            transfer,
            &self.metadata(transfer),
        )
    }
}

/// Whether `path` names a `.film` (in any case).
#[must_use]
pub fn is_film_path(path: &Path) -> bool {
    path.extension()
        .is_some_and(|e| e.eq_ignore_ascii_case("film"))
}
