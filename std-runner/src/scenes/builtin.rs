//! The built-in scenes: `week09` (the course's picture, the default),
//! `cover` (the cover of *Ray Tracing in One Weekend*), `showcase` (every
//! material, sphere lights and an image texture), `horizon` (a fine
//! checker plane to the horizon, for the aliasing demo) and `caustics` (a
//! small light through glass: noise in a few places, for adaptive
//! sampling).

use glam::Vec3;
use strata::render::{Background, CameraDesc, Material, Texture};
use strata::rng::{Pcg32, next_f32};
use strata::trace::Sphere;

use super::geometry::{COURSE_VIEW, COVER_VIEW, course_spheres, cover_spheres};
use super::{Defaults, Image, SceneData};

/// The names of the built-in scenes.
pub const BUILT_IN: [&str; 5] = ["week09", "cover", "showcase", "horizon", "caustics"];

/// A built-in scene by name.
pub fn built_in(name: &str) -> Option<SceneData> {
    match name {
        "week09" => Some(week09()),
        "cover" => Some(cover()),
        "showcase" => Some(showcase()),
        "horizon" => Some(horizon()),
        "caustics" => Some(caustics()),
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
            look_from: COURSE_VIEW.from,
            look_at: COURSE_VIEW.at,
            up: Vec3::Y,
            vfov_deg: COURSE_VIEW.vfov,
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
            look_from: COVER_VIEW.from,
            look_at: COVER_VIEW.at,
            up: Vec3::Y,
            vfov_deg: COVER_VIEW.vfov,
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

/// The radius of `caustics`' light: about 1/40 of the floor's visible
/// width across the frame at the spheres (4.3 units), so the light is
/// small and the caustics it throws are sharp and rare.
pub const CAUSTICS_LIGHT_RADIUS: f32 = 0.11;

/// Adaptive sampling's test scene: a glass sphere (ior 1.5) and a glossy
/// metal one on a diffuse checker floor with large cells, lit by one small
/// sphere light (radius [`CAUSTICS_LIGHT_RADIUS`]) above and behind the
/// glass, under a dim uniform sky. The glass focuses the light into a
/// caustic on the floor in front of it, which only paths that bounce off
/// the floor and through the glass into the light find (no light sample
/// passes the glass), so it stays noisy for many samples; contact shadows
/// and the metal's blurred reflections are noisy too; the rest of the
/// frame (floor lit directly, sky, the spheres' smooth sides) converges
/// fast. The floor's top is at `y = −0.25`, half a checker cell from the
/// cells' boundary at 0, so rounding of hit points never flips a cell.
/// 320 × 180, 64 spp, depth 8.
pub fn caustics() -> SceneData {
    let materials = vec![
        Material::Lambertian {
            albedo: Texture::Checker {
                scale: 0.5,
                even: Vec3::splat(0.35),
                odd: Vec3::splat(0.75),
            },
        },
        Material::Dielectric { ior: 1.5 },
        Material::Metal {
            albedo: Vec3::new(0.85, 0.75, 0.6),
            roughness: 0.15,
        },
        Material::DiffuseLight {
            emit: Vec3::new(1.0, 0.95, 0.85) * 600.0,
        },
    ];
    let s = |x: f32, y: f32, z: f32, r: f32| Sphere::new(Vec3::new(x, y, z), r);
    let list = [
        (s(0.0, -1000.25, 0.0, 1000.0), 0),
        (s(-0.65, 0.25, 0.0, 0.5), 1),
        (s(0.75, 0.25, -0.5, 0.5), 2),
        (s(-1.3, 2.35, -1.4, CAUSTICS_LIGHT_RADIUS), 3),
    ];
    SceneData {
        name: "caustics".into(),
        spheres: list.iter().map(|l| l.0).collect(),
        sphere_material: list.iter().map(|l| l.1).collect(),
        materials,
        image_albedo: vec![],
        images: vec![],
        camera: CameraDesc {
            look_from: Vec3::new(0.0, 1.05, 3.2),
            look_at: Vec3::new(0.0, 0.1, 0.0),
            up: Vec3::Y,
            vfov_deg: 40.0,
            defocus_angle_deg: 0.0,
            focus_dist: 3.3,
        },
        background: Background::Flat(Vec3::splat(0.03)),
        defaults: Defaults {
            width: 320,
            aspect: 16.0 / 9.0,
            spp: 64,
            max_depth: 8,
        },
    }
}
