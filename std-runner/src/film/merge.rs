//! Adding parts into one film, after checking that they come from one
//! render and cover every pixel and sample index of one window × one
//! sample range exactly once (the whole render, or a staged part of it).

use std::ops::Range;
use std::path::PathBuf;

use anyhow::{Context, Result, bail};
use strata::render::{PixelSum, Tile};

use super::Film;
use super::format::{check_border, check_counts};

/// Merges parts whose cells (`window × samples`) are disjoint and join
/// into one window × one sample range: the whole image and every sample
/// (the finished film), or a staged part of it (a partial film that
/// merges on with the rest). Borders are added wherever they fall.
/// `names` label the parts in errors (one per part). Refuses parts of
/// different renders, overlaps, and cells that leave a gap in their
/// window × range.
pub fn merge(parts: &[Film], names: &[PathBuf]) -> Result<Film> {
    merge_cells(parts, names, false)
}

/// As [`merge()`], but the cells must fill the whole image and every
/// sample: the finished film, for an image.
pub fn merge_whole(parts: &[Film], names: &[PathBuf]) -> Result<Film> {
    merge_cells(parts, names, true)
}

fn merge_cells(parts: &[Film], names: &[PathBuf], whole_only: bool) -> Result<Film> {
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
        if !inside || p.samples.start >= p.samples.end || p.samples.end > spp {
            bail!(
                "`{}` is inconsistent: its window or samples do not fit the render",
                name(i)
            );
        }
        check_border(&p.key, p.border)
            .and_then(|()| check_counts(p))
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
    // The cells' hull: the window and the sample range they must fill.
    let hull = |f: fn(&Film) -> (u32, u32)| {
        parts
            .iter()
            .map(f)
            .fold((u32::MAX, 0), |(lo, hi), (a, b)| (lo.min(a), hi.max(b)))
    };
    let ((x0, x1), (y0, y1), (s0, s1)) = match whole_only {
        true => ((0, w), (0, h), (0, spp)),
        false => (
            hull(|p| (p.window.x0, p.window.x0 + p.window.width)),
            hull(|p| (p.window.y0, p.window.y0 + p.window.height)),
            hull(|p| (p.samples.start, p.samples.end)),
        ),
    };
    let window = Tile {
        x0,
        y0,
        width: x1 - x0,
        height: y1 - y0,
    };
    // One key, one border: each part's is checked against the key.
    let border = first.border;
    let out = super::extent(window, border, w, h);
    let mut pixels = vec![PixelSum::ZERO; out.area()];
    let mut covered = vec![0u64; window.area()];
    for p in parts {
        let from = p.extent();
        for (r, y) in rows(&from).enumerate() {
            for (c, x) in cols(&from).enumerate() {
                let at = (y - out.y0) as usize * out.width as usize + (x - out.x0) as usize;
                pixels[at].merge(&p.pixels[r * from.width as usize + c]);
            }
        }
        let n = (p.samples.end - p.samples.start) as u64;
        for y in rows(&p.window) {
            for x in cols(&p.window) {
                covered[(y - y0) as usize * window.width as usize + (x - x0) as usize] += n;
            }
        }
    }
    // With no overlap, every cell lies in the hull, so a pixel's ranges
    // fill the hull's exactly when their lengths add up to it.
    let whole = window == Tile::whole(w, h) && (s0, s1) == (0, spp);
    if let Some(at) = covered.iter().position(|&c| c != (s1 - s0) as u64) {
        let (x, y) = (
            x0 as usize + at % window.width as usize,
            y0 as usize + at / window.width as usize,
        );
        if whole {
            let hint = match whole_only {
                true => " (an image needs the whole render; a .film output may be a staged part)",
                false => "",
            };
            bail!(
                "the parts leave a gap: pixel ({x}, {y}) has {} of its {spp} samples{hint}",
                covered[at]
            );
        }
        bail!(
            "the parts leave a gap in the window x {x0}..{x1}, y {y0}..{y1} × samples {s0}..{s1} \
             they span: pixel ({x}, {y}) has {} of those {} samples (a staged merge must join \
             into one window and one sample range)",
            covered[at],
            s1 - s0
        );
    }
    Ok(Film {
        key: first.key.clone(),
        window,
        samples: s0..s1,
        border,
        pixels,
    })
}

/// The indices both ranges hold, if any.
fn overlap(a: &Range<u32>, b: &Range<u32>) -> Option<Range<u32>> {
    let r = a.start.max(b.start)..a.end.min(b.end);
    (r.start < r.end).then_some(r)
}
