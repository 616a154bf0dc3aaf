//! One check of a render's settings, however they arrive: from this
//! command line, from a checkpoint's header on `--resume`, and (later)
//! from the C and Python bindings. Parsers only parse; every range, every
//! relation between settings and every size is checked here, with
//! checked arithmetic, before anything is allocated. A message names the
//! setting by its flag (`--spp 0: …`).
//!
//! What needs the scene (its default size, the window inside the image,
//! the samples within spp) is checked by the render's plan right after,
//! from values this check has bounded.

use anyhow::{Result, bail};

use crate::cli::RenderArgs;
use crate::job::SamplerKind;
use crate::limits::{MAX_DEPTH, MAX_SPP, MAX_THREADS, MAX_TILE, MAX_WIDTH};

/// `value` of `flag` within `range`, or an error naming both.
fn within<T: PartialOrd + std::fmt::Display>(
    flag: &str,
    value: T,
    range: std::ops::RangeInclusive<T>,
) -> Result<()> {
    if !range.contains(&value) {
        bail!(
            "{flag} {value} is not in {}..={}",
            range.start(),
            range.end()
        );
    }
    Ok(())
}

/// A positive, finite `value` of `flag`.
fn positive(flag: &str, value: f32) -> Result<()> {
    if !(value > 0.0 && value.is_finite()) {
        bail!("{flag} {value}: must be positive and finite");
    }
    Ok(())
}

/// Two flags that exclude each other.
fn not_both(a: (&str, bool), b: (&str, bool)) -> Result<()> {
    if a.1 && b.1 {
        bail!("{} cannot be used with {}", a.0, b.0);
    }
    Ok(())
}

/// `--min-spp`, `--max-spp` and the threshold (given with `flag`) as
/// adaptive settings, or an error naming the flags.
pub fn adaptive_settings(
    min: u32,
    max: u32,
    threshold: f32,
    flag: &str,
) -> Result<strata::render::Adaptive> {
    use strata::render::{Adaptive, AdaptiveError};
    Adaptive::new(min, max, threshold).map_err(|e| match e {
        AdaptiveError::Max => anyhow::anyhow!(
            "--max-spp {max} is below --min-spp {min} (default {})",
            Adaptive::DEFAULT_MIN
        ),
        AdaptiveError::Min => anyhow::anyhow!(
            "--min-spp {min} must be a multiple of 4 of at least 8 (four blocks of at least 2 \
             samples)"
        ),
        AdaptiveError::Threshold => anyhow::anyhow!("{flag} {threshold}: {e}"),
    })
}

impl RenderArgs {
    /// Checks every setting that does not need the scene: ranges (the
    /// limits of `crate::limits`), windows and sample ranges that are not
    /// empty, and the flags that exclude or need each other. The one
    /// check of every way in; `strata render` runs it first.
    ///
    /// ```
    /// use clap::Parser;
    /// use strata_runner::cli::{Cli, Command};
    ///
    /// let Some(Command::Render(mut args)) =
    ///     Cli::try_parse_from(["strata", "render", "--spp", "16"]).unwrap().command
    /// else {
    ///     unreachable!()
    /// };
    /// assert!(args.validate().is_ok());
    /// // The same settings from elsewhere (a checkpoint) get the same check.
    /// args.tile = 0;
    /// let e = args.validate().unwrap_err().to_string();
    /// assert!(e.contains("--tile 0"), "{e}");
    /// ```
    pub fn validate(&self) -> Result<()> {
        if self.scene.is_empty() {
            bail!("--scene is empty: give a built-in scene's name or a .toml file");
        }
        if let Some(w) = self.width {
            within("--width", w, 1..=MAX_WIDTH)?;
        }
        if let Some(h) = self.height {
            within("--height", h, 1..=MAX_WIDTH)?;
        }
        if let Some(a) = self.aspect {
            positive("--aspect", a)?;
        }
        not_both(
            ("--height", self.height.is_some()),
            ("--aspect", self.aspect.is_some()),
        )?;
        if let Some(spp) = self.spp {
            within("--spp", spp, 1..=MAX_SPP)?;
        }
        if let Some(d) = self.max_depth {
            within("--max-depth", d, 1..=MAX_DEPTH)?;
        }
        within("--threads", self.threads, 1..=MAX_THREADS)?;
        within("--tile", self.tile, 1..=MAX_TILE)?;
        not_both(
            ("--crop", self.crop.is_some()),
            ("--pixel-bounds", self.pixel_bounds.is_some()),
        )?;
        if let Some(c) = self.crop {
            let text = format!("{},{},{},{}", c[0], c[1], c[2], c[3]);
            if !c.iter().all(|f| (0.0..=1.0).contains(f)) {
                bail!("--crop {text}: every value must be a fraction in [0, 1]");
            }
            if c[0] >= c[1] || c[2] >= c[3] {
                bail!("--crop {text} is empty: need x0 < x1 and y0 < y1");
            }
        }
        if let Some([x0, x1, y0, y1]) = self.pixel_bounds
            && (x0 >= x1 || y0 >= y1)
        {
            bail!("--pixel-bounds {x0},{x1},{y0},{y1} is empty: need x0 < x1 and y0 < y1");
        }
        if let Some(s) = &self.samples {
            if s.start >= s.end {
                bail!("--samples {}..{} is empty: need A < B", s.start, s.end);
            }
            within("--samples' end", s.end, 1..=MAX_SPP)?;
        }
        if let (Some(s), Some(spp)) = (&self.samples, self.spp)
            && s.end > spp
        {
            bail!(
                "--samples {}..{} reaches past the {spp} samples per pixel",
                s.start,
                s.end
            );
        }
        match self.adaptive {
            Some(t) => {
                positive("--adaptive", t)?;
                not_both(("--adaptive", true), ("--samples", self.samples.is_some()))?;
                not_both(("--adaptive", true), ("--spp", self.spp.is_some()))?;
                within("--min-spp", self.min_spp, 8..=MAX_SPP)?;
                within("--max-spp", self.max_spp, 8..=MAX_SPP)?;
                adaptive_settings(self.min_spp, self.max_spp, t, "--adaptive")?;
                if self.sampler == SamplerKind::Grid {
                    bail!(
                        "--adaptive needs a sampler whose first samples spread over the pixel \
                         (independent, stratified, sobol, halton, zsobol): the grid fills its \
                         rows in order"
                    );
                }
            }
            None => {
                if self.spp_map.is_some() {
                    bail!("--spp-map needs --adaptive");
                }
            }
        }
        if let Some(r) = self.filter_radius {
            positive("--filter-radius", r)?;
        }
        // The filter's own limits (its largest radius).
        self.filter.filter(self.filter_radius)?;
        not_both(
            ("--checkpoint", self.checkpoint.is_some()),
            ("--no-checkpoint", self.no_checkpoint),
        )?;
        Ok(())
    }
}

#[cfg(test)]
mod tests {
    use clap::Parser;

    use crate::cli::{Cli, Command, RenderArgs};

    fn args(flags: &[&str]) -> RenderArgs {
        let mut all = vec!["strata", "render"];
        all.extend(flags);
        match Cli::try_parse_from(all).unwrap().command {
            Some(Command::Render(a)) => a,
            _ => unreachable!("a render command line"),
        }
    }

    /// Every setting the command line parses but must not accept is
    /// refused by the one check, naming its flag: what a damaged
    /// checkpoint or a binding would hand it.
    #[test]
    fn every_setting_is_checked_with_its_flag() {
        let ok = args(&[]);
        ok.validate().unwrap();
        let cases: Vec<(RenderArgs, &str)> = vec![
            (args(&["--width", "0"]), "--width 0"),
            (args(&["--width", "16385"]), "--width 16385"),
            (args(&["--height", "0"]), "--height 0"),
            (args(&["--aspect", "-2"]), "--aspect -2"),
            (args(&["--aspect", "nan"]), "--aspect NaN"),
            (args(&["--aspect", "inf"]), "--aspect inf"),
            (args(&["--spp", "0"]), "--spp 0"),
            (args(&["--spp", "1048577"]), "--spp 1048577"),
            (args(&["--max-depth", "0"]), "--max-depth 0"),
            (args(&["--max-depth", "10001"]), "--max-depth 10001"),
            (args(&["--threads", "0"]), "--threads 0"),
            (args(&["--threads", "513"]), "--threads 513"),
            (args(&["--threads", "65535"]), "--threads 65535"),
            (args(&["--tile", "0"]), "--tile 0"),
            (args(&["--tile", "4097"]), "--tile 4097"),
            (args(&["--crop", "0,2,0,1"]), "--crop 0,2,0,1"),
            (
                args(&["--crop", "0.5,0.5,0,1"]),
                "--crop 0.5,0.5,0,1 is empty",
            ),
            (args(&["--crop", "0,1,nan,1"]), "--crop"),
            (
                args(&["--pixel-bounds", "0,96,90,30"]),
                "--pixel-bounds 0,96,90,30 is empty",
            ),
            (args(&["--samples", "3..3"]), "--samples 3..3 is empty"),
            (args(&["--samples", "5..2"]), "--samples 5..2"),
            (args(&["--adaptive", "0"]), "--adaptive 0"),
            (args(&["--adaptive=-1"]), "--adaptive -1"),
            (args(&["--adaptive", "--min-spp", "4"]), "--min-spp 4"),
            (args(&["--adaptive", "--max-spp", "1"]), "--max-spp 1"),
            (args(&["--filter-radius", "0"]), "--filter-radius 0"),
            (args(&["--filter-radius", "nan"]), "--filter-radius NaN"),
            (args(&["--filter-radius", "9"]), "--filter-radius 9"),
            (args(&["--adaptive", "--min-spp", "10"]), "--min-spp 10"),
            (
                args(&["--adaptive", "--min-spp", "64", "--max-spp", "32"]),
                "--max-spp 32",
            ),
            (
                args(&["--adaptive", "--sampler", "grid"]),
                "the grid fills its rows",
            ),
            (
                args(&["--spp", "4", "--samples", "2..5"]),
                "past the 4 samples",
            ),
        ];
        for (a, want) in cases {
            let e = a.validate().unwrap_err().to_string();
            assert!(e.contains(want), "{want}: {e}");
        }
        // Relations clap enforces on the command line, as a checkpoint's
        // JSON could break them.
        let mut a = args(&["--height", "9"]);
        a.aspect = Some(2.0);
        assert!(a.validate().unwrap_err().to_string().contains("--aspect"));
        let mut a = args(&["--crop", "0,1,0,1"]);
        a.pixel_bounds = Some([0, 1, 0, 1]);
        assert!(
            a.validate()
                .unwrap_err()
                .to_string()
                .contains("--pixel-bounds")
        );
        let mut a = args(&["--adaptive"]);
        a.samples = Some(0..2);
        assert!(a.validate().unwrap_err().to_string().contains("--samples"));
        let mut a = args(&["--adaptive"]);
        a.spp = Some(8);
        assert!(a.validate().unwrap_err().to_string().contains("--spp"));
        let mut a = args(&[]);
        a.spp_map = Some("m.png".into());
        assert!(a.validate().unwrap_err().to_string().contains("--spp-map"));
        let mut a = args(&["--no-checkpoint"]);
        a.checkpoint = Some("c".into());
        assert!(
            a.validate()
                .unwrap_err()
                .to_string()
                .contains("--checkpoint")
        );
        let mut a = args(&[]);
        a.scene = String::new();
        assert!(a.validate().unwrap_err().to_string().contains("--scene"));
    }
}
