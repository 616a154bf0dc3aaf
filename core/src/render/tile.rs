//! Tiles: rectangles of the image rendered into the caller's film, one
//! group of up to 8 neighbouring pixels at a time so camera rays travel as
//! packets. Here the uniform render ([`render_tile`]), the groups and
//! their camera packets that the adaptive ([`super::adaptive`]) and
//! splatting ([`super::splat`]) renders share, and the one answer to how a
//! render's films are laid out ([`Layout`]). With the uniform and adaptive
//! renders a pixel's value depends only on its own samples; splatted, on
//! the samples within the filter's reach, added as exact integers. Either
//! way tiles, their order and threads never change a bit.

use super::RenderSettings;
use super::camera::Camera;
use super::film::PixelSum;
use super::integrator::{
    CameraSample, Integrator, Scratch, TileStats, camera_ray, differential_spacing, differentials,
    trace_path,
};
use super::lockstep::trace_lockstep;
use super::scene::Scene;
use crate::filter::PixelFilter;
use crate::sampler::Sampler;
use crate::trace::{BvhStack, HitPacket8, Ray, RayPacket8};
use core::ops::Range;
use glam::{UVec2, Vec2, Vec3};

/// A rectangle of the image: `width × height` pixels from `(x0, y0)`.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct Tile {
    /// Left column.
    pub x0: u32,
    /// Top row.
    pub y0: u32,
    /// Columns.
    pub width: u32,
    /// Rows.
    pub height: u32,
}

impl Tile {
    /// The whole `width × height` image as one tile.
    ///
    /// ```
    /// use strata::render::Tile;
    /// let t = Tile::whole(320, 180);
    /// assert_eq!((t.x0, t.y0, t.area()), (0, 0, 320 * 180));
    /// ```
    #[inline]
    #[must_use]
    pub const fn whole(width: u32, height: u32) -> Tile {
        Tile {
            x0: 0,
            y0: 0,
            width,
            height,
        }
    }

    /// Pixels in the tile.
    #[inline]
    #[must_use]
    pub fn area(&self) -> usize {
        self.width as usize * self.height as usize
    }
}
impl Tile {
    /// The tile grown by `margin` pixels on every side and clipped to a
    /// `width × height` image (of width or height 0 if nothing of it is
    /// left inside).
    ///
    /// ```
    /// use strata::render::Tile;
    /// let t = Tile { x0: 1, y0: 5, width: 4, height: 2 };
    /// assert_eq!(t.grown(2, 8, 8), Tile { x0: 0, y0: 3, width: 7, height: 5 });
    /// ```
    #[inline]
    #[must_use]
    pub fn grown(&self, margin: u32, width: u32, height: u32) -> Tile {
        let x0 = self.x0.saturating_sub(margin);
        let y0 = self.y0.saturating_sub(margin);
        let end = |start: u32, len: u32, size: u32| {
            (start as u64 + len as u64 + margin as u64).min(size as u64) as u32
        };
        let (x1, y1) = (
            end(self.x0, self.width, width),
            end(self.y0, self.height, height),
        );
        Tile {
            x0,
            y0,
            width: x1.saturating_sub(x0),
            height: y1.saturating_sub(y0),
        }
    }
}

/// Which tile renderer a render runs ([`Layout::renderer`]).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum TileRenderer {
    /// [`render_tile`]: every pixel takes its own samples, positioned by
    /// the filter's importance sampling.
    Uniform,
    /// [`render_tile_adaptive`](super::render_tile_adaptive): every pixel
    /// takes as many samples as its pilot asks for.
    Adaptive,
    /// [`render_tile_splat`](super::render_tile_splat): every sample is
    /// splatted into the pixels its filter reaches.
    Splat,
}

/// How a render's films are laid out, from its pixel filter and whether
/// it samples adaptively: the one answer to "does this render splat, and
/// with what margin". A filter with negative lobes splats, unless the
/// render is adaptive (whose pixels depend on their own samples alone, so
/// the filter is importance-sampled there as every other filter is). A
/// splatting render's tile films, and the films of its windows, hold the
/// pixels within [`Layout::margin`] around them, which their samples
/// reach.
///
/// ```
/// use strata::filter::{FilterKind, PixelFilter};
/// use strata::render::{Layout, Tile, TileRenderer};
/// let mitchell = PixelFilter::new(FilterKind::named("mitchell").unwrap(), 2.0).unwrap();
/// let splat = Layout::of(&mitchell, false);
/// assert_eq!((splat.renderer(), splat.margin()), (TileRenderer::Splat, 2));
/// let t = Tile { x0: 8, y0: 0, width: 16, height: 4 };
/// assert_eq!(splat.film_size(t), Some((20, 8)));
/// assert_eq!(Layout::of(&mitchell, true).renderer(), TileRenderer::Adaptive);
/// assert_eq!(Layout::of(&PixelFilter::BOX, false).film_size(t), Some((16, 4)));
/// ```
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct Layout {
    renderer: TileRenderer,
    margin: u32,
}

impl Layout {
    /// The layout of a render with `filter`, `adaptive` or not.
    #[inline]
    #[must_use]
    pub fn of(filter: &PixelFilter, adaptive: bool) -> Layout {
        match (adaptive, filter.splats()) {
            (true, _) => Layout {
                renderer: TileRenderer::Adaptive,
                margin: 0,
            },
            (false, true) => Layout {
                renderer: TileRenderer::Splat,
                margin: filter.splat_margin(),
            },
            (false, false) => Layout {
                renderer: TileRenderer::Uniform,
                margin: 0,
            },
        }
    }

    /// The tile renderer the render runs.
    #[inline]
    #[must_use]
    pub fn renderer(&self) -> TileRenderer {
        self.renderer
    }

    /// Whether samples are splatted into the pixels around their own.
    #[inline]
    #[must_use]
    pub fn splats(&self) -> bool {
        self.renderer == TileRenderer::Splat
    }

    /// The pixels a film holds beyond its tile or window on every side:
    /// the filter's splat margin when it splats, else 0.
    #[inline]
    #[must_use]
    pub fn margin(&self) -> u32 {
        self.margin
    }

    /// The `(width, height)` of the film the tile renderer fills for
    /// `tile`: the tile and its margin on every side (from pixel `(x0 −
    /// m, y0 − m)`, which may lie outside the image: such entries are the
    /// caller's to drop); `None` if that overflows.
    #[inline]
    #[must_use]
    pub fn film_size(&self, tile: Tile) -> Option<(u32, u32)> {
        padded(tile, self.margin)
    }

    /// The film length of [`Layout::film_size`].
    #[inline]
    #[must_use]
    pub fn film_len(&self, tile: Tile) -> Option<usize> {
        let (w, h) = self.film_size(tile)?;
        (w as usize).checked_mul(h as usize)
    }

    /// The pixels a film of `window` of a `width × height` render holds:
    /// the window and its margin, clipped to the image ([`Tile::grown`]).
    #[inline]
    #[must_use]
    pub fn extent(&self, window: Tile, width: u32, height: u32) -> Tile {
        window.grown(self.margin, width, height)
    }
}

/// Whether every sample of a render with `settings` weighs 1 (the box
/// filter's): its tiles then add with the plain add, which leaves the own
/// sums alone (they move with the sums), in an instance of their own.
#[inline(always)]
pub(super) fn unit_weights(settings: &RenderSettings) -> bool {
    settings.filter == PixelFilter::BOX
}

/// `tile`'s size with `margin` pixels on every side; `None` if that
/// overflows.
#[inline]
pub(super) fn padded(tile: Tile, margin: u32) -> Option<(u32, u32)> {
    let m2 = margin.checked_mul(2)?;
    Some((tile.width.checked_add(m2)?, tile.height.checked_add(m2)?))
}

/// Why a tile could not be rendered.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum RenderError {
    /// `max_depth` is 0.
    MaxDepth,
    /// The tile is empty or reaches outside the camera's image.
    Tile,
    /// The sampler's pattern is smaller than the adaptive maximum
    /// ([`render_tile_adaptive`](super::render_tile_adaptive)).
    SamplerTooSmall {
        /// The sampler's samples per pixel.
        spp: u32,
        /// The most samples a pixel may take.
        max: u32,
    },
    /// The film slice does not have one entry per tile pixel.
    FilmSize {
        /// Entries needed: the tile's area.
        needed: usize,
        /// Entries given.
        provided: usize,
    },
}

impl core::fmt::Display for RenderError {
    #[inline]
    fn fmt(&self, f: &mut core::fmt::Formatter<'_>) -> core::fmt::Result {
        match self {
            RenderError::MaxDepth => f.write_str("max_depth must be at least 1"),
            RenderError::Tile => f.write_str("the tile is empty or reaches outside the image"),
            RenderError::SamplerTooSmall { spp, max } => write!(
                f,
                "the sampler holds {spp} samples per pixel but adaptive sampling may take {max}"
            ),
            RenderError::FilmSize { needed, provided } => write!(
                f,
                "the film has {provided} entries where the tile needs {needed} (its pixels, and \
                 a splatted filter's margin)"
            ),
        }
    }
}

impl core::error::Error for RenderError {}
/// The checks every tile render makes before tracing anything.
pub(super) fn check_tile(
    camera: &Camera,
    settings: &RenderSettings,
    tile: Tile,
    film_len: usize,
) -> Result<(), RenderError> {
    if settings.max_depth == 0 {
        return Err(RenderError::MaxDepth);
    }
    let size = camera.size();
    let inside = tile.width > 0
        && tile.height > 0
        && tile.x0.checked_add(tile.width).is_some_and(|x| x <= size.x)
        && tile
            .y0
            .checked_add(tile.height)
            .is_some_and(|y| y <= size.y);
    if !inside {
        return Err(RenderError::Tile);
    }
    if film_len != tile.area() {
        return Err(RenderError::FilmSize {
            needed: tile.area(),
            provided: film_len,
        });
    }
    Ok(())
}
/// Up to 8 neighbouring pixels of a row, traced together: lane `l` is
/// pixel `first + (l, 0)`, with its sampler.
pub(super) struct Group<'a, 's, 'k, S> {
    scene: &'a Scene<'s>,
    /// The tile's traversal stack and counts.
    scratch: &'a mut Scratch<'k>,
    camera: &'a Camera,
    settings: &'a RenderSettings,
    first: UVec2,
    /// The differential spacing (0: no texture filtering).
    spacing: f32,
    lanes: &'a mut [S; 8],
}

impl<S: Sampler> Group<'_, '_, '_, S> {
    /// Traces sample `index` of the lanes `ids` (ascending), their camera
    /// rays as one packet (one by one for two lanes or fewer, where a
    /// packet costs as much as eight), and gives each lane's value, filter
    /// weight, rays traced and position in its pixel to `sink(lane, value,
    /// weight, rays, offset)`.
    #[inline(always)]
    pub(super) fn trace(
        &mut self,
        ids: &[usize],
        index: u32,
        sink: impl FnMut(usize, Vec3, f32, u32, Vec2),
    ) {
        if self.settings.integrator == Integrator::Lockstep {
            self.trace_with::<true>(ids, index, sink);
        } else {
            self.trace_with::<false>(ids, index, sink);
        }
    }

    /// [`Group::trace`] with the integrator fixed at compile time
    /// (`LOCKSTEP`), so the scalar loop carries no trace of the other.
    #[inline(always)]
    pub(super) fn trace_with<const LOCKSTEP: bool>(
        &mut self,
        ids: &[usize],
        index: u32,
        mut sink: impl FnMut(usize, Vec3, f32, u32, Vec2),
    ) {
        let (scene, camera, settings) = (self.scene, self.camera, self.settings);
        let mut rays = [Ray::new(Vec3::ZERO, Vec3::Z); 8];
        let mut weights = [0.0f32; 8];
        let mut offsets = [Vec2::ZERO; 8];
        let mut lens = [Vec2::ZERO; 8];
        for (k, &l) in ids.iter().enumerate() {
            let pixel = self.first + UVec2::new(l as u32, 0);
            let c = camera_ray(camera, &settings.filter, &mut self.lanes[l], pixel, index);
            (rays[k], weights[k], offsets[k], lens[k]) = (c.ray, c.weight, c.offset, c.lens);
        }
        // A packet costs about as much as 8 rays, so when adaptive sampling
        // leaves few lanes active they are traced one by one (the hits are
        // the same either way).
        let mut first = [None; 8];
        let mut hits = HitPacket8::NONE;
        let packet = ids.len() > 2;
        if packet {
            scene.closest_hit_x8_with(
                &RayPacket8::from_rays(&rays[..ids.len()]),
                &mut hits,
                self.scratch.stack,
            );
        } else {
            for (f, r) in first.iter_mut().zip(&rays[..ids.len()]) {
                *f = scene.closest_hit_with(r, self.scratch.stack);
            }
        }
        if LOCKSTEP && ids.len() > 1 {
            // Unused lanes copy lane 0, so no lane shades a made-up
            // vertex (a degenerate one would send every lane down a slow
            // path).
            for k in ids.len()..8 {
                rays[k] = rays[0];
            }
            // The lockstep tracer keeps hits as lanes.
            if !packet {
                hits = HitPacket8::from_hits(&first[..ids.len()]);
            }
            let out = self.lockstep(ids, &rays, &hits, &offsets, &lens);
            for (k, &l) in ids.iter().enumerate() {
                sink(l, out[k].0, weights[k], out[k].1, offsets[k]);
            }
            return;
        }
        if packet {
            for (k, f) in first.iter_mut().enumerate().take(ids.len()) {
                *f = hits.hit(k);
            }
        }
        for (k, &l) in ids.iter().enumerate() {
            let c = CameraSample {
                ray: rays[k],
                offset: offsets[k],
                weight: weights[k],
                lens: lens[k],
            };
            let pixel = self.first + UVec2::new(l as u32, 0);
            let diff = c.differentials(camera, pixel, self.spacing);
            let (v, rays) = trace_path(
                scene,
                self.scratch,
                &mut self.lanes[l],
                settings,
                rays[k],
                first[k],
                diff,
            );
            sink(l, v, weights[k], rays, offsets[k]);
        }
    }
}
impl<S: Sampler> Group<'_, '_, '_, S> {
    /// The paths of lanes `ids` from their camera rays and first hits, in
    /// lockstep. Not inlined: the scalar loop of [`Group::trace`] keeps
    /// the code it had.
    #[inline(never)]
    fn lockstep(
        &mut self,
        ids: &[usize],
        rays: &[Ray; 8],
        first: &HitPacket8,
        offsets: &[Vec2; 8],
        lens: &[Vec2; 8],
    ) -> [(Vec3, u32); 8] {
        // Without texture filtering there are none (and building them
        // would copy 0.5 KiB a call).
        const NONE: [Option<[Ray; 2]>; 8] = [None; 8];
        let made: [Option<[Ray; 2]>; 8];
        let diff = if self.spacing > 0.0 {
            made = core::array::from_fn(|k| self.differentials_of(ids, k, offsets, lens));
            &made
        } else {
            &NONE
        };
        let (scene, settings) = (self.scene, self.settings);
        trace_lockstep(
            scene,
            self.scratch,
            self.lanes,
            ids,
            settings,
            rays,
            first,
            diff,
        )
    }

    /// The differential rays of lane `k` (pixel lane `ids[k]`), if it is
    /// one of `ids` (the caller checks that texture filtering wants them).
    #[inline(always)]
    fn differentials_of(
        &self,
        ids: &[usize],
        k: usize,
        offsets: &[Vec2; 8],
        lens: &[Vec2; 8],
    ) -> Option<[Ray; 2]> {
        let &l = ids.get(k)?;
        let pixel = self.first + UVec2::new(l as u32, 0);
        Some(differentials(
            self.camera,
            pixel,
            offsets[k],
            lens[k],
            self.spacing,
        ))
    }
}

/// Renders samples `samples` of every pixel of `tile` and adds them to
/// `film` (row-major over the tile, one [`PixelSum`] per pixel), in place:
/// a film may collect several runs. Camera rays of up to 8 neighbouring
/// pixels are traced as one packet (one by one for two or fewer, which
/// gives the same hits). The result equals calling
/// [`pixel_sample`](super::pixel_sample) for every pixel and index and adding the values with
/// [`PixelSum::add_weighted`].
///
/// `sampler` is the prototype: its kind, spp and seed are used, its
/// current position is not. Returns what was traced.
#[inline]
pub fn render_tile<S: Sampler + Clone>(
    scene: &Scene<'_>,
    camera: &Camera,
    sampler: &S,
    settings: &RenderSettings,
    tile: Tile,
    samples: Range<u32>,
    film: &mut [PixelSum],
) -> Result<TileStats, RenderError> {
    check_tile(camera, settings, tile, film.len())?;
    let (s, c) = (scene, camera);
    Ok(match (unit_weights(settings), settings.integrator) {
        (true, Integrator::Scalar) => {
            render_tile_adding::<S, true, false>(s, c, sampler, settings, tile, samples, film)
        }
        (false, Integrator::Scalar) => {
            render_tile_adding::<S, false, false>(s, c, sampler, settings, tile, samples, film)
        }
        (true, Integrator::Lockstep) => {
            render_tile_adding::<S, true, true>(s, c, sampler, settings, tile, samples, film)
        }
        (false, Integrator::Lockstep) => {
            render_tile_adding::<S, false, true>(s, c, sampler, settings, tile, samples, film)
        }
    })
}

/// [`render_tile`] after its checks; `UNIT`: every weight is 1;
/// `LOCKSTEP`: the lockstep integrator.
#[inline]
fn render_tile_adding<S: Sampler + Clone, const UNIT: bool, const LOCKSTEP: bool>(
    scene: &Scene<'_>,
    camera: &Camera,
    sampler: &S,
    settings: &RenderSettings,
    tile: Tile,
    samples: Range<u32>,
    film: &mut [PixelSum],
) -> TileStats {
    const ALL: [usize; 8] = [0, 1, 2, 3, 4, 5, 6, 7];
    for_each_group(scene, camera, sampler, settings, tile, |group, at, n| {
        let film = &mut film[at..at + n];
        for index in samples.clone() {
            group.trace_with::<LOCKSTEP>(&ALL[..n], index, |l, v, w, _, _| {
                if UNIT {
                    film[l].add_unit(v, w);
                } else {
                    film[l].add_weighted_inline(v, w);
                }
            });
        }
    })
}
/// Calls `f` with each group of up to 8 neighbouring pixels of `tile`,
/// row by row, the index of its first pixel in the tile (row-major) and
/// its lane count. Returns what was traced.
#[inline(always)]
pub(super) fn for_each_group<S: Sampler + Clone>(
    scene: &Scene<'_>,
    camera: &Camera,
    sampler: &S,
    settings: &RenderSettings,
    tile: Tile,
    mut f: impl FnMut(&mut Group<'_, '_, '_, S>, usize, usize),
) -> TileStats {
    let mut lanes: [S; 8] = core::array::from_fn(|_| sampler.clone());
    // Zeroed once per tile, not per ray.
    let mut stack = BvhStack::new();
    let mut scratch = Scratch::new(&mut stack);
    let spacing = differential_spacing(settings, sampler.samples_per_pixel());
    for row in 0..tile.height {
        let mut col = 0;
        while col < tile.width {
            let n = (tile.width - col).min(8) as usize;
            let at = (row * tile.width + col) as usize;
            let mut group = Group {
                scene,
                scratch: &mut scratch,
                camera,
                settings,
                first: UVec2::new(tile.x0 + col, tile.y0 + row),
                spacing,
                lanes: &mut lanes,
            };
            f(&mut group, at, n);
            col += n as u32;
        }
    }
    scratch.stats
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::filter::FilterKind;

    fn filter(name: &str, r: f32) -> PixelFilter {
        PixelFilter::new(FilterKind::named(name).unwrap(), r).unwrap()
    }

    /// One rule: only filters that splat, and only without adaptive
    /// sampling, splat; then with the filter's margin, else none (a wide
    /// Gaussian is importance-sampled: its films hold no margin).
    #[test]
    fn the_layout_is_the_splat_rule() {
        for (name, r) in [
            ("box", 0.5),
            ("tent", 1.0),
            ("gaussian", 1.5),
            ("mitchell", 2.0),
            ("lanczos", 3.0),
        ] {
            let f = filter(name, r);
            let plain = Layout::of(&f, false);
            assert_eq!(plain.splats(), f.splats(), "{name}");
            assert_eq!(
                plain.margin(),
                if f.splats() { f.splat_margin() } else { 0 }
            );
            let want = if f.splats() {
                TileRenderer::Splat
            } else {
                TileRenderer::Uniform
            };
            assert_eq!(plain.renderer(), want, "{name}");
            let adaptive = Layout::of(&f, true);
            assert_eq!(
                (adaptive.renderer(), adaptive.margin()),
                (TileRenderer::Adaptive, 0)
            );
        }
        assert_eq!(filter("gaussian", 1.5).splat_margin(), 1);
    }

    #[test]
    fn films_hold_the_tile_and_the_margin_clipped_to_the_image() {
        let l = Layout::of(&filter("lanczos", 3.0), false);
        let t = Tile {
            x0: 1,
            y0: 0,
            width: 4,
            height: 2,
        };
        assert_eq!(l.film_size(t), Some((10, 8)));
        assert_eq!(l.film_len(t), Some(80));
        assert_eq!(
            l.extent(t, 6, 6),
            Tile {
                x0: 0,
                y0: 0,
                width: 6,
                height: 5
            }
        );
        // A window at the far edge: clipped there.
        let edge = Tile {
            x0: 5,
            y0: 5,
            width: 1,
            height: 1,
        };
        assert_eq!(
            l.extent(edge, 6, 6),
            Tile {
                x0: 2,
                y0: 2,
                width: 4,
                height: 4
            }
        );
        // Sizes that overflow are refused, not wrapped.
        let huge = Tile {
            x0: 0,
            y0: 0,
            width: u32::MAX - 2,
            height: 1,
        };
        assert_eq!(l.film_size(huge), None);
        assert_eq!(l.film_len(huge), None);
    }
}
