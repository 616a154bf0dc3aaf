//! The library behind the `strata` command: the command line, built-in
//! scenes and TOML scene files, the parallel renderer, image files, and
//! the benchmark workloads.

pub mod batch;
pub mod bench;
pub mod checkpoint;
pub mod cli;
pub mod commands;
pub mod film;
pub mod golden;
pub mod hash;
pub mod image_io;
pub mod job;
pub mod limits;
pub mod plot;
pub mod progress;
pub mod scenes;
pub mod settings;
pub mod spectrum;
pub mod study;
pub mod workload;

/// One line describing this build: the version and the SIMD level its
/// kernels run on.
#[must_use]
pub fn version_line() -> String {
    format!(
        "strata {} (simd: {})",
        env!("CARGO_PKG_VERSION"),
        strata::trace::simd_level().name()
    )
}

#[cfg(test)]
mod tests {
    #[test]
    fn version_line_names_the_version_and_simd_level() {
        let line = super::version_line();
        assert!(line.contains(env!("CARGO_PKG_VERSION")));
        assert!(line.contains(strata::trace::simd_level().name()));
    }
}
