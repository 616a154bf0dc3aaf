//! The library behind the `strata` command. The renderer and scene files
//! land here; for now it holds the benchmark workloads.

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
