//! The core's value locks: the bits the core alone produces, checked on
//! every platform CI builds (x86-64 native and portable SSE2, aarch64
//! under qemu, WebAssembly under a WASI runtime). This binary needs only
//! `strata` and its own dependencies, so it builds for any of them; the
//! render and output-file locks, which need the runner, are in
//! `std-runner/tests/output_locks.rs`.
//!
//! 1. The PCG32 reference vector: `pcg32_srandom(42, 54)` from the official
//!    pcg-c-basic demo, the same check `shared/scenes/gen_scenes.py` makes.
//! 2. The stream lock: `stream_state` and the first outputs of a few pixel
//!    samples' streams, and the first values of each sampler kind.
//! 3. The mapping lock: a hash of the bits every mapping (sample, pdf,
//!    invert) and both ONBs produce on a fixed grid. It pins the `libm`
//!    paths, so a build for another SIMD level, architecture or `libm`
//!    that rounds differently fails here.
//! 4. The tracing lock: a hash of the closest hits (sphere and `t` bits)
//!    of seeded random rays against the course and cover layouts
//!    (`core/tests/data/*.csv`, the reference sphere lists, built in with
//!    `include_str!`), through the
//!    scalar, 1×8, packet and BVH paths.
//!
//! These numbers were produced by this implementation and are a lock, not
//! a derivation: the properties (uniformity, independence, stratification,
//! order independence) are proved by the root suite's statistical tests.
//! If a change trips this test on purpose, every seeded render changes:
//! update the values, raise `strata::render::OUTPUT_REVISION` and add a
//! line under "Output changes" in CHANGELOG.md.

use glam::{UVec2, Vec2, Vec3};
use rand_core::Rng;
use strata::Onb;
use strata::mapping::*;
use strata::rng::{ONE_MINUS_EPSILON, Pcg32, STREAM, next_f32, pixel_sample_rng, stream_state};
use strata::sampler::{Independent, Sampler, Stratified, UniformGrid};
use strata::trace::*;

const CHANGED: &str = "the core's output changed: every seeded render changes with it. \
     If intended, update this lock, raise strata::render::OUTPUT_REVISION and record it under \
     \"Output changes\" in CHANGELOG.md";

#[test]
fn pcg32_reference_vector() {
    let mut rng = Pcg32::new(42, 54);
    let want = [
        0xa15c02b7u32,
        0x7b47f409,
        0xba1d3330,
        0x83d2f293,
        0xbfa4784b,
        0xcbed606e,
    ];
    for w in want {
        assert_eq!(rng.next_u32(), w);
    }
}

#[test]
fn stream_derivation_lock() {
    // (seed, px, py, index, state, first three outputs)
    let lock: [(u64, u32, u32, u32, u64, [u32; 3]); 3] = [
        (
            0x0,
            0,
            0,
            0,
            0x33fe8bd4f9c57863,
            [0xff60136e, 0x720f7507, 0x8f1f78c0],
        ),
        (
            0x2a,
            3,
            4,
            5,
            0x7015e27388e6cb45,
            [0x045447b2, 0xceef152f, 0x7df4876c],
        ),
        (
            u64::MAX,
            1919,
            1079,
            1023,
            0x01009ce033f56bce,
            [0xad03f53a, 0x1a6092af, 0x0ff1fd8b],
        ),
    ];
    for (seed, x, y, i, state, outputs) in lock {
        let p = UVec2::new(x, y);
        assert_eq!(stream_state(seed, p, i), state, "{CHANGED}");
        let mut rng = pixel_sample_rng(seed, p, i);
        assert_eq!(
            [rng.next_u32(), rng.next_u32(), rng.next_u32()],
            outputs,
            "{CHANGED}"
        );
        // The documented construction: Pcg32::new(state, STREAM).
        let mut again = Pcg32::new(state, STREAM);
        assert_eq!(again.next_u32(), outputs[0]);
    }
}

fn first_values<S: Sampler>(s: &mut S) -> [u32; 5] {
    s.start_pixel_sample(UVec2::new(12, 34), 5);
    let p = s.pixel_2d();
    let a = s.next_1d();
    let b = s.next_2d();
    [p.x, p.y, a, b.x, b.y].map(f32::to_bits)
}

/// The first values ([`first_values`]: pixel (12, 34), sample 5, 16 spp,
/// seed 2026) of each sampler kind; ZSobol' at 320 × 180, and `zsobol_wide`
/// at 256 spp over 2²⁰ × 2²⁰ (a 48-bit Morton index: the permuted index
/// reaches the columns of Sobol' dimension 1 beyond bit 32).
const SAMPLER_LOCK: [(&str, [u32; 5]); 7] = [
    (
        "independent",
        [0x3eca1a4a, 0x3f3bb1f6, 0x3efbcbbc, 0x3ed05536, 0x3f7a8381],
    ),
    (
        "grid",
        [0x3ec00000, 0x3ec00000, 0x3f180000, 0x3f600000, 0x3e000000],
    ),
    (
        "stratified",
        [0x3f1ca665, 0x3eac78e2, 0x3f114207, 0x3f5532c9, 0x3cfa8500],
    ),
    (
        "sobol",
        [0x3e74e798, 0x3cbf9640, 0x3ea31c00, 0x3f4374b6, 0x3f4153ae],
    ),
    (
        "halton",
        [0x3f0dc8a3, 0x3f328641, 0x3e95ab0f, 0x3f66ef64, 0x3e79350f],
    ),
    (
        "zsobol",
        [0x3e92464c, 0x3d41ca40, 0x3f2971f7, 0x3f48054f, 0x3e94588a],
    ),
    (
        "zsobol_wide",
        [0x3ed76230, 0x3f498e8b, 0x3f1210fb, 0x3f48fd44, 0x3eadc392],
    ),
];

#[test]
fn sampler_lock() {
    let got = [
        first_values(&mut Independent::new(16, 2026).unwrap()),
        first_values(&mut UniformGrid::new(16, 2026).unwrap()),
        first_values(&mut Stratified::new(16, 2026).unwrap()),
        first_values(&mut strata::Sobol::new(16, 2026).unwrap()),
        first_values(&mut strata::Halton::new(16, 2026).unwrap()),
        first_values(&mut strata::ZSobol::new(16, 2026, UVec2::new(320, 180)).unwrap()),
        first_values(&mut strata::ZSobol::new(256, 2026, UVec2::splat(1 << 20)).unwrap()),
    ];
    for ((name, want), got) in SAMPLER_LOCK.iter().zip(got) {
        assert_eq!(&got, want, "{name}: {CHANGED}");
    }
}

/// Rows of the renderer's draw order (`pixel_2d`, then `next_2d` pairs,
/// then `next_1d`: 7 dimensions) for 64 pixel samples, pixel
/// `(37k mod 320, 11k mod 180)` and index `k mod 16`, FNV-1a over their
/// bits: what the bindings' batch calls (C's `strata_sampler_fill`,
/// Python's `pixel_samples` and engines) give, per kind as
/// [`SAMPLER_LOCK`] builds it.
fn sample_rows<S: Sampler>(s: &mut S) -> u64 {
    let mut words = Vec::new();
    for k in 0..64u32 {
        s.start_pixel_sample(UVec2::new(37 * k % 320, 11 * k % 180), k % 16);
        let p = s.pixel_2d();
        let (a, b) = (s.next_2d(), s.next_2d());
        let c = s.next_1d();
        words.extend([p.x, p.y, a.x, a.y, b.x, b.y, c].map(f32::to_bits));
    }
    fnv(words)
}

/// [`sample_rows`] of each kind, in [`SAMPLER_LOCK`]'s order.
const SAMPLER_ROWS_LOCK: [u64; 7] = [
    0x820132544dbba419,
    0xee43b4fd1669a62c,
    0xe79082f11b03ecf8,
    0x8fa70b22c51e38d6,
    0x41377895593f164d,
    0x98a768f03fdfd8f8,
    0x6071861c505f91a1,
];

#[test]
fn sampler_rows_lock() {
    let got = [
        sample_rows(&mut Independent::new(16, 2026).unwrap()),
        sample_rows(&mut UniformGrid::new(16, 2026).unwrap()),
        sample_rows(&mut Stratified::new(16, 2026).unwrap()),
        sample_rows(&mut strata::Sobol::new(16, 2026).unwrap()),
        sample_rows(&mut strata::Halton::new(16, 2026).unwrap()),
        sample_rows(&mut strata::ZSobol::new(16, 2026, UVec2::new(320, 180)).unwrap()),
        sample_rows(&mut strata::ZSobol::new(256, 2026, UVec2::splat(1 << 20)).unwrap()),
    ];
    assert_eq!(
        got, SAMPLER_ROWS_LOCK,
        "rows changed: {got:#018x?}\n{CHANGED}"
    );
}

/// FNV-1a over 32-bit words. Its own copy: this test belongs to the core
/// package, which cannot depend on the runner (the runner depends on it),
/// and the runner's `hash.rs` is the one FNV-1a everywhere else.
fn fnv(words: impl IntoIterator<Item = u32>) -> u64 {
    words.into_iter().fold(0xcbf2_9ce4_8422_2325u64, |h, w| {
        w.to_le_bytes()
            .iter()
            .fold(h, |h, &b| (h ^ b as u64).wrapping_mul(0x0100_0000_01b3))
    })
}

/// A 97 × 97 grid over [0, 1)², edges included.
fn grid() -> impl Iterator<Item = Vec2> {
    let t = |k: u32| {
        if k == 96 {
            ONE_MINUS_EPSILON
        } else {
            k as f32 / 96.0
        }
    };
    (0..97).flat_map(move |i| (0..97).map(move |j| Vec2::new(t(i), t(j))))
}

fn v3(w: Vec3) -> [u32; 3] {
    w.to_array().map(f32::to_bits)
}

fn v2(w: Vec2) -> [u32; 2] {
    w.to_array().map(f32::to_bits)
}

/// FNV-1a of every mapping's words on [`grid`], as [`mapping_lock`]
/// makes them.
const MAPPING_LOCK: [(&str, u64); 8] = [
    ("uniform_sphere", 0xd074475691ec7496),
    ("uniform_hemisphere", 0x100d822a729b54f8),
    ("cosine_hemisphere", 0x4d24764520a9d6fe),
    ("concentric_disk", 0xa336b2ca1704290a),
    ("polar_disk", 0xae81f3436e32bd83),
    ("uniform_cone", 0x7da39f65cf5ea3e7),
    ("onb", 0x13d8b714175f56f0),
    ("uniform_ball", 0x09e7cb26c6da1dfc),
];

#[test]
fn mapping_lock() {
    let cone = Cone::from_cos(0.3);
    let tiny = Cone::from_sin2(1e-7);
    let mut words: Vec<(&str, Vec<u32>)> = vec![];
    let mut push = |name, f: &dyn Fn(Vec2) -> Vec<u32>| {
        words.push((name, grid().flat_map(f).collect()));
    };
    push("uniform_sphere", &|u| {
        let w = sample_uniform_sphere(u);
        [
            &v3(w)[..],
            &v2(invert_uniform_sphere(w))[..],
            &[pdf_uniform_sphere(w).to_bits()],
        ]
        .concat()
    });
    push("uniform_hemisphere", &|u| {
        let w = sample_uniform_hemisphere(u);
        [
            &v3(w)[..],
            &v2(invert_uniform_hemisphere(w))[..],
            &[pdf_uniform_hemisphere(w).to_bits()],
        ]
        .concat()
    });
    push("cosine_hemisphere", &|u| {
        let w = sample_cosine_hemisphere(u);
        [
            &v3(w)[..],
            &v2(invert_cosine_hemisphere(w))[..],
            &[pdf_cosine_hemisphere(w).to_bits()],
        ]
        .concat()
    });
    push("concentric_disk", &|u| {
        let p = sample_concentric_disk(u);
        [&v2(p)[..], &v2(invert_concentric_disk(p))[..]].concat()
    });
    push("polar_disk", &|u| {
        let p = sample_polar_disk(u);
        [&v2(p)[..], &v2(invert_polar_disk(p))[..]].concat()
    });
    push("uniform_cone", &|u| {
        let w = sample_uniform_cone(u, cone);
        let t = sample_uniform_cone(u, tiny);
        [
            &v3(w)[..],
            &v2(invert_uniform_cone(w, cone))[..],
            &v3(t)[..],
            &v2(invert_uniform_cone(t, tiny))[..],
        ]
        .concat()
    });
    push("onb", &|u| {
        let n = sample_uniform_sphere(u);
        let d = Vec3::new(0.3, -0.2, 0.9);
        [
            &v3(Onb::from_normal(n).to_world(d))[..],
            &v3(Onb::from_normal_axis_switch(n).to_world(d))[..],
        ]
        .concat()
    });
    push("uniform_ball", &|u| {
        // The third coordinate runs along the grid's diagonal.
        let u3 = Vec3::new(u.x, u.y, (u.x + u.y) * 0.5);
        let p = sample_uniform_ball(u3);
        [
            &v3(p)[..],
            &v3(invert_uniform_ball(p))[..],
            &[pdf_uniform_ball(p).to_bits()],
        ]
        .concat()
    });
    let mut failures = vec![];
    for ((name, w), &(lock_name, want)) in words.into_iter().zip(&MAPPING_LOCK) {
        assert_eq!(name, lock_name);
        let got = fnv(w);
        if got != want {
            failures.push(format!("{name}: {got:#018x} (locked {want:#018x})"));
        }
    }
    assert!(
        failures.is_empty(),
        "mapping outputs changed:\n{}\n{CHANGED}",
        failures.join("\n")
    );
}

/// The reference sphere lists (`x,y,z,r` per line after a header), built
/// into the binary so it needs no file system (WebAssembly has none).
fn spheres(csv: &str) -> Vec<Sphere> {
    csv.lines()
        .skip(1)
        .filter(|l| !l.trim().is_empty())
        .map(|l| {
            let v: Vec<f32> = l.split(',').map(|x| x.trim().parse().unwrap()).collect();
            Sphere::new(Vec3::new(v[0], v[1], v[2]), v[3])
        })
        .collect()
}

/// `n` rays from a PCG32 with `seed`: origins uniform in `[lo, hi]`,
/// directions uniform on the sphere.
fn random_rays(n: usize, lo: Vec3, hi: Vec3, seed: u64) -> Vec<Ray> {
    let mut rng = Pcg32::new(seed, STREAM);
    let mut u = move || next_f32(&mut rng);
    (0..n)
        .map(|_| {
            let o = lo + (hi - lo) * Vec3::new(u(), u(), u());
            let d = sample_uniform_sphere(Vec2::new(u(), u()));
            Ray::new(o, d.normalize())
        })
        .collect()
}

/// FNV-1a of the tabulated mapping on [`grid`] (see [`piecewise_lock`]).
const PIECEWISE_LOCK: u64 = 0x6895e85866df53b4;

/// The tabulated 2-D mapping over a fixed table (`(row · 32 + column) mod
/// 7`, zeros included): each grid point's sample and its pdf, the pdf at
/// the point and the inverse, hashed.
#[test]
fn piecewise_lock() {
    use strata::mapping::{PIECEWISE_2D_SIZE as N, PiecewiseConstant2D};
    let mut values = [[0.0f32; N]; N];
    for (r, row) in values.iter_mut().enumerate() {
        for (c, v) in row.iter_mut().enumerate() {
            *v = ((r * N + c) % 7) as f32;
        }
    }
    let table = PiecewiseConstant2D::new(&values).unwrap();
    let words: Vec<u32> = grid()
        .flat_map(|u| {
            let (p, pdf) = table.sample(u);
            [
                &v2(p)[..],
                &[pdf.to_bits(), table.pdf(p).to_bits()],
                &v2(table.invert(p))[..],
            ]
            .concat()
        })
        .collect();
    let got = fnv(words);
    assert_eq!(got, PIECEWISE_LOCK, "piecewise: {got:#018x}\n{CHANGED}");
}

/// FNV-1a of the closest and any hits of 4096 seeded rays through each
/// reference layout, as [`tracing_lock`] makes them.
const TRACING_LOCK: [(&str, u64); 2] = [
    ("course", 0x9e8f9e61958e4b51),
    ("cover", 0xaa1ad740e725e168),
];

#[test]
fn tracing_lock() {
    let layouts = [
        (
            spheres(include_str!("data/course.csv")),
            Vec3::new(-2.0, -0.5, -2.0),
            Vec3::new(2.0, 1.0, 1.0),
        ),
        (
            spheres(include_str!("data/cover.csv")),
            Vec3::new(-11.0, 0.0, -11.0),
            Vec3::new(11.0, 2.0, 11.0),
        ),
    ];
    let mut digests = vec![];
    for (spheres, lo, hi) in layouts {
        let mut storage = vec![SphereChunk8::EMPTY; chunks_for(spheres.len())];
        let set = SphereSet::build(&spheres, &mut storage).unwrap();
        let rays = random_rays(4096, lo, hi, 3);
        let size = bvh_storage_for(spheres.len());
        let mut nodes = vec![BvhNode8::EMPTY; size.nodes];
        let mut lanes = vec![0.0f32; size.lanes];
        let mut ids = vec![0u32; size.ids];
        let bvh = Bvh::build(&spheres, &mut nodes, &mut lanes, &mut ids).unwrap();
        let mut words = vec![];
        for chunk in rays.chunks(8) {
            let packet_rays = RayPacket8::from_rays(chunk);
            let mut packet = HitPacket8::NONE;
            closest_hit_x8(&set, &packet_rays, &mut packet);
            let mut bvh_packet = HitPacket8::NONE;
            bvh.closest_hit_x8(&packet_rays, &mut bvh_packet);
            for (lane, ray) in chunk.iter().enumerate() {
                let a = closest_hit(&spheres, ray);
                assert_eq!(a, closest_hit_1x8(&set, ray));
                assert_eq!(a, packet.hit(lane));
                assert_eq!(a, bvh.closest_hit(ray));
                assert_eq!(a, bvh_packet.hit(lane));
                assert_eq!(any_hit(&spheres, ray), bvh.any_hit(ray));
                let (s, t) = a.map_or((u32::MAX, 0), |h| (h.sphere, h.t.to_bits()));
                words.extend([s, t, any_hit(&spheres, ray) as u32]);
            }
        }
        digests.push(fnv(words));
    }
    let lock = TRACING_LOCK.map(|(_, h)| h);
    assert_eq!(digests, lock, "hits changed: {digests:#018x?}\n{CHANGED}");
}

/// The locks above as the data file other languages read
/// (`core/tests/data/locks.json`: the C tests, and later Python and the
/// browser), so no constant is copied by hand. Run with `STRATA_BLESS=1`
/// to write it after a deliberate change.
fn locks_json() -> String {
    let mut out = String::from(
        "{\n  \"about\": \"Strata's value locks, written by core/tests/locks.rs (locks_file_is_current); see that file for how each value is made.\",\n",
    );
    // The stream of the tracing lock's ray generator (PCG32 with this
    // stream and seed 3), which other languages rebuild.
    out += &format!("  \"pcg_stream\": \"{STREAM:#018x}\",\n");
    out += "  \"sampler_first_values\": {\n";
    for (k, (name, v)) in SAMPLER_LOCK.iter().enumerate() {
        let words: Vec<String> = v.iter().map(|w| w.to_string()).collect();
        let comma = if k + 1 < SAMPLER_LOCK.len() { "," } else { "" };
        out += &format!("    \"{name}\": [{}]{comma}\n", words.join(", "));
    }
    out += "  },\n  \"sampler_rows_fnv\": {\n";
    for (k, ((name, _), h)) in SAMPLER_LOCK.iter().zip(SAMPLER_ROWS_LOCK).enumerate() {
        let comma = if k + 1 < SAMPLER_LOCK.len() { "," } else { "" };
        out += &format!("    \"rows_{name}\": \"{h:#018x}\"{comma}\n");
    }
    out += "  },\n  \"mapping_fnv\": {\n";
    for (k, (name, h)) in MAPPING_LOCK.iter().enumerate() {
        let comma = if k + 1 < MAPPING_LOCK.len() { "," } else { "" };
        out += &format!("    \"{name}\": \"{h:#018x}\"{comma}\n");
    }
    out += &format!("  }},\n  \"piecewise_fnv\": \"{PIECEWISE_LOCK:#018x}\",\n");
    out += "  \"tracing_fnv\": {\n";
    for (k, (name, h)) in TRACING_LOCK.iter().enumerate() {
        let comma = if k + 1 < TRACING_LOCK.len() { "," } else { "" };
        out += &format!("    \"{name}\": \"{h:#018x}\"{comma}\n");
    }
    out += "  }\n}\n";
    out
}

#[test]
fn locks_file_is_current() {
    let want = locks_json();
    #[cfg(not(target_family = "wasm"))]
    if std::env::var_os("STRATA_BLESS").is_some() {
        let path = concat!(env!("CARGO_MANIFEST_DIR"), "/tests/data/locks.json");
        std::fs::write(path, &want).unwrap();
    }
    assert_eq!(
        include_str!("data/locks.json"),
        want,
        "core/tests/data/locks.json differs from the locks: run `STRATA_BLESS=1 cargo test -p strata --test locks`"
    );
}
