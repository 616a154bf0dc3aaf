//! Partial films on disk, and merging them.
//!
//! A render of part of a frame (a pixel window, a range of sample indices,
//! or both) is saved as a `.film`: the exact per-pixel sums of
//! [`PixelSum`] (integers, so adding parts is associative), the sample
//! counts, and the [`RenderKey`] that defines the pixels. [`merge()`] adds
//! any set of parts that partitions `image × samples` exactly, so the
//! merged image is bit-identical to the one-shot render; it refuses
//! overlaps, gaps and parts of another render.
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
pub use key::{
    KEY_FIELDS, RenderKey, adaptive_text, filter_text, parse_samples, samples_text, version,
    window_text,
};
pub use merge::merge;

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
        let pixels: Vec<glam::Vec3> = self.pixels.iter().map(|p| p.mean()).collect();
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
