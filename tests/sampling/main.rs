//! Sampling: samplers, mappings, bases and filters, checked statistically
//! (fixed seeds, stated significance levels) and exactly.
//!
//! | module | guards |
//! |---|---|
//! | `chi2` | every mapping and filter sampler against its own pdf (χ², must-fail controls) |
//! | `round_trip` | every inverse undoes its mapping |
//! | `onb` | orthonormal bases, handedness, adversarial normals |
//! | `stratification` | one sample per stratum, per pass, for any spp; nets of pixels and of ZSobol' pixel blocks |
//! | `order` | a sample's bits do not depend on visiting order |
//! | `independence` | neighbouring streams are uncorrelated; ZSobol' neighbours are anti-correlated, on purpose |
//! | `filters` | filters integrate to 1; filter importance sampling is unbiased |
//! | `convergence` | stratified and low-discrepancy errors order as the lecture says |
//! | `spectrum` | the samplers' periodograms: flat, blue, spiky |
//! | `limits` | every sampler at its limits: spp, dimensions, the largest pixel and index |

#[path = "../support/mod.rs"]
mod support;

mod chi2;
mod convergence;
mod filters;
mod independence;
mod limits;
mod onb;
mod order;
mod round_trip;
mod spectrum;
mod stratification;
