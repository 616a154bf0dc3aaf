//! Helpers shared by the root test suite.
#![allow(dead_code)] // each test binary uses a different part

pub mod chi2;

/// A fixed seed per test, from its name (FNV-1a), so tests do not share
/// streams yet every run is the same.
pub fn seed_for(name: &str) -> u64 {
    strata_runner::hash::fnv1a(name.as_bytes())
}
