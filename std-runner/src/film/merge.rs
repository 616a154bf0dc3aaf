//! Adding parts into the whole film, after checking that they come from one
//! render and cover every pixel and sample index exactly once.

use std::ops::Range;
use std::path::PathBuf;

use anyhow::{Context, Result, bail};
use strata::render::{PixelSum, Tile};

use super::Film;
use super::format::check_counts;

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

/// The indices both ranges hold, if any.
fn overlap(a: &Range<u32>, b: &Range<u32>) -> Option<Range<u32>> {
    let r = a.start.max(b.start)..a.end.min(b.end);
    (r.start < r.end).then_some(r)
}
