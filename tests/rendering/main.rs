//! Rendering through the library: exact determinism across tiles, threads
//! and splits, the materials and lights against analytic values, and the
//! reconstruction settings.
//!
//! | module | guards |
//! |---|---|
//! | `determinism` | the contract on whole renders: tiles, threads, sample runs, random partitions, adaptive crops, all bit for bit |
//! | `render` | albedos, MIS, lights, the course's defects fixed |
//! | `adaptive` | adaptive renders stop where they should and agree with uniform sampling |
//! | `prefilter` | the prefiltered checker and its ray-differential footprint |
//! | `splat` | splatted filters: exact flat regions, no speckles, the contract bit for bit |
//! | `filter_bias` | every filter averages, over seeds, to its convolution of a converged image |

#[path = "../support/mod.rs"]
mod support;

mod adaptive;
mod determinism;
mod filter_bias;
mod prefilter;
mod render;
mod splat;
