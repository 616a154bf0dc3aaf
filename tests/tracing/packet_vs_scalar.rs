//! The 1×8 and packet kernels against the scalar reference: same sphere
//! index and bit-identical `t` on over 10⁶ seeded random rays against
//! random sphere sets, with inputs weighted toward the hard cases (rays
//! from inside, on the surface, tangent, aimed at centres; zero, negative,
//! NaN, tiny and huge radii; NaN and huge coordinates; empty and NaN
//! ranges; duplicate spheres for ties). Also: inactive lanes untouched, a
//! NaN lane never poisons the others, any-hit equality.

use glam::Vec3;
use rand_core::Rng;
use strata::mapping::sample_uniform_sphere;
use strata::rng::{Pcg32, STREAM, next_f32};
use strata::trace::*;

struct Fuzz(Pcg32);

impl Fuzz {
    fn f(&mut self) -> f32 {
        next_f32(&mut self.0)
    }
    fn pick(&mut self, n: u32) -> u32 {
        self.0.next_u32() % n
    }
    fn range(&mut self, lo: f32, hi: f32) -> f32 {
        lo + (hi - lo) * self.f()
    }
    fn unit(&mut self) -> Vec3 {
        let u = glam::Vec2::new(self.f(), self.f());
        sample_uniform_sphere(u).normalize()
    }
    fn point(&mut self, scale: f32) -> Vec3 {
        Vec3::new(
            self.range(-scale, scale),
            self.range(-scale, scale),
            self.range(-scale, scale),
        )
    }

    fn sphere(&mut self) -> Sphere {
        let center = match self.pick(10) {
            0 => Vec3::ZERO,
            1 => Vec3::new(0.0, -100.5, -1.0),
            2 => self.point(1e4),
            _ => self.point(10.0),
        };
        let radius = match self.pick(20) {
            0 => 0.0,
            1 => -0.5,
            2 => f32::NAN,
            3 => 1e-6,
            4 => 1000.0,
            5 => 100.0,
            _ => self.range(0.05, 3.0),
        };
        Sphere::new(center, radius)
    }

    fn ray(&mut self, spheres: &[Sphere]) -> Ray {
        let s = spheres[self.pick(spheres.len() as u32) as usize];
        let r = if s.radius.is_finite() {
            s.radius.abs()
        } else {
            1.0
        };
        let dir = self.unit();
        let origin = match self.pick(10) {
            // Inside a sphere.
            0 => s.center + self.unit() * (r * self.f()),
            // On its surface (as rounded).
            1 => s.center + self.unit() * r,
            // Tangent: offset perpendicular to the direction by r.
            2 => {
                let side = dir.any_orthonormal_vector();
                s.center + side * r - dir * self.range(1.0, 20.0)
            }
            // Aimed at a centre.
            3 => {
                let o = self.point(20.0);
                return Ray::new(o, (s.center - o).normalize());
            }
            4 => self.point(1e5),
            _ => self.point(15.0),
        };
        let ray = Ray::new(origin, dir);
        match self.pick(12) {
            0 => ray.with_range(1e-3, 5.0),
            1 => ray.with_range(5.0, 1.0),
            2 => ray.with_range(f32::NAN, f32::INFINITY),
            3 => Ray {
                origin: Vec3::new(f32::NAN, 0.0, 0.0),
                ..ray
            },
            4 => Ray {
                dir: Vec3::ZERO,
                ..ray
            },
            5 => ray.with_range(-f32::INFINITY, f32::INFINITY),
            _ => ray,
        }
    }

    fn scene(&mut self) -> Vec<Sphere> {
        let n = 1 + self.pick(24) as usize;
        let mut v: Vec<Sphere> = (0..n).map(|_| self.sphere()).collect();
        if self.pick(4) == 0 {
            // A duplicate: equal t, the lower index must win everywhere.
            let k = self.pick(n as u32) as usize;
            v.push(v[k]);
        }
        v
    }
}

fn key(h: Option<Hit>) -> Option<(u32, u32)> {
    h.map(|h| (h.sphere, h.t.to_bits()))
}

#[test]
fn kernels_match_scalar_on_a_million_rays() {
    let mut fz = Fuzz(Pcg32::new(3, STREAM));
    let mut rays_done = 0usize;
    let mut hits = 0usize;
    let mut storage = vec![SphereChunk8::EMPTY; 8];
    while rays_done < 1_048_576 {
        let spheres = fz.scene();
        let set = SphereSet::build(&spheres, &mut storage).unwrap();
        for _ in 0..64 {
            let rays: Vec<Ray> = (0..8).map(|_| fz.ray(&spheres)).collect();
            let packet = RayPacket8::from_rays(&rays);
            let mut packet_hits = HitPacket8::NONE;
            closest_hit_x8(&set, &packet, &mut packet_hits);
            let occluded = any_hit_x8(&set, &packet);
            for (lane, ray) in rays.iter().enumerate() {
                let want = closest_hit(&spheres, ray);
                let ctx = || format!("ray {ray:?}\nspheres {spheres:?}");
                assert_eq!(key(closest_hit_1x8(&set, ray)), key(want), "1x8\n{}", ctx());
                assert_eq!(key(packet_hits.hit(lane)), key(want), "packet\n{}", ctx());
                let any = any_hit(&spheres, ray);
                assert_eq!(any, want.is_some(), "any_hit vs closest\n{}", ctx());
                assert_eq!(any_hit_1x8(&set, ray), any, "any 1x8\n{}", ctx());
                assert_eq!(occluded >> lane & 1 == 1, any, "any packet\n{}", ctx());
                hits += want.is_some() as usize;
            }
            rays_done += 8;
        }
    }
    // The fuzz must exercise hits and misses alike.
    let frac = hits as f64 / rays_done as f64;
    assert!((0.2..0.8).contains(&frac), "hit fraction {frac}");
}

#[test]
fn inactive_lanes_are_untouched() {
    let spheres = [Sphere::new(Vec3::new(0.0, 0.0, -3.0), 1.0)];
    let mut storage = [SphereChunk8::EMPTY];
    let set = SphereSet::build(&spheres, &mut storage).unwrap();
    // Eight rays that all hit; only the first three lanes are active.
    let rays = [Ray::new(Vec3::ZERO, -Vec3::Z); 8];
    let packet = RayPacket8::from_rays(&rays).with_active_bits(0b111);
    assert_eq!(packet.active_bits(), 0b111);
    let sentinel_t = [9.0, 9.0, 9.0, 7.0, 6.0, 5.0, 4.0, 3.0];
    let sentinel_i = [-1, -1, -1, 40, 41, 42, 43, 44];
    let mut hits = HitPacket8::new(sentinel_t, sentinel_i);
    closest_hit_x8(&set, &packet, &mut hits);
    let (t, i) = (hits.t(), hits.spheres());
    assert_eq!(&t[..3], &[2.0; 3]);
    assert_eq!(&i[..3], &[0; 3]);
    assert_eq!(&t[3..], &sentinel_t[3..]);
    assert_eq!(&i[3..], &sentinel_i[3..]);
    assert_eq!(any_hit_x8(&set, &packet), 0b111);
    // An all-inactive packet does nothing.
    assert_eq!(any_hit_x8(&set, &RayPacket8::from_rays(&[])), 0);
}

#[test]
fn a_nan_lane_does_not_poison_the_others() {
    let spheres = [Sphere::new(Vec3::new(0.0, 0.0, -3.0), 1.0)];
    let mut storage = [SphereChunk8::EMPTY];
    let set = SphereSet::build(&spheres, &mut storage).unwrap();
    let good = Ray::new(Vec3::ZERO, -Vec3::Z);
    let bad = [
        Ray::new(Vec3::new(f32::NAN, 0.0, 0.0), -Vec3::Z),
        Ray::new(Vec3::ZERO, Vec3::new(0.0, f32::NAN, -1.0)),
        good.with_range(f32::NAN, 10.0),
        good.with_range(0.0, f32::NAN),
    ];
    for b in bad {
        let rays = [good, b, good, b, good, good, b, good];
        let packet = RayPacket8::from_rays(&rays);
        let mut hits = HitPacket8::NONE;
        closest_hit_x8(&set, &packet, &mut hits);
        let occluded = any_hit_x8(&set, &packet);
        for (lane, r) in rays.iter().enumerate() {
            if *r == good {
                assert_eq!(hits.hit(lane), Some(Hit { t: 2.0, sphere: 0 }), "{b:?}");
                assert_eq!(occluded >> lane & 1, 1);
            } else {
                assert_eq!(hits.hit(lane), None, "{b:?}");
                assert_eq!(occluded >> lane & 1, 0);
            }
        }
    }
}
