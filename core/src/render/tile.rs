//! Tiles: rectangles of the image rendered into the caller's film, one
//! group of up to 8 neighbouring pixels at a time so camera rays travel as
//! packets; uniformly ([`render_tile`]), adaptively
//! ([`render_tile_adaptive`]) or splatting a filter with negative lobes
//! ([`render_tile_splat`]). With the first two a pixel's value depends
//! only on its own samples; splatted, on the samples within the filter's
//! reach, added as exact integers. Either way tiles, their order and
//! threads never change a bit.

use super::RenderSettings;
use super::adaptive::{Adaptive, PilotStats};
use super::camera::Camera;
use super::film::{MAX_SAMPLE_VALUE, PixelSum};
use super::integrator::{CameraSample, Scratch, camera_ray, differential_spacing, trace_path};
use super::scene::Scene;
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

/// What rendering a tile traced.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub struct TileStats {
    /// Camera paths (pixel samples).
    pub paths: u64,
    /// Closest-hit rays: camera rays and bounces.
    pub rays: u64,
    /// Any-hit shadow rays of direct lighting.
    pub shadow_rays: u64,
}

impl TileStats {
    /// Adds another tile's counts.
    #[inline]
    pub fn add(&mut self, other: &TileStats) {
        self.paths += other.paths;
        self.rays += other.rays;
        self.shadow_rays += other.shadow_rays;
    }
}

/// Why a tile could not be rendered.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum RenderError {
    /// `max_depth` is 0.
    MaxDepth,
    /// The tile is empty or reaches outside the camera's image.
    Tile,
    /// The sampler's pattern is smaller than the adaptive maximum
    /// ([`render_tile_adaptive`]).
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
fn check_tile(
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
struct Group<'a, 's, 'k, S> {
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
    fn trace(
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
        if ids.len() > 2 {
            let mut hits = HitPacket8::NONE;
            scene.closest_hit_x8_with(
                &RayPacket8::from_rays(&rays[..ids.len()]),
                &mut hits,
                self.scratch.stack,
            );
            for (k, f) in first.iter_mut().enumerate().take(ids.len()) {
                *f = hits.hit(k);
            }
        } else {
            for (f, r) in first.iter_mut().zip(&rays[..ids.len()]) {
                *f = scene.closest_hit_with(r, self.scratch.stack);
            }
        }
        for (k, &l) in ids.iter().enumerate() {
            let before = self.scratch.stats.rays + self.scratch.stats.shadow_rays;
            let c = CameraSample {
                ray: rays[k],
                offset: offsets[k],
                weight: weights[k],
                lens: lens[k],
            };
            let pixel = self.first + UVec2::new(l as u32, 0);
            let diff = c.differentials(camera, pixel, self.spacing);
            let v = trace_path(
                scene,
                self.scratch,
                &mut self.lanes[l],
                settings,
                rays[k],
                first[k],
                diff,
            );
            let rays = self.scratch.stats.rays + self.scratch.stats.shadow_rays - before;
            sink(l, v, weights[k], rays as u32, offsets[k]);
        }
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
    // The box's weights are 1: its instance adds with the plain add, which
    // leaves the own sums alone (they move with the sums).
    Ok(if settings.filter == crate::filter::PixelFilter::BOX {
        render_tile_adding::<S, true>(scene, camera, sampler, settings, tile, samples, film)
    } else {
        render_tile_adding::<S, false>(scene, camera, sampler, settings, tile, samples, film)
    })
}

/// [`render_tile`] after its checks; `UNIT`: every weight is 1.
#[inline]
fn render_tile_adding<S: Sampler + Clone, const UNIT: bool>(
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
            group.trace(&ALL[..n], index, |l, v, w, _, _| {
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
fn for_each_group<S: Sampler + Clone>(
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

/// Renders every pixel of `tile` adaptively and writes it to `film`
/// (row-major over the tile; what was there is replaced): each pixel holds
/// its blended value (its `weight` is `2²⁴` times its kept samples, not a
/// filter-weight sum) and its sample count as `samples + dropped`, as
/// [`Adaptive`] describes: the pilot's two blocks, then the rest the
/// pilot asks for, joined by [`PixelSum::blend`] with weights that never
/// depend on the samples they weigh. A pixel depends on its own samples
/// alone, so tiles, threads and windows do not change it.
///
/// `sampler` is the prototype; its pattern must hold every index a pixel
/// may take (`samples_per_pixel() ≥ adaptive.max()`, else
/// [`RenderError::SamplerTooSmall`]), and each block should spread over
/// the pixel: [`UniformGrid`](crate::UniformGrid) fills its grid in
/// raster order, so its blocks cover a few rows each and adaptive renders
/// with it are biased.
///
/// ```
/// use glam::{UVec2, Vec3};
/// use strata::render::*;
/// use strata::trace::{Sphere, SphereChunk8};
/// use strata::Independent;
/// // A diffuse sphere on a diffuse ground under a flat white sky.
/// let spheres = [
///     Sphere::new(Vec3::new(-1.0, 0.0, 0.0), 1.0),
///     Sphere::new(Vec3::new(0.0, -101.0, 0.0), 100.0),
/// ];
/// let materials = [Material::Lambertian { albedo: Texture::Solid(Vec3::splat(0.5)) }];
/// const SIZE: SceneStorageSize = SceneStorageSize::for_spheres(2, false);
/// let (mut chunks, mut lights) = ([SphereChunk8::EMPTY; SIZE.chunks], [0u32; SIZE.lights]);
/// let storage = SceneStorage {
///     chunks: &mut chunks, lights: &mut lights,
///     bvh_nodes: &mut [], bvh_lanes: &mut [], bvh_ids: &mut [],
/// };
/// let sky = Background::Flat(Vec3::ONE);
/// let scene = Scene::build(&spheres, &materials, &[0, 0], sky, storage).unwrap();
/// let desc = CameraDesc {
///     look_from: Vec3::new(0.0, 0.0, 5.0), look_at: Vec3::ZERO, up: Vec3::Y,
///     vfov_deg: 40.0, defocus_angle_deg: 0.0, focus_dist: 5.0,
/// };
/// let camera = Camera::new(&desc, 8, 4).unwrap();
/// let settings = RenderSettings { max_depth: 8, direct_lighting: true, filter: PixelFilter::BOX,
///     texture_filter: TextureFilter::None };
/// let adaptive = Adaptive::new(8, 64, 0.002).unwrap();
/// let tile = Tile { x0: 0, y0: 0, width: 8, height: 4 };
/// let mut film = [PixelSum::ZERO; 32];
/// let sampler = Independent::new(64, 1).unwrap();
/// render_tile_adaptive(&scene, &camera, &sampler, &settings, tile, adaptive, &mut film).unwrap();
/// let taken = |x: usize, y: usize| film[y * 8 + x].samples;
/// assert!(taken(2, 2) > 8); // on the sphere, lit by the sky and the ground
/// assert_eq!(taken(7, 0), 8); // the flat sky: no variance, the pilot only
/// ```
#[inline]
pub fn render_tile_adaptive<S: Sampler + Clone>(
    scene: &Scene<'_>,
    camera: &Camera,
    sampler: &S,
    settings: &RenderSettings,
    tile: Tile,
    adaptive: Adaptive,
    film: &mut [PixelSum],
) -> Result<TileStats, RenderError> {
    check_tile(camera, settings, tile, film.len())?;
    if sampler.samples_per_pixel() < adaptive.max() {
        return Err(RenderError::SamplerTooSmall {
            spp: sampler.samples_per_pixel(),
            max: adaptive.max(),
        });
    }
    // As in `render_tile`: the box's instance adds with the plain add.
    Ok(if settings.filter == crate::filter::PixelFilter::BOX {
        render_tile_adaptive_adding::<S, true>(
            scene, camera, sampler, settings, tile, adaptive, film,
        )
    } else {
        render_tile_adaptive_adding::<S, false>(
            scene, camera, sampler, settings, tile, adaptive, film,
        )
    })
}

/// [`render_tile_adaptive`] after its checks; `UNIT`: every weight is 1.
#[inline]
fn render_tile_adaptive_adding<S: Sampler + Clone, const UNIT: bool>(
    scene: &Scene<'_>,
    camera: &Camera,
    sampler: &S,
    settings: &RenderSettings,
    tile: Tile,
    adaptive: Adaptive,
    film: &mut [PixelSum],
) -> TileStats {
    let b = adaptive.block();
    let add = |sum: &mut PixelSum, v: Vec3, w: f32| {
        if UNIT {
            sum.add_unit(v, w);
        } else {
            sum.add_weighted(v, w);
        }
    };
    for_each_group(scene, camera, sampler, settings, tile, |group, at, n| {
        let film = &mut film[at..at + n];
        // Each lane's pilot halves and rest, and the halves' statistics.
        let mut parts = [[PixelSum::ZERO; 3]; 8];
        let mut pilots = [[PilotStats::ZERO; 2]; 8];
        let mut rests = [0u32; 8];
        let mut weights = [[0.0f64; 3]; 8];
        // One trace site for the pilot and the rest (two would inline the
        // path tracer twice, at a measured ~6 % per sample): the pilot's
        // two blocks, then the rest in index order, where the lanes still
        // sampling trace each index together so their camera rays stay one
        // packet.
        let mut ids = [0usize, 1, 2, 3, 4, 5, 6, 7];
        let mut m = n;
        let mut end = 2 * b;
        let mut index = 0;
        while index < end {
            let h = if index < 2 * b {
                (index / b) as usize
            } else {
                let mut kept = 0;
                for k in 0..m {
                    if index - 2 * b < rests[ids[k]] {
                        ids[kept] = ids[k];
                        kept += 1;
                    }
                }
                m = kept;
                2
            };
            group.trace(&ids[..m], index, |l, v, w, rays, _| {
                add(&mut parts[l][h], v, w);
                if h < 2 {
                    // A literal 1 lets the box's instance fold the weight
                    // products (the same values: w = 1 exactly).
                    pilots[l][h].add(v, if UNIT { 1.0 } else { w }, rays);
                }
            });
            index += 1;
            if index == 2 * b {
                for l in 0..n {
                    let [a, bh] = pilots[l];
                    let mut both = a;
                    both.merge(&bh);
                    rests[l] = adaptive.rest_for(&both);
                    let [ca, cb] =
                        adaptive.pilot_weights(adaptive.rest_for(&a), adaptive.rest_for(&bh));
                    // A pilot half with no kept sample gives its weight to
                    // the rest, whose weight then still depends on the
                    // pilot only.
                    let ca = if parts[l][0].samples == 0 { 0.0 } else { ca };
                    let cb = if parts[l][1].samples == 0 { 0.0 } else { cb };
                    weights[l] = [ca, cb, 1.0 - ca - cb];
                }
                end += rests[..n].iter().max().copied().unwrap_or(0);
            }
        }
        for l in 0..n {
            let blended = PixelSum::blend(&[
                (parts[l][0], weights[l][0]),
                (parts[l][1], weights[l][1]),
                (parts[l][2], weights[l][2]),
            ]);
            // Written, not added: a blend's `weight` is 2²⁴·n, not a
            // filter-weight sum, so it does not merge with one.
            film[l] = blended;
        }
    })
}

/// The most pixels a splat reaches along an axis: `2m + 1` for the
/// largest margin, that of [`FILTER_MAX_RADIUS`](crate::filter::FILTER_MAX_RADIUS).
pub const SPLAT_SIDE: usize = crate::filter::TAPS;
// The margin of the largest radius is ⌈r + ½⌉ − 1 = r for an integer r.
const _: () = assert!(crate::filter::FILTER_MAX_RADIUS == 8.0);

/// Fixed-point scale of a splat's filter values: `2⁻¹²` per axis, so
/// their product is in the film's units of `2⁻²⁴`.
const SPLAT_FILTER_SCALE: f32 = 4096.0;
/// Fixed-point scale of a splatted radiance: `2⁻¹⁸`.
const SPLAT_RADIANCE_SCALE: f32 = 262_144.0;

/// One splatted sample in fixed point: its radiance (clamped to
/// `±MAX_SAMPLE_VALUE`, in units of `2⁻¹⁸`) and the filter per axis at
/// the centres around its pixel (units of `2⁻¹²`). A target pixel `(dx,
/// dy)` of the `(2m + 1)²` around it (its own at `(m, m)`) gets the
/// weight `Fx·Fy` (units `2⁻²⁴`, the film's) and the sums `Fx·Fy·L`
/// rounded to the film's units, all in integers: each target costs a few
/// integer multiplies instead of four float roundings, and the bits are
/// the same on every CPU and in any order of addition.
///
/// ```
/// use glam::{Vec2, Vec3};
/// use strata::filter::{FilterKind, PixelFilter};
/// use strata::render::{PixelSum, Splat};
/// let mitchell = PixelFilter::new(FilterKind::named("mitchell").unwrap(), 2.0).unwrap();
/// let s = Splat::new(&mitchell, Vec2::splat(0.5), Vec3::splat(0.25)).unwrap();
/// let mut own = PixelSum::ZERO;
/// s.add_to(&mut own, 2, 2, true); // the centre of the 5 × 5 it reaches
/// assert_eq!(own.samples, 1);
/// // f·L is rounded to the film's 2⁻²⁴: within a unit of the radiance.
/// assert!((own.mean() - Vec3::splat(0.25)).abs().max_element() < 1e-6);
/// assert!(Splat::new(&mitchell, Vec2::ZERO, Vec3::NAN).is_none());
/// ```
#[derive(Clone, Copy, Debug)]
pub struct Splat {
    l: [i64; 3],
    /// The radiance in the film's units, for its own pixel's box sum.
    own: [i64; 3],
    /// Every filter value within `±2¹⁴` units (`±4`): no product
    /// overflows, so [`Splat::add_square`] needs no saturating multiplies.
    small: bool,
    fx: [i64; SPLAT_SIDE],
    fy: [i64; SPLAT_SIDE],
}

impl Splat {
    /// The splat of radiance `l` at offset `u` (from the pixel's corner,
    /// in `[0, 1)²`) under `filter`; `None` if `l` is not finite.
    #[inline]
    #[must_use]
    pub fn new(filter: &crate::filter::PixelFilter, u: Vec2, l: Vec3) -> Option<Splat> {
        if !l.is_finite() {
            return None;
        }
        let lc = l.clamp(
            Vec3::splat(-MAX_SAMPLE_VALUE),
            Vec3::splat(MAX_SAMPLE_VALUE),
        );
        // The centre `k` pixels from the sample's own is `u − ½ − k` away.
        let (tx, ty) = (filter.eval_taps(u.x - 0.5), filter.eval_taps(u.y - 0.5));
        let (fx, fy) = (
            fixed_taps(&tx, SPLAT_FILTER_SCALE)
                .unwrap_or_else(|| tx.map(|t| fixed(t, SPLAT_FILTER_SCALE))),
            fixed_taps(&ty, SPLAT_FILTER_SCALE)
                .unwrap_or_else(|| ty.map(|t| fixed(t, SPLAT_FILTER_SCALE))),
        );
        let small = |f: &[i64; SPLAT_SIDE]| f.iter().all(|v| v.unsigned_abs() <= 1 << 14);
        Some(Splat {
            l: lc.to_array().map(|c| fixed(c, SPLAT_RADIANCE_SCALE)),
            own: lc.to_array().map(super::film::to_fixed),
            small: small(&fx) && small(&fy),
            fx,
            fy,
        })
    }

    /// The weight the target `(dx, dy)` gets, in the film's units.
    #[inline]
    #[must_use]
    pub fn weight(&self, dx: usize, dy: usize) -> i64 {
        self.fx[dx].saturating_mul(self.fy[dy])
    }

    /// Adds the splat to target `(dx, dy)`'s accumulator, counting it as
    /// one of that pixel's samples (and its radiance in the pixel's own
    /// sum, [`PixelSum::own`]) if `own`.
    #[inline]
    pub fn add_to(&self, pixel: &mut PixelSum, dx: usize, dy: usize, own: bool) {
        let before = pixel.sum;
        self.add_sums(pixel, dx, dy);
        // The own sum does not move with the sums: own − sum moves
        // against them (as saturated).
        for ((o, s), b) in pixel.own_minus_sum.iter_mut().zip(pixel.sum).zip(before) {
            *o = o.wrapping_sub(s.wrapping_sub(b));
        }
        if own {
            self.add_own(pixel);
        }
    }

    /// `f·L` and `f` to target `(dx, dy)`'s sums, leaving `own_minus_sum`.
    #[inline]
    fn add_sums(&self, pixel: &mut PixelSum, dx: usize, dy: usize) {
        let f = self.weight(dx, dy);
        if f != 0 {
            for (s, l) in pixel.sum.iter_mut().zip(self.l) {
                // f·L in units of 2⁻⁴², rounded (half up) to 2⁻²⁴. With
                // |L| ≤ 2¹⁶ (2³⁴ units) it fits an i64 while |f| < 32
                // (2²⁹ units), true of every usual filter; beyond, it
                // saturates.
                let v = f.saturating_mul(l).saturating_add(1 << 17) >> 18;
                *s = s.saturating_add(v);
            }
            pixel.weight = pixel.weight.saturating_add(f);
        }
    }

    /// Counts the splat as one of `pixel`'s own samples: its radiance to
    /// the own sum (here `own_minus_sum`, whose sum part the caller keeps
    /// right), and the sample count.
    #[inline]
    pub(crate) fn add_own(&self, pixel: &mut PixelSum) {
        for (o, l) in pixel.own_minus_sum.iter_mut().zip(self.own) {
            *o = o.wrapping_add(l);
        }
        pixel.samples = pixel.samples.saturating_add(1);
    }

    /// Adds the splat to its `side × side` targets, target `(dx, dy)` at
    /// `film[first + dy·stride + dx]` (none counted as a sample):
    /// [`Splat::add_to`] on each, but for `own_minus_sum`, which it leaves
    /// (the caller takes the sums' change off it once, after all splats). Where the values are small enough for
    /// no product to overflow (`|Fx·L| ≤ 2⁴⁸`, `|Fx·Fy·L| ≤ 2⁶²`) the
    /// products `Fx·L` are formed once per column and the weight rides
    /// along as a fourth channel of radiance `2¹⁸` (`(Fx·Fy·2¹⁸ + 2¹⁷) >>
    /// 18 = Fx·Fy`): the same sums, four lanes of one multiply, add and
    /// shift per target. `SATURATE = false` adds with plain (wrapping)
    /// adds: the caller's promise that no sum reaches `i64`'s end (see
    /// [`Splat::reach`]), where they give the saturating adds' sums.
    #[inline]
    fn add_square<const SATURATE: bool>(
        &self,
        film: &mut [PixelSum],
        first: usize,
        stride: usize,
        side: usize,
    ) {
        if !self.small {
            for dy in 0..side {
                let row = first + dy * stride;
                for (dx, p) in film[row..row + side].iter_mut().enumerate() {
                    self.add_sums(p, dx, dy);
                }
            }
            return;
        }
        // Columns of zero weight (a radius below the margin's reach, as
        // Lanczos-3's outer column on the far side) are skipped.
        let fx = &self.fx[..side];
        let lo = fx.iter().position(|&f| f != 0).unwrap_or(side);
        let hi = fx.iter().rposition(|&f| f != 0).map_or(lo, |i| i + 1);
        let mut columns = [[0i64; 4]; SPLAT_SIDE];
        for (g, &fx) in columns.iter_mut().zip(&fx[lo..hi]) {
            *g = [fx * self.l[0], fx * self.l[1], fx * self.l[2], fx << 18];
        }
        for (dy, &fy) in self.fy[..side].iter().enumerate() {
            if fy == 0 {
                continue;
            }
            let row = first + dy * stride;
            for (p, g) in film[row + lo..row + hi].iter_mut().zip(&columns) {
                let v: [i64; 4] = core::array::from_fn(|c| (fy * g[c] + (1 << 17)) >> 18);
                let add = |s: i64, v: i64| {
                    if SATURATE {
                        s.saturating_add(v)
                    } else {
                        s.wrapping_add(v)
                    }
                };
                for (s, v) in p.sum.iter_mut().zip(v) {
                    *s = add(*s, v);
                }
                p.weight = add(p.weight, v[3]);
            }
        }
    }

    /// The most this splat changes any one sum of any target, when
    /// `small`: `|(f·L + 2¹⁷) >> 18| ≤ (|f|·|L| >> 18) + 1`, with the
    /// weight's lane as radiance 2¹⁸ (`None` when not `small`).
    #[inline]
    fn reach(&self) -> Option<i64> {
        let most = |f: &[i64; SPLAT_SIDE]| f.iter().fold(0, |m, v| m.max(v.abs()));
        let l = self.l.iter().fold(1 << 18, |m: i64, v| m.max(v.abs()));
        // |f| ≤ 2²⁸ and |L| ≤ 2³⁴ (clamped): the product fits.
        self.small
            .then(|| ((most(&self.fx) * most(&self.fy) * l) >> 18) + 1)
    }
}

/// `x·scale` rounded half away from zero, exactly, as the film's
/// `to_fixed` (saturating beyond `i64`).
#[inline]
fn fixed(x: f32, scale: f32) -> i64 {
    let y = x * scale;
    let t = y as i64;
    let frac = y - t as f32;
    t + (frac >= 0.5) as i64 - (frac <= -0.5) as i64
}

/// `x·scale` rounded half away from zero, as [`fixed`],
/// for every tap at once, or `None` if some `|x·scale|` is not below
/// 2²²: the rounding by the float's own (to even, in `[2²³, 2²⁴)`, where
/// the integer is the bits' low part) corrected at ties, in a loop of
/// plain lane operations that compilers vectorise, where the saturating
/// `as i64` is a branchy scalar conversion per tap.
#[inline]
fn fixed_taps(x: &[f32; SPLAT_SIDE], scale: f32) -> Option<[i64; SPLAT_SIDE]> {
    const BIG: f32 = 8_388_608.0; // 2²³
    let mut out = [0i64; SPLAT_SIDE];
    let mut small = true;
    for (o, &x) in out.iter_mut().zip(x) {
        let y = x * scale;
        let a = y.abs();
        small &= a < 4_194_304.0; // 2²², false for NaN
        let shifted = a + BIG;
        let t = shifted.to_bits() as i32 - BIG.to_bits() as i32;
        // To even gave `t` below a tie `a = t + ½`; away from zero wants
        // one more.
        let t = t + (a - (shifted - BIG) == 0.5) as i32;
        *o = i64::from(if y < 0.0 { -t } else { t });
    }
    small.then_some(out)
}

/// The film a splatted render of `tile` fills: the tile and a margin of
/// [`PixelFilter::splat_margin`](crate::filter::PixelFilter::splat_margin)
/// pixels on every side, `(width + 2m) × (height + 2m)` entries row-major
/// from pixel `(x0 − m, y0 − m)` (which may lie outside the image: such
/// entries are the caller's to drop). `None` if that overflows.
///
/// ```
/// use strata::filter::{FilterKind, PixelFilter};
/// use strata::render::{Tile, splat_film_size};
/// let mitchell = PixelFilter::new(FilterKind::named("mitchell").unwrap(), 2.0).unwrap();
/// let t = Tile { x0: 8, y0: 0, width: 16, height: 4 };
/// assert_eq!(splat_film_size(&mitchell, t), Some((20, 8)));
/// ```
#[inline]
#[must_use]
pub fn splat_film_size(filter: &crate::filter::PixelFilter, tile: Tile) -> Option<(u32, u32)> {
    let m2 = filter.splat_margin().checked_mul(2)?;
    Some((tile.width.checked_add(m2)?, tile.height.checked_add(m2)?))
}

/// Renders samples `samples` of every pixel of `tile` and splats each into
/// the pixels its filter (`settings.filter`) reaches, adding to `film`,
/// the tile and its margin ([`splat_film_size`]): a sample at `x`, with
/// radiance `L`, adds `f(x − c)·L` and `f(x − c)` to every pixel of
/// centre `c` within the filter's radius, in fixed point ([`Splat`]), and
/// counts as a sample of its own pixel only (a sample that is not finite
/// counts as dropped there and adds nothing). Positions are uniform in the
/// pixel (the box's), and the tracing is the box render's. A pixel's value
/// `Σ f·L / Σ f` gathers every sample near it, and where radiance is
/// constant it is that constant whatever the weights' signs, to the
/// fixed point's rounding of each product (exactly for radiance 1, as
/// `horizon`'s sky: each product is then an integer).
///
/// Sums are exact integers, so films of tiles, threads and sample runs
/// add to the same bits in any order; a pixel near a tile's edge gets its
/// value once the neighbouring tiles' margins are added.
#[inline]
pub fn render_tile_splat<S: Sampler + Clone>(
    scene: &Scene<'_>,
    camera: &Camera,
    sampler: &S,
    settings: &RenderSettings,
    tile: Tile,
    samples: Range<u32>,
    film: &mut [PixelSum],
) -> Result<TileStats, RenderError> {
    let filter = settings.filter;
    let (pw, ph) = splat_film_size(&filter, tile).ok_or(RenderError::Tile)?;
    let needed = pw as usize * ph as usize;
    check_tile(camera, settings, tile, tile.area())?;
    if film.len() != needed {
        return Err(RenderError::FilmSize {
            needed,
            provided: film.len(),
        });
    }
    let (m, pw) = (filter.splat_margin() as usize, pw as usize);
    let side = 2 * m + 1;
    debug_assert!(side <= SPLAT_SIDE);
    // Positions come from the box, so the tracing is the box render's.
    let boxed = RenderSettings {
        filter: crate::filter::PixelFilter::BOX,
        ..*settings
    };
    const ALL: [usize; 8] = [0, 1, 2, 3, 4, 5, 6, 7];
    let width = tile.width as usize;
    // Saturating adds are needed only near `i64`'s end: while the film's
    // largest sum plus every splat's largest change (`Splat::reach`)
    // stays within 2⁶², plain adds give the same sums, cheaper.
    let largest = film
        .iter()
        .flat_map(|p| p.sum.iter().chain([&p.weight]))
        .fold(0u64, |m, v| m.max(v.unsigned_abs()));
    let mut headroom = (1i64 << 62) - largest.min(1 << 62) as i64;
    // `own_minus_sum` is own − sum, but the splats below move the sums
    // without it: it holds own − sum + sum = own while they run (wrapping
    // adds, exact), and the final sums come off after.
    for p in film.iter_mut() {
        for (o, s) in p.own_minus_sum.iter_mut().zip(p.sum) {
            *o = o.wrapping_add(s);
        }
    }
    let stats = for_each_group(scene, camera, sampler, &boxed, tile, |group, at, n| {
        // The group's first pixel's top-left splat target in the
        // padded film (its own pixel is m further right and down).
        let (gx, gy) = (at % width, at / width);
        for index in samples.clone() {
            group.trace(&ALL[..n], index, |l, v, _, _, u| {
                let own = (gy + m) * pw + gx + l + m;
                let Some(splat) = Splat::new(&filter, u, v) else {
                    // Counted as dropped by its own pixel only.
                    film[own].dropped = film[own].dropped.saturating_add(1);
                    return;
                };
                let first = gy * pw + gx + l;
                match splat.reach() {
                    Some(r) if r <= headroom => {
                        headroom -= r;
                        splat.add_square::<false>(film, first, pw, side);
                    }
                    _ => {
                        // Uncharged, this splat may bring a sum near
                        // i64's end: every later one saturates too.
                        headroom = 0;
                        splat.add_square::<true>(film, first, pw, side);
                    }
                }
                splat.add_own(&mut film[own]);
            });
        }
    });
    for p in film.iter_mut() {
        for (o, s) in p.own_minus_sum.iter_mut().zip(p.sum) {
            *o = o.wrapping_sub(s);
        }
    }
    Ok(stats)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn fixed_taps_round_as_fixed_does() {
        // Ties (x·scale = k + ½) both ways, values near the 2²² bound, a
        // NaN and the bound itself (which send every tap the slow way).
        let mut values = [0.0f32; SPLAT_SIDE];
        let mut seen = 0;
        for i in -3000i32..3000 {
            let base = i as f32 * 0.33;
            let ties = [(i as f32 + 0.5) / 4096.0, (i as f32 - 0.5) / 4096.0];
            for (j, x) in [base, -base, ties[0], ties[1], base * 1e-3]
                .into_iter()
                .enumerate()
            {
                values[(i.unsigned_abs() as usize + j) % SPLAT_SIDE] = x;
            }
            let got = fixed_taps(&values, SPLAT_FILTER_SCALE).unwrap();
            assert_eq!(got, values.map(|x| fixed(x, SPLAT_FILTER_SCALE)));
            seen += 1;
        }
        assert_eq!(seen, 6000);
        let edge = 4_194_303.5 / SPLAT_FILTER_SCALE;
        values[3] = edge;
        assert_eq!(
            fixed_taps(&values, SPLAT_FILTER_SCALE).unwrap()[3],
            fixed(edge, SPLAT_FILTER_SCALE)
        );
        values[3] = 4_194_304.0 / SPLAT_FILTER_SCALE;
        assert!(fixed_taps(&values, SPLAT_FILTER_SCALE).is_none());
        values[3] = f32::NAN;
        assert!(fixed_taps(&values, SPLAT_FILTER_SCALE).is_none());
    }

    #[test]
    fn plain_and_saturating_squares_add_the_same_sums_unless_they_overflow() {
        use crate::filter::{FilterKind, PixelFilter};
        let f = PixelFilter::new(FilterKind::Lanczos { tau: 3.0 }, 3.0).unwrap();
        let side = 2 * f.splat_margin() as usize + 1;
        let splat = Splat::new(&f, Vec2::new(0.3, 0.8), Vec3::new(0.5, 2.0, 900.0)).unwrap();
        let reach = splat.reach().unwrap();
        assert_eq!(side, 7);
        let start: [PixelSum; 49] = core::array::from_fn(|i| PixelSum {
            sum: [i as i64 * 1_000_003, -(i as i64), 7],
            weight: 1 << 30,
            ..PixelSum::ZERO
        });
        let (mut plain, mut saturating, mut one_by_one) = (start, start, start);
        // add_square leaves own − sum to its caller, which takes the sums'
        // change off it once.
        let settle = |after: &mut [PixelSum; 49], before: &[PixelSum; 49]| {
            for (a, b) in after.iter_mut().zip(before) {
                for c in 0..3 {
                    let moved = a.sum[c].wrapping_sub(b.sum[c]);
                    a.own_minus_sum[c] = a.own_minus_sum[c].wrapping_sub(moved);
                }
            }
        };
        splat.add_square::<false>(&mut plain, 0, side, side);
        splat.add_square::<true>(&mut saturating, 0, side, side);
        settle(&mut plain, &start);
        settle(&mut saturating, &start);
        for dy in 0..side {
            for dx in 0..side {
                splat.add_to(&mut one_by_one[dy * side + dx], dx, dy, false);
            }
        }
        assert_eq!(plain, saturating);
        assert_eq!(plain, one_by_one);
        // The reach bounds every change.
        for (a, b) in plain.iter().zip(&start) {
            for (x, y) in a
                .sum
                .iter()
                .chain([&a.weight])
                .zip(b.sum.iter().chain([&b.weight]))
            {
                assert!((x - y).abs() <= reach);
            }
        }
        // Near i64's end only the saturating adds are right.
        let full = [PixelSum {
            sum: [i64::MAX; 3],
            weight: i64::MAX,
            ..PixelSum::ZERO
        }; 49];
        let mut saturated = full;
        splat.add_square::<true>(&mut saturated, 0, side, side);
        settle(&mut saturated, &full);
        let mut want = full;
        for dy in 0..side {
            for dx in 0..side {
                splat.add_to(&mut want[dy * side + dx], dx, dy, false);
            }
        }
        assert_eq!(saturated, want);
        assert!(saturated.iter().any(|p| p.sum[2] == i64::MAX));
    }
}
