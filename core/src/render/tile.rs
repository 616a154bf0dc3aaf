//! Tiles: rectangles of the image rendered into the caller's film, one
//! group of up to 8 neighbouring pixels at a time so camera rays travel as
//! packets; uniformly ([`render_tile`]) or adaptively
//! ([`render_tile_adaptive`]). A pixel's value depends only on its own
//! samples, so tiles, their order and threads never change a bit.

use super::RenderSettings;
use super::adaptive::{Adaptive, PixelError};
use super::camera::Camera;
use super::film::PixelSum;
use super::integrator::{Scratch, camera_ray, differential_spacing, trace_path};
use super::scene::Scene;
use crate::sampler::Sampler;
use crate::trace::{BvhStack, HitPacket8, Ray, RayPacket8};
use core::ops::Range;
use glam::{UVec2, Vec3};

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
                "the film has {provided} entries for a tile of {needed} pixels"
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
/// pixel `first + (l, 0)`, with its sampler and its film entry.
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
    film: &'a mut [PixelSum],
}

impl<S: Sampler> Group<'_, '_, '_, S> {
    /// Traces sample `index` of the lanes `ids` (ascending), their camera
    /// rays as one packet (one by one for two lanes or fewer, where a
    /// packet costs as much as eight), and adds each value to its pixel and, when
    /// sampling adaptively, to its error statistics.
    #[inline(always)]
    fn trace(&mut self, ids: &[usize], index: u32, mut errors: Option<&mut [PixelError; 8]>) {
        let (scene, camera, settings) = (self.scene, self.camera, self.settings);
        let mut rays = [Ray::new(Vec3::ZERO, Vec3::Z); 8];
        let mut weights = [0.0f32; 8];
        let mut diffs = [None; 8];
        for (k, &l) in ids.iter().enumerate() {
            let pixel = self.first + UVec2::new(l as u32, 0);
            let c = camera_ray(
                camera,
                &settings.filter,
                self.spacing,
                &mut self.lanes[l],
                pixel,
                index,
            );
            (rays[k], weights[k], diffs[k]) = (c.ray, c.weight, c.diff);
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
            let v = trace_path(
                scene,
                self.scratch,
                &mut self.lanes[l],
                settings,
                rays[k],
                first[k],
                diffs[k],
            );
            self.film[l].add_weighted(v, weights[k]);
            if let Some(e) = errors.as_deref_mut() {
                e[l].add(v, weights[k]);
            }
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
    const ALL: [usize; 8] = [0, 1, 2, 3, 4, 5, 6, 7];
    Ok(for_each_group(
        scene,
        camera,
        sampler,
        settings,
        tile,
        film,
        |group, n| {
            for index in samples.clone() {
                group.trace(&ALL[..n], index, None);
            }
        },
    ))
}

/// Calls `f` with each group of up to 8 neighbouring pixels of `tile`,
/// row by row, and its lane count; each group's film entries are its
/// slice of `film` (row-major over the tile). Returns what was traced.
#[inline(always)]
fn for_each_group<S: Sampler + Clone>(
    scene: &Scene<'_>,
    camera: &Camera,
    sampler: &S,
    settings: &RenderSettings,
    tile: Tile,
    film: &mut [PixelSum],
    mut f: impl FnMut(&mut Group<'_, '_, '_, S>, usize),
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
                film: &mut film[at..at + n],
            };
            f(&mut group, n);
            col += n as u32;
        }
    }
    scratch.stats
}

/// Renders every pixel of `tile` adaptively and adds the samples to
/// `film` (row-major over the tile; started at [`PixelSum::ZERO`] it
/// holds each pixel's sample count as `samples + dropped`): samples
/// `0..base` of each pixel, then batches of `base` more, in index order,
/// while [`Adaptive::wants_more`] says so (see [`Adaptive`] for the error
/// estimator). Each pixel equals [`pixel_sample`](super::pixel_sample) over its indices `0..k`
/// with `k` decided by its own samples alone, so tiles, threads and
/// windows do not change it.
///
/// `sampler` is the prototype; its pattern must hold every index a pixel
/// may take (`samples_per_pixel() ≥ adaptive.max()`, else
/// [`RenderError::SamplerTooSmall`]), and its first samples should spread
/// over the pixel: [`UniformGrid`](crate::UniformGrid) fills its grid in
/// raster order, so its base pass covers the pixel's top rows only and
/// adaptive renders with it are biased.
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
/// let adaptive = Adaptive::new(4, 64, 0.02).unwrap();
/// let tile = Tile { x0: 0, y0: 0, width: 8, height: 4 };
/// let mut film = [PixelSum::ZERO; 32];
/// let sampler = Independent::new(64, 1).unwrap();
/// render_tile_adaptive(&scene, &camera, &sampler, &settings, tile, adaptive, &mut film).unwrap();
/// let taken = |x: usize, y: usize| film[y * 8 + x].samples;
/// assert!(taken(2, 2) > 4); // on the sphere, lit by the sky and the ground
/// assert_eq!(taken(7, 0), 4); // the flat sky: no variance, the base only
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
    Ok(for_each_group(
        scene,
        camera,
        sampler,
        settings,
        tile,
        film,
        |group, n| {
            let mut errors = [PixelError::ZERO; 8];
            // Every active lane has taken the same samples, so one batch
            // serves them all and their camera rays stay one packet.
            let mut ids = [0usize, 1, 2, 3, 4, 5, 6, 7];
            let mut active = n;
            let mut taken = 0;
            loop {
                for index in adaptive.next_batch(taken) {
                    group.trace(&ids[..active], index, Some(&mut errors));
                }
                taken = adaptive.next_batch(taken).end;
                let mut kept = 0;
                for k in 0..active {
                    if adaptive.wants_more(taken, &errors[ids[k]]) {
                        ids[kept] = ids[k];
                        kept += 1;
                    }
                }
                active = kept;
                if active == 0 {
                    break;
                }
            }
        },
    ))
}
