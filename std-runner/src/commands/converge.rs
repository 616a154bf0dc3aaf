//! `strata converge`: RMSE against spp for every sampler, against a cached
//! high-spp reference, as a CSV, a log–log plot and fitted slopes.

use std::path::PathBuf;
use std::time::Instant;

use anyhow::{Result, bail};
use strata::render::{TextureFilter, Tile};

use crate::cli::ConvergeArgs;
use crate::commands::output::write_text;
use crate::commands::{
    check_output_ext, check_pixels, height_for, resolve_scene, samplers_or_all, window_of,
};
use crate::image_io::say;
use crate::plot;
use crate::render::SamplerKind;
use crate::scenes::SceneData;
use crate::study::{self, Point, View};

/// The plot's size in pixels.
const PLOT_SIZE: (u32, u32) = (800, 560);

/// Runs `strata converge`: the plan (every check), the reference, the
/// measured points, the files, the table.
pub fn converge(args: &ConvergeArgs) -> Result<()> {
    let scene = resolve_scene(&args.scene)?;
    let plan = args.plan(&scene)?;
    let view = &plan.view;
    let started = Instant::now();
    let (reference, cached) = study::reference(view, args.reference_spp, &plan.cache_dir)?;
    let w = view.window;
    say(&format!(
        "{}: {}x{} crop at ({}, {}) of {}x{}, depth {}; reference: sobol {} spp, {}",
        scene.name,
        w.width,
        w.height,
        w.x0,
        w.y0,
        view.width,
        view.height,
        view.max_depth,
        args.reference_spp,
        if cached {
            "cached".to_string()
        } else {
            format!("rendered in {:.1} s", started.elapsed().as_secs_f64())
        }
    ));
    let points = study::converge(
        view,
        &plan.samplers,
        &plan.spps,
        args.seeds,
        &reference,
        &|_| {},
    )?;
    plan.write(&points)?;
    say(&study::table(&points, &plan.samplers, &plan.spps));
    say(&format!(
        "wrote {} and {}",
        plan.csv.display(),
        plan.plot.display()
    ));
    Ok(())
}

/// `strata converge` with every flag checked.
struct ConvergePlan<'a> {
    /// The scene, size and crop measured.
    view: View<'a>,
    /// The spp of the measured points.
    spps: Vec<u32>,
    /// The samplers measured, in order.
    samplers: Vec<SamplerKind>,
    /// The CSV written.
    csv: PathBuf,
    /// The plot written.
    plot: PathBuf,
    /// Where the reference is cached.
    cache_dir: PathBuf,
}

impl ConvergeArgs {
    /// Checks every flag against `scene`: the size and crop, the spp
    /// list against the reference, the files.
    fn plan<'a>(&self, scene: &'a SceneData) -> Result<ConvergePlan<'a>> {
        let width = self.width.unwrap_or(scene.defaults.width);
        let height = height_for(scene, width, None)?;
        check_pixels(width, height, 1)?;
        let window = match self.pixel_bounds {
            Some(b) => window_of(b, width, height)?,
            None => Tile {
                x0: width / 4,
                y0: height / 4,
                width: (width / 2).max(1),
                height: (height / 2).max(1),
            },
        };
        let mut spps = vec![1u32, 4, 16, 64, 256];
        if self.with_1024 {
            spps.push(1024);
        }
        let top = *spps.last().expect("spp list");
        // The reference's own error adds to every measured point: at 16
        // times the largest spp it adds at most about 3 % to the last
        // point's RMSE.
        if self.reference_spp < 16 * top {
            bail!(
                "--reference-spp {} must be at least 16 x {top} (the largest measured spp)",
                self.reference_spp
            );
        }
        let named = |flag: &Option<PathBuf>, ext: &str| {
            flag.clone()
                .unwrap_or_else(|| PathBuf::from(format!("converge-{}.{ext}", scene.name)))
        };
        let (csv, plot) = (named(&self.csv, "csv"), named(&self.plot, "png"));
        check_output_ext(&csv, "csv", "--csv")?;
        check_output_ext(&plot, "png", "--plot")?;
        Ok(ConvergePlan {
            view: View {
                scene,
                width,
                height,
                window,
                max_depth: self.max_depth.unwrap_or(scene.defaults.max_depth),
                threads: self.threads as usize,
                texture_filter: TextureFilter::None,
            },
            spps,
            samplers: samplers_or_all(&self.samplers),
            csv,
            plot,
            cache_dir: self
                .cache_dir
                .clone()
                .unwrap_or_else(study::default_cache_dir),
        })
    }
}

impl ConvergePlan<'_> {
    /// Writes the plot and the CSV of `points`: both files or neither.
    fn write(&self, points: &[Point]) -> Result<()> {
        let w = self.view.window;
        let title = format!(
            "{}: RMSE of a {}x{} crop vs spp",
            self.view.scene.name, w.width, w.height
        );
        let (pw, ph) = PLOT_SIZE;
        let image = study::plot_convergence(points, &self.samplers, &title, pw, ph)?;
        let text = study::csv(points);
        plot::write_png(&self.plot, &image, pw, ph)?;
        if let Err(e) = write_text(&self.csv, &text) {
            std::fs::remove_file(&self.plot).ok();
            return Err(e);
        }
        Ok(())
    }
}
