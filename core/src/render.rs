//! Rendering: where sampling and tracing meet. A camera, textures,
//! materials, sphere lights and a background make a [`Scene`];
//! [`render_tile`] traces paths through it into the caller's [`PixelSum`]
//! buffer.
//!
//! Everything is borrowed and nothing allocates: the caller owns the
//! spheres, their 8-wide chunks, the materials, the texels of image
//! textures, the light list and the film.
//!
//! See [`integrator`](self::render_tile) for the path, the dimension
//! layout and the depth convention, [`film`](PixelSum) for the exact
//! accumulation, and [`Material`] for each model and how it differs from
//! the course's.

mod adaptive;
mod camera;
mod film;
mod integrator;
mod material;
mod scene;
mod texture;
mod tile;

pub use crate::filter::PixelFilter;
pub use adaptive::{Adaptive, AdaptiveError, ERROR_FLOOR, PixelError};
pub use camera::{Camera, CameraDesc, CameraError};
pub use film::{FILM_SCALE, MAX_SAMPLE_VALUE, PixelSum};
pub use integrator::{RenderSettings, pixel_sample};
pub use material::{BsdfSample, Lobe, Material, MaterialError, SurfaceHit};
pub use scene::{Background, Scene, SceneError, SceneStorage, SceneStorageSize};
pub use texture::{ImageTexture, Texture, TextureFilter, sphere_uv};
pub use tile::{RenderError, Tile, TileStats, render_tile, render_tile_adaptive};

/// The revision of what renders compute: raised whenever a change alters
/// an existing output (a pixel, a scene hash, a file's bytes; the output
/// locks in `std-runner/tests/output_locks.rs` fail then, and say to
/// raise it), never for new outputs. Film files and caches of rendered
/// results (e.g. `strata converge`'s references) key on it.
pub const OUTPUT_REVISION: u32 = 3;
