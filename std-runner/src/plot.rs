//! Drawing shared by the studies and the spp maps: the bundled font, a
//! colour per sampler, plotters charts drawn into 8-bit RGB, labelled
//! panels side by side, the spp heat map, and the PNG a study's image is
//! written as. Each chart itself lives with its study.

use std::path::Path;

use anyhow::{Context, Result, bail};
use plotters::coord::Shift;
use plotters::prelude::*;
use strata::render::PixelSum;

use crate::image_io::{Transfer, write_png_rgb8};
use crate::job::SamplerKind;

/// plotters' drawing area over an 8-bit RGB buffer.
pub(crate) type Area<'a> = DrawingArea<BitMapBackend<'a>, Shift>;

/// What drawing on an [`Area`] returns.
pub(crate) type Drawn =
    Result<(), DrawingAreaErrorKind<<BitMapBackend<'static> as DrawingBackend>::ErrorType>>;

/// Registers the bundled font (Ubuntu Light, from `epaint_default_fonts`)
/// as plotters' `sans-serif` once, so text draws the same on any machine
/// and needs no system fonts.
#[cfg(not(target_family = "wasm"))]
fn fonts() -> Result<()> {
    static DONE: std::sync::OnceLock<bool> = std::sync::OnceLock::new();
    let ok = *DONE.get_or_init(|| {
        plotters::style::register_font(
            "sans-serif",
            FontStyle::Normal,
            epaint_default_fonts::UBUNTU_LIGHT,
        )
        .is_ok()
    });
    if ok {
        Ok(())
    } else {
        bail!("the bundled font did not load")
    }
}

/// On WebAssembly plotters has no font registry: the page draws its own
/// plots, and a plot asked for there fails.
#[cfg(target_family = "wasm")]
fn fonts() -> Result<()> {
    bail!("plots are not drawn on WebAssembly")
}

/// Line colours, one per sampler, in [`SamplerKind`] order.
pub(crate) fn colour(sampler: SamplerKind) -> RGBColor {
    match sampler {
        SamplerKind::Independent => RGBColor(0xd6, 0x27, 0x28),
        SamplerKind::Grid => RGBColor(0x7f, 0x7f, 0x7f),
        SamplerKind::Stratified => RGBColor(0x1f, 0x77, 0xb4),
        SamplerKind::Sobol => RGBColor(0x2c, 0xa0, 0x2c),
        SamplerKind::Halton => RGBColor(0x94, 0x67, 0xbd),
        SamplerKind::ZSobol => RGBColor(0xff, 0x7f, 0x0e),
    }
}

/// A `width × height` chart as 8-bit RGB: `draw` draws on a white area,
/// with the bundled font loaded.
pub(crate) fn chart(
    width: u32,
    height: u32,
    draw: impl FnOnce(&Area<'_>) -> Drawn,
) -> Result<Vec<u8>> {
    fonts()?;
    let mut buf = vec![0u8; width as usize * height as usize * 3];
    draw_on(&mut buf, width, height, "plotting", |root| {
        root.fill(&WHITE)?;
        draw(root)
    })?;
    Ok(buf)
}

/// Draws on `buf`, an 8-bit RGB image of `width × height`; errors say
/// `what` was being drawn.
fn draw_on(
    buf: &mut [u8],
    width: u32,
    height: u32,
    what: &str,
    draw: impl FnOnce(&Area<'_>) -> Drawn,
) -> Result<()> {
    let root = BitMapBackend::with_buffer(buf, (width, height)).into_drawing_area();
    draw(&root)
        .and_then(|()| root.present())
        .map_err(|e| anyhow::anyhow!("{what}: {e}"))
}

/// The frame every study chart shares: `title` as the caption, the margin,
/// and label areas (`y_labels` pixels wide for the y axis's).
pub(crate) fn titled<'a, 'b>(
    root: &'a Area<'b>,
    title: &str,
    y_labels: u32,
) -> ChartBuilder<'a, 'static, BitMapBackend<'b>> {
    let mut builder = ChartBuilder::on(root);
    builder
        .caption(title, ("sans-serif", 22))
        .margin(12)
        .x_label_area_size(44)
        .y_label_area_size(y_labels);
    builder
}

/// A legend entry for a line drawn in `style`: a short stroke of it.
pub(crate) fn legend_line(
    style: impl Into<ShapeStyle> + Copy,
) -> impl Fn((i32, i32)) -> PathElement<(i32, i32)> {
    move |(x, y)| PathElement::new(vec![(x, y), (x + 20, y)], style)
}

/// Draws `chart`'s legend at `position`, on a bordered, nearly opaque
/// white box so lines behind it stay faintly visible.
pub(crate) fn legend<'a, 'b: 'a, CT: CoordTranslate>(
    chart: &mut ChartContext<'a, BitMapBackend<'b>, CT>,
    position: SeriesLabelPosition,
) -> Drawn {
    chart
        .configure_series_labels()
        .position(position)
        .label_font(("sans-serif", 15))
        .background_style(WHITE.mix(0.85))
        .border_style(BLACK)
        .draw()
}

/// Puts `panels` (each `width × height` 8-bit RGB, already encoded) side
/// by side with a gap between them and a caption band under each holding
/// its label; returns the 8-bit RGB buffer and its size.
pub fn side_by_side(
    panels: &[(impl AsRef<str>, impl AsRef<[u8]>)],
    width: u32,
    height: u32,
) -> Result<(Vec<u8>, u32, u32)> {
    fonts()?;
    const GAP: u32 = 6;
    const BAND: u32 = 30;
    let n = panels.len() as u32;
    let w = n
        .checked_mul(width + GAP)
        .and_then(|x| x.checked_add(GAP))
        .filter(|&w| w <= 1 << 16)
        .ok_or_else(|| anyhow::anyhow!("{n} panels of width {width} make too wide an image"))?;
    let h = height + GAP + BAND;
    let (wu, gap) = (w as usize, GAP as usize);
    let mut buf = vec![255u8; wu * h as usize * 3];
    let row = width as usize * 3;
    for (i, (_, rgb)) in panels.iter().enumerate() {
        let rgb = rgb.as_ref();
        assert_eq!(rgb.len(), row * height as usize);
        let x0 = gap + i * (width as usize + gap);
        for (y, line) in rgb.chunks_exact(row).enumerate() {
            let at = ((y + gap) * wu + x0) * 3;
            buf[at..at + row].copy_from_slice(line);
        }
    }
    draw_on(&mut buf, w, h, "drawing labels", |root| {
        let style = TextStyle::from(("sans-serif", 18)).color(&BLACK).pos(
            plotters::style::text_anchor::Pos::new(
                plotters::style::text_anchor::HPos::Center,
                plotters::style::text_anchor::VPos::Center,
            ),
        );
        for (i, (label, _)) in panels.iter().enumerate() {
            let cx = GAP + i as u32 * (width + GAP) + width / 2;
            let cy = GAP + height + BAND / 2;
            root.draw_text(label.as_ref(), &style, (cx as i32, cy as i32))?;
        }
        Ok(())
    })?;
    Ok((buf, w, h))
}

/// The heat map of the samples each pixel took ([`PixelSum::taken`]), as
/// 8-bit RGB: viridis on a log scale, from `base` samples (dark blue) to
/// `max` (yellow). Counts outside are clamped; with `max == base` every
/// pixel is dark.
#[must_use]
pub fn spp_heat_map(pixels: &[PixelSum], base: u32, max: u32) -> Vec<u8> {
    pixels
        .iter()
        .flat_map(|p| {
            let c = spp_colour(p.taken() as f64, base, max);
            [c.0, c.1, c.2]
        })
        .collect()
}

/// The viridis colour of `taken` samples on the spp map's log scale from
/// `base` to `max`.
fn spp_colour(taken: f64, base: u32, max: u32) -> RGBColor {
    use plotters::style::colors::colormaps::{ColorMap, ViridisRGB};
    let lo = (base.max(1) as f64).ln();
    let span = (max.max(base).max(1) as f64).ln() - lo;
    let t = if span > 0.0 {
        ((taken.max(1.0).ln() - lo) / span).clamp(0.0, 1.0)
    } else {
        0.0
    };
    ViridisRGB.get_color_normalized(t, 0.0, 1.0)
}

/// The width the legend's 13-pixel labels take per digit (an upper bound
/// for the bundled font's digits).
const LABEL_DIGIT_WIDTH: f64 = 8.0;

/// Where the label of tick `v` at `at` on a bar `length` long lies: the
/// first is anchored left at the bar's start, the last right at its end,
/// the others centred; extents are padded by half of a 6-pixel gap.
fn label_extent(v: u32, at: f64, first: bool, last: bool, length: f64) -> (f64, f64) {
    let w = v.to_string().len() as f64 * LABEL_DIGIT_WIDTH;
    let (lo, hi) = if first {
        (-3.0, w - 3.0)
    } else if last {
        (length + 3.0 - w, length + 3.0)
    } else {
        (at - w / 2.0, at + w / 2.0)
    };
    (lo - 3.0, hi + 3.0)
}

/// The spp values a legend from `base` to `max` labels on a log-scale bar
/// `length` pixels long: both ends and the powers of two between, thinned
/// so that no two labels overlap ([`label_extent`]).
fn legend_ticks(base: u32, max: u32, length: f64) -> Vec<u32> {
    let (base, max) = (base.max(1), max.max(base).max(1));
    let at = |v: u32| {
        if max == base {
            0.0
        } else {
            ((v as f64).ln() - (base as f64).ln()) / ((max as f64).ln() - (base as f64).ln())
                * length
        }
    };
    let extent = |v: u32, first: bool, last: bool| label_extent(v, at(v), first, last, length);
    let mut ticks = vec![base];
    let mut p = base.checked_next_power_of_two().unwrap_or(u32::MAX);
    while p < max {
        let previous = *ticks.last().expect("one tick");
        if p > base && extent(previous, ticks.len() == 1, false).1 <= extent(p, false, false).0 {
            ticks.push(p);
        }
        p = match p.checked_mul(2) {
            Some(q) => q,
            None => break,
        };
    }
    if max > base {
        // The last label always shows; it displaces the powers too near.
        let last = extent(max, false, true).0;
        while ticks.len() > 1 && extent(*ticks.last().expect("one tick"), false, false).1 > last {
            ticks.pop();
        }
        ticks.push(max);
    }
    ticks
}

/// Height of the spp map's legend band.
pub const SPP_LEGEND_HEIGHT: u32 = 46;

/// The narrowest spp map image: a map narrower than this is padded with
/// white on the right so the legend's labels fit.
pub const SPP_LEGEND_MIN_WIDTH: u32 = 240;

/// The spp map of a `width × height` window with its legend under it: the
/// heat map ([`spp_heat_map`]) in the top-left corner, then a band with
/// the colour scale from `base` to `max` samples and its spp values.
/// Returns the 8-bit RGB buffer and its size (at least
/// [`SPP_LEGEND_MIN_WIDTH`] wide, [`SPP_LEGEND_HEIGHT`] taller than the
/// map).
pub fn spp_map_with_legend(
    pixels: &[PixelSum],
    width: u32,
    height: u32,
    base: u32,
    max: u32,
) -> Result<(Vec<u8>, u32, u32)> {
    fonts()?;
    let map = spp_heat_map(pixels, base, max);
    if map.len() != width as usize * height as usize * 3 {
        bail!(
            "{} pixels do not fill a {width} x {height} map",
            pixels.len()
        );
    }
    let w = width.max(SPP_LEGEND_MIN_WIDTH);
    let h = height
        .checked_add(SPP_LEGEND_HEIGHT)
        .ok_or_else(|| anyhow::anyhow!("a map {height} pixels high is too tall"))?;
    let wu = w as usize;
    let mut buf = vec![255u8; wu * h as usize * 3];
    let row = width as usize * 3;
    for (y, line) in map.chunks_exact(row.max(1)).enumerate() {
        let at = y * wu * 3;
        buf[at..at + row].copy_from_slice(line);
    }
    // The colour bar, from base (left) to max (right).
    const MARGIN: u32 = 16;
    let (x0, x1) = (MARGIN, w - MARGIN);
    let (bar_top, bar_bottom) = (height + 6, height + 20);
    let length = f64::from(x1 - 1 - x0);
    let (lo, hi) = (
        (base.max(1) as f64).ln(),
        (max.max(base).max(1) as f64).ln(),
    );
    for x in x0..x1 {
        let t = f64::from(x - x0) / length;
        let c = spp_colour((lo + t * (hi - lo)).exp(), base, max);
        for y in bar_top..bar_bottom {
            let at = (y as usize * wu + x as usize) * 3;
            buf[at..at + 3].copy_from_slice(&[c.0, c.1, c.2]);
        }
    }
    let ticks = legend_ticks(base, max, length);
    draw_on(&mut buf, w, h, "drawing the spp legend", |root| {
        use plotters::style::text_anchor::{HPos, Pos, VPos};
        let style = |h| {
            TextStyle::from(("sans-serif", 13))
                .color(&BLACK)
                .pos(Pos::new(h, VPos::Top))
        };
        for (i, &v) in ticks.iter().enumerate() {
            let t = if hi > lo {
                ((v as f64).ln() - lo) / (hi - lo)
            } else {
                0.0
            };
            let x = x0 as i32 + (t * length).round() as i32;
            root.draw(&PathElement::new(
                vec![(x, bar_bottom as i32), (x, bar_bottom as i32 + 4)],
                BLACK,
            ))?;
            // The end labels stay inside the image: anchored at the
            // bar's ends, as legend_ticks spaces them.
            let (anchor, tx) = if i == 0 && ticks.len() > 1 {
                (HPos::Left, x0 as i32 - 3)
            } else if i + 1 == ticks.len() && ticks.len() > 1 {
                (HPos::Right, x1 as i32 + 2)
            } else {
                (HPos::Center, x)
            };
            root.draw_text(&v.to_string(), &style(anchor), (tx, bar_bottom as i32 + 6))?;
        }
        Ok(())
    })?;
    Ok((buf, w, h))
}

/// Writes an 8-bit RGB buffer as an sRGB PNG, atomically.
pub fn write_png(path: &Path, bytes: &[u8], width: u32, height: u32) -> Result<()> {
    let meta = [(
        "Software".to_string(),
        format!("strata {}", env!("CARGO_PKG_VERSION")),
    )];
    write_png_rgb8(path, width, height, bytes, Transfer::Srgb, &meta)
        .with_context(|| format!("writing `{}`", path.display()))
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn legend_ticks_label_both_ends_and_powers_of_two() {
        assert_eq!(legend_ticks(16, 256, 200.0), vec![16, 32, 64, 128, 256]);
        assert_eq!(legend_ticks(16, 16, 200.0), vec![16]);
        assert_eq!(legend_ticks(3, 100, 1000.0), vec![3, 4, 8, 16, 32, 64, 100]);
        // The last label displaces a power too near it.
        assert_eq!(legend_ticks(16, 130, 200.0), vec![16, 32, 64, 130]);
        // Thinned on a short bar, and no two labels overlap.
        for (base, max, length) in [(1, 1 << 20, 207.0), (1, u32::MAX, 207.0), (7, 9, 207.0)] {
            let t = legend_ticks(base, max, length);
            assert_eq!((t[0], *t.last().unwrap()), (base, max));
            let at = |v: u32| {
                ((v as f64).ln() - (base as f64).ln()) / ((max as f64).ln() - (base as f64).ln())
                    * length
            };
            let n = t.len();
            let extents: Vec<_> = t
                .iter()
                .enumerate()
                .map(|(i, &v)| label_extent(v, at(v), i == 0, i + 1 == n, length))
                .collect();
            for pair in extents.windows(2) {
                assert!(pair[0].1 <= pair[1].0, "{t:?}: {extents:?}");
            }
            // Inside the image: the bar starts 16 pixels in.
            assert!(extents[0].0 >= -16.0 && extents[n - 1].1 <= length + 16.0);
        }
    }

    #[test]
    fn spp_map_legend_shows_the_scale_under_the_map() {
        let p = |taken: u32| PixelSum {
            samples: taken,
            ..PixelSum::default()
        };
        // A 4 x 2 map: base, max and between.
        let pixels = [p(16), p(256), p(64), p(16), p(16), p(16), p(16), p(256)];
        let (buf, w, h) = spp_map_with_legend(&pixels, 4, 2, 16, 256).unwrap();
        assert_eq!((w, h), (SPP_LEGEND_MIN_WIDTH, 2 + SPP_LEGEND_HEIGHT));
        let px = |x: u32, y: u32| {
            let at = ((y * w + x) * 3) as usize;
            [buf[at], buf[at + 1], buf[at + 2]]
        };
        let heat = spp_heat_map(&pixels, 16, 256);
        assert_eq!(px(1, 0), [heat[3], heat[4], heat[5]]);
        assert_eq!(px(4, 0), [255; 3]); // padding
        // The bar's ends are the map's darkest and brightest colours.
        assert_eq!(px(16, 2 + 10), px(0, 0));
        assert_eq!(px(w - 17, 2 + 10), px(1, 0));
        assert_ne!(px(0, 0), px(1, 0));
        // Labels: dark pixels in the band under the bar.
        let dark = (0..w)
            .flat_map(|x| (2 + 26..h).map(move |y| (x, y)))
            .filter(|&(x, y)| px(x, y)[0] < 100)
            .count();
        assert!(dark > 20, "{dark} label pixels");
        assert!(spp_map_with_legend(&pixels, 3, 2, 16, 256).is_err());
    }

    #[test]
    fn side_by_side_places_panels_and_labels() {
        let red = [255, 0, 0].repeat(20 * 10);
        let blue = [0, 0, 255].repeat(20 * 10);
        let (buf, w, h) = side_by_side(&[("red", red), ("blue", blue)], 20, 10).unwrap();
        assert_eq!((w, h), (2 * 20 + 3 * 6, 10 + 6 + 30));
        let px = |x: u32, y: u32| {
            let at = ((y * w + x) * 3) as usize;
            [buf[at], buf[at + 1], buf[at + 2]]
        };
        assert_eq!(px(6, 6), [255, 0, 0]);
        assert_eq!(px(6 + 20 + 6, 6), [0, 0, 255]);
        assert_eq!(px(0, 0), [255, 255, 255]);
        // Some dark label pixels in the band under each panel.
        for x0 in [6, 32] {
            let dark = (x0..x0 + 20)
                .flat_map(|x| (16..h).map(move |y| (x, y)))
                .filter(|&(x, y)| px(x, y)[0] < 128)
                .count();
            assert!(dark > 5, "no label under the panel at {x0}");
        }
    }
}
