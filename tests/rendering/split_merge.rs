//! Every split of the work merges exactly: random partitions of the image
//! into pixel rectangles, each cut at random sample indices, rendered as
//! separate jobs and merged, give the one-shot film bit for bit, for every
//! sampler. Parts are merged in a shuffled order.

use std::path::PathBuf;

use proptest::prelude::*;
use strata::render::{PixelSum, Tile};
use strata_runner::film::{Film, RenderKey, merge};
use strata_runner::render::{Job, SamplerKind, run};
use strata_runner::scenes::{SceneData, built_in};

const W: u32 = 19;
const H: u32 = 11;
const SPP: u32 = 6;

fn job(
    scene: &SceneData,
    sampler: SamplerKind,
    seed: u64,
    window: Tile,
    samples: std::ops::Range<u32>,
) -> Job<'_> {
    Job {
        window,
        samples,
        max_depth: 4,
        sampler,
        seed,
        threads: 1,
        tile: 4,
        ..Job::new(scene, W, H, SPP)
    }
}

fn film(j: &Job<'_>) -> Film {
    Film {
        key: RenderKey::of(j),
        window: j.window,
        samples: j.samples.clone(),
        pixels: run(j, &|_| {}).unwrap().pixels,
    }
}

/// Guillotine cuts of the image driven by `cuts`: each value picks a
/// rectangle, an axis and a position.
fn rectangles(cuts: &[u32]) -> Vec<Tile> {
    let mut rects = vec![Tile::whole(W, H)];
    for &v in cuts {
        let k = v as usize % rects.len();
        let r = rects[k];
        let vertical = (v >> 8) & 1 == 0;
        let extent = if vertical { r.width } else { r.height };
        if extent < 2 {
            continue;
        }
        let at = 1 + (v >> 9) % (extent - 1);
        let (a, b) = if vertical {
            (
                Tile { width: at, ..r },
                Tile {
                    x0: r.x0 + at,
                    width: r.width - at,
                    ..r
                },
            )
        } else {
            (
                Tile { height: at, ..r },
                Tile {
                    y0: r.y0 + at,
                    height: r.height - at,
                    ..r
                },
            )
        };
        rects[k] = a;
        rects.push(b);
    }
    rects
}

/// Sample ranges of `0..SPP` cut at the given points (any order, repeats
/// and out-of-range values ignored).
fn sample_runs(points: &[u32]) -> Vec<std::ops::Range<u32>> {
    let mut cuts: Vec<u32> = points.iter().map(|p| p % SPP).filter(|&p| p > 0).collect();
    cuts.extend([0, SPP]);
    cuts.sort_unstable();
    cuts.dedup();
    cuts.windows(2).map(|w| w[0]..w[1]).collect()
}

proptest! {
    #![proptest_config(ProptestConfig { cases: 12, ..ProptestConfig::default() })]

    #[test]
    fn random_partitions_merge_to_the_one_shot_film(
        scene in prop::sample::select(vec!["week09", "showcase", "cover"]),
        seed in any::<u64>(),
        cuts in prop::collection::vec(any::<u32>(), 0..6),
        sample_points in prop::collection::vec(prop::collection::vec(any::<u32>(), 0..3), 6),
        order in any::<u64>(),
    ) {
        let data = built_in(scene).unwrap();
        // Every case checks every sampler on the same partition.
        for sampler in SamplerKind::ALL {
        let one_shot = film(&job(&data, sampler, seed, Tile::whole(W, H), 0..SPP));
        let mut parts = vec![];
        for (i, rect) in rectangles(&cuts).into_iter().enumerate() {
            for samples in sample_runs(&sample_points[i % sample_points.len()]) {
                parts.push(film(&job(&data, sampler, seed, rect, samples)));
            }
        }
        // A deterministic shuffle: merging does not depend on the order.
        let mut state = order | 1;
        for i in (1..parts.len()).rev() {
            state ^= state << 13;
            state ^= state >> 7;
            state ^= state << 17;
            parts.swap(i, (state % (i as u64 + 1)) as usize);
        }
        let names: Vec<PathBuf> = (0..parts.len()).map(|i| format!("part{i}.film").into()).collect();
        let merged = merge(&parts, &names).unwrap();
        prop_assert_eq!(&merged.pixels, &one_shot.pixels);
        prop_assert!(merged.pixels.iter().all(|p: &PixelSum| p.taken() == SPP));
        // The same parts through the file format.
        let reread: Vec<Film> = parts.iter().map(|p| Film::from_bytes(&p.to_bytes()).unwrap()).collect();
        prop_assert_eq!(&reread, &parts);
        }
    }
}

#[test]
fn a_missing_or_doubled_part_is_refused() {
    let data = built_in("week09").unwrap();
    let j = |window, samples| film(&job(&data, SamplerKind::Stratified, 1, window, samples));
    let left = Tile {
        x0: 0,
        y0: 0,
        width: 9,
        height: H,
    };
    let right = Tile {
        x0: 9,
        y0: 0,
        width: W - 9,
        height: H,
    };
    let parts = [j(left, 0..SPP), j(right, 0..2), j(right, 2..SPP)];
    let names: Vec<PathBuf> = ["l", "r1", "r2"].map(PathBuf::from).to_vec();
    assert!(merge(&parts, &names).is_ok());
    let e = merge(&parts[..2], &names[..2]).unwrap_err().to_string();
    assert!(e.contains("gap: pixel (9, 0) has 2 of its 6"), "{e}");
    let doubled = [
        parts[0].clone(),
        parts[1].clone(),
        parts[2].clone(),
        parts[2].clone(),
    ];
    let names4: Vec<PathBuf> = ["l", "r1", "r2", "r2b"].map(PathBuf::from).to_vec();
    let e = merge(&doubled, &names4).unwrap_err().to_string();
    assert!(e.contains("`r2` and `r2b` overlap"), "{e}");
}
