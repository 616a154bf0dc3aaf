//! Rendering: where sampling and tracing meet. A camera, textures,
//! materials, sphere lights and a background make a [`Scene`];
//! [`render_tile`] traces paths through it into the caller's [`PixelSum`]
//! buffer.
//!
//! Everything is borrowed and nothing allocates: the caller owns the
//! spheres, their 8-wide chunks, the materials, the texels of image
//! textures, the light list and the film.
//!
//! The submodules group the docs by concept; every item is also
//! re-exported here, so `strata::render::Scene` and
//! `strata::render::scene::Scene` are the same type.
//!
//! | module | what |
//! |---|---|
//! | [`camera`] | the course's thin-lens camera |
//! | [`texture`] | solid, checker (point-sampled or prefiltered) and image textures |
//! | [`material`] | the material models and how each differs from the course's |
//! | [`scene`] | spheres, materials, lights and background, built into caller-owned storage |
//! | [`integrator`] | one camera path: the dimension layout and the depth convention |
//! | [`film`] | exact fixed-point accumulation |
//! | [`tile`] | rectangles of pixels rendered into the caller's film, and how a render's films are laid out |
//! | [`adaptive`] | the adaptive-sampling rule and its tiles |
//! | [`splat`] | filters with negative lobes, splatted into the pixels they reach |

pub mod adaptive;
pub mod camera;
pub mod film;
pub mod integrator;
#[cfg(test)]
mod lanes_check;
mod lockstep;
pub mod material;
pub mod scene;
pub mod splat;
pub mod texture;
pub mod tile;

pub use crate::filter::PixelFilter;
pub use adaptive::{Adaptive, AdaptiveError, ERROR_FLOOR, PilotStats, render_tile_adaptive};
pub use camera::{Camera, CameraDesc, CameraError};
pub use film::{FILM_SCALE, MAX_SAMPLE_VALUE, PixelSum};
pub use integrator::{
    CAMERA_DIMENSIONS, Integrator, RenderSettings, TileStats, VERTEX_DIMENSIONS, pixel_sample,
    pixel_sample_with,
};
pub use material::{BsdfSample, Lobe, Material, MaterialError, SurfaceHit};
pub use scene::{Background, Scene, SceneError, SceneStorage, SceneStorageSize};
pub use splat::{SPLAT_SIDE, Splat, render_tile_splat, splat_film_size};
pub use texture::{ImageTexture, Texture, TextureFilter, sphere_uv};
pub use tile::{Layout, RenderError, Tile, TileRenderer, render_tile};

/// The revision of what renders compute: raised whenever a change alters
/// an existing output (a pixel, a scene hash, a file's bytes; the output
/// locks in `std-runner/tests/output_locks.rs` fail then, and say to
/// raise it), never for new outputs. Film files and caches of rendered
/// results (e.g. `strata converge`'s references) key on it.
pub const OUTPUT_REVISION: u32 = 16;
