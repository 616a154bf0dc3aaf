//! The BVH over the caller's own primitives: [`Primitives`] (bounds and an
//! intersection routine), the brute-force references
//! [`closest_primitive_hit`] and [`any_primitive_hit`], and
//! [`PrimitiveBvh`], the same 8-wide nodes and build as the sphere
//! [`Bvh`](super::Bvh), with leaves that call the caller's routine.

use glam::Vec3;

use super::build::{Box3, Source, build_tree};
use super::traverse::{STACK, walk_any, walk_closest};
use super::{
    BVH_MAX_COORDINATE, BVH_MAX_SPHERES, BvhError, BvhNode8, BvhStack, BvhStorage, LEAF_BIT, SLACK,
    Shape, bvh_storage_for,
};
use crate::trace::Ray;

/// An axis-aligned box: the bounds of one of the caller's primitives.
/// A box with `min > max` on some axis is empty ([`Aabb::EMPTY`]): its
/// primitive is never hit, and a BVH leaves it out.
///
/// ```
/// use glam::Vec3;
/// use strata::trace::Aabb;
/// let b = Aabb::from_points(&[Vec3::ZERO, Vec3::new(1.0, -2.0, 3.0)]);
/// assert_eq!(b, Aabb::new([0.0, -2.0, 0.0], [1.0, 0.0, 3.0]));
/// assert!(b.contains(Vec3::new(0.5, -1.0, 3.0)) && !b.is_empty());
/// assert!(Aabb::EMPTY.is_empty() && Aabb::from_points(&[]).is_empty());
/// ```
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Aabb {
    /// The least corner.
    pub min: Vec3,
    /// The greatest corner.
    pub max: Vec3,
}

impl Aabb {
    /// The empty box (`min = +∞`, `max = −∞`), which grows to any point.
    pub const EMPTY: Aabb = Aabb {
        min: Vec3::INFINITY,
        max: Vec3::NEG_INFINITY,
    };

    /// The box from `min` to `max` (arrays of three `f32` work too).
    #[inline]
    #[must_use]
    pub fn new(min: impl Into<Vec3>, max: impl Into<Vec3>) -> Self {
        Self {
            min: min.into(),
            max: max.into(),
        }
    }

    /// The least box holding every point ([`Aabb::EMPTY`] for none).
    #[inline]
    #[must_use]
    pub fn from_points(points: &[Vec3]) -> Self {
        points.iter().fold(Self::EMPTY, |b, &p| Self {
            min: b.min.min(p),
            max: b.max.max(p),
        })
    }

    /// Whether no point is inside: `min > max` on some axis.
    #[inline]
    #[must_use]
    pub fn is_empty(&self) -> bool {
        self.min.cmpgt(self.max).any()
    }

    /// Whether `p` is inside or on the boundary.
    #[inline]
    #[must_use]
    pub fn contains(&self, p: Vec3) -> bool {
        self.min.cmple(p).all() && p.cmple(self.max).all()
    }

    /// Whether the hit at `t` along `ray` lies in the box, up to
    /// `16 ε (|o|₁ + |b|₁)` (`ε = 2⁻²⁴`, `o` the ray's origin, `|b|₁` the
    /// box's farthest reach from the origin on each axis, summed): the
    /// test an intersection routine applies to its hits to meet
    /// [`Primitives`]' one requirement. The tree's boxes allow
    /// [`BVH_SLACK_ULPS`](super::BVH_SLACK_ULPS)` = 128` such `ε` (less its
    /// slab test's rounding), so hits this keeps are never skipped.
    ///
    /// ```
    /// use strata::trace::{Aabb, Ray};
    /// let b = Aabb::new([0.0, 0.0, 0.0], [1.0, 1.0, 1.0]);
    /// let ray = Ray::new([0.5, 0.5, 5.0], [0.0, 0.0, -1.0]);
    /// assert!(b.holds_hit(&ray, 4.0) && b.holds_hit(&ray, 5.0));
    /// assert!(!b.holds_hit(&ray, 3.9) && !b.holds_hit(&ray, 5.01));
    /// ```
    #[inline]
    #[must_use]
    pub fn holds_hit(&self, ray: &Ray, t: f32) -> bool {
        let p = ray.at(t);
        let reach = self.min.abs().max(self.max.abs()).element_sum();
        // f32::EPSILON is 2ε.
        let tol = 8.0 * f32::EPSILON * (ray.origin.abs().element_sum() + reach);
        self.min.cmple(p + tol).all() && p.cmple(self.max + tol).all()
    }
}

/// The caller's primitives, as a [`PrimitiveBvh`] sees them: a count, a
/// box for each, and an intersection routine. Indices run over
/// `0..len()`; every method must be a pure function of its arguments
/// while a tree built over the primitives is in use.
///
/// **The one requirement.** Every `t` that [`intersect`](Self::intersect)
/// reports (and every hit [`occludes`](Self::occludes) answers `true`
/// for) lies in the primitive's [`bounds`](Self::bounds) as
/// [`Aabb::holds_hit`] tests it: inside the box up to `16 ε` times the
/// ray origin's and the box's 1-norms (`ε = 2⁻²⁴`). A slab test against the box meets
/// it; a ray–triangle test alone does not always (a ray within rounding
/// of the triangle's plane can get a `t` far outside it, watertight tests
/// too): drop hits that `holds_hit` refuses. Then every query of the tree
/// returns exactly what the brute-force loop over the routine
/// ([`closest_primitive_hit`], [`any_primitive_hit`]) returns; the suite
/// checks it on 10⁶ rays over triangles and boxes, with controls whose
/// boxes are too small.
///
/// Rays follow the module's contract (unit `dir`); hits are taken in the
/// ray's open interval `(t_min, t_max)` (a reported `t` outside it, or
/// NaN, is ignored), and ties at equal `t` go to the lowest index.
///
/// ```
/// use glam::Vec3;
/// use strata::trace::{Aabb, Primitives, Ray, closest_primitive_hit};
///
/// /// Planes `z = k` for k in 0..n, each a unit square.
/// struct Tiles(usize);
///
/// impl Primitives for Tiles {
///     type Data = ();
///     fn len(&self) -> usize {
///         self.0
///     }
///     fn bounds(&self, index: usize) -> Aabb {
///         Aabb::new([0.0, 0.0, index as f32], [1.0, 1.0, index as f32])
///     }
///     fn intersect(&self, index: usize, ray: &Ray) -> Option<(f32, ())> {
///         let t = (index as f32 - ray.origin.z) / ray.dir.z;
///         let p = ray.at(t);
///         let inside = (0.0..=1.0).contains(&p.x) && (0.0..=1.0).contains(&p.y);
///         (inside && t > ray.t_min && t < ray.t_max).then_some((t, ()))
///     }
/// }
///
/// let ray = Ray::new([0.5, 0.5, 2.5], [0.0, 0.0, -1.0]);
/// let hit = closest_primitive_hit(&Tiles(5), &ray).unwrap();
/// assert_eq!((hit.primitive, hit.t), (2, 0.5));
/// ```
pub trait Primitives {
    /// What a hit carries besides its `t` (barycentrics, a face, a normal
    /// ...; `()` for nothing). The closest hit returns the one its
    /// routine call reported.
    type Data: Copy;

    /// The number of primitives.
    fn len(&self) -> usize;

    /// Whether there are none.
    #[inline]
    fn is_empty(&self) -> bool {
        self.len() == 0
    }

    /// The box of primitive `index`; empty if it can never be hit. Every
    /// coordinate must be finite and within ±[`BVH_MAX_COORDINATE`]
    /// (a build refuses others).
    fn bounds(&self, index: usize) -> Aabb;

    /// Where `ray` hits primitive `index`, if it does: the `t` of its
    /// first hit in `(t_min, t_max)` and the hit's data.
    fn intersect(&self, index: usize, ray: &Ray) -> Option<(f32, Self::Data)>;

    /// Whether `ray` hits primitive `index` in `(t_min, t_max)` (for
    /// shadow rays). By default [`intersect`](Self::intersect) with the
    /// interval checked; override it with a cheaper test that agrees.
    #[inline]
    fn occludes(&self, index: usize, ray: &Ray) -> bool {
        self.intersect(index, ray)
            .is_some_and(|(t, _)| in_range(t, ray))
    }
}

/// A closest hit among the caller's primitives.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct PrimitiveHit<D> {
    /// Ray parameter of the hit, in the ray's open interval.
    pub t: f32,
    /// Index of the primitive hit.
    pub primitive: u32,
    /// What the routine reported with it.
    pub data: D,
}

/// Whether `t` is in the ray's open interval (false for NaN).
#[inline(always)]
fn in_range(t: f32, ray: &Ray) -> bool {
    t > ray.t_min && t < ray.t_max
}

/// The closest hit among all primitives, testing each in index order: the
/// reference a [`PrimitiveBvh`] reproduces. Ties go to the lowest index.
/// Like the tree, it sees the first [`BVH_MAX_SPHERES`] primitives only
/// (a tree's leaf references keep 27 bits).
///
/// ```
/// use strata::trace::*;
/// struct Walls;
/// impl Primitives for Walls {
///     type Data = ();
///     fn len(&self) -> usize { 3 }
///     fn bounds(&self, i: usize) -> Aabb { Aabb::new([-1.0, -1.0, 2.0], [1.0, 1.0, 2.0]) }
///     fn intersect(&self, i: usize, ray: &Ray) -> Option<(f32, ())> {
///         // Three walls at z = 2 (a tie): the lowest index wins.
///         let t = (2.0 - ray.origin.z) / ray.dir.z;
///         (t > ray.t_min && t < ray.t_max).then_some((t, ()))
///     }
/// }
/// let hit = closest_primitive_hit(&Walls, &Ray::new([0.0; 3], [0.0, 0.0, 1.0])).unwrap();
/// assert_eq!((hit.t, hit.primitive), (2.0, 0));
/// assert!(any_primitive_hit(&Walls, &Ray::new([0.0; 3], [0.0, 0.0, 1.0])));
/// ```
#[must_use]
#[inline]
pub fn closest_primitive_hit<P: Primitives + ?Sized>(
    prims: &P,
    ray: &Ray,
) -> Option<PrimitiveHit<P::Data>> {
    let mut best: Option<PrimitiveHit<P::Data>> = None;
    for index in 0..prims.len().min(BVH_MAX_SPHERES) {
        if let Some((t, data)) = prims.intersect(index, ray)
            && in_range(t, ray)
            && best.is_none_or(|b| t < b.t)
        {
            best = Some(PrimitiveHit {
                t,
                primitive: index as u32,
                data,
            });
        }
    }
    best
}

/// Whether any primitive occludes `ray` ([`Primitives::occludes`]), in
/// index order, stopping at the first (of the first [`BVH_MAX_SPHERES`],
/// like [`closest_primitive_hit`]).
#[must_use]
#[inline]
pub fn any_primitive_hit<P: Primitives + ?Sized>(prims: &P, ray: &Ray) -> bool {
    (0..prims.len().min(BVH_MAX_SPHERES)).any(|index| prims.occludes(index, ray))
}

/// The slice lengths a [`PrimitiveBvh`] over `n` primitives needs: the
/// nodes of [`bvh_storage_for`]`(n)`, one `u32` id per primitive, no
/// lanes (the primitives stay in the caller's hands).
///
/// ```
/// use strata::trace::{bvh_storage_for, primitive_bvh_storage_for};
/// let s = primitive_bvh_storage_for(1000);
/// assert_eq!((s.nodes, s.lanes, s.ids), (bvh_storage_for(1000).nodes, 0, 1000));
/// ```
#[must_use]
#[inline]
pub const fn primitive_bvh_storage_for(n: usize) -> BvhStorage {
    BvhStorage {
        nodes: bvh_storage_for(n).nodes,
        lanes: 0,
        ids: n,
    }
}

/// The caller's primitives as the build sees them: padded boxes
/// (conservative against rounding, as sphere boxes are), centroids and
/// sizes of the boxes as given.
pub(super) struct Padded<'p, P: ?Sized>(pub(super) &'p P);

/// The box of `b` grown by `SLACK` times its 1-norm distance from the
/// origin; [`Box3::EMPTY`] for an empty box.
pub(super) fn padded(b: &Aabb) -> Box3 {
    if b.is_empty() {
        return Box3::EMPTY;
    }
    let reach = b.min.abs().max(b.max.abs());
    let pad = (reach.x + reach.y + reach.z) * SLACK;
    Box3 {
        min: (b.min - Vec3::splat(pad)).to_array(),
        max: (b.max + Vec3::splat(pad)).to_array(),
    }
}

impl<P: Primitives + ?Sized> Source for Padded<'_, P> {
    #[inline]
    fn bounds(&self, id: u32) -> Box3 {
        padded(&self.0.bounds(id as usize))
    }
    #[inline]
    fn centroid(&self, id: u32) -> [f32; 3] {
        let b = self.0.bounds(id as usize);
        // Halves first: no overflow near the coordinate limit.
        (b.min * 0.5 + b.max * 0.5).to_array()
    }
    #[inline]
    fn size(&self, id: u32) -> f32 {
        let b = self.0.bounds(id as usize);
        let e = b.max - b.min;
        e.x * e.y + e.y * e.z + e.z * e.x
    }
}

/// Whether a box's coordinates are all finite and within the BVH's range.
pub(super) fn bounds_in_range(b: &Aabb) -> bool {
    let ok = |v: Vec3| v.abs().cmplt(Vec3::splat(BVH_MAX_COORDINATE)).all();
    ok(b.min) && ok(b.max)
}

/// A BVH8 over the caller's primitives: the sphere [`Bvh`](super::Bvh)'s
/// nodes, build and traversal, with leaves of up to eight primitive ids
/// whose hits the caller's [`Primitives::intersect`] reports. Storage is
/// the caller's ([`primitive_bvh_storage_for`] gives the lengths); the
/// tree borrows the primitives it was built over, so a query cannot pass
/// others.
///
/// What it promises: the traversal of the sphere tree, and — when the
/// routine keeps its hits inside its boxes ([`Primitives`]' one
/// requirement) — exactly the hit [`closest_primitive_hit`] and the
/// answer [`any_primitive_hit`] give, ties to the lowest index.
///
/// ```
/// use glam::Vec3;
/// use strata::trace::*;
///
/// /// Unit cubes `[k, k + 1] × [0, 1] × [0, 1]`.
/// struct Cubes(usize);
/// impl Primitives for Cubes {
///     type Data = ();
///     fn len(&self) -> usize { self.0 }
///     fn bounds(&self, i: usize) -> Aabb {
///         Aabb::new([i as f32, 0.0, 0.0], [i as f32 + 1.0, 1.0, 1.0])
///     }
///     fn intersect(&self, i: usize, ray: &Ray) -> Option<(f32, ())> {
///         let b = self.bounds(i);
///         let (t0, t1) = ((b.min - ray.origin) / ray.dir, (b.max - ray.origin) / ray.dir);
///         let (near, far) = (t0.min(t1).max_element(), t0.max(t1).min_element());
///         let t = if near > ray.t_min { near } else { far };
///         (near <= far && t > ray.t_min && t < ray.t_max).then_some((t, ()))
///     }
/// }
///
/// let cubes = Cubes(100);
/// let size = primitive_bvh_storage_for(cubes.len());
/// let mut nodes = vec![BvhNode8::EMPTY; size.nodes];
/// let mut ids = vec![0; size.ids];
/// let bvh = PrimitiveBvh::build(&cubes, &mut nodes, &mut ids).unwrap();
/// let ray = Ray::new([42.5, 0.5, 5.0], [0.0, 0.0, -1.0]);
/// let hit = bvh.closest_hit(&ray).unwrap();
/// assert_eq!((hit.primitive, hit.t), (42, 4.0));
/// assert_eq!(Some(hit), closest_primitive_hit(&cubes, &ray));
/// assert!(bvh.any_hit(&ray) && !bvh.any_hit(&Ray::new([42.5, 0.5, 5.0], [0.0, 0.0, 1.0])));
/// ```
pub struct PrimitiveBvh<'a, P: ?Sized> {
    prims: &'a P,
    nodes: &'a [BvhNode8],
    /// Primitive ids: outliers, then the leaves' runs, then `u32::MAX`
    /// for primitives that can never be hit.
    ids: &'a [u32],
    shape: Shape,
}

// Without requiring `P: Debug`: the tree's shape, not the primitives.
impl<P: ?Sized> core::fmt::Debug for PrimitiveBvh<'_, P> {
    #[inline]
    fn fmt(&self, f: &mut core::fmt::Formatter<'_>) -> core::fmt::Result {
        f.debug_struct("PrimitiveBvh")
            .field("len", &self.shape.len)
            .field("nodes", &self.shape.used_nodes)
            .field("depth", &self.shape.depth)
            .field("outliers", &self.shape.outliers)
            .finish_non_exhaustive()
    }
}

// Copy without requiring `P: Copy` (only a reference is held).
impl<P: ?Sized> Clone for PrimitiveBvh<'_, P> {
    #[inline]
    fn clone(&self) -> Self {
        *self
    }
}

impl<P: ?Sized> Copy for PrimitiveBvh<'_, P> {}

impl<'a, P: Primitives + ?Sized> PrimitiveBvh<'a, P> {
    /// Builds the tree over `prims` into the two storage slices (at least
    /// [`primitive_bvh_storage_for`]`(prims.len())` long; longer is fine):
    /// the sphere build (binned SAH, then median splits; deterministic),
    /// over each primitive's padded box and its centre. Primitives with
    /// empty boxes are left out; a box with a NaN or a coordinate beyond
    /// ±[`BVH_MAX_COORDINATE`] is refused. `bounds` is called
    /// `O(n log n)` times, so it should be cheap. On error nothing is
    /// written.
    ///
    /// ```
    /// use strata::trace::*;
    /// struct Points;
    /// impl Primitives for Points {
    ///     type Data = ();
    ///     fn len(&self) -> usize { 2 }
    ///     fn bounds(&self, i: usize) -> Aabb {
    ///         if i == 0 { Aabb::new([0.0; 3], [1.0; 3]) } else { Aabb::new([f32::NAN; 3], [0.0; 3]) }
    ///     }
    ///     fn intersect(&self, _: usize, _: &Ray) -> Option<(f32, ())> { None }
    /// }
    /// let (mut nodes, mut ids) = ([BvhNode8::EMPTY; 1], [0u32; 2]);
    /// let err = PrimitiveBvh::build(&Points, &mut nodes, &mut ids).unwrap_err();
    /// assert_eq!(err, BvhError::BoundsOutOfRange { index: 1 });
    /// ```
    #[inline]
    pub fn build(
        prims: &'a P,
        nodes: &'a mut [BvhNode8],
        ids: &'a mut [u32],
    ) -> Result<Self, BvhError> {
        let n = prims.len();
        if n > BVH_MAX_SPHERES {
            return Err(BvhError::TooManySpheres);
        }
        let need = primitive_bvh_storage_for(n);
        for (slice, needed, provided) in [
            ("nodes", need.nodes, nodes.len()),
            ("ids", need.ids, ids.len()),
        ] {
            if provided < needed {
                return Err(BvhError::StorageTooSmall {
                    slice,
                    needed,
                    provided,
                });
            }
        }
        for index in 0..n {
            let b = prims.bounds(index);
            if b.min.is_nan() || b.max.is_nan() || (!b.is_empty() && !bounds_in_range(&b)) {
                return Err(BvhError::BoundsOutOfRange { index });
            }
        }
        let ids = &mut ids[..n];
        let mut m = 0;
        for index in 0..n {
            if !prims.bounds(index).is_empty() {
                ids[m] = index as u32;
                m += 1;
            }
        }
        ids[m..].fill(u32::MAX);
        let nodes = &mut nodes[..need.nodes];
        let shape = build_tree(&Padded(prims), nodes, ids, m);
        Ok(Self::assemble(prims, nodes, ids, Shape { len: n, ..shape }))
    }

    /// The tree's shape (for an owner of the storage).
    #[cfg(feature = "alloc")]
    pub(super) fn shape(&self) -> Shape {
        self.shape
    }

    /// The view of checked or freshly built parts.
    pub(super) fn assemble(
        prims: &'a P,
        nodes: &'a [BvhNode8],
        ids: &'a [u32],
        shape: Shape,
    ) -> Self {
        Self {
            prims,
            nodes,
            ids,
            shape,
        }
    }

    /// The primitives it was built over.
    #[must_use]
    #[inline]
    pub fn primitives(&self) -> &'a P {
        self.prims
    }

    /// The closest hit of `ray`: [`closest_primitive_hit`] over its
    /// primitives (see [`Primitives`] for the requirement that makes it so).
    #[must_use]
    #[inline]
    pub fn closest_hit(&self, ray: &Ray) -> Option<PrimitiveHit<P::Data>> {
        self.closest_on(ray, &mut [(0, 0.0); STACK])
    }

    /// [`PrimitiveBvh::closest_hit`] on the caller's reusable `stack`.
    #[must_use]
    #[inline]
    pub fn closest_hit_with(
        &self,
        ray: &Ray,
        stack: &mut BvhStack,
    ) -> Option<PrimitiveHit<P::Data>> {
        self.closest_on(ray, &mut stack.closest)
    }

    fn closest_on(
        &self,
        ray: &Ray,
        stack: &mut [(u32, f32); STACK],
    ) -> Option<PrimitiveHit<P::Data>> {
        let (prims, ids) = (self.prims, self.ids);
        let mut best: Option<PrimitiveHit<P::Data>> = None;
        // The closest t so far; the ray's t_max before any hit, which no
        // accepted t reaches.
        let mut far = ray.t_max;
        let mut consider = |id: u32, far: &mut f32| {
            if let Some((t, data)) = prims.intersect(id as usize, ray)
                && in_range(t, ray)
                && (t < *far || (t == *far && best.is_some_and(|b| id < b.primitive)))
            {
                *far = t;
                best = Some(PrimitiveHit {
                    t,
                    primitive: id,
                    data,
                });
            }
        };
        walk_closest(self.nodes, 0, ray, &mut far, stack, |entry, far| {
            let start = ((entry & !LEAF_BIT) >> 3) as usize;
            let count = (entry & 7) as usize + 1;
            for &id in &ids[start..start + count] {
                consider(id, far);
            }
        });
        // The outliers after the tree, as the sphere tree does.
        for &id in &ids[..self.shape.outliers] {
            consider(id, &mut far);
        }
        best
    }

    /// Whether `ray` hits any primitive: [`any_primitive_hit`] over its
    /// primitives.
    #[must_use]
    #[inline]
    pub fn any_hit(&self, ray: &Ray) -> bool {
        self.any_on(ray, &mut [0; STACK])
    }

    /// [`PrimitiveBvh::any_hit`] on the caller's reusable `stack`.
    #[must_use]
    #[inline]
    pub fn any_hit_with(&self, ray: &Ray, stack: &mut BvhStack) -> bool {
        self.any_on(ray, &mut stack.any)
    }

    fn any_on(&self, ray: &Ray, stack: &mut [u32; STACK]) -> bool {
        let (prims, ids) = (self.prims, self.ids);
        // Outliers first: a ground often ends the query at once.
        if ids[..self.shape.outliers]
            .iter()
            .any(|&id| prims.occludes(id as usize, ray))
        {
            return true;
        }
        walk_any(self.nodes, ray, stack, |entry| {
            let start = ((entry & !LEAF_BIT) >> 3) as usize;
            let count = (entry & 7) as usize + 1;
            ids[start..start + count]
                .iter()
                .any(|&id| prims.occludes(id as usize, ray))
        })
    }
}

impl<P: ?Sized> PrimitiveBvh<'_, P> {
    /// The number of primitives it was built over (hittable or not).
    #[must_use]
    #[inline]
    pub fn len(&self) -> usize {
        self.shape.len
    }

    /// Whether it was built over no primitives.
    #[must_use]
    #[inline]
    pub fn is_empty(&self) -> bool {
        self.shape.len == 0
    }

    /// Nodes in use.
    #[must_use]
    #[inline]
    pub fn node_count(&self) -> usize {
        self.shape.used_nodes
    }

    /// Node levels (at most [`BVH_MAX_DEPTH`](super::BVH_MAX_DEPTH)).
    #[must_use]
    #[inline]
    pub fn depth(&self) -> u32 {
        self.shape.depth
    }

    /// How many primitives were kept out of the tree and are tested on
    /// their own by every query (at most 8): those whose box's surface
    /// dwarfs the rest's, as on the sphere tree ([`Bvh::outliers`](super::Bvh::outliers)).
    #[must_use]
    #[inline]
    pub fn outliers(&self) -> usize {
        self.shape.outliers
    }
}
