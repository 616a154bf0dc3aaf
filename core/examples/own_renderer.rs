//! How to use Strata in your own renderer: a compact path tracer with its
//! own camera, materials, film and geometry (spheres beside a box and a
//! floor made of triangles), taking from Strata only the sampling (a
//! seeded Sobol' sampler, the cosine-hemisphere mapping, an orthonormal
//! basis), the sphere kernel, and a BVH over its own primitives.
//!
//! It asserts what Strata promises it: the tree's hits are the brute-force
//! hits; the image is the same, bit for bit, however its rows are split
//! between threads; and the picture is plausible (lit, with the red
//! sphere red). Then it writes a PPM.
//!
//! Run with `cargo run --release -p strata --features alloc --example
//! own_renderer [out.ppm]` (the `alloc` feature gives the owning tree).

use strata::glam::{UVec2, Vec3};
use strata::mapping::sample_cosine_hemisphere;
use strata::onb::Onb;
use strata::trace::{Aabb, OwnedPrimitiveBvh, Primitives, Ray, Sphere, intersect_sphere};
use strata::{Sampler, Sobol};

const WIDTH: u32 = 160;
const HEIGHT: u32 = 90;
const SPP: u32 = 16;
const DEPTH: u32 = 5;

/// The renderer's own materials.
#[derive(Clone, Copy)]
enum Material {
    Diffuse(Vec3),
    Mirror(Vec3),
    Light(Vec3),
}

/// The renderer's own shapes.
#[derive(Clone, Copy)]
enum Shape {
    Ball(Sphere),
    Triangle([Vec3; 3]),
}

/// The scene: shapes with a material each.
struct World {
    shapes: Vec<(Shape, Material)>,
}

impl World {
    /// A unit box's 12 triangles, scaled and moved.
    fn add_box(&mut self, lo: Vec3, hi: Vec3, m: Material) {
        let c = |i: u32| {
            Vec3::new(
                if i & 1 == 0 { lo.x } else { hi.x },
                if i & 2 == 0 { lo.y } else { hi.y },
                if i & 4 == 0 { lo.z } else { hi.z },
            )
        };
        for [a, b, d, e] in [
            [0, 1, 3, 2],
            [4, 6, 7, 5],
            [0, 4, 5, 1],
            [2, 3, 7, 6],
            [0, 2, 6, 4],
            [1, 5, 7, 3],
        ] {
            self.shapes.push((Shape::Triangle([c(a), c(b), c(d)]), m));
            self.shapes.push((Shape::Triangle([c(a), c(d), c(e)]), m));
        }
    }
}

/// Möller–Trumbore; the hit is kept only if it lies in the triangle's
/// box (a ray within rounding of the plane can compute a `t` far off):
/// the requirement of `Primitives`, checked by `Aabb::holds_hit`.
fn hit_triangle(v: &[Vec3; 3], ray: &Ray) -> Option<f32> {
    let (e1, e2) = (v[1] - v[0], v[2] - v[0]);
    let p = ray.dir.cross(e2);
    let det = e1.dot(p);
    if det.abs() < 1e-12 {
        return None;
    }
    let s = ray.origin - v[0];
    let u = s.dot(p) / det;
    let q = s.cross(e1);
    let w = ray.dir.dot(q) / det;
    let t = e2.dot(q) / det;
    let inside = u >= 0.0 && w >= 0.0 && u + w <= 1.0 && t > ray.t_min && t < ray.t_max;
    (inside && Aabb::from_points(v).holds_hit(ray, t)).then_some(t)
}

impl Primitives for World {
    type Data = ();
    fn len(&self) -> usize {
        self.shapes.len()
    }
    fn bounds(&self, i: usize) -> Aabb {
        match self.shapes[i].0 {
            Shape::Ball(s) => Aabb::new(s.center - s.radius, s.center + s.radius),
            Shape::Triangle(v) => Aabb::from_points(&v),
        }
    }
    fn intersect(&self, i: usize, ray: &Ray) -> Option<(f32, ())> {
        match &self.shapes[i].0 {
            Shape::Ball(s) => intersect_sphere(s, ray),
            Shape::Triangle(v) => hit_triangle(v, ray),
        }
        .map(|t| (t, ()))
    }
}

/// The renderer's own pinhole camera.
struct Camera {
    from: Vec3,
    corner: Vec3,
    right: Vec3,
    up: Vec3,
}

impl Camera {
    fn new(from: Vec3, at: Vec3, vfov_deg: f32) -> Self {
        let w = (from - at).normalize();
        let u = Vec3::Y.cross(w).normalize();
        let v = w.cross(u);
        let h = (vfov_deg.to_radians() / 2.0).tan();
        let aspect = WIDTH as f32 / HEIGHT as f32;
        Self {
            from,
            corner: -w - u * h * aspect + v * h,
            right: u * 2.0 * h * aspect,
            up: -v * 2.0 * h,
        }
    }
    fn ray(&self, x: f32, y: f32) -> Ray {
        let d = self.corner + self.right * (x / WIDTH as f32) + self.up * (y / HEIGHT as f32);
        Ray::new(self.from, d.normalize())
    }
}

/// One path: the sampler's dimensions per bounce are fixed (two for the
/// direction), so a sample is a pure function of (pixel, index, seed).
fn radiance(bvh: &OwnedPrimitiveBvh<World>, mut ray: Ray, s: &mut Sobol) -> Vec3 {
    let mut weight = Vec3::ONE;
    for _ in 0..DEPTH {
        let Some(hit) = bvh.view().closest_hit(&ray) else {
            let sky = Vec3::new(0.5, 0.7, 1.0).lerp(Vec3::ONE, 0.5 - 0.5 * ray.dir.y);
            return weight * sky;
        };
        let (shape, material) = bvh.primitives().shapes[hit.primitive as usize];
        let p = ray.at(hit.t);
        let (normal, origin) = match shape {
            Shape::Ball(b) => {
                let n = b.unit_normal(p);
                (n, b.spawn_origin_along(n, true))
            }
            Shape::Triangle(v) => {
                let n = (v[1] - v[0]).cross(v[2] - v[0]).normalize();
                let n = if n.dot(ray.dir) > 0.0 { -n } else { n };
                (n, p + n * 1e-4 * (1.0 + p.abs().max_element()))
            }
        };
        let u = s.next_2d();
        match material {
            Material::Light(e) => return weight * e,
            Material::Mirror(albedo) => {
                weight *= albedo;
                ray = Ray::new(origin, ray.dir - 2.0 * ray.dir.dot(normal) * normal);
            }
            Material::Diffuse(albedo) => {
                // Cosine sampling: the weight is the albedo.
                weight *= albedo;
                let d = Onb::from_normal(normal).to_world(sample_cosine_hemisphere(u));
                ray = Ray::new(origin, d.normalize());
            }
        }
    }
    Vec3::ZERO
}

/// Rows `rows` of the image into `film` (one `Vec3` per pixel of those
/// rows): each pixel's samples in index order, so the sums are the same
/// whoever renders the rows.
fn render_rows(
    bvh: &OwnedPrimitiveBvh<World>,
    camera: &Camera,
    rows: core::ops::Range<u32>,
    film: &mut [Vec3],
) {
    let mut sampler = Sobol::new(SPP, 2026).expect("spp > 0");
    for (k, y) in rows.enumerate() {
        for x in 0..WIDTH {
            let mut sum = Vec3::ZERO;
            for index in 0..SPP {
                sampler.start_pixel_sample(UVec2::new(x, y), index);
                let o = sampler.pixel_2d();
                let ray = camera.ray(x as f32 + o.x, y as f32 + o.y);
                sum += radiance(bvh, ray, &mut sampler);
            }
            film[k * WIDTH as usize + x as usize] = sum / SPP as f32;
        }
    }
}

fn main() -> Result<(), Box<dyn std::error::Error>> {
    let out = std::env::args()
        .nth(1)
        .unwrap_or_else(|| "own_renderer.ppm".into());
    let mut world = World { shapes: Vec::new() };
    let floor = Material::Diffuse(Vec3::splat(0.6));
    let (a, b, c, d) = (
        Vec3::new(-20.0, 0.0, -20.0),
        Vec3::new(20.0, 0.0, -20.0),
        Vec3::new(20.0, 0.0, 20.0),
        Vec3::new(-20.0, 0.0, 20.0),
    );
    world.shapes.push((Shape::Triangle([a, c, b]), floor));
    world.shapes.push((Shape::Triangle([a, d, c]), floor));
    world.add_box(
        Vec3::new(0.6, 0.0, -1.6),
        Vec3::new(1.6, 1.2, -0.6),
        Material::Diffuse(Vec3::new(0.2, 0.3, 0.8)),
    );
    let red = Material::Diffuse(Vec3::new(0.8, 0.1, 0.1));
    world.shapes.push((
        Shape::Ball(Sphere::new(Vec3::new(-1.2, 0.7, -1.0), 0.7)),
        red,
    ));
    let mirror = Material::Mirror(Vec3::splat(0.9));
    world.shapes.push((
        Shape::Ball(Sphere::new(Vec3::new(0.1, 0.4, 0.3), 0.4)),
        mirror,
    ));
    let lamp = Material::Light(Vec3::splat(6.0));
    world.shapes.push((
        Shape::Ball(Sphere::new(Vec3::new(0.0, 4.0, 0.0), 0.8)),
        lamp,
    ));

    let red_ball = world.shapes.len() as u32 - 3;

    // The tree owns the shapes; the renderer reads them through it.
    let bvh = OwnedPrimitiveBvh::build(world)?;

    // Through every pixel centre, the tree finds what testing every shape
    // finds; the red sphere's pixels are noted.
    let camera = Camera::new(Vec3::new(0.0, 1.5, 5.0), Vec3::new(0.0, 0.5, -0.5), 40.0);
    let mut red_pixels = Vec::new();
    for i in 0..WIDTH * HEIGHT {
        let ray = camera.ray((i % WIDTH) as f32 + 0.5, (i / WIDTH) as f32 + 0.5);
        let hit = bvh.view().closest_hit(&ray);
        assert_eq!(
            hit,
            strata::trace::closest_primitive_hit(bvh.primitives(), &ray)
        );
        if hit.is_some_and(|h| h.primitive == red_ball) {
            red_pixels.push(i as usize);
        }
    }

    // Rendered on one thread, then on two (rows split unevenly): the same
    // bits.
    let pixels = (WIDTH * HEIGHT) as usize;
    let mut one = vec![Vec3::ZERO; pixels];
    render_rows(&bvh, &camera, 0..HEIGHT, &mut one);
    let mut two = vec![Vec3::ZERO; pixels];
    let (top, bottom) = two.split_at_mut(37 * WIDTH as usize);
    std::thread::scope(|s| {
        s.spawn(|| render_rows(&bvh, &camera, 0..37, top));
        s.spawn(|| render_rows(&bvh, &camera, 37..HEIGHT, bottom));
    });
    let bits = |f: &[Vec3]| {
        f.iter()
            .flat_map(|v| v.to_array().map(f32::to_bits))
            .collect::<Vec<_>>()
    };
    assert_eq!(
        bits(&one),
        bits(&two),
        "the image depends on the thread split"
    );

    // Plausible: lit, and the red sphere's pixels red.
    let mean = one.iter().sum::<Vec3>() / pixels as f32;
    assert!(
        mean.min_element() > 0.1 && mean.max_element() < 2.0,
        "mean {mean}"
    );
    assert!(
        red_pixels.len() > 100,
        "{} red-sphere pixels",
        red_pixels.len()
    );
    let ball = red_pixels.iter().map(|&i| one[i]).sum::<Vec3>() / red_pixels.len() as f32;
    assert!(
        ball.x > 2.0 * ball.y && ball.x > 2.0 * ball.z,
        "red sphere {ball}"
    );

    let mut ppm = format!("P3\n{WIDTH} {HEIGHT}\n255\n");
    for v in &one {
        let g = |c: f32| (255.0 * c.clamp(0.0, 1.0).powf(1.0 / 2.2)).round() as u8;
        ppm += &format!("{} {} {}\n", g(v.x), g(v.y), g(v.z));
    }
    std::fs::write(&out, ppm)?;
    println!("wrote {out}: {WIDTH}x{HEIGHT}, {SPP} spp, mean {mean:.3}");
    Ok(())
}
