//! Views of built storage: [`Bvh::from_parts`] and
//! [`PrimitiveBvh::from_parts`] check that slices kept from a build (in a
//! struct, another thread's buffers) still hold a tree the build
//! could have written, so that every query stays in bounds, ends, and
//! skips no box it must enter; then they view it without copying.

use super::build::{Box3, sphere_box};
use super::primitive::{bounds_in_range, padded, primitive_bvh_storage_for};
use super::{
    BVH_MAX_COORDINATE, BVH_MAX_DEPTH, BVH_MAX_SPHERES, Bvh, BvhError, BvhNode8, LEAF_BIT,
    PACKET_FALLBACK, PrimitiveBvh, Primitives, Shape, bvh_storage_for,
};
use crate::trace::Sphere;

fn invalid(reason: &'static str) -> BvhError {
    BvhError::InvalidStorage { reason }
}

/// The Mersenne prime `2⁶¹ − 1`, the modulus of [`IdSums`].
const SUMS_MODULUS: u64 = (1 << 61) - 1;

/// The count and the power sums `Σ idᵏ mod (2⁶¹ − 1)`, `k = 1..=4`, of a
/// list of ids: a check without memory that two lists hold the same ids.
/// Lists of equal count that differ in at most four entries always differ
/// here (Newton's identities: four power sums fix the multiset of the
/// differing entries, ids being below the modulus); lists that differ in
/// more differ unless four 61-bit sums agree by chance.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub(super) struct IdSums {
    count: usize,
    sums: [u64; 4],
}

impl IdSums {
    /// Adds one id.
    pub(super) fn add(&mut self, id: u32) {
        let mul =
            |a: u64, b: u64| ((u128::from(a) * u128::from(b)) % u128::from(SUMS_MODULUS)) as u64;
        let x = u64::from(id);
        let mut power = x;
        for sum in &mut self.sums {
            *sum = (*sum + power) % SUMS_MODULUS;
            power = mul(power, x);
        }
        self.count += 1;
    }

    /// The sums of `ids`.
    pub(super) fn of(ids: impl IntoIterator<Item = u32>) -> Self {
        let mut s = Self::default();
        for id in ids {
            s.add(id);
        }
        s
    }
}

/// Checks the lengths of the slices against what `n` items need.
fn check_lengths(n: usize, slices: [(&'static str, usize, usize); 3]) -> Result<(), BvhError> {
    if n > BVH_MAX_SPHERES {
        return Err(BvhError::TooManySpheres);
    }
    for (slice, needed, provided) in slices {
        if provided < needed {
            return Err(BvhError::StorageTooSmall {
                slice,
                needed,
                provided,
            });
        }
    }
    Ok(())
}

/// The tree walk of a check: node indices in the build's preorder, every
/// child's box holding what is under it, leaves partitioning the items.
struct Checker<'s, F> {
    nodes: &'s [BvhNode8],
    /// Items in use (the ids before the first `u32::MAX`).
    m: usize,
    /// The padded box of the item at a position.
    item_box: F,
    /// The next node index the preorder expects.
    next: usize,
    depth: u32,
}

impl<F: FnMut(usize) -> Result<Box3, BvhError>> Checker<'_, F> {
    /// Checks node `index` at `depth`; returns the range of item
    /// positions under it and the union of its children's stored boxes.
    fn node(&mut self, index: usize, depth: u32) -> Result<((usize, usize), Box3), BvhError> {
        if depth > BVH_MAX_DEPTH {
            return Err(invalid("deeper than BVH_MAX_DEPTH"));
        }
        self.depth = self.depth.max(depth);
        let node = self
            .nodes
            .get(index)
            .ok_or(invalid("a child index past the nodes"))?;
        let count = node.count as usize;
        if !(1..=8).contains(&count) {
            return Err(invalid("a node without 1 to 8 children"));
        }
        let lanes = |v: &crate::lanes::f32x8| v.to_array();
        let (min, max) = (
            [lanes(&node.min_x), lanes(&node.min_y), lanes(&node.min_z)],
            [lanes(&node.max_x), lanes(&node.max_y), lanes(&node.max_z)],
        );
        let mut ranges = [(0usize, 0usize); 8];
        let mut all = Box3::EMPTY;
        for k in 0..count {
            let child = node.child[k];
            let (range, content) = if child & LEAF_BIT != 0 {
                let start = ((child & !LEAF_BIT) >> 3) as usize;
                let end = start + (child & 7) as usize + 1;
                if end > self.m {
                    return Err(invalid("a leaf past the items"));
                }
                let mut b = Box3::EMPTY;
                for pos in start..end {
                    b.grow(&(self.item_box)(pos)?);
                }
                ((start, end), b)
            } else {
                // The build numbers nodes in preorder: this also rules out
                // shared children and cycles.
                if child as usize != self.next {
                    return Err(invalid("nodes out of the build's order"));
                }
                self.next += 1;
                self.node(child as usize, depth + 1)?
            };
            let stored = Box3 {
                min: [min[0][k], min[1][k], min[2][k]],
                max: [max[0][k], max[1][k], max[2][k]],
            };
            // NaN compares false: a NaN box is refused.
            let holds = (0..3).all(|a| {
                let empty = content.min[a] > content.max[a];
                empty || stored.min[a] <= content.min[a] && content.max[a] <= stored.max[a]
            });
            if !holds {
                return Err(invalid("a box does not hold what is under it"));
            }
            all.grow(&stored);
            ranges[k] = range;
        }
        let ranges = &mut ranges[..count];
        ranges.sort_unstable();
        if ranges.windows(2).any(|w| w[0].1 != w[1].0) {
            return Err(invalid("leaves that overlap or leave items out"));
        }
        Ok(((ranges[0].0, ranges[count - 1].1), all))
    }
}

/// Checks a tree over the items `ids[..m]` (`m`: the first `u32::MAX`,
/// all after it `u32::MAX`; every id below `n`) and returns its shape.
fn check_tree(
    nodes: &[BvhNode8],
    ids: &[u32],
    n: usize,
    item_box: impl FnMut(usize) -> Result<Box3, BvhError>,
) -> Result<Shape, BvhError> {
    let m = ids.iter().position(|&i| i == u32::MAX).unwrap_or(ids.len());
    if ids[m..].iter().any(|&i| i != u32::MAX) {
        return Err(invalid("an id after the unused ones"));
    }
    // A leaf's 8-wide loads reach 7 past its start: items past `n` would
    // take them past the storage.
    if m > n {
        return Err(invalid("more ids in use than items"));
    }
    if ids[..m].iter().any(|&i| i as usize >= n) {
        return Err(invalid("an id past the items"));
    }
    let mut c = Checker {
        nodes,
        m,
        item_box,
        next: 1,
        depth: 1,
    };
    let root = nodes.first().ok_or(invalid("no root node"))?;
    let outliers = if root.count == 0 {
        // An empty tree: every item is an outlier (the build makes one
        // only when there are none).
        m
    } else {
        let ((lo, hi), _) = c.node(0, 1)?;
        if hi != m {
            return Err(invalid("leaves that leave items out"));
        }
        lo
    };
    if outliers > 8 {
        return Err(invalid("more than 8 items outside the tree"));
    }
    // Outliers are tested on their own: their boxes must be sound too.
    for pos in 0..outliers {
        (c.item_box)(pos)?;
    }
    Ok(Shape {
        len: n,
        outliers,
        used_nodes: c.next,
        depth: c.depth,
    })
}

impl<'a> Bvh<'a> {
    /// A view of a tree over `len` spheres that [`Bvh::build`] wrote
    /// earlier into these slices (kept, for instance, in a struct that
    /// owns its storage), after checking it, in `O(len)`: the lengths;
    /// every node reachable in the build's order with 1 to 8 children and
    /// at most [`BVH_MAX_DEPTH`] levels; every box holding the padded boxes
    /// of the spheres under it (recomputed from the sphere lanes); the
    /// leaves covering each stored sphere once; ids below `len`. So every
    /// query stays in bounds, ends, and returns the brute-force answer over
    /// the spheres in the lanes. Which spheres those should be it cannot
    /// know without them: [`Bvh::built_from`] checks the lanes and ids
    /// against the spheres (an id repeated or left out is found when at
    /// most four ids differ from the build's, and otherwise unless four
    /// 61-bit sums agree by chance).
    ///
    /// ```
    /// use glam::Vec3;
    /// use strata::trace::*;
    /// let spheres: Vec<Sphere> =
    ///     (0..50).map(|i| Sphere::new(Vec3::new(i as f32, 0.0, -5.0), 0.4)).collect();
    /// let size = bvh_storage_for(spheres.len());
    /// let (mut nodes, mut lanes, mut ids) =
    ///     (vec![BvhNode8::EMPTY; size.nodes], vec![0.0; size.lanes], vec![0; size.ids]);
    /// Bvh::build(&spheres, &mut nodes, &mut lanes, &mut ids).unwrap();
    /// // Later, from the kept buffers:
    /// let bvh = Bvh::from_parts(&nodes, &lanes, &ids, spheres.len()).unwrap();
    /// assert!(bvh.built_from(&spheres));
    /// let ray = Ray::new(Vec3::new(7.0, 0.0, 0.0), -Vec3::Z);
    /// assert_eq!(bvh.closest_hit(&ray).map(|h| h.sphere), Some(7));
    /// // Damaged storage is refused.
    /// lanes[3] = f32::NAN;
    /// assert!(Bvh::from_parts(&nodes, &lanes, &ids, spheres.len()).is_err());
    /// ```
    #[inline]
    pub fn from_parts(
        nodes: &'a [BvhNode8],
        lanes: &'a [f32],
        ids: &'a [u32],
        len: usize,
    ) -> Result<Self, BvhError> {
        let need = bvh_storage_for(len);
        check_lengths(
            len,
            [
                ("nodes", need.nodes, nodes.len()),
                ("lanes", need.lanes, lanes.len()),
                ("ids", need.ids, ids.len()),
            ],
        )?;
        let width = need.ids;
        let (nodes, ids) = (&nodes[..need.nodes], &ids[..width]);
        let (cx, rest) = lanes[..need.lanes].split_at(width);
        let (cy, rest) = rest.split_at(width);
        let (cz, r) = rest.split_at(width);
        let shape = check_tree(nodes, ids, len, |pos| {
            let s = Sphere::new(glam::Vec3::new(cx[pos], cy[pos], cz[pos]), r[pos]);
            let ok = |x: f32| x.abs() < BVH_MAX_COORDINATE;
            if !(ok(s.center.x) && ok(s.center.y) && ok(s.center.z) && ok(s.radius)) {
                return Err(BvhError::SphereOutOfRange {
                    index: ids[pos] as usize,
                });
            }
            Ok(sphere_box(&s))
        })?;
        Ok(Bvh {
            nodes,
            cx,
            cy,
            cz,
            r,
            ids,
            shape,
            packet_fallback: PACKET_FALLBACK,
        })
    }
}

impl<'a, P: Primitives + ?Sized> PrimitiveBvh<'a, P> {
    /// A view of a tree that [`PrimitiveBvh::build`] wrote earlier into
    /// these slices over `prims`, after the checks of [`Bvh::from_parts`]
    /// (boxes recomputed from `prims.bounds`), in `O(n)` calls of
    /// `bounds`. The ids must list every primitive with a box once: an id
    /// repeated or left out is refused when at most four ids differ from
    /// the build's, and otherwise unless four 61-bit sums agree by chance
    /// (a check without memory).
    ///
    /// ```
    /// use strata::trace::*;
    /// struct Dots;
    /// impl Primitives for Dots {
    ///     type Data = ();
    ///     fn len(&self) -> usize { 20 }
    ///     fn bounds(&self, i: usize) -> Aabb { Aabb::new([i as f32; 3], [i as f32 + 0.5; 3]) }
    ///     fn intersect(&self, _: usize, _: &Ray) -> Option<(f32, ())> { None }
    /// }
    /// let size = primitive_bvh_storage_for(20);
    /// let (mut nodes, mut ids) = (vec![BvhNode8::EMPTY; size.nodes], vec![0; size.ids]);
    /// PrimitiveBvh::build(&Dots, &mut nodes, &mut ids).unwrap();
    /// let bvh = PrimitiveBvh::from_parts(&Dots, &nodes, &ids).unwrap();
    /// assert_eq!(bvh.len(), 20);
    /// ids.swap(0, 19); // another order: the boxes no longer hold their leaves
    /// assert!(PrimitiveBvh::from_parts(&Dots, &nodes, &ids).is_err());
    /// ```
    #[inline]
    pub fn from_parts(
        prims: &'a P,
        nodes: &'a [BvhNode8],
        ids: &'a [u32],
    ) -> Result<Self, BvhError> {
        let n = prims.len();
        let need = primitive_bvh_storage_for(n);
        check_lengths(
            n,
            [
                ("nodes", need.nodes, nodes.len()),
                ("ids", need.ids, ids.len()),
                ("lanes", 0, 0),
            ],
        )?;
        let (nodes, ids) = (&nodes[..need.nodes], &ids[..n]);
        let shape = check_tree(nodes, ids, n, |pos| {
            let index = ids[pos] as usize;
            let b = prims.bounds(index);
            if b.min.is_nan() || b.max.is_nan() || (!b.is_empty() && !bounds_in_range(&b)) {
                return Err(BvhError::BoundsOutOfRange { index });
            }
            Ok(padded(&b))
        })?;
        // The build lists every primitive with a box, once, in some order.
        let expected = IdSums::of((0..n as u32).filter(|&i| !prims.bounds(i as usize).is_empty()));
        let held = IdSums::of(ids.iter().copied().take_while(|&i| i != u32::MAX));
        if held != expected {
            return Err(invalid("ids that repeat or leave a primitive out"));
        }
        Ok(Self::assemble(prims, nodes, ids, shape))
    }
}

#[cfg(test)]
mod tests {
    use super::super::{Bvh, BvhNode8, bvh_storage_for};
    use crate::lanes::f32x8;
    use crate::trace::{HitPacket8, Ray, RayPacket8, Sphere, any_hit, closest_hit};
    use glam::Vec3;
    use rand_core::Rng;
    use rand_pcg::Pcg32;
    use std::vec;
    use std::vec::Vec;

    fn f(rng: &mut Pcg32) -> f32 {
        (rng.next_u32() >> 8) as f32 / 16_777_216.0
    }

    /// Damaged storage (one field of a node, an id or a lane changed at
    /// random) is refused, or, where accepted, answers every query
    /// exactly as brute force over the spheres its lanes hold: never a
    /// panic, a hang or a missed sphere.
    #[test]
    fn damaged_storage_is_refused_or_still_exact() {
        let mut rng = Pcg32::new(17, 17);
        let mut spheres: Vec<Sphere> = (0..300)
            .map(|_| {
                let c = Vec3::new(f(&mut rng), f(&mut rng), f(&mut rng)) * 20.0 - 10.0;
                Sphere::new(c, 0.1 + 0.5 * f(&mut rng))
            })
            .collect();
        spheres.push(Sphere::new(Vec3::new(0.0, -1000.0, 0.0), 990.0));
        let n = spheres.len();
        let size = bvh_storage_for(n);
        let (mut nodes, mut lanes, mut ids) = (
            vec![BvhNode8::EMPTY; size.nodes],
            vec![0.0; size.lanes],
            vec![0u32; size.ids],
        );
        let used = Bvh::build(&spheres, &mut nodes, &mut lanes, &mut ids)
            .unwrap()
            .node_count();
        assert!(Bvh::from_parts(&nodes, &lanes, &ids, n).is_ok());
        let rays: Vec<Ray> = (0..64)
            .map(|_| {
                let o = Vec3::new(f(&mut rng), f(&mut rng), f(&mut rng)) * 24.0 - 12.0;
                let d = Vec3::new(f(&mut rng), f(&mut rng), f(&mut rng)) * 2.0 - 1.0;
                Ray::new(o, d.normalize())
            })
            .collect();
        let (mut refused, mut accepted) = (0, 0);
        for trial in 0..4000 {
            let (mut nodes, mut lanes, mut ids) = (nodes.clone(), lanes.clone(), ids.clone());
            let node = &mut nodes[(rng.next_u32() as usize) % used];
            let k = (rng.next_u32() % 8) as usize;
            let x = rng.next_u32();
            match trial % 8 {
                0 => node.count = x % 12,
                1 => node.child[k] = x,
                2 => node.child[k] = x % (used as u32 + 2),
                3 => node.child[k] = (1 << 31) | (x % 4096),
                4 | 5 => {
                    let mut a = node.min_x.to_array();
                    a[k] += [1.0, -1.0, f32::NAN, 1e-3][(x % 4) as usize];
                    node.min_x = f32x8::new(a);
                    let mut b = node.max_z.to_array();
                    b[(k + 3) % 8] -= [0.0, 1e-4, 2.0, -1.0][(x % 4) as usize];
                    node.max_z = f32x8::new(b);
                }
                6 => {
                    let i = (x as usize) % ids.len();
                    let j = (rng.next_u32() as usize) % n;
                    ids[i] =
                        [x % 400, u32::MAX, ids[(i + 1) % ids.len()], ids[j]][(x % 4) as usize];
                }
                _ => {
                    let i = (x as usize) % lanes.len();
                    lanes[i] = [lanes[i] + 0.5, f32::NAN, 3e18, 0.0][(x % 4) as usize];
                }
            }
            let Ok(bvh) = Bvh::from_parts(&nodes, &lanes, &ids, n) else {
                refused += 1;
                continue;
            };
            accepted += 1;
            // The spheres the lanes hold, at their ids (when distinct).
            let width = ids.len();
            let mut held = vec![Sphere::new(Vec3::ZERO, 0.0); n];
            let mut seen = vec![false; n];
            let mut distinct = true;
            for pos in 0..width {
                let Some(&id) = ids.get(pos).filter(|&&id| id != u32::MAX) else {
                    break;
                };
                distinct &= !std::mem::replace(&mut seen[id as usize], true);
                let l = |a: usize| lanes[a * width + pos];
                held[id as usize] = Sphere::new(Vec3::new(l(0), l(1), l(2)), l(3));
            }
            // A repeated id means a sphere left out: never taken for the
            // build's tree.
            if !distinct {
                assert!(!bvh.built_from(&spheres), "trial {trial}");
            }
            for ray in &rays {
                let got = bvh.closest_hit(ray);
                let any = bvh.any_hit(ray);
                let mut hits = HitPacket8::NONE;
                bvh.closest_hit_x8(&RayPacket8::from_rays(&[*ray; 8]), &mut hits);
                if distinct {
                    assert_eq!(got, closest_hit(&held, ray), "trial {trial}");
                    assert_eq!(any, any_hit(&held, ray), "trial {trial}");
                    assert_eq!(hits.hit(3), got, "trial {trial}");
                }
            }
        }
        assert!(
            Bvh::from_parts(&nodes, &lanes, &ids, n)
                .unwrap()
                .built_from(&spheres)
        );
        std::eprintln!("{refused} refused, {accepted} accepted");
        assert!(
            refused > 1000 && accepted > 100,
            "{refused} refused, {accepted} accepted"
        );
    }

    /// Storage of a larger tree viewed as a smaller one (its ids folded
    /// into range) is refused: its leaves would load lanes past the
    /// storage. And a view repeating an id is never the build's.
    #[test]
    fn a_larger_tree_viewed_as_a_smaller_one_is_refused() {
        let spheres: Vec<Sphere> = (0..9)
            .map(|i| Sphere::new(Vec3::new(i as f32 * 3.0, 0.0, -5.0), 1.0))
            .collect();
        let size = bvh_storage_for(spheres.len());
        let (mut nodes, mut lanes, mut ids) = (
            vec![BvhNode8::EMPTY; size.nodes],
            vec![0.0; size.lanes],
            vec![0u32; size.ids],
        );
        Bvh::build(&spheres, &mut nodes, &mut lanes, &mut ids).unwrap();
        for len in 0..9 {
            let folded: Vec<u32> = ids
                .iter()
                .map(|&i| {
                    if i == u32::MAX || len == 0 {
                        i
                    } else {
                        i % len as u32
                    }
                })
                .collect();
            let need = bvh_storage_for(len);
            // Lanes re-laid at the smaller width, as such storage would be.
            let mut small = vec![0.0; need.lanes];
            for a in 0..4 {
                for pos in 0..need.ids {
                    small[a * need.ids + pos] = lanes[a * size.ids + pos];
                }
            }
            assert!(
                Bvh::from_parts(&nodes, &small, &folded, len).is_err(),
                "len {len}"
            );
        }
        let mut twice = ids.clone();
        twice[1] = twice[0];
        if let Ok(bvh) = Bvh::from_parts(&nodes, &lanes, &twice, spheres.len()) {
            assert!(!bvh.built_from(&spheres));
        }
    }

    /// Primitives whose boxes overlap, so ids can move between leaves
    /// without a box check noticing.
    struct Dots(usize);
    impl crate::trace::Primitives for Dots {
        type Data = ();
        fn len(&self) -> usize {
            self.0
        }
        fn bounds(&self, i: usize) -> crate::trace::Aabb {
            // Every third primitive can never be hit: the build leaves it out.
            if i % 3 == 2 {
                return crate::trace::Aabb::new([1.0; 3], [0.0; 3]);
            }
            crate::trace::Aabb::new([0.0; 3], [1.0; 3])
        }
        fn intersect(&self, _: usize, _: &Ray) -> Option<(f32, ())> {
            None
        }
    }

    /// A primitive tree whose ids repeat one or leave one out is refused,
    /// though every box still holds its leaves.
    #[test]
    fn primitive_ids_that_repeat_or_leave_one_out_are_refused() {
        use super::super::{PrimitiveBvh, primitive_bvh_storage_for};
        let prims = Dots(40);
        let size = primitive_bvh_storage_for(prims.0);
        let (mut nodes, mut ids) = (vec![BvhNode8::EMPTY; size.nodes], vec![0u32; size.ids]);
        PrimitiveBvh::build(&prims, &mut nodes, &mut ids).unwrap();
        assert!(PrimitiveBvh::from_parts(&prims, &nodes, &ids).is_ok());
        let used = ids.iter().take_while(|&&i| i != u32::MAX).count();
        assert_eq!(used, 27);
        for (a, b) in [(0, 1), (5, 20), (26, 0)] {
            let mut twice = ids.clone();
            twice[a] = twice[b];
            assert!(PrimitiveBvh::from_parts(&prims, &nodes, &twice).is_err());
            // An unhittable primitive's id in place of a hittable one.
            let mut other = ids.clone();
            other[a] = 2;
            assert!(PrimitiveBvh::from_parts(&prims, &nodes, &other).is_err());
        }
    }

    /// Lists of equal length that differ in one to four entries always
    /// have different sums (a must-pass of the exactness claim; the
    /// control: a reordering keeps them).
    #[test]
    fn id_sums_tell_lists_apart_that_differ_in_up_to_four_entries() {
        use super::IdSums;
        let mut rng = Pcg32::new(3, 5);
        let base: Vec<u32> = (0..1000).collect();
        let sums = IdSums::of(base.iter().copied());
        for trial in 0..20_000 {
            let mut ids = base.clone();
            let changes = 1 + trial % 4;
            for _ in 0..changes {
                let i = (rng.next_u32() % 1000) as usize;
                ids[i] = rng.next_u32() % (1 << 27);
            }
            let mut sorted = ids.clone();
            sorted.sort_unstable();
            if sorted != base {
                assert_ne!(IdSums::of(ids.iter().copied()), sums, "trial {trial}");
            }
        }
        let mut shuffled = base.clone();
        shuffled.reverse();
        shuffled.swap(3, 700);
        assert_eq!(IdSums::of(shuffled.iter().copied()), sums);
    }
}
