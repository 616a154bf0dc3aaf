//! Ray–sphere intersection: a scalar reference and SIMD twins that return
//! the same bits.
//!
//! # Kernels
//!
//! | query | scalar reference | 1 ray × 8 spheres | 8 rays × spheres | through a [`Bvh`] |
//! |---|---|---|---|---|
//! | one sphere | [`intersect_sphere`] | | | |
//! | closest hit | [`closest_hit`] | [`closest_hit_1x8`] | [`closest_hit_x8`] | [`Bvh::closest_hit`], [`Bvh::closest_hit_x8`] |
//! | any hit (shadow rays) | [`any_hit`] | [`any_hit_1x8`] | [`any_hit_x8`] | [`Bvh::any_hit`], [`Bvh::any_hit_x8`] |
//! | the caller's primitives | [`closest_primitive_hit`], [`any_primitive_hit`] | | | [`PrimitiveBvh::closest_hit`], [`PrimitiveBvh::any_hit`] |
//!
//! Suffixes: `_1x8` is one ray against the spheres of a [`SphereSet`] eight
//! at a time (for incoherent rays); `_x8` is a [`RayPacket8`] of eight rays
//! against one sphere at a time (for coherent rays, e.g. camera rays of
//! eight neighbouring pixels).
//!
//! Every query has one shape: what is traced first (a [`Sphere`], a slice,
//! a [`SphereSet`], or the receiver: a [`Bvh`] or a
//! [`Scene`](crate::render::Scene)), then the [`Ray`] or [`RayPacket8`],
//! then, for packet closest hits, the [`HitPacket8`] to update, then, for
//! the `_with` queries, the caller's [`BvhStack`].
//!
//! # One contract for every query: unit directions
//!
//! Every query, scalar, SIMD or through a [`Bvh`], takes a [`Ray`] whose
//! `dir` is unit length to a few ulps (as `Vec3::normalize` gives): the
//! kernel's formula assumes `d·d = 1` (see below), and the BVH's boxes
//! are made conservative for hit points `o + t d` of such rays. With it,
//! all paths return the same bits (the brute-force answer). With any
//! other direction the roots are not the ray's intersections, and the
//! answer is unspecified: each path returns a hit or a miss without
//! panicking, but they may disagree (e.g. `Bvh::any_hit` and `any_hit`
//! on a ray of length 2). Normalise first; `t` is then a distance.
//!
//! # The rest of the module
//!
//! - Data: [`Ray`], [`Sphere`] (with [`Sphere::spawn_origin`] for rays
//!   leaving a surface), [`Hit`].
//! - 8-wide storage: [`SphereChunk8`] and [`SphereSet`] (sized by
//!   [`chunks_for`], refused with [`SphereSetError`]), [`RayPacket8`],
//!   [`HitPacket8`].
//! - The BVH, which returns the brute-force bits faster from
//!   [`BVH_MIN_SPHERES`] spheres: [`Bvh`] and its queries, [`BvhStack`]
//!   (reusable traversal memory), [`BvhNode8`] and [`BvhStorage`] (caller
//!   storage, sized by [`bvh_storage_for`]; [`Bvh::from_parts`] views it
//!   again after checking it), [`BvhError`], and its limits
//!   [`BVH_MAX_SPHERES`], [`BVH_MAX_COORDINATE`] and [`BVH_MAX_DEPTH`].
//! - The same BVH over the caller's own primitives (triangles, boxes,
//!   anything with a box and an intersection routine): [`Primitives`],
//!   [`PrimitiveBvh`] (storage sized by [`primitive_bvh_storage_for`]),
//!   [`PrimitiveHit`], [`Aabb`], and the brute-force references
//!   [`closest_primitive_hit`] and [`any_primitive_hit`] it reproduces.
//!   Spheres keep their own kernels; for a caller's primitive Strata
//!   promises the traversal and the hit the caller's routine reports.
//! - With the `alloc` feature, `OwnedBvh` and `OwnedPrimitiveBvh`: a tree
//!   and its storage in one value.
//! - The build's SIMD level: [`simd_level`], [`SimdLevel`].
//!
//! # The same bits on every path
//!
//! Every kernel runs one function, written once for `f32` and `f32x8`
//! over the private `lanes` module's ray and sphere bundles, so a ray gets the same sphere index and
//! the bit-identical `t` from the scalar, 1×8 and packet paths, on SSE2,
//! AVX2 or AVX-512 builds. No operation is fused; `√` is IEEE-exact
//! everywhere. `tests/tracing/packet_vs_scalar.rs` checks this on 10⁶ rays.
//!
//! # The formula
//!
//! After Haines, Günther and Akenine-Möller, *Precision Improvements for
//! Ray/Sphere Intersection* (Ray Tracing Gems, ch. 7, 2019). With a unit
//! direction `d`, `f = o − c`, `b = f·d` and `c₀ = |f|² − r²`:
//!
//! ```text
//! Δ = r² − |f − b d|²    if |f|² ≥ 1.5 r²   (origin beyond 1.22 radii)
//! Δ = b² − c₀            otherwise
//! q = −(b + sign(b) √Δ)                     (the larger root, stable)
//! t₀ = c₀ / q,  t₁ = q
//! ```
//!
//! The hit is the nearer root in the open interval `(t_min, t_max)`, else
//! the farther one.
//!
//! Why two discriminants: near the silhouette the rounding error of
//! `r² − |f − b d|²` is about `2ε r |f|`, that of `b² − c₀` about
//! `ε (3|f|² − 2r²)`; they cross at `|f| ≈ 1.22 r`. The chapter's form is
//! far better for a sphere small against its distance (the textbook form
//! gets 16 % of hit/miss decisions wrong on a r = 0.5 sphere 2000 away),
//! but for an origin near a big sphere — a camera just above a r = 1000
//! ground, looking at the horizon — its `t` is 7× less accurate.
//! `tests/tracing/precision.rs` measures all three against `f64`, and sweeps
//! `|f| / r` to check the choice never does worse than the better form.
//!
//! Rays that leave a surface start from [`Sphere::spawn_origin`], not from
//! the hit point with a parametric epsilon (the course's `t_min = 1e-6`
//! self-intersects on about 29 % of grazing secondary rays).
//!
//! # Degenerate input
//!
//! - A sphere with radius `≤ 0` or NaN is never hit; padding lanes of a
//!   [`SphereSet`] have radius 0.
//! - A ray with a NaN component, or NaN `t_min`/`t_max`, hits nothing; in a
//!   packet, a NaN lane never affects the other lanes.
//! - An empty range (`t_min ≥ t_max`) hits nothing.
//! - A direction that is not unit length (zero included) breaks the
//!   one contract above: the result is unspecified and paths may
//!   disagree, never a panic.
//! - Coordinates whose squares overflow `f32` (beyond about 1.8e19) give
//!   unspecified results, never a panic.
//! - Ties (two spheres at the same `t`) go to the lower sphere index on
//!   every path.

use glam::Vec3;

mod bvh;
mod packet;

use crate::lanes::{Lanes, RayLanes, SphereLanes, V3, max_lanes};
pub use bvh::{
    Aabb, BVH_MAX_COORDINATE, BVH_MAX_DEPTH, BVH_MAX_SPHERES, BVH_MIN_SPHERES, BVH_SLACK_ULPS, Bvh,
    BvhError, BvhNode8, BvhStack, BvhStorage, PrimitiveBvh, PrimitiveHit, Primitives,
    any_primitive_hit, bvh_storage_for, closest_primitive_hit, primitive_bvh_storage_for,
};
#[cfg(feature = "alloc")]
pub use bvh::{OwnedBvh, OwnedPrimitiveBvh};
pub use packet::{
    HitPacket8, RayPacket8, SphereChunk8, SphereSet, SphereSetError, any_hit_1x8, any_hit_x8,
    chunks_for, closest_hit_1x8, closest_hit_x8,
};

/// A ray `o + t d` restricted to `t ∈ (t_min, t_max)`, both ends open.
/// Every query needs `dir` unit length (the module's contract, "One
/// contract for every query"); `t` is then a distance.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Ray {
    /// Origin.
    pub origin: Vec3,
    /// Unit direction.
    pub dir: Vec3,
    /// Lower end of the open `t` interval.
    pub t_min: f32,
    /// Upper end of the open `t` interval.
    pub t_max: f32,
}

impl Ray {
    /// A ray over `(0, ∞)`.
    ///
    /// `origin` and `dir` are a [`Vec3`] or anything that becomes one,
    /// such as `[f32; 3]` (a renderer on another glam, or none, passes
    /// arrays).
    ///
    /// ```
    /// use glam::Vec3;
    /// use strata::trace::Ray;
    /// let r = Ray::new(Vec3::ZERO, Vec3::X);
    /// assert_eq!(r.at(2.0), Vec3::new(2.0, 0.0, 0.0));
    /// assert_eq!(Ray::new([0.0, 0.0, 0.0], [1.0, 0.0, 0.0]), r);
    /// ```
    #[inline]
    #[must_use]
    pub fn new(origin: impl Into<Vec3>, dir: impl Into<Vec3>) -> Self {
        Self {
            origin: origin.into(),
            dir: dir.into(),
            t_min: 0.0,
            t_max: f32::INFINITY,
        }
    }

    /// [`Ray::new`], checked: `None` unless `dir` is unit length as every
    /// query requires (`|d·d − 1| ≤ 16 ε`, which `Vec3::normalize` meets)
    /// and `origin` and `dir` are finite. A renderer that keeps
    /// unnormalised directions (as *Ray Tracing in One Weekend*'s camera
    /// does) finds out here rather than in wrong hits.
    ///
    /// ```
    /// use glam::Vec3;
    /// use strata::trace::Ray;
    /// assert!(Ray::try_new(Vec3::ZERO, Vec3::new(1.0, 2.0, 2.0).normalize()).is_some());
    /// assert!(Ray::try_new(Vec3::ZERO, [1.0, 2.0, 2.0]).is_none()); // length 3
    /// assert!(Ray::try_new(Vec3::NAN, Vec3::X).is_none());
    /// ```
    #[inline]
    #[must_use]
    pub fn try_new(origin: impl Into<Vec3>, dir: impl Into<Vec3>) -> Option<Self> {
        let r = Self::new(origin, dir);
        let unit = (r.dir.dot(r.dir) - 1.0).abs() <= 16.0 * f32::EPSILON;
        (unit && r.origin.is_finite() && r.dir.is_finite()).then_some(r)
    }

    /// The same ray over `(t_min, t_max)`.
    #[inline]
    #[must_use]
    pub fn with_range(self, t_min: f32, t_max: f32) -> Self {
        Self {
            t_min,
            t_max,
            ..self
        }
    }

    /// The point at parameter `t`: `origin + t · dir` (no fused multiply-add).
    #[inline]
    #[must_use]
    pub fn at(&self, t: f32) -> Vec3 {
        self.lanes().at(t).into()
    }
}

/// A sphere. A radius `≤ 0` or NaN makes it invisible to every query.
///
/// **Range and resolution.** The kernels square distances in `f32`, so
/// centre coordinates and radius must be within ±[`BVH_MAX_COORDINATE`]
/// (2⁶⁰ ≈ 1.15e18; beyond about 1.8e19 the squares overflow and the sphere
/// is never hit). And `o − c` is rounded to about `2⁻²⁴ |o − c|`, which
/// blurs a silhouette by that much: a sphere whose radius is at least
/// [`SPHERE_MIN_RADIUS_RATIO`] (2⁻²⁰) times its distance from a ray's
/// origin is hit when the ray's line passes within `r` of its centre, to
/// within 10 % of `r` (measured against `f64` in
/// `tests/tracing/precision.rs`: lines from 0.92 r to 1.05 r may go either
/// way); far smaller spheres report hits for lines that miss them by many
/// radii.
/// [`Sphere::is_resolved_within`] checks the bound for a whole scene.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Sphere {
    /// Centre.
    pub center: Vec3,
    /// Radius.
    pub radius: f32,
}

impl Sphere {
    /// A sphere of `radius` around `center`.
    #[inline]
    #[must_use]
    pub const fn new(center: Vec3, radius: f32) -> Self {
        Self { center, radius }
    }

    /// A sphere of `radius` around `center` given as `[x, y, z]`: for a
    /// renderer whose vectors are not this crate's glam (`Sphere::new`
    /// stays a `const fn`).
    ///
    /// ```
    /// use strata::trace::Sphere;
    /// let s = Sphere::from_array([1.0, 2.0, 3.0], 0.5);
    /// assert_eq!(s, Sphere::new(glam::Vec3::new(1.0, 2.0, 3.0), 0.5));
    /// ```
    #[inline]
    #[must_use]
    pub const fn from_array(center: [f32; 3], radius: f32) -> Self {
        Self {
            center: Vec3::from_array(center),
            radius,
        }
    }

    /// Whether rays from origins within `reach` of the coordinate origin
    /// see this sphere to 10 % of its radius (see "Range and resolution"
    /// above): `r ≥ 2⁻²⁰ (reach + |c|)`, since `|o − c| ≤ reach + |c|`.
    /// With `reach` the camera's distance from 0 this covers camera rays,
    /// which draw every silhouette an image shows directly; with the
    /// largest `|c| + r` of a scene's spheres it covers every ray (they
    /// start on the camera or on a sphere). False for a NaN or
    /// non-positive radius.
    ///
    /// ```
    /// use glam::Vec3;
    /// use strata::trace::Sphere;
    /// let grain = Sphere::new(Vec3::new(0.0, 0.0, -1e6), 1e-4);
    /// assert!(!grain.is_resolved_within(10.0));
    /// let marble = Sphere::new(Vec3::new(0.0, 0.0, -10.0), 0.01);
    /// assert!(marble.is_resolved_within(2000.0));
    /// ```
    #[inline]
    #[must_use]
    pub fn is_resolved_within(&self, reach: f32) -> bool {
        self.radius >= SPHERE_MIN_RADIUS_RATIO * (reach + self.center.length())
    }

    /// The outward unit normal at a point `p` on the surface: `(p − c) / r`.
    ///
    /// ```
    /// use glam::Vec3;
    /// use strata::trace::Sphere;
    /// let s = Sphere::new(Vec3::ZERO, 2.0);
    /// assert_eq!(s.normal_at(Vec3::new(0.0, 2.0, 0.0)), Vec3::Y);
    /// ```
    #[inline]
    #[must_use]
    pub fn normal_at(&self, p: Vec3) -> Vec3 {
        (p - self.center) / self.radius
    }
}

/// The smallest radius a sphere may have, as a fraction of its distance
/// from a ray's origin, for its silhouette to be right to 10 % of the
/// radius (2⁻²⁰: sixteen times the rounding of `o − c`). See
/// [`Sphere::is_resolved_within`].
pub const SPHERE_MIN_RADIUS_RATIO: f32 = 1.0 / 1_048_576.0;

/// The offset that moves a point on a sphere off its surface for good, in
/// units of `f32::EPSILON · (max |centre component| + radius)`.
/// Measured: 1 suffices for every case in `tests/tracing/precision.rs` (0.5 does
/// not); 8 is the margin. Callers see it through [`Sphere::offset_bound`].
const SPAWN_OFFSET_ULPS: f32 = 8.0;

impl Sphere {
    /// The distance a new ray's origin keeps from this sphere's surface:
    /// `8 · f32::EPSILON · (max |cᵢ| + r)`. It bounds the rounding of
    /// `o − c` and `|o − c|² − r²` for points on the surface, so a ray
    /// spawned that far out (in) cannot re-hit the surface it leaves at
    /// `t ≈ 0`.
    ///
    /// ```
    /// use glam::Vec3;
    /// use strata::trace::Sphere;
    /// let ground = Sphere::new(Vec3::new(0.0, -100.5, -1.0), 100.0);
    /// assert!(ground.offset_bound() < 2e-4);
    /// ```
    #[inline]
    #[must_use]
    pub fn offset_bound(&self) -> f32 {
        offset_bound_lanes(&self.lanes())
    }

    /// A safe origin for a ray leaving the surface near `p` (e.g. a hit
    /// point `ray.at(t)`) to the `outside` of the sphere (reflection) or
    /// its inside (transmission): `p` is projected back onto the sphere,
    /// then moved [`Sphere::offset_bound`] along the normal to that side.
    /// This replaces the course's parametric `t_min = 1e-6` (COURSE.md D9),
    /// which lets grazing rays re-hit their own surface.
    ///
    /// The side is the caller's to state, not inferred from the direction:
    /// for a direction within rounding of the tangent plane the sign of
    /// `dir · n` is noise. A `p` at the centre gives NaN. For a sphere so
    /// small against its distance from the origin that the bound reaches
    /// its radius (`r` below about `10⁻⁶ · max |cᵢ|`), the offset is capped
    /// at `r / 2`; such a sphere is below `f32` resolution there.
    ///
    /// ```
    /// use glam::Vec3;
    /// use strata::trace::{intersect_sphere, Ray, Sphere};
    /// let s = Sphere::new(Vec3::new(0.3, -100.5, -1.0), 100.0);
    /// let p = Vec3::new(0.3, -0.5, -1.0);
    /// // Leaving almost parallel to the surface: no self-hit.
    /// let dir = Vec3::new(1.0, 1e-4, 0.0).normalize();
    /// let o = s.spawn_origin(p, true);
    /// assert_eq!(intersect_sphere(&s, &Ray::new(o, dir)), None);
    /// // Entering: the ray crosses to the far side, 200 away.
    /// let t = intersect_sphere(&s, &Ray::new(s.spawn_origin(p, false), -Vec3::Y)).unwrap();
    /// assert!((t - 200.0).abs() < 1e-3);
    /// ```
    #[inline]
    #[must_use]
    pub fn spawn_origin(&self, p: Vec3, outside: bool) -> Vec3 {
        self.spawn_origin_along(self.unit_normal(p), outside)
    }

    /// [`Sphere::spawn_origin`] from the outward unit normal `n` already
    /// known at the point (as [`Sphere::unit_normal`] gives it): the
    /// centre plus `n` times the radius moved [`Sphere::offset_bound`]
    /// (capped at `r / 2`) to the chosen side. A renderer that shades with
    /// the normal saves computing it twice.
    ///
    /// ```
    /// use glam::Vec3;
    /// use strata::trace::Sphere;
    /// let s = Sphere::new(Vec3::new(1.0, 2.0, 3.0), 0.5);
    /// let p = Vec3::new(1.0, 2.5, 3.0);
    /// let o = s.spawn_origin_along(s.unit_normal(p), true);
    /// assert_eq!(o, s.spawn_origin(p, true));
    /// assert!(o.y > 2.5 && o.y - 2.5 <= s.offset_bound());
    /// ```
    #[inline]
    #[must_use]
    pub fn spawn_origin_along(&self, n: Vec3, outside: bool) -> Vec3 {
        spawn_origin_lanes(&self.lanes(), V3::from(n), outside).into()
    }

    /// The outward unit normal towards `p` (a point on or near the
    /// surface): `(p − c) / |p − c|`, with glam's `normalize` bits where
    /// `|p − c|²` is comfortably inside the `f32` range (`10⁻³⁰` to
    /// `10³⁰`) and, beyond, scaled by its largest component first so it
    /// neither underflows nor overflows. NaN for `p` at the centre.
    ///
    /// ```
    /// use glam::Vec3;
    /// use strata::trace::Sphere;
    /// let s = Sphere::new(Vec3::new(0.0, -1000.0, 0.0), 1000.0);
    /// let n = s.unit_normal(Vec3::new(3.0, 0.0, 4.0));
    /// assert!((n.length() - 1.0).abs() < 1e-6 && n.y > 0.99);
    /// // A sphere of radius 10⁻²⁵: |p − c|² underflows, the normal does not.
    /// let tiny = Sphere::new(Vec3::ZERO, 1e-25);
    /// assert_eq!(tiny.unit_normal(Vec3::new(0.0, 0.0, -1e-25)), -Vec3::Z);
    /// ```
    #[inline]
    #[must_use]
    pub fn unit_normal(&self, p: Vec3) -> Vec3 {
        unit_normal_lanes(V3::from(p), V3::from(self.center)).into()
    }
}

/// A closest hit: the distance along the ray and the index of the sphere in
/// the slice or set that was traced.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Hit {
    /// Ray parameter of the hit, in the ray's open interval.
    pub t: f32,
    /// Index of the sphere hit.
    pub sphere: u32,
}

/// The first stage of the kernel: everything up to the discriminant.
/// `valid` is false where no root can exist (`Δ < 0`, radius `≤ 0`, NaN),
/// so a caller may skip [`sphere_roots`] when no lane is valid: it would
/// return `+∞` there.
#[derive(Clone, Copy)]
pub(crate) struct Quadratic<L: Lanes> {
    b: L,
    c: L,
    disc: L,
    valid: L::Mask,
}

/// Stage one (see the module docs for the formula). Written once for `f32`
/// and `f32x8` so all paths agree bit for bit.
#[inline(always)]
pub(crate) fn sphere_quadratic<L: Lanes>(ray: &RayLanes<L>, s: &SphereLanes<L>) -> Quadratic<L> {
    let (d, r) = (ray.dir, s.radius);
    let f = ray.origin - s.center;
    let b = f.dot(d);
    let l = f - d * b;
    let r2 = r * r;
    let ff = f.dot(f);
    let c = ff - r2;
    // The better-conditioned discriminant for where the origin is: the
    // errors cross near |f| = 1.22 r (see the module docs).
    let far_origin = ff.ge(L::splat(1.5) * r2);
    let disc = L::select(far_origin, r2 - l.dot(l), b * b - c);
    let valid = L::and(r.gt(L::splat(0.0)), disc.ge(L::splat(0.0)));
    Quadratic { b, c, disc, valid }
}

/// Stage two: the first root in `(t_min, t_max)`, or `+∞` for a miss.
#[inline(always)]
pub(crate) fn sphere_roots<L: Lanes>(k: Quadratic<L>, t_min: L, t_max: L) -> L {
    let root = k.disc.sqrt();
    let q = L::select(k.b.gt(L::splat(0.0)), -k.b - root, -k.b + root);
    let t0 = k.c / q;
    // near/far by compare and select, so a NaN root is rejected alike on
    // every path (f32::min and SIMD min disagree on NaN).
    let t0_first = t0.lt(q);
    let near = L::select(t0_first, t0, q);
    let far = L::select(t0_first, q, t0);
    let near_ok = L::and(k.valid, L::and(near.gt(t_min), near.lt(t_max)));
    let far_ok = L::and(k.valid, L::and(far.gt(t_min), far.lt(t_max)));
    L::select(
        near_ok,
        near,
        L::select(far_ok, far, L::splat(f32::INFINITY)),
    )
}

/// The whole kernel, skipping stage two when no lane can hit: first by
/// the cheap root test alone (brute force over chunks: most chunks miss
/// outright), then by [`may_hit`] (a chunk that holds the sphere a ray
/// leaves).
#[inline(always)]
pub(crate) fn sphere_t<L: Lanes>(ray: &RayLanes<L>, s: &SphereLanes<L>) -> L {
    let k = sphere_quadratic(ray, s);
    if L::any(k.valid) && L::any(may_hit(&k, ray.t_min)) {
        sphere_roots(k, ray.t_min, ray.t_max)
    } else {
        L::splat(f32::INFINITY)
    }
}

/// [`sphere_t`] for a caller that reads only the `live` lanes: stage two
/// is skipped when none of them can hit by [`may_hit`] (the other lanes'
/// `t` is then unspecified). For BVH leaves and outliers, whose spheres
/// are near the ray, so that the finer test often pays.
#[inline(always)]
pub(crate) fn sphere_t_live<L: Lanes>(ray: &RayLanes<L>, s: &SphereLanes<L>, live: L::Mask) -> L {
    let k = sphere_quadratic(ray, s);
    if L::any(L::and(may_hit(&k, ray.t_min), live)) {
        sphere_roots(k, ray.t_min, ray.t_max)
    } else {
        L::splat(f32::INFINITY)
    }
}

/// Lanes where [`sphere_roots`] can return a hit. Beyond `valid`: an
/// origin outside the sphere (`c₀ > 0`) moving away from it (`b > 0`)
/// has both roots behind it, which stage two rejects whenever
/// `t_min ≥ 0`: `q = −b − √Δ < 0`, so `t₁ = q < 0` and `t₀ = c₀ / q ≤ 0`
/// (−0 at worst), neither above `t_min`. Skipping them saves a square
/// root and a division, on the critical path, for every ray leaving a
/// surface, and changes no result.
#[inline(always)]
pub(crate) fn may_hit<L: Lanes>(k: &Quadratic<L>, t_min: L) -> L::Mask {
    let zero = L::splat(0.0);
    // Not (c₀ > 0 and b > 0 and t_min ≥ 0). A NaN in c₀ or b, which the
    // complements below count as "behind", leaves no root above a
    // non-negative t_min either: t₀ is NaN, and q is NaN or negative.
    let ahead = L::or(zero.ge(k.c), L::or(zero.ge(k.b), t_min.lt(zero)));
    L::and(k.valid, ahead)
}

/// [`Sphere::offset_bound`] per lane.
#[inline(always)]
pub(crate) fn offset_bound_lanes<L: Lanes>(s: &SphereLanes<L>) -> L {
    let c = s.center;
    let m = max_lanes(c.x.abs(), max_lanes(c.y.abs(), c.z.abs()));
    L::splat(SPAWN_OFFSET_ULPS * f32::EPSILON) * (m + s.radius.abs())
}

/// [`Sphere::spawn_origin_along`] per lane.
#[inline(always)]
pub(crate) fn spawn_origin_lanes<L: Lanes>(
    s: &SphereLanes<L>,
    n: V3<L>,
    outside: L::Mask,
) -> V3<L> {
    // A sphere smaller than its own rounding at this position: stay
    // within it rather than jump past its centre.
    let half = L::splat(0.5) * s.radius;
    let bound = offset_bound_lanes(s);
    // min(bound, half), as `f32::min` (a NaN side gives the other).
    let offset = L::select(L::or(half.lt(bound), L::not(bound.eq(bound))), half, bound);
    let side = L::select(outside, offset, -offset);
    s.center + n * (s.radius + side)
}

/// [`Sphere::unit_normal`] per lane.
#[inline(always)]
pub(crate) fn unit_normal_lanes<L: Lanes>(p: V3<L>, center: V3<L>) -> V3<L> {
    let k1 = L::splat(1.0);
    let v = p - center;
    let len2 = v.dot(v);
    let ordinary = L::and(len2.ge(L::splat(1e-30)), len2.le(L::splat(1e30)));
    let direct = v * (k1 / len2.sqrt());
    if !L::any(L::not(ordinary)) {
        return direct;
    }
    // Scale before squaring.
    let scaled = v.normalize_scaled();
    V3::select(ordinary, direct, scaled)
}

/// The scalar kernel on a ray and a sphere (the brute-force loops' and
/// the BVH outliers'), with [`may_hit`]'s early-out: one sphere, so the
/// finer test costs one branch, not one per chunk.
#[inline(always)]
pub(crate) fn ray_sphere_t(ray: &Ray, s: &Sphere, t_max: f32) -> f32 {
    sphere_t_live(
        &RayLanes {
            t_max,
            ..ray.lanes()
        },
        &s.lanes(),
        true,
    )
}

impl Ray {
    /// The ray as one lane.
    #[inline(always)]
    pub(crate) fn lanes(&self) -> RayLanes<f32> {
        RayLanes {
            origin: V3::splat(self.origin),
            dir: V3::splat(self.dir),
            t_min: self.t_min,
            t_max: self.t_max,
        }
    }

    /// The ray in every lane of eight.
    #[inline(always)]
    pub(crate) fn lanes_x8(&self) -> RayLanes<crate::lanes::f32x8> {
        use crate::lanes::f32x8;
        RayLanes {
            origin: V3::splat(self.origin),
            dir: V3::splat(self.dir),
            t_min: f32x8::splat(self.t_min),
            t_max: f32x8::splat(self.t_max),
        }
    }
}

impl Sphere {
    /// The sphere as one lane.
    #[inline(always)]
    pub(crate) fn lanes(&self) -> SphereLanes<f32> {
        SphereLanes {
            center: V3::splat(self.center),
            radius: self.radius,
        }
    }
}

/// The first intersection of `ray` with `sphere` in `(t_min, t_max)`, by
/// the robust formulation (module docs); `None` for a miss.
///
/// ```
/// use glam::Vec3;
/// use strata::trace::{Ray, Sphere, intersect_sphere};
/// let s = Sphere::new(Vec3::new(0.0, 0.0, -5.0), 1.0);
/// assert_eq!(intersect_sphere(&s, &Ray::new(Vec3::ZERO, -Vec3::Z)), Some(4.0));
/// // From inside, the far side.
/// let inside = Ray::new(Vec3::new(0.0, 0.0, -5.0), Vec3::X);
/// assert_eq!(intersect_sphere(&s, &inside), Some(1.0));
/// assert_eq!(intersect_sphere(&s, &Ray::new(Vec3::ZERO, Vec3::Z)), None);
/// ```
#[inline]
#[must_use]
pub fn intersect_sphere(sphere: &Sphere, ray: &Ray) -> Option<f32> {
    let t = ray_sphere_t(ray, sphere, ray.t_max);
    (t < f32::INFINITY).then_some(t)
}

/// The course's textbook intersection (`RT_object.Sphere.intersect`), kept
/// to show why Strata does not use it: `Δ = b² − a c` with `a = d·d`,
/// `b = f·d`, `c = |f|² − r²`, roots `(−b ∓ √Δ) / a`. Its discriminant
/// cancels catastrophically when a sphere is small against its distance
/// (see `tests/tracing/precision.rs`). Same interval and degenerate-input rules
/// as [`intersect_sphere`].
///
/// ```
/// use glam::Vec3;
/// use strata::trace::{Ray, Sphere, intersect_sphere_naive};
/// let s = Sphere::new(Vec3::new(0.0, 0.0, -5.0), 1.0);
/// assert_eq!(intersect_sphere_naive(&s, &Ray::new(Vec3::ZERO, -Vec3::Z)), Some(4.0));
/// ```
#[inline]
#[must_use]
// `!(x > 0)` on purpose: a NaN must take the miss branch.
#[allow(clippy::neg_cmp_op_on_partial_ord)]
pub fn intersect_sphere_naive(sphere: &Sphere, ray: &Ray) -> Option<f32> {
    if !(sphere.radius > 0.0) {
        return None;
    }
    let f = ray.origin - sphere.center;
    let a = ray.dir.dot(ray.dir);
    let half_b = f.dot(ray.dir);
    let c = f.dot(f) - sphere.radius * sphere.radius;
    let disc = half_b * half_b - a * c;
    if !(disc >= 0.0) {
        return None;
    }
    let root = crate::float::sqrtf(disc);
    let inside = |t: f32| t > ray.t_min && t < ray.t_max;
    let near = (-half_b - root) / a;
    if inside(near) {
        return Some(near);
    }
    let far = (-half_b + root) / a;
    inside(far).then_some(far)
}

/// The closest sphere `ray` hits in `(t_min, t_max)`: the scalar reference
/// every other closest-hit path must equal. Spheres are tested in slice
/// order and the interval shrinks to each hit, so ties go to the lower
/// index.
///
/// ```
/// use glam::Vec3;
/// use strata::trace::{closest_hit, Ray, Sphere};
/// let spheres = [
///     Sphere::new(Vec3::new(0.0, 0.0, -10.0), 1.0),
///     Sphere::new(Vec3::new(0.0, 0.0, -4.0), 1.0),
/// ];
/// let hit = closest_hit(&spheres, &Ray::new(Vec3::ZERO, -Vec3::Z)).unwrap();
/// assert_eq!((hit.sphere, hit.t), (1, 3.0));
/// ```
#[inline]
#[must_use]
pub fn closest_hit(spheres: &[Sphere], ray: &Ray) -> Option<Hit> {
    let mut best: Option<Hit> = None;
    let mut t_max = ray.t_max;
    for (i, s) in spheres.iter().enumerate() {
        let t = ray_sphere_t(ray, s, t_max);
        if t < t_max {
            t_max = t;
            best = Some(Hit {
                t,
                sphere: i as u32,
            });
        }
    }
    best
}

/// Whether `ray` hits any sphere in `(t_min, t_max)`, stopping at the first
/// one found: the shadow-ray query. Unlike the course's `find_occlusion`
/// (COURSE.md D1), it does not count hits: one blocker is enough, and
/// nothing beyond `t_max` (e.g. behind the light) counts.
///
/// ```
/// use glam::Vec3;
/// use strata::trace::{any_hit, Ray, Sphere};
/// let blocker = [Sphere::new(Vec3::new(0.0, 2.0, 0.0), 0.5)];
/// let to_light = Ray::new(Vec3::ZERO, Vec3::Y).with_range(1e-4, 5.0);
/// assert!(any_hit(&blocker, &to_light));
/// // A light closer than the blocker is not occluded by it.
/// assert!(!any_hit(&blocker, &to_light.with_range(1e-4, 1.0)));
/// ```
#[inline]
#[must_use]
pub fn any_hit(spheres: &[Sphere], ray: &Ray) -> bool {
    spheres
        .iter()
        .any(|s| ray_sphere_t(ray, s, ray.t_max) < f32::INFINITY)
}

/// The SIMD instruction set this build of `strata` runs its 8-wide kernels
/// on, fixed at compile time by the target features. More variants may come
/// with new targets, so matches need a wildcard arm. The order (`Ord`)
/// ranks the x86 levels from `Sse2` to `Avx512`; it means nothing across
/// architectures (`Neon` and `Simd128` sort last).
#[derive(Clone, Copy, Debug, PartialEq, Eq, PartialOrd, Ord)]
#[non_exhaustive]
pub enum SimdLevel {
    /// No SIMD this build knows of: `wide` falls back to arrays of scalars.
    Scalar,
    /// SSE2 (every x86-64): an `f32x8` is two 4-lane halves.
    Sse2,
    /// SSE4.1.
    Sse41,
    /// AVX: one 256-bit register per `f32x8`.
    Avx,
    /// AVX2.
    Avx2,
    /// AVX-512 (F) is available to the build; `f32x8` kernels still use
    /// 256-bit registers.
    Avx512,
    /// NEON (every aarch64): an `f32x8` is two 4-lane halves.
    Neon,
    /// WebAssembly `simd128`: an `f32x8` is two 4-lane halves.
    Simd128,
}

impl SimdLevel {
    /// A short name: `scalar`, `sse2`, `sse4.1`, `avx`, `avx2`, `avx512`,
    /// `neon`, `simd128`.
    #[inline]
    #[must_use]
    pub const fn name(self) -> &'static str {
        match self {
            SimdLevel::Scalar => "scalar",
            SimdLevel::Sse2 => "sse2",
            SimdLevel::Sse41 => "sse4.1",
            SimdLevel::Avx => "avx",
            SimdLevel::Avx2 => "avx2",
            SimdLevel::Avx512 => "avx512",
            SimdLevel::Neon => "neon",
            SimdLevel::Simd128 => "simd128",
        }
    }
}

/// The SIMD level of this build (from `cfg!(target_feature = ...)`). It
/// changes speed only: every level returns the same bits.
///
/// ```
/// use strata::trace::{SimdLevel, simd_level};
/// let level = simd_level();
/// assert!(!level.name().is_empty());
/// if cfg!(target_arch = "aarch64") {
///     assert_eq!(level, SimdLevel::Neon);
/// }
/// ```
#[inline]
#[must_use]
pub const fn simd_level() -> SimdLevel {
    if cfg!(target_feature = "avx512f") {
        SimdLevel::Avx512
    } else if cfg!(target_feature = "avx2") {
        SimdLevel::Avx2
    } else if cfg!(target_feature = "avx") {
        SimdLevel::Avx
    } else if cfg!(target_feature = "sse4.1") {
        SimdLevel::Sse41
    } else if cfg!(target_feature = "sse2") {
        SimdLevel::Sse2
    } else if cfg!(all(target_arch = "aarch64", target_feature = "neon")) {
        SimdLevel::Neon
    } else if cfg!(target_feature = "simd128") {
        SimdLevel::Simd128
    } else {
        SimdLevel::Scalar
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    const UNIT: Sphere = Sphere::new(Vec3::ZERO, 1.0);

    /// Skipping stage two where `may_hit` is unset changes no result: the
    /// kernel equals stage two run on every lane its `valid` allows, for
    /// rays leaving surfaces (outward and inward), passing, inside and
    /// NaN rays, `t_min` from −1 to 1 and NaN.
    #[test]
    fn skipping_rays_that_leave_a_sphere_changes_no_result() {
        use rand_core::Rng;
        let mut rng = rand_pcg::Pcg32::new(11, 3);
        let mut u = || (rng.next_u32() >> 8) as f32 * (1.0 / 16_777_216.0);
        let mut skipped = 0;
        for k in 0..400_000u32 {
            let c = Vec3::new(u() * 20.0 - 10.0, u() * 20.0 - 10.0, u() * 20.0 - 10.0);
            let r = [0.01, 1.0, 1000.0][(k % 3) as usize] * (0.5 + u());
            let d = crate::mapping::sample_uniform_sphere(glam::Vec2::new(u(), u()));
            let n = crate::mapping::sample_uniform_sphere(glam::Vec2::new(u(), u()));
            let s = Sphere::new(c, r);
            let o = match k % 4 {
                // On the surface, nudged out or in by the spawn rule.
                0 => s.spawn_origin_along(n, true),
                1 => s.spawn_origin_along(n, false),
                2 => c + n * r * (u() * 3.0),
                _ => c + n * r * (1.0 + (u() - 0.5) * 1e-6),
            };
            let t_min = match k % 7 {
                0 => -1.0,
                1 => f32::NAN,
                2 => -0.0,
                _ => u() - 0.5,
            };
            let o = if k % 101 == 0 { Vec3::NAN } else { o };
            let ray = RayLanes {
                origin: V3::splat(o),
                dir: V3::splat(d),
                t_min,
                t_max: f32::INFINITY,
            };
            let sphere = s.lanes();
            let q = sphere_quadratic(&ray, &sphere);
            let want = if q.valid {
                sphere_roots(q, t_min, f32::INFINITY)
            } else {
                f32::INFINITY
            };
            let got = sphere_t_live(&ray, &sphere, true);
            assert_eq!(got.to_bits(), want.to_bits(), "ray {k}");
            let brute = sphere_t(&ray, &sphere);
            assert_eq!(brute.to_bits(), want.to_bits(), "ray {k}");
            skipped += usize::from(q.valid && !may_hit(&q, t_min));
        }
        // The case it is for is common: about half the rays leaving outward.
        assert!(skipped > 40_000, "{skipped}");
    }

    #[test]
    fn origin_inside_hits_the_far_side() {
        let r = Ray::new(Vec3::new(0.0, 0.0, 0.5), Vec3::Z);
        assert_eq!(intersect_sphere(&UNIT, &r), Some(0.5));
        let r = Ray::new(Vec3::new(0.0, 0.0, 0.5), -Vec3::Z);
        assert_eq!(intersect_sphere(&UNIT, &r), Some(1.5));
    }

    #[test]
    fn tangent_rays_hit_once_and_near_misses_miss() {
        // Passing at exactly distance r: Δ = 0, a (double) hit.
        let r = Ray::new(Vec3::new(-5.0, 1.0, 0.0), Vec3::X);
        assert_eq!(intersect_sphere(&UNIT, &r), Some(5.0));
        let r = Ray::new(Vec3::new(-5.0, 1.000_001, 0.0), Vec3::X);
        assert_eq!(intersect_sphere(&UNIT, &r), None);
    }

    #[test]
    fn degenerate_spheres_are_never_hit() {
        let r = Ray::new(Vec3::new(0.0, 0.0, -5.0), Vec3::Z);
        for radius in [0.0, -1.0, f32::NAN, -0.0] {
            let s = Sphere::new(Vec3::ZERO, radius);
            assert_eq!(intersect_sphere(&s, &r), None, "radius {radius}");
            assert_eq!(intersect_sphere_naive(&s, &r), None, "radius {radius}");
            assert!(!any_hit(&[s], &r));
        }
    }

    #[test]
    fn interval_ends_are_open() {
        let r = Ray::new(Vec3::new(0.0, 0.0, -5.0), Vec3::Z); // hits at 4 and 6
        assert_eq!(intersect_sphere(&UNIT, &r.with_range(4.0, 10.0)), Some(6.0));
        assert_eq!(intersect_sphere(&UNIT, &r.with_range(0.0, 4.0)), None);
        assert_eq!(intersect_sphere(&UNIT, &r.with_range(3.0, 6.0)), Some(4.0));
        assert_eq!(intersect_sphere(&UNIT, &r.with_range(4.0, 6.0)), None);
        assert_eq!(intersect_sphere(&UNIT, &r.with_range(6.0, 10.0)), None);
        assert_eq!(intersect_sphere(&UNIT, &r.with_range(7.0, 3.0)), None); // empty
        assert_eq!(intersect_sphere(&UNIT, &r.with_range(f32::NAN, 10.0)), None);
    }

    #[test]
    fn huge_and_tiny_coordinates() {
        let far = Sphere::new(Vec3::new(1e7, 0.0, 0.0), 1e3);
        let r = Ray::new(Vec3::ZERO, Vec3::X);
        assert_eq!(intersect_sphere(&far, &r), Some(1e7 - 1e3));
        let tiny = Sphere::new(Vec3::new(0.0, 0.0, -1e-3), 1e-5);
        let t = intersect_sphere(&tiny, &Ray::new(Vec3::ZERO, -Vec3::Z)).unwrap();
        assert!((t - 0.99e-3).abs() < 1e-9, "{t}");
    }

    #[test]
    fn ties_go_to_the_lowest_index() {
        let spheres = [UNIT, Sphere::new(Vec3::new(0.0, 0.0, -10.0), 1.0), UNIT];
        let hit = closest_hit(&spheres, &Ray::new(Vec3::new(0.0, 0.0, 5.0), -Vec3::Z));
        assert_eq!(hit, Some(Hit { t: 4.0, sphere: 0 }));
    }

    /// COURSE.md D1: the course's `find_occlusion` counts hits and calls a
    /// shadow ray blocked only at two or more, on an unnormalised direction
    /// with the interval (1e-6, |d|). A shadow ray from a surface point to
    /// a light, with one blocker between, is occluded here; one with the
    /// blocker behind the light is not; the surface it leaves never counts.
    #[test]
    fn shadow_rays_are_right_where_the_course_is_wrong() {
        let surface = Sphere::new(Vec3::ZERO, 1.0);
        let light = Vec3::new(0.0, 4.0, 0.0);
        let p = surface.spawn_origin(Vec3::Y, true);
        let to_light = (light - p).normalize();
        // Stop short of the light itself (its own sphere is not a blocker).
        let shadow = Ray::new(p, to_light).with_range(0.0, (light - p).length() - 0.05);
        let blocker = Sphere::new(Vec3::new(0.0, 2.5, 0.0), 0.3);
        let behind = Sphere::new(Vec3::new(0.0, 6.0, 0.0), 0.5);
        // One blocker: occluded (the course needs two hits).
        assert!(any_hit(&[surface, blocker], &shadow));
        // Only what lies beyond the light: not occluded (the course's
        // interval (1e-6, |d|²) reaches past the light when |d| > 1).
        assert!(!any_hit(&[surface, behind], &shadow));
        // The surface the ray leaves is never its own blocker.
        assert!(!any_hit(&[surface], &shadow));
        // A light 0.6 away with a blocker 0.4–0.5 along: occluded. (The
        // course's interval ends at t = |d| in units of |d|, 0.36 away in
        // world units, so it never reaches this blocker.)
        let near_light = Vec3::new(0.0, 1.6, 0.0);
        let thin = Sphere::new(Vec3::new(0.0, 1.45, 0.0), 0.05);
        let r = Ray::new(p, Vec3::Y).with_range(0.0, (near_light - p).length());
        assert!(any_hit(&[surface, thin], &r));
    }

    #[test]
    fn trace_types_are_send_and_sync() {
        fn assert_send_sync<T: Send + Sync>() {}
        assert_send_sync::<Ray>();
        assert_send_sync::<Sphere>();
        assert_send_sync::<RayPacket8>();
        assert_send_sync::<HitPacket8>();
        assert_send_sync::<SphereSet<'static>>();
    }

    #[test]
    fn simd_level_matches_target_features() {
        let level = simd_level();
        assert_eq!(
            level == SimdLevel::Avx2 || level == SimdLevel::Avx512,
            cfg!(target_feature = "avx2")
        );
        if cfg!(target_arch = "x86_64") {
            assert!(level >= SimdLevel::Sse2 && level <= SimdLevel::Avx512);
        }
        assert_eq!(level == SimdLevel::Neon, cfg!(target_arch = "aarch64"));
    }
}
