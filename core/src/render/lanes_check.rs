//! The lane forms of shading give, lane by lane, the bits of their
//! one-lane forms (which the scalar integrator runs): every material's
//! sampling, evaluation and BRDF, the camera ray, the surface record, the
//! footprint, the light density, the background and next-event
//! estimation with its eight-ray shadow query. Inputs are random and
//! include the awkward cases (directions below the surface, grazing
//! rays, zero and huge footprints, dead lanes).

// Lane k indexes several arrays at once here.
#![allow(clippy::needless_range_loop)]

use std::vec::Vec;

use glam::{UVec2, Vec2, Vec3};

use super::camera::{Camera, CameraDesc};
use super::integrator::{
    direct_light_lanes, footprint_lanes, light_pdf_lanes, power_heuristic, surface_lanes,
};
use super::material::{BsdfLanes, Material, SurfaceLanes};
use super::scene::{Background, Scene, SceneStorage, SceneStorageSize};
use super::texture::{ImageTexture, Texture};
use crate::lanes::{Lanes, RayLanes, SphereLanes, V3, f32x8, lanes_bitmask, mask_from_bools};
use crate::rng::{Pcg32, STREAM, next_f32};
use crate::trace::{BvhNode8, BvhStack, Ray, Sphere, SphereChunk8};

/// Uniform numbers from a fixed stream.
struct Draw(Pcg32);

impl Draw {
    fn new(seed: u64) -> Self {
        Self(Pcg32::new(seed, STREAM))
    }
    fn f(&mut self) -> f32 {
        next_f32(&mut self.0)
    }
    fn unit(&mut self) -> Vec3 {
        crate::mapping::sample_uniform_sphere(Vec2::new(self.f(), self.f()))
    }
}

fn bits(v: Vec3) -> [u32; 3] {
    v.to_array().map(f32::to_bits)
}

/// Lane `k` of a surface record in lanes, as one lane.
fn lane_of(h: &SurfaceLanes<f32x8>, k: usize) -> SurfaceLanes<f32> {
    SurfaceLanes {
        p: h.p.lane(k).into(),
        n: h.n.lane(k).into(),
        front_face: lanes_bitmask(h.front_face) >> k & 1 == 1,
        uv: (h.uv.0.lane(k), h.uv.1.lane(k)),
        footprint: h.footprint.lane(k).into(),
        wanted: 1,
    }
}

fn v8(f: impl FnMut(usize) -> Vec3) -> V3<f32x8> {
    V3::from_fn(f)
}

fn l8(f: impl FnMut(usize) -> f32) -> f32x8 {
    f32x8::from_fn(f)
}

fn same_sample(a: &BsdfLanes<f32>, b: &BsdfLanes<f32x8>, k: usize, what: &str) {
    assert_eq!(bits(a.wi.into()), bits(b.wi.lane(k)), "{what}: wi");
    assert_eq!(
        bits(a.weight.into()),
        bits(b.weight.lane(k)),
        "{what}: weight"
    );
    assert_eq!(a.pdf.to_bits(), b.pdf.lane(k).to_bits(), "{what}: pdf");
    let flag = |m: f32x8| lanes_bitmask(m) >> k & 1 == 1;
    assert_eq!(a.transmitted, flag(b.transmitted), "{what}: transmitted");
    assert_eq!(a.live, flag(b.live), "{what}: live");
}

#[test]
fn every_material_gives_the_same_bits_in_one_lane_and_eight() {
    let texels: Vec<Vec3> = (0..12)
        .map(|i| Vec3::new(i as f32 / 12.0, 0.5, 1.0 - i as f32 / 12.0))
        .collect();
    let image = Texture::Image(ImageTexture::new(4, 3, &texels).unwrap());
    let checker = Texture::Checker {
        scale: 0.3,
        even: Vec3::new(0.9, 0.8, 0.1),
        odd: Vec3::new(0.1, 0.2, 0.3),
    };
    let solid = Texture::Solid(Vec3::new(0.8, 0.5, 0.3));
    let mut materials = Vec::new();
    for t in [solid, checker, image] {
        materials.extend([
            Material::Lambertian { albedo: t },
            Material::Phong {
                albedo: t,
                kd: 0.5,
                ks: 0.5,
                exponent: 20.0,
            },
            Material::Blinn {
                albedo: t,
                kd: 0.5,
                ks: 0.6,
                exponent: 0.0,
            },
            Material::PhongNormalized {
                albedo: t,
                kd: 0.3,
                ks: 0.6,
                exponent: 3.5,
            },
            Material::BlinnNormalized {
                albedo: t,
                kd: 0.2,
                ks: 0.7,
                exponent: 300.0,
            },
            Material::CookTorrance {
                albedo: t,
                kd: 0.4,
                ks: 0.5,
                alpha: 0.25,
                ior: 1.5,
            },
        ]);
    }
    materials.extend([
        Material::Mirror {
            albedo: Vec3::new(0.9, 0.8, 0.7),
        },
        Material::Metal {
            albedo: Vec3::ONE,
            roughness: 0.0,
        },
        Material::Metal {
            albedo: Vec3::new(0.5, 0.6, 0.7),
            roughness: 0.4,
        },
        Material::Dielectric { ior: 1.5 },
        Material::Dielectric { ior: 0.7 },
        Material::DiffuseLight {
            emit: Vec3::splat(3.0),
        },
    ]);
    let mut r = Draw::new(3);
    let (mut live, mut dead, mut transmitted) = (0, 0, 0);
    for m in &materials {
        m.validate().unwrap();
        for round in 0..300 {
            // Eight hits: unit normals, a direction mostly against the
            // normal (sometimes along it or grazing), footprints from zero
            // to huge.
            let n: [Vec3; 8] = core::array::from_fn(|_| r.unit());
            let d: [Vec3; 8] = core::array::from_fn(|k| {
                let a = r.unit();
                match (round + k) % 4 {
                    0 => (a - n[k] * (a.dot(n[k]) + 1e-7)).normalize(), // grazing
                    1 => a,                                             // either side
                    _ => -(a + n[k] * 1.5).normalize(),                 // against n
                }
            });
            let hit = SurfaceLanes::<f32x8> {
                p: v8(|_| r.unit() * 3.0),
                n: v8(|k| n[k]),
                front_face: mask_from_bools(core::array::from_fn(|k| (round + k) % 3 != 0)),
                uv: (l8(|_| r.f() * 1.2 - 0.1), l8(|_| r.f())),
                footprint: v8(|k| match k % 3 {
                    0 => Vec3::ZERO,
                    1 => Vec3::splat(r.f() * 0.2),
                    _ => Vec3::splat(1e12),
                }),
                // Some rounds read only some lanes (a per-lane texture
                // then skips the others).
                wanted: if round % 4 == 3 { 0b1011_0110 } else { u8::MAX },
            };
            let mut hit = hit;
            let mut d = d;
            let mut wi_lanes: [Vec3; 8] = core::array::from_fn(|_| r.unit());
            // Degenerate lanes among the others: a zero and a NaN normal,
            // a NaN direction, a zero outgoing direction.
            if round % 5 == 0 {
                let mut n = n;
                n[2] = Vec3::ZERO;
                n[5] = Vec3::NAN;
                hit.n = v8(|k| n[k]);
                d[1] = Vec3::new(f32::NAN, 0.0, -1.0);
                wi_lanes[6] = Vec3::ZERO;
            }
            let d8 = v8(|k| d[k]);
            let u = (l8(|_| r.f()), l8(|_| r.f()));
            let u_lobe = l8(|_| r.f());
            let wi = v8(|k| wi_lanes[k]);
            let s8 = m.sample_lanes(d8, &hit, u, u_lobe);
            let (f8, pdf8) = m.eval_lanes(d8, &hit, wi);
            let b8 = m.brdf_lanes(d8, &hit, wi);
            for k in (0..8).filter(|k| hit.wanted >> k & 1 == 1) {
                let h1 = lane_of(&hit, k);
                let d1: V3<f32> = d[k].into();
                let s1 = m.sample_lanes(d1, &h1, (u.0.lane(k), u.1.lane(k)), u_lobe.lane(k));
                let what = std::format!("{m:?}, round {round}, lane {k}");
                same_sample(&s1, &s8, k, &what);
                let wi1: V3<f32> = wi.lane(k).into();
                let (f1, pdf1) = m.eval_lanes(d1, &h1, wi1);
                assert_eq!(bits(f1.into()), bits(f8.lane(k)), "{what}: f cos");
                assert_eq!(pdf1.to_bits(), pdf8.lane(k).to_bits(), "{what}: pdf");
                let b1 = m.brdf_lanes(d1, &h1, wi1);
                assert_eq!(bits(b1.into()), bits(b8.lane(k)), "{what}: brdf");
                if s1.live {
                    live += 1;
                } else {
                    dead += 1;
                }
                transmitted += u32::from(s1.transmitted);
            }
        }
    }
    // Every outcome was reached.
    assert!(
        live > 10_000 && dead > 2_400 && transmitted > 500,
        "{live} {dead} {transmitted}"
    );
}

/// Spheres for the scene checks: a ground, two lights, and shapes around
/// the origin.
fn spheres() -> [Sphere; 12] {
    let mut r = Draw::new(17);
    core::array::from_fn(|i| match i {
        0 => Sphere::new(Vec3::new(0.0, -1000.0, 0.0), 1000.0),
        1 => Sphere::new(Vec3::new(2.0, 4.0, -1.0), 0.8),
        2 => Sphere::new(Vec3::new(-3.0, 3.0, 2.0), 0.3),
        _ => Sphere::new(
            Vec3::new(r.f() * 8.0 - 4.0, r.f() * 1.5 + 0.2, r.f() * 8.0 - 4.0),
            0.2 + r.f() * 0.6,
        ),
    })
}

#[test]
fn camera_surface_and_direct_light_give_the_same_bits_in_one_lane_and_eight() {
    let s = spheres();
    let materials = [
        Material::Lambertian {
            albedo: Texture::Checker {
                scale: 0.5,
                even: Vec3::splat(0.8),
                odd: Vec3::splat(0.2),
            },
        },
        Material::DiffuseLight {
            emit: Vec3::new(4.0, 3.5, 3.0),
        },
        Material::Blinn {
            albedo: Texture::Solid(Vec3::new(0.7, 0.3, 0.2)),
            kd: 0.6,
            ks: 0.4,
            exponent: 30.0,
        },
        Material::CookTorrance {
            albedo: Texture::Solid(Vec3::splat(0.5)),
            kd: 0.3,
            ks: 0.6,
            alpha: 0.2,
            ior: 1.6,
        },
        Material::Dielectric { ior: 1.5 },
    ];
    let sphere_material: [u32; 12] =
        core::array::from_fn(|i| [0, 1, 1, 2, 3, 4, 2, 0, 3, 2, 4, 2][i]);
    const SIZE: SceneStorageSize = SceneStorageSize::for_spheres(12, true);
    let bvh_size = SIZE.bvh.unwrap();
    let mut chunks = [SphereChunk8::EMPTY; SIZE.chunks];
    let mut lights = [0u32; SIZE.lights];
    let mut nodes = std::vec![BvhNode8::EMPTY; bvh_size.nodes];
    let mut lanes = std::vec![0.0f32; bvh_size.lanes];
    let mut ids = std::vec![0u32; bvh_size.ids];
    let storage = SceneStorage {
        chunks: &mut chunks,
        lights: &mut lights,
        bvh_nodes: &mut nodes,
        bvh_lanes: &mut lanes,
        bvh_ids: &mut ids,
    };
    let scene = Scene::build(&s, &materials, &sphere_material, Background::Sky, storage).unwrap();
    assert!(scene.has_bvh() && scene.lights().len() == 2);
    let desc = |defocus: f32| CameraDesc {
        // Looking down, so most rays hit something.
        look_from: Vec3::new(0.0, 7.0, 7.0),
        look_at: Vec3::new(0.0, 0.0, 0.0),
        up: Vec3::Y,
        vfov_deg: 40.0,
        defocus_angle_deg: defocus,
        focus_dist: 9.0,
    };
    let mut stack = BvhStack::new();
    let mut r = Draw::new(29);
    let (mut traced_total, mut lit) = (0u32, 0u32);
    for (c, defocus) in [0.0f32, 1.5].into_iter().enumerate() {
        let camera = Camera::new(&desc(defocus), 64, 36).unwrap();
        for round in 0..400 {
            let px: [UVec2; 8] =
                core::array::from_fn(|_| UVec2::new((r.f() * 64.0) as u32, (r.f() * 36.0) as u32));
            let offset = (l8(|_| r.f()), l8(|_| r.f()));
            let lens = (l8(|_| r.f()), l8(|_| r.f()));
            let pixel = (l8(|k| px[k].x as f32), l8(|k| px[k].y as f32));
            let (o8, dir8) = camera.ray_lanes(pixel, offset, lens);
            let rays: [Ray; 8] = core::array::from_fn(|k| {
                let one = camera.ray(
                    px[k],
                    Vec2::new(offset.0.lane(k), offset.1.lane(k)),
                    Vec2::new(lens.0.lane(k), lens.1.lane(k)),
                );
                assert_eq!(bits(one.origin), bits(o8.lane(k)), "camera {c} origin");
                assert_eq!(bits(one.dir), bits(dir8.lane(k)), "camera {c} dir");
                one
            });
            let bg = scene.background().radiance_lanes(dir8);
            for (k, ray) in rays.iter().enumerate() {
                let want = scene.background().radiance(ray.dir);
                assert_eq!(bits(want), bits(bg.lane(k)));
            }
            // Every lane's first hit (the ground catches most rays).
            let hits: [_; 8] = core::array::from_fn(|k| scene.closest_hit(&rays[k]));
            if hits.iter().any(Option::is_none) {
                continue;
            }
            let hit = |k: usize| hits[k].unwrap();
            let sphere = SphereLanes {
                center: v8(|k| s[hit(k).sphere as usize].center),
                radius: l8(|k| s[hit(k).sphere as usize].radius),
            };
            let ray8 = RayLanes {
                origin: o8,
                dir: dir8,
                t_min: f32x8::splat(0.0),
                t_max: f32x8::splat(f32::INFINITY),
            };
            let uses_uv = round % 2 == 0;
            let t8 = l8(|k| hit(k).t);
            let mut surf8 = surface_lanes(&ray8, t8, &sphere, uses_uv);
            let diff8 = [
                (o8, dir8 + V3::splat(Vec3::new(0.01, 0.0, 0.0))),
                (o8, dir8),
            ];
            surf8.footprint = footprint_lanes(&surf8, &diff8);
            // The material every lane shades with, and the live lanes.
            let material = &materials[[0, 2, 3][round % 3]];
            let live_bits: [bool; 8] = core::array::from_fn(|k| (round * 7 + k) % 5 != 0);
            let u_choice = l8(|_| r.f());
            let u_dir = (l8(|_| r.f()), l8(|_| r.f()));
            let (l8v, traced8) = direct_light_lanes(
                &scene,
                &mut stack,
                material,
                dir8,
                &surf8,
                &sphere,
                (u_choice, u_dir),
                mask_from_bools(live_bits),
            );
            let light = SphereLanes {
                center: v8(|k| s[1 + k % 2].center),
                radius: l8(|k| s[1 + k % 2].radius),
            };
            let pdf8 = light_pdf_lanes(&scene, surf8.p, &light);
            let mut traced1 = 0;
            for k in 0..8 {
                let ray1 = RayLanes {
                    origin: o8.lane(k).into(),
                    dir: dir8.lane(k).into(),
                    t_min: 0.0,
                    t_max: f32::INFINITY,
                };
                let sphere1 = SphereLanes {
                    center: sphere.center.lane(k).into(),
                    radius: sphere.radius.lane(k),
                };
                let mut surf1 = surface_lanes(&ray1, hit(k).t, &sphere1, uses_uv);
                let diff1 = [
                    (ray1.origin, diff8[0].1.lane(k).into()),
                    (ray1.origin, ray1.dir),
                ];
                surf1.footprint = footprint_lanes(&surf1, &diff1);
                let same = lane_of(&surf8, k);
                assert_eq!(bits(surf1.p.into()), bits(same.p.into()));
                assert_eq!(bits(surf1.n.into()), bits(same.n.into()));
                assert_eq!(surf1.front_face, same.front_face);
                assert_eq!(
                    (surf1.uv.0.to_bits(), surf1.uv.1.to_bits()),
                    (same.uv.0.to_bits(), same.uv.1.to_bits())
                );
                assert_eq!(bits(surf1.footprint.into()), bits(same.footprint.into()));
                let (l1, t1) = direct_light_lanes(
                    &scene,
                    &mut stack,
                    material,
                    ray1.dir,
                    &surf1,
                    &sphere1,
                    (u_choice.lane(k), (u_dir.0.lane(k), u_dir.1.lane(k))),
                    live_bits[k],
                );
                assert_eq!(
                    bits(l1.into()),
                    bits(l8v.lane(k)),
                    "round {round}, lane {k}"
                );
                traced1 += u32::from(t1);
                lit += u32::from(Vec3::from(l1) != Vec3::ZERO);
                let light1 = SphereLanes {
                    center: light.center.lane(k).into(),
                    radius: light.radius.lane(k),
                };
                let pdf1 = light_pdf_lanes(&scene, surf1.p, &light1);
                assert_eq!(pdf1.to_bits(), pdf8.lane(k).to_bits());
                let (a, b) = (r.f(), r.f() * 2.0);
                let h8 = power_heuristic(f32x8::splat(a), f32x8::splat(b)).lane(0);
                assert_eq!(power_heuristic(a, b).to_bits(), h8.to_bits());
            }
            assert_eq!(
                traced1,
                lanes_bitmask(traced8).count_ones(),
                "round {round}: shadow rays"
            );
            traced_total += lanes_bitmask(traced8).count_ones();
        }
    }
    // Shadow rays were traced, some lanes lit and some not.
    assert!(traced_total > 1000 && lit > 500, "{traced_total} {lit}");
}

/// Degenerate vertices beside ordinary ones: a point inside a light (no
/// cone), a point at its sphere's centre (the normal is 0/0), a point
/// 10⁻²⁰ from it (the scaled normal), huge coordinates, and dead lanes.
#[test]
fn degenerate_vertices_give_the_same_bits_in_one_lane_and_eight() {
    let s = spheres();
    let materials = [
        Material::Lambertian {
            albedo: Texture::Solid(Vec3::splat(0.6)),
        },
        Material::DiffuseLight {
            emit: Vec3::splat(2.0),
        },
    ];
    let sphere_material: [u32; 12] = core::array::from_fn(|i| u32::from(i == 1 || i == 2));
    const SIZE: SceneStorageSize = SceneStorageSize::for_spheres(12, false);
    let mut chunks = [SphereChunk8::EMPTY; SIZE.chunks];
    let mut lights = [0u32; SIZE.lights];
    let storage = SceneStorage {
        chunks: &mut chunks,
        lights: &mut lights,
        bvh_nodes: &mut [],
        bvh_lanes: &mut [],
        bvh_ids: &mut [],
    };
    let scene = Scene::build(&s, &materials, &sphere_material, Background::Sky, storage).unwrap();
    let mut stack = BvhStack::new();
    let mut r = Draw::new(41);
    let mut seen_nan = false;
    for round in 0..200 {
        // Lane k's ray starts at `origin[k]` and is taken at `t[k]`.
        let target: [usize; 8] = core::array::from_fn(|k| (round + k) % 12);
        let origin: [Vec3; 8] = core::array::from_fn(|k| match k {
            0 => s[1].center,             // inside a light
            1 | 2 => s[target[k]].center, // at a centre
            3 => Vec3::splat(1e20),       // huge
            _ => s[target[k]].center + r.unit() * 30.0,
        });
        let dir: [Vec3; 8] = core::array::from_fn(|k| {
            (s[target[k]].center - origin[k] + r.unit() * 0.1).normalize_or(Vec3::Y)
        });
        let t: [f32; 8] = core::array::from_fn(|k| match k {
            0 | 1 => 0.0,
            2 => 1e-20,
            _ => (s[target[k]].center - origin[k]).length() - s[target[k]].radius,
        });
        let ray8 = RayLanes {
            origin: v8(|k| origin[k]),
            dir: v8(|k| dir[k]),
            t_min: f32x8::splat(0.0),
            t_max: f32x8::splat(f32::INFINITY),
        };
        let sphere = SphereLanes {
            center: v8(|k| s[target[k]].center),
            radius: l8(|k| s[target[k]].radius),
        };
        let surf8 = surface_lanes(&ray8, l8(|k| t[k]), &sphere, true);
        let live: [bool; 8] = core::array::from_fn(|k| (round + k) % 4 != 3);
        let u = (l8(|_| r.f()), (l8(|_| r.f()), l8(|_| r.f())));
        let (l8v, traced8) = direct_light_lanes(
            &scene,
            &mut stack,
            &materials[0],
            ray8.dir,
            &surf8,
            &sphere,
            u,
            mask_from_bools(live),
        );
        let mut traced1 = 0;
        for k in 0..8 {
            let ray1 = RayLanes {
                origin: origin[k].into(),
                dir: dir[k].into(),
                t_min: 0.0,
                t_max: f32::INFINITY,
            };
            let sphere1 = SphereLanes {
                center: s[target[k]].center.into(),
                radius: s[target[k]].radius,
            };
            let surf1 = surface_lanes(&ray1, t[k], &sphere1, true);
            let same = lane_of(&surf8, k);
            assert_eq!(
                bits(surf1.n.into()),
                bits(same.n.into()),
                "round {round} lane {k}"
            );
            assert_eq!(bits(surf1.p.into()), bits(same.p.into()));
            assert_eq!(
                (surf1.uv.0.to_bits(), surf1.uv.1.to_bits()),
                (same.uv.0.to_bits(), same.uv.1.to_bits())
            );
            seen_nan |= Vec3::from(surf1.n).is_nan();
            let (l1, t1) = direct_light_lanes(
                &scene,
                &mut stack,
                &materials[0],
                ray1.dir,
                &surf1,
                &sphere1,
                (u.0.lane(k), (u.1.0.lane(k), u.1.1.lane(k))),
                live[k],
            );
            assert_eq!(bits(l1.into()), bits(l8v.lane(k)), "round {round} lane {k}");
            traced1 += u32::from(t1);
        }
        assert_eq!(
            traced1,
            lanes_bitmask(traced8).count_ones(),
            "round {round}"
        );
    }
    assert!(seen_nan, "no lane reached the 0/0 normal");
}
