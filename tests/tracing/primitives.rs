//! The BVH over the caller's primitives returns what the brute-force loop
//! over the caller's routine returns: closest hit (t, index and the data
//! the routine reported) and any hit, on random triangles and boxes with
//! degenerate ones (zero area, zero thickness, points), coplanar meshes
//! and stacked boxes sharing faces, duplicates (ties go to the lowest
//! index), huge ones kept out of the tree, and rays along faces and edges,
//! in axis directions, from surfaces and with odd ranges: 10⁶ rays over
//! 1,000 primitives of each kind and 10⁴ rays over 10,000; `--ignored`
//! adds 10⁶ rays over 100,000 of each. A routine that breaks the one requirement
//! (hits outside its box) is caught, so the agreement is not vacuous.

use glam::Vec3;
use rand_core::Rng;
use rand_pcg::Pcg32;
use strata::trace::{
    Aabb, BVH_MAX_DEPTH, BvhError, BvhNode8, BvhStack, PrimitiveBvh, Primitives, Ray,
    any_primitive_hit, closest_primitive_hit, primitive_bvh_storage_for,
};

use super::bvh::{range, unit};

/// Triangles, tested watertight (Woop, Benthin and Wald 2013: shear the
/// triangle into the ray's frame, signed edge functions, the depth as
/// their weighted sum): the hit's data is its barycentrics `(u, v)`.
struct Triangles {
    v: Vec<[Vec3; 3]>,
    /// How much `bounds` shrinks each box towards its centre (0; the
    /// must-fail control's boxes break the requirement).
    shrink: f32,
}

fn watertight(tri: &[Vec3; 3], ray: &Ray) -> Option<(f32, (f32, f32))> {
    let d = ray.dir;
    let kz = d.abs().max_position();
    let (mut kx, mut ky) = ((kz + 1) % 3, (kz + 2) % 3);
    if d[kz] < 0.0 {
        core::mem::swap(&mut kx, &mut ky);
    }
    let (sx, sy, sz) = (d[kx] / d[kz], d[ky] / d[kz], 1.0 / d[kz]);
    let rel = tri.map(|p| p - ray.origin);
    let sheared = rel.map(|a| (a[kx] - sx * a[kz], a[ky] - sy * a[kz]));
    let [(ax, ay), (bx, by), (cx, cy)] = sheared;
    let mut u = cx * by - cy * bx;
    let mut v = ax * cy - ay * cx;
    let mut w = bx * ay - by * ax;
    if u == 0.0 || v == 0.0 || w == 0.0 {
        // On an edge in f32: decide in f64, as the paper does.
        let f = |a: f32| a as f64;
        u = (f(cx) * f(by) - f(cy) * f(bx)) as f32;
        v = (f(ax) * f(cy) - f(ay) * f(cx)) as f32;
        w = (f(bx) * f(ay) - f(by) * f(ax)) as f32;
    }
    if (u < 0.0 || v < 0.0 || w < 0.0) && (u > 0.0 || v > 0.0 || w > 0.0) {
        return None;
    }
    let det = u + v + w;
    if det == 0.0 {
        return None;
    }
    let z = rel.map(|a| sz * a[kz]);
    let t = (u * z[0] + v * z[1] + w * z[2]) / det;
    (t > ray.t_min && t < ray.t_max).then_some((t, (u / det, v / det)))
}

impl Primitives for Triangles {
    type Data = (f32, f32);
    fn len(&self) -> usize {
        self.v.len()
    }
    fn bounds(&self, i: usize) -> Aabb {
        let b = Aabb::from_points(&self.v[i]);
        let cut = (b.max - b.min) * (0.5 * self.shrink);
        Aabb::new(b.min + cut, b.max - cut)
    }
    fn intersect(&self, i: usize, ray: &Ray) -> Option<(f32, (f32, f32))> {
        let hit = watertight(&self.v[i], ray)?;
        Aabb::from_points(&self.v[i])
            .holds_hit(ray, hit.0)
            .then_some(hit)
    }
}

/// Boxes, tested by slabs: the data is the axis of the face entered (3
/// from inside). Any hit uses its own test (`occludes`).
struct Boxes(Vec<Aabb>);

fn slab(b: &Aabb, ray: &Ray) -> Option<(f32, f32, usize)> {
    let inv = ray.dir.recip();
    let (mut near, mut far, mut axis) = (f32::NEG_INFINITY, f32::INFINITY, 3);
    for k in 0..3 {
        // A NaN (0 · ∞: the origin in a face plane, moving along it) says
        // nothing: `max` and `min` ignore it.
        let t0 = (b.min[k] - ray.origin[k]) * inv[k];
        let t1 = (b.max[k] - ray.origin[k]) * inv[k];
        let (lo, hi) = if t0 < t1 { (t0, t1) } else { (t1, t0) };
        if lo > near {
            (near, axis) = (lo, k);
        }
        far = far.min(hi);
    }
    (near <= far).then_some((near, far, axis))
}

impl Primitives for Boxes {
    type Data = u8;
    fn len(&self) -> usize {
        self.0.len()
    }
    fn bounds(&self, i: usize) -> Aabb {
        self.0[i]
    }
    fn intersect(&self, i: usize, ray: &Ray) -> Option<(f32, u8)> {
        let b = &self.0[i];
        let (near, far, axis) = slab(b, ray)?;
        let (t, axis) = if near > ray.t_min {
            (near, axis)
        } else {
            (far, 3)
        };
        (t > ray.t_min && t < ray.t_max && b.holds_hit(ray, t)).then_some((t, axis as u8))
    }
    fn occludes(&self, i: usize, ray: &Ray) -> bool {
        let b = &self.0[i];
        slab(b, ray).is_some_and(|(near, far, _)| {
            let t = if near > ray.t_min { near } else { far };
            t > ray.t_min && t < ray.t_max && b.holds_hit(ray, t)
        })
    }
}

fn point(rng: &mut Pcg32, s: f32) -> Vec3 {
    Vec3::new(range(rng, -s, s), range(rng, -s, s), range(rng, -s, s))
}

/// `n` triangles: mostly small random ones, with degenerate ones (zero
/// area: coincident or collinear vertices), a coplanar grid mesh on
/// `z = 0`, duplicates, and two huge ground triangles.
fn triangles(n: usize, rng: &mut Pcg32) -> Vec<[Vec3; 3]> {
    let size = 3.0 / (n as f32).cbrt();
    let mut v = Vec::with_capacity(n);
    // A 10 × 10 grid of quads on z = 0 (200 triangles sharing edges).
    let grid = if n >= 1000 { 10 } else { 0 };
    for i in 0..grid {
        for j in 0..grid {
            let p = |a: usize, b: usize| Vec3::new(a as f32 - 5.0, b as f32 - 5.0, 0.0);
            v.push([p(i, j), p(i + 1, j), p(i + 1, j + 1)]);
            v.push([p(i, j), p(i + 1, j + 1), p(i, j + 1)]);
        }
    }
    // The ground: one triangle far bigger than the rest.
    if n >= 1000 {
        let g = |x: f32, y: f32| Vec3::new(x, -12.0, y);
        v.push([g(-1e3, -1e3), g(2e3, -1e3), g(-1e3, 2e3)]);
    }
    let special = v.len();
    while v.len() < n {
        let c = point(rng, 10.0);
        let tri = match rng.next_u32() % 10 {
            // Coincident vertices.
            0 => [c, c, c + unit(rng) * size],
            // Collinear.
            1 => {
                let d = unit(rng) * size;
                [c, c + d, c + d * range(rng, -1.0, 2.0)]
            }
            // A duplicate of an earlier random one.
            2 if v.len() > special => v[special + (rng.next_u32() as usize) % (v.len() - special)],
            // Axis-aligned (flat in one coordinate).
            3 => {
                let k = (rng.next_u32() % 3) as usize;
                let mut t = [c, c + unit(rng) * size, c + unit(rng) * size];
                for p in &mut t {
                    p[k] = c[k];
                }
                t
            }
            _ => [c, c + unit(rng) * size, c + unit(rng) * size],
        };
        v.push(tri);
    }
    v
}

/// `n` boxes: random ones, flat ones (zero thickness), points, a stack of
/// unit cubes sharing faces, duplicates, and a huge floor slab.
fn boxes(n: usize, rng: &mut Pcg32) -> Vec<Aabb> {
    let size = 3.0 / (n as f32).cbrt();
    let mut b = Vec::with_capacity(n);
    if n >= 1000 {
        for i in 0..5 {
            for j in 0..5 {
                for k in 0..4 {
                    let lo = Vec3::new(i as f32, j as f32, k as f32) - Vec3::splat(2.0);
                    b.push(Aabb::new(lo, lo + Vec3::ONE));
                }
            }
        }
        b.push(Aabb::new([-1e3, -13.0, -1e3], [1e3, -12.0, 1e3]));
    }
    let special = b.len();
    while b.len() < n {
        let c = point(rng, 10.0);
        let e = Vec3::new(
            range(rng, 0.0, size),
            range(rng, 0.0, size),
            range(rng, 0.0, size),
        );
        let bx = match rng.next_u32() % 8 {
            0 => {
                let mut e = e;
                e[(rng.next_u32() % 3) as usize] = 0.0;
                Aabb::new(c, c + e)
            }
            1 => Aabb::new(c, c),
            2 if b.len() > special => b[special + (rng.next_u32() as usize) % (b.len() - special)],
            // An empty box: never hit, left out of the tree.
            3 if rng.next_u32().is_multiple_of(8) => Aabb::EMPTY,
            _ => Aabb::new(c, c + e),
        };
        b.push(bx);
    }
    b
}

/// Rays: from a box around the scene in random and axis directions,
/// aimed at a primitive's corner, centre or a point on an edge, in a face
/// or mesh plane (coplanar), from a surface point, and with odd ranges.
fn rays<P: Primitives>(prims: &P, n: usize, rng: &mut Pcg32) -> Vec<Ray> {
    let axis = |rng: &mut Pcg32| {
        let mut d = Vec3::ZERO;
        d[(rng.next_u32() % 3) as usize] = if rng.next_u32() & 1 == 0 { 1.0 } else { -1.0 };
        d
    };
    (0..n)
        .map(|k| {
            let o = point(rng, 14.0);
            let i = (rng.next_u32() as usize) % prims.len();
            let b = prims.bounds(i);
            let target = if b.is_empty() {
                Vec3::ZERO
            } else {
                let w = Vec3::new(
                    range(rng, 0.0, 1.0),
                    range(rng, 0.0, 1.0),
                    range(rng, 0.0, 1.0),
                );
                match rng.next_u32() % 3 {
                    0 => b.min,
                    1 => b.max,
                    _ => b.min + (b.max - b.min) * w,
                }
            };
            let ray = match k % 8 {
                0 => Ray::new(o, unit(rng)),
                1 => Ray::new(o, axis(rng)),
                2 | 3 => Ray::new(o, (target - o).normalize_or(Vec3::X)),
                4 => {
                    // In the plane z = 0 (the grid mesh) or a box face
                    // plane, along a direction in it.
                    let mut d = unit(rng);
                    d.z = 0.0;
                    let plane = if rng.next_u32() & 1 == 0 {
                        0.0
                    } else {
                        b.min.z
                    };
                    Ray::new(Vec3::new(o.x, o.y, plane), d.normalize_or(Vec3::X))
                }
                5 => Ray::new(target, unit(rng)),
                6 => Ray::new(target, axis(rng)),
                _ => Ray::new(o, (target - o).normalize_or(Vec3::X))
                    .with_range(range(rng, -1.0, 5.0), range(rng, 0.0, 30.0)),
            };
            if !ray.origin.is_finite() {
                Ray::new(o, unit(rng))
            } else {
                ray
            }
        })
        .collect()
}

/// Rays in the plane of a random tilted triangle (up to the rounding of
/// their directions) through a point inside it: where a watertight
/// test's weights are noise.
fn coplanar_rays(tris: &[[Vec3; 3]], n: usize, rng: &mut Pcg32) -> Vec<Ray> {
    let mut out = Vec::with_capacity(n);
    while out.len() < n {
        let t = tris[(rng.next_u32() as usize) % tris.len()];
        let normal = (t[1] - t[0]).cross(t[2] - t[0]);
        if normal.length().is_nan() || normal.length() <= 1e-6 {
            continue;
        }
        let normal = normal.normalize();
        let a = normal.any_orthonormal_vector();
        let b = normal.cross(a);
        let angle = range(rng, 0.0, core::f32::consts::TAU);
        let d = (a * angle.cos() + b * angle.sin()).normalize();
        let reach = (t[1] - t[0]).length() + (t[2] - t[0]).length();
        let (u, v) = (range(rng, 0.0, 1.0), range(rng, 0.0, 1.0));
        let (u, v) = if u + v > 1.0 {
            (1.0 - u, 1.0 - v)
        } else {
            (u, v)
        };
        let inside = t[0] + (t[1] - t[0]) * u + (t[2] - t[0]) * v;
        out.push(Ray::new(inside - d * range(rng, 0.0, 2.0 * reach), d));
    }
    out
}

/// Every ray's closest hit (all fields, bit for bit) and any hit through
/// the tree equal the brute-force loop's; returns how many hit.
fn assert_matches<P>(name: &str, prims: &P, bvh: &PrimitiveBvh<'_, P>, rays: &[Ray]) -> usize
where
    P: Primitives,
    P::Data: PartialEq + core::fmt::Debug,
{
    let bits = |h: Option<strata::trace::PrimitiveHit<P::Data>>| {
        h.map(|h| (h.t.to_bits(), h.primitive, h.data))
    };
    let mut stack = BvhStack::new();
    let mut hits = 0;
    for (k, ray) in rays.iter().enumerate() {
        let want = closest_primitive_hit(prims, ray);
        let got = bvh.closest_hit_with(ray, &mut stack);
        assert_eq!(bits(got), bits(want), "{name}: closest, ray {k} {ray:?}");
        let any = any_primitive_hit(prims, ray);
        assert_eq!(
            bvh.any_hit_with(ray, &mut stack),
            any,
            "{name}: any, ray {k} {ray:?}"
        );
        hits += usize::from(want.is_some());
    }
    // The queries without a caller's stack agree too.
    for ray in rays.iter().step_by(97) {
        assert_eq!(
            bits(bvh.closest_hit(ray)),
            bits(closest_primitive_hit(prims, ray))
        );
        assert_eq!(bvh.any_hit(ray), any_primitive_hit(prims, ray));
    }
    hits
}

/// Builds a tree over `n` triangles, checks `n_rays` rays; returns how
/// many hit.
fn run_triangles(n: usize, n_rays: usize, seed: u64) -> usize {
    let mut rng = Pcg32::new(seed, 37);
    let prims = Triangles {
        v: triangles(n, &mut rng),
        shrink: 0.0,
    };
    let s = primitive_bvh_storage_for(n);
    let (mut nodes, mut ids) = (vec![BvhNode8::EMPTY; s.nodes], vec![0; s.ids]);
    let bvh = PrimitiveBvh::build(&prims, &mut nodes, &mut ids).unwrap();
    assert!(bvh.depth() <= BVH_MAX_DEPTH && bvh.node_count() <= s.nodes);
    if n >= 1000 {
        assert_eq!(bvh.outliers(), 1, "the ground triangle");
    }
    // One ray in eight runs in a triangle's plane.
    let mut rays = rays(&prims, n_rays - n_rays / 8, &mut rng);
    rays.extend(coplanar_rays(&prims.v, n_rays / 8, &mut rng));
    assert_matches(&format!("{n} triangles"), &prims, &bvh, &rays)
}

/// [`run_triangles`] for boxes.
fn run_boxes(n: usize, n_rays: usize, seed: u64) -> usize {
    let mut rng = Pcg32::new(seed, 41);
    let prims = Boxes(boxes(n, &mut rng));
    let s = primitive_bvh_storage_for(n);
    let (mut nodes, mut ids) = (vec![BvhNode8::EMPTY; s.nodes], vec![0; s.ids]);
    let bvh = PrimitiveBvh::build(&prims, &mut nodes, &mut ids).unwrap();
    assert!(bvh.depth() <= BVH_MAX_DEPTH && bvh.node_count() <= s.nodes);
    if n >= 1000 {
        assert_eq!(bvh.outliers(), 1, "the floor slab");
    }
    let rays = rays(&prims, n_rays, &mut rng);
    assert_matches(&format!("{n} boxes"), &prims, &bvh, &rays)
}

/// Enough of both outcomes to mean something.
fn assert_mixed(hits: usize, rays: usize) {
    assert!(
        hits > rays / 5 && hits < rays * 19 / 20,
        "{hits} of {rays} hit"
    );
}

#[test]
fn triangles_match_brute_force_million_rays() {
    assert_mixed(run_triangles(1000, 1_000_000, 1), 1_000_000);
}

#[test]
fn boxes_match_brute_force_million_rays() {
    assert_mixed(run_boxes(1000, 1_000_000, 2), 1_000_000);
}

#[test]
fn ten_thousand_primitives_match_brute_force() {
    assert_mixed(run_triangles(10_000, 10_000, 3), 10_000);
    assert_mixed(run_boxes(10_000, 10_000, 4), 10_000);
}

#[test]
fn small_trees_match_brute_force() {
    for n in [1, 2, 7, 8, 9, 17, 64, 100] {
        let hits = run_triangles(n, 20_000, 10 + n as u64) + run_boxes(n, 20_000, 20 + n as u64);
        assert!(hits > 0, "{n}: nothing hit");
    }
}

/// The larger run: 10⁶ rays over 100,000 triangles and 10⁶ over 100,000
/// boxes (brute force makes it slow: 2 · 10¹¹ routine calls).
#[test]
#[ignore = "10^6 rays x 10^5 primitives, twice, of brute force: run with --ignored"]
fn hundred_thousand_primitives_match_brute_force() {
    std::thread::scope(|s| {
        s.spawn(|| assert_mixed(run_triangles(100_000, 1_000_000, 5), 1_000_000));
        s.spawn(|| assert_mixed(run_boxes(100_000, 1_000_000, 6), 1_000_000));
    });
}

/// Why the routines above check their hit point against their box: a
/// watertight test alone, on rays within rounding of a tilted triangle's
/// plane through it, reports a few hits far outside the triangle's box
/// (its weights are noise there), which a tree that skips the box would
/// not find. The coplanar rays of the suite reach these cases.
#[test]
fn watertight_alone_can_hit_outside_its_box() {
    let mut rng = Pcg32::new(9, 9);
    let v: Vec<[Vec3; 3]> = (0..2000)
        .map(|_| {
            let c = point(&mut rng, 10.0);
            [c, c + unit(&mut rng), c + unit(&mut rng)]
        })
        .collect();
    let (mut hits, mut outside) = (0, 0);
    for ray in &coplanar_rays(&v, 20_000, &mut rng) {
        for t in &v {
            if let Some((t_hit, _)) = watertight(t, ray) {
                hits += 1;
                let b = Aabb::from_points(t);
                outside += usize::from(!b.holds_hit(ray, t_hit));
            }
        }
    }
    assert!(
        hits > 5000 && outside > 0,
        "{outside} of {hits} hits outside"
    );
}

/// Must fail: boxes 10 % too small (the requirement broken) make the tree
/// disagree with brute force on the suite's rays, so the agreement above
/// is not vacuous: the rays reach what a wrongly skipped box would lose.
#[test]
fn boxes_too_small_break_the_agreement() {
    let mut rng = Pcg32::new(9, 9);
    let prims = Triangles {
        v: triangles(1000, &mut rng),
        shrink: 0.1,
    };
    let s = primitive_bvh_storage_for(prims.len());
    let (mut nodes, mut ids) = (vec![BvhNode8::EMPTY; s.nodes], vec![0; s.ids]);
    let bvh = PrimitiveBvh::build(&prims, &mut nodes, &mut ids).unwrap();
    let differ = rays(&prims, 20_000, &mut rng)
        .iter()
        .filter(|ray| {
            let want = closest_primitive_hit(&prims, ray).map(|h| (h.t.to_bits(), h.primitive));
            want != bvh.closest_hit(ray).map(|h| (h.t.to_bits(), h.primitive))
        })
        .count();
    assert!(
        differ > 0,
        "no disagreement: the control does not reach its cases"
    );
}

#[test]
fn bad_bounds_and_short_storage_are_errors() {
    let mut rng = Pcg32::new(3, 3);
    let mut b = boxes(100, &mut rng);
    let s = primitive_bvh_storage_for(b.len());
    let (mut nodes, mut ids) = (vec![BvhNode8::EMPTY; s.nodes], vec![0; s.ids]);
    for (bad, what) in [
        (Aabb::new([0.0, f32::NAN, 0.0], [1.0; 3]), "NaN"),
        (Aabb::new([0.0; 3], [f32::INFINITY, 1.0, 1.0]), "infinite"),
        (Aabb::new([0.0; 3], [2e18, 1.0, 1.0]), "beyond the limit"),
    ] {
        let keep = b[42];
        b[42] = bad;
        let err = PrimitiveBvh::build(&Boxes(b.clone()), &mut nodes, &mut ids).unwrap_err();
        assert_eq!(err, BvhError::BoundsOutOfRange { index: 42 }, "{what}");
        b[42] = keep;
    }
    let prims = Boxes(b);
    let err = PrimitiveBvh::build(&prims, &mut nodes[..s.nodes - 1], &mut ids).unwrap_err();
    assert!(matches!(
        err,
        BvhError::StorageTooSmall { slice: "nodes", .. }
    ));
    let err = PrimitiveBvh::build(&prims, &mut nodes, &mut ids[..99]).unwrap_err();
    assert!(matches!(
        err,
        BvhError::StorageTooSmall { slice: "ids", .. }
    ));
    // Empty: builds, hits nothing.
    let none = Boxes(Vec::new());
    let (mut n0, mut i0) = ([BvhNode8::EMPTY; 1], [0u32; 0]);
    let bvh = PrimitiveBvh::build(&none, &mut n0, &mut i0).unwrap();
    assert!(bvh.is_empty() && bvh.closest_hit(&Ray::new(Vec3::ZERO, Vec3::X)).is_none());
}

/// The same primitives in the same order give the same tree, and a tree
/// over spheres as primitives finds the sphere kernel's hits.
#[test]
fn builds_are_deterministic() {
    let mut rng = Pcg32::new(5, 5);
    let prims = Boxes(boxes(3000, &mut rng));
    let s = primitive_bvh_storage_for(prims.len());
    let mut a = (vec![BvhNode8::EMPTY; s.nodes], vec![0; s.ids]);
    let mut b = (vec![BvhNode8::EMPTY; s.nodes], vec![7; s.ids]);
    let (na, nb) = {
        let x = PrimitiveBvh::build(&prims, &mut a.0, &mut a.1).unwrap();
        let y = PrimitiveBvh::build(&prims, &mut b.0, &mut b.1).unwrap();
        ((x.node_count(), x.depth()), (y.node_count(), y.depth()))
    };
    assert_eq!(na, nb);
    assert_eq!(a.1, b.1);
    assert_eq!(format!("{:?}", a.0), format!("{:?}", b.0));
}

/// A view of kept storage answers as the tree the build returned; storage
/// from another build, or viewed over other primitives, is refused.
#[test]
fn views_of_kept_storage_answer_as_the_build() {
    let mut rng = Pcg32::new(8, 8);
    let prims = Boxes(boxes(2000, &mut rng));
    let s = primitive_bvh_storage_for(prims.len());
    let (mut nodes, mut ids) = (vec![BvhNode8::EMPTY; s.nodes], vec![0; s.ids]);
    let built = format!(
        "{:?}",
        PrimitiveBvh::build(&prims, &mut nodes, &mut ids).unwrap()
    );
    let view = PrimitiveBvh::from_parts(&prims, &nodes, &ids).unwrap();
    assert_eq!(format!("{view:?}"), built);
    assert_matches("view", &prims, &view, &rays(&prims, 20_000, &mut rng));
    // Other primitives: fewer, or moved.
    let fewer = Boxes(prims.0[..1999].to_vec());
    assert!(PrimitiveBvh::from_parts(&fewer, &nodes, &ids).is_err());
    let moved = Boxes(
        prims
            .0
            .iter()
            .map(|b| Aabb::new(b.min + 1.0, b.max + 1.0))
            .collect(),
    );
    assert!(PrimitiveBvh::from_parts(&moved, &nodes, &ids).is_err());
    // Nodes of another build over the same count.
    let other = Boxes(boxes(2000, &mut rng));
    let (mut nodes2, mut ids2) = (vec![BvhNode8::EMPTY; s.nodes], vec![0; s.ids]);
    PrimitiveBvh::build(&other, &mut nodes2, &mut ids2).unwrap();
    assert!(PrimitiveBvh::from_parts(&prims, &nodes2, &ids).is_err());
    assert!(PrimitiveBvh::from_parts(&prims, &nodes, &ids2).is_err());
    // Short slices.
    assert!(PrimitiveBvh::from_parts(&prims, &nodes[..s.nodes - 1], &ids).is_err());
    assert!(PrimitiveBvh::from_parts(&prims, &nodes, &ids[..1999]).is_err());
}
