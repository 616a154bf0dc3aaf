//! Sampling throughput: every mapping, analytic vs the course's rejection
//! methods vs `rand_distr` (a peer), and every sampler kind. One group per
//! comparison so the ratios come from one run. Inputs are drawn from a
//! seeded PCG32 before timing, or, where the method itself draws (rejection
//! loops), every contender draws from the same kind of generator inside the
//! timed loop.

use std::hint::black_box;

use criterion::{Criterion, Throughput, criterion_group, criterion_main};
use glam::{Vec2, Vec3};
use rand_distr::{Distribution, UnitDisc, UnitSphere};
use strata::mapping::{self, rejection};
use strata::rng::{Pcg32, STREAM, next_f32};
use strata::sampler::{Halton, Independent, Sobol, Stratified, UniformGrid, ZSobol};
use strata_runner::workload::sampler_pattern;

const N: usize = 4096;

fn inputs() -> Vec<Vec2> {
    let mut rng = Pcg32::new(7, STREAM);
    (0..N)
        .map(|_| Vec2::new(next_f32(&mut rng), next_f32(&mut rng)))
        .collect()
}

fn u2(rng: &mut Pcg32) -> Vec2 {
    Vec2::new(next_f32(rng), next_f32(rng))
}

/// Each mapping alone, on precomputed `u`.
fn mappings(c: &mut Criterion) {
    let us = inputs();
    let mut g = c.benchmark_group("mapping");
    g.throughput(Throughput::Elements(N as u64));
    let mut run3 = |name: &str, f: &dyn Fn(Vec2) -> Vec3| {
        g.bench_function(name, |b| {
            b.iter(|| us.iter().fold(Vec3::ZERO, |acc, &u| acc + f(black_box(u))))
        });
    };
    run3("uniform_sphere", &mapping::sample_uniform_sphere);
    run3("uniform_hemisphere", &mapping::sample_uniform_hemisphere);
    run3("cosine_hemisphere", &mapping::sample_cosine_hemisphere);
    let cone = mapping::Cone::from_cos(0.8);
    run3("uniform_cone", &|u| mapping::sample_uniform_cone(u, cone));
    run3("invert_cosine_hemisphere", &|u| {
        let w = mapping::sample_cosine_hemisphere(u);
        mapping::invert_cosine_hemisphere(w).extend(mapping::pdf_cosine_hemisphere(w))
    });
    let mut run2 = |name: &str, f: &dyn Fn(Vec2) -> Vec2| {
        g.bench_function(name, |b| {
            b.iter(|| us.iter().fold(Vec2::ZERO, |acc, &u| acc + f(black_box(u))))
        });
    };
    run2("concentric_disk", &mapping::sample_concentric_disk);
    run2("polar_disk", &mapping::sample_polar_disk);
    g.finish();
}

/// Points in the unit disk: analytic (two draws + map), rejection, peer.
fn disk(c: &mut Criterion) {
    let mut g = c.benchmark_group("disk");
    g.throughput(Throughput::Elements(N as u64));
    let mut rng = Pcg32::new(1, STREAM);
    g.bench_function("concentric", |b| {
        b.iter(|| {
            (0..N).fold(Vec2::ZERO, |a, _| {
                a + mapping::sample_concentric_disk(u2(&mut rng))
            })
        })
    });
    g.bench_function("polar", |b| {
        b.iter(|| {
            (0..N).fold(Vec2::ZERO, |a, _| {
                a + mapping::sample_polar_disk(u2(&mut rng))
            })
        })
    });
    g.bench_function("rejection", |b| {
        b.iter(|| {
            (0..N).fold(Vec2::ZERO, |a, _| {
                a + rejection::rejection_unit_disk(&mut rng)
            })
        })
    });
    g.bench_function("rand_distr_unit_disc", |b| {
        b.iter(|| {
            (0..N).fold(Vec2::ZERO, |a, _| {
                let p: [f32; 2] = UnitDisc.sample(&mut rng);
                a + Vec2::from(p)
            })
        })
    });
    g.finish();
}

/// Directions on the sphere and hemisphere: analytic, rejection, peer.
fn sphere(c: &mut Criterion) {
    let mut g = c.benchmark_group("sphere");
    g.throughput(Throughput::Elements(N as u64));
    let mut rng = Pcg32::new(2, STREAM);
    g.bench_function("uniform_sphere", |b| {
        b.iter(|| {
            (0..N).fold(Vec3::ZERO, |a, _| {
                a + mapping::sample_uniform_sphere(u2(&mut rng))
            })
        })
    });
    g.bench_function("rejection_unit_sphere", |b| {
        b.iter(|| {
            (0..N).fold(Vec3::ZERO, |a, _| {
                a + rejection::rejection_unit_sphere(&mut rng)
            })
        })
    });
    g.bench_function("rand_distr_unit_sphere", |b| {
        b.iter(|| {
            (0..N).fold(Vec3::ZERO, |a, _| {
                let p: [f32; 3] = UnitSphere.sample(&mut rng);
                a + Vec3::from(p)
            })
        })
    });
    g.finish();

    let mut g = c.benchmark_group("hemisphere");
    g.throughput(Throughput::Elements(N as u64));
    g.bench_function("uniform", |b| {
        b.iter(|| {
            (0..N).fold(Vec3::ZERO, |a, _| {
                a + mapping::sample_uniform_hemisphere(u2(&mut rng))
            })
        })
    });
    g.bench_function("rejection_uniform_flip", |b| {
        b.iter(|| {
            (0..N).fold(Vec3::ZERO, |a, _| {
                a + rejection::rejection_uniform_hemisphere(&mut rng)
            })
        })
    });
    g.bench_function("cosine", |b| {
        b.iter(|| {
            (0..N).fold(Vec3::ZERO, |a, _| {
                a + mapping::sample_cosine_hemisphere(u2(&mut rng))
            })
        })
    });
    g.bench_function("rejection_cosine_normal_plus_unit", |b| {
        b.iter(|| {
            (0..N).fold(Vec3::ZERO, |a, _| {
                a + rejection::rejection_cosine_hemisphere(&mut rng)
            })
        })
    });
    g.finish();
}

/// One pixel sample as a depth-2 path consumes a sampler
/// ([`sampler_pattern`]). Throughput counts pixel samples.
fn samplers(c: &mut Criterion) {
    const SPP: u32 = 16;
    let mut g = c.benchmark_group("sampler");
    g.throughput(Throughput::Elements((16 * 16 * SPP) as u64));
    let mut ind = Independent::new(SPP, 1).unwrap();
    g.bench_function("independent", |b| {
        b.iter(|| sampler_pattern(black_box(&mut ind), SPP))
    });
    let mut grid = UniformGrid::new(SPP, 1).unwrap();
    g.bench_function("grid", |b| {
        b.iter(|| sampler_pattern(black_box(&mut grid), SPP))
    });
    let mut st = Stratified::new(SPP, 1).unwrap();
    g.bench_function("stratified", |b| {
        b.iter(|| sampler_pattern(black_box(&mut st), SPP))
    });
    let mut sobol = Sobol::new(SPP, 1).unwrap();
    g.bench_function("sobol", |b| {
        b.iter(|| sampler_pattern(black_box(&mut sobol), SPP))
    });
    let mut halton = Halton::new(SPP, 1).unwrap();
    g.bench_function("halton", |b| {
        b.iter(|| sampler_pattern(black_box(&mut halton), SPP))
    });
    // The pattern's 16 × 16 pixels as the image.
    let mut zsobol = ZSobol::new(SPP, 1, glam::UVec2::splat(16)).unwrap();
    g.bench_function("zsobol", |b| {
        b.iter(|| sampler_pattern(black_box(&mut zsobol), SPP))
    });
    g.finish();
}

criterion_group!(benches, mappings, disk, sphere, samplers);
criterion_main!(benches);
