//! The path tracer: one camera path, from the pixel sample to radiance
//! (tiles of them are in [`tile`](super::tile)).
//!
//! # One camera path
//!
//! ```text
//! sampler.start_pixel_sample(pixel, index)
//! ray = camera.ray(pixel, sampler.pixel_2d(), sampler.next_2d())   dims 0-1, 2-3
//! for segment 1..=max_depth:
//!     closest hit (camera rays: 8-ray packets; the rest: one ray at a
//!     time; through the scene's BVH if it has one, else 8 spheres a step)
//!     miss      -> add background, stop
//!     emitter   -> add emission (MIS-weighted after a smooth bounce), stop
//!     last segment -> stop (no direct light whose BSDF twin is not traced)
//!     draw scatter 2D, lobe 1D, light-choice 1D, light 2D           6 dims
//!     smooth material -> direct light from one sphere light (MIS)
//!     sample the material, multiply the throughput, spawn the next ray
//! ```
//!
//! Every vertex takes its six dimensions whether or not it uses them (those
//! it does not read are skipped, `Sampler::skip_1d`/`skip_2d`, not made),
//! so a dimension's index never depends on the path taken.
//!
//! **max_depth** is the number of ray segments from the camera (the
//! course's, RTIOW's and Mitsuba's convention, COURSE.md D8): 1 sees only
//! what camera rays hit; shadow rays do not count. No Russian roulette: a
//! path still bouncing after `max_depth` segments ends black. Direct
//! lighting is the light-sampling twin of the next BSDF segment, so, as in
//! pbrt and Mitsuba, the vertex at the end of the last segment takes none:
//! `max_depth = 1` shows emitters and the background only, and depth 2 is
//! direct lighting. (The course also lit its last vertex; with MIS that
//! would weight a strategy whose twin is never traced.)
//!
//! **Direct lighting** picks one light uniformly, samples the cone its
//! sphere subtends ([`sample_uniform_cone`](crate::mapping::sample_uniform_cone)), and traces a shadow ray
//! ([`Scene::any_hit`]) that stops at the light: one blocker is enough and
//! nothing beyond the light counts (the course's D1 counted hits). BSDF
//! samples that hit a light are weighted against it by the power
//! heuristic, so no emission is counted twice (the course's D7).
//!
//! **One path or eight.** Every step of a vertex (the camera ray, the
//! surface record and footprint, the material's sampling and evaluation,
//! the light's cone and density, next-event estimation and its shadow
//! query) is written once over the crate's lanes type, `f32` or `f32x8`;
//! this loop runs the one-lane form, so an eight-path loop over the same
//! functions gives each path these bits (tested lane by lane).
//!
//! A sample's radiance depends only on (scene, camera, sampler, seed,
//! pixel, index): [`render_tile`](super::render_tile) gives every pixel the same bits whatever
//! the tile, the order or the thread, and camera-ray packets return the
//! same hits as single rays.

use super::camera::Camera;
use super::material::{Material, SurfaceLanes};
use super::scene::Scene;
use super::texture::{TextureFilter, sphere_uv_lanes};
use crate::filter::PixelFilter;
use crate::float::sqrtf;
use crate::lanes::{Lanes, RayLanes, SphereLanes, V3, f32x8, mask_from_bits};
use crate::mapping::{ConeLanes, uniform_cone, uniform_cone_pdf};
use crate::onb::OnbLanes;
use crate::sampler::Sampler;
use crate::trace::{
    BvhStack, Hit, Ray, RayPacket8, spawn_origin_lanes, sphere_t_live, unit_normal_lanes,
};
use glam::{UVec2, Vec2, Vec3};

/// Which path tracer a tile renderer runs. Both give the same bits for
/// every sample (tested); only speed differs.
///
/// The default is the faster for the build: [`Integrator::Lockstep`]
/// where eight `f32` lanes are one register (AVX and up: 1.06–1.31× the
/// scalar paths/s on the built-in scenes), [`Integrator::Scalar`] where
/// they take two (SSE2, NEON, WebAssembly's `simd128`), or none. The
/// choice is made when the core is compiled, by its target features.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Integrator {
    /// One path at a time, the readable specification.
    Scalar,
    /// Up to eight paths in lockstep (the pixels a camera packet shares),
    /// shaded a material at a time through eight-lane forms of the same
    /// shading code.
    Lockstep,
}

impl Default for Integrator {
    #[inline]
    fn default() -> Self {
        if cfg!(target_feature = "avx") {
            Integrator::Lockstep
        } else {
            Integrator::Scalar
        }
    }
}

impl Integrator {
    /// A short name: `scalar` or `lockstep`.
    ///
    /// ```
    /// assert_eq!(strata::render::Integrator::Lockstep.name(), "lockstep");
    /// ```
    #[inline]
    #[must_use]
    pub fn name(self) -> &'static str {
        match self {
            Integrator::Scalar => "scalar",
            Integrator::Lockstep => "lockstep",
        }
    }
}

/// How paths are traced.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct RenderSettings {
    /// Ray segments from the camera, at least 1.
    pub max_depth: u32,
    /// Next-event estimation from sphere lights (the course's "direct
    /// lighting"); without it lights are found by BSDF sampling alone.
    pub direct_lighting: bool,
    /// The pixel filter, applied by importance sampling: each sample's
    /// offset is drawn from it and its radiance weighted by `f / pdf`
    /// ([`PixelFilter::BOX`] is the course's: weight 1). `render_tile`
    /// and `pixel_sample` importance-sample every filter; a filter that
    /// [splats](PixelFilter::splats) is meant for
    /// [`render_tile_splat`](super::render_tile_splat).
    pub filter: PixelFilter,
    /// Texture filtering at camera rays' first hits ([`TextureFilter::None`]
    /// is the course's point sampling). With [`TextureFilter::Box`] the
    /// footprint comes from ray differentials: the rays through the same
    /// lens point and the pixel position moved by `δ` in x and in y,
    /// intersected with the hit's tangent plane, give the offsets `Δx` and
    /// `Δy` (per `δ`, not per pixel); the box's half-width per world axis,
    /// `√(Δxᵢ² + Δyᵢ²) / 2`, gives it the standard deviation of the
    /// parallelogram they span. `δ = max(1/8, 1/√spp)` pixels, as in
    /// pbrt-v4: more samples per pixel already average over the pixel, so
    /// each filters less. Later vertices are point-sampled.
    pub texture_filter: TextureFilter,
    /// The path tracer: [`Integrator::Scalar`] or
    /// [`Integrator::Lockstep`] (the default is the build's faster); the
    /// film is the same either way.
    pub integrator: Integrator,
}

/// The power heuristic (β = 2): the weight of a strategy with density `a`
/// against one with density `b`.
#[inline]
#[must_use]
pub(crate) fn power_heuristic<L: Lanes>(a: L, b: L) -> L {
    let (a2, b2) = (a * a, b * b);
    let sum = a2 + b2;
    L::select(sum.gt(L::splat(0.0)), a2 / sum, L::splat(0.0))
}

/// The surface record of each lane's hit at `t` on its sphere: the point,
/// the shading normal turned to face the ray, the side, and `(u, v)` when
/// the material reads it (else zero; the footprint is zero until a
/// camera ray's differentials give it).
#[inline(always)]
pub(crate) fn surface_lanes<L: Lanes>(
    ray: &RayLanes<L>,
    t: L,
    sphere: &SphereLanes<L>,
    uses_uv: bool,
) -> SurfaceLanes<L> {
    let p = ray.at(t);
    let outward = unit_normal_lanes(p, sphere.center);
    let front_face = ray.dir.dot(outward).lt(L::splat(0.0));
    let zero = L::splat(0.0);
    SurfaceLanes {
        p,
        n: V3::select(front_face, outward, -outward),
        front_face,
        footprint: V3::splat(Vec3::ZERO),
        wanted: u8::MAX,
        // acos and atan2 cost more than the rest of the record; only an
        // image texture reads uv.
        uv: if uses_uv {
            sphere_uv_lanes(outward)
        } else {
            (zero, zero)
        },
    }
}

/// The half-widths of the box textures are averaged over at `surf`, from
/// the differential rays' origins and directions (see
/// [`RenderSettings::texture_filter`]); infinite on every axis when a
/// differential ray runs parallel to the tangent plane.
#[inline(always)]
pub(crate) fn footprint_lanes<L: Lanes>(
    surf: &SurfaceLanes<L>,
    diff: &[(V3<L>, V3<L>); 2],
) -> V3<L> {
    let offset = |(origin, dir): &(V3<L>, V3<L>)| {
        let t = surf.n.dot(surf.p - *origin) / surf.n.dot(*dir);
        *origin + *dir * t - surf.p
    };
    let (dx, dy) = (offset(&diff[0]), offset(&diff[1]));
    let v = dx.mul_v(dx) + dy.mul_v(dy);
    let w = V3::new(v.x.sqrt(), v.y.sqrt(), v.z.sqrt()) * L::splat(0.5);
    V3::select(w.is_finite(), w, V3::splat(Vec3::INFINITY))
}

/// The density, per steradian, with which direct lighting from `p` picks a
/// direction towards light sphere `light` (0 from inside it).
#[inline]
fn light_pdf(scene: &Scene<'_>, p: Vec3, light: u32) -> f32 {
    let s = scene.spheres()[light as usize];
    light_pdf_lanes(scene, V3::from(p), &s.lanes())
}

/// [`light_pdf`] over lanes, each lane with its light's sphere.
#[inline(always)]
pub(crate) fn light_pdf_lanes<L: Lanes>(scene: &Scene<'_>, p: V3<L>, light: &SphereLanes<L>) -> L {
    let (cone, ok) = ConeLanes::subtended_by_sphere((light.center - p).length(), light.radius);
    let pdf = uniform_cone_pdf(V3::splat(Vec3::Z), &cone) / L::splat(scene.lights().len() as f32);
    L::select(ok, pdf, L::splat(0.0))
}

/// What rendering traced: counted by the path tracer as it goes, per
/// path, and summed per tile.
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

/// What one thread's tracing reuses and counts: the caller's BVH
/// traversal stack (cleared once, not per ray) and the statistics.
pub(crate) struct Scratch<'s> {
    pub(crate) stack: &'s mut BvhStack,
    pub(crate) stats: TileStats,
}

impl<'s> Scratch<'s> {
    #[inline(always)]
    pub(crate) fn new(stack: &'s mut BvhStack) -> Self {
        Self {
            stack,
            stats: TileStats::default(),
        }
    }
}

/// What a lane form needs that differs between one lane and eight: the
/// shadow query (one ray through [`Scene::any_hit_with`], or a packet
/// through [`Scene::any_hit_x8_with`], which answers each lane as the
/// one-ray query does).
pub(crate) trait Occlusion: Lanes {
    /// Which `live` lanes' rays are blocked; the others' answers are
    /// unspecified.
    fn occluded(
        scene: &Scene<'_>,
        rays: &RayLanes<Self>,
        live: Self::Mask,
        stack: &mut BvhStack,
    ) -> Self::Mask;
}

impl Occlusion for f32 {
    #[inline(always)]
    fn occluded(scene: &Scene<'_>, r: &RayLanes<f32>, live: bool, stack: &mut BvhStack) -> bool {
        let ray = Ray::new(Vec3::from(r.origin), Vec3::from(r.dir)).with_range(r.t_min, r.t_max);
        live && scene.any_hit_with(&ray, stack)
    }
}

impl Occlusion for f32x8 {
    #[inline(always)]
    fn occluded(
        scene: &Scene<'_>,
        r: &RayLanes<f32x8>,
        live: f32x8,
        stack: &mut BvhStack,
    ) -> f32x8 {
        let packet = RayPacket8::from_lanes(r, live);
        mask_from_bits(scene.any_hit_x8_with(&packet, stack) as u8)
    }
}

/// Next-event estimation at each `live` lane's vertex: one light chosen
/// by `u.0`, a direction in the cone its sphere subtends drawn from
/// `u.1`, the material's `f cos θ` there, and a shadow ray that stops at
/// the light, MIS-weighted against BSDF sampling by the power heuristic.
/// Returns the radiance (zero in dead lanes) and the lanes that traced a
/// shadow ray.
/// `material` is every lane's; `here` each lane's sphere.
#[inline(always)]
#[allow(clippy::too_many_arguments)]
pub(crate) fn direct_light_lanes<L: Occlusion>(
    scene: &Scene<'_>,
    stack: &mut BvhStack,
    material: &Material<'_>,
    d: V3<L>,
    surf: &SurfaceLanes<L>,
    here: &SphereLanes<L>,
    u: (L, (L, L)),
    live: L::Mask,
) -> (V3<L>, L::Mask) {
    let zero = V3::splat(Vec3::ZERO);
    let none = L::mask_splat(false);
    let lights = scene.lights();
    let n = lights.len();
    let choice = u.0 * L::splat(n as f32);
    // Each lane's light, chosen once (the lanes' gathers below read it).
    let light_of: [u32; 8] = core::array::from_fn(|k| {
        if k < L::WIDTH {
            lights[(choice.lane(k) as usize).min(n - 1)]
        } else {
            0
        }
    });
    let sphere_of = |k: usize| &scene.spheres()[light_of[k] as usize];
    let light = SphereLanes {
        center: V3::from_fn(|k| sphere_of(k).center),
        radius: L::from_fn(|k| sphere_of(k).radius),
    };
    let to_light = light.center - surf.p;
    let dist = to_light.length();
    let (cone, ok) = ConeLanes::subtended_by_sphere(dist, light.radius);
    let live = L::and(live, ok);
    if !L::any(live) {
        return (zero, none);
    }
    let local = uniform_cone(u.1.0, u.1.1, &cone);
    let wi = OnbLanes::from_normal(to_light.div(dist)).to_world(local);
    let (f_cos, bsdf_pdf) = material.eval_lanes(d, surf, wi);
    let live = L::and(live, L::not(f_cos.is_zero()));
    if !L::any(live) {
        return (zero, none);
    }
    // The shadow ray leaves on the side the shading normal faces.
    let origin = spawn_origin_lanes(here, surf.outward(), surf.front_face);
    let inf = L::splat(f32::INFINITY);
    let shadow = RayLanes {
        origin,
        dir: wi,
        t_min: L::splat(0.0),
        t_max: inf,
    };
    let t_light = sphere_t_live(&shadow, &light, live);
    // A ray that grazes the light's rim by rounding misses it: no shadow ray.
    let live = L::and(live, t_light.lt(inf));
    if !L::any(live) {
        return (zero, none);
    }
    let traced = live;
    let blocked = L::occluded(
        scene,
        &RayLanes {
            t_max: t_light,
            ..shadow
        },
        live,
        stack,
    );
    let live = L::and(live, L::not(blocked));
    let pdf = uniform_cone_pdf(local, &cone) / L::splat(n as f32);
    let emit = V3::from_fn(|k| scene.material_of(light_of[k]).emitted());
    let l = f_cos.mul_v(emit) * (power_heuristic(pdf, bsdf_pdf) / pdf);
    (V3::select(live, l, zero), traced)
}

/// The dimensions a camera sample takes before its path's first vertex:
/// the position in the pixel (0–1) and the lens (2–3).
pub const CAMERA_DIMENSIONS: u32 = 4;

/// The dimensions every path vertex takes, read or not.
pub const VERTEX_DIMENSIONS: u32 = 6;

/// What one path vertex draws from its sampler, as pbrt-v4's wavefront
/// `RaySamples`: the vertex at the end of segment `s` reads dimensions
/// `CAMERA_DIMENSIONS + VERTEX_DIMENSIONS·(s − 1)` on, in this order,
/// whatever the path did before, so a dimension's index is a function of
/// the depth alone. Dimensions a vertex does not read are skipped, not
/// made (the skipped fields hold 0).
#[derive(Clone, Copy, Debug)]
pub(crate) struct VertexSamples {
    /// The BSDF's direction (2D).
    pub(crate) scatter: Vec2,
    /// The BSDF's lobe or Fresnel choice (1D).
    pub(crate) lobe: f32,
    /// Which light direct lighting samples (1D).
    pub(crate) light_choice: f32,
    /// Where on that light's cone (2D).
    pub(crate) light: Vec2,
}

impl VertexSamples {
    /// Draws the vertex's six dimensions from `sampler`: those of the
    /// BSDF as the material `reads` them (direction, lobe), and the light
    /// sample's if `direct` (direct lighting at a smooth vertex).
    #[inline(always)]
    pub(crate) fn draw<S: Sampler>(sampler: &mut S, reads: (bool, bool), direct: bool) -> Self {
        let (reads_u, reads_lobe) = reads;
        let scatter = if reads_u {
            sampler.next_2d()
        } else {
            sampler.skip_2d();
            Vec2::ZERO
        };
        let lobe = if reads_lobe {
            sampler.next_1d()
        } else {
            sampler.skip_1d();
            0.0
        };
        let (light_choice, light) = if direct {
            (sampler.next_1d(), sampler.next_2d())
        } else {
            sampler.skip_1d();
            sampler.skip_2d();
            (0.0, Vec2::ZERO)
        };
        Self {
            scatter,
            lobe,
            light_choice,
            light,
        }
    }
}

/// The radiance of one camera path that starts with `ray`, whose first
/// hit (`first`) is already known, with the differential rays `diff` when
/// textures are filtered, and the rays it traced (closest-hit and shadow:
/// counted per path, so paths traced side by side count their own). The
/// sampler is positioned after the camera's [`CAMERA_DIMENSIONS`].
#[inline(always)]
pub(crate) fn trace_path<S: Sampler>(
    scene: &Scene<'_>,
    scratch: &mut Scratch<'_>,
    sampler: &mut S,
    settings: &RenderSettings,
    mut ray: Ray,
    first: Option<Hit>,
    diff: Option<[Ray; 2]>,
) -> (Vec3, u32) {
    let mut radiance = Vec3::ZERO;
    let mut throughput = Vec3::ONE;
    // The last bounce: where it left from and its BSDF density (None for
    // the camera and specular bounces, whose emission hits count fully).
    let mut last_smooth: Option<(Vec3, f32)> = None;
    let nee = settings.direct_lighting && !scene.lights().is_empty();
    let mut hit = first;
    let (mut rays, mut shadow_rays) = (0u32, 0u32);
    for segment in 1..=settings.max_depth {
        rays += 1;
        if segment > 1 {
            hit = scene.closest_hit_with(&ray, scratch.stack);
        }
        let Some(h) = hit else {
            radiance += throughput * scene.background().radiance(ray.dir);
            break;
        };
        let material = scene.material_of(h.sphere);
        if material.is_light() {
            let weight = match last_smooth {
                Some((p, bsdf_pdf)) if nee => {
                    power_heuristic(bsdf_pdf, light_pdf(scene, p, h.sphere))
                }
                _ => 1.0,
            };
            radiance += throughput * material.emitted() * weight;
            break;
        }
        if segment == settings.max_depth {
            break;
        }
        // The vertex in the one-lane forms (lanes_check tests them against
        // eight lanes).
        let here = scene.spheres()[h.sphere as usize].lanes();
        let d = V3::from(ray.dir);
        let mut surf = surface_lanes(&ray.lanes(), h.t, &here, material.uses_uv());
        if segment == 1
            && let Some(diff) = &diff
        {
            let ends = |r: &Ray| (V3::from(r.origin), V3::from(r.dir));
            surf.footprint = footprint_lanes(&surf, &[ends(&diff[0]), ends(&diff[1])]);
        }
        let direct = nee && material.is_smooth();
        let u = VertexSamples::draw(sampler, material.reads(), direct);
        if direct {
            let stack = &mut *scratch.stack;
            let u_light = (u.light_choice, (u.light.x, u.light.y));
            let (l, traced) =
                direct_light_lanes(scene, stack, material, d, &surf, &here, u_light, true);
            shadow_rays += u32::from(traced);
            radiance += throughput * Vec3::from(l);
        }
        let s = material.sample_lanes(d, &surf, (u.scatter.x, u.scatter.y), u.lobe);
        if !s.live {
            break;
        }
        throughput *= Vec3::from(s.weight);
        if throughput == Vec3::ZERO {
            break;
        }
        last_smooth = material.is_smooth().then_some((Vec3::from(surf.p), s.pdf));
        let outside = surf.front_face != s.transmitted;
        let origin = spawn_origin_lanes(&here, surf.outward(), outside);
        ray = Ray::new(Vec3::from(origin), Vec3::from(s.wi));
    }
    scratch.stats.paths += 1;
    scratch.stats.rays += rays as u64;
    scratch.stats.shadow_rays += shadow_rays as u64;
    (radiance, rays + shadow_rays)
}

/// One camera sample: the ray, the filter weight, and what the
/// differential rays are made from when textures are filtered.
#[derive(Clone, Copy)]
pub(crate) struct CameraSample {
    pub(crate) ray: Ray,
    /// Where in the pixel, from its corner (the filter's offset).
    pub(crate) offset: Vec2,
    pub(crate) weight: f32,
    /// The lens sample.
    pub(crate) lens: Vec2,
}

impl CameraSample {
    /// The differential rays `spacing` pixels apart (none if 0), made on
    /// demand: most renders filter no texture, and carrying two rays per
    /// sample cost them copies.
    #[inline(always)]
    pub(crate) fn differentials(
        &self,
        camera: &Camera,
        pixel: UVec2,
        spacing: f32,
    ) -> Option<[Ray; 2]> {
        (spacing > 0.0).then(|| differentials(camera, pixel, self.offset, self.lens, spacing))
    }
}

/// The differential spacing `δ` in pixels for a sampler of `spp` (see
/// [`RenderSettings::texture_filter`]); 0 without texture filtering.
#[inline]
pub(crate) fn differential_spacing(settings: &RenderSettings, spp: u32) -> f32 {
    match settings.texture_filter {
        TextureFilter::None => 0.0,
        TextureFilter::Box => (1.0 / sqrtf(spp.max(1) as f32)).max(0.125),
    }
}

/// The rays through `offset` moved by `spacing` pixels in x and in y.
/// Out of line: the common path without texture filtering keeps its one
/// camera ray inlined.
#[inline(never)]
pub(crate) fn differentials(
    camera: &Camera,
    pixel: UVec2,
    offset: Vec2,
    lens: Vec2,
    spacing: f32,
) -> [Ray; 2] {
    [
        camera.ray(pixel, offset + Vec2::new(spacing, 0.0), lens),
        camera.ray(pixel, offset + Vec2::new(0.0, spacing), lens),
    ]
}

/// The camera sample `index` of `pixel`; leaves the sampler after the
/// camera's dimensions (pixel 0–1, lens 2–3).
#[inline(always)]
pub(crate) fn camera_ray<S: Sampler>(
    camera: &Camera,
    filter: &PixelFilter,
    sampler: &mut S,
    pixel: UVec2,
    index: u32,
) -> CameraSample {
    sampler.start_pixel_sample(pixel, index);
    let f = filter.pixel_sample(sampler.pixel_2d());
    // A pinhole ignores the lens sample: skip its dimensions, not make them.
    let lens = if camera.is_pinhole() {
        sampler.skip_2d();
        Vec2::ZERO
    } else {
        sampler.next_2d()
    };
    CameraSample {
        ray: camera.ray(pixel, f.offset, lens),
        offset: f.offset,
        weight: f.weight,
        lens,
    }
}

/// The radiance of sample `index` of `pixel` and the sample's filter
/// weight, one ray at a time: the reference that [`render_tile`](super::render_tile) must
/// equal bit for bit (it adds them with [`PixelSum::add_weighted`](super::PixelSum::add_weighted)).
///
/// Each call makes and zeroes its own [`BvhStack`] (about 3.6 KB); to
/// trace many samples, keep one stack and call [`pixel_sample_with`],
/// which gives the same bits.
///
/// ```
/// use glam::{UVec2, Vec3};
/// use strata::render::*;
/// use strata::trace::{Sphere, SphereChunk8};
/// use strata::Independent;
/// // A white furnace: a white diffuse sphere under a sky of radiance 1.
/// let spheres = [Sphere::new(Vec3::ZERO, 1.0)];
/// let materials = [Material::Lambertian { albedo: Texture::Solid(Vec3::ONE) }];
/// const SIZE: SceneStorageSize = SceneStorageSize::for_spheres(1, false);
/// let (mut chunks, mut lights) = ([SphereChunk8::EMPTY; SIZE.chunks], [0u32; SIZE.lights]);
/// let storage = SceneStorage {
///     chunks: &mut chunks, lights: &mut lights,
///     bvh_nodes: &mut [], bvh_lanes: &mut [], bvh_ids: &mut [],
/// };
/// let scene = Scene::build(&spheres, &materials, &[0], Background::Flat(Vec3::ONE), storage).unwrap();
/// let desc = CameraDesc {
///     look_from: Vec3::new(0.0, 0.0, 5.0), look_at: Vec3::ZERO, up: Vec3::Y,
///     vfov_deg: 30.0, defocus_angle_deg: 0.0, focus_dist: 5.0,
/// };
/// let camera = Camera::new(&desc, 8, 8).unwrap();
/// let settings = RenderSettings { max_depth: 50, direct_lighting: true, filter: PixelFilter::BOX,
///     texture_filter: TextureFilter::None, integrator: Integrator::Scalar };
/// let mut sampler = Independent::new(1, 7).unwrap();
/// let (l, w) = pixel_sample(&scene, &camera, &mut sampler, &settings, UVec2::new(4, 4), 0);
/// assert!((l - Vec3::ONE).abs().max_element() < 1e-5); // every path sees 1
/// assert_eq!(w, 1.0); // the box filter's weight
/// ```
#[inline]
pub fn pixel_sample<S: Sampler>(
    scene: &Scene<'_>,
    camera: &Camera,
    sampler: &mut S,
    settings: &RenderSettings,
    pixel: UVec2,
    index: u32,
) -> (Vec3, f32) {
    let mut stack = BvhStack::new();
    pixel_sample_with(scene, camera, sampler, settings, pixel, index, &mut stack)
}

/// [`pixel_sample`] on the caller's reusable `stack`: the same bits,
/// without zeroing a stack per sample. One stack serves any number of
/// calls, scenes and threads in turn (see [`BvhStack`]).
///
/// ```
/// use glam::{UVec2, Vec3};
/// use strata::render::*;
/// use strata::trace::{BvhNode8, BvhStack, BvhStorage, Sphere, SphereChunk8};
/// use strata::Independent;
/// // A row of diffuse spheres, one of them a light, traced through a BVH.
/// let spheres: [Sphere; 20] =
///     core::array::from_fn(|i| Sphere::new(Vec3::new(i as f32 - 10.0, 0.0, 0.0), 0.45));
/// let materials = [
///     Material::Lambertian { albedo: Texture::Solid(Vec3::splat(0.5)) },
///     Material::DiffuseLight { emit: Vec3::splat(4.0) },
/// ];
/// let sphere_material: [u32; 20] = core::array::from_fn(|i| (i == 9) as u32);
/// const SIZE: SceneStorageSize = SceneStorageSize::for_spheres(20, true);
/// const BVH: BvhStorage = SIZE.bvh.unwrap();
/// let (mut chunks, mut lights) = ([SphereChunk8::EMPTY; SIZE.chunks], [0u32; SIZE.lights]);
/// let (mut nodes, mut lanes, mut ids) =
///     ([BvhNode8::EMPTY; BVH.nodes], [0.0; BVH.lanes], [0u32; BVH.ids]);
/// let storage = SceneStorage {
///     chunks: &mut chunks, lights: &mut lights,
///     bvh_nodes: &mut nodes, bvh_lanes: &mut lanes, bvh_ids: &mut ids,
/// };
/// let sky = Background::Flat(Vec3::splat(0.2));
/// let scene = Scene::build(&spheres, &materials, &sphere_material, sky, storage).unwrap();
/// assert!(scene.has_bvh());
/// let desc = CameraDesc {
///     look_from: Vec3::new(0.0, 2.0, 12.0), look_at: Vec3::ZERO, up: Vec3::Y,
///     vfov_deg: 60.0, defocus_angle_deg: 0.0, focus_dist: 12.0,
/// };
/// let camera = Camera::new(&desc, 16, 8).unwrap();
/// let settings = RenderSettings { max_depth: 8, direct_lighting: true, filter: PixelFilter::BOX,
///     texture_filter: TextureFilter::None, integrator: Integrator::Scalar };
/// let mut sampler = Independent::new(4, 3).unwrap();
/// let mut stack = BvhStack::new(); // zeroed once, reused for every sample
/// for i in 0..4 {
///     let pixel = UVec2::new(3 + i, 4);
///     let (l, w) = pixel_sample_with(&scene, &camera, &mut sampler, &settings, pixel, i, &mut stack);
///     let (l0, w0) = pixel_sample(&scene, &camera, &mut sampler, &settings, pixel, i);
///     assert_eq!((l.to_array().map(f32::to_bits), w), (l0.to_array().map(f32::to_bits), w0));
/// }
/// ```
#[inline]
pub fn pixel_sample_with<S: Sampler>(
    scene: &Scene<'_>,
    camera: &Camera,
    sampler: &mut S,
    settings: &RenderSettings,
    pixel: UVec2,
    index: u32,
    stack: &mut BvhStack,
) -> (Vec3, f32) {
    let spacing = differential_spacing(settings, sampler.samples_per_pixel());
    let c = camera_ray(camera, &settings.filter, sampler, pixel, index);
    let mut scratch = Scratch::new(stack);
    let first = scene.closest_hit_with(&c.ray, scratch.stack);
    let diff = c.differentials(camera, pixel, spacing);
    let (l, _) = trace_path(scene, &mut scratch, sampler, settings, c.ray, first, diff);
    (l, c.weight)
}

#[cfg(test)]
mod tests {
    use super::*;

    /// The default follows the lane width of the build the core was
    /// compiled for: lockstep on the repository's native AVX2 or AVX-512
    /// build, scalar on a portable SSE2 one.
    #[test]
    fn the_default_integrator_is_lockstep_exactly_with_avx() {
        let avx = cfg!(target_feature = "avx");
        assert_eq!(Integrator::default() == Integrator::Lockstep, avx);
        assert_eq!(Integrator::default() == Integrator::Scalar, !avx);
    }

    /// A sampler that counts the dimensions it hands out (drawn or
    /// skipped) and the width of each step.
    #[derive(Clone, Debug)]
    struct Counting {
        dimension: u32,
        steps: [u8; 64],
        n: usize,
    }

    impl Counting {
        fn new() -> Self {
            Self {
                dimension: 0,
                steps: [0; 64],
                n: 0,
            }
        }
        fn step(&mut self, w: u32) {
            self.dimension += w;
            self.steps[self.n % 64] = w as u8;
            self.n += 1;
        }
    }

    impl Sampler for Counting {
        fn samples_per_pixel(&self) -> u32 {
            1
        }
        fn start_pixel_sample(&mut self, _: UVec2, _: u32) {
            (self.dimension, self.n) = (2, 0);
        }
        fn pixel_2d(&mut self) -> Vec2 {
            Vec2::splat(0.5)
        }
        fn next_1d(&mut self) -> f32 {
            self.step(1);
            0.5
        }
        fn next_2d(&mut self) -> Vec2 {
            self.step(2);
            Vec2::splat(0.5)
        }
        fn skip_1d(&mut self) {
            self.step(1);
        }
        fn skip_2d(&mut self) {
            self.step(2);
        }
    }

    /// A camera sample takes [`CAMERA_DIMENSIONS`] (pinhole or lens), and
    /// every vertex [`VERTEX_DIMENSIONS`] in the same steps (2, 1, 1, 2)
    /// whatever it reads: so the vertex at the end of segment `s` starts
    /// at `CAMERA_DIMENSIONS + VERTEX_DIMENSIONS·(s − 1)`.
    #[test]
    fn dimensions_are_a_function_of_the_depth() {
        // A whole path: the camera inside a closed diffuse sphere, so
        // every path reaches max_depth, whose last vertex draws nothing.
        use crate::render::{Background, Material, SceneStorage, SceneStorageSize, Texture};
        use crate::trace::{Sphere, SphereChunk8};
        let spheres = [Sphere::new(Vec3::ZERO, 10.0)];
        let materials = [Material::Lambertian {
            albedo: Texture::Solid(Vec3::splat(0.5)),
        }];
        const SIZE: SceneStorageSize = SceneStorageSize::for_spheres(1, false);
        let (mut chunks, mut lights) = ([SphereChunk8::EMPTY; SIZE.chunks], [0u32; SIZE.lights]);
        let storage = SceneStorage {
            chunks: &mut chunks,
            lights: &mut lights,
            bvh_nodes: &mut [],
            bvh_lanes: &mut [],
            bvh_ids: &mut [],
        };
        let scene = Scene::build(
            &spheres,
            &materials,
            &[0],
            Background::Flat(Vec3::ONE),
            storage,
        )
        .unwrap();
        let desc = crate::render::CameraDesc {
            look_from: Vec3::ZERO,
            look_at: Vec3::Z,
            up: Vec3::Y,
            vfov_deg: 60.0,
            defocus_angle_deg: 0.0,
            focus_dist: 1.0,
        };
        let camera = Camera::new(&desc, 4, 4).unwrap();
        for depth in [1, 2, 5, 9] {
            let settings = RenderSettings {
                max_depth: depth,
                direct_lighting: true,
                filter: PixelFilter::BOX,
                texture_filter: TextureFilter::None,
                integrator: Integrator::Scalar,
            };
            let mut s = Counting::new();
            pixel_sample(&scene, &camera, &mut s, &settings, UVec2::new(1, 2), 0);
            assert_eq!(
                s.dimension,
                CAMERA_DIMENSIONS + VERTEX_DIMENSIONS * (depth - 1),
                "depth {depth}"
            );
        }
        for defocus in [0.0, 2.0] {
            let desc = crate::render::CameraDesc {
                look_from: Vec3::new(0.0, 0.0, 5.0),
                look_at: Vec3::ZERO,
                up: Vec3::Y,
                vfov_deg: 40.0,
                defocus_angle_deg: defocus,
                focus_dist: 5.0,
            };
            let camera = Camera::new(&desc, 4, 4).unwrap();
            let mut s = Counting::new();
            camera_ray(&camera, &PixelFilter::BOX, &mut s, UVec2::ZERO, 0);
            assert_eq!(s.dimension, CAMERA_DIMENSIONS, "defocus {defocus}");
        }
        for reads in [(false, false), (true, false), (false, true), (true, true)] {
            for direct in [false, true] {
                let mut s = Counting::new();
                s.start_pixel_sample(UVec2::ZERO, 0);
                for vertex in 0..3 {
                    let first = s.dimension;
                    s.n = 0;
                    VertexSamples::draw(&mut s, reads, direct);
                    assert_eq!(s.dimension - first, VERTEX_DIMENSIONS);
                    assert_eq!(s.steps[..s.n], [2, 1, 1, 2], "{reads:?} {direct} {vertex}");
                }
            }
        }
    }

    #[test]
    fn power_heuristic_weights() {
        assert_eq!(power_heuristic(1.0, 1.0), 0.5);
        assert_eq!(power_heuristic(3.0, 0.0), 1.0);
        assert_eq!(power_heuristic(0.0, 0.0), 0.0);
        assert_eq!(power_heuristic(1.0, 3.0), 0.1);
        // The two strategies' weights sum to 1.
        assert_eq!(power_heuristic(2.0, 5.0) + power_heuristic(5.0, 2.0), 1.0);
    }
}
