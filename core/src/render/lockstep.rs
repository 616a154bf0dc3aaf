//! Eight paths in lockstep: the twin of [`trace_path`](super::integrator)
//! that advances up to eight camera paths one vertex at a time, shading
//! the live lanes of each material together through the eight-lane forms
//! of the shared shading code (the same functions the scalar path tracer
//! runs with one lane), with eight-ray shadow queries. Each lane keeps its
//! own sampler and draws its dimensions exactly as the scalar path does,
//! so every path, and so every film, is the scalar one bit for bit.
//!
//! The path state is kept as lanes (structure of arrays): rays,
//! throughput, radiance and the last smooth bounce are updated eight at a
//! time under masks, with the scalar path's operations in its order, so a
//! lane's bits are those of its scalar path; the live lanes' next rays
//! are traced as one packet. What still runs lane by lane: the sampler's
//! draws, the material lookups and an emitter's MIS weight. A lane that
//! has finished keeps its last (finite) ray and hit: it is computed with
//! the others and its results are not read.

use glam::Vec3;

use super::integrator::{
    RenderSettings, Scratch, VertexSamples, direct_light_lanes, footprint_lanes, light_pdf_lanes,
    power_heuristic, surface_lanes,
};
use super::material::Material;
use super::scene::Scene;
use crate::lanes::{
    Lanes, RayLanes, SphereLanes, V3, f32x8, lanes_bitmask, mask_from_bits, set_lanes,
};
use crate::sampler::Sampler;
use crate::trace::{HitPacket8, Ray, RayPacket8, spawn_origin_lanes};

/// The lanes (bit `k`: lane `k`) where `key[k] == key[lead]`.
#[inline(always)]
fn same_as(key: &[u32; 8], lead: usize) -> u32 {
    let m = key[lead];
    (0..8).fold(0, |bits, k| bits | u32::from(key[k] == m) << k)
}

/// `mask_from_bits` for a lane set held as `u32`.
#[inline(always)]
fn mask(bits: u32) -> f32x8 {
    mask_from_bits(bits as u8)
}

/// Traces the paths of lanes `0..n` in lockstep (lane `k` with sampler
/// `samplers[ids[k]]`, camera ray `rays[k]`, its first hit in lane `k` of
/// `first` and differentials `diff[k]`; past `n`, `rays` are copies of
/// lane 0's and `diff` is `None`), returning each lane's radiance and rays traced, as
/// [`trace_path`](super::integrator) would one by one.
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
    first: &HitPacket8,
    diff: &[Option<[Ray; 2]>; 8],
) -> [(Vec3, u32); 8] {
    let n = ids.len();
    debug_assert!((1..=8).contains(&n));
    debug_assert!(diff[n..].iter().all(Option::is_none));
    let nee = settings.direct_lighting && !scene.lights().is_empty();
    let spheres = scene.spheres();
    // Lanes past `n` hold the caller's copies of lane 0's ray, so they
    // make the vertex lane 0 makes, which is never read.
    let mut origin: V3<f32x8> = V3::from_fn(|k| rays[k].origin);
    let mut dir: V3<f32x8> = V3::from_fn(|k| rays[k].dir);
    // The closest hit of each lane (a lane without one keeps its last, or
    // from the start sphere 0 at t = 0; lanes past `n` lane 0's); `found`
    // marks the lanes that have one now.
    let (mut found, mut t, mut sphere) = first.found_lanes();
    found &= (1 << n) - 1;
    for k in n..8 {
        (t[k], sphere[k]) = (t[0], sphere[0]);
    }
    let mut radiance = V3::splat(Vec3::ZERO);
    let mut throughput = V3::splat(Vec3::ONE);
    // The last smooth bounce (lanes in `smooth`): where it left from and
    // its BSDF density.
    let mut smooth = 0u32;
    let mut smooth_at = V3::splat(Vec3::ZERO);
    let mut smooth_pdf = f32x8::splat(0.0);
    // Rays traced by each lane: path segments, shadow rays.
    let (mut segments, mut shadows) = ([0u32; 8], [0u32; 8]);
    let mut alive: u32 = (1 << n) - 1;
    for segment in 1..=settings.max_depth {
        if segment > 1 {
            let packet = RayPacket8::from_lanes(
                &RayLanes {
                    origin,
                    dir,
                    t_min: f32x8::splat(0.0),
                    t_max: f32x8::splat(f32::INFINITY),
                },
                mask(alive),
            );
            let mut hits = HitPacket8::NONE;
            scene.closest_hit_x8_with(&packet, &mut hits, scratch.stack);
            let (hit, ht, hs) = hits.found_lanes();
            found = hit & alive;
            for k in set_lanes(found) {
                (t[k], sphere[k]) = (ht[k], hs[k]);
            }
        }
        // (Branch-free: all eight counters at once.)
        for (k, s) in segments.iter_mut().enumerate() {
            *s += alive >> k & 1;
        }
        let missed = alive & !found;
        if missed != 0 {
            let sky = throughput.mul_v(scene.background().radiance_lanes(dir));
            radiance = V3::select(mask(missed), radiance + sky, radiance);
            alive &= !missed;
        }
        // (Also before any material lookup: a scene may have no spheres.)
        if alive == 0 {
            break;
        }
        let material_id: [u32; 8] = core::array::from_fn(|k| scene.material_index(sphere[k]));
        let materials: [&Material<'_>; 8] =
            core::array::from_fn(|k| scene.material(material_id[k]));
        let lights = set_lanes(alive)
            .filter(|&k| materials[k].is_light())
            .fold(0u32, |bits, k| bits | 1 << k);
        if lights != 0 {
            let emitted = V3::from_fn(|k| materials[k].emitted());
            let weight = f32x8::from_fn(|k| {
                if !(nee && lights >> k & smooth >> k & 1 == 1) {
                    return 1.0;
                }
                let light = spheres[sphere[k] as usize].lanes();
                let at = V3::from(smooth_at.lane(k));
                power_heuristic(smooth_pdf.lane(k), light_pdf_lanes(scene, at, &light))
            });
            let e = throughput.mul_v(emitted) * weight;
            radiance = V3::select(mask(lights), radiance + e, radiance);
            alive &= !lights;
        }
        if segment == settings.max_depth || alive == 0 {
            break;
        }
        // The vertices of all eight lanes (a finished lane's results are
        // not read).
        let here = SphereLanes {
            center: V3::from_fn(|k| spheres[sphere[k] as usize].center),
            radius: f32x8::from_fn(|k| spheres[sphere[k] as usize].radius),
        };
        let ray = RayLanes {
            origin,
            dir,
            t_min: f32x8::splat(0.0),
            t_max: f32x8::splat(f32::INFINITY),
        };
        // The vertex's incoming directions: `dir` takes each group's next
        // directions as it is shaded.
        let d = dir;
        let uses_uv = set_lanes(alive).any(|k| materials[k].uses_uv());
        let mut surf = surface_lanes(&ray, f32x8::new(t), &here, uses_uv);
        if segment == 1 && diff[0].is_some() {
            let ends = |i: usize| {
                let r = |k: usize| diff[k].map_or(rays[k], |dk| dk[i]);
                (V3::from_fn(|k| r(k).origin), V3::from_fn(|k| r(k).dir))
            };
            surf.footprint = footprint_lanes(&surf, &[ends(0), ends(1)]);
        }
        let outward = surf.outward();
        // One material at a time, over the lanes that hit it.
        let mut todo = alive;
        while todo != 0 {
            let lead = todo.trailing_zeros() as usize;
            let material = materials[lead];
            let group = todo & same_as(&material_id, lead);
            todo &= !group;
            let in_group = mask(group);
            surf.wanted = group as u8;
            let direct = nee && material.is_smooth();
            let reads = material.reads();
            let mut u = [[0.0f32; 8]; 6];
            for k in set_lanes(group) {
                let v = VertexSamples::draw(&mut samplers[ids[k]], reads, direct);
                let draws = [
                    v.scatter.x,
                    v.scatter.y,
                    v.lobe,
                    v.light_choice,
                    v.light.x,
                    v.light.y,
                ];
                for (lane, x) in u.iter_mut().zip(draws) {
                    lane[k] = x;
                }
            }
            let [u0, u1, u_lobe, u_choice, ul0, ul1] = u.map(f32x8::new);
            if direct {
                let (l, shadow) = direct_light_lanes(
                    scene,
                    &mut *scratch.stack,
                    material,
                    d,
                    &surf,
                    &here,
                    (u_choice, (ul0, ul1)),
                    in_group,
                );
                radiance = V3::select(in_group, radiance + throughput.mul_v(l), radiance);
                for k in set_lanes(lanes_bitmask(shadow) & group) {
                    shadows[k] += 1;
                }
            }
            let s = material.sample_lanes(d, &surf, (u0, u1), u_lobe);
            let weighted = throughput.mul_v(s.weight);
            let scattered = lanes_bitmask(s.live) & group;
            // A path ends where the BSDF absorbs or the throughput is 0.
            let go = scattered & !lanes_bitmask(weighted.is_zero());
            alive &= !(group & !go);
            let go_mask = mask(go);
            throughput = V3::select(go_mask, weighted, throughput);
            if material.is_smooth() {
                smooth |= go;
                smooth_at = V3::select(go_mask, surf.p, smooth_at);
                smooth_pdf = Lanes::select(go_mask, s.pdf, smooth_pdf);
            } else {
                smooth &= !go;
            }
            // Masks are all ones or zeros: xor is `!=`.
            let outside = surf.front_face ^ s.transmitted;
            let next = spawn_origin_lanes(&here, outward, outside);
            origin = V3::select(go_mask, next, origin);
            dir = V3::select(go_mask, s.wi, dir);
        }
    }
    let stats = &mut scratch.stats;
    for k in 0..n {
        stats.paths += 1;
        stats.rays += u64::from(segments[k]);
        stats.shadow_rays += u64::from(shadows[k]);
    }
    core::array::from_fn(|k| (radiance.lane(k), segments[k] + shadows[k]))
}

#[cfg(test)]
mod tests {
    use glam::Vec3;

    use crate::render::{
        Background, Camera, CameraDesc, Integrator, Material, PixelFilter, PixelSum,
        RenderSettings, Scene, SceneStorage, TextureFilter, Tile, render_tile,
    };
    use crate::sampler::Independent;
    use crate::trace::{Sphere, SphereChunk8};

    /// An 8×2 render of `spheres` (one material) with `integrator`: its
    /// film and what it traced.
    fn render(spheres: &[Sphere], integrator: Integrator) -> ([PixelSum; 16], u64, u64) {
        render_from(Vec3::new(0.0, 0.0, 5.0), 5.0, spheres, integrator)
    }

    /// [`render`] seen from `look_from`, focused at `focus_dist`.
    fn render_from(
        look_from: Vec3,
        focus_dist: f32,
        spheres: &[Sphere],
        integrator: Integrator,
    ) -> ([PixelSum; 16], u64, u64) {
        let materials = [Material::Metal {
            albedo: Vec3::splat(0.8),
            roughness: 0.3,
        }];
        let sphere_material = [0u32; 2];
        let mut chunks = [SphereChunk8::EMPTY; 1];
        let mut lights = [0u32; 2];
        let storage = SceneStorage {
            chunks: &mut chunks,
            lights: &mut lights,
            bvh_nodes: &mut [],
            bvh_lanes: &mut [],
            bvh_ids: &mut [],
        };
        let materials = &materials[..spheres.len().min(1)];
        let scene = Scene::build(
            spheres,
            materials,
            &sphere_material[..spheres.len()],
            Background::Sky,
            storage,
        )
        .unwrap();
        let desc = CameraDesc {
            look_from,
            look_at: Vec3::ZERO,
            up: Vec3::Y,
            vfov_deg: 30.0,
            defocus_angle_deg: 0.0,
            focus_dist,
        };
        let camera = Camera::new(&desc, 8, 2).unwrap();
        let settings = RenderSettings {
            max_depth: 5,
            direct_lighting: true,
            filter: PixelFilter::BOX,
            texture_filter: TextureFilter::None,
            integrator,
        };
        let sampler = Independent::new(2, 7).unwrap();
        let mut film = [PixelSum::ZERO; 16];
        let tile = Tile::whole(8, 2);
        let st = render_tile(&scene, &camera, &sampler, &settings, tile, 0..2, &mut film).unwrap();
        (film, st.rays, st.paths)
    }

    /// Scenes where every path misses at once: none of their lanes reads
    /// a material (an empty scene has none to read).
    #[test]
    fn scenes_that_every_path_misses_give_the_scalar_film() {
        let behind = Sphere::new(Vec3::new(0.0, 0.0, 9.0), 1.0);
        for spheres in [&[][..], &[behind][..]] {
            let scalar = render(spheres, Integrator::Scalar);
            let lockstep = render(spheres, Integrator::Lockstep);
            assert_eq!(lockstep, scalar, "{} spheres", spheres.len());
            assert_eq!(scalar.1, 32, "one ray a path");
        }
    }

    /// A camera so far out that its pixel steps vanish in rounding gives
    /// NaN rays: both integrators drop those samples alike (the lockstep
    /// one neither panics nor asserts on them).
    #[test]
    fn a_camera_with_nan_rays_gives_the_scalar_film() {
        let ball = [Sphere::new(Vec3::ZERO, 1.0)];
        let far = Vec3::splat(1e9);
        let scalar = render_from(far, 1.0, &ball, Integrator::Scalar);
        let lockstep = render_from(far, 1.0, &ball, Integrator::Lockstep);
        assert_eq!(lockstep, scalar);
        // The rays were NaN: every sample was dropped.
        assert!(scalar.0.iter().all(|p| p.dropped > 0), "{:?}", scalar.0[0]);
    }
}
