//! Rendering through the library: exact determinism across tiles, threads
//! and splits, the materials and lights against analytic values, and the
//! reconstruction settings.
//!
//! | module | guards |
//! |---|---|
//! | `render` | tiles and sample splits are exact; albedos, MIS, the course's defects fixed |
//! | `split_merge` | random pixel and sample partitions merge to the one-shot film |
//! | `adaptive` | adaptive renders are exact for any split; they stop where they should |
//! | `prefilter` | the prefiltered checker and its ray-differential footprint |

mod adaptive;
mod prefilter;
mod render;
mod split_merge;
