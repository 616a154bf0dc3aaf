//! The owning buffers of the `alloc` feature: the trees they hold answer
//! as the borrowed builds do, and a struct can hold them across threads.
//! Run with `cargo test -p strata --features alloc`.

use glam::Vec3;
use rand_core::Rng;
use rand_pcg::Pcg32;
use strata::trace::{
    Aabb, Bvh, BvhNode8, OwnedBvh, OwnedPrimitiveBvh, PrimitiveBvh, Primitives, Ray, Sphere,
    bvh_storage_for, intersect_sphere, primitive_bvh_storage_for,
};

fn f(rng: &mut Pcg32) -> f32 {
    (rng.next_u32() >> 8) as f32 / 16_777_216.0
}

fn spheres(n: usize, rng: &mut Pcg32) -> Vec<Sphere> {
    (0..n)
        .map(|_| {
            let c = Vec3::new(f(rng), f(rng), f(rng)) * 20.0 - 10.0;
            Sphere::new(c, 0.1 + 0.4 * f(rng))
        })
        .collect()
}

fn rays(n: usize, rng: &mut Pcg32) -> Vec<Ray> {
    (0..n)
        .map(|_| {
            let o = Vec3::new(f(rng), f(rng), f(rng)) * 24.0 - 12.0;
            let d = Vec3::new(f(rng), f(rng), f(rng)) * 2.0 - 1.0;
            Ray::new(o, d.normalize_or(Vec3::X))
        })
        .collect()
}

/// Spheres as the caller's primitives, owned.
struct Balls(Vec<Sphere>);

impl Primitives for Balls {
    type Data = ();
    fn len(&self) -> usize {
        self.0.len()
    }
    fn bounds(&self, i: usize) -> Aabb {
        let s = self.0[i];
        Aabb::new(s.center - s.radius, s.center + s.radius)
    }
    fn intersect(&self, i: usize, ray: &Ray) -> Option<(f32, ())> {
        intersect_sphere(&self.0[i], ray).map(|t| (t, ()))
    }
}

#[test]
fn owned_trees_answer_as_borrowed_builds() {
    let mut rng = Pcg32::new(1, 1);
    let s = spheres(3000, &mut rng);
    let size = bvh_storage_for(s.len());
    let (mut nodes, mut lanes, mut ids) = (
        vec![BvhNode8::EMPTY; size.nodes],
        vec![0.0; size.lanes],
        vec![0; size.ids],
    );
    let borrowed = Bvh::build(&s, &mut nodes, &mut lanes, &mut ids).unwrap();
    let owned = OwnedBvh::build(&s).unwrap();
    let view = owned.view();
    assert!(view.built_from(&s));
    assert_eq!(
        (view.node_count(), view.depth(), view.outliers()),
        (borrowed.node_count(), borrowed.depth(), borrowed.outliers())
    );
    let balls = Balls(s.clone());
    let psize = primitive_bvh_storage_for(s.len());
    let (mut pnodes, mut pids) = (vec![BvhNode8::EMPTY; psize.nodes], vec![0; psize.ids]);
    let pborrowed = PrimitiveBvh::build(&balls, &mut pnodes, &mut pids).unwrap();
    let powned = OwnedPrimitiveBvh::build(Balls(s.clone())).unwrap();
    for ray in rays(20_000, &mut rng) {
        assert_eq!(view.closest_hit(&ray), borrowed.closest_hit(&ray));
        assert_eq!(view.any_hit(&ray), borrowed.any_hit(&ray));
        assert_eq!(powned.view().closest_hit(&ray), pborrowed.closest_hit(&ray));
        assert_eq!(powned.view().any_hit(&ray), pborrowed.any_hit(&ray));
        // The primitive tree over spheres finds the sphere tree's hit.
        assert_eq!(
            powned.view().closest_hit(&ray).map(|h| (h.t, h.primitive)),
            view.closest_hit(&ray).map(|h| (h.t, h.sphere))
        );
    }
    assert_eq!(powned.into_primitives().0, s);
}

#[test]
fn a_scene_struct_holds_its_tree_across_threads() {
    struct Scene {
        spheres: Vec<Sphere>,
        bvh: OwnedBvh,
        boxes: OwnedPrimitiveBvh<Balls>,
    }
    fn shareable<T: Send + Sync>(_: &T) {}
    let mut rng = Pcg32::new(2, 2);
    let s = spheres(500, &mut rng);
    let scene = Scene {
        bvh: OwnedBvh::build(&s).unwrap(),
        boxes: OwnedPrimitiveBvh::build(Balls(s.clone())).unwrap(),
        spheres: s,
    };
    shareable(&scene);
    let rays = rays(4000, &mut rng);
    let counts: Vec<usize> = std::thread::scope(|t| {
        let handles: Vec<_> = rays
            .chunks(2000)
            .map(|chunk| {
                let scene = &scene;
                t.spawn(move || {
                    chunk
                        .iter()
                        .filter(|r| {
                            let a = scene.bvh.view().closest_hit(r);
                            let b = scene.boxes.view().closest_hit(r);
                            assert_eq!(a, strata::trace::closest_hit(&scene.spheres, r));
                            assert_eq!(a.map(|h| h.sphere), b.map(|h| h.primitive));
                            a.is_some()
                        })
                        .count()
                })
            })
            .collect();
        handles.into_iter().map(|h| h.join().unwrap()).collect()
    });
    assert!(counts.iter().all(|&c| c > 0));
}

#[test]
fn owned_builds_refuse_what_borrowed_builds_refuse() {
    let bad = [Sphere::new(Vec3::new(f32::INFINITY, 0.0, 0.0), 1.0)];
    assert!(OwnedBvh::build(&bad).is_err());
    let mut rng = Pcg32::new(3, 3);
    let mut s = spheres(10, &mut rng);
    s[4].center.y = 2e18;
    assert!(OwnedPrimitiveBvh::build(Balls(s)).is_err());
}
