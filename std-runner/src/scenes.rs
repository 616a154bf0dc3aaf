//! Scenes as owned data, and the built-in ones: `week09` (the course's
//! picture, the default), `cover` (the cover of *Ray Tracing in One
//! Weekend*) and `showcase` (every material, sphere lights and an image
//! texture).

use glam::Vec3;
use strata::render::{
    Background, CameraDesc, ImageTexture, Material, Scene, SceneStorage, SceneStorageSize, Texture,
};
use strata::rng::{Pcg32, next_f32};
use strata::trace::{Bvh, BvhError, BvhNode8, BvhStorage, Sphere, SphereChunk8, SphereSet};

use crate::hash::Fnv;
use crate::workload::{course_spheres, cover_spheres};

/// The sphere count from which the runner traces a scene through a BVH.
/// On the course's 4 spheres the brute-force 8-wide loop is faster and on
/// the cover's 485 the BVH is (`strata bench`); 16 (two 8-wide chunks) is
/// a round point between, not a measured crossover. The choice never
/// changes a pixel.
pub const BVH_THRESHOLD: usize = 16;

/// An image texture's texels, linear RGB, row 0 at the top.
#[derive(Clone, Debug, PartialEq)]
pub struct Image {
    /// Columns.
    pub width: u32,
    /// Rows.
    pub height: u32,
    /// `width × height` linear RGB values, row-major.
    pub texels: Vec<Vec3>,
}

/// Whether a scene is traced through a BVH (it never changes a pixel).
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, clap::ValueEnum)]
pub enum BvhMode {
    /// From [`BVH_THRESHOLD`] spheres.
    #[default]
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
    /// their BVH, for tracing without a scene (benchmarks, tests).
    pub fn trace<'a>(
        &'a mut self,
        spheres: &[Sphere],
    ) -> anyhow::Result<(SphereSet<'a>, Option<Bvh<'a>>)> {
        let set = SphereSet::build(spheres, &mut self.chunks)?;
        if self.nodes.is_empty() {
            return Ok((set, None));
        }
        // As in `Scene::build`: spheres the BVH cannot hold give no BVH.
        match Bvh::build(spheres, &mut self.nodes, &mut self.lanes, &mut self.ids) {
            Ok(bvh) => Ok((set, Some(bvh))),
            Err(BvhError::SphereOutOfRange { .. } | BvhError::TooManySpheres) => Ok((set, None)),
            Err(e) => Err(e.into()),
        }
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

    /// A stable 64-bit hash of everything that defines the picture: FNV-1a
    /// over the exact bits of the spheres, materials, textures, images,
    /// camera and background, fed as a stream (no formatting, so it does
    /// not change with the toolchain). The name and the render defaults are
    /// left out: renaming a scene file does not change its renders.
    pub fn content_hash(&self) -> u64 {
        let mut h = Fnv::default();
        h.u64(self.spheres.len() as u64);
        for s in &self.spheres {
            h.v3(s.center);
            h.f(s.radius);
        }
        for &m in &self.sphere_material {
            h.u32(m);
        }
        h.u64(self.materials.len() as u64);
        for m in &self.materials {
            hash_material(&mut h, m);
        }
        for &(m, i) in &self.image_albedo {
            h.u64(m as u64);
            h.u64(i as u64);
        }
        for img in &self.images {
            h.u32(img.width);
            h.u32(img.height);
            for &t in &img.texels {
                h.v3(t);
            }
        }
        let c = &self.camera;
        for v in [c.look_from, c.look_at, c.up] {
            h.v3(v);
        }
        for x in [c.vfov_deg, c.defocus_angle_deg, c.focus_dist] {
            h.f(x);
        }
        match self.background {
            Background::Sky => h.u32(1),
            Background::Flat(c) => {
                h.u32(2);
                h.v3(c);
            }
        }
        h.finish()
    }
}

fn hash_texture(h: &mut Fnv, t: &Texture<'_>) {
    match t {
        Texture::Solid(c) => {
            h.u32(1);
            h.v3(*c);
        }
        Texture::Checker { scale, even, odd } => {
            h.u32(2);
            h.f(*scale);
            h.v3(*even);
            h.v3(*odd);
        }
        // Images are hashed with the scene's image list.
        Texture::Image(_) => h.u32(3),
    }
}

fn hash_material(h: &mut Fnv, m: &Material<'_>) {
    let lobe = |h: &mut Fnv, tag: u32, albedo: &Texture<'_>, params: &[f32]| {
        h.u32(tag);
        hash_texture(h, albedo);
        for &p in params {
            h.f(p);
        }
    };
    match m {
        Material::Lambertian { albedo } => lobe(h, 1, albedo, &[]),
        Material::Mirror { albedo } => {
            h.u32(2);
            h.v3(*albedo);
        }
        Material::Metal { albedo, roughness } => {
            h.u32(3);
            h.v3(*albedo);
            h.f(*roughness);
        }
        Material::Dielectric { ior } => {
            h.u32(4);
            h.f(*ior);
        }
        Material::Phong {
            albedo,
            kd,
            ks,
            exponent,
        } => lobe(h, 5, albedo, &[*kd, *ks, *exponent]),
        Material::Blinn {
            albedo,
            kd,
            ks,
            exponent,
        } => lobe(h, 6, albedo, &[*kd, *ks, *exponent]),
        Material::PhongNormalized {
            albedo,
            kd,
            ks,
            exponent,
        } => lobe(h, 7, albedo, &[*kd, *ks, *exponent]),
        Material::BlinnNormalized {
            albedo,
            kd,
            ks,
            exponent,
        } => lobe(h, 8, albedo, &[*kd, *ks, *exponent]),
        Material::CookTorrance {
            albedo,
            kd,
            ks,
            alpha,
            ior,
        } => lobe(h, 9, albedo, &[*kd, *ks, *alpha, *ior]),
        Material::DiffuseLight { emit } => {
            h.u32(10);
            h.v3(*emit);
        }
    }
}

/// The names of the built-in scenes.
pub const BUILT_IN: [&str; 4] = ["week09", "cover", "showcase", "horizon"];

/// A built-in scene by name.
pub fn built_in(name: &str) -> Option<SceneData> {
    match name {
        "week09" => Some(week09()),
        "cover" => Some(cover()),
        "showcase" => Some(showcase()),
        "horizon" => Some(horizon()),
        _ => None,
    }
}

/// The course's `main.py` (`renderBlinn`): 16:9, camera from (−2, 2, 1) to
/// (0, 0, −1), vfov 60, pinhole focused at 5; checker ground (cell 0.32,
/// 0.2 / 0.9 grey); Blinn spheres left, centre, right with (colour, kd, ks,
/// exponent) = ((.8,.5,.8), .5, .2, .08), ((.4,.5,.4), .5, .6, 8),
/// ((.8,.5,.4), .5, .2, 300); the sky; 320 wide, 30 spp, depth 5.
pub fn week09() -> SceneData {
    let blinn = |c: Vec3, kd, ks, exponent| Material::Blinn {
        albedo: Texture::Solid(c),
        kd,
        ks,
        exponent,
    };
    SceneData {
        name: "week09".into(),
        spheres: course_spheres(),
        sphere_material: vec![0, 1, 2, 3],
        materials: vec![
            Material::Lambertian {
                albedo: Texture::Checker {
                    scale: 0.32,
                    even: Vec3::splat(0.2),
                    odd: Vec3::splat(0.9),
                },
            },
            blinn(Vec3::new(0.8, 0.5, 0.8), 0.5, 0.2, 0.08),
            blinn(Vec3::new(0.4, 0.5, 0.4), 0.5, 0.6, 8.0),
            blinn(Vec3::new(0.8, 0.5, 0.4), 0.5, 0.2, 300.0),
        ],
        image_albedo: vec![],
        images: vec![],
        camera: CameraDesc {
            look_from: Vec3::new(-2.0, 2.0, 1.0),
            look_at: Vec3::new(0.0, 0.0, -1.0),
            up: Vec3::Y,
            vfov_deg: 60.0,
            defocus_angle_deg: 0.0,
            focus_dist: 5.0,
        },
        background: Background::Sky,
        defaults: Defaults {
            width: 320,
            aspect: 16.0 / 9.0,
            spp: 30,
            max_depth: 5,
        },
    }
}

/// The cover of *Ray Tracing in One Weekend*: the geometry of
/// [`cover_spheres`]; materials by the book's rule, drawn from a second
/// PCG32 stream, `Pcg32::new(42, 55)` (the geometry uses stream 54), one
/// small sphere at a time in layout order: `choose < 0.8` Lambertian with
/// albedo `a ⊙ b` for two random colours `a`, `b` (3 draws each); `< 0.95`
/// metal with albedo `0.5 + 0.5 c` (3 draws) and fuzz `0.5 u`; else glass
/// 1.5. Ground Lambertian 0.5; big spheres glass 1.5 at (0, 1, 0),
/// Lambertian (0.4, 0.2, 0.1) at (−4, 1, 0), metal (0.7, 0.6, 0.5) fuzz 0
/// at (4, 1, 0). Camera from (13, 2, 3) to the origin, vfov 20, aperture
/// 0.1 (lens radius 0.05) focused at 10; 400 × 225, 32 spp, depth 50.
pub fn cover() -> SceneData {
    let spheres = cover_spheres();
    let mut rng = Pcg32::new(42, 55);
    let mut f = || next_f32(&mut rng);
    let glass = Material::Dielectric { ior: 1.5 };
    let mut materials = vec![
        Material::Lambertian {
            albedo: Texture::Solid(Vec3::splat(0.5)),
        },
        glass,
    ];
    let mut sphere_material = vec![0];
    let small = spheres.len() - 4;
    for _ in 0..small {
        let choose = f();
        let material = if choose < 0.8 {
            let a = Vec3::new(f(), f(), f());
            let b = Vec3::new(f(), f(), f());
            Material::Lambertian {
                albedo: Texture::Solid(a * b),
            }
        } else if choose < 0.95 {
            let albedo = Vec3::new(0.5 + 0.5 * f(), 0.5 + 0.5 * f(), 0.5 + 0.5 * f());
            Material::Metal {
                albedo,
                roughness: 0.5 * f(),
            }
        } else {
            sphere_material.push(1); // the shared glass
            continue;
        };
        materials.push(material);
        sphere_material.push(materials.len() as u32 - 1);
    }
    materials.push(Material::Lambertian {
        albedo: Texture::Solid(Vec3::new(0.4, 0.2, 0.1)),
    });
    materials.push(Material::Metal {
        albedo: Vec3::new(0.7, 0.6, 0.5),
        roughness: 0.0,
    });
    let n = materials.len() as u32;
    sphere_material.extend([1, n - 2, n - 1]);
    let focus = 10.0f32;
    SceneData {
        name: "cover".into(),
        spheres,
        sphere_material,
        materials,
        image_albedo: vec![],
        images: vec![],
        camera: CameraDesc {
            look_from: Vec3::new(13.0, 2.0, 3.0),
            look_at: Vec3::ZERO,
            up: Vec3::Y,
            vfov_deg: 20.0,
            // libm, not the platform's atan: the same lens bits everywhere.
            defocus_angle_deg: 2.0 * libm::atanf(0.05 / focus).to_degrees(),
            focus_dist: focus,
        },
        background: Background::Sky,
        defaults: Defaults {
            width: 400,
            aspect: 16.0 / 9.0,
            spp: 32,
            max_depth: 50,
        },
    }
}

/// A 64 × 32 latitude–longitude test image: a blue–green gradient with
/// bright meridians every 45° and parallels every 30°, so its orientation
/// (and the `v` flip) shows on a sphere.
pub fn globe_image() -> Image {
    let (width, height) = (64u32, 32u32);
    let mut texels = Vec::with_capacity((width * height) as usize);
    for j in 0..height {
        for i in 0..width {
            let line = i % 8 == 0 || j % (height / 6).max(1) == 0;
            let t = j as f32 / (height - 1) as f32;
            let base = Vec3::new(0.1, 0.3 + 0.4 * t, 0.7 - 0.4 * t);
            texels.push(if line {
                Vec3::new(0.95, 0.9, 0.6)
            } else {
                base
            });
        }
    }
    Image {
        width,
        height,
        texels,
    }
}

/// Every material, two sphere lights and an image texture, under a dim
/// background: a check that everything renders together.
pub fn showcase() -> SceneData {
    let solid = |r: f32, g: f32, b: f32| Texture::Solid(Vec3::new(r, g, b));
    let materials = vec![
        Material::Lambertian {
            albedo: Texture::Checker {
                scale: 0.32,
                even: Vec3::splat(0.2),
                odd: Vec3::splat(0.9),
            },
        },
        Material::Blinn {
            albedo: solid(0.8, 0.5, 0.8),
            kd: 0.5,
            ks: 0.2,
            exponent: 0.08,
        },
        Material::Phong {
            albedo: solid(0.4, 0.5, 0.4),
            kd: 0.5,
            ks: 0.4,
            exponent: 8.0,
        },
        Material::BlinnNormalized {
            albedo: solid(0.8, 0.5, 0.4),
            kd: 0.6,
            ks: 0.4,
            exponent: 60.0,
        },
        Material::PhongNormalized {
            albedo: solid(0.3, 0.4, 0.8),
            kd: 0.7,
            ks: 0.3,
            exponent: 30.0,
        },
        Material::CookTorrance {
            albedo: solid(0.7, 0.2, 0.2),
            kd: 0.6,
            ks: 0.4,
            alpha: 0.25,
            ior: 1.5,
        },
        Material::Mirror {
            albedo: Vec3::splat(0.9),
        },
        Material::Metal {
            albedo: Vec3::new(0.8, 0.6, 0.2),
            roughness: 0.25,
        },
        Material::Dielectric { ior: 1.5 },
        // Its albedo becomes the globe image.
        Material::Lambertian {
            albedo: Texture::Solid(Vec3::splat(0.5)),
        },
        Material::DiffuseLight {
            emit: Vec3::new(12.0, 11.0, 9.0),
        },
        Material::DiffuseLight {
            emit: Vec3::new(3.0, 4.0, 8.0),
        },
    ];
    let s = |x: f32, y: f32, z: f32, r: f32| Sphere::new(Vec3::new(x, y, z), r);
    let list = [
        (s(0.0, -100.5, -1.0, 100.0), 0),
        (s(-2.2, 0.0, -1.6, 0.5), 1),
        (s(-1.1, 0.0, -1.4, 0.5), 2),
        (s(0.0, 0.0, -1.2, 0.5), 3),
        (s(1.1, 0.0, -1.4, 0.5), 4),
        (s(2.2, 0.0, -1.6, 0.5), 5),
        (s(-1.6, 0.0, -3.0, 0.5), 6),
        (s(-0.5, 0.0, -3.0, 0.5), 7),
        (s(0.6, 0.0, -3.0, 0.5), 8),
        (s(1.7, 0.0, -3.0, 0.5), 9),
        (s(-0.8, 1.6, -0.6, 0.3), 10),
        (s(1.8, 1.2, 0.4, 0.2), 11),
    ];
    SceneData {
        name: "showcase".into(),
        spheres: list.iter().map(|l| l.0).collect(),
        sphere_material: list.iter().map(|l| l.1).collect(),
        materials,
        image_albedo: vec![(9, 0)],
        images: vec![globe_image()],
        camera: CameraDesc {
            look_from: Vec3::new(0.0, 1.6, 2.8),
            look_at: Vec3::new(0.0, 0.0, -1.8),
            up: Vec3::Y,
            vfov_deg: 50.0,
            defocus_angle_deg: 0.0,
            focus_dist: 4.0,
        },
        background: Background::Flat(Vec3::new(0.04, 0.05, 0.08)),
        defaults: Defaults {
            width: 480,
            aspect: 16.0 / 9.0,
            spp: 64,
            max_depth: 8,
        },
    }
}

/// The radius of `horizon`'s ground sphere: big enough that the plane
/// runs to a horizon 0.8° below eye level from 1 unit up, small enough
/// that f32 keeps the hit points to about a millimetre.
pub const HORIZON_RADIUS: f32 = 1.0e4;

/// The aliasing demo: a high-frequency checker plane (0.25 cells, black
/// and white) running to the horizon under a uniform white sky, seen from
/// 1 unit above it. The ground is a sphere of radius [`HORIZON_RADIUS`]
/// whose top is at `y = 0`; the checker is the course's 3-D one, so far
/// away, where the ground curves below the cell size, its `y` term adds
/// rings. Lambertian ground under a uniform sky of radiance 1 sends back
/// exactly its albedo along every bounce (the ground is convex, so no
/// bounce hits it again): a pixel's value is the checker's average over
/// the pixel, free of shading noise, which is what shows aliasing. 320 ×
/// 180, 4 spp, depth 2.
pub fn horizon() -> SceneData {
    SceneData {
        name: "horizon".into(),
        spheres: vec![Sphere::new(
            Vec3::new(0.0, -HORIZON_RADIUS, 0.0),
            HORIZON_RADIUS,
        )],
        sphere_material: vec![0],
        materials: vec![Material::Lambertian {
            albedo: Texture::Checker {
                scale: 0.25,
                even: Vec3::splat(0.05),
                odd: Vec3::splat(0.95),
            },
        }],
        image_albedo: vec![],
        images: vec![],
        camera: CameraDesc {
            look_from: Vec3::new(0.0, 1.0, 0.0),
            // Turned off the checker's axes so its rows run diagonally.
            look_at: Vec3::new(3.0, 0.0, -8.0),
            up: Vec3::Y,
            vfov_deg: 40.0,
            defocus_angle_deg: 0.0,
            focus_dist: 1.0,
        },
        background: Background::Flat(Vec3::ONE),
        defaults: Defaults {
            width: 320,
            aspect: 16.0 / 9.0,
            spp: 4,
            max_depth: 2,
        },
    }
}

#[cfg(test)]
mod tests {
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
