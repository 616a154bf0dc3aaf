//! The queries: closest and any hit for one ray (a stack of children
//! sorted by entry distance) and for packets of eight (one box test per
//! child for the rays that reach it, handing subtrees that few rays reach
//! to the single-ray traversal), and the [`BvhStack`] they run on.

use glam::Vec3;

use super::{BVH_MAX_DEPTH, Bvh, BvhNode8, LEAF_BIT, SLACK};
use crate::lanes::{
    Lanes, SphereLanes, V3, f32x8, i32x8, lanes_bitmask, lanes_eq, lanes_eq_i32, lanes_gt,
    lanes_le, lanes_lt, lanes_lt_i32, lanes_select, lanes_select_i32, mask_from_bits,
    mask_from_i32,
};
use crate::trace::{
    Hit, HitPacket8, Ray, RayPacket8, Sphere, ray_sphere_t, sphere_t, sphere_t_live,
};

/// Traversal stack entries: the stack holds the unvisited siblings along
/// the current path, at most 7 a level and 8 while a node's children are
/// sorted in, so `7 · (`[`BVH_MAX_DEPTH`]` − 1) + 8` (183) suffice;
/// rounded up to a power of two, so an index masked by [`STACK_MASK`]
/// needs no bounds check (the mask never changes an index below the
/// bound, which the assertion below keeps).
pub(super) const STACK: usize = (7 * BVH_MAX_DEPTH as usize + 1).next_power_of_two();
const _: () = assert!(7 * (BVH_MAX_DEPTH as usize - 1) + 8 <= STACK);

/// `STACK − 1`.
const STACK_MASK: usize = STACK - 1;

/// Reusable traversal memory for [`Bvh`] queries: keep one per thread (or
/// per tile) and pass it to the `_with` queries. It is zeroed once, when
/// made; queries only read entries they wrote, so it is never cleared
/// again (the queries without `_with` clear a fresh stack of their own,
/// 1–4 KB, on every call).
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
    pub(super) closest: [(u32, f32); STACK],
    /// Any-hit traversal of one ray.
    pub(super) any: [u32; STACK],
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
        (lanes_bitmask(lanes_le(tn, tf)) & used, tn)
    }
}

/// A BVH's sphere lanes (centre and radius as SoA arrays), all of one
/// width.
struct LeafLanes<'a> {
    cx: &'a [f32],
    cy: &'a [f32],
    cz: &'a [f32],
    r: &'a [f32],
}

impl LeafLanes<'_> {
    /// The 8-wide kernel on the lanes from `start`: `t` per lane, `+∞` for
    /// a miss. Lanes past the leaf's count hold other leaves' spheres: the
    /// callers mask them out of their hit bits.
    #[inline(always)]
    fn leaf_t(&self, entry: u32, start: usize, ray: &Ray) -> f32x8 {
        let end = start + 8;
        let load = |v: &[f32]| {
            let mut a = [0.0f32; 8];
            a.copy_from_slice(&v[start..end]);
            f32x8::new(a)
        };
        let spheres = SphereLanes {
            center: V3::new(load(self.cx), load(self.cy), load(self.cz)),
            radius: load(self.r),
        };
        sphere_t_live(
            &ray.lanes_x8(),
            &spheres,
            f32x8::new(LEAF_MASKS[(entry & 7) as usize]),
        )
    }
}

/// The lane masks of leaves of 1 to 8 spheres (all ones: a NaN's bits).
const LEAF_MASKS: [[f32; 8]; 8] = {
    let mut m = [[0.0f32; 8]; 8];
    let mut n = 0;
    while n < 8 {
        let mut k = 0;
        while k <= n {
            m[n][k] = f32::from_bits(u32::MAX);
            k += 1;
        }
        n += 1;
    }
    m
};

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
        let first = lanes_lt(t0, t1);
        let near = lanes_select(first, t0, t1);
        let far = lanes_select(first, t1, t0);
        tn = lanes_select(lanes_gt(near, tn), near, tn);
        tf = lanes_select(lanes_lt(far, tf), far, tf);
    }
    (tn, tf)
}

/// The lane bits of a leaf reference's spheres.
#[inline(always)]
fn leaf_lanes(entry: u32) -> u32 {
    (2u32 << (entry & 7)) - 1
}

impl Bvh<'_> {
    /// The sphere lanes, each cut to the same width, so one bounds check
    /// covers a leaf's four loads.
    #[inline(always)]
    fn lanes(&self) -> LeafLanes<'_> {
        let w = self.ids.len();
        LeafLanes {
            cx: &self.cx[..w],
            cy: &self.cy[..w],
            cz: &self.cz[..w],
            r: &self.r[..w],
        }
    }

    /// The closest hit of `ray`: bit for bit
    /// [`closest_hit`](crate::trace::closest_hit) over the spheres it was
    /// built from.
    #[must_use]
    #[inline]
    pub fn closest_hit(&self, ray: &Ray) -> Option<Hit> {
        let mut best = None;
        self.closest_from(0, ray, &mut best, &mut [(0, 0.0); STACK]);
        self.closest_outlier(ray, best)
    }

    /// [`Bvh::closest_hit`] on the caller's reusable `stack`.
    #[must_use]
    #[inline]
    pub fn closest_hit_with(&self, ray: &Ray, stack: &mut BvhStack) -> Option<Hit> {
        // The tree first, the outliers after: the tree's walk then does
        // not wait on an outlier's square root and divide, which the
        // processor overlaps with it (a ground sphere's hit would prune
        // little of the tree anyway). Ties go to the lower index either way.
        let mut best = None;
        self.closest_from(0, ray, &mut best, &mut stack.closest);
        self.closest_outlier(ray, best)
    }

    /// The closest hit among the spheres kept out of the tree, one at a
    /// time with the scalar kernel (the same bits as the 8-wide one).
    #[inline(always)]
    fn closest_outlier(&self, ray: &Ray, mut best: Option<Hit>) -> Option<Hit> {
        for k in 0..self.shape.outliers {
            let t = self.outlier_t(k, ray);
            if t < f32::INFINITY {
                let id = self.ids[k];
                if best.is_none_or(|b| t < b.t || (t == b.t && id < b.sphere)) {
                    best = Some(Hit { t, sphere: id });
                }
            }
        }
        best
    }

    /// The kernel's `t` for outlier `k` (`+∞` for a miss).
    #[inline(always)]
    fn outlier_t(&self, k: usize, ray: &Ray) -> f32 {
        let s = Sphere::new(Vec3::new(self.cx[k], self.cy[k], self.cz[k]), self.r[k]);
        ray_sphere_t(ray, &s, ray.t_max)
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
        let lanes = self.lanes();
        let ids = self.ids;
        // The closest t so far (t_max before any hit) and its sphere:
        // children entered beyond it are skipped, entered at it are kept.
        let (mut far, mut id_best, mut found) = match *best {
            Some(h) => (h.t, h.sphere, true),
            None => (ray.t_max, u32::MAX, false),
        };
        walk_closest(self.nodes, root, ray, &mut far, stack, |entry, far| {
            let start = ((entry & !LEAF_BIT) >> 3) as usize;
            let t = lanes.leaf_t(entry, start, ray);
            // Only the leaf's lanes that hit at or before the closest
            // so far can be taken: most leaves have none.
            let inf = f32x8::splat(f32::INFINITY);
            let mut hits = lanes_bitmask(lanes_le(t, f32x8::splat(*far)) & lanes_lt(t, inf))
                & leaf_lanes(entry);
            if hits != 0 {
                let ts = t.to_array();
                while hits != 0 {
                    let lane = hits.trailing_zeros() as usize;
                    hits &= hits - 1;
                    let (t, id) = (ts[lane], ids[start + lane]);
                    // Before any hit `far` is t_max, which every
                    // kernel t is below.
                    if t < *far || (t == *far && id < id_best) {
                        (*far, id_best, found) = (t, id, true);
                    }
                }
            }
        });
        if found {
            *best = Some(Hit {
                t: far,
                sphere: id_best,
            });
        }
    }

    /// Whether `ray` hits any sphere: [`any_hit`](crate::trace::any_hit)
    /// over the spheres it was built from.
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
        for k in 0..self.shape.outliers {
            if self.outlier_t(k, ray) < f32::INFINITY {
                return true;
            }
        }
        let lanes = self.lanes();
        walk_any(self.nodes, ray, stack, |entry| {
            let start = ((entry & !LEAF_BIT) >> 3) as usize;
            let t = lanes.leaf_t(entry, start, ray);
            lanes_bitmask(lanes_lt(t, f32x8::splat(f32::INFINITY))) & leaf_lanes(entry) != 0
        })
    }

    /// The closest hits of a packet, traversed as a packet: one box test
    /// per child covers the 8 rays, one kernel call per leaf sphere; where
    /// few rays reach a subtree they continue alone
    /// ([`Bvh::with_packet_fallback`]). Same contract as
    /// [`closest_hit_x8`](crate::trace::closest_hit_x8), lane by lane the
    /// same bits: `hits` is read and updated, inactive lanes are not
    /// written.
    ///
    /// ```
    /// use glam::Vec3;
    /// use strata::trace::*;
    /// let spheres: Vec<Sphere> = (0..40)
    ///     .map(|i| Sphere::new(Vec3::new(i as f32, 0.0, -5.0), 0.4))
    ///     .collect();
    /// let size = bvh_storage_for(spheres.len());
    /// let (mut nodes, mut lanes, mut ids) =
    ///     (vec![BvhNode8::EMPTY; size.nodes], vec![0.0; size.lanes], vec![0; size.ids]);
    /// let bvh = Bvh::build(&spheres, &mut nodes, &mut lanes, &mut ids).unwrap();
    /// let rays = [
    ///     Ray::new(Vec3::new(7.0, 0.0, 0.0), -Vec3::Z),
    ///     Ray::new(Vec3::ZERO, Vec3::Z),
    /// ];
    /// let mut hits = HitPacket8::NONE;
    /// bvh.closest_hit_x8(&RayPacket8::from_rays(&rays), &mut hits);
    /// assert_eq!(hits.hit(0), closest_hit(&spheres, &rays[0]));
    /// assert_eq!(hits.hit(0).map(|h| h.sphere), Some(7));
    /// assert_eq!(hits.hit(1), None);
    /// ```
    #[inline]
    pub fn closest_hit_x8(&self, packet: &RayPacket8, hits: &mut HitPacket8) {
        // Only the two stacks this query uses, not a whole `BvhStack`.
        self.closest_x8_on(packet, hits, &mut [(0, 0.0); STACK], &mut [(0, 0); STACK]);
    }

    /// [`Bvh::closest_hit_x8`] on the caller's reusable `stack`.
    #[inline]
    pub fn closest_hit_x8_with(
        &self,
        packet: &RayPacket8,
        hits: &mut HitPacket8,
        stack: &mut BvhStack,
    ) {
        self.closest_x8_on(packet, hits, &mut stack.closest, &mut stack.packet);
    }

    /// Packet traversal on `stack`, handing subtrees few rays reach to
    /// single-ray traversal on `single`.
    #[inline(always)]
    fn closest_x8_on(
        &self,
        packet: &RayPacket8,
        hits: &mut HitPacket8,
        single: &mut [(u32, f32); STACK],
        stack: &mut [(u32, u8); STACK],
    ) {
        let fallback = self.packet_fallback;
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
        let s = (Lanes::abs(packet.ox) + Lanes::abs(packet.oy) + Lanes::abs(packet.oz))
            * f32x8::splat(SLACK);
        let slab_lo = [lo[0] + s, lo[1] + s, lo[2] + s];
        let slab_hi = [lo[0] - s, lo[1] - s, lo[2] - s];
        let inv = [inv8(packet.dx), inv8(packet.dy), inv8(packet.dz)];
        self.packet_lanes(
            packet,
            0..self.shape.outliers,
            mask_from_bits(active as u8),
            &mut bt,
            &mut bi,
        );
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
                self.packet_lanes(packet, start..start + count, lane_on, &mut bt, &mut bi);
                continue;
            }
            let node = &self.nodes[entry as usize];
            // The closest so far per lane, else the ray's t_max.
            let far = lanes_select(lanes_lt(bt, inf), bt, packet.t_max);
            let mut order = [(0.0f32, (0u32, 0u8)); 8];
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
                let enter = lanes_le(tn, tf) & lane_on;
                let lanes = lanes_bitmask(enter) as u8;
                if lanes == 0 {
                    continue;
                }
                // Order by the nearest entry among the lanes that enter (a
                // tree of minima; the order never changes a result).
                let m = lanes_select(enter, tn, inf).to_array();
                let min = |a: f32, b: f32| if b < a { b } else { a };
                let key = min(
                    min(min(m[0], m[1]), min(m[2], m[3])),
                    min(min(m[4], m[5]), min(m[6], m[7])),
                );
                insert_far_to_near(&mut order, n, (key, (node.child[c], lanes)));
                n += 1;
            }
            for &(_, (child, lanes)) in &order[..n] {
                stack[sp] = (child, lanes);
                sp += 1;
            }
        }
        let take = lanes_lt(bt, hits.t) & mask_from_bits(active as u8);
        hits.t = lanes_select(take, bt, hits.t);
        hits.sphere = lanes_select_i32(take, bi, hits.sphere);
    }

    /// The packet kernel on sphere lanes `lanes`, one at a time, for the
    /// rays of `lane_on`: improves each ray's best `t` and sphere (ties to
    /// the lower index; −1 for none yet).
    #[inline(always)]
    fn packet_lanes(
        &self,
        packet: &RayPacket8,
        lanes: core::ops::Range<usize>,
        lane_on: f32x8,
        bt: &mut f32x8,
        bi: &mut i32x8,
    ) {
        let inf = f32x8::splat(f32::INFINITY);
        for k in lanes {
            let sphere = SphereLanes {
                center: V3::new(
                    f32x8::splat(self.cx[k]),
                    f32x8::splat(self.cy[k]),
                    f32x8::splat(self.cz[k]),
                ),
                radius: f32x8::splat(self.r[k]),
            };
            let t = sphere_t(&packet.lanes(), &sphere);
            let id = i32x8::splat(self.ids[k] as i32);
            let hit = lane_on & lanes_lt(t, inf);
            let id_lower =
                mask_from_i32(lanes_lt_i32(id, *bi) | lanes_eq_i32(*bi, i32x8::splat(-1)));
            let take = hit & (lanes_lt(t, *bt) | (lanes_eq(t, *bt) & id_lower));
            *bt = lanes_select(take, t, *bt);
            *bi = lanes_select_i32(take, id, *bi);
        }
    }

    /// Which rays of a packet hit any sphere: bit `k` for active lane `k`,
    /// as [`any_hit_x8`](crate::trace::any_hit_x8). Each ray is traced
    /// alone, stopping at its first blocker (shadow rays of a packet rarely
    /// share a path).
    #[must_use]
    #[inline]
    pub fn any_hit_x8(&self, packet: &RayPacket8) -> u32 {
        self.any_x8_from(packet, &mut [0; STACK])
    }

    /// [`Bvh::any_hit_x8`] on the caller's reusable `stack`.
    #[must_use]
    #[inline]
    pub fn any_hit_x8_with(&self, packet: &RayPacket8, stack: &mut BvhStack) -> u32 {
        self.any_x8_from(packet, &mut stack.any)
    }

    fn any_x8_from(&self, packet: &RayPacket8, stack: &mut [u32; STACK]) -> u32 {
        let mut out = 0;
        let mut m = packet.active_bits();
        while m != 0 {
            let lane = m.trailing_zeros();
            m &= m - 1;
            if self.any_from(&packet.ray(lane as usize), stack) {
                out |= 1 << lane;
            }
        }
        out
    }
}

/// Closest-hit traversal of the subtree at `root` (a node index or a leaf
/// reference) over any leaves: `leaf(entry, far)` tests a leaf's items
/// and lowers `far`, the closest `t` so far (the ray's `t_max` before any
/// hit; it tracks its own best item). Children entered beyond `far` are
/// skipped, entered at it are kept (a tie may go to a lower index).
///
/// The nearest child a node's test enters is visited next without a trip
/// through the stack; the others are inserted into the stack's top, far to
/// near, so they pop nearest first. Entries popped beyond the closest hit
/// so far are skipped.
#[inline(always)]
pub(super) fn walk_closest(
    nodes: &[BvhNode8],
    root: u32,
    ray: &Ray,
    far: &mut f32,
    stack: &mut [(u32, f32); STACK],
    mut leaf: impl FnMut(u32, &mut f32),
) {
    let slab = SlabRay::new(ray);
    let mut sp = 0usize;
    let mut entry = root;
    'visit: loop {
        if entry & LEAF_BIT != 0 {
            leaf(entry, far);
        } else {
            let node = &nodes[entry as usize];
            let (mut bits, tn) = slab.test(node, ray.t_min, *far);
            if bits != 0 {
                let tn = tn.to_array();
                let lane = bits.trailing_zeros() as usize;
                bits &= bits - 1;
                if bits == 0 {
                    // One child: nothing to order.
                    entry = node.child[lane];
                    continue 'visit;
                }
                // Two or more: sort them into the stack's top, then
                // take the nearest off it.
                let base = sp;
                stack[sp & STACK_MASK] = (node.child[lane], tn[lane]);
                sp += 1;
                while bits != 0 {
                    let lane = bits.trailing_zeros() as usize;
                    bits &= bits - 1;
                    let item = (node.child[lane], tn[lane]);
                    let mut j = sp;
                    while j > base && stack[(j - 1) & STACK_MASK].1 < item.1 {
                        stack[j & STACK_MASK] = stack[(j - 1) & STACK_MASK];
                        j -= 1;
                    }
                    stack[j & STACK_MASK] = item;
                    sp += 1;
                }
                sp -= 1;
                entry = stack[sp & STACK_MASK].0;
                continue 'visit;
            }
        }
        // The next stacked child not beyond the closest hit.
        loop {
            if sp == 0 {
                break 'visit;
            }
            sp -= 1;
            let (e, t_enter) = stack[sp & STACK_MASK];
            // A NaN entry distance cannot rule the child out: visit it.
            if t_enter.partial_cmp(far) != Some(core::cmp::Ordering::Greater) {
                entry = e;
                continue 'visit;
            }
        }
    }
}

/// Any-hit traversal of the whole tree over any leaves: true as soon as
/// `leaf(entry)` reports a hit.
#[inline(always)]
pub(super) fn walk_any(
    nodes: &[BvhNode8],
    ray: &Ray,
    stack: &mut [u32; STACK],
    mut leaf: impl FnMut(u32) -> bool,
) -> bool {
    let slab = SlabRay::new(ray);
    let mut sp = 0usize;
    let mut entry = 0u32;
    loop {
        if entry & LEAF_BIT != 0 {
            if leaf(entry) {
                return true;
            }
        } else {
            let node = &nodes[entry as usize];
            let (mut bits, _) = slab.test(node, ray.t_min, ray.t_max);
            if bits != 0 {
                // Visit the first child now, stack the rest.
                entry = node.child[bits.trailing_zeros() as usize];
                bits &= bits - 1;
                while bits != 0 {
                    stack[sp & STACK_MASK] = node.child[bits.trailing_zeros() as usize];
                    sp += 1;
                    bits &= bits - 1;
                }
                continue;
            }
        }
        if sp == 0 {
            return false;
        }
        sp -= 1;
        entry = stack[sp & STACK_MASK];
    }
}

/// Inserts `item` into `order[..n]`, kept sorted from far to near by entry
/// distance, so that pushing it in order pops the nearest child first.
#[inline(always)]
fn insert_far_to_near<T: Copy>(order: &mut [(f32, T); 8], n: usize, item: (f32, T)) {
    let mut j = n;
    while j > 0 && order[j - 1].0 < item.0 {
        order[j] = order[j - 1];
        j -= 1;
    }
    order[j] = item;
}

/// `1 / d` per lane, with `±10⁻³⁰` (by the sign bit) for a zero `d`, so a
/// slab test never computes `0 × ∞`.
fn inv8(d: f32x8) -> f32x8 {
    let tiny = f32x8::splat(1e-30);
    let neg_tiny = f32x8::splat(-1e-30);
    let negative = Lanes::sign_bit(d);
    let zero = lanes_eq(d, f32x8::splat(0.0));
    let d = lanes_select(zero, lanes_select(negative, neg_tiny, tiny), d);
    f32x8::splat(1.0) / d
}
