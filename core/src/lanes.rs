//! Lanes, a ground module beside `float`: the one place that names
//! `wide`'s 8-lane methods (`float` uses its 4-lane square root for
//! scalars), the lane abstraction that lets a formula be written once for
//! `f32` and for `f32x8` ([`Lanes`]), and vectors of lanes ([`V3`], as
//! Embree's `Vec3<vfloat<K>>`) with the ray and sphere bundles the
//! kernels take ([`RayLanes`], [`SphereLanes`]).
//!
//! Tracing's SIMD modules, `trace::packet` (sphere chunks, ray and hit
//! packets, the brute-force 8-wide kernels) and `trace::bvh` (node boxes,
//! slab tests, packet traversal), and sampling's piecewise-constant
//! tables' cell search (`mapping::piecewise`) take `f32x8` and `i32x8`
//! from here: neither imports the other. They build and read
//! them (`ZERO`, `splat`, `new`, `to_array`, `as_array`) and use the
//! arithmetic and bitwise operators; every comparison, select, bitmask
//! and bit cast goes through the wrappers below, because `wide` has
//! renamed exactly those between versions (`cmp_lt` became `simd_lt` in
//! 1.5, `blend` gave way to `select`), and here a rename is one edit. The
//! mask convention (all ones or all zeros per lane) is kept here too;
//! `clippy.toml` bans `wide`'s fused and approximate operations
//! everywhere.
//!
//! A kernel generic over [`Lanes`] performs the same IEEE operations in the
//! same order for one lane and for eight, so the scalar reference and its
//! SIMD twin return the same bits by construction. Only operations that are
//! exact per lane on every x86-64 level are exposed: `+ − × ÷ √`,
//! comparisons and selects. Not `recip`, `recip_sqrt`, `mul_add`, `min` or
//! `max`, whose results or NaN rules differ between CPUs or between `f32`
//! and `f32x8`.

use core::ops::{Add, Div, Mul, Neg, Sub};

use glam::Vec3;

pub(crate) use wide::{f32x8, i32x8};

/// `f32` or `f32x8`, with a boolean or lane mask.
pub(crate) trait Lanes:
    Copy
    + Add<Output = Self>
    + Sub<Output = Self>
    + Mul<Output = Self>
    + Div<Output = Self>
    + Neg<Output = Self>
{
    /// `bool` for one lane, an all-ones/all-zeros `f32x8` for eight.
    type Mask: Copy;
    fn splat(x: f32) -> Self;
    fn sqrt(self) -> Self;
    /// Comparisons are false when either side is NaN.
    fn lt(self, rhs: Self) -> Self::Mask;
    fn gt(self, rhs: Self) -> Self::Mask;
    fn ge(self, rhs: Self) -> Self::Mask;
    fn and(a: Self::Mask, b: Self::Mask) -> Self::Mask;
    fn or(a: Self::Mask, b: Self::Mask) -> Self::Mask;
    /// Whether any lane of the mask is set.
    fn any(mask: Self::Mask) -> bool;
    /// `if mask { a } else { b }` per lane.
    fn select(mask: Self::Mask, a: Self, b: Self) -> Self;
}

impl Lanes for f32 {
    type Mask = bool;
    #[inline(always)]
    fn splat(x: f32) -> Self {
        x
    }
    #[inline(always)]
    fn sqrt(self) -> Self {
        crate::float::sqrtf(self)
    }
    #[inline(always)]
    fn lt(self, rhs: Self) -> bool {
        self < rhs
    }
    #[inline(always)]
    fn gt(self, rhs: Self) -> bool {
        self > rhs
    }
    #[inline(always)]
    fn ge(self, rhs: Self) -> bool {
        self >= rhs
    }
    #[inline(always)]
    fn and(a: bool, b: bool) -> bool {
        a & b
    }
    #[inline(always)]
    fn or(a: bool, b: bool) -> bool {
        a | b
    }
    #[inline(always)]
    fn any(mask: bool) -> bool {
        mask
    }
    #[inline(always)]
    fn select(mask: bool, a: Self, b: Self) -> Self {
        if mask { a } else { b }
    }
}

impl Lanes for f32x8 {
    type Mask = f32x8;
    #[inline(always)]
    fn splat(x: f32) -> Self {
        f32x8::splat(x)
    }
    #[inline(always)]
    fn sqrt(self) -> Self {
        f32x8::sqrt(self)
    }
    #[inline(always)]
    fn lt(self, rhs: Self) -> f32x8 {
        lanes_lt(self, rhs)
    }
    #[inline(always)]
    fn gt(self, rhs: Self) -> f32x8 {
        lanes_gt(self, rhs)
    }
    #[inline(always)]
    fn ge(self, rhs: Self) -> f32x8 {
        lanes_ge(self, rhs)
    }
    #[inline(always)]
    fn and(a: f32x8, b: f32x8) -> f32x8 {
        a & b
    }
    #[inline(always)]
    fn or(a: f32x8, b: f32x8) -> f32x8 {
        a | b
    }
    #[inline(always)]
    fn any(mask: f32x8) -> bool {
        lanes_bitmask(mask) != 0
    }
    #[inline(always)]
    fn select(mask: f32x8, a: Self, b: Self) -> Self {
        lanes_select(mask, a, b)
    }
}

/// Three lanes of `L` as a vector: `x`, `y` and `z` of one point or
/// direction (`L = f32`) or of eight (`L = f32x8`). Its operations are
/// written once, in one order, so both forms give the same bits.
#[derive(Clone, Copy, Debug)]
pub(crate) struct V3<L> {
    pub(crate) x: L,
    pub(crate) y: L,
    pub(crate) z: L,
}

impl<L: Lanes> V3<L> {
    /// The vector of the three lanes.
    #[inline(always)]
    pub(crate) fn new(x: L, y: L, z: L) -> Self {
        Self { x, y, z }
    }

    /// `v` in every lane.
    #[inline(always)]
    pub(crate) fn splat(v: Vec3) -> Self {
        Self::new(L::splat(v.x), L::splat(v.y), L::splat(v.z))
    }

    /// `x·x' + y·y' + z·z'`, summed left to right.
    #[inline(always)]
    pub(crate) fn dot(self, o: Self) -> L {
        self.x * o.x + self.y * o.y + self.z * o.z
    }
}

impl<L: Lanes> Sub for V3<L> {
    type Output = Self;
    #[inline(always)]
    fn sub(self, o: Self) -> Self {
        Self::new(self.x - o.x, self.y - o.y, self.z - o.z)
    }
}

impl<L: Lanes> Mul<L> for V3<L> {
    type Output = Self;
    /// Each component times `s` (`s · x` and `x · s` are the same bits:
    /// IEEE multiplication commutes).
    #[inline(always)]
    fn mul(self, s: L) -> Self {
        Self::new(self.x * s, self.y * s, self.z * s)
    }
}

/// A ray in lanes: origin, unit direction, and the open interval
/// `(t_min, t_max)` of distances it takes hits in.
#[derive(Clone, Copy, Debug)]
pub(crate) struct RayLanes<L> {
    pub(crate) origin: V3<L>,
    pub(crate) dir: V3<L>,
    pub(crate) t_min: L,
    pub(crate) t_max: L,
}

/// A sphere in lanes: centre and radius.
#[derive(Clone, Copy, Debug)]
pub(crate) struct SphereLanes<L> {
    pub(crate) center: V3<L>,
    pub(crate) radius: L,
}

/// `a < b` per lane: a mask, unset where either side is NaN.
#[inline(always)]
pub(crate) fn lanes_lt(a: f32x8, b: f32x8) -> f32x8 {
    a.simd_lt(b)
}

/// `a <= b` per lane: a mask, unset where either side is NaN.
#[inline(always)]
pub(crate) fn lanes_le(a: f32x8, b: f32x8) -> f32x8 {
    a.simd_le(b)
}

/// `a > b` per lane: a mask, unset where either side is NaN.
#[inline(always)]
pub(crate) fn lanes_gt(a: f32x8, b: f32x8) -> f32x8 {
    a.simd_gt(b)
}

/// `a >= b` per lane: a mask, unset where either side is NaN.
#[inline(always)]
pub(crate) fn lanes_ge(a: f32x8, b: f32x8) -> f32x8 {
    a.simd_ge(b)
}

/// `a == b` per lane: a mask, unset where either side is NaN (`-0.0`
/// equals `0.0`).
#[inline(always)]
pub(crate) fn lanes_eq(a: f32x8, b: f32x8) -> f32x8 {
    a.simd_eq(b)
}

/// `a < b` per integer lane: an integer-lane mask.
#[inline(always)]
pub(crate) fn lanes_lt_i32(a: i32x8, b: i32x8) -> i32x8 {
    a.simd_lt(b)
}

/// `a == b` per integer lane: an integer-lane mask.
#[inline(always)]
pub(crate) fn lanes_eq_i32(a: i32x8, b: i32x8) -> i32x8 {
    a.simd_eq(b)
}

/// `if mask { a } else { b }` per lane of an `f32x8`.
#[inline(always)]
pub(crate) fn lanes_select(mask: f32x8, a: f32x8, b: f32x8) -> f32x8 {
    wide::Select::select(mask, a, b)
}

/// `if mask { a } else { b }` per lane, for integer lanes under a float
/// mask.
#[inline(always)]
pub(crate) fn lanes_select_i32(mask: f32x8, a: i32x8, b: i32x8) -> i32x8 {
    let m: i32x8 = wide::bytemuck::cast(mask);
    wide::Select::select(m, a, b)
}

/// Bit `k` set when lane `k` of the mask is set.
#[inline(always)]
pub(crate) fn lanes_bitmask(mask: f32x8) -> u32 {
    mask.to_bitmask()
}

/// A mask from eight booleans.
#[inline(always)]
pub(crate) fn mask_from_bools(b: [bool; 8]) -> f32x8 {
    f32x8::new(b.map(|x| if x { f32::from_bits(u32::MAX) } else { 0.0 }))
}

/// A mask with lane `k` set where bit `k` of `bits` is.
#[inline(always)]
pub(crate) fn mask_from_bits(bits: u8) -> f32x8 {
    mask_from_bools(core::array::from_fn(|k| bits >> k & 1 == 1))
}

/// A float mask from an integer-lane mask (the same bits).
#[inline(always)]
pub(crate) fn mask_from_i32(mask: i32x8) -> f32x8 {
    wide::bytemuck::cast(mask)
}

/// The lanes whose sign bit is set (`-0.0` and negative NaNs included).
#[inline(always)]
pub(crate) fn mask_sign(v: f32x8) -> f32x8 {
    let bits: i32x8 = wide::bytemuck::cast(v);
    mask_from_i32(lanes_lt_i32(bits, i32x8::splat(0)))
}

/// `|v|` per lane by clearing the sign bit: exact on every level.
#[inline(always)]
pub(crate) fn lanes_abs(v: f32x8) -> f32x8 {
    let bits: i32x8 = wide::bytemuck::cast(v);
    wide::bytemuck::cast(bits & i32x8::splat(i32::MAX))
}
