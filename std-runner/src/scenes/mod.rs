//! Scenes as owned data ([`SceneData`]) and the memory the core builds
//! them into ([`SceneBuffers`]); the built-in scenes are in `builtin.rs`
//! (their sphere layouts and views, which the benchmarks share, in
//! `geometry.rs`), the scene hash in `hash.rs`, scene files in
//! [`file`](mod@file).

use strata::render::{
    Background, CameraDesc, ImageTexture, Material, Scene, SceneStorage, SceneStorageSize, Texture,
};
use strata::trace::{Bvh, BvhNode8, BvhStorage, Sphere, SphereChunk8, SphereSet};

mod builtin;
pub mod file;
mod geometry;
mod hash;

pub use builtin::{
    BUILT_IN, CAUSTICS_LIGHT_RADIUS, HORIZON_RADIUS, built_in, caustics, cover, globe_image,
    horizon, showcase, week09,
};
pub use geometry::{COURSE_VIEW, COVER_VIEW, View, course_spheres, cover_spheres};

// Image textures are scene data; the type lives with the PNG decoder that
// makes them.
pub use crate::image_io::Image;

/// The sphere count from which the runner traces a scene through a BVH:
/// the core's measured crossover, [`strata::trace::BVH_MIN_SPHERES`]. The
/// choice never changes a pixel.
pub const BVH_THRESHOLD: usize = strata::trace::BVH_MIN_SPHERES;

/// Whether a scene is traced through a BVH (it never changes a pixel).
#[derive(
    Clone,
    Copy,
    Debug,
    Default,
    PartialEq,
    Eq,
    clap::ValueEnum,
    serde::Serialize,
    serde::Deserialize,
)]
pub enum BvhMode {
    /// From [`BVH_THRESHOLD`] spheres.
    #[default]
    #[value(help = format!("From {BVH_THRESHOLD} spheres"))]
    Auto,
    /// Always.
    On,
    /// Never (brute force).
    Off,
}

/// What a scene renders at when the command line does not say.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Defaults {
    /// Image width in pixels.
    pub width: u32,
    /// Width / height.
    pub aspect: f32,
    /// Samples per pixel.
    pub spp: u32,
    /// Ray segments per path.
    pub max_depth: u32,
}

/// A scene that owns everything the core borrows.
#[derive(Clone, Debug, PartialEq)]
pub struct SceneData {
    /// Name, for metadata and messages.
    pub name: String,
    /// The spheres.
    pub spheres: Vec<Sphere>,
    /// Material index of each sphere.
    pub sphere_material: Vec<u32>,
    /// Materials; those listed in `image_albedo` get an image as albedo.
    pub materials: Vec<Material<'static>>,
    /// `(material, image)`: the material's albedo is that image.
    pub image_albedo: Vec<(usize, usize)>,
    /// Image textures.
    pub images: Vec<Image>,
    /// The camera.
    pub camera: CameraDesc,
    /// What escaping rays see.
    pub background: Background,
    /// Render defaults.
    pub defaults: Defaults,
}

/// `material` with its albedo replaced by `albedo` (materials without a
/// textured albedo are returned unchanged).
fn with_albedo<'a>(material: Material<'static>, albedo: Texture<'a>) -> Material<'a> {
    match material {
        Material::Lambertian { .. } => Material::Lambertian { albedo },
        Material::Phong {
            kd, ks, exponent, ..
        } => Material::Phong {
            albedo,
            kd,
            ks,
            exponent,
        },
        Material::Blinn {
            kd, ks, exponent, ..
        } => Material::Blinn {
            albedo,
            kd,
            ks,
            exponent,
        },
        Material::PhongNormalized {
            kd, ks, exponent, ..
        } => Material::PhongNormalized {
            albedo,
            kd,
            ks,
            exponent,
        },
        Material::BlinnNormalized {
            kd, ks, exponent, ..
        } => Material::BlinnNormalized {
            albedo,
            kd,
            ks,
            exponent,
        },
        Material::CookTorrance {
            kd, ks, alpha, ior, ..
        } => Material::CookTorrance {
            albedo,
            kd,
            ks,
            alpha,
            ior,
        },
        // No textured albedo to replace.
        Material::Mirror { albedo } => Material::Mirror { albedo },
        Material::Metal { albedo, roughness } => Material::Metal { albedo, roughness },
        Material::Dielectric { ior } => Material::Dielectric { ior },
        Material::DiffuseLight { emit } => Material::DiffuseLight { emit },
    }
}

/// Owned memory for a core [`Scene`] of `n` spheres, sized by
/// [`SceneStorageSize`]: what the renderer, the benchmarks and the tests
/// build scenes and sphere sets into (the benchmark of BVH build time
/// sizes its own).
#[derive(Debug)]
pub struct SceneBuffers {
    chunks: Vec<SphereChunk8>,
    lights: Vec<u32>,
    nodes: Vec<BvhNode8>,
    lanes: Vec<f32>,
    ids: Vec<u32>,
}

impl SceneBuffers {
    /// Buffers for `n` spheres, with room for a BVH if `bvh`.
    #[must_use]
    pub fn new(n: usize, bvh: bool) -> Self {
        let size = SceneStorageSize::for_spheres(n, bvh);
        let b = size.bvh.unwrap_or(BvhStorage {
            nodes: 0,
            lanes: 0,
            ids: 0,
        });
        Self {
            chunks: vec![SphereChunk8::EMPTY; size.chunks],
            lights: vec![0; size.lights],
            nodes: vec![BvhNode8::EMPTY; b.nodes],
            lanes: vec![0.0; b.lanes],
            ids: vec![0; b.ids],
        }
    }

    /// The buffers as [`Scene::build`] takes them.
    pub fn storage(&mut self) -> SceneStorage<'_> {
        SceneStorage {
            chunks: &mut self.chunks,
            lights: &mut self.lights,
            bvh_nodes: &mut self.nodes,
            bvh_lanes: &mut self.lanes,
            bvh_ids: &mut self.ids,
        }
    }

    /// The spheres' 8-wide set and, if the buffers have room for one,
    /// their BVH, for tracing without a scene (benchmarks, tests). Spheres
    /// the BVH cannot hold are an error: a benchmark layout must be within
    /// its range, or it would time the brute-force loop as the BVH.
    pub fn trace<'a>(
        &'a mut self,
        spheres: &[Sphere],
    ) -> anyhow::Result<(SphereSet<'a>, Option<Bvh<'a>>)> {
        let set = SphereSet::build(spheres, &mut self.chunks)?;
        if self.nodes.is_empty() {
            return Ok((set, None));
        }
        let bvh = Bvh::build(spheres, &mut self.nodes, &mut self.lanes, &mut self.ids)?;
        Ok((set, Some(bvh)))
    }
}

impl SceneData {
    /// Builds the core's view of the scene (8-wide sphere chunks, the
    /// materials with their images, the light list) and hands it to `f`.
    pub fn with_scene<R>(&self, f: impl FnOnce(&Scene<'_>) -> R) -> anyhow::Result<R> {
        self.with_scene_bvh(BvhMode::Auto, f)
    }

    /// [`SceneData::with_scene`], with the BVH chosen by `mode`.
    pub fn with_scene_bvh<R>(
        &self,
        mode: BvhMode,
        f: impl FnOnce(&Scene<'_>) -> R,
    ) -> anyhow::Result<R> {
        let mut buffers = SceneBuffers::new(self.spheres.len(), self.use_bvh(mode));
        let materials = self.materials();
        let scene = Scene::build(
            &self.spheres,
            &materials,
            &self.sphere_material,
            self.background,
            buffers.storage(),
        )
        .map_err(|e| anyhow::anyhow!("scene `{}` is invalid: {e}", self.name))?;
        Ok(f(&scene))
    }

    /// Whether the scene is traced through a BVH under `mode`: `Auto`
    /// from [`BVH_THRESHOLD`] spheres. Pixels are the same either way.
    pub fn use_bvh(&self, mode: BvhMode) -> bool {
        match mode {
            BvhMode::Auto => self.spheres.len() >= BVH_THRESHOLD,
            BvhMode::On => true,
            BvhMode::Off => false,
        }
    }

    /// The materials with image textures attached, borrowing the texels.
    pub fn materials(&self) -> Vec<Material<'_>> {
        let mut out: Vec<Material<'_>> = self.materials.to_vec();
        for &(m, i) in &self.image_albedo {
            let img = &self.images[i];
            if let Some(tex) = ImageTexture::new(img.width, img.height, &img.texels) {
                out[m] = with_albedo(self.materials[m], Texture::Image(tex));
            }
        }
        out
    }
}

#[cfg(test)]
mod tests {
    use glam::Vec3;

    use super::*;

    #[test]
    fn built_ins_are_valid() {
        for name in BUILT_IN {
            let s = built_in(name).unwrap();
            assert_eq!(s.spheres.len(), s.sphere_material.len(), "{name}");
            for m in s.materials() {
                m.validate()
                    .unwrap_or_else(|e| panic!("{name}: {m:?}: {e:?}"));
            }
            assert!(
                s.sphere_material
                    .iter()
                    .all(|&m| (m as usize) < s.materials.len())
            );
            // What a scene file must satisfy: the kernel's range, and every
            // sphere resolved from the camera (and here from every sphere).
            let reach = s
                .spheres
                .iter()
                .map(|p| p.center.length() + p.radius)
                .fold(s.camera.look_from.length(), f32::max);
            for p in &s.spheres {
                assert!(p.is_resolved_within(reach), "{name}: {p:?}");
                let max = p.center.abs().max_element().max(p.radius);
                assert!(max <= strata::trace::BVH_MAX_COORDINATE, "{name}: {p:?}");
            }
        }
        assert!(built_in("nope").is_none());
    }

    #[test]
    fn cover_materials_follow_the_book() {
        let s = cover();
        assert_eq!(s.spheres.len(), 485);
        let mats = s.materials();
        let kind = |i: usize| mats[s.sphere_material[i] as usize];
        assert!(matches!(kind(0), Material::Lambertian { .. }));
        assert!(matches!(kind(482), Material::Dielectric { .. }));
        assert!(matches!(kind(483), Material::Lambertian { .. }));
        assert!(matches!(kind(484), Material::Metal { roughness, .. } if roughness == 0.0));
        // Roughly 80 / 15 / 5 % among the small spheres.
        let small = 1..482;
        let lambert = small
            .clone()
            .filter(|&i| matches!(kind(i), Material::Lambertian { .. }))
            .count();
        let glass = small
            .clone()
            .filter(|&i| matches!(kind(i), Material::Dielectric { .. }))
            .count();
        assert!((330..440).contains(&lambert), "{lambert}");
        assert!((8..45).contains(&glass), "{glass}");
        // The lens: aperture 0.1 at focus 10.
        let r = 10.0 * (s.camera.defocus_angle_deg.to_radians() * 0.5).tan();
        assert!((r - 0.05).abs() < 1e-6);
    }

    /// `caustics` is what adaptive sampling is measured on: one sphere
    /// light no wider than 1/20 of the floor's visible width, a glass and
    /// a glossy metal sphere standing on a diffuse checker floor, a dim
    /// uniform sky.
    #[test]
    fn caustics_has_one_small_light_over_glass_and_metal() {
        let s = caustics();
        let mats = s.materials();
        let of = |i: usize| mats[s.sphere_material[i] as usize];
        let lights: Vec<usize> = (0..s.spheres.len())
            .filter(|&i| matches!(of(i), Material::DiffuseLight { .. }))
            .collect();
        assert_eq!(lights.len(), 1);
        assert!(matches!(
            of(0),
            Material::Lambertian {
                albedo: Texture::Checker { .. }
            }
        ));
        assert!((0..s.spheres.len()).any(|i| matches!(of(i), Material::Dielectric { .. })));
        assert!(
            (0..s.spheres.len())
                .any(|i| matches!(of(i), Material::Metal { roughness, .. } if roughness > 0.0))
        );
        // The floor's top is half a cell from the checker's boundaries
        // (so rounding never flips a cell); the other spheres stand on it.
        let floor = s.spheres[0];
        let top = floor.center.y + floor.radius;
        let Material::Lambertian {
            albedo: Texture::Checker { scale, .. },
        } = of(0)
        else {
            panic!("a checker floor")
        };
        assert_eq!((top / scale).rem_euclid(1.0), 0.5, "floor top {top}");
        for i in 1..s.spheres.len() {
            if i != lights[0] {
                let b = s.spheres[i];
                assert!((b.center.y - b.radius - top).abs() < 1e-6, "sphere {i}");
            }
        }
        // The frame's width at the distance of what it looks at.
        let c = s.camera;
        let distance = (c.look_at - c.look_from).length();
        let height = 2.0 * distance * (c.vfov_deg.to_radians() * 0.5).tan();
        let width = height * s.defaults.aspect;
        let light = s.spheres[lights[0]];
        assert_eq!(light.radius, CAUSTICS_LIGHT_RADIUS);
        assert!(light.radius <= width / 20.0, "{} vs {width}", light.radius);
        assert!((width / light.radius - 40.0).abs() < 2.0, "about 1/40");
        let Background::Flat(sky) = s.background else {
            panic!("a uniform sky")
        };
        assert!(sky.max_element() > 0.0 && sky.max_element() <= 0.1);
    }

    #[test]
    fn content_hash_sees_every_change() {
        let a = showcase();
        let h = a.content_hash();
        assert_eq!(h, showcase().content_hash());
        let changed = |f: &dyn Fn(&mut SceneData)| {
            let mut b = showcase();
            f(&mut b);
            b.content_hash()
        };
        assert_ne!(h, changed(&|b| b.spheres[2].radius = 0.500_001));
        assert_ne!(h, changed(&|b| b.sphere_material.swap(1, 2)));
        assert_ne!(h, changed(&|b| b.images[0].texels[5].x += 1e-6));
        assert_ne!(h, changed(&|b| b.camera.vfov_deg = 50.000_004));
        assert_ne!(h, changed(&|b| b.background = Background::Sky));
        assert_ne!(
            h,
            changed(&|b| b.materials[6] = Material::Mirror {
                albedo: Vec3::splat(0.8)
            })
        );
        // The name and the defaults do not define the picture.
        assert_eq!(h, changed(&|b| b.name = "renamed".into()));
        assert_eq!(h, changed(&|b| b.defaults.spp = 1));
        // A value lock: the hash is a file-format promise.
        assert_eq!(
            week09().content_hash(),
            WEEK09_HASH,
            "{:#018x}",
            week09().content_hash()
        );
    }

    /// The locked hash of `week09` (it appears in every PNG of it).
    const WEEK09_HASH: u64 = 0x7ee690f76348c390;

    #[test]
    fn image_albedo_is_attached() {
        let s = showcase();
        assert!(matches!(
            s.materials()[9],
            Material::Lambertian {
                albedo: Texture::Image(_)
            }
        ));
    }
}
