//! Ray–sphere throughput: scalar reference vs one ray × 8 spheres (1×8) vs
//! 8-ray packets, on the course scene (4 spheres) and the cover scene (485),
//! with coherent camera rays and incoherent random rays; closest hit, and
//! any hit on shadow rays from those rays' hit points to a point light.
//! One criterion group per comparison, so the ratios come from one run.
//! Throughput counts rays; ray–sphere tests are rays × spheres. Packets are
//! assembled (the AoS → SoA transpose) before timing, as a renderer that
//! generates rays in SoA form would have them.

use std::hint::black_box;

use criterion::{Criterion, Throughput, criterion_group, criterion_main};
use glam::Vec3;
use strata::trace::*;
use strata_runner::workload::{
    COURSE_VIEW, COVER_VIEW, View, camera_rays, course_spheres, cover_spheres, random_rays, ray_box,
};

struct Workload {
    name: &'static str,
    spheres: Vec<Sphere>,
    rays: Vec<Ray>,
    /// A point light for the shadow rays.
    light: Vec3,
}

/// Camera rays (coherent) and random rays (incoherent) for both scenes.
fn workloads() -> Vec<Workload> {
    let light = |cover: bool| {
        if cover {
            Vec3::new(2.0, 8.0, 3.0)
        } else {
            Vec3::new(-1.0, 3.0, 1.0)
        }
    };
    let camera = |name, spheres, view: View, (w, h), cover| Workload {
        name,
        spheres,
        rays: camera_rays(view, w, h),
        light: light(cover),
    };
    let random = |name, spheres, n, cover| {
        let (lo, hi) = ray_box(cover);
        Workload {
            name,
            spheres,
            rays: random_rays(n, lo, hi, 11),
            light: light(cover),
        }
    };
    vec![
        camera(
            "course_camera",
            course_spheres(),
            COURSE_VIEW,
            (320, 180),
            false,
        ),
        random("course_random", course_spheres(), 65_536, false),
        camera("cover_camera", cover_spheres(), COVER_VIEW, (160, 90), true),
        random("cover_random", cover_spheres(), 16_384, true),
    ]
}

/// For every ray that hits, a shadow ray from its hit point (spawned on the
/// side it arrived from) to `light`, open at both ends.
fn shadow_rays(spheres: &[Sphere], rays: &[Ray], light: Vec3) -> Vec<Ray> {
    rays.iter()
        .filter_map(|r| {
            let h = closest_hit(r, spheres)?;
            let s = spheres[h.sphere as usize];
            let p = r.at(h.t);
            let outside = r.dir.dot(p - s.center) < 0.0;
            let o = s.spawn_origin(p, outside);
            let to = light - o;
            let d = to.length();
            Some(Ray::new(o, to / d).with_range(0.0, d))
        })
        .collect()
}

fn intersect(c: &mut Criterion) {
    for w in workloads() {
        let mut storage = vec![SphereChunk8::EMPTY; chunks_for(w.spheres.len())];
        let set = SphereSet::build(&w.spheres, &mut storage).unwrap();
        let packets: Vec<RayPacket8> = w.rays.chunks(8).map(RayPacket8::from_rays).collect();
        let scalar = |rays: &[Ray]| {
            rays.iter()
                .filter(|r| closest_hit(black_box(r), &w.spheres).is_some())
                .count()
        };
        let one_by_8 = |rays: &[Ray]| {
            rays.iter()
                .filter(|r| closest_hit_1x8(black_box(r), &set).is_some())
                .count()
        };
        let packet = |ps: &[RayPacket8]| {
            ps.iter()
                .map(|p| {
                    let mut hits = HitPacket8::NONE;
                    closest_hit_x8(black_box(p), &set, &mut hits);
                    (0..8).filter(|&l| hits.hit(l).is_some()).count()
                })
                .sum::<usize>()
        };
        // The three paths must agree before they are timed.
        let hits = scalar(&w.rays);
        assert_eq!(
            (one_by_8(&w.rays), packet(&packets)),
            (hits, hits),
            "{}",
            w.name
        );

        let mut g = c.benchmark_group(format!("closest/{}", w.name));
        g.throughput(Throughput::Elements(w.rays.len() as u64));
        g.bench_function("scalar", |b| b.iter(|| scalar(&w.rays)));
        g.bench_function("1x8", |b| b.iter(|| one_by_8(&w.rays)));
        g.bench_function("packet", |b| b.iter(|| packet(&packets)));
        g.finish();

        let shadows = shadow_rays(&w.spheres, &w.rays, w.light);
        let shadow_packets: Vec<RayPacket8> =
            shadows.chunks(8).map(RayPacket8::from_rays).collect();
        let any_scalar = |rays: &[Ray]| {
            rays.iter()
                .filter(|r| any_hit(black_box(r), &w.spheres))
                .count()
        };
        let any_1x8 = |rays: &[Ray]| {
            rays.iter()
                .filter(|r| any_hit_1x8(black_box(r), &set))
                .count()
        };
        let any_packet = |ps: &[RayPacket8]| {
            ps.iter()
                .map(|p| any_hit_x8(black_box(p), &set).count_ones() as usize)
                .sum::<usize>()
        };
        let blocked = any_scalar(&shadows);
        assert_eq!(
            (any_1x8(&shadows), any_packet(&shadow_packets)),
            (blocked, blocked),
            "{}",
            w.name
        );

        let mut g = c.benchmark_group(format!("shadow/{}", w.name));
        g.throughput(Throughput::Elements(shadows.len() as u64));
        g.bench_function("scalar", |b| b.iter(|| any_scalar(&shadows)));
        g.bench_function("1x8", |b| b.iter(|| any_1x8(&shadows)));
        g.bench_function("packet", |b| b.iter(|| any_packet(&shadow_packets)));
        g.finish();
    }
}

criterion_group!(benches, intersect);
criterion_main!(benches);
