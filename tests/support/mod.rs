//! Helpers shared by the root test suite.
#![allow(dead_code)] // each test binary uses a different part

pub mod chi2;

/// A fixed seed per test, from its name (FNV-1a), so tests do not share
/// streams yet every run is the same.
pub fn seed_for(name: &str) -> u64 {
    name.bytes().fold(0xcbf2_9ce4_8422_2325u64, |h, b| {
        (h ^ b as u64).wrapping_mul(0x0100_0000_01b3)
    })
}
