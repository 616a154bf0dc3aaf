//! A χ² goodness-of-fit harness for warps, in the spirit of Mitsuba 3's
//! `ChiSquareTest`: histogram `n` samples over a grid on the domain,
//! integrate the claimed pdf over each cell for the expected counts, pool
//! cells expected below 5, and compare the statistic with the χ²
//! distribution.
//!
//! Verdicts:
//! - a sample outside the domain, or with a negative or non-finite pdf,
//!   fails outright;
//! - samples where the pdf is exactly 0 may only lie on a boundary of
//!   measure zero (a cosine lobe's rim): more than one in 10⁵ fails;
//! - otherwise the p-value must exceed the per-test level after a Šidák
//!   correction: `1 − (1 − α)^(1/k)` for `k` tests in the suite.
//!
//! On failure the observed and expected tables are written as CSV under
//! `target/tmp/chi2/` for plotting.

use std::f64::consts::{PI, TAU};

/// The suite-wide significance level.
pub const ALPHA: f64 = 0.01;

/// Where samples live and how the grid is laid over them. Points are
/// `[f64; 3]`; 2D domains use `[x, y, 0]`, the line `[x, 0, 0]`.
#[derive(Clone, Copy, Debug)]
pub enum Domain {
    /// Directions with `z ∈ [z_min, z_max]`, gridded over `(z, φ)`; the
    /// measure `dz dφ` is solid angle. `z_min = -1, z_max = 1` is the sphere.
    Sphere { z_min: f64, z_max: f64 },
    /// The closed unit disk, gridded over `(r², φ)`: equal-area cells.
    Disk,
    /// The rectangle `[x0, x1) × [y0, y1)`.
    Rect { x0: f64, x1: f64, y0: f64, y1: f64 },
    /// The interval `[x0, x1)`: a 1D grid (the second resolution is 1).
    Line { x0: f64, x1: f64 },
}

impl Domain {
    pub const SPHERE: Domain = Domain::Sphere {
        z_min: -1.0,
        z_max: 1.0,
    };
    pub const HEMISPHERE: Domain = Domain::Sphere {
        z_min: 0.0,
        z_max: 1.0,
    };
    pub const UNIT_SQUARE: Domain = Domain::Rect {
        x0: 0.0,
        x1: 1.0,
        y0: 0.0,
        y1: 1.0,
    };

    /// The cell parameters `(a, b) ∈ [0, 1)²` of a point, or `None` when it
    /// lies outside the domain.
    fn params(&self, p: [f64; 3]) -> Option<(f64, f64)> {
        let inside = |t: f64| (0.0..1.0).contains(&t);
        let phi = |x: f64, y: f64| {
            let a = y.atan2(x);
            (if a < 0.0 { a + TAU } else { a }) / TAU
        };
        let (a, b) = match *self {
            Domain::Sphere { z_min, z_max } => {
                let len = (p[0] * p[0] + p[1] * p[1] + p[2] * p[2]).sqrt();
                if (len - 1.0).abs() > 1e-4 || p[2] < z_min || p[2] > z_max {
                    return None;
                }
                // z = z_max lands in the last cell, not outside.
                let a = ((p[2] - z_min) / (z_max - z_min)).min(1.0 - 1e-12);
                (a, phi(p[0], p[1]).min(1.0 - 1e-12))
            }
            Domain::Disk => {
                let r2 = p[0] * p[0] + p[1] * p[1];
                // Maps may round a hair past the rim (see pdf_concentric_disk).
                if r2 > 1.0 + 1e-6 {
                    return None;
                }
                (r2.min(1.0 - 1e-12), phi(p[0], p[1]).min(1.0 - 1e-12))
            }
            Domain::Rect { x0, x1, y0, y1 } => ((p[0] - x0) / (x1 - x0), (p[1] - y0) / (y1 - y0)),
            Domain::Line { x0, x1 } => ((p[0] - x0) / (x1 - x0), 0.0),
        };
        (inside(a) && inside(b)).then_some((a, b))
    }

    /// The point at cell parameters `(a, b)` and the Jacobian that turns
    /// `da db` into the domain's measure.
    fn point(&self, a: f64, b: f64) -> ([f64; 3], f64) {
        match *self {
            Domain::Sphere { z_min, z_max } => {
                let z = z_min + a * (z_max - z_min);
                let r = (1.0 - z * z).max(0.0).sqrt();
                let phi = b * TAU;
                ([r * phi.cos(), r * phi.sin(), z], (z_max - z_min) * TAU)
            }
            Domain::Disk => {
                // s = r², dA = r dr dφ = ½ ds dφ.
                let r = a.sqrt();
                let phi = b * TAU;
                ([r * phi.cos(), r * phi.sin(), 0.0], 0.5 * TAU)
            }
            Domain::Rect { x0, x1, y0, y1 } => (
                [x0 + a * (x1 - x0), y0 + b * (y1 - y0), 0.0],
                (x1 - x0) * (y1 - y0),
            ),
            Domain::Line { x0, x1 } => ([x0 + a * (x1 - x0), 0.0, 0.0], x1 - x0),
        }
    }
}

/// One χ² test: a sampler, the pdf it claims, and the grid.
pub struct Chi2<'a> {
    pub name: &'a str,
    pub domain: Domain,
    /// Cells along the first and second parameter. Odd counts keep cell
    /// edges off symmetry lines.
    pub res: (usize, usize),
    pub samples: usize,
    /// Midpoint-rule points per cell and axis for integrating the pdf.
    pub ires: usize,
    /// How many χ² tests share the suite's α (Šidák).
    pub test_count: usize,
}

/// What a run found.
#[derive(Debug)]
pub struct Outcome {
    pub name: String,
    /// Samples outside the domain, or with a negative or non-finite pdf.
    pub impossible: usize,
    /// Samples where the pdf is exactly 0.
    pub zero_density: usize,
    /// Samples drawn.
    pub samples: usize,
    /// The claimed pdf's integral over the domain.
    pub integral: f64,
    pub statistic: f64,
    pub dof: usize,
    pub p_value: f64,
    /// The per-test level after the Šidák correction.
    pub level: f64,
}

impl Outcome {
    pub fn passed(&self) -> bool {
        self.impossible == 0
            && self.zero_density * 100_000 <= self.samples
            && self.dof >= 1
            && self.p_value > self.level
    }

    pub fn assert_passed(&self) {
        assert!(
            self.passed(),
            "χ² test `{}` rejected: {} impossible samples, {} of {} at zero density, \
             χ² = {:.1} with {} dof, p = {:.3e} (level {:.3e}), pdf integral {:.5}; \
             tables in target/tmp/chi2/",
            self.name,
            self.impossible,
            self.zero_density,
            self.samples,
            self.statistic,
            self.dof,
            self.p_value,
            self.level,
            self.integral
        );
    }
}

impl Chi2<'_> {
    /// A test with the suite defaults: 10⁶ samples, 8 × 8 integration
    /// points per cell.
    pub fn new(name: &str, domain: Domain, res: (usize, usize), test_count: usize) -> Chi2<'_> {
        Chi2 {
            name,
            domain,
            res,
            samples: 1_000_000,
            ires: 8,
            test_count,
        }
    }

    /// Integrates `pdf` over every cell: the expected fraction per cell.
    pub fn expected(&self, pdf: &dyn Fn([f64; 3]) -> f64) -> Vec<f64> {
        let (ra, rb) = self.res;
        let mut out = vec![0.0; ra * rb];
        let k = self.ires;
        for i in 0..ra {
            for j in 0..rb {
                let mut sum = 0.0;
                for si in 0..k {
                    for sj in 0..k {
                        let a = (i as f64 + (si as f64 + 0.5) / k as f64) / ra as f64;
                        let b = (j as f64 + (sj as f64 + 0.5) / k as f64) / rb as f64;
                        let (p, jac) = self.domain.point(a, b);
                        sum += pdf(p) * jac;
                    }
                }
                out[i * rb + j] = sum / (k * k * ra * rb) as f64;
            }
        }
        out
    }

    /// Draws `samples` points with `sample` (called once per sample) and
    /// tests them against `pdf`.
    pub fn run(
        &self,
        mut sample: impl FnMut() -> [f64; 3],
        pdf: impl Fn([f64; 3]) -> f64,
    ) -> Outcome {
        let (ra, rb) = self.res;
        let mut observed = vec![0.0f64; ra * rb];
        let (mut impossible, mut zero_density) = (0, 0);
        for _ in 0..self.samples {
            let p = sample();
            let density = pdf(p);
            match self.domain.params(p) {
                Some((a, b)) if density >= 0.0 && density.is_finite() => {
                    zero_density += (density == 0.0) as usize;
                    let i = ((a * ra as f64) as usize).min(ra - 1);
                    let j = ((b * rb as f64) as usize).min(rb - 1);
                    observed[i * rb + j] += 1.0;
                }
                _ => impossible += 1,
            }
        }
        let fractions = self.expected(&pdf);
        let integral: f64 = fractions.iter().sum();
        let expected: Vec<f64> = fractions.iter().map(|f| f * self.samples as f64).collect();
        let (statistic, dof) = pooled_statistic(&observed, &expected);
        let p_value = if dof >= 1 {
            chi2_sf(statistic, dof as f64)
        } else {
            0.0
        };
        let level = 1.0 - (1.0 - ALPHA).powf(1.0 / self.test_count as f64);
        let outcome = Outcome {
            name: self.name.to_string(),
            impossible,
            zero_density,
            samples: self.samples,
            integral,
            statistic,
            dof,
            p_value,
            level,
        };
        if !outcome.passed() {
            self.write_tables(&observed, &expected);
        }
        outcome
    }

    fn write_tables(&self, observed: &[f64], expected: &[f64]) {
        let dir = std::path::Path::new(env!("CARGO_TARGET_TMPDIR")).join("chi2");
        let _ = std::fs::create_dir_all(&dir);
        let mut csv = String::from("i,j,observed,expected\n");
        for (k, (o, e)) in observed.iter().zip(expected).enumerate() {
            csv += &format!("{},{},{o},{e}\n", k / self.res.1, k % self.res.1);
        }
        let _ = std::fs::write(dir.join(format!("{}.csv", self.name)), csv);
    }
}

/// Σ (O − E)² / E after pooling: cells are taken in order of increasing
/// expectation and merged until each bin expects at least 5; a remainder
/// joins the smallest full bin. Cells with E = 0 and O = 0 carry nothing.
/// Returns the statistic and the degrees of freedom (bins − 1).
pub fn pooled_statistic(observed: &[f64], expected: &[f64]) -> (f64, usize) {
    const MIN_EXPECTED: f64 = 5.0;
    let mut order: Vec<usize> = (0..expected.len()).collect();
    order.sort_by(|&a, &b| expected[a].total_cmp(&expected[b]));
    let mut bins: Vec<(f64, f64)> = Vec::new();
    let (mut po, mut pe) = (0.0, 0.0);
    for &k in &order {
        let (o, e) = (observed[k], expected[k]);
        if o == 0.0 && e == 0.0 {
            continue;
        }
        if e < MIN_EXPECTED || pe > 0.0 && pe < MIN_EXPECTED {
            po += o;
            pe += e;
            if pe >= MIN_EXPECTED {
                bins.push((po, pe));
                po = 0.0;
                pe = 0.0;
            }
        } else {
            bins.push((o, e));
        }
    }
    if po > 0.0 || pe > 0.0 {
        match bins.first_mut() {
            Some(b) => {
                b.0 += po;
                b.1 += pe;
            }
            None => bins.push((po, pe)),
        }
    }
    let stat = bins
        .iter()
        .map(|&(o, e)| {
            if e > 0.0 {
                (o - e) * (o - e) / e
            } else {
                f64::INFINITY
            }
        })
        .sum();
    (stat, bins.len().saturating_sub(1))
}

/// The survival function of the χ² distribution with `dof` degrees of
/// freedom: `P(X ≥ x) = Q(dof/2, x/2)`.
pub fn chi2_sf(x: f64, dof: f64) -> f64 {
    gamma_q(0.5 * dof, 0.5 * x)
}

/// `ln Γ(x)` for `x > 0`, Lanczos (g = 7, 9 terms), about 15 digits.
pub fn ln_gamma(x: f64) -> f64 {
    const G: f64 = 7.0;
    const C: [f64; 9] = [
        0.999_999_999_999_809_9,
        676.520_368_121_885_1,
        -1_259.139_216_722_402_8,
        771.323_428_777_653_1,
        -176.615_029_162_140_6,
        12.507_343_278_686_905,
        -0.138_571_095_265_720_12,
        9.984_369_578_019_572e-6,
        1.505_632_735_149_311_6e-7,
    ];
    if x < 0.5 {
        // Reflection: Γ(x) Γ(1 − x) = π / sin(πx).
        return (PI / (PI * x).sin()).ln() - ln_gamma(1.0 - x);
    }
    let x = x - 1.0;
    let mut a = C[0];
    let t = x + G + 0.5;
    for (i, c) in C.iter().enumerate().skip(1) {
        a += c / (x + i as f64);
    }
    0.5 * TAU.ln() + (x + 0.5) * t.ln() - t + a.ln()
}

/// The regularised upper incomplete gamma function `Q(a, x)`: by its
/// series where `x < a + 1`, by a continued fraction (modified Lentz)
/// elsewhere.
pub fn gamma_q(a: f64, x: f64) -> f64 {
    if x <= 0.0 {
        return 1.0;
    }
    let log_prefix = a * x.ln() - x - ln_gamma(a);
    if x < a + 1.0 {
        let (mut term, mut sum, mut n) = (1.0 / a, 1.0 / a, a);
        for _ in 0..100_000 {
            n += 1.0;
            term *= x / n;
            sum += term;
            if term.abs() < sum.abs() * 1e-15 {
                break;
            }
        }
        (1.0 - sum * log_prefix.exp()).clamp(0.0, 1.0)
    } else {
        let tiny = 1e-300;
        let mut b = x + 1.0 - a;
        let mut c = 1.0 / tiny;
        let mut d = 1.0 / b;
        let mut h = d;
        for i in 1..100_000 {
            let an = -(i as f64) * (i as f64 - a);
            b += 2.0;
            d = an * d + b;
            if d.abs() < tiny {
                d = tiny;
            }
            c = b + an / c;
            if c.abs() < tiny {
                c = tiny;
            }
            d = 1.0 / d;
            let delta = d * c;
            h *= delta;
            if (delta - 1.0).abs() < 1e-15 {
                break;
            }
        }
        (log_prefix.exp() * h).clamp(0.0, 1.0)
    }
}
