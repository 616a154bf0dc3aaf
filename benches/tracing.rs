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
use strata_runner::workload::{shadow_rays, trace_workloads};

fn intersect(c: &mut Criterion) {
    for w in trace_workloads() {
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
                    hits.t
                        .simd_lt(wide::f32x8::splat(f32::INFINITY))
                        .to_bitmask()
                        .count_ones() as usize
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
