//! # Strata: a deterministic sampling core for ray tracers
//!
//! Strata is the sampling and tracing core of a renderer, small enough to
//! link into any of them, firmware included: `no_std`, no allocation, no
//! `unsafe`. Every function takes values or slices and writes into buffers
//! the caller owns.
//!
//! ## The contract
//!
//! A pixel sample is a pure function of (scene, camera, sampler kind, seed,
//! pixel, sample index). Strata turns those numbers into values with no
//! global state and no dependence on thread count, tile size or order, or
//! how the samples of a pixel were split into runs:
//!
//! - every pixel sample gets a fresh PCG32 whose state is a documented hash
//!   of `(seed, px, py, index)` ([`rng`]); nothing advances a shared
//!   generator;
//! - dimensions are consumed in a fixed order ([`sampler`]);
//! - no multiply-add is fused and transcendental functions come from
//!   `libm`, so the same inputs give the same bits on every CPU (x86-64
//!   at any SIMD level, aarch64, WebAssembly; CI checks them against
//!   locked values);
//! - the scalar and SIMD ray–sphere kernels are one function written for
//!   both `f32` and `f32x8`, so every path returns the same hit.
//!
//! ## Modules
//!
//! | module | what |
//! |---|---|
//! | [`rng`] | per-sample stream derivation, `u32 → f32` in `[0, 1)` |
//! | [`sampler`] | the [`Sampler`] trait; [`Independent`], [`UniformGrid`], [`Stratified`], [`Sobol`], [`Halton`], [`ZSobol`] |
//! | [`mapping`] | sample / pdf / invert triads: sphere, hemispheres, disks, cone, the tabulated [`mapping::PiecewiseConstant2D`]; [`mapping::rejection`] keeps the course's methods |
//! | [`onb`] | orthonormal bases: Duff et al. (default) and the course's |
//! | [`trace`] | rays and spheres: scalar, 1×8 and 8-ray packet closest/any hit, same bits on every path; [`trace::simd_level`] |
//! | [`render`] | camera, textures, materials, sphere lights, [`render::Scene::build`], the exact film, the path tracer and tiles ([`render::render_tile`]) |
//! | [`filter`] | pixel filters, importance-sampled or (negative lobes) splatted |
//!
//! Beneath them, private ground modules that both sampling and tracing
//! stand on (neither imports the other): `float`, `trig` and `pow`
//! (portable maths in fixed IEEE sequences), and `lanes` (the `f32` /
//! `f32x8` lane abstraction, vectors of lanes, and the ray and sphere
//! bundles the kernels take).
//!
//! ## Example
//!
//! One pixel sample: a position in the pixel, then a cosine-weighted bounce
//! direction around a surface normal, with its pdf.
//!
//! ```
//! use glam::{UVec2, Vec3};
//! use strata::{mapping, onb::Onb, Sampler, Stratified};
//!
//! let mut sampler = Stratified::new(16, 2026).expect("spp > 0");
//! sampler.start_pixel_sample(UVec2::new(120, 45), 3);
//! let offset = sampler.pixel_2d(); // in [0, 1)² of the pixel
//! assert!(offset.x < 1.0 && offset.y < 1.0);
//!
//! let normal = Vec3::new(0.0, 1.0, 0.0);
//! let local = mapping::sample_cosine_hemisphere(sampler.next_2d());
//! let pdf = mapping::pdf_cosine_hemisphere(local);
//! let world = Onb::from_normal(normal).to_world(local);
//! assert!(world.dot(normal) >= -1e-6 && pdf >= 0.0);
//! assert!((pdf - world.dot(normal).max(0.0) / core::f32::consts::PI).abs() < 1e-5);
//! ```
//!
//! And one pixel rendered, a white diffuse sphere under a sky of radiance
//! 1 (a white furnace), into nothing but stack storage:
//!
//! ```
//! use glam::{UVec2, Vec3};
//! use strata::render::*;
//! use strata::trace::{Sphere, SphereChunk8};
//! use strata::Independent;
//!
//! let spheres = [Sphere::new(Vec3::ZERO, 1.0)];
//! let materials = [Material::Lambertian { albedo: Texture::Solid(Vec3::ONE) }];
//! // One sphere, too few for a BVH to pay.
//! const SIZE: SceneStorageSize = SceneStorageSize::for_spheres(1, false);
//! let (mut chunks, mut lights) = ([SphereChunk8::EMPTY; SIZE.chunks], [0u32; SIZE.lights]);
//! let storage = SceneStorage {
//!     chunks: &mut chunks, lights: &mut lights,
//!     bvh_nodes: &mut [], bvh_lanes: &mut [], bvh_ids: &mut [],
//! };
//! let scene = Scene::build(&spheres, &materials, &[0], Background::Flat(Vec3::ONE), storage).unwrap();
//! let camera = Camera::new(
//!     &CameraDesc {
//!         look_from: Vec3::new(0.0, 0.0, 4.0), look_at: Vec3::ZERO, up: Vec3::Y,
//!         vfov_deg: 40.0, defocus_angle_deg: 0.0, focus_dist: 4.0,
//!     },
//!     16, 16,
//! ).unwrap();
//! let settings = RenderSettings {
//!     max_depth: 8, direct_lighting: true,
//!     filter: strata::filter::PixelFilter::BOX, texture_filter: TextureFilter::None,
//!     integrator: strata::render::Integrator::Scalar,
//! };
//! let tile = Tile { x0: 8, y0: 8, width: 1, height: 1 };
//! let mut film = [PixelSum::ZERO; 1];
//! render_tile(&scene, &camera, &Independent::new(16, 1).unwrap(), &settings, tile, 0..16, &mut film).unwrap();
//! assert_eq!(film[0].samples, 16);
//! assert!((film[0].mean() - Vec3::ONE).abs().max_element() < 1e-5);
//! ```
//!
//! ## Limitations
//!
//! - `f32` only.
//! - The built-in renderer ([`render`]) draws spheres only (the course's
//!   quads and triangles are out of scope); the BVH also serves the
//!   caller's own primitives ([`trace::PrimitiveBvh`]), with the caller's
//!   intersection routine.
//! - Rejection samplers ([`mapping::rejection`]) consume a random count of
//!   values, so they take their own generator and never a pixel's sampler.
//! - The strata samplers accept at most 2²⁴ samples per pixel; a prime spp
//!   stratifies the pixel in strips (`p × 1`).
//! - The 8-wide kernels use 256-bit vectors; an AVX-512 build runs them on
//!   AVX2-width registers.
//!
//! ## Thread safety
//!
//! Every type is a plain value: samplers, `Onb`, `Ray`, `Sphere`,
//! `RayPacket8`, `HitPacket8`, `SphereSet` and `Bvh` (shared borrows) are
//! `Send` and `Sync`; a `PrimitiveBvh` is when the caller's primitives
//! are `Sync`. Give each thread its own sampler and `BvhStack`; share
//! sphere sets and trees freely.
//!
//! ## Features
//!
//! - `alloc` (off by default): owning buffers beside the borrowed views,
//!   `trace::OwnedBvh` and `trace::OwnedPrimitiveBvh`, so a scene
//!   struct can hold its tree. Without it the crate does not link `alloc`.
#![no_std]
#![forbid(unsafe_code)]
#![deny(missing_docs, missing_debug_implementations)]
#![warn(clippy::missing_inline_in_public_items)]

#[cfg(feature = "alloc")]
extern crate alloc;
// Unit tests may allocate (the library never does without `alloc`).
#[cfg(test)]
extern crate std;

pub mod filter;
mod float;
mod lanes;
pub mod mapping;
pub mod onb;
mod pow;
pub mod render;
pub mod rng;
pub mod sampler;
pub mod trace;
mod trig;

/// The glam this crate's signatures use (0.34, `libm` maths, no
/// `fast-math`): a renderer on another glam version names these types
/// through `strata::glam` instead of adding a second glam.
pub use glam;
pub use onb::Onb;
pub use sampler::{Halton, Independent, Sampler, Sobol, Stratified, UniformGrid, ZSobol};
