//! The library behind the `strata` command. The renderer, scene files and
//! benchmarks land here; for now it reports what the core build offers.

/// One line describing this build: the crate version and the core it links.
#[must_use]
pub fn version_line() -> String {
    format!(
        "strata {} (core: no_std sampling)",
        env!("CARGO_PKG_VERSION")
    )
}

#[cfg(test)]
mod tests {
    #[test]
    fn version_line_names_the_version() {
        assert!(super::version_line().contains(env!("CARGO_PKG_VERSION")));
    }
}
