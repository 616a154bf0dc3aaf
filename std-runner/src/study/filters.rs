//! The reconstruction study (`strata filters`): every pixel filter against
//! the box at equal time.
//!
//! For each filter and spp, `seeds` renders of the whole image (seeds 0,
//! 1, …) are measured against that filter's own reference (Sobol' at the
//! reference spp, cached): RMSE, the share of negative pixels (split by
//! the reference there: a negative pixel where the reference is at least
//! [`CLEAR`] is noise, one where it is below 0 is the filter's own
//! ringing, and one in between is a pixel whose value is about 0, where
//! the reference's sign is itself uncertain), the
//! pixels that fell back to their box mean, and the mean luminance
//! against the box's at the same spp. Cost is a render's wall time
//! ([`crate::job::Rendered::wall`]: its BVH and its tracing, on the
//! view's threads), measured with the renders interleaved, filter by
//! filter within each seed, and again in further rounds: a filter's time
//! against the box's is the median, over seeds and rounds, of its render's
//! time over the box render's of the same seed and round, so a change in
//! the machine's load falls on both alike. The RMSE at equal time gives the
//! box the filter's time, its error falling at its own measured rate
//! ([`Report::against_box`]).

use crate::progress::Phase;
use std::fmt::Write as _;

use anyhow::{Result, bail};
use glam::Vec3;
use strata::render::{PixelFilter, PixelSum};

use super::{View, luminance, rmse};
use crate::film::filter_text;
use crate::job::{Job, SamplerKind, run};

/// A reference value from which a negative pixel counts as noise: 1 % of
/// white, above the reference's own error on the study's scenes.
pub const CLEAR: f32 = 0.01;

/// One filter at one spp, over every seed.
#[derive(Clone, Debug)]
pub struct Row {
    /// The filter.
    pub filter: PixelFilter,
    /// Samples per pixel.
    pub spp: u32,
    /// RMSE against the filter's own reference (root of the mean over
    /// seeds of the squared RMSE).
    pub rmse: f64,
    /// Pixels (over all seeds) with a channel below 0 where the
    /// reference's channel is at least [`CLEAR`]: noise.
    pub negative_noise: u64,
    /// Pixels (over all seeds) with a channel below 0 where the
    /// reference's is in `[0, CLEAR)`, none where it is [`CLEAR`] or more.
    pub negative_near: u64,
    /// Pixels (over all seeds) with a channel below 0 only where the
    /// reference's is too: the filter's ringing.
    pub negative_ringing: u64,
    /// Pixels (over all seeds) whose weights nearly cancelled, so the film
    /// took their box mean ([`PixelSum::falls_back`]).
    pub fallbacks: u64,
    /// Pixels over all seeds.
    pub pixels: u64,
    /// Mean luminance over pixels and seeds.
    pub mean_luminance: f64,
    /// The median wall seconds of one render ([`crate::job::Rendered::wall`]).
    pub seconds: f64,
    /// The median over renders of the time against the box's render of
    /// the same seed and round (NaN where unknown).
    pub time_ratio: f64,
}

/// What [`study`] measured: every filter (the box first) at every spp.
#[derive(Clone, Debug)]
pub struct Report {
    /// Rows by spp, then by filter (the box first).
    pub rows: Vec<Row>,
    /// The references' spp.
    pub reference_spp: u32,
    /// Seeds per row.
    pub seeds: u32,
}

impl Report {
    /// The box's row at `spp`.
    fn box_at(&self, spp: u32) -> Option<&Row> {
        self.rows
            .iter()
            .find(|r| r.spp == spp && r.filter == PixelFilter::BOX)
    }

    /// The box's log–log slope of RMSE against spp at `spp`: from its row
    /// at the next lower spp measured (the next higher for the lowest);
    /// `−½`, independent samples' rate, where only one spp was measured or
    /// an RMSE is 0.
    #[must_use]
    pub fn box_slope(&self, spp: u32) -> f64 {
        let mut boxes: Vec<&Row> = self
            .rows
            .iter()
            .filter(|r| r.filter == PixelFilter::BOX)
            .collect();
        boxes.sort_by_key(|r| r.spp);
        let Some(k) = boxes.iter().position(|r| r.spp == spp) else {
            return -0.5;
        };
        let (a, b) = match k {
            0 if boxes.len() > 1 => (boxes[0], boxes[1]),
            0 => return -0.5,
            k => (boxes[k - 1], boxes[k]),
        };
        let slope = (b.rmse / a.rmse).ln() / (f64::from(b.spp) / f64::from(a.spp)).ln();
        if slope.is_finite() { slope } else { -0.5 }
    }

    /// `(mean luminance − 1, RMSE, time, RMSE at equal time)` as ratios to
    /// the box's at the same spp; each `None` where the box's is 0 or the
    /// time unknown. At equal time the box is given the filter's time `t`
    /// (as a multiple of its own): its RMSE would be `RMSE_box · tˢ`, `s`
    /// its measured slope ([`Report::box_slope`]), so the ratio is `RMSE /
    /// RMSE_box · t⁻ˢ` (`√t` for independent samples; more for Sobol',
    /// whose error falls faster).
    #[must_use]
    pub fn against_box(&self, r: &Row) -> [Option<f64>; 4] {
        let Some(b) = self.box_at(r.spp) else {
            return [None; 4];
        };
        let ratio = |x: f64, y: f64| (y > 0.0).then(|| x / y);
        let e = ratio(r.rmse, b.rmse);
        let t = (r.time_ratio.is_finite() && r.time_ratio > 0.0).then_some(r.time_ratio);
        let s = self.box_slope(r.spp);
        [
            ratio(r.mean_luminance, b.mean_luminance).map(|y| y - 1.0),
            e,
            t,
            e.zip(t).map(|(e, t)| e * t.powf(-s)),
        ]
    }

    /// The table `strata filters` prints.
    #[must_use]
    pub fn table(&self) -> String {
        let mut t = String::new();
        write!(
            t,
            "{} seed(s); each filter against its own reference: sobol {} spp\n\
             {:<22} {:>5} {:>11} {:>27} {:>11} {:>11} {:>9} {:>9} {:>9} {:>12}",
            self.seeds,
            self.reference_spp,
            "filter",
            "spp",
            "RMSE",
            "negative: noise/near 0/ring",
            "fallbacks",
            "mean Y/box",
            "RMSE/box",
            "time/box",
            "wall s",
            "at equal time"
        )
        .ok();
        let share = |n: u64, of: u64| 100.0 * n as f64 / of.max(1) as f64;
        for r in &self.rows {
            let negative = format!(
                "{:.3} / {:.3} / {:.3} %",
                share(r.negative_noise, r.pixels),
                share(r.negative_near, r.pixels),
                share(r.negative_ringing, r.pixels)
            );
            let [y, e, c, eq] = self.against_box(r);
            let na = |x: Option<f64>, f: &dyn Fn(f64) -> String| x.map_or("n/a".into(), f);
            let y = na(y, &|y| format!("{:+.3} %", 100.0 * y));
            let [e, c, eq] = [e, c, eq].map(|x| na(x, &|x| format!("{x:.3}")));
            write!(
                t,
                "\n{:<22} {:>5} {:>11.4e} {:>27} {:>9.3} % {:>11} {:>9} {:>9} {:>9.3} {:>12}",
                short_name(&r.filter),
                r.spp,
                r.rmse,
                negative,
                share(r.fallbacks, r.pixels),
                y,
                e,
                c,
                r.seconds,
                eq
            )
            .ok();
        }
        t
    }

    /// The rows as CSV.
    #[must_use]
    pub fn csv(&self) -> String {
        let mut s = String::from(
            "filter,spp,rmse,negative_noise,negative_near,negative_ringing,fallbacks,pixels,\
             mean_luminance,\
             wall_seconds,time_vs_box,rmse_at_equal_time_vs_box\n",
        );
        for r in &self.rows {
            let eq = self.against_box(r)[3].map_or(String::new(), |eq| format!("{eq}"));
            writeln!(
                s,
                "{},{},{},{},{},{},{},{},{},{},{},{}",
                filter_text(&r.filter),
                r.spp,
                r.rmse,
                r.negative_noise,
                r.negative_near,
                r.negative_ringing,
                r.fallbacks,
                r.pixels,
                r.mean_luminance,
                r.seconds,
                r.time_ratio,
                eq
            )
            .ok();
        }
        s
    }
}

/// A filter's name and radius, for the table.
fn short_name(f: &PixelFilter) -> String {
    format!("{} r={}", f.kind().name(), f.radius())
}

/// The median of `v` (the mean of the middle two for an even count); NaN
/// for none or where any is NaN.
fn median(v: &[f64]) -> f64 {
    if v.is_empty() || v.iter().any(|x| x.is_nan()) {
        return f64::NAN;
    }
    let mut v = v.to_vec();
    v.sort_by(f64::total_cmp);
    let m = v.len() / 2;
    match v.len() % 2 {
        1 => v[m],
        _ => (v[m - 1] + v[m]) / 2.0,
    }
}

/// One render's measures against `reference`: `(squared RMSE, negatives
/// [noise, near 0, ringing], fallbacks, mean luminance)`.
fn measure(pixels: &[PixelSum], reference: &[Vec3]) -> (f64, [u64; 3], u64, f64) {
    let image: Vec<Vec3> = pixels.iter().map(PixelSum::mean).collect();
    let mut negative = [0u64; 3];
    for (v, r) in image.iter().zip(reference) {
        let below = v.cmplt(Vec3::ZERO);
        if (below & r.cmpge(Vec3::splat(CLEAR))).any() {
            negative[0] += 1;
        } else if (below & r.cmpge(Vec3::ZERO)).any() {
            negative[1] += 1;
        } else if below.any() {
            negative[2] += 1;
        }
    }
    let fallbacks = pixels.iter().filter(|p| p.falls_back()).count() as u64;
    let y = image.iter().map(|&v| luminance(v)).sum::<f64>() / image.len() as f64;
    (rmse(&image, reference).powi(2), negative, fallbacks, y)
}

/// How much the study renders.
#[derive(Clone, Debug)]
pub struct Settings {
    /// The spp measured.
    pub spps: Vec<u32>,
    /// Seeds per row.
    pub seeds: u32,
    /// Times every render is timed (the first also measures its error).
    pub rounds: u32,
    /// The references' spp.
    pub reference_spp: u32,
}

/// Runs the study of `filters` (the box is added first if missing) as
/// `settings` say: every spp, every seed, against references at the
/// reference spp, each render timed `rounds` times; `say` gets progress
/// lines. The view's window must be the whole image (a splatted filter's
/// window render also holds its border).
pub fn study(
    view: &View<'_>,
    sampler: SamplerKind,
    filters: &[PixelFilter],
    settings: &Settings,
    cache_dir: &std::path::Path,
    say: &dyn Fn(&str),
) -> Result<Report> {
    let Settings {
        ref spps,
        seeds,
        rounds,
        reference_spp,
    } = *settings;
    if seeds == 0 || rounds == 0 || spps.is_empty() {
        bail!("the study needs at least one seed, one round and one spp");
    }
    if view.window.x0 != 0
        || view.window.y0 != 0
        || view.window.width != view.width
        || view.window.height != view.height
    {
        bail!("the filter study measures whole images");
    }
    let mut all = vec![PixelFilter::BOX];
    all.extend(filters.iter().copied().filter(|&f| f != PixelFilter::BOX));
    let views: Vec<View<'_>> = all
        .iter()
        .map(|&filter| View {
            filter,
            ..view.clone()
        })
        .collect();
    let mut references = Vec::with_capacity(all.len());
    for v in &views {
        let (r, cached) = super::reference(v, reference_spp, cache_dir)?;
        say(&format!(
            "reference {}: sobol {reference_spp} spp{}",
            filter_text(&v.filter),
            if cached { " (cached)" } else { "" }
        ));
        references.push(r);
    }
    let mut rows = Vec::new();
    for &spp in spps.iter() {
        let phase = Phase::start(
            &format!(
                "{spp} spp: {} filters, {seeds} seed(s), {rounds} round(s)",
                all.len()
            ),
            (rounds * seeds) as u64 * all.len() as u64 * view.window.area() as u64,
        );
        let render = |v: &View<'_>, seed: u64| {
            let job = Job {
                window: v.window,
                max_depth: v.max_depth,
                sampler,
                seed,
                threads: v.threads,
                texture_filter: v.texture_filter,
                filter: v.filter,
                ..Job::new(v.scene, v.width, v.height, spp)
            };
            run(&job, &|n| phase.inc(n))
        };
        // Per filter: summed squared RMSE, negatives, fallbacks and
        // luminance over seeds, and every render's seconds; the filters
        // interleaved in each seed and round (later rounds only time).
        let mut sums = vec![(0.0, [0u64; 3], 0u64, 0.0); all.len()];
        let mut times = vec![Vec::new(); all.len()];
        for round in 0..rounds {
            for seed in 0..seeds as u64 {
                for (k, (v, reference)) in views.iter().zip(&references).enumerate() {
                    let done = render(v, seed)?;
                    times[k].push(done.wall.as_secs_f64());
                    if round > 0 {
                        continue;
                    }
                    let (e2, negative, fallbacks, y) = measure(&done.pixels, reference);
                    let sum = &mut sums[k];
                    sum.0 += e2;
                    for (a, b) in sum.1.iter_mut().zip(negative) {
                        *a += b;
                    }
                    sum.2 += fallbacks;
                    sum.3 += y;
                }
            }
        }
        let n = seeds as f64;
        for (k, (&filter, s)) in all.iter().zip(&sums).enumerate() {
            let ratios: Vec<f64> = times[k].iter().zip(&times[0]).map(|(t, b)| t / b).collect();
            rows.push(Row {
                filter,
                spp,
                rmse: (s.0 / n).sqrt(),
                negative_noise: s.1[0],
                negative_near: s.1[1],
                negative_ringing: s.1[2],
                fallbacks: s.2,
                pixels: seeds as u64 * view.window.area() as u64,
                mean_luminance: s.3 / n,
                seconds: median(&times[k]),
                time_ratio: median(&ratios),
            });
        }
        phase.finish();
        say(&format!("{spp} spp: done"));
    }
    Ok(Report {
        rows,
        reference_spp,
        seeds,
    })
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn negatives_are_split_by_the_reference_sign() {
        let px = |v: Vec3| {
            let mut p = PixelSum::ZERO;
            p.add_weighted(v, 1.0);
            p
        };
        let pixels = [
            px(Vec3::new(-0.1, 0.5, 0.5)), // noise: the reference's red is ≥ CLEAR
            px(Vec3::new(-0.1, 0.5, 0.5)), // ringing: the reference's red is < 0
            px(Vec3::new(0.5, -0.1, 0.5)), // near 0: the reference's green
            px(Vec3::splat(0.5)),
        ];
        let reference = [
            Vec3::splat(0.5),
            Vec3::new(-0.2, 0.5, 0.5),
            Vec3::new(0.5, 0.005, 0.5),
            Vec3::splat(0.5),
        ];
        let (e2, negative, fallbacks, _) = measure(&pixels, &reference);
        assert_eq!((negative, fallbacks), ([1, 1, 1], 0));
        let want = (0.6f64.powi(2) + 0.1f64.powi(2) + 0.105f64.powi(2)) / 12.0;
        assert!((e2 - want).abs() < 1e-7, "{e2} {want}"); // f32 inputs
    }

    #[test]
    fn equal_time_gives_the_box_the_time_at_its_measured_rate() {
        let row = |filter, rmse, seconds| Row {
            filter,
            spp: 4,
            rmse,
            negative_noise: 0,
            negative_near: 0,
            negative_ringing: 0,
            fallbacks: 0,
            pixels: 1,
            mean_luminance: 1.0,
            seconds,
            time_ratio: seconds,
        };
        let lanczos = PixelFilter::new(strata::filter::FilterKind::Lanczos { tau: 3.0 }, 3.0)
            .expect("lanczos");
        let report = Report {
            rows: vec![row(PixelFilter::BOX, 0.1, 1.0), row(lanczos, 0.1, 4.0)],
            reference_spp: 64,
            seeds: 1,
        };
        let [y, e, t, eq] = report.against_box(&report.rows[1]);
        assert_eq!((y, e, t), (Some(0.0), Some(1.0), Some(4.0)));
        // Four times the time: the box's error would halve.
        assert!((eq.unwrap() - 2.0).abs() < 1e-12);
        // An unknown time ratio leaves out only what needs it.
        let mut unknown = report.clone();
        unknown.rows[1].time_ratio = f64::NAN;
        assert_eq!(unknown.against_box(&unknown.rows[1])[1], Some(1.0));
        assert_eq!(unknown.against_box(&unknown.rows[1])[3], None);
        assert!(report.table().contains("lanczos"));
        assert_eq!(report.csv().lines().count(), 3);
        // With the box also at 16 spp, its error falling as spp^-0.75, the
        // box given four times the time gains 4^0.75 at 4 and at 16 spp.
        let mut two = report.clone();
        let at16 = |mut r: Row, rmse: f64| {
            r.spp = 16;
            r.rmse = rmse;
            r
        };
        two.rows
            .push(at16(two.rows[0].clone(), 0.1 * 4f64.powf(-0.75)));
        two.rows
            .push(at16(two.rows[1].clone(), 0.1 * 4f64.powf(-0.75)));
        assert!((two.box_slope(4) + 0.75).abs() < 1e-12);
        assert!((two.box_slope(16) + 0.75).abs() < 1e-12);
        for r in &two.rows[2..] {
            let eq = two.against_box(r)[3].unwrap();
            let want = if r.filter == PixelFilter::BOX {
                1.0
            } else {
                4f64.powf(0.75)
            };
            assert!((eq - want).abs() < 1e-12, "{eq}");
        }
    }
}
