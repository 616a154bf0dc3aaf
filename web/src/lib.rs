//! The browser page's entry points (`web/`): thin `wasm-bindgen` wrappers
//! over the runner's library — its golden table, scenes and samplers — so
//! the page computes the very bits a native build computes, and nothing
//! is copied. Each entry point is a plain Rust function (tested natively)
//! and a wrapper that turns its error into a JavaScript `Error`.
//!
//! Built by `web/build.sh` for `wasm32-unknown-unknown`; there a render
//! runs on the calling thread (the page, still to come, will call these
//! from a Web Worker).

#![forbid(unsafe_code)]

use anyhow::{Result, bail};
use strata::glam::UVec2;
use strata_runner::batch::AnySampler;
use strata_runner::golden;
use strata_runner::job::SamplerKind;
use wasm_bindgen::prelude::*;

/// The most samples [`sample_points`] draws (the page's patterns are to
/// go up to 1024).
pub const MAX_POINTS: u32 = 4096;

/// The most dimensions per sample [`sample_points`] draws.
pub const MAX_DIMS: u32 = 64;

/// The golden table's rows, one `scene key hash` line each (the hash as
/// 16 hex digits), in the table's order.
///
/// ```
/// let rows = strata_web::golden_rows();
/// assert!(rows.lines().any(|l| l.starts_with("week09 sobol ")));
/// ```
#[wasm_bindgen(js_name = goldenRows)]
#[must_use]
pub fn golden_rows() -> String {
    golden::GOLDEN
        .iter()
        .map(|(scene, key, hash)| format!("{scene} {key} {hash:016x}\n"))
        .collect()
}

/// This build's value of the golden row (`scene`, `key`), as 16 hex
/// digits, rendered on the calling thread.
///
/// # Errors
/// A (scene, key) pair that is not a row of the table.
///
/// ```
/// let hash = strata_web::golden_value("week09", "scene").unwrap();
/// assert!(strata_web::golden_rows().contains(&format!("week09 scene {hash}")));
/// assert!(strata_web::golden_value("week09", "no such key").is_err());
/// ```
pub fn golden_value(scene: &str, key: &str) -> Result<String> {
    if golden::expected(scene, key).is_none() {
        bail!("({scene}, {key}) is not a row of the golden table");
    }
    let data = golden::scene(scene)?;
    Ok(format!("{:016x}", golden::compute(scene, &data, key, 1)?))
}

/// [`golden_value`] for JavaScript (errors become `Error`s).
#[wasm_bindgen(js_name = goldenValue)]
pub fn golden_value_js(scene: &str, key: &str) -> Result<String, JsError> {
    golden_value(scene, key).map_err(|e| JsError::new(&format!("{e:#}")))
}

/// The first `dims` dimensions of samples `0..n` of pixel (0, 0) of the
/// sampler `kind` built for `n` samples per pixel and `seed` (zsobol for
/// a 1×1 image), row after row as the renderer draws them: the position
/// in the pixel, then pairs, then a last single dimension when `dims` is
/// odd. The page plots two columns of these rows.
///
/// # Errors
/// An unknown kind, `n` outside `1..=MAX_POINTS`, `dims` outside
/// `1..=MAX_DIMS`, or a kind that refuses `n` samples per pixel.
///
/// ```
/// let p = strata_web::sample_points("stratified", 16, 7, 2).unwrap();
/// assert_eq!(p.len(), 32);
/// // One sample per stratum of the 4 × 4 grid.
/// let mut cells: Vec<u32> = p.chunks(2).map(|s| (s[0] * 4.0) as u32 + 4 * (s[1] * 4.0) as u32).collect();
/// cells.sort();
/// assert_eq!(cells, (0..16).collect::<Vec<u32>>());
/// assert!(strata_web::sample_points("stratified", 0, 7, 2).is_err());
/// ```
pub fn sample_points(kind: &str, n: u32, seed: u64, dims: u32) -> Result<Vec<f32>> {
    let kind = SamplerKind::from_name(kind)?;
    if !(1..=MAX_POINTS).contains(&n) {
        bail!("{n} samples: the page draws 1 to {MAX_POINTS}");
    }
    if !(1..=MAX_DIMS).contains(&dims) {
        bail!("{dims} dimensions: the page draws 1 to {MAX_DIMS}");
    }
    let mut sampler = AnySampler::new(kind, n, seed, UVec2::ONE)?;
    let mut out = vec![0.0; n as usize * dims as usize];
    sampler.fill_pixel(UVec2::ZERO, 0, dims as usize, &mut out)?;
    Ok(out)
}

/// [`sample_points`] for JavaScript (errors become `Error`s; `seed` is a
/// `BigInt`). `n` and `dims` arrive as numbers, checked here: a
/// fraction, a negative or a value past `u32` is refused, not wrapped.
#[wasm_bindgen(js_name = samplePoints)]
pub fn sample_points_js(kind: &str, n: f64, seed: u64, dims: f64) -> Result<Vec<f32>, JsError> {
    let count = |x: f64, what: &str| {
        if x.fract() == 0.0 && (0.0..=f64::from(u32::MAX)).contains(&x) {
            Ok(x as u32)
        } else {
            Err(JsError::new(&format!(
                "{what} must be a whole number from 0, not {x}"
            )))
        }
    };
    sample_points(kind, count(n, "n")?, seed, count(dims, "dims")?)
        .map_err(|e| JsError::new(&format!("{e:#}")))
}

/// The output identity films carry (crate version and output revision),
/// which the page shows beside its golden check.
#[wasm_bindgen(js_name = outputVersion)]
#[must_use]
pub fn output_version() -> String {
    strata_runner::film::version()
}

#[cfg(test)]
mod tests {
    use super::*;

    /// The page's golden check reproduces rows natively too, through the
    /// one-thread path the browser takes: a render, a variant and a file.
    #[test]
    fn golden_values_reproduce_table_rows() {
        for (scene, key) in [
            ("week09", "sobol"),
            ("cover", "independent"),
            ("horizon", "stratified+texture-box"),
            ("showcase", "stratified+lanczos"),
            ("week09", "sobol+adaptive"),
            ("caustics", "file.png"),
        ] {
            let Some(want) = golden::expected(scene, key) else {
                panic!("{scene} {key} is not a row");
            };
            assert_eq!(
                golden_value(scene, key).unwrap(),
                format!("{want:016x}"),
                "{scene} {key}"
            );
        }
        assert!(golden_value("no such scene", "sobol").is_err());
        // Not a row, though both exist: refused, not computed.
        assert!(golden_value("examples/scenes/materials.toml", "file.png").is_err());
    }

    /// Sample rows are the renderer's, bad requests are refused.
    #[test]
    fn sample_points_are_the_batch_rows_and_bad_requests_fail() {
        for kind in SamplerKind::ALL {
            let p = sample_points(kind.name(), 64, 3, 5).unwrap();
            assert_eq!(p.len(), 64 * 5);
            assert!(p.iter().all(|v| (0.0..1.0).contains(v)), "{}", kind.name());
            let mut s = AnySampler::new(kind, 64, 3, UVec2::ONE).unwrap();
            let mut row = [0.0f32; 5];
            s.fill_pixel(UVec2::ZERO, 17, 5, &mut row).unwrap();
            assert_eq!(row, p[17 * 5..18 * 5], "{}", kind.name());
        }
        for (kind, n, dims) in [
            ("nope", 4, 2),
            ("sobol", 0, 2),
            ("sobol", MAX_POINTS + 1, 2),
            ("sobol", 4, 0),
            ("sobol", 4, MAX_DIMS + 1),
        ] {
            assert!(
                sample_points(kind, n, 1, dims).is_err(),
                "{kind} {n} {dims}"
            );
        }
    }
}
