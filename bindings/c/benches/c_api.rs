//! The C API's batch calls against the same work written idiomatically
//! on the core's Rust API, timed in turns (A, B, A, B, ...) in one
//! process: the sampler fill and BVH closest hits. The C functions are
//! called through their Rust declarations: the same machine code a C
//! caller reaches through the library.
//!
//! `cargo bench -p strata-c` (add `-- --quick` for one short round, or
//! `-- --once rust` / `-- --once c` to run one side once, untimed, under
//! an instruction counter).

use std::hint::black_box;
use std::time::{Duration, Instant};

use strata::{StrataHit, StrataRay, StrataStatus};
use strata_core::glam::{UVec2, Vec2, Vec3};
use strata_core::mapping::sample_uniform_sphere;
use strata_core::rng::{Pcg32, STREAM, next_f32};
use strata_core::trace::{Bvh, BvhNode8, BvhStack, Ray, Sphere, bvh_storage_for};
use strata_core::{Sampler, Sobol};

/// Seconds per run of `f`, the least of enough runs to fill `min`.
fn time(min: Duration, mut f: impl FnMut()) -> f64 {
    let start = Instant::now();
    let mut best = f64::INFINITY;
    while start.elapsed() < min {
        let t = Instant::now();
        f();
        best = best.min(t.elapsed().as_secs_f64());
    }
    best
}

fn median(mut v: Vec<f64>) -> f64 {
    v.sort_by(f64::total_cmp);
    v[v.len() / 2]
}

/// Times `a` (Rust) and `b` (C) in turns; prints rates and the ratio.
/// With `--once rust` or `--once c` it runs that side once and times
/// nothing: for instruction counters (callgrind).
fn compare(
    name: &str,
    unit: &str,
    work: f64,
    rounds: usize,
    min: Duration,
    mut a: impl FnMut(),
    mut b: impl FnMut(),
) {
    let args: Vec<String> = std::env::args().collect();
    // `--part sampler` or `--part BVH`: only the comparison so named.
    if let Some(i) = args.iter().position(|a| a == "--part")
        && !args
            .get(i + 1)
            .is_some_and(|p| name.starts_with(p.as_str()))
    {
        return;
    }
    if let Some(i) = args.iter().position(|a| a == "--once") {
        match args.get(i + 1).map(String::as_str) {
            Some("rust") => a(),
            Some("c") => b(),
            Some("none") => {}
            _ => panic!("--once rust|c|none"),
        }
        return;
    }
    let (mut ta, mut tb, mut ratio) = (vec![], vec![], vec![]);
    for _ in 0..rounds {
        let x = time(min, &mut a);
        let y = time(min, &mut b);
        ta.push(x);
        tb.push(y);
        ratio.push(y / x);
    }
    println!(
        "{name}: Rust API {:.1} M {unit}/s, C API {:.1} M {unit}/s; C time / Rust time {:.3} (median of {rounds} turns, {:.3}-{:.3})",
        work / median(ta) / 1e6,
        work / median(tb) / 1e6,
        median(ratio.clone()),
        ratio.iter().copied().fold(f64::INFINITY, f64::min),
        ratio.iter().copied().fold(0.0, f64::max),
    );
}

fn cover() -> Vec<Sphere> {
    include_str!("../../../core/tests/data/cover.csv")
        .lines()
        .skip(1)
        .filter(|l| !l.trim().is_empty())
        .map(|l| {
            let v: Vec<f32> = l.split(',').map(|x| x.trim().parse().unwrap()).collect();
            Sphere::new(Vec3::new(v[0], v[1], v[2]), v[3])
        })
        .collect()
}

fn main() {
    let quick = std::env::args().any(|a| a == "--quick");
    let (rounds, min) = if quick {
        (1, Duration::from_millis(20))
    } else {
        (9, Duration::from_millis(300))
    };

    // The sampler fill: 128 x 128 pixels x 16 samples, 10 dimensions.
    const DIMS: usize = 10;
    let (w, spp) = (128u32, 16u32);
    let n = (w * w * spp) as usize;
    let pixels: Vec<u32> = (0..n)
        .flat_map(|i| {
            let p = i as u32 / spp;
            [p % w, p / w]
        })
        .collect();
    let indices: Vec<u32> = (0..n).map(|i| i as u32 % spp).collect();
    let mut out = vec![0.0f32; n * DIMS];
    let mut rust = Sobol::new(spp, 7).unwrap();
    let mut handle = std::ptr::null_mut();
    // SAFETY: a valid out-pointer.
    assert_eq!(
        unsafe { strata::strata_sampler_new(3, spp, 7, w, w, &mut handle) },
        StrataStatus::Ok
    );
    let mut check = vec![0.0f32; n * DIMS];
    let mut fill_rust = |out: &mut [f32]| {
        for ((row, p), &i) in out
            .chunks_exact_mut(DIMS)
            .zip(pixels.chunks_exact(2))
            .zip(&indices)
        {
            rust.start_pixel_sample(UVec2::new(p[0], p[1]), i);
            let q = rust.pixel_2d();
            row[0] = q.x;
            row[1] = q.y;
            for k in (2..DIMS).step_by(2) {
                let v = rust.next_2d();
                row[k] = v.x;
                row[k + 1] = v.y;
            }
        }
    };
    let fill_c = |out: &mut [f32]| {
        // SAFETY: every array is valid for its length.
        let s = unsafe {
            strata::strata_sampler_fill(
                handle,
                pixels.as_ptr(),
                pixels.len(),
                indices.as_ptr(),
                n,
                DIMS as u32,
                out.as_mut_ptr(),
                out.len(),
            )
        };
        assert_eq!(s, StrataStatus::Ok);
    };
    fill_rust(&mut check);
    fill_c(&mut out);
    assert!(
        check
            .iter()
            .zip(&out)
            .all(|(a, b)| a.to_bits() == b.to_bits()),
        "the fills differ"
    );
    compare(
        "sampler fill (Sobol', 10 dims)",
        "values",
        (n * DIMS) as f64,
        rounds,
        min,
        || fill_rust(black_box(&mut check)),
        || fill_c(black_box(&mut out)),
    );
    // SAFETY: from strata_sampler_new, freed once.
    unsafe { strata::strata_sampler_free(handle) };

    // BVH closest hits: the cover's 485 spheres, 2^17 incoherent rays.
    let spheres = cover();
    let mut rng = Pcg32::new(3, STREAM);
    let mut u = || next_f32(&mut rng);
    let rays: Vec<Ray> = (0..1 << 17)
        .map(|_| {
            let o = Vec3::new(-11.0, 0.0, -11.0)
                + Vec3::new(22.0, 2.0, 22.0) * Vec3::new(u(), u(), u());
            Ray::new(o, sample_uniform_sphere(Vec2::new(u(), u())).normalize())
        })
        .collect();
    let c_rays: Vec<StrataRay> = rays
        .iter()
        .map(|r| StrataRay {
            origin: r.origin.to_array(),
            dir: r.dir.to_array(),
            t_min: r.t_min,
            t_max: r.t_max,
        })
        .collect();
    let size = bvh_storage_for(spheres.len());
    let (mut nodes, mut lanes, mut ids) = (
        vec![BvhNode8::EMPTY; size.nodes],
        vec![0.0; size.lanes],
        vec![0u32; size.ids],
    );
    let bvh = Bvh::build(&spheres, &mut nodes, &mut lanes, &mut ids).unwrap();
    let flat: Vec<f32> = spheres
        .iter()
        .flat_map(|s| [s.center.x, s.center.y, s.center.z, s.radius])
        .collect();
    let mut bytes = 0usize;
    // SAFETY: a valid out-pointer.
    assert_eq!(
        unsafe { strata::strata_bvh_storage_size(spheres.len(), &mut bytes) },
        StrataStatus::Ok
    );
    let layout = std::alloc::Layout::from_size_align(bytes, 64).unwrap();
    // SAFETY: a non-zero size.
    let storage = unsafe { std::alloc::alloc(layout) };
    let mut tree = std::ptr::null_mut();
    // SAFETY: the spheres and storage are valid for their lengths; the
    // storage outlives the handle.
    assert_eq!(
        unsafe {
            strata::strata_bvh_build(flat.as_ptr(), flat.len(), storage.cast(), bytes, &mut tree)
        },
        StrataStatus::Ok
    );
    let mut hits_rust = vec![None; rays.len()];
    let mut hits_c = vec![StrataHit { t: 0.0, id: 0 }; rays.len()];
    let closest_rust = |hits: &mut [Option<strata_core::trace::Hit>]| {
        let mut stack = BvhStack::new();
        for (h, r) in hits.iter_mut().zip(&rays) {
            *h = bvh.closest_hit_with(r, &mut stack);
        }
    };
    let closest_c = |hits: &mut [StrataHit]| {
        // SAFETY: a live tree; the arrays are valid for their lengths.
        let s = unsafe {
            strata::strata_bvh_closest_hit(
                tree,
                c_rays.as_ptr(),
                c_rays.len(),
                hits.as_mut_ptr(),
                hits.len(),
            )
        };
        assert_eq!(s, StrataStatus::Ok);
    };
    closest_rust(&mut hits_rust);
    closest_c(&mut hits_c);
    assert!(
        hits_rust.iter().zip(&hits_c).all(|(a, b)| match a {
            Some(h) => h.sphere == b.id && h.t.to_bits() == b.t.to_bits(),
            None => b.id == u32::MAX,
        }),
        "the hits differ"
    );
    compare(
        "BVH closest hit (cover, incoherent)",
        "rays",
        rays.len() as f64,
        rounds,
        min,
        || closest_rust(black_box(&mut hits_rust)),
        || closest_c(black_box(&mut hits_c)),
    );
    // SAFETY: the handle first, then its storage, each once.
    unsafe {
        strata::strata_bvh_free(tree);
        std::alloc::dealloc(storage, layout);
    }
}
