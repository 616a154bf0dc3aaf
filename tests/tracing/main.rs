//! Tracing: every kernel returns the scalar reference's hit bit for bit,
//! and how precise that reference is.
//!
//! | module | guards |
//! |---|---|
//! | `packet_vs_scalar` | scalar, 1×8 and packet kernels agree on 10⁶ rays; inactive lanes |
//! | `bvh` | the BVH returns the brute-force hits; storage and degenerate input |
//! | `primitives` | the BVH over the caller's triangles and boxes returns the brute-force hits |
//! | `precision` | the kernel against an f64 reference; spawn offsets |
//! | `layouts` | the built-in sphere lists are the reference CSVs |

mod bvh;
mod layouts;
mod packet_vs_scalar;
mod precision;
mod primitives;
