//! Each stratum of each stratified dimension gets exactly one sample per
//! pixel (per pass of `spp` samples), for square and non-square spp alike;
//! the course's jitter defect D3 (an offset that drifts with spp) is gone.

use glam::{UVec2, Vec2};
use strata::sampler::{Independent, Sampler, Stratified, UniformGrid, grid_dims};

const SPPS: [u32; 14] = [1, 2, 3, 4, 5, 7, 9, 12, 16, 30, 64, 97, 100, 256];
const PIXELS: [UVec2; 4] = [
    UVec2::new(0, 0),
    UVec2::new(1, 0),
    UVec2::new(319, 179),
    UVec2::new(70_000, 3),
];

/// The call pattern of one sample after `pixel_2d`: a mix of 1D and 2D
/// draws, as a path's bounces make them.
const PATTERN: [u8; 8] = [2, 1, 1, 2, 2, 1, 2, 1];

/// Draws pass `pass` of every sample of `pixel` and checks, per dimension,
/// that the samples fill the strata exactly once.
fn check_pixel<S: Sampler>(s: &mut S, pixel: UVec2, pass: u32, what: &str) {
    let spp = s.samples_per_pixel();
    let (nx, ny) = grid_dims(spp);
    // counts[d][cell]
    let mut counts = vec![vec![0u32; spp as usize]; PATTERN.len() + 1];
    for i in pass * spp..(pass + 1) * spp {
        s.start_pixel_sample(pixel, i);
        let cell2 = |p: Vec2| {
            let cx = (p.x as f64 * nx as f64).floor() as u32;
            let cy = (p.y as f64 * ny as f64).floor() as u32;
            assert!(cx < nx && cy < ny, "{what}: {p} outside [0,1)²");
            (cy * nx + cx) as usize
        };
        counts[0][cell2(s.pixel_2d())] += 1;
        for (d, &kind) in PATTERN.iter().enumerate() {
            let cell = if kind == 1 {
                let v = s.next_1d();
                assert!((0.0..1.0).contains(&v), "{what}: {v}");
                (v as f64 * spp as f64).floor() as usize
            } else {
                cell2(s.next_2d())
            };
            counts[d + 1][cell] += 1;
        }
    }
    for (d, c) in counts.iter().enumerate() {
        assert!(
            c.iter().all(|&k| k == 1),
            "{what}: spp {spp} pixel {pixel} pass {pass} dimension slot {d}: counts {c:?}"
        );
    }
}

#[test]
fn stratified_one_sample_per_stratum() {
    for spp in SPPS {
        for seed in [0u64, 1, 0xfeed_f00d] {
            let mut s = Stratified::new(spp, seed).unwrap();
            for pixel in PIXELS {
                for pass in [0, 1, 7] {
                    check_pixel(&mut s, pixel, pass, "stratified");
                }
            }
        }
    }
}

#[test]
fn grid_one_sample_per_stratum() {
    for spp in SPPS {
        let mut s = UniformGrid::new(spp, 5).unwrap();
        for pixel in PIXELS {
            for pass in [0, 3] {
                check_pixel(&mut s, pixel, pass, "grid");
            }
        }
    }
}

/// The control: independent samples leave strata empty, so the check
/// above has teeth.
#[test]
fn independent_is_not_stratified() {
    let spp = 64;
    let mut s = Independent::new(spp, 1).unwrap();
    let mut empty = 0;
    for pixel in PIXELS {
        let mut counts = [0u32; 64];
        for i in 0..spp {
            s.start_pixel_sample(pixel, i);
            counts[(s.next_1d() * 64.0) as usize] += 1;
        }
        empty += counts.iter().filter(|&&c| c == 0).count();
    }
    // About 64/e ≈ 23.5 of 64 strata stay empty per pixel.
    assert!(empty > 40, "{empty}");
}

/// Jitter moves a sample inside its stratum: the same stratum takes
/// different values in different pixels (stratified), the centre always
/// (grid).
#[test]
fn stratified_jitters_and_grid_does_not() {
    let spp = 16;
    let mut st = Stratified::new(spp, 3).unwrap();
    let mut gr = UniformGrid::new(spp, 3).unwrap();
    let mut distinct = std::collections::BTreeSet::new();
    for x in 0..64 {
        for i in 0..spp {
            st.start_pixel_sample(UVec2::new(x, 0), i);
            distinct.insert(st.next_1d().to_bits());
            gr.start_pixel_sample(UVec2::new(x, 0), i);
            let v = gr.next_1d() as f64 * spp as f64;
            assert_eq!(v.fract(), 0.5, "grid sample off its stratum centre");
        }
    }
    assert!(distinct.len() > 1000, "{}", distinct.len());
}

/// COURSE.md D3: the course's jittered offset drifts with spp (at 100 spp
/// its range is [-0.25, 1.42] px, mean +0.58). Strata's offsets cover the
/// pixel evenly for every spp: mean exactly at the centre up to the
/// jitter's average, extremes within one stratum of the edges.
#[test]
fn pixel_offsets_cover_the_pixel_for_any_spp() {
    for spp in [4u32, 9, 16, 30, 100] {
        let (nx, ny) = grid_dims(spp);
        let mut s = Stratified::new(spp, 17).unwrap();
        let (mut sum, mut lo, mut hi) = (Vec2::ZERO, Vec2::ONE, Vec2::ZERO);
        let pixels = 200;
        for x in 0..pixels {
            for i in 0..spp {
                s.start_pixel_sample(UVec2::new(x, 1), i);
                let p = s.pixel_2d();
                sum += p;
                lo = lo.min(p);
                hi = hi.max(p);
            }
        }
        let mean = sum / (pixels * spp) as f32;
        // Strata centres average to exactly 0.5; the jitter's mean error
        // over N samples has sd 1/(n sqrt(12 N)) < 0.001 here.
        assert!(
            (mean - Vec2::splat(0.5)).abs().max_element() < 0.005,
            "spp {spp}: {mean}"
        );
        assert!(
            lo.x < 1.0 / nx as f32 && lo.y < 1.0 / ny as f32,
            "spp {spp}: {lo}"
        );
        assert!(
            hi.x > 1.0 - 1.0 / nx as f32 && hi.y > 1.0 - 1.0 / ny as f32,
            "spp {spp}: {hi}"
        );
    }
}

/// Each pass of `spp` samples is a fresh stratified set: sample `i` and
/// sample `i + spp` of a pixel fall in the same stratum of a dimension only
/// by chance (1 in spp), not always.
#[test]
fn passes_reshuffle_the_strata() {
    let spp = 16;
    let mut s = Stratified::new(spp, 9).unwrap();
    let (mut same, mut total) = (0, 0);
    for x in 0..500 {
        for i in 0..spp {
            let p = UVec2::new(x, 2);
            s.start_pixel_sample(p, i);
            let a = (s.next_1d() * spp as f32) as u32;
            s.start_pixel_sample(p, i + spp);
            let b = (s.next_1d() * spp as f32) as u32;
            same += (a == b) as u32;
            total += 1;
        }
    }
    // Expected 1/16 = 0.0625 of 8000; binomial sd ≈ 0.0027.
    let frac = same as f64 / total as f64;
    assert!((frac - 1.0 / 16.0).abs() < 0.015, "{frac}");
}

/// Owen-scrambled Sobol': the first 2^k samples of a pixel put exactly one
/// point in every elementary interval of area 2^-k — every shape
/// 2^-a × 2^-b with a + b = k — in the pixel position and in every 2D
/// draw, the lens pair and an odd-started one included (the
/// (0, 2)-sequence property, kept by the scrambling).
#[test]
fn sobol_first_pairs_are_nets() {
    use strata::Sobol;
    for seed in [0u64, 7, 0xfeed] {
        for pixel in PIXELS {
            for k in 1..=10u32 {
                let n = 1u32 << k;
                let mut s = Sobol::new(n, seed).unwrap();
                // The pixel pair, the lens (2, 3), dimensions (4, 5), and a
                // 2D draw after three 1D draws (aligned to (10, 11)).
                let mut sets: Vec<Vec<Vec2>> = vec![Vec::new(); 4];
                for i in 0..n {
                    s.start_pixel_sample(pixel, i);
                    sets[0].push(s.pixel_2d());
                    sets[1].push(s.next_2d());
                    sets[2].push(s.next_2d());
                    let _ = (s.next_1d(), s.next_1d(), s.next_1d());
                    sets[3].push(s.next_2d());
                }
                for (which, pts) in sets.iter().enumerate() {
                    assert_net(pts, k, &format!("seed {seed} pixel {pixel} set {which}"));
                }
            }
        }
    }
}

/// Every Sobol' dimension alone stratifies: 2^k samples, 2^k strata, one
/// each, for the first 40 dimensions.
#[test]
fn sobol_every_dimension_is_stratified() {
    use strata::Sobol;
    for k in [2u32, 5, 8] {
        let n = 1u32 << k;
        let mut s = Sobol::new(n, 3).unwrap();
        let mut counts = vec![vec![0u32; n as usize]; 40];
        for i in 0..n {
            s.start_pixel_sample(UVec2::new(3, 8), i);
            for c in counts.iter_mut() {
                c[(s.next_1d() as f64 * n as f64) as usize] += 1;
            }
        }
        for (d, c) in counts.iter().enumerate() {
            assert!(
                c.iter().all(|&x| x == 1),
                "k {k} dimension {}: {c:?}",
                d + 2
            );
        }
    }
}

/// Owen-scrambled Halton: with 2^a · 3^b samples the pixel positions fill
/// a 2^a × 3^b grid once each; every dimension alone fills b^k strata of
/// its base once each; and a second run of indices is a fresh set.
#[test]
fn halton_is_stratified_in_its_bases() {
    use strata::Halton;
    for seed in [0u64, 9] {
        for pixel in PIXELS {
            for (a, b) in [(1u32, 1u32), (2, 1), (3, 2), (4, 2), (2, 3), (5, 3)] {
                let (nx, ny) = (1u32 << a, 3u32.pow(b));
                let n = nx * ny;
                let mut s = Halton::new(n, seed).unwrap();
                let mut cells = vec![0u32; n as usize];
                for i in 0..n {
                    s.start_pixel_sample(pixel, i);
                    let p = s.pixel_2d();
                    let cx = (p.x as f64 * nx as f64) as u32;
                    let cy = (p.y as f64 * ny as f64) as u32;
                    cells[(cy * nx + cx) as usize] += 1;
                }
                assert!(
                    cells.iter().all(|&c| c == 1),
                    "seed {seed} {pixel} {nx}x{ny}: {cells:?}"
                );
            }
        }
    }
    // Dimensions 2.. use bases 5, 7, 11, ...: b^k samples fill b^k strata.
    let bases = [5u32, 7, 11, 13, 17, 19];
    for (d, &base) in bases.iter().enumerate() {
        for k in 1..=2u32 {
            let n = base.pow(k);
            let mut s = Halton::new(n, 4).unwrap();
            let mut counts = vec![0u32; n as usize];
            for i in 0..n {
                s.start_pixel_sample(UVec2::new(7, 1), i);
                for _ in 0..d {
                    let _ = s.next_1d();
                }
                counts[(s.next_1d() as f64 * n as f64) as usize] += 1;
            }
            assert!(
                counts.iter().all(|&c| c == 1),
                "base {base} k {k}: {counts:?}"
            );
        }
    }
}

/// Indices come in blocks of `b^k` per base (`b^k` the smallest power of
/// the base at least spp): every block `[j·b^k, (j+1)·b^k)` fills the
/// `b^k` strata once each, and a later block is scrambled afresh (its
/// strata come in another order).
#[test]
fn halton_blocks_are_fresh_stratified_sets() {
    use strata::Halton;
    let mut reordered = 0;
    for seed in 0..50u64 {
        // (spp, dimension, its base's b^k)
        for (spp, dim, n) in [
            (4u32, 0usize, 4u32),
            (3, 1, 3),
            (8, 0, 8),
            (5, 0, 8),
            (5, 1, 9),
        ] {
            let mut s = Halton::new(spp, seed).unwrap();
            let mut orders = Vec::new();
            for block in 0..3 {
                let mut cells = vec![0u32; n as usize];
                let mut order = Vec::new();
                for i in block * n..(block + 1) * n {
                    s.start_pixel_sample(UVec2::new(3, 8), i);
                    let p = s.pixel_2d();
                    let v = if dim == 0 { p.x } else { p.y };
                    let c = (v as f64 * n as f64) as usize;
                    cells[c] += 1;
                    order.push(c);
                }
                assert!(
                    cells.iter().all(|&c| c == 1),
                    "seed {seed} spp {spp} dim {dim} block {block}: {cells:?}"
                );
                orders.push(order);
            }
            reordered += (orders[0] != orders[1]) as u32 + (orders[1] != orders[2]) as u32;
        }
    }
    // 500 block pairs; a fresh scramble repeats the order with probability
    // 1/n! (at most 1/6 here).
    assert!(reordered > 350, "{reordered} of 500 block pairs reordered");
}

/// The (0,2)-sequence property of the first two Sobol' dimensions beyond
/// the first block: every aligned block `[j·2^k, (j+1)·2^k)` of the 256
/// samples of a pixel is a (0,k,2)-net, for the pixel pair and the lens
/// pair.
#[test]
fn sobol_later_blocks_are_nets_too() {
    use strata::Sobol;
    const N: u32 = 256;
    for seed in [0u64, 11] {
        for pixel in PIXELS {
            let mut s = Sobol::new(N, seed).unwrap();
            let mut pts = [Vec::new(), Vec::new()];
            for i in 0..N {
                s.start_pixel_sample(pixel, i);
                pts[0].push(s.pixel_2d());
                pts[1].push(s.next_2d());
            }
            for (which, pts) in pts.iter().enumerate() {
                for k in 1..=7u32 {
                    let n = 1usize << k;
                    for (j, block) in pts.chunks(n).enumerate() {
                        let what = format!("seed {seed} {pixel} set {which} block {j}");
                        assert_net(block, k, &what);
                    }
                }
            }
        }
    }
}

/// `pts` (2^k points) is a (0,k,2)-net: every elementary interval of area
/// 2^-k holds exactly one point, for every shape 2^a × 2^(k−a).
fn assert_net(pts: &[Vec2], k: u32, what: &str) {
    assert_eq!(pts.len(), 1 << k, "{what}");
    for a in 0..=k {
        let (nx, ny) = (1u32 << a, 1u32 << (k - a));
        let mut cells = vec![0u32; pts.len()];
        for p in pts {
            let cx = (p.x as f64 * nx as f64) as u32;
            let cy = (p.y as f64 * ny as f64) as u32;
            cells[(cy * nx + cx) as usize] += 1;
        }
        assert!(
            cells.iter().all(|&c| c == 1),
            "{what} k {k}: {nx}x{ny} intervals {cells:?}"
        );
    }
}

/// The draws of one ZSobol' sample: the pixel position, then 1D and 2D
/// draws in a path's order (the 2D draws start on odd and even
/// dimensions alike: ZSobol' does not align them).
fn zsobol_draws<S: Sampler>(s: &mut S, pixel: UVec2, index: u32) -> (Vec<Vec2>, Vec<f32>) {
    s.start_pixel_sample(pixel, index);
    let p = s.pixel_2d();
    let a = s.next_1d();
    let b = s.next_2d();
    let c = s.next_1d();
    let d = s.next_2d();
    (vec![p, b, d], vec![a, c])
}

/// The draws of every (pixel, index) of `samples`, gathered per draw: the
/// three 2D draws' point sets and the two 1D draws' value sets.
fn gather<S: Sampler>(
    s: &mut S,
    samples: impl IntoIterator<Item = (UVec2, u32)>,
) -> (Vec<Vec<Vec2>>, Vec<Vec<f32>>) {
    let (mut sets, mut ones) = (vec![Vec::new(); 3], vec![Vec::new(); 2]);
    for (pixel, i) in samples {
        let (two, one) = zsobol_draws(s, pixel, i);
        two.into_iter()
            .zip(&mut sets)
            .for_each(|(v, set)| set.push(v));
        one.into_iter()
            .zip(&mut ones)
            .for_each(|(v, set)| set.push(v));
    }
    (sets, ones)
}

/// Every 2D draw of `gathered` is a (0, k, 2)-net and every 1D draw fills
/// 2^k strata once each.
fn assert_gathered_nets((sets, ones): &(Vec<Vec<Vec2>>, Vec<Vec<f32>>), k: u32, what: &str) {
    for (j, pts) in sets.iter().enumerate() {
        assert_net(pts, k, &format!("{what} 2D draw {j}"));
    }
    for (j, values) in ones.iter().enumerate() {
        let n = values.len();
        let mut counts = vec![0u32; n];
        for &v in values {
            counts[(v as f64 * n as f64) as usize] += 1;
        }
        assert!(
            counts.iter().all(|&c| c == 1),
            "{what} 1D draw {j}: {counts:?}"
        );
    }
}

/// ZSobol': with 2^k samples, each pixel's samples (every pass of them)
/// are a (0, k, 2)-net in the pixel position and in every 2D draw, and
/// fill 2^k strata in every 1D draw, as Sobol' does, for pixels inside
/// and outside the resolution (a 2^20-wide one makes 40-bit and wider
/// indices).
#[test]
fn zsobol_pixels_are_nets() {
    use strata::ZSobol;
    for seed in [0u64, 7, 0xfeed] {
        for res in [
            UVec2::new(320, 180),
            UVec2::new(1, 1),
            UVec2::new(1 << 20, 5),
        ] {
            for k in 0..=8u32 {
                let n = 1u32 << k;
                let mut s = ZSobol::new(n, seed, res).unwrap();
                for pixel in PIXELS {
                    for pass in [0, 1, 7] {
                        let g = gather(&mut s, (pass * n..(pass + 1) * n).map(|i| (pixel, i)));
                        let what = format!("seed {seed} res {res} {pixel} pass {pass}");
                        assert_gathered_nets(&g, k, &what);
                    }
                }
            }
        }
    }
}

/// What makes ZSobol' blue: the samples of an aligned 2^a × 2^a block of
/// pixels together form a (0, 2a + k, 2)-net, and fill 4^a · 2^k strata
/// of every 1D draw, so each pixel's samples fall where its neighbours'
/// are not. The control: Sobol' pixels are independent, so their union
/// is not a net.
#[test]
fn zsobol_pixel_blocks_are_nets_and_sobol_blocks_are_not() {
    use strata::{Sobol, ZSobol};
    fn block<S: Sampler>(s: &mut S, origin: UVec2, side: u32) -> (Vec<Vec<Vec2>>, Vec<Vec<f32>>) {
        let n = s.samples_per_pixel();
        let pixels = (0..side * side).map(move |p| origin + UVec2::new(p % side, p / side));
        gather(s, pixels.flat_map(|p| (0..n).map(move |i| (p, i))))
    }
    for seed in [1u64, 99] {
        for k in 0..=4u32 {
            for a in 1..=3u32 {
                let side = 1 << a;
                let mut s = ZSobol::new(1 << k, seed, UVec2::new(320, 180)).unwrap();
                for origin in [
                    UVec2::ZERO,
                    UVec2::new(8 * side, 2 * side),
                    UVec2::new(312, 176),
                ] {
                    let origin = origin / side * side;
                    let what = format!("seed {seed} spp {} block {origin} side {side}", 1 << k);
                    assert_gathered_nets(&block(&mut s, origin, side), 2 * a + k, &what);
                }
            }
        }
    }
    // Sobol': a 2 × 2 block of one-sample pixels leaves a quarter of the
    // 1D strata empty or doubled in most blocks.
    let mut s = Sobol::new(1, 1).unwrap();
    let mut failed = 0;
    for b in 0..64 {
        let (_, ones) = block(&mut s, UVec2::new(2 * (b % 8), 2 * (b / 8)), 2);
        let mut counts = [0u32; 4];
        ones[0]
            .iter()
            .for_each(|&v| counts[(v * 4.0) as usize] += 1);
        failed += counts.iter().any(|&c| c != 1) as u32;
    }
    // 1 − 4!/4⁴ ≈ 91 % of blocks of independent pixels; asserted half.
    assert!(failed > 32, "{failed} of 64");
}

/// A prefix of a ZSobol' pixel's samples is a net when it ends on a
/// base-4 digit: the first 4 of 16, the first 2 and 8 of 32; and a spp
/// that is not a power of two takes the first slots of the next power
/// of two, so its samples never share a stratum of that power.
#[test]
fn zsobol_prefixes_and_other_spp() {
    use strata::ZSobol;
    for seed in 0..20u64 {
        for (spp, prefix) in [(16u32, 4u32), (16, 1), (32, 2), (32, 8), (8, 2), (64, 16)] {
            let mut s = ZSobol::new(spp, seed, UVec2::new(100, 100)).unwrap();
            let pixel = UVec2::new(seed as u32 * 3, 41);
            let (sets, _) = gather(&mut s, (0..prefix).map(|i| (pixel, i)));
            for p in &sets {
                assert_net(
                    p,
                    prefix.trailing_zeros(),
                    &format!("seed {seed} {prefix} of {spp}"),
                );
            }
        }
        for spp in [3u32, 6, 12, 100] {
            let block = spp.next_power_of_two();
            let mut s = ZSobol::new(spp, seed, UVec2::new(100, 100)).unwrap();
            let (_, ones) = gather(&mut s, (0..spp).map(|i| (UVec2::new(5, seed as u32), i)));
            let mut counts = vec![0u32; block as usize];
            ones[1]
                .iter()
                .for_each(|&v| counts[(v as f64 * block as f64) as usize] += 1);
            assert!(
                counts.iter().all(|&c| c <= 1),
                "seed {seed} spp {spp}: {counts:?}"
            );
        }
    }
}
