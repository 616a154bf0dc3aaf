//! Embedding the sampling core: fill a caller-owned buffer with the sample
//! positions of one image tile, then estimate a pixel integral with them.
//!
//! Run with `cargo run -p strata --example tile_samples`.

use glam::{UVec2, Vec2};
use strata::{Sampler, Stratified, mapping};

const TILE: UVec2 = UVec2::new(8, 4);
const SPP: u32 = 16;

/// Writes sample `i` of pixel `(x, y)` (tile-local) to
/// `out[(y * TILE.x + x) * SPP + i]`, in image coordinates.
fn tile_positions<S: Sampler>(sampler: &mut S, origin: UVec2, out: &mut [Vec2]) {
    assert_eq!(out.len(), (TILE.x * TILE.y * SPP) as usize, "buffer size");
    for y in 0..TILE.y {
        for x in 0..TILE.x {
            let pixel = origin + UVec2::new(x, y);
            for i in 0..SPP {
                sampler.start_pixel_sample(pixel, i);
                out[((y * TILE.x + x) * SPP + i) as usize] = pixel.as_vec2() + sampler.pixel_2d();
            }
        }
    }
}

fn main() {
    let mut sampler = Stratified::new(SPP, 2026).expect("spp > 0");
    let mut buffer = [Vec2::ZERO; (TILE.x * TILE.y * SPP) as usize];
    tile_positions(&mut sampler, UVec2::new(64, 32), &mut buffer);
    // Every position lies in its own pixel.
    for (k, p) in buffer.iter().enumerate() {
        let pixel = UVec2::new(64 + (k as u32 / SPP) % TILE.x, 32 + k as u32 / SPP / TILE.x);
        assert_eq!(p.floor().as_uvec2(), pixel);
    }

    // The irradiance from a uniform sky of radiance 1 is π: estimate it with
    // cosine-weighted directions, weighting each by cos θ / pdf.
    let mut sum = 0.0;
    for i in 0..SPP {
        sampler.start_pixel_sample(UVec2::new(0, 0), i);
        let w = mapping::sample_cosine_hemisphere(sampler.next_2d());
        sum += w.z / mapping::pdf_cosine_hemisphere(w);
    }
    let estimate = sum / SPP as f32;
    // Cosine sampling makes the weight constant: no variance at all.
    assert!((estimate - core::f32::consts::PI).abs() < 1e-4);
    println!("first sample {}, irradiance estimate {estimate}", buffer[0]);
}
