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
use strata::trace::*;
use strata_runner::scenes::SceneBuffers;
use strata_runner::workload::{shadow_rays, trace_workloads};

fn intersect(c: &mut Criterion) {
    for w in trace_workloads() {
        let mut buffers = SceneBuffers::new(w.spheres.len(), false);
        let (set, _) = buffers.trace(&w.spheres).unwrap();
        let packets: Vec<RayPacket8> = w.rays.chunks(8).map(RayPacket8::from_rays).collect();
        let scalar = |rays: &[Ray]| {
            rays.iter()
                .filter(|r| closest_hit(&w.spheres, black_box(r)).is_some())
                .count()
        };
        let one_by_8 = |rays: &[Ray]| {
            rays.iter()
                .filter(|r| closest_hit_1x8(&set, black_box(r)).is_some())
                .count()
        };
        let packet = |ps: &[RayPacket8]| {
            ps.iter()
                .map(|p| {
                    let mut hits = HitPacket8::NONE;
                    closest_hit_x8(&set, black_box(p), &mut hits);
                    hits.hit_bits().count_ones() as usize
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
                .filter(|r| any_hit(&w.spheres, black_box(r)))
                .count()
        };
        let any_1x8 = |rays: &[Ray]| {
            rays.iter()
                .filter(|r| any_hit_1x8(&set, black_box(r)))
                .count()
        };
        let any_packet = |ps: &[RayPacket8]| {
            ps.iter()
                .map(|p| any_hit_x8(&set, black_box(p)).count_ones() as usize)
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

/// The cover layout from `core/tests/data/cover.csv` (the reference
/// sphere list; the built-in scene is tested equal to it), built into the
/// bench so a moved file is a compile error.
fn cover_from_csv() -> Vec<Sphere> {
    include_str!("../core/tests/data/cover.csv")
        .lines()
        .skip(1)
        .filter(|l| !l.trim().is_empty())
        .map(|l| {
            let v: Vec<f32> = l.split(',').map(|x| x.trim().parse().unwrap()).collect();
            Sphere::new(glam::Vec3::new(v[0], v[1], v[2]), v[3])
        })
        .collect()
}

/// BVH vs the brute-force 8-wide loop on the cover layout (from its CSV)
/// and on 10 000 random spheres: 10⁵ incoherent rays, closest hit one ray
/// at a time and in packets, and any hit.
fn bvh(c: &mut Criterion) {
    use strata_runner::workload::{random_rays, random_spheres_10k, ray_box};
    let (lo, hi) = ray_box(true);
    let box10k = (glam::Vec3::splat(-20.0), glam::Vec3::splat(20.0));
    for (name, spheres, (lo, hi)) in [
        ("cover", cover_from_csv(), (lo, hi)),
        ("random10k", random_spheres_10k(), box10k),
    ] {
        let rays = random_rays(100_000, lo, hi, 12);
        let mut buffers = SceneBuffers::new(spheres.len(), true);
        let (set, tree) = buffers.trace(&spheres).unwrap();
        let tree = tree.unwrap();
        let packets: Vec<RayPacket8> = rays.chunks(8).map(RayPacket8::from_rays).collect();
        let mut g = c.benchmark_group(format!("bvh_closest/{name}"));
        g.sample_size(10);
        let brute = &rays[..if spheres.len() > 1000 {
            2_000
        } else {
            rays.len()
        }];
        g.throughput(Throughput::Elements(brute.len() as u64));
        g.bench_function("brute_1x8", |b| {
            b.iter(|| {
                brute
                    .iter()
                    .filter(|r| closest_hit_1x8(&set, black_box(r)).is_some())
                    .count()
            })
        });
        g.throughput(Throughput::Elements(rays.len() as u64));
        g.bench_function("bvh", |b| {
            b.iter(|| {
                let mut stack = BvhStack::new();
                rays.iter()
                    .filter(|r| tree.closest_hit_with(black_box(r), &mut stack).is_some())
                    .count()
            })
        });
        g.bench_function("bvh_packet", |b| {
            b.iter(|| {
                let mut stack = BvhStack::new();
                packets.iter().fold(0i64, |a, p| {
                    let mut h = HitPacket8::NONE;
                    tree.closest_hit_x8_with(black_box(p), &mut h, &mut stack);
                    a + h.spheres()[0] as i64
                })
            })
        });
        g.bench_function("bvh_any", |b| {
            b.iter(|| {
                let mut stack = BvhStack::new();
                rays.iter()
                    .filter(|r| tree.any_hit_with(black_box(r), &mut stack))
                    .count()
            })
        });
        g.finish();
    }
}

criterion_group!(benches, intersect, bvh);
criterion_main!(benches);
