//! Adding parts into one film, after checking that they come from one
//! render and cover every pixel and sample index of one window × one
//! sample range exactly once (the whole render, or a staged part of it).

use std::ops::Range;
use std::path::PathBuf;

use anyhow::{Context, Result, bail};
use strata::render::{PixelSum, Tile};

use super::Film;
use super::format::{CountCheck, FilmFile, FilmHead, check_border, check_counts};
use super::key::clip;

/// Merges parts whose cells (`window × samples`) are disjoint and join
/// into one window × one sample range: the whole image and every sample
/// (the finished film), or a staged part of it (a partial film that
/// merges on with the rest). Borders are added wherever they fall.
/// `names` label the parts in errors (one per part). Refuses parts of
/// different renders, overlaps, and cells that leave a gap in their
/// window × range.
pub fn merge(parts: &[Film], names: &[PathBuf]) -> Result<Film> {
    merge_films(parts, names, false)
}

/// As [`merge()`], but the cells must fill the whole image and every
/// sample: the finished film, for an image.
pub fn merge_whole(parts: &[Film], names: &[PathBuf]) -> Result<Film> {
    merge_films(parts, names, true)
}

/// [`merge()`] (or with `whole_only`, [`merge_whole`]) of film files,
/// holding one image whatever the part count: every header is read and
/// every check made on them first, then the bodies are added one at a
/// time, a chunk at a time (each checked as it is read).
pub fn merge_files(paths: &[PathBuf], whole_only: bool) -> Result<Film> {
    let files: Vec<FilmFile> = paths
        .iter()
        .map(|p| FilmFile::open(p))
        .collect::<Result<_>>()?;
    let heads: Vec<&FilmHead> = files.iter().map(|f| &f.head).collect();
    let mut out = Merged::plan(&heads, paths, whole_only)?;
    for f in &files {
        let check = CountCheck::new(&f.head).with_context(|| format!("`{}`", f.path.display()))?;
        f.for_each_chunk(|at, chunk| {
            for (k, p) in chunk.iter().enumerate() {
                check.pixel(at + k, p)?;
            }
            out.add(check.extent, at, chunk);
            Ok(())
        })?;
    }
    Ok(out.into_film(heads[0]))
}

fn merge_films(parts: &[Film], names: &[PathBuf], whole_only: bool) -> Result<Film> {
    assert_eq!(parts.len(), names.len());
    let heads: Vec<FilmHead> = parts.iter().map(Film::head_unchecked).collect();
    let refs: Vec<&FilmHead> = heads.iter().collect();
    let mut out = Merged::plan(&refs, names, whole_only)?;
    // Films built in code rather than read: the same checks as `from_bytes`.
    for (i, p) in parts.iter().enumerate() {
        check_counts(p).with_context(|| format!("`{}` is inconsistent", names[i].display()))?;
        out.add(p.extent(), 0, &p.pixels);
    }
    Ok(out.into_film(refs[0]))
}

/// A merge's result as it is added up.
struct Merged {
    window: Tile,
    samples: Range<u32>,
    border: u32,
    /// The window grown by the border: the pixels' extent.
    extent: Tile,
    pixels: Vec<PixelSum>,
}

impl Merged {
    /// Checks that the parts are of one render, fit it, do not overlap and
    /// (as far as their cells go) join into one window × one sample range,
    /// or with `whole_only` the whole render; an empty result to add them
    /// to.
    fn plan(parts: &[&FilmHead], names: &[PathBuf], whole_only: bool) -> Result<Merged> {
        assert_eq!(parts.len(), names.len());
        let Some(first) = parts.first() else {
            bail!("nothing to merge");
        };
        let name = |i: usize| names[i].display().to_string();
        for (i, p) in parts.iter().enumerate().skip(1) {
            if let Some((field, ours, theirs)) = first.key.first_difference(&p.key) {
                bail!(
                    "`{}` is from another render than `{}`: {field} is `{}`, not `{}`",
                    name(i),
                    name(0),
                    clip(theirs),
                    clip(ours)
                );
            }
        }
        let (w, h, spp) = (first.key.width(), first.key.height(), first.key.spp());
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
                .with_context(|| format!("`{}` is inconsistent", name(i)))?;
        }
        let cols = |t: &Tile| t.x0..t.x0 + t.width;
        let rows = |t: &Tile| t.y0..t.y0 + t.height;
        // Pairwise overlap: the windows and the sample ranges both meet.
        for i in 0..parts.len() {
            for j in i + 1..parts.len() {
                let (a, b) = (parts[i], parts[j]);
                if let (Some(x), Some(y), Some(s)) = (
                    overlap(&cols(&a.window), &cols(&b.window)),
                    overlap(&rows(&a.window), &rows(&b.window)),
                    overlap(&a.samples, &b.samples),
                ) {
                    bail!(
                        "`{}` and `{}` overlap: both hold pixels x {}..{}, y {}..{}, samples \
                         {}..{}",
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
        let hull = |f: fn(&FilmHead) -> (u32, u32)| {
            parts
                .iter()
                .map(|p| f(p))
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
        // Samples per window pixel; with no overlap every cell lies in the
        // hull, so a pixel's ranges fill the hull's exactly when their
        // lengths add up to it (at most spp, so u32).
        let mut covered = vec![0u32; window.area()];
        for p in parts {
            let n = p.samples.end - p.samples.start;
            for y in rows(&p.window) {
                let row = (y - y0) as usize * window.width as usize;
                for x in cols(&p.window) {
                    covered[row + (x - x0) as usize] += n;
                }
            }
        }
        let whole = window == Tile::whole(w, h) && (s0, s1) == (0, spp);
        if let Some(at) = covered.iter().position(|&c| c != s1 - s0) {
            let (x, y) = (
                x0 as usize + at % window.width as usize,
                y0 as usize + at / window.width as usize,
            );
            if whole_only {
                bail!(
                    "the parts leave a gap: pixel ({x}, {y}) has {} of its {spp} samples (an \
                     image needs the whole render; a .film output may be a staged part)",
                    covered[at]
                );
            }
            bail!(
                "the parts leave a gap in the window x {x0}..{x1}, y {y0}..{y1} × samples \
                 {s0}..{s1} they span: pixel ({x}, {y}) has {} of those {} samples (a staged \
                 merge must join into one window and one sample range{})",
                covered[at],
                s1 - s0,
                if whole {
                    "; the whole render needs every part"
                } else {
                    ""
                }
            );
        }
        drop(covered);
        // One key, one border: each part's is checked against the key.
        let border = first.border;
        let extent = window.grown(border, w, h);
        Ok(Merged {
            window,
            samples: s0..s1,
            border,
            extent,
            pixels: vec![PixelSum::ZERO; extent.area()],
        })
    }

    /// Adds `chunk`, pixels `at..` of a part whose body covers `from`.
    fn add(&mut self, from: Tile, at: usize, chunk: &[PixelSum]) {
        let (out, fw) = (self.extent, from.width as usize);
        for (k, p) in chunk.iter().enumerate() {
            let (x, y) = (
                from.x0 as usize + (at + k) % fw,
                from.y0 as usize + (at + k) / fw,
            );
            let i = (y - out.y0 as usize) * out.width as usize + (x - out.x0 as usize);
            self.pixels[i].merge(p);
        }
    }

    fn into_film(self, first: &FilmHead) -> Film {
        Film {
            key: first.key.clone(),
            window: self.window,
            samples: self.samples,
            border: self.border,
            pixels: self.pixels,
        }
    }
}

/// The indices both ranges hold, if any.
fn overlap(a: &Range<u32>, b: &Range<u32>) -> Option<Range<u32>> {
    let r = a.start.max(b.start)..a.end.min(b.end);
    (r.start < r.end).then_some(r)
}
