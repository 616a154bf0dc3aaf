//! Orthonormal bases around a normal, to take sampled local directions
//! (`+z` = the normal) to the world and back.
//!
//! Two constructions:
//!
//! - [`Onb::from_normal`], the default: the branchless basis of Duff,
//!   Burgess, Christensen, Hery, Kensler, Liani and Villemin, *Building an
//!   Orthonormal Basis, Revisited* (JCGT 6(1), 2017). Right-handed
//!   (`u × v = w`), continuous except across `n.z = 0⁻/0⁺`, accurate to a
//!   few ulps for every unit normal including `−z`.
//! - [`Onb::from_normal_axis_switch`], the course's `ONB.build_from_w`:
//!   `a = y` if `|w.x| > 0.9` else `x`; `v = normalize(w × a)`; `u = w × v`.
//!   **It is left-handed** (`u × v = −w`; with `w = z` it gives `u = −x`,
//!   `v = y`), kept that way so directions match the course's.
//!
//! # Degenerate normals
//!
//! `from_normal` and `from_normal_axis_switch` trust their caller: a zero,
//! infinite or NaN normal gives a basis with NaN or zero axes (documented
//! per function, never a panic). [`Onb::try_from_normal`] is for untrusted
//! input: it normalises any finite non-zero vector, however tiny or huge,
//! and returns `None` otherwise.

use glam::Vec3;

use crate::lanes::{Lanes, V3};

/// A right- or left-handed orthonormal basis `(u, v, w)` with `w` the
/// normal. `to_world` maps local `(x, y, z)` to `x u + y v + z w`.
///
/// `Onb` is `Copy`, `Send` and `Sync`: it is a plain value.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Onb {
    /// First tangent.
    pub u: Vec3,
    /// Second tangent.
    pub v: Vec3,
    /// The normal.
    pub w: Vec3,
}

/// `v / |v|`, computed after scaling by the largest component so that
/// neither the square of a tiny vector underflows nor that of a huge one
/// overflows. `None` for a zero or non-finite vector.
#[inline]
fn robust_normalize(v: Vec3) -> Option<Vec3> {
    if !v.is_finite() || v == Vec3::ZERO {
        return None;
    }
    Some(V3::<f32>::from(v).normalize_scaled().into())
}

impl Onb {
    /// The basis with `w = n`, by Duff et al. 2017: right-handed and
    /// branch-free but for the sign of `n.z`.
    ///
    /// `n` must be unit length. A non-unit `n` gives a basis that is not
    /// orthonormal; a zero `n` gives `u = x`, `v = y`, `w = 0`; a NaN
    /// component makes every axis NaN. Use [`Onb::try_from_normal`] for
    /// input you do not control.
    ///
    /// ```
    /// use glam::Vec3;
    /// use strata::onb::Onb;
    /// let n = Vec3::new(0.0, 0.6, 0.8);
    /// let b = Onb::from_normal(n);
    /// assert_eq!(Onb::from_normal([0.0, 0.6, 0.8]), b); // arrays too
    /// assert!(b.u.dot(b.v).abs() < 1e-6);
    /// assert!((b.u.cross(b.v) - n).length() < 1e-6); // right-handed
    /// let d = Vec3::new(0.2, -0.3, 0.9);
    /// assert!((b.to_local(b.to_world(d)) - d).length() < 1e-6);
    /// ```
    #[inline]
    #[must_use]
    pub fn from_normal(n: impl Into<Vec3>) -> Self {
        let b = OnbLanes::from_normal(V3::<f32>::from(n.into()));
        Self {
            u: b.u.into(),
            v: b.v.into(),
            w: b.w.into(),
        }
    }

    /// [`Onb::from_normal`] of `n / |n|` for any finite non-zero `n`, of any
    /// magnitude (1e-30 and 1e30 both work); `None` for a zero, infinite or
    /// NaN vector.
    ///
    /// ```
    /// use glam::Vec3;
    /// use strata::onb::Onb;
    /// let b = Onb::try_from_normal(Vec3::new(0.0, 0.0, 1e-30)).unwrap();
    /// assert_eq!(b.w, Vec3::Z);
    /// assert!(Onb::try_from_normal(Vec3::ZERO).is_none());
    /// assert!(Onb::try_from_normal(Vec3::new(f32::NAN, 0.0, 1.0)).is_none());
    /// ```
    #[inline]
    #[must_use]
    pub fn try_from_normal(n: Vec3) -> Option<Self> {
        robust_normalize(n).map(Self::from_normal)
    }

    /// The course's basis (`ONB.build_from_w`): `w = normalize(n)`, helper
    /// axis `y` if `|w.x| > 0.9` else `x`, `v = normalize(w × a)`,
    /// `u = w × v`. **Left-handed**: `u × v = −w`.
    ///
    /// `n` need not be unit length (it is normalised, robustly against
    /// underflow and overflow); a zero, infinite or NaN `n` gives NaN axes.
    ///
    /// ```
    /// use glam::Vec3;
    /// use strata::onb::Onb;
    /// let b = Onb::from_normal_axis_switch(Vec3::Z * 3.0);
    /// assert_eq!((b.u, b.v, b.w), (-Vec3::X, Vec3::Y, Vec3::Z));
    /// assert!((b.u.cross(b.v) + b.w).length() < 1e-6); // left-handed
    /// ```
    #[inline]
    #[must_use]
    pub fn from_normal_axis_switch(n: Vec3) -> Self {
        let w = robust_normalize(n).unwrap_or(Vec3::NAN);
        let a = if w.x.abs() > 0.9 { Vec3::Y } else { Vec3::X };
        let c = w.cross(a);
        let v = c / crate::float::sqrtf(c.length_squared());
        Self {
            u: w.cross(v),
            v,
            w,
        }
    }

    /// The world direction of local coordinates `d`: `d.x u + d.y v + d.z w`.
    ///
    /// ```
    /// use glam::Vec3;
    /// use strata::onb::Onb;
    /// let b = Onb::from_normal(Vec3::Y);
    /// assert!((b.to_world(Vec3::Z) - Vec3::Y).length() < 1e-7); // local +z is the normal
    /// ```
    #[inline]
    #[must_use]
    pub fn to_world(&self, d: Vec3) -> Vec3 {
        let b = OnbLanes::<f32> {
            u: self.u.into(),
            v: self.v.into(),
            w: self.w.into(),
        };
        b.to_world(d.into()).into()
    }

    /// The local coordinates of world direction `d`: `(d·u, d·v, d·w)`. The
    /// inverse of [`Onb::to_world`] for an orthonormal basis.
    ///
    /// ```
    /// use glam::Vec3;
    /// use strata::onb::Onb;
    /// let b = Onb::from_normal(Vec3::new(0.6, 0.0, 0.8));
    /// // The cosine to the normal is the local z.
    /// assert!((b.to_local(Vec3::Z).z - 0.8).abs() < 1e-6);
    /// ```
    #[inline]
    #[must_use]
    pub fn to_local(&self, d: Vec3) -> Vec3 {
        Vec3::new(d.dot(self.u), d.dot(self.v), d.dot(self.w))
    }
}

/// [`Onb`] over lanes: one basis per lane, by the same operations.
#[derive(Clone, Copy, Debug)]
pub(crate) struct OnbLanes<L> {
    pub(crate) u: V3<L>,
    pub(crate) v: V3<L>,
    pub(crate) w: V3<L>,
}

impl<L: Lanes> OnbLanes<L> {
    /// [`Onb::from_normal`] per lane.
    #[inline(always)]
    pub(crate) fn from_normal(n: V3<L>) -> Self {
        let k1 = L::splat(1.0);
        let sign = k1.copysign(n.z);
        let a = -k1 / (sign + n.z);
        let b = n.x * n.y * a;
        Self {
            u: V3::new(k1 + sign * n.x * n.x * a, sign * b, -sign * n.x),
            v: V3::new(b, sign + n.y * n.y * a, -n.y),
            w: n,
        }
    }

    /// [`Onb::to_world`] per lane.
    #[inline(always)]
    pub(crate) fn to_world(self, d: V3<L>) -> V3<L> {
        self.u * d.x + self.v * d.y + self.w * d.z
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn zero_and_nan_normals() {
        let z = Onb::from_normal(Vec3::ZERO);
        assert_eq!((z.u, z.v, z.w), (Vec3::X, Vec3::Y, Vec3::ZERO));
        let n = Onb::from_normal(Vec3::new(f32::NAN, 0.0, 1.0));
        assert!(n.u.is_nan() && n.v.is_nan());
        let c = Onb::from_normal_axis_switch(Vec3::ZERO);
        assert!(c.u.is_nan() && c.v.is_nan() && c.w.is_nan());
        assert!(Onb::try_from_normal(Vec3::new(f32::INFINITY, 0.0, 0.0)).is_none());
    }

    #[test]
    fn minus_z_and_negative_zero() {
        // The sign branch of Duff et al.: n.z = -0.0 takes the negative one.
        for n in [
            -Vec3::Z,
            Vec3::new(1.0, 0.0, -0.0),
            Vec3::new(1.0, 0.0, 0.0),
        ] {
            let b = Onb::from_normal(n);
            assert!((b.u.cross(b.v) - n).length() < 1e-6, "{n}");
            assert!(b.u.dot(n).abs() < 1e-7 && b.v.dot(n).abs() < 1e-7);
        }
    }

    #[test]
    fn course_axis_switch_matches_the_course() {
        // |w.x| > 0.9 takes a = y; otherwise a = x.
        let b = Onb::from_normal_axis_switch(Vec3::X);
        // w × y = x × y = z; u = x × z = -y.
        assert_eq!((b.u, b.v, b.w), (-Vec3::Y, Vec3::Z, Vec3::X));
        let b = Onb::from_normal_axis_switch(Vec3::Y);
        // w × x = y × x = -z; u = y × -z = -x.
        assert_eq!((b.u, b.v, b.w), (-Vec3::X, -Vec3::Z, Vec3::Y));
    }
}
