//! Scenes, cameras and a tile loop shared by the rendering tests.

use glam::Vec3;
use strata::Sampler;
use strata::render::*;
use strata::trace::Sphere;
use strata_runner::scenes::SceneBuffers;

fn solid(c: f32) -> Texture<'static> {
    Texture::Solid(Vec3::splat(c))
}

/// A scene's data and the buffers it is built into.
pub struct OwnedScene<'a> {
    spheres: Vec<Sphere>,
    materials: Vec<Material<'a>>,
    sphere_material: Vec<u32>,
    background: Background,
    buffers: SceneBuffers,
}

impl<'a> OwnedScene<'a> {
    pub fn new(
        list: Vec<(Sphere, u32)>,
        materials: Vec<Material<'a>>,
        background: Background,
    ) -> Self {
        let (spheres, sphere_material): (Vec<_>, Vec<_>) = list.into_iter().unzip();
        let buffers = SceneBuffers::new(spheres.len(), false);
        Self {
            spheres,
            materials,
            sphere_material,
            background,
            buffers,
        }
    }

    pub fn scene(&mut self) -> Scene<'_> {
        Scene::build(
            &self.spheres,
            &self.materials,
            &self.sphere_material,
            self.background,
            self.buffers.storage(),
        )
        .unwrap()
    }
}

/// A small scene with every kind of material and two lights.
pub fn showcase() -> OwnedScene<'static> {
    let checker = Texture::Checker {
        scale: 0.5,
        even: Vec3::splat(0.2),
        odd: Vec3::splat(0.9),
    };
    let m = vec![
        Material::Lambertian { albedo: checker },
        Material::Blinn {
            albedo: Texture::Solid(Vec3::new(0.4, 0.5, 0.4)),
            kd: 0.5,
            ks: 0.6,
            exponent: 8.0,
        },
        Material::Dielectric { ior: 1.5 },
        Material::Metal {
            albedo: Vec3::new(0.8, 0.6, 0.2),
            roughness: 0.3,
        },
        Material::Mirror {
            albedo: Vec3::splat(0.9),
        },
        Material::CookTorrance {
            albedo: solid(0.5),
            kd: 0.5,
            ks: 0.5,
            alpha: 0.3,
            ior: 1.5,
        },
        Material::DiffuseLight {
            emit: Vec3::splat(8.0),
        },
        Material::PhongNormalized {
            albedo: solid(0.7),
            kd: 0.6,
            ks: 0.3,
            exponent: 20.0,
        },
    ];
    let s = |x: f32, y: f32, z: f32, r: f32| Sphere::new(Vec3::new(x, y, z), r);
    OwnedScene::new(
        vec![
            (s(0.0, -100.5, -1.0, 100.0), 0),
            (s(-1.0, 0.0, -1.0, 0.5), 1),
            (s(0.0, 0.0, -1.0, 0.5), 2),
            (s(1.0, 0.0, -1.0, 0.5), 3),
            (s(0.0, 0.0, -2.5, 0.5), 4),
            (s(-0.6, -0.3, -0.3, 0.2), 5),
            (s(0.0, 1.5, -1.0, 0.25), 6),
            (s(1.5, 1.0, 0.0, 0.15), 6),
            (s(0.6, -0.3, -0.2, 0.2), 7),
        ],
        m,
        Background::Sky,
    )
}

/// The course's camera: look-from (−2, 2, 1) at (0, 0, −1), 60°, a thin lens.
pub fn course_camera(w: u32, h: u32) -> Camera {
    let desc = CameraDesc {
        look_from: Vec3::new(-2.0, 2.0, 1.0),
        look_at: Vec3::new(0.0, 0.0, -1.0),
        up: Vec3::Y,
        vfov_deg: 60.0,
        defocus_angle_deg: 2.0,
        focus_dist: 3.4,
    };
    Camera::new(&desc, w, h).unwrap()
}

/// Depth 6, direct lighting, the box filter, point-sampled textures.
pub const SETTINGS: RenderSettings = RenderSettings {
    max_depth: 6,
    direct_lighting: true,
    filter: strata::render::PixelFilter::BOX,
    texture_filter: strata::render::TextureFilter::None,
    integrator: strata::render::Integrator::Scalar,
};

/// The whole image through `render_tile` in tiles of `tile_w × tile_h`.
pub fn render_tiles<S: Sampler + Clone>(
    scene: &Scene,
    cam: &Camera,
    s: &S,
    tile_w: u32,
    tile_h: u32,
    samples: std::ops::Range<u32>,
) -> Vec<PixelSum> {
    let size = cam.size();
    let mut image = vec![PixelSum::ZERO; (size.x * size.y) as usize];
    let mut y0 = 0;
    while y0 < size.y {
        let mut x0 = 0;
        while x0 < size.x {
            let tile = Tile {
                x0,
                y0,
                width: tile_w.min(size.x - x0),
                height: tile_h.min(size.y - y0),
            };
            let mut film = vec![PixelSum::ZERO; tile.area()];
            render_tile(scene, cam, s, &SETTINGS, tile, samples.clone(), &mut film).unwrap();
            for r in 0..tile.height {
                for c in 0..tile.width {
                    image[((y0 + r) * size.x + x0 + c) as usize] =
                        film[(r * tile.width + c) as usize];
                }
            }
            x0 += tile.width;
        }
        y0 += tile_h;
    }
    image
}
