//! A tabulated 2-D distribution: a piecewise-constant density on the unit
//! square with the same sample / pdf / invert triad as every mapping
//! (pbrt-v4's `PiecewiseConstant2D`, at a fixed size so it needs no
//! allocation). The pixel filters without a closed-form sampler draw from
//! one.

use glam::Vec2;

use crate::rng::ONE_MINUS_EPSILON;

/// Cells per axis of a [`PiecewiseConstant2D`].
pub const PIECEWISE_2D_SIZE: usize = 32;
const N: usize = PIECEWISE_2D_SIZE;
const N1: usize = PIECEWISE_2D_SIZE + 1;

/// A piecewise-constant density on `[0, 1)²` over `PIECEWISE_2D_SIZE²`
/// cells, with sample, pdf and invert like every other mapping. Fixed
/// size: no allocation.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct PiecewiseConstant2D {
    /// Cell values, `[row (y)][column (x)]`.
    func: [[f32; N]; N],
    /// Per row, the CDF over its columns (`N + 1` entries, 0 to 1).
    row_cdf: [[f32; N1]; N],
    /// The CDF over rows.
    marginal: [f32; N1],
    /// Mean cell value: the density of a cell is `func / mean`.
    mean: f32,
}

/// The CDF of `values` (non-negative), normalised to end at exactly 1, and
/// their sum; `None` if the sum is not positive and finite.
fn cdf(values: &[f32; N]) -> Option<([f32; N1], f32)> {
    let mut c = [0.0f32; N1];
    let mut acc = 0.0f64;
    for (k, &v) in values.iter().enumerate() {
        acc += v as f64;
        c[k + 1] = acc as f32;
    }
    if !(acc > 0.0 && acc.is_finite()) {
        return None;
    }
    for x in &mut c[1..] {
        *x = (*x as f64 / acc) as f32;
    }
    c[N] = 1.0;
    Some((c, acc as f32))
}

/// The index `k` with `c[k] ≤ u < c[k + 1]` (skipping empty intervals).
/// `c` is non-decreasing, so the entries `≤ u` are a prefix and their
/// count is the binary search's answer: counted in vector compares it
/// costs no chain of dependent loads (a binary search's 6 took 15 % of a
/// Gaussian-filtered render).
#[inline]
fn find(c: &[f32; N1], u: f32) -> usize {
    use crate::lanes::{f32x8, lanes_bitmask, lanes_le};
    const _: () = assert!(N.is_multiple_of(8));
    let u8 = f32x8::splat(u);
    let below: u32 = c[1..]
        .chunks_exact(8)
        .map(|x| {
            let x: [f32; 8] = x.try_into().unwrap_or([f32::NAN; 8]);
            lanes_bitmask(lanes_le(f32x8::from(x), u8)).count_ones()
        })
        .sum();
    (below as usize).min(N - 1)
}

impl PiecewiseConstant2D {
    /// The distribution proportional to `values` (`[row][column]`, every
    /// value `≥ 0` and finite); `None` if they are all zero, or any is
    /// negative or not finite.
    ///
    /// ```
    /// use glam::Vec2;
    /// use strata::mapping::{PiecewiseConstant2D, PIECEWISE_2D_SIZE};
    /// let mut v = [[1.0f32; PIECEWISE_2D_SIZE]; PIECEWISE_2D_SIZE];
    /// v[0][0] = 0.0;
    /// let d = PiecewiseConstant2D::new(&v).unwrap();
    /// let (p, pdf) = d.sample(Vec2::new(0.3, 0.7));
    /// assert_eq!(pdf, d.pdf(p));
    /// assert!((d.invert(p) - Vec2::new(0.3, 0.7)).abs().max_element() < 1e-5);
    /// assert_eq!(d.pdf(Vec2::new(0.01, 0.01)), 0.0);
    /// ```
    #[inline]
    #[must_use]
    pub fn new(values: &[[f32; N]; N]) -> Option<Self> {
        if values
            .iter()
            .flatten()
            .any(|&v| !(v >= 0.0 && v.is_finite()))
        {
            return None;
        }
        let mut row_cdf = [[0.0f32; N1]; N];
        let mut sums = [0.0f32; N];
        for (r, row) in values.iter().enumerate() {
            if let Some((c, s)) = cdf(row) {
                row_cdf[r] = c;
                sums[r] = s;
            }
        }
        let (marginal, total) = cdf(&sums)?;
        Some(Self {
            func: *values,
            row_cdf,
            marginal,
            mean: total / (N * N) as f32,
        })
    }

    /// A point of `[0, 1)²` drawn with this density, and the density there.
    #[inline]
    #[must_use]
    pub fn sample(&self, u: Vec2) -> (Vec2, f32) {
        let r = find(&self.marginal, u.y);
        let (m0, m1) = (self.marginal[r], self.marginal[r + 1]);
        let dv = ((u.y - m0) / (m1 - m0)).clamp(0.0, 1.0);
        let c = find(&self.row_cdf[r], u.x);
        let (c0, c1) = (self.row_cdf[r][c], self.row_cdf[r][c + 1]);
        let du = ((u.x - c0) / (c1 - c0)).clamp(0.0, 1.0);
        let p = Vec2::new(
            ((c as f32 + du) / N as f32).min(ONE_MINUS_EPSILON),
            ((r as f32 + dv) / N as f32).min(ONE_MINUS_EPSILON),
        );
        (p, self.func[r][c] / self.mean)
    }

    /// The density at `p` (0 outside `[0, 1)²`).
    #[inline]
    #[must_use]
    pub fn pdf(&self, p: Vec2) -> f32 {
        if !(p.x >= 0.0 && p.x < 1.0 && p.y >= 0.0 && p.y < 1.0) {
            return 0.0;
        }
        let (c, r) = cell(p);
        self.func[r][c] / self.mean
    }

    /// The `u` that [`PiecewiseConstant2D::sample`] maps to `p` (clamped
    /// into `[0, 1)²`).
    #[inline]
    #[must_use]
    pub fn invert(&self, p: Vec2) -> Vec2 {
        let p = p.clamp(Vec2::ZERO, Vec2::splat(ONE_MINUS_EPSILON));
        let (c, r) = cell(p);
        let fy = p.y * N as f32 - r as f32;
        let fx = p.x * N as f32 - c as f32;
        let (m0, m1) = (self.marginal[r], self.marginal[r + 1]);
        let (c0, c1) = (self.row_cdf[r][c], self.row_cdf[r][c + 1]);
        Vec2::new(c0 + fx * (c1 - c0), m0 + fy * (m1 - m0))
    }
}

fn cell(p: Vec2) -> (usize, usize) {
    let k = |v: f32| ((v * N as f32) as usize).min(N - 1);
    (k(p.x), k(p.y))
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn find_counts_as_a_binary_search_finds() {
        let search = |c: &[f32; N1], u: f32| c[1..].partition_point(|&x| x <= u).min(N - 1);
        // A CDF with empty intervals (repeated values), one that is all 0
        // but its end, and an even one.
        let mut steps = [0.0f32; N1];
        for (k, c) in steps.iter_mut().enumerate() {
            *c = ((k / 3) as f32 * 3.0 / N as f32).min(1.0);
        }
        steps[N] = 1.0;
        let mut zero = [0.0f32; N1];
        zero[N] = 1.0;
        let mut even = [0.0f32; N1];
        for (k, c) in even.iter_mut().enumerate() {
            *c = k as f32 / N as f32;
        }
        for c in [steps, zero, even] {
            let edges = [
                -1.0,
                -0.0,
                0.0,
                0.999_999_94,
                1.0,
                2.0,
                f32::NAN,
                f32::INFINITY,
            ];
            let us = c
                .iter()
                .copied()
                .chain(edges)
                .chain((0..=1000).map(|i| i as f32 / 1000.0))
                .chain(
                    c.iter()
                        .map(|&x| f32::from_bits(x.to_bits().wrapping_add(1))),
                );
            for u in us {
                assert_eq!(find(&c, u), search(&c, u), "{u}");
            }
        }
    }
}
