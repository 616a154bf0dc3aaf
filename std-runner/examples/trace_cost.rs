//! The tracing workloads of `strata bench --group bvh` as a program, for
//! instruction counters such as callgrind, which a timed suite cannot run
//! under:
//!
//! ```sh
//! cargo run --release -p strata-runner --example trace_cost -- cover_incoherent bvh 100000 2
//! ```
//!
//! traces `RAYS` rays of the workload (evenly through its list) `PASSES`
//! times with the named kernel. Two counts give the marginal cost per ray: the
//! difference of the instruction totals over `RAYS` times the difference
//! of passes.
//!
//! Workloads: `cover_camera` (the cover camera's rays at 1280 × 720),
//! `cover_incoherent` and `random10k` (10⁶ incoherent rays each; the
//! bench's), and `small:N` — the ground, the three big spheres and
//! `N − 4` of the small spheres of the cover taken evenly through the
//! list (8 ≤ N ≤ 484), traced with 10⁶ incoherent rays (`small:N` or
//! `small_camera:N` for the cover camera's rays at 1280 × 720).
//!
//! Kernels: `brute` and `brute_any` (the 1×8 loop), `bvh` and `bvh_any`
//! (the sphere BVH, one ray at a time), `auto` (what the render picks at
//! this size: from `strata::trace::BVH_MIN_SPHERES`), `prim_bvh`, `prim_bvh_any` and
//! `prim_brute` (the spheres as the caller's primitives: a
//! [`PrimitiveBvh`] whose routine is `intersect_sphere`, and its brute
//! force loop), `textbook` (a 1×8 loop of the textbook formula: one
//! discriminant, no robustness; not part of the library), and
//! `accuracy` (not for counting: how often the robust and the textbook
//! formula pick another sphere than an `f64` reference does, as is, moved
//! 4096 from the origin, and seen from 2000 further back).

use glam::Vec3;
use strata::trace::{
    BVH_MIN_SPHERES, Bvh, BvhNode8, BvhStack, PrimitiveBvh, Ray, Sphere, SphereChunk8, SphereSet,
    any_hit_1x8, bvh_storage_for, chunks_for, closest_hit_1x8, closest_primitive_hit,
    primitive_bvh_storage_for,
};
use strata_runner::scenes::{COVER_VIEW, cover_spheres};
use strata_runner::workload::{
    SpheresAsPrimitives, camera_rays, random_rays, random_spheres_10k, ray_box,
};
use wide::f32x8;

/// The ground, the three big spheres and `n − 4` small ones of the cover,
/// evenly through its list.
fn small_cover(n: usize) -> Vec<Sphere> {
    let all = cover_spheres();
    let (ground, small, big) = (all[0], &all[1..all.len() - 3], &all[all.len() - 3..]);
    let k = n.saturating_sub(4).min(small.len());
    let mut out = vec![ground];
    out.extend((0..k).map(|i| small[i * small.len() / k.max(1)]));
    out.extend_from_slice(big);
    out
}

/// The textbook kernel, 8 spheres a lane: `b = f·d`, `c = |f|² − r²`,
/// `Δ = b² − c`, the nearer root above `t_min`, else the farther.
fn textbook_closest(chunks: &[[f32x8; 4]], ray: &Ray) -> Option<(f32, u32)> {
    let (o, d) = (ray.origin, ray.dir);
    let (t_min, t_max) = (f32x8::splat(ray.t_min), f32x8::splat(ray.t_max));
    let mut best = (f32::INFINITY, u32::MAX);
    for (k, c) in chunks.iter().enumerate() {
        let fx = f32x8::splat(o.x) - c[0];
        let fy = f32x8::splat(o.y) - c[1];
        let fz = f32x8::splat(o.z) - c[2];
        let b = fx * f32x8::splat(d.x) + fy * f32x8::splat(d.y) + fz * f32x8::splat(d.z);
        let cc = fx * fx + fy * fy + fz * fz - c[3] * c[3];
        let disc = b * b - cc;
        let s = disc.sqrt();
        let t0 = -b - s;
        let t1 = -b + s;
        let t = wide::Select::select(t0.simd_gt(t_min), t0, t1);
        let hit = disc.simd_gt(f32x8::ZERO) & t.simd_gt(t_min) & t.simd_lt(t_max);
        let mut bits = hit.to_bitmask();
        let ts = t.to_array();
        while bits != 0 {
            let lane = bits.trailing_zeros() as usize;
            bits &= bits - 1;
            if ts[lane] < best.0 {
                best = (ts[lane], (8 * k + lane) as u32);
            }
        }
    }
    (best.1 != u32::MAX).then_some(best)
}

/// How often each formula's closest sphere (or miss) differs from the
/// `f64` reference: on the workload as it is, moved 4096 away along x
/// and z, and with every ray started 2000 further back along itself.
fn accuracy(workload: &str, spheres: &[Sphere], rays: &[Ray], n: usize) {
    let step = (rays.len() / n.max(1)).max(1);
    let rays: Vec<Ray> = rays.iter().step_by(step).take(n).copied().collect();
    let text = |s: &[Sphere]| -> Vec<[f32x8; 4]> {
        s.chunks(8)
            .map(|c| {
                let mut a = [[0.0f32; 8]; 4];
                for (lane, s) in c.iter().enumerate() {
                    a[0][lane] = s.center.x;
                    a[1][lane] = s.center.y;
                    a[2][lane] = s.center.z;
                    a[3][lane] = s.radius;
                }
                a.map(f32x8::new)
            })
            .collect()
    };
    let far = shifted(spheres, &rays, Vec3::new(4096.0, 0.0, 4096.0));
    let from_afar = backed(&rays, 2000.0);
    for (name, s, r) in [
        ("as is", spheres, &rays[..]),
        ("moved 4096 away", &far.0[..], &far.1[..]),
        ("from 2000 back", spheres, &from_afar[..]),
    ] {
        let t = text(s);
        let (mut robust, mut textbook) = (0, 0);
        for ray in r {
            let want = f64_closest(s, ray);
            robust += usize::from(strata::trace::closest_hit(s, ray).map(|h| h.sphere) != want);
            textbook += usize::from(textbook_closest(&t, ray).map(|h| h.1) != want);
        }
        println!(
            "{workload} {name}: {} rays; wrong sphere or hit/miss against f64: robust {robust}, textbook {textbook}",
            r.len()
        );
    }
}

/// The closest hit in `f64` (the inputs as given, exact to rounding in
/// `f64`): the reference the `accuracy` kernel judges both formulas by.
fn f64_closest(spheres: &[Sphere], ray: &Ray) -> Option<u32> {
    let d = ray.dir.as_dvec3();
    let mut best = (f64::INFINITY, None);
    for (i, s) in spheres.iter().enumerate() {
        let f = ray.origin.as_dvec3() - s.center.as_dvec3();
        let r = s.radius as f64;
        // a = d·d in full, so the unit-direction rounding costs nothing.
        let (a, b, c) = (d.dot(d), f.dot(d), f.dot(f) - r * r);
        let disc = b * b - a * c;
        if disc < 0.0 {
            continue;
        }
        for t in [(-b - disc.sqrt()) / a, (-b + disc.sqrt()) / a] {
            if t > ray.t_min as f64 && t < ray.t_max as f64 {
                if t < best.0 {
                    best = (t, Some(i as u32));
                }
                break;
            }
        }
    }
    best.1
}

/// The workload's spheres and rays moved by `shift` (a scene away from
/// the origin, where `f32` has fewer bits to spare).
fn shifted(spheres: &[Sphere], rays: &[Ray], shift: Vec3) -> (Vec<Sphere>, Vec<Ray>) {
    (
        spheres
            .iter()
            .map(|s| Sphere::new(s.center + shift, s.radius))
            .collect(),
        rays.iter()
            .map(|r| Ray {
                origin: r.origin + shift,
                ..*r
            })
            .collect(),
    )
}

/// The rays started `back` further back along themselves: the same
/// lines, seen from afar (a telephoto view).
fn backed(rays: &[Ray], back: f32) -> Vec<Ray> {
    rays.iter()
        .map(|r| Ray::new(r.origin - r.dir * back, r.dir))
        .collect()
}

fn main() {
    let args: Vec<String> = std::env::args().skip(1).collect();
    let parse = |i: usize| args.get(i).and_then(|n| n.parse::<usize>().ok());
    let (Some(workload), Some(kernel), Some(n), Some(passes)) =
        (args.first(), args.get(1), parse(2), parse(3))
    else {
        eprintln!("usage: trace_cost WORKLOAD KERNEL RAYS PASSES (see the source's header)");
        std::process::exit(2);
    };
    let (lo, hi) = ray_box(true);
    let incoherent = || random_rays(1_000_000, lo, hi, 12);
    let camera = || camera_rays(COVER_VIEW, 1280, 720);
    let size = |w: &str| w.split(':').nth(1).and_then(|n| n.parse::<usize>().ok());
    let (spheres, rays) = match workload.as_str() {
        "cover_camera" => (cover_spheres(), camera()),
        "cover_incoherent" => (cover_spheres(), incoherent()),
        "random10k" => (
            random_spheres_10k(),
            random_rays(1_000_000, Vec3::splat(-20.0), Vec3::splat(20.0), 13),
        ),
        w if w.starts_with("small:") && size(w).is_some_and(|n| (8..=484).contains(&n)) => {
            (small_cover(size(w).unwrap_or(8)), incoherent())
        }
        w if w.starts_with("small_camera:") && size(w).is_some_and(|n| (8..=484).contains(&n)) => {
            (small_cover(size(w).unwrap_or(8)), camera())
        }
        _ => {
            eprintln!("unknown workload `{workload}`");
            std::process::exit(2);
        }
    };
    if kernel == "accuracy" {
        accuracy(workload, &spheres, &rays, n);
        return;
    }
    // `RAYS` of them, evenly through the list (a prefix of the camera's
    // would be the sky's top rows).
    let step = (rays.len() / n.max(1)).max(1);
    let rays: Vec<Ray> = rays.iter().step_by(step).take(n).copied().collect();
    let rays = &rays[..];
    let mut chunks = vec![SphereChunk8::EMPTY; chunks_for(spheres.len())];
    let set = SphereSet::build(&spheres, &mut chunks).expect("a valid layout");
    let s = bvh_storage_for(spheres.len());
    let (mut nodes, mut lanes, mut ids) = (
        vec![BvhNode8::EMPTY; s.nodes],
        vec![0.0; s.lanes],
        vec![0; s.ids],
    );
    let bvh = Bvh::build(&spheres, &mut nodes, &mut lanes, &mut ids).expect("in range");
    let balls = SpheresAsPrimitives(&spheres);
    let ps = primitive_bvh_storage_for(spheres.len());
    let (mut pnodes, mut pids) = (vec![BvhNode8::EMPTY; ps.nodes], vec![0; ps.ids]);
    let pbvh = PrimitiveBvh::build(&balls, &mut pnodes, &mut pids).expect("in range");
    let text: Vec<[f32x8; 4]> = spheres
        .chunks(8)
        .map(|c| {
            let mut a = [[0.0f32; 8]; 4];
            for (lane, s) in c.iter().enumerate() {
                a[0][lane] = s.center.x;
                a[1][lane] = s.center.y;
                a[2][lane] = s.center.z;
                a[3][lane] = s.radius;
            }
            a.map(f32x8::new)
        })
        .collect();
    let use_bvh = spheres.len() >= BVH_MIN_SPHERES;
    let mut stack = BvhStack::new();
    let mut sum = 0u64;
    for _ in 0..passes {
        for r in rays {
            let id = |h: Option<u32>| h.map_or(0, |i| i as u64 + 1);
            sum += match kernel.as_str() {
                "brute" => id(closest_hit_1x8(&set, r).map(|h| h.sphere)),
                "brute_any" => any_hit_1x8(&set, r) as u64,
                "bvh" => id(bvh.closest_hit_with(r, &mut stack).map(|h| h.sphere)),
                "bvh_any" => bvh.any_hit_with(r, &mut stack) as u64,
                "auto" if use_bvh => id(bvh.closest_hit_with(r, &mut stack).map(|h| h.sphere)),
                "auto" => id(closest_hit_1x8(&set, r).map(|h| h.sphere)),
                "prim_bvh" => id(pbvh.closest_hit_with(r, &mut stack).map(|h| h.primitive)),
                "prim_bvh_any" => pbvh.any_hit_with(r, &mut stack) as u64,
                "prim_brute" => id(closest_primitive_hit(&balls, r).map(|h| h.primitive)),
                "textbook" => id(textbook_closest(&text, r).map(|h| h.1)),
                _ => {
                    eprintln!("unknown kernel `{kernel}`");
                    std::process::exit(2);
                }
            };
        }
    }
    println!(
        "{workload} {kernel}: {} rays x {passes}, {} spheres, checksum {sum}",
        rays.len(),
        spheres.len()
    );
}
