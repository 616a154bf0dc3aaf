//! The build: top-down and single-threaded, so the tree depends only on
//! the spheres and their order. A node's children are made by repeatedly
//! splitting the child with the largest box surface (among those with more
//! than `BVH_LEAF_MAX` = 8 spheres) until there are eight or none can
//! split. Splits are binned SAH (16 bins of the centroid bounds, on each
//! axis) down to depth `BVH_SAH_DEPTH` = 16; below it, and wherever all
//! centroids coincide, a split at the median of the longest centroid axis
//! (ties by sphere index). Median splits divide the spheres by eight per
//! level, which bounds the depth by [`BVH_MAX_DEPTH`].

use super::{
    BVH_LEAF_MAX, BVH_MAX_COORDINATE, BVH_MAX_DEPTH, BVH_MAX_SPHERES, BVH_SAH_DEPTH, Bvh, BvhError,
    BvhNode8, LEAF_BIT, PACKET_FALLBACK, SLACK, Shape, bvh_storage_for, hittable,
};
use crate::lanes::f32x8;
use crate::trace::Sphere;
use core::cmp::Ordering;

/// An axis-aligned box.
#[derive(Clone, Copy, Debug)]
pub(super) struct Box3 {
    pub(super) min: [f32; 3],
    pub(super) max: [f32; 3],
}

impl Box3 {
    pub(super) const EMPTY: Box3 = Box3 {
        min: [f32::INFINITY; 3],
        max: [f32::NEG_INFINITY; 3],
    };

    pub(super) fn grow(&mut self, o: &Box3) {
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
        self.grow(&Box3 { min: p, max: p });
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

/// The conservative box of a sphere (see "Why the results are exact" on
/// [`Bvh`]).
pub(super) fn sphere_box(s: &Sphere) -> Box3 {
    let c = s.center;
    let pad = s.radius + (c.x.abs() + c.y.abs() + c.z.abs() + s.radius) * SLACK;
    Box3 {
        min: [c.x - pad, c.y - pad, c.z - pad],
        max: [c.x + pad, c.y + pad, c.z + pad],
    }
}

fn centroid(s: &Sphere) -> [f32; 3] {
    [s.center.x, s.center.y, s.center.z]
}

/// What the build needs of the items it sorts into leaves: spheres, or
/// the caller's primitives. Every method is a pure function of the id.
pub(super) trait Source {
    /// The conservative box (padded against rounding, see [`Bvh`]).
    fn bounds(&self, id: u32) -> Box3;
    /// The point splits sort by.
    fn centroid(&self, id: u32) -> [f32; 3];
    /// The size outliers are picked by (largest first).
    fn size(&self, id: u32) -> f32;
}

impl Source for [Sphere] {
    #[inline(always)]
    fn bounds(&self, id: u32) -> Box3 {
        sphere_box(&self[id as usize])
    }
    #[inline(always)]
    fn centroid(&self, id: u32) -> [f32; 3] {
        centroid(&self[id as usize])
    }
    #[inline(always)]
    fn size(&self, id: u32) -> f32 {
        self[id as usize].radius
    }
}

struct Builder<'s, 'b, S: Source + ?Sized> {
    items: &'s S,
    nodes: &'b mut [BvhNode8],
    ids: &'b mut [u32],
    used: usize,
    depth: u32,
}

const BINS: usize = 16;

impl<S: Source + ?Sized> Builder<'_, '_, S> {
    fn bounds(&self, lo: usize, hi: usize) -> (Box3, Box3) {
        let mut b = Box3::EMPTY;
        let mut c = Box3::EMPTY;
        for &id in &self.ids[lo..hi] {
            b.grow(&self.items.bounds(id));
            c.grow_point(self.items.centroid(id));
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
        let spheres = self.items;
        self.ids[lo..hi].select_nth_unstable_by(mid - lo, |&a, &b| {
            let ca = spheres.centroid(a)[axis];
            let cb = spheres.centroid(b)[axis];
            ca.total_cmp(&cb).then(a.cmp(&b))
        });
        mid
    }

    fn sah_split(&mut self, lo: usize, hi: usize, cb: &Box3, ext: &[f32; 3]) -> Option<usize> {
        let spheres = self.items;
        let bin_of = |id: u32, axis: usize| -> usize {
            let x = (spheres.centroid(id)[axis] - cb.min[axis]) / ext[axis] * BINS as f32;
            // Truncation floors (x ≥ 0); the max centroid clamps to the last bin.
            (x as usize).min(BINS - 1)
        };
        let mut best: Option<(f32, usize, usize)> = None; // (cost, axis, split bin)
        for (axis, &e) in ext.iter().enumerate() {
            if e <= 0.0 {
                continue;
            }
            let mut boxes = [Box3::EMPTY; BINS];
            let mut counts = [0u32; BINS];
            for &id in &self.ids[lo..hi] {
                let b = bin_of(id, axis);
                boxes[b].grow(&spheres.bounds(id));
                counts[b] += 1;
            }
            // Right-to-left sweep of areas × counts.
            let mut right_cost = [0.0f32; BINS];
            let mut acc = Box3::EMPTY;
            let mut n = 0u32;
            for b in (1..BINS).rev() {
                acc.grow(&boxes[b]);
                n += counts[b];
                right_cost[b] = acc.half_area() * n as f32;
            }
            let mut acc = Box3::EMPTY;
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
        let ids = &mut self.ids[lo..hi];
        let mut left = 0;
        for k in 0..ids.len() {
            if bin_of(ids[k], axis) < split {
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
        let priority = |b: &Self, lo: usize, hi: usize| -> (Box3, f32) {
            let bx = b.bounds(lo, hi).0;
            let p = if depth < BVH_SAH_DEPTH {
                bx.half_area()
            } else {
                (hi - lo) as f32
            };
            (bx, p)
        };
        let mut ranges = [(0usize, 0usize, Box3::EMPTY, 0.0f32); 8];
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

/// How many times the rest's box surface a sphere's box must exceed to be
/// kept out of the tree.
const OUTLIER_RATIO: f32 = 64.0;

/// Moves the outliers to the front of `ids` (hittable spheres) and returns
/// their count, at most [`BVH_LEAF_MAX`], none when all fit one leaf: repeatedly, the largest sphere
/// left (ties to the lowest index) while its box's surface is more than
/// [`OUTLIER_RATIO`] times that of the box of all the others left. Such
/// a sphere (a ground of radius 1000 under a scene 20 wide) would make
/// every box above it huge and be entered by nearly every ray; kept out,
/// it is tested once per ray on its own, and the tree stays tight.
fn pick_outliers<S: Source + ?Sized>(spheres: &S, ids: &mut [u32]) -> usize {
    // A tree of one leaf tests its spheres in one kernel call already.
    if ids.len() <= BVH_LEAF_MAX {
        return 0;
    }
    let mut k = 0;
    while k < BVH_LEAF_MAX.min(ids.len()) {
        let radius = |id: u32| spheres.size(id);
        let mut big = k;
        for j in k + 1..ids.len() {
            if radius(ids[j]) > radius(ids[big]) {
                big = j;
            }
        }
        let mut rest = Box3::EMPTY;
        for (j, &id) in ids.iter().enumerate().skip(k) {
            if j != big {
                rest.grow(&spheres.bounds(id));
            }
        }
        let area = spheres.bounds(ids[big]).half_area();
        // More than 8 spheres and at most 8 outliers: the rest is never
        // empty, and the tree never is.
        if area.partial_cmp(&(OUTLIER_RATIO * rest.half_area())) != Some(Ordering::Greater) {
            break;
        }
        // Keep the others in their order (the tree's build depends on it).
        ids[k..=big].rotate_right(1);
        k += 1;
    }
    k
}

/// Builds the tree over the items `ids[..m]` (the hittable ones) into
/// `nodes`, reordering `ids` so the outliers come first and every leaf is
/// a contiguous run; `len` of the returned shape is left 0 for the caller.
pub(super) fn build_tree<S: Source + ?Sized>(
    items: &S,
    nodes: &mut [BvhNode8],
    ids: &mut [u32],
    m: usize,
) -> Shape {
    let outliers = pick_outliers(items, &mut ids[..m]);
    let capacity = nodes.len();
    let mut b = Builder {
        items,
        nodes,
        ids,
        used: 1,
        depth: 1,
    };
    if m == outliers {
        b.nodes[0] = BvhNode8::EMPTY;
    } else {
        b.node(0, outliers, m, 1);
    }
    debug_assert!(b.used <= capacity && b.depth <= BVH_MAX_DEPTH);
    Shape {
        len: 0,
        outliers,
        used_nodes: b.used,
        depth: b.depth,
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

impl<'a> Bvh<'a> {
    /// Builds the tree over `spheres` into the three storage slices (at
    /// least [`bvh_storage_for`]`(spheres.len())` long; longer is fine).
    /// Sphere indices in hits are positions in `spheres`. On error nothing
    /// is written.
    ///
    /// Top-down and single-threaded, so the tree depends only on the
    /// spheres and their order: binned SAH splits near the root, median
    /// splits below depth 16, at most [`BVH_MAX_DEPTH`] node levels for up
    /// to [`BVH_MAX_SPHERES`] spheres. Spheres that can never be hit
    /// (radius `≤ 0` or NaN, a NaN centre) are left out.
    ///
    /// ```
    /// use glam::Vec3;
    /// use strata::trace::{Bvh, BvhError, BvhNode8, Sphere, bvh_storage_for};
    /// let spheres = [Sphere::new(Vec3::ZERO, 1.0), Sphere::new(Vec3::X, 0.0)];
    /// let size = bvh_storage_for(spheres.len());
    /// let (mut nodes, mut lanes, mut ids) =
    ///     (vec![BvhNode8::EMPTY; size.nodes], vec![0.0; size.lanes], vec![0; size.ids]);
    /// let short = Bvh::build(&spheres, &mut nodes, &mut lanes, &mut ids[..1]);
    /// assert!(matches!(short, Err(BvhError::StorageTooSmall { slice: "ids", .. })));
    /// let bvh = Bvh::build(&spheres, &mut nodes, &mut lanes, &mut ids).unwrap();
    /// // Both spheres count, though the one of radius 0 is left out of the tree.
    /// assert_eq!((bvh.len(), bvh.node_count(), bvh.depth()), (2, 1, 1));
    /// ```
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
        let shape = build_tree(spheres, nodes, ids, m);
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
            shape: Shape { len: n, ..shape },
            packet_fallback: PACKET_FALLBACK,
        })
    }
}
