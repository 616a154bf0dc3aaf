//! A scene: spheres, their materials, the emitters among them, and what
//! rays that escape see. Everything is borrowed from the caller.

use glam::Vec3;

use crate::lanes::{Lanes, V3};

use super::material::{Material, MaterialError};
use crate::trace::{
    Bvh, BvhError, BvhNode8, BvhStack, BvhStorage, Hit, HitPacket8, Ray, RayPacket8, Sphere,
    SphereChunk8, SphereSet, SphereSetError, any_hit_1x8, any_hit_x8, bvh_storage_for, chunks_for,
    closest_hit_1x8, closest_hit_x8,
};

/// The radiance of rays that leave the scene.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum Background {
    /// The course's sky: with `a = (d_y + 1) / 2` for the unit direction,
    /// `(1 − a)·white + a·(0.5, 0.7, 1.0)`: white at the nadir, pale blue at
    /// the zenith. It is the only light of `week09`.
    Sky,
    /// One radiance in every direction (a white furnace with `Vec3::ONE`).
    Flat(Vec3),
}

impl Background {
    /// The radiance seen along unit direction `dir`.
    ///
    /// ```
    /// use glam::Vec3;
    /// use strata::render::Background;
    /// assert_eq!(Background::Sky.radiance(Vec3::Y), Vec3::new(0.5, 0.7, 1.0));
    /// assert_eq!(Background::Sky.radiance(-Vec3::Y), Vec3::ONE);
    /// ```
    #[inline]
    #[must_use]
    pub fn radiance(&self, dir: Vec3) -> Vec3 {
        self.radiance_lanes(V3::from(dir)).into()
    }

    /// [`Background::radiance`] over lanes.
    #[inline(always)]
    pub(crate) fn radiance_lanes<L: Lanes>(&self, dir: V3<L>) -> V3<L> {
        match self {
            Background::Sky => {
                let a = L::splat(0.5) * (dir.y + L::splat(1.0));
                V3::splat(Vec3::ONE) * (L::splat(1.0) - a) + V3::splat(Vec3::new(0.5, 0.7, 1.0)) * a
            }
            Background::Flat(c) => V3::splat(*c),
        }
    }
}

/// Why a scene was refused.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum SceneError {
    /// The sphere set, sphere list and material map have different
    /// lengths, or the set does not hold the listed spheres.
    Mismatch,
    /// Sphere `sphere` has a non-finite centre or a radius that is not
    /// positive and finite.
    Sphere {
        /// Index of the sphere.
        sphere: usize,
    },
    /// Sphere `sphere` names a material that does not exist.
    MaterialIndex {
        /// Index of the sphere.
        sphere: usize,
    },
    /// Material `material` has a parameter out of range.
    Material {
        /// Index of the material.
        material: usize,
        /// What is wrong.
        error: MaterialError,
    },
    /// The light list is not exactly the emissive spheres, in index order.
    Lights,
    /// [`Scene::build`]: the spheres' 8-wide set could not be built.
    Set(SphereSetError),
    /// [`Scene::build`]: the light slice is shorter than the emissive
    /// spheres.
    LightStorage {
        /// Entries needed.
        needed: usize,
        /// Entries given.
        provided: usize,
    },
    /// [`Scene::build`]: the BVH could not be built (other than for
    /// coordinates beyond its range, where the scene is traced without it).
    Bvh(BvhError),
}

impl core::fmt::Display for SceneError {
    #[inline]
    fn fmt(&self, f: &mut core::fmt::Formatter<'_>) -> core::fmt::Result {
        match self {
            SceneError::Mismatch => f.write_str(
                "the sphere set, sphere list and material map do not describe the same spheres",
            ),
            SceneError::Sphere { sphere } => write!(
                f,
                "sphere {sphere} has a non-finite centre or a radius that is not positive and finite"
            ),
            SceneError::MaterialIndex { sphere } => {
                write!(f, "sphere {sphere} names a material that does not exist")
            }
            SceneError::Material { material, error } => write!(f, "material {material}: {error}"),
            SceneError::Lights => {
                f.write_str("the light list is not exactly the emissive spheres, in index order")
            }
            SceneError::Set(e) => write!(f, "sphere set: {e}"),
            SceneError::LightStorage { needed, provided } => write!(
                f,
                "light storage too small: {needed} entries needed, {provided} given"
            ),
            SceneError::Bvh(e) => write!(f, "BVH: {e}"),
        }
    }
}

// The inner errors' text is part of `Display`, so they are not also
// given as `source` (a chained report would print them twice).
impl core::error::Error for SceneError {}

/// A scene for [`super::render_tile`]. Sphere `i` has material
/// `materials[sphere_material[i]]`; `lights` lists, in increasing order,
/// the indices of the spheres whose material emits (the direct-lighting
/// candidates; [`Scene::build`] collects them).
#[derive(Clone, Copy, Debug)]
pub struct Scene<'a> {
    spheres: &'a [Sphere],
    set: SphereSet<'a>,
    materials: &'a [Material<'a>],
    sphere_material: &'a [u32],
    lights: &'a [u32],
    background: Background,
    bvh: Option<Bvh<'a>>,
}

/// Writes the indices of the emissive spheres into `out` in increasing
/// order and returns how many there are; `None` if `out` is too short or a
/// material index is out of range.
#[inline]
pub(crate) fn collect_lights(
    materials: &[Material<'_>],
    sphere_material: &[u32],
    out: &mut [u32],
) -> Option<usize> {
    let mut n = 0;
    for (i, &m) in sphere_material.iter().enumerate() {
        if materials.get(m as usize)?.is_light() {
            *out.get_mut(n)? = i as u32;
            n += 1;
        }
    }
    Some(n)
}

/// The slice lengths [`Scene::build`] needs for `n` spheres: one
/// [`SceneStorage`] field each. Longer slices are fine.
///
/// ```
/// use strata::render::SceneStorageSize;
/// let size = SceneStorageSize::for_spheres(485, true);
/// assert_eq!((size.chunks, size.lights), (61, 485));
/// assert!(size.bvh.is_some_and(|b| b.nodes >= 1));
/// assert!(SceneStorageSize::for_spheres(4, false).bvh.is_none());
/// ```
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct SceneStorageSize {
    /// [`SphereChunk8`]s: [`chunks_for`]`(n)`.
    pub chunks: usize,
    /// Light indices: `n` (every sphere may emit).
    pub lights: usize,
    /// The BVH's slices ([`bvh_storage_for`]`(n)`), if one is wanted.
    pub bvh: Option<BvhStorage>,
}

impl SceneStorageSize {
    /// The sizes for `n` spheres, with room for a BVH if `bvh` (it pays
    /// for itself from about [`BVH_MIN_SPHERES`](crate::trace::BVH_MIN_SPHERES)
    /// spheres; it never changes a hit).
    /// A `const fn`, so storage without an allocator can be sized by it:
    ///
    /// ```
    /// use strata::render::SceneStorageSize;
    /// use strata::trace::{BvhNode8, SphereChunk8};
    /// const SIZE: SceneStorageSize = SceneStorageSize::for_spheres(20, true);
    /// const BVH: strata::trace::BvhStorage = SIZE.bvh.unwrap();
    /// let chunks = [SphereChunk8::EMPTY; SIZE.chunks];
    /// let nodes = [BvhNode8::EMPTY; BVH.nodes];
    /// assert_eq!((chunks.len(), nodes.len(), BVH.ids), (3, 4, 27));
    /// ```
    #[inline]
    #[must_use]
    pub const fn for_spheres(n: usize, bvh: bool) -> Self {
        Self {
            chunks: chunks_for(n),
            lights: n,
            // `bool::then` is not const.
            bvh: if bvh { Some(bvh_storage_for(n)) } else { None },
        }
    }
}

/// The caller's memory a [`Scene`] is built into by [`Scene::build`],
/// sized by [`SceneStorageSize`]. Empty `bvh_nodes` means no BVH.
#[derive(Debug)]
pub struct SceneStorage<'a> {
    /// The spheres as 8-wide chunks.
    pub chunks: &'a mut [SphereChunk8],
    /// The emissive spheres' indices.
    pub lights: &'a mut [u32],
    /// BVH nodes (empty: no BVH).
    pub bvh_nodes: &'a mut [BvhNode8],
    /// BVH sphere lanes.
    pub bvh_lanes: &'a mut [f32],
    /// BVH sphere indices.
    pub bvh_ids: &'a mut [u32],
}

impl<'a> Scene<'a> {
    /// Builds a scene into the caller's `storage`: the 8-wide sphere set,
    /// the light list, and, if `storage` has BVH nodes, a BVH (traced
    /// without it where the BVH cannot hold the spheres: beyond its
    /// coordinate range or [`BVH_MAX_SPHERES`](crate::trace::BVH_MAX_SPHERES);
    /// brute force gives the same hits). Then checks it as [`Scene::new`].
    ///
    /// ```
    /// use glam::Vec3;
    /// use strata::render::{Background, Material, Scene, SceneStorage, SceneStorageSize, Texture};
    /// use strata::trace::{Ray, Sphere, SphereChunk8};
    /// let spheres = [Sphere::new(Vec3::new(0.0, 0.0, -3.0), 1.0)];
    /// let materials = [Material::Lambertian { albedo: Texture::Solid(Vec3::splat(0.5)) }];
    /// // Sized at compile time: no allocator needed.
    /// const SIZE: SceneStorageSize = SceneStorageSize::for_spheres(1, false);
    /// let (mut chunks, mut lights) = ([SphereChunk8::EMPTY; SIZE.chunks], [0u32; SIZE.lights]);
    /// let storage = SceneStorage {
    ///     chunks: &mut chunks,
    ///     lights: &mut lights,
    ///     bvh_nodes: &mut [],
    ///     bvh_lanes: &mut [],
    ///     bvh_ids: &mut [],
    /// };
    /// let scene = Scene::build(&spheres, &materials, &[0], Background::Sky, storage).unwrap();
    /// let hit = scene.closest_hit(&Ray::new(Vec3::ZERO, -Vec3::Z)).unwrap();
    /// assert_eq!((hit.sphere, hit.t), (0, 2.0));
    /// assert!(!scene.has_bvh());
    /// ```
    #[inline]
    pub fn build(
        spheres: &'a [Sphere],
        materials: &'a [Material<'a>],
        sphere_material: &'a [u32],
        background: Background,
        storage: SceneStorage<'a>,
    ) -> Result<Self, SceneError> {
        let SceneStorage {
            chunks,
            lights,
            bvh_nodes,
            bvh_lanes,
            bvh_ids,
        } = storage;
        if sphere_material.len() != spheres.len() {
            return Err(SceneError::Mismatch);
        }
        let set = SphereSet::build(spheres, chunks).map_err(SceneError::Set)?;
        let provided = lights.len();
        let n = collect_lights(materials, sphere_material, lights).ok_or_else(|| {
            // Either a material index is out of range or the slice is short.
            match sphere_material
                .iter()
                .position(|&m| m as usize >= materials.len())
            {
                Some(sphere) => SceneError::MaterialIndex { sphere },
                None => SceneError::LightStorage {
                    needed: sphere_material
                        .iter()
                        .filter(|&&m| materials[m as usize].is_light())
                        .count(),
                    provided,
                },
            }
        })?;
        let lights: &'a [u32] = lights;
        let lights = &lights[..n];
        let scene = Self::new(spheres, set, materials, sphere_material, lights, background)?;
        if bvh_nodes.is_empty() {
            return Ok(scene);
        }
        match Bvh::build(spheres, bvh_nodes, bvh_lanes, bvh_ids) {
            Ok(bvh) => scene.with_bvh(bvh),
            Err(BvhError::SphereOutOfRange { .. } | BvhError::TooManySpheres) => Ok(scene),
            Err(e) => Err(SceneError::Bvh(e)),
        }
    }

    /// Checks and assembles a scene from parts the caller built. `set` must
    /// be built from `spheres`. [`Scene::build`] builds the parts too.
    #[inline]
    pub fn new(
        spheres: &'a [Sphere],
        set: SphereSet<'a>,
        materials: &'a [Material<'a>],
        sphere_material: &'a [u32],
        lights: &'a [u32],
        background: Background,
    ) -> Result<Self, SceneError> {
        if set.len() != spheres.len() || sphere_material.len() != spheres.len() {
            return Err(SceneError::Mismatch);
        }
        for (i, s) in spheres.iter().enumerate() {
            if !(s.center.is_finite() && s.radius > 0.0 && s.radius.is_finite()) {
                return Err(SceneError::Sphere { sphere: i });
            }
            if set.sphere(i) != Some(*s) {
                return Err(SceneError::Mismatch);
            }
        }
        for (i, m) in materials.iter().enumerate() {
            m.validate()
                .map_err(|error| SceneError::Material { material: i, error })?;
        }
        let mut expected = lights.iter();
        for (i, &m) in sphere_material.iter().enumerate() {
            let Some(material) = materials.get(m as usize) else {
                return Err(SceneError::MaterialIndex { sphere: i });
            };
            if material.is_light() && expected.next() != Some(&(i as u32)) {
                return Err(SceneError::Lights);
            }
        }
        if expected.next().is_some() {
            return Err(SceneError::Lights);
        }
        Ok(Self {
            spheres,
            set,
            materials,
            sphere_material,
            lights,
            background,
            bvh: None,
        })
    }

    /// The scene traced through `bvh`, which must have been built from
    /// exactly this scene's spheres ([`SceneError::Mismatch`] otherwise).
    /// Every query returns the same bits as without it.
    #[inline]
    pub fn with_bvh(self, bvh: Bvh<'a>) -> Result<Self, SceneError> {
        if !bvh.built_from(self.spheres) {
            return Err(SceneError::Mismatch);
        }
        Ok(Self {
            bvh: Some(bvh),
            ..self
        })
    }

    /// Whether a BVH is attached.
    #[inline]
    #[must_use]
    pub fn has_bvh(&self) -> bool {
        self.bvh.is_some()
    }

    /// The closest hit of `ray` (through the BVH if attached). In a loop,
    /// prefer [`Scene::closest_hit_with`] and one [`BvhStack`].
    #[inline]
    #[must_use]
    pub fn closest_hit(&self, ray: &Ray) -> Option<Hit> {
        match &self.bvh {
            Some(b) => b.closest_hit(ray),
            None => closest_hit_1x8(&self.set, ray),
        }
    }

    /// [`Scene::closest_hit`] on the caller's reusable traversal `stack`.
    /// Always inlined: the path loop's ray, just written field by field,
    /// is then read from registers, not reloaded in wider pieces that the
    /// processor cannot forward from those stores.
    #[inline(always)]
    #[must_use]
    pub fn closest_hit_with(&self, ray: &Ray, stack: &mut BvhStack) -> Option<Hit> {
        match &self.bvh {
            Some(b) => b.closest_hit_with(ray, stack),
            None => closest_hit_1x8(&self.set, ray),
        }
    }

    /// Whether `ray` hits any sphere (through the BVH if attached).
    #[inline]
    #[must_use]
    pub fn any_hit(&self, ray: &Ray) -> bool {
        match &self.bvh {
            Some(b) => b.any_hit(ray),
            None => any_hit_1x8(&self.set, ray),
        }
    }

    /// [`Scene::any_hit`] on the caller's reusable traversal `stack`.
    #[inline]
    #[must_use]
    pub fn any_hit_with(&self, ray: &Ray, stack: &mut BvhStack) -> bool {
        match &self.bvh {
            Some(b) => b.any_hit_with(ray, stack),
            None => any_hit_1x8(&self.set, ray),
        }
    }

    /// Which rays of a packet hit any sphere (shadow rays, each within its
    /// own `[t_min, t_max]`): bit `k` for active lane `k`, the same as
    /// [`Scene::any_hit`] on each lane's ray, through the BVH if attached
    /// (one ray at a time: shadow rays of eight paths rarely share nodes),
    /// else eight spheres a step for all eight rays. In a loop, prefer
    /// [`Scene::any_hit_x8_with`] and one [`BvhStack`].
    ///
    /// ```
    /// use glam::Vec3;
    /// use strata::render::{Background, Material, Scene, SceneStorage, Texture};
    /// use strata::trace::{Ray, RayPacket8, Sphere, SphereChunk8};
    /// let spheres = [Sphere::new(Vec3::new(0.0, 2.0, 0.0), 0.5)];
    /// let materials = [Material::Lambertian { albedo: Texture::Solid(Vec3::ONE) }];
    /// let (mut chunks, mut lights) = ([SphereChunk8::EMPTY; 1], [0u32; 1]);
    /// let storage = SceneStorage {
    ///     chunks: &mut chunks,
    ///     lights: &mut lights,
    ///     bvh_nodes: &mut [],
    ///     bvh_lanes: &mut [],
    ///     bvh_ids: &mut [],
    /// };
    /// let scene = Scene::build(&spheres, &materials, &[0], Background::Sky, storage).unwrap();
    /// let up = Ray::new(Vec3::ZERO, Vec3::Y).with_range(1e-4, 5.0);
    /// let short = Ray::new(Vec3::ZERO, Vec3::Y).with_range(1e-4, 1.0);
    /// let side = Ray::new(Vec3::ZERO, Vec3::X).with_range(1e-4, 5.0);
    /// let packet = RayPacket8::from_rays(&[up, short, side]);
    /// assert_eq!(scene.any_hit_x8(&packet), 0b001);
    /// ```
    #[inline]
    #[must_use]
    pub fn any_hit_x8(&self, packet: &RayPacket8) -> u32 {
        match &self.bvh {
            Some(b) => b.any_hit_x8(packet),
            None => any_hit_x8(&self.set, packet),
        }
    }

    /// [`Scene::any_hit_x8`] on the caller's reusable traversal `stack`.
    #[inline]
    #[must_use]
    pub fn any_hit_x8_with(&self, packet: &RayPacket8, stack: &mut BvhStack) -> u32 {
        match &self.bvh {
            Some(b) => b.any_hit_x8_with(packet, stack),
            None => any_hit_x8(&self.set, packet),
        }
    }

    /// The closest hits of a packet, as [`closest_hit_x8`] (through the BVH
    /// if attached).
    #[inline]
    pub fn closest_hit_x8(&self, packet: &RayPacket8, hits: &mut HitPacket8) {
        match &self.bvh {
            Some(b) => b.closest_hit_x8(packet, hits),
            None => closest_hit_x8(&self.set, packet, hits),
        }
    }

    /// [`Scene::closest_hit_x8`] on the caller's reusable traversal `stack`.
    /// Always inlined: the tile loop's packet and hits then stay in
    /// registers.
    #[inline(always)]
    pub fn closest_hit_x8_with(
        &self,
        packet: &RayPacket8,
        hits: &mut HitPacket8,
        stack: &mut BvhStack,
    ) {
        match &self.bvh {
            Some(b) => b.closest_hit_x8_with(packet, hits, stack),
            None => closest_hit_x8(&self.set, packet, hits),
        }
    }

    /// The spheres.
    #[inline]
    #[must_use]
    pub fn spheres(&self) -> &'a [Sphere] {
        self.spheres
    }

    /// The spheres as 8-wide chunks.
    #[inline]
    #[must_use]
    pub fn set(&self) -> &SphereSet<'a> {
        &self.set
    }

    /// The material of sphere `i` (which [`Scene::new`] checked exists).
    #[inline]
    #[must_use]
    pub fn material_of(&self, sphere: u32) -> &Material<'a> {
        self.material(self.material_index(sphere))
    }

    /// The index of the material of sphere `sphere` (which [`Scene::new`]
    /// checked exists).
    #[inline(always)]
    pub(crate) fn material_index(&self, sphere: u32) -> u32 {
        self.sphere_material[sphere as usize]
    }

    /// Material `m` (an index from [`Scene::material_index`]).
    #[inline(always)]
    pub(crate) fn material(&self, m: u32) -> &Material<'a> {
        &self.materials[m as usize]
    }

    /// The emissive spheres' indices.
    #[inline]
    #[must_use]
    pub fn lights(&self) -> &'a [u32] {
        self.lights
    }

    /// What escaping rays see.
    #[inline]
    #[must_use]
    pub fn background(&self) -> Background {
        self.background
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::render::Texture;

    const GREY: Material<'static> = Material::Lambertian {
        albedo: Texture::Solid(Vec3::splat(0.5)),
    };
    const LAMP: Material<'static> = Material::DiffuseLight {
        emit: Vec3::splat(4.0),
    };

    /// Fixed-size storage for up to 20 spheres with a BVH.
    struct Buffers {
        chunks: [SphereChunk8; 3],
        lights: [u32; 20],
        nodes: [BvhNode8; 8],
        lanes: [f32; 128],
        ids: [u32; 32],
    }

    impl Buffers {
        fn new() -> Self {
            let size = SceneStorageSize::for_spheres(20, true);
            let bvh = size.bvh.unwrap();
            assert!(size.chunks <= 3 && bvh.nodes <= 8 && bvh.lanes <= 128 && bvh.ids <= 32);
            Self {
                chunks: [SphereChunk8::EMPTY; 3],
                lights: [u32::MAX; 20],
                nodes: [BvhNode8::EMPTY; 8],
                lanes: [0.0; 128],
                ids: [0; 32],
            }
        }

        fn storage(&mut self) -> SceneStorage<'_> {
            SceneStorage {
                chunks: &mut self.chunks,
                lights: &mut self.lights,
                bvh_nodes: &mut self.nodes,
                bvh_lanes: &mut self.lanes,
                bvh_ids: &mut self.ids,
            }
        }
    }

    fn spheres(n: usize) -> [Sphere; 20] {
        core::array::from_fn(|i| {
            let r = if i < n { 0.4 } else { 1.0 };
            Sphere::new(Vec3::new(i as f32, 0.0, -5.0), r)
        })
    }

    /// The eight-ray any-hit answers, lane by lane, what the one-ray
    /// any-hit does, with a BVH and without, for shadow rays that stop
    /// at a sphere (as direct lighting's do), rays that stop short of one
    /// and rays that miss, under every mask of live lanes tried.
    #[test]
    fn eight_shadow_rays_answer_as_one_ray_each() {
        use crate::rng::{Pcg32, STREAM, next_f32};
        let mut rng = Pcg32::new(11, STREAM);
        let mut f = move || next_f32(&mut rng);
        let s: [Sphere; 20] = core::array::from_fn(|_| {
            let c = Vec3::new(f() * 8.0 - 4.0, f() * 4.0 - 2.0, f() * 8.0 - 4.0);
            Sphere::new(c, 0.2 + f() * 0.8)
        });
        let materials = [GREY, LAMP];
        let sphere_material: [u32; 20] = core::array::from_fn(|i| (i % 5 == 0) as u32);
        let (mut with_bvh, mut brute) = (Buffers::new(), Buffers::new());
        let bvh = Scene::build(
            &s,
            &materials,
            &sphere_material,
            Background::Sky,
            with_bvh.storage(),
        )
        .unwrap();
        let mut plain = brute.storage();
        plain.bvh_nodes = &mut [];
        let flat = Scene::build(&s, &materials, &sphere_material, Background::Sky, plain).unwrap();
        assert!(bvh.has_bvh() && !flat.has_bvh());
        let mut stack = BvhStack::new();
        let (mut hits, mut total) = (0, 0);
        for round in 0..400u32 {
            let rays: [Ray; 8] = core::array::from_fn(|_| {
                let o = Vec3::new(f() * 10.0 - 5.0, f() * 6.0 - 3.0, f() * 10.0 - 5.0);
                let target = s[(f() * 20.0) as usize];
                let to = target.center - o;
                let dist = to.length();
                let ray = Ray::new(o, to / dist);
                // Up to the target's near side, short of it, or past it.
                let t_max = match round % 3 {
                    0 => dist - target.radius,
                    1 => dist * f() * 0.5,
                    _ => f32::INFINITY,
                };
                ray.with_range(1e-4, t_max)
            });
            let packet =
                RayPacket8::from_rays(&rays).with_active_bits((round * 37 % 255 + 1) as u8);
            let want: u32 = (0..8)
                .filter(|&k| packet.active_bits() >> k & 1 == 1 && bvh.any_hit(&rays[k]))
                .map(|k| 1 << k)
                .sum();
            let want_flat: u32 = (0..8)
                .filter(|&k| packet.active_bits() >> k & 1 == 1 && flat.any_hit(&rays[k]))
                .map(|k| 1 << k)
                .sum();
            assert_eq!(want, want_flat, "round {round}");
            assert_eq!(bvh.any_hit_x8(&packet), want, "round {round}");
            assert_eq!(
                bvh.any_hit_x8_with(&packet, &mut stack),
                want,
                "round {round}"
            );
            assert_eq!(flat.any_hit_x8(&packet), want, "round {round}");
            assert_eq!(
                flat.any_hit_x8_with(&packet, &mut stack),
                want,
                "round {round}"
            );
            hits += want.count_ones();
            total += packet.active_bits().count_ones();
        }
        // Both answers occur often.
        assert!(
            hits > total / 5 && hits < total * 4 / 5,
            "{hits} of {total}"
        );
    }

    #[test]
    fn collect_lights_in_index_order() {
        let materials = [GREY, LAMP];
        let mut lights = [0u32; 3];
        assert_eq!(collect_lights(&materials, &[0, 1, 1], &mut lights), Some(2));
        assert_eq!(&lights[..2], &[1, 2]);
        // Too short a slice, or a missing material: None.
        assert_eq!(collect_lights(&materials, &[1, 1], &mut lights[..1]), None);
        assert_eq!(collect_lights(&materials, &[0, 2], &mut lights), None);
    }

    #[test]
    fn build_collects_lights_and_attaches_a_bvh() {
        let s = spheres(20);
        let materials = [GREY, LAMP];
        let sphere_material: [u32; 20] = core::array::from_fn(|i| (i % 7 == 3) as u32);
        let mut buffers = Buffers::new();
        let scene = Scene::build(
            &s,
            &materials,
            &sphere_material,
            Background::Sky,
            buffers.storage(),
        )
        .unwrap();
        assert_eq!(scene.lights(), &[3, 10, 17]);
        assert!(scene.has_bvh());
        let ray = Ray::new(Vec3::new(5.0, 0.0, 0.0), -Vec3::Z);
        assert_eq!(scene.closest_hit(&ray).map(|h| h.sphere), Some(5));
    }

    #[test]
    fn build_refuses_short_storage_and_missing_materials() {
        let s = spheres(9);
        let s = &s[..9];
        let lamps = [LAMP; 9];
        let ids = [0u32; 9];
        let build = |chunks: &mut [SphereChunk8], lights: &mut [u32], material: &[u32]| {
            let storage = SceneStorage {
                chunks,
                lights,
                bvh_nodes: &mut [],
                bvh_lanes: &mut [],
                bvh_ids: &mut [],
            };
            Scene::build(s, &lamps, material, Background::Sky, storage).map(|_| ())
        };
        let mut chunks = [SphereChunk8::EMPTY; 2];
        assert_eq!(
            build(&mut chunks[..1], &mut [0; 9], &ids),
            Err(SceneError::Set(SphereSetError::StorageTooSmall {
                needed: 2,
                provided: 1
            }))
        );
        assert_eq!(
            build(&mut chunks, &mut [0; 4], &ids),
            Err(SceneError::LightStorage {
                needed: 9,
                provided: 4
            })
        );
        let mut bad = ids;
        bad[6] = 9;
        assert_eq!(
            build(&mut chunks, &mut [0; 9], &bad),
            Err(SceneError::MaterialIndex { sphere: 6 })
        );
        assert_eq!(build(&mut chunks, &mut [0; 9], &ids), Ok(()));
    }

    /// A sphere beyond the BVH's coordinate range: the scene is traced
    /// without a BVH (the same hits), not refused.
    #[test]
    fn build_without_a_bvh_where_its_range_ends() {
        let s = [
            Sphere::new(Vec3::new(0.0, 0.0, -3.0), 1.0),
            Sphere::new(Vec3::new(1.0e19, 0.0, 0.0), 1.0),
        ];
        let mut buffers = Buffers::new();
        let scene = Scene::build(&s, &[GREY], &[0, 0], Background::Sky, buffers.storage()).unwrap();
        assert!(!scene.has_bvh());
        let hit = scene.closest_hit(&Ray::new(Vec3::ZERO, -Vec3::Z)).unwrap();
        assert_eq!((hit.sphere, hit.t), (0, 2.0));
    }
}
