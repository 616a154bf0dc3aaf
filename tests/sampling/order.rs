//! Order independence: the same (seed, pixel, sample, dimension) gives
//! the same bits however samples are visited (raster, reversed, shuffled,
//! interleaved with other pixels, on a fresh or a reused sampler), and
//! seeds change every kind.
use glam::UVec2;
use rand_core::Rng;
use strata::rng::{Pcg32, STREAM};
use strata::sampler::{Halton, Independent, Sampler, Sobol, Stratified, UniformGrid, ZSobol};

/// Every value one sample produces, as bits: pixel 2D, then a fixed
/// pattern of 1D and 2D draws.
fn sample_bits<S: Sampler>(s: &mut S, pixel: UVec2, index: u32) -> [u32; 10] {
    s.start_pixel_sample(pixel, index);
    let p = s.pixel_2d();
    let a = s.next_1d();
    let b = s.next_2d();
    let c = s.next_2d();
    let d = s.next_1d();
    let e = s.next_2d();
    [p.x, p.y, a, b.x, b.y, c.x, c.y, d, e.x, e.y].map(f32::to_bits)
}

fn check_order_independence<S: Sampler + Clone>(fresh: S, what: &str) {
    let spp = fresh.samples_per_pixel();
    let mut keys: Vec<(UVec2, u32)> = Vec::new();
    for y in 0..6 {
        for x in 0..7 {
            for i in 0..spp + 3 {
                keys.push((UVec2::new(x, y), i));
            }
        }
    }
    let mut s = fresh.clone();
    let raster: Vec<[u32; 10]> = keys
        .iter()
        .map(|&(p, i)| sample_bits(&mut s, p, i))
        .collect();

    // Reversed, on the same (now used) sampler.
    for (k, &(p, i)) in keys.iter().enumerate().rev() {
        assert_eq!(
            sample_bits(&mut s, p, i),
            raster[k],
            "{what}: reversed at {p} #{i}"
        );
    }
    // Shuffled, each sample on a fresh clone.
    let mut order: Vec<usize> = (0..keys.len()).collect();
    let mut rng = Pcg32::new(99, STREAM);
    for k in (1..order.len()).rev() {
        order.swap(k, rng.next_u32() as usize % (k + 1));
    }
    for &k in &order {
        let (p, i) = keys[k];
        let mut t = fresh.clone();
        assert_eq!(
            sample_bits(&mut t, p, i),
            raster[k],
            "{what}: shuffled at {p} #{i}"
        );
    }
    // A sample abandoned half-way leaves no trace in the next one.
    let mut u = fresh.clone();
    for (k, &(p, i)) in keys.iter().enumerate() {
        u.start_pixel_sample(UVec2::new(1000, 1000), 5);
        let _ = u.next_2d();
        assert_eq!(
            sample_bits(&mut u, p, i),
            raster[k],
            "{what}: after a partial sample"
        );
    }
}

#[test]
fn independent_values_do_not_depend_on_order() {
    check_order_independence(Independent::new(5, 42).unwrap(), "independent");
}

#[test]
fn grid_values_do_not_depend_on_order() {
    check_order_independence(UniformGrid::new(6, 42).unwrap(), "grid");
}

#[test]
fn stratified_values_do_not_depend_on_order() {
    check_order_independence(Stratified::new(7, 42).unwrap(), "stratified");
}

#[test]
fn halton_values_do_not_depend_on_order() {
    check_order_independence(Halton::new(6, 42).unwrap(), "halton");
}

#[test]
fn sobol_values_do_not_depend_on_order() {
    check_order_independence(Sobol::new(8, 42).unwrap(), "sobol");
}

/// ZSobol' correlates pixels through their Morton index, never through
/// state: any visiting order gives the same bits (odd and even block
/// sizes, and a spp that is not a power of two).
#[test]
fn zsobol_values_do_not_depend_on_order() {
    for spp in [8, 2, 6] {
        check_order_independence(ZSobol::new(spp, 42, UVec2::new(7, 6)).unwrap(), "zsobol");
    }
}

#[test]
fn seeds_change_every_kind() {
    let p = UVec2::new(3, 4);
    let mut a = Independent::new(4, 1).unwrap();
    let mut b = Independent::new(4, 2).unwrap();
    assert_ne!(sample_bits(&mut a, p, 0), sample_bits(&mut b, p, 0));
    let mut a = Stratified::new(4, 1).unwrap();
    let mut b = Stratified::new(4, 2).unwrap();
    assert_ne!(sample_bits(&mut a, p, 0), sample_bits(&mut b, p, 0));
    // The grid's pixel positions do not depend on the seed, its shuffles do.
    let mut a = UniformGrid::new(4, 1).unwrap();
    let mut b = UniformGrid::new(4, 2).unwrap();
    let (ga, gb): (Vec<_>, Vec<_>) = (0..4)
        .map(|i| (sample_bits(&mut a, p, i), sample_bits(&mut b, p, i)))
        .unzip();
    assert!(ga.iter().zip(&gb).all(|(x, y)| x[..2] == y[..2]));
    assert_ne!(ga, gb);
}
