//! The BVH8 over spheres: the [`Bvh`] type, its limits and storage
//! sizing. Its contract (storage, why hits are exact, the build) is
//! documented on [`Bvh`] and [`Bvh::build`], where the public API shows it.
//! The build is in `build`, the queries and their [`BvhStack`] in
//! `traverse`.

mod build;
#[cfg(feature = "alloc")]
mod owned;
mod parts;
mod primitive;
mod traverse;

#[cfg(feature = "alloc")]
pub use owned::{OwnedBvh, OwnedPrimitiveBvh};
pub use primitive::{
    Aabb, PrimitiveBvh, PrimitiveHit, Primitives, any_primitive_hit, closest_primitive_hit,
    primitive_bvh_storage_for,
};
pub use traverse::BvhStack;

use super::Sphere;
use crate::lanes::f32x8;

/// Most spheres in a leaf.
pub(crate) const BVH_LEAF_MAX: usize = 8;

/// Most spheres a [`Bvh`] holds: leaf references keep 27 bits of lane
/// position.
pub const BVH_MAX_SPHERES: usize = 1 << 27;

/// The sphere count from which tracing through a [`Bvh`] takes fewer
/// instructions per ray than the brute-force 1×8 loop
/// ([`closest_hit_1x8`](super::closest_hit_1x8)) on incoherent rays, as
/// a path tracer's bounces are: measured with callgrind on an x86-64-v3
/// build, on scenes of the cover's kind (a ground sphere, three large
/// spheres and small ones scattered evenly) of every size from 8 to 64
/// spheres, the loop is cheaper up to 32 spheres (four 8-wide chunks)
/// and the tree from 33 on, at every size. Whole renders (instructions
/// per path, 8 spp) agree within 2 % but at one size of the sweep (26
/// spheres, where that scene's layout suits the tree: 3.9 %). Coherent
/// rays traced one at a time cross later (camera rays: from 41 spheres);
/// a renderer that traces such rays singly may choose its own threshold.
/// Results are the same bits either way; this only picks the faster.
pub const BVH_MIN_SPHERES: usize = 33;

/// Depth (in node levels) above which splits are binned SAH; below, median
/// splits.
pub(crate) const BVH_SAH_DEPTH: u32 = 16;

/// The deepest a tree can be, in node levels: `BVH_SAH_DEPTH` (16) SAH levels
/// and at most ten median levels (each divides the spheres by 8, and
/// `8¹⁰ · 8 ≥ 2²⁷`).
pub const BVH_MAX_DEPTH: u32 = BVH_SAH_DEPTH + 10;

/// The slack factor `K` of the conservative boxes, in units of `ε = 2⁻²⁴`
/// (see "Why the results are exact" on [`Bvh`], and [`Primitives`] for the
/// caller's primitives).
pub const BVH_SLACK_ULPS: f32 = 128.0;

/// The largest centre coordinate or radius a [`Bvh`] accepts: `2⁶⁰`,
/// where squares and sums of squares still fit an `f32`.
pub const BVH_MAX_COORDINATE: f32 = 1.152_921_5e18;

/// Child references: bit 31 marks a leaf, whose lane start is in bits
/// 3–29 and count − 1 in bits 0–2; otherwise the node index.
const LEAF_BIT: u32 = 1 << 31;

/// [`BVH_SLACK_ULPS`] · ε.
const SLACK: f32 = BVH_SLACK_ULPS / 16_777_216.0;

/// Packet rays that continue alone in a subtree when no more than this
/// many of the 8 reach it, unless [`Bvh::with_packet_fallback`] says
/// otherwise (measured best for camera packets).
const PACKET_FALLBACK: u32 = 2;

/// One node: the boxes of up to eight children as SoA vectors, and the
/// children. Lanes at `count` and beyond are unused.
#[derive(Clone, Copy, Debug)]
pub struct BvhNode8 {
    min_x: f32x8,
    min_y: f32x8,
    min_z: f32x8,
    max_x: f32x8,
    max_y: f32x8,
    max_z: f32x8,
    child: [u32; 8],
    count: u32,
}

impl BvhNode8 {
    /// A node with no children (what storage holds before a build).
    pub const EMPTY: BvhNode8 = BvhNode8 {
        min_x: f32x8::ZERO,
        min_y: f32x8::ZERO,
        min_z: f32x8::ZERO,
        max_x: f32x8::ZERO,
        max_y: f32x8::ZERO,
        max_z: f32x8::ZERO,
        child: [0; 8],
        count: 0,
    };
}

/// The slice lengths a [`Bvh`] of `n` spheres needs.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct BvhStorage {
    /// [`BvhNode8`]s.
    pub nodes: usize,
    /// `f32`s of sphere lanes (four arrays of `n + 7`).
    pub lanes: usize,
    /// `u32` sphere indices, one per lane (`n + 7`).
    pub ids: usize,
}

/// The storage a [`Bvh`] of `n` spheres needs. The node count is a proven
/// bound: every node but a root with fewer than nine spheres has at least
/// two children; one with fewer than eight children has only leaves and
/// more than eight spheres, so at most `n / 9` such nodes exist; counting
/// child slots then gives at most `(5n − 3) / 21` nodes.
///
/// ```
/// use strata::trace::bvh_storage_for;
/// let s = bvh_storage_for(1000);
/// assert_eq!((s.nodes, s.lanes, s.ids), (237, 4 * 1007, 1007));
/// assert_eq!(bvh_storage_for(0).nodes, 1);
/// ```
#[must_use]
#[inline]
pub const fn bvh_storage_for(n: usize) -> BvhStorage {
    // Saturating: sizes past BVH_MAX_SPHERES are refused by the build
    // anyway, and must not overflow here.
    let nodes = if n <= 8 {
        1
    } else {
        n.saturating_mul(5).saturating_sub(3) / 21
    };
    BvhStorage {
        nodes,
        lanes: n.saturating_add(7).saturating_mul(4),
        ids: n.saturating_add(7),
    }
}

/// Why a [`Bvh`] could not be built.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum BvhError {
    /// A storage slice is shorter than [`bvh_storage_for`] requires.
    StorageTooSmall {
        /// Which slice: `"nodes"`, `"lanes"` or `"ids"`.
        slice: &'static str,
        /// Length required.
        needed: usize,
        /// Length provided.
        provided: usize,
    },
    /// More than [`BVH_MAX_SPHERES`] spheres (or primitives).
    TooManySpheres,
    /// A sphere has an infinite centre or radius, or one beyond
    /// [`BVH_MAX_COORDINATE`].
    SphereOutOfRange {
        /// Its index.
        index: usize,
    },
    /// A primitive's box has a NaN, an infinite coordinate or one beyond
    /// [`BVH_MAX_COORDINATE`].
    BoundsOutOfRange {
        /// Its index.
        index: usize,
    },
    /// Storage given to a `from_parts` view is not a tree the build could
    /// have written over these items.
    InvalidStorage {
        /// What is wrong.
        reason: &'static str,
    },
}

impl core::fmt::Display for BvhError {
    #[inline]
    fn fmt(&self, f: &mut core::fmt::Formatter<'_>) -> core::fmt::Result {
        match self {
            BvhError::StorageTooSmall {
                slice,
                needed,
                provided,
            } => write!(
                f,
                "BVH storage too small: `{slice}` needs {needed} entries, {provided} given"
            ),
            BvhError::TooManySpheres => {
                write!(
                    f,
                    "a BVH holds at most {BVH_MAX_SPHERES} spheres or primitives"
                )
            }
            BvhError::SphereOutOfRange { index } => write!(
                f,
                "sphere {index} is infinite or beyond ±{BVH_MAX_COORDINATE:e} (BVH limit)"
            ),
            BvhError::BoundsOutOfRange { index } => write!(
                f,
                "primitive {index}'s box has a NaN, or is infinite or beyond \
                 ±{BVH_MAX_COORDINATE:e} (BVH limit)"
            ),
            BvhError::InvalidStorage { reason } => write!(f, "invalid BVH storage: {reason}"),
        }
    }
}

impl core::error::Error for BvhError {}

/// A BVH8 over spheres in caller storage: one box test covers the eight
/// children of a node with `f32x8`, leaves are runs of up to eight spheres
/// tested with the same 8-wide kernel as the brute-force path. It only
/// skips work: every query returns the bits of the brute-force query it
/// replaces ([`closest_hit`](super::closest_hit), [`any_hit`](super::any_hit)
/// and their 8-wide twins over the same spheres).
///
/// # Storage
///
/// Everything lives in caller slices whose lengths [`bvh_storage_for`]
/// gives for `n` spheres: nodes, the spheres as four SoA lanes arrays
/// (reordered so each leaf is a contiguous run), and the original index of
/// each lane. [`Bvh::build`] checks the lengths before writing anything.
///
/// # Why the results are exact
///
/// The kernel's `t` for one sphere does not depend on the other spheres:
/// it is the first root above `t_min` when that is below `t_max`. So the
/// closest hit is the least such `t`, ties to the lowest index — the
/// brute-force loop's answer — whatever order the spheres are visited in,
/// provided no box test drops a sphere the kernel would report. Boxes are
/// made conservative against the kernel's rounding:
///
/// - The kernel's hit point `o + t d` (with its rounded `t`) lies within
///   `r + K ε (|o|₁ + |c|₁ + r)` of the centre `c` (`K = 128`,
///   `ε = 2⁻²⁴`; a unit test checks a margin of 4 on grazing, tangent,
///   distant and inside rays). The sphere's box
///   gets the `|c|₁ + r` part of that slack at build time, the ray adds the
///   `|o|₁` part at traversal (by moving the slab planes, at no cost per
///   node). The slack also covers the slab test's own rounding.
/// - A child is kept when its entry `t` is `≤` the current closest `t`
///   (not `<`), so a sphere at the same `t` with a lower index is still
///   found.
/// - Zero direction components are replaced by `±10⁻³⁰`, so a slab test
///   never computes `0 × ∞`.
///
/// This holds for unit directions, which every query of
/// [`trace`](crate::trace) requires (its "One contract for every query":
/// with another direction the kernels' roots are not intersections, and
/// the BVH and brute-force answers may differ). Spheres whose
/// centre or radius is infinite, or whose coordinates reach
/// [`BVH_MAX_COORDINATE`] (where the kernel's squares overflow), are
/// refused at build time: use the brute-force path for them.
///
/// # Queries
///
/// The shape of every query in [`trace`](crate::trace): the tree, then the
/// ray or packet, then (packet closest hits) the hits to update, then
/// (`_with`) the caller's [`BvhStack`].
///
///
/// ```
/// use glam::Vec3;
/// use strata::trace::*;
/// let spheres: Vec<Sphere> = (0..100)
///     .map(|i| Sphere::new(Vec3::new(i as f32, 0.0, -5.0), 0.4))
///     .collect();
/// let size = bvh_storage_for(spheres.len());
/// let mut nodes = vec![BvhNode8::EMPTY; size.nodes];
/// let mut lanes = vec![0.0; size.lanes];
/// let mut ids = vec![0; size.ids];
/// let bvh = Bvh::build(&spheres, &mut nodes, &mut lanes, &mut ids).unwrap();
/// let ray = Ray::new(Vec3::new(42.0, 0.0, 0.0), -Vec3::Z);
/// assert_eq!(bvh.closest_hit(&ray), closest_hit(&spheres, &ray));
/// assert_eq!(bvh.closest_hit(&ray).unwrap().sphere, 42);
/// assert!(bvh.any_hit(&ray));
/// ```
#[derive(Clone, Copy, Debug)]
pub struct Bvh<'a> {
    nodes: &'a [BvhNode8],
    cx: &'a [f32],
    cy: &'a [f32],
    cz: &'a [f32],
    r: &'a [f32],
    ids: &'a [u32],
    shape: Shape,
    /// See [`Bvh::with_packet_fallback`].
    packet_fallback: u32,
}

/// What a tree is beyond its storage: the few numbers a view of built
/// storage needs back.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
struct Shape {
    /// Items it was built over (hittable or not).
    len: usize,
    /// Positions `0..outliers` of `ids` (and of sphere lanes) hold the
    /// items kept out of the tree (tested on their own by every query);
    /// the tree's leaves follow.
    outliers: usize,
    /// Nodes in use.
    used_nodes: usize,
    /// Node levels.
    depth: u32,
}

/// Whether the kernel can ever hit `s`.
#[allow(clippy::neg_cmp_op_on_partial_ord)]
fn hittable(s: &Sphere) -> bool {
    s.radius > 0.0 && !s.center.is_nan()
}

impl Bvh<'_> {
    /// Whether this tree was built from exactly `spheres`: the same count,
    /// and every hittable sphere in its lanes with the same bits, once.
    #[inline]
    #[must_use]
    pub fn built_from(&self, spheres: &[Sphere]) -> bool {
        if spheres.len() != self.shape.len {
            return false;
        }
        let mut k = 0;
        while k < self.ids.len() && self.ids[k] != u32::MAX {
            let Some(s) = spheres.get(self.ids[k] as usize) else {
                return false;
            };
            let lane = [self.cx[k], self.cy[k], self.cz[k], self.r[k]].map(f32::to_bits);
            let want = [s.center.x, s.center.y, s.center.z, s.radius].map(f32::to_bits);
            if lane != want {
                return false;
            }
            k += 1;
        }
        // Every hittable sphere once: the ids held are the build's.
        let expected = parts::IdSums::of(
            (0..spheres.len() as u32).filter(|&i| hittable(&spheres[i as usize])),
        );
        parts::IdSums::of(self.ids[..k].iter().copied()) == expected
    }

    /// The number of spheres it was built over (hittable or not).
    #[must_use]
    #[inline]
    pub fn len(&self) -> usize {
        self.shape.len
    }

    /// Whether it was built over no spheres.
    #[must_use]
    #[inline]
    pub fn is_empty(&self) -> bool {
        self.shape.len == 0
    }

    /// Nodes in use (at most [`bvh_storage_for`]`(len).nodes`).
    #[must_use]
    #[inline]
    pub fn node_count(&self) -> usize {
        self.shape.used_nodes
    }

    /// How many spheres were kept out of the tree and are tested on their
    /// own by every query (at most 8; after the tree for closest hits, so
    /// the walk need not wait for them, first for any hit, where they
    /// often end the query): spheres whose box dwarfs the rest of the
    /// scene's, such as a large ground sphere, which inside the tree
    /// would be entered by nearly every ray.
    ///
    /// ```
    /// use glam::Vec3;
    /// use strata::trace::*;
    /// let mut spheres: Vec<Sphere> =
    ///     (0..20).map(|i| Sphere::new(Vec3::new(i as f32, 0.2, 0.0), 0.2)).collect();
    /// spheres.push(Sphere::new(Vec3::new(0.0, -1000.0, 0.0), 1000.0));
    /// let size = bvh_storage_for(spheres.len());
    /// let (mut nodes, mut lanes, mut ids) =
    ///     (vec![BvhNode8::EMPTY; size.nodes], vec![0.0; size.lanes], vec![0; size.ids]);
    /// let bvh = Bvh::build(&spheres, &mut nodes, &mut lanes, &mut ids).unwrap();
    /// assert_eq!(bvh.outliers(), 1);
    /// let down = Ray::new(Vec3::new(0.5, 5.0, 3.0), -Vec3::Y);
    /// assert_eq!(bvh.closest_hit(&down), closest_hit(&spheres, &down));
    /// assert_eq!(bvh.closest_hit(&down).unwrap().sphere, 20);
    /// ```
    #[must_use]
    #[inline]
    pub fn outliers(&self) -> usize {
        self.shape.outliers
    }

    /// Node levels (at most [`BVH_MAX_DEPTH`]).
    #[must_use]
    #[inline]
    pub fn depth(&self) -> u32 {
        self.shape.depth
    }
}

impl Bvh<'_> {
    /// The same tree with another packet fallback, a performance setting
    /// that never changes a result: every value returns the same hits, bit
    /// for bit. Where no more than `rays` of a packet's rays reach a
    /// subtree, [`Bvh::closest_hit_x8`] traces each of them alone through
    /// it (a box test for 8 rays costs about as much as one for a single
    /// ray, so a packet with few rays left wastes most of its lanes). 0
    /// never falls back, 8 or more traces every ray alone; the default, 2,
    /// measured fastest for camera packets.
    ///
    /// ```
    /// use glam::Vec3;
    /// use strata::trace::*;
    /// let spheres: Vec<Sphere> = (0..64)
    ///     .map(|i| Sphere::new(Vec3::new(i as f32, 0.0, -5.0), 0.4))
    ///     .collect();
    /// let size = bvh_storage_for(spheres.len());
    /// let (mut nodes, mut lanes, mut ids) =
    ///     (vec![BvhNode8::EMPTY; size.nodes], vec![0.0; size.lanes], vec![0; size.ids]);
    /// let bvh = Bvh::build(&spheres, &mut nodes, &mut lanes, &mut ids).unwrap();
    /// let rays: Vec<Ray> = (0..8)
    ///     .map(|k| Ray::new(Vec3::new(8.0 * k as f32, 0.0, 0.0), -Vec3::Z))
    ///     .collect();
    /// let packet = RayPacket8::from_rays(&rays);
    /// let hits = [0, 2, 8].map(|fallback| {
    ///     let mut hits = HitPacket8::NONE;
    ///     bvh.with_packet_fallback(fallback).closest_hit_x8(&packet, &mut hits);
    ///     (hits.t().map(f32::to_bits), hits.spheres())
    /// });
    /// assert!(hits.iter().all(|h| *h == hits[0]));
    /// assert_eq!(hits[0].1[3], 24);
    /// ```
    #[must_use]
    #[inline]
    pub fn with_packet_fallback(self, rays: u32) -> Self {
        Self {
            packet_fallback: rays,
            ..self
        }
    }
}

#[cfg(test)]
mod tests {
    use super::BVH_SLACK_ULPS;
    use crate::mapping::sample_uniform_sphere;
    use crate::trace::{Ray, Sphere, intersect_sphere};
    use glam::{Vec2, Vec3};
    use rand_core::Rng;
    use rand_pcg::Pcg32;

    fn range(rng: &mut Pcg32, lo: f32, hi: f32) -> f32 {
        lo + (hi - lo) * ((rng.next_u32() >> 8) as f32 * (1.0 / 16_777_216.0))
    }

    /// The kernel's hit point stays within the slack the boxes are padded
    /// by, with a margin of 4 (the assumption that makes the BVH exact):
    /// grazing and tangent rays (origins nudged off the rim by up to 64
    /// ulps), distant and inside rays, radii from 10⁻⁴ to 1000, centres up
    /// to 10⁴ away. Measured in `f64`.
    #[test]
    fn kernel_hit_points_stay_within_the_box_slack() {
        let mut rng = Pcg32::new(3, 1);
        let mut worst = 0.0f64;
        for k in 0..2_000_000u32 {
            let r = match k % 3 {
                0 => range(&mut rng, 0.01, 1.0),
                1 => range(&mut rng, 1.0, 1000.0),
                _ => range(&mut rng, 1e-4, 0.01),
            };
            let scale = [1.0f32, 100.0, 10_000.0][(k / 3 % 3) as usize];
            let c = Vec3::new(
                range(&mut rng, -scale, scale),
                range(&mut rng, -scale, scale),
                range(&mut rng, -scale, scale),
            );
            let u = Vec2::new(range(&mut rng, 0.0, 1.0), range(&mut rng, 0.0, 1.0));
            let d = sample_uniform_sphere(u);
            let side = d.any_orthonormal_vector();
            let nudge = 1.0 + range(&mut rng, -64.0, 64.0) * f32::EPSILON;
            let dist = range(&mut rng, 0.0, 4.0) * (r + scale);
            let o = c + side * r * nudge - d * dist;
            if let Some(t) = intersect_sphere(&Sphere::new(c, r), &Ray::new(o, d)) {
                let f = |a: f32| a as f64;
                let (o, d, c) = (
                    o.to_array().map(f),
                    d.to_array().map(f),
                    c.to_array().map(f),
                );
                let e: [f64; 3] = core::array::from_fn(|i| o[i] + d[i] * t as f64 - c[i]);
                let excess = crate::float::sqrt(e[0] * e[0] + e[1] * e[1] + e[2] * e[2]) - r as f64;
                let l1 = |v: [f64; 3]| v[0].abs() + v[1].abs() + v[2].abs();
                let slack =
                    BVH_SLACK_ULPS as f64 * f32::EPSILON as f64 / 2.0 * (l1(o) + l1(c) + r as f64);
                worst = worst.max(excess / slack);
            }
        }
        assert!(worst < 0.25, "hit points reach {worst} of the box slack");
    }
}
