//! The fixed workloads that both `strata bench` and the criterion benches
//! run: camera rays and incoherent rays on the built-in scenes' sphere
//! layouts (`crate::scenes`), and a 10 000-sphere layout of their own, all
//! generated from fixed seeds so every run traces the same rays.

use glam::{Vec2, Vec3};
use strata::mapping::sample_uniform_sphere;
use strata::rng::{Pcg32, next_f32};
use strata::trace::{Aabb, Primitives, Ray, Sphere, intersect_sphere};

use crate::scenes::{COURSE_VIEW, COVER_VIEW, View, course_spheres, cover_spheres};

/// Unit-direction camera rays through the pixel centres of a `width ×
/// height` image, in raster order (rows top to bottom), with `up = +y`.
#[must_use]
pub fn camera_rays(view: View, width: u32, height: u32) -> Vec<Ray> {
    let w = (view.from - view.at).normalize();
    let u = Vec3::Y.cross(w).normalize();
    let v = w.cross(u);
    let half_h = (view.vfov.to_radians() * 0.5).tan();
    let half_w = half_h * width as f32 / height as f32;
    let mut rays = Vec::with_capacity((width * height) as usize);
    for y in 0..height {
        for x in 0..width {
            let p = Vec2::new(
                (x as f32 + 0.5) / width as f32,
                (y as f32 + 0.5) / height as f32,
            );
            let d = u * ((2.0 * p.x - 1.0) * half_w) + v * ((1.0 - 2.0 * p.y) * half_h) - w;
            rays.push(Ray::new(view.from, d.normalize()));
        }
    }
    rays
}

/// `n` incoherent rays: origins uniform in the box `[lo, hi]`, directions
/// uniform on the sphere, from a PCG32 with `seed`.
#[must_use]
pub fn random_rays(n: usize, lo: Vec3, hi: Vec3, seed: u64) -> Vec<Ray> {
    let mut rng = Pcg32::new(seed, strata::rng::STREAM);
    (0..n)
        .map(|_| {
            let t = Vec3::new(next_f32(&mut rng), next_f32(&mut rng), next_f32(&mut rng));
            let o = lo + (hi - lo) * t;
            let d = sample_uniform_sphere(Vec2::new(next_f32(&mut rng), next_f32(&mut rng)));
            Ray::new(o, d.normalize())
        })
        .collect()
}

/// The 10 000-sphere scene of the BVH benchmarks: centres uniform in
/// `[-20, 20]³`, radii uniform in `[0.05, 0.35]` (PCG32 seeded 10 000 on
/// the default stream; overlaps allowed).
#[must_use]
pub fn random_spheres_10k() -> Vec<Sphere> {
    let mut rng = Pcg32::new(10_000, strata::rng::STREAM);
    (0..10_000)
        .map(|_| {
            let mut f = || next_f32(&mut rng);
            let c = Vec3::new(f(), f(), f()) * 40.0 - Vec3::splat(20.0);
            Sphere::new(c, 0.05 + 0.3 * f())
        })
        .collect()
}

/// The box incoherent rays start in for a scene: around the course's
/// spheres, or the cover's `[−11, 11] × [0, 2] × [−11, 11]`.
#[must_use]
pub fn ray_box(cover: bool) -> (Vec3, Vec3) {
    if cover {
        (Vec3::new(-11.0, 0.0, -11.0), Vec3::new(11.0, 2.0, 11.0))
    } else {
        (Vec3::new(-2.0, -0.5, -2.0), Vec3::new(2.0, 1.0, 1.0))
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn camera_rays_are_unit_and_centred() {
        let rays = camera_rays(COURSE_VIEW, 320, 180);
        assert_eq!(rays.len(), 320 * 180);
        assert!(rays.iter().all(|r| (r.dir.length() - 1.0).abs() < 1e-6));
        // The image centre looks at the target.
        let mid = camera_rays(COURSE_VIEW, 1, 1)[0];
        let want = (COURSE_VIEW.at - COURSE_VIEW.from).normalize();
        assert!((mid.dir - want).length() < 1e-6);
        // Row 0 is the top of the image.
        assert!(rays[0].dir.y > rays[rays.len() - 1].dir.y);
    }

    #[test]
    fn random_rays_fill_their_box() {
        let (lo, hi) = ray_box(true);
        let rays = random_rays(10_000, lo, hi, 1);
        assert!(
            rays.iter()
                .all(|r| r.origin.cmpge(lo).all() && r.origin.cmple(hi).all())
        );
        let mean = rays.iter().map(|r| r.dir).sum::<Vec3>() / rays.len() as f32;
        assert!(mean.length() < 0.05, "{mean}");
    }
}

/// Spheres as a caller's own primitives (their boxes, the sphere kernel
/// as the routine): what the BVH over the caller's primitives costs
/// against the sphere BVH on the same geometry.
#[derive(Clone, Copy, Debug)]
pub struct SpheresAsPrimitives<'a>(pub &'a [Sphere]);

impl Primitives for SpheresAsPrimitives<'_> {
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

/// A tracing workload: spheres, rays to trace, and a point light for
/// shadow rays.
#[derive(Clone, Debug)]
pub struct TraceWorkload {
    /// Name, `course_camera` etc.
    pub name: &'static str,
    /// The spheres.
    pub spheres: Vec<Sphere>,
    /// Closest-hit rays.
    pub rays: Vec<Ray>,
    /// A point light the shadow rays aim at.
    pub light: Vec3,
}

/// The four tracing workloads every benchmark uses: camera rays (coherent,
/// course 320 × 180, cover 160 × 90) and incoherent random rays (course
/// 65 536, cover 16 384, seed 11) on the course and cover layouts.
#[must_use]
pub fn trace_workloads() -> Vec<TraceWorkload> {
    let light = |cover: bool| {
        if cover {
            Vec3::new(2.0, 8.0, 3.0)
        } else {
            Vec3::new(-1.0, 3.0, 1.0)
        }
    };
    let camera = |name, spheres, view: View, (w, h), cover| TraceWorkload {
        name,
        spheres,
        rays: camera_rays(view, w, h),
        light: light(cover),
    };
    let random = |name, spheres, n, cover| {
        let (lo, hi) = ray_box(cover);
        TraceWorkload {
            name,
            spheres,
            rays: random_rays(n, lo, hi, 11),
            light: light(cover),
        }
    };
    vec![
        camera(
            "course_camera",
            course_spheres(),
            COURSE_VIEW,
            (320, 180),
            false,
        ),
        random("course_random", course_spheres(), 65_536, false),
        camera("cover_camera", cover_spheres(), COVER_VIEW, (160, 90), true),
        random("cover_random", cover_spheres(), 16_384, true),
    ]
}

/// For every ray that hits, a shadow ray from its hit point (spawned on the
/// side it arrived from) to `light`, open at both ends: what direct
/// lighting traces.
#[must_use]
pub fn shadow_rays(spheres: &[Sphere], rays: &[Ray], light: Vec3) -> Vec<Ray> {
    rays.iter()
        .filter_map(|r| {
            let h = strata::trace::closest_hit(spheres, r)?;
            let s = spheres[h.sphere as usize];
            let p = r.at(h.t);
            let outside = r.dir.dot(p - s.center) < 0.0;
            let o = s.spawn_origin(p, outside);
            let to = light - o;
            let d = to.length();
            Some(Ray::new(o, to / d).with_range(0.0, d))
        })
        .collect()
}

/// One pixel sample as a depth-2 path consumes a sampler: start, pixel 2D,
/// then 2D + 1D + 1D + 2D per bounce, over a `16 × 16` pixel block at
/// `spp` samples. Returns a checksum so the work cannot be optimised away.
pub fn sampler_pattern<S: strata::Sampler>(s: &mut S, spp: u32) -> f32 {
    let mut acc = 0.0;
    for y in 0..16 {
        for x in 0..16 {
            for i in 0..spp {
                s.start_pixel_sample(glam::UVec2::new(x, y), i);
                acc += s.pixel_2d().x;
                for _ in 0..2 {
                    acc += s.next_2d().y + s.next_1d() + s.next_1d() + s.next_2d().x;
                }
            }
        }
    }
    acc
}
