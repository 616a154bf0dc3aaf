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
//! Shading is written over [`Lanes`] too: `trig` and `pow`, the
//! mappings, the basis, every material, the camera ray, the surface
//! record and next-event estimation (`render::lanes_check` tests each
//! lane of eight against the one-lane form the scalar integrator runs).
//!
//! A kernel generic over [`Lanes`] performs the same IEEE operations in the
//! same order for one lane and for eight, so the scalar reference and its
//! SIMD twin return the same bits by construction. A branch where lanes
//! could part is a select; a rare special case may sit behind a test of
//! every lane (`if L::any(mask)`), which one lane takes as a plain branch. Only operations that are
//! exact per lane on every x86-64 level are exposed: `+ − × ÷ √`,
//! comparisons and selects, bit casts, integer `+ − & | ^ << >>`, and the
//! conversions between integers and floats (truncating, saturating with
//! NaN to 0 like Rust's `as` in both forms). Not `recip`, `recip_sqrt`,
//! `mul_add`, `min` or `max`, whose results or NaN rules differ between
//! CPUs or between `f32` and `f32x8`.

use core::ops::{Add, BitAnd, BitOr, BitXor, Div, Mul, Neg, Shl, Shr, Sub};

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
    /// `i32` lanes of the same width: `i32` or `i32x8`. Their `+` and `−`
    /// must not overflow (a debug build checks the scalar form); shifts
    /// are by less than 32, `>>` is arithmetic.
    type Int: Copy
        + Add<Output = Self::Int>
        + Sub<Output = Self::Int>
        + BitAnd<Output = Self::Int>
        + BitOr<Output = Self::Int>
        + BitXor<Output = Self::Int>
        + Shl<u32, Output = Self::Int>
        + Shr<u32, Output = Self::Int>;
    fn splat(x: f32) -> Self;
    fn sqrt(self) -> Self;
    /// Comparisons are false when either side is NaN.
    fn lt(self, rhs: Self) -> Self::Mask;
    fn le(self, rhs: Self) -> Self::Mask;
    fn gt(self, rhs: Self) -> Self::Mask;
    fn ge(self, rhs: Self) -> Self::Mask;
    /// `-0.0` equals `0.0`; NaN equals nothing.
    fn eq(self, rhs: Self) -> Self::Mask;
    fn and(a: Self::Mask, b: Self::Mask) -> Self::Mask;
    fn or(a: Self::Mask, b: Self::Mask) -> Self::Mask;
    /// The lanes not set in `mask`.
    fn not(mask: Self::Mask) -> Self::Mask;
    /// Whether any lane of the mask is set.
    fn any(mask: Self::Mask) -> bool;
    /// `if mask { a } else { b }` per lane.
    fn select(mask: Self::Mask, a: Self, b: Self) -> Self;
    /// `x` in every integer lane.
    fn splat_int(x: i32) -> Self::Int;
    /// The IEEE bits of each lane.
    fn to_bits(self) -> Self::Int;
    /// The lanes with these IEEE bits.
    fn from_bits(bits: Self::Int) -> Self;
    /// Each lane truncated towards zero to an integer, saturating, NaN to
    /// 0 (Rust's `as i32`).
    fn to_int(self) -> Self::Int;
    /// Each integer lane rounded to the nearest float (Rust's `as f32`).
    fn from_int(i: Self::Int) -> Self;
    /// `a == b` per integer lane.
    fn int_eq(a: Self::Int, b: Self::Int) -> Self::Mask;
    /// `a < b` per integer lane.
    fn int_lt(a: Self::Int, b: Self::Int) -> Self::Mask;
    /// `if mask { a } else { b }` per integer lane.
    fn select_int(mask: Self::Mask, a: Self::Int, b: Self::Int) -> Self::Int;

    /// Lanes: 1 or 8.
    const WIDTH: usize;
    /// Lane `k`'s value.
    fn lane(self, k: usize) -> f32;
    /// Lanes from a value per lane: what a lane form uses for what stays
    /// per lane (a texel fetch, a sphere's parameters).
    fn from_fn(f: impl FnMut(usize) -> f32) -> Self;
    /// `b` in every lane of a mask.
    fn mask_splat(b: bool) -> Self::Mask;

    /// `|x|`, by clearing the sign bit (so `|−0| = 0` and NaNs lose their
    /// sign).
    #[inline(always)]
    fn abs(self) -> Self {
        Self::from_bits(self.to_bits() & Self::splat_int(i32::MAX))
    }

    /// The lanes whose sign bit is set (`−0.0` and negative NaNs included).
    #[inline(always)]
    fn sign_bit(self) -> Self::Mask {
        Self::int_lt(self.to_bits(), Self::splat_int(0))
    }

    /// `|x|` with the sign bit of `sign`.
    #[inline(always)]
    fn copysign(self, sign: Self) -> Self {
        let magnitude = self.to_bits() & Self::splat_int(i32::MAX);
        Self::from_bits(magnitude | (sign.to_bits() & Self::splat_int(i32::MIN)))
    }

    /// `x` clamped to `[lo, hi]`; NaN stays NaN (unlike `max`/`min`,
    /// whose NaN rules differ between `f32` and SIMD instructions).
    #[inline(always)]
    fn clamp_to(self, lo: f32, hi: f32) -> Self {
        let x = Self::select(self.lt(Self::splat(lo)), Self::splat(lo), self);
        Self::select(x.gt(Self::splat(hi)), Self::splat(hi), x)
    }
}

impl Lanes for f32 {
    type Mask = bool;
    type Int = i32;
    const WIDTH: usize = 1;
    #[inline(always)]
    fn lane(self, _: usize) -> f32 {
        self
    }
    #[inline(always)]
    fn from_fn(mut f: impl FnMut(usize) -> f32) -> Self {
        f(0)
    }
    #[inline(always)]
    fn mask_splat(b: bool) -> bool {
        b
    }
    // The trait's bit forms, by the instructions that do them on a float
    // register (the same bits: each clears, tests or copies the sign bit).
    #[inline(always)]
    fn abs(self) -> f32 {
        f32::abs(self)
    }
    #[inline(always)]
    fn sign_bit(self) -> bool {
        self.is_sign_negative()
    }
    #[inline(always)]
    fn copysign(self, sign: f32) -> f32 {
        f32::copysign(self, sign)
    }
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
    fn le(self, rhs: Self) -> bool {
        self <= rhs
    }
    #[inline(always)]
    fn eq(self, rhs: Self) -> bool {
        self == rhs
    }
    #[inline(always)]
    fn not(mask: bool) -> bool {
        !mask
    }
    #[inline(always)]
    fn splat_int(x: i32) -> i32 {
        x
    }
    #[inline(always)]
    fn to_bits(self) -> i32 {
        f32::to_bits(self) as i32
    }
    #[inline(always)]
    fn from_bits(bits: i32) -> Self {
        f32::from_bits(bits as u32)
    }
    #[inline(always)]
    fn to_int(self) -> i32 {
        self as i32
    }
    #[inline(always)]
    fn from_int(i: i32) -> Self {
        i as f32
    }
    #[inline(always)]
    fn int_eq(a: i32, b: i32) -> bool {
        a == b
    }
    #[inline(always)]
    fn int_lt(a: i32, b: i32) -> bool {
        a < b
    }
    #[inline(always)]
    fn select_int(mask: bool, a: i32, b: i32) -> i32 {
        if mask { a } else { b }
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
    type Int = i32x8;
    const WIDTH: usize = 8;
    #[inline(always)]
    fn lane(self, k: usize) -> f32 {
        self.as_array()[k]
    }
    #[inline(always)]
    fn from_fn(f: impl FnMut(usize) -> f32) -> Self {
        f32x8::new(core::array::from_fn(f))
    }
    #[inline(always)]
    fn mask_splat(b: bool) -> f32x8 {
        mask_from_bools([b; 8])
    }
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
    fn le(self, rhs: Self) -> f32x8 {
        lanes_le(self, rhs)
    }
    #[inline(always)]
    fn eq(self, rhs: Self) -> f32x8 {
        lanes_eq(self, rhs)
    }
    #[inline(always)]
    fn not(mask: f32x8) -> f32x8 {
        !mask
    }
    #[inline(always)]
    fn splat_int(x: i32) -> i32x8 {
        i32x8::splat(x)
    }
    #[inline(always)]
    fn to_bits(self) -> i32x8 {
        wide::bytemuck::cast(self)
    }
    #[inline(always)]
    fn from_bits(bits: i32x8) -> Self {
        wide::bytemuck::cast(bits)
    }
    #[inline(always)]
    fn to_int(self) -> i32x8 {
        // wide's saturating form: NaN to 0, like `as` (not `fast_trunc_int`).
        self.trunc_int()
    }
    #[inline(always)]
    fn from_int(i: i32x8) -> Self {
        f32x8::from_i32x8(i)
    }
    #[inline(always)]
    fn int_eq(a: i32x8, b: i32x8) -> f32x8 {
        mask_from_i32(lanes_eq_i32(a, b))
    }
    #[inline(always)]
    fn int_lt(a: i32x8, b: i32x8) -> f32x8 {
        mask_from_i32(lanes_lt_i32(a, b))
    }
    #[inline(always)]
    fn select_int(mask: f32x8, a: i32x8, b: i32x8) -> i32x8 {
        lanes_select_i32(mask, a, b)
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

impl<L: Lanes> V3<L> {
    /// Lane `k` as a vector.
    #[inline(always)]
    pub(crate) fn lane(self, k: usize) -> Vec3 {
        Vec3::new(self.x.lane(k), self.y.lane(k), self.z.lane(k))
    }

    /// A vector per lane: `f` runs once for each lane, in lane order.
    #[inline(always)]
    pub(crate) fn from_fn(mut f: impl FnMut(usize) -> Vec3) -> Self {
        if L::WIDTH == 1 {
            return Self::splat(f(0));
        }
        debug_assert!(L::WIDTH <= 8);
        let v: [Vec3; 8] = core::array::from_fn(|k| if k < L::WIDTH { f(k) } else { Vec3::ZERO });
        Self::new(
            L::from_fn(|k| v[k].x),
            L::from_fn(|k| v[k].y),
            L::from_fn(|k| v[k].z),
        )
    }

    /// `v / |v|` for any finite non-zero `v`, however tiny or huge:
    /// divided by its largest magnitude first, so squaring cannot
    /// overflow or underflow (NaN where `v` is zero or not finite).
    #[inline(always)]
    pub(crate) fn normalize_scaled(self) -> Self {
        let (x, y, z) = (self.x.abs(), self.y.abs(), self.z.abs());
        let m = max_lanes(x, max_lanes(y, z));
        let s = self.div(m);
        s.div(s.dot(s).sqrt())
    }

    /// `if mask { a } else { b }` per lane.
    #[inline(always)]
    pub(crate) fn select(mask: L::Mask, a: Self, b: Self) -> Self {
        Self::new(
            L::select(mask, a.x, b.x),
            L::select(mask, a.y, b.y),
            L::select(mask, a.z, b.z),
        )
    }

    /// Component by component.
    #[inline(always)]
    pub(crate) fn mul_v(self, o: Self) -> Self {
        Self::new(self.x * o.x, self.y * o.y, self.z * o.z)
    }

    /// Each component divided by `s` (not times `1/s`: glam's `v / s`).
    #[inline(always)]
    pub(crate) fn div(self, s: L) -> Self {
        Self::new(self.x / s, self.y / s, self.z / s)
    }

    /// The lanes where every component is finite.
    #[inline(always)]
    pub(crate) fn is_finite(self) -> L::Mask {
        let inf = L::splat(f32::INFINITY);
        L::and(
            L::and(self.x.abs().lt(inf), self.y.abs().lt(inf)),
            self.z.abs().lt(inf),
        )
    }

    /// The lanes where every component is zero (either sign).
    #[inline(always)]
    pub(crate) fn is_zero(self) -> L::Mask {
        let z = L::splat(0.0);
        L::and(L::and(self.x.eq(z), self.y.eq(z)), self.z.eq(z))
    }

    /// `|v|`, with the bits of glam's `Vec3::length`.
    #[inline(always)]
    pub(crate) fn length(self) -> L {
        self.dot(self).sqrt()
    }

    /// `v · (1 / |v|)`, with the bits of glam's `Vec3::normalize`
    /// (non-finite for a zero or non-finite `v`).
    #[inline(always)]
    pub(crate) fn normalize(self) -> Self {
        self * (L::splat(1.0) / self.length())
    }

    /// [`V3::normalize`], or zero where `1 / |v|` is not finite and
    /// positive, with the bits of glam's `Vec3::normalize_or_zero`.
    #[inline(always)]
    pub(crate) fn normalize_or_zero(self) -> Self {
        let rcp = L::splat(1.0) / self.length();
        let ok = L::and(rcp.gt(L::splat(0.0)), rcp.lt(L::splat(f32::INFINITY)));
        Self::select(ok, self * rcp, Self::splat(Vec3::ZERO))
    }
}

impl<L: Lanes> Add for V3<L> {
    type Output = Self;
    #[inline(always)]
    fn add(self, o: Self) -> Self {
        Self::new(self.x + o.x, self.y + o.y, self.z + o.z)
    }
}

impl<L: Lanes> Neg for V3<L> {
    type Output = Self;
    #[inline(always)]
    fn neg(self) -> Self {
        Self::new(-self.x, -self.y, -self.z)
    }
}

impl From<Vec3> for V3<f32> {
    #[inline(always)]
    fn from(v: Vec3) -> Self {
        Self::new(v.x, v.y, v.z)
    }
}

impl From<V3<f32>> for Vec3 {
    #[inline(always)]
    fn from(v: V3<f32>) -> Self {
        Vec3::new(v.x, v.y, v.z)
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

/// The larger of `a` and `b`; NaN only if both are (as `f32::max`).
#[inline(always)]
pub(crate) fn max_lanes<L: Lanes>(a: L, b: L) -> L {
    L::select(L::or(a.lt(b), L::not(a.eq(a))), b, a)
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

impl<L: Lanes> RayLanes<L> {
    /// The point at parameter `t`: `origin + t · dir` (no fused
    /// multiply-add).
    #[inline(always)]
    pub(crate) fn at(&self, t: L) -> V3<L> {
        self.origin + self.dir * t
    }
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

/// The lanes set in `bits` (bit `k`: lane `k`), in lane order: one step
/// per set bit, not per lane.
#[inline(always)]
pub(crate) fn set_lanes(bits: u32) -> SetLanes {
    SetLanes(bits)
}

/// The iterator of [`set_lanes`].
pub(crate) struct SetLanes(u32);

impl Iterator for SetLanes {
    type Item = usize;
    #[inline(always)]
    fn next(&mut self) -> Option<usize> {
        if self.0 == 0 {
            return None;
        }
        let k = self.0.trailing_zeros() as usize;
        self.0 &= self.0 - 1;
        Some(k)
    }
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

/// Test inputs of every class a lane function must treat alike in both
/// forms, and the check that it does.
#[cfg(test)]
pub(crate) mod classes {
    use std::vec::Vec;

    use super::f32x8;

    /// Zeros, subnormals, the smallest normal, ±1 and their neighbours,
    /// halves, NaNs (both signs, a payload), infinities, huge values,
    /// and a spread of ordinary ones of both signs.
    pub(crate) fn inputs() -> Vec<f32> {
        let mut v = std::vec![
            0.0,
            -0.0,
            f32::from_bits(1),
            -f32::from_bits(1),
            f32::from_bits(0x007f_ffff),
            -f32::from_bits(0x0040_0000),
            f32::MIN_POSITIVE,
            1.0,
            -1.0,
            f32::from_bits(1.0f32.to_bits() + 1),
            f32::from_bits(1.0f32.to_bits() - 1),
            -f32::from_bits(1.0f32.to_bits() + 1),
            -f32::from_bits(1.0f32.to_bits() - 1),
            0.5,
            -0.5,
            0.414_213_57,
            f32::NAN,
            -f32::NAN,
            f32::from_bits(0x7fc0_1234),
            f32::INFINITY,
            f32::NEG_INFINITY,
            f32::MAX,
            -f32::MAX,
            1e30,
            -1e30,
            3e9,
            -3e9,
            1_048_576.0,
            127.5,
            128.0,
            -150.0,
            -150.5,
            -126.5,
            // exp2's exponent boundaries, acos's switch at ½, the end of
            // sin_cos_turn's exact reduction, and the integer range.
            -151.0,
            -149.0,
            -127.0,
            -126.0,
            127.0,
            f32::from_bits(0.5f32.to_bits() + 1),
            f32::from_bits(0.5f32.to_bits() - 1),
            -f32::from_bits(0.5f32.to_bits() + 1),
            f32::from_bits(1_048_576.0f32.to_bits() + 1),
            f32::from_bits(1_048_576.0f32.to_bits() - 1),
            4_194_304.0,
            2_147_483_648.0,
            -2_147_483_648.0,
            2_147_483_520.0,
            -2_147_483_904.0,
        ];
        for k in -40..=40 {
            v.push(k as f32 * 0.061_3);
            v.push(k as f32 * 7.37);
        }
        v
    }

    /// `scalar(x)` and lane `k` of `wide(x₀…x₇)` agree bit for bit on
    /// every input, with each input tried in every lane position.
    pub(crate) fn same_bits_1(
        name: &str,
        scalar: impl Fn(f32) -> f32,
        wide: impl Fn(f32x8) -> f32x8,
    ) {
        let xs = inputs();
        for shift in 0..8 {
            for chunk in xs.chunks(8) {
                let mut a = [0.25f32; 8];
                for (k, &x) in chunk.iter().enumerate() {
                    a[(k + shift) % 8] = x;
                }
                let got = wide(f32x8::new(a)).to_array();
                for k in 0..8 {
                    let want = scalar(a[k]);
                    assert_eq!(got[k].to_bits(), want.to_bits(), "{name}({:e})", a[k]);
                }
            }
        }
    }

    /// [`same_bits_1`] for functions of two lanes, on every pair of
    /// inputs.
    pub(crate) fn same_bits_2(
        name: &str,
        scalar: impl Fn(f32, f32) -> f32,
        wide: impl Fn(f32x8, f32x8) -> f32x8,
    ) {
        let xs = inputs();
        let pairs: Vec<(f32, f32)> = xs
            .iter()
            .flat_map(|&a| xs.iter().map(move |&b| (a, b)))
            .collect();
        for chunk in pairs.chunks(8) {
            let (mut a, mut b) = ([0.25f32; 8], [0.5f32; 8]);
            for (k, &(x, y)) in chunk.iter().enumerate() {
                (a[k], b[k]) = (x, y);
            }
            let got = wide(f32x8::new(a), f32x8::new(b)).to_array();
            for k in 0..8 {
                let want = scalar(a[k], b[k]);
                assert_eq!(
                    got[k].to_bits(),
                    want.to_bits(),
                    "{name}({:e}, {:e})",
                    a[k],
                    b[k]
                );
            }
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// The bit and integer operations agree between the forms, and with
    /// Rust's own (`as`, `copysign`, `is_sign_negative`, `abs`).
    #[test]
    fn bit_and_integer_operations_match_rust_and_each_other() {
        let to_int = |x: f32| f32::from_bits(Lanes::to_int(x) as u32);
        let to_int8 = |x: f32x8| <f32x8 as Lanes>::from_bits(Lanes::to_int(x));
        classes::same_bits_1("to_int", to_int, to_int8);
        let round_trip = |x: f32| f32::from_int(Lanes::to_int(x));
        let round_trip8 = |x: f32x8| f32x8::from_int(Lanes::to_int(x));
        classes::same_bits_1("from_int", round_trip, round_trip8);
        classes::same_bits_1("abs", Lanes::abs, <f32x8 as Lanes>::abs);
        let sign = |x: f32| if Lanes::sign_bit(x) { 1.0 } else { 0.0 };
        let sign8 = |x: f32x8| f32x8::select(Lanes::sign_bit(x), f32x8::splat(1.0), f32x8::ZERO);
        classes::same_bits_1("sign_bit", sign, sign8);
        classes::same_bits_2("copysign", Lanes::copysign, <f32x8 as Lanes>::copysign);
        classes::same_bits_1(
            "clamp_to",
            |x| x.clamp_to(-1.0, 2.0),
            |x: f32x8| x.clamp_to(-1.0, 2.0),
        );
        for x in classes::inputs() {
            assert_eq!(Lanes::to_int(x), x as i32, "{x:e}");
            assert_eq!(Lanes::abs(x).to_bits(), x.abs().to_bits(), "{x:e}");
            assert_eq!(Lanes::sign_bit(x), x.is_sign_negative(), "{x:e}");
            let wide = <f32x8 as Lanes>::to_int(f32x8::splat(x)).to_array();
            assert!(wide.iter().all(|&i| i == x as i32), "{x:e}");
            for s in [1.0f32, -1.0, -0.0, f32::NAN, -f32::NAN] {
                let bits = <f32x8 as Lanes>::copysign(f32x8::splat(x), f32x8::splat(s)).lane(5);
                assert_eq!(bits.to_bits(), x.copysign(s).to_bits(), "{x:e} {s}");
            }
        }
        // The conversions saturate, and NaN goes to 0.
        assert_eq!(Lanes::to_int(3e9f32), i32::MAX);
        assert_eq!(Lanes::to_int(-3e9f32), i32::MIN);
        assert_eq!(Lanes::to_int(f32::NAN), 0);
    }
}
