//! Ray–sphere throughput: scalar reference vs one ray × 8 spheres (1×8) vs
//! 8-ray packets, on the course scene (4 spheres) and the cover scene (485),
//! with coherent camera rays and incoherent random rays; closest hit and
//! any hit. One criterion group per comparison, so the ratios come from one
//! run. Throughput counts rays; ray–sphere tests are rays × spheres.

use std::hint::black_box;

use criterion::{Criterion, Throughput, criterion_group, criterion_main};
use strata::trace::*;
use strata_runner::workload::{
    COURSE_VIEW, COVER_VIEW, View, camera_rays, course_spheres, cover_spheres, random_rays, ray_box,
};

struct Workload {
    name: &'static str,
    spheres: Vec<Sphere>,
    rays: Vec<Ray>,
}

/// Camera rays (coherent) and random rays (incoherent) for both scenes.
fn workloads() -> Vec<Workload> {
    let camera = |name, spheres, view: View, (w, h)| Workload {
        name,
        spheres,
        rays: camera_rays(view, w, h),
    };
    let random = |name, spheres, n, cover| {
        let (lo, hi) = ray_box(cover);
        Workload {
            name,
            spheres,
            rays: random_rays(n, lo, hi, 11),
        }
    };
    vec![
        camera("course_camera", course_spheres(), COURSE_VIEW, (320, 180)),
        random("course_random", course_spheres(), 65_536, false),
        camera("cover_camera", cover_spheres(), COVER_VIEW, (160, 90)),
        random("cover_random", cover_spheres(), 16_384, true),
    ]
}

fn intersect(c: &mut Criterion) {
    for w in workloads() {
        let mut storage = vec![SphereChunk8::EMPTY; chunks_for(w.spheres.len())];
        let set = SphereSet::build(&w.spheres, &mut storage).unwrap();
        let packets: Vec<RayPacket8> = w.rays.chunks(8).map(RayPacket8::from_rays).collect();

        let mut g = c.benchmark_group(format!("closest/{}", w.name));
        g.throughput(Throughput::Elements(w.rays.len() as u64));
        g.bench_function("scalar", |b| {
            b.iter(|| {
                w.rays
                    .iter()
                    .filter(|r| closest_hit(black_box(r), &w.spheres).is_some())
                    .count()
            })
        });
        g.bench_function("1x8", |b| {
            b.iter(|| {
                w.rays
                    .iter()
                    .filter(|r| closest_hit_1x8(black_box(r), &set).is_some())
                    .count()
            })
        });
        g.bench_function("packet", |b| {
            b.iter(|| {
                let mut n = 0u32;
                for p in &packets {
                    let mut hits = HitPacket8::NONE;
                    closest_hit_x8(black_box(p), &set, &mut hits);
                    n += hits.t.to_bitmask();
                }
                n
            })
        });
        g.finish();

        let mut g = c.benchmark_group(format!("any/{}", w.name));
        g.throughput(Throughput::Elements(w.rays.len() as u64));
        g.bench_function("scalar", |b| {
            b.iter(|| {
                w.rays
                    .iter()
                    .filter(|r| any_hit(black_box(r), &w.spheres))
                    .count()
            })
        });
        g.bench_function("1x8", |b| {
            b.iter(|| {
                w.rays
                    .iter()
                    .filter(|r| any_hit_1x8(black_box(r), &set))
                    .count()
            })
        });
        g.bench_function("packet", |b| {
            b.iter(|| {
                packets
                    .iter()
                    .map(|p| any_hit_x8(black_box(p), &set).count_ones())
                    .sum::<u32>()
            })
        });
        g.finish();
    }
}

criterion_group!(benches, intersect);
criterion_main!(benches);
