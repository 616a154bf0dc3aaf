//! The BVH only skips work: on millions of random rays over random scenes
//! (1 to 10 000 spheres, coincident and overlapping spheres, radius 0 and
//! 1000, all centres at one point, spheres kept out of the tree, rays
//! from inside, leaving surfaces, grazing and tangent, with NaN parts or
//! odd ranges), its closest and any hits equal the brute-force kernels bit for
//! bit, for one ray and for packets (traversed as packets, per ray, and
//! mixed). Storage too small is an error; degenerate input builds within
//! the depth bound.

use glam::Vec3;
use rand_core::Rng;
use rand_pcg::Pcg32;
use strata::trace::{
    BVH_MAX_DEPTH, Bvh, BvhError, BvhNode8, BvhStack, HitPacket8, Ray, RayPacket8, Sphere, any_hit,
    bvh_storage_for, closest_hit,
};

fn uniform(rng: &mut Pcg32) -> f32 {
    (rng.next_u32() >> 8) as f32 * (1.0 / 16_777_216.0)
}

pub(super) fn range(rng: &mut Pcg32, lo: f32, hi: f32) -> f32 {
    lo + (hi - lo) * uniform(rng)
}

pub(super) fn unit(rng: &mut Pcg32) -> Vec3 {
    loop {
        let v = Vec3::new(
            range(rng, -1.0, 1.0),
            range(rng, -1.0, 1.0),
            range(rng, -1.0, 1.0),
        );
        let l = v.length_squared();
        if l > 1e-4 && l <= 1.0 {
            return v.normalize();
        }
    }
}

/// Storage a tree is built into.
struct BvhBuffers {
    nodes: Vec<BvhNode8>,
    lanes: Vec<f32>,
    ids: Vec<u32>,
}

impl BvhBuffers {
    fn new(n: usize) -> Self {
        let s = bvh_storage_for(n);
        Self {
            nodes: vec![BvhNode8::EMPTY; s.nodes],
            lanes: vec![0.0; s.lanes],
            ids: vec![0; s.ids],
        }
    }
    fn build<'a>(&'a mut self, spheres: &[Sphere]) -> Bvh<'a> {
        Bvh::build(spheres, &mut self.nodes, &mut self.lanes, &mut self.ids).unwrap()
    }
}

/// The scenes: (name, spheres).
fn scenes() -> Vec<(String, Vec<Sphere>)> {
    let mut rng = Pcg32::new(2026, 8);
    let mut out = Vec::new();
    for n in [1usize, 7, 8, 9, 100, 10_000] {
        let spheres: Vec<Sphere> = (0..n)
            .map(|_| {
                let c = Vec3::new(
                    range(&mut rng, -10.0, 10.0),
                    range(&mut rng, -10.0, 10.0),
                    range(&mut rng, -10.0, 10.0),
                );
                Sphere::new(c, range(&mut rng, 0.0, 2.0 / (n as f32).cbrt()))
            })
            .collect();
        out.push((format!("random {n}"), spheres));
    }
    // Coincident, overlapping, radius 0 and 1000, NaN radius, a ground.
    let mut mixed = Vec::new();
    for k in 0..300 {
        let c = Vec3::new(
            range(&mut rng, -5.0, 5.0),
            range(&mut rng, 0.0, 2.0),
            range(&mut rng, -5.0, 5.0),
        );
        let r = match k % 10 {
            0 => 0.0,
            1 => f32::NAN,
            _ => range(&mut rng, 0.05, 0.8),
        };
        mixed.push(Sphere::new(c, r));
        if k % 7 == 0 {
            mixed.push(Sphere::new(c, r)); // coincident duplicate
        }
    }
    mixed.push(Sphere::new(Vec3::new(0.0, -1000.0, 0.0), 1000.0));
    mixed.push(Sphere::new(Vec3::new(3.0, 1.0, 0.0), 1000.0));
    out.push(("mixed".into(), mixed));
    // Every centre at one point, radii varied.
    let same: Vec<Sphere> = (0..500)
        .map(|k| Sphere::new(Vec3::new(1.0, 2.0, 3.0), 0.01 + (k % 37) as f32 * 0.05))
        .collect();
    out.push(("one centre".into(), same));
    // The cover layout.
    out.push(("cover".into(), strata_runner::scenes::cover_spheres()));
    // Two outliers kept out of the tree (a ground, and a huge sphere far
    // above), around small spheres, one of them a hair above the ground.
    let mut outliers: Vec<Sphere> = (0..200)
        .map(|_| {
            let c = Vec3::new(
                range(&mut rng, -5.0, 5.0),
                range(&mut rng, 0.1, 3.0),
                range(&mut rng, -5.0, 5.0),
            );
            Sphere::new(c, range(&mut rng, 0.05, 0.3))
        })
        .collect();
    outliers.insert(50, Sphere::new(Vec3::new(0.0, -1000.0, 0.0), 1000.0));
    outliers.push(Sphere::new(Vec3::new(0.0, 30_000.0, 0.0), 20_000.0));
    outliers.push(Sphere::new(Vec3::new(1.0, 0.25, 1.0), 0.25));
    out.push(("outliers".into(), outliers));
    out
}

/// Spheres whose box dwarfs the rest are kept out of the tree (and the
/// brute-force test above covers their scenes); spheres that all fit one
/// leaf, or of similar sizes, are not.
#[test]
fn outliers_are_the_spheres_that_dwarf_the_rest() {
    let want = [
        ("random 1", 0),
        ("random 7", 0),
        ("random 8", 0),
        ("random 9", 0),
        ("random 100", 0),
        ("random 10000", 0),
        ("mixed", 0), // two radius-1000 spheres: neither dwarfs the other
        ("one centre", 0),
        ("cover", 1),
        ("outliers", 2),
    ];
    let scenes = scenes();
    assert_eq!(scenes.len(), want.len());
    for ((name, spheres), (want_name, count)) in scenes.iter().zip(want) {
        assert_eq!(name, want_name);
        let mut store = BvhBuffers::new(spheres.len());
        let bvh = store.build(spheres);
        assert_eq!(bvh.outliers(), count, "{name}");
        assert!(bvh.built_from(spheres), "{name}");
    }
}

/// Rays for a scene: from a box around it, from sphere centres (inside),
/// and grazing/tangent rays aimed at sphere silhouettes.
fn rays(spheres: &[Sphere], n: usize, rng: &mut Pcg32) -> Vec<Ray> {
    let hittable: Vec<&Sphere> = spheres.iter().filter(|s| s.radius > 0.0).collect();
    (0..n)
        .map(|k| {
            let kind = k % 6;
            if kind == 0 || hittable.is_empty() {
                let o = Vec3::new(
                    range(rng, -14.0, 14.0),
                    range(rng, -14.0, 14.0),
                    range(rng, -14.0, 14.0),
                );
                return Ray::new(o, unit(rng));
            }
            let s = hittable[(rng.next_u32() as usize) % hittable.len()];
            match kind {
                1 => Ray::new(s.center, unit(rng)),
                4 | 5 => {
                    // Tangent where the sphere touches its box: at the
                    // extreme point along an axis, moving in the box face
                    // (along an axis, for kind 5), nudged by ulps.
                    let axis = (rng.next_u32() % 3) as usize;
                    let sign = if rng.next_u32() & 1 == 0 { 1.0 } else { -1.0 };
                    let mut n = Vec3::ZERO;
                    n[axis] = sign;
                    let mut d = unit(rng);
                    d[axis] = 0.0;
                    if kind == 5 {
                        d = Vec3::ZERO;
                        d[(axis + 1) % 3] = sign;
                    }
                    let d = d.normalize_or(Vec3::X);
                    let nudge = 1.0 + range(rng, -3.0, 3.0) * f32::EPSILON;
                    let target = s.center + n * s.radius * nudge;
                    Ray::new(target - d * range(rng, 0.1, 30.0), d)
                }
                _ => {
                    // Aim at a point on the silhouette (tangent), nudged
                    // by a few ulps in or out.
                    let d = unit(rng);
                    let side = d.any_orthonormal_vector();
                    let nudge = 1.0 + range(rng, -4.0, 4.0) * f32::EPSILON;
                    let target = s.center + side * s.radius * nudge;
                    let o = target - d * range(rng, 0.5, 30.0);
                    let r = Ray::new(o, d);
                    if kind == 3 {
                        r.with_range(range(rng, -1.0, 1.0), range(rng, 1.0, 60.0))
                    } else {
                        r
                    }
                }
            }
        })
        .collect()
}

#[test]
fn bvh_matches_brute_force_bit_for_bit() {
    let mut rng = Pcg32::new(7, 7);
    let mut total = 0;
    for (name, spheres) in scenes() {
        let mut store = BvhBuffers::new(spheres.len());
        let bvh = store.build(&spheres);
        assert!(bvh.depth() <= BVH_MAX_DEPTH, "{name}");
        assert!(bvh.node_count() <= bvh_storage_for(spheres.len()).nodes);
        // Fewer rays for the big scene: brute force is the slow side.
        let n = if spheres.len() > 1000 {
            40_000
        } else {
            160_000
        };
        let rays = rays(&spheres, n, &mut rng);
        // Packets for the first half of the rays (brute force is slow).
        assert_matches_brute_force(&name, &spheres, &bvh, &rays, n / 2);
        total += rays.len();
    }
    assert!(total >= 1_000_000, "{total} rays");
}

/// Ties: identical spheres give the lowest index, whichever leaf holds it.
/// One caller-owned stack serves every kind of query in any interleaving:
/// closest hits, any hits and packets (with every fallback, so packet
/// traversal hands subtrees to the single-ray stack mid-query), never
/// cleared between them, and every answer is the brute-force one.
#[test]
fn one_stack_serves_interleaved_queries() {
    let mut rng = Pcg32::new(11, 11);
    let mut stack = BvhStack::new();
    for (name, spheres) in scenes().into_iter().filter(|(_, s)| s.len() <= 1000) {
        let mut store = BvhBuffers::new(spheres.len());
        let bvh = store.build(&spheres);
        let rays = rays(&spheres, 2048, &mut rng);
        for (k, chunk) in rays.chunks(8).enumerate() {
            let packet = RayPacket8::from_rays(chunk);
            let mut hits = HitPacket8::NONE;
            bvh.with_packet_fallback([0, 2, 8][k % 3])
                .closest_hit_x8_with(&packet, &mut hits, &mut stack);
            for (lane, ray) in chunk.iter().enumerate() {
                let want = closest_hit(&spheres, ray);
                assert_eq!(hits.hit(lane), want, "{name}: packet lane {lane}");
                assert_eq!(
                    bvh.any_hit_with(ray, &mut stack),
                    any_hit(&spheres, ray),
                    "{name}"
                );
                assert_eq!(bvh.closest_hit_with(ray, &mut stack), want, "{name}");
            }
        }
    }
}

#[test]
fn ties_go_to_the_lowest_index() {
    let mut spheres = vec![Sphere::new(Vec3::new(0.0, 0.0, -5.0), 1.0); 40];
    // Unhittable spheres first, so the lowest hittable index is 3.
    spheres[0].radius = 0.0;
    spheres[1].radius = -1.0;
    spheres[2].radius = f32::NAN;
    let mut store = BvhBuffers::new(spheres.len());
    let bvh = store.build(&spheres);
    let hit = bvh.closest_hit(&Ray::new(Vec3::ZERO, -Vec3::Z)).unwrap();
    assert_eq!((hit.sphere, hit.t), (3, 4.0));
    let mut hits = HitPacket8::NONE;
    bvh.with_packet_fallback(0).closest_hit_x8(
        &RayPacket8::from_rays(&[Ray::new(Vec3::ZERO, -Vec3::Z)]),
        &mut hits,
    );
    assert_eq!(hits.hit(0).unwrap().sphere, 3);
}

#[test]
fn storage_too_small_is_an_error_and_writes_nothing() {
    let spheres: Vec<Sphere> = (0..100)
        .map(|i| Sphere::new(Vec3::new(i as f32, 0.0, 0.0), 0.5))
        .collect();
    let need = bvh_storage_for(100);
    for (dn, dl, di, slice) in [(1, 0, 0, "nodes"), (0, 1, 0, "lanes"), (0, 0, 1, "ids")] {
        let mut nodes = vec![BvhNode8::EMPTY; need.nodes - dn];
        let mut lanes = vec![7.0; need.lanes - dl];
        let mut ids = vec![9; need.ids - di];
        match Bvh::build(&spheres, &mut nodes, &mut lanes, &mut ids) {
            Err(BvhError::StorageTooSmall { slice: s, .. }) => assert_eq!(s, slice),
            other => panic!("{slice}: {other:?}"),
        }
        assert!(lanes.iter().all(|&x| x == 7.0) && ids.iter().all(|&x| x == 9));
    }
    let mut store = BvhBuffers::new(1);
    let bad = [Sphere::new(Vec3::new(f32::INFINITY, 0.0, 0.0), 1.0)];
    assert_eq!(
        Bvh::build(&bad, &mut store.nodes, &mut store.lanes, &mut store.ids).err(),
        Some(BvhError::SphereOutOfRange { index: 0 })
    );
    // No spheres: an empty tree that hits nothing.
    let mut store = BvhBuffers::new(0);
    let bvh = store.build(&[]);
    assert_eq!(bvh.closest_hit(&Ray::new(Vec3::ZERO, Vec3::X)), None);
}

/// Degenerate input still builds within the depth bound: 100 000 spheres
/// at one point, and a line of spheres with exponentially growing radii.
#[test]
fn degenerate_input_builds_within_the_depth_bound() {
    let same = vec![Sphere::new(Vec3::ONE, 0.5); 100_000];
    let mut store = BvhBuffers::new(same.len());
    let bvh = store.build(&same);
    assert!(bvh.depth() <= BVH_MAX_DEPTH, "depth {}", bvh.depth());
    let ray = Ray::new(Vec3::new(1.0, 1.0, 5.0), -Vec3::Z);
    assert_eq!(bvh.closest_hit(&ray), closest_hit(&same, &ray));
    let line: Vec<Sphere> = (0..3000)
        .map(|i| {
            let x = 1.01f32.powi(i);
            Sphere::new(Vec3::new(x, 0.0, 0.0), x * 0.001)
        })
        .collect();
    let mut store = BvhBuffers::new(line.len());
    let bvh = store.build(&line);
    assert!(bvh.depth() <= BVH_MAX_DEPTH, "depth {}", bvh.depth());
    assert!(bvh.node_count() <= bvh_storage_for(line.len()).nodes);
}

/// The tree depends only on the input: two builds give the same answers
/// and the same shape.
#[test]
fn builds_are_deterministic() {
    let spheres = strata_runner::scenes::cover_spheres();
    let mut a = BvhBuffers::new(spheres.len());
    let mut b = BvhBuffers::new(spheres.len());
    {
        let (ta, tb) = (a.build(&spheres), b.build(&spheres));
        assert_eq!((ta.node_count(), ta.depth()), (tb.node_count(), tb.depth()));
    }
    assert_eq!(a.ids, b.ids);
    assert_eq!(
        a.lanes.iter().map(|x| x.to_bits()).collect::<Vec<_>>(),
        b.lanes.iter().map(|x| x.to_bits()).collect::<Vec<_>>()
    );
}

/// Renders are bit-identical with the BVH on and off: every built-in
/// scene (the BVH forced on the small ones too), every sampler kind, 2
/// threads.
#[test]
fn renders_are_identical_with_and_without_the_bvh() {
    use strata_runner::job::{Job, SamplerKind, run};
    use strata_runner::scenes::{BUILT_IN, BvhMode, built_in};
    for name in BUILT_IN {
        let scene = built_in(name).unwrap();
        for sampler in [SamplerKind::Independent, SamplerKind::Sobol] {
            let job = |bvh| Job {
                max_depth: 50,
                sampler,
                seed: 3,
                bvh,
                ..Job::new(&scene, 64, 36, 4)
            };
            let on = run(&job(BvhMode::On), &|_| {}).unwrap();
            let off = run(&job(BvhMode::Off), &|_| {}).unwrap();
            assert_eq!(on.pixels, off.pixels, "{name} {sampler:?}");
            assert_eq!(on.stats.rays, off.stats.rays, "{name}");
        }
    }
}

/// Every query of `bvh` on `rays` equals brute force over `spheres`: one
/// ray (fresh and caller stacks) and any hits for all of them, packets
/// (with every fallback) for the first `packet_rays`.
fn assert_matches_brute_force(
    name: &str,
    spheres: &[Sphere],
    bvh: &Bvh<'_>,
    rays: &[Ray],
    packet_rays: usize,
) {
    let bits = |h: Option<strata::trace::Hit>| h.map(|h| (h.sphere, h.t.to_bits()));
    let mut stack = BvhStack::new();
    for (k, ray) in rays.iter().enumerate() {
        let want = closest_hit(spheres, ray);
        assert_eq!(
            bits(bvh.closest_hit(ray)),
            bits(want),
            "{name} ray {k}: {ray:?}"
        );
        assert_eq!(
            bits(bvh.closest_hit_with(ray, &mut stack)),
            bits(want),
            "{name} {k}"
        );
        assert_eq!(
            bvh.any_hit(ray),
            any_hit(spheres, ray),
            "{name} ray {k}: {ray:?}"
        );
    }
    for chunk in rays[..packet_rays.min(rays.len())].chunks(8) {
        let packet = RayPacket8::from_rays(chunk);
        for fallback in [0, 2, 8] {
            let mut hits = HitPacket8::NONE;
            bvh.with_packet_fallback(fallback)
                .closest_hit_x8(&packet, &mut hits);
            for (lane, ray) in chunk.iter().enumerate() {
                let want = closest_hit(spheres, ray);
                assert_eq!(bits(hits.hit(lane)), bits(want), "{name} x8/{fallback}");
            }
        }
        let want = chunk
            .iter()
            .enumerate()
            .fold(0, |m, (lane, r)| m | (any_hit(spheres, r) as u32) << lane);
        assert_eq!(bvh.any_hit_x8(&packet), want, "{name}");
    }
}

/// Rays leaving surfaces (the spawn rule's origins, outward and inward,
/// in every direction: the rays the kernel's `may_hit` test skips work
/// for) and rays with NaN parts or unusual ranges (`t_min` of −0.0,
/// negative or NaN, `t_max` NaN) give the brute-force answers.
#[test]
fn rays_leaving_surfaces_and_odd_ranges_match_brute_force() {
    let mut rng = Pcg32::new(23, 5);
    for (name, spheres) in scenes().into_iter().filter(|(_, s)| s.len() <= 1000) {
        let hittable: Vec<Sphere> = spheres.iter().copied().filter(|s| s.radius > 0.0).collect();
        if hittable.is_empty() {
            continue;
        }
        let mut store = BvhBuffers::new(spheres.len());
        let bvh = store.build(&spheres);
        let rays: Vec<Ray> = (0..24_000)
            .map(|k| {
                let s = hittable[(rng.next_u32() as usize) % hittable.len()];
                let n = unit(&mut rng);
                let o = s.spawn_origin(s.center + n * s.radius, k % 2 == 0);
                let ray = Ray::new(o, unit(&mut rng));
                match k % 12 {
                    0 => ray.with_range(-0.0, f32::INFINITY),
                    1 => ray.with_range(f32::NAN, f32::INFINITY),
                    2 => ray.with_range(0.0, f32::NAN),
                    3 => ray.with_range(-range(&mut rng, 0.0, 2.0), f32::INFINITY),
                    4 => Ray::new(Vec3::new(f32::NAN, o.y, o.z), ray.dir),
                    5 => Ray::new(o, Vec3::new(ray.dir.x, f32::NAN, ray.dir.z)),
                    _ => ray,
                }
            })
            .collect();
        assert_matches_brute_force(&name, &spheres, &bvh, &rays, rays.len());
    }
}

/// An outlier and a tree sphere hit at exactly the same `t` (a ground of
/// radius 1000 and a unit sphere touching it from above, both reached at
/// `t = 5` along −z): the lower index wins, whichever of the two it is.
#[test]
fn ties_between_an_outlier_and_the_tree_go_to_the_lowest_index() {
    let ground = Sphere::new(Vec3::new(0.0, 0.0, -1005.0), 1000.0);
    let ball = Sphere::new(Vec3::new(0.0, 0.0, -6.0), 1.0);
    let ray = Ray::new(Vec3::ZERO, -Vec3::Z);
    assert_eq!(strata::trace::intersect_sphere(&ground, &ray), Some(5.0));
    assert_eq!(strata::trace::intersect_sphere(&ball, &ray), Some(5.0));
    let others = (0..20).map(|i| Sphere::new(Vec3::new(i as f32 - 10.0, 3.0, -8.0), 0.3));
    for ground_first in [true, false] {
        let mut spheres: Vec<Sphere> = others.clone().collect();
        let (g, b) = if ground_first { (4, 11) } else { (11, 4) };
        spheres.insert(g.min(b), if ground_first { ground } else { ball });
        spheres.insert(g.max(b), if ground_first { ball } else { ground });
        let mut store = BvhBuffers::new(spheres.len());
        let bvh = store.build(&spheres);
        assert_eq!(bvh.outliers(), 1);
        let want = closest_hit(&spheres, &ray).unwrap();
        assert_eq!((want.sphere, want.t), (4, 5.0));
        assert_matches_brute_force("tie", &spheres, &bvh, &[ray; 8], 8);
    }
}

/// More than eight spheres that dwarf the rest: eight are kept out (the
/// cap), and every query still equals brute force.
#[test]
fn at_most_eight_outliers() {
    let mut rng = Pcg32::new(31, 1);
    let mut spheres: Vec<Sphere> = (0..60)
        .map(|_| {
            let c = Vec3::new(
                range(&mut rng, -3.0, 3.0),
                range(&mut rng, -3.0, 3.0),
                range(&mut rng, -3.0, 3.0),
            );
            Sphere::new(c, range(&mut rng, 0.05, 0.2))
        })
        .collect();
    // Twelve giants far apart, each far larger than all before it.
    for k in 0..12 {
        let r = 1e3 * 20f32.powi(k);
        let dir = [Vec3::X, Vec3::Y, Vec3::Z, -Vec3::X][k as usize % 4];
        spheres.insert(5 * k as usize, Sphere::new(dir * (r + 10.0), r));
    }
    let mut store = BvhBuffers::new(spheres.len());
    let bvh = store.build(&spheres);
    assert_eq!(bvh.outliers(), 8);
    assert!(bvh.built_from(&spheres));
    let rays = rays(&spheres, 20_000, &mut rng);
    assert_matches_brute_force("giants", &spheres, &bvh, &rays, rays.len());
}

/// The unit-direction contract's tolerance: directions off unit length by
/// up to 8 ulps (`Vec3::normalize` is within about 2) still get the
/// brute-force bits from the BVH, on every scene.
#[test]
fn nearly_unit_directions_match_brute_force() {
    let mut rng = Pcg32::new(21, 21);
    for (name, spheres) in scenes().into_iter().filter(|(_, s)| s.len() <= 1000) {
        let mut store = BvhBuffers::new(spheres.len());
        let bvh = store.build(&spheres);
        let rays: Vec<Ray> = rays(&spheres, 40_000, &mut rng)
            .into_iter()
            .enumerate()
            .map(|(k, r)| {
                let ulps = (k % 17) as f32 - 8.0;
                let scale = 1.0 + ulps * f32::EPSILON;
                Ray {
                    dir: r.dir * scale,
                    ..r
                }
            })
            .collect();
        assert_matches_brute_force(&name, &spheres, &bvh, &rays, 0);
    }
}
