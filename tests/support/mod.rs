//! Helpers shared by the root test suite.
#![allow(dead_code)] // the sampling and rendering binaries each use a part

pub mod chi2;
pub mod scenes;

/// A fixed seed per test, from its name (FNV-1a), so tests do not share
/// streams yet every run is the same.
pub fn seed_for(name: &str) -> u64 {
    strata_runner::hash::fnv1a(name.as_bytes())
}
