//! Every sampler's limits, as the `sampler` module documents them (its
//! "Limits" table): spp beyond what a kind stratifies, Halton dimensions
//! beyond its 64 bases, the largest pixel and index. Indices `≥ spp` are
//! checked in `stratification`, with each kind's structure
//! (`stratified_one_sample_per_stratum` and `passes_reshuffle_the_strata`
//! for passes, `sobol_later_blocks_are_nets_too`,
//! `halton_blocks_are_fresh_stratified_sets`).
//!
//! The χ² tests use 16 × 16 cells, fixed seeds and α = 1 %,
//! Šidák-corrected over this file's [`CHI2_TESTS`].

use crate::support::chi2::{Chi2, Domain};
use glam::{UVec2, Vec2};
use strata::sampler::{
    Halton, Independent, MAX_STRATA_SPP, Sampler, Sobol, Stratified, UniformGrid, ZSobol,
    ZSobolError,
};

const CHI2_TESTS: usize = 2;

/// The strata samplers refuse an spp they could not stratify (a stratum
/// narrower than the `f32` spacing near 1) and take the largest they can;
/// the other kinds take any spp, and none takes 0.
#[test]
fn strata_samplers_refuse_spp_beyond_2_24() {
    assert!(Stratified::new(MAX_STRATA_SPP + 1, 1).is_none());
    assert!(UniformGrid::new(MAX_STRATA_SPP + 1, 1).is_none());
    assert!(Stratified::new(u32::MAX, 1).is_none());
    let mut s = Stratified::new(MAX_STRATA_SPP, 1).unwrap();
    let mut g = UniformGrid::new(MAX_STRATA_SPP, 1).unwrap();
    assert_eq!((s.grid(), g.grid()), ((4096, 4096), (4096, 4096)));
    for index in [0, MAX_STRATA_SPP - 1, MAX_STRATA_SPP, u32::MAX] {
        s.start_pixel_sample(UVec2::new(2, 3), index);
        g.start_pixel_sample(UVec2::new(2, 3), index);
        for v in [s.pixel_2d(), s.next_2d(), g.pixel_2d(), g.next_2d()] {
            assert!(v.cmpge(Vec2::ZERO).all() && v.cmplt(Vec2::ONE).all(), "{v}");
        }
        let v = s.next_1d();
        assert!((0.0..1.0).contains(&v));
    }
    assert!(Independent::new(u32::MAX, 1).is_some());
    assert!(Sobol::new(u32::MAX, 1).is_some());
    assert!(Halton::new(u32::MAX, 1).is_some());
    assert!(Independent::new(0, 1).is_none());
    assert!(UniformGrid::new(0, 1).is_none());
    assert!(Stratified::new(0, 1).is_none());
    assert!(Sobol::new(0, 1).is_none());
    assert!(Halton::new(0, 1).is_none());
}

/// Beyond `2²⁴` samples Sobol' values are still balanced at the `f32`
/// resolution: `2²⁵` samples of one pixel give each of the `2²⁴` values of
/// each pixel dimension exactly twice.
#[test]
fn sobol_beyond_2_24_samples_fills_each_value_equally() {
    const N: u32 = 1 << 25;
    let mut s = Sobol::new(N, 4).unwrap();
    let mut counts = vec![[0u8; 2]; 1 << 24];
    for i in 0..N {
        s.start_pixel_sample(UVec2::new(9, 2), i);
        let p = s.pixel_2d();
        counts[(p.x * 16_777_216.0) as usize][0] += 1;
        counts[(p.y * 16_777_216.0) as usize][1] += 1;
    }
    assert!(counts.iter().all(|c| *c == [2, 2]));
}

/// Halton stratifies up to the `f32` resolution: in base 311 (dimension
/// 63) that is `311² = 96 721` strata, and with a larger spp the first
/// `311²` samples fill them once each, then the next block starts afresh.
#[test]
fn halton_stratifies_up_to_the_f32_resolution() {
    const CELLS: u32 = 311 * 311;
    let mut s = Halton::new(100_000, 6).unwrap();
    let mut counts = vec![0u8; CELLS as usize];
    let mut dim63 = |i| {
        s.start_pixel_sample(UVec2::new(1, 1), i);
        for _ in 2..63 {
            let _ = s.next_1d();
        }
        (s.next_1d() as f64 * CELLS as f64) as usize
    };
    for i in 0..CELLS {
        counts[dim63(i)] += 1;
    }
    assert!(counts.iter().all(|&c| c == 1));
    // The next block: distinct strata again, in another order.
    let mut again = vec![0u8; CELLS as usize];
    let mut moved = 0;
    for i in CELLS..CELLS + 1000 {
        let c = dim63(i);
        again[c] += 1;
        moved += (c != dim63(i - CELLS)) as u32;
    }
    assert!(again.iter().all(|&c| c <= 1));
    assert!(moved > 990, "{moved} of 1000 moved");
}

/// From dimension 64 on, Halton values are independent uniforms: pairs of
/// dimensions beyond the bases, and one of them with the base-2 pixel
/// coordinate, are uniform on the square (χ²).
#[test]
fn halton_dimensions_beyond_the_bases_are_independent_uniforms() {
    let mut s = Halton::new(16, 12).unwrap();
    let mut draw = |k: usize| {
        s.start_pixel_sample(
            UVec2::new((k / 16 % 500) as u32, (k / 8000) as u32),
            k as u32 % 16,
        );
        let x = s.pixel_2d().x;
        for _ in 2..64 {
            let _ = s.next_1d();
        }
        [x, s.next_1d(), s.next_1d()] // dimensions 0, 64, 65
    };
    for (name, pick) in [
        ("halton_dims_64_65", [1usize, 2]),
        ("halton_dims_0_64", [0, 1]),
    ] {
        let mut test = Chi2::new(name, Domain::UNIT_SQUARE, (16, 16), CHI2_TESTS);
        test.samples = 200_000;
        let mut k = 0;
        test.run(
            || {
                let v = draw(k);
                k += 1;
                [v[pick[0]] as f64, v[pick[1]] as f64, 0.0]
            },
            |_| 1.0,
        )
        .assert_passed();
    }
}

/// The largest pixel and index are valid for every kind, and what each
/// kind stratifies holds there too: the last 16 indices of a pixel at
/// `(u32::MAX, u32::MAX)` are a complete pass (strata samplers, spp 16), an
/// aligned block of a net (Sobol') and a block of `2⁴` (Halton, base 2).
#[test]
fn every_sampler_works_at_the_largest_pixel_and_index() {
    /// What a kind stratifies at spp 16: the 4 × 4 cells of the pixel,
    /// the 16 strata of the pixel's x, of the first 1D draw.
    struct Strata {
        cells: bool,
        x: bool,
        one_d: bool,
    }
    fn check<S: Sampler>(mut s: S, what: &str, want: Strata) {
        let far = UVec2::new(u32::MAX, u32::MAX);
        let (mut cells, mut x, mut one_d) = ([0u32; 16], [0u32; 16], [0u32; 16]);
        for i in u32::MAX - 15..=u32::MAX {
            s.start_pixel_sample(far, i);
            let (p, a, b) = (s.pixel_2d(), s.next_1d(), s.next_2d());
            for v in [p, b, Vec2::splat(a)] {
                assert!(
                    v.cmpge(Vec2::ZERO).all() && v.cmplt(Vec2::ONE).all(),
                    "{what}: {v}"
                );
            }
            s.start_pixel_sample(far, i);
            assert_eq!(
                (s.pixel_2d(), s.next_1d(), s.next_2d()),
                (p, a, b),
                "{what}"
            );
            cells[(p.y * 4.0) as usize * 4 + (p.x * 4.0) as usize] += 1;
            x[(p.x * 16.0) as usize] += 1;
            one_d[(a * 16.0) as usize] += 1;
        }
        for (on, counts, name) in [
            (want.cells, cells, "4 × 4 cells"),
            (want.x, x, "pixel x strata"),
            (want.one_d, one_d, "1D strata"),
        ] {
            if on {
                assert_eq!(counts, [1; 16], "{what}: {name}");
            }
        }
    }
    let all = |cells, x, one_d| Strata { cells, x, one_d };
    check(
        Independent::new(16, 1).unwrap(),
        "independent",
        all(false, false, false),
    );
    check(
        Stratified::new(16, 1).unwrap(),
        "stratified",
        all(true, false, true),
    );
    check(
        UniformGrid::new(16, 1).unwrap(),
        "grid",
        all(true, false, true),
    );
    check(Sobol::new(16, 1).unwrap(), "sobol", all(true, true, true));
    check(
        Halton::new(16, 1).unwrap(),
        "halton",
        all(false, true, false),
    );
}

/// ZSobol' takes any spp and resolution whose Morton index with the
/// sample slot fits 64 bits, refuses the next bit, and gives values in
/// `[0, 1)` at the extreme pixels and indices it accepts.
#[test]
fn zsobol_takes_every_index_that_fits_64_bits() {
    // 2^32 slots and 2^16 x 2^16 pixels: exactly 64 bits.
    let side = 1u32 << 16;
    let mut s = ZSobol::new(u32::MAX, 3, UVec2::splat(side)).unwrap();
    assert_eq!(s.index_bits(), 64);
    assert!(matches!(
        ZSobol::new(u32::MAX, 3, UVec2::new(side + 1, 1)),
        Err(ZSobolError::IndexTooWide { bits: 66, .. })
    ));
    assert!(matches!(
        ZSobol::new(2, 3, UVec2::splat(u32::MAX)),
        Err(ZSobolError::IndexTooWide { bits: 65, .. })
    ));
    assert_eq!(
        ZSobol::new(0, 3, UVec2::ONE).unwrap_err(),
        ZSobolError::NoSamples
    );
    assert_eq!(
        ZSobol::new(1, 3, UVec2::new(0, 5)).unwrap_err(),
        ZSobolError::NoPixels
    );
    // Pixels inside and outside the resolution, the first and last index.
    for pixel in [UVec2::ZERO, UVec2::splat(side - 1), UVec2::splat(u32::MAX)] {
        for index in [0, u32::MAX - 1, u32::MAX] {
            s.start_pixel_sample(pixel, index);
            for v in [s.pixel_2d(), s.next_2d()] {
                assert!(v.cmpge(Vec2::ZERO).all() && v.cmplt(Vec2::ONE).all(), "{v}");
            }
            assert!((0.0..1.0).contains(&s.next_1d()));
        }
    }
}
