//! Owen-scrambled Sobol' samples by hashing (Burley 2020, *Practical
//! Hash-based Owen Scrambling*, JCGT 9(4)), padded in pairs of dimensions
//! (as pbrt's `PaddedSobolSampler`).
//!
//! Sample dimension `d` of a pixel belongs to pair `g = d / 2` and uses
//! Sobol' dimension `d % 2`. Within a pair the sample index is shuffled by
//! a nested uniform scramble keyed by `(seed, pixel, g)`, and every output
//! value is Owen-scrambled by a key of `(seed, pixel, d)`. So:
//!
//! - the first `2^k` samples of a pixel, in every pair, form a
//!   `(0, k, 2)`-net: every elementary interval of area `2^-k` holds
//!   exactly one point (the pixel position and every 2D draw are pairs);
//! - every single dimension is a `(0, 1)`-sequence: `2^k` samples fill
//!   `2^k` equal strata exactly once;
//! - pairs are decorrelated from each other and pixels from each other.
//!
//! Only Sobol' dimensions 0 and 1 are drawn; the table keeps 2 and 3 for a
//! 4D padding.
//!
//! Direction numbers: dimension 0 is van der Corput; 1–3 come from the
//! rows for dimensions 2–4 of Joe and Kuo's `new-joe-kuo-6.21201` (2008),
//! whose licence is in `core/data/LICENSE-JOE-KUO.txt`.

/// `(s, a, m₁..m_s)` of Sobol' dimensions 1–3 (Joe and Kuo, rows 2–4).
const JOE_KUO: [(u32, u32, [u32; 3]); 3] =
    [(1, 0, [1, 0, 0]), (2, 1, [1, 3, 0]), (3, 1, [1, 3, 1])];

/// The 32 direction vectors of Sobol' dimension `dim` (0–3), MSB-aligned:
/// bit `j` of an index contributes `v[j]`.
const fn directions(dim: usize) -> [u32; 32] {
    let mut v = [0u32; 32];
    let mut j = 0;
    if dim == 0 {
        while j < 32 {
            v[j] = 1 << (31 - j);
            j += 1;
        }
        return v;
    }
    let (s, a, m) = JOE_KUO[dim - 1];
    let s = s as usize;
    while j < 32 {
        if j < s {
            v[j] = m[j] << (31 - j);
        } else {
            let mut x = v[j - s] ^ (v[j - s] >> s);
            let mut k = 1;
            while k < s {
                if (a >> (s - 1 - k)) & 1 == 1 {
                    x ^= v[j - k];
                }
                k += 1;
            }
            v[j] = x;
        }
        j += 1;
    }
    v
}

const DIRECTIONS: [[u32; 32]; 4] = [directions(0), directions(1), directions(2), directions(3)];

/// The Sobol' matrices as byte tables: `TABLES[dim][k][b]` is the XOR of
/// the direction vectors selected by byte `b` at byte position `k` of the
/// index. Four lookups replace a 32-step bit loop (16 KiB, built at
/// compile time).
static TABLES: [[[u32; 256]; 4]; 4] = byte_tables();

const fn byte_tables() -> [[[u32; 256]; 4]; 4] {
    let mut t = [[[0u32; 256]; 4]; 4];
    let mut dim = 0;
    while dim < 4 {
        let mut k = 0;
        while k < 4 {
            let mut b = 0;
            while b < 256 {
                let mut x = 0u32;
                let mut bit = 0;
                while bit < 8 {
                    if (b >> bit) & 1 == 1 {
                        x ^= DIRECTIONS[dim][8 * k + bit];
                    }
                    bit += 1;
                }
                t[dim][k][b] = x;
                b += 1;
            }
            k += 1;
        }
        dim += 1;
    }
    t
}

/// Sobol' point `index` in dimension `dim` (0–3) as a 32-bit fraction.
#[inline]
pub(crate) fn sobol(index: u32, dim: usize) -> u32 {
    let t = &TABLES[dim & 3];
    let b = index.to_le_bytes();
    t[0][b[0] as usize] ^ t[1][b[1] as usize] ^ t[2][b[2] as usize] ^ t[3][b[3] as usize]
}

/// The reference bit loop the tables replace (for the tests).
#[cfg(test)]
fn sobol_bits(mut index: u32, dim: usize) -> u32 {
    let v = &DIRECTIONS[dim & 3];
    let (mut x, mut j) = (0, 0);
    while index != 0 {
        if index & 1 == 1 {
            x ^= v[j];
        }
        index >>= 1;
        j += 1;
    }
    x
}

/// The Laine–Karras permutation as Burley improves it: output bit `j`
/// depends only on input bits `0..=j` and the seed.
#[inline]
fn laine_karras(mut x: u32, seed: u32) -> u32 {
    x = x.wrapping_add(seed);
    x ^= x.wrapping_mul(0x6c50_b47c);
    x ^= x.wrapping_mul(0xb82f_1e52);
    x ^= x.wrapping_mul(0xc7af_e638);
    x ^= x.wrapping_mul(0x8d22_f6e6);
    x
}

/// A nested uniform (Owen) scramble of `x` keyed by `seed`: bit `j` is
/// flipped by a hash of the bits above it. As a shuffle of indices it
/// keeps every aligned block of `2^k` indices together.
#[inline]
pub(crate) fn nested_uniform_scramble(x: u32, seed: u32) -> u32 {
    laine_karras(x.reverse_bits(), seed).reverse_bits()
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn first_points_are_the_textbook_ones() {
        // Dimension 0: 0, 1/2, 1/4, 3/4; dimension 1: 0, 1/2, 3/4, 1/4.
        let f = |i, d| sobol(i, d) as f64 / 4_294_967_296.0;
        assert_eq!([f(0, 0), f(1, 0), f(2, 0), f(3, 0)], [0.0, 0.5, 0.25, 0.75]);
        assert_eq!([f(0, 1), f(1, 1), f(2, 1), f(3, 1)], [0.0, 0.5, 0.75, 0.25]);
    }

    #[test]
    fn tables_equal_the_bit_loop() {
        let mut x = 0x1234_5678u32;
        for _ in 0..100_000 {
            x = x.wrapping_mul(747_796_405).wrapping_add(2_891_336_453);
            for d in 0..4 {
                assert_eq!(sobol(x, d), sobol_bits(x, d), "index {x} dim {d}");
            }
        }
        for i in [0, 1, u32::MAX, 1 << 31] {
            assert_eq!(sobol(i, 0), i.reverse_bits()); // van der Corput
        }
    }

    #[test]
    fn scramble_is_a_bijection_that_keeps_blocks() {
        for seed in [0u32, 1, 0xdead_beef] {
            let mut seen = [false; 256];
            for i in 0..256u32 {
                let j = nested_uniform_scramble(i, seed);
                // The first 2^8 indices stay in one aligned block of 2^8.
                assert_eq!(j >> 8, nested_uniform_scramble(0, seed) >> 8);
                assert!(!seen[(j & 255) as usize]);
                seen[(j & 255) as usize] = true;
            }
        }
    }
}
