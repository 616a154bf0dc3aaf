//! A scene: spheres, their materials, the emitters among them, and what
//! rays that escape see. Everything is borrowed from the caller.

use glam::Vec3;

use super::material::{Material, MaterialError};
use crate::trace::{
    Bvh, Hit, HitPacket8, Ray, RayPacket8, Sphere, SphereSet, any_hit_1x8, closest_hit_1x8,
    closest_hit_x8,
};

/// The sphere count from which a BVH pays for itself: below it the
/// brute-force 8-wide loop is as fast (measured on the course's 4 spheres
/// and the cover's 485; `strata bench`). The runner attaches a BVH to
/// scenes of at least this many spheres; the choice never changes a
/// pixel.
pub const BVH_THRESHOLD: usize = 16;

/// Packet rays that continue alone in a BVH subtree when no more than
/// this many of the 8 reach it (measured best for camera packets).
const PACKET_FALLBACK: u32 = 2;

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
        match self {
            Background::Sky => {
                let a = 0.5 * (dir.y + 1.0);
                Vec3::ONE * (1.0 - a) + Vec3::new(0.5, 0.7, 1.0) * a
            }
            Background::Flat(c) => *c,
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
        }
    }
}

impl core::error::Error for SceneError {
    #[inline]
    fn source(&self) -> Option<&(dyn core::error::Error + 'static)> {
        match self {
            SceneError::Material { error, .. } => Some(error),
            _ => None,
        }
    }
}

/// A scene for [`super::render_tile`]. Sphere `i` has material
/// `materials[sphere_material[i]]`; `lights` lists, in increasing order,
/// the indices of the spheres whose material emits (the direct-lighting
/// candidates; see [`collect_lights`]).
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
///
/// ```
/// use glam::Vec3;
/// use strata::render::{collect_lights, Material, Texture};
/// let materials = [
///     Material::Lambertian { albedo: Texture::Solid(Vec3::splat(0.5)) },
///     Material::DiffuseLight { emit: Vec3::splat(4.0) },
/// ];
/// let mut lights = [0u32; 3];
/// assert_eq!(collect_lights(&materials, &[0, 1, 1], &mut lights), Some(2));
/// assert_eq!(&lights[..2], &[1, 2]);
/// ```
#[inline]
pub fn collect_lights(
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

impl<'a> Scene<'a> {
    /// Checks and assembles a scene. `set` must be built from `spheres`.
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

    /// The closest hit of `ray` (through the BVH if attached).
    #[inline]
    #[must_use]
    pub fn closest_hit(&self, ray: &Ray) -> Option<Hit> {
        match &self.bvh {
            Some(b) => b.closest_hit(ray),
            None => closest_hit_1x8(ray, &self.set),
        }
    }

    /// Whether `ray` hits any sphere (through the BVH if attached).
    #[inline]
    #[must_use]
    pub fn any_hit(&self, ray: &Ray) -> bool {
        match &self.bvh {
            Some(b) => b.any_hit(ray),
            None => any_hit_1x8(ray, &self.set),
        }
    }

    /// The closest hits of a packet, as [`closest_hit_x8`] (through the BVH
    /// if attached).
    #[inline]
    pub fn closest_hit_x8(&self, packet: &RayPacket8, hits: &mut HitPacket8) {
        match &self.bvh {
            Some(b) => b.closest_hit_x8(packet, hits, PACKET_FALLBACK),
            None => closest_hit_x8(packet, &self.set, hits),
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
        &self.materials[self.sphere_material[sphere as usize] as usize]
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
