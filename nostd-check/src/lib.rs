//! A `no_std` consumer of `strata`: it exercises each module so the linker
//! keeps them, and supplies the panic handler a `no_std` library needs.
#![no_std]

use core::panic::PanicInfo;

use glam::{UVec2, Vec3};
use strata::trace::{Ray, Sphere, SphereChunk8, SphereSet, closest_hit_1x8};
use strata::{Onb, Sampler, Stratified, mapping};

/// The cosine-weighted bounce of one pixel sample, as world x, y, z.
#[unsafe(no_mangle)]
pub extern "C" fn strata_check(px: u32, py: u32, index: u32, out: &mut [f32; 3]) -> bool {
    let Some(mut sampler) = Stratified::new(16, 1) else {
        return false;
    };
    sampler.start_pixel_sample(UVec2::new(px, py), index);
    let local = mapping::sample_cosine_hemisphere(sampler.next_2d());
    let world = Onb::from_normal(Vec3::Y).to_world(local);
    *out = world.to_array();
    true
}

/// The distance to the closest of two spheres along +x from the origin,
/// through the SIMD path (so `wide` is linked too); `-1` for a miss.
#[unsafe(no_mangle)]
pub extern "C" fn strata_check_trace(x0: f32, x1: f32) -> f32 {
    let spheres = [Sphere::new(Vec3::new(x0, 0.0, 0.0), 0.5), Sphere::new(Vec3::new(x1, 0.0, 0.0), 0.5)];
    let mut storage = [SphereChunk8::EMPTY];
    let Ok(set) = SphereSet::build(&spheres, &mut storage) else {
        return -1.0;
    };
    closest_hit_1x8(&set, &Ray::new(Vec3::ZERO, Vec3::X)).map_or(-1.0, |h| h.t)
}

#[panic_handler]
fn panic(_: &PanicInfo) -> ! {
    loop {}
}
