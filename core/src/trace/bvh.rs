//! A wide bounding volume hierarchy over spheres (BVH8): one box test
//! covers the eight children of a node with `f32x8`, leaves are runs of up
//! to eight spheres tested with the same 8-wide kernel as the brute-force
//! path. It only skips work: every query returns the bits of the
//! brute-force query it replaces.
//!
//! # Storage
//!
//! Everything lives in caller slices whose lengths [`bvh_storage_for`]
//! gives for `n` spheres: nodes, the spheres as four SoA lanes arrays
//! (reordered so each leaf is a contiguous run), and the original index of
//! each lane. [`Bvh::build`] checks the lengths before writing anything.
//!
//! # Build
//!
//! Top-down and single-threaded, so the tree depends only on the spheres
//! and their order. A node's children are made by repeatedly splitting the
//! child with the largest box surface (among those with more than
//! `BVH_LEAF_MAX` = 8 spheres) until there are eight or none can split.
//! Splits are binned SAH (16 bins of the centroid bounds, on each axis)
//! down to depth `BVH_SAH_DEPTH` = 16; below it, and wherever all centroids
//! coincide, a split at the median of the longest centroid axis (ties by
//! sphere index). Median splits divide the spheres by eight per level, so
//! the tree is at most [`BVH_MAX_DEPTH`] nodes deep for up to
//! [`BVH_MAX_SPHERES`] spheres. Spheres that can never be hit (radius
//! `≤ 0` or NaN, a NaN centre) are left out.
//!
//! # Why the results are exact
//!
//! The kernel's `t` for one sphere does not depend on the other spheres:
//! it is the first root above `t_min` when that is below `t_max`. So the
//! closest hit is the least such `t`, ties to the lowest index — the
//! brute-force loop's answer — whatever order the spheres are visited in,
//! provided no box test drops a sphere the kernel would report. Boxes are
//! made conservative against the kernel's rounding:
//!
//! - The kernel's hit point `o + t d` (with its rounded `t`) lies within
//!   `r + K ε (|o|₁ + |c|₁ + r)` of the centre `c` (`K` =
//!   [`BVH_SLACK_ULPS`], `ε = 2⁻²⁴`; `tests/tracing/bvh.rs` checks a margin of 4
//!   on grazing, tangent, distant and inside rays). The sphere's box gets
//!   the `|c|₁ + r` part of that slack at build time, the ray adds the
//!   `|o|₁` part at traversal (by moving the slab planes, at no cost per
//!   node). The slack also covers the slab test's own rounding.
//! - A child is kept when its entry `t` is `≤` the current closest `t`
//!   (not `<`), so a sphere at the same `t` with a lower index is still
//!   found.
//! - Zero direction components are replaced by `±10⁻³⁰`, so a slab test
//!   never computes `0 × ∞`.
//!
//! This holds for unit directions, as the kernels require. Spheres whose
//! centre or radius is infinite, or whose coordinates reach
//! [`BVH_MAX_COORDINATE`] (where the kernel's squares overflow), are
//! refused at build time: use the brute-force path for them.

use wide::{f32x8, i32x8};

use super::lanes::{lanes_bitmask, lanes_select, lanes_select_i32, mask_from_bits};
use super::packet::HitPacket8;
use super::{Hit, Ray, RayPacket8, Sphere, sphere_t};

/// Most spheres in a leaf.
pub(crate) const BVH_LEAF_MAX: usize = 8;

/// Most spheres a [`Bvh`] holds: leaf references keep 27 bits of lane
/// position.
pub const BVH_MAX_SPHERES: usize = 1 << 27;

/// Depth (in node levels) above which splits are binned SAH; below, median
/// splits.
pub(crate) const BVH_SAH_DEPTH: u32 = 16;

/// The deepest a tree can be, in node levels: `BVH_SAH_DEPTH` (16) SAH levels
/// and at most ten median levels (each divides the spheres by 8, and
/// `8¹⁰ · 8 ≥ 2²⁷`).
pub const BVH_MAX_DEPTH: u32 = BVH_SAH_DEPTH + 10;

/// The slack factor `K` of the conservative boxes, in units of `ε = 2⁻²⁴`
/// (see the module docs).
pub const BVH_SLACK_ULPS: f32 = 128.0;

/// The largest centre coordinate or radius a [`Bvh`] accepts: `2⁶⁰`,
/// where squares and sums of squares still fit an `f32`.
pub const BVH_MAX_COORDINATE: f32 = 1.152_921_5e18;

/// Traversal stack entries: every visited node pushes at most 8 and pops
/// one, so `7 ·` [`BVH_MAX_DEPTH`] `+ 1` suffice.
const STACK: usize = 7 * BVH_MAX_DEPTH as usize + 1;

/// Reusable traversal memory for [`Bvh`] queries: keep one per thread (or
/// per tile) and pass it to the `_with` queries. It is zeroed once, when
/// made; queries only read entries they wrote, so it is never cleared
/// again (the queries without `_with` clear a fresh stack of their own,
/// 0.7–3.6 KB, on every call).
///
/// ```
/// use glam::Vec3;
/// use strata::trace::{Bvh, BvhNode8, BvhStack, Ray, Sphere, bvh_storage_for};
/// let spheres = [Sphere::new(Vec3::new(0.0, 0.0, -3.0), 1.0)];
/// let size = bvh_storage_for(1);
/// let (mut nodes, mut lanes, mut ids) =
///     (vec![BvhNode8::EMPTY; size.nodes], vec![0.0; size.lanes], vec![0; size.ids]);
/// let bvh = Bvh::build(&spheres, &mut nodes, &mut lanes, &mut ids).unwrap();
/// let mut stack = BvhStack::new();
/// let ray = Ray::new(Vec3::ZERO, -Vec3::Z);
/// assert_eq!(bvh.closest_hit_with(&ray, &mut stack).map(|h| h.t), Some(2.0));
/// assert!(bvh.any_hit_with(&ray, &mut stack));
/// ```
#[derive(Clone, Debug)]
pub struct BvhStack {
    /// Closest-hit traversal of one ray: (child, entry distance).
    closest: [(u32, f32); STACK],
    /// Any-hit traversal of one ray.
    any: [u32; STACK],
    /// Packet traversal: (child, lanes that enter it).
    packet: [(u32, u8); STACK],
}

impl BvhStack {
    /// A stack for every query of any [`Bvh`] (its size covers
    /// [`BVH_MAX_DEPTH`]).
    #[inline]
    #[must_use]
    pub const fn new() -> Self {
        Self {
            closest: [(0, 0.0); STACK],
            any: [0; STACK],
            packet: [(0, 0); STACK],
        }
    }
}

impl Default for BvhStack {
    #[inline]
    fn default() -> Self {
        Self::new()
    }
}

/// Child references: bit 31 marks a leaf, whose lane start is in bits
/// 3–29 and count − 1 in bits 0–2; otherwise the node index.
const LEAF_BIT: u32 = 1 << 31;

const SLACK: f32 = BVH_SLACK_ULPS / 16_777_216.0;

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
    /// More than [`BVH_MAX_SPHERES`] spheres.
    TooManySpheres,
    /// A sphere has an infinite centre or radius, or one beyond
    /// [`BVH_MAX_COORDINATE`].
    SphereOutOfRange {
        /// Its index.
        index: usize,
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
                write!(f, "a BVH holds at most {BVH_MAX_SPHERES} spheres")
            }
            BvhError::SphereOutOfRange { index } => write!(
                f,
                "sphere {index} is infinite or beyond ±{BVH_MAX_COORDINATE:e} (BVH limit)"
            ),
        }
    }
}

impl core::error::Error for BvhError {}

/// A BVH8 over spheres in caller storage (see the module docs).
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
/// assert_eq!(bvh.closest_hit(&ray), closest_hit(&ray, &spheres));
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
    len: usize,
    used_nodes: usize,
    depth: u32,
}

/// An axis-aligned box.
#[derive(Clone, Copy, Debug)]
struct Aabb {
    min: [f32; 3],
    max: [f32; 3],
}

impl Aabb {
    const EMPTY: Aabb = Aabb {
        min: [f32::INFINITY; 3],
        max: [f32::NEG_INFINITY; 3],
    };

    fn grow(&mut self, o: &Aabb) {
        for k in 0..3 {
            if o.min[k] < self.min[k] {
                self.min[k] = o.min[k];
            }
            if o.max[k] > self.max[k] {
                self.max[k] = o.max[k];
            }
        }
    }

    fn grow_point(&mut self, p: [f32; 3]) {
        self.grow(&Aabb { min: p, max: p });
    }

    /// Half the surface area (what SAH compares); 0 for an empty box.
    fn half_area(&self) -> f32 {
        let e = [
            self.max[0] - self.min[0],
            self.max[1] - self.min[1],
            self.max[2] - self.min[2],
        ];
        if e[0] < 0.0 {
            return 0.0;
        }
        e[0] * e[1] + e[1] * e[2] + e[2] * e[0]
    }
}

/// The conservative box of a sphere (module docs).
fn sphere_box(s: &Sphere) -> Aabb {
    let c = s.center;
    let pad = s.radius + (c.x.abs() + c.y.abs() + c.z.abs() + s.radius) * SLACK;
    Aabb {
        min: [c.x - pad, c.y - pad, c.z - pad],
        max: [c.x + pad, c.y + pad, c.z + pad],
    }
}

fn centroid(s: &Sphere) -> [f32; 3] {
    [s.center.x, s.center.y, s.center.z]
}

/// Whether the kernel can ever hit `s`.
#[allow(clippy::neg_cmp_op_on_partial_ord)]
fn hittable(s: &Sphere) -> bool {
    s.radius > 0.0 && !s.center.is_nan()
}

struct Builder<'s, 'b> {
    spheres: &'s [Sphere],
    nodes: &'b mut [BvhNode8],
    ids: &'b mut [u32],
    used: usize,
    depth: u32,
}

const BINS: usize = 16;

impl Builder<'_, '_> {
    fn bounds(&self, lo: usize, hi: usize) -> (Aabb, Aabb) {
        let mut b = Aabb::EMPTY;
        let mut c = Aabb::EMPTY;
        for &id in &self.ids[lo..hi] {
            let s = &self.spheres[id as usize];
            b.grow(&sphere_box(s));
            c.grow_point(centroid(s));
        }
        (b, c)
    }

    /// Splits `ids[lo..hi]` (more than one sphere) in two; returns the
    /// first index of the right part, strictly inside.
    fn split(&mut self, lo: usize, hi: usize, depth: u32) -> usize {
        let (_, cb) = self.bounds(lo, hi);
        let ext = [
            cb.max[0] - cb.min[0],
            cb.max[1] - cb.min[1],
            cb.max[2] - cb.min[2],
        ];
        let spread = ext.iter().any(|&e| e > 0.0);
        if depth < BVH_SAH_DEPTH
            && spread
            && let Some(mid) = self.sah_split(lo, hi, &cb, &ext)
        {
            return mid;
        }
        // Median of the longest centroid axis, ties by sphere index: the
        // same halves whatever order the ids are in.
        let axis = longest(&ext);
        let mid = lo + (hi - lo) / 2;
        let spheres = self.spheres;
        self.ids[lo..hi].select_nth_unstable_by(mid - lo, |&a, &b| {
            let ca = centroid(&spheres[a as usize])[axis];
            let cb = centroid(&spheres[b as usize])[axis];
            ca.total_cmp(&cb).then(a.cmp(&b))
        });
        mid
    }

    fn sah_split(&mut self, lo: usize, hi: usize, cb: &Aabb, ext: &[f32; 3]) -> Option<usize> {
        let bin_of = |s: &Sphere, axis: usize| -> usize {
            let x = (centroid(s)[axis] - cb.min[axis]) / ext[axis] * BINS as f32;
            // Truncation floors (x ≥ 0); the max centroid clamps to the last bin.
            (x as usize).min(BINS - 1)
        };
        let mut best: Option<(f32, usize, usize)> = None; // (cost, axis, split bin)
        for (axis, &e) in ext.iter().enumerate() {
            if e <= 0.0 {
                continue;
            }
            let mut boxes = [Aabb::EMPTY; BINS];
            let mut counts = [0u32; BINS];
            for &id in &self.ids[lo..hi] {
                let s = &self.spheres[id as usize];
                let b = bin_of(s, axis);
                boxes[b].grow(&sphere_box(s));
                counts[b] += 1;
            }
            // Right-to-left sweep of areas × counts.
            let mut right_cost = [0.0f32; BINS];
            let mut acc = Aabb::EMPTY;
            let mut n = 0u32;
            for b in (1..BINS).rev() {
                acc.grow(&boxes[b]);
                n += counts[b];
                right_cost[b] = acc.half_area() * n as f32;
            }
            let mut acc = Aabb::EMPTY;
            let mut n = 0u32;
            for b in 1..BINS {
                acc.grow(&boxes[b - 1]);
                n += counts[b - 1];
                let cost = acc.half_area() * n as f32 + right_cost[b];
                if best.is_none_or(|(c, _, _)| cost < c) {
                    best = Some((cost, axis, b));
                }
            }
        }
        let (_, axis, split) = best?;
        // Partition in place: bins below `split` first.
        let spheres = self.spheres;
        let ids = &mut self.ids[lo..hi];
        let mut left = 0;
        for k in 0..ids.len() {
            if bin_of(&spheres[ids[k] as usize], axis) < split {
                ids.swap(left, k);
                left += 1;
            }
        }
        (left > 0 && left < ids.len()).then_some(lo + left)
    }

    /// Builds node `index` over `ids[lo..hi]` at `depth` (1 for the root).
    fn node(&mut self, index: usize, lo: usize, hi: usize, depth: u32) {
        self.depth = self.depth.max(depth);
        // Children as (start, end, box); the priority of splitting is the
        // box surface in SAH levels, the sphere count in median levels
        // (which keeps the depth bound).
        let priority = |b: &Builder<'_, '_>, lo: usize, hi: usize| -> (Aabb, f32) {
            let bx = b.bounds(lo, hi).0;
            let p = if depth < BVH_SAH_DEPTH {
                bx.half_area()
            } else {
                (hi - lo) as f32
            };
            (bx, p)
        };
        let mut ranges = [(0usize, 0usize, Aabb::EMPTY, 0.0f32); 8];
        let (bx, p) = priority(self, lo, hi);
        ranges[0] = (lo, hi, bx, p);
        let mut count = 1;
        while count < 8 {
            // The splittable child of highest priority; ties to the first.
            let mut pick: Option<(usize, f32)> = None;
            for (k, &(a, b, _, p)) in ranges[..count].iter().enumerate() {
                if b - a > BVH_LEAF_MAX && pick.is_none_or(|(_, best)| p > best) {
                    pick = Some((k, p));
                }
            }
            let Some((k, _)) = pick else { break };
            let (a, b, _, _) = ranges[k];
            let mid = self.split(a, b, depth);
            let (bl, pl) = priority(self, a, mid);
            let (br, pr) = priority(self, mid, b);
            ranges[k] = (a, mid, bl, pl);
            ranges[count] = (mid, b, br, pr);
            count += 1;
        }
        let mut node = BvhNode8::EMPTY;
        let mut min = [[0.0f32; 8]; 3];
        let mut max = [[0.0f32; 8]; 3];
        for (k, &(a, b, bx, _)) in ranges[..count].iter().enumerate() {
            for axis in 0..3 {
                min[axis][k] = bx.min[axis];
                max[axis][k] = bx.max[axis];
            }
            node.child[k] = if b - a <= BVH_LEAF_MAX {
                LEAF_BIT | (a as u32) << 3 | (b - a - 1) as u32
            } else {
                let child = self.used;
                self.used += 1;
                self.node(child, a, b, depth + 1);
                child as u32
            };
        }
        node.min_x = f32x8::new(min[0]);
        node.min_y = f32x8::new(min[1]);
        node.min_z = f32x8::new(min[2]);
        node.max_x = f32x8::new(max[0]);
        node.max_y = f32x8::new(max[1]);
        node.max_z = f32x8::new(max[2]);
        node.count = count as u32;
        self.nodes[index] = node;
    }
}

fn longest(ext: &[f32; 3]) -> usize {
    let mut axis = 0;
    for k in 1..3 {
        if ext[k] > ext[axis] {
            axis = k;
        }
    }
    axis
}

/// A ray prepared for slab tests against 8 boxes: slab planes moved by the
/// ray's slack, reciprocal directions without zeros.
struct SlabRay {
    lo: [f32x8; 3],
    hi: [f32x8; 3],
    inv: [f32x8; 3],
}

impl SlabRay {
    fn new(ray: &Ray) -> Self {
        let o = ray.origin;
        let s = (o.x.abs() + o.y.abs() + o.z.abs()) * SLACK;
        let inv = |d: f32| {
            // ±1e-30 for a zero component keeps 0 × ∞ out of the slabs.
            let d = if d == 0.0 { 1e-30f32.copysign(d) } else { d };
            f32x8::splat(1.0 / d)
        };
        Self {
            // Box min planes move by −s, max planes by +s: subtracting
            // o + s and o − s does both.
            lo: [
                f32x8::splat(o.x + s),
                f32x8::splat(o.y + s),
                f32x8::splat(o.z + s),
            ],
            hi: [
                f32x8::splat(o.x - s),
                f32x8::splat(o.y - s),
                f32x8::splat(o.z - s),
            ],
            inv: [inv(ray.dir.x), inv(ray.dir.y), inv(ray.dir.z)],
        }
    }

    /// Entry `t` of each child box (kept where the bit is set): the slab
    /// interval clipped to `[t_min, t_far]` is non-empty.
    #[inline(always)]
    fn test(&self, n: &BvhNode8, t_min: f32, t_far: f32) -> (u32, f32x8) {
        let (tn, tf) = slabs(
            [n.min_x, n.min_y, n.min_z],
            [n.max_x, n.max_y, n.max_z],
            self.lo,
            self.hi,
            self.inv,
            f32x8::splat(t_min),
            f32x8::splat(t_far),
        );
        let used = (1u32 << n.count) - 1;
        (lanes_bitmask(tn.simd_le(tf)) & used, tn)
    }
}

/// Per-lane slab test: entry and exit `t`, clipped to `[t_min, t_far]`.
/// Min and max by compare and select, the same on every SIMD level.
#[inline(always)]
fn slabs(
    bmin: [f32x8; 3],
    bmax: [f32x8; 3],
    lo: [f32x8; 3],
    hi: [f32x8; 3],
    inv: [f32x8; 3],
    t_min: f32x8,
    t_far: f32x8,
) -> (f32x8, f32x8) {
    let mut tn = t_min;
    let mut tf = t_far;
    for k in 0..3 {
        let t0 = (bmin[k] - lo[k]) * inv[k];
        let t1 = (bmax[k] - hi[k]) * inv[k];
        let first = t0.simd_lt(t1);
        let near = lanes_select(first, t0, t1);
        let far = lanes_select(first, t1, t0);
        tn = lanes_select(near.simd_gt(tn), near, tn);
        tf = lanes_select(far.simd_lt(tf), far, tf);
    }
    (tn, tf)
}

const LANE_INDEX: [f32; 8] = [0.0, 1.0, 2.0, 3.0, 4.0, 5.0, 6.0, 7.0];

impl<'a> Bvh<'a> {
    /// Builds the tree over `spheres` into the three storage slices (at
    /// least [`bvh_storage_for`]`(spheres.len())` long; longer is fine).
    /// Sphere indices in hits are positions in `spheres`. On error nothing
    /// is written.
    #[inline]
    pub fn build(
        spheres: &[Sphere],
        nodes: &'a mut [BvhNode8],
        lanes: &'a mut [f32],
        ids: &'a mut [u32],
    ) -> Result<Bvh<'a>, BvhError> {
        let n = spheres.len();
        if n > BVH_MAX_SPHERES {
            return Err(BvhError::TooManySpheres);
        }
        let need = bvh_storage_for(n);
        for (slice, needed, provided) in [
            ("nodes", need.nodes, nodes.len()),
            ("lanes", need.lanes, lanes.len()),
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
        for (index, s) in spheres.iter().enumerate() {
            let c = s.center;
            let ok = |x: f32| x.is_nan() || x.abs() < BVH_MAX_COORDINATE;
            if !(ok(c.x) && ok(c.y) && ok(c.z) && ok(s.radius)) {
                return Err(BvhError::SphereOutOfRange { index });
            }
        }
        let width = n + 7;
        let ids = &mut ids[..width];
        let mut m = 0;
        for (i, s) in spheres.iter().enumerate() {
            if hittable(s) {
                ids[m] = i as u32;
                m += 1;
            }
        }
        let nodes = &mut nodes[..need.nodes];
        let mut b = Builder {
            spheres,
            nodes,
            ids,
            used: 1,
            depth: 1,
        };
        if m == 0 {
            b.nodes[0] = BvhNode8::EMPTY;
        } else {
            b.node(0, 0, m, 1);
        }
        let (used, depth) = (b.used, b.depth);
        debug_assert!(used <= need.nodes && depth <= BVH_MAX_DEPTH);
        // Lanes in leaf order; padding after the last leaf never hits.
        let (cx, rest) = lanes[..4 * width].split_at_mut(width);
        let (cy, rest) = rest.split_at_mut(width);
        let (cz, r) = rest.split_at_mut(width);
        for k in 0..width {
            if k < m {
                let s = &spheres[ids[k] as usize];
                (cx[k], cy[k], cz[k], r[k]) = (s.center.x, s.center.y, s.center.z, s.radius);
            } else {
                (cx[k], cy[k], cz[k], r[k]) = (0.0, 0.0, 0.0, 0.0);
                ids[k] = u32::MAX;
            }
        }
        Ok(Bvh {
            nodes,
            cx,
            cy,
            cz,
            r,
            ids,
            len: n,
            used_nodes: used,
            depth,
        })
    }

    /// Whether this tree was built from exactly `spheres`: the same count,
    /// and every hittable sphere in its lanes with the same bits, once.
    #[inline]
    #[must_use]
    pub fn built_from(&self, spheres: &[Sphere]) -> bool {
        if spheres.len() != self.len {
            return false;
        }
        let hittable = spheres.iter().filter(|s| hittable(s)).count();
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
        // Ids are distinct by construction, so a full count is a match.
        k == hittable
    }

    /// The number of spheres it was built over (hittable or not).
    #[must_use]
    #[inline]
    pub fn len(&self) -> usize {
        self.len
    }

    /// Whether it was built over no spheres.
    #[must_use]
    #[inline]
    pub fn is_empty(&self) -> bool {
        self.len == 0
    }

    /// Nodes in use (at most [`bvh_storage_for`]`(len).nodes`).
    #[must_use]
    #[inline]
    pub fn node_count(&self) -> usize {
        self.used_nodes
    }

    /// Node levels (at most [`BVH_MAX_DEPTH`]).
    #[must_use]
    #[inline]
    pub fn depth(&self) -> u32 {
        self.depth
    }

    /// The 8-wide kernel on the leaf lanes from `start` (count of them
    /// valid): `t` per lane, `+∞` for a miss or an unused lane.
    #[inline(always)]
    fn leaf_t(&self, start: usize, count: usize, ray: &Ray) -> f32x8 {
        let load = |v: &[f32]| {
            let mut a = [0.0f32; 8];
            a.copy_from_slice(&v[start..start + 8]);
            f32x8::new(a)
        };
        let t = sphere_t(
            f32x8::splat(ray.origin.x),
            f32x8::splat(ray.origin.y),
            f32x8::splat(ray.origin.z),
            f32x8::splat(ray.dir.x),
            f32x8::splat(ray.dir.y),
            f32x8::splat(ray.dir.z),
            load(self.cx),
            load(self.cy),
            load(self.cz),
            load(self.r),
            f32x8::splat(ray.t_min),
            f32x8::splat(ray.t_max),
        );
        let used = f32x8::new(LANE_INDEX).simd_lt(f32x8::splat(count as f32));
        lanes_select(used, t, f32x8::splat(f32::INFINITY))
    }

    /// The closest hit of `ray`: bit for bit [`super::closest_hit`] over
    /// the spheres it was built from.
    #[must_use]
    #[inline]
    pub fn closest_hit(&self, ray: &Ray) -> Option<Hit> {
        let mut best: Option<Hit> = None;
        self.closest_from(0, ray, &mut best, &mut [(0, 0.0); STACK]);
        best
    }

    /// [`Bvh::closest_hit`] on the caller's reusable `stack`.
    #[must_use]
    #[inline]
    pub fn closest_hit_with(&self, ray: &Ray, stack: &mut BvhStack) -> Option<Hit> {
        let mut best: Option<Hit> = None;
        self.closest_from(0, ray, &mut best, &mut stack.closest);
        best
    }

    /// Closest-hit traversal of the subtree at `root` (a node index or a
    /// leaf reference), improving `best`.
    fn closest_from(
        &self,
        root: u32,
        ray: &Ray,
        best: &mut Option<Hit>,
        stack: &mut [(u32, f32); STACK],
    ) {
        let slab = SlabRay::new(ray);
        stack[0] = (root, f32::NEG_INFINITY);
        let mut sp = 1;
        // The closest t so far (t_max before any hit): children entered
        // beyond it are skipped, entered at it are kept.
        let mut far = best.map_or(ray.t_max, |h| h.t);
        while sp > 0 {
            sp -= 1;
            let (entry, t_enter) = stack[sp];
            if t_enter > far {
                continue;
            }
            if entry & LEAF_BIT != 0 {
                let start = ((entry & !LEAF_BIT) >> 3) as usize;
                let count = (entry & 7) as usize + 1;
                let ts = self.leaf_t(start, count, ray).to_array();
                for (lane, &t) in ts.iter().enumerate().take(count) {
                    if t < f32::INFINITY {
                        let id = self.ids[start + lane];
                        let take = match best {
                            Some(b) => t < b.t || (t == b.t && id < b.sphere),
                            None => true,
                        };
                        if take {
                            *best = Some(Hit { t, sphere: id });
                            far = t;
                        }
                    }
                }
                continue;
            }
            let node = &self.nodes[entry as usize];
            let (mut bits, tn) = slab.test(node, ray.t_min, far);
            if bits == 0 {
                continue;
            }
            let tn = tn.to_array();
            // Push far to near, so the nearest child is popped first.
            let mut order = [(0.0f32, 0u32); 8];
            let mut k = 0;
            while bits != 0 {
                let lane = bits.trailing_zeros() as usize;
                bits &= bits - 1;
                let item = (tn[lane], node.child[lane]);
                let mut j = k;
                while j > 0 && order[j - 1].0 < item.0 {
                    order[j] = order[j - 1];
                    j -= 1;
                }
                order[j] = item;
                k += 1;
            }
            for &(t, child) in &order[..k] {
                stack[sp] = (child, t);
                sp += 1;
            }
        }
    }

    /// Whether `ray` hits any sphere: [`super::any_hit`] over the spheres
    /// it was built from.
    #[must_use]
    #[inline]
    pub fn any_hit(&self, ray: &Ray) -> bool {
        self.any_from(ray, &mut [0; STACK])
    }

    /// [`Bvh::any_hit`] on the caller's reusable `stack`.
    #[must_use]
    #[inline]
    pub fn any_hit_with(&self, ray: &Ray, stack: &mut BvhStack) -> bool {
        self.any_from(ray, &mut stack.any)
    }

    fn any_from(&self, ray: &Ray, stack: &mut [u32; STACK]) -> bool {
        let slab = SlabRay::new(ray);
        stack[0] = 0;
        let mut sp = 1;
        while sp > 0 {
            sp -= 1;
            let entry = stack[sp];
            if entry & LEAF_BIT != 0 {
                let start = ((entry & !LEAF_BIT) >> 3) as usize;
                let count = (entry & 7) as usize + 1;
                let t = self.leaf_t(start, count, ray);
                if lanes_bitmask(t.simd_lt(f32x8::splat(f32::INFINITY))) != 0 {
                    return true;
                }
                continue;
            }
            let node = &self.nodes[entry as usize];
            let (mut bits, _) = slab.test(node, ray.t_min, ray.t_max);
            while bits != 0 {
                let lane = bits.trailing_zeros() as usize;
                bits &= bits - 1;
                stack[sp] = node.child[lane];
                sp += 1;
            }
        }
        false
    }

    /// The closest hits of a packet, traversed as a packet: one box test
    /// per child covers the 8 rays, one kernel call per leaf sphere. Where
    /// no more than `fallback` rays reach a subtree, each continues alone
    /// ([`Bvh::closest_hit`]'s traversal); `fallback = 0` never falls
    /// back, `8` traces every ray alone. Same contract as
    /// [`super::closest_hit_x8`], lane by lane the same bits.
    #[inline]
    pub fn closest_hit_x8(&self, packet: &RayPacket8, hits: &mut HitPacket8, fallback: u32) {
        self.closest_hit_x8_with(packet, hits, fallback, &mut BvhStack::new());
    }

    /// [`Bvh::closest_hit_x8`] on the caller's reusable `stack`.
    #[inline]
    pub fn closest_hit_x8_with(
        &self,
        packet: &RayPacket8,
        hits: &mut HitPacket8,
        fallback: u32,
        stack: &mut BvhStack,
    ) {
        let BvhStack {
            closest: single,
            packet: stack,
            ..
        } = stack;
        let active = packet.active_bits();
        if active == 0 {
            return;
        }
        // Own best per lane, from no hit; merged into `hits` at the end
        // by the strict rule of `closest_hit_x8`.
        let mut bt = f32x8::splat(f32::INFINITY);
        let mut bi = i32x8::splat(-1);
        let rays: [Ray; 8] = core::array::from_fn(|k| packet.ray(k));
        let inf = f32x8::splat(f32::INFINITY);
        let lo = [packet.ox, packet.oy, packet.oz];
        let s = (abs8(packet.ox) + abs8(packet.oy) + abs8(packet.oz)) * f32x8::splat(SLACK);
        let slab_lo = [lo[0] + s, lo[1] + s, lo[2] + s];
        let slab_hi = [lo[0] - s, lo[1] - s, lo[2] - s];
        let inv = [inv8(packet.dx), inv8(packet.dy), inv8(packet.dz)];
        stack[0] = (0, active as u8);
        let mut sp = 1;
        while sp > 0 {
            sp -= 1;
            let (entry, mask) = stack[sp];
            // Lanes skip a subtree only by their own box tests, done when
            // it was pushed; `far` below re-checks against newer hits.
            if mask.count_ones() <= fallback {
                let (mut ts, mut is) = (bt.to_array(), bi.to_array());
                let mut m = mask;
                while m != 0 {
                    let lane = m.trailing_zeros() as usize;
                    m &= m - 1;
                    let mut best = (is[lane] >= 0).then_some(Hit {
                        t: ts[lane],
                        sphere: is[lane] as u32,
                    });
                    self.closest_from(entry, &rays[lane], &mut best, single);
                    if let Some(h) = best {
                        (ts[lane], is[lane]) = (h.t, h.sphere as i32);
                    }
                }
                bt = f32x8::new(ts);
                bi = i32x8::new(is);
                continue;
            }
            let lane_on = mask_from_bits(mask);
            if entry & LEAF_BIT != 0 {
                let start = ((entry & !LEAF_BIT) >> 3) as usize;
                let count = (entry & 7) as usize + 1;
                for k in start..start + count {
                    let t = sphere_t(
                        packet.ox,
                        packet.oy,
                        packet.oz,
                        packet.dx,
                        packet.dy,
                        packet.dz,
                        f32x8::splat(self.cx[k]),
                        f32x8::splat(self.cy[k]),
                        f32x8::splat(self.cz[k]),
                        f32x8::splat(self.r[k]),
                        packet.t_min,
                        packet.t_max,
                    );
                    let id = i32x8::splat(self.ids[k] as i32);
                    let hit = lane_on & t.simd_lt(inf);
                    let id_lower: f32x8 =
                        wide::bytemuck::cast(id.simd_lt(bi) | bi.simd_eq(i32x8::splat(-1)));
                    let take = hit & (t.simd_lt(bt) | (t.simd_eq(bt) & id_lower));
                    bt = lanes_select(take, t, bt);
                    bi = lanes_select_i32(take, id, bi);
                }
                continue;
            }
            let node = &self.nodes[entry as usize];
            // The closest so far per lane, else the ray's t_max.
            let far = lanes_select(bt.simd_lt(inf), bt, packet.t_max);
            let mut order = [(0.0f32, 0u32, 0u8); 8];
            let mut n = 0;
            for c in 0..node.count as usize {
                let at = |v: &f32x8| f32x8::splat(v.as_array()[c]);
                let (tn, tf) = slabs(
                    [at(&node.min_x), at(&node.min_y), at(&node.min_z)],
                    [at(&node.max_x), at(&node.max_y), at(&node.max_z)],
                    slab_lo,
                    slab_hi,
                    inv,
                    packet.t_min,
                    far,
                );
                let lanes = lanes_bitmask(tn.simd_le(tf) & lane_on) as u8;
                if lanes == 0 {
                    continue;
                }
                // Order by the nearest entry among the lanes that enter.
                let tn = tn.to_array();
                let mut key = f32::INFINITY;
                for (l, &t) in tn.iter().enumerate() {
                    if lanes >> l & 1 == 1 && t < key {
                        key = t;
                    }
                }
                let item = (key, node.child[c], lanes);
                let mut j = n;
                while j > 0 && order[j - 1].0 < item.0 {
                    order[j] = order[j - 1];
                    j -= 1;
                }
                order[j] = item;
                n += 1;
            }
            for &(_, child, lanes) in &order[..n] {
                stack[sp] = (child, lanes);
                sp += 1;
            }
        }
        let take = bt.simd_lt(hits.t) & mask_from_bits(active as u8);
        hits.t = lanes_select(take, bt, hits.t);
        hits.sphere = lanes_select_i32(take, bi, hits.sphere);
    }

    /// Which rays of a packet hit any sphere: bit `k` for active lane `k`,
    /// as [`super::any_hit_x8`]. Each ray is traced alone, stopping at its
    /// first blocker (shadow rays of a packet rarely share a path).
    #[must_use]
    #[inline]
    pub fn any_hit_x8(&self, packet: &RayPacket8) -> u32 {
        let mut out = 0;
        let mut stack = [0; STACK];
        let mut m = packet.active_bits();
        while m != 0 {
            let lane = m.trailing_zeros();
            m &= m - 1;
            if self.any_from(&packet.ray(lane as usize), &mut stack) {
                out |= 1 << lane;
            }
        }
        out
    }
}

fn abs8(v: f32x8) -> f32x8 {
    // Clear the sign bit: exact on every level.
    let bits: i32x8 = wide::bytemuck::cast(v);
    wide::bytemuck::cast(bits & i32x8::splat(i32::MAX))
}

fn inv8(d: f32x8) -> f32x8 {
    let tiny = f32x8::splat(1e-30);
    let neg_tiny = f32x8::splat(-1e-30);
    let bits: i32x8 = wide::bytemuck::cast(d);
    let negative: f32x8 = wide::bytemuck::cast(bits.simd_lt(i32x8::splat(0)));
    let zero = d.simd_eq(f32x8::splat(0.0));
    let d = lanes_select(zero, lanes_select(negative, neg_tiny, tiny), d);
    f32x8::splat(1.0) / d
}
