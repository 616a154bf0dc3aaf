//! A renderer author's first hour: a small image with the core alone.
//!
//! Four spheres (a checker ground, a matte, a glass and a metal ball)
//! under the course's sky, path traced at 16 samples per pixel, tile by
//! tile into one film buffer the caller owns, then written as a plain
//! PPM. Every buffer here is the caller's: the core allocates nothing.
//!
//! Run with `cargo run --release -p strata --example render_image [out.ppm]`.

use glam::Vec3;
use strata::Independent;
use strata::render::{
    Background, Camera, CameraDesc, Material, PixelSum, RenderSettings, Scene, SceneStorage,
    SceneStorageSize, Texture, Tile, render_tile,
};
use strata::trace::{Sphere, SphereChunk8};

const WIDTH: u32 = 160;
const HEIGHT: u32 = 90;
const SPP: u32 = 16;
const TILE: u32 = 16;

fn main() -> Result<(), Box<dyn std::error::Error>> {
    // The scene: spheres, their materials, and which sphere has which.
    let spheres = [
        Sphere::new(Vec3::new(0.0, -100.5, -1.0), 100.0),
        Sphere::new(Vec3::new(-1.0, 0.0, -1.0), 0.5),
        Sphere::new(Vec3::new(0.0, 0.0, -1.0), 0.5),
        Sphere::new(Vec3::new(1.0, 0.0, -1.0), 0.5),
    ];
    let materials = [
        Material::Lambertian {
            albedo: Texture::Checker {
                scale: 0.5,
                even: Vec3::splat(0.2),
                odd: Vec3::splat(0.9),
            },
        },
        Material::Lambertian {
            albedo: Texture::Solid(Vec3::new(0.7, 0.3, 0.3)),
        },
        Material::Dielectric { ior: 1.5 },
        Material::Metal {
            albedo: Vec3::new(0.8, 0.6, 0.2),
            roughness: 0.1,
        },
    ];
    let sphere_material = [0, 1, 2, 3];

    // Caller-owned storage, sized for 4 spheres without a BVH (a BVH pays
    // from about `strata::trace::BVH_MIN_SPHERES` spheres; it never changes
    // a pixel).
    let size = SceneStorageSize::for_spheres(spheres.len(), false);
    let mut chunks = [SphereChunk8::EMPTY; 1];
    let mut lights = [0u32; 4];
    assert_eq!((size.chunks, size.lights), (chunks.len(), lights.len()));
    let storage = SceneStorage {
        chunks: &mut chunks,
        lights: &mut lights,
        bvh_nodes: &mut [],
        bvh_lanes: &mut [],
        bvh_ids: &mut [],
    };
    let scene = Scene::build(
        &spheres,
        &materials,
        &sphere_material,
        Background::Sky,
        storage,
    )?;

    let camera = Camera::new(
        &CameraDesc {
            look_from: Vec3::new(-2.0, 2.0, 1.0),
            look_at: Vec3::new(0.0, 0.0, -1.0),
            up: Vec3::Y,
            vfov_deg: 60.0,
            defocus_angle_deg: 0.0,
            focus_dist: 1.0,
        },
        WIDTH,
        HEIGHT,
    )?;
    let settings = RenderSettings {
        max_depth: 8,
        direct_lighting: true,
        filter: strata::render::PixelFilter::BOX,
        texture_filter: strata::render::TextureFilter::None,
        integrator: strata::render::Integrator::Scalar,
    };
    // The sampler is a prototype: each pixel sample derives its own stream
    // from (seed, pixel, index), so tiles may run in any order or thread.
    let sampler = Independent::new(SPP, 2026).ok_or("spp must be > 0")?;

    // Render tile by tile into one image-sized film.
    let mut image = vec![PixelSum::ZERO; Tile::whole(WIDTH, HEIGHT).area()];
    let mut tile_film = vec![PixelSum::ZERO; (TILE * TILE) as usize];
    for y0 in (0..HEIGHT).step_by(TILE as usize) {
        for x0 in (0..WIDTH).step_by(TILE as usize) {
            let tile = Tile {
                x0,
                y0,
                width: TILE.min(WIDTH - x0),
                height: TILE.min(HEIGHT - y0),
            };
            let film = &mut tile_film[..tile.area()];
            film.fill(PixelSum::ZERO);
            render_tile(&scene, &camera, &sampler, &settings, tile, 0..SPP, film)?;
            for (k, p) in film.iter().enumerate() {
                let (x, y) = (x0 + k as u32 % tile.width, y0 + k as u32 / tile.width);
                image[(y * WIDTH + x) as usize] = *p;
            }
        }
    }

    // Linear radiance per pixel; the sky at the top is blue-white, and
    // every pixel took every sample.
    let pixels: Vec<Vec3> = image.iter().map(PixelSum::mean).collect();
    assert!(image.iter().all(|p| p.samples == SPP));
    let top = pixels[(WIDTH / 2) as usize];
    assert!(top.z > top.x && top.min_element() > 0.5, "sky {top}");

    // A binary PPM with the sRGB curve, for any image viewer.
    let encode = |v: f32| {
        let v = v.clamp(0.0, 1.0);
        let s = if v <= 0.003_130_8 {
            12.92 * v
        } else {
            1.055 * v.powf(1.0 / 2.4) - 0.055
        };
        (s * 255.0).round() as u8
    };
    let mut ppm = format!("P6\n{WIDTH} {HEIGHT}\n255\n").into_bytes();
    ppm.extend(pixels.iter().flat_map(|p| [p.x, p.y, p.z].map(encode)));
    let path = std::env::args()
        .nth(1)
        .unwrap_or_else(|| "render_image.ppm".into());
    std::fs::write(&path, ppm)?;
    println!("wrote {path}: {WIDTH}x{HEIGHT}, {SPP} spp, sky {top}");
    Ok(())
}
