//! Owning buffers (the `alloc` feature): a tree and its storage in one
//! value, so a renderer's scene struct can hold its BVH and lend out
//! views. The core's own paths never need them.

use alloc::vec;
use alloc::vec::Vec;

use super::{
    Bvh, BvhError, BvhNode8, PACKET_FALLBACK, PrimitiveBvh, Primitives, Shape, bvh_storage_for,
    primitive_bvh_storage_for,
};
use crate::trace::Sphere;

/// A sphere [`Bvh`] with its storage, built once and viewed as often as
/// needed: [`OwnedBvh::view`] is free (no check: the storage is private
/// and was written by the build). `Send` and `Sync`.
///
/// ```
/// use glam::Vec3;
/// use strata::trace::{OwnedBvh, Ray, Sphere, closest_hit};
///
/// struct MyScene {
///     spheres: Vec<Sphere>,
///     bvh: OwnedBvh,
/// }
///
/// let spheres: Vec<Sphere> =
///     (0..100).map(|i| Sphere::new(Vec3::new(i as f32, 0.0, -5.0), 0.4)).collect();
/// let scene = MyScene { bvh: OwnedBvh::build(&spheres).unwrap(), spheres };
/// let ray = Ray::new(Vec3::new(42.0, 0.0, 0.0), -Vec3::Z);
/// assert_eq!(scene.bvh.view().closest_hit(&ray), closest_hit(&scene.spheres, &ray));
/// ```
#[derive(Clone, Debug)]
pub struct OwnedBvh {
    nodes: Vec<BvhNode8>,
    lanes: Vec<f32>,
    ids: Vec<u32>,
    shape: Shape,
}

impl OwnedBvh {
    /// Builds the tree over `spheres` into buffers of its own, as
    /// [`Bvh::build`] does into the caller's.
    #[inline]
    pub fn build(spheres: &[Sphere]) -> Result<Self, BvhError> {
        let size = bvh_storage_for(spheres.len());
        if spheres.len() > super::BVH_MAX_SPHERES {
            return Err(BvhError::TooManySpheres);
        }
        let mut nodes = vec![BvhNode8::EMPTY; size.nodes];
        let mut lanes = vec![0.0; size.lanes];
        let mut ids = vec![0; size.ids];
        let shape = Bvh::build(spheres, &mut nodes, &mut lanes, &mut ids)?.shape;
        Ok(Self {
            nodes,
            lanes,
            ids,
            shape,
        })
    }

    /// The tree, to query.
    #[must_use]
    #[inline]
    pub fn view(&self) -> Bvh<'_> {
        let width = self.ids.len();
        let (cx, rest) = self.lanes.split_at(width);
        let (cy, rest) = rest.split_at(width);
        let (cz, r) = rest.split_at(width);
        Bvh {
            nodes: &self.nodes,
            cx,
            cy,
            cz,
            r,
            ids: &self.ids,
            shape: self.shape,
            packet_fallback: PACKET_FALLBACK,
        }
    }
}

/// A [`PrimitiveBvh`] that owns its primitives and its storage:
/// [`OwnedPrimitiveBvh::view`] lends the tree (free, unchecked: both are
/// private), [`OwnedPrimitiveBvh::into_primitives`] gives the primitives
/// back (to change them and build again). `Send` and `Sync` when `P` is.
///
/// ```
/// use strata::trace::*;
///
/// /// A row of unit cubes.
/// struct Row(Vec<[f32; 3]>);
/// impl Primitives for Row {
///     type Data = ();
///     fn len(&self) -> usize { self.0.len() }
///     fn bounds(&self, i: usize) -> Aabb {
///         let [x, y, z] = self.0[i];
///         Aabb::new([x, y, z], [x + 1.0, y + 1.0, z + 1.0])
///     }
///     fn intersect(&self, i: usize, ray: &Ray) -> Option<(f32, ())> {
///         // Only rays straight down the z axis, for brevity.
///         let b = self.bounds(i);
///         let t = ray.origin.z - b.max.z;
///         let inside = (b.min.x..=b.max.x).contains(&ray.origin.x)
///             && (b.min.y..=b.max.y).contains(&ray.origin.y);
///         (ray.dir.z == -1.0 && inside && t > ray.t_min && t < ray.t_max).then_some((t, ()))
///     }
/// }
///
/// let bvh = OwnedPrimitiveBvh::build(Row((0..64).map(|i| [i as f32, 0.0, 0.0]).collect()))
///     .unwrap();
/// let hit = bvh.view().closest_hit(&Ray::new([10.5, 0.5, 3.0], [0.0, 0.0, -1.0])).unwrap();
/// assert_eq!((hit.primitive, hit.t), (10, 2.0));
/// assert_eq!(bvh.into_primitives().0.len(), 64);
/// ```
pub struct OwnedPrimitiveBvh<P> {
    prims: P,
    nodes: Vec<BvhNode8>,
    ids: Vec<u32>,
    shape: Shape,
}

impl<P> core::fmt::Debug for OwnedPrimitiveBvh<P> {
    #[inline]
    fn fmt(&self, f: &mut core::fmt::Formatter<'_>) -> core::fmt::Result {
        f.debug_struct("OwnedPrimitiveBvh")
            .field("len", &self.shape.len)
            .field("nodes", &self.shape.used_nodes)
            .field("depth", &self.shape.depth)
            .field("outliers", &self.shape.outliers)
            .finish_non_exhaustive()
    }
}

impl<P: Primitives> OwnedPrimitiveBvh<P> {
    /// Builds the tree over `prims`, which it keeps, as
    /// [`PrimitiveBvh::build`] does into the caller's storage.
    #[inline]
    pub fn build(prims: P) -> Result<Self, BvhError> {
        if prims.len() > super::BVH_MAX_SPHERES {
            return Err(BvhError::TooManySpheres);
        }
        let size = primitive_bvh_storage_for(prims.len());
        let mut nodes = vec![BvhNode8::EMPTY; size.nodes];
        let mut ids = vec![0; size.ids];
        let shape = PrimitiveBvh::build(&prims, &mut nodes, &mut ids)?.shape();
        Ok(Self {
            prims,
            nodes,
            ids,
            shape,
        })
    }

    /// The tree, to query.
    #[must_use]
    #[inline]
    pub fn view(&self) -> PrimitiveBvh<'_, P> {
        PrimitiveBvh::assemble(&self.prims, &self.nodes, &self.ids, self.shape)
    }

    /// The primitives.
    #[must_use]
    #[inline]
    pub fn primitives(&self) -> &P {
        &self.prims
    }

    /// The primitives back, the tree dropped.
    #[must_use]
    #[inline]
    pub fn into_primitives(self) -> P {
        self.prims
    }
}
