//! Eight paths in lockstep: the twin of [`trace_path`](super::integrator)
//! that advances up to eight camera paths one vertex at a time, shading
//! the live lanes of each material together through the eight-lane forms
//! of the shared shading code (the same functions the scalar path tracer
//! runs with one lane), with eight-ray shadow queries. Each lane keeps its
//! own sampler and draws its dimensions exactly as the scalar path does,
//! so every path, and so every film, is the scalar one bit for bit.
//!
//! The bookkeeping that differs from lane to lane (hits, misses,
//! emitters, the sampler's draws, throughput and radiance sums) stays per
//! lane, in the scalar path's operations and order.

use glam::Vec3;

use super::integrator::{
    RenderSettings, Scratch, VertexSamples, direct_light_lanes, footprint_lanes, light_pdf_lanes,
    power_heuristic, surface_lanes,
};
use super::material::Material;
use super::scene::Scene;
use crate::lanes::{Lanes, RayLanes, SphereLanes, V3, f32x8, lanes_bitmask, mask_from_bools};
use crate::sampler::Sampler;
use crate::trace::{Hit, Ray, Sphere, spawn_origin_lanes};

/// One lane's path state between vertices.
#[derive(Clone, Copy)]
struct PathLane {
    ray: Ray,
    hit: Option<Hit>,
    radiance: Vec3,
    throughput: Vec3,
    /// Where the last smooth bounce left from and its BSDF density.
    last_smooth: Option<(Vec3, f32)>,
    rays: u32,
    shadow_rays: u32,
    alive: bool,
}

/// Traces the paths of lanes `0..n` in lockstep (lane `k` with sampler
/// `samplers[ids[k]]`, camera ray `rays[k]`, its first hit `first[k]` and
/// differentials `diff[k]`), returning each lane's radiance and rays
/// traced, as [`trace_path`](super::integrator) would one by one.
/// Not inlined: the scalar tile loop that calls it stays as it was.
#[inline(never)]
#[allow(clippy::too_many_arguments)]
pub(crate) fn trace_lockstep<S: Sampler>(
    scene: &Scene<'_>,
    scratch: &mut Scratch<'_>,
    samplers: &mut [S; 8],
    ids: &[usize],
    settings: &RenderSettings,
    rays: &[Ray; 8],
    first: &[Option<Hit>; 8],
    diff: &[Option<[Ray; 2]>; 8],
) -> [(Vec3, u32); 8] {
    let n = ids.len();
    let nee = settings.direct_lighting && !scene.lights().is_empty();
    let mut lane: [PathLane; 8] = core::array::from_fn(|k| PathLane {
        ray: rays[k],
        hit: first[k],
        radiance: Vec3::ZERO,
        throughput: Vec3::ONE,
        last_smooth: None,
        rays: 0,
        shadow_rays: 0,
        alive: k < n,
    });
    let spheres = scene.spheres();
    for segment in 1..=settings.max_depth {
        // Hits, misses and emitters, lane by lane.
        for p in lane.iter_mut().filter(|p| p.alive) {
            p.rays += 1;
            if segment > 1 {
                p.hit = scene.closest_hit_with(&p.ray, scratch.stack);
            }
            let Some(h) = p.hit else {
                p.radiance += p.throughput * scene.background().radiance(p.ray.dir);
                p.alive = false;
                continue;
            };
            let material = scene.material_of(h.sphere);
            if material.is_light() {
                let weight = match p.last_smooth {
                    Some((at, bsdf_pdf)) if nee => {
                        let light = spheres[h.sphere as usize].lanes();
                        power_heuristic(bsdf_pdf, light_pdf_lanes(scene, V3::from(at), &light))
                    }
                    _ => 1.0,
                };
                p.radiance += p.throughput * material.emitted() * weight;
                p.alive = false;
            }
        }
        if segment == settings.max_depth || !lane.iter().any(|p| p.alive) {
            break;
        }
        // The vertices of the live lanes, eight at a time (a dead lane
        // repeats a live one's, so it stays finite; its results are not
        // read).
        let live_lane = lane.iter().position(|p| p.alive).unwrap_or(0);
        let src = |k: usize| if lane[k].alive { k } else { live_lane };
        let hit_of = |k: usize| lane[src(k)].hit.unwrap_or(Hit { t: 0.0, sphere: 0 });
        let sphere_of: [Sphere; 8] = core::array::from_fn(|k| spheres[hit_of(k).sphere as usize]);
        let here = SphereLanes {
            center: V3::from_fn(|k| sphere_of[k].center),
            radius: f32x8::from_fn(|k| sphere_of[k].radius),
        };
        let ray = RayLanes {
            origin: V3::from_fn(|k| lane[src(k)].ray.origin),
            dir: V3::from_fn(|k| lane[src(k)].ray.dir),
            t_min: f32x8::splat(0.0),
            t_max: f32x8::splat(f32::INFINITY),
        };
        let d = ray.dir;
        let t = f32x8::from_fn(|k| hit_of(k).t);
        let materials: [&Material<'_>; 8] =
            core::array::from_fn(|k| scene.material_of(hit_of(k).sphere));
        let uses_uv = (0..8).any(|k| lane[k].alive && materials[k].uses_uv());
        let mut surf = surface_lanes(&ray, t, &here, uses_uv);
        if segment == 1 && diff[src(0)].is_some() {
            let ends = |i: usize| {
                let r = |k: usize| diff[src(k)].map_or(lane[src(k)].ray, |dk| dk[i]);
                (V3::from_fn(|k| r(k).origin), V3::from_fn(|k| r(k).dir))
            };
            surf.footprint = footprint_lanes(&surf, &[ends(0), ends(1)]);
        }
        // One material at a time, over the lanes that hit it.
        let mut todo: u32 = (0..8).filter(|&k| lane[k].alive).map(|k| 1 << k).sum();
        while todo != 0 {
            let lead = todo.trailing_zeros() as usize;
            let material = materials[lead];
            let group: u32 = (0..8)
                .filter(|&k| todo >> k & 1 == 1 && core::ptr::eq(materials[k], material))
                .map(|k| 1 << k)
                .sum();
            todo &= !group;
            let in_group = |k: usize| group >> k & 1 == 1;
            let direct = nee && material.is_smooth();
            let mut u: [VertexSamples; 8] = [VertexSamples::NONE; 8];
            for k in (0..8).filter(|&k| in_group(k)) {
                u[k] = VertexSamples::draw(&mut samplers[ids[k]], material.reads(), direct);
            }
            let live = mask_from_bools(core::array::from_fn(in_group));
            if direct {
                let u_light = (
                    f32x8::from_fn(|k| u[k].light_choice),
                    (
                        f32x8::from_fn(|k| u[k].light.x),
                        f32x8::from_fn(|k| u[k].light.y),
                    ),
                );
                let (l, traced) = direct_light_lanes(
                    scene,
                    &mut *scratch.stack,
                    material,
                    d,
                    &surf,
                    &here,
                    u_light,
                    live,
                );
                let traced = lanes_bitmask(traced);
                for k in (0..8).filter(|&k| in_group(k)) {
                    let p = &mut lane[k];
                    p.radiance += p.throughput * l.lane(k);
                    p.shadow_rays += traced >> k & 1;
                }
            }
            let scatter = (
                f32x8::from_fn(|k| u[k].scatter.x),
                f32x8::from_fn(|k| u[k].scatter.y),
            );
            let u_lobe = f32x8::from_fn(|k| u[k].lobe);
            let s = material.sample_lanes(d, &surf, scatter, u_lobe);
            // Masks are all ones or zeros: xor is `!=`.
            let outside = surf.front_face ^ s.transmitted;
            let origin = spawn_origin_lanes(&here, surf.outward(), outside);
            let s_live = lanes_bitmask(s.live);
            for k in (0..8).filter(|&k| in_group(k)) {
                let p = &mut lane[k];
                if s_live >> k & 1 == 0 {
                    p.alive = false;
                    continue;
                }
                p.throughput *= s.weight.lane(k);
                if p.throughput == Vec3::ZERO {
                    p.alive = false;
                    continue;
                }
                p.last_smooth = material
                    .is_smooth()
                    .then_some((surf.p.lane(k), s.pdf.lane(k)));
                p.ray = Ray::new(origin.lane(k), s.wi.lane(k));
            }
        }
    }
    let stats = &mut scratch.stats;
    core::array::from_fn(|k| {
        let p = &lane[k];
        if k < n {
            stats.paths += 1;
            stats.rays += u64::from(p.rays);
            stats.shadow_rays += u64::from(p.shadow_rays);
        }
        (p.radiance, p.rays + p.shadow_rays)
    })
}
