//! The equal-cost study of adaptive sampling (`strata adaptive`):
//! adaptive renders against uniform ones of the same cost.
//!
//! Each seed renders the view adaptively; the mean samples per pixel set
//! the reference (Sobol' at 64 times that, rounded up to a power of two)
//! and the uniform ladder (powers of two, widened until it brackets the
//! adaptive cost). Cost is counted two ways, rays traced (closest-hit and
//! shadow) and CPU seconds of the process. The CPU seconds come from a
//! second pass that renders the adaptive view and every ladder rung in
//! turn, seed by seed (A, U₁, U₂, …, A, U₁, …), so a change in the
//! machine's load falls on all of them alike; the first pass runs each
//! row's seeds back to back and only chooses the ladder (should the second
//! pass's times fall outside it, the CPU-seconds ratio reads n/a). The
//! uniform RMSE and relMSE are interpolated log–log between the two ladder
//! points around the
//! adaptive run's cost. Bias is the adaptive image's mean luminance
//! against the reference's, with its standard error over seeds (which
//! leaves out the reference's own error, shared by every seed: at 64
//! times the spp it adds about `1/√64` of one seed's).

use crate::progress::Phase;
use std::fmt::Write as _;

use anyhow::{Result, bail};
use glam::Vec3;
use strata::render::Adaptive;

use super::{View, luminance};
use crate::bench::harness::process_cpu_seconds;
use crate::job::{Job, SamplerKind, run};
use crate::limits::MAX_STUDY_SPP;

/// The ε of relMSE, `(x − r)² / (r² + ε)`.
pub const REL_EPSILON: f64 = 0.01;

/// How many times the adaptive mean spp the reference takes.
pub const REFERENCE_FACTOR: f64 = 64.0;

/// The relative MSE over pixels and channels: `(x − r)² / (r² + ε)`.
///
/// # Panics
/// If the slices differ in length or are empty.
#[must_use]
pub fn rel_mse(image: &[Vec3], reference: &[Vec3]) -> f64 {
    assert_eq!(image.len(), reference.len());
    assert!(!image.is_empty());
    let sum: f64 = image
        .iter()
        .zip(reference)
        .map(|(a, b)| {
            let (a, b) = (a.as_dvec3(), b.as_dvec3());
            let d = a - b;
            (d * d / (b * b + REL_EPSILON)).element_sum()
        })
        .sum();
    sum / (3 * image.len()) as f64
}

/// One render of the study, errors not yet measured.
struct Render {
    image: Vec<Vec3>,
    /// Closest-hit plus shadow rays.
    rays: u64,
    /// Pixel samples.
    paths: u64,
    /// CPU seconds of the process while it ran (all threads).
    cpu: f64,
}

/// A row of the study: one setting averaged over seeds.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Row {
    /// `None` for the adaptive renders, else the uniform spp.
    pub uniform_spp: Option<u32>,
    /// Mean samples per pixel.
    pub spp: f64,
    /// Mean rays per pixel.
    pub rays: f64,
    /// Mean CPU seconds per render.
    pub cpu: f64,
    /// Root of the mean over seeds of the MSE.
    pub rmse: f64,
    /// Mean over seeds of the relMSE.
    pub rel_mse: f64,
}

impl Row {
    /// `adaptive`, or `uniform` and the spp joined by `sep`.
    fn name(&self, sep: &str) -> String {
        match self.uniform_spp {
            None => "adaptive".to_string(),
            Some(n) => format!("uniform{sep}{n}"),
        }
    }
}

/// The study's result.
#[derive(Clone, Debug)]
pub struct Report {
    /// The adaptive row.
    pub adaptive: Row,
    /// The uniform ladder, by spp.
    pub uniform: Vec<Row>,
    /// The reference's spp.
    pub reference_spp: u32,
    /// Adaptive mean luminance over the reference's, minus 1.
    pub bias: f64,
    /// The standard error of `bias` over seeds.
    pub bias_se: f64,
    /// Seeds per row.
    pub seeds: u32,
}

/// Uniform `(rmse, rel_mse)` interpolated log–log at `cost`, from the two
/// ladder rows around it by `cost_of`; `None` if the ladder does not
/// bracket it or a cost is not positive (CPU time unknown).
#[must_use]
pub fn at_cost(rows: &[Row], cost: f64, cost_of: fn(&Row) -> f64) -> Option<(f64, f64)> {
    let positive = |c: f64| c.is_finite() && c > 0.0;
    if !positive(cost) || !rows.iter().all(|r| positive(cost_of(r))) {
        return None;
    }
    let mut sorted: Vec<&Row> = rows.iter().collect();
    sorted.sort_by(|a, b| cost_of(a).total_cmp(&cost_of(b)));
    let pair = sorted
        .windows(2)
        .find(|w| cost_of(w[0]) <= cost && cost <= cost_of(w[1]))?;
    let (a, b) = (pair[0], pair[1]);
    let (ca, cb) = (cost_of(a).ln(), cost_of(b).ln());
    let t = if cb > ca {
        (cost.ln() - ca) / (cb - ca)
    } else {
        0.0
    };
    let lerp = |x: f64, y: f64| (x.ln() + t * (y.ln() - x.ln())).exp();
    Some((lerp(a.rmse, b.rmse), lerp(a.rel_mse, b.rel_mse)))
}

impl Report {
    /// The table `strata adaptive` prints.
    #[must_use]
    pub fn table(&self) -> String {
        let mut t = format!(
            "{} seed(s); reference: sobol {} spp\n{:<14} {:>9} {:>10} {:>9} {:>11} {:>11}",
            self.seeds, self.reference_spp, "run", "spp/px", "rays/px", "CPU s", "RMSE", "relMSE"
        );
        for r in std::iter::once(&self.adaptive).chain(&self.uniform) {
            let name = r.name(" ");
            write!(
                t,
                "\n{name:<14} {:>9.2} {:>10.1} {:>9.2} {:>11.4e} {:>11.4e}",
                r.spp, r.rays, r.cpu, r.rmse, r.rel_mse
            )
            .ok();
        }
        let a = &self.adaptive;
        for (what, cost, of) in [
            ("rays", a.rays, (|r: &Row| r.rays) as fn(&Row) -> f64),
            ("CPU seconds", a.cpu, |r: &Row| r.cpu),
        ] {
            match at_cost(&self.uniform, cost, of) {
                Some((rmse, rel)) => write!(
                    t,
                    "\nat equal {what}: uniform RMSE {rmse:.4e}, relMSE {rel:.4e}; \
                     adaptive/uniform RMSE {:.3}, relMSE {:.3}",
                    a.rmse / rmse,
                    a.rel_mse / rel
                ),
                None => write!(
                    t,
                    "\nat equal {what}: n/a (the uniform ladder does not bracket it, or the cost \
                     is unknown)"
                ),
            }
            .ok();
        }
        match (self.bias.is_finite(), self.bias_se.is_finite()) {
            (true, true) => write!(
                t,
                "\nbias: adaptive mean luminance {:+.3} % ± {:.3} % (1 s.e.) of the reference's",
                100.0 * self.bias,
                100.0 * self.bias_se
            ),
            (true, false) => write!(
                t,
                "\nbias: adaptive mean luminance {:+.3} % of the reference's (one seed: no \
                 standard error)",
                100.0 * self.bias
            ),
            _ => write!(t, "\nbias: n/a (the reference is black)"),
        }
        .ok();
        t
    }

    /// The rows as CSV: `run,spp,rays_per_pixel,cpu_seconds,rmse,rel_mse`.
    #[must_use]
    pub fn csv(&self) -> String {
        let mut s = String::from("run,spp,rays_per_pixel,cpu_seconds,rmse,rel_mse\n");
        for r in std::iter::once(&self.adaptive).chain(&self.uniform) {
            let name = r.name("");
            writeln!(
                s,
                "{name},{},{},{},{},{}",
                r.spp, r.rays, r.cpu, r.rmse, r.rel_mse
            )
            .ok();
        }
        s
    }
}

/// Renders `view` once with `sampler` and `seed`, adaptively or at a
/// uniform `spp`, counting its pixels into `phase`.
fn render_once(
    view: &View<'_>,
    sampler: SamplerKind,
    seed: u64,
    adaptive: Option<Adaptive>,
    spp: u32,
    phase: &Phase,
) -> Result<Render> {
    let spp = adaptive.map_or(spp, |a| a.max());
    let job = Job {
        window: view.window,
        max_depth: view.max_depth,
        sampler,
        seed,
        threads: view.threads,
        texture_filter: view.texture_filter,
        adaptive,
        ..Job::new(view.scene, view.width, view.height, spp)
    };
    let before = process_cpu_seconds().unwrap_or(0.0);
    let done = run(&job, &|n| phase.inc(n))?;
    let cpu = process_cpu_seconds().unwrap_or(0.0) - before;
    Ok(Render {
        image: done.pixels.iter().map(|p| p.mean()).collect(),
        rays: done.stats.rays + done.stats.shadow_rays,
        paths: done.stats.paths,
        cpu,
    })
}

/// The row of `renders` (one per seed) against `reference`.
fn row(uniform_spp: Option<u32>, renders: &[Render], reference: &[Vec3]) -> Row {
    let n = renders.len() as f64;
    let px = reference.len() as f64;
    let mean = |f: &dyn Fn(&Render) -> f64| renders.iter().map(f).sum::<f64>() / n;
    Row {
        uniform_spp,
        spp: mean(&|r| r.paths as f64) / px,
        rays: mean(&|r| r.rays as f64) / px,
        cpu: mean(&|r| r.cpu),
        rmse: mean(&|r| super::rmse(&r.image, reference).powi(2)).sqrt(),
        rel_mse: mean(&|r| rel_mse(&r.image, reference)),
    }
}

/// Runs the study: `seeds` adaptive renders of `view` with `adaptive`,
/// the reference, and the uniform ladder; `say` gets progress lines.
pub fn study(
    view: &View<'_>,
    sampler: SamplerKind,
    adaptive: Adaptive,
    seeds: u32,
    cache_dir: &std::path::Path,
    say: &dyn Fn(&str),
) -> Result<Report> {
    if seeds == 0 {
        bail!("the study needs at least one seed");
    }
    let area = view.window.area() as u64;
    let phase = Phase::start(&format!("adaptive: {seeds} render(s)"), seeds as u64 * area);
    let adaptive_runs = (0..seeds)
        .map(|s| render_once(view, sampler, s as u64, Some(adaptive), 0, &phase))
        .collect::<Result<Vec<_>>>()?;
    phase.finish();
    let px = view.window.area() as f64;
    let mean_spp = adaptive_runs.iter().map(|r| r.paths as f64).sum::<f64>() / (seeds as f64 * px);
    let wanted = (REFERENCE_FACTOR * mean_spp).ceil();
    if wanted > MAX_STUDY_SPP as f64 {
        bail!(
            "the reference would need {wanted} spp (64 times the adaptive mean of {mean_spp:.1}), \
             above {MAX_STUDY_SPP}: lower --max-spp or raise --threshold"
        );
    }
    let reference_spp = (wanted as u32).next_power_of_two();
    say(&format!(
        "adaptive: {mean_spp:.2} samples per pixel on average; reference: sobol {reference_spp} spp"
    ));
    let (reference, _) = super::reference(view, reference_spp, cache_dir)?;
    let mut adaptive_row = row(None, &adaptive_runs, &reference);
    let mean_luma = |imgs: &[&[Vec3]]| -> Vec<f64> {
        imgs.iter()
            .map(|i| i.iter().map(|&v| luminance(v)).sum::<f64>() / px)
            .collect()
    };
    let reference_luma = mean_luma(&[&reference])[0];
    let per_seed: Vec<f64> = mean_luma(
        &adaptive_runs
            .iter()
            .map(|r| r.image.as_slice())
            .collect::<Vec<_>>(),
    )
    .into_iter()
    .map(|l| l / reference_luma - 1.0)
    .collect();
    drop(adaptive_runs);
    let n = per_seed.len() as f64;
    let bias = per_seed.iter().sum::<f64>() / n;
    let bias_se = if per_seed.len() > 1 {
        (per_seed.iter().map(|b| (b - bias).powi(2)).sum::<f64>() / (n - 1.0) / n).sqrt()
    } else {
        f64::NAN
    };
    // The ladder: powers of two around the mean spp, widened until both
    // costs are bracketed.
    let mut uniform: Vec<Row> = Vec::new();
    let mut spp = (mean_spp / 2.0).max(1.0).floor() as u32;
    spp = 1 << (31 - spp.leading_zeros());
    let limit = adaptive
        .max()
        .max(2 * mean_spp.ceil() as u32)
        .next_power_of_two()
        * 4;
    loop {
        if !uniform.iter().any(|r| r.uniform_spp == Some(spp)) {
            let phase = Phase::start(
                &format!("uniform {spp} spp: {seeds} render(s)"),
                seeds as u64 * area,
            );
            let runs = (0..seeds)
                .map(|s| render_once(view, sampler, s as u64, None, spp, &phase))
                .collect::<Result<Vec<_>>>()?;
            phase.finish();
            let r = row(Some(spp), &runs, &reference);
            say(&format!(
                "uniform {spp}: RMSE {:.4e}, {:.1} rays/px, {:.2} CPU s",
                r.rmse, r.rays, r.cpu
            ));
            uniform.push(r);
            uniform.sort_by_key(|r| r.uniform_spp);
        }
        let (lo, hi) = (&uniform[0], &uniform[uniform.len() - 1]);
        let (lo_spp, hi_spp) = (lo.uniform_spp.unwrap_or(1), hi.uniform_spp.unwrap_or(1));
        let below = lo.rays > adaptive_row.rays || lo.cpu > adaptive_row.cpu;
        let above = hi.rays < adaptive_row.rays || hi.cpu < adaptive_row.cpu;
        spp = if below && lo_spp > 1 {
            lo_spp / 2
        } else if (above || uniform.len() < 2) && hi_spp < limit {
            hi_spp * 2
        } else {
            break;
        };
    }
    // The CPU seconds, interleaved (see the module docs); the images are
    // those of the first pass (the same bits).
    say("CPU seconds: the adaptive render and the ladder again, interleaved seed by seed");
    let mut cpu = vec![0.0; uniform.len() + 1];
    let phase = Phase::start(
        &format!("CPU seconds: {} render(s)", seeds as usize * cpu.len()),
        (seeds as usize * cpu.len()) as u64 * area,
    );
    for s in 0..seeds {
        cpu[0] += render_once(view, sampler, s as u64, Some(adaptive), 0, &phase)?.cpu;
        for (c, r) in cpu[1..].iter_mut().zip(&uniform) {
            let spp = r.uniform_spp.unwrap_or(1);
            *c += render_once(view, sampler, s as u64, None, spp, &phase)?.cpu;
        }
    }
    phase.finish();
    adaptive_row.cpu = cpu[0] / seeds as f64;
    for (r, c) in uniform.iter_mut().zip(&cpu[1..]) {
        r.cpu = c / seeds as f64;
    }
    Ok(Report {
        adaptive: adaptive_row,
        uniform,
        reference_spp,
        bias,
        bias_se,
        seeds,
    })
}

#[cfg(test)]
mod tests {
    use super::*;

    fn r(spp: u32, rays: f64, rmse: f64) -> Row {
        Row {
            uniform_spp: Some(spp),
            spp: spp as f64,
            rays,
            cpu: rays / 100.0,
            rmse,
            rel_mse: rmse * rmse,
        }
    }

    #[test]
    fn equal_cost_interpolates_log_log_between_brackets() {
        // RMSE ∝ cost^-1/2: interpolation in log–log is exact.
        let rows = [
            r(4, 40.0, 0.4),
            r(16, 160.0, 0.2),
            r(8, 80.0, 0.4 / 2f64.sqrt()),
        ];
        let (rmse, rel) = at_cost(&rows, 100.0, |r| r.rays).unwrap();
        assert!(
            (rmse - 0.4 * (40.0f64 / 100.0).sqrt()).abs() < 1e-12,
            "{rmse}"
        );
        assert!((rel - 0.16 * 0.4).abs() < 1e-12, "{rel}");
        assert!(at_cost(&rows, 39.0, |r| r.rays).is_none());
        assert!(at_cost(&rows, 161.0, |r| r.rays).is_none());
        // Unknown CPU time (0) is not a cost.
        assert!(at_cost(&rows, 0.0, |r| r.rays).is_none());
        let mut unknown = rows;
        unknown[1].cpu = 0.0;
        assert!(at_cost(&unknown, 1.0, |r| r.cpu).is_none());
    }

    #[test]
    fn rel_mse_divides_by_the_reference_squared_plus_epsilon() {
        let reference = [Vec3::splat(1.0), Vec3::ZERO];
        let image = [Vec3::splat(2.0), Vec3::splat(0.1)];
        let want = (1.0 / (1.0 + REL_EPSILON) + 0.01 / REL_EPSILON) / 2.0;
        assert!((rel_mse(&image, &reference) - want).abs() < 1e-6);
    }
}
