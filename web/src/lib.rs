//! The browser page's entry points (`web/`): thin `wasm-bindgen` wrappers
//! over the runner's library — its scenes, the command line's one check
//! of render settings, the golden table, samplers and spectra — so the
//! page computes the very bits a native build computes, and nothing is
//! copied. Each entry point is a plain Rust function (tested natively)
//! and a wrapper that turns its error into a JavaScript `Error` and
//! checks the numbers JavaScript passes (whole, in range: refused, never
//! wrapped).
//!
//! Built by `web/build.sh` for `wasm32-unknown-unknown`, where the page's
//! Web Workers call them; a render runs on the calling thread.

#![forbid(unsafe_code)]

use anyhow::{Result, anyhow, bail};
use strata::glam::{UVec2, Vec3};
use strata_runner::batch::AnySampler;
use strata_runner::cli::library_render;
use strata_runner::golden;
use strata_runner::image_io::srgb_code;
use strata_runner::job::{Job, SamplerKind, run};
use strata_runner::scenes::{BUILT_IN, built_in};
use strata_runner::{plot, spectrum, study};
use wasm_bindgen::prelude::*;

/// The most samples [`sample_points`] and [`periodogram`] draw per pixel
/// (the page's patterns go up to 1024).
pub const MAX_POINTS: u32 = 4096;

/// The most dimensions per sample [`sample_points`] draws.
pub const MAX_DIMS: u32 = 64;

/// The golden table's rows this module computes, one `scene key hash`
/// line each (the hash as 16 hex digits), in the table's order: every row
/// of a built-in scene but the file rows (the bytes of PNG, EXR and film
/// files, whose encoders the page does not carry; every native build
/// checks those).
///
/// ```
/// let rows = strata_web::golden_rows();
/// assert!(rows.lines().any(|l| l.starts_with("week09 sobol ")));
/// assert!(!rows.contains("file.png"));
/// ```
#[wasm_bindgen(js_name = goldenRows)]
#[must_use]
pub fn golden_rows() -> String {
    golden::GOLDEN
        .iter()
        .filter(|(scene, key, _)| page_row(scene, key))
        .map(|(scene, key, hash)| format!("{scene} {key} {hash:016x}\n"))
        .collect()
}

/// Whether the page computes the row (`scene`, `key`).
fn page_row(scene: &str, key: &str) -> bool {
    BUILT_IN.contains(&scene) && !key.starts_with("file.")
}

/// This build's value of the golden row (`scene`, `key`), as 16 hex
/// digits, rendered on the calling thread.
///
/// # Errors
/// A (scene, key) pair that is not one of [`golden_rows`].
///
/// ```
/// let hash = strata_web::golden_value("week09", "scene").unwrap();
/// assert!(strata_web::golden_rows().contains(&format!("week09 scene {hash}")));
/// assert!(strata_web::golden_value("week09", "no such key").is_err());
/// assert!(strata_web::golden_value("week09", "file.png").is_err());
/// ```
pub fn golden_value(scene: &str, key: &str) -> Result<String> {
    if golden::expected(scene, key).is_none() || !page_row(scene, key) {
        bail!("({scene}, {key}) is not a golden row the page computes");
    }
    let data = built_in(scene).ok_or_else(|| anyhow!("no built-in scene {scene}"))?;
    Ok(format!(
        "{:016x}",
        golden::compute_film(scene, &data, key, 1)?
    ))
}

/// [`golden_value`] for JavaScript (errors become `Error`s).
#[wasm_bindgen(js_name = goldenValue)]
pub fn golden_value_js(scene: &str, key: &str) -> Result<String, JsError> {
    golden_value(scene, key).map_err(js_error)
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

/// [`sample_points`] for JavaScript (errors become `Error`s). `n`,
/// `dims` and `seed` arrive as numbers, checked here: a fraction, a
/// negative or a value past `u32` (the seed: past 2⁵³) is refused, not
/// wrapped.
#[wasm_bindgen(js_name = samplePoints)]
pub fn sample_points_js(kind: &str, n: f64, seed: f64, dims: f64) -> Result<Vec<f32>, JsError> {
    sample_points(kind, whole(n, "n")?, seed_of(seed)?, whole(dims, "dims")?).map_err(js_error)
}

/// The most samples (pixels × samples per pixel, the most an adaptive
/// render may take) a [`render`] traces: about a minute in the plain
/// module, so a request cannot hold a worker for long.
pub const MAX_PATHS: u64 = 1 << 25;

/// The most pixels a [`render`] takes: its film and images stay within
/// about 150 MB of the module's memory (the command line's own cap, 2²⁵,
/// would need about 4 GiB, all of wasm32's address space).
pub const MAX_PIXELS: u64 = 1 << 20;

/// What the page renders: a built-in scene at a size and samples per
/// pixel, with a sampler, pixel filter, adaptive sampling or not, the
/// prefiltered checker or not.
#[derive(Clone, Debug)]
pub struct Settings {
    /// A built-in scene (`week09`, `cover`, `showcase`, `horizon`, `caustics`).
    pub scene: String,
    /// A sampler name ([`SamplerKind::name`]).
    pub sampler: String,
    /// A pixel filter name (`box`, `tent`, `gaussian`, `mitchell`,
    /// `lanczos`) at its default radius.
    pub filter: String,
    /// Adaptive sampling: a pilot of `spp / 4` samples (at least 8, a
    /// multiple of 4), then up to `spp` (at least the pilot) where the
    /// error asks for them.
    pub adaptive: bool,
    /// The box-filtered checker at camera rays' first hits.
    pub texture_box: bool,
    /// Image width.
    pub width: u32,
    /// Image height.
    pub height: u32,
    /// Samples per pixel (the most, when adaptive).
    pub spp: u32,
    /// Seed of every sample stream.
    pub seed: u64,
}

/// The threshold of the page's adaptive renders: higher than the
/// renderer's default, so that at the page's few samples the map shows
/// where samples go.
pub const PAGE_ADAPTIVE_THRESHOLD: f32 = 0.002;

/// A finished render: its pixels as the page shows them.
#[wasm_bindgen]
#[derive(Clone, Debug)]
pub struct Frame {
    width: u32,
    height: u32,
    linear: Vec<f32>,
    rgba: Vec<u8>,
    heat: Vec<u8>,
    samples: u64,
}

#[wasm_bindgen]
impl Frame {
    /// Image width.
    #[wasm_bindgen(getter)]
    #[must_use]
    pub fn width(&self) -> u32 {
        self.width
    }

    /// Image height.
    #[wasm_bindgen(getter)]
    #[must_use]
    pub fn height(&self) -> u32 {
        self.height
    }

    /// Pixel means, linear RGB, row-major (3 values a pixel).
    #[must_use]
    pub fn linear(&self) -> Vec<f32> {
        self.linear.clone()
    }

    /// The image as sRGB bytes with opaque alpha (4 a pixel), what a
    /// canvas's `ImageData` takes; the renderer's PNG codes.
    #[must_use]
    pub fn rgba(&self) -> Vec<u8> {
        self.rgba.clone()
    }

    /// The samples each pixel took, as the renderer's heat map (viridis on
    /// a log scale from the fewest to the most a pixel may take), RGBA.
    #[must_use]
    pub fn heat(&self) -> Vec<u8> {
        self.heat.clone()
    }

    /// Samples taken over all pixels.
    #[wasm_bindgen(getter)]
    #[must_use]
    pub fn samples(&self) -> f64 {
        self.samples as f64
    }
}

impl Settings {
    /// These settings as the flags of `strata render`, which the runner
    /// checks as it checks its command line ([`library_render`]).
    #[must_use]
    pub fn flags(&self) -> Vec<String> {
        let mut flags: Vec<String> = [
            "--scene",
            &self.scene,
            "--sampler",
            &self.sampler,
            "--filter",
            &self.filter,
            "--width",
            &self.width.to_string(),
            "--height",
            &self.height.to_string(),
            "--seed",
            &self.seed.to_string(),
        ]
        .map(String::from)
        .into();
        if self.texture_box {
            flags.extend(["--texture-filter", "box"].map(String::from));
        }
        if self.adaptive {
            let min = (self.spp / 4).max(8) / 4 * 4;
            let max = self.spp.max(min).to_string();
            let min = min.to_string();
            let threshold = PAGE_ADAPTIVE_THRESHOLD.to_string();
            flags.extend(
                [
                    "--adaptive",
                    &threshold,
                    "--min-spp",
                    &min,
                    "--max-spp",
                    &max,
                ]
                .map(String::from),
            );
        } else {
            flags.extend(["--spp".to_string(), self.spp.to_string()]);
        }
        flags
    }

    /// The render job of these settings on one thread, checked: the
    /// command line's one check, a built-in scene, at most
    /// [`MAX_PIXELS`] pixels and [`MAX_PATHS`] samples.
    fn job<'a>(&self, scene: &'a strata_runner::scenes::SceneData) -> Result<Job<'a>> {
        let (args, _) = library_render(&self.flags())?;
        let job = Job {
            threads: 1,
            ..args.job(scene)?
        };
        let pixels = u64::from(job.width) * u64::from(job.height);
        if pixels > MAX_PIXELS {
            bail!(
                "{}x{} pixels: the page renders at most {MAX_PIXELS} pixels",
                job.width,
                job.height
            );
        }
        let paths = pixels * u64::from(job.spp);
        if paths > MAX_PATHS {
            bail!(
                "{}x{} pixels at {} samples: the page renders at most {MAX_PATHS} samples",
                job.width,
                job.height,
                job.spp
            );
        }
        Ok(job)
    }
}

/// Renders `settings` on the calling thread.
///
/// # Errors
/// A scene that is not built in, and whatever `strata render` refuses
/// of these settings (an unknown sampler or filter, sizes and counts out
/// of range, the grid sampler with adaptive sampling), or more than
/// [`MAX_PIXELS`] pixels or [`MAX_PATHS`] samples.
///
/// ```
/// use strata_web::{Settings, render};
/// let s = Settings {
///     scene: "week09".into(), sampler: "sobol".into(), filter: "box".into(),
///     adaptive: false, texture_box: false, width: 8, height: 6, spp: 2, seed: 1,
/// };
/// let f = render(&s).unwrap();
/// assert_eq!((f.width(), f.height(), f.samples()), (8, 6, 96.0));
/// assert_eq!(f.rgba().len(), 8 * 6 * 4);
/// assert!(render(&Settings { scene: "nope".into(), ..s }).is_err());
/// ```
pub fn render(settings: &Settings) -> Result<Frame> {
    // Built-in only: a browser has no scene files.
    let scene = built_in(&settings.scene).ok_or_else(|| {
        anyhow!(
            "unknown scene {:?}: one of {}",
            settings.scene,
            BUILT_IN.join(", ")
        )
    })?;
    let job = settings.job(&scene)?;
    let done = run(&job, &|_| {})?;
    let means: Vec<Vec3> = done.pixels.iter().map(|p| p.mean()).collect();
    let linear = means.iter().flat_map(|v| v.to_array()).collect();
    let rgba = means
        .iter()
        .flat_map(|v| [srgb_code(v.x), srgb_code(v.y), srgb_code(v.z), 255])
        .collect();
    let (base, max) = job
        .adaptive
        .map_or((job.spp, job.spp), |a| (a.min(), a.max()));
    let heat = plot::spp_heat_map(&done.pixels, base, max)
        .chunks_exact(3)
        .flat_map(|c| [c[0], c[1], c[2], 255])
        .collect();
    Ok(Frame {
        width: job.width,
        height: job.height,
        linear,
        rgba,
        heat,
        samples: done.pixels.iter().map(|p| u64::from(p.taken())).sum(),
    })
}

/// [`render`] for JavaScript (errors become `Error`s; sizes, counts and
/// the seed are checked whole numbers).
#[wasm_bindgen(js_name = render)]
#[allow(clippy::too_many_arguments)]
pub fn render_js(
    scene: String,
    sampler: String,
    filter: String,
    adaptive: bool,
    texture_box: bool,
    width: f64,
    height: f64,
    spp: f64,
    seed: f64,
) -> Result<Frame, JsError> {
    let settings = Settings {
        scene,
        sampler,
        filter,
        adaptive,
        texture_box,
        width: whole(width, "width")?,
        height: whole(height, "height")?,
        spp: whole(spp, "spp")?,
        seed: seed_of(seed)?,
    };
    render(&settings).map_err(js_error)
}

/// Root mean square error of two frames' linear pixels
/// ([`Frame::linear`]), over pixels and channels: the renderer's
/// `study::rmse`.
///
/// # Errors
/// Lengths that differ, are 0 or are not whole pixels.
///
/// ```
/// let e = strata_web::rmse(&[1.0, 1.0, 1.0], &[0.0, 1.0, 1.0]).unwrap();
/// assert!((e - (1.0f64 / 3.0).sqrt()).abs() < 1e-12);
/// assert!(strata_web::rmse(&[1.0], &[1.0]).is_err());
/// ```
pub fn rmse(image: &[f32], reference: &[f32]) -> Result<f64> {
    if image.len() != reference.len() || image.is_empty() || !image.len().is_multiple_of(3) {
        bail!(
            "images of {} and {} values: equal, non-zero, 3 a pixel",
            image.len(),
            reference.len()
        );
    }
    let pixels = |v: &[f32]| -> Vec<Vec3> { v.chunks_exact(3).map(Vec3::from_slice).collect() };
    Ok(study::rmse(&pixels(image), &pixels(reference)))
}

/// [`rmse`] for JavaScript.
#[wasm_bindgen(js_name = rmse)]
pub fn rmse_js(image: &[f32], reference: &[f32]) -> Result<f64, JsError> {
    rmse(image, reference).map_err(js_error)
}

/// The most pixels a [`periodogram`] averages.
pub const MAX_SPECTRUM_PIXELS: u32 = 4096;

/// The most terms (samples × pixels × (frequencies + dimensions drawn)) a
/// [`periodogram`] sums: a few seconds in the plain module.
pub const MAX_SPECTRUM_WORK: u64 = 1 << 30;

/// An averaged periodogram of sample positions and its radial average.
#[wasm_bindgen]
#[derive(Clone, Debug)]
pub struct Periodogram {
    r: u32,
    power: Vec<f32>,
    radial: Vec<f32>,
}

#[wasm_bindgen]
impl Periodogram {
    /// Frequencies run over `−r..=r` on each axis.
    #[wasm_bindgen(getter)]
    #[must_use]
    pub fn r(&self) -> u32 {
        self.r
    }

    /// `P(ω)`, row-major over `ω_y` then `ω_x`, each from `−r` to `r`
    /// (`ω = 0` at the centre): 1 is white noise's level.
    #[must_use]
    pub fn power(&self) -> Vec<f32> {
        self.power.clone()
    }

    /// The radial average at radii `1..=r`.
    #[must_use]
    pub fn radial(&self) -> Vec<f32> {
        self.radial.clone()
    }
}

/// The periodogram of the sampler `kind` at `n` samples per pixel,
/// projected on the sample dimensions `dims` (`[0, 1]`: the position in
/// the pixel), averaged over `pixels` pixels, up to frequency `r`: the
/// runner's `strata spectrum`.
///
/// # Errors
/// An unknown kind, `n` outside `1..=MAX_POINTS`, `pixels` outside
/// `1..=MAX_SPECTRUM_PIXELS`, `r` outside `1..=128`, more than
/// [`MAX_SPECTRUM_WORK`] terms, equal dimensions or one past 63.
///
/// ```
/// // A 4 × 4 grid: all power at multiples of 4.
/// let p = strata_web::periodogram("grid", 16, 1, [0, 1], 4, 8).unwrap();
/// let at = |wx: usize, wy: usize| p.power()[(wy + 8) * 17 + wx + 8];
/// assert!((at(4, 0) - 16.0).abs() < 1e-3 && at(1, 0) < 1e-3);
/// assert!(p.radial()[0] < 1e-3);
/// ```
pub fn periodogram(
    kind: &str,
    n: u32,
    seed: u64,
    dims: [u32; 2],
    pixels: u32,
    r: u32,
) -> Result<Periodogram> {
    let kind = SamplerKind::from_name(kind)?;
    if !(1..=MAX_POINTS).contains(&n) {
        bail!("{n} samples: the page draws 1 to {MAX_POINTS}");
    }
    if !(1..=MAX_SPECTRUM_PIXELS).contains(&pixels) {
        bail!("{pixels} pixels: the page averages 1 to {MAX_SPECTRUM_PIXELS}");
    }
    // Per sample: the frequencies' terms and the values drawn for its row.
    let row = u64::from(dims[0].max(dims[1])) + 1;
    let work = u64::from(n) * u64::from(pixels) * ((2 * u64::from(r) + 1).pow(2) + row);
    if work > MAX_SPECTRUM_WORK {
        bail!(
            "{n} samples over {pixels} pixels up to frequency {r}: {work} terms, the page sums at \
             most {MAX_SPECTRUM_WORK}"
        );
    }
    let s = spectrum::spectrum_of_dims(kind, n, seed, pixels, r, dims, &|_| {})?;
    Ok(Periodogram {
        r: s.r,
        power: s.power.iter().map(|&p| p as f32).collect(),
        radial: s.radial().iter().map(|&(_, p)| p as f32).collect(),
    })
}

/// [`periodogram`] for JavaScript.
#[wasm_bindgen(js_name = periodogram)]
pub fn periodogram_js(
    kind: &str,
    n: f64,
    seed: f64,
    dim_x: f64,
    dim_y: f64,
    pixels: f64,
    r: f64,
) -> Result<Periodogram, JsError> {
    periodogram(
        kind,
        whole(n, "n")?,
        seed_of(seed)?,
        [whole(dim_x, "dimX")?, whole(dim_y, "dimY")?],
        whole(pixels, "pixels")?,
        whole(r, "r")?,
    )
    .map_err(js_error)
}

/// A count from JavaScript (a number): a fraction, a negative or a value
/// past `u32` is refused, not wrapped.
fn whole(x: f64, what: &str) -> Result<u32, JsError> {
    if x.fract() == 0.0 && (0.0..=f64::from(u32::MAX)).contains(&x) {
        Ok(x as u32)
    } else {
        Err(JsError::new(&format!(
            "{what} must be a whole number from 0, not {x}"
        )))
    }
}

/// A seed from JavaScript (a number): a whole number from 0 to 2⁵³, the
/// integers a number holds exactly; anything else is refused.
fn seed_of(x: f64) -> Result<u64, JsError> {
    if x.fract() == 0.0 && (0.0..=9_007_199_254_740_992.0).contains(&x) {
        Ok(x as u64)
    } else {
        Err(JsError::new(&format!(
            "seed must be a whole number from 0 to 2^53, not {x}"
        )))
    }
}

/// An error as a JavaScript `Error` with its whole chain.
fn js_error(e: anyhow::Error) -> JsError {
    JsError::new(&format!("{e:#}"))
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
            ("caustics", "scene"),
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
        // File rows are the native builds' (the page has no encoders).
        assert!(golden::expected("caustics", "file.png").is_some());
        assert!(golden_value("caustics", "file.png").is_err());
        let rows = golden_rows();
        assert_eq!(
            rows.lines().count(),
            golden::GOLDEN
                .iter()
                .filter(|(s, k, _)| BUILT_IN.contains(s) && !k.starts_with("file."))
                .count()
        );
        // Not a row, though both exist: refused, not computed.
        assert!(golden_value("examples/scenes/materials.toml", "file.png").is_err());
    }

    fn settings() -> Settings {
        Settings {
            scene: "week09".into(),
            sampler: "sobol".into(),
            filter: "box".into(),
            adaptive: false,
            texture_box: false,
            width: golden::SIZE.0,
            height: golden::SIZE.1,
            spp: golden::SPP,
            seed: golden::SEED,
        }
    }

    /// A page render is the renderer's: the golden job's pixel means
    /// (the golden job's depth is the scene's here), and settings reach
    /// the job.
    #[test]
    fn renders_are_the_runners_and_settings_reach_the_job() {
        let scene = built_in("week09").unwrap();
        let job = Job {
            max_depth: scene.defaults.max_depth,
            threads: 2,
            ..golden::job(&scene, SamplerKind::Sobol, 2)
        };
        let want: Vec<f32> = run(&job, &|_| {})
            .unwrap()
            .pixels
            .iter()
            .flat_map(|p| p.mean().to_array())
            .collect();
        let f = render(&settings()).unwrap();
        assert_eq!(f.linear(), want);
        assert_eq!(f.samples(), f64::from(32 * 18 * golden::SPP));
        let codes: Vec<u8> = want.iter().map(|&v| srgb_code(v)).collect();
        let rgb: Vec<u8> = f.rgba().chunks(4).flat_map(|c| c[..3].to_vec()).collect();
        assert_eq!(rgb, codes);
        // Each setting changes the image.
        for other in [
            Settings {
                sampler: "halton".into(),
                ..settings()
            },
            Settings {
                filter: "mitchell".into(),
                ..settings()
            },
            Settings {
                seed: 6,
                ..settings()
            },
            Settings {
                scene: "horizon".into(),
                ..settings()
            },
        ] {
            assert_ne!(render(&other).unwrap().linear(), want, "{other:?}");
        }
        let prefiltered = Settings {
            scene: "horizon".into(),
            texture_box: true,
            ..settings()
        };
        assert_ne!(
            render(&prefiltered).unwrap().linear(),
            render(&Settings {
                scene: "horizon".into(),
                ..settings()
            })
            .unwrap()
            .linear()
        );
        // Adaptive: a pilot of spp / 4, at most spp; the map shows both.
        let adaptive = Settings {
            scene: "caustics".into(),
            adaptive: true,
            spp: 64,
            ..settings()
        };
        let f = render(&adaptive).unwrap();
        let pixels = f64::from(32 * 18);
        assert!(
            f.samples() >= 16.0 * pixels && f.samples() < 64.0 * pixels,
            "{}",
            f.samples()
        );
        let heat = f.heat();
        assert!(heat.chunks(4).any(|c| c != &heat[..4]), "a uniform map");
        // Below the least pilot, the pilot's 8 samples are all there is.
        let few = Settings { spp: 4, ..adaptive };
        assert_eq!(render(&few).unwrap().samples(), 8.0 * pixels);
        for bad in [
            Settings {
                scene: "materials".into(),
                ..settings()
            },
            Settings {
                sampler: "nope".into(),
                ..settings()
            },
            Settings {
                filter: "nope".into(),
                ..settings()
            },
            Settings {
                width: 0,
                ..settings()
            },
            Settings {
                width: 20_000,
                height: 1,
                ..settings()
            },
            Settings {
                width: 4096,
                height: 4096,
                ..settings()
            },
            // Few samples, but more pixels than the module's memory holds.
            Settings {
                width: 8192,
                height: 4096,
                spp: 1,
                ..settings()
            },
            Settings {
                adaptive: true,
                spp: 1 << 20,
                ..settings()
            },
            // The command line's rules: the grid fills its rows in order.
            Settings {
                sampler: "grid".into(),
                adaptive: true,
                spp: 64,
                ..settings()
            },
            Settings {
                spp: 0,
                ..settings()
            },
            Settings {
                width: 1024,
                height: 1024,
                spp: 257,
                ..settings()
            },
        ] {
            assert!(render(&bad).is_err(), "{bad:?}");
        }
    }

    /// The periodogram is the runner's, for the projection asked for.
    #[test]
    fn periodograms_are_the_runners() {
        let p = periodogram("sobol", 64, 2, [2, 3], 20, 12).unwrap();
        let s =
            spectrum::spectrum_of_dims(SamplerKind::Sobol, 64, 2, 20, 12, [2, 3], &|_| {}).unwrap();
        assert_eq!(p.r(), 12);
        assert_eq!(
            p.power(),
            s.power.iter().map(|&v| v as f32).collect::<Vec<_>>()
        );
        assert_eq!(p.radial().len(), 12);
        assert_eq!(p.radial()[5], s.radial()[5].1 as f32);
        for (kind, n, dims, pixels, r) in [
            ("nope", 4, [0, 1], 4, 8),
            ("sobol", 0, [0, 1], 4, 8),
            ("sobol", MAX_POINTS + 1, [0, 1], 4, 8),
            ("sobol", 4, [1, 1], 4, 8),
            ("sobol", 4, [0, 64], 4, 8),
            ("sobol", 4, [0, 1], 0, 8),
            ("sobol", 4, [0, 1], MAX_SPECTRUM_PIXELS + 1, 8),
            ("sobol", 4, [0, 1], 4, 0),
            ("sobol", 4, [0, 1], 4, 129),
            // Each in range, too much work together.
            ("sobol", MAX_POINTS, [0, 1], MAX_SPECTRUM_PIXELS, 128),
            ("sobol", MAX_POINTS, [62, 63], MAX_SPECTRUM_PIXELS, 1),
        ] {
            assert!(
                periodogram(kind, n, 1, dims, pixels, r).is_err(),
                "{kind} {n} {dims:?} {pixels} {r}"
            );
        }
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
