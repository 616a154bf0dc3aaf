//! The suite of `strata bench`: the fixed workloads and comparisons
//! (documented in the module docs of `crate::bench`).

use anyhow::Result;
use glam::{Vec2, Vec3};
use strata::mapping::{self, Cone, rejection};
use strata::rng::{Pcg32, STREAM, next_f32};
use strata::trace::*;
use strata::{Halton, Independent, Sobol, Stratified, UniformGrid, ZSobol};

use crate::job::{Job, run, run_with_sampler};
use crate::scenes::{SceneBuffers, built_in};
use crate::workload::{SpheresAsPrimitives, sampler_pattern, shadow_rays, trace_workloads};

use super::harness::{
    Contender, Done, Group, Options, RENDER_COST, Ratios, Report, Suite, contender, cpu_model,
    goals,
};

fn uniforms(n: usize) -> Vec<Vec2> {
    let mut rng = Pcg32::new(7, STREAM);
    (0..n)
        .map(|_| Vec2::new(next_f32(&mut rng), next_f32(&mut rng)))
        .collect()
}

fn checksum(v: Vec3) -> u64 {
    (v.x + v.y + v.z).to_bits() as u64
}

fn sampling(s: &mut Suite<'_>) -> Result<()> {
    const N: usize = 1 << 16;
    let us = uniforms(N);
    let cone = Cone::from_cos(0.8);
    let us = &us;
    // Generic over the mapping so each call inlines, like the cone's.
    fn map3<'a>(us: &'a [Vec2], f: impl Fn(Vec2) -> Vec3 + 'a) -> impl FnMut() -> u64 + 'a {
        move || checksum(us.iter().fold(Vec3::ZERO, |a, &u| a + f(u)))
    }
    let mut cs = vec![
        contender(
            "uniform_sphere",
            N as f64,
            map3(us, mapping::sample_uniform_sphere),
        ),
        contender(
            "uniform_hemisphere",
            N as f64,
            map3(us, mapping::sample_uniform_hemisphere),
        ),
        contender(
            "cosine_hemisphere",
            N as f64,
            map3(us, mapping::sample_cosine_hemisphere),
        ),
    ];
    cs.push(contender("uniform_cone", N as f64, || {
        checksum(us.iter().fold(Vec3::ZERO, |a, &u| {
            a + mapping::sample_uniform_cone(u, cone)
        }))
    }));
    cs.push(contender("concentric_disk", N as f64, || {
        checksum(us.iter().fold(Vec3::ZERO, |a, &u| {
            a + mapping::sample_concentric_disk(u).extend(0.0)
        }))
    }));
    cs.push(contender("polar_disk", N as f64, || {
        checksum(us.iter().fold(Vec3::ZERO, |a, &u| {
            a + mapping::sample_polar_disk(u).extend(0.0)
        }))
    }));
    s.compare("sampling", "mapping", "samples", cs, Ratios::None)?;

    let rng = std::cell::RefCell::new(Pcg32::new(1, STREAM));
    let draw = |f: &dyn Fn(&mut Pcg32) -> Vec3| {
        let mut r = rng.borrow_mut();
        checksum((0..N).fold(Vec3::ZERO, |a, _| a + f(&mut r)))
    };
    let u2 = |r: &mut Pcg32| Vec2::new(next_f32(r), next_f32(r));
    s.compare(
        "sampling",
        "disk",
        "samples",
        vec![
            contender("concentric", N as f64, || {
                draw(&|r| mapping::sample_concentric_disk(u2(r)).extend(0.0))
            }),
            contender("polar", N as f64, || {
                draw(&|r| mapping::sample_polar_disk(u2(r)).extend(0.0))
            }),
            contender("rejection", N as f64, || {
                draw(&|r| rejection::rejection_unit_disk(r).extend(0.0))
            }),
        ],
        Ratios::Rate,
    )?;
    s.compare(
        "sampling",
        "sphere",
        "samples",
        vec![
            contender("analytic", N as f64, || {
                draw(&|r| mapping::sample_uniform_sphere(u2(r)))
            }),
            contender("rejection", N as f64, || {
                draw(&|r| rejection::rejection_unit_sphere(r))
            }),
        ],
        Ratios::Rate,
    )?;
    s.compare(
        "sampling",
        "cosine_hemisphere",
        "samples",
        vec![
            contender("analytic", N as f64, || {
                draw(&|r| mapping::sample_cosine_hemisphere(u2(r)))
            }),
            contender("rejection", N as f64, || {
                draw(&|r| rejection::rejection_cosine_hemisphere(r))
            }),
        ],
        Ratios::Rate,
    )?;

    s.compare(
        "sampling",
        "uniform_hemisphere",
        "samples",
        vec![
            contender("analytic", N as f64, || {
                draw(&|r| mapping::sample_uniform_hemisphere(u2(r)))
            }),
            contender("rejection", N as f64, || {
                draw(&|r| rejection::rejection_uniform_hemisphere(r))
            }),
        ],
        Ratios::Rate,
    )?;

    const SPP: u32 = 16;
    let units = (16 * 16 * SPP) as f64;
    let mut ind = Independent::new(SPP, 1).expect("spp > 0");
    let mut grid = UniformGrid::new(SPP, 1).expect("spp > 0");
    let mut st = Stratified::new(SPP, 1).expect("spp > 0");
    let mut sob = Sobol::new(SPP, 1).expect("spp > 0");
    let mut hal = Halton::new(SPP, 1).expect("spp > 0");
    // The pattern's 16 × 16 pixels as the image.
    let mut zs = ZSobol::new(SPP, 1, glam::UVec2::splat(16))?;
    s.compare(
        "sampling",
        "sampler",
        "pixel samples",
        vec![
            contender("independent", units, || {
                sampler_pattern(&mut ind, SPP).to_bits() as u64
            }),
            contender("grid", units, || {
                sampler_pattern(&mut grid, SPP).to_bits() as u64
            }),
            contender("stratified", units, || {
                sampler_pattern(&mut st, SPP).to_bits() as u64
            }),
            contender("sobol", units, || {
                sampler_pattern(&mut sob, SPP).to_bits() as u64
            }),
            contender("halton", units, || {
                sampler_pattern(&mut hal, SPP).to_bits() as u64
            }),
            contender("zsobol", units, || {
                sampler_pattern(&mut zs, SPP).to_bits() as u64
            }),
        ],
        Ratios::Rate,
    )?;
    render_cost(s)
}

/// What a render costs with each sampler, against the independent one:
/// [`RENDER_COST`] (`week09`, 160 × 90, 16 spp, depth 5, one thread),
/// timed by the render, with the must-fail control (the independent
/// sampler slowed on purpose, [`Slowed`]) last.
fn render_cost(s: &mut Suite<'_>) -> Result<()> {
    const SPP: u32 = 16;
    let scene = built_in("week09").ok_or_else(|| anyhow::anyhow!("no built-in scene `week09`"))?;
    let job = |sampler| Job {
        max_depth: 5,
        sampler,
        threads: 1,
        ..Job::new(&scene, 160, 90, SPP)
    };
    let paths = (160 * 90 * SPP) as f64;
    let seconds = |r: Result<crate::job::Rendered>| Ok(Done::Seconds(r?.wall.as_secs_f64()));
    let mut cs: Vec<Contender<'_>> = crate::job::SamplerKind::ALL
        .into_iter()
        .map(|kind| {
            let j = job(kind);
            Contender {
                name: kind.name().into(),
                units: paths,
                work: Box::new(move || seconds(run(&j, &|_| {}))),
            }
        })
        .collect();
    let j = job(crate::job::SamplerKind::Independent);
    let slowed = Slowed(Independent::new(SPP, j.seed).expect("spp > 0"));
    cs.push(Contender {
        name: "slowed control".into(),
        units: paths,
        work: Box::new(move || seconds(run_with_sampler(&j, slowed.clone()))),
    });
    let names: Vec<String> = cs.iter().map(|c| c.name.clone()).collect();
    let cores = s.compare("sampling", RENDER_COST, "camera paths", cs, Ratios::Cost)?;
    for (name, c) in names.iter().zip(cores) {
        if let Some(c) = c {
            s.effective_cores.push((format!("{RENDER_COST} {name}"), c));
        }
    }
    Ok(())
}

/// Rounds of busy work [`Slowed`] adds to every value it draws: a
/// [`RENDER_COST`] render with it costs 1.40 times the independent
/// sampler's instructions (callgrind on an x86-64-v3 build: 220.8 M in
/// `render_tile`, 88.1 M more in `Slowed::burn`), above the 1.3 the
/// control must reach.
pub const SLOWED_ROUNDS: u32 = 14;

/// The independent sampler with [`SLOWED_ROUNDS`] rounds of a
/// multiply–xorshift hash added to every value drawn: the same values,
/// a dearer sampler. The must-fail control of the render-cost goals.
#[derive(Clone, Debug)]
pub struct Slowed(pub Independent);

impl Slowed {
    #[inline(never)]
    fn burn() {
        let mut x = std::hint::black_box(0x9e37_79b9_7f4a_7c15u64);
        for _ in 0..SLOWED_ROUNDS {
            x ^= x >> 29;
            x = x.wrapping_mul(0xbf58_476d_1ce4_e5b9);
        }
        std::hint::black_box(x);
    }
}

impl strata::Sampler for Slowed {
    fn samples_per_pixel(&self) -> u32 {
        self.0.samples_per_pixel()
    }
    fn start_pixel_sample(&mut self, pixel: glam::UVec2, index: u32) {
        self.0.start_pixel_sample(pixel, index);
    }
    fn pixel_2d(&mut self) -> Vec2 {
        Slowed::burn();
        self.0.pixel_2d()
    }
    fn next_1d(&mut self) -> f32 {
        Slowed::burn();
        self.0.next_1d()
    }
    fn next_2d(&mut self) -> Vec2 {
        Slowed::burn();
        self.0.next_2d()
    }
}

fn intersection(s: &mut Suite<'_>) -> Result<()> {
    for w in trace_workloads() {
        let mut buffers = SceneBuffers::new(w.spheres.len(), false);
        let (set, _) = buffers.trace(&w.spheres)?;
        let spheres = &w.spheres;
        let packets: Vec<RayPacket8> = w.rays.chunks(8).map(RayPacket8::from_rays).collect();
        let n = w.rays.len() as f64;
        let rays = &w.rays;
        let first = s.figures.len();
        s.compare(
            "intersection",
            &format!("closest/{}", w.name),
            "rays",
            vec![
                contender("scalar", n, || {
                    rays.iter()
                        .filter(|r| closest_hit(spheres, r).is_some())
                        .count() as u64
                }),
                contender("1x8", n, || {
                    rays.iter()
                        .filter(|r| closest_hit_1x8(&set, r).is_some())
                        .count() as u64
                }),
                contender("packet", n, || {
                    packets
                        .iter()
                        .map(|p| {
                            let mut h = HitPacket8::NONE;
                            closest_hit_x8(&set, p, &mut h);
                            h.hit_bits().count_ones() as u64
                        })
                        .sum()
                }),
            ],
            Ratios::Rate,
        )?;
        let shadows = shadow_rays(spheres, rays, w.light);
        let shadow_packets: Vec<RayPacket8> =
            shadows.chunks(8).map(RayPacket8::from_rays).collect();
        let m = shadows.len() as f64;
        let sh = &shadows;
        s.compare(
            "intersection",
            &format!("shadow/{}", w.name),
            "rays",
            vec![
                contender("scalar", m, || {
                    sh.iter().filter(|r| any_hit(spheres, r)).count() as u64
                }),
                contender("1x8", m, || {
                    sh.iter().filter(|r| any_hit_1x8(&set, r)).count() as u64
                }),
                contender("packet", m, || {
                    shadow_packets
                        .iter()
                        .map(|p| any_hit_x8(&set, p).count_ones() as u64)
                        .sum()
                }),
            ],
            Ratios::Rate,
        )?;
        // Closest-hit rays test every sphere: tests/s = rays/s × spheres.
        for f in &mut s.figures[first..first + 3] {
            f.extra.push((
                "M tests/s".into(),
                f.mega_per_s.median * spheres.len() as f64,
            ));
        }
    }
    Ok(())
}

/// The BVH against the brute-force 8-wide loop, one ray at a time and in
/// packets, and the BVH over the same spheres as a caller's primitives
/// (`SpheresAsPrimitives`: their boxes, `intersect_sphere` as the routine)
/// with its brute-force loop: closest and any hit on the cover layout (camera rays of the
/// cover camera at 1280 × 720; 10⁶ incoherent rays from
/// `[-11, 11] × [0, 2] × [-11, 11]`, directions uniform on the sphere) and
/// on 10 000 random spheres (10⁶ incoherent rays from their box); then the
/// build time of 10⁶ spheres. Brute force traces the first 20 000 rays of
/// the 10 000-sphere workload (rates are per ray).
fn bvh(s: &mut Suite<'_>) -> Result<()> {
    use crate::scenes::{COVER_VIEW, cover_spheres};
    use crate::workload::{camera_rays, random_rays, random_spheres_10k};
    let (lo, hi) = crate::workload::ray_box(true);
    let workloads = [
        (
            "cover_camera_720p",
            cover_spheres(),
            camera_rays(COVER_VIEW, 1280, 720),
        ),
        (
            "cover_incoherent",
            cover_spheres(),
            random_rays(1_000_000, lo, hi, 12),
        ),
        (
            "random10k_incoherent",
            random_spheres_10k(),
            random_rays(1_000_000, Vec3::splat(-20.0), Vec3::splat(20.0), 13),
        ),
    ];
    for (name, spheres, rays) in &workloads {
        let mut buffers = SceneBuffers::new(spheres.len(), true);
        let (set, tree) = buffers.trace(spheres)?;
        let tree = tree.expect("buffers with BVH room");
        let brute = &rays[..rays.len().min(if spheres.len() > 1000 {
            20_000
        } else {
            rays.len()
        })];
        let packets: Vec<RayPacket8> = rays.chunks(8).map(RayPacket8::from_rays).collect();
        // The same spheres as a caller's own primitives.
        let prims = SpheresAsPrimitives(spheres);
        let size = primitive_bvh_storage_for(spheres.len());
        let (mut prim_nodes, mut prim_ids) = (vec![BvhNode8::EMPTY; size.nodes], vec![0; size.ids]);
        let prim_tree = PrimitiveBvh::build(&prims, &mut prim_nodes, &mut prim_ids)?;
        let (set, tree, packets, prim_tree, prims) = (&set, &tree, &packets, &prim_tree, &prims);
        // Packets traversed as packets throughout, and handing subtrees
        // that at most 2 of their rays reach to the single-ray traversal.
        let (no_fallback, fallback_2) =
            (&tree.with_packet_fallback(0), &tree.with_packet_fallback(2));
        let n = rays.len() as f64;
        let closest = |r: Option<Hit>| r.map_or(0, |h| h.sphere as u64);
        s.compare(
            "bvh",
            &format!("bvh closest/{name}"),
            "rays",
            vec![
                contender("brute 1x8", brute.len() as f64, || {
                    brute.iter().map(|r| closest(closest_hit_1x8(set, r))).sum()
                }),
                // One traversal stack per call, as the renderer keeps one
                // per tile.
                contender("bvh", n, || {
                    let mut stack = BvhStack::new();
                    rays.iter()
                        .map(|r| closest(tree.closest_hit_with(r, &mut stack)))
                        .sum()
                }),
                contender("primitive bvh", n, || {
                    let mut stack = BvhStack::new();
                    rays.iter()
                        .map(|r| {
                            prim_tree
                                .closest_hit_with(r, &mut stack)
                                .map_or(0, |h| h.primitive as u64)
                        })
                        .sum()
                }),
                contender("primitive brute", brute.len() as f64, || {
                    brute
                        .iter()
                        .map(|r| closest_primitive_hit(prims, r).map_or(0, |h| h.primitive as u64))
                        .sum()
                }),
                contender("bvh packet", n, || {
                    let mut stack = BvhStack::new();
                    packets.iter().fold(0u64, |a, p| {
                        let mut h = HitPacket8::NONE;
                        no_fallback.closest_hit_x8_with(p, &mut h, &mut stack);
                        a.wrapping_add(h.spheres()[0] as u64)
                    })
                }),
                contender("bvh packet, fallback 2", n, || {
                    let mut stack = BvhStack::new();
                    packets.iter().fold(0u64, |a, p| {
                        let mut h = HitPacket8::NONE;
                        fallback_2.closest_hit_x8_with(p, &mut h, &mut stack);
                        a.wrapping_add(h.spheres()[0] as u64)
                    })
                }),
            ],
            Ratios::Rate,
        )?;
        s.compare(
            "bvh",
            &format!("bvh any/{name}"),
            "rays",
            vec![
                contender("brute 1x8", brute.len() as f64, || {
                    brute.iter().filter(|r| any_hit_1x8(set, r)).count() as u64
                }),
                contender("bvh", n, || {
                    let mut stack = BvhStack::new();
                    rays.iter()
                        .filter(|r| tree.any_hit_with(r, &mut stack))
                        .count() as u64
                }),
                contender("primitive bvh", n, || {
                    let mut stack = BvhStack::new();
                    rays.iter()
                        .filter(|r| prim_tree.any_hit_with(r, &mut stack))
                        .count() as u64
                }),
            ],
            Ratios::Rate,
        )?;
    }
    // Build time of 10⁶ spheres (the random layout, scaled up).
    let mut rng = Pcg32::new(1_000_000, STREAM);
    let million: Vec<Sphere> = (0..1_000_000)
        .map(|_| {
            let mut f = || next_f32(&mut rng);
            Sphere::new(
                Vec3::new(f(), f(), f()) * 200.0 - Vec3::splat(100.0),
                0.05 + 0.3 * f(),
            )
        })
        .collect();
    let size = bvh_storage_for(million.len());
    let mut nodes = vec![BvhNode8::EMPTY; size.nodes];
    let mut lanes = vec![0.0f32; size.lanes];
    let mut ids = vec![0u32; size.ids];
    s.compare(
        "bvh",
        "bvh build/1M spheres",
        "spheres",
        vec![contender("build", million.len() as f64, || {
            Bvh::build(&million, &mut nodes, &mut lanes, &mut ids)
                .map_or(0, |b| b.node_count() as u64)
        })],
        Ratios::None,
    )?;
    Ok(())
}

fn rendering(s: &mut Suite<'_>) -> Result<()> {
    for (name, spp, depth) in [("week09", 32u32, 5u32), ("cover", 8, 50)] {
        let scene = built_in(name).ok_or_else(|| anyhow::anyhow!("no built-in scene `{name}`"))?;
        let integrator = s.options.integrator;
        let job = |threads| Job {
            max_depth: depth,
            threads,
            integrator,
            ..Job::new(&scene, 320, 180, spp)
        };
        let probe = run(&job(1), &|_| {})?;
        let paths = probe.stats.paths as f64;
        let rays_per_path = (probe.stats.rays + probe.stats.shadow_rays) as f64 / paths;
        let first = s.figures.len();
        // Timed by the render itself: the tracing, without building the
        // scene's core structures and the thread pool.
        let render = |threads: usize| -> Contender<'_> {
            let j = job(threads);
            let name = if threads == 1 {
                "1 thread"
            } else {
                "2 threads"
            };
            Contender {
                name: name.into(),
                units: paths,
                work: Box::new(move || Ok(Done::Seconds(run(&j, &|_| {})?.wall.as_secs_f64()))),
            }
        };
        let cores = s.compare(
            "rendering",
            &format!("render/{name}"),
            "camera paths",
            vec![render(1), render(2)],
            Ratios::Rate,
        )?;
        if let Some(c) = cores[1] {
            s.effective_cores
                .push((format!("render/{name} 2 threads"), c));
        }
        for f in &mut s.figures[first..] {
            f.extra
                .push(("M rays/s".into(), f.mega_per_s.median * rays_per_path));
        }
    }
    // The cover at the book's settings on 2 threads, BVH (auto) vs brute
    // force: the throughput figure.
    let scene = built_in("cover").ok_or_else(|| anyhow::anyhow!("no built-in scene `cover`"))?;
    let integrator = s.options.integrator;
    let job = |bvh| Job {
        max_depth: 50,
        bvh,
        integrator,
        ..Job::new(&scene, 400, 225, 32)
    };
    let render = |name: &str, bvh| -> Contender<'_> {
        let j = job(bvh);
        Contender {
            name: name.into(),
            units: 400.0 * 225.0 * 32.0,
            work: Box::new(move || Ok(Done::Seconds(run(&j, &|_| {})?.wall.as_secs_f64()))),
        }
    };
    s.compare(
        "rendering",
        "render/cover_400x225_32spp",
        "camera paths",
        vec![
            render("2 threads, brute force", crate::scenes::BvhMode::Off),
            render("2 threads", crate::scenes::BvhMode::Auto),
        ],
        Ratios::Rate,
    )?;
    Ok(())
}

/// Runs the whole suite, reporting each comparison's name as it starts.
pub fn run_suite(options: Options, progress: &dyn Fn(&str)) -> Result<Report> {
    let mut s = Suite {
        options,
        figures: vec![],
        ratios: vec![],
        effective_cores: vec![],
        progress,
    };
    let runs = |g: Group| options.group.is_none_or(|only| only == g);
    if runs(Group::Sampling) {
        sampling(&mut s)?;
    }
    if runs(Group::Intersection) {
        intersection(&mut s)?;
    }
    if runs(Group::Bvh) {
        bvh(&mut s)?;
    }
    if runs(Group::Rendering) {
        rendering(&mut s)?;
    }
    let goals = goals(&s.ratios, &s.effective_cores);
    Ok(Report {
        version: env!("CARGO_PKG_VERSION").into(),
        simd: strata::trace::simd_level().name().into(),
        integrator: options.integrator.name().into(),
        cpu: cpu_model(),
        cpus: std::thread::available_parallelism().map_or(1, |n| n.get()),
        repetitions: options.repetitions,
        figures: s.figures,
        ratios: s.ratios,
        effective_cores: s.effective_cores,
        goals,
    })
}

/// The number of comparisons the whole suite runs (for a progress bar).
pub const COMPARISONS: u64 = Group::Sampling.comparisons()
    + Group::Intersection.comparisons()
    + Group::Bvh.comparisons()
    + Group::Rendering.comparisons();
