//! Stream independence: value pairs from adjacent pixels, adjacent sample
//! indices, adjacent seeds and adjacent dimensions are uniform on [0, 1)²
//! by a χ² test (32 × 32 cells, 10⁶ pairs, α = 1 % Šidák-corrected over
//! this file's χ² tests), and their Pearson correlation is below 5
//! standard errors.
use crate::support::chi2::{Chi2, Domain};
use glam::{UVec2, Vec2};
use strata::sampler::{Halton, Independent, Sampler, Sobol, Stratified};
const PAIR_TESTS: usize = 11;
const PAIRS: usize = 1_000_000;

/// χ² of `PAIRS` value pairs on the unit square against the uniform
/// density, plus their Pearson correlation.
fn check_pairs(name: &str, mut pair: impl FnMut(usize) -> Vec2) {
    let mut k = 0;
    let (mut sx, mut sy, mut sxx, mut syy, mut sxy) = (0.0, 0.0, 0.0, 0.0, 0.0);
    let test = Chi2::new(name, Domain::UNIT_SQUARE, (32, 32), PAIR_TESTS);
    let outcome = test.run(
        || {
            let p = pair(k);
            k += 1;
            let (x, y) = (p.x as f64, p.y as f64);
            sx += x;
            sy += y;
            sxx += x * x;
            syy += y * y;
            sxy += x * y;
            [x, y, 0.0]
        },
        |_| 1.0,
    );
    outcome.assert_passed();
    let n = PAIRS as f64;
    let cov = sxy / n - (sx / n) * (sy / n);
    let r = cov / ((sxx / n - (sx / n).powi(2)) * (syy / n - (sy / n).powi(2))).sqrt();
    assert!(r.abs() < 5.0 / n.sqrt(), "{name}: correlation {r}");
}

/// The same dimension of the same sample index in horizontally
/// neighbouring pixels (16 samples per pixel): must be uncorrelated.
fn check_neighbour_pixels<S: Sampler>(name: &str, mut s: S) {
    check_pairs(name, |k| {
        let i = (k % 16) as u32;
        let p = pixel(k / 16);
        s.start_pixel_sample(p, i);
        let a = s.next_1d();
        s.start_pixel_sample(p + UVec2::X, i);
        Vec2::new(a, s.next_1d())
    });
}

/// Pixel `k` of a 1000-wide image.
fn pixel(k: usize) -> UVec2 {
    UVec2::new((k % 1000) as u32, (k / 1000) as u32)
}

#[test]
fn horizontal_neighbour_pixels_are_independent() {
    let mut s = Independent::new(1, 7).unwrap();
    check_pairs("pairs_pixel_x", |k| {
        s.start_pixel_sample(pixel(k), 0);
        let a = s.next_1d();
        s.start_pixel_sample(pixel(k) + UVec2::X, 0);
        Vec2::new(a, s.next_1d())
    });
}

#[test]
fn vertical_neighbour_pixels_are_independent() {
    let mut s = Independent::new(1, 7).unwrap();
    check_pairs("pairs_pixel_y", |k| {
        s.start_pixel_sample(pixel(k), 0);
        let a = s.pixel_2d().x;
        s.start_pixel_sample(pixel(k) + UVec2::Y, 0);
        Vec2::new(a, s.pixel_2d().x)
    });
}

#[test]
fn consecutive_sample_indices_are_independent() {
    let mut s = Independent::new(1024, 7).unwrap();
    check_pairs("pairs_index", |k| {
        let p = UVec2::new(k as u32 / 1000, 5);
        let i = (k % 1000) as u32;
        s.start_pixel_sample(p, i);
        let a = s.next_1d();
        s.start_pixel_sample(p, i + 1);
        Vec2::new(a, s.next_1d())
    });
}

#[test]
fn consecutive_seeds_are_independent() {
    check_pairs("pairs_seed", |k| {
        let mut a = Independent::new(1, k as u64).unwrap();
        let mut b = Independent::new(1, k as u64 + 1).unwrap();
        a.start_pixel_sample(UVec2::new(2, 2), 0);
        b.start_pixel_sample(UVec2::new(2, 2), 0);
        Vec2::new(a.next_1d(), b.next_1d())
    });
}

#[test]
fn consecutive_dimensions_are_independent() {
    let mut s = Independent::new(1, 7).unwrap();
    check_pairs("pairs_dimension", |k| {
        s.start_pixel_sample(pixel(k), 0);
        let _ = s.next_2d();
        Vec2::new(s.next_1d(), s.next_1d())
    });
}

/// Stratified samples of neighbouring pixels use independent shuffles and
/// jitters: the same dimension of the same sample index is uncorrelated.
#[test]
fn stratified_neighbour_pixels_are_independent() {
    check_neighbour_pixels("pairs_stratified_pixel_x", Stratified::new(16, 7).unwrap());
}

/// A stratified sample's pixel position and its first bounce dimension are
/// uncorrelated (each comes from its own shuffle).
#[test]
fn stratified_pixel_and_bounce_dimensions_are_independent() {
    let mut s = Stratified::new(16, 7).unwrap();
    check_pairs("pairs_stratified_pixel_dim2", |k| {
        s.start_pixel_sample(pixel(k / 16), (k % 16) as u32);
        Vec2::new(s.pixel_2d().x, s.next_1d())
    });
}

/// Consecutive stratified dimensions are uncorrelated.
#[test]
fn stratified_consecutive_dimensions_are_independent() {
    let mut s = Stratified::new(16, 7).unwrap();
    check_pairs("pairs_stratified_dim2_dim3", |k| {
        s.start_pixel_sample(pixel(k / 16), (k % 16) as u32);
        Vec2::new(s.next_1d(), s.next_1d())
    });
}

/// Stream states use every bit of the seed, the pixel and the index: no
/// two of these inputs, which differ only in high bits, share a state.
#[test]
fn stream_states_use_every_input_bit() {
    use strata::rng::stream_state;
    let words = [0u32, 1, 1 << 16, 1 << 24, 1 << 31, u32::MAX];
    let seeds = [0u64, 1 << 32, 1 << 63, u64::MAX];
    let mut states = Vec::new();
    for seed in seeds {
        for &x in &words {
            for &y in &words {
                for &i in &words {
                    states.push(stream_state(seed, UVec2::new(x, y), i));
                }
            }
        }
    }
    let n = states.len();
    states.sort_unstable();
    states.dedup();
    assert_eq!(states.len(), n, "colliding stream states");
}

/// Sobol' samples of neighbouring pixels use independent scrambles: the
/// same dimension of the same index is uncorrelated across pixels.
#[test]
fn sobol_neighbour_pixels_are_independent() {
    check_neighbour_pixels("pairs_sobol_pixel_x", Sobol::new(16, 7).unwrap());
}

/// Halton samples of neighbouring pixels use independent digit scrambles
/// (without them every pixel would repeat one sequence).
#[test]
fn halton_neighbour_pixels_are_independent() {
    check_neighbour_pixels("pairs_halton_pixel_x", Halton::new(16, 7).unwrap());
}

/// Below the digits that tell its 4 samples apart, a Halton value is a
/// uniform point of its cell (base 2: cells of 1/4; base 3: cells of 1/9),
/// independently in each dimension: the positions within the cells of
/// the pixel's two dimensions are uniform on the square.
#[test]
fn halton_points_are_uniform_within_their_cells() {
    let mut s = Halton::new(4, 3).unwrap();
    check_pairs("pairs_halton_within_cells", |k| {
        s.start_pixel_sample(pixel(k / 4), (k % 4) as u32);
        let p = s.pixel_2d();
        let frac = |v: f32, cells: f64| {
            let x = v as f64 * cells;
            (x - x.floor()) as f32
        };
        Vec2::new(frac(p.x, 4.0), frac(p.y, 9.0))
    });
}
